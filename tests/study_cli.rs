//! Filtered study and leeches through the real binary: `flipcard review`
//! without DECK checks a tag or state against every deck, and a filter that
//! matches nothing says so in one line before the terminal is touched;
//! `flipcard stats` and `stats --json` name the leeches (with their lapses)
//! and count the suspended and buried items, from the status log the review
//! screen writes.

use std::path::Path;

use chrono::Duration;
use flipcard::sched::{Direction, ItemKey, Rating, ReviewKind, State};
use flipcard::store::{AfterRating, StatusAction, Store};
use serde_json::Value;

use crate::store_support::{at, review};
use crate::support::{Flipcard, Output};

const NOW: &str = "2026-05-10T12:00:00Z";

/// The fixture deck opens beside the bundled ones.
fn flipcard(data: &Path, args: &[&str]) -> Output {
    Flipcard::new(data)
        .now(NOW)
        .decks(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/decks/study/decks"
        ))
        .args(args)
        .run()
}

fn item(card: &str, direction: Direction) -> ItemKey {
    ItemKey {
        deck: "study".into(),
        card: card.into(),
        direction,
    }
}

/// `lapses` review answers rated Again, two days apart, each followed by
/// the leech check at `threshold`.
fn lapse(store: &mut Store, key: &ItemKey, lapses: u32, threshold: u32, suspend: bool) {
    let mut when = at("2026-04-01T10:00:00Z");
    for _ in 0..lapses {
        when += Duration::days(2);
        let r = review(
            key,
            when,
            Rating::Again,
            ReviewKind::Review,
            State::Relearning,
            Duration::minutes(10),
        );
        let after = AfterRating {
            leech_threshold: threshold,
            leech_suspend: suspend,
            bury: Vec::new(),
            bury_until: when,
        };
        store.record_study(&r, &after).unwrap();
    }
}

fn setup(data: &Path) {
    let mut store = Store::open(data).unwrap();
    // A leech suspended (the default action), one only tagged, and an item
    // with lapses under the threshold.
    lapse(&mut store, &item("middle", Direction::Forward), 3, 3, true);
    lapse(
        &mut store,
        &item("spin-axis", Direction::Backward),
        4,
        4,
        false,
    );
    lapse(
        &mut store,
        &item("torque-rate", Direction::Cloze(1)),
        2,
        3,
        true,
    );
    let now = at(NOW);
    store
        .set_status(
            &[item("torque-rate", Direction::Cloze(2))],
            StatusAction::Bury,
            now,
            Some(now + Duration::hours(6)),
        )
        .unwrap();
}

#[test]
fn stats_json_lists_leeches_with_lapses_and_counts_marks() {
    let dir = tempfile::tempdir().unwrap();
    setup(dir.path());
    let o = flipcard(dir.path(), &["stats", "--json"]);
    assert!(o.status.success(), "{}", o.stderr());
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["suspended"], 1);
    assert_eq!(v["buried"], 1);
    assert_eq!(
        v["leeches"],
        serde_json::json!([
            {"deck": "study", "card": "middle", "direction": "forward", "lapses": 3,
             "front": "Middle axis spin?"},
            // Asked backwards: what it asks is the back.
            {"deck": "study", "card": "spin-axis", "direction": "backward", "lapses": 4,
             "front": "Stable spin"},
        ])
    );
    // The fields before these are a contract: the new ones only add.
    let keys: Vec<&str> = v.as_object().unwrap().keys().map(String::as_str).collect();
    for k in [
        "deck",
        "now",
        "today",
        "cards",
        "due",
        "reviews_per_day",
        "retention",
        "prompts",
        "orphans",
        "true_retention",
        "fsrs_parameters",
        "suspended",
        "buried",
        "leeches",
    ] {
        assert!(keys.contains(&k), "missing `{k}` in {keys:?}");
    }

    // One deck's stats keep to that deck.
    let o = flipcard(dir.path(), &["stats", "--json", "--deck", "oscillations"]);
    assert!(o.status.success(), "{}", o.stderr());
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["leeches"], serde_json::json!([]));
    assert_eq!(v["suspended"], 0);
}

#[test]
fn stats_text_names_each_leech_with_its_lapses() {
    let dir = tempfile::tempdir().unwrap();
    setup(dir.path());
    let o = flipcard(dir.path(), &["stats", "--deck", "study"]);
    assert!(o.status.success(), "{}", o.stderr());
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("Suspended: 1; buried today: 1; leeches: 2\n")
            && text.contains("  leech study/middle/forward (3 lapses): Middle axis spin?\n")
            && text.contains("  leech study/spin-axis/backward (4 lapses): Stable spin\n")
            && !text.contains("torque-rate/c1"),
        "{text}"
    );
}

#[test]
fn a_filter_without_a_deck_checks_names_against_every_deck() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (args, says) in [
        // A tag of no deck: named, with the tags of every deck.
        (
            vec!["review", "--tag", "nope"],
            "no card has tag `nope`; tags are ",
        ),
        (
            vec!["review", "--state", "asleep"],
            "unknown state `asleep`; states are new, learning, review, relearning, suspended, leech, buried",
        ),
        // `pendulum` is a tag of the oscillations deck only: unknown there
        // for the study deck, fine across decks (where nothing is due yet).
        (
            vec!["review", "study", "--tag", "pendulum"],
            "no card has tag `pendulum`; tags are euler, frames",
        ),
        (
            vec!["review", "--tag", "pendulum", "--due-within", "3d"],
            "no card of any deck matches the filter (suspended and buried cards are left out)",
        ),
        (
            vec!["review", "--tag", "euler", "--state", "leech"],
            "no card of any deck matches the filter",
        ),
        (
            vec!["review", "--state", "suspended"],
            "add --cram to look through them",
        ),
    ] {
        let o = flipcard(d, &args);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", o.stderr());
        assert!(o.stderr().contains(says), "{args:?}: {}", o.stderr());
        assert_eq!(o.stderr().lines().count(), 1, "{args:?}: {}", o.stderr());
    }
    // The tags listed come from every deck: the fixture's and the bundled.
    let o = flipcard(d, &["review", "--tag", "nope"]);
    for tag in ["euler", "pendulum", "stability", "frames"] {
        assert!(o.stderr().contains(tag), "{tag}: {}", o.stderr());
    }
}

/// `flipcard stats` adds time spent, answer buttons, the interval and
/// difficulty distributions and a 90-day forecast, in text and JSON (the
/// fields before stay as they were).
#[test]
fn stats_show_time_buttons_distributions_and_a_long_forecast() {
    let dir = tempfile::tempdir().unwrap();
    setup(dir.path());
    let o = flipcard(dir.path(), &["stats", "--json", "--deck", "study"]);
    assert!(o.status.success(), "{}", o.stderr());
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    // Nine review answers rated Again (3 + 4 + 2 lapses), each asked the
    // day of the answer before as the fixture writes them: young.
    let young = &v["answer_buttons"]["young"];
    assert_eq!(
        (
            &young["again"],
            &young["hard"],
            &young["good"],
            &young["easy"]
        ),
        (
            &Value::from(9),
            &Value::from(0),
            &Value::from(0),
            &Value::from(0)
        )
    );
    assert_eq!(v["answer_buttons"]["mature"]["again"], 0);
    assert_eq!(v["due"]["per_day_90"].as_array().unwrap().len(), 90);
    assert_eq!(v["due"]["per_day"].as_array().unwrap().len(), 30);
    assert_eq!(v["intervals"].as_array().unwrap().len(), 9);
    assert_eq!(v["difficulty"].as_array().unwrap().len(), 10);
    // Every answer takes 4 s in the fixture: a day's seconds are 4 × its
    // answers.
    for day in v["reviews_per_day"].as_array().unwrap() {
        assert_eq!(
            day["seconds"].as_f64().unwrap(),
            4.0 * day["total"].as_f64().unwrap(),
            "{day}"
        );
    }
    let o = flipcard(dir.path(), &["stats", "--deck", "study"]);
    assert!(o.status.success(), "{}", o.stderr());
    let text = String::from_utf8_lossy(&o.stdout);
    let next_90 = v["due"]["next_90_days"].as_u64().unwrap();
    let seconds: f64 = v["reviews_per_day"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d["seconds"].as_f64().unwrap())
        .sum();
    for want in [
        format!("next 90 days {next_90}\n"),
        "  young          9       0       0       0  0.0%\n".to_string(),
        format!("Time spent, last 30 days: {}s in all", seconds as u64),
        "Intervals (review and relearning items".to_string(),
        "Difficulty (FSRS".to_string(),
    ] {
        assert!(text.contains(&want), "{want:?} in\n{text}");
    }
}
