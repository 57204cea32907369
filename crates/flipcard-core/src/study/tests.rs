//! The policy of a rating and of a mark, through the store as the front
//! ends reach it.

use super::*;
use crate::sched::Direction;
use crate::store::ItemStatus;
use std::collections::HashMap;

fn deck() -> Deck {
    let loaded = crate::deck::load_dir(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/decks/study/decks"
    )));
    loaded
        .decks
        .into_iter()
        .next()
        .expect("the study deck loads")
}

fn at(s: &str) -> DateTime<Utc> {
    DateTime::parse_from_rfc3339(s).unwrap().with_timezone(&Utc)
}

fn study(config: Config) -> (tempfile::TempDir, Study) {
    let dir = tempfile::tempdir().unwrap();
    let store = Store::open(dir.path()).unwrap();
    (dir, Study::new(config, DayZone::Utc, store))
}

fn key(card: &str, direction: Direction) -> ItemKey {
    ItemKey {
        deck: "study".into(),
        card: card.into(),
        direction,
    }
}

fn answer(key: &ItemKey, rating: Rating) -> Answer<'_> {
    Answer {
        key,
        before: None,
        rating,
        duration_ms: 1200,
        cram: false,
    }
}

#[test]
fn a_rating_buries_its_siblings_until_the_next_study_day() {
    let d = deck();
    let (_dir, mut s) = study(Config {
        bury_siblings: true,
        ..Config::default()
    });
    let now = at("2026-05-01T10:00:00Z");
    let front = key("spin-axis", Direction::Forward);
    let rated = s.rate(Some(&d), answer(&front, Rating::Good), now).unwrap();
    assert_eq!(
        rated.after.bury,
        vec![key("spin-axis", Direction::Backward)]
    );
    assert_eq!(rated.after.bury_until, s.study_day(now).1);
    let statuses = s.store.statuses().unwrap();
    let back = statuses
        .get(&key("spin-axis", Direction::Backward))
        .expect("the sibling has a status");
    assert!(!back.studyable(now), "{back:?}");
    assert!(back.studyable(s.study_day(now).1));
    // The answer is in the log, at the millisecond of `now`.
    assert_eq!(s.store.state(&front).unwrap(), Some(rated.record.after));
    assert_eq!(rated.record.reviewed_at, now);
}

#[test]
fn cramming_moves_nothing_and_buries_nothing() {
    let d = deck();
    let (_dir, mut s) = study(Config {
        bury_siblings: true,
        ..Config::default()
    });
    let now = at("2026-05-01T10:00:00Z");
    let front = key("spin-axis", Direction::Forward);
    let cram = Answer {
        cram: true,
        ..answer(&front, Rating::Again)
    };
    let rated = s.rate(Some(&d), cram, now).unwrap();
    assert!(rated.after.bury.is_empty());
    assert!(s.store.statuses().unwrap().is_empty());
    assert_eq!(s.store.state(&front).unwrap(), None, "cram leaves it new");
}

#[test]
fn lapses_past_the_threshold_suspend_a_leech_when_the_config_says_so() {
    let d = deck();
    let (_dir, mut s) = study(Config {
        leech_threshold: 2,
        leech_action: LeechAction::Suspend,
        ..Config::default()
    });
    let k = key("middle", Direction::Forward);
    let mut now = at("2026-05-01T10:00:00Z");
    let mut leech = false;
    // Learn it, then forget it until it is a leech.
    for rating in [Rating::Easy, Rating::Again, Rating::Easy, Rating::Again] {
        let before = s.store.state(&k).unwrap();
        let a = Answer {
            before: before.as_ref(),
            ..answer(&k, rating)
        };
        leech |= s.rate(Some(&d), a, now).unwrap().recorded.leech;
        now += chrono::TimeDelta::days(30);
    }
    assert!(leech, "two lapses reach a threshold of two");
    let status: ItemStatus = s.store.statuses().unwrap()[&k];
    assert!(status.leech);
    assert!(!status.studyable(now), "suspended as a leech");
}

#[test]
fn two_answers_in_one_millisecond_are_two_answers() {
    let (_dir, mut s) = study(Config::default());
    let k = key("middle", Direction::Forward);
    let now = at("2026-05-01T10:00:00Z");
    let first = s.rate(None, answer(&k, Rating::Good), now).unwrap();
    let before = s.store.state(&k).unwrap();
    let a = Answer {
        before: before.as_ref(),
        ..answer(&k, Rating::Good)
    };
    let second = s.rate(None, a, now).unwrap();
    assert!(second.record.reviewed_at > first.record.reviewed_at);
    assert_ne!(first.recorded.id, second.recorded.id);
}

#[test]
fn marks_bury_to_the_day_suspend_until_undone_and_undo() {
    let (_dir, mut s) = study(Config::default());
    let k = key("middle", Direction::Forward);
    let now = at("2026-05-01T23:30:00Z");
    s.mark(std::slice::from_ref(&k), Mark::Bury, now).unwrap();
    let st = s.store.statuses().unwrap()[&k];
    assert!(!st.studyable(now));
    assert!(st.studyable(s.study_day(now).1), "back when the day turns");
    s.mark(std::slice::from_ref(&k), Mark::Suspend, now)
        .unwrap();
    assert!(!s.store.statuses().unwrap()[&k].studyable(now + chrono::TimeDelta::days(400)));
    assert!(matches!(s.undo().unwrap(), Some(Undone::Status(_))));
    let st = s.store.statuses().unwrap()[&k];
    assert!(st.studyable(s.study_day(now).1), "the bury is what remains");
    s.mark(std::slice::from_ref(&k), Mark::Unsuspend, now)
        .unwrap();
    assert!(
        s.store
            .statuses()
            .unwrap()
            .get(&k)
            .is_none_or(|st| st.studyable(now))
    );
}

#[test]
fn the_queue_leaves_out_what_is_suspended_or_buried() {
    let d = deck();
    let (_dir, mut s) = study(Config::default());
    let now = at("2026-05-01T10:00:00Z");
    let all = s.counts(&d, now).unwrap().new;
    assert!(all >= 3, "{all}");
    let k = key("middle", Direction::Forward);
    s.mark(std::slice::from_ref(&k), Mark::Suspend, now)
        .unwrap();
    assert_eq!(s.counts(&d, now).unwrap().new, all - 1);
}

#[test]
fn a_derivation_is_rated_as_one_item_stored_and_exported_as_derive() {
    let d = deck();
    let (_dir, mut s) = study(Config {
        bury_siblings: true,
        ..Config::default()
    });
    let now = at("2026-05-01T10:00:00Z");
    // The study deck has no derivation of this id: a derive item is named
    // by id as any item is (an orphan's history is kept, as a card's).
    let k = key("euler", Direction::Derive);
    let rated = s.rate(Some(&d), answer(&k, Rating::Good), now).unwrap();
    assert!(rated.after.bury.is_empty(), "a derivation has no siblings");
    let later = at("2026-05-03T10:00:00Z");
    let before = s.store.state(&k).unwrap();
    s.rate(
        Some(&d),
        Answer {
            before: before.as_ref(),
            ..answer(&k, Rating::Again)
        },
        later,
    )
    .unwrap();
    assert_eq!(
        s.progress(&k).unwrap(),
        derive::Progress {
            successes: 1,
            lapses: 1
        }
    );
    let history = s.store.history(&k).unwrap();
    assert_eq!(history.len(), 2);
    assert!(
        history
            .iter()
            .all(|r| r.record.key.direction == Direction::Derive)
    );
    let mut csv = Vec::new();
    crate::interop::export::write_reviews_csv(&s.store, &mut csv).unwrap();
    let csv = String::from_utf8(csv).unwrap();
    assert_eq!(csv.matches("study,euler,derive,").count(), 2, "{csv}");
}

/// A deck's preset schedules `Study::rate` (the rating a front end
/// stores) and a merged history replayed with `Schedulers` alike: the
/// same answers give the same state on both machines.
#[test]
fn a_presets_scheduler_rates_and_replays_the_same() {
    use crate::sched::Schedulers;
    use crate::sched::preset::{DeckSettings, Preset};
    let config = Config {
        fuzz: false,
        learning_steps: Vec::new(),
        presets: [(
            "short".to_string(),
            Preset {
                maximum_interval: Some(3),
                ..Preset::default()
            },
        )]
        .into(),
        decks: [(
            "study".to_string(),
            DeckSettings {
                preset: Some("short".into()),
            },
        )]
        .into(),
        ..Config::default()
    };
    let d = deck();
    let (_dir, mut s) = study(config.clone());
    let k = key("spin-axis", Direction::Forward);
    let t0 = at("2026-05-01T10:00:00Z");
    let first = s.rate(Some(&d), answer(&k, Rating::Easy), t0).unwrap();
    let t1 = first.record.after.due;
    let before = first.record.after;
    let second = s
        .rate(
            Some(&d),
            Answer {
                before: Some(&before),
                ..answer(&k, Rating::Easy)
            },
            t1,
        )
        .unwrap();
    // Capped at 3 days each time (Easy at 0.9 would be over a week).
    assert!(t1 - t0 <= chrono::TimeDelta::days(3));
    assert_eq!(
        second.record.after.due - second.record.reviewed_at,
        chrono::TimeDelta::days(3)
    );
    let top = Scheduler::new(&config).review(&k, None, Rating::Easy, t0, 0);
    assert!(top.after.due - t0 > chrono::TimeDelta::days(3));

    // Another machine merges the same answers: the same state.
    let dir = tempfile::tempdir().unwrap();
    let mut other = Store::open(dir.path()).unwrap();
    let rows: Vec<crate::store::IncomingReview> = [&first.record, &second.record]
        .iter()
        .map(|r| crate::store::IncomingReview {
            key: r.key.clone(),
            reviewed_at: r.reviewed_at,
            rating: r.rating,
            cram: false,
            duration_ms: r.duration_ms,
            undone: false,
            balanced_days: None,
        })
        .collect();
    other
        .merge_reviews(&rows, &Schedulers::new(&config))
        .unwrap();
    assert_eq!(other.state(&k).unwrap(), Some(second.record.after));
    // With one scheduler for every deck it would differ.
    let dir = tempfile::tempdir().unwrap();
    let mut plain = Store::open(dir.path()).unwrap();
    plain
        .merge_reviews(&rows, &Scheduler::new(&config))
        .unwrap();
    assert_ne!(plain.state(&k).unwrap(), Some(second.record.after));
}

mod balance {
    //! Hard < Good < Easy, load balancing and easy days through
    //! `Study::rate` and `Study::preview`, over due counts in the store.

    use super::*;
    use crate::sched::scheduler::fuzz_range_of;
    use crate::store::KeptState;
    use crate::store::merge::IncomingReview;
    use chrono::{Datelike, TimeDelta};
    use proptest::prelude::*;

    /// Puts `counts[k]` review items of another deck due in the study day
    /// `k` days after the one of `now` (one merge, one transaction).
    fn fill(s: &mut Study, counts: &[u32], now: DateTime<Utc>) {
        let (start, _) = s.study_day(now);
        let mut rows = Vec::new();
        let mut kept = HashMap::new();
        for (k, n) in counts.iter().enumerate() {
            for j in 0..*n {
                let key = ItemKey {
                    deck: "others".into(),
                    card: format!("o{k}-{j}"),
                    direction: Direction::Forward,
                };
                rows.push(IncomingReview {
                    key: key.clone(),
                    reviewed_at: now - TimeDelta::days(40),
                    rating: Rating::Easy,
                    cram: false,
                    duration_ms: 1000,
                    undone: false,
                    balanced_days: None,
                });
                kept.insert(
                    key,
                    KeptState {
                        at: now - TimeDelta::days(40),
                        state: crate::sched::State::Review,
                        due: start + TimeDelta::days(k as i64) + TimeDelta::hours(6),
                        stability: Some(30.0),
                        difficulty: Some(5.0),
                        last_review: Some(now - TimeDelta::days(40)),
                    },
                );
            }
        }
        let scheduler = s.scheduler.clone();
        s.store
            .merge_reviews_keeping(&rows, &scheduler, &kept)
            .unwrap();
    }

    /// A review card last answered `days` ago with stability `stab`, due now.
    fn review_card(s: &mut Study, name: &str, stab: f64, days: i64, now: DateTime<Utc>) -> ItemKey {
        let k = key(name, Direction::Forward);
        let row = IncomingReview {
            key: k.clone(),
            reviewed_at: now - TimeDelta::days(days),
            rating: Rating::Easy,
            cram: false,
            duration_ms: 1000,
            undone: false,
            balanced_days: None,
        };
        let kept = KeptState {
            at: row.reviewed_at,
            state: crate::sched::State::Review,
            due: now,
            stability: Some(stab),
            difficulty: Some(5.0),
            last_review: Some(row.reviewed_at),
        };
        let scheduler = s.scheduler.clone();
        s.store
            .merge_reviews_keeping(&[row], &scheduler, &HashMap::from([(k.clone(), kept)]))
            .unwrap();
        k
    }

    fn days(p: &Preview, now: DateTime<Utc>) -> i64 {
        (p.after.due - now).num_days()
    }

    /// Rates Hard, Good and Easy in turn (undoing each), as the review
    /// screen would, and checks each against the preview shown for its
    /// instant (each answer is recorded after the item's latest, undone
    /// ones too, so each has its own millisecond and fuzz draw), in which
    /// Hard < Good < Easy. Returns the days recorded, and the first
    /// preview's three days with its instant.
    fn rate_each(
        s: &mut Study,
        k: &ItemKey,
        now: DateTime<Utc>,
    ) -> ([i64; 3], [i64; 3], DateTime<Utc>) {
        let before = s.store.state(k).unwrap();
        let mut out = [0; 3];
        let mut first = None;
        for (i, rating) in [Rating::Hard, Rating::Good, Rating::Easy]
            .into_iter()
            .enumerate()
        {
            let at = s.answer_time(k, now).unwrap();
            let shown = s.preview(k, before.as_ref(), at).unwrap();
            let [_, h, g, e] = &shown;
            let three = [days(h, at), days(g, at), days(e, at)];
            assert!(three[0] < three[1] && three[1] < three[2], "{three:?}");
            first.get_or_insert((three, at));
            let answer = Answer {
                key: k,
                before: before.as_ref(),
                rating,
                duration_ms: 1000,
                cram: false,
            };
            let rated = s.rate(None, answer, now).unwrap();
            assert_eq!(rated.record.reviewed_at, at);
            assert_eq!(rated.record.after, shown[i + 1].after, "{rating:?}");
            out[i] = three[i];
            assert!(s.undo().unwrap().is_some());
        }
        let (three, at) = first.unwrap();
        (out, three, at)
    }

    #[test]
    fn a_rating_lands_on_the_emptiest_day_of_its_fuzz_range() {
        let now = at("2026-05-04T10:00:00Z");
        let plain = Scheduler::new(&Config {
            fuzz: false,
            ..Config::default()
        });
        let (_dir, mut s) = study(Config {
            load_balance: true,
            ..Config::default()
        });
        let k = review_card(&mut s, "spin-axis", 12.0, 12, now);
        let before = s.store.state(&k).unwrap();
        let good = days(&plain.preview(&k, before.as_ref(), now)[2], now);
        let (lo, hi) = fuzz_range_of(good);
        assert!(hi - lo >= 4, "{lo}..={hi}");
        // Every day of Good's range crowded but one, which is not the
        // day the uniform draw picks.
        let uniform = days(&s.scheduler.preview(&k, before.as_ref(), now)[2], now);
        let empty = if uniform == lo + 1 { lo + 2 } else { lo + 1 };
        let mut counts = vec![0u32; (hi + 3) as usize];
        for d in lo..=hi {
            counts[d as usize] = if d == empty { 0 } else { 40 };
        }
        fill(&mut s, &counts, now);
        assert_eq!(s.load(now).unwrap().unwrap().count(lo), 40);
        let ([_, g, _], _, _) = rate_each(&mut s, &k, now);
        assert_eq!(g, empty, "Good lands on the empty day, not {uniform}");

        // Load balancing off: the uniform draw, whatever the load.
        s.config.load_balance = false;
        assert_eq!(s.load(now).unwrap(), None);
        let at = s.answer_time(&k, now).unwrap();
        assert_eq!(
            s.preview(&k, before.as_ref(), at).unwrap(),
            s.scheduler.preview(&k, before.as_ref(), at)
        );
        rate_each(&mut s, &k, now);
    }

    #[test]
    fn easy_days_keep_reviews_off_a_weekday() {
        // 2026-05-04 is a Monday; the range of ~12 days holds a Sunday or two.
        let now = at("2026-05-04T10:00:00Z");
        let mut config = Config {
            load_balance: true,
            ..Config::default()
        };
        config.easy_days.0[6] = 0.0;
        let (_dir, mut s) = study(config);
        fill(&mut s, &[3; 40], now);
        let mut seen = std::collections::BTreeSet::new();
        for i in 0..12 {
            let k = review_card(&mut s, &format!("c{i}"), 12.0, 12, now);
            let ([h, g, e], _, _) = rate_each(&mut s, &k, now);
            for d in [h, g, e] {
                let day = (now + TimeDelta::days(d)).date_naive();
                assert_ne!(
                    day.weekday(),
                    chrono::Weekday::Sun,
                    "{d} days on is a Sunday"
                );
                seen.insert(d);
            }
        }
        assert!(seen.len() > 3, "{seen:?}");
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

        /// Through `Study::rate` over any due counts: each button's day is
        /// within its fuzz range above its floor, Hard < Good < Easy, and
        /// the preview the screen shows is what the rating records.
        #[test]
        fn balanced_days_stay_in_range_and_in_order(
            counts in proptest::collection::vec(0u32..12, 0..60),
            stab in 1.0f64..60.0,
            elapsed in 1i64..60,
            sunday in 0.0f64..=1.0,
        ) {
            let now = at("2026-05-04T10:00:00Z");
            let mut config = Config {
                load_balance: true,
                ..Config::default()
            };
            config.easy_days.0[6] = sunday;
            let (_dir, mut s) = study(config);
            fill(&mut s, &counts, now);
            let k = review_card(&mut s, "spin-axis", stab, elapsed, now);
            let before = s.store.state(&k).unwrap().unwrap();
            let (_, [h, g, e], at) = rate_each(&mut s, &k, now);
            prop_assert!(h >= 1 && h < g && g < e, "{} {} {}", h, g, e);
            // Each day within its button's fuzz range (held above the
            // floor the previous interval and the button below set).
            let ranges = s.scheduler.passing_ranges(&before, at, [h, g, e]);
            for (d, (lo, hi)) in [h, g, e].into_iter().zip(ranges) {
                prop_assert!((lo..=hi).contains(&d), "{} outside {}..={}", d, lo, hi);
            }
        }
    }

    /// The review card of `review_card` and the row and kept state that
    /// make it, for another store to start from the same state.
    fn card_rows(
        name: &str,
        stab: f64,
        days: i64,
        now: DateTime<Utc>,
    ) -> (IncomingReview, HashMap<ItemKey, KeptState>) {
        let k = key(name, Direction::Forward);
        let row = IncomingReview {
            key: k.clone(),
            reviewed_at: now - TimeDelta::days(days),
            rating: Rating::Easy,
            cram: false,
            duration_ms: 1000,
            undone: false,
            balanced_days: None,
        };
        let kept = KeptState {
            at: row.reviewed_at,
            state: crate::sched::State::Review,
            due: now,
            stability: Some(stab),
            difficulty: Some(5.0),
            last_review: Some(row.reviewed_at),
        };
        (row, HashMap::from([(k, kept)]))
    }

    /// `record` merged into a fresh store holding only the card's earlier
    /// row and kept state (another machine, which knows nothing of the
    /// due counts of the answer), with the balanced day `day`.
    fn replayed(
        record: &ReviewRecord,
        base: &(IncomingReview, HashMap<ItemKey, KeptState>),
        day: Option<i64>,
        scheduler: &Scheduler,
    ) -> CardState {
        let dir = tempfile::tempdir().unwrap();
        let mut other = Store::open(dir.path()).unwrap();
        let row = IncomingReview {
            key: record.key.clone(),
            reviewed_at: record.reviewed_at,
            rating: record.rating,
            cram: false,
            duration_ms: record.duration_ms,
            undone: false,
            balanced_days: day,
        };
        other
            .merge_reviews_keeping(&[base.0.clone(), row], scheduler, &base.1)
            .unwrap();
        other.state(&record.key).unwrap().unwrap()
    }

    #[test]
    fn a_balanced_rating_keeps_its_day_and_a_replay_takes_it() {
        let now = at("2026-05-04T10:00:00Z");
        // On by default.
        assert!(Config::default().load_balance);
        let (_dir, mut s) = study(Config::default());
        let base = card_rows("spin-axis", 12.0, 12, now);
        let k = review_card(&mut s, "spin-axis", 12.0, 12, now);
        let before = s.store.state(&k).unwrap();
        let at_ = s.answer_time(&k, now).unwrap();
        let plain = Scheduler::new(&Config {
            fuzz: false,
            ..Config::default()
        });
        let good = days(&plain.preview(&k, before.as_ref(), now)[2], now);
        let (lo, hi) = fuzz_range_of(good);
        let uniform = days(&s.scheduler.preview(&k, before.as_ref(), at_)[2], at_);
        let empty = if uniform == lo + 1 { lo + 2 } else { lo + 1 };
        assert!(empty <= hi, "{lo}..={hi}");
        let mut counts = vec![0u32; (hi + 3) as usize];
        for d in lo..=hi {
            counts[d as usize] = if d == empty { 0 } else { 40 };
        }
        fill(&mut s, &counts, now);
        let answer = Answer {
            key: &k,
            before: before.as_ref(),
            rating: Rating::Good,
            duration_ms: 1000,
            cram: false,
        };
        let rated = s.rate(None, answer, now).unwrap();
        assert_eq!(rated.record.reviewed_at, at_);
        assert_eq!(days_of(&rated.record), empty);
        // The day is kept with the answer, in the log.
        assert_eq!(rated.record.balanced_days, Some(empty));
        let logged = s.store.history(&k).unwrap();
        assert_eq!(logged.last().unwrap().record, rated.record);
        // A machine that knows nothing of the load puts it on the same day
        // from the day kept; without it (a line of an older build), on the
        // uniform draw's.
        let scheduler = s.scheduler.clone();
        assert_eq!(
            replayed(&rated.record, &base, Some(empty), &scheduler),
            rated.record.after
        );
        let drawn = replayed(&rated.record, &base, None, &scheduler);
        assert_eq!((drawn.due - at_).num_days(), uniform);
        assert_ne!(drawn.due, rated.record.after.due);
        // A day outside the range the answer allows is not taken.
        for forged in [lo - 1, hi + 40, 1] {
            let got = replayed(&rated.record, &base, Some(forged), &scheduler);
            assert_eq!(got, drawn, "{forged}");
        }
        // The cache, rebuilt from the log, agrees.
        s.store.rebuild().unwrap();
        assert_eq!(s.store.state(&k).unwrap(), Some(rated.record.after));

        // With balancing off nothing is kept.
        s.undo().unwrap().unwrap();
        s.config.load_balance = false;
        let rated = s.rate(None, answer, now).unwrap();
        assert_eq!(rated.record.balanced_days, None);
        let r = &rated.record;
        let drawn = s
            .scheduler
            .review(&k, before.as_ref(), Rating::Good, r.reviewed_at, 1000);
        assert_eq!(r.after, drawn.after);
    }

    fn days_of(r: &ReviewRecord) -> i64 {
        (r.after.due - r.reviewed_at).num_days()
    }

    /// For button `i`, the widest range the buttons below may leave it:
    /// from its start with each below at the start of its own, to its end
    /// with each below at the end of its own.
    fn widest(s: &Scheduler, before: &CardState, at: DateTime<Utc>, i: usize) -> (i64, i64) {
        let chain = |end: bool| {
            let mut chosen = [0; 3];
            let mut out = (0, 0);
            for j in 0..=i {
                let r = s.passing_ranges(before, at, chosen)[j];
                chosen[j] = if end { r.1 } else { r.0 };
                out = r;
            }
            out
        };
        (chain(false).0, chain(true).1)
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 16, ..ProptestConfig::default() })]

        /// Any answer rated through `Study::rate` over any due counts is
        /// replayed by a machine that does not know them onto the same
        /// state; a forged day is taken only within the widest fuzz range
        /// the answer allows, else the uniform draw stands.
        #[test]
        fn a_replay_keeps_the_balanced_day_and_bounds_a_forged_one(
            counts in proptest::collection::vec(0u32..12, 0..60),
            stab in 1.0f64..60.0,
            elapsed in 1i64..60,
            rating in 2usize..=4,
            forged in -5i64..130,
        ) {
            let now = at("2026-05-04T10:00:00Z");
            let (_dir, mut s) = study(Config::default());
            fill(&mut s, &counts, now);
            let base = card_rows("spin-axis", stab, elapsed, now);
            let k = review_card(&mut s, "spin-axis", stab, elapsed, now);
            let before = s.store.state(&k).unwrap();
            let rating = Rating::ALL[rating - 1];
            let answer = Answer {
                key: &k,
                before: before.as_ref(),
                rating,
                duration_ms: 1000,
                cram: false,
            };
            let rated = s.rate(None, answer, now).unwrap();
            let r = &rated.record;
            let scheduler = s.scheduler.clone();
            prop_assert_eq!(
                replayed(r, &base, r.balanced_days, &scheduler),
                r.after
            );
            let i = rating as usize - 2;
            let (lo, hi) = widest(&scheduler, before.as_ref().unwrap(), r.reviewed_at, i);
            if let Some(d) = r.balanced_days {
                prop_assert!((lo..=hi).contains(&d), "{} outside {}..={}", d, lo, hi);
            }
            let drawn = replayed(r, &base, None, &scheduler);
            let got = replayed(r, &base, Some(forged), &scheduler);
            let got_days = (got.due - r.reviewed_at).num_days();
            if !(lo..=hi).contains(&forged) {
                prop_assert_eq!(got, drawn);
            } else if hi <= 90 {
                prop_assert_eq!(got_days, forged);
            } else {
                // An interval too long to balance keeps the draw.
                prop_assert!(got_days == forged || got == drawn);
            }
        }
    }
}
