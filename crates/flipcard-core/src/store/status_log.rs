//! The status log's rows: its events (suspend, unsuspend, bury, leech),
//! appending one, reading them back, taking back those a rating caused,
//! and the `item_status` cache derived from them alone. The latest live
//! event by time decides, so events merged from another machine count
//! where they happened; between events of the same millisecond an
//! unsuspend comes last, then the later end of a bury (the same order on
//! every machine, whatever order their rows were written in).
//!
//! The time of a change the learner makes is a hybrid logical clock
//! ([`event_time`]): the wall clock, or a millisecond after every event this
//! log holds when that is later, so a change just made always takes effect,
//! here and on every machine that merges it, even when an event from a
//! machine whose clock runs ahead is already in the log.
//!
//! These are the pieces the review log (an undo takes back what a rating
//! caused), the card-state cache (rebuilt with this one), the sync merge
//! and [`super::status`]'s changes share; they use nothing of those.

use chrono::{DateTime, Utc};
use rusqlite::{Connection, Transaction, params};

use super::codec::Ms;
use crate::sched::ItemKey;

/// What a status event does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum StatusAction {
    Suspend,
    /// Lifts a suspension and a bury.
    Unsuspend,
    Bury,
    Leech,
}

impl StatusAction {
    pub fn as_str(self) -> &'static str {
        match self {
            StatusAction::Suspend => "suspend",
            StatusAction::Unsuspend => "unsuspend",
            StatusAction::Bury => "bury",
            StatusAction::Leech => "leech",
        }
    }
    pub fn parse(s: &str) -> Option<StatusAction> {
        [
            StatusAction::Suspend,
            StatusAction::Unsuspend,
            StatusAction::Bury,
            StatusAction::Leech,
        ]
        .into_iter()
        .find(|a| a.as_str() == s)
    }
}

/// One row of the status log.
#[derive(Debug, Clone, PartialEq)]
pub struct StatusEvent {
    pub id: i64,
    pub key: ItemKey,
    pub at: DateTime<Utc>,
    pub action: StatusAction,
    pub until: Option<DateTime<Utc>>,
    /// The rating that brought this event about.
    pub cause: Option<i64>,
    pub undone: bool,
}

const STATUS_OF: &str = "SELECT k.deck, k.card, k.direction, \
    coalesce((SELECT e.action = 'suspend' FROM status_event AS e \
              WHERE e.deck = k.deck AND e.card = k.card AND e.direction = k.direction \
                AND e.undone = 0 AND e.action IN ('suspend', 'unsuspend') \
              ORDER BY e.at DESC, e.action DESC, e.id DESC LIMIT 1), 0), \
    (SELECT e.until FROM status_event AS e \
     WHERE e.deck = k.deck AND e.card = k.card AND e.direction = k.direction \
       AND e.undone = 0 AND e.action IN ('bury', 'unsuspend') \
     ORDER BY e.at DESC, e.action DESC, e.until DESC, e.id DESC LIMIT 1), \
    EXISTS (SELECT 1 FROM status_event AS e \
            WHERE e.deck = k.deck AND e.card = k.card AND e.direction = k.direction \
              AND e.undone = 0 AND e.action = 'leech')";

/// Recomputes the cached status of one item from the log.
pub(super) fn refresh(conn: &Connection, key: &ItemKey) -> rusqlite::Result<()> {
    let k = params![key.deck, key.card, key.direction];
    conn.execute(
        "DELETE FROM item_status WHERE deck = ?1 AND card = ?2 AND direction = ?3",
        k,
    )?;
    conn.execute(
        &format!(
            "INSERT INTO item_status (deck, card, direction, suspended, buried_until, leech) \
             SELECT * FROM ({STATUS_OF} FROM (SELECT ?1 AS deck, ?2 AS card, ?3 AS direction) AS k) \
             WHERE EXISTS (SELECT 1 FROM status_event WHERE deck = ?1 AND card = ?2 \
                           AND direction = ?3)"
        ),
        k,
    )?;
    Ok(())
}

/// One row of the status cache as stored.
type StatusRow = (String, String, String, i64, Option<i64>, i64);

/// Recomputes the whole status cache; true when it differed.
pub(super) fn rebuild(tx: &Transaction<'_>) -> rusqlite::Result<bool> {
    let read = |tx: &Transaction<'_>| -> rusqlite::Result<Vec<StatusRow>> {
        let mut st = tx.prepare(
            "SELECT deck, card, direction, suspended, buried_until, leech FROM item_status \
             ORDER BY deck, card, direction",
        )?;
        st.query_map([], |r| {
            Ok((
                r.get(0)?,
                r.get(1)?,
                r.get(2)?,
                r.get(3)?,
                r.get(4)?,
                r.get(5)?,
            ))
        })?
        .collect()
    };
    let before = read(tx)?;
    tx.execute("DELETE FROM item_status", [])?;
    tx.execute(
        &format!(
            "INSERT INTO item_status (deck, card, direction, suspended, buried_until, leech) \
             {STATUS_OF} FROM (SELECT DISTINCT deck, card, direction FROM status_event) AS k"
        ),
        [],
    )?;
    Ok(read(tx)? != before)
}

/// The time of a change the learner makes at `wall`: `wall` to the
/// millisecond, or a millisecond after the latest event this log holds
/// (merged ones included) when that is not earlier. The events of one change
/// share it (they are of distinct items).
pub(super) fn event_time(
    tx: &Transaction<'_>,
    wall: DateTime<Utc>,
) -> rusqlite::Result<DateTime<Utc>> {
    let wall = crate::sched::clock::to_millisecond(wall);
    let latest: Option<Ms> = tx.query_row("SELECT max(at) FROM status_event", [], |r| r.get(0))?;
    Ok(match latest {
        Some(Ms(t)) if t >= wall => t + chrono::TimeDelta::milliseconds(1),
        _ => wall,
    })
}

/// The batch id of the next change: the id its first event will get.
pub(super) fn next_batch(tx: &Transaction<'_>) -> rusqlite::Result<i64> {
    tx.query_row(
        "SELECT coalesce(max(id), 0) + 1 FROM status_event",
        [],
        |r| r.get(0),
    )
}

#[allow(clippy::too_many_arguments)]
pub(super) fn append(
    tx: &Transaction<'_>,
    session: i64,
    batch: i64,
    key: &ItemKey,
    at: DateTime<Utc>,
    action: StatusAction,
    until: Option<DateTime<Utc>>,
    cause: Option<i64>,
) -> rusqlite::Result<i64> {
    let id = tx
        .prepare_cached(
            "INSERT INTO status_event (session, deck, card, direction, at, action, until, cause, \
             batch, after_review) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, \
             coalesce((SELECT max(id) FROM review), 0)) RETURNING id",
        )?
        .query_row(
            params![
                session,
                key.deck,
                key.card,
                key.direction,
                Ms(at),
                action.as_str(),
                until.map(Ms),
                cause,
                batch
            ],
            |r| r.get(0),
        )?;
    refresh(tx, key)?;
    Ok(id)
}

pub(super) const EVENT_COLUMNS: &str =
    "id, deck, card, direction, at, action, until, cause, undone";

pub(super) fn read_event(r: &rusqlite::Row<'_>) -> rusqlite::Result<StatusEvent> {
    let action: String = r.get(5)?;
    Ok(StatusEvent {
        id: r.get(0)?,
        key: ItemKey {
            deck: r.get(1)?,
            card: r.get(2)?,
            direction: r.get(3)?,
        },
        at: r.get::<_, Ms>(4)?.0,
        action: StatusAction::parse(&action).ok_or_else(|| {
            rusqlite::Error::FromSqlConversionFailure(
                5,
                rusqlite::types::Type::Text,
                format!("unknown status action {action:?}").into(),
            )
        })?,
        until: r.get::<_, Option<Ms>>(6)?.map(|m| m.0),
        cause: r.get(7)?,
        undone: r.get::<_, i64>(8)? != 0,
    })
}

/// Marks undone every event a rating brought about (through any row of
/// the same answer: a merge may have appended it again); returns them.
pub(super) fn undo_caused(tx: &Transaction<'_>, review: i64) -> rusqlite::Result<Vec<StatusEvent>> {
    let events: Vec<StatusEvent> = tx
        .prepare_cached(&format!(
            "SELECT {EVENT_COLUMNS} FROM status_event WHERE undone = 0 AND cause IN ( \
               SELECT o.id FROM review AS r JOIN review AS o ON o.deck = r.deck \
                 AND o.card = r.card AND o.direction = r.direction \
                 AND o.reviewed_at = r.reviewed_at AND o.rating = r.rating \
                 AND o.origin IS r.origin \
               WHERE r.id = ?1) ORDER BY id"
        ))?
        .query_map([review], read_event)?
        .collect::<Result<_, _>>()?;
    for e in &events {
        tx.execute("UPDATE status_event SET undone = 1 WHERE id = ?1", [e.id])?;
        refresh(tx, &e.key)?;
    }
    Ok(events)
}
