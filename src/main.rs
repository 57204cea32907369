use std::process::ExitCode;

use clap::Parser;
use flipcard::cmd::{self, args::Cli};

fn main() -> ExitCode {
    match Cli::try_parse() {
        Ok(cli) => cmd::run(&cli),
        Err(err) => cmd::usage_error(err),
    }
}
