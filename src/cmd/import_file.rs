//! Reading a file someone else wrote for an import (a CSV of cards, a
//! review log, a class's exports for the report): a regular file within a
//! size, what is wrong with it said in words, and its bad rows named up to
//! a screenful. The import commands share this, so it sits below them.

use std::io::Read;
use std::path::Path;

use crate::text::plural;

/// How many bad rows are named before the rest are only counted (a file of
/// garbage gives a screenful, not one line per row).
pub const MAX_ROW_ERRORS: usize = 20;

/// Reads a file someone else wrote: a regular file (a FIFO is refused
/// without waiting, a folder named as such), at most `max` bytes (a larger
/// one is refused before its rows are read, and one that grows while read
/// is caught too). What is wrong with the path instead of a file, or with
/// its size, is an error of kind `Other` whose text says it.
pub fn read_limited(path: &Path, max: u64) -> std::io::Result<Vec<u8>> {
    let too_large = || {
        std::io::Error::other(format!(
            "it is larger than {} MiB, the most flipcard reads from a file like this",
            max >> 20
        ))
    };
    let file = crate::deck::files::open_regular(path)?;
    if file.metadata()?.len() > max {
        return Err(too_large());
    }
    let mut bytes = Vec::new();
    file.take(max + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max {
        return Err(too_large());
    }
    Ok(bytes)
}

/// Why a file could not be read, in words: what the path is instead of a
/// file, or the system's reason.
pub fn cannot_read(e: &std::io::Error) -> String {
    use std::io::ErrorKind;
    match e.kind() {
        ErrorKind::Other => e.to_string(),
        ErrorKind::NotFound => "no such file or directory".to_string(),
        ErrorKind::PermissionDenied => "cannot be read: permission denied".to_string(),
        _ => format!("cannot be read: {e}"),
    }
}

/// `FILE:LINE: message` for the first [`MAX_ROW_ERRORS`] bad rows, then
/// how many more there are.
pub fn print_bad_rows<'a>(file: &Path, errors: impl ExactSizeIterator<Item = (u64, &'a str)>) {
    let n = errors.len();
    for (line, message) in errors.take(MAX_ROW_ERRORS) {
        crate::errln!("{}:{line}: {message}", file.display());
    }
    if n > MAX_ROW_ERRORS {
        crate::errln!(
            "{}: … and {}",
            file.display(),
            plural(n - MAX_ROW_ERRORS, "more bad row", "more bad rows")
        );
    }
}
