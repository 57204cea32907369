//! `flipcard sync [DIR]`.

use std::process::ExitCode;

use crate::cmd::args::{Cli, SyncArgs};

pub fn run(_cli: &Cli, _args: &SyncArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("sync: not built yet")
}
