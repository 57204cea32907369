//! Load balancing across machines: an answer rated through `Study::rate`
//! with balancing on (the default) is placed on the day the balancer chose
//! over this machine's due counts; a second machine that syncs it (and
//! `db rebuild` on either) puts the card on the same day, though it knows
//! nothing of those counts; a forged line naming a day outside the answer's
//! fuzz range does not move the card there.
//!
//! In-process, through `flipcard_core::sync::sync_with` (what `flipcard
//! sync` and the app call) and `Store::rebuild` (what `flipcard db
//! rebuild` calls).

use std::collections::HashMap;
use std::path::Path;

use chrono::{DateTime, TimeDelta, Utc};
use flipcard_core::sched::{CardState, Config, DayZone, Direction, ItemKey, Rating, Scheduler};
use flipcard_core::store::{IncomingReview, KeptState, Store};
use flipcard_core::study::{Answer, Study};
use flipcard_core::sync::{Wait, sync_with};

const FORGER: &str = "ffffffffffffffffffffffffffffffff";

fn at(s: &str) -> DateTime<Utc> {
    DateTime::parse_from_rfc3339(s).unwrap().with_timezone(&Utc)
}

fn key(card: &str) -> ItemKey {
    ItemKey {
        deck: "physics".into(),
        card: card.into(),
        direction: Direction::Forward,
    }
}

/// `counts[k]` review items of another deck due `k` days after `now`'s
/// study day, with no answer the card's replay depends on.
fn fill(store: &mut Store, counts: &[u32], now: DateTime<Utc>, scheduler: &Scheduler) {
    let start = now.date_naive().and_hms_opt(0, 0, 0).unwrap().and_utc();
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
                reviewed_at: now - TimeDelta::days(60),
                rating: Rating::Easy,
                cram: false,
                duration_ms: 1000,
                undone: false,
                balanced_days: None,
            });
            kept.insert(
                key,
                KeptState {
                    at: now - TimeDelta::days(60),
                    state: flipcard_core::sched::State::Review,
                    due: start + TimeDelta::days(k as i64) + TimeDelta::hours(6),
                    stability: Some(30.0),
                    difficulty: Some(5.0),
                    last_review: Some(now - TimeDelta::days(60)),
                },
            );
        }
    }
    store
        .merge_reviews_keeping(&rows, scheduler, &kept)
        .unwrap();
}

fn sync(data: &Path, folder: &Path, now: DateTime<Utc>) {
    let wait = Wait::Up(std::time::Duration::from_secs(5));
    sync_with(data, folder, &Config::default(), now, wait)
        .unwrap_or_else(|e| panic!("sync of {}: {e}", data.display()));
}

fn state(data: &Path, k: &ItemKey) -> CardState {
    Store::open(data).unwrap().state(k).unwrap().unwrap()
}

fn days(due: DateTime<Utc>, from: DateTime<Utc>) -> i64 {
    (due - from).num_days()
}

/// What one scenario gave: the balanced answer on the first machine, and
/// the day a uniform draw would have given it.
struct Scenario {
    _root: tempfile::TempDir,
    folder: std::path::PathBuf,
    root: std::path::PathBuf,
    k: ItemKey,
    answered: flipcard_core::sched::ReviewRecord,
    uniform: i64,
    range: (i64, i64),
    now: DateTime<Utc>,
}

/// Machine `a` learns a card (Easy), then answers it Good on its due day
/// over due counts crowded on every day of Good's fuzz range but one, not
/// the day the uniform draw gives; then syncs.
fn scenario() -> Scenario {
    let root = tempfile::tempdir().unwrap();
    let folder = root.path().join("folder");
    std::fs::create_dir(&folder).unwrap();
    let a = root.path().join("a");
    let config = Config::default();
    assert!(config.load_balance, "on by default");
    let mut study = Study::new(config.clone(), DayZone::Utc, Store::open(&a).unwrap());
    let k = key("torque");
    let t0 = at("2026-04-01T09:00:00Z");
    let first = Answer {
        key: &k,
        before: None,
        rating: Rating::Easy,
        duration_ms: 1500,
        cram: false,
    };
    let learnt = study.rate(None, first, t0).unwrap().record;
    assert_eq!(learnt.after.state, flipcard_core::sched::State::Review);
    let now = learnt.after.due + TimeDelta::hours(1);
    let before = Some(learnt.after);
    let at_ = study.answer_time(&k, now).unwrap();
    let plain = Scheduler::new(&Config {
        fuzz: false,
        ..config.clone()
    });
    let good = days(plain.preview(&k, before.as_ref(), at_)[2].after.due, at_);
    let uniform = days(
        study.scheduler.preview(&k, before.as_ref(), at_)[2]
            .after
            .due,
        at_,
    );
    // Good's range: the uniform draws of every instant nearby span it.
    let (lo, hi) = (0..400)
        .map(|ms| {
            let t = at_ + TimeDelta::milliseconds(ms);
            days(
                study.scheduler.preview(&k, before.as_ref(), t)[2].after.due,
                t,
            )
        })
        .fold((i64::MAX, i64::MIN), |(lo, hi), d| (lo.min(d), hi.max(d)));
    assert!(
        lo <= good && good <= hi && hi - lo >= 2,
        "{lo}..={hi} around {good}"
    );
    let empty = if uniform == lo { lo + 1 } else { lo };
    let mut counts = vec![0u32; (hi + 3) as usize];
    for d in lo..=hi {
        counts[d as usize] = if d == empty { 0 } else { 30 };
    }
    let scheduler = study.scheduler.clone();
    fill(&mut study.store, &counts, now, &scheduler);
    let second = Answer {
        key: &k,
        before: before.as_ref(),
        rating: Rating::Good,
        duration_ms: 1500,
        cram: false,
    };
    let answered = study.rate(None, second, now).unwrap().record;
    assert_eq!(answered.reviewed_at, at_);
    assert_eq!(days(answered.after.due, at_), empty, "on the empty day");
    assert_eq!(answered.balanced_days, Some(empty));
    drop(study);
    let now = now + TimeDelta::hours(1);
    sync(&a, &folder, now);
    Scenario {
        folder,
        root: root.path().to_path_buf(),
        _root: root,
        k,
        answered,
        uniform,
        range: (lo, hi),
        now,
    }
}

#[test]
fn a_synced_machine_and_a_rebuild_keep_the_balanced_day() {
    let s = scenario();
    let a = s.root.join("a");
    let b = s.root.join("b");
    sync(&b, &s.folder, s.now);
    let want = s.answered.after;
    // Without the day kept, the second machine would draw another one.
    assert_ne!(s.uniform, days(want.due, s.answered.reviewed_at));
    assert_eq!(state(&b, &s.k), want, "the second machine");
    // `db rebuild` on either machine: the same.
    for data in [&a, &b] {
        let mut store = Store::open(data).unwrap();
        store.rebuild().unwrap();
        assert_eq!(store.state(&s.k).unwrap(), Some(want), "{}", data.display());
    }
    // The second machine's own log keeps the day too: syncing back and
    // forth changes nothing.
    sync(&a, &s.folder, s.now);
    sync(&b, &s.folder, s.now);
    assert_eq!(state(&a, &s.k), want);
    assert_eq!(state(&b, &s.k), want);
    let history = Store::open(&b).unwrap().history(&s.k).unwrap();
    assert_eq!(history.last().unwrap().record, s.answered);
}

#[test]
fn a_forged_day_outside_the_fuzz_range_does_not_move_the_card() {
    let s = scenario();
    let own = std::fs::read_dir(&s.folder)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "jsonl"))
        .unwrap();
    let text = std::fs::read_to_string(&own).unwrap();
    let (lo, hi) = s.range;
    let empty = s.answered.balanced_days.unwrap();
    let marker = format!("\"balanced_days\":{empty}");
    assert!(text.contains(&marker), "{text}");
    let uniform_due = s.answered.reviewed_at + TimeDelta::days(s.uniform);
    for (n, forged) in [hi + 30, lo - 3, 0, -7, 400, 90_000]
        .into_iter()
        .enumerate()
    {
        let folder = s.root.join(format!("forged-{n}"));
        std::fs::create_dir(&folder).unwrap();
        std::fs::write(
            folder.join(format!("{FORGER}.jsonl")),
            text.replace(&marker, &format!("\"balanced_days\":{forged}")),
        )
        .unwrap();
        let c = s.root.join(format!("c-{n}"));
        sync(&c, &folder, s.now);
        let got = state(&c, &s.k);
        assert_eq!(got.due, uniform_due, "forged {forged}: the uniform draw");
    }
    // A day within the range is taken: the field is what decides.
    let other = if empty == hi { lo } else { hi };
    let folder = s.root.join("moved");
    std::fs::create_dir(&folder).unwrap();
    std::fs::write(
        folder.join(format!("{FORGER}.jsonl")),
        text.replace(&marker, &format!("\"balanced_days\":{other}")),
    )
    .unwrap();
    let c = s.root.join("c-moved");
    sync(&c, &folder, s.now);
    assert_eq!(
        state(&c, &s.k).due,
        s.answered.reviewed_at + TimeDelta::days(other)
    );
}
