//! `flipcard import --reviews FILE` through the real binary: an export
//! moves a history to a new machine, importing twice changes nothing, and a
//! malformed file names every bad row and writes nothing.

use std::path::Path;
use std::process::{Command, Output};

use chrono::Duration;
use flipcard::sched::{Config, Rating, Scheduler};
use flipcard::store::Store;

use crate::store_support::{at, back_key, key};

const NOW: &str = "2026-05-10T12:00:00Z";

fn flipcard(data: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_flipcard"))
        .args(args)
        .env("FLIPCARD_DATA_DIR", data)
        .env("FLIPCARD_NOW", NOW)
        .env("TZ", "UTC")
        .env("FLIPCARD_CONFIG", data.join("no-such-config.toml"))
        .env_remove("FLIPCARD_DECKS")
        .output()
        .expect("run flipcard")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
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
        assert!(out.status.success(), "{}", text(&out.stderr));
        let file = old.path().join(format!("log.{format}"));
        std::fs::write(&file, &out.stdout).unwrap();

        let new = tempfile::tempdir().unwrap();
        let first = flipcard(new.path(), &["import", "--reviews", file.to_str().unwrap()]);
        assert!(first.status.success(), "{}", text(&first.stderr));
        assert!(
            text(&first.stdout).starts_with("imported 13 reviews from"),
            "{}",
            text(&first.stdout)
        );
        assert!(text(&first.stdout).contains("1 came undone"));
        let exported_again = flipcard(new.path(), &["export", "--reviews", "--format", format]);
        // Same rows, states, kinds and flags: the replay reproduces them.
        assert_eq!(text(&exported_again.stdout), text(&out.stdout), "{format}");

        let second = flipcard(new.path(), &["import", "--reviews", file.to_str().unwrap()]);
        assert!(second.status.success());
        assert!(
            text(&second.stdout).starts_with("imported 0 reviews from"),
            "{}",
            text(&second.stdout)
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
    let err = text(&out.stderr);
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
        text(&out.stderr).contains(&format!("{}:2: card is 3, not a string", json.display())),
        "{}",
        text(&out.stderr)
    );

    let unknown = dir.path().join("log.txt");
    std::fs::write(&unknown, "[]").unwrap();
    let out = flipcard(
        dir.path(),
        &["import", "--reviews", unknown.to_str().unwrap()],
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr).contains("--format json"),
        "{}",
        text(&out.stderr)
    );
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
    assert!(out.status.success(), "{}", text(&out.stderr));
}
