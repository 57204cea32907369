//! `flipcard check`.

use std::process::ExitCode;

use crate::cli::{CheckArgs, Cli};

pub fn run(_cli: &Cli, _args: &CheckArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("check: not built yet")
}
