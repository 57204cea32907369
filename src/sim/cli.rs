//! `flipcard sim`.

use std::process::ExitCode;

use crate::cli::{Cli, SimArgs};

pub fn run(_cli: &Cli, _args: &SimArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("sim: not built yet")
}
