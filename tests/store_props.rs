//! Property: whatever happens between ratings — undo, closing and opening
//! again, another program reading the file, another process writing and
//! being killed with SIGKILL — every acknowledged rating is in the log as
//! written (undone exactly when an undo was acknowledged), and `db rebuild`
//! finds the caches in agreement with the log.
//!
//! Ratings are stored the way the app stores them, `Store::record_study`,
//! with what follows from them: the second lapse of an item makes it a
//! leech and suspends it, every rating buries the other direction of its
//! card (cram ratings change no status). The model predicts which rating
//! makes a leech; an undo (`undo_last_change`, the app's) takes the rating
//! back with its events; and afterwards every rating in the log has exactly
//! the events the rule gives it, live, or all of them undone.
//!
//! Runs `PROPTEST_CASES` sequences (default 24, a few seconds); for a longer
//! search: `PROPTEST_CASES=500 cargo test --test main store_props::`.

use std::collections::HashMap;
use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration as StdDuration;

use crate::store_support::{LEECH_AT, after_rating, at, check_consequences, key, study};
use chrono::Duration;
use flipcard::sched::{Direction, ItemKey};
use flipcard::store::{Store, StoreError, Undone};
use proptest::prelude::*;

const CHILD_DIR: &str = "FLIPCARD_TEST_PROPS_DIR";
const CHILD_SEQ: &str = "FLIPCARD_TEST_PROPS_SEQ";
const CHILD_TEST: &str = "store_props::child_writer";

#[derive(Debug, Clone)]
enum Op {
    /// A rating of card `card` (forward or backward): a lapse or a good
    /// review, or a cram rating.
    Rate {
        card: u8,
        backward: bool,
        lapse: bool,
        cram: bool,
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
        8 => (0u8..4, any::<bool>(), prop::bool::weighted(0.6), prop::bool::weighted(0.1))
            .prop_map(|(card, backward, lapse, cram)| Op::Rate { card, backward, lapse, cram }),
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
    /// This process's ratings in order: id, item, lapse, cram.
    rated: Vec<(i64, ItemKey, bool, bool)>,
}

impl Expected {
    /// Whether a rating of `key` now makes it a leech: a lapse that brings
    /// its live lapses to the threshold while it is not one already.
    fn makes_leech(&self, key: &ItemKey, lapse: bool, cram: bool) -> bool {
        if cram || !lapse {
            return false;
        }
        let mut lapses = 0;
        let mut leech = false;
        for (id, k, l, c) in &self.rated {
            if k != key || *c || !*l || self.rows[id].1 {
                continue;
            }
            lapses += 1;
            leech |= lapses >= LEECH_AT;
        }
        !leech && lapses + 1 >= LEECH_AT
    }
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
            Op::Rate {
                card,
                backward,
                lapse,
                cram,
            } => {
                let marker = want.next_marker;
                want.next_marker += 1;
                let mut k = key("props", &format!("c{card}"));
                if *backward {
                    k.direction = Direction::Backward;
                }
                let when = t0 + Duration::minutes(marker);
                let mut r = study(&k, when, *lapse, *cram);
                r.duration_ms = marker;
                let leech = want.makes_leech(&k, *lapse, *cram);
                let recorded = s.record_study(&r, &after_rating(&k, when)).unwrap();
                prop_assert_eq!(
                    recorded.leech,
                    leech,
                    "step {}: a leech or not, against the model",
                    step
                );
                want.rows.insert(recorded.id, (marker, false));
                want.session.push(recorded.id);
                want.rated.push((recorded.id, k, *lapse, *cram));
            }
            Op::Undo => {
                let undone = match s.undo_last_change().unwrap() {
                    Some(Undone::Review(r)) => Some(r.id),
                    Some(Undone::Status(events)) => {
                        return Err(TestCaseError::fail(format!(
                            "step {step}: undid a status change {events:?}"
                        )));
                    }
                    None => None,
                };
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
                // A writer killed mid-rating left the rating with all its
                // events or neither.
                if let Err(e) = check_consequences(s) {
                    return Err(TestCaseError::fail(format!("step {step}: {e}")));
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
    // The events and statuses, also as a reader of its own sees them.
    let reader = Store::open_read_only(dir.path()).unwrap();
    if let Err(e) = check_consequences(&reader) {
        return Err(TestCaseError::fail(format!("at the end: {e}")));
    }
    drop(reader);
    let s = store.as_mut().unwrap();
    let rebuilt = s.rebuild().unwrap();
    prop_assert_eq!(
        rebuilt.changed,
        0,
        "caches disagreed with the log: {:?}",
        rebuilt
    );
    prop_assert!(!rebuilt.tallies_changed);
    prop_assert!(
        !rebuilt.statuses_changed,
        "status cache disagreed with the log"
    );
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
/// through `record_study` as fast as it can until killed, each printed
/// once committed.
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
        // Cards of its own (a lapse, a lapse: a leech; a good one), so the
        // parent's model of its cards holds.
        let k = key("child", &format!("c{}", marker / 3));
        let when = t0 + Duration::minutes(marker);
        let mut r = study(&k, when, marker % 3 != 2, false);
        r.duration_ms = marker;
        let id = store.record_study(&r, &after_rating(&k, when)).unwrap().id;
        if writeln!(out, "committed {id} {marker}").is_err() || out.flush().is_err() {
            return;
        }
    }
}
