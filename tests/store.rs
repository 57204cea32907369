//! The review store through its public API: the cache always equals what
//! the log alone gives, undo restores exactly, history survives deck edits,
//! and damaged, locked or unwritable databases are reported, never harmed.

use std::collections::HashMap;
use std::time::Duration as StdDuration;

use crate::store_support::{at, back_key, key, random_review, review};
use chrono::{Duration, NaiveTime, Utc};
use flipcard::sched::DayGrid;
use flipcard::sched::{ItemKey, Rating, ReviewKind, State};
use flipcard::store::stats::StatsScope;
use flipcard::store::{OpenOptions, PromptAttempt, Store, StoreError};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use rusqlite::Connection;

fn open(dir: &std::path::Path) -> Store {
    Store::open(dir).expect("open store")
}

/// Random histories over a few decks and items, several sessions, cram
/// answers and undos mixed in. Returns the items touched.
fn random_history(dir: &std::path::Path, seed: u64, ratings: usize) -> Vec<ItemKey> {
    let mut rng = StdRng::seed_from_u64(seed);
    let items: Vec<ItemKey> = (0..12)
        .map(|i| {
            let deck = ["mech", "rot"][i % 2];
            if i % 5 == 0 {
                back_key(deck, &format!("c{i}"))
            } else {
                key(deck, &format!("c{i}"))
            }
        })
        .collect();
    let mut when = at("2026-01-05T09:00:00Z");
    let mut store = open(dir);
    for _ in 0..ratings {
        when += Duration::milliseconds(rng.random_range(1_000..3 * 86_400_000));
        let item = &items[rng.random_range(0..items.len())];
        match rng.random_range(0..10) {
            0 => {
                store.undo_last().unwrap();
            }
            1 => {
                drop(store);
                store = open(dir);
            }
            _ => {
                store.record(&random_review(&mut rng, item, when)).unwrap();
            }
        }
    }
    items
}

#[test]
fn rebuild_from_the_log_equals_the_cache() {
    for seed in 0..5 {
        let dir = tempfile::tempdir().unwrap();
        random_history(dir.path(), seed, 200);
        let mut store = open(dir.path());
        let before = store.cached_states().unwrap();
        assert!(!before.is_empty());
        let retention = all_time_retention(&store);
        assert!(retention.total > 0);
        let report = store.rebuild().unwrap();
        assert_eq!(report.changed, 0, "seed {seed}");
        assert!(!report.tallies_changed, "seed {seed}");
        assert_eq!(report.items, before.len());
        assert_eq!(store.cached_states().unwrap(), before, "seed {seed}");
        assert_eq!(all_time_retention(&store), retention);

        // The cache is only a cache: damage it behind the store's back and
        // the log alone brings it back.
        let raw = Connection::open(store.path()).unwrap();
        let removed = raw
            .execute("DELETE FROM card_state WHERE card IN ('c1', 'c2')", [])
            .unwrap();
        raw.execute(
            "UPDATE card_state SET reps = reps + 7, stability = 0.5 WHERE card = 'c3'",
            [],
        )
        .unwrap();
        raw.execute("UPDATE review_tally SET n = n + 3", [])
            .unwrap();
        drop(raw);
        assert_ne!(store.cached_states().unwrap(), before);
        assert_ne!(all_time_retention(&store), retention);
        let report = store.rebuild().unwrap();
        assert!(report.changed >= removed, "seed {seed}: {report:?}");
        assert!(report.tallies_changed);
        assert_eq!(store.cached_states().unwrap(), before, "seed {seed}");
        assert_eq!(all_time_retention(&store), retention);
    }
}

/// All-time retention over every deck (it comes from the answer tallies).
fn all_time_retention(store: &Store) -> flipcard::store::stats::Ratio {
    let grid = DayGrid::new(Utc, NaiveTime::from_hms_opt(4, 0, 0).unwrap());
    let scope = StatsScope {
        deck: None,
        items: &[],
    };
    store
        .stats(scope, at("2026-01-01T00:00:00Z"), &grid)
        .unwrap()
        .retention
        .all_time
}

#[test]
fn cache_counts_reps_and_lapses_from_the_log() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = open(dir.path());
    let k = key("mech", "torque");
    let t = at("2026-02-01T10:00:00Z");
    let d = Duration::days;
    store
        .record(&review(
            &k,
            t,
            Rating::Good,
            ReviewKind::Learn,
            State::Review,
            d(1),
        ))
        .unwrap();
    store
        .record(&review(
            &k,
            t + d(1),
            Rating::Again,
            ReviewKind::Review,
            State::Relearning,
            Duration::minutes(10),
        ))
        .unwrap();
    store
        .record(&review(
            &k,
            t + d(1),
            Rating::Again,
            ReviewKind::Relearn,
            State::Relearning,
            Duration::minutes(10),
        ))
        .unwrap();
    let cram = review(
        &k,
        t + d(1),
        Rating::Easy,
        ReviewKind::Cram,
        State::Review,
        d(40),
    );
    store.record(&cram).unwrap();
    let c = store.cached_state(&k).unwrap().unwrap();
    assert_eq!((c.reps, c.lapses), (3, 1));
    assert_eq!(
        c.state.state,
        State::Relearning,
        "cram leaves the state alone"
    );
    assert_eq!(c.state.due, t + d(1) + Duration::minutes(10));
}

#[test]
fn undo_restores_the_exact_previous_state() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = open(dir.path());
    let mut rng = StdRng::seed_from_u64(42);
    let items: Vec<ItemKey> = (0..4).map(|i| key("mech", &format!("c{i}"))).collect();
    let mut when = at("2026-03-01T08:00:00Z");
    for round in 0..200 {
        let item = &items[rng.random_range(0..items.len())];
        when += Duration::milliseconds(rng.random_range(1_000..86_400_000));
        let before = store.cached_state(item).unwrap();
        let all_before = store.cached_states().unwrap();
        let rec = random_review(&mut rng, item, when);
        store.record(&rec).unwrap();
        if rng.random_bool(0.4) {
            let undone = store.undo_last().unwrap().expect("something to undo");
            assert_eq!(undone.record, rec, "round {round}: undo returns the rating");
            assert!(undone.undone);
            assert_eq!(store.cached_state(item).unwrap(), before, "round {round}");
            assert_eq!(store.cached_states().unwrap(), all_before, "round {round}");
        }
    }
}

#[test]
fn undo_takes_a_new_item_back_to_new_and_walks_back_the_session() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = open(dir.path());
    assert_eq!(
        store.undo_last().unwrap(),
        None,
        "nothing in a fresh session"
    );
    let k = key("mech", "fresh");
    let t = at("2026-03-01T08:00:00Z");
    let first = review(
        &k,
        t,
        Rating::Good,
        ReviewKind::Learn,
        State::Learning,
        Duration::minutes(10),
    );
    let second = review(
        &k,
        t + Duration::minutes(10),
        Rating::Good,
        ReviewKind::Learn,
        State::Review,
        Duration::days(2),
    );
    store.record(&first).unwrap();
    let after_first = store.cached_state(&k).unwrap();
    store.record(&second).unwrap();

    assert_eq!(store.undo_last().unwrap().map(|u| u.record), Some(second));
    assert_eq!(store.cached_state(&k).unwrap(), after_first);
    assert_eq!(store.undo_last().unwrap().map(|u| u.record), Some(first));
    assert_eq!(store.state(&k).unwrap(), None, "new again");
    assert!(store.states("mech").unwrap().is_empty());
    assert_eq!(store.undo_last().unwrap(), None);

    // The log keeps both rows, marked undone.
    let history = store.history(&k).unwrap();
    assert_eq!(history.len(), 2);
    assert!(history.iter().all(|r| r.undone));
}

#[test]
fn undo_stays_within_its_own_session() {
    let dir = tempfile::tempdir().unwrap();
    let t = at("2026-03-01T08:00:00Z");
    let k = key("mech", "shared");
    let mut a = open(dir.path());
    let mut b = open(dir.path());
    let ra = review(
        &k,
        t,
        Rating::Good,
        ReviewKind::Learn,
        State::Learning,
        Duration::minutes(10),
    );
    let rb = review(
        &k,
        t + Duration::minutes(1),
        Rating::Hard,
        ReviewKind::Learn,
        State::Learning,
        Duration::minutes(5),
    );
    a.record(&ra).unwrap();
    b.record(&rb).unwrap();
    // `a` undoes its own rating, not the later one of `b`.
    assert_eq!(a.undo_last().unwrap().map(|u| u.record), Some(ra));
    assert_eq!(a.undo_last().unwrap(), None);
    assert_eq!(a.state(&k).unwrap(), Some(rb.after));

    // A new session cannot reach back into the previous one.
    b.start_session().unwrap();
    assert_eq!(b.undo_last().unwrap(), None);
    assert_eq!(b.state(&k).unwrap(), Some(rb.after));
}

#[test]
fn history_survives_deck_edits_and_removed_cards_are_orphans() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = open(dir.path());
    let t = at("2026-04-01T08:00:00Z");
    let kept = key("mech", "kept");
    let gone = key("mech", "gone");
    let gone_back = back_key("mech", "gone");
    for k in [&kept, &gone, &gone_back] {
        store
            .record(&review(
                k,
                t,
                Rating::Good,
                ReviewKind::Learn,
                State::Review,
                Duration::days(3),
            ))
            .unwrap();
    }
    store
        .record(&review(
            &gone,
            t + Duration::days(3),
            Rating::Good,
            ReviewKind::Review,
            State::Review,
            Duration::days(8),
        ))
        .unwrap();
    let gone_state = store.state(&gone).unwrap();
    let other_deck = key("old-deck", "x");
    store
        .record(&review(
            &other_deck,
            t,
            Rating::Easy,
            ReviewKind::Learn,
            State::Review,
            Duration::days(4),
        ))
        .unwrap();
    // Only ever crammed (so without a state), then removed; and a cram
    // answer to `gone` on top of its two scheduling answers.
    for k in [&key("mech", "crammed"), &gone] {
        store
            .record(&review(
                k,
                t + Duration::days(3),
                Rating::Good,
                ReviewKind::Cram,
                State::New,
                Duration::days(0),
            ))
            .unwrap();
    }

    let grid = DayGrid::new(Utc, NaiveTime::from_hms_opt(4, 0, 0).unwrap());
    let now = t + Duration::days(4);

    // The deck now has only `kept` (and a brand-new card).
    let fresh = key("mech", "fresh");
    let items = vec![kept.clone(), fresh.clone()];
    let s = store
        .stats(
            StatsScope {
                deck: None,
                items: &items,
            },
            now,
            &grid,
        )
        .unwrap();
    let orphans: Vec<(&str, &str, &str, u64, bool)> = s
        .orphans
        .iter()
        .map(|o| {
            (
                o.deck.as_str(),
                o.card.as_str(),
                o.direction.as_str(),
                o.reviews,
                o.deck_present,
            )
        })
        .collect();
    assert_eq!(
        orphans,
        [
            ("mech", "crammed", "forward", 1, true),
            ("mech", "gone", "backward", 1, true),
            ("mech", "gone", "forward", 3, true),
            ("old-deck", "x", "forward", 1, false),
        ]
    );
    assert_eq!((s.cards.new, s.cards.review, s.cards.total), (1, 1, 2));

    // Scoped to one deck, other decks' orphans are not reported.
    let s = store
        .stats(
            StatsScope {
                deck: Some("mech"),
                items: &items,
            },
            now,
            &grid,
        )
        .unwrap();
    assert_eq!(s.orphans.len(), 3);

    // The card comes back (its text edited, its id the same): its history
    // and state are intact and it is no orphan any more.
    let items = vec![
        kept.clone(),
        fresh,
        gone.clone(),
        gone_back.clone(),
        key("mech", "crammed"),
    ];
    let s = store
        .stats(
            StatsScope {
                deck: Some("mech"),
                items: &items,
            },
            now,
            &grid,
        )
        .unwrap();
    assert!(s.orphans.is_empty());
    assert_eq!(s.cards.review, 3);
    assert_eq!(store.state(&gone).unwrap(), gone_state);
    assert_eq!(store.history(&gone).unwrap().len(), 3);
}

#[test]
fn stats_count_states_forecast_days_retention_and_prompts() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = open(dir.path());
    let grid = DayGrid::new(Utc, NaiveTime::from_hms_opt(4, 0, 0).unwrap());
    let now = at("2026-05-10T12:00:00Z");
    let d = Duration::days;
    let mins = Duration::minutes;
    let k = |c: &str| key("mech", c);
    let at_day = |back: i64| now - d(back);

    // due today (overdue), today (learning), tomorrow, in 5 days, in 20 days, in 60 days
    let plan = [
        (
            "overdue",
            at_day(10),
            Rating::Good,
            ReviewKind::Learn,
            State::Review,
            d(3),
        ),
        (
            "learning",
            now - mins(5),
            Rating::Again,
            ReviewKind::Learn,
            State::Learning,
            mins(10),
        ),
        (
            "tomorrow",
            at_day(2),
            Rating::Good,
            ReviewKind::Review,
            State::Review,
            d(3),
        ),
        (
            "in5",
            at_day(1),
            Rating::Hard,
            ReviewKind::Review,
            State::Review,
            d(6),
        ),
        (
            "in20",
            at_day(1),
            Rating::Again,
            ReviewKind::Review,
            State::Relearning,
            d(21),
        ),
        (
            "in60",
            at_day(40),
            Rating::Easy,
            ReviewKind::Review,
            State::Review,
            d(100),
        ),
    ];
    for (card, when, rating, kind, state, due_in) in plan {
        store
            .record(&review(&k(card), when, rating, kind, state, due_in))
            .unwrap();
    }
    // Cram and undone answers count in neither retention nor state.
    store
        .record(&review(
            &k("in5"),
            now - mins(1),
            Rating::Again,
            ReviewKind::Cram,
            State::Review,
            d(1),
        ))
        .unwrap();
    store
        .record(&review(
            &k("in60"),
            now - mins(1),
            Rating::Again,
            ReviewKind::Review,
            State::Relearning,
            mins(10),
        ))
        .unwrap();
    store.undo_last().unwrap();

    for (prompt, correct) in [("p1", true), ("p1", false), ("p2", true)] {
        store
            .record_attempt(&PromptAttempt {
                deck: "mech".into(),
                prompt: prompt.into(),
                attempted_at: now,
                prediction: "flips".into(),
                measured: Some(3.0),
                correct,
            })
            .unwrap();
    }

    let items: Vec<ItemKey> = [
        "overdue", "learning", "tomorrow", "in5", "in20", "in60", "new1", "new2",
    ]
    .iter()
    .map(|c| k(c))
    .collect();
    let s = store
        .stats(
            StatsScope {
                deck: Some("mech"),
                items: &items,
            },
            now,
            &grid,
        )
        .unwrap();
    assert_eq!(s.today, now.date_naive());
    assert_eq!(
        (
            s.cards.new,
            s.cards.learning,
            s.cards.review,
            s.cards.relearning,
            s.cards.total
        ),
        (2, 1, 4, 1, 8)
    );
    assert_eq!(
        (
            s.due.today,
            s.due.tomorrow,
            s.due.next_7_days,
            s.due.next_30_days
        ),
        (2, 1, 4, 5)
    );
    assert_eq!(s.due.per_day.len(), 30);
    assert_eq!(s.due.per_day[0].date, s.today);
    // Due 6 days after yesterday noon: five learning days from today.
    assert_eq!(
        s.due.per_day[5].date,
        at("2026-05-15T00:00:00Z").date_naive()
    );
    assert_eq!(s.due.per_day[5].due, 1);
    assert_eq!(s.due.per_day[20].due, 1);
    assert_eq!(s.due.per_day.iter().map(|d| d.due).sum::<u32>(), 5);

    assert_eq!(s.reviews_per_day.len(), 30);
    assert_eq!(s.reviews_per_day.last().unwrap().date, s.today);
    let today = s.reviews_per_day.last().unwrap();
    assert_eq!(
        (today.total, today.learn, today.cram, today.again),
        (2, 1, 1, 2)
    );
    let yesterday = &s.reviews_per_day[28];
    assert_eq!(
        (yesterday.total, yesterday.review, yesterday.again),
        (2, 2, 1)
    );
    assert_eq!(
        s.reviews_per_day.iter().map(|d| d.total).sum::<u32>(),
        6,
        "40 days back is outside"
    );

    // Review-kind answers: tomorrow Good, in5 Hard, in20 Again, in60 Easy (40 days ago).
    assert_eq!(
        (s.retention.all_time.total, s.retention.all_time.passed),
        (4, 3)
    );
    assert_eq!(s.retention.all_time.rate, Some(0.75));
    assert_eq!(
        (
            s.retention.last_30_days.total,
            s.retention.last_30_days.passed
        ),
        (3, 2)
    );

    assert_eq!((s.prompts.overall.total, s.prompts.overall.passed), (3, 2));
    assert_eq!(s.prompts.by_prompt.len(), 2);
    assert_eq!(
        (
            s.prompts.by_prompt[0].attempts,
            s.prompts.by_prompt[0].correct
        ),
        (2, 1)
    );
    // Accuracy over time: the week (from Monday, UTC) of each attempt;
    // 2026-05-10 is a Sunday.
    let weeks: Vec<(String, u64, u64)> = s.prompts.by_prompt[0]
        .weeks
        .iter()
        .map(|w| (w.week.clone(), w.attempts, w.correct))
        .collect();
    assert_eq!(weeks, [("2026-05-04".to_string(), 2, 1)]);

    let json = serde_json::to_value(&s).unwrap();
    assert_eq!(json["cards"]["new"], 2);
    assert_eq!(json["due"]["next_30_days"], 5);
}

#[test]
fn today_counts_new_items_and_reviews_since_the_day_began() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = open(dir.path());
    let day_start = at("2026-05-10T04:00:00Z");
    let d = Duration::days;
    let h = Duration::hours;
    let k = |c: &str| key("mech", c);
    let old = k("old");
    store
        .record(&review(
            &old,
            day_start - d(3),
            Rating::Good,
            ReviewKind::Learn,
            State::Review,
            d(3),
        ))
        .unwrap();
    store
        .record(&review(
            &old,
            day_start + h(1),
            Rating::Good,
            ReviewKind::Review,
            State::Review,
            d(7),
        ))
        .unwrap();
    for c in ["n1", "n2"] {
        store
            .record(&review(
                &k(c),
                day_start + h(2),
                Rating::Again,
                ReviewKind::Learn,
                State::Learning,
                Duration::minutes(1),
            ))
            .unwrap();
        store
            .record(&review(
                &k(c),
                day_start + h(3),
                Rating::Good,
                ReviewKind::Learn,
                State::Learning,
                Duration::minutes(10),
            ))
            .unwrap();
    }
    store
        .record(&review(
            &k("crammed"),
            day_start + h(4),
            Rating::Good,
            ReviewKind::Cram,
            State::New,
            d(0),
        ))
        .unwrap();
    store
        .record(&review(
            &k("undone"),
            day_start + h(4),
            Rating::Good,
            ReviewKind::Learn,
            State::Learning,
            d(0),
        ))
        .unwrap();
    store.undo_last().unwrap();
    store
        .record(&review(
            &key("other", "x"),
            day_start + h(4),
            Rating::Good,
            ReviewKind::Review,
            State::Review,
            d(9),
        ))
        .unwrap();

    let c = store.reviews_today("mech", day_start).unwrap();
    assert_eq!((c.new, c.reviews), (2, 1));
    assert_eq!(store.last_studied("mech").unwrap(), Some(day_start + h(4)));
    assert_eq!(store.last_studied("never").unwrap(), None);
}

#[test]
fn records_that_cannot_be_stored_faithfully_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = open(dir.path());
    let mut r = review(
        &key("mech", "c"),
        at("2026-01-01T00:00:00Z"),
        Rating::Good,
        ReviewKind::Learn,
        State::Learning,
        Duration::minutes(1),
    );
    r.after.stability = Some(f64::NAN);
    let err = store.record(&r).unwrap_err();
    assert!(err.to_string().contains("stability is NaN"), "{err}");
    assert_eq!(store.review_count().unwrap(), 0);
}

#[test]
fn corrupt_file_is_reported_with_its_path_and_left_untouched() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("flipcard.db");
    let garbage: Vec<u8> = (0..9000u32).map(|i| (i * 7919 % 251) as u8).collect();
    std::fs::write(&db, &garbage).unwrap();
    let err = Store::open(dir.path()).unwrap_err();
    match &err {
        StoreError::Corrupt {
            path,
            newest_backup,
            ..
        } => {
            assert_eq!(path, &db);
            assert_eq!(newest_backup, &None);
        }
        other => panic!("expected Corrupt, got {other}"),
    }
    assert!(err.to_string().contains(&db.display().to_string()), "{err}");
    assert_eq!(std::fs::read(&db).unwrap(), garbage, "file untouched");
    let siblings: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(siblings.len(), 1, "nothing created beside it");
}

#[test]
fn truncated_file_is_corrupt_and_the_newest_backup_is_suggested() {
    let dir = tempfile::tempdir().unwrap();
    {
        let mut store = open(dir.path());
        let mut rng = StdRng::seed_from_u64(7);
        let t = at("2026-01-01T00:00:00Z");
        let recs: Vec<_> = (0..3000)
            .map(|i| {
                random_review(
                    &mut rng,
                    &key("mech", &format!("card-{}", i % 500)),
                    t + Duration::minutes(i),
                )
            })
            .collect();
        store.record_batch(&recs).unwrap();
    }
    // A second open writes today's copy (the store has history now).
    drop(open(dir.path()));
    let backups = flipcard::store::backup::daily_backups(dir.path());
    assert_eq!(backups.len(), 1, "daily copy written");

    let db = dir.path().join("flipcard.db");
    let bytes = std::fs::read(&db).unwrap();
    assert!(bytes.len() > 100_000);
    let cut = &bytes[..bytes.len() / 2];
    std::fs::write(&db, cut).unwrap();
    let err = Store::open(dir.path()).unwrap_err();
    let StoreError::Corrupt {
        path,
        newest_backup,
        ..
    } = &err
    else {
        panic!("expected Corrupt, got {err}");
    };
    assert_eq!(path, &db);
    assert_eq!(newest_backup.as_ref(), Some(&backups[0].1));
    let msg = err.to_string();
    assert!(msg.contains(&backups[0].1.display().to_string()), "{msg}");
    assert_eq!(std::fs::read(&db).unwrap(), cut, "file untouched");
}

#[test]
fn damaged_pages_are_found_by_the_daily_full_check() {
    let dir = tempfile::tempdir().unwrap();
    {
        // The first open has no history yet, so no daily copy is written.
        let mut store = open(dir.path());
        let mut rng = StdRng::seed_from_u64(8);
        let t = at("2026-01-01T00:00:00Z");
        let recs: Vec<_> = (0..3000)
            .map(|i| {
                random_review(
                    &mut rng,
                    &key("mech", &format!("card-{}", i % 500)),
                    t + Duration::minutes(i),
                )
            })
            .collect();
        store.record_batch(&recs).unwrap();
    }
    assert!(flipcard::store::backup::daily_backups(dir.path()).is_empty());
    let db = dir.path().join("flipcard.db");
    let mut bytes = std::fs::read(&db).unwrap();
    let middle = bytes.len() / 2;
    for b in &mut bytes[middle..middle + 20_000] {
        *b = 0xA5;
    }
    std::fs::write(&db, &bytes).unwrap();

    let err = Store::open(dir.path()).unwrap_err();
    assert!(matches!(err, StoreError::Corrupt { .. }), "{err}");
    assert!(err.to_string().contains(&db.display().to_string()), "{err}");
    assert_eq!(std::fs::read(&db).unwrap(), bytes, "file untouched");
    assert!(
        flipcard::store::backup::daily_backups(dir.path()).is_empty(),
        "no copy of a damaged file"
    );
}

#[test]
fn locked_database_gives_a_clear_error_and_no_damage() {
    let dir = tempfile::tempdir().unwrap();
    let quick = OpenOptions {
        busy_timeout: StdDuration::from_millis(200),
        daily_backup: true,
        ..OpenOptions::default()
    };
    let mut store = Store::open_with(dir.path(), &quick).unwrap();
    let t = at("2026-01-01T00:00:00Z");
    let k = key("mech", "c");
    store
        .record(&review(
            &k,
            t,
            Rating::Good,
            ReviewKind::Learn,
            State::Learning,
            Duration::minutes(1),
        ))
        .unwrap();

    // Another program holds the write lock.
    let other = Connection::open(store.path()).unwrap();
    other.execute_batch("BEGIN EXCLUSIVE;").unwrap();
    let err = store
        .record(&review(
            &k,
            t + Duration::minutes(1),
            Rating::Good,
            ReviewKind::Learn,
            State::Review,
            Duration::days(1),
        ))
        .unwrap_err();
    assert!(matches!(err, StoreError::Locked { .. }), "{err}");
    assert!(
        err.to_string()
            .contains(&store.path().display().to_string())
    );
    assert!(
        store
            .undo_last()
            .unwrap_err()
            .to_string()
            .contains("locked")
    );
    other.execute_batch("COMMIT;").unwrap();

    // Released: the write goes through, nothing was lost or half-written.
    store
        .record(&review(
            &k,
            t + Duration::minutes(2),
            Rating::Good,
            ReviewKind::Learn,
            State::Review,
            Duration::days(1),
        ))
        .unwrap();
    assert_eq!(store.review_count().unwrap(), 2);
    assert_eq!(store.integrity_check().unwrap(), ["ok"]);
    drop(store);
    drop(other);

    // A program holding the file in exclusive locking mode keeps even
    // readers out: opening says so instead of calling the file corrupt.
    let other = Connection::open(dir.path().join("flipcard.db")).unwrap();
    other
        .pragma_update(None, "locking_mode", "EXCLUSIVE")
        .unwrap();
    other.execute_batch("BEGIN EXCLUSIVE; COMMIT;").unwrap();
    let err = Store::open_with(dir.path(), &quick).unwrap_err();
    assert!(matches!(err, StoreError::Locked { .. }), "{err}");
    drop(other);
    let store = Store::open_with(dir.path(), &quick).unwrap();
    assert_eq!(store.review_count().unwrap(), 2);
}

#[test]
fn two_open_stores_share_the_file_safely() {
    let dir = tempfile::tempdir().unwrap();
    drop(open(dir.path()));
    let handles: Vec<_> = (0..2)
        .map(|w| {
            let path = dir.path().to_path_buf();
            std::thread::spawn(move || {
                let mut store = Store::open(&path).unwrap();
                let t = at("2026-01-01T00:00:00Z");
                for i in 0..50 {
                    let k = key("mech", &format!("w{w}-{}", i % 5));
                    store
                        .record(&review(
                            &k,
                            t + Duration::seconds(i),
                            Rating::Good,
                            ReviewKind::Learn,
                            State::Learning,
                            Duration::minutes(1),
                        ))
                        .unwrap();
                }
            })
        })
        .collect();
    for h in handles {
        h.join().unwrap();
    }
    let mut store = open(dir.path());
    assert_eq!(store.review_count().unwrap(), 100);
    assert_eq!(store.integrity_check().unwrap(), ["ok"]);
    let c = store.cached_states().unwrap();
    assert_eq!(c.len(), 10);
    assert!(c.iter().all(|s| s.reps == 10));
    assert_eq!(store.rebuild().unwrap().changed, 0);
}

#[test]
fn missing_parent_and_read_only_dirs_are_named_in_the_error() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("a-file");
    std::fs::write(&file, "x").unwrap();
    let under_file = file.join("data");
    let err = Store::open(&under_file).unwrap_err();
    assert!(matches!(err, StoreError::DataDir { .. }), "{err}");
    assert!(
        err.to_string().contains(&under_file.display().to_string()),
        "{err}"
    );

    // A folder this process cannot write to. Permission bits do not stop a
    // privileged user, so fall back on a kernel folder nobody can write.
    let ro = dir.path().join("ro");
    std::fs::create_dir(&ro).unwrap();
    set_mode(&ro, 0o555);
    let ro_dir = if std::fs::write(ro.join("probe"), "x").is_err() {
        ro.clone()
    } else {
        std::path::PathBuf::from("/proc/self")
    };
    let err = Store::open(&ro_dir).unwrap_err();
    assert!(matches!(err, StoreError::NotWritable { .. }), "{err}");
    let msg = err.to_string();
    assert!(
        msg.contains(&ro_dir.display().to_string()) && msg.contains("not writable"),
        "{msg}"
    );
    set_mode(&ro, 0o755);
}

fn set_mode(path: &std::path::Path, mode: u32) {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(mode)).unwrap();
}

#[test]
fn the_log_is_append_only_even_for_other_programs() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = open(dir.path());
    let k = key("mech", "c");
    store
        .record(&review(
            &k,
            at("2026-01-01T00:00:00Z"),
            Rating::Good,
            ReviewKind::Learn,
            State::Learning,
            Duration::minutes(1),
        ))
        .unwrap();
    let raw = Connection::open(store.path()).unwrap();
    assert!(raw.execute("DELETE FROM review", []).is_err());
    assert!(raw.execute("UPDATE review SET rating = 1", []).is_err());
    assert_eq!(store.review_count().unwrap(), 1);
    let mut seen = HashMap::new();
    store
        .each_review(|r| -> Result<(), StoreError> {
            seen.insert(r.id, r.record.rating);
            Ok(())
        })
        .unwrap();
    assert_eq!(seen.into_values().collect::<Vec<_>>(), [Rating::Good]);
}

/// Time spent per day, answer buttons by kind (young and mature reviews
/// apart), the interval and difficulty distributions and the 90-day
/// forecast, from a log written as the app writes it.
#[test]
fn stats_count_time_buttons_intervals_difficulty_and_a_long_forecast() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = open(dir.path());
    let grid = DayGrid::new(Utc, NaiveTime::from_hms_opt(4, 0, 0).unwrap());
    let now = at("2026-05-10T12:00:00Z");
    let d = Duration::days;
    let k = |c: &str| key("mech", c);
    // (card, days back, rating, kind, days since the answer before, state,
    // due in, difficulty, milliseconds taken)
    let plan = [
        (
            "mature",
            2,
            Rating::Good,
            ReviewKind::Review,
            30,
            State::Review,
            d(100),
            2.0,
            3_000,
        ),
        (
            "young",
            2,
            Rating::Hard,
            ReviewKind::Review,
            5,
            State::Review,
            d(50),
            6.5,
            7_500,
        ),
        (
            "young2",
            0,
            Rating::Easy,
            ReviewKind::Review,
            20,
            State::Review,
            d(10),
            10.0,
            1_250,
        ),
        (
            "lapsed",
            0,
            Rating::Again,
            ReviewKind::Review,
            40,
            State::Relearning,
            d(2),
            9.2,
            12_000,
        ),
        (
            "step",
            0,
            Rating::Again,
            ReviewKind::Learn,
            0,
            State::Learning,
            Duration::minutes(10),
            5.0,
            2_000,
        ),
        (
            "crammed",
            0,
            Rating::Good,
            ReviewKind::Cram,
            0,
            State::Review,
            d(400),
            5.0,
            500,
        ),
    ];
    for (card, back, rating, kind, elapsed, state, due_in, difficulty, ms) in plan {
        let mut r = review(&k(card), now - d(back), rating, kind, state, due_in);
        r.elapsed_days = elapsed;
        r.after.difficulty = Some(difficulty);
        r.duration_ms = ms;
        store.record(&r).unwrap();
    }
    let items: Vec<ItemKey> = ["mature", "young", "young2", "lapsed", "step", "new"]
        .iter()
        .map(|c| k(c))
        .collect();
    let s = store
        .stats(
            StatsScope {
                deck: Some("mech"),
                items: &items,
            },
            now,
            &grid,
        )
        .unwrap();
    let today = s.reviews_per_day.last().unwrap();
    assert_eq!(today.seconds, 1.25 + 12.0 + 2.0 + 0.5);
    assert_eq!(s.reviews_per_day[27].seconds, 3.0 + 7.5);
    assert_eq!(
        s.reviews_per_day.iter().map(|d| d.seconds).sum::<f64>(),
        26.25
    );

    let b = &s.answer_buttons;
    let row = |x: flipcard::store::stats::Buttons| (x.again, x.hard, x.good, x.easy);
    assert_eq!(
        row(b.mature),
        (1, 0, 1, 0),
        "30 and 40 days since the answer before"
    );
    assert_eq!(row(b.young), (0, 1, 0, 1));
    assert_eq!(row(b.learn), (1, 0, 0, 0));
    assert_eq!(row(b.relearn), (0, 0, 0, 0));
    assert_eq!(row(b.cram), (0, 0, 1, 0));

    // Review and relearning items only: 100, 50, 10 and 2 days.
    let counts: Vec<(Option<f64>, u32)> = s.intervals.iter().map(|x| (x.up_to, x.items)).collect();
    assert_eq!(
        counts,
        [
            (Some(1.0), 0),
            (Some(3.0), 1),
            (Some(7.0), 0),
            (Some(14.0), 1),
            (Some(30.0), 0),
            (Some(90.0), 1),
            (Some(180.0), 1),
            (Some(365.0), 0),
            (None, 0)
        ]
    );
    // Every item with a state (not the crammed one, not in the deck, and
    // not the new one): 2.0 → ≤2, 6.5 → ≤7, 10.0 → ≤10, 9.2 → ≤10, 5.0 → ≤5.
    let diff: Vec<u32> = s.difficulty.iter().map(|x| x.items).collect();
    assert_eq!(diff, [0, 1, 0, 0, 1, 0, 1, 0, 0, 2]);

    // 90 days: the one due in 100 days is past it; 30 days: only 2 and 10
    // days (and the learning step today) of the 50.
    assert_eq!(s.due.per_day_90.len(), 90);
    assert_eq!(s.due.per_day_90[..30], s.due.per_day[..]);
    assert_eq!(s.due.next_30_days, 3);
    assert_eq!(s.due.next_90_days, 4);
    assert_eq!(
        s.due.per_day_90.iter().map(|x| x.due).sum::<u32>(),
        s.due.next_90_days
    );
    let json = serde_json::to_value(&s).unwrap();
    assert_eq!(json["answer_buttons"]["young"]["easy"], 1);
    assert_eq!(json["due"]["next_90_days"], 4);
    assert_eq!(json["reviews_per_day"][29]["seconds"], 15.75);
    assert_eq!(json["intervals"][8]["up_to"], serde_json::Value::Null);
}
