//! This machine's id and the lock that lets one sync of a data folder run
//! at a time.
//!
//! The id (128 random bits, in hexadecimal) is made once and kept in
//! `<data dir>/machine-id`, so renaming the host keeps it. A data folder
//! copied to a second machine keeps it too, until a sync finds the other
//! copy's lines in its file and gives this copy a new one ([`renew`]).

use std::fs;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, bail};

use crate::deck::files::open_regular;

/// The file that holds the id, in the data dir.
pub const ID_FILE: &str = "machine-id";

/// Whether `s` is spelled like a machine id (32 lowercase hexadecimal
/// digits).
pub fn is_machine_id(s: &str) -> bool {
    s.len() == 32
        && s.bytes()
            .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b))
}

/// This machine's id, made on first use.
pub fn id(data: &Path) -> anyhow::Result<String> {
    let path = data.join(ID_FILE);
    match fs::symlink_metadata(&path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            fs::create_dir_all(data)
                .with_context(|| format!("cannot create {}", data.display()))?;
            let tmp = write_new(data)?;
            // Two processes making an id at once: the first link wins for
            // both (the second finds it there).
            let linked = fs::hard_link(&tmp, &path);
            let _ = fs::remove_file(&tmp);
            match linked {
                Ok(()) => sync_folder(data),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
                Err(e) => {
                    return Err(e).with_context(|| format!("cannot write {}", path.display()));
                }
            }
            read(&path)
        }
        Err(e) => Err(e).with_context(|| format!("cannot read {}", path.display())),
        // A file, or a link (followed; a link to nothing is said as such).
        Ok(_) => read(&path),
    }
}

/// Gives this machine a new id (the old one is in use by another copy of
/// this data folder); returns it.
pub fn renew(data: &Path) -> anyhow::Result<String> {
    let path = data.join(ID_FILE);
    let tmp = write_new(data)?;
    fs::rename(&tmp, &path).with_context(|| format!("cannot write {}", path.display()))?;
    sync_folder(data);
    read(&path)
}

fn read(path: &Path) -> anyhow::Result<String> {
    let mut text = String::new();
    open_regular(path)
        .and_then(|f| f.take(256).read_to_string(&mut text))
        .map_err(|e| {
            let why = match fs::symlink_metadata(path) {
                Ok(m) if m.file_type().is_symlink() && !path.exists() => {
                    "a link to nothing".to_string()
                }
                _ => e.to_string(),
            };
            anyhow::anyhow!(
                "{}: {why}; remove it to make a new machine id",
                path.display()
            )
        })?;
    let id = text.trim().to_ascii_lowercase();
    if !is_machine_id(&id) {
        bail!(
            "{}: not a machine id (32 hexadecimal digits); remove it to make a new one",
            path.display()
        );
    }
    Ok(id)
}

/// A new id written and synced under a temporary name; returns that name.
fn write_new(data: &Path) -> anyhow::Result<PathBuf> {
    let id = format!("{:032x}", rand::random::<u128>());
    let tmp = data.join(format!(".machine-id.{}.tmp", std::process::id()));
    write_synced(&tmp, id.as_bytes())?;
    Ok(tmp)
}

pub(super) fn write_synced(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let mut f =
        fs::File::create(path).with_context(|| format!("cannot write {}", path.display()))?;
    f.write_all(bytes)
        .and_then(|()| f.sync_all())
        .with_context(|| format!("cannot write {}", path.display()))
}

pub(super) fn sync_folder(dir: &Path) {
    if let Ok(d) = fs::File::open(dir) {
        let _ = d.sync_all();
    }
}

/// How long a sync waits for another sync of the same data folder.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wait {
    /// Not at all: the caller says that a sync is running.
    No,
    /// Up to this long.
    Up(Duration),
}

/// One sync of a data folder at a time: an exclusive `flock` on
/// `<data dir>/sync.lock`, released when this is dropped (or the process
/// ends, however it ends).
#[derive(Debug)]
pub struct Lock {
    _file: fs::File,
}

/// Why the lock was not taken.
#[derive(Debug, thiserror::Error)]
pub enum LockError {
    #[error("another sync of {0} is running; try again when it ends")]
    Busy(PathBuf),
    #[error("{0}")]
    Other(#[from] anyhow::Error),
}

impl Lock {
    pub fn take(data: &Path, wait: Wait) -> Result<Lock, LockError> {
        use rustix::fs::{FlockOperation, flock};
        use std::os::unix::fs::OpenOptionsExt;
        fs::create_dir_all(data).with_context(|| format!("cannot create {}", data.display()))?;
        let path = data.join("sync.lock");
        let file = fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .custom_flags(nix::libc::O_NOFOLLOW | nix::libc::O_NONBLOCK)
            .open(&path)
            .with_context(|| format!("cannot open {}", path.display()))?;
        if !file
            .metadata()
            .with_context(|| format!("cannot read {}", path.display()))?
            .is_file()
        {
            return Err(anyhow::anyhow!("{}: not a regular file", path.display()).into());
        }
        let start = Instant::now();
        loop {
            match flock(&file, FlockOperation::NonBlockingLockExclusive) {
                Ok(()) => return Ok(Lock { _file: file }),
                Err(e) if e == rustix::io::Errno::WOULDBLOCK || e == rustix::io::Errno::INTR => {
                    match wait {
                        Wait::Up(d) if start.elapsed() < d => {
                            std::thread::sleep(Duration::from_millis(50))
                        }
                        _ => return Err(LockError::Busy(data.to_path_buf())),
                    }
                }
                Err(e) => {
                    return Err(anyhow::anyhow!("cannot lock {}: {e}", path.display()).into());
                }
            }
        }
    }
}
