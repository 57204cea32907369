//! The other file operations flipcard needs, each named once here so that
//! no module outside `io` touches `std::fs` (the architecture test checks
//! it): folders, renames, removals, looking at what a path is.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

pub use std::fs::{File, Metadata};

/// Every entry directly in `dir`, in no particular order.
pub fn entries(dir: impl AsRef<Path>) -> io::Result<Vec<PathBuf>> {
    Ok(fs::read_dir(dir)?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .collect())
}

/// The files of `dir` whose names end with `.ext` and do not start with a
/// dot (temporary and editor files do), with their names, by name.
pub fn visible_files(dir: impl AsRef<Path>, ext: &str) -> io::Result<Vec<(PathBuf, String)>> {
    let suffix = format!(".{ext}");
    let dir = dir.as_ref();
    let mut files: Vec<(PathBuf, String)> = fs::read_dir(dir)?
        .filter_map(Result::ok)
        .filter_map(|e| {
            let name = e.file_name().to_str()?.to_string();
            (name.ends_with(&suffix) && !name.starts_with('.')).then(|| (e.path(), name))
        })
        .collect();
    files.sort_by(|a, b| a.1.cmp(&b.1));
    Ok(files)
}

/// The entries of `dir` whose names start with `prefix`.
pub fn entries_starting_with(dir: impl AsRef<Path>, prefix: &str) -> Vec<PathBuf> {
    fs::read_dir(dir)
        .map(|it| {
            it.filter_map(Result::ok)
                .filter(|e| e.file_name().to_string_lossy().starts_with(prefix))
                .map(|e| e.path())
                .collect()
        })
        .unwrap_or_default()
}

/// One name for a file however it was reached (links, `..`), or the path
/// as given when it cannot be resolved.
pub fn canonical(path: impl AsRef<Path>) -> PathBuf {
    let path = path.as_ref();
    fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf())
}

/// What is at `path` itself (a link is not followed).
pub fn metadata_no_follow(path: impl AsRef<Path>) -> io::Result<Metadata> {
    fs::symlink_metadata(path)
}

/// What `path` names, following links.
pub fn metadata(path: impl AsRef<Path>) -> io::Result<Metadata> {
    fs::metadata(path)
}

/// Whether anything (even a link to nothing) is at `path`.
pub fn exists_no_follow(path: impl AsRef<Path>) -> bool {
    fs::symlink_metadata(path).is_ok()
}

/// Where the link at `path` points.
pub fn read_link(path: impl AsRef<Path>) -> io::Result<PathBuf> {
    fs::read_link(path)
}

pub fn create_dir(path: impl AsRef<Path>) -> io::Result<()> {
    fs::create_dir(path)
}

pub fn create_dir_all(path: impl AsRef<Path>) -> io::Result<()> {
    fs::create_dir_all(path)
}

/// Renames `from` to `to` (replacing a file at `to`); see
/// [`sync_dir`](super::sync_dir) to make it durable.
pub fn rename(from: impl AsRef<Path>, to: impl AsRef<Path>) -> io::Result<()> {
    fs::rename(from, to)
}

/// A second name for the file at `from` (fails if `to` exists: the
/// first of two racing creators wins).
pub fn hard_link(from: impl AsRef<Path>, to: impl AsRef<Path>) -> io::Result<()> {
    fs::hard_link(from, to)
}

pub fn remove_file(path: impl AsRef<Path>) -> io::Result<()> {
    fs::remove_file(path)
}

pub fn remove_dir(path: impl AsRef<Path>) -> io::Result<()> {
    fs::remove_dir(path)
}

/// Removes a folder and everything in it; a symbolic link inside is
/// removed, never followed.
pub fn remove_tree(path: impl AsRef<Path>) -> io::Result<()> {
    fs::remove_dir_all(path)
}

/// Opens `path` for reading as it is (for a database copy or a package the
/// caller checks itself; files to parse go through
/// [`open_regular`](super::open_regular)).
pub fn open(path: impl AsRef<Path>) -> io::Result<File> {
    File::open(path)
}

/// Creates (or truncates) `path` for writing, for a copy the caller
/// flushes and renames into place.
pub fn create(path: impl AsRef<Path>) -> io::Result<File> {
    File::create(path)
}

/// A file made new at `path` (an existing entry is an error), opened with
/// `flags` on Unix (e.g. `O_NOFOLLOW`).
pub fn create_new(path: impl AsRef<Path>) -> io::Result<File> {
    fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path)
}

/// Opens `path` to append, creating it.
pub fn append(path: impl AsRef<Path>) -> io::Result<File> {
    fs::OpenOptions::new().append(true).create(true).open(path)
}

/// The bytes still free for an unprivileged writer on the disk holding
/// `path`, when the system says.
pub fn space_left(path: impl AsRef<Path>) -> Option<u64> {
    rustix::fs::statvfs(path.as_ref())
        .ok()
        .map(|s| s.f_bavail.saturating_mul(s.f_frsize))
}

/// What kind of file `meta` describes, for messages about a path that is
/// not the regular file it should be.
pub fn file_kind(meta: &Metadata) -> &'static str {
    use std::os::unix::fs::FileTypeExt as _;
    let t = meta.file_type();
    if t.is_dir() {
        "a directory"
    } else if t.is_fifo() {
        "a FIFO (named pipe)"
    } else if t.is_socket() {
        "a socket"
    } else if t.is_block_device() || t.is_char_device() {
        "a device"
    } else if t.is_symlink() {
        "a symbolic link"
    } else if t.is_file() {
        "a regular file"
    } else {
        "not a regular file"
    }
}
