//! Where deck and content files are read from: the disk (through `io`,
//! which never waits on a FIFO and names what is not a regular file), or
//! files held in memory (the decks built into the binary), behind one
//! [`Tree`] so the loader reads both alike.

use std::io;
use std::path::{Path, PathBuf};

pub use flipcard_io::{Probe, open_regular, probe, read_regular};

/// Where deck and content files are read from: the disk, or files held in
/// memory (the decks built into the binary).
pub trait Tree: Sync {
    fn probe(&self, path: &Path) -> Probe;
    fn read(&self, path: &Path) -> Result<Vec<u8>, String>;
    fn is_dir(&self, path: &Path) -> bool;
    /// The entries directly in `dir`, in no particular order.
    fn list(&self, dir: &Path) -> io::Result<Vec<PathBuf>>;
    /// One name per file, however it was reached (links, `..`).
    fn identity(&self, path: &Path) -> PathBuf;
    /// The size of the file at `path` (through links), when it can be told
    /// without reading it.
    fn len(&self, path: &Path) -> Option<u64>;
}

/// The file system.
pub struct Disk;

impl Tree for Disk {
    fn probe(&self, path: &Path) -> Probe {
        probe(path)
    }

    fn read(&self, path: &Path) -> Result<Vec<u8>, String> {
        read_regular(path)
    }

    fn is_dir(&self, path: &Path) -> bool {
        path.is_dir()
    }

    fn list(&self, dir: &Path) -> io::Result<Vec<PathBuf>> {
        flipcard_io::entries(dir)
    }

    fn identity(&self, path: &Path) -> PathBuf {
        flipcard_io::canonical(path)
    }

    fn len(&self, path: &Path) -> Option<u64> {
        flipcard_io::metadata(path).ok().map(|m| m.len())
    }
}

/// Files held in memory, by path.
pub struct Memory {
    files: std::collections::BTreeMap<PathBuf, &'static [u8]>,
}

impl Memory {
    pub fn new(files: impl IntoIterator<Item = (PathBuf, &'static [u8])>) -> Memory {
        Memory {
            files: files.into_iter().collect(),
        }
    }
}

impl Tree for Memory {
    fn probe(&self, path: &Path) -> Probe {
        if self.files.contains_key(path) {
            Probe::Regular
        } else if self.is_dir(path) {
            Probe::Unusable("is a directory, not a regular file".to_string())
        } else {
            Probe::Missing
        }
    }

    fn read(&self, path: &Path) -> Result<Vec<u8>, String> {
        match self.files.get(path) {
            Some(bytes) => Ok(bytes.to_vec()),
            None => Err("no such file or directory".to_string()),
        }
    }

    fn is_dir(&self, path: &Path) -> bool {
        self.files.keys().any(|f| f != path && f.starts_with(path))
    }

    fn list(&self, dir: &Path) -> io::Result<Vec<PathBuf>> {
        if !self.is_dir(dir) {
            return Err(io::Error::from(io::ErrorKind::NotFound));
        }
        Ok(self
            .files
            .keys()
            .filter(|f| f.parent() == Some(dir))
            .cloned()
            .collect())
    }

    fn identity(&self, path: &Path) -> PathBuf {
        path.to_path_buf()
    }

    fn len(&self, path: &Path) -> Option<u64> {
        self.files.get(path).map(|b| b.len() as u64)
    }
}
