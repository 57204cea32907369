//! Copies of the database: a daily one (the last 7 kept) and the ones made
//! before a migration. Copies are written with `VACUUM INTO` to a temporary
//! name and renamed, so a crash never leaves a half-written copy that looks
//! complete.

use std::path::{Path, PathBuf};

use chrono::NaiveDate;
use rusqlite::Connection;

pub use super::backup_files::{backups_dir, daily_backups, daily_path, newest_backup};
use super::error::StoreError;

/// How many daily copies are kept.
pub(crate) const KEEP_DAILY: usize = 7;

/// A consistent copy of the open database at `target` (which must not exist).
pub(crate) fn vacuum_into(conn: &Connection, target: &Path) -> Result<(), StoreError> {
    let fail = |detail: String| StoreError::Backup {
        path: target.to_path_buf(),
        detail,
    };
    let partial = PathBuf::from(format!(
        "{}.partial-{}",
        target.display(),
        std::process::id()
    ));
    let partial_str = partial
        .to_str()
        .ok_or_else(|| fail("the path is not valid UTF-8".into()))?;
    let _ = flipcard_io::remove_file(&partial);
    if let Err(e) = conn.execute("VACUUM INTO ?1", [partial_str]) {
        let _ = flipcard_io::remove_file(&partial);
        return Err(fail(e.to_string()));
    }
    flipcard_io::rename(&partial, target).map_err(|e| {
        let _ = flipcard_io::remove_file(&partial);
        fail(e.to_string())
    })
}

/// On the first open of `today`, copies the database into `backups/` and
/// keeps only the newest [`KEEP_DAILY`] copies. Returns the copy written, if
/// one was.
pub fn daily_backup(
    conn: &Connection,
    data_dir: &Path,
    today: NaiveDate,
) -> Result<Option<PathBuf>, StoreError> {
    let target = daily_path(data_dir, today);
    if target.exists() {
        return Ok(None);
    }
    let dir = backups_dir(data_dir);
    flipcard_io::create_dir_all(&dir).map_err(|e| StoreError::Backup {
        path: dir.clone(),
        detail: e.to_string(),
    })?;
    vacuum_into(conn, &target)?;
    prune_daily(data_dir, KEEP_DAILY)?;
    Ok(Some(target))
}

fn prune_daily(data_dir: &Path, keep: usize) -> Result<(), StoreError> {
    for (_, path) in daily_backups(data_dir).into_iter().skip(keep) {
        flipcard_io::remove_file(&path).map_err(|e| StoreError::Backup {
            path: path.clone(),
            detail: format!("cannot remove an old copy: {e}"),
        })?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn day(s: &str) -> NaiveDate {
        NaiveDate::parse_from_str(s, "%Y-%m-%d").unwrap()
    }

    #[test]
    fn one_copy_a_day_and_only_the_newest_seven_kept() {
        let dir = tempfile::tempdir().unwrap();
        let conn = Connection::open(dir.path().join("flipcard.db")).unwrap();
        conn.execute_batch("CREATE TABLE t (x INTEGER); INSERT INTO t VALUES (42);")
            .unwrap();
        let first = daily_backup(&conn, dir.path(), day("2026-03-01")).unwrap();
        assert_eq!(first, Some(daily_path(dir.path(), day("2026-03-01"))));
        assert_eq!(
            daily_backup(&conn, dir.path(), day("2026-03-01")).unwrap(),
            None
        );

        for d in 2..=10 {
            daily_backup(&conn, dir.path(), day(&format!("2026-03-{d:02}"))).unwrap();
        }
        let kept: Vec<NaiveDate> = daily_backups(dir.path())
            .into_iter()
            .map(|(d, _)| d)
            .collect();
        let want: Vec<NaiveDate> = (4..=10)
            .rev()
            .map(|d| day(&format!("2026-03-{d:02}")))
            .collect();
        assert_eq!(kept, want);

        let copy = Connection::open(daily_path(dir.path(), day("2026-03-10"))).unwrap();
        let x: i64 = copy.query_row("SELECT x FROM t", [], |r| r.get(0)).unwrap();
        assert_eq!(x, 42);
        let leftovers = std::fs::read_dir(backups_dir(dir.path()))
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .unwrap()
                    .file_name()
                    .to_string_lossy()
                    .contains("partial")
            })
            .count();
        assert_eq!(leftovers, 0);
    }

    #[test]
    fn newest_backup_is_found_among_daily_and_migration_copies() {
        let dir = tempfile::tempdir().unwrap();
        let db = dir.path().join("flipcard.db");
        assert_eq!(newest_backup(&db), None);
        let conn = Connection::open(&db).unwrap();
        conn.execute_batch("CREATE TABLE t (x INTEGER);").unwrap();
        daily_backup(&conn, dir.path(), day("2026-03-01")).unwrap();
        assert_eq!(
            newest_backup(&db),
            Some(daily_path(dir.path(), day("2026-03-01")))
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
        let mig = dir.path().join("flipcard.db.bak-v1-20260302T000000Z");
        vacuum_into(&conn, &mig).unwrap();
        assert_eq!(newest_backup(&db), Some(mig));
    }
}
