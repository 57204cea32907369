//! `flipcard import FILE.apkg|.colpkg` through the real binary, on packages
//! made by `tests/golden/anki/gen_anki_fixtures.py` (genanki for the legacy
//! layout, Anki itself for the zstd one): decks that pass `flipcard check`,
//! the revlog replayed through FSRS, and bad packages refused with nothing
//! written.

use std::path::{Path, PathBuf};

use chrono::{DateTime, Utc};
use flipcard::sched::{Config, Direction, ItemKey, Rating, Scheduler};
use flipcard::store::Store;

use crate::support::{Flipcard, Output};

const NOW: &str = "2026-03-01T12:00:00Z";
const T0_MS: i64 = 1_767_600_000_000;
const DAY_MS: f64 = 86_400_000.0;

fn fixture(name: &str) -> String {
    format!("{}/tests/golden/anki/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn flipcard(data: &Path, args: &[&str]) -> Output {
    Flipcard::new(data).now(NOW).args(args).run()
}

/// The card id of the card whose front is `front` in a written deck.
fn card_id(deck: &str, front: &str) -> String {
    let doc: toml::Table = deck.parse().expect("deck TOML");
    doc["card"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c.get("front").and_then(|f| f.as_str()) == Some(front))
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
        let stdout = run.stdout();
        assert!(run.status.success(), "{package}: {}", run.stderr());
        assert!(
            stdout.contains("media skipped: 1 file in the package, 1 reference"),
            "{stdout}"
        );

        let deck_path: PathBuf = out.join("decks/physics-rotation.toml");
        let deck = std::fs::read_to_string(&deck_path).unwrap();
        // A subdeck is titled by its own name, under its parent.
        assert!(deck.contains("title = 'Rotation'"), "{deck}");
        assert!(deck.contains("parent = 'physics'"), "{deck}");
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
        let check = Flipcard::without_data()
            .args(["check", out.join("decks").to_str().unwrap()])
            .run();
        assert!(check.status.success(), "{package}: {}", check.stdout());
        assert!(out.join("content/physics-rotation/en.toml").is_file());

        // The history, replayed through FSRS as if answered here.
        let store = Store::open(&data).unwrap();
        let scheduler = Scheduler::new(&Config::default());
        let torque = ItemKey {
            deck: "physics-rotation".into(),
            card: card_id(&deck, "What is **torque**?"),
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
            again
                .stdout()
                .contains("review history: 0 added, 15 already present"),
            "{}",
            again.stdout()
        );
        // Into the same folder: refused, nothing overwritten.
        let clash = flipcard(
            &data,
            &["import", &fixture(package), "--out", out.to_str().unwrap()],
        );
        assert_eq!(clash.status.code(), Some(1));
        assert!(clash.stderr().contains("already exists"));
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
    ] {
        let dir = tempfile::tempdir().unwrap();
        let data = dir.path().join("data");
        let out = dir.path().join("out");
        let run = flipcard(
            &data,
            &["import", &fixture(name), "--out", out.to_str().unwrap()],
        );
        assert_eq!(run.status.code(), Some(1), "{name}");
        let err = run.stderr();
        assert_eq!(err.lines().count(), 1, "{name}: {err}");
        assert!(err.contains(want), "{name}: {err}");
        assert!(!out.exists(), "{name}: no deck folder");
        assert!(!data.join("flipcard.db").exists(), "{name}: no database");
    }
    let dir = tempfile::tempdir().unwrap();
    let missing = flipcard(dir.path(), &["import", "nowhere.apkg"]);
    assert_eq!(missing.status.code(), Some(1));
    assert!(missing.stderr().contains("cannot read nowhere.apkg"));
}

/// `legacy.apkg` with its collection changed by `change` (SQL run on the
/// unpacked `collection.anki2`), written as `name` in `dir`: the hostile
/// packages below are built from a real one.
fn rewritten(dir: &Path, name: &str, change: impl FnOnce(&rusqlite::Connection)) -> PathBuf {
    use std::io::{Read, Write};
    let mut zip =
        zip::ZipArchive::new(std::fs::File::open(fixture("legacy.apkg")).unwrap()).unwrap();
    let db = dir.join(format!("{name}.anki2"));
    let mut members: Vec<(String, Vec<u8>)> = Vec::new();
    for i in 0..zip.len() {
        let mut m = zip.by_index(i).unwrap();
        let mut bytes = Vec::new();
        m.read_to_end(&mut bytes).unwrap();
        members.push((m.name().unwrap().into_owned(), bytes));
    }
    for (n, bytes) in &members {
        if n == "collection.anki2" {
            std::fs::write(&db, bytes).unwrap();
        }
    }
    {
        let conn = rusqlite::Connection::open(&db).unwrap();
        change(&conn);
    }
    let collection = std::fs::read(&db).unwrap();
    let path = dir.join(name);
    let mut out = zip::ZipWriter::new(std::fs::File::create(&path).unwrap());
    for (n, bytes) in members {
        out.start_file(n.as_str(), zip::write::SimpleFileOptions::default())
            .unwrap();
        out.write_all(if n == "collection.anki2" {
            &collection
        } else {
            &bytes
        })
        .unwrap();
    }
    out.finish().unwrap();
    path
}

/// `flipcard import PACKAGE --out OUT` with its own data folder, killed
/// and failed after `seconds` (a hang is a failure, not a test that runs
/// for ever).
fn import_within(dir: &Path, package: &Path, seconds: u64) -> Output {
    std::fs::create_dir_all(dir.join("tmp")).unwrap();
    Flipcard::new(dir.join("data"))
        .now(NOW)
        .env("TMPDIR", dir.join("tmp"))
        .args(["import", package.to_str().unwrap(), "--out"])
        .arg(dir.join("out"))
        .run_within(seconds)
}

/// The id of the first note (the one asking "What is torque?").
fn first_note(conn: &rusqlite::Connection) -> i64 {
    conn.query_row("SELECT id FROM notes ORDER BY id LIMIT 1", [], |r| r.get(0))
        .unwrap()
}

/// Sets the front of the first note.
fn set_front(conn: &rusqlite::Connection, front: &str) {
    let id = first_note(conn);
    let flds: String = conn
        .query_row("SELECT flds FROM notes WHERE id = ?1", [id], |r| r.get(0))
        .unwrap();
    let back = flds.split('\u{1f}').nth(1).unwrap().to_string();
    conn.execute(
        "UPDATE notes SET flds = ?1 WHERE id = ?2",
        rusqlite::params![format!("{front}\u{1f}{back}"), id],
    )
    .unwrap();
}

#[test]
fn a_view_in_place_of_a_table_is_refused_in_one_line() {
    // Each view counts up for ever: reading it never ends.
    for (table, columns) in [
        ("notes", "n AS id, 0 AS mid, '' AS flds, '' AS tags"),
        ("cards", "n AS id, n AS nid, 0 AS did, 0 AS ord"),
        (
            "revlog",
            "n AS id, n AS cid, 3 AS ease, 0 AS time, 0 AS type",
        ),
        ("col", "'{}' AS models, '{}' AS decks"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let package = rewritten(dir.path(), "view.apkg", |c| {
            c.execute_batch(&format!(
                "DROP TABLE {table}; CREATE VIEW {table} AS \
                 WITH RECURSIVE r(n) AS (SELECT 1 UNION ALL SELECT n + 1 FROM r) \
                 SELECT {columns} FROM r;"
            ))
            .unwrap();
        });
        let run = import_within(dir.path(), &package, 60);
        let err = run.stderr();
        assert_eq!(run.status.code(), Some(1), "{table}: {err}");
        assert_eq!(err.lines().count(), 1, "{table}: {err}");
        assert!(
            err.contains(&format!("`{table}` is a view, not a table; refusing it")),
            "{table}: {err}"
        );
        assert!(!dir.path().join("out").exists(), "{table}: nothing written");
        assert!(!dir.path().join("data/flipcard.db").exists(), "{table}");
    }
}

#[test]
fn field_text_is_converted_in_linear_time() {
    // 2 MB of `&` took over 100 s, 1.8 MB of `\(x^2\)` 118 s: each `&`
    // searched the rest of the text for a `;`, each MathJax opener the rest
    // for the other kind. The bound is a hang guard (both take seconds).
    for (front, want) in [
        ("&".repeat(2_000_000), "&".repeat(2_000_000)),
        ("\\(x^2\\)".repeat(257_143), "$x^2$".repeat(257_143)),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let package = rewritten(dir.path(), "long.apkg", |c| set_front(c, &front));
        assert!(std::fs::metadata(&package).unwrap().len() < 64 << 10);
        let run = import_within(dir.path(), &package, 120);
        assert!(run.status.success(), "{}", run.stderr());
        let deck =
            std::fs::read_to_string(dir.path().join("out/decks/physics-rotation.toml")).unwrap();
        let doc: toml::Table = deck.parse().unwrap();
        let fronts: Vec<&str> = doc["card"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|c| c.get("front").and_then(|f| f.as_str()))
            .collect();
        assert!(fronts.contains(&want.as_str()), "the long front, exactly");
    }
}

#[test]
fn a_field_longer_than_a_card_can_be_skips_its_note_only() {
    let dir = tempfile::tempdir().unwrap();
    let package = rewritten(dir.path(), "huge.apkg", |c| {
        set_front(c, &"x".repeat(5 << 20))
    });
    let run = import_within(dir.path(), &package, 120);
    let out = run.stdout();
    assert!(run.status.success(), "{}", run.stderr());
    assert!(out.contains("1 note not imported:"), "{out}");
    assert!(
        out.contains("field 1 is 5 MiB of text; a card's text may be at most 4 MiB"),
        "{out}"
    );
    // The other notes are there; the long one is not.
    let deck = std::fs::read_to_string(dir.path().join("out/decks/physics-rotation.toml")).unwrap();
    assert!(deck.contains("angular momentum"), "{deck}");
    assert!(!deck.contains("xxxxxxxx"), "the long note is left out");
}

#[test]
fn a_note_type_of_its_own_maps_its_first_field_to_the_front() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let run = flipcard(
        &dir.path().join("data"),
        &[
            "import",
            &fixture("unknown-type.apkg"),
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let stdout = run.stdout();
    assert!(run.status.success(), "{}", run.stderr());
    assert!(
        stdout.contains(
            "Vocabulary (three fields) (1 note) → basic: front \"Word\", the other fields labelled on the back"
        ),
        "{stdout}"
    );
    let deck = std::fs::read_to_string(out.join("decks/physics-rotation.toml")).unwrap();
    assert!(
        deck.contains(
            "front = 'lever'\nback = '''\nMeaning: a bar on a pivot\nExample: see-saw'''"
        ),
        "{deck}"
    );
}

#[test]
fn answers_dated_before_1970_or_in_the_future_are_refused() {
    for (id, says) in [
        (
            -1_000i64,
            "revlog row -1000: the answer time 1969-12-31T23:59:59Z is before 1970",
        ),
        // NOW is 2026-03-01T12:00:00Z; a day and a minute later.
        (
            1_772_452_860_000,
            "revlog row 1772452860000: the answer time 2026-03-02T12:01:00Z is in the future",
        ),
        // 9999-12-31T23:59:59.999-23:59, in UTC the year 10000.
        (
            253_402_386_339_999,
            "the answer time a time in the year 10000 is in the future",
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let package = rewritten(dir.path(), "dates.apkg", |c| {
            let first: i64 = c
                .query_row("SELECT min(id) FROM revlog", [], |r| r.get(0))
                .unwrap();
            c.execute("UPDATE revlog SET id = ?1 WHERE id = ?2", [id, first])
                .unwrap();
        });
        let run = import_within(dir.path(), &package, 60);
        let err = run.stderr();
        assert_eq!(run.status.code(), Some(1), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains(says), "{err}");
        assert!(err.contains("nothing imported"), "{err}");
        assert!(!dir.path().join("out").exists());
        assert!(!dir.path().join("data/flipcard.db").exists());
    }
}

#[test]
fn the_summary_escapes_deck_names_from_the_collection() {
    let dir = tempfile::tempdir().unwrap();
    let package = rewritten(dir.path(), "names.apkg", |c| {
        let decks: String = c
            .query_row("SELECT decks FROM col", [], |r| r.get(0))
            .unwrap();
        // JSON text: the control characters written as JSON escapes.
        let decks = decks.replace(
            "Physics::Rotation",
            "Physics\\u001b]0;owned\\u0007::Rot\\u001b[2J",
        );
        c.execute("UPDATE col SET decks = ?1", [decks]).unwrap();
    });
    let run = import_within(dir.path(), &package, 60);
    assert!(run.status.success(), "{}", run.stderr());
    assert!(!run.stdout.contains(&0x1b) && !run.stdout.contains(&0x07));
    let out = run.stdout();
    assert!(
        out.contains("(Physics\\u001b]0;owned\\u0007::Rot\\u001b[2J)"),
        "{out}"
    );
    // The deck written has a plain title.
    let deck = std::fs::read_to_string(dir.path().join("out/decks/physics-0-owned-rot-2j.toml"))
        .unwrap_or_else(|_| panic!("{out}"));
    assert!(!deck.contains('\u{1b}'), "{deck}");
}

#[test]
fn a_killed_import_leaves_no_scratch_copy_behind() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir_all(&tmp).unwrap();
    // Large enough that reading it takes a while: a window to kill in.
    let package = rewritten(dir.path(), "big.apkg", |c| {
        let tx = c.unchecked_transaction().unwrap();
        let (mid, did): (i64, i64) = tx
            .query_row(
                "SELECT n.mid, c.did FROM notes n JOIN cards c ON c.nid = n.id LIMIT 1",
                [],
                |r| Ok((r.get(0)?, r.get(1)?)),
            )
            .unwrap();
        for i in 0..20_000i64 {
            tx.execute(
                "INSERT INTO notes (id, guid, mid, mod, usn, tags, flds, sfld, csum, flags, data) \
                 VALUES (?1, ?2, ?3, 0, 0, '', ?4, '', 0, 0, '')",
                rusqlite::params![
                    1_000_000 + i,
                    format!("g{i}"),
                    mid,
                    format!("front {i} {}\u{1f}back {i}", "text ".repeat(40))
                ],
            )
            .unwrap();
            tx.execute(
                "INSERT INTO cards (id, nid, did, ord, mod, usn, type, queue, due, ivl, factor, \
                 reps, lapses, left, odue, odid, flags, data) \
                 VALUES (?1, ?2, ?3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, '')",
                rusqlite::params![5_000_000 + i, 1_000_000 + i, did],
            )
            .unwrap();
        }
        tx.commit().unwrap();
    });
    let scratch = || -> Vec<PathBuf> {
        let mut found: Vec<PathBuf> = std::fs::read_dir(&tmp)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        if let Ok(entries) = std::fs::read_dir(dir.path().join("data")) {
            found.extend(
                entries
                    .map(|e| e.unwrap().path())
                    .filter(|p| !p.to_string_lossy().contains("flipcard.db"))
                    .filter(|p| !p.ends_with("backups")),
            );
        }
        // The day's copy of the database is no scratch file: the next open
        // of a database with history writes it (the killed import may have
        // committed some before the kill, on a slow machine). A copy left
        // half-written would be.
        if let Ok(entries) = std::fs::read_dir(dir.path().join("data/backups")) {
            found.extend(entries.map(|e| e.unwrap().path()).filter(|p| {
                let name = p.file_name().unwrap().to_string_lossy().into_owned();
                !(name.starts_with("flipcard-") && name.ends_with(".db"))
            }));
        }
        found
    };
    let mut child = Flipcard::new(dir.path().join("data"))
        .now(NOW)
        .env("TMPDIR", &tmp)
        .args(["import", package.to_str().unwrap(), "--out"])
        .arg(dir.path().join("out"))
        .command()
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Killed (SIGKILL: nothing runs after it) as soon as a scratch copy
    // appears, or mid-read when none ever does.
    let start = std::time::Instant::now();
    while scratch().is_empty()
        && start.elapsed() < std::time::Duration::from_millis(1500)
        && child.try_wait().unwrap().is_none()
    {
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    let _ = child.kill();
    child.wait().unwrap();
    // The next import runs to its end, and nothing is left from either.
    let left = tempfile::tempdir().unwrap();
    let run = Flipcard::new(dir.path().join("data"))
        .now(NOW)
        .env("TMPDIR", &tmp)
        .args(["import", &fixture("legacy.apkg"), "--out"])
        .arg(left.path().join("out"))
        .run();
    assert!(run.status.success(), "{}", run.stderr());
    assert_eq!(
        scratch(),
        Vec::<PathBuf>::new(),
        "scratch files left behind"
    );
}

/// `stock.json`: what Anki itself had in `stock.apkg`, written by the
/// generator beside it.
fn stock_expectations() -> serde_json::Value {
    let text = std::fs::read_to_string(fixture("stock.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// The item a card of `stock.json` is in flipcard (its deck from the
/// note's Anki deck).
fn stock_key(card: &serde_json::Value) -> ItemKey {
    let deck = if card["note"].as_i64().unwrap() >= 13 {
        "oscillations-anki"
    } else {
        "physics-waves"
    };
    let ord = card["ord"].as_i64().unwrap();
    let direction = match (card["note_type"].as_str().unwrap(), ord) {
        ("Cloze", n) => Direction::Cloze(n as u16 + 1),
        (_, 1) => Direction::Backward,
        _ => Direction::Forward,
    };
    ItemKey {
        deck: deck.into(),
        card: format!("n{}", card["nid"].as_i64().unwrap()),
        direction,
    }
}

/// The due date Anki gives a card of `stock.json`.
fn anki_due(crt: i64, card: &serde_json::Value) -> DateTime<Utc> {
    let due = card["due"].as_i64().unwrap();
    let secs = match card["type"].as_i64().unwrap() {
        1 | 3 if due > 1_000_000_000 => due,
        _ => crt + due * 86_400,
    };
    DateTime::from_timestamp(secs, 0).unwrap()
}

#[test]
fn every_stock_note_type_and_state_of_an_anki_collection_is_imported() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let out = dir.path().join("out");
    let run = flipcard(
        &data,
        &[
            "import",
            &fixture("stock.apkg"),
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let stdout = run.stdout();
    assert!(run.status.success(), "{}", run.stderr());
    for line in [
        "states kept: suspended 1, buried 1, flagged 2 (as flag: tags), leeches 1; due dates and intervals as Anki had them: 10 cards",
        "  Basic (and reversed card) (1 note) → reversed",
        "  Basic (optional reversed card) (2 notes) → basic (1), reversed (1) by its Add Reverse field",
        "  Basic (type in the answer) (1 note) → typed",
        "  Cloze (2 notes) → cloze",
        "  Physics constant (1 note) → basic: front \"Name\", the other fields labelled on the back",
        "1 note not imported:",
        "(Basic): its front is only media, which is not imported",
        "math not rendered (kept as text) in 1 field:",
        " Back\n",
        "deck \"Oscillations\" is oscillations-anki (the bundled deck oscillations has the id oscillations)",
        "deck options of physics-waves: Anki preset \"Physics preset\", 7 new/day, 70 reviews/day, steps 2m 15m, relearning steps 5m, desired retention 0.85, 21 FSRS parameters",
        "media skipped: 1 file in the package, 1 reference in the notes",
        &format!(
            "add them for good with `flipcard decks add {}`",
            out.display()
        ),
    ] {
        assert!(stdout.contains(line), "{line:?} in\n{stdout}");
    }
    let check = Flipcard::without_data()
        .args(["check", out.join("decks").to_str().unwrap()])
        .run();
    assert!(check.status.success(), "{}", check.stdout());

    let waves = std::fs::read_to_string(out.join("decks/physics-waves.toml")).unwrap();
    let osc = std::fs::read_to_string(out.join("decks/oscillations-anki.toml")).unwrap();
    for want in [
        // Deletions inside MathJax stay inside the math, beside one outside.
        "text = \"Hooke's law: $F = -{{c1::k}} x$\"",
        "text = 'The {{c1::speed of light}} is $c = 1/\\sqrt{ {{c2::\\mu_0\\varepsilon_0}} }$'",
        // <sup>, <sub>, bold, italic, lists, tables, an empty field.
        "back = '**c** = 3.00 × 10⁸ m/s'",
        "back = 'a₀ ≈ 5.3 × 10⁻¹¹ m, about *half* an ångström'",
        "back = 'n₁ sin θ₁ = n₂ sin θ₂'",
        "back = '''\n- mass\n- length\n- time'''",
        "back = '''\nForce | N\nEnergy | J'''",
        "front = 'Nothing on the back'\nback = ''",
        // Optional reversed: reversed when filled, else basic; type-in: typed.
        "kind = \"reversed\"\nfront = \"Hooke's law\"",
        "front = 'Unit of frequency'\nback = 'hertz'\n",
        "kind = \"typed\"\nfront = 'SI unit of force'\nback = 'newton'\naccept = ['newton']",
        // Flags as tags.
        "tags = ['constants', 'flag:red']",
        "tags = ['optics', 'flag:blue']",
        // Math flipcard cannot render, kept as text.
        "back = '\\(\\bra{\\psi} H \\ket{\\psi}\\) costs \\$0'",
    ] {
        assert!(waves.contains(want), "{want:?} in\n{waves}");
    }
    assert!(!waves.contains("(media not imported)"), "{waves}");
    assert!(
        osc.contains(
            "front = 'Planck constant'\nback = '''\nSymbol: h\nValue: 6.626 × 10⁻³⁴ J s'''"
        ),
        "{osc}"
    );
    assert!(!osc.contains("leech"), "the leech tag is a mark: {osc}");
    // The options as presets the config reads, and `A::B` under `A`.
    let presets = std::fs::read_to_string(out.join("anki-presets.toml")).unwrap();
    let c = Config::parse(&presets, Path::new("anki-presets.toml")).unwrap();
    assert_eq!(c.preset_of("physics-waves"), Some("anki-physics-preset"));
    let waves_preset = c.for_deck("physics-waves");
    assert_eq!(waves_preset.new_per_day, 7);
    assert_eq!(waves_preset.reviews_per_day, 70);
    assert_eq!(
        waves_preset.learning_steps,
        [
            chrono::TimeDelta::minutes(2),
            chrono::TimeDelta::minutes(15)
        ]
    );
    assert_eq!(
        waves_preset.relearning_steps,
        [chrono::TimeDelta::minutes(5)]
    );
    assert_eq!(waves_preset.desired_retention, 0.85);
    assert_eq!(waves_preset.maximum_interval, 36500);
    assert!(waves_preset.fsrs_parameters.is_some());
    assert_eq!(c.preset_of("oscillations-anki"), Some("anki-default"));
    assert!(
        stdout.contains("written to ")
            && stdout.contains(
                "anki-presets.toml as presets [preset.anki-default], [preset.anki-physics-preset]"
            ),
        "{stdout}"
    );
    assert!(waves.contains("parent = 'physics'\n"), "{waves}");
    let physics = std::fs::read_to_string(out.join("decks/physics.toml")).unwrap();
    assert!(physics.contains("title = 'Physics'"), "{physics}");

    // Every card with a history: its reviews, and Anki's due date exactly.
    let expect = stock_expectations();
    let crt = expect["crt"].as_i64().unwrap();
    let now: DateTime<Utc> = NOW.parse().unwrap();
    let check_dues = |store: &Store| {
        let mut kept = 0;
        for card in expect["cards"].as_array().unwrap() {
            let revlog: Vec<i64> = card["revlog"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_i64().unwrap())
                .collect();
            let front = card["front"].as_str().unwrap();
            if front.starts_with("<img") {
                continue;
            }
            let key = stock_key(card);
            let logged: Vec<i64> = store
                .history(&key)
                .unwrap()
                .iter()
                .map(|l| l.record.reviewed_at.timestamp_millis())
                .collect();
            assert_eq!(logged, revlog, "{front} {key:?}");
            if revlog.is_empty() {
                assert_eq!(store.state(&key).unwrap(), None, "{front}");
                continue;
            }
            let state = store.state(&key).unwrap().unwrap();
            assert_eq!(
                state.due,
                anki_due(crt, card),
                "{front} {key:?}: Anki's due"
            );
            kept += 1;
        }
        kept
    };
    let store = Store::open(&data).unwrap();
    assert_eq!(check_dues(&store), 10);
    // Anki's states, as flipcard's marks.
    let status_of = |front: &str| {
        let card = expect["cards"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["front"] == front)
            .unwrap();
        store.status(&stock_key(card)).unwrap()
    };
    assert!(status_of("Bohr radius").suspended);
    assert!(status_of("SI unit of force").buried(now));
    assert!(status_of("Period of a pendulum").leech);
    assert!(!status_of("Speed of light in vacuum").suspended);
    drop(store);
    // The due dates live in the log: a rebuild of the cache keeps them.
    let rebuild = flipcard(&data, &["db", "rebuild"]);
    assert!(rebuild.status.success(), "{}", rebuild.stderr());
    assert_eq!(check_dues(&Store::open(&data).unwrap()), 10);
}

/// Anki's own library (the `anki` package on PyPI), through
/// [`crate::support::require`]: `.ci/run` installs the version pinned there.
fn require_anki_library() -> bool {
    crate::support::require(
        crate::support::works("python3", &["-c", "import anki.collection"]),
        "Python 3 with Anki's library (`anki`)",
        "pip install anki==26.9.3",
    )
}

#[test]
fn an_anki_collection_goes_through_flipcard_and_back_into_anki() {
    if !require_anki_library() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let out = dir.path().join("out");
    let run = flipcard(
        &data,
        &[
            "import",
            &fixture("stock.apkg"),
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(run.status.success(), "{}", run.stderr());
    let package = dir.path().join("back.apkg");
    let export = Flipcard::new(&data)
        .now(NOW)
        .args([
            "--decks",
            out.join("decks").to_str().unwrap(),
            "export",
            "--apkg",
            package.to_str().unwrap(),
        ])
        .run();
    assert!(export.status.success(), "{}", export.stderr());
    assert!(
        export.stdout().contains("38 reviews"),
        "{}",
        export.stdout()
    );
    // One deck only: the others are not in the package.
    let one = dir.path().join("one.apkg");
    let export_one = Flipcard::new(&data)
        .now(NOW)
        .args([
            "--decks",
            out.join("decks").to_str().unwrap(),
            "export",
            "--apkg",
            one.to_str().unwrap(),
            "--deck",
            "oscillations-anki",
        ])
        .run();
    assert!(export_one.status.success(), "{}", export_one.stderr());
    assert!(
        export_one
            .stdout()
            .contains("1 deck, 2 notes, 2 cards, 9 reviews"),
        "{}",
        export_one.stdout()
    );

    // Anki's own library imports it into a fresh collection.
    let script = format!(
        "{}/tests/golden/anki/roundtrip.py",
        env!("CARGO_MANIFEST_DIR")
    );
    let read = std::process::Command::new("python3")
        .args([script.as_str(), package.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(
        read.status.success(),
        "{}",
        String::from_utf8_lossy(&read.stderr)
    );
    let back: serde_json::Value = serde_json::from_slice(&read.stdout).unwrap();
    let today = back["today"].as_i64().unwrap();
    let cutoff = back["cutoff"].as_i64().unwrap();
    let expect = stock_expectations();
    let crt = expect["crt"].as_i64().unwrap();
    let mut compared = 0;
    let mut emphasised = 0;
    for card in expect["cards"].as_array().unwrap() {
        let fields: Vec<&str> = card["fields"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f.as_str().unwrap())
            .collect();
        if fields[0].starts_with("<img") {
            continue;
        }
        let key = stock_key(card);
        let guid = format!("flipcard/{}/{}", key.deck, key.card);
        let note = back["notes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|n| n["guid"] == guid.as_str())
            .unwrap_or_else(|| panic!("no note {guid} back in Anki"));
        // The same text where the field had no HTML to convert but bold
        // and italic (imported as the reader's `**`/`*`, exported back).
        let front = note["fields"][0].as_str().unwrap();
        let without_emphasis = ["<b>", "</b>", "<i>", "</i>"]
            .iter()
            .fold(fields[0].to_string(), |f, t| f.replace(t, ""));
        if !without_emphasis.contains(['<', '&']) {
            assert_eq!(front, fields[0], "{guid}");
            emphasised += usize::from(without_emphasis != fields[0]);
        }
        let ord = card["ord"].as_i64().unwrap();
        let again = note["cards"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["ord"].as_i64() == Some(ord))
            .unwrap_or_else(|| panic!("{guid}: no card {ord} back in Anki"));
        // The same revlog: its ids (answer times) and eases.
        assert_eq!(again["revlog"], card["revlog"], "{guid} card {ord}");
        assert_eq!(again["eases"], card["eases"], "{guid} card {ord}");
        // The same state: type, queue (suspended, buried), due date.
        assert_eq!(again["type"], card["type"], "{guid} card {ord}");
        assert_eq!(again["queue"], card["queue"], "{guid} card {ord}");
        let due = again["due"].as_i64().unwrap();
        match card["type"].as_i64().unwrap() {
            2 => {
                // Day numbers count from each collection's own day 0: the
                // date they name is the same.
                let date = cutoff - 86_400 + (due - today) * 86_400;
                assert_eq!(
                    DateTime::from_timestamp(date, 0),
                    Some(anki_due(crt, card)),
                    "{guid} card {ord}"
                );
                compared += 1;
            }
            1 | 3 => {
                assert_eq!(
                    DateTime::from_timestamp(due, 0),
                    Some(anki_due(crt, card)),
                    "{guid} card {ord}"
                );
                compared += 1;
            }
            _ => {}
        }
    }
    assert_eq!(compared, 10, "every card with a history compared");
    assert!(emphasised > 0, "bold or italic went through and back");
}

/// `no-history.json`: what Anki had in `no-history.apkg`.
fn no_history_expectations() -> serde_json::Value {
    let text = std::fs::read_to_string(fixture("no-history.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// Cards Anki scheduled whose review history is not in the package keep
/// Anki's state (due date, interval, memory state): in the store, in
/// `cards list` and in the queue; a new card stays new, and a card with
/// its history keeps Anki's due date as before.
#[test]
fn cards_with_a_schedule_and_no_review_history_keep_ankis_state() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let out = dir.path().join("out");
    let run = flipcard(
        &data,
        &[
            "import",
            &fixture("no-history.apkg"),
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(run.status.success(), "{}", run.stderr());
    let stdout = run.stdout();
    assert!(
        stdout.contains(
            "due dates and intervals as Anki had them: 4 cards (3 with no review history"
        ),
        "{stdout}"
    );
    let expect = no_history_expectations();
    let crt = expect["crt"].as_i64().unwrap();
    let store = Store::open(&data).unwrap();
    let key = |card: &serde_json::Value| ItemKey {
        deck: "scheduled".into(),
        card: format!("n{}", card["nid"].as_i64().unwrap()),
        direction: Direction::Forward,
    };
    let mut kept = Vec::new();
    for card in expect["cards"].as_array().unwrap() {
        let front = card["front"].as_str().unwrap();
        let state = store.state(&key(card)).unwrap();
        if card["type"].as_i64().unwrap() == 0 {
            assert_eq!(state, None, "{front}: new stays new");
            continue;
        }
        let state = state.unwrap_or_else(|| panic!("{front}: Anki's state was not kept"));
        assert_eq!(state.due, anki_due(crt, card), "{front}: Anki's due");
        let data: serde_json::Value = serde_json::from_str(card["data"].as_str().unwrap()).unwrap();
        assert_eq!(state.stability, data["s"].as_f64(), "{front}");
        assert_eq!(state.difficulty, data["d"].as_f64(), "{front}");
        let want = match card["type"].as_i64().unwrap() {
            1 => flipcard::sched::State::Learning,
            2 => flipcard::sched::State::Review,
            _ => flipcard::sched::State::Relearning,
        };
        assert_eq!(state.state, want, "{front}");
        if card["revlog"].as_array().unwrap().is_empty() {
            assert!(store.history(&key(card)).unwrap().is_empty(), "{front}");
            assert_eq!(
                state.last_review.map(|t| t.timestamp()),
                data["lrt"].as_i64(),
                "{front}"
            );
        }
        kept.push((key(card), state));
    }
    assert_eq!(kept.len(), 4);
    // `cards list` shows them as Anki had them.
    let deck = out.join("decks");
    let list = Flipcard::new(&data)
        .now(NOW)
        .decks(&deck)
        .args(["cards", "list", "deck:scheduled", "--format", "json"])
        .run();
    assert!(list.status.success(), "{}", list.stderr());
    let rows: serde_json::Value = serde_json::from_str(&list.stdout()).unwrap();
    for (key, state) in &kept {
        let row = rows
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["card"] == key.card.as_str())
            .unwrap_or_else(|| panic!("{} not listed", key.card));
        assert_ne!(row["state"], "new", "{row}");
        let due: DateTime<Utc> = row["due"].as_str().unwrap().parse().unwrap();
        assert_eq!(due, state.due, "{row}");
    }
    // The day's queue: the review card due by then is a review, not new.
    let config = Config::default();
    let study = flipcard::study::Study::new(config, flipcard::study::DayZone::Utc, store);
    let loaded = flipcard::deck::load_dir(&deck);
    let d = loaded.decks.iter().find(|d| d.id == "scheduled").unwrap();
    let late: DateTime<Utc> =
        kept.iter().map(|(_, s)| s.due).max().unwrap() + chrono::TimeDelta::days(1);
    let (queue, _) = study.queue(d, late).unwrap();
    let counts = queue.counts();
    assert_eq!(counts.new, 1, "only the new card is new: {counts:?}");
    assert_eq!(counts.due + counts.learning, 4, "{counts:?}");
}

/// A sync that brings another machine's answer from before Anki's last
/// review leaves Anki's due date as it was; one from after it is scheduled
/// from Anki's state (a review card stays a review card).
#[test]
fn a_sync_of_an_earlier_answer_keeps_ankis_due_date() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let out = dir.path().join("out");
    let run = flipcard(
        &data,
        &[
            "import",
            &fixture("no-history.apkg"),
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(run.status.success(), "{}", run.stderr());
    let expect = no_history_expectations();
    let crt = expect["crt"].as_i64().unwrap();
    let card = &expect["cards"][0];
    assert_eq!(card["type"].as_i64(), Some(2), "a review card");
    let key = ItemKey {
        deck: "scheduled".into(),
        card: format!("n{}", card["nid"].as_i64().unwrap()),
        direction: Direction::Forward,
    };
    let data_json: serde_json::Value =
        serde_json::from_str(card["data"].as_str().unwrap()).unwrap();
    let lrt = DateTime::<Utc>::from_timestamp(data_json["lrt"].as_i64().unwrap(), 0).unwrap();
    let anki = anki_due(crt, card);
    let folder = dir.path().join("sync");
    std::fs::create_dir_all(&folder).unwrap();
    let other = folder.join("0123456789abcdef0123456789abcdef.jsonl");
    let line = |at: DateTime<Utc>, rating: u8| {
        format!(
            "{{\"event\":\"review\",\"deck\":\"scheduled\",\"card\":\"{}\",\"direction\":\"forward\",\"reviewed_at\":\"{}\",\"rating\":{rating},\"cram\":false,\"duration_ms\":2000,\"undone\":false}}\n",
            key.card,
            at.format("%Y-%m-%dT%H:%M:%S%.3fZ")
        )
    };
    let earlier = lrt - chrono::TimeDelta::days(2);
    std::fs::write(&other, line(earlier, 1)).unwrap();
    let synced = flipcard(&data, &["sync", folder.to_str().unwrap()]);
    assert!(synced.status.success(), "{}", synced.stderr());
    let store = Store::open_read_only(&data).unwrap();
    assert_eq!(store.history(&key).unwrap().len(), 1, "the answer merged");
    let state = store.state(&key).unwrap().unwrap();
    assert_eq!(state.due, anki, "Anki's due date replayed away");
    assert_eq!(state.stability, data_json["s"].as_f64());
    drop(store);
    // An answer after Anki's last review: scheduled from Anki's state.
    let later = lrt + chrono::TimeDelta::days(30);
    let mut text = std::fs::read_to_string(&other).unwrap();
    text.push_str(&line(later, 3));
    std::fs::write(&other, text).unwrap();
    let synced = flipcard(&data, &["sync", folder.to_str().unwrap()]);
    assert!(synced.status.success(), "{}", synced.stderr());
    let store = Store::open_read_only(&data).unwrap();
    let state = store.state(&key).unwrap().unwrap();
    assert_eq!(state.state, flipcard::sched::State::Review);
    assert!(state.due > later + chrono::TimeDelta::days(30), "{state:?}");
    // Good on a card Anki held for 400+ days grows its stability.
    assert!(
        state.stability.unwrap() > data_json["s"].as_f64().unwrap(),
        "{state:?}"
    );
}

#[test]
fn merge_presets_puts_the_decks_options_into_the_config() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let out = dir.path().join("out");
    let config = dir.path().join("config.toml");
    let original = "# mine\nnew_per_day = 15 # enough\n";
    std::fs::write(&config, original).unwrap();
    let run = Flipcard::new(&data)
        .now(NOW)
        .config(&config)
        .args([
            "import",
            &fixture("stock.apkg"),
            "--out",
            out.to_str().unwrap(),
            "--merge-presets",
        ])
        .run();
    assert!(run.status.success(), "{}", run.stderr());
    let stdout = run.stdout();
    assert!(
        stdout.contains(&format!(
            "merged into {} as presets: [preset.anki-default], [preset.anki-physics-preset]; decks: oscillations-anki → anki-default, physics → anki-default, physics-waves → anki-physics-preset",
            config.display()
        )),
        "{stdout}"
    );
    let text = std::fs::read_to_string(&config).unwrap();
    assert!(text.starts_with(original), "{text}");
    let c = Config::load(Some(&config)).unwrap();
    assert_eq!(c.new_per_day, 15);
    assert_eq!(c.for_deck("physics-waves").new_per_day, 7);
    assert_eq!(c.for_deck("physics-waves").desired_retention, 0.85);

    // The imported decks open with it: the child under its parent, each
    // within its preset's limits (`flipcard cards list` reads the decks).
    let check = Flipcard::without_data()
        .config(&config)
        .args(["check", out.join("decks").to_str().unwrap()])
        .run();
    assert!(check.status.success(), "{}", check.stderr());
}
