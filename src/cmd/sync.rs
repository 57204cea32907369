//! `flipcard sync [DIR]` (and `sync_dir` in the config): one sync of this
//! machine's log through the folder (see `crate::sync` for what it does),
//! said in one line, with a warning line for each file or line left out.

use std::process::ExitCode;
use std::time::Duration;

use anyhow::bail;

use crate::cmd::args::{Cli, SyncArgs};
use crate::cmd::paths;
use crate::sched::Config;
use crate::sync::{SyncError, Wait};

/// How long the command waits for another sync of the same data folder.
const WAIT_FOR_OTHER_SYNC: Duration = Duration::from_secs(120);

pub fn run(cli: &Cli, args: &SyncArgs) -> anyhow::Result<ExitCode> {
    let now = crate::cmd::clock::now()?;
    let config = Config::load(paths::config_file(cli.config.clone()).as_deref())?;
    let Some(dir) = args.dir.clone().or_else(|| config.sync_dir.clone()) else {
        bail!(
            "say which folder to sync through: flipcard sync DIR, or sync_dir = \"…\" in the config"
        );
    };
    let data = paths::data_dir(cli.data_dir.clone())?;
    let outcome = match crate::sync::sync_with(&data, &dir, &config, now, Wait::No) {
        Err(SyncError::Busy(_)) => {
            crate::errln!(
                "flipcard: waiting for another sync of {} to end…",
                data.display()
            );
            crate::sync::sync_with(&data, &dir, &config, now, Wait::Up(WAIT_FOR_OTHER_SYNC))
        }
        other => other,
    }?;
    for w in &outcome.warnings {
        crate::errln!("flipcard: warning: {w}");
    }
    crate::outln!("{}", outcome.summary(&dir))?;
    Ok(ExitCode::SUCCESS)
}
