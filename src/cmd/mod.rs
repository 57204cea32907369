//! One module per subcommand: each turns its arguments into calls of the
//! domain modules and prints the results. Only here (and in the terminal
//! app) does anything print or know about the command line.

pub mod args;
pub mod bench;
pub mod cards;
pub mod check;
pub mod clock;
mod common;
pub mod db;
pub mod decks;
pub mod export;
pub mod grade;
pub mod import;
pub mod import_anki;
pub mod import_file;
pub mod import_reviews;
pub mod library;
pub mod optimize;
pub mod output;
pub mod paths;
pub mod plan;
pub mod report;
pub mod review;
pub mod schema;
pub mod sim;
pub mod sim_samples;
pub mod sim_scene;
pub mod sim_system;
pub mod sim_variant;
pub mod stats;
pub mod sync;

use std::process::ExitCode;

use clap::CommandFactory;
use clap::error::ErrorKind;

use crate::errln;
use args::{Cli, Command};
use output::StdoutStatus;

/// Runs the command the line asks for and turns its outcome into the exit
/// status, reporting a failure in one line.
pub fn run(cli: &Cli) -> ExitCode {
    let result = match &cli.command {
        None => review::run(cli, None),
        Some(Command::Review(args)) => review::run(cli, Some(args)),
        Some(Command::Check(args)) => check::run(cli, args),
        Some(Command::Sim(args)) => sim::run(cli, args),
        Some(Command::Bench(args)) => bench::run(cli, args),
        Some(Command::Grade(args)) => grade::run(cli, args),
        Some(Command::Stats(args)) => stats::run(cli, args),
        Some(Command::Export(args)) => export::run(cli, args),
        Some(Command::Import(args)) => import::run(cli, args),
        Some(Command::Db(args)) => db::run(cli, args),
        Some(Command::Optimize(args)) => optimize::run(cli, args),
        Some(Command::Plan(args)) => plan::run(cli, args),
        Some(Command::Cards(args)) => cards::run(cli, args),
        Some(Command::Schema(args)) => schema::run(cli, args),
        Some(Command::Decks(args)) => decks::run(cli, args),
        Some(Command::Report(args)) => report::run(cli, args),
        Some(Command::Sync(args)) => sync::run(cli, args),
    };
    // A failed write to stdout comes first: whatever error the handler
    // returned is then only its consequence.
    match output::stdout_status() {
        // The reader has all it wanted (`| head`): a normal end, unless the
        // command finished and gave its own verdict.
        StdoutStatus::Closed => result.unwrap_or(ExitCode::SUCCESS),
        StdoutStatus::Failed(why) => {
            errln!("flipcard: error: cannot write to standard output: {why}");
            ExitCode::FAILURE
        }
        StdoutStatus::Written => match result {
            Ok(code) => code,
            Err(err) => {
                errln!("flipcard: error: {}", output::chain_text(&err));
                ExitCode::FAILURE
            }
        },
    }
}

/// Help and version print as clap does. A malformed command line is one line
/// on stderr and exit status 2 (the usage-error status scripts expect from
/// `check`), except for `sim`, whose contract treats every invalid input
/// alike: exit status 1.
pub fn usage_error(err: clap::Error) -> ExitCode {
    match err.kind() {
        ErrorKind::DisplayHelp
        | ErrorKind::DisplayVersion
        | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => print_help(&err),
        _ => {
            let text = err.render().to_string();
            let mut line = String::new();
            for part in text
                .lines()
                .map(str::trim)
                .filter(|l| !l.is_empty() && !l.starts_with("For more information"))
                .map(|l| l.strip_prefix("error: ").unwrap_or(l))
            {
                // "not provided:" introduces the next line; it ends nothing.
                if line.ends_with(':') {
                    line.push(' ');
                } else if !line.is_empty() {
                    line.push_str("; ");
                }
                line.push_str(part);
            }
            errln!("flipcard: error: {line}");
            if subcommand_given().as_deref() == Some("sim") {
                ExitCode::FAILURE
            } else {
                ExitCode::from(2)
            }
        }
    }
}

/// Help or version text, through clap (which colours it for a terminal)
/// but with the outcome of the write checked: `clap::Error::exit` ignores
/// it, so help sent to a full disk would vanish with exit status 0.
fn print_help(err: &clap::Error) -> ExitCode {
    let printed = err.print();
    let code = ExitCode::from(u8::try_from(err.exit_code()).unwrap_or(1));
    if err.use_stderr() {
        return code;
    }
    match printed.map(|()| output::stdout_status()) {
        Ok(StdoutStatus::Written) => code,
        Ok(StdoutStatus::Closed) => ExitCode::SUCCESS,
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
        Ok(StdoutStatus::Failed(why)) => {
            errln!("flipcard: error: cannot write to standard output: {why}");
            ExitCode::FAILURE
        }
        Err(e) => {
            errln!("flipcard: error: cannot write to standard output: {e}");
            ExitCode::FAILURE
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
