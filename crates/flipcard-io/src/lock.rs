//! One process at a time: an advisory lock on a file (`flock`), released
//! when the holder drops it or the process ends, however it ends. The lock
//! file is opened without following a link and without waiting on a FIFO,
//! and must be a regular file.

use std::fs;
use std::io;
use std::path::Path;
use std::time::{Duration, Instant};

/// How long to wait for a lock another process holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wait {
    /// Not at all: the caller says another run holds it.
    No,
    /// Up to this long.
    Up(Duration),
    /// As long as it takes.
    Forever,
}

/// A held lock.
#[derive(Debug)]
pub struct Lock {
    _file: fs::File,
}

impl Lock {
    /// Takes the lock on `path` (creating the file), waiting as `wait`
    /// says; `Ok(None)` when another process holds it past that.
    pub fn take(path: &Path, wait: Wait) -> io::Result<Option<Lock>> {
        let file = open_lock_file(path)?;
        if wait == Wait::Forever {
            file.lock()?;
            return Ok(Some(Lock { _file: file }));
        }
        let start = Instant::now();
        loop {
            match file.try_lock() {
                Ok(()) => return Ok(Some(Lock { _file: file })),
                Err(fs::TryLockError::WouldBlock) => match wait {
                    Wait::Up(d) if start.elapsed() < d => {
                        std::thread::sleep(Duration::from_millis(50))
                    }
                    _ => return Ok(None),
                },
                Err(fs::TryLockError::Error(e)) => return Err(e),
            }
        }
    }
}

fn open_lock_file(path: &Path) -> io::Result<fs::File> {
    let mut options = fs::OpenOptions::new();
    options.read(true).write(true).create(true).truncate(false);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(nix::libc::O_NOFOLLOW | nix::libc::O_NONBLOCK);
    }
    let file = options.open(path)?;
    if !file.metadata()?.is_file() {
        return Err(io::Error::other("not a regular file"));
    }
    Ok(file)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_taker_waits_or_is_told() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.lock");
        let held = Lock::take(&path, Wait::No).unwrap();
        assert!(held.is_some());
        // flock locks are per open file: a second open in this process
        // conflicts as another process would.
        assert!(Lock::take(&path, Wait::No).unwrap().is_none());
        assert!(
            Lock::take(&path, Wait::Up(Duration::from_millis(120)))
                .unwrap()
                .is_none()
        );
        drop(held);
        assert!(Lock::take(&path, Wait::No).unwrap().is_some());
    }
}
