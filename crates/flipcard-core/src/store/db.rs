//! Opening the database: checks on the data dir, corruption detection before
//! anything is written, connection settings, migrations, the daily copy.

use std::path::{Path, PathBuf};
use std::time::Duration;

use rusqlite::{Connection, OpenFlags};

use super::backup;
use super::error::StoreError;
use super::schema;
use crate::sched::clock::Clock;

/// The database file inside the data dir.
pub(crate) const FILE_NAME: &str = "flipcard.db";

/// How long a write waits for another running flipcard before giving up.
pub(crate) const DEFAULT_BUSY_TIMEOUT: Duration = Duration::from_secs(5);

#[derive(Debug, Clone)]
pub struct OpenOptions {
    pub busy_timeout: Duration,
    /// Write the daily copy on the first open of a day.
    pub daily_backup: bool,
    /// The time of the daily copy and of each session's start.
    pub clock: Clock,
}

impl Default for OpenOptions {
    fn default() -> Self {
        OpenOptions {
            busy_timeout: DEFAULT_BUSY_TIMEOUT,
            daily_backup: true,
            clock: Clock::System,
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
    /// The time a session starts at.
    pub(super) clock: Clock,
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
        // Looked at with `stat` only: a descriptor of the file opened and
        // closed here, while this process holds an SQLite connection to it,
        // would drop that connection's locks (POSIX closes every lock of a
        // process on a file with any of its descriptors), and another
        // client could then delete the write-ahead log still in use.
        let found = inspect(&path)?;
        let sql_err = |e: rusqlite::Error| StoreError::from_sqlite(&path, e);

        let flags = OpenFlags::SQLITE_OPEN_READ_WRITE
            | OpenFlags::SQLITE_OPEN_CREATE
            | OpenFlags::SQLITE_OPEN_NO_MUTEX;
        let mut conn = Connection::open_with_flags(&path, flags).map_err(sql_err)?;
        conn.busy_timeout(options.busy_timeout).map_err(sql_err)?;

        let now = options.clock.now();
        let today = now.with_timezone(&chrono::Local).date_naive();
        let backup_due = options.daily_backup && !backup::daily_path(data_dir, today).exists();

        // Checked before any setting that writes: a damaged file must stay
        // exactly as it was, for the learner (or a recovery tool) to inspect.
        // The quick checks run on every open; the full page-by-page check,
        // whose time grows with the log, once a day before the daily copy
        // (so a damaged file never replaces a good copy).
        if found == Found::Present {
            check_readable(&conn, &path)?;
            check_length(&conn, &path)?;
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
        configure(&conn).map_err(sql_err)?;

        let stamp = now.format("%Y%m%dT%H%M%SZ").to_string();
        schema::migrate(&mut conn, &path, schema::MIGRATIONS, &stamp)?;

        let mut store = Store {
            conn,
            path,
            data_dir: data_dir.to_path_buf(),
            session: None,
            clock: options.clock,
            warnings,
        };
        if backup_due
            && store.has_history()?
            && let Err(e) = backup::daily_backup(&store.conn, data_dir, today)
        {
            store.warnings.push(format!("daily backup skipped: {e}"));
        }
        Ok(store)
    }

    /// Opens `<data_dir>/flipcard.db` for reading only: nothing is created,
    /// migrated or copied, so it works from a read-only data dir and on a
    /// full disk. A data dir without a database reads as an empty one.
    pub fn open_read_only(data_dir: &Path) -> Result<Store, StoreError> {
        let path = data_dir.join(FILE_NAME);
        let sql_err = |e: rusqlite::Error| StoreError::from_sqlite(&path, e);
        let conn = match inspect(&path)? {
            Found::Missing | Found::Empty => {
                let mut conn = Connection::open_in_memory().map_err(sql_err)?;
                schema::migrate(&mut conn, &path, schema::MIGRATIONS, "")?;
                conn
            }
            Found::Present => {
                let conn = open_reader(&path)?;
                check_length(&conn, &path)?;
                let version: i64 = conn
                    .pragma_query_value(None, "user_version", |r| r.get(0))
                    .map_err(sql_err)?;
                let supported = schema::current_version();
                if version > supported {
                    return Err(StoreError::TooNew {
                        path,
                        found: version,
                        supported,
                    });
                }
                if version < supported {
                    return Err(StoreError::NeedsUpgrade {
                        path,
                        found: version,
                    });
                }
                conn
            }
        };
        configure(&conn).map_err(sql_err)?;
        Ok(Store {
            conn,
            path,
            data_dir: data_dir.to_path_buf(),
            session: None,
            clock: Clock::System,
            warnings: Vec::new(),
        })
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

/// Settings every connection gets, reading or writing.
fn configure(conn: &Connection) -> rusqlite::Result<()> {
    // Stats read the recent part of the log and the caches; 16 MiB keeps
    // those pages at hand.
    conn.pragma_update(None, "cache_size", -16_384)?;
    conn.pragma_update(None, "foreign_keys", true)?;
    // So that a REPLACE conflict resolution cannot remove log rows around
    // the delete trigger.
    conn.pragma_update(None, "recursive_triggers", true)
}

/// What lies at the database's path, as far as `stat` tells.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Found {
    Missing,
    /// A regular file of 0 bytes with no write-ahead log holding pages.
    Empty,
    Present,
}

/// Looks at the database's path without opening it (see [`Store::open_with`]
/// for why). A path that is not a regular file is refused; an empty file is
/// damage when copies of a database once there sit beside it, since a fresh
/// database is never left empty once opened.
fn inspect(path: &Path) -> Result<Found, StoreError> {
    let meta = match flipcard_io::metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return match flipcard_io::read_link(path) {
                Ok(target) => Err(StoreError::NotAFile {
                    path: path.to_path_buf(),
                    what: format!(
                        "a symbolic link to {}, which does not exist",
                        target.display()
                    ),
                }),
                Err(_) => Ok(Found::Missing),
            };
        }
        Err(e) => {
            return Err(StoreError::NotAFile {
                path: path.to_path_buf(),
                what: format!("not usable ({})", crate::store::error::io_cause(&e)),
            });
        }
    };
    if !meta.is_file() {
        return Err(StoreError::NotAFile {
            path: path.to_path_buf(),
            what: crate::store::error::file_kind(&meta).to_string(),
        });
    }
    if meta.len() > 0 || wal_len(path) > 0 {
        return Ok(Found::Present);
    }
    match backup::newest_backup(path) {
        Some(newest) => Err(StoreError::Corrupt {
            path: path.to_path_buf(),
            detail: "the file is empty (0 bytes) although backups of it exist".into(),
            newest_backup: Some(newest),
        }),
        None => Ok(Found::Empty),
    }
}

/// The size of the write-ahead log beside `db` (0 when there is none).
fn wal_len(db: &Path) -> u64 {
    flipcard_io::metadata(wal_path(db)).map_or(0, |m| m.len())
}

pub(super) fn wal_path(db: &Path) -> PathBuf {
    PathBuf::from(format!("{}-wal", db.display()))
}

/// A reading connection. SQLite needs the `-shm` index of a WAL database,
/// which it cannot create in a read-only folder or on a full disk; when no
/// write-ahead log holds pages, the file alone is the whole database and
/// is opened as immutable (no index, no locks) instead.
fn open_reader(path: &Path) -> Result<Connection, StoreError> {
    let flags = OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX;
    let plain = || -> Result<Connection, StoreError> {
        let conn = Connection::open_with_flags(path, flags)
            .map_err(|e| StoreError::from_sqlite(path, e))?;
        conn.busy_timeout(DEFAULT_BUSY_TIMEOUT)
            .map_err(|e| StoreError::from_sqlite(path, e))?;
        check_readable(&conn, path)?;
        Ok(conn)
    };
    match plain() {
        Ok(conn) => Ok(conn),
        // A damaged or locked file stays so however it is opened, and pages
        // waiting in the log are seen only through the index.
        Err(e @ (StoreError::Corrupt { .. } | StoreError::Locked { .. })) => Err(e),
        Err(e) if wal_len(path) > 0 => Err(e),
        Err(_) => {
            let conn = Connection::open_with_flags(
                immutable_uri(path),
                flags | OpenFlags::SQLITE_OPEN_URI,
            )
            .map_err(|e| StoreError::from_sqlite(path, e))?;
            check_readable(&conn, path)?;
            Ok(conn)
        }
    }
}

/// `file:` URI of `path` with `immutable=1`, percent-encoding what a URI
/// path cannot hold.
fn immutable_uri(path: &Path) -> String {
    use std::os::unix::ffi::OsStrExt as _;
    let mut uri = String::from("file:");
    for &b in path.as_os_str().as_bytes() {
        if b.is_ascii_alphanumeric() || b"/-._~".contains(&b) {
            uri.push(b as char);
        } else {
            uri.push_str(&format!("%{b:02X}"));
        }
    }
    uri.push_str("?immutable=1");
    uri
}

/// Creates the data dir if needed and proves it writable, so that a
/// read-only or missing dir is reported as such rather than as an obscure
/// SQLite failure.
fn prepare_dir(dir: &Path) -> Result<(), StoreError> {
    flipcard_io::create_dir_all(dir).map_err(|source| StoreError::DataDir {
        path: dir.to_path_buf(),
        source,
    })?;
    let probe = dir.join(format!(".flipcard-write-probe-{}", std::process::id()));
    match flipcard_io::create_new(&probe) {
        Ok(_) => {
            let _ = flipcard_io::remove_file(&probe);
            Ok(())
        }
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
            // A probe left by a crashed run of this very process id.
            let _ = flipcard_io::remove_file(&probe);
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

/// A file shorter than its pages was cut off (a copy interrupted, a full
/// disk). SQLite counts the pages from the file's header; the file's length
/// comes from `stat`. Only judged when no write-ahead log holds pages, since
/// those pages may not have reached the file yet.
fn check_length(conn: &Connection, path: &Path) -> Result<(), StoreError> {
    if wal_len(path) > 0 {
        return Ok(());
    }
    let sql_err = |e: rusqlite::Error| StoreError::from_sqlite(path, e);
    let pages: i64 = conn
        .pragma_query_value(None, "page_count", |r| r.get(0))
        .map_err(sql_err)?;
    let page_size: i64 = conn
        .pragma_query_value(None, "page_size", |r| r.get(0))
        .map_err(sql_err)?;
    let expected = u64::try_from(pages.saturating_mul(page_size)).unwrap_or(0);
    let actual = flipcard_io::metadata(path).map(|m| m.len()).unwrap_or(0);
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
        let more = flipcard_text::plural(problems.len() - 3, "more problem", "more problems");
        detail.push_str(&format!("; and {more}"));
    }
    Err(StoreError::Corrupt {
        path: path.to_path_buf(),
        detail,
        newest_backup: backup::newest_backup(path),
    })
}

impl Store {
    /// Runs `work` in one immediate transaction and commits it: on `Ok` the
    /// change is on disk (WAL, `synchronous=FULL`) when this returns; on any
    /// error nothing of it is. A session the work started becomes the
    /// store's session only after the commit.
    pub(crate) fn write<T>(
        &mut self,
        work: impl FnOnce(&mut super::write::Write<'_>) -> Result<T, super::write::Failed>,
    ) -> Result<T, StoreError> {
        let (value, session) =
            super::write::immediate(&mut self.conn, &self.path, self.session, self.clock, work)?;
        self.session = session;
        Ok(value)
    }
}
