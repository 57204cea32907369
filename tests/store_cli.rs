//! The headless store commands through the real binary: `stats`,
//! `export --reviews`, `export --deck`, `import` and `db rebuild`.

use std::path::{Path, PathBuf};

use crate::store_support::{at, back_key, key, review};
use crate::support::{Flipcard, Output};
use chrono::Duration;
use flipcard::interop::export::REVIEW_FIELDS;
use flipcard::sched::{Rating, ReviewKind, State};
use flipcard::store::Store;

const NOW: &str = "2026-05-10T12:00:00Z";

fn flipcard(data: &Path, args: &[&str]) -> Output {
    Flipcard::new(data).now(NOW).args(args).run()
}

/// A deck folder with one deck `mini` holding `cards` (id, kind), and its
/// (empty) content file.
fn mini_deck(root: &Path, cards: &[(&str, &str)]) -> PathBuf {
    let decks = root.join("decks");
    std::fs::create_dir_all(&decks).unwrap();
    std::fs::create_dir_all(root.join("content/mini")).unwrap();
    std::fs::write(root.join("content/mini/en.toml"), "").unwrap();
    let mut toml =
        String::from("[deck]\nid = 'mini'\ntitle = { en = 'Mini' }\nlanguages = ['en']\n");
    for (id, kind) in cards {
        toml.push_str(&format!(
            "\n[[card]]\nid = '{id}'\nkind = '{kind}'\nfront = {{ en = 'Front of {id}, edited' }}\nback = {{ en = 'Back of {id}' }}\n"
        ));
    }
    std::fs::write(decks.join("mini.toml"), toml).unwrap();
    decks
}

/// Three ratings of `mini`: `a` (twice, the second undone) and `b`.
fn some_history(data: &Path) {
    let mut store = Store::open(data).unwrap();
    let t = at("2026-05-09T08:30:00.250Z");
    store
        .record(&review(
            &key("mini", "a"),
            t,
            Rating::Good,
            ReviewKind::Learn,
            State::Review,
            Duration::days(2),
        ))
        .unwrap();
    store
        .record(&review(
            &key("mini", "b"),
            t,
            Rating::Again,
            ReviewKind::Learn,
            State::Learning,
            Duration::minutes(1),
        ))
        .unwrap();
    store
        .record(&review(
            &key("mini", "a"),
            t + Duration::hours(1),
            Rating::Easy,
            ReviewKind::Review,
            State::Review,
            Duration::days(9),
        ))
        .unwrap();
    store.undo_last().unwrap();
}

#[test]
fn export_reviews_as_json_has_exactly_the_contract_fields() {
    let dir = tempfile::tempdir().unwrap();
    some_history(dir.path());
    let out = flipcard(dir.path(), &["export", "--reviews"]);
    assert!(out.status.success(), "{}", out.stderr());
    let text = out.stdout();
    let records: Vec<serde_json::Value> = serde_json::from_str(&text).unwrap();
    assert_eq!(records.len(), 3);

    // Field order as written, one record per line.
    let first_line = text.lines().nth(1).unwrap();
    let mut keys = Vec::new();
    let mut rest = first_line;
    while let Some(i) = rest.find("\":") {
        let start = rest[..i].rfind('"').unwrap();
        keys.push(rest[start + 1..i].to_string());
        rest = &rest[i + 2..];
        if let Some(comma) = rest.find(",\"") {
            rest = &rest[comma + 1..];
        } else {
            break;
        }
    }
    assert_eq!(keys, REVIEW_FIELDS);

    let r = &records[0];
    assert_eq!(r["deck"], "mini");
    assert_eq!(r["card"], "a");
    assert_eq!(r["direction"], "forward");
    assert_eq!(r["reviewed_at"], "2026-05-09T08:30:00.250Z");
    assert_eq!(r["rating"], 3);
    assert_eq!(r["kind"], "learn");
    assert_eq!(r["state"], "review");
    assert_eq!(r["due"], "2026-05-11T08:30:00.250Z");
    assert_eq!(r["stability"], 2.5);
    assert_eq!(r["duration_ms"], 4000);
    assert_eq!(r["undone"], false);
    assert_eq!(records[2]["undone"], true);
    assert_eq!(records[2]["kind"], "review");
}

#[test]
fn export_reviews_as_csv_has_the_contract_header() {
    let dir = tempfile::tempdir().unwrap();
    some_history(dir.path());
    let out = flipcard(dir.path(), &["export", "--reviews", "--format", "csv"]);
    assert!(out.status.success(), "{}", out.stderr());
    let text = out.stdout();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "deck,card,direction,reviewed_at,rating,kind,elapsed_days,scheduled_days,stability,difficulty,state,due,duration_ms,undone"
    );
    assert_eq!(
        lines.next().unwrap(),
        "mini,a,forward,2026-05-09T08:30:00.250Z,3,learn,0,2,2.5,5.0,review,2026-05-11T08:30:00.250Z,4000,false"
    );
    assert_eq!(lines.count(), 2);
}

#[test]
fn export_of_an_empty_log_is_empty() {
    let dir = tempfile::tempdir().unwrap();
    let out = flipcard(dir.path(), &["export", "--reviews"]);
    assert!(out.status.success(), "{}", out.stderr());
    assert_eq!(
        serde_json::from_str::<Vec<serde_json::Value>>(&out.stdout())
            .unwrap()
            .len(),
        0
    );
}

#[test]
fn db_rebuild_restores_a_damaged_cache() {
    let dir = tempfile::tempdir().unwrap();
    some_history(dir.path());
    let before = Store::open(dir.path()).unwrap().cached_states().unwrap();
    {
        let raw = rusqlite::Connection::open(dir.path().join("flipcard.db")).unwrap();
        raw.execute("DELETE FROM card_state WHERE card = 'a'", [])
            .unwrap();
    }
    let out = flipcard(dir.path(), &["db", "rebuild"]);
    assert!(out.status.success(), "{}", out.stderr());
    assert!(
        out.stdout()
            .contains("rebuilt 2 card states from 3 log rows"),
        "{}",
        out.stdout()
    );
    assert!(out.stdout().contains("1 differed"), "{}", out.stdout());
    assert_eq!(
        Store::open(dir.path()).unwrap().cached_states().unwrap(),
        before
    );
}

#[test]
fn stats_report_orphans_and_history_returns_with_the_card() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    some_history(&data);
    {
        let mut store = Store::open(&data).unwrap();
        store
            .record(&review(
                &back_key("mini", "r"),
                at("2026-05-10T09:00:00Z"),
                Rating::Hard,
                ReviewKind::Learn,
                State::Learning,
                Duration::minutes(10),
            ))
            .unwrap();
    }

    // `b` is gone from the deck (and `a` was edited); `r` is reversed.
    let decks = mini_deck(
        dir.path(),
        &[("a", "basic"), ("r", "reversed"), ("n", "basic")],
    );
    let decks_arg = decks.to_str().unwrap();
    // The bundled decks open too: `--deck mini` keeps to the one deck.
    let out = flipcard(
        &data,
        &["stats", "--decks", decks_arg, "--deck", "mini", "--json"],
    );
    assert!(out.status.success(), "{}", out.stderr());
    let s: serde_json::Value = serde_json::from_str(&out.stdout()).unwrap();
    assert_eq!(s["cards"]["total"], 4, "a, r forward and backward, n");
    assert_eq!(s["cards"]["new"], 2);
    assert_eq!(s["cards"]["review"], 1);
    assert_eq!(s["cards"]["learning"], 1);
    assert_eq!(s["orphans"].as_array().unwrap().len(), 1);
    assert_eq!(s["orphans"][0]["card"], "b");
    assert_eq!(s["orphans"][0]["reviews"], 1);
    assert_eq!(s["orphans"][0]["deck_present"], true);
    assert_eq!(s["due"]["tomorrow"], 1, "a is due 2026-05-11");
    assert_eq!(s["reviews_per_day"][29]["total"], 1);
    assert_eq!(s["reviews_per_day"][28]["total"], 2);

    let text = flipcard(&data, &["stats", "--decks", decks_arg, "--deck", "mini"]);
    assert!(text.status.success(), "{}", text.stderr());
    let t = text.stdout();
    assert!(
        t.contains("Cards: 4 — new 2, learning 1, review 1, relearning 0"),
        "{t}"
    );
    assert!(t.contains("mini/b forward: 1 review\n"), "{t}");

    // `b` comes back: no orphan, and its state is what its history says.
    mini_deck(
        dir.path(),
        &[("a", "basic"), ("b", "basic"), ("r", "reversed")],
    );
    let out = flipcard(
        &data,
        &["stats", "--decks", decks_arg, "--deck", "mini", "--json"],
    );
    let s: serde_json::Value = serde_json::from_str(&out.stdout()).unwrap();
    assert_eq!(s["orphans"].as_array().unwrap().len(), 0);
    assert_eq!(s["cards"]["learning"], 2);
    assert_eq!(s["cards"]["new"], 1);
}

#[test]
fn stats_of_an_unknown_deck_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let decks = mini_deck(dir.path(), &[("a", "basic")]);
    let out = flipcard(
        &dir.path().join("data"),
        &[
            "stats",
            "--decks",
            decks.to_str().unwrap(),
            "--deck",
            "nope",
        ],
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stderr().contains("no deck `nope`"), "{}", out.stderr());
    assert!(out.stderr().contains("mini"), "{}", out.stderr());
}

#[test]
fn a_deck_exported_to_csv_imports_back_and_passes_check() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let out = flipcard(
        &data,
        &[
            "export",
            "--deck",
            "torque-free-rotation",
            "--format",
            "csv",
        ],
    );
    assert!(out.status.success(), "{}", out.stderr());
    let csv_path = dir.path().join("cards.csv");
    std::fs::write(&csv_path, &out.stdout).unwrap();
    assert!(out.stdout().starts_with("front,back,tags\n"));

    let out = flipcard(
        &data,
        &["import", csv_path.to_str().unwrap(), "--deck-id", "again"],
    );
    assert!(out.status.success(), "{}", out.stderr());
    assert!(
        out.stderr().contains("decks/again.toml"),
        "{}",
        out.stderr()
    );
    assert!(
        out.stderr().contains("content/again/en.toml"),
        "{}",
        out.stderr()
    );
    let root = dir.path().join("placed");
    std::fs::create_dir_all(root.join("decks")).unwrap();
    std::fs::create_dir_all(root.join("content/again")).unwrap();
    std::fs::write(root.join("decks/again.toml"), &out.stdout).unwrap();
    std::fs::write(root.join("content/again/en.toml"), "").unwrap();

    let check = flipcard(&data, &["check", root.join("decks").to_str().unwrap()]);
    assert!(
        check.status.success(),
        "{}{}",
        check.stdout(),
        check.stderr()
    );

    // Same texts (primary language) and tags, card for card.
    let original = flipcard::bundled::load();
    let original = original
        .decks
        .iter()
        .find(|d| d.id == "torque-free-rotation")
        .unwrap();
    let again = flipcard::deck::load_dir(&root.join("decks"));
    assert_eq!(again.errors(), 0);
    let again = &again.decks[0];
    let lang = &original.languages[0];
    assert_eq!(again.cards.len(), original.cards.len());
    for (o, n) in original.cards.iter().zip(&again.cards) {
        assert_eq!(n.front.get("en"), o.front.get(lang));
        assert_eq!(n.back.get("en"), o.back.get(lang));
        assert_eq!(n.tags, o.tags);
    }
}

#[test]
fn import_reports_every_bad_row_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let csv_path = dir.path().join("bad.csv");
    std::fs::write(
        &csv_path,
        "front,back,tags\nfine,ok,t\n,no front,t\nfine 2,ok\nx,y,z,w\n",
    )
    .unwrap();
    let out = flipcard(
        dir.path(),
        &["import", csv_path.to_str().unwrap(), "--deck-id", "x"],
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty(), "no deck on stdout");
    let err = out.stderr();
    let file = csv_path.display().to_string();
    assert!(err.contains(&format!("{file}:3: front is empty")), "{err}");
    assert!(
        err.contains(&format!("{file}:5: expected 3 columns")),
        "{err}"
    );
    assert!(
        !err.contains(&format!("{file}:4:")),
        "a row without tags is fine: {err}"
    );
    assert!(err.contains("2 bad rows"), "{err}");

    let out = flipcard(
        dir.path(),
        &[
            "import",
            csv_path.to_str().unwrap(),
            "--deck-id",
            "Not An Id",
        ],
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stderr().contains("not a deck id"), "{}", out.stderr());

    let out = flipcard(
        dir.path(),
        &[
            "import",
            dir.path().join("missing.csv").to_str().unwrap(),
            "--deck-id",
            "x",
        ],
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stderr().contains("missing.csv"), "{}", out.stderr());
}

#[test]
fn imported_math_keeps_its_backslashes() {
    let dir = tempfile::tempdir().unwrap();
    let csv_path = dir.path().join("math.csv");
    std::fs::write(
        &csv_path,
        "front,back,tags\n\"Euler: $I_1\\dot\\omega_1$?\",\"$\\frac{1}{2}$ and it's fine\",euler\n",
    )
    .unwrap();
    let out = flipcard(
        dir.path(),
        &[
            "import",
            csv_path.to_str().unwrap(),
            "--deck-id",
            "m",
            "--lang",
            "hi-Latn",
        ],
    );
    assert!(out.status.success(), "{}", out.stderr());
    let toml_text = out.stdout();
    assert!(
        toml_text.contains(r"'Euler: $I_1\dot\omega_1$?'"),
        "{toml_text}"
    );
    let v: toml::Table = toml::from_str(&toml_text).unwrap();
    assert_eq!(v["deck"]["languages"][0].as_str(), Some("hi-Latn"));
    assert_eq!(
        v["card"][0]["back"]["hi-Latn"].as_str(),
        Some(r"$\frac{1}{2}$ and it's fine")
    );
}

/// 10000-01-01T00:00:00Z and 0001-12-31T00:00:00 BC in milliseconds: times
/// RFC 3339 cannot write (its year has four digits, and no sign).
const YEAR_10000_MS: i64 = 253_402_300_800_000;

fn year_minus_one_ms() -> i64 {
    chrono::NaiveDate::from_ymd_opt(-1, 6, 1)
        .unwrap()
        .and_hms_opt(0, 0, 0)
        .unwrap()
        .and_utc()
        .timestamp_millis()
}

/// Rows that no import writes any more (answer times are checked now),
/// written straight into the database as an older flipcard could have:
/// a review answered in the year 10000, one due in the year -1, and a
/// prompt attempt in the year 10000, after `some_history`'s three rows.
fn rows_out_of_range(data: &Path) {
    some_history(data);
    let raw = rusqlite::Connection::open(data.join("flipcard.db")).unwrap();
    let insert = "INSERT INTO review (deck, card, direction, reviewed_at, rating, kind, \
                  elapsed_days, scheduled_days, state, due, duration_ms) \
                  VALUES ('mini', 'a', 'forward', ?1, 3, 'review', 0, 1, 'review', ?2, 1000)";
    raw.execute(insert, [YEAR_10000_MS, YEAR_10000_MS]).unwrap();
    raw.execute(insert, [1_778_400_000_000, year_minus_one_ms()])
        .unwrap();
    raw.execute(
        "INSERT INTO prompt_attempt (deck, prompt, attempted_at, prediction, correct) \
         VALUES ('mini', 'p', ?1, 'x', 0), ('mini', 'p', 1778400000000, 'y', 1)",
        [YEAR_10000_MS],
    )
    .unwrap();
}

#[test]
fn export_never_writes_a_time_rfc_3339_cannot_hold() {
    let dir = tempfile::tempdir().unwrap();
    rows_out_of_range(dir.path());
    for (args, written, named) in [
        (
            &["export", "--reviews"][..],
            3,
            &[
                "review 4: its reviewed_at is in the year 10000",
                "review 5: its due is in the year -1",
            ][..],
        ),
        (
            &["export", "--reviews", "--format", "csv"],
            3,
            &[
                "review 4: its reviewed_at is in the year 10000",
                "review 5: its due is in the year -1",
            ],
        ),
        (
            &["export", "--attempts"],
            1,
            &["attempt 1 (mini/p): its attempted_at is in the year 10000"],
        ),
        (
            &["export", "--attempts", "--format", "csv"],
            1,
            &["attempt 1 (mini/p): its attempted_at is in the year 10000"],
        ),
    ] {
        let out = flipcard(dir.path(), args);
        let (text, err) = (out.stdout(), out.stderr());
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        // Every time written is RFC 3339; the rows that cannot be are left
        // out and named.
        let times: Vec<String> = if args.contains(&"csv") {
            let mut r = csv::Reader::from_reader(text.as_bytes());
            let header = r.headers().unwrap().clone();
            let rows: Vec<csv::StringRecord> = r.records().map(Result::unwrap).collect();
            assert_eq!(rows.len(), written, "{args:?}: {text}");
            rows.iter()
                .flat_map(|row| {
                    header
                        .iter()
                        .zip(row.iter())
                        .filter(|(h, _)| h.ends_with("_at") || *h == "due")
                        .map(|(_, v)| v.to_string())
                        .collect::<Vec<_>>()
                })
                .collect()
        } else {
            let records: Vec<serde_json::Value> = serde_json::from_str(&text).unwrap();
            assert_eq!(records.len(), written, "{args:?}: {text}");
            records
                .iter()
                .flat_map(|r| {
                    ["reviewed_at", "due", "attempted_at"]
                        .iter()
                        .filter_map(|f| r.get(*f).and_then(|v| v.as_str()).map(String::from))
                        .collect::<Vec<_>>()
                })
                .collect()
        };
        assert!(!times.is_empty());
        for t in &times {
            assert!(
                chrono::DateTime::parse_from_rfc3339(t).is_ok() && t.len() == 24,
                "{args:?}: {t}"
            );
        }
        assert!(
            !text.contains("+10000") && !text.contains("-0001-"),
            "{text}"
        );
        for n in named {
            assert!(err.contains(n), "{args:?}: {err}");
        }
        let last = err.lines().last().unwrap();
        assert!(
            last.starts_with("flipcard: error: ")
                && last.contains("not exported")
                && last.contains("RFC 3339"),
            "{err}"
        );
    }
}

#[test]
fn stats_escapes_the_ids_of_an_orphan_from_the_log() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    {
        // An id no deck can have (the deck format refuses it, and imports
        // check ids now): only a row written straight into the log holds it.
        let mut store = Store::open(&data).unwrap();
        store
            .record(&review(
                &key("ghost\u{1b}]0;owned\u{7}", "c\u{1b}[2J"),
                at("2026-05-09T09:00:00Z"),
                Rating::Good,
                ReviewKind::Learn,
                State::Review,
                Duration::days(1),
            ))
            .unwrap();
    }
    let decks = mini_deck(dir.path(), &[("a", "basic")]);
    for args in [&["stats"][..], &["stats", "--json"]] {
        let mut all = vec!["--decks", decks.to_str().unwrap()];
        all.extend_from_slice(args);
        let out = flipcard(&data, &all);
        assert!(out.status.success(), "{}", out.stderr());
        assert!(!out.stdout.contains(&0x1b), "{args:?}: raw ESC");
        assert!(!out.stdout.contains(&0x07), "{args:?}: raw BEL");
        let text = out.stdout();
        assert!(text.contains("ghost\\u001b]0;owned\\u0007"), "{text}");
        assert!(text.contains("c\\u001b[2J"), "{text}");
    }
}

/// `flipcard import FILE --deck-id mini`, bounded in time.
fn import_cards(dir: &Path, file: &Path) -> Output {
    Flipcard::new(dir)
        .now(NOW)
        .args(["import", file.to_str().unwrap(), "--deck-id", "mini"])
        .run_within(120)
}

#[test]
fn a_csv_of_cards_has_the_limits_of_every_import() {
    let dir = tempfile::tempdir().unwrap();
    // 20,000 cards of the same front: each id was found by trying card,
    // card-2, … card-n again (200 million tries); now one step each.
    let same = dir.path().join("same.csv");
    let mut csv = String::from("front,back\n");
    for i in 0..20_000 {
        csv.push_str(&format!("?,answer {i}\n"));
    }
    std::fs::write(&same, csv).unwrap();
    let out = import_cards(dir.path(), &same);
    assert!(out.status.success(), "{}", out.stderr());
    let deck: toml::Table = out.stdout().parse().unwrap();
    let ids: Vec<&str> = deck["card"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["id"].as_str().unwrap())
        .collect();
    assert_eq!(ids.len(), 20_000);
    assert_eq!(ids[0], "card");
    assert_eq!(ids[1], "card-2");
    assert_eq!(ids[19_999], "card-20000");

    // A file of garbage: twenty rows named, the rest counted.
    let garbage = dir.path().join("garbage.csv");
    std::fs::write(&garbage, "front,back\n".to_string() + &",\n".repeat(500)).unwrap();
    let out = import_cards(dir.path(), &garbage);
    assert_eq!(out.status.code(), Some(1));
    let err = out.stderr();
    assert_eq!(err.lines().count(), 22, "{err}");
    assert!(err.contains("… and 480 more bad rows"), "{err}");
    assert!(out.stdout().is_empty(), "no deck written");

    // A field longer than a card's text can be.
    let long = dir.path().join("long.csv");
    std::fs::write(
        &long,
        format!("front,back\nq,a\nq2,{}\n", "x".repeat(5 << 20)),
    )
    .unwrap();
    let out = import_cards(dir.path(), &long);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        out.stderr()
            .contains("long.csv:3: back is 5 MiB long; a card's text may be at most 4 MiB"),
        "{}",
        out.stderr()
    );

    // A file larger than a deck can sensibly be, refused before it is read
    // (sparse: no disk used).
    let huge = dir.path().join("huge.csv");
    std::fs::File::create(&huge)
        .unwrap()
        .set_len((64 << 20) + 1)
        .unwrap();
    let out = import_cards(dir.path(), &huge);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        out.stderr().contains("huge.csv: it is larger than 64 MiB"),
        "{}",
        out.stderr()
    );
}
