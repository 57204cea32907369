//! `flipcard import --reviews FILE` through the real binary: an export
//! moves a history to a new machine, importing twice changes nothing, and a
//! malformed file names every bad row and writes nothing.

use std::path::Path;

use chrono::Duration;
use flipcard::sched::{Config, Rating, Scheduler};
use flipcard::store::Store;

use crate::store_support::{at, back_key, key};
use crate::support::{Flipcard, Output};

const NOW: &str = "2026-05-10T12:00:00Z";

fn flipcard(data: &Path, args: &[&str]) -> Output {
    Flipcard::new(data).now(NOW).args(args).run()
}

/// A history recorded with the default scheduler (fuzz on, as the app).
fn history(dir: &Path) {
    let s = Scheduler::new(&Config::default());
    let mut store = Store::open(dir).unwrap();
    let t = at("2026-04-01T09:00:00Z");
    for (i, k) in [key("mech", "a"), back_key("mech", "a"), key("rot", "b")]
        .iter()
        .enumerate()
    {
        let mut state = None;
        for (j, (d, r)) in [
            (0, Rating::Good),
            (0, Rating::Good),
            (3, Rating::Again),
            (9, Rating::Good),
        ]
        .into_iter()
        .enumerate()
        {
            let when = t + Duration::days(d) + Duration::minutes(i as i64 * 11 + j as i64 * 3);
            let rec = s.review(k, state.as_ref(), r, when, 2_500);
            state = Some(rec.after);
            store.record(&rec).unwrap();
        }
    }
    // One answer taken back.
    let rec = s.review(
        &key("rot", "b"),
        store.state(&key("rot", "b")).unwrap().as_ref(),
        Rating::Easy,
        at("2026-04-20T09:00:00Z"),
        900,
    );
    store.record(&rec).unwrap();
    store.undo_last().unwrap();
}

#[test]
fn export_then_import_moves_a_history_and_twice_changes_nothing() {
    for format in ["json", "csv"] {
        let old = tempfile::tempdir().unwrap();
        history(old.path());
        let out = flipcard(old.path(), &["export", "--reviews", "--format", format]);
        assert!(out.status.success(), "{}", out.stderr());
        let file = old.path().join(format!("log.{format}"));
        std::fs::write(&file, &out.stdout).unwrap();

        let new = tempfile::tempdir().unwrap();
        let first = flipcard(new.path(), &["import", "--reviews", file.to_str().unwrap()]);
        assert!(first.status.success(), "{}", first.stderr());
        assert!(
            first.stdout().starts_with("imported 13 reviews from"),
            "{}",
            first.stdout()
        );
        assert!(first.stdout().contains("1 came undone"));
        let exported_again = flipcard(new.path(), &["export", "--reviews", "--format", format]);
        // Same rows, states, kinds and flags: the replay reproduces them.
        assert_eq!(exported_again.stdout(), out.stdout(), "{format}");

        let second = flipcard(new.path(), &["import", "--reviews", file.to_str().unwrap()]);
        assert!(second.status.success());
        assert!(
            second.stdout().starts_with("imported 0 reviews from"),
            "{}",
            second.stdout()
        );
        let after = flipcard(new.path(), &["export", "--reviews", "--format", format]);
        assert_eq!(after.stdout, exported_again.stdout);
        let old_states = Store::open(old.path()).unwrap().cached_states().unwrap();
        let new_states = Store::open(new.path()).unwrap().cached_states().unwrap();
        let strip = |v: Vec<flipcard::store::CachedState>| {
            v.into_iter()
                .map(|c| (c.key, c.state, c.reps, c.lapses))
                .collect::<Vec<_>>()
        };
        assert_eq!(strip(new_states), strip(old_states));
    }
}

#[test]
fn malformed_files_name_every_bad_row_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("bad.csv");
    std::fs::write(
        &csv,
        "deck,card,direction,reviewed_at,rating\n\
         mech,a,forward,2026-04-01T09:00:00Z,3\n\
         mech,a,forward,2026-04-02T09:00:00Z,5\n\
         mech,,forward,2026-04-03T09:00:00Z,3\n\
         mech,a,up,2026-04-04T09:00:00Z,3\n",
    )
    .unwrap();
    let out = flipcard(dir.path(), &["import", "--reviews", csv.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let err = out.stderr();
    let name = csv.display().to_string();
    for line in [3, 4, 5] {
        assert!(err.contains(&format!("{name}:{line}: ")), "{err}");
    }
    assert!(!err.contains(&format!("{name}:2:")), "{err}");
    assert!(err.contains("3 bad rows"), "{err}");
    assert!(
        !dir.path().join("flipcard.db").exists(),
        "nothing written, not even an empty database"
    );

    let json = dir.path().join("bad.json");
    std::fs::write(&json, "[\n{\"deck\": \"mech\",\n \"card\": 3}\n]\n").unwrap();
    let out = flipcard(dir.path(), &["import", "--reviews", json.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        out.stderr()
            .contains(&format!("{}:2: card is 3, not a string", json.display())),
        "{}",
        out.stderr()
    );

    let unknown = dir.path().join("log.txt");
    std::fs::write(&unknown, "[]").unwrap();
    let out = flipcard(
        dir.path(),
        &["import", "--reviews", unknown.to_str().unwrap()],
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stderr().contains("--format json"), "{}", out.stderr());
    let out = flipcard(
        dir.path(),
        &[
            "import",
            "--reviews",
            unknown.to_str().unwrap(),
            "--format",
            "json",
        ],
    );
    assert!(out.status.success(), "{}", out.stderr());
}

/// One good row (line 2) and `bad` rows (lines 3…), as CSV and as JSON.
fn both_formats(dir: &Path, bad: &[(&str, &str, &str, &str)]) -> Vec<std::path::PathBuf> {
    let row = |(deck, card, direction, at): (&str, &str, &str, &str)| {
        (
            format!("{deck},{card},{direction},{at},3\n"),
            serde_json::json!({
                "deck": deck, "card": card, "direction": direction,
                "reviewed_at": at, "rating": 3
            })
            .to_string(),
        )
    };
    let good = ("mech", "a", "forward", "2026-04-01T09:00:00Z");
    let rows: Vec<(String, String)> = std::iter::once(good)
        .chain(bad.iter().copied())
        .map(row)
        .collect();
    let csv = dir.join("log.csv");
    let mut text = String::from("deck,card,direction,reviewed_at,rating\n");
    for (c, _) in &rows {
        text.push_str(c);
    }
    std::fs::write(&csv, text).unwrap();
    let json = dir.join("log.json");
    let records: Vec<&str> = rows.iter().map(|(_, j)| j.as_str()).collect();
    std::fs::write(&json, format!("[\n{}\n]\n", records.join(",\n"))).unwrap();
    vec![csv, json]
}

#[test]
fn answers_dated_before_1970_or_in_the_future_are_refused_with_their_line() {
    let dir = tempfile::tempdir().unwrap();
    let bad = [
        ("mech", "b", "forward", "1969-12-31T23:59:59.999Z"),
        // A day and a second after NOW (2026-05-10T12:00:00Z).
        ("mech", "c", "forward", "2026-05-11T12:00:01Z"),
        // In UTC the year 10000.
        ("mech", "d", "forward", "9999-12-31T23:59:59.999-23:59"),
        ("mech", "e", "forward", "9899-06-01T00:00:00Z"),
    ];
    for file in both_formats(dir.path(), &bad) {
        let out = flipcard(dir.path(), &["import", "--reviews", file.to_str().unwrap()]);
        let err = out.stderr();
        assert_eq!(out.status.code(), Some(1), "{err}");
        let name = file.display();
        for (line, says) in [
            (3, "reviewed_at 1969-12-31T23:59:59Z is before 1970"),
            (4, "reviewed_at 2026-05-11T12:00:01Z is in the future"),
            (5, "reviewed_at a time in the year 10000 is in the future"),
            (6, "reviewed_at 9899-06-01T00:00:00Z is in the future"),
        ] {
            assert!(err.contains(&format!("{name}:{line}: {says}")), "{err}");
        }
        assert!(err.contains("4 bad rows"), "{err}");
        assert!(!dir.path().join("flipcard.db").exists(), "nothing written");
    }
    // A day ahead of this clock is still an answer (clocks differ).
    let ok = both_formats(
        dir.path(),
        &[("mech", "b", "forward", "2026-05-11T11:59:59Z")],
    );
    let out = flipcard(
        dir.path(),
        &["import", "--reviews", ok[0].to_str().unwrap()],
    );
    assert!(out.status.success(), "{}", out.stderr());
}

#[test]
fn ids_that_are_not_of_the_deck_format_are_refused_and_quoted_escaped() {
    let dir = tempfile::tempdir().unwrap();
    let t = "2026-04-02T09:00:00Z";
    let bad = [
        ("../../etc", "a", "forward", t),
        ("mech", "A B", "forward", t),
        ("mech", "a\u{1b}[2J\u{1b}]0;owned\u{7}", "forward", t),
        ("mech", "a", "c1000", t),
        ("mech", "a", "sideways\u{1b}[31m", t),
        ("mech", "a", "forward", "when\u{1b}[2J"),
    ];
    for file in both_formats(dir.path(), &bad) {
        let out = flipcard(dir.path(), &["import", "--reviews", file.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(1));
        assert!(
            !out.stderr.contains(&0x1b),
            "no raw ESC reaches the terminal"
        );
        assert!(
            !out.stderr.contains(&0x07),
            "no raw BEL reaches the terminal"
        );
        let err = out.stderr();
        let name = file.display();
        for (line, says) in [
            (3, "deck id \"../../etc\" is not an id"),
            (4, "card id \"A B\" is not an id"),
            (
                5,
                "card id \"a\\u001b[2J\\u001b]0;owned\\u0007\" is not an id",
            ),
            (
                6,
                "direction \"c1000\" is not forward, backward, c1 … c999, predict or derive",
            ),
            (7, "direction \"sideways\\u001b[31m\""),
            (8, "reviewed_at \"when\\u001b[2J\" is not an RFC 3339 time"),
        ] {
            assert!(err.contains(&format!("{name}:{line}: {says}")), "{err}");
        }
        assert!(!dir.path().join("flipcard.db").exists(), "nothing written");
    }
    // Cloze deletions are items too.
    let ok = both_formats(dir.path(), &[("mech", "a", "c999", t)]);
    let out = flipcard(
        dir.path(),
        &["import", "--reviews", ok[1].to_str().unwrap()],
    );
    assert!(out.status.success(), "{}", out.stderr());
    // So is a derivation (direction `derive`), whatever id no deck knows:
    // kept, as another unknown id's history is.
    let ok = both_formats(dir.path(), &[("mech", "no-such-derivation", "derive", t)]);
    let out = flipcard(
        dir.path(),
        &["import", "--reviews", ok[0].to_str().unwrap()],
    );
    assert!(out.status.success(), "{}", out.stderr());
    let listed = flipcard(dir.path(), &["export", "--reviews"]);
    assert!(
        listed
            .stdout()
            .contains("\"card\":\"no-such-derivation\",\"direction\":\"derive\""),
        "{}",
        listed.stdout()
    );
}

#[test]
fn a_file_of_garbage_names_twenty_rows_and_counts_the_rest() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("garbage.csv");
    let mut text_ = String::from("deck,card,direction,reviewed_at,rating\n");
    for i in 0..5000 {
        text_.push_str(&format!("d,c{i},forward,nonsense,3\n"));
    }
    std::fs::write(&csv, text_).unwrap();
    let out = flipcard(dir.path(), &["import", "--reviews", csv.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let err = out.stderr();
    assert_eq!(err.lines().count(), 22, "{err}");
    assert!(err.contains(&format!("{}:21: ", csv.display())), "{err}");
    assert!(!err.contains(&format!("{}:22: ", csv.display())), "{err}");
    assert!(err.contains("… and 4980 more bad rows"), "{err}");
    assert!(err.contains("5000 bad rows in"), "{err}");

    // A file larger than a review log can sensibly be is refused before it
    // is read (a sparse file: no disk is used).
    let huge = dir.path().join("huge.json");
    std::fs::File::create(&huge)
        .unwrap()
        .set_len((512 << 20) + 1)
        .unwrap();
    let out = flipcard(dir.path(), &["import", "--reviews", huge.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        out.stderr().contains("larger than 512 MiB"),
        "{}",
        out.stderr()
    );
    assert!(!dir.path().join("flipcard.db").exists(), "nothing written");
}

#[test]
fn a_large_log_is_read_in_linear_time() {
    // 100,000 records: each record's line was counted from the start of
    // the file (minutes for 15 MB). Every row is bad, so the reading is
    // all there is; the bound only guards against a hang.
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("big.json");
    let mut text_ = String::from("[\n");
    for i in 0..100_000 {
        if i > 0 {
            text_.push_str(",\n");
        }
        text_.push_str(&format!(
            "{{\"deck\":\"d\",\"card\":\"c{i}\",\"direction\":\"forward\",\
             \"reviewed_at\":\"2026-01-01T00:00:00.000Z\",\"rating\":9,\"kind\":\"review\"}}"
        ));
    }
    text_.push_str("\n]\n");
    std::fs::write(&file, text_).unwrap();
    let out = Flipcard::new(dir.path())
        .now(NOW)
        .args(["import", "--reviews", file.to_str().unwrap()])
        .run_within(120);
    assert_eq!(out.status.code(), Some(1));
    let err = out.stderr();
    // Record k is on line k + 1.
    assert!(
        err.contains(&format!("{}:21: rating 9 is not 1–4", file.display())),
        "{err}"
    );
    assert!(err.contains("… and 99980 more bad rows"), "{err}");
}
