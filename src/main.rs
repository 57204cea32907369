use std::process::ExitCode;

use clap::Parser;
use flipcard::cmd::{self, args::Cli};

/// mimalloc, not the system's malloc: a large collection's first frame
/// allocates about half a million small strings (a 50,000-card deck taken
/// from the deck cache), and glibc's malloc spent most of that time in its
/// slow path and in 20,000 page faults. With mimalloc the whole start took
/// half the CPU time (61 against 115 ms to the first frame, 400 page faults
/// against 20,000; README, "Large collections").
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> ExitCode {
    match Cli::try_parse() {
        Ok(cli) => cmd::run(&cli),
        Err(err) => cmd::usage_error(err),
    }
}
