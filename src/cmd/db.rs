//! `flipcard db rebuild` and `flipcard db restore [BACKUP] [--force]`.

use std::process::ExitCode;

use crate::cmd::args::{Cli, DbArgs, DbCommand};
use crate::cmd::common::open_store;
use crate::cmd::paths;
use crate::text::plural;

pub fn run(cli: &Cli, args: &DbArgs) -> anyhow::Result<ExitCode> {
    match &args.command {
        DbCommand::Restore(restore) => {
            let clock = crate::cmd::clock::from_env()?;
            let dir = paths::data_dir(cli.data_dir.clone())?;
            let done = crate::store::restore::restore(
                &dir,
                restore.backup.as_deref(),
                restore.force,
                clock,
            )?;
            crate::outln!(
                "restored {} ({}) as {}",
                done.backup.display(),
                plural(done.reviews, "review", "reviews"),
                done.database.display()
            )?;
            for p in &done.set_aside {
                crate::outln!("set aside: {}", p.display())?;
            }
            Ok(ExitCode::SUCCESS)
        }
        DbCommand::Rebuild => {
            let mut store = open_store(cli)?;
            let report = store.rebuild()?;
            crate::outln!(
                "rebuilt {} from {} in {}; {} differed from the cache",
                plural(report.items, "card state", "card states"),
                plural(report.reviews, "log row", "log rows"),
                store.path().display(),
                report.changed
            )?;
            if report.tallies_changed {
                crate::outln!("the answer tallies did not match the log and were recomputed")?;
            }
            if report.statuses_changed {
                crate::outln!(
                    "the suspended, buried and leech marks did not match the status log and were recomputed"
                )?;
            }
            Ok(ExitCode::SUCCESS)
        }
    }
}
