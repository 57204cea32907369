//! `flipcard bench`.

use std::process::ExitCode;

use crate::cli::{BenchArgs, Cli};

pub fn run(_cli: &Cli, _args: &BenchArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("bench: not built yet")
}
