//! `flipcard report FILES… [--deck ID] [--out DIR]`.

use std::process::ExitCode;

use crate::cmd::args::{Cli, ReportArgs};

pub fn run(_cli: &Cli, _args: &ReportArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("report: not built yet")
}
