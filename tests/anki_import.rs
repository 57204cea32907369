//! `flipcard import FILE.apkg|.colpkg` through the real binary, on packages
//! made by `tests/golden/anki/gen_anki_fixtures.py` (genanki for the legacy
//! layout, Anki itself for the zstd one): decks that pass `flipcard check`,
//! the revlog replayed through FSRS, and bad packages refused with nothing
//! written.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use chrono::{DateTime, Utc};
use flipcard::sched::{Config, Direction, ItemKey, Rating, Scheduler};
use flipcard::store::Store;

const NOW: &str = "2026-03-01T12:00:00Z";
const T0_MS: i64 = 1_767_600_000_000;
const DAY_MS: f64 = 86_400_000.0;

fn fixture(name: &str) -> String {
    format!("{}/tests/golden/anki/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn flipcard(data: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_flipcard"))
        .args(args)
        .env("FLIPCARD_DATA_DIR", data)
        .env("FLIPCARD_NOW", NOW)
        .env("TZ", "UTC")
        .env("FLIPCARD_CONFIG", data.join("none.toml"))
        .env_remove("FLIPCARD_DECKS")
        .output()
        .expect("run flipcard")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// The card id of the card whose front is `front` in a written deck.
fn card_id(deck: &str, front: &str) -> String {
    let doc: toml::Table = deck.parse().expect("deck TOML");
    doc["card"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["front"].as_str() == Some(front))
        .unwrap_or_else(|| panic!("no card {front:?} in\n{deck}"))["id"]
        .as_str()
        .unwrap()
        .to_string()
}

/// The generator's history of one card: (days after T0, ease) with its
/// offsets, manual reschedules (ease 0) left out.
fn history(note: i64, ord: i64, answers: &[(f64, i64)]) -> Vec<(DateTime<Utc>, Rating)> {
    answers
        .iter()
        .filter(|(_, e)| *e > 0)
        .map(|(d, e)| {
            let ms = T0_MS + (d * DAY_MS) as i64 + note * 60_000 + ord * 7_000;
            (
                DateTime::from_timestamp_millis(ms).unwrap(),
                Rating::from_number(*e).unwrap(),
            )
        })
        .collect()
}

#[test]
fn both_layouts_import_decks_that_pass_check_and_their_history() {
    for package in ["legacy.apkg", "modern.apkg", "modern.colpkg"] {
        let dir = tempfile::tempdir().unwrap();
        let data = dir.path().join("data");
        let out = dir.path().join("out");
        let run = flipcard(
            &data,
            &["import", &fixture(package), "--out", out.to_str().unwrap()],
        );
        let stdout = text(&run.stdout);
        assert!(run.status.success(), "{package}: {}", text(&run.stderr));
        assert!(
            stdout.contains("media skipped: 1 file in the package, 1 reference"),
            "{stdout}"
        );

        let deck_path: PathBuf = out.join("decks/physics-rotation.toml");
        let deck = std::fs::read_to_string(&deck_path).unwrap();
        assert!(deck.contains("title = 'Physics::Rotation'"), "{deck}");
        assert!(
            deck.contains("back = 'The rate of change of angular momentum: $\\tau = \\dot L$'"),
            "{deck}"
        );
        assert!(
            deck.contains("back = '$$I = \\frac{1}{3} m L^2$$'"),
            "{deck}"
        );
        assert!(deck.contains("back = 'L = Iω'"), "{deck}");
        assert!(deck.contains("costs \\$0"), "{deck}");
        assert!(!deck.contains('<'), "no HTML left: {deck}");
        // Cloze notes become cloze cards, their deletions in `text`.
        assert!(!stdout.contains("cloze note left out"), "{stdout}");
        assert!(deck.contains("kind = \"cloze\""), "{deck}");
        assert!(deck.contains("{{c1::Euler}}"), "{deck}");
        let check = Command::new(env!("CARGO_BIN_EXE_flipcard"))
            .args(["check", out.join("decks").to_str().unwrap()])
            .output()
            .unwrap();
        assert!(check.status.success(), "{package}: {}", text(&check.stdout));
        assert!(out.join("content/physics-rotation/en.toml").is_file());

        // The history, replayed through FSRS as if answered here.
        let store = Store::open(&data).unwrap();
        let scheduler = Scheduler::new(&Config::default());
        let torque = ItemKey {
            deck: "physics-rotation".into(),
            card: card_id(&deck, "What is torque?"),
            direction: Direction::Forward,
        };
        let momentum_back = ItemKey {
            deck: "physics-rotation".into(),
            card: card_id(&deck, "angular momentum"),
            direction: Direction::Backward,
        };
        for (k, took, answers) in [
            (
                &torque,
                6000,
                history(
                    0,
                    0,
                    &[
                        (0.0, 3),
                        (0.01, 3),
                        (2.0, 3),
                        (9.0, 1),
                        (9.01, 3),
                        (12.0, 3),
                    ],
                ),
            ),
            (
                &momentum_back,
                6200,
                history(2, 1, &[(0.0, 2), (0.01, 3), (1.0, 1), (20.0, 0)]),
            ),
        ] {
            let mut state = None;
            for (at, r) in &answers {
                state = Some(scheduler.review(k, state.as_ref(), *r, *at, 0).after);
            }
            assert_eq!(store.state(k).unwrap(), state, "{package} {k:?}");
            let logged = store.history(k).unwrap();
            assert_eq!(logged.len(), answers.len(), "{package}");
            assert_eq!(logged[0].record.duration_ms, took, "the answer's time");
        }
        // The cloze note's history continues under its deletion c1.
        let doc: toml::Table = deck.parse().expect("deck TOML");
        let cloze = doc["card"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c.get("kind").and_then(|k| k.as_str()) == Some("cloze"))
            .unwrap_or_else(|| panic!("no cloze card in\n{deck}"))["id"]
            .as_str()
            .unwrap()
            .to_string();
        let c1 = ItemKey {
            deck: "physics-rotation".into(),
            card: cloze,
            direction: Direction::Cloze(1),
        };
        assert!(
            !store.history(&c1).unwrap().is_empty(),
            "{package}: the cloze deletion's reviews"
        );
        drop(store);

        // Imported again into another folder: the history is already there.
        let again = flipcard(
            &data,
            &[
                "import",
                &fixture(package),
                "--out",
                dir.path().join("out2").to_str().unwrap(),
            ],
        );
        assert!(
            text(&again.stdout).contains("review history: 0 added, 15 already present"),
            "{}",
            text(&again.stdout)
        );
        // Into the same folder: refused, nothing overwritten.
        let clash = flipcard(
            &data,
            &["import", &fixture(package), "--out", out.to_str().unwrap()],
        );
        assert_eq!(clash.status.code(), Some(1));
        assert!(text(&clash.stderr).contains("already exists"));
        assert_eq!(std::fs::read_to_string(&deck_path).unwrap(), deck);
    }
}

#[test]
fn bad_packages_are_refused_and_nothing_is_written() {
    for (name, want) in [
        (
            "not-a-zip.apkg",
            "is not an Anki package (not a zip archive",
        ),
        (
            "bomb.apkg",
            "unpacks to more than 512 MiB; refusing it as a likely zip bomb",
        ),
        ("damaged.apkg", "the collection collection.anki2 is damaged"),
        (
            "unknown-type.apkg",
            "note type \"Vocabulary (three fields)\" (3 fields, 1 card types) is not Basic",
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let data = dir.path().join("data");
        let out = dir.path().join("out");
        let run = flipcard(
            &data,
            &["import", &fixture(name), "--out", out.to_str().unwrap()],
        );
        assert_eq!(run.status.code(), Some(1), "{name}");
        let err = text(&run.stderr);
        assert_eq!(err.lines().count(), 1, "{name}: {err}");
        assert!(err.contains(want), "{name}: {err}");
        assert!(!out.exists(), "{name}: no deck folder");
        assert!(!data.join("flipcard.db").exists(), "{name}: no database");
    }
    let dir = tempfile::tempdir().unwrap();
    let missing = flipcard(dir.path(), &["import", "nowhere.apkg"]);
    assert_eq!(missing.status.code(), Some(1));
    assert!(text(&missing.stderr).contains("cannot read nowhere.apkg"));
}
