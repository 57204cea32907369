//! Durability: a child process records ratings the way the app does
//! (`Store::record_study`: the rating with the leech, suspend and sibling
//! bury events it brings about) and now and then undoes one as the app does
//! (`undo_last_change`), as fast as it can, printing each id once its
//! transaction is committed; it is killed with SIGKILL at random moments.
//! Afterwards every printed rating is in the log as written, at most the
//! one rating in flight is there unprinted, every rating has all of its
//! events or (undone) all of them undone — never a rating without its
//! events — the caches agree with the log, and `PRAGMA integrity_check` is
//! ok.
//!
//! The child is this very test binary, started again with an environment
//! variable naming the data dir.

use std::collections::{HashMap, HashSet};
use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration as StdDuration;

use crate::store_support::{Consequences, after_rating, at, check_consequences, key, study};
use chrono::Duration;
use flipcard::store::{Store, StoreError, Undone};
use rand::{Rng, SeedableRng};

const CHILD_DIR: &str = "FLIPCARD_TEST_DURABILITY_DIR";
const CHILD_FIRST_SEQ: &str = "FLIPCARD_TEST_DURABILITY_SEQ";
const TEST_NAME: &str = "store_durability::sigkill_at_random_moments_loses_no_committed_rating";
const ROUNDS: usize = 40;

#[test]
fn sigkill_at_random_moments_loses_no_committed_rating() {
    if let Some(dir) = std::env::var_os(CHILD_DIR) {
        let first: u64 = std::env::var(CHILD_FIRST_SEQ)
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(0);
        write_until_killed(Path::new(&dir), first);
        return;
    }

    let seed: u64 = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos() as u64)
        .unwrap_or(1);
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let dir = tempfile::tempdir().unwrap();
    let exe = std::env::current_exe().unwrap();

    // seq → id of every rating printed as committed, over all rounds.
    let mut committed: HashMap<u64, i64> = HashMap::new();
    let mut undone_printed: HashSet<i64> = HashSet::new();
    let mut next_seq = 0u64;
    let mut rounds_with_writes = 0;
    let mut in_flight = 0;
    let mut printed_leeches: HashSet<i64> = HashSet::new();
    let mut consequences = Consequences::default();

    for round in 0..ROUNDS {
        let mut child = Command::new(&exe)
            .args(["--exact", TEST_NAME, "--nocapture", "--test-threads=1"])
            .env(CHILD_DIR, dir.path())
            .env(CHILD_FIRST_SEQ, next_seq.to_string())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let stdout = child.stdout.take().unwrap();
        let reader = std::thread::spawn(move || {
            let mut lines = Vec::new();
            let mut r = BufReader::new(stdout);
            let mut line = String::new();
            // Only whole lines count: a line cut by the kill was not printed.
            while r.read_line(&mut line).unwrap_or(0) > 0 {
                if line.ends_with('\n') {
                    lines.push(line.trim_end().to_string());
                }
                line.clear();
            }
            lines
        });
        // Mostly mid-stream, sometimes while the child is still starting
        // (opening, migrating, writing its daily copy).
        let wait = if rng.random_bool(0.15) {
            rng.random_range(0..40)
        } else {
            rng.random_range(40..400)
        };
        std::thread::sleep(StdDuration::from_millis(wait));
        child.kill().unwrap(); // SIGKILL
        child.wait().unwrap();
        let lines = reader.join().unwrap();

        let mut round_committed = 0;
        for l in &lines {
            let parts: Vec<&str> = l.split_whitespace().collect();
            match parts.as_slice() {
                ["committed", id, seq, leech] => {
                    committed.insert(seq.parse().unwrap(), id.parse().unwrap());
                    if *leech == "leech" {
                        printed_leeches.insert(id.parse().unwrap());
                    }
                    round_committed += 1;
                }
                ["undone", id] => {
                    undone_printed.insert(id.parse().unwrap());
                }
                _ => {}
            }
        }
        if round_committed > 0 {
            rounds_with_writes += 1;
        }

        let context = format!("round {round}, seed {seed}, killed after {wait} ms");
        let mut store = match Store::open(dir.path()) {
            Ok(s) => s,
            Err(e) => panic!("{context}: reopening failed: {e}"),
        };
        assert_eq!(store.integrity_check().unwrap(), ["ok"], "{context}");

        let mut rows: HashMap<i64, (u64, bool)> = HashMap::new();
        // Each rating's item, read in the same pass (one scan a round: a
        // scan per printed leech made the test quadratic in the ratings a
        // fast machine writes).
        let mut keys: HashMap<i64, flipcard::sched::ItemKey> = HashMap::new();
        let mut max_seq = None;
        store
            .each_review(|r| -> Result<(), StoreError> {
                let seq = r.record.duration_ms as u64;
                rows.insert(r.id, (seq, r.undone));
                keys.insert(r.id, r.record.key.clone());
                max_seq = max_seq.max(Some(seq));
                Ok(())
            })
            .unwrap();
        for (seq, id) in &committed {
            let Some((stored_seq, _)) = rows.get(id) else {
                panic!("{context}: committed rating {id} (seq {seq}) is missing");
            };
            assert_eq!(stored_seq, seq, "{context}: row {id} holds another rating");
        }
        for id in &undone_printed {
            assert!(
                rows[id].1,
                "{context}: undo of {id} was printed but is not in the log"
            );
        }
        let printed_ids: HashSet<i64> = committed.values().copied().collect();
        let unprinted_rows = rows.keys().filter(|id| !printed_ids.contains(id)).count();
        let unprinted_undos = rows
            .iter()
            .filter(|(id, (_, undone))| *undone && !undone_printed.contains(id))
            .count();
        // A kill may fall between a commit and its print: one write (a
        // rating or an undo) in flight, no more.
        in_flight += unprinted_rows + unprinted_undos;
        assert!(
            unprinted_rows + unprinted_undos <= 1,
            "{context}: {unprinted_rows} unprinted ratings and {unprinted_undos} unprinted undos"
        );
        // Every rating with all that it brought about, or (undone) with
        // all of it taken back.
        consequences = check_consequences(&store).unwrap_or_else(|e| panic!("{context}: {e}"));
        for id in &printed_leeches {
            let Some(key) = keys.get(id) else {
                panic!("{context}: no rating {id}");
            };
            let leeched =
                store.status_history(key).unwrap().iter().any(|e| {
                    e.cause == Some(*id) && e.action == flipcard::store::StatusAction::Leech
                });
            assert!(
                leeched,
                "{context}: rating {id} was printed as a leech; no leech event"
            );
        }
        let rebuilt = store.rebuild().unwrap();
        assert!(
            rebuilt.changed == 0 && !rebuilt.tallies_changed && !rebuilt.statuses_changed,
            "{context}: the caches disagree with the log: {rebuilt:?}"
        );
        next_seq = max_seq.map_or(0, |s| s + 1);
        // An unprinted rating counts as committed from now on.
        for (id, (seq, _)) in &rows {
            committed.entry(*seq).or_insert(*id);
        }
        for (id, (_, undone)) in &rows {
            if *undone {
                undone_printed.insert(*id);
            }
        }
    }
    eprintln!(
        "durability: {} ratings over {ROUNDS} kills, {in_flight} writes caught between commit and print; \
         live at the end: {consequences:?}",
        committed.len()
    );
    assert!(
        consequences.leeches > 10 && consequences.buries > 100,
        "too few leeches and buries to prove anything: {consequences:?}"
    );
    assert!(
        rounds_with_writes >= ROUNDS / 2,
        "only {rounds_with_writes} of {ROUNDS} rounds wrote anything: the test proved little"
    );
    assert!(
        committed.len() > 100,
        "only {} ratings written",
        committed.len()
    );
}

/// The child: ratings as fast as possible through `record_study`, each id
/// printed once committed (with `leech` when it made the item one). Each
/// card gets three: a lapse, a lapse (the second makes it a leech, and
/// suspends it), a good one; every rating buries the other direction.
/// Every seventh step undoes the last rating instead, with its events.
fn write_until_killed(dir: &Path, first_seq: u64) {
    let mut store = match Store::open(dir) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("child: {e}");
            std::process::exit(2);
        }
    };
    let mut out = std::io::stdout().lock();
    // The test harness has printed `test <name> ... ` without a line break.
    if writeln!(out).is_err() {
        std::process::exit(0);
    }
    let start = at("2026-01-01T00:00:00Z");
    for seq in first_seq.. {
        let print = if seq % 7 == 6 {
            match store.undo_last_change() {
                Ok(Some(Undone::Review(undone))) => Some(format!("undone {}", undone.id)),
                Ok(Some(Undone::Status(events))) => {
                    panic!("child: undid a status change {events:?}")
                }
                Ok(None) => None,
                Err(e) => panic!("child: undo failed: {e}"),
            }
        } else {
            let k = key("durable", &format!("c{}", seq / 3));
            let when = start + Duration::seconds(seq as i64);
            let mut r = study(&k, when, seq % 3 != 2, false);
            // The sequence number marks the row, to check its content later.
            r.duration_ms = seq as i64;
            match store.record_study(&r, &after_rating(&k, when)) {
                Ok(rec) => Some(format!(
                    "committed {} {seq} {}",
                    rec.id,
                    if rec.leech { "leech" } else { "-" }
                )),
                Err(e) => panic!("child: record failed: {e}"),
            }
        };
        if let Some(line) = print
            && (writeln!(out, "{line}").is_err() || out.flush().is_err())
        {
            std::process::exit(0);
        }
    }
}
