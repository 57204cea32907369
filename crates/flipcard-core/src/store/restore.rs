//! `flipcard db restore`: a damaged database is set aside (renamed, never
//! deleted) together with its write-ahead log and index, and a backup
//! takes its place.
//!
//! Nothing here opens the database through SQLite while it also holds a
//! plain descriptor of it: the lock probe opens the file only when no
//! connection to it exists in this process.

use std::os::fd::AsFd as _;
use std::path::{Path, PathBuf};

use rusqlite::{Connection, OpenFlags};

use super::backup;
use super::db::{FILE_NAME, Store, wal_path};
use super::error::{StoreError, file_kind, io_cause};
use crate::sched::clock::Clock;

/// What a restore did.
#[derive(Debug, Clone, PartialEq)]
pub struct Restored {
    pub backup: PathBuf,
    pub database: PathBuf,
    /// Where the previous database (and its `-wal` / `-shm`) went.
    pub set_aside: Vec<PathBuf>,
    /// Review log rows in the restored database.
    pub reviews: i64,
}

#[derive(Debug, thiserror::Error)]
pub enum RestoreError {
    #[error("no backup found in {dir}; name one: `flipcard db restore FILE`")]
    NoBackup { dir: PathBuf },
    #[error("backup {path} cannot be used: {detail}")]
    BadBackup { path: PathBuf, detail: String },
    #[error(
        "database {path} is sound ({}); restoring would set aside every rating made since the backup. Pass --force to restore anyway",
        flipcard_text::plural(*reviews, "review", "reviews")
    )]
    Sound { path: PathBuf, reviews: i64 },
    #[error(
        "database {path} is open in another program (a running flipcard?); close it and try again"
    )]
    InUse { path: PathBuf },
    #[error("cannot {what} {path}: {cause}")]
    Io {
        what: &'static str,
        path: PathBuf,
        cause: String,
    },
    #[error(transparent)]
    Store(#[from] StoreError),
}

/// Restores `backup` (default: the newest one) as the database of
/// `data_dir`. A sound database is replaced only with `force`. The
/// database set aside is named by the time of `clock`.
pub fn restore(
    data_dir: &Path,
    backup: Option<&Path>,
    force: bool,
    clock: Clock,
) -> Result<Restored, RestoreError> {
    let db = data_dir.join(FILE_NAME);
    let backup = match backup {
        Some(b) => b.to_path_buf(),
        None => backup::newest_backup(&db).ok_or_else(|| RestoreError::NoBackup {
            dir: backup::backups_dir(data_dir),
        })?,
    };
    let backup_reviews = check_backup(&backup)?;

    if flipcard_io::metadata_no_follow(&db).is_ok() {
        if in_use(&db)? {
            return Err(RestoreError::InUse { path: db });
        }
        if !force && let Some(reviews) = sound(data_dir) {
            return Err(RestoreError::Sound { path: db, reviews });
        }
    }

    let stamp = clock.now().format("%Y%m%dT%H%M%SZ").to_string();
    let set_aside = set_aside(&db, &stamp)?;
    copy_durably(&backup, &db)?;
    // Opening brings the copy up to this build's schema and WAL mode.
    let options = super::OpenOptions {
        clock,
        ..super::OpenOptions::default()
    };
    let store = Store::open_with(data_dir, &options)?;
    let reviews = store.review_count()?;
    debug_assert_eq!(reviews, backup_reviews);
    Ok(Restored {
        backup,
        database: db,
        set_aside,
        reviews,
    })
}

/// The backup is a sound flipcard database; returns its review count.
fn check_backup(path: &Path) -> Result<i64, RestoreError> {
    let bad = |detail: String| RestoreError::BadBackup {
        path: path.to_path_buf(),
        detail,
    };
    let meta = flipcard_io::metadata(path).map_err(|e| bad(io_cause(&e)))?;
    if !meta.is_file() {
        return Err(bad(format!("it is {}", file_kind(&meta))));
    }
    let conn = Connection::open_with_flags(
        path,
        OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX,
    )
    .map_err(|e| bad(e.to_string()))?;
    let problems: Vec<String> = conn
        .prepare("PRAGMA quick_check")
        .and_then(|mut st| {
            st.query_map([], |r| r.get::<_, String>(0))?
                .collect::<rusqlite::Result<_>>()
        })
        .map_err(|e| bad(e.to_string()))?;
    if problems != ["ok"] {
        return Err(bad(format!("it is damaged too ({})", problems.join("; "))));
    }
    let version: i64 = conn
        .pragma_query_value(None, "user_version", |r| r.get(0))
        .map_err(|e| bad(e.to_string()))?;
    if version < 1 || version > super::schema::current_version() {
        return Err(bad(format!(
            "it is not a flipcard database this version reads (schema version {version})"
        )));
    }
    conn.query_row("SELECT count(*) FROM review", [], |r| r.get(0))
        .map_err(|e| bad(e.to_string()))
}

/// The review count of the database when it opens and passes its checks.
fn sound(data_dir: &Path) -> Option<i64> {
    let store = Store::open_read_only(data_dir).ok()?;
    (store.integrity_check().ok()? == ["ok"])
        .then(|| store.review_count().ok())
        .flatten()
}

/// SQLite's lock bytes: a connection of another process holds a lock there
/// for as long as it is open (a shared one, in WAL mode).
const PENDING_BYTE: i64 = 0x4000_0000;
const LOCK_BYTES: i64 = 512;

/// Whether another process holds any SQLite lock on the database file.
fn in_use(db: &Path) -> Result<bool, RestoreError> {
    let io = |e: std::io::Error| RestoreError::Io {
        what: "look at",
        path: db.to_path_buf(),
        cause: io_cause(&e),
    };
    let meta = flipcard_io::metadata(db).map_err(io)?;
    if !meta.is_file() {
        // Nothing to probe: it is set aside as it is.
        return Ok(false);
    }
    let file = flipcard_io::open(db).map_err(io)?;
    let mut probe = nix::libc::flock {
        l_type: nix::libc::F_WRLCK as i16,
        l_whence: nix::libc::SEEK_SET as i16,
        l_start: PENDING_BYTE,
        l_len: LOCK_BYTES,
        l_pid: 0,
    };
    nix::fcntl::fcntl(file.as_fd(), nix::fcntl::FcntlArg::F_GETLK(&mut probe))
        .map_err(|e| io(std::io::Error::from(e)))?;
    Ok(probe.l_type != nix::libc::F_UNLCK as i16)
}

/// Renames the database and its `-wal` / `-shm` to `…damaged-<stamp>`
/// names (the log keeps its `-wal` suffix so that SQLite pairs them again
/// when the set-aside file is opened for recovery).
fn set_aside(db: &Path, stamp: &str) -> Result<Vec<PathBuf>, RestoreError> {
    let aside = unused_name(db, stamp);
    let mut moved = Vec::new();
    for (from, to) in [
        (db.to_path_buf(), aside.clone()),
        (wal_path(db), suffixed(&aside, "-wal")),
        (suffixed(db, "-shm"), suffixed(&aside, "-shm")),
    ] {
        if flipcard_io::metadata_no_follow(&from).is_err() {
            continue;
        }
        flipcard_io::rename(&from, &to).map_err(|e| RestoreError::Io {
            what: "set aside",
            path: from.clone(),
            cause: io_cause(&e),
        })?;
        moved.push(to);
    }
    Ok(moved)
}

fn unused_name(db: &Path, stamp: &str) -> PathBuf {
    let base = suffixed(db, &format!(".damaged-{stamp}"));
    let mut candidate = base.clone();
    let mut n = 1;
    while flipcard_io::metadata_no_follow(&candidate).is_ok() {
        n += 1;
        candidate = suffixed(&base, &format!("-{n}"));
    }
    candidate
}

fn suffixed(path: &Path, suffix: &str) -> PathBuf {
    let mut s = path.as_os_str().to_owned();
    s.push(suffix);
    PathBuf::from(s)
}

/// Copies `from` to `to` through a temporary name, on disk (file and
/// folder synced) before the rename makes it the database.
fn copy_durably(from: &Path, to: &Path) -> Result<(), RestoreError> {
    flipcard_io::copy_atomic(from, to).map_err(|e| RestoreError::Io {
        what: "write",
        path: to.to_path_buf(),
        cause: io_cause(&e),
    })
}
