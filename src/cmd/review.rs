//! `flipcard` and `flipcard review [DECK] [--cram]`: the terminal app.
//! Everything that can fail with a message (the clock, the config, the
//! store, the decks) is opened here, before the terminal switches to raw
//! mode, so errors print as ordinary lines.

use std::collections::HashSet;
use std::process::ExitCode;

use crate::cmd::args::{Cli, ReviewArgs};
use crate::cmd::paths;
use crate::sched::Config;
use crate::store::Store;
use crate::store::catalog::{Filter, parse_span};
use crate::tui::app::{App, DeckLoad};
use crate::tui::services::{Clock, DayZone, Services};
use crate::tui::theme::Theme;

pub fn run(cli: &Cli, review: Option<&ReviewArgs>) -> anyhow::Result<ExitCode> {
    let clock = Clock::from_env()?;
    let config_path = paths::config_file(cli.config.clone());
    let config = Config::load(config_path.as_deref())?;
    let data_dir = paths::data_dir(cli.data_dir.clone())?;
    let store = Store::open(&data_dir)?;
    let deck_dir = cli.decks.clone().unwrap_or_else(paths::bundled_decks);
    let loaded = crate::deck::load_dir(&deck_dir);
    let deck_load = DeckLoad {
        from: Some(deck_dir.clone()),
        errors: loaded.errors(),
        failed_files: loaded
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .map(|d| &d.path)
            .collect::<HashSet<_>>()
            .len(),
    };
    let lang = config.language.clone();
    let mut services = Services::new(clock, config, config_path, DayZone::Local, store);
    services.bench_csv = paths::bench_csv();
    let mut app = App::new(loaded.decks, services, &lang, Theme::from_env());
    app.deck_load = deck_load;
    if let Some(args) = review {
        let filter = review_filter(args)?;
        if filter.is_empty() {
            crate::tui::open_review(&mut app, args.deck.as_deref(), args.cram)?;
        } else {
            crate::tui::open_filtered_review(&mut app, args.deck.as_deref(), &filter, args.cram)?;
        }
    }
    crate::tui::run(&mut app)?;
    Ok(ExitCode::SUCCESS)
}

/// The filter `--tag`, `--state` and `--due-within` ask for (empty when
/// none is given).
fn review_filter(args: &ReviewArgs) -> anyhow::Result<Filter> {
    let mut filter = Filter {
        tags: args.tag.clone(),
        ..Filter::default()
    };
    for s in &args.state {
        filter.add_state(s)?;
    }
    if let Some(span) = &args.due_within {
        filter.due_within = Some(parse_span(span)?);
    }
    if !args.cram && filter.states.iter().any(|s| s == "suspended") {
        anyhow::bail!(
            "suspended cards are out of every queue: add --cram to look through them, or unsuspend them with `flipcard cards unsuspend`"
        );
    }
    Ok(filter)
}
