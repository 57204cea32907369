//! `flipcard plan` through the real binary: the JSON contract, the plan it
//! prints against the retrievability the scheduler computes, a cap too small
//! for the target, and bad input.

use std::path::{Path, PathBuf};

use chrono::{DateTime, Duration, Utc};
use flipcard::sched::{CardState, Config, Direction, ItemKey, Rating, Scheduler};
use flipcard::store::Store;
use serde_json::Value;

use crate::support::{Flipcard, Output};

const NOW: &str = "2026-05-10T12:00:00Z";

fn now() -> DateTime<Utc> {
    DateTime::parse_from_rfc3339(NOW)
        .unwrap()
        .with_timezone(&Utc)
}

fn flipcard(root: &Path, args: &[&str]) -> Output {
    // The bundled decks are opened too: plan the fixture deck alone unless
    // the test names a deck itself.
    let mut args = args.to_vec();
    if args.first() == Some(&"plan") && !args.contains(&"--deck") {
        args.extend(["--deck", "mini"]);
    }
    Flipcard::new(root.join("data"))
        .decks(root.join("decks"))
        .config(root.join("config.toml"))
        .now(NOW)
        .args(args)
        .run()
}

/// A deck `mini` with `n` basic cards c0, c1, … and its content file.
fn deck(root: &Path, n: usize) -> PathBuf {
    let decks = root.join("decks");
    std::fs::create_dir_all(&decks).unwrap();
    std::fs::create_dir_all(root.join("content/mini")).unwrap();
    std::fs::write(root.join("content/mini/en.toml"), "").unwrap();
    let mut toml =
        String::from("[deck]\nid = 'mini'\ntitle = { en = 'Mini' }\nlanguages = ['en']\n");
    for i in 0..n {
        toml.push_str(&format!(
            "\n[[card]]\nid = 'c{i}'\nkind = 'basic'\nfront = {{ en = 'Front {i}' }}\nback = {{ en = 'Back {i}' }}\n"
        ));
    }
    std::fs::write(decks.join("mini.toml"), toml).unwrap();
    decks
}

fn key(i: usize) -> ItemKey {
    ItemKey {
        deck: "mini".into(),
        card: format!("c{i}"),
        direction: Direction::Forward,
    }
}

/// Reviews of the first `n` cards through the scheduler: card i learnt
/// (Easy) 30 − 3i days ago, then answered Good once when due (if that is
/// before now). Returns the states the store then holds.
fn history(root: &Path, n: usize) -> Vec<CardState> {
    let s = Scheduler::new(&Config {
        fuzz: false,
        ..Config::default()
    });
    let mut store = Store::open(&root.join("data")).unwrap();
    let mut states = Vec::new();
    for i in 0..n {
        let k = key(i);
        let first = now() - Duration::days(30 - 3 * i as i64);
        let r = s.review(&k, None, Rating::Easy, first, 0);
        store.record(&r).unwrap();
        let mut state = r.after;
        if state.due < now() {
            let r2 = s.review(&k, Some(&state), Rating::Good, state.due, 0);
            store.record(&r2).unwrap();
            state = r2.after;
        }
        states.push(state);
    }
    states
}

fn json(out: &Output) -> Value {
    assert!(out.status.success(), "{}", out.stderr());
    serde_json::from_slice(&out.stdout).expect("one JSON object")
}

#[test]
fn json_has_the_contract_fields_and_a_plan_that_reaches_the_target() {
    let dir = tempfile::tempdir().unwrap();
    deck(dir.path(), 6);
    let states = history(dir.path(), 4);
    let out = flipcard(
        dir.path(),
        &[
            "plan",
            "--exam",
            "2026-05-24",
            "--format",
            "json",
            "--retention",
            "0.9",
        ],
    );
    let v = json(&out);
    assert_eq!(v["exam"], "2026-05-24");
    assert_eq!(v["items"], 6);
    assert_eq!(v["retention"], 0.9);
    assert_eq!(v["shortfall"].as_f64(), Some(0.0));
    let days = v["days"].as_array().unwrap();
    assert_eq!(
        days.len(),
        14,
        "one row a day from today to the day before the exam"
    );
    assert_eq!(days[0]["date"], "2026-05-10");
    assert_eq!(days[13]["date"], "2026-05-23");
    let total: u64 = days.iter().map(|d| d["reviews"].as_u64().unwrap()).sum();
    assert_eq!(v["reviews"].as_u64(), Some(total));
    // The two new cards need a review each at least; nothing needs more
    // than one here (all answers Good, two weeks to go).
    assert!((2..=6).contains(&total), "{total}");

    // Without the plan: the forgetting curve at the exam day, as the
    // scheduler computes it for the stored states.
    let s = Scheduler::new(&Config::default());
    let exam = DateTime::parse_from_rfc3339("2026-05-24T12:00:00Z")
        .unwrap()
        .with_timezone(&Utc);
    let per_item = v["per_item"].as_array().unwrap();
    let mut without = 0.0;
    for (i, item) in per_item.iter().enumerate() {
        assert_eq!(item["card"], format!("c{i}"));
        let want = states.get(i).map_or(0.0, |st| {
            // Whole study days from the last review to the exam day.
            let last = st.last_review.unwrap().date_naive();
            let days = (exam.date_naive() - last).num_days() as f64;
            s.forgetting_curve(days, st.stability.unwrap())
        });
        let got = item["retrievability_without_plan"].as_f64().unwrap();
        assert!((got - want).abs() < 1e-12, "c{i}: {got} vs {want}");
        without += want;
        let with = item["retrievability_with_plan"].as_f64().unwrap();
        assert!(with >= 0.9, "c{i} reaches the target: {with}");
        let reviews = item["reviews"].as_array().unwrap();
        assert_eq!(
            reviews.is_empty(),
            want >= 0.9,
            "c{i}: reviewed only if short"
        );
    }
    let expected = v["expected_recalled_without_plan"].as_f64().unwrap();
    assert!((expected - without).abs() < 1e-9, "{expected} vs {without}");
    let with = v["expected_recalled_with_plan"].as_f64().unwrap();
    assert!(with >= 0.9 * 6.0 && with > expected, "{with}");
}

#[test]
fn a_suspended_card_is_never_planned() {
    let dir = tempfile::tempdir().unwrap();
    deck(dir.path(), 4);
    history(dir.path(), 2);
    let out = flipcard(dir.path(), &["cards", "suspend", "mini/c3"]);
    assert!(out.status.success(), "{}", out.stderr());
    let out = flipcard(
        dir.path(),
        &["plan", "--exam", "2026-05-24", "--format", "json"],
    );
    let v = json(&out);
    assert_eq!(v["items"], 3, "c3 is suspended: {v}");
    let cards: Vec<&str> = v["per_item"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i["card"].as_str().unwrap())
        .collect();
    assert_eq!(cards, ["c0", "c1", "c2"]);
}

#[test]
fn a_cap_too_small_says_how_far_the_plan_falls_short() {
    let dir = tempfile::tempdir().unwrap();
    deck(dir.path(), 5);
    // Five new cards, the exam in two days, one review a day: one review
    // of a new card (stability 2.3 days) leaves 0.909 two days later, so
    // two cards can be brought to 0.9 and three cannot.
    let args = [
        "plan",
        "--exam",
        "2026-05-12",
        "--max-per-day",
        "1",
        "--retention",
        "0.9",
    ];
    let v = json(&flipcard(
        dir.path(),
        &[&args[..], &["--format", "json"]].concat(),
    ));
    assert_eq!(v["reviews"], 2);
    assert_eq!(v["shortfall"].as_f64(), Some(3.0));
    assert_eq!(
        v["days"],
        serde_json::json!([
            {"date": "2026-05-10", "reviews": 1},
            {"date": "2026-05-11", "reviews": 1}
        ])
    );
    assert!(v["cap_needed"].as_u64().is_some_and(|c| c > 1), "{v}");
    let with = v["expected_recalled_with_plan"].as_f64().unwrap();
    assert!(with > 1.8 && with < 2.0, "{with}");

    let text = flipcard(dir.path(), &args);
    assert!(text.status.success(), "{}", text.stderr());
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(
        text.contains("Short: 3 cards of 5 stay below 0.9"),
        "{text}"
    );
    assert!(text.contains("--max-per-day"), "{text}");
    assert!(text.contains("2026-05-11        1"), "{text}");

    // With no time left at all, no cap helps: it says so.
    let today = flipcard(dir.path(), &["plan", "--exam", "2026-05-10"]);
    let today = String::from_utf8_lossy(&today.stdout);
    assert!(today.contains("too little time"), "{today}");
}

#[test]
fn the_configured_retention_and_review_limit_are_the_defaults() {
    let dir = tempfile::tempdir().unwrap();
    deck(dir.path(), 3);
    std::fs::write(
        dir.path().join("config.toml"),
        "desired_retention = 0.8\nreviews_per_day = 2\n",
    )
    .unwrap();
    let v = json(&flipcard(
        dir.path(),
        &["plan", "--exam", "2026-05-20", "--format", "json"],
    ));
    assert_eq!(v["retention"], 0.8);
    assert_eq!(v["max_per_day"], 2);
}

#[test]
fn bad_input_is_one_line_and_exit_status_1() {
    let dir = tempfile::tempdir().unwrap();
    deck(dir.path(), 2);
    let cases: &[(&[&str], &str)] = &[
        (&["--exam", "2026-05-09"], "in the past"),
        (&["--exam", "tomorrow"], "YYYY-MM-DD"),
        (&["--exam", "2026-02-30"], "YYYY-MM-DD"),
        (
            &["--exam", "2026-05-20", "--retention", "1"],
            "between 0 and 1",
        ),
        (
            &["--exam", "2026-05-20", "--retention", "0"],
            "between 0 and 1",
        ),
        (
            &["--exam", "2026-05-20", "--retention", "-0.5"],
            "between 0 and 1",
        ),
        (
            &["--exam", "2026-05-20", "--retention", "NaN"],
            "between 0 and 1",
        ),
        (
            &["--exam", "2026-05-20", "--retention", "x"],
            "between 0 and 1",
        ),
        (
            &["--exam", "2026-05-20", "--deck", "nope"],
            "no deck `nope`",
        ),
        (
            &["--exam", "2026-05-20", "--max-per-day", "0"],
            "--max-per-day",
        ),
        (
            &["--exam", "2026-05-20", "--max-per-day", "-3"],
            "--max-per-day",
        ),
        (&["--exam", "9999-01-01"], "days away"),
    ];
    for (args, says) in cases {
        let out = flipcard(dir.path(), &[&["plan"][..], args].concat());
        let err = out.stderr();
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(out.stdout.is_empty(), "{args:?}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(
            err.starts_with("flipcard: error: ") && err.contains(says),
            "{args:?}: {err}"
        );
    }
}

/// Each planned item says what it asks: `front` in JSON (a field added,
/// none renamed), an "Asks" column in the text.
#[test]
fn the_plan_shows_what_each_item_asks() {
    let dir = tempfile::tempdir().unwrap();
    deck(dir.path(), 3);
    history(dir.path(), 2);
    let out = flipcard(
        dir.path(),
        &["plan", "--exam", "2026-05-24", "--format", "json"],
    );
    let v = json(&out);
    let items = v["per_item"].as_array().unwrap();
    for (i, item) in items.iter().enumerate() {
        assert_eq!(item["card"], format!("c{i}"));
        assert_eq!(item["front"], format!("Front {i}"));
        for k in ["deck", "direction", "retrievability_now", "reviews"] {
            assert!(item.get(k).is_some(), "{k} kept: {item}");
        }
    }
    let out = flipcard(dir.path(), &["plan", "--exam", "2026-05-24"]);
    assert!(out.status.success(), "{}", out.stderr());
    let text = out.stdout();
    let head = text
        .lines()
        .find(|l| l.starts_with("Card"))
        .unwrap_or_else(|| panic!("{text}"));
    assert!(head.contains("Asks"), "{head}");
    for i in 0..3 {
        assert!(
            text.lines()
                .any(|l| l.starts_with(&format!("mini/c{i} forward"))
                    && l.contains(&format!("Front {i}"))),
            "{text}"
        );
    }
}

/// `plan --exam DATE` remembers the date in the config; `plan` alone plans
/// for it until it passes, then says so; a hand-edited bad date is refused
/// with its place.
#[test]
fn the_exam_date_is_remembered_until_it_passes() {
    let dir = tempfile::tempdir().unwrap();
    deck(dir.path(), 3);
    let config = dir.path().join("config.toml");
    std::fs::write(&config, "# mine\nreviews_per_day = 2\n").unwrap();

    let none = flipcard(dir.path(), &["plan"]);
    assert_eq!(none.status.code(), Some(1));
    assert!(
        none.stderr()
            .contains("no exam date: give one with --exam DATE"),
        "{}",
        none.stderr()
    );

    let first = flipcard(dir.path(), &["plan", "--exam", "2026-05-20"]);
    assert!(first.status.success(), "{}", first.stderr());
    assert!(
        first.stdout().contains("exam date 2026-05-20 remembered"),
        "{}",
        first.stdout()
    );
    assert_eq!(
        std::fs::read_to_string(&config).unwrap(),
        "# mine\nreviews_per_day = 2\nexam_date = \"2026-05-20\"\n"
    );
    // Planned again for the same date: nothing to remember anew.
    let again = flipcard(dir.path(), &["plan", "--exam", "2026-05-20"]);
    assert!(!again.stdout().contains("remembered"), "{}", again.stdout());

    let given = json(&flipcard(
        dir.path(),
        &["plan", "--exam", "2026-05-20", "--format", "json"],
    ));
    let remembered = json(&flipcard(dir.path(), &["plan", "--format", "json"]));
    assert_eq!(remembered["exam"], "2026-05-20");
    assert_eq!(remembered, given);

    // The exam day itself still plans for it; the day after, it has passed.
    let on_the_day = |now: &str| {
        Flipcard::new(dir.path().join("data"))
            .decks(dir.path().join("decks"))
            .config(config.clone())
            .now(now)
            .args(["plan", "--deck", "mini"])
            .run()
    };
    assert!(on_the_day("2026-05-20T12:00:00Z").status.success());
    let after = on_the_day("2026-05-21T12:00:00Z");
    assert_eq!(after.status.code(), Some(1));
    assert!(
        after
            .stderr()
            .contains("the remembered exam date 2026-05-20 has passed (today is 2026-05-21)"),
        "{}",
        after.stderr()
    );

    std::fs::write(&config, "exam_date = \"20/05/2026\"\n").unwrap();
    let bad = flipcard(dir.path(), &["plan"]);
    assert_eq!(bad.status.code(), Some(1));
    let msg = bad.stderr();
    assert!(
        msg.contains("config.toml:1:13: `exam_date`") && msg.contains("YYYY-MM-DD"),
        "{msg}"
    );
}

#[test]
fn a_deck_preset_plans_lists_and_counts_with_its_own_parameters() {
    let dir = tempfile::tempdir().unwrap();
    deck(dir.path(), 6);
    let states = history(dir.path(), 4);
    // A preset whose memory model forgets otherwise (another decay, other
    // initial stabilities) and asks for more recall.
    let mut w = flipcard::sched::scheduler::default_parameters();
    w[20] = 0.5;
    w[2] = 1.5;
    let list = w
        .iter()
        .map(|v| v.to_string())
        .collect::<Vec<_>>()
        .join(", ");
    let with_preset = format!(
        "[preset.slow]\ndesired_retention = 0.95\nfsrs_parameters = [{list}]\n\n[deck.mini]\npreset = \"slow\"\n"
    );
    let config_path = dir.path().join("config.toml");
    let plan = |config: &str| {
        std::fs::write(&config_path, config).unwrap();
        json(&flipcard(
            dir.path(),
            &["plan", "--exam", "2026-05-24", "--format", "json"],
        ))
    };
    let top = plan("");
    let preset = plan(&with_preset);
    let config = Config::parse(&with_preset, &config_path).unwrap();
    let theirs = Scheduler::new(&config.for_deck("mini"));
    let plain = Scheduler::new(&Config::default());
    for (i, st) in states.iter().enumerate() {
        let want = theirs.retrievability(st, now());
        let not = plain.retrievability(st, now());
        assert!((want - not).abs() > 1e-3, "c{i}: the models differ");
        for (v, r) in [(&preset, want), (&top, not)] {
            let got = v["per_item"][i]["retrievability_now"].as_f64().unwrap();
            assert!((got - r).abs() < 1e-12, "c{i}: {got} vs {r}");
        }
    }
    // Each card's target is its preset's retention; the plan reaches it.
    for item in preset["per_item"].as_array().unwrap() {
        assert_eq!(item["target"], 0.95, "{item}");
        assert!(item["retrievability_with_plan"].as_f64().unwrap() >= 0.95);
    }
    assert_eq!(top["per_item"][0]["target"], 0.9);
    assert_ne!(
        preset["expected_recalled_without_plan"],
        top["expected_recalled_without_plan"]
    );
    // --retention still asks for one target for every card.
    let asked = json(&flipcard(
        dir.path(),
        &[
            "plan",
            "--exam",
            "2026-05-24",
            "--format",
            "json",
            "--retention",
            "0.8",
        ],
    ));
    assert!(
        asked["per_item"]
            .as_array()
            .unwrap()
            .iter()
            .all(|i| i["target"] == 0.8)
    );
    let text = flipcard(dir.path(), &["plan", "--exam", "2026-05-24"]);
    assert!(text.status.success(), "{}", text.stderr());
    assert!(
        text.stdout().contains("target recall 0.95"),
        "{}",
        text.stdout()
    );

    // The card list's retrievability: the preset's model.
    let cards = flipcard(
        dir.path(),
        &["cards", "list", "deck:mini", "--format", "json"],
    );
    assert!(cards.status.success(), "{}", cards.stderr());
    let rows: Value = serde_json::from_slice(&cards.stdout).unwrap();
    let c0 = rows
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["card"] == "c0")
        .unwrap();
    let got: f64 = c0["retrievability"]
        .as_str()
        .map(|s| s.parse().unwrap())
        .or_else(|| c0["retrievability"].as_f64())
        .unwrap();
    let want = theirs.retrievability(&states[0], now());
    assert!((got - want).abs() < 1e-3, "{got} vs {want}");

    // One deck's statistics name the preset's parameters.
    let stats = json(&flipcard(
        dir.path(),
        &["stats", "--deck", "mini", "--json"],
    ));
    assert_eq!(stats["fsrs_parameters"]["preset"], "slow");
    let values: Vec<f64> = stats["fsrs_parameters"]["values"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(values, w.to_vec());
    let all = json(&flipcard(dir.path(), &["stats", "--json"]));
    assert_eq!(all["fsrs_parameters"]["source"], "default");
    assert!(all["fsrs_parameters"].get("preset").is_none());
}
