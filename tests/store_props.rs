//! Property: whatever happens between ratings — undo, closing and opening
//! again, another program reading the file, another process writing and
//! being killed with SIGKILL — every acknowledged rating is in the log as
//! written (undone exactly when an undo was acknowledged), and `db rebuild`
//! finds the caches in agreement with the log.
//!
//! Runs `PROPTEST_CASES` sequences (default 24, a few seconds); for a longer
//! search: `PROPTEST_CASES=500 cargo test --test main store_props::`.

use std::collections::HashMap;
use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration as StdDuration;

use crate::store_support::{at, key, review};
use chrono::Duration;
use flipcard::sched::{Rating, ReviewKind, State};
use flipcard::store::{Store, StoreError};
use proptest::prelude::*;

const CHILD_DIR: &str = "FLIPCARD_TEST_PROPS_DIR";
const CHILD_SEQ: &str = "FLIPCARD_TEST_PROPS_SEQ";
const CHILD_TEST: &str = "store_props::child_writer";

#[derive(Debug, Clone)]
enum Op {
    Rate {
        card: u8,
        rating: u8,
    },
    Undo,
    Reopen,
    /// Another program opens the file, reads and closes it.
    OutsideRead,
    /// Another process writes ratings and is killed after `after_ms`.
    KilledWriter {
        after_ms: u16,
    },
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        8 => (0u8..6, 0u8..4).prop_map(|(card, rating)| Op::Rate { card, rating }),
        3 => Just(Op::Undo),
        2 => Just(Op::Reopen),
        3 => Just(Op::OutsideRead),
        1 => (0u16..120).prop_map(|after_ms| Op::KilledWriter { after_ms }),
    ]
}

/// What the log must hold: every acknowledged row id with its marker
/// (the `duration_ms` each rating was written with) and whether an undo of
/// it was acknowledged.
#[derive(Debug, Default)]
struct Expected {
    rows: HashMap<i64, (i64, bool)>,
    /// Ids rated by this process in the current session, newest last, not
    /// undone: what the next undo must take.
    session: Vec<i64>,
    next_marker: i64,
}

fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(24)
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: cases(),
        // Each failing case spawns processes; shrinking stays short.
        max_shrink_iters: 64,
        ..ProptestConfig::default()
    })]

    #[test]
    fn acknowledged_ratings_survive_any_sequence(ops in prop::collection::vec(op(), 1..40)) {
        run(&ops)?;
    }
}

fn run(ops: &[Op]) -> Result<(), TestCaseError> {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("flipcard.db");
    let mut store = Some(Store::open(dir.path()).unwrap());
    let mut want = Expected::default();
    let t0 = at("2026-01-01T00:00:00Z");

    for (step, op) in ops.iter().enumerate() {
        let s = store.as_mut().unwrap();
        match op {
            Op::Rate { card, rating } => {
                let marker = want.next_marker;
                want.next_marker += 1;
                let mut r = review(
                    &key("props", &format!("c{card}")),
                    t0 + Duration::minutes(marker),
                    Rating::ALL[usize::from(*rating)],
                    ReviewKind::Learn,
                    State::Learning,
                    Duration::minutes(10),
                );
                r.duration_ms = marker;
                let id = s.record(&r).unwrap();
                want.rows.insert(id, (marker, false));
                want.session.push(id);
            }
            Op::Undo => {
                let undone = s.undo_last().unwrap().map(|r| r.id);
                prop_assert_eq!(
                    undone,
                    want.session.pop(),
                    "step {}: undo took another row",
                    step
                );
                if let Some(id) = undone {
                    want.rows.get_mut(&id).unwrap().1 = true;
                }
            }
            Op::Reopen => {
                // The old store closes before the new one opens.
                drop(store.take());
                store = Some(Store::open(dir.path()).unwrap());
                want.session.clear();
            }
            Op::OutsideRead => outside_read(&db),
            Op::KilledWriter { after_ms } => {
                let printed = killed_writer(dir.path(), want.next_marker, *after_ms);
                // Everything the writer printed is acknowledged; a row it
                // committed but could not print is adopted as it stands.
                let s = store.as_ref().unwrap();
                let mut seen: HashMap<i64, i64> = HashMap::new();
                s.each_review(|r| -> Result<(), StoreError> {
                    seen.insert(r.id, r.record.duration_ms);
                    Ok(())
                })
                .unwrap();
                for (id, marker) in &printed {
                    prop_assert_eq!(
                        seen.get(id),
                        Some(marker),
                        "step {}: child rating lost",
                        step
                    );
                }
                let unprinted = seen
                    .iter()
                    .filter(|(id, _)| !want.rows.contains_key(id) && !printed.contains_key(id))
                    .count();
                prop_assert!(
                    unprinted <= 1,
                    "step {}: {} unprinted child rows",
                    step,
                    unprinted
                );
                for (id, marker) in seen {
                    want.rows.entry(id).or_insert((marker, false));
                    want.next_marker = want.next_marker.max(marker + 1);
                }
            }
        }
    }

    // Read through a connection of its own while the store is still open:
    // the store's own connection would see its writes even in a log that
    // another client has deleted.
    let fresh = rusqlite::Connection::open(&db).unwrap();
    let got: HashMap<i64, (i64, bool)> = fresh
        .prepare("SELECT id, duration_ms, undone FROM review")
        .unwrap()
        .query_map([], |r| Ok((r.get(0)?, (r.get(1)?, r.get(2)?))))
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    drop(fresh);
    prop_assert_eq!(&got, &want.rows);
    let s = store.as_mut().unwrap();
    let rebuilt = s.rebuild().unwrap();
    prop_assert_eq!(
        rebuilt.changed,
        0,
        "caches disagreed with the log: {:?}",
        rebuilt
    );
    prop_assert!(!rebuilt.tallies_changed);
    prop_assert_eq!(s.integrity_check().unwrap(), vec!["ok".to_string()]);
    Ok(())
}

/// Another process (the `sqlite3` shell when installed, always under
/// `CI=true`; else this test binary as a reader) opens the file, reads and
/// closes it.
fn outside_read(db: &Path) {
    if crate::support::require_tool("sqlite3")
        && Command::new("sqlite3")
            .arg(db)
            .arg("SELECT count(*) FROM review;")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    {
        return;
    }
    let status = Command::new(std::env::current_exe().unwrap())
        .args(["--exact", CHILD_TEST, "--test-threads=1", "--quiet"])
        .env(CHILD_DIR, db.parent().unwrap())
        .env(CHILD_SEQ, "read")
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
}

/// Starts a writer process, kills it with SIGKILL after `after_ms`, and
/// returns the (id, marker) of every rating it printed as committed.
fn killed_writer(dir: &Path, first_marker: i64, after_ms: u16) -> HashMap<i64, i64> {
    let mut child = Command::new(std::env::current_exe().unwrap())
        .args(["--exact", CHILD_TEST, "--nocapture", "--test-threads=1"])
        .env(CHILD_DIR, dir)
        .env(CHILD_SEQ, first_marker.to_string())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let stdout = child.stdout.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut printed = HashMap::new();
        let mut r = BufReader::new(stdout);
        let mut line = String::new();
        while r.read_line(&mut line).unwrap_or(0) > 0 {
            // A line cut by the kill was not printed.
            if line.ends_with('\n')
                && let ["committed", id, marker] =
                    line.split_whitespace().collect::<Vec<_>>().as_slice()
            {
                printed.insert(id.parse().unwrap(), marker.parse().unwrap());
            }
            line.clear();
        }
        printed
    });
    std::thread::sleep(StdDuration::from_millis(u64::from(after_ms)));
    child.kill().unwrap();
    child.wait().unwrap();
    reader.join().unwrap()
}

/// The child: with `CHILD_SEQ=read`, one outside read; otherwise ratings
/// as fast as it can until killed, each printed once committed.
#[test]
fn child_writer() {
    let Some(dir) = std::env::var_os(CHILD_DIR) else {
        return;
    };
    let dir = Path::new(&dir);
    let seq = std::env::var(CHILD_SEQ).unwrap_or_default();
    if seq == "read" {
        let conn = rusqlite::Connection::open(dir.join("flipcard.db")).unwrap();
        let _: i64 = conn
            .query_row("SELECT count(*) FROM review", [], |r| r.get(0))
            .unwrap();
        return;
    }
    let first: i64 = seq.parse().unwrap_or(0);
    let mut store = Store::open(dir).unwrap();
    let mut out = std::io::stdout().lock();
    if writeln!(out).is_err() {
        return;
    }
    let t0 = at("2026-01-01T00:00:00Z");
    for marker in first.. {
        let mut r = review(
            &key("props", &format!("c{}", marker % 6)),
            t0 + Duration::minutes(marker),
            Rating::ALL[(marker % 4) as usize],
            ReviewKind::Learn,
            State::Learning,
            Duration::minutes(10),
        );
        r.duration_ms = marker;
        let id = store.record(&r).unwrap();
        if writeln!(out, "committed {id} {marker}").is_err() || out.flush().is_err() {
            return;
        }
    }
}
