//! What can go wrong with the review database, phrased for the learner:
//! every message names the file or folder involved and says what to do.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    #[error("cannot use data dir {path}: {source}; pass --data-dir or set FLIPCARD_DATA_DIR")]
    DataDir {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },

    #[error(
        "data dir {path} is not writable ({source}); pass --data-dir or set FLIPCARD_DATA_DIR to a writable folder"
    )]
    NotWritable {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },

    #[error("{}", corrupt_message(path, detail, newest_backup.as_ref()))]
    Corrupt {
        path: PathBuf,
        detail: String,
        newest_backup: Option<PathBuf>,
    },

    #[error("database path {path} is {what}; move it away or pass another --data-dir")]
    NotAFile { path: PathBuf, what: String },

    #[error(
        "disk full: cannot write to database {path}; free some space on its disk and try again (nothing saved before was lost)"
    )]
    DiskFull { path: PathBuf },

    #[error(
        "database {path} has schema version {found}, older than this flipcard writes; open it once with a command that writes (e.g. `flipcard db rebuild`) to upgrade it"
    )]
    NeedsUpgrade { path: PathBuf, found: i64 },

    #[error(
        "database {path} is locked by another program (still busy after waiting); close the other flipcard and try again"
    )]
    Locked { path: PathBuf },

    #[error(
        "database {path} has schema version {found}, newer than this flipcard understands ({supported}); upgrade flipcard"
    )]
    TooNew {
        path: PathBuf,
        found: i64,
        supported: i64,
    },

    #[error(
        "{path} is an SQLite database but not a flipcard one (it has tables and no schema version); move it away or pass another --data-dir"
    )]
    Foreign { path: PathBuf },

    #[error("cannot write backup {path}: {detail}")]
    Backup { path: PathBuf, detail: String },

    #[error("review log row {id} is unreadable: {detail}")]
    BadRow { id: i64, detail: String },

    /// Not a `source`: SQLite's message already says what its code does,
    /// which a chain would say again ("Error code 14: unable to open ...").
    #[error("database {path}: {error}")]
    Sqlite {
        path: PathBuf,
        error: rusqlite::Error,
    },
}

fn corrupt_message(path: &std::path::Path, detail: &str, backup: Option<&PathBuf>) -> String {
    let advice = match backup {
        Some(b) => format!(
            "The newest backup is {}; `flipcard db restore` sets the damaged file aside (it is kept) and restores that backup.",
            b.display()
        ),
        None => "No backup was found next to it.".to_string(),
    };
    format!(
        "database {} is corrupt ({detail}); it was left untouched. {advice}",
        path.display()
    )
}

impl StoreError {
    /// Classifies an SQLite error: busy and corrupt files get their own
    /// messages, everything else is reported with the database path.
    pub(crate) fn from_sqlite(path: &std::path::Path, err: rusqlite::Error) -> StoreError {
        use rusqlite::ErrorCode;
        match err.sqlite_error_code() {
            Some(ErrorCode::DatabaseBusy | ErrorCode::DatabaseLocked) => StoreError::Locked {
                path: path.to_path_buf(),
            },
            Some(ErrorCode::DatabaseCorrupt | ErrorCode::NotADatabase) => StoreError::Corrupt {
                path: path.to_path_buf(),
                detail: err.to_string(),
                newest_backup: super::backup_files::newest_backup(path),
            },
            Some(ErrorCode::DiskFull) => StoreError::DiskFull {
                path: path.to_path_buf(),
            },
            // A full disk often surfaces as a failed write, sync or resize of
            // the log or its index rather than as SQLITE_FULL.
            Some(ErrorCode::SystemIoFailure | ErrorCode::CannotOpen) if disk_nearly_full(path) => {
                StoreError::DiskFull {
                    path: path.to_path_buf(),
                }
            }
            _ => StoreError::Sqlite {
                path: path.to_path_buf(),
                error: err,
            },
        }
    }
}

/// Below this much free space, a failed write is taken for a full disk.
const NEARLY_FULL: u64 = 1 << 20;

/// Whether the disk holding `path` has (almost) no space left for it.
fn disk_nearly_full(path: &std::path::Path) -> bool {
    let dir = path.parent().unwrap_or(path);
    flipcard_io::space_left(dir).is_some_and(|left| left < NEARLY_FULL)
}

/// An I/O error's cause in words, without Rust's `(os error N)` suffix.
pub(crate) fn io_cause(e: &std::io::Error) -> String {
    let text = e.to_string();
    match text.find(" (os error") {
        Some(at) => text[..at].to_string(),
        None => text,
    }
}

pub use flipcard_io::file_kind;
