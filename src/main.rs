use std::process::ExitCode;

use clap::error::ErrorKind;
use clap::{CommandFactory, Parser};
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

/// Help and version print as clap does. A malformed command line is one line
/// on stderr and exit status 2 (the usage-error status scripts expect from
/// `check`), except for `sim`, whose contract treats every invalid input
/// alike: exit status 1.
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
            if subcommand_given().as_deref() == Some("sim") {
                ExitCode::FAILURE
            } else {
                ExitCode::from(2)
            }
        }
    }
}

/// The subcommand named on the command line, found without clap (which has
/// just refused the line).
fn subcommand_given() -> Option<String> {
    let names: Vec<String> = Cli::command()
        .get_subcommands()
        .map(|c| c.get_name().to_string())
        .collect();
    std::env::args().skip(1).find(|a| names.contains(a))
}
