//! Replacing a file whole: the new bytes go to a temporary name in the same
//! folder, are flushed, and the temporary file is renamed over the target,
//! so a reader (or a crash) sees the old file or the new one, never part of
//! either. A symbolic link at the target is written through: the file it
//! names is replaced and the link stays (a config kept in a dotfiles
//! repository).

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// How sure a write must be before it returns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Durability {
    /// On disk: the file and its folder flushed (a learner's data, the
    /// config, sync files, backups).
    Synced,
    /// Whole but not flushed (outputs that can be made again: a report,
    /// exported schemas, a benchmark's table).
    Whole,
}

/// Replaces `path` with `bytes` (creating it and its folder if needed).
pub fn write_atomic(path: &Path, bytes: &[u8], durability: Durability) -> io::Result<()> {
    let target = resolve_links(path)?;
    replace_atomic(&target, bytes, durability)
}

/// Replaces what is at `path` itself with a regular file of `bytes`, as
/// [`write_atomic`] does but following no link: a link (or a FIFO, or any
/// other file) put at `path` is replaced, and what a link named is left
/// as it was. For putting back a file whose name something else may have
/// taken meanwhile (an edit reverted).
pub fn replace_atomic(target: &Path, bytes: &[u8], durability: Durability) -> io::Result<()> {
    let target = target.to_path_buf();
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    fs::create_dir_all(&dir)?;
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let written = (|| {
        let mut file = fs::File::create(&tmp)?;
        file.write_all(bytes)?;
        if durability == Durability::Synced {
            file.sync_all()?;
        }
        fs::rename(&tmp, &target)
    })();
    if written.is_err() {
        let _ = fs::remove_file(&tmp);
        return written;
    }
    if durability == Durability::Synced {
        sync_dir(&dir);
    }
    Ok(())
}

/// Copies the file `from` over `to` as [`write_atomic`] replaces a file:
/// a reader of `to` sees the old file or the whole copy, flushed to disk
/// with its folder (a database restored from a copy).
pub fn copy_atomic(from: &Path, to: &Path) -> io::Result<()> {
    let dir = match to.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = to
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let copied = (|| {
        let mut source = fs::File::open(from)?;
        let mut target = fs::File::create(&tmp)?;
        io::copy(&mut source, &mut target)?;
        target.sync_all()?;
        fs::rename(&tmp, to)
    })();
    if copied.is_err() {
        let _ = fs::remove_file(&tmp);
        return copied;
    }
    sync_dir(&dir);
    Ok(())
}

/// Writes a new file at `path` (never through something already there:
/// an existing entry is an error) and flushes it.
pub fn write_new(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let mut file = fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path)?;
    file.write_all(bytes)?;
    file.sync_all()
}

/// Makes the renames and creations in `dir` durable (best effort: not
/// every file system lets a folder be flushed).
pub fn sync_dir(dir: &Path) {
    if let Ok(d) = fs::File::open(dir) {
        let _ = d.sync_all();
    }
}

/// The file `path` finally names once every symbolic link on the way is
/// followed (the last target need not exist yet).
fn resolve_links(path: &Path) -> io::Result<PathBuf> {
    let mut current = path.to_path_buf();
    // Linux's own limit on links followed while resolving one path.
    for _ in 0..40 {
        match fs::symlink_metadata(&current) {
            Ok(m) if m.file_type().is_symlink() => {
                let next = fs::read_link(&current)?;
                current = match current.parent() {
                    Some(dir) if next.is_relative() => dir.join(next),
                    _ => next,
                };
            }
            _ => return Ok(current),
        }
    }
    Err(io::Error::other("too many levels of symbolic links"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(unix)]
    #[test]
    fn replace_atomic_replaces_a_link_and_leaves_its_target() {
        let dir = tempfile::tempdir().unwrap();
        let outside = dir.path().join("outside.txt");
        fs::write(&outside, b"keep me").unwrap();
        let path = dir.path().join("en.toml");
        std::os::unix::fs::symlink(&outside, &path).unwrap();
        replace_atomic(&path, b"restored", Durability::Synced).unwrap();
        assert!(
            !fs::symlink_metadata(&path)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(fs::read(&path).unwrap(), b"restored");
        assert_eq!(fs::read(&outside).unwrap(), b"keep me");
        // A FIFO in its place is replaced too, without opening it.
        fs::remove_file(&path).unwrap();
        nix::unistd::mkfifo(&path, nix::sys::stat::Mode::S_IRWXU).unwrap();
        replace_atomic(&path, b"again", Durability::Synced).unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"again");
    }

    #[test]
    fn a_file_is_replaced_whole_and_no_temporary_is_left() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sub/a.txt");
        write_atomic(&path, b"one", Durability::Synced).unwrap();
        write_atomic(&path, b"two", Durability::Whole).unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"two");
        let names: Vec<_> = fs::read_dir(dir.path().join("sub"))
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["a.txt"]);
    }

    #[cfg(unix)]
    #[test]
    fn a_link_is_written_through() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.toml");
        fs::write(&real, "old").unwrap();
        let link = dir.path().join("link.toml");
        std::os::unix::fs::symlink("real.toml", &link).unwrap();
        write_atomic(&link, b"new", Durability::Synced).unwrap();
        assert!(
            fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(fs::read(&real).unwrap(), b"new");
    }

    #[test]
    fn write_new_never_replaces() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a");
        write_new(&path, b"x").unwrap();
        assert_eq!(
            write_new(&path, b"y").unwrap_err().kind(),
            io::ErrorKind::AlreadyExists
        );
        assert_eq!(fs::read(&path).unwrap(), b"x");
    }
}
