//! Why a sync failed, as one type a caller can match on (the command waits
//! and tries again when another sync holds the lock; the app says the rest
//! in its status line). Each message is the one the app has always shown;
//! a file's error keeps its cause as the source, so the app's one-line
//! chain reads "cannot write …: permission denied".

use std::path::PathBuf;

use crate::store::StoreError;

/// Why a sync (or the machine id it needs) failed.
#[derive(Debug, thiserror::Error)]
pub enum SyncError {
    /// Another sync of this data folder holds its lock.
    #[error("another sync of {} is running; try again when it ends", .0.display())]
    Busy(PathBuf),
    #[error("cannot lock {}: {source}", path.display())]
    Lock {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("cannot create {}", path.display())]
    Create {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("cannot read {}", path.display())]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("cannot write {}", path.display())]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The machine id's file cannot be read (`why` says how).
    #[error("{}: {why}; remove it to make a new machine id", path.display())]
    IdUnreadable { path: PathBuf, why: String },
    #[error(
        "{}: not a machine id (32 hexadecimal digits); remove it to make a new one",
        .0.display()
    )]
    NotAnId(PathBuf),
    #[error("cannot read the sync folder {}", path.display())]
    ReadFolder {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error(
        "{}: not a folder (sync goes through a folder another tool keeps in step)",
        .0.display()
    )]
    NotAFolder(PathBuf),
    #[error(
        "{}: no such folder (create it, or point the sync tool's folder there)",
        .0.display()
    )]
    NoFolder(PathBuf),
    #[error(transparent)]
    Store(#[from] StoreError),
    /// The thread of a background sync could not be started.
    #[error("cannot start a sync: {0}")]
    Spawn(std::io::Error),
    /// The thread of a background sync ended without a result.
    #[error("the sync stopped without a word")]
    Stopped,
}
