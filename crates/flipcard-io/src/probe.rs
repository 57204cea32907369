//! What a path names, found before it is opened, and the one way to open a
//! file that must be regular.
//!
//! A file flipcard reads (a deck, a learner's export, a sync file, the
//! config) must be a regular file, directly or through symbolic links.
//! Anything else is named for what it is rather than opened or skipped:
//! opening a FIFO blocks until something writes to it, a device can be
//! endless, and a deck that is silently left out lets a broken course pass
//! its checks.

use std::fs::{self, File, FileType};
use std::io::{self, Read};
use std::path::{Path, PathBuf};

/// More links than this in one chain is a loop (Linux gives up at 40 too).
const MAX_LINK_HOPS: usize = 40;

/// What a path turned out to be.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Probe {
    /// A regular file, or a symbolic link that ends at one.
    Regular,
    /// Nothing at all at that path.
    Missing,
    /// Not something to read, and what it is instead (a sentence that
    /// follows the path, e.g. "is a FIFO, not a regular file").
    Unusable(String),
}

/// Looks at `path` without opening it.
pub fn probe(path: &Path) -> Probe {
    let meta = match fs::symlink_metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Probe::Missing,
        Err(e) => return Probe::Unusable(cannot_read(&e)),
    };
    if !meta.file_type().is_symlink() {
        return match kind_name(&meta.file_type()) {
            None => Probe::Regular,
            Some(kind) => Probe::Unusable(format!("is {kind}, not a regular file")),
        };
    }
    let target = fs::read_link(path)
        .map(|t| t.display().to_string())
        .unwrap_or_default();
    match fs::metadata(path) {
        Ok(m) => match kind_name(&m.file_type()) {
            None => Probe::Regular,
            Some(kind) => Probe::Unusable(format!(
                "is a symbolic link to {kind} ({target}), not a regular file"
            )),
        },
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            Probe::Unusable(format!("dangling symbolic link to {target}"))
        }
        // The kind for ELOOP is not stable in std, so the chain is walked.
        Err(_) if link_chain_loops(path) => Probe::Unusable("symbolic link loop".to_string()),
        Err(e) => Probe::Unusable(cannot_read(&e)),
    }
}

/// Reads a regular file (directly or through links). The file is opened
/// without waiting (a FIFO would otherwise block the open until something
/// writes to it) and checked once open, so something swapped in after a
/// `probe` is refused rather than read.
pub fn read_regular(path: &Path) -> Result<Vec<u8>, String> {
    let mut file = open_regular(path).map_err(|e| match e.kind() {
        // What the path is instead of a file, said as it is.
        io::ErrorKind::Other => e.to_string(),
        _ => cannot_read(&e),
    })?;
    let mut bytes = Vec::new();
    file.read_to_end(&mut bytes).map_err(|e| cannot_read(&e))?;
    Ok(bytes)
}

/// Opens a file that must be regular (a learner's export, a package, a
/// sync file): without waiting on a FIFO, and refused with what it is
/// (`is a FIFO, not a regular file`) when it is not a file.
pub fn open_regular(path: &Path) -> io::Result<File> {
    let file = open_nonblocking(path)?;
    if let Some(kind) = kind_name(&file.metadata()?.file_type()) {
        return Err(io::Error::other(format!("is {kind}, not a regular file")));
    }
    Ok(file)
}

#[cfg(unix)]
fn open_nonblocking(path: &Path) -> io::Result<File> {
    use std::os::unix::fs::OpenOptionsExt;
    fs::OpenOptions::new()
        .read(true)
        .custom_flags(nix::libc::O_NONBLOCK)
        .open(path)
}

#[cfg(not(unix))]
fn open_nonblocking(path: &Path) -> io::Result<File> {
    File::open(path)
}

/// Reads a regular file of at most `limit` bytes (a longer one is an
/// error saying so, read no further).
pub fn read_regular_limited(path: &Path, limit: u64) -> io::Result<Vec<u8>> {
    let file = open_regular(path)?;
    let mut bytes = Vec::new();
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(io::Error::other(format!(
            "is larger than {} (the most flipcard reads of such a file)",
            crate::size(limit)
        )));
    }
    Ok(bytes)
}

/// A regular file's text (invalid UTF-8 is an error), opened as
/// [`open_regular`] does: for the config, whose absence the caller
/// tells apart by `NotFound`.
pub fn read_text(path: &Path) -> io::Result<String> {
    let mut text = String::new();
    open_regular(path)?.read_to_string(&mut text)?;
    Ok(text)
}

pub fn cannot_read(e: &io::Error) -> String {
    match e.kind() {
        io::ErrorKind::PermissionDenied => "cannot be read: permission denied".to_string(),
        io::ErrorKind::NotFound => "no such file or directory".to_string(),
        _ => format!("cannot be read: {e}"),
    }
}

/// "a FIFO", "a directory", ...; `None` for a regular file.
pub(crate) fn kind_name(t: &FileType) -> Option<&'static str> {
    if t.is_file() {
        return None;
    }
    if t.is_dir() {
        return Some("a directory");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return Some("a FIFO");
        }
        if t.is_socket() {
            return Some("a socket");
        }
        if t.is_block_device() {
            return Some("a block device");
        }
        if t.is_char_device() {
            return Some("a character device");
        }
    }
    Some("a special file")
}

/// Whether following `path`'s symbolic links never reaches anything else.
fn link_chain_loops(path: &Path) -> bool {
    let mut current: PathBuf = path.to_path_buf();
    for _ in 0..MAX_LINK_HOPS {
        match fs::read_link(&current) {
            Ok(target) => {
                let base = current.parent().unwrap_or(Path::new(""));
                current = base.join(target);
            }
            Err(_) => return false,
        }
    }
    true
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use std::os::unix::fs::symlink;

    #[test]
    fn regular_files_and_links_to_them_are_regular() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("a.toml");
        fs::write(&file, "x = 1").unwrap();
        symlink("a.toml", dir.path().join("b.toml")).unwrap();
        symlink("b.toml", dir.path().join("c.toml")).unwrap();
        for name in ["a.toml", "b.toml", "c.toml"] {
            assert_eq!(probe(&dir.path().join(name)), Probe::Regular, "{name}");
        }
        assert_eq!(read_regular(&file).unwrap(), b"x = 1");
    }

    #[test]
    fn everything_else_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let p = |n: &str| dir.path().join(n);
        fs::create_dir(p("dir.toml")).unwrap();
        symlink("nowhere/x.toml", p("dangling.toml")).unwrap();
        symlink("loop-b.toml", p("loop-a.toml")).unwrap();
        symlink("loop-a.toml", p("loop-b.toml")).unwrap();
        symlink("self.toml", p("self.toml")).unwrap();
        symlink("dir.toml", p("to-dir.toml")).unwrap();
        symlink("/dev/null", p("null.toml")).unwrap();
        let _socket = std::os::unix::net::UnixListener::bind(p("socket.toml")).unwrap();
        let unusable = |n: &str| match probe(&p(n)) {
            Probe::Unusable(why) => why,
            other => panic!("{n}: {other:?}"),
        };
        assert_eq!(unusable("dir.toml"), "is a directory, not a regular file");
        assert_eq!(
            unusable("dangling.toml"),
            "dangling symbolic link to nowhere/x.toml"
        );
        assert_eq!(unusable("loop-a.toml"), "symbolic link loop");
        assert_eq!(unusable("self.toml"), "symbolic link loop");
        assert_eq!(
            unusable("to-dir.toml"),
            "is a symbolic link to a directory (dir.toml), not a regular file"
        );
        assert_eq!(
            unusable("null.toml"),
            "is a symbolic link to a character device (/dev/null), not a regular file"
        );
        assert_eq!(unusable("socket.toml"), "is a socket, not a regular file");
        assert_eq!(probe(&p("absent.toml")), Probe::Missing);
        assert_eq!(
            read_regular(&p("dir.toml")).unwrap_err(),
            "is a directory, not a regular file"
        );
    }

    #[test]
    fn a_path_through_a_file_cannot_be_read() {
        let dir = tempfile::tempdir().unwrap();
        fs::write(dir.path().join("f"), "").unwrap();
        match probe(&dir.path().join("f/en.toml")) {
            Probe::Unusable(why) => assert!(why.starts_with("cannot be read: "), "{why}"),
            other => panic!("{other:?}"),
        }
    }
}
