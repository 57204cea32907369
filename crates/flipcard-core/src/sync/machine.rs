//! This machine's id and the lock that lets one sync of a data folder run
//! at a time.
//!
//! The id (128 random bits, in hexadecimal) is made once and kept in
//! `<data dir>/machine-id`, so renaming the host keeps it. A data folder
//! copied to a second machine keeps it too, until a sync finds the other
//! copy's lines in its file and gives this copy a new one ([`renew`]).

use std::io::Read;
use std::path::{Path, PathBuf};

use flipcard_io::{self as disk, Durability, open_regular};

use super::error::SyncError;

/// The file that holds the id, in the data dir.
pub(crate) const ID_FILE: &str = "machine-id";

/// Whether `s` is spelled like a machine id (32 lowercase hexadecimal
/// digits).
pub(crate) fn is_machine_id(s: &str) -> bool {
    s.len() == 32
        && s.bytes()
            .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b))
}

/// This machine's id, made on first use.
pub fn id(data: &Path) -> Result<String, SyncError> {
    let path = data.join(ID_FILE);
    match disk::metadata_no_follow(&path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            disk::create_dir_all(data).map_err(|source| SyncError::Create {
                path: data.to_path_buf(),
                source,
            })?;
            let tmp = write_new(data)?;
            // Two processes making an id at once: the first link wins for
            // both (the second finds it there).
            let linked = disk::hard_link(&tmp, &path);
            let _ = disk::remove_file(&tmp);
            match linked {
                Ok(()) => disk::sync_dir(data),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
                Err(source) => return Err(SyncError::Write { path, source }),
            }
            read(&path)
        }
        Err(source) => Err(SyncError::Read { path, source }),
        // A file, or a link (followed; a link to nothing is said as such).
        Ok(_) => read(&path),
    }
}

/// Gives this machine a new id (the old one is in use by another copy of
/// this data folder); returns it.
pub(crate) fn renew(data: &Path) -> Result<String, SyncError> {
    let path = data.join(ID_FILE);
    let id = format!("{:032x}", rand::random::<u128>());
    if let Err(source) = disk::write_atomic(&path, id.as_bytes(), Durability::Synced) {
        return Err(SyncError::Write { path, source });
    }
    read(&path)
}

fn read(path: &Path) -> Result<String, SyncError> {
    let mut text = String::new();
    open_regular(path)
        .and_then(|f| f.take(256).read_to_string(&mut text))
        .map_err(|e| {
            let why = match disk::metadata_no_follow(path) {
                Ok(m) if m.file_type().is_symlink() && !path.exists() => {
                    "a link to nothing".to_string()
                }
                _ => e.to_string(),
            };
            SyncError::IdUnreadable {
                path: path.to_path_buf(),
                why,
            }
        })?;
    let id = text.trim().to_ascii_lowercase();
    if !is_machine_id(&id) {
        return Err(SyncError::NotAnId(path.to_path_buf()));
    }
    Ok(id)
}

/// A new id written and synced under a temporary name; returns that name.
fn write_new(data: &Path) -> Result<PathBuf, SyncError> {
    let id = format!("{:032x}", rand::random::<u128>());
    let tmp = data.join(format!(".machine-id.{}.tmp", std::process::id()));
    let _ = disk::remove_file(&tmp);
    match disk::write_new(&tmp, id.as_bytes()) {
        Ok(()) => Ok(tmp),
        Err(source) => Err(SyncError::Write { path: tmp, source }),
    }
}

pub use flipcard_io::Wait;

/// One sync of a data folder at a time: an exclusive lock on
/// `<data dir>/sync.lock`, released when this is dropped (or the process
/// ends, however it ends).
#[derive(Debug)]
pub struct Lock {
    _lock: disk::Lock,
}

impl Lock {
    /// The lock, or [`SyncError::Busy`] when another sync holds it.
    pub fn take(data: &Path, wait: Wait) -> Result<Lock, SyncError> {
        disk::create_dir_all(data).map_err(|source| SyncError::Create {
            path: data.to_path_buf(),
            source,
        })?;
        let path = data.join("sync.lock");
        match disk::Lock::take(&path, wait) {
            Ok(Some(lock)) => Ok(Lock { _lock: lock }),
            Ok(None) => Err(SyncError::Busy(data.to_path_buf())),
            Err(source) => Err(SyncError::Lock { path, source }),
        }
    }
}
