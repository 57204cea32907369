//! The card-state cache: each item's state after its last rating that is
//! neither undone nor cram, with its count of ratings and lapses. It is
//! derived from the log alone, so it can always be rebuilt (the answer
//! tallies are rebuilt along with it).

use crate::sched::States;
use std::collections::HashMap;

use rusqlite::{Connection, Row, Transaction, params};

use super::codec::{self, Count, Ms};
use super::db::Store;
use super::error::StoreError;
use super::write::Failed;
use crate::sched::{CardState, ItemKey, Rating, ReviewKind, ReviewRecord};

/// One cached item state, with the counts the log gives.
#[derive(Debug, Clone, PartialEq)]
pub struct CachedState {
    pub key: ItemKey,
    pub state: CardState,
    /// Ratings that count for scheduling (not undone, not cram).
    pub reps: u32,
    /// Of those, review-kind answers rated Again.
    pub lapses: u32,
    /// The log row this state comes from.
    pub review_id: i64,
}

/// What `rebuild` did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RebuildReport {
    /// Items with a state after the rebuild (items never rated stay new).
    pub items: usize,
    /// Items whose cached state was missing, different or stale before.
    pub changed: usize,
    /// Log rows read (undone ones included).
    pub reviews: i64,
    /// Whether the answer tallies differed from the log.
    pub tallies_changed: bool,
    /// Whether the status cache (suspended, buried, leech) differed from
    /// the status log.
    pub statuses_changed: bool,
}

const STATE_COLUMNS: &str = "deck, card, direction, state, step, stability, difficulty, due, \
     last_review, reps, lapses, review_id";

/// The state of every item (or of the one item `?1, ?2, ?3` when `one` is
/// set) computed from the log alone: the last row that counts, its counts.
fn from_log_sql(one: bool) -> String {
    let filter = if one {
        "AND deck = ?1 AND card = ?2 AND direction = ?3"
    } else {
        ""
    };
    format!(
        "SELECT r.deck, r.card, r.direction, r.state, r.step, r.stability, r.difficulty, r.due, \
                r.last_review, agg.reps, agg.lapses, r.id \
         FROM (SELECT max(id) AS last, count(*) AS reps, \
                      sum(kind = 'review' AND rating = {again}) AS lapses \
               FROM review WHERE undone = 0 AND kind <> 'cram' {filter} \
               GROUP BY deck, card, direction) AS agg \
         JOIN review AS r ON r.id = agg.last",
        again = Rating::Again as i64
    )
}

/// Folds a new (non-cram) rating into the cache.
pub(super) fn apply(tx: &Transaction<'_>, r: &ReviewRecord, id: i64) -> rusqlite::Result<()> {
    let a = &r.after;
    let lapse = i64::from(r.kind == ReviewKind::Review && r.rating == Rating::Again);
    tx.prepare_cached(
        "INSERT INTO card_state (deck, card, direction, state, step, stability, difficulty, due, \
         last_review, reps, lapses, review_id) \
         VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, 1, ?10, ?11) \
         ON CONFLICT (deck, card, direction) DO UPDATE SET \
           state = excluded.state, step = excluded.step, stability = excluded.stability, \
           difficulty = excluded.difficulty, due = excluded.due, \
           last_review = excluded.last_review, reps = card_state.reps + 1, \
           lapses = card_state.lapses + excluded.lapses, review_id = excluded.review_id",
    )?
    .execute(params![
        r.key.deck,
        r.key.card,
        r.key.direction,
        a.state,
        a.step.map(i64::from),
        a.stability,
        a.difficulty,
        Ms(a.due),
        a.last_review.map(Ms),
        lapse,
        id,
    ])?;
    Ok(())
}

/// Recomputes one item's cached state from the log (removing it when no
/// rating of the item counts any more: the item is new again).
pub(super) fn refresh_item(tx: &Transaction<'_>, key: &ItemKey) -> rusqlite::Result<()> {
    let k = params![key.deck, key.card, key.direction.as_str()];
    tx.execute(
        "DELETE FROM card_state WHERE deck = ?1 AND card = ?2 AND direction = ?3",
        k,
    )?;
    tx.execute(
        &format!(
            "INSERT INTO card_state ({STATE_COLUMNS}) {}",
            from_log_sql(true)
        ),
        k,
    )?;
    Ok(())
}

impl Store {
    /// The state of every item of `deck` that has been rated; an item not in
    /// the map is new.
    pub fn states(&self, deck: &str) -> Result<States, StoreError> {
        // In no order (a map is made of them): sorting a deck's 50,000
        // states took SQLite longer than reading them. Only what a state
        // is made of is read; the deck is the one asked for.
        let mut st = self
            .conn
            .prepare_cached(&format!(
                "SELECT card, direction, state, step, stability, difficulty, due, last_review, \
                        review_id FROM card_state WHERE deck = ?1 UNION ALL {}",
                super::kept::kept_sql(
                    "k.card, k.direction, k.state, k.step, k.stability, k.difficulty, k.due, \
                     k.last_review, 0",
                    "WHERE k.deck = ?1"
                )
            ))
            .map_err(|e| self.err(e))?;
        let read = |row: &Row<'_>| -> rusqlite::Result<Result<(ItemKey, CardState), StoreError>> {
            let review_id: i64 = row.get(8)?;
            let decoded = (|| {
                Ok((
                    ItemKey {
                        deck: deck.to_string(),
                        card: row.get(0)?,
                        direction: row.get(1)?,
                    },
                    codec::card_state(row, [2, 3, 4, 5, 6, 7])?,
                ))
            })();
            checked(decoded, review_id)
        };
        let mut map = States::default();
        let mut rows = st.query([deck]).map_err(|e| self.err(e))?;
        while let Some(row) = rows.next().map_err(|e| self.err(e))? {
            let (key, state) = read(row).map_err(|e| self.err(e))??;
            map.insert(key, state);
        }
        Ok(map)
    }

    /// The state of one item (`None`: new).
    pub fn state(&self, key: &ItemKey) -> Result<Option<CardState>, StoreError> {
        Ok(self.cached_state(key)?.map(|c| c.state))
    }

    /// The cached state of one item with its counts (`None`: new).
    pub fn cached_state(&self, key: &ItemKey) -> Result<Option<CachedState>, StoreError> {
        // An item no answer of the log counts for may have a kept state
        // (an Anki card with a schedule and no review history).
        let mut st = self
            .conn
            .prepare_cached(&format!(
                "SELECT {STATE_COLUMNS} FROM card_state \
                 WHERE deck = ?1 AND card = ?2 AND direction = ?3 \
                 UNION ALL {}",
                super::kept::as_cached_sql(
                    "WHERE k.deck = ?1 AND k.card = ?2 AND k.direction = ?3"
                )
            ))
            .map_err(|e| self.err(e))?;
        let rows = read_states(&mut st, params![key.deck, key.card, key.direction.as_str()])
            .map_err(|e| self.err(e))?;
        rows.into_iter().next().transpose()
    }

    /// The whole cache, ordered by deck, card, direction.
    pub fn cached_states(&self) -> Result<Vec<CachedState>, StoreError> {
        self.cached_states_in(None)
    }

    /// The cache of one deck (or all), ordered by deck, card, direction.
    pub fn cached_states_in(&self, deck: Option<&str>) -> Result<Vec<CachedState>, StoreError> {
        // Two spellings, so that one deck is read through the primary key.
        let (filter, kept) = if deck.is_some() {
            ("WHERE deck = ?1", "WHERE k.deck = ?1")
        } else {
            ("", "")
        };
        // With the kept states of items no answer of the log counts for
        // (an Anki card with a schedule and no review history).
        let mut st = self
            .conn
            .prepare_cached(&format!(
                "SELECT * FROM (SELECT {STATE_COLUMNS} FROM card_state {filter} \
                 UNION ALL {}) ORDER BY deck, card, direction",
                super::kept::as_cached_sql(kept)
            ))
            .map_err(|e| self.err(e))?;
        let rows = match deck {
            Some(d) => read_states(&mut st, [d]),
            None => read_states(&mut st, []),
        }
        .map_err(|e| self.err(e))?;
        rows.into_iter().collect()
    }

    /// Recomputes the whole cache from the log alone, in one transaction.
    pub fn rebuild(&mut self) -> Result<RebuildReport, StoreError> {
        self.write(|tx| {
            let before = all_states(tx, &format!("SELECT {STATE_COLUMNS} FROM card_state"))?
                .into_iter()
                .map(|c| (c.key.clone(), c))
                .collect::<HashMap<_, _>>();
            let after = all_states(tx, &from_log_sql(false))?;
            let mut changed = before.len();
            for c in &after {
                if before.get(&c.key) == Some(c) {
                    changed -= 1;
                } else if !before.contains_key(&c.key) {
                    changed += 1;
                }
            }
            tx.execute("DELETE FROM card_state", [])?;
            tx.execute(
                &format!(
                    "INSERT INTO card_state ({STATE_COLUMNS}) {}",
                    from_log_sql(false)
                ),
                [],
            )?;
            let tallies_changed = super::tally::rebuild(tx)?;
            let statuses_changed = super::status_log::rebuild(tx)?;
            let reviews: i64 = tx.query_row("SELECT count(*) FROM review", [], |r| r.get(0))?;
            Ok(RebuildReport {
                items: after.len(),
                changed,
                reviews,
                tallies_changed,
                statuses_changed,
            })
        })
    }
}

fn all_states(conn: &Connection, sql: &str) -> Result<Vec<CachedState>, Failed> {
    let mut st = conn.prepare(sql)?;
    let rows = read_states(&mut st, [])?;
    Ok(rows.into_iter().collect::<Result<_, _>>()?)
}

type StateRows = Vec<Result<CachedState, StoreError>>;

fn read_states(
    st: &mut rusqlite::Statement<'_>,
    params: impl rusqlite::Params,
) -> rusqlite::Result<StateRows> {
    let mut rows = st.query(params)?;
    let mut out = Vec::new();
    while let Some(row) = rows.next()? {
        out.push(read_state(row)?);
    }
    Ok(out)
}

fn read_state(row: &Row<'_>) -> rusqlite::Result<Result<CachedState, StoreError>> {
    let review_id: i64 = row.get(11)?;
    let decoded = (|| {
        Ok(CachedState {
            key: ItemKey {
                deck: row.get(0)?,
                card: row.get(1)?,
                direction: row.get(2)?,
            },
            state: codec::card_state(row, [3, 4, 5, 6, 7, 8])?,
            reps: row.get::<_, Count>(9)?.0,
            lapses: row.get::<_, Count>(10)?.0,
            review_id,
        })
    })();
    checked(decoded, review_id)
}

/// A cached state row as decoded: a value of the wrong kind is the row's
/// fault (`BadRow`, naming the answer it came from), any other error
/// SQLite's.
fn checked<T>(
    decoded: rusqlite::Result<T>,
    review_id: i64,
) -> rusqlite::Result<Result<T, StoreError>> {
    match decoded {
        Ok(v) => Ok(Ok(v)),
        Err(e) => codec::bad_value(e).map(|detail| {
            Err(StoreError::BadRow {
                id: review_id,
                detail: format!("cached state: {detail}"),
            })
        }),
    }
}
