//! Merging review histories (`Store::merge_reviews`): idempotent, states
//! replayed in time order through the scheduler, undone rows kept undone,
//! and the cache always what `rebuild` gives from the log alone.

use chrono::{DateTime, Duration, Utc};
use flipcard::sched::{CardState, Config, ItemKey, Rating, Scheduler};
use flipcard::store::{IncomingReview, Store};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

use crate::store_support::{at, back_key, key};

fn scheduler() -> Scheduler {
    Scheduler::new(&Config {
        fuzz: false,
        ..Config::default()
    })
}

fn incoming(k: &ItemKey, when: DateTime<Utc>, rating: Rating) -> IncomingReview {
    IncomingReview {
        key: k.clone(),
        reviewed_at: when,
        rating,
        cram: false,
        duration_ms: 3_000,
        undone: false,
        balanced_days: None,
    }
}

/// The state of `k` after replaying `answers` in time order from new.
fn replayed(s: &Scheduler, k: &ItemKey, answers: &[(DateTime<Utc>, Rating)]) -> Option<CardState> {
    let mut sorted = answers.to_vec();
    sorted.sort();
    let mut state = None;
    for (t, r) in sorted {
        state = Some(s.review(k, state.as_ref(), r, t, 3_000).after);
    }
    state
}

/// The whole log as (item, time, rating, undone), sorted: what a second
/// merge must leave exactly as it was.
fn log_rows(store: &Store) -> Vec<(String, i64, u8, bool, i64)> {
    let mut rows = Vec::new();
    store
        .each_review(|l| -> Result<(), flipcard::store::StoreError> {
            rows.push((
                format!("{}/{}", l.record.key.deck, l.record.key.card),
                l.record.reviewed_at.timestamp_millis(),
                l.record.rating as u8,
                l.undone,
                l.id,
            ));
            Ok(())
        })
        .unwrap();
    rows
}

#[test]
fn merging_twice_changes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = Store::open(dir.path()).unwrap();
    let s = scheduler();
    let k = key("mech", "a");
    let t = at("2026-02-01T10:00:00Z");
    let rows = vec![
        incoming(&k, t, Rating::Good),
        incoming(&k, t + Duration::minutes(10), Rating::Good),
        incoming(&k, t + Duration::days(3), Rating::Again),
        incoming(&back_key("mech", "a"), t, Rating::Easy),
    ];
    let first = store.merge_reviews(&rows, &s).unwrap();
    assert_eq!((first.added, first.duplicates, first.items), (4, 0, 2));
    let before = log_rows(&store);
    let states = store.cached_states().unwrap();
    let second = store.merge_reviews(&rows, &s).unwrap();
    assert_eq!((second.added, second.duplicates, second.items), (0, 4, 0));
    assert_eq!(log_rows(&store), before);
    assert_eq!(store.cached_states().unwrap(), states);
    // Repeats inside one input are duplicates too.
    let doubled = [rows[0].clone(), rows[0].clone()];
    assert_eq!(store.merge_reviews(&doubled, &s).unwrap().duplicates, 2);
}

#[test]
fn interleaved_histories_replay_in_time_order() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = Store::open(dir.path()).unwrap();
    let s = scheduler();
    let k = key("mech", "a");
    let t = at("2026-02-01T10:00:00Z");
    // This machine: days 0, 5 and 20. The other: days 2 and 12.
    let here = [
        (t, Rating::Good),
        (t + Duration::days(5), Rating::Hard),
        (t + Duration::days(20), Rating::Good),
    ];
    let there = [
        (t + Duration::days(2), Rating::Again),
        (t + Duration::days(12), Rating::Easy),
    ];
    let mut state = None;
    for (when, r) in here {
        let rec = s.review(&k, state.as_ref(), r, when, 3_000);
        state = Some(rec.after);
        store.record(&rec).unwrap();
    }
    let rows: Vec<_> = there.iter().map(|(w, r)| incoming(&k, *w, *r)).collect();
    let summary = store.merge_reviews(&rows, &s).unwrap();
    assert_eq!(summary.added, 2);
    assert_eq!(summary.replayed_local, 2, "days 5 and 20 follow day 2");

    let all: Vec<_> = here.iter().chain(there.iter()).copied().collect();
    let want = replayed(&s, &k, &all).unwrap();
    assert_eq!(store.state(&k).unwrap(), Some(want));
    let cached = store.cached_state(&k).unwrap().unwrap();
    assert_eq!(cached.reps, 5);

    // The live rows are in time order, each with its replayed state.
    let live: Vec<_> = store
        .history(&k)
        .unwrap()
        .into_iter()
        .filter(|l| !l.undone)
        .collect();
    let times: Vec<_> = live.iter().map(|l| l.record.reviewed_at).collect();
    let mut sorted = times.clone();
    sorted.sort();
    assert_eq!(times, sorted);
    let mut prefix = Vec::new();
    for l in &live {
        prefix.push((l.record.reviewed_at, l.record.rating));
        assert_eq!(Some(l.record.after), replayed(&s, &k, &prefix));
    }

    // The cache is what the log alone gives.
    let cache = store.cached_states().unwrap();
    let report = store.rebuild().unwrap();
    assert_eq!(report.changed, 0);
    assert!(!report.tallies_changed);
    assert_eq!(store.cached_states().unwrap(), cache);

    // Merging this machine's history into a fresh one gives the same state.
    let other = tempfile::tempdir().unwrap();
    let mut fresh = Store::open(other.path()).unwrap();
    let everything: Vec<_> = all.iter().map(|(w, r)| incoming(&k, *w, *r)).collect();
    fresh.merge_reviews(&everything, &s).unwrap();
    assert_eq!(fresh.state(&k).unwrap(), Some(want));
}

#[test]
fn undone_rows_stay_undone_and_change_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = Store::open(dir.path()).unwrap();
    let s = scheduler();
    let k = key("mech", "a");
    let t = at("2026-02-01T10:00:00Z");
    let mut undone = incoming(&k, t + Duration::days(1), Rating::Again);
    undone.undone = true;
    let rows = [
        incoming(&k, t, Rating::Easy),
        undone,
        incoming(&k, t + Duration::days(9), Rating::Good),
    ];
    let summary = store.merge_reviews(&rows, &s).unwrap();
    assert_eq!((summary.added, summary.added_undone), (3, 1));
    let want = replayed(
        &s,
        &k,
        &[(t, Rating::Easy), (t + Duration::days(9), Rating::Good)],
    );
    assert_eq!(store.state(&k).unwrap(), want);
    let history = store.history(&k).unwrap();
    let flags: Vec<_> = history.iter().map(|l| l.undone).collect();
    assert_eq!(flags, [false, true, false]);
    assert_eq!(store.cached_state(&k).unwrap().unwrap().reps, 2);
    // Merged again: still one undone row, nothing added.
    assert_eq!(store.merge_reviews(&rows, &s).unwrap().added, 0);
    assert_eq!(store.history(&k).unwrap().len(), 3);
    // An undo in this store never reaches into a merged history.
    assert!(store.undo_last().unwrap().is_none());
}

#[test]
fn a_refused_row_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = Store::open(dir.path()).unwrap();
    let s = scheduler();
    let t = at("2026-02-01T10:00:00Z");
    let mut bad = incoming(&key("mech", "b"), t, Rating::Good);
    bad.duration_ms = -1;
    let rows = [incoming(&key("mech", "a"), t, Rating::Good), bad];
    let err = store.merge_reviews(&rows, &s).unwrap_err();
    assert!(err.to_string().contains("negative duration"), "{err}");
    assert_eq!(store.review_count().unwrap(), 0);
}

#[test]
fn random_splits_of_one_history_merge_to_its_replay() {
    let s = scheduler();
    for seed in 0..6 {
        let mut rng = StdRng::seed_from_u64(seed);
        let items: Vec<ItemKey> = (0..4).map(|i| key("rot", &format!("c{i}"))).collect();
        let mut when = at("2026-03-01T08:00:00Z");
        let mut answers: Vec<(ItemKey, DateTime<Utc>, Rating)> = Vec::new();
        for _ in 0..60 {
            when += Duration::milliseconds(rng.random_range(60_000..4 * 86_400_000));
            let k = items[rng.random_range(0..items.len())].clone();
            answers.push((k, when, Rating::ALL[rng.random_range(0..4)]));
        }
        // Two machines each saw a random part; this one recorded its part
        // live, then merges the other's, then its own again.
        let (mine, theirs): (Vec<_>, Vec<_>) = answers.iter().partition(|_| rng.random_bool(0.5));
        let dir = tempfile::tempdir().unwrap();
        let mut store = Store::open(dir.path()).unwrap();
        for (k, w, r) in &mine {
            let before = store.state(k).unwrap();
            store
                .record(&s.review(k, before.as_ref(), *r, *w, 3_000))
                .unwrap();
        }
        let to_rows = |v: &[&(ItemKey, DateTime<Utc>, Rating)]| -> Vec<IncomingReview> {
            v.iter().map(|(k, w, r)| incoming(k, *w, *r)).collect()
        };
        store.merge_reviews(&to_rows(&theirs), &s).unwrap();
        let again = store.merge_reviews(&to_rows(&mine), &s).unwrap();
        assert_eq!(again.added, 0, "seed {seed}");
        for k in &items {
            let own: Vec<_> = answers
                .iter()
                .filter(|(x, _, _)| x == k)
                .map(|(_, w, r)| (*w, *r))
                .collect();
            assert_eq!(
                store.state(k).unwrap(),
                replayed(&s, k, &own),
                "seed {seed} {k:?}"
            );
        }
        let cache = store.cached_states().unwrap();
        assert_eq!(store.rebuild().unwrap().changed, 0, "seed {seed}");
        assert_eq!(store.cached_states().unwrap(), cache);
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]
    /// `merge_reviews_keeping`: whatever the history, the item ends with the
    /// due date and memory state kept (an Anki import keeps Anki's), the
    /// cache agrees with `rebuild`, the other answers are replayed as
    /// ever, and merging again changes nothing.
    #[test]
    fn a_kept_state_ends_the_item_whatever_its_history(
        answers in proptest::collection::vec((0i64..2_000_000, 1u8..=4), 1..12),
        due_days in 0i64..4_000,
        stability in proptest::option::of(0.1f64..5_000.0),
    ) {
        let dir = tempfile::tempdir().unwrap();
        let mut store = Store::open(dir.path()).unwrap();
        let s = scheduler();
        let k = key("d", "c");
        let t0 = at("2026-01-05T08:00:00Z");
        let mut rows: Vec<IncomingReview> = answers
            .iter()
            .map(|(min, r)| incoming(&k, t0 + Duration::minutes(*min), Rating::from_number(i64::from(*r)).unwrap()))
            .collect();
        rows.sort_by_key(|r| r.reviewed_at);
        rows.dedup_by_key(|r| r.reviewed_at);
        let last = rows.last().unwrap().reviewed_at;
        let kept = flipcard::store::KeptState {
            at: last,
            state: flipcard::sched::State::Review,
            due: last + Duration::days(due_days) + Duration::seconds(1),
            stability,
            difficulty: Some(5.5),
            last_review: Some(last),
        };
        let map = std::collections::HashMap::from([(k.clone(), kept)]);
        let summary = store.merge_reviews_keeping(&rows, &s, &map).unwrap();
        proptest::prop_assert_eq!(summary.added, rows.len());
        let state = store.state(&k).unwrap().unwrap();
        proptest::prop_assert_eq!(state.due, kept.due);
        proptest::prop_assert_eq!(state.difficulty, Some(5.5));
        if let Some(st) = stability {
            proptest::prop_assert_eq!(state.stability, Some(st));
        }
        // Every answer but the last is the replay.
        let answers: Vec<(DateTime<Utc>, Rating)> =
            rows.iter().map(|r| (r.reviewed_at, r.rating)).collect();
        let history = store.history(&k).unwrap();
        if answers.len() > 1 {
            let before = replayed(&s, &k, &answers[..answers.len() - 1]).unwrap();
            proptest::prop_assert_eq!(history[history.len() - 2].record.after, before);
        }
        let before = log_rows(&store);
        let again = store.merge_reviews_keeping(&rows, &s, &map).unwrap();
        proptest::prop_assert_eq!(again.added, 0);
        proptest::prop_assert_eq!(log_rows(&store), before);
        let report = store.rebuild().unwrap();
        proptest::prop_assert_eq!(report.changed, 0);
        proptest::prop_assert_eq!(store.state(&k).unwrap().unwrap().due, kept.due);
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]
    /// A kept state stays the base later merges replay from (a sync that
    /// brings answers of another machine goes through the same merge):
    /// answers up to its time end in it, so Anki's due date survives
    /// them; an answer after it is replayed from it; `rebuild` agrees.
    /// An item with no answer at all (Anki's schedule without its review
    /// history) has the kept state as its state, as the queue reads it.
    #[test]
    fn a_kept_state_survives_later_merges_of_earlier_answers(
        anki in proptest::collection::vec((0i64..200_000, 1u8..=4), 0..6),
        earlier in proptest::collection::vec((0i64..200_000, 1u8..=4), 1..5),
        later in proptest::option::of((1i64..100_000, 1u8..=4)),
        due_days in 1i64..400,
        stability in 0.5f64..500.0,
        learning in proptest::bool::ANY,
    ) {
        let dir = tempfile::tempdir().unwrap();
        let mut store = Store::open(dir.path()).unwrap();
        let s = scheduler();
        let k = key("d", "c");
        let t0 = at("2026-01-05T08:00:00Z");
        let answer = |(min, r): &(i64, u8)| incoming(&k, t0 + Duration::minutes(*min), Rating::from_number(i64::from(*r)).unwrap());
        let mut rows: Vec<IncomingReview> = anki.iter().map(answer).collect();
        rows.sort_by_key(|r| r.reviewed_at);
        rows.dedup_by_key(|r| r.reviewed_at);
        // Anki's last answer, or its last review when none came along.
        let last = rows.last().map_or(t0 + Duration::minutes(200_000), |r| r.reviewed_at);
        let kept = flipcard::store::KeptState {
            at: last,
            state: if learning { flipcard::sched::State::Learning } else { flipcard::sched::State::Review },
            due: last + Duration::days(due_days),
            stability: Some(stability),
            difficulty: Some(4.5),
            last_review: Some(last),
        };
        let map = std::collections::HashMap::from([(k.clone(), kept)]);
        store.merge_reviews_keeping(&rows, &s, &map).unwrap();
        let state = store.state(&k).unwrap().unwrap();
        proptest::prop_assert_eq!(state.due, kept.due);
        proptest::prop_assert_eq!(state.state, kept.state);
        proptest::prop_assert_eq!(state.stability, Some(stability));
        // Answers from elsewhere, up to Anki's last: absorbed in its state.
        let seen: std::collections::HashSet<_> = rows.iter().map(|r| r.reviewed_at).collect();
        let mut more: Vec<IncomingReview> = earlier
            .iter()
            .map(|(min, r)| answer(&(min % 200_000, *r)))
            .filter(|r| r.reviewed_at <= last && !seen.contains(&r.reviewed_at))
            .collect();
        more.sort_by_key(|r| r.reviewed_at);
        more.dedup_by_key(|r| r.reviewed_at);
        store.merge_reviews(&more, &s).unwrap();
        let state = store.state(&k).unwrap().unwrap();
        proptest::prop_assert_eq!(state.due, kept.due, "an earlier answer replayed Anki's due away");
        proptest::prop_assert_eq!(state.stability, Some(stability));
        proptest::prop_assert_eq!(store.rebuild().unwrap().changed, 0);
        // An answer after it: replayed from Anki's state.
        if let Some((min, r)) = later {
            let when = last + Duration::minutes(min);
            let rating = Rating::from_number(i64::from(r)).unwrap();
            store.merge_reviews(&[incoming(&k, when, rating)], &s).unwrap();
            let want = s.review(&k, Some(&kept.base()), rating, when, 3_000).after;
            proptest::prop_assert_eq!(store.state(&k).unwrap().unwrap(), want);
            proptest::prop_assert_eq!(store.rebuild().unwrap().changed, 0);
        }
    }
}
