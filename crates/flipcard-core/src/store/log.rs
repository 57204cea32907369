//! The append-only review log: recording a rating, undoing the last one,
//! reading rows back.

use chrono::{DateTime, Utc};
use rusqlite::{Row, Transaction, params};

use super::codec::{self, BalancedDays, Ms};
use super::db::Store;
use super::error::StoreError;
use super::state;
use super::tally;
use super::write::insert_session;
use crate::sched::{ItemKey, ReviewKind, ReviewRecord};

/// One row of the log as stored.
#[derive(Debug, Clone, PartialEq)]
pub struct LoggedReview {
    pub id: i64,
    pub record: ReviewRecord,
    pub undone: bool,
}

/// The identity (item, time, rating) of the last answer of session `?1`
/// that is still live. An answer that a merge appended again after an
/// earlier one arrived is live in its copy, outside the session: it keeps
/// its place in the session's order by its first row.
pub(super) const LAST_ANSWER: &str = "SELECT r.deck, r.card, r.direction, r.reviewed_at, r.rating \
     FROM review AS r WHERE r.session = ?1 AND r.origin IS NULL AND EXISTS (SELECT 1 \
       FROM review AS o WHERE o.deck = r.deck AND o.card = r.card AND o.direction = r.direction \
         AND o.reviewed_at = r.reviewed_at AND o.rating = r.rating AND o.origin IS NULL \
         AND o.undone = 0) \
     ORDER BY r.id DESC LIMIT 1";

/// The log's columns in the order [`read_logged`] expects.
pub(super) const COLUMNS: &str = "id, deck, card, direction, reviewed_at, rating, kind, \
     elapsed_days, scheduled_days, stability, difficulty, state, step, due, last_review, \
     duration_ms, undone, balanced_days";

impl Store {
    /// Appends one rating to the log and updates the item's cached state, in
    /// one transaction that is on disk when this returns. Returns the log id.
    pub fn record(&mut self, review: &ReviewRecord) -> Result<i64, StoreError> {
        let ids = self.record_batch(std::slice::from_ref(review))?;
        ids.first().copied().ok_or_else(|| StoreError::BadRow {
            id: 0,
            detail: "no id returned for the inserted row".into(),
        })
    }

    /// Appends several ratings in one transaction (imports of histories,
    /// benchmarks); each is applied exactly as [`Store::record`] would.
    pub fn record_batch(&mut self, reviews: &[ReviewRecord]) -> Result<Vec<i64>, StoreError> {
        if reviews.is_empty() {
            return Ok(Vec::new());
        }
        for r in reviews {
            validate(r)?;
        }
        self.write(|w| {
            let session = w.session()?;
            let mut ids = Vec::with_capacity(reviews.len());
            for r in reviews {
                ids.push(append(w, session, r)?);
            }
            Ok(ids)
        })
    }

    /// Starts a new session: [`Store::undo_last`] reaches back only to the
    /// start of the current session. A session starts by itself with the
    /// first write.
    pub fn start_session(&mut self) -> Result<i64, StoreError> {
        let id = insert_session(&self.conn, self.clock.now()).map_err(|e| self.err(e))?;
        self.session = Some(id);
        Ok(id)
    }

    /// The current session, if one has started.
    pub fn session(&self) -> Option<i64> {
        self.session
    }

    /// Reverts the last rating of this session that is not yet undone (with
    /// the status events it brought about; a copy a merge appended is the
    /// one taken back): the log row is marked undone and the item's state is recomputed from the
    /// log (back to new when no rating of it remains), in one transaction.
    /// Returns the undone log row (marked undone), or `None` when there is
    /// nothing to undo.
    pub fn undo_last(&mut self) -> Result<Option<LoggedReview>, StoreError> {
        let Some(session) = self.session else {
            return Ok(None);
        };
        self.write(|tx| {
            let last = {
                let mut st = tx.prepare_cached(&format!(
                    "SELECT {COLUMNS} FROM review WHERE undone = 0 AND origin IS NULL \
                     AND (deck, card, direction, reviewed_at, rating) = ({LAST_ANSWER}) \
                     ORDER BY id DESC LIMIT 1"
                ))?;
                let mut rows = st.query([session])?;
                match rows.next()? {
                    Some(row) => Some(read_logged(row)??),
                    None => None,
                }
            };
            let Some(last) = last else {
                return Ok(None);
            };
            tx.execute("UPDATE review SET undone = 1 WHERE id = ?1", [last.id])?;
            state::refresh_item(tx, &last.record.key)?;
            tally::count(tx, &last.record, -1)?;
            // A leech found or siblings buried by this rating go with it.
            super::status_log::undo_caused(tx, last.id)?;
            Ok(Some(LoggedReview {
                undone: true,
                ..last
            }))
        })
    }

    /// Every row of the log in id order (undone ones included), handed to
    /// `each` one at a time; stops at the first error `each` returns.
    pub fn each_review<E>(
        &self,
        mut each: impl FnMut(LoggedReview) -> Result<(), E>,
    ) -> Result<(), E>
    where
        E: From<StoreError>,
    {
        let mut st = self
            .conn
            .prepare(&format!("SELECT {COLUMNS} FROM review ORDER BY id"))
            .map_err(|e| self.err(e))?;
        let mut rows = st.query([]).map_err(|e| self.err(e))?;
        while let Some(row) = rows.next().map_err(|e| self.err(e))? {
            let logged = read_logged(row).map_err(|e| self.err(e))??;
            each(logged)?;
        }
        Ok(())
    }

    /// The log rows of one item in id order (undone ones included).
    pub fn history(&self, key: &ItemKey) -> Result<Vec<LoggedReview>, StoreError> {
        let mut st = self
            .conn
            .prepare_cached(&format!(
                "SELECT {COLUMNS} FROM review WHERE deck = ?1 AND card = ?2 AND direction = ?3 \
                 ORDER BY id"
            ))
            .map_err(|e| self.err(e))?;
        let mut rows = st
            .query(params![key.deck, key.card, key.direction.as_str()])
            .map_err(|e| self.err(e))?;
        let mut out = Vec::new();
        while let Some(row) = rows.next().map_err(|e| self.err(e))? {
            out.push(read_logged(row).map_err(|e| self.err(e))??);
        }
        Ok(out)
    }

    /// The time to record an answer of `key` given at `now`: `now` to the
    /// millisecond (the precision the log and sync keep), or a millisecond
    /// after the item's latest answer when that is not earlier (a frozen or
    /// stepped-back clock), so two answers are never taken for one: an
    /// answer's identity across machines is its item, time and rating.
    pub fn answer_time(
        &self,
        key: &ItemKey,
        now: DateTime<Utc>,
    ) -> Result<DateTime<Utc>, StoreError> {
        let now = crate::sched::clock::to_millisecond(now);
        let latest: Option<Ms> = self
            .conn
            .prepare_cached(
                "SELECT max(reviewed_at) FROM review WHERE deck = ?1 AND card = ?2 \
                 AND direction = ?3",
            )
            .and_then(|mut st| {
                st.query_row(params![key.deck, key.card, key.direction.as_str()], |r| {
                    r.get(0)
                })
            })
            .map_err(|e| self.err(e))?;
        Ok(match latest {
            Some(Ms(t)) if t >= now => t + chrono::TimeDelta::milliseconds(1),
            _ => now,
        })
    }

    /// The number of rows in the log (undone ones included).
    pub fn review_count(&self) -> Result<i64, StoreError> {
        self.conn
            .query_row("SELECT count(*) FROM review", [], |r| r.get(0))
            .map_err(|e| self.err(e))
    }
}

pub(super) fn append(
    tx: &Transaction<'_>,
    session: i64,
    r: &ReviewRecord,
) -> rusqlite::Result<i64> {
    let id = insert_row(tx, session, r, false, None)?;
    if r.kind != ReviewKind::Cram {
        state::apply(tx, r, id)?;
    }
    tally::count(tx, r, 1)?;
    Ok(id)
}

/// One row of the review log as it is written (the only INSERT into it, so
/// an append and a merge spell the columns alike). `origin` is the machine
/// a merged answer came from (`None`: this one).
pub(super) fn insert_row(
    tx: &Transaction<'_>,
    session: i64,
    r: &ReviewRecord,
    undone: bool,
    origin: Option<&str>,
) -> rusqlite::Result<i64> {
    let a = &r.after;
    tx.prepare_cached(
        "INSERT INTO review (session, deck, card, direction, reviewed_at, rating, kind, \
         elapsed_days, scheduled_days, stability, difficulty, state, step, due, last_review, \
         duration_ms, undone, origin, balanced_days) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, \
         ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16, ?17, ?18, ?19) RETURNING id",
    )?
    .query_row(
        params![
            session,
            r.key.deck,
            r.key.card,
            r.key.direction,
            Ms(r.reviewed_at),
            r.rating,
            r.kind,
            r.elapsed_days,
            r.scheduled_days,
            a.stability,
            a.difficulty,
            a.state,
            a.step.map(i64::from),
            Ms(a.due),
            a.last_review.map(Ms),
            r.duration_ms,
            i64::from(undone),
            origin,
            r.balanced_days,
        ],
        |row| row.get(0),
    )
}

/// What the database cannot keep faithfully is refused with a clear message
/// (SQLite would store a NaN as NULL, for instance).
pub(super) fn validate(r: &ReviewRecord) -> Result<(), StoreError> {
    let bad = |detail: String| {
        Err(StoreError::BadRow {
            id: 0,
            detail: format!(
                "refusing to record {}/{} ({}): {detail}",
                r.key.deck,
                r.key.card,
                r.key.direction.as_str()
            ),
        })
    };
    if r.key.deck.is_empty() || r.key.card.is_empty() {
        return bad("empty deck or card id".into());
    }
    for (name, v) in [
        ("stability", r.after.stability),
        ("difficulty", r.after.difficulty),
    ] {
        if let Some(v) = v
            && !v.is_finite()
        {
            return bad(format!("{name} is {v}"));
        }
    }
    if r.duration_ms < 0 {
        return bad(format!("negative duration {} ms", r.duration_ms));
    }
    if let Some(d) = r.balanced_days
        && !(1..=crate::sched::scheduler::MAXIMUM_INTERVAL).contains(&d)
    {
        return bad(format!("balanced interval {d} days is out of range"));
    }
    Ok(())
}

/// Reads one row selected with [`COLUMNS`]. The outer error is SQLite's, the
/// inner one a value this build cannot interpret.
pub(super) fn read_logged(row: &Row<'_>) -> rusqlite::Result<Result<LoggedReview, StoreError>> {
    let id: i64 = row.get(0)?;
    let decoded = (|| {
        Ok(LoggedReview {
            id,
            record: ReviewRecord {
                key: ItemKey {
                    deck: row.get(1)?,
                    card: row.get(2)?,
                    direction: row.get(3)?,
                },
                reviewed_at: row.get::<_, Ms>(4)?.0,
                rating: row.get(5)?,
                kind: row.get(6)?,
                elapsed_days: row.get(7)?,
                scheduled_days: row.get(8)?,
                after: codec::card_state(row, [11, 12, 9, 10, 13, 14])?,
                duration_ms: row.get(15)?,
                balanced_days: row.get::<_, Option<BalancedDays>>(17)?.map(|d| d.0),
            },
            undone: row.get::<_, i64>(16)? != 0,
        })
    })();
    match decoded {
        Ok(logged) => Ok(Ok(logged)),
        Err(e) => codec::bad_value(e).map(|detail| Err(StoreError::BadRow { id, detail })),
    }
}
