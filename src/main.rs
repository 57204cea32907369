use std::process::ExitCode;

use clap::Parser;
use clap::error::ErrorKind;
use flipcard::cli::{Cli, Command};

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(err) => return usage_error(err),
    };
    let result = match &cli.command {
        None => flipcard::tui::run(&cli, None),
        Some(Command::Review(args)) => flipcard::tui::run(&cli, Some(args)),
        Some(Command::Check(args)) => flipcard::deck::check::run(&cli, args),
        Some(Command::Sim(args)) => flipcard::sim::cli::run(&cli, args),
        Some(Command::Bench(args)) => flipcard::sim::bench::run(&cli, args),
        Some(Command::Stats(args)) => flipcard::store::cli::stats(&cli, args),
        Some(Command::Export(args)) => flipcard::store::cli::export(&cli, args),
        Some(Command::Import(args)) => flipcard::store::cli::import(&cli, args),
        Some(Command::Db(args)) => flipcard::store::cli::db(&cli, args),
    };
    match result {
        Ok(code) => code,
        Err(err) => {
            eprintln!("flipcard: error: {err:#}");
            ExitCode::FAILURE
        }
    }
}

/// Help and version print as clap does; a malformed command line is invalid
/// input like any other: one line on stderr, exit status 1.
fn usage_error(err: clap::Error) -> ExitCode {
    match err.kind() {
        ErrorKind::DisplayHelp
        | ErrorKind::DisplayVersion
        | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => err.exit(),
        _ => {
            let text = err.render().to_string();
            let line = text
                .lines()
                .map(str::trim)
                .filter(|l| !l.is_empty() && !l.starts_with("For more information"))
                .map(|l| l.strip_prefix("error: ").unwrap_or(l))
                .collect::<Vec<_>>()
                .join("; ");
            eprintln!("flipcard: error: {line}");
            ExitCode::FAILURE
        }
    }
}
