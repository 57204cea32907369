//! Review records for the store tests: hand-made ones and random histories,
//! and ratings stored the way the app stores them (`record_study`, with the
//! leech and bury events they bring about) with a check of the log against
//! that rule. The store takes the scheduler's output as given, so the
//! values here only need to be well-formed, not what FSRS would compute.

#![allow(dead_code)]

use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};

use chrono::{DateTime, Duration, Utc};
use flipcard::sched::{CardState, Direction, ItemKey, Rating, ReviewKind, ReviewRecord, State};
use flipcard::store::{AfterRating, LoggedReview, StatusAction, StatusEvent, Store, StoreError};
use rand::Rng;

pub fn at(s: &str) -> DateTime<Utc> {
    DateTime::parse_from_rfc3339(s)
        .expect("test time")
        .with_timezone(&Utc)
}

pub fn key(deck: &str, card: &str) -> ItemKey {
    ItemKey {
        deck: deck.into(),
        card: card.into(),
        direction: Direction::Forward,
    }
}

pub fn back_key(deck: &str, card: &str) -> ItemKey {
    ItemKey {
        direction: Direction::Backward,
        ..key(deck, card)
    }
}

/// A rating at `when` leaving the item in `state`, due `due_in` later.
pub fn review(
    key: &ItemKey,
    when: DateTime<Utc>,
    rating: Rating,
    kind: ReviewKind,
    state: State,
    due_in: Duration,
) -> ReviewRecord {
    ReviewRecord {
        key: key.clone(),
        reviewed_at: when,
        rating,
        kind,
        elapsed_days: 0,
        scheduled_days: due_in.num_days(),
        after: CardState {
            state,
            step: matches!(state, State::Learning | State::Relearning).then_some(0),
            stability: Some(2.5),
            difficulty: Some(5.0),
            due: when + due_in,
            last_review: Some(when),
        },
        duration_ms: 4_000,
        balanced_days: None,
    }
}

/// A well-formed rating with random values (millisecond times, as stored).
pub fn random_review(rng: &mut impl Rng, key: &ItemKey, when: DateTime<Utc>) -> ReviewRecord {
    let rating = Rating::ALL[rng.random_range(0..4)];
    let kind = [
        ReviewKind::Learn,
        ReviewKind::Review,
        ReviewKind::Relearn,
        ReviewKind::Cram,
    ][rng.random_range(0..4)];
    let state = [State::Learning, State::Review, State::Relearning][rng.random_range(0..3)];
    let due = when + Duration::milliseconds(rng.random_range(60_000..90 * 86_400_000));
    ReviewRecord {
        key: key.clone(),
        reviewed_at: when,
        rating,
        kind,
        elapsed_days: rng.random_range(0..40),
        scheduled_days: rng.random_range(0..90),
        after: CardState {
            state,
            step: (state != State::Review).then(|| rng.random_range(0..3)),
            stability: Some(rng.random_range(0.1..300.0)),
            difficulty: Some(rng.random_range(1.0..10.0)),
            due,
            last_review: Some(when),
        },
        duration_ms: rng.random_range(300..60_000),
        balanced_days: None,
    }
}

// ---------------------------------------------------------------------------
// What follows a rating: the path the app takes to store one is
// `Store::record_study`, which writes the rating together with the status
// events it brings about (the item made a leech, and suspended, at the
// lapse that reaches the threshold; its sibling buried). The tests that
// kill writers and replay random histories use these to drive that path
// and to check the log against the rule.
// ---------------------------------------------------------------------------

/// Lapses at which an item becomes a leech, in the store tests.
pub const LEECH_AT: u32 = 2;

/// The other direction of the same card.
pub fn sibling(key: &ItemKey) -> ItemKey {
    ItemKey {
        direction: match key.direction {
            Direction::Forward => Direction::Backward,
            _ => Direction::Forward,
        },
        ..key.clone()
    }
}

/// What the app passes with a rating of `key` at `at` (as
/// `Services::after_rating` builds it): leeches at [`LEECH_AT`] lapses,
/// suspended; the sibling buried for a day.
pub fn after_rating(key: &ItemKey, at: DateTime<Utc>) -> AfterRating {
    AfterRating {
        leech_threshold: LEECH_AT,
        leech_suspend: true,
        bury: vec![key.clone(), sibling(key)],
        bury_until: at + Duration::days(1),
    }
}

/// A rating as the app stores it: a lapse (kind review, rating again) when
/// `lapse`, else a good review, or a cram rating (which changes no status).
pub fn study(key: &ItemKey, when: DateTime<Utc>, lapse: bool, cram: bool) -> ReviewRecord {
    let (rating, kind) = match (cram, lapse) {
        (true, _) => (Rating::Again, ReviewKind::Cram),
        (false, true) => (Rating::Again, ReviewKind::Review),
        (false, false) => (Rating::Good, ReviewKind::Review),
    };
    review(
        key,
        when,
        rating,
        kind,
        if lapse {
            State::Relearning
        } else {
            State::Review
        },
        Duration::minutes(10),
    )
}

/// What [`check_consequences`] found: live events by action.
#[derive(Debug, Default, Clone, Copy)]
pub struct Consequences {
    pub leeches: usize,
    pub suspends: usize,
    pub buries: usize,
}

/// Checks the status log against the ratings, as the rule says: each live
/// rating (in log order, which for one item is the order it was rated in)
/// has exactly the events it brings about, live; an undone rating has all
/// of its events undone; no event is without its rating. The cached
/// statuses agree (leech, suspended, buried until the latest bury).
pub fn check_consequences(store: &Store) -> Result<Consequences, String> {
    let mut ratings: Vec<LoggedReview> = Vec::new();
    store
        .each_review(|r| -> Result<(), StoreError> {
            ratings.push(r);
            Ok(())
        })
        .map_err(|e| e.to_string())?;
    let mut keys: BTreeSet<ItemKey> = BTreeSet::new();
    for r in &ratings {
        keys.insert(r.record.key.clone());
        keys.insert(sibling(&r.record.key));
    }
    // Every event, by the rating that caused it.
    let mut by_cause: BTreeMap<i64, Vec<StatusEvent>> = BTreeMap::new();
    for key in &keys {
        for e in store.status_history(key).map_err(|e| e.to_string())? {
            let Some(cause) = e.cause else {
                return Err(format!("event {} of {key:?} has no cause", e.id));
            };
            by_cause.entry(cause).or_default().push(e);
        }
    }
    let ids: BTreeSet<i64> = ratings.iter().map(|r| r.id).collect();
    if let Some(orphan) = by_cause.keys().find(|c| !ids.contains(c)) {
        return Err(format!(
            "events caused by rating {orphan}, which is not in the log"
        ));
    }

    let mut lapses: HashMap<ItemKey, u32> = HashMap::new();
    let mut leech: HashSet<ItemKey> = HashSet::new();
    let mut suspended: HashSet<ItemKey> = HashSet::new();
    let mut buried: HashMap<ItemKey, DateTime<Utc>> = HashMap::new();
    let mut found = Consequences::default();
    for r in &ratings {
        let key = &r.record.key;
        let events = by_cause.remove(&r.id).unwrap_or_default();
        let mut got: Vec<(ItemKey, StatusAction, bool)> = events
            .iter()
            .map(|e| (e.key.clone(), e.action, e.undone))
            .collect();
        got.sort_by(|a, b| (&a.0, a.1.as_str()).cmp(&(&b.0, b.1.as_str())));
        let cram = r.record.kind == ReviewKind::Cram;
        if r.undone {
            // Whatever it brought about was taken back with it; the bury
            // of its sibling it always brought about.
            if let Some(live) = events.iter().find(|e| !e.undone) {
                return Err(format!(
                    "rating {} is undone but its {} of {:?} is not",
                    r.id,
                    live.action.as_str(),
                    live.key
                ));
            }
            let bury = events.iter().any(|e| e.action == StatusAction::Bury);
            if bury == cram {
                return Err(format!(
                    "undone rating {} (cram: {cram}) has events {got:?}",
                    r.id
                ));
            }
            continue;
        }
        let mut want: Vec<(ItemKey, StatusAction, bool)> = Vec::new();
        if !cram {
            let lapse = r.record.kind == ReviewKind::Review && r.record.rating == Rating::Again;
            if lapse {
                let n = lapses.entry(key.clone()).or_default();
                *n += 1;
                if *n >= LEECH_AT && leech.insert(key.clone()) {
                    want.push((key.clone(), StatusAction::Leech, false));
                    want.push((key.clone(), StatusAction::Suspend, false));
                    suspended.insert(key.clone());
                    found.leeches += 1;
                    found.suspends += 1;
                }
            }
            want.push((sibling(key), StatusAction::Bury, false));
            found.buries += 1;
            let until = r.record.reviewed_at + Duration::days(1);
            let latest = buried.entry(sibling(key)).or_insert(until);
            *latest = (*latest).max(until);
        }
        want.sort_by(|a, b| (&a.0, a.1.as_str()).cmp(&(&b.0, b.1.as_str())));
        if got != want {
            return Err(format!(
                "rating {} of {key:?} ({:?} {:?}) has events {got:?}, the rule says {want:?}",
                r.id, r.record.kind, r.record.rating
            ));
        }
    }
    let statuses = store.statuses().map_err(|e| e.to_string())?;
    for key in &keys {
        let s = statuses.get(key).copied().unwrap_or_default();
        let want = (
            leech.contains(key),
            suspended.contains(key),
            buried.get(key).copied(),
        );
        if (s.leech, s.suspended, s.buried_until) != want {
            return Err(format!(
                "{key:?}: cached status {s:?}, the log says (leech, suspended, buried until) {want:?}"
            ));
        }
    }
    Ok(found)
}
