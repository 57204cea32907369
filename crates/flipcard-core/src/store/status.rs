//! Item status: suspended (out of every queue until unsuspended), buried
//! (out of the queue until a given time, the start of the next study day),
//! leech (lapsed too often), as the learner and a rating change it. Every
//! change is an event in the append-only status log ([`super::status_log`]:
//! its rows, the order that decides, the time a change gets); the
//! `item_status` cache is derived from it alone and rebuilt with the card
//! states.

use std::collections::HashMap;

use chrono::{DateTime, Utc};
use rusqlite::params;

use super::codec::Ms;
use super::db::Store;
use super::error::StoreError;
use super::log::LoggedReview;
use super::status_log::{EVENT_COLUMNS, append, event_time, next_batch, read_event, refresh};
pub use super::status_log::{StatusAction, StatusEvent};
use crate::sched::{Direction, ItemKey, Rating, ReviewKind, ReviewRecord};

/// An item's status; the default is active.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ItemStatus {
    pub suspended: bool,
    /// Buried until this time (it may have passed: then it is not buried).
    pub buried_until: Option<DateTime<Utc>>,
    pub leech: bool,
}

impl ItemStatus {
    pub fn buried(&self, now: DateTime<Utc>) -> bool {
        self.buried_until.is_some_and(|t| t > now)
    }
    /// Whether the item may be shown for review at `now`.
    pub fn studyable(&self, now: DateTime<Utc>) -> bool {
        !self.suspended && !self.buried(now)
    }
}

/// What follows a rating, in the same transaction.
#[derive(Debug, Clone, PartialEq)]
pub struct AfterRating {
    /// Lapses at which an item becomes a leech (0: never).
    pub leech_threshold: u32,
    /// Suspend a new leech (else it is only marked).
    pub leech_suspend: bool,
    /// Items to bury (the siblings of the one rated), and until when.
    pub bury: Vec<ItemKey>,
    pub bury_until: DateTime<Utc>,
}

/// What [`Store::record_study`] wrote.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Recorded {
    pub id: i64,
    /// The rating made the item a leech.
    pub leech: bool,
}

/// What an undo took back.
#[derive(Debug, Clone, PartialEq)]
pub enum Undone {
    /// A rating, with the events it brought about.
    Review(LoggedReview),
    /// A change of status made by the learner (several items at once).
    Status(Vec<StatusEvent>),
}

impl Store {
    /// Writes `action` for every item of `keys` in one transaction (all or
    /// none), as one change for undo. `until` is required for a bury.
    pub fn set_status(
        &mut self,
        keys: &[ItemKey],
        action: StatusAction,
        at: DateTime<Utc>,
        until: Option<DateTime<Utc>>,
    ) -> Result<Vec<i64>, StoreError> {
        if (action == StatusAction::Bury) != until.is_some() {
            return Err(StoreError::BadRow {
                id: 0,
                detail: "a bury, and only a bury, has an end time".into(),
            });
        }
        self.write(|tx| {
            let session = tx.session()?;
            let mut ids = Vec::with_capacity(keys.len());
            let batch = next_batch(tx)?;
            let at = event_time(tx, at)?;
            let mut seen = std::collections::HashSet::with_capacity(keys.len());
            for key in keys {
                // One event an item: the same item named twice is one change.
                if !seen.insert(key) {
                    continue;
                }
                ids.push(append(tx, session, batch, key, at, action, until, None)?);
            }
            Ok(ids)
        })
    }

    /// Records a rating and what follows from it, in one transaction: the
    /// item becomes a leech when this lapse brings its lapses to the
    /// threshold (suspended too, if so configured), and its siblings are
    /// buried. Cram ratings change no status.
    pub fn record_study(
        &mut self,
        review: &ReviewRecord,
        after: &AfterRating,
    ) -> Result<Recorded, StoreError> {
        self.record_study_judged(review, after, None)
    }

    /// [`Store::record_study`] with the verdict of the prompt attempt
    /// `judged` (its row id) written in the same transaction: a prompt
    /// rated by its verdict (issue 24 §2) has both or neither on disk.
    pub fn record_study_judged(
        &mut self,
        review: &ReviewRecord,
        after: &AfterRating,
        judged: Option<(i64, &super::attempt::AttemptVerdict)>,
    ) -> Result<Recorded, StoreError> {
        super::log::validate(review)?;
        if let Some((id, v)) = judged {
            super::attempt::refuse_misconception(id, v)?;
        }
        self.write(|tx| {
            if let Some((id, v)) = judged
                && super::attempt::judge_in(tx, id, v)? == 0
            {
                return Err(StoreError::BadRow {
                    id,
                    detail: "no such prompt attempt to judge".into(),
                }
                .into());
            }
            let session = tx.session()?;
            let id = super::log::append(tx, session, review)?;
            let batch = next_batch(tx)?;
            let mut leech = false;
            if review.kind != ReviewKind::Cram {
                let at = review.reviewed_at;
                let lapse = review.kind == ReviewKind::Review && review.rating == Rating::Again;
                if lapse && after.leech_threshold > 0 {
                    let k = &review.key;
                    let (lapses, already): (i64, bool) = tx.query_row(
                        "SELECT coalesce((SELECT lapses FROM card_state WHERE deck = ?1 \
                               AND card = ?2 AND direction = ?3), 0), \
                             coalesce((SELECT leech FROM item_status WHERE deck = ?1 AND card = ?2 \
                               AND direction = ?3), 0)",
                        params![k.deck, k.card, k.direction],
                        |r| Ok((r.get(0)?, r.get::<_, i64>(1)? != 0)),
                    )?;
                    if !already && lapses >= i64::from(after.leech_threshold) {
                        leech = true;
                        append(
                            tx,
                            session,
                            batch,
                            k,
                            at,
                            StatusAction::Leech,
                            None,
                            Some(id),
                        )?;
                        if after.leech_suspend {
                            append(
                                tx,
                                session,
                                batch,
                                k,
                                at,
                                StatusAction::Suspend,
                                None,
                                Some(id),
                            )?;
                        }
                    }
                }
                let bury_at = event_time(tx, at)?;
                for sibling in after.bury.iter().filter(|s| **s != review.key) {
                    append(
                        tx,
                        session,
                        batch,
                        sibling,
                        bury_at,
                        StatusAction::Bury,
                        Some(after.bury_until),
                        Some(id),
                    )?;
                }
            }
            Ok(Recorded { id, leech })
        })
    }

    /// Takes back the last change of this session, a rating (with what it
    /// brought about) or a change of status, whichever came last.
    pub fn undo_last_change(&mut self) -> Result<Option<Undone>, StoreError> {
        let Some(session) = self.session else {
            return Ok(None);
        };
        // By the first row of each answer: a merge may have appended one
        // again, after later ones, outside this session.
        let last_review: Option<i64> = self
            .conn
            .query_row(
                "SELECT max(r.id) FROM review AS r WHERE r.session = ?1 AND r.origin IS NULL \
                   AND EXISTS (SELECT 1 FROM review AS o WHERE o.deck = r.deck \
                     AND o.card = r.card AND o.direction = r.direction \
                     AND o.reviewed_at = r.reviewed_at AND o.rating = r.rating \
                     AND o.origin IS NULL AND o.undone = 0)",
                [session],
                |r| r.get(0),
            )
            .map_err(|e| self.err(e))?;
        // The learner's own change: every event written by that one call
        // shares its batch.
        let last_status: Option<(i64, i64)> = self
            .conn
            .query_row(
                "SELECT batch, after_review FROM status_event \
                 WHERE session = ?1 AND undone = 0 AND cause IS NULL ORDER BY id DESC LIMIT 1",
                [session],
                |r| Ok((r.get(0)?, r.get(1)?)),
            )
            .map(Some)
            .or_else(|e| match e {
                rusqlite::Error::QueryReturnedNoRows => Ok(None),
                e => Err(e),
            })
            .map_err(|e| self.err(e))?;
        match (last_review, last_status) {
            (None, None) => Ok(None),
            (Some(r), Some((_, after))) if r > after => Ok(self.undo_last()?.map(Undone::Review)),
            (Some(_), None) => Ok(self.undo_last()?.map(Undone::Review)),
            (_, Some((batch, _))) => self.write(|tx| {
                let events: Vec<StatusEvent> = tx
                    .prepare(&format!(
                        "SELECT {EVENT_COLUMNS} FROM status_event WHERE session = ?1 \
                             AND undone = 0 AND batch = ?2 ORDER BY id"
                    ))?
                    .query_map(params![session, batch], read_event)?
                    .collect::<Result<_, _>>()?;
                for e in &events {
                    tx.execute("UPDATE status_event SET undone = 1 WHERE id = ?1", [e.id])?;
                    refresh(tx, &e.key)?;
                }
                Ok(Some(Undone::Status(
                    events
                        .into_iter()
                        .map(|e| StatusEvent { undone: true, ..e })
                        .collect(),
                )))
            }),
        }
    }

    /// The status of every item that has one; an item not in the map is
    /// active.
    pub fn statuses(&self) -> Result<HashMap<ItemKey, ItemStatus>, StoreError> {
        let mut st = self
            .conn
            .prepare_cached(
                "SELECT deck, card, direction, suspended, buried_until, leech FROM item_status",
            )
            .map_err(|e| self.err(e))?;
        let rows = st
            .query_map([], |r| {
                Ok((
                    ItemKey {
                        deck: r.get(0)?,
                        card: r.get(1)?,
                        direction: r.get::<_, Direction>(2)?,
                    },
                    ItemStatus {
                        suspended: r.get::<_, i64>(3)? != 0,
                        buried_until: r.get::<_, Option<Ms>>(4)?.map(|m| m.0),
                        leech: r.get::<_, i64>(5)? != 0,
                    },
                ))
            })
            .map_err(|e| self.err(e))?;
        rows.collect::<Result<_, _>>().map_err(|e| self.err(e))
    }

    /// The status of one item.
    pub fn status(&self, key: &ItemKey) -> Result<ItemStatus, StoreError> {
        Ok(self.statuses()?.remove(key).unwrap_or_default())
    }

    /// Every row of the status log of one item, in order (undone included).
    pub fn status_history(&self, key: &ItemKey) -> Result<Vec<StatusEvent>, StoreError> {
        let mut st = self
            .conn
            .prepare_cached(&format!(
                "SELECT {EVENT_COLUMNS} FROM status_event WHERE deck = ?1 AND card = ?2 \
                 AND direction = ?3 ORDER BY id"
            ))
            .map_err(|e| self.err(e))?;
        let rows = st
            .query_map(params![key.deck, key.card, key.direction], read_event)
            .map_err(|e| self.err(e))?;
        rows.collect::<Result<_, _>>().map_err(|e| self.err(e))
    }
}
