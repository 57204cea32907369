//! `flipcard sim`.

use std::process::ExitCode;

use crate::cli::{Cli, SimArgs};

pub fn run(cli: &Cli, args: &SimArgs) -> anyhow::Result<ExitCode> {
    if args.list {
        return super::scene_cli::list(cli, args);
    }
    if let Some(id) = &args.scene {
        return super::scene_cli::scene(cli, args, id);
    }
    anyhow::bail!("sim: not built yet")
}
