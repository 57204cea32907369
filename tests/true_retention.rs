//! Anki's true-retention table: review answers by maturity (stability
//! before the answer under 21 days or not) over today, yesterday and the
//! last 7, 30 and 365 learning days; `stats --json` carries it under
//! `true_retention` in the issue's shape.

use std::path::Path;

use chrono::{DateTime, Duration, NaiveTime, Utc};
use flipcard::sched::DayGrid;
use flipcard::sched::{CardState, ItemKey, Rating, ReviewKind, ReviewRecord, State};
use flipcard::store::Store;
use flipcard::store::true_retention::PassFail;

use crate::store_support::{at, key};
use crate::support::Flipcard;

const NOW: &str = "2026-05-10T12:00:00Z";

fn answer(
    k: &ItemKey,
    when: DateTime<Utc>,
    rating: Rating,
    kind: ReviewKind,
    stability_after: f64,
) -> ReviewRecord {
    ReviewRecord {
        key: k.clone(),
        reviewed_at: when,
        rating,
        kind,
        elapsed_days: 0,
        scheduled_days: 1,
        after: CardState {
            state: State::Review,
            step: None,
            stability: Some(stability_after),
            difficulty: Some(5.0),
            due: when + Duration::days(1),
            last_review: Some(when),
        },
        duration_ms: 1_000,
        balanced_days: None,
    }
}

fn pf(passed: u64, failed: u64) -> PassFail {
    PassFail {
        passed,
        failed,
        rate: (passed + failed > 0).then(|| passed as f64 / (passed + failed) as f64),
    }
}

/// A log whose table is known by hand.
fn history(dir: &Path) {
    let now = at(NOW);
    let mut store = Store::open(dir).unwrap();
    let (a, b, c, d) = (key("m", "a"), key("m", "b"), key("m", "c"), key("m", "d"));
    use ReviewKind::*;
    for r in [
        // a: mature (30 d) before today's pass and an hour later a fail.
        answer(&a, now - Duration::days(60), Rating::Good, Learn, 30.0),
        answer(&a, now - Duration::hours(2), Rating::Good, Review, 45.0),
        answer(&a, now - Duration::hours(1), Rating::Again, Review, 3.0),
        // b: young (5 d): failed yesterday, passed 4 days ago.
        answer(&b, now - Duration::days(10), Rating::Good, Learn, 5.0),
        answer(&b, now - Duration::days(4), Rating::Good, Review, 5.0),
        answer(&b, now - Duration::days(1), Rating::Again, Review, 1.0),
        // c: young, 20 days ago (month, not week) and 200 days ago (year).
        answer(&c, now - Duration::days(300), Rating::Easy, Learn, 8.0),
        answer(&c, now - Duration::days(200), Rating::Hard, Review, 12.0),
        answer(&c, now - Duration::days(20), Rating::Good, Review, 20.0),
        // d: mature, 400 days ago: outside every period.
        answer(&d, now - Duration::days(500), Rating::Good, Learn, 40.0),
        answer(&d, now - Duration::days(400), Rating::Good, Review, 80.0),
        // Relearning answers are not review answers.
        answer(&b, now - Duration::hours(20), Rating::Good, Relearn, 2.0),
    ] {
        store.record(&r).unwrap();
    }
    // Undone and cram answers do not count.
    store
        .record(&answer(
            &c,
            now - Duration::hours(3),
            Rating::Again,
            Review,
            1.0,
        ))
        .unwrap();
    store.undo_last().unwrap();
    store
        .record(&answer(
            &d,
            now - Duration::hours(3),
            Rating::Again,
            Cram,
            80.0,
        ))
        .unwrap();
}

#[test]
fn the_table_counts_review_answers_by_maturity_and_period() {
    let dir = tempfile::tempdir().unwrap();
    history(dir.path());
    let store = Store::open(dir.path()).unwrap();
    let grid = DayGrid::new(Utc, NaiveTime::from_hms_opt(4, 0, 0).unwrap());
    let t = store.true_retention(None, at(NOW), &grid).unwrap();
    assert_eq!(t.mature.today, pf(1, 1));
    assert_eq!(t.mature.yesterday, pf(0, 0));
    assert_eq!(t.mature.week, pf(1, 1));
    assert_eq!(t.mature.year, pf(1, 1), "d's answer is 400 days old");
    assert_eq!(t.young.today, pf(0, 0));
    assert_eq!(t.young.yesterday, pf(0, 1));
    assert_eq!(t.young.week, pf(1, 1));
    assert_eq!(t.young.month, pf(2, 1));
    assert_eq!(t.young.year, pf(3, 1));
    assert_eq!(t.young.today.rate, None);
    // One deck only: none in another.
    let other = store.true_retention(Some("x"), at(NOW), &grid).unwrap();
    assert_eq!(other.young.year, pf(0, 0));
}

#[test]
fn stats_json_has_the_table_in_the_issue_shape() {
    let dir = tempfile::tempdir().unwrap();
    history(dir.path());
    let out = Flipcard::new(dir.path())
        .now(NOW)
        .args(["stats", "--json"])
        .run();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let tr = &v["true_retention"];
    for maturity in ["young", "mature"] {
        let m = tr[maturity].as_object().expect(maturity);
        let keys: Vec<&str> = m.keys().map(String::as_str).collect();
        assert_eq!(keys.len(), 5, "{keys:?}");
        for period in ["today", "yesterday", "week", "month", "year"] {
            let p = m[period].as_object().expect(period);
            assert_eq!(p.len(), 3, "{p:?}");
            assert!(p["passed"].is_u64() && p["failed"].is_u64());
            assert!(p["rate"].is_f64() || p["rate"].is_null());
        }
    }
    assert_eq!(tr["young"]["month"]["passed"], 2);
    assert_eq!(tr["young"]["today"]["rate"], serde_json::Value::Null);
    assert_eq!(tr["mature"]["today"]["rate"], 0.5);
    assert_eq!(v["fsrs_parameters"]["source"], "default");

    let text = Flipcard::new(dir.path()).now(NOW).arg("stats").run();
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(text.contains("  month      66.7% (2/3)"), "{text}");
    assert!(text.contains("FSRS parameters: the defaults"), "{text}");
}
