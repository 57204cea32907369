//! Custom (fitted) FSRS parameters: the scheduler, and a log replayed
//! through the merge, agree with py-fsrs 6 given the same parameters, card
//! for card (`tests/golden/fsrs_py_custom.json`, made by
//! `tests/golden/gen_fsrs_custom_golden.py` with fuzzing off).

use chrono::{DateTime, TimeDelta, Utc};
use flipcard_core::sched::{CardState, Config, Direction, ItemKey, Rating, Scheduler, State};
use flipcard_core::store::{IncomingReview, Store};

use crate::sched_golden::due_or_ordered;
use serde::Deserialize;

/// py-fsrs and the scheduler evaluate the same formulas in the same order
/// in f64: the numbers are expected to be identical.
const REL_TOL: f64 = 1e-12;

#[derive(Deserialize)]
struct Golden {
    fsrs_version: String,
    enable_fuzzing: bool,
    learning_steps: Vec<i64>,
    relearning_steps: Vec<i64>,
    sequences: Vec<Sequence>,
}

#[derive(Deserialize)]
struct Sequence {
    name: String,
    parameters: Vec<String>,
    desired_retention: String,
    reviews: Vec<Review>,
}

#[derive(Deserialize)]
struct Review {
    rating: i64,
    at: String,
    card: PyCard,
}

#[derive(Deserialize)]
struct PyCard {
    state: i64,
    step: Option<u32>,
    stability: Option<String>,
    difficulty: Option<String>,
    due: String,
    last_review: Option<String>,
}

fn time(s: &str) -> DateTime<Utc> {
    DateTime::parse_from_rfc3339(s)
        .expect("time")
        .with_timezone(&Utc)
}

fn float(s: &Option<String>) -> Option<f64> {
    s.as_ref().map(|v| v.parse().expect("a float"))
}

fn card_state(c: &PyCard) -> CardState {
    CardState {
        state: match c.state {
            1 => State::Learning,
            2 => State::Review,
            3 => State::Relearning,
            other => panic!("py-fsrs has no state {other}"),
        },
        step: c.step,
        stability: float(&c.stability),
        difficulty: float(&c.difficulty),
        due: time(&c.due),
        last_review: c.last_review.as_deref().map(time),
    }
}

fn load() -> Golden {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/golden/fsrs_py_custom.json"
    );
    serde_json::from_str(&std::fs::read_to_string(path).expect("golden file")).expect("JSON")
}

/// The config `optimize --apply` would leave, read through the config
/// parser (so the parameters pass its checks).
fn config_for(g: &Golden, seq: &Sequence) -> Config {
    let text = format!(
        "desired_retention = {}\nfuzz = false\nlearning_steps = [{}]\nrelearning_steps = [{}]\nfsrs_parameters = [{}]\n",
        seq.desired_retention,
        g.learning_steps
            .iter()
            .map(|s| format!("\"{s}s\""))
            .collect::<Vec<_>>()
            .join(", "),
        g.relearning_steps
            .iter()
            .map(|s| format!("\"{s}s\""))
            .collect::<Vec<_>>()
            .join(", "),
        seq.parameters.join(", ")
    );
    let config = Config::parse(&text, std::path::Path::new("config.toml"))
        .unwrap_or_else(|e| panic!("{}: {e}", seq.name));
    assert_eq!(config.learning_steps[1], TimeDelta::minutes(10));
    config
}

/// Everything py-fsrs gave but the due time, which `due_or_ordered`
/// checks (Hard < Good < Easy on review cards may raise it).
fn assert_same(got: &CardState, want: &CardState, ctx: &str) {
    assert_eq!(got.state, want.state, "state: {ctx}");
    assert_eq!(got.step, want.step, "step: {ctx}");
    assert_eq!(got.last_review, want.last_review, "last review: {ctx}");
    for (what, g, w) in [
        ("stability", got.stability, want.stability),
        ("difficulty", got.difficulty, want.difficulty),
    ] {
        let (g, w) = (g.expect(what), w.expect(what));
        let d = if g == w {
            0.0
        } else {
            (g - w).abs() / g.abs().max(w.abs())
        };
        assert!(d <= REL_TOL, "{what}: {ctx}: ours {g:?}, py-fsrs {w:?}");
    }
}

#[test]
fn custom_parameters_match_py_fsrs_card_for_card() {
    let g = load();
    assert!(g.fsrs_version.starts_with("6."), "{}", g.fsrs_version);
    assert!(!g.enable_fuzzing);
    let key = ItemKey {
        deck: "golden".into(),
        card: "card".into(),
        direction: Direction::Forward,
    };
    let mut checked = 0;
    let mut ordered = 0;
    for seq in &g.sequences {
        let config = config_for(&g, seq);
        assert_ne!(
            config.fsrs_parameters,
            Some(flipcard_core::sched::scheduler::default_parameters())
        );
        let scheduler = Scheduler::new(&config);
        let mut card: Option<CardState> = None;
        for (i, review) in seq.reviews.iter().enumerate() {
            let rating = Rating::from_number(review.rating).expect("rating");
            let at = time(&review.at);
            let rec = scheduler.review(&key, card.as_ref(), rating, at, 0);
            let want = card_state(&review.card);
            let ctx = format!("{} review {}", seq.name, i + 1);
            assert_same(&rec.after, &want, &ctx);
            let before = card.as_ref();
            if due_or_ordered(
                &scheduler,
                &key,
                before,
                rating,
                at,
                rec.after.due,
                want.due,
                &ctx,
            ) {
                ordered += 1;
            }
            card = Some(want);
            checked += 1;
        }
    }
    eprintln!("{checked} reviews; {ordered} due times raised to keep Hard < Good < Easy");
    assert!(checked > 500, "only {checked} reviews checked");
}

#[test]
fn a_log_merged_with_custom_parameters_replays_as_py_fsrs() {
    let g = load();
    for seq in g.sequences.iter().step_by(5) {
        let scheduler = Scheduler::new(&config_for(&g, seq));
        let dir = tempfile::tempdir().unwrap();
        let mut store = Store::open(dir.path()).unwrap();
        let key = ItemKey {
            deck: "golden".into(),
            card: seq.name.clone(),
            direction: Direction::Forward,
        };
        // Offered newest first: the merge puts them in time order itself.
        let rows: Vec<IncomingReview> = seq
            .reviews
            .iter()
            .rev()
            .map(|r| IncomingReview {
                key: key.clone(),
                reviewed_at: time(&r.at),
                rating: Rating::from_number(r.rating).unwrap(),
                cram: false,
                duration_ms: 1_000,
                undone: false,
                balanced_days: None,
            })
            .collect();
        store.merge_reviews(&rows, &scheduler).unwrap();
        let logged = store.history(&key).unwrap();
        let mut live: Vec<_> = logged.iter().filter(|l| !l.undone).collect();
        live.sort_by_key(|l| (l.record.reviewed_at, l.id));
        // Equal times keep py-fsrs's order only when the ratings say so; the
        // generator's sequences never repeat an instant.
        assert_eq!(live.len(), seq.reviews.len(), "{}", seq.name);
        let mut before: Option<CardState> = None;
        for (i, (l, review)) in live.iter().zip(&seq.reviews).enumerate() {
            let want = card_state(&review.card);
            let ctx = format!("{} logged review {}", seq.name, i + 1);
            assert_same(&l.record.after, &want, &ctx);
            // The replay continues from its own card, whose due time may
            // already be a raised one.
            let at = l.record.reviewed_at;
            let rating = l.record.rating;
            let ours = scheduler.review(&key, before.as_ref(), rating, at, 0).after;
            assert_eq!(
                ours, l.record.after,
                "{ctx}: the merge replays the scheduler"
            );
            due_or_ordered(
                &scheduler,
                &key,
                before.as_ref(),
                rating,
                at,
                ours.due,
                want.due,
                &ctx,
            );
            before = Some(l.record.after);
        }
    }
}
