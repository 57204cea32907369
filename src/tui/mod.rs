//! The terminal app. Owns view state only.

use std::process::ExitCode;

use crate::cli::{Cli, ReviewArgs};

pub fn run(_cli: &Cli, _review: Option<&ReviewArgs>) -> anyhow::Result<ExitCode> {
    anyhow::bail!("tui: not built yet")
}
