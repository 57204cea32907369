//! `flipcard import FILE.apkg|FILE.colpkg [--out DIR]`: an Anki collection
//! becomes a deck folder, and its review history joins the log.

use std::path::Path;
use std::process::ExitCode;

use crate::cmd::args::{Cli, ImportArgs};

/// Whether `file` is named as an Anki package.
pub fn is_anki_file(file: &Path) -> bool {
    file.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("apkg") || e.eq_ignore_ascii_case("colpkg"))
}

pub fn run(_cli: &Cli, args: &ImportArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("{}: Anki import is not available yet", args.file.display())
}
