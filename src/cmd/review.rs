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
        crate::tui::open_review(&mut app, args.deck.as_deref(), args.cram)?;
    }
    crate::tui::run(&mut app)?;
    Ok(ExitCode::SUCCESS)
}
