//! Opening the database: checks on the data dir, corruption detection before
//! anything is written, connection settings, migrations, the daily copy.

use std::path::{Path, PathBuf};
use std::time::Duration;

use rusqlite::{Connection, OpenFlags};

use super::backup;
use super::error::StoreError;
use super::schema;

/// The database file inside the data dir.
pub const FILE_NAME: &str = "flipcard.db";

/// How long a write waits for another running flipcard before giving up.
pub const DEFAULT_BUSY_TIMEOUT: Duration = Duration::from_secs(5);

#[derive(Debug, Clone)]
pub struct OpenOptions {
    pub busy_timeout: Duration,
    /// Write the daily copy on the first open of a day.
    pub daily_backup: bool,
}

impl Default for OpenOptions {
    fn default() -> Self {
        OpenOptions {
            busy_timeout: DEFAULT_BUSY_TIMEOUT,
            daily_backup: true,
        }
    }
}

/// An open review database. Every write is one transaction committed to disk
/// (`synchronous=FULL`) before the call returns.
pub struct Store {
    pub(super) conn: Connection,
    pub(super) path: PathBuf,
    pub(super) data_dir: PathBuf,
    /// The session this store writes under, started with the first write.
    pub(super) session: Option<i64>,
    warnings: Vec<String>,
}

impl std::fmt::Debug for Store {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Store")
            .field("path", &self.path)
            .field("session", &self.session)
            .finish_non_exhaustive()
    }
}

impl Store {
    /// Opens (creating if needed) `<data_dir>/flipcard.db`.
    pub fn open(data_dir: &Path) -> Result<Store, StoreError> {
        Store::open_with(data_dir, &OpenOptions::default())
    }

    pub fn open_with(data_dir: &Path, options: &OpenOptions) -> Result<Store, StoreError> {
        prepare_dir(data_dir)?;
        let path = data_dir.join(FILE_NAME);
        let existed = std::fs::metadata(&path)
            .map(|m| m.len() > 0)
            .unwrap_or(false);
        let sql_err = |e: rusqlite::Error| StoreError::from_sqlite(&path, e);

        let flags = OpenFlags::SQLITE_OPEN_READ_WRITE
            | OpenFlags::SQLITE_OPEN_CREATE
            | OpenFlags::SQLITE_OPEN_NO_MUTEX;
        let mut conn = Connection::open_with_flags(&path, flags).map_err(sql_err)?;
        conn.busy_timeout(options.busy_timeout).map_err(sql_err)?;

        let now = crate::clock::now()?;
        let today = now.with_timezone(&chrono::Local).date_naive();
        let backup_due = options.daily_backup && !backup::daily_path(data_dir, today).exists();

        // Checked before any setting that writes: a damaged file must stay
        // exactly as it was, for the learner (or a recovery tool) to inspect.
        // The quick checks run on every open; the full page-by-page check,
        // whose time grows with the log, once a day before the daily copy
        // (so a damaged file never replaces a good copy).
        if existed {
            check_readable(&conn, &path)?;
            check_length(&path)?;
            if backup_due {
                check_pages(&conn, &path)?;
            }
        }

        let mut warnings = Vec::new();
        let mode: String = conn
            .pragma_update_and_check(None, "journal_mode", "WAL", |r| r.get(0))
            .map_err(sql_err)?;
        if !mode.eq_ignore_ascii_case("wal") {
            warnings.push(format!(
                "database {} could not switch to WAL mode (it is in {mode} mode); a second running flipcard may have to wait",
                path.display()
            ));
        }
        conn.pragma_update(None, "synchronous", "FULL")
            .map_err(sql_err)?;
        // Stats read the recent part of the log and the caches; 16 MiB
        // keeps those pages at hand.
        conn.pragma_update(None, "cache_size", -16_384)
            .map_err(sql_err)?;
        conn.pragma_update(None, "foreign_keys", true)
            .map_err(sql_err)?;
        // So that a REPLACE conflict resolution cannot remove log rows
        // around the delete trigger.
        conn.pragma_update(None, "recursive_triggers", true)
            .map_err(sql_err)?;

        let stamp = now.format("%Y%m%dT%H%M%SZ").to_string();
        schema::migrate(&mut conn, &path, schema::MIGRATIONS, &stamp)?;

        let store = Store {
            conn,
            path,
            data_dir: data_dir.to_path_buf(),
            session: None,
            warnings,
        };
        let mut store = store;
        if backup_due
            && store.has_history()?
            && let Err(e) = backup::daily_backup(&store.conn, data_dir, today)
        {
            store.warnings.push(format!("daily backup skipped: {e}"));
        }
        Ok(store)
    }

    /// The database file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    pub fn data_dir(&self) -> &Path {
        &self.data_dir
    }

    /// Problems met while opening that did not stop it (e.g. a daily backup
    /// that could not be written), for the caller to show.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// `PRAGMA integrity_check`: `["ok"]` for a sound file, else the problems.
    pub fn integrity_check(&self) -> Result<Vec<String>, StoreError> {
        let mut st = self
            .conn
            .prepare("PRAGMA integrity_check")
            .map_err(|e| self.err(e))?;
        let rows = st
            .query_map([], |r| r.get::<_, String>(0))
            .map_err(|e| self.err(e))?;
        rows.collect::<Result<_, _>>().map_err(|e| self.err(e))
    }

    pub(super) fn err(&self, e: rusqlite::Error) -> StoreError {
        StoreError::from_sqlite(&self.path, e)
    }

    fn has_history(&self) -> Result<bool, StoreError> {
        self.conn
            .query_row(
                "SELECT EXISTS (SELECT 1 FROM review) OR EXISTS (SELECT 1 FROM prompt_attempt)",
                [],
                |r| r.get(0),
            )
            .map_err(|e| self.err(e))
    }
}

/// Creates the data dir if needed and proves it writable, so that a
/// read-only or missing dir is reported as such rather than as an obscure
/// SQLite failure.
fn prepare_dir(dir: &Path) -> Result<(), StoreError> {
    std::fs::create_dir_all(dir).map_err(|source| StoreError::DataDir {
        path: dir.to_path_buf(),
        source,
    })?;
    let probe = dir.join(format!(".flipcard-write-probe-{}", std::process::id()));
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
    {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
            // A probe left by a crashed run of this very process id.
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(source) => Err(StoreError::NotWritable {
            path: dir.to_path_buf(),
            source,
        }),
    }
}

/// Reading the schema parses the file's header and first pages: a file
/// that is not an SQLite database fails here.
fn check_readable(conn: &Connection, path: &Path) -> Result<(), StoreError> {
    conn.query_row("SELECT count(*) FROM sqlite_schema", [], |r| {
        r.get::<_, i64>(0)
    })
    .map(|_| ())
    .map_err(|e| StoreError::from_sqlite(path, e))
}

/// A file shorter than its header says was cut off (a copy interrupted, a
/// full disk). The header's size is trusted only when it is marked valid
/// and no write-ahead log holds pages yet to be copied into the file.
fn check_length(path: &Path) -> Result<(), StoreError> {
    let wal = PathBuf::from(format!("{}-wal", path.display()));
    if std::fs::metadata(&wal).is_ok_and(|m| m.len() > 0) {
        return Ok(());
    }
    let mut header = [0u8; 100];
    let read = std::fs::File::open(path).and_then(|mut f| {
        use std::io::Read as _;
        f.read_exact(&mut header)
    });
    if read.is_err() {
        // Shorter than a header: the schema read has already judged it.
        return Ok(());
    }
    let be32 = |at: usize| {
        u32::from_be_bytes([header[at], header[at + 1], header[at + 2], header[at + 3]])
    };
    if !header.starts_with(b"SQLite format 3\0") || be32(24) != be32(92) {
        return Ok(());
    }
    let page_size = match u16::from_be_bytes([header[16], header[17]]) {
        1 => 65_536,
        n => u64::from(n),
    };
    let expected = u64::from(be32(28)) * page_size;
    let actual = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
    if expected > actual {
        return Err(StoreError::Corrupt {
            path: path.to_path_buf(),
            detail: format!("the file is cut short: {actual} of its {expected} bytes are there"),
            newest_backup: backup::newest_backup(path),
        });
    }
    Ok(())
}

/// `PRAGMA quick_check`: every page and index entry looked at.
fn check_pages(conn: &Connection, path: &Path) -> Result<(), StoreError> {
    let mut st = conn
        .prepare("PRAGMA quick_check")
        .map_err(|e| StoreError::from_sqlite(path, e))?;
    let problems: Vec<String> = st
        .query_map([], |r| r.get::<_, String>(0))
        .and_then(|rows| rows.collect())
        .map_err(|e| StoreError::from_sqlite(path, e))?;
    if problems.len() == 1 && problems[0] == "ok" {
        return Ok(());
    }
    let mut detail = problems
        .iter()
        .take(3)
        .cloned()
        .collect::<Vec<_>>()
        .join("; ");
    if problems.len() > 3 {
        detail.push_str(&format!("; and {} more problems", problems.len() - 3));
    }
    Err(StoreError::Corrupt {
        path: path.to_path_buf(),
        detail,
        newest_backup: backup::newest_backup(path),
    })
}
