//! What can go wrong with the review database, phrased for the learner:
//! every message names the file or folder involved and says what to do.

use std::path::PathBuf;

use crate::clock::ClockError;

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

    #[error("database {path}: {source}")]
    Sqlite {
        path: PathBuf,
        #[source]
        source: rusqlite::Error,
    },

    #[error(transparent)]
    Clock(#[from] ClockError),
}

fn corrupt_message(path: &std::path::Path, detail: &str, backup: Option<&PathBuf>) -> String {
    let advice = match backup {
        Some(b) => format!(
            "the newest backup is {}; to restore it, move the damaged file away and copy the backup to {}",
            b.display(),
            path.display()
        ),
        None => "no backup was found next to it".to_string(),
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
                newest_backup: super::backup::newest_backup(path),
            },
            _ => StoreError::Sqlite {
                path: path.to_path_buf(),
                source: err,
            },
        }
    }
}
