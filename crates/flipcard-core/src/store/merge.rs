//! Merging a review history from elsewhere (an export from another
//! machine, a synced copy, an Anki collection) into the log.
//!
//! A review is the same review when deck, card, direction, review time (to
//! the millisecond) and rating agree; such rows are skipped, so merging the
//! same history twice changes nothing. The states are then rebuilt by
//! replaying every touched item's ratings in time order through the
//! scheduler, since the stored states of two interleaved histories were each
//! computed without the other's answers.
//!
//! The log stays append-only: a local answer that an incoming, earlier one
//! now precedes is not rewritten but marked undone and appended again with
//! its replayed state, after the incoming rows (an undo in the session
//! that gave the answer follows it there: see `Store::undo_last`). Afterwards each item's live
//! rows are in time order by id, so the card-state cache (the last live row)
//! and `flipcard db rebuild` agree with the replay.

use std::collections::{BTreeMap, HashSet};

use chrono::{DateTime, Utc};
use rusqlite::{Transaction, params};

use super::codec::to_ms;
use super::db::Store;
use super::error::StoreError;
use super::kept::KeptState;
use super::log::insert_row;
use super::log::{COLUMNS, LoggedReview, read_logged};
use super::write::{Failed, Write, session_in};
use super::{state, tally};
use crate::sched::scheduler::ForDeck;
use crate::sched::{CardState, ItemKey, Rating, ReviewKind};

/// One review to merge: what was answered, when and how. Its state after
/// the answer is not taken from the source but replayed.
#[derive(Debug, Clone, PartialEq)]
pub struct IncomingReview {
    pub key: ItemKey,
    pub reviewed_at: DateTime<Utc>,
    pub rating: Rating,
    /// A cram answer stays one (logged, no effect on scheduling); any other
    /// kind is recomputed from the replayed state before the answer.
    pub cram: bool,
    pub duration_ms: i64,
    /// Undone where it comes from: kept, and undone here too.
    pub undone: bool,
    /// The interval the load balancer of the machine that gave the answer
    /// chose (`ReviewRecord::balanced_days`): the replay takes it when the
    /// answer's fuzz range allows it ([`crate::sched::Scheduler::replay`]).
    pub balanced_days: Option<i64>,
}

/// What a merge did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MergeSummary {
    /// Rows offered.
    pub offered: usize,
    /// Rows appended (undone ones included).
    pub added: usize,
    /// Of those, rows that came undone.
    pub added_undone: usize,
    /// Rows already in the log (or repeated in the input), skipped.
    pub duplicates: usize,
    /// Local answers that incoming ones now precede, appended again after
    /// them with their replayed state (the earlier row is marked undone).
    pub replayed_local: usize,
    /// Items whose state was rebuilt.
    pub items: usize,
}

/// The identity of a review across machines.
pub(super) type Identity = (i64, Rating);

impl IncomingReview {
    pub(super) fn identity(&self) -> Identity {
        (to_ms(self.reviewed_at), self.rating)
    }

    /// Refused before anything is written: what the log cannot hold.
    pub(super) fn check(&self) -> Result<(), Unfit> {
        if self.key.deck.is_empty() || self.key.card.is_empty() {
            return Err(Unfit::EmptyId);
        }
        if self.duration_ms < 0 {
            return Err(Unfit::NegativeDuration(self.duration_ms));
        }
        Ok(())
    }
}

/// What the log cannot hold of an incoming answer.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub(super) enum Unfit {
    #[error("empty deck or card id")]
    EmptyId,
    #[error("negative duration {0} ms")]
    NegativeDuration(i64),
}

impl Store {
    /// Merges `rows` into the log in one transaction (nothing is written
    /// when any row is refused) and rebuilds the state of every item they
    /// touch by replaying its answers in time order with `scheduler` (one
    /// for every deck, or each deck's: [`crate::sched::Schedulers`]).
    pub fn merge_reviews(
        &mut self,
        rows: &[IncomingReview],
        scheduler: &dyn ForDeck,
    ) -> Result<MergeSummary, StoreError> {
        self.merge_reviews_keeping(rows, scheduler, &std::collections::HashMap::new())
    }

    /// [`Store::merge_reviews`], where the items of `kept` take the state
    /// given there (due date, interval, memory state) at its time rather
    /// than the replayed one, and keep it as the base later merges replay
    /// from. An item of `kept` with no answer in `rows` takes it as its
    /// state, unless this log already has answers of it (its own state
    /// then stands).
    pub fn merge_reviews_keeping(
        &mut self,
        rows: &[IncomingReview],
        scheduler: &dyn ForDeck,
        kept: &std::collections::HashMap<ItemKey, KeptState>,
    ) -> Result<MergeSummary, StoreError> {
        for (i, r) in rows.iter().enumerate() {
            r.check().map_err(|detail| StoreError::BadRow {
                id: 0,
                detail: format!(
                    "incoming review {} ({}/{} {}): {detail}",
                    i + 1,
                    r.key.deck,
                    r.key.card,
                    r.key.direction.as_str()
                ),
            })?;
        }
        let mut by_item: BTreeMap<&ItemKey, Vec<&IncomingReview>> = BTreeMap::new();
        for r in rows {
            by_item.entry(&r.key).or_default().push(r);
        }
        let mut summary = MergeSummary {
            offered: rows.len(),
            ..MergeSummary::default()
        };
        self.write(|tx| {
            // Its own session, not adopted by this store: an undo in the app
            // must not reach into a merged history.
            let mut session = None;
            let none = HashSet::new();
            for (key, k) in kept {
                if !by_item.contains_key(key) && item_rows(tx, key)??.iter().any(|l| !l.undone) {
                    continue;
                }
                super::kept::put(tx, key, k)?;
            }
            for (key, incoming) in by_item {
                // Answers imported here are this machine's to publish.
                let incoming: Vec<_> = incoming.into_iter().map(|r| (r, None)).collect();
                let m = merge_one(
                    tx,
                    &mut session,
                    key,
                    &incoming,
                    &none,
                    &none,
                    None,
                    false,
                    scheduler,
                    kept.get(key),
                )?;
                summary.added += m.added;
                summary.added_undone += m.added_undone;
                summary.duplicates += m.duplicates;
                summary.replayed_local += m.replayed_local;
                summary.items += usize::from(m.added > 0);
            }
            if summary.added > 0 {
                tally::rebuild(tx)?;
            }
            Ok(summary)
        })
    }
}

/// What merging one item did.
#[derive(Debug, Default)]
pub(super) struct ItemMerge {
    pub added: usize,
    pub added_undone: usize,
    pub duplicates: usize,
    /// Local answers appended again with their replayed state.
    pub replayed_local: usize,
    /// Local answers taken back because the source undid them.
    pub undone: usize,
}

/// An answer taken back by the machine it came from: time (ms), rating
/// and that machine.
pub(super) type UndoneBy = (i64, Rating, String);

/// Merges into one item: `incoming` answers it lacks are appended, its
/// live answers named in `undo` (time in ms, rating, the machine they came
/// from) are taken back with the status events they brought about, and
/// every live answer from the earliest change on (or from `replay_from`, an
/// answer undone here that others have not seen undone yet) is replayed, so
/// the item's states are the replay of its live answers in time order.
/// `session` is made on the first write. An answer named in `revive` is
/// appended again, live, although an undone row of it is in the log (its
/// machine has it live). Each incoming answer comes with
/// the machine it came from (`None`: this one), which its row keeps, as a
/// replayed row keeps its original's. With `by_origin`, an answer is the
/// same answer only when it also came from the same machine (a sync: two
/// machines may answer alike in one millisecond); without (an import), any
/// row of the same time and rating is it.
#[allow(clippy::too_many_arguments)]
pub(super) fn merge_one(
    tx: &Write<'_>,
    session: &mut Option<i64>,
    key: &ItemKey,
    incoming: &[(&IncomingReview, Option<&str>)],
    undo: &HashSet<UndoneBy>,
    revive: &HashSet<UndoneBy>,
    replay_from: Option<DateTime<Utc>>,
    by_origin: bool,
    scheduler: &dyn ForDeck,
    kept: Option<&KeptState>,
) -> Result<ItemMerge, Failed> {
    let mut out = ItemMerge::default();
    let stored = match kept {
        Some(_) => None,
        None => super::kept::get(tx, key)?,
    };
    let kept = kept.or(stored.as_ref());
    let existing = item_rows(tx, key)??;
    let origins = item_origins(tx, key)?;
    let origin_of = |l: &LoggedReview| origins.get(&l.id).cloned();
    let same = |origin: Option<String>| if by_origin { origin } else { None };
    let mut seen: HashSet<(i64, Rating, Option<String>)> = existing
        .iter()
        .map(|l| {
            (
                to_ms(l.record.reviewed_at),
                l.record.rating,
                same(origin_of(l)),
            )
        })
        .collect();
    let mut fresh: Vec<(IncomingReview, Option<&str>)> = Vec::new();
    for (r, origin) in incoming {
        let (ms, rating) = r.identity();
        let again = origin.is_some_and(|o| revive.contains(&(ms, rating, o.to_string())));
        if seen.insert((ms, rating, same(origin.map(str::to_string)))) || again {
            let undone =
                r.undone || origin.is_some_and(|o| undo.contains(&(ms, rating, o.to_string())));
            fresh.push((
                IncomingReview {
                    undone,
                    ..(*r).clone()
                },
                *origin,
            ));
        } else {
            out.duplicates += 1;
        }
    }
    let mut t0 = fresh.iter().map(|(r, _)| r.reviewed_at).min();
    let mut taken_back: HashSet<i64> = HashSet::new();
    if !undo.is_empty() {
        for l in &existing {
            let Some(origin) = origin_of(l) else {
                continue;
            };
            if !undo.contains(&(to_ms(l.record.reviewed_at), l.record.rating, origin)) {
                continue;
            }
            // A copy an earlier merge re-appended may carry the events
            // the answer brought about.
            super::status_log::undo_caused(tx, l.id)?;
            if !l.undone {
                tx.execute("UPDATE review SET undone = 1 WHERE id = ?1", [l.id])?;
                taken_back.insert(l.id);
                t0 = Some(t0.map_or(l.record.reviewed_at, |t| t.min(l.record.reviewed_at)));
            }
        }
    }
    out.undone = taken_back.len();
    if let Some(t) = replay_from {
        t0 = Some(t0.map_or(t, |t0| t0.min(t)));
    }
    let Some(t0) = t0 else {
        return Ok(out);
    };
    let live: Vec<&LoggedReview> = existing
        .iter()
        .filter(|l| !l.undone && !taken_back.contains(&l.id))
        .collect();
    let session_id = match *session {
        Some(s) => s,
        None => session_in(tx, session)?,
    };
    out.replayed_local = merge_item(
        tx, session_id, key, live, &fresh, &origins, t0, scheduler, kept,
    )?;
    out.added = fresh.len();
    out.added_undone = fresh.iter().filter(|(r, _)| r.undone).count();
    state::refresh_item(tx, key)?;
    Ok(out)
}

/// One answer in the replay: a local live row or an incoming one.
struct Step<'a> {
    at: DateTime<Utc>,
    /// Local rows first among equal times and ratings (there is only one
    /// answer of an identity: a tie breaker that never decides).
    incoming: bool,
    rating: Rating,
    cram: bool,
    duration_ms: i64,
    undone: bool,
    /// The local row this step may re-append, to be marked undone.
    local: Option<&'a LoggedReview>,
    /// The machine the answer came from (`None`: this one).
    origin: Option<&'a str>,
    /// The day its load balancer chose, if it did.
    balanced_days: Option<i64>,
}

/// Appends `fresh` and replays the live local answers after `t0` from the
/// last live answer not after it. A local answer whose replay gives back
/// the row it has stays as it is, as long as nothing was appended before
/// it (so each item's live rows stay in time order by id); the others are
/// marked undone and appended again. Returns how many were re-appended.
#[allow(clippy::too_many_arguments)]
fn merge_item<'a>(
    tx: &Transaction<'_>,
    session: i64,
    key: &ItemKey,
    mut live: Vec<&'a LoggedReview>,
    fresh: &'a [(IncomingReview, Option<&'a str>)],
    origins: &'a std::collections::HashMap<i64, String>,
    t0: DateTime<Utc>,
    scheduler: &dyn ForDeck,
    kept: Option<&KeptState>,
) -> Result<usize, Failed> {
    // The item's deck's scheduler (its preset's, when it has one).
    let scheduler = scheduler.for_deck(&key.deck);
    live.sort_by_key(|l| (l.record.reviewed_at, l.id));
    // The state to replay from: the last live, non-cram local answer before
    // the earliest change (one of the same millisecond is replayed with the
    // incoming ones, in the order every machine uses).
    let mut state: Option<CardState> = live
        .iter()
        .rfind(|l| l.record.reviewed_at < t0 && l.record.kind != ReviewKind::Cram)
        .map(|l| l.record.after);
    let mut steps: Vec<Step> = live
        .iter()
        .filter(|l| l.record.reviewed_at >= t0)
        .map(|l| Step {
            at: l.record.reviewed_at,
            incoming: false,
            rating: l.record.rating,
            cram: l.record.kind == ReviewKind::Cram,
            duration_ms: l.record.duration_ms,
            undone: false,
            local: Some(l),
            origin: origins.get(&l.id).map(String::as_str),
            balanced_days: l.record.balanced_days,
        })
        .collect();
    steps.extend(fresh.iter().map(|(r, origin)| Step {
        at: r.reviewed_at,
        incoming: true,
        rating: r.rating,
        cram: r.cram,
        duration_ms: r.duration_ms,
        undone: r.undone,
        local: None,
        origin: *origin,
        balanced_days: r.balanced_days,
    }));
    // In time order; answers of the same millisecond (two machines, or a
    // frozen clock) by rating, so every machine replays them alike.
    steps.sort_by_key(|s| (s.at, s.rating, s.cram, s.incoming));
    // The step whose state is kept: the last that counts up to the kept
    // state's time. With none (every answer replayed here came after it),
    // the replay starts from the kept state itself when no earlier answer
    // of the log gives one.
    let keep_at = kept.and_then(|k| {
        steps
            .iter()
            .rposition(|s| !s.cram && !s.undone && s.at <= k.at)
    });
    if keep_at.is_none()
        && state.is_none()
        && let Some(k) = kept
    {
        state = Some(k.base());
    }

    let mut appended = false;
    let mut relocated = 0;
    for (i, s) in steps.iter().enumerate() {
        let record = if s.cram {
            scheduler.cram(key, state.as_ref(), s.rating, s.at, s.duration_ms)
        } else {
            let mut r = scheduler.replay(
                key,
                state.as_ref(),
                s.rating,
                s.at,
                s.duration_ms,
                s.balanced_days,
            );
            if keep_at == Some(i)
                && let Some(k) = kept
            {
                k.apply(&mut r);
            }
            // An undone answer keeps the state it gave, as the log recorded
            // it, but the next answer starts from the state it found.
            if !s.undone {
                state = Some(r.after);
            }
            r
        };
        if s.local.is_some_and(|l| !appended && l.record == record) {
            continue;
        }
        super::log::validate(&record)?;
        if let Some(l) = s.local {
            tx.execute("UPDATE review SET undone = 1 WHERE id = ?1", [l.id])?;
            relocated += 1;
        }
        appended = true;
        insert_row(tx, session, &record, s.undone, s.origin)?;
    }
    Ok(relocated)
}

/// The machine each of an item's rows came from, for the rows merged from
/// another.
fn item_origins(
    tx: &Transaction<'_>,
    key: &ItemKey,
) -> rusqlite::Result<std::collections::HashMap<i64, String>> {
    let mut st = tx.prepare_cached(
        "SELECT id, origin FROM review WHERE deck = ?1 AND card = ?2 AND direction = ?3 \
         AND origin IS NOT NULL",
    )?;
    let rows = st.query_map(params![key.deck, key.card, key.direction.as_str()], |r| {
        Ok((r.get(0)?, r.get(1)?))
    })?;
    rows.collect()
}

/// Every row of one item (undone ones included), in id order.
fn item_rows(
    tx: &Transaction<'_>,
    key: &ItemKey,
) -> rusqlite::Result<Result<Vec<LoggedReview>, StoreError>> {
    let mut st = tx.prepare_cached(&format!(
        "SELECT {COLUMNS} FROM review WHERE deck = ?1 AND card = ?2 AND direction = ?3 ORDER BY id"
    ))?;
    let mut rows = st.query(params![key.deck, key.card, key.direction.as_str()])?;
    let mut out = Vec::new();
    while let Some(row) = rows.next()? {
        match read_logged(row)? {
            Ok(l) => out.push(l),
            Err(e) => return Ok(Err(e)),
        }
    }
    Ok(Ok(out))
}
