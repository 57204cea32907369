//! Headless commands over the store: stats, export, import, db.

use std::process::ExitCode;

use crate::cli::{Cli, DbArgs, ExportArgs, ImportArgs, StatsArgs};

pub fn stats(_cli: &Cli, _args: &StatsArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("stats: not built yet")
}
pub fn export(_cli: &Cli, _args: &ExportArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("export: not built yet")
}
pub fn import(_cli: &Cli, _args: &ImportArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("import: not built yet")
}
pub fn db(_cli: &Cli, _args: &DbArgs) -> anyhow::Result<ExitCode> {
    anyhow::bail!("db: not built yet")
}
