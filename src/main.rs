use std::process::ExitCode;

use clap::Parser;
use flipcard::cli::{Cli, Command};

fn main() -> ExitCode {
    let cli = Cli::parse();
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
