//! The merge of a sync: reviews, status events and undos from the other
//! machines' files, in one transaction (a sync killed at any point leaves
//! nothing half-merged), then the leech events every machine derives from
//! the merged answers.

use std::collections::{BTreeMap, HashMap, HashSet};

use chrono::{DateTime, Utc};
use rusqlite::params;

use super::codec::{Ms, to_ms};
use super::db::Store;
use super::error::StoreError;
use super::merge::{IncomingReview, merge_one};
use super::status_log::{self, StatusAction};
use super::tally;
use super::write::{Write, session_in};
use crate::sched::{ItemKey, Rating};

/// A review's identity across machines: item, time (ms), rating.
pub(crate) type ReviewId = (ItemKey, i64, Rating);

/// A status event's identity across machines: item, time (ms), action.
pub(crate) type StatusId = (ItemKey, i64, StatusAction);

/// One status event to merge.
#[derive(Debug, Clone, PartialEq)]
pub struct IncomingStatus {
    pub key: ItemKey,
    pub at: DateTime<Utc>,
    pub action: StatusAction,
    pub until: Option<DateTime<Utc>>,
    /// The answer that brought it about (a sibling bury).
    pub cause: Option<ReviewId>,
    pub undone: bool,
}

/// One status event that travels, once per identity and origin.
#[derive(Debug, Clone)]
pub struct LocalStatus {
    pub status: IncomingStatus,
    pub origin: Option<String>,
    pub legacy: bool,
}

impl IncomingReview {
    pub fn review_id(&self) -> ReviewId {
        (self.key.clone(), to_ms(self.reviewed_at), self.rating)
    }
}

impl IncomingStatus {
    pub(crate) fn status_id(&self) -> StatusId {
        (self.key.clone(), to_ms(self.at), self.action)
    }
}

/// What the other machines' files bring, already narrowed to what this
/// log lacks (the merge skips what it has all the same). Each review and
/// status event comes with the machine it came from, which its row keeps:
/// only that machine's undo takes it back.
#[derive(Debug, Clone, Default)]
pub struct SyncIncoming {
    pub reviews: Vec<(IncomingReview, String)>,
    pub statuses: Vec<(IncomingStatus, String)>,
    /// Answers undone by the machine they came from, live here.
    pub undo_reviews: HashSet<(ReviewId, String)>,
    /// Status events undone by the machine they came from, live here.
    pub undo_statuses: HashSet<(StatusId, String)>,
    /// Answers undone here that the folder does not show undone yet: the
    /// answers after them are replayed as the other machines will.
    pub replay: Vec<ReviewId>,
    /// Answers and status events undone here that the machine they came
    /// from has live: appended again, live.
    pub revive_reviews: Vec<(IncomingReview, String)>,
    pub revive_statuses: Vec<(IncomingStatus, String)>,
    /// This machine's rows (origin NULL) found to have come from another
    /// machine: merged before origins were kept, or written under this
    /// machine's previous id. Their origin is set, once.
    pub stamp_reviews: Vec<(ReviewId, String)>,
    pub stamp_statuses: Vec<(StatusId, String)>,
}

/// How this machine marks leeches (from its config).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct LeechRule {
    /// Lapses at which an item becomes a leech (0: never, and leech events
    /// are left as they are).
    pub threshold: u32,
    /// A new leech is suspended too.
    pub suspend: bool,
}

/// What a sync merge did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct SyncMerged {
    pub reviews: usize,
    pub statuses: usize,
    /// Answers and status events taken back because another machine
    /// undid them.
    pub undos: usize,
    /// Local answers appended again with their replayed state.
    pub replayed_local: usize,
    /// Items whose leech event was added, moved or taken back.
    pub leeches: usize,
}

impl Store {
    /// Merges `incoming` in one transaction: reviews as
    /// [`Store::merge_reviews`] does, undone ones taken back and the answers
    /// after them replayed, status events the log lacks appended (their
    /// cause found by identity), undone ones taken back; then each item's
    /// leech event is put where its live lapses first reach
    /// `leech.threshold`.
    pub(crate) fn merge_sync(
        &mut self,
        incoming: &SyncIncoming,
        scheduler: &dyn crate::sched::scheduler::ForDeck,
        leech: LeechRule,
    ) -> Result<SyncMerged, StoreError> {
        for (r, _) in &incoming.reviews {
            r.check().map_err(|detail| StoreError::BadRow {
                id: 0,
                detail: format!(
                    "incoming review ({}/{} {}): {detail}",
                    r.key.deck,
                    r.key.card,
                    r.key.direction.as_str()
                ),
            })?;
        }
        self.write(|tx| {
            let mut session = None;
            let mut out = SyncMerged::default();

            for ((k, ms, rating), origin) in &incoming.stamp_reviews {
                tx.execute(
                    "UPDATE review SET origin = ?1 WHERE deck = ?2 AND card = ?3 AND direction = ?4 \
                     AND reviewed_at = ?5 AND rating = ?6 AND origin IS NULL",
                    params![origin, k.deck, k.card, k.direction, ms, rating],
                )?;
            }
            for ((k, ms, action), origin) in &incoming.stamp_statuses {
                tx.execute(
                    "UPDATE status_event SET origin = ?1 WHERE deck = ?2 AND card = ?3 \
                     AND direction = ?4 AND at = ?5 AND action = ?6 AND origin IS NULL",
                    params![origin, k.deck, k.card, k.direction, ms, action.as_str()],
                )?;
            }

            type Work<'a> = (
                Vec<(&'a IncomingReview, Option<&'a str>)>,
                HashSet<(i64, Rating, String)>,
                Option<DateTime<Utc>>,
                HashSet<(i64, Rating, String)>,
            );
            let mut by_item: BTreeMap<&ItemKey, Work> = BTreeMap::new();
            for (r, origin) in &incoming.reviews {
                by_item
                    .entry(&r.key)
                    .or_default()
                    .0
                    .push((r, Some(origin.as_str())));
            }
            for (r, origin) in &incoming.revive_reviews {
                let w = by_item.entry(&r.key).or_default();
                w.0.push((r, Some(origin.as_str())));
                let (ms, rating) = (to_ms(r.reviewed_at), r.rating);
                w.3.insert((ms, rating, origin.clone()));
            }
            for ((key, ms, rating), origin) in &incoming.undo_reviews {
                by_item
                    .entry(key)
                    .or_default()
                    .1
                    .insert((*ms, *rating, origin.clone()));
            }
            for (key, ms, _) in &incoming.replay {
                let at = DateTime::from_timestamp_millis(*ms).unwrap_or_default();
                let w = by_item.entry(key).or_default();
                w.2 = Some(w.2.map_or(at, |t| t.min(at)));
            }
            let mut reviews_changed = false;
            for (key, (rows, undo, replay_from, revive)) in &by_item {
                let m = merge_one(
                    tx,
                    &mut session,
                    key,
                    rows,
                    undo,
                    revive,
                    *replay_from,
                    true,
                    scheduler,
                    None,
                )?;
                out.reviews += m.added;
                out.undos += m.undone;
                out.replayed_local += m.replayed_local;
                reviews_changed |= m.added + m.undone + m.replayed_local > 0;
            }

            for (s, origin) in &incoming.revive_statuses {
                let session = session_in(tx, &mut session)?;
                let batch = status_log::next_batch(tx)?;
                let id = status_log::append(tx, session, batch, &s.key, s.at, s.action, s.until, None)?;
                tx.execute(
                    "UPDATE status_event SET origin = ?1 WHERE id = ?2",
                    params![origin, id],
                )?;
                out.statuses += 1;
            }
            for (s, origin) in &incoming.statuses {
                let (n, undone) = merge_status(tx, &mut session, s, origin, &incoming.undo_statuses)?;
                out.statuses += n;
                out.undos += usize::from(undone && !s.undone);
            }
            for ((key, ms, action), origin) in &incoming.undo_statuses {
                let n = tx
                    .execute(
                        "UPDATE status_event SET undone = 1 WHERE deck = ?1 AND card = ?2 \
                         AND direction = ?3 AND at = ?4 AND action = ?5 AND origin = ?6 \
                         AND undone = 0",
                        params![
                            key.deck,
                            key.card,
                            key.direction,
                            ms,
                            action.as_str(),
                            origin
                        ],
                    )?;
                if n > 0 {
                    status_log::refresh(tx, key)?;
                    out.undos += 1;
                }
            }
            if leech.threshold > 0 {
                out.leeches = derive_leeches(tx, &mut session, leech)?;
            }
            if reviews_changed {
                tally::rebuild(tx)?;
            }
            Ok(out)
        })
    }

    /// The status events that travel (every one but leech events and the
    /// suspend of a new leech, which each machine derives), once each: live
    /// when any row with its identity is; with the machine each came from.
    pub(crate) fn travelling_statuses(&self) -> Result<Vec<LocalStatus>, StoreError> {
        let mut st = self
            .conn
            .prepare(
                "SELECT e.deck, e.card, e.direction, e.at, e.action, e.until, e.undone, \
                        r.deck, r.card, r.direction, r.reviewed_at, r.rating, e.origin, \
                        e.id <= (SELECT status_max FROM sync_legacy) \
                 FROM status_event AS e LEFT JOIN review AS r ON r.id = e.cause \
                 WHERE e.action IN ('suspend', 'unsuspend', 'bury') \
                   AND NOT (e.action = 'suspend' AND e.cause IS NOT NULL) \
                 ORDER BY e.id",
            )
            .map_err(|e| self.err(e))?;
        let rows = st
            .query_map([], |r| {
                let key = ItemKey {
                    deck: r.get(0)?,
                    card: r.get(1)?,
                    direction: r.get(2)?,
                };
                let action: String = r.get(4)?;
                let cause = match r.get::<_, Option<String>>(7)? {
                    Some(deck) => Some((
                        ItemKey {
                            deck,
                            card: r.get(8)?,
                            direction: r.get(9)?,
                        },
                        r.get::<_, Ms>(10)?.0.timestamp_millis(),
                        r.get::<_, Rating>(11)?,
                    )),
                    None => None,
                };
                Ok(LocalStatus {
                    status: IncomingStatus {
                        key,
                        at: r.get::<_, Ms>(3)?.0,
                        action: StatusAction::parse(&action).unwrap_or(StatusAction::Suspend),
                        until: r.get::<_, Option<Ms>>(5)?.map(|m| m.0),
                        cause,
                        undone: r.get::<_, i64>(6)? != 0,
                    },
                    origin: r.get(12)?,
                    legacy: r.get::<_, Option<bool>>(13)?.unwrap_or(false),
                })
            })
            .map_err(|e| self.err(e))?;
        let mut order: Vec<(StatusId, Option<String>)> = Vec::new();
        let mut by_id: HashMap<(StatusId, Option<String>), LocalStatus> = HashMap::new();
        for row in rows {
            let s = row.map_err(|e| self.err(e))?;
            let id = (s.status.status_id(), s.origin.clone());
            match by_id.get_mut(&id) {
                Some(e) => e.status.undone &= s.status.undone,
                None => {
                    order.push(id.clone());
                    by_id.insert(id, s);
                }
            }
        }
        Ok(order
            .into_iter()
            .filter_map(|id| by_id.remove(&id))
            .collect())
    }
}

/// Appends one incoming status event unless one with its identity is in
/// the log; returns (events appended, whether it was appended undone).
fn merge_status(
    tx: &Write<'_>,
    session: &mut Option<i64>,
    s: &IncomingStatus,
    origin: &str,
    undo: &HashSet<(StatusId, String)>,
) -> rusqlite::Result<(usize, bool)> {
    let k = &s.key;
    let present: bool = tx
        .prepare_cached(
            "SELECT EXISTS (SELECT 1 FROM status_event WHERE deck = ?1 AND card = ?2 \
             AND direction = ?3 AND at = ?4 AND action = ?5 AND origin = ?6)",
        )?
        .query_row(
            params![
                k.deck,
                k.card,
                k.direction,
                Ms(s.at),
                s.action.as_str(),
                origin
            ],
            |r| r.get(0),
        )?;
    if present {
        return Ok((0, false));
    }
    let cause: Option<i64> = match &s.cause {
        Some((ck, ms, rating)) => tx
            .prepare_cached(
                "SELECT id FROM review WHERE deck = ?1 AND card = ?2 AND direction = ?3 \
                 AND reviewed_at = ?4 AND rating = ?5 \
                 ORDER BY origin IS ?6 DESC, undone, id DESC LIMIT 1",
            )?
            .query_row(
                params![ck.deck, ck.card, ck.direction, ms, rating, origin],
                |r| r.get(0),
            )
            .map(Some)
            .or_else(|e| match e {
                rusqlite::Error::QueryReturnedNoRows => Ok(None),
                e => Err(e),
            })?,
        None => None,
    };
    let session = session_in(tx, session)?;
    let batch = status_log::next_batch(tx)?;
    let id = status_log::append(tx, session, batch, k, s.at, s.action, s.until, cause)?;
    tx.execute(
        "UPDATE status_event SET origin = ?1 WHERE id = ?2",
        params![origin, id],
    )?;
    let undone = s.undone || undo.contains(&(s.status_id(), origin.to_string()));
    if undone {
        tx.execute("UPDATE status_event SET undone = 1 WHERE id = ?1", [id])?;
        status_log::refresh(tx, k)?;
    }
    Ok((1, undone))
}

/// Puts each item's leech event at the answer where its live lapses first
/// reach the threshold, the rule a rating follows as it is recorded: a
/// leech event elsewhere (the lapses of two machines' histories combined
/// cross earlier, or an undo took the crossing back) is taken back with
/// the suspend it brought, and the right one appended. Returns how many
/// items changed.
fn derive_leeches(
    tx: &Write<'_>,
    session: &mut Option<i64>,
    rule: LeechRule,
) -> rusqlite::Result<usize> {
    // Where each item's live lapses reach the threshold: (review id, time).
    let mut crossing: HashMap<ItemKey, (i64, i64)> = HashMap::new();
    {
        let mut st = tx.prepare(&format!(
            "SELECT deck, card, direction, id, reviewed_at FROM ( \
               SELECT id, deck, card, direction, reviewed_at, kind, rating, \
                 sum(kind = 'review' AND rating = {again}) OVER (PARTITION BY deck, card, \
                   direction ORDER BY reviewed_at, id ROWS UNBOUNDED PRECEDING) AS lapses \
               FROM review WHERE undone = 0 AND kind <> 'cram') \
             WHERE lapses = ?1 AND kind = 'review' AND rating = {again}",
            again = Rating::Again as i64
        ))?;
        let rows = st.query_map([rule.threshold], |r| {
            Ok((
                ItemKey {
                    deck: r.get(0)?,
                    card: r.get(1)?,
                    direction: r.get(2)?,
                },
                (r.get::<_, i64>(3)?, r.get::<_, i64>(4)?),
            ))
        })?;
        for row in rows {
            let (k, c) = row?;
            crossing.insert(k, c);
        }
    }
    // The live derived events: (event id, action, time, cause's time).
    type Derived = (i64, String, i64, Option<i64>);
    let mut derived: HashMap<ItemKey, Vec<Derived>> = HashMap::new();
    {
        let mut st = tx.prepare(
            "SELECT e.deck, e.card, e.direction, e.id, e.action, e.at, r.reviewed_at \
             FROM status_event AS e LEFT JOIN review AS r ON r.id = e.cause \
             WHERE e.undone = 0 AND (e.action = 'leech' \
               OR (e.action = 'suspend' AND e.cause IS NOT NULL))",
        )?;
        let rows = st.query_map([], |r| {
            Ok((
                ItemKey {
                    deck: r.get(0)?,
                    card: r.get(1)?,
                    direction: r.get(2)?,
                },
                (r.get(3)?, r.get(4)?, r.get(5)?, r.get(6)?),
            ))
        })?;
        for row in rows {
            let (k, e) = row?;
            derived.entry(k).or_default().push(e);
        }
    }
    let mut keys: Vec<&ItemKey> = crossing.keys().chain(derived.keys()).collect();
    keys.sort();
    keys.dedup();
    let mut changed = 0;
    for key in keys {
        let want = crossing.get(key);
        let have = derived.get(key).map(Vec::as_slice).unwrap_or_default();
        let leeches: Vec<_> = have.iter().filter(|e| e.1 == "leech").collect();
        let right = match want {
            Some((_, at)) => leeches.len() == 1 && leeches[0].2 == *at && leeches[0].3 == Some(*at),
            None => leeches.is_empty(),
        };
        if right {
            continue;
        }
        changed += 1;
        for e in have {
            tx.execute("UPDATE status_event SET undone = 1 WHERE id = ?1", [e.0])?;
        }
        if let Some((cause, at)) = want {
            let at = DateTime::from_timestamp_millis(*at).unwrap_or_default();
            let session = session_in(tx, session)?;
            let batch = status_log::next_batch(tx)?;
            status_log::append(
                tx,
                session,
                batch,
                key,
                at,
                StatusAction::Leech,
                None,
                Some(*cause),
            )?;
            if rule.suspend {
                status_log::append(
                    tx,
                    session,
                    batch,
                    key,
                    at,
                    StatusAction::Suspend,
                    None,
                    Some(*cause),
                )?;
            }
        }
        status_log::refresh(tx, key)?;
    }
    Ok(changed)
}
