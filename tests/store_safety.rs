//! The database under hostile conditions: an empty file where the database
//! was, restoring a backup, a full disk, a read-only data dir, something
//! other than a file at the database's path.
//!
//! The full-disk and read-only cases run on a small tmpfs mounted for the
//! test; where mounting is not permitted (not root, no CAP_SYS_ADMIN) they
//! say so and stop early.

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use crate::store_support::{at, key, review};
use chrono::Duration;
use flipcard::sched::clock::Clock;
use flipcard::sched::{Rating, ReviewKind, State};
use flipcard::store::restore::{RestoreError, restore};
use flipcard::store::{Store, StoreError};

use crate::support::{Flipcard, Output};

const NOW: &str = "2026-03-02T09:00:00Z";

fn rate(store: &mut Store, card: &str, minutes: i64) -> i64 {
    store
        .record(&review(
            &key("safety", card),
            at("2026-03-01T08:00:00Z") + Duration::minutes(minutes),
            Rating::Good,
            ReviewKind::Learn,
            State::Learning,
            Duration::minutes(10),
        ))
        .unwrap()
}

/// A data dir with `n` ratings and (from a second open) today's backup.
fn data_with_backup(n: i64) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    {
        let mut store = Store::open(dir.path()).unwrap();
        for i in 0..n {
            rate(&mut store, &format!("c{i}"), i);
        }
    }
    drop(Store::open(dir.path()).unwrap());
    assert_eq!(
        flipcard::store::backup::daily_backups(dir.path()).len(),
        1,
        "daily copy written"
    );
    dir
}

fn flipcard(data: &Path, args: &[&str]) -> Output {
    Flipcard::new(data).now(NOW).args(args).run()
}

#[test]
fn an_empty_file_with_backups_beside_it_is_damage_not_a_new_database() {
    let dir = data_with_backup(3);
    let db = dir.path().join("flipcard.db");
    std::fs::write(&db, b"").unwrap();
    let _ = std::fs::remove_file(dir.path().join("flipcard.db-wal"));
    let err = Store::open(dir.path()).unwrap_err();
    let StoreError::Corrupt { newest_backup, .. } = &err else {
        panic!("expected Corrupt, got {err}");
    };
    let newest = flipcard::store::backup::daily_backups(dir.path())[0]
        .1
        .clone();
    assert_eq!(newest_backup.as_ref(), Some(&newest));
    let msg = err.to_string();
    assert!(
        msg.contains("empty") && msg.contains("flipcard db restore"),
        "{msg}"
    );
    assert_eq!(std::fs::metadata(&db).unwrap().len(), 0, "left as it was");

    // Through the binary: every command refuses, nothing is replaced.
    let out = flipcard(dir.path(), &["db", "rebuild"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stderr().contains(&newest.display().to_string()));
    assert_eq!(std::fs::metadata(&db).unwrap().len(), 0);

    // Without any backup an empty file is a database not yet written.
    let fresh = tempfile::tempdir().unwrap();
    std::fs::write(fresh.path().join("flipcard.db"), b"").unwrap();
    let store = Store::open(fresh.path()).unwrap();
    assert_eq!(store.review_count().unwrap(), 0);
}

#[test]
fn restore_sets_the_damaged_file_aside_and_brings_the_backup_back() {
    let dir = data_with_backup(4);
    let db = dir.path().join("flipcard.db");
    let damaged: Vec<u8> = (0..5000u32).map(|i| (i * 31 % 251) as u8).collect();
    std::fs::write(&db, &damaged).unwrap();
    assert!(matches!(
        Store::open(dir.path()),
        Err(StoreError::Corrupt { .. })
    ));

    let out = flipcard(dir.path(), &["db", "restore"]);
    assert!(out.status.success(), "{}", out.stderr());
    let said = out.stdout();
    assert!(said.contains("(4 reviews)"), "{said}");
    // The damaged bytes are kept, under a name that says what they are.
    let aside: Vec<PathBuf> = std::fs::read_dir(dir.path())
        .unwrap()
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.to_string_lossy().contains(".damaged-"))
        .collect();
    assert_eq!(aside.len(), 1, "{aside:?}");
    assert_eq!(std::fs::read(&aside[0]).unwrap(), damaged);
    assert!(said.contains(&aside[0].display().to_string()), "{said}");

    let store = Store::open(dir.path()).unwrap();
    assert_eq!(store.review_count().unwrap(), 4);
    assert_eq!(store.integrity_check().unwrap(), ["ok"]);
}

#[test]
fn restore_refuses_a_sound_database_unless_forced_and_a_database_in_use() {
    let dir = data_with_backup(2);
    {
        let mut store = Store::open(dir.path()).unwrap();
        rate(&mut store, "after-backup", 100);
    }
    let err = restore(dir.path(), None, false, Clock::System).unwrap_err();
    assert!(
        matches!(err, RestoreError::Sound { reviews: 3, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("--force"), "{err}");
    assert_eq!(Store::open(dir.path()).unwrap().review_count().unwrap(), 3);

    // Another program has it open: never pulled from under it.
    let mut holder = hold_open(dir.path());
    let err = restore(dir.path(), None, true, Clock::System).unwrap_err();
    assert!(matches!(err, RestoreError::InUse { .. }), "{err}");
    holder.stdin.take().unwrap().write_all(b"quit\n").unwrap();
    holder.wait().unwrap();

    let done = restore(dir.path(), None, true, Clock::System).unwrap();
    assert_eq!(done.reviews, 2);
    // The rating made after the backup is still there, in the file set aside.
    let aside = &done.set_aside[0];
    let conn = rusqlite::Connection::open(aside).unwrap();
    let n: i64 = conn
        .query_row("SELECT count(*) FROM review", [], |r| r.get(0))
        .unwrap();
    assert_eq!(n, 3);

    // A named backup that is not one is refused before anything moves.
    let junk = dir.path().join("junk.db");
    std::fs::write(&junk, b"not a database at all, not even close......").unwrap();
    let err = restore(dir.path(), Some(&junk), true, Clock::System).unwrap_err();
    assert!(matches!(err, RestoreError::BadBackup { .. }), "{err}");
    assert_eq!(Store::open(dir.path()).unwrap().review_count().unwrap(), 2);
}

const HOLD_DIR: &str = "FLIPCARD_TEST_HOLD_DIR";

/// Another process with the database open until it reads a line.
fn hold_open(dir: &Path) -> std::process::Child {
    let mut child = Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "store_safety::holder",
            "--nocapture",
            "--test-threads=1",
        ])
        .env(HOLD_DIR, dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    for line in lines.by_ref() {
        if line.unwrap().contains("holding") {
            // Keep reading what the child's harness prints after it.
            std::thread::spawn(move || lines.for_each(drop));
            return child;
        }
    }
    let _ = child.kill();
    let _ = child.wait();
    panic!("the holder never opened the database");
}

#[test]
fn holder() {
    let Some(dir) = std::env::var_os(HOLD_DIR) else {
        return;
    };
    let store = Store::open(Path::new(&dir)).unwrap();
    store.review_count().unwrap();
    println!("\nholding");
    let mut line = String::new();
    let _ = std::io::stdin().read_line(&mut line);
}

#[test]
fn something_other_than_a_file_at_the_database_path_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("flipcard.db");
    std::fs::create_dir(&db).unwrap();
    let err = Store::open(dir.path()).unwrap_err();
    assert!(err.to_string().contains("is a directory"), "{err}");
    std::fs::remove_dir(&db).unwrap();

    let status = Command::new("mkfifo").arg(&db).status().unwrap();
    assert!(status.success());
    let err = Store::open(dir.path()).unwrap_err();
    assert!(err.to_string().contains("FIFO"), "{err}");
    let err = Store::open_read_only(dir.path()).unwrap_err();
    assert!(err.to_string().contains("FIFO"), "{err}");
    std::fs::remove_file(&db).unwrap();

    std::os::unix::fs::symlink(dir.path().join("gone/flipcard.db"), &db).unwrap();
    let err = Store::open(dir.path()).unwrap_err();
    assert!(err.to_string().contains("does not exist"), "{err}");
    std::fs::remove_file(&db).unwrap();

    // A link to a real database is followed.
    let real = tempfile::tempdir().unwrap();
    {
        let mut store = Store::open(real.path()).unwrap();
        rate(&mut store, "linked", 0);
    }
    std::os::unix::fs::symlink(real.path().join("flipcard.db"), &db).unwrap();
    assert_eq!(Store::open(dir.path()).unwrap().review_count().unwrap(), 1);
}

/// A tmpfs of `kib` KiB mounted for one test, unmounted on drop.
struct SmallDisk {
    dir: tempfile::TempDir,
}

impl SmallDisk {
    fn mount(kib: u32) -> Option<SmallDisk> {
        let dir = tempfile::tempdir().unwrap();
        let ok = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={kib}k"), "tmpfs"])
            .arg(dir.path())
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success());
        if !crate::support::require(ok, "mounting a tmpfs", "needs root, as in CI") {
            return None;
        }
        Some(SmallDisk { dir })
    }

    fn path(&self) -> &Path {
        self.dir.path()
    }

    /// Fills what is left of the disk; returns the filler file.
    fn fill(&self) -> PathBuf {
        let filler = self.path().join("filler");
        let mut f = std::fs::File::create(&filler).unwrap();
        let block = vec![0xAAu8; 4096];
        while f.write_all(&block).is_ok() {}
        let _ = f.sync_all();
        filler
    }

    fn remount(&self, option: &str) {
        let ok = Command::new("mount")
            .args(["-o", &format!("remount,{option}")])
            .arg(self.path())
            .status()
            .is_ok_and(|s| s.success());
        assert!(ok, "remount {option}");
    }
}

impl Drop for SmallDisk {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(self.dir.path()).status();
    }
}

#[test]
fn a_full_disk_says_so_keeps_every_saved_rating_and_reads_still_work() {
    let Some(disk) = SmallDisk::mount(1024) else {
        return;
    };
    let data = disk.path().join("data");
    let mut store = Store::open(&data).unwrap();
    let mut saved = Vec::new();
    for i in 0..20 {
        saved.push(rate(&mut store, &format!("c{i}"), i));
    }
    let filler = disk.fill();

    // Ratings now fail with a plain "disk full", never a code number.
    let mut failures = 0;
    for i in 20..400 {
        match store.record(&review(
            &key("safety", &format!("c{}", i % 50)),
            at("2026-03-01T08:00:00Z") + Duration::minutes(i),
            Rating::Good,
            ReviewKind::Learn,
            State::Learning,
            Duration::minutes(10),
        )) {
            Ok(id) => saved.push(id),
            Err(e) => {
                assert!(matches!(e, StoreError::DiskFull { .. }), "{e}");
                let msg = e.to_string();
                assert!(msg.starts_with("disk full"), "{msg}");
                assert!(!msg.contains("code"), "{msg}");
                failures += 1;
            }
        }
    }
    assert!(failures > 0, "the disk never filled up");

    // Reading commands work on the full disk (from another process).
    let out = flipcard(&data, &["export", "--reviews", "--format", "csv"]);
    assert!(out.status.success(), "{}", out.stderr());
    assert_eq!(out.stdout().lines().count(), saved.len() + 1);
    let out = flipcard(&data, &["stats", "--json"]);
    assert!(out.status.success(), "{}", out.stderr());

    // Space again: writing resumes, nothing acknowledged was lost.
    std::fs::remove_file(&filler).unwrap();
    saved.push(rate(&mut store, "after", 1000));
    let mut ids = Vec::new();
    store
        .each_review(|r| -> Result<(), StoreError> {
            ids.push(r.id);
            Ok(())
        })
        .unwrap();
    for id in &saved {
        assert!(ids.contains(id), "rating {id} lost");
    }
    assert_eq!(store.integrity_check().unwrap(), ["ok"]);
    drop(store);

    // A fresh start on the full disk: the reading commands still answer,
    // even though SQLite cannot create its index file.
    let filler = disk.fill();
    let out = flipcard(&data, &["export", "--reviews", "--format", "json"]);
    assert!(out.status.success(), "{}", out.stderr());
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(rows.as_array().map(Vec::len), Some(saved.len()));
    let out = flipcard(&data, &["stats"]);
    assert!(out.status.success(), "{}", out.stderr());
    // A command that writes says "disk full" in one line.
    let out = flipcard(&data, &["db", "rebuild"]);
    let err = out.stderr();
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("disk full") || err.contains("not writable"),
        "{err}"
    );
    // One error line; the daily copy the open tried first may say it found
    // no room either (when SQLite's shared-memory file is still there, the
    // open gets that far).
    let errors: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(
        errors
            .iter()
            .filter(|l| l.starts_with("flipcard: error:"))
            .count(),
        1,
        "{err}"
    );
    assert!(
        errors
            .iter()
            .all(|l| l.starts_with("flipcard: error:") || l.contains("daily backup skipped")),
        "{err}"
    );
    std::fs::remove_file(filler).unwrap();
}

#[test]
fn reading_commands_work_from_a_read_only_data_dir() {
    let Some(disk) = SmallDisk::mount(2048) else {
        return;
    };
    let data = disk.path().join("data");
    {
        let mut store = Store::open(&data).unwrap();
        for i in 0..5 {
            rate(&mut store, &format!("c{i}"), i);
        }
    }
    disk.remount("ro");
    let out = flipcard(&data, &["export", "--reviews", "--format", "csv"]);
    assert!(out.status.success(), "{}", out.stderr());
    assert_eq!(out.stdout().lines().count(), 6);
    let out = flipcard(&data, &["stats", "--json"]);
    assert!(out.status.success(), "{}", out.stderr());
    let stats: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(stats.is_object());
    // Writing is refused with the reason.
    let out = flipcard(&data, &["db", "rebuild"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stderr().contains("not writable"), "{}", out.stderr());
    disk.remount("rw");

    // A data dir that does not exist reads as empty and is not created.
    let none = disk.path().join("never-made");
    let out = flipcard(&none, &["export", "--reviews", "--format", "json"]);
    assert!(out.status.success(), "{}", out.stderr());
    assert_eq!(out.stdout().trim(), "[]");
    assert!(!none.exists());
}
