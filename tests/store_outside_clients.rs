//! Other SQLite clients may open, read and close the database while
//! flipcard writes to it (Python's `sqlite3`, the `sqlite3` shell and its
//! `.backup`, a database browser, another flipcard). None of them may make an
//! acknowledged rating disappear.
//!
//! On POSIX, closing any descriptor of a file drops every lock the process
//! holds on it. Were flipcard to open the database file outside SQLite while
//! its connection is open, an outside client closing last would believe it
//! is alone, checkpoint and delete the write-ahead log flipcard keeps writing
//! into: ratings shown as saved would be gone. This test cannot pass then.
//!
//! A child process (this test binary run again) writes ratings through the
//! store and prints each id once committed; meanwhile this process opens,
//! reads and closes the file again and again with rusqlite, Python and the
//! `sqlite3` shell when they are installed. While the child still runs, a
//! fresh connection must see every printed rating; after the child is
//! killed, and again after a clean close, too.

use std::collections::HashMap;
use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, mpsc};
use std::time::Duration as StdDuration;

use crate::store_support::{at, key, review};
use chrono::Duration;
use flipcard::sched::{Rating, ReviewKind, State};
use flipcard::store::Store;

const CHILD_DIR: &str = "FLIPCARD_TEST_OUTSIDE_DIR";
const CHILD_COUNT: &str = "FLIPCARD_TEST_OUTSIDE_COUNT";
const TEST_NAME: &str = "store_outside_clients::outside_clients_never_lose_an_acknowledged_rating";
const RATINGS: u64 = 120;

#[test]
fn outside_clients_never_lose_an_acknowledged_rating() {
    if let Some(dir) = std::env::var_os(CHILD_DIR) {
        let count = std::env::var(CHILD_COUNT)
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(RATINGS);
        write_then_wait(Path::new(&dir), count);
        return;
    }
    for ending in [Ending::Kill, Ending::Close] {
        let dir = tempfile::tempdir().unwrap();
        // An existing database, as in the field: the first open created it.
        drop(Store::open(dir.path()).unwrap());
        let db = dir.path().join("flipcard.db");

        let mut child = spawn_writer(dir.path(), RATINGS);
        let stdout = child.stdout.take().unwrap();
        let (lines_tx, lines_rx) = mpsc::channel::<String>();
        let reader = std::thread::spawn(move || {
            let r = BufReader::new(stdout);
            for line in r.lines().map_while(Result::ok) {
                if lines_tx.send(line).is_err() {
                    break;
                }
            }
        });

        let stop = Arc::new(AtomicBool::new(false));
        let visits = Arc::new(AtomicUsize::new(0));
        let clients = start_outside_clients(&db, dir.path(), &stop, &visits);

        let mut committed: HashMap<u64, i64> = HashMap::new();
        let mut done = false;
        while !done {
            let line = lines_rx
                .recv_timeout(StdDuration::from_secs(60))
                .expect("the writer stopped printing");
            let parts: Vec<&str> = line.split_whitespace().collect();
            match parts.as_slice() {
                ["committed", id, seq] => {
                    committed.insert(seq.parse().unwrap(), id.parse().unwrap());
                }
                ["done"] => done = true,
                ["failed", ..] => panic!("the writer failed: {line}"),
                _ => {}
            }
        }
        // Keep the outside clients busy a little longer with the writer
        // idle but alive, then stop them.
        std::thread::sleep(StdDuration::from_millis(300));
        stop.store(true, Ordering::SeqCst);
        for c in clients {
            c.join().unwrap();
        }
        let visited = visits.load(Ordering::SeqCst);
        assert!(
            visited >= 20,
            "only {visited} outside opens: the test proved little"
        );
        assert_eq!(committed.len() as u64, RATINGS);

        // The writer still runs: a fresh reader must see every rating.
        assert_all_present(&db, &committed, "while the writer runs");

        match ending {
            Ending::Kill => {
                child.kill().unwrap();
                child.wait().unwrap();
            }
            Ending::Close => {
                child.stdin.take().unwrap().write_all(b"quit\n").unwrap();
                assert!(child.wait().unwrap().success());
            }
        }
        reader.join().unwrap();
        assert_all_present(&db, &committed, &format!("after the writer {ending:?}"));
        let store = Store::open(dir.path()).unwrap();
        assert_eq!(store.integrity_check().unwrap(), ["ok"]);
        eprintln!(
            "outside clients ({ending:?}): {} ratings, {visited} outside opens",
            committed.len()
        );
    }
}

#[derive(Debug, Clone, Copy)]
enum Ending {
    Kill,
    Close,
}

fn spawn_writer(dir: &Path, count: u64) -> std::process::Child {
    Command::new(std::env::current_exe().unwrap())
        .args(["--exact", TEST_NAME, "--nocapture", "--test-threads=1"])
        .env(CHILD_DIR, dir)
        .env(CHILD_COUNT, count.to_string())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .unwrap()
}

/// Threads that open, read and close the database until told to stop:
/// rusqlite in this process, and Python's `sqlite3` module and the `sqlite3`
/// shell (with `.backup`) as separate programs when they are installed.
fn start_outside_clients(
    db: &Path,
    dir: &Path,
    stop: &Arc<AtomicBool>,
    visits: &Arc<AtomicUsize>,
) -> Vec<std::thread::JoinHandle<()>> {
    let mut handles = Vec::new();
    {
        let (db, stop, visits) = (db.to_path_buf(), Arc::clone(stop), Arc::clone(visits));
        handles.push(std::thread::spawn(move || {
            while !stop.load(Ordering::SeqCst) {
                let conn = rusqlite::Connection::open(&db).unwrap();
                let _: i64 = conn
                    .query_row("SELECT count(*) FROM review", [], |r| r.get(0))
                    .unwrap();
                drop(conn);
                visits.fetch_add(1, Ordering::SeqCst);
                std::thread::sleep(StdDuration::from_millis(7));
            }
        }));
    }
    if crate::support::require_python_module("sqlite3") {
        let (db, stop, visits) = (db.to_path_buf(), Arc::clone(stop), Arc::clone(visits));
        handles.push(std::thread::spawn(move || {
            let script = "import sqlite3, sys\n\
                          c = sqlite3.connect(sys.argv[1])\n\
                          c.execute('select count(*) from review').fetchall()\n\
                          c.close()\n";
            while !stop.load(Ordering::SeqCst) {
                let status = Command::new("python3")
                    .args(["-c", script])
                    .arg(&db)
                    .stderr(Stdio::null())
                    .status()
                    .unwrap();
                // A busy moment is fine for an outside reader; what matters
                // is that it opened and closed the file.
                let _ = status;
                visits.fetch_add(1, Ordering::SeqCst);
            }
        }));
    }
    if crate::support::require_tool("sqlite3") {
        let (db, stop, visits) = (db.to_path_buf(), Arc::clone(stop), Arc::clone(visits));
        let copy = dir.join("outside-backup.db");
        handles.push(std::thread::spawn(move || {
            while !stop.load(Ordering::SeqCst) {
                let _ = Command::new("sqlite3")
                    .arg(&db)
                    .arg(format!(".backup '{}'", copy.display()))
                    .stdout(Stdio::null())
                    .stderr(Stdio::null())
                    .status()
                    .unwrap();
                let _ = std::fs::remove_file(&copy);
                visits.fetch_add(1, Ordering::SeqCst);
            }
        }));
    }
    handles
}

fn assert_all_present(db: &Path, committed: &HashMap<u64, i64>, when: &str) {
    let conn = rusqlite::Connection::open(db).unwrap();
    let mut rows: HashMap<i64, i64> = HashMap::new();
    let mut st = conn.prepare("SELECT id, duration_ms FROM review").unwrap();
    for row in st
        .query_map([], |r| Ok((r.get::<_, i64>(0)?, r.get::<_, i64>(1)?)))
        .unwrap()
    {
        let (id, seq) = row.unwrap();
        rows.insert(id, seq);
    }
    let missing: Vec<_> = committed
        .iter()
        .filter(|(seq, id)| rows.get(id) != Some(&(**seq as i64)))
        .collect();
    assert!(
        missing.is_empty(),
        "{when}: {} of {} acknowledged ratings are missing (e.g. seq/id {:?})",
        missing.len(),
        committed.len(),
        missing.first()
    );
}

/// The child: `count` ratings a few milliseconds apart, each id printed once
/// committed; then it waits for `quit` on stdin (or a kill).
fn write_then_wait(dir: &Path, count: u64) {
    let mut out = std::io::stdout().lock();
    let mut store = match Store::open(dir) {
        Ok(s) => s,
        Err(e) => {
            let _ = writeln!(out, "\nfailed {e}");
            std::process::exit(2);
        }
    };
    // The test harness has printed `test <name> ... ` without a line break.
    let _ = writeln!(out);
    let start = at("2026-01-01T00:00:00Z");
    for seq in 0..count {
        let k = key("outside", &format!("c{}", seq % 17));
        let mut r = review(
            &k,
            start + Duration::seconds(seq as i64),
            Rating::ALL[(seq % 4) as usize],
            ReviewKind::Learn,
            State::Learning,
            Duration::minutes(10),
        );
        r.duration_ms = seq as i64;
        match store.record(&r) {
            Ok(id) => {
                let _ = writeln!(out, "committed {id} {seq}");
                let _ = out.flush();
            }
            Err(e) => {
                let _ = writeln!(out, "failed {e}");
                let _ = out.flush();
                std::process::exit(2);
            }
        }
        std::thread::sleep(StdDuration::from_millis(4));
    }
    let _ = writeln!(out, "done");
    let _ = out.flush();
    let mut line = String::new();
    let _ = std::io::stdin().read_line(&mut line);
    drop(store);
    std::process::exit(0);
}
