//! The one door to the file system. Everything flipcard reads or writes on
//! disk goes through here (the architecture test refuses `std::fs`
//! elsewhere), so the disciplines hold on every path:
//!
//! - a file to read must be a regular file: opened without waiting on a
//!   FIFO, refused by what it is otherwise ([`probe`], [`open_regular`],
//!   [`read_regular`], bounded reads);
//! - a file is replaced whole: written under a temporary name beside it,
//!   flushed to disk, renamed over the old one, its folder flushed
//!   ([`write_atomic`], one fsync discipline for the config, backups,
//!   restore, the deck library, the report, sync and the machine id);
//! - a folder is listed for its visible files of a kind ([`visible_files`]);
//! - one process at a time where it matters ([`Lock`]).
//!
//! Paths go in; `std::io::Result`s come out, and callers add what the
//! path was for.

mod lock;
mod ops;
mod probe;
mod write;

pub use lock::{Lock, Wait};
pub use ops::*;
pub use probe::{
    Probe, cannot_read, open_regular, probe, read_regular, read_regular_limited, read_text,
};
pub use write::{Durability, copy_atomic, replace_atomic, sync_dir, write_atomic, write_new};

/// `bytes` for a message: "64 MiB", "512 KiB", "100 bytes".
pub fn size(bytes: u64) -> String {
    const UNITS: [(u64, &str); 3] = [(1 << 30, "GiB"), (1 << 20, "MiB"), (1 << 10, "KiB")];
    for (unit, name) in UNITS {
        if bytes >= unit && bytes.is_multiple_of(unit) {
            return format!("{} {name}", bytes / unit);
        }
    }
    format!("{bytes} bytes")
}
