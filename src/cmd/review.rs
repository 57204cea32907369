//! `flipcard` and `flipcard review [DECK] [--cram]`: the terminal app.
//! Everything that can fail with a message (the clock, the config, the
//! store, the decks) is opened here, before the terminal switches to raw
//! mode, so errors print as ordinary lines.

use std::process::ExitCode;

use crate::catalog::{Filter, parse_span};
use crate::cmd::args::{Cli, ReviewArgs};
use crate::cmd::paths;
use crate::sched::Config;
use crate::store::Store;
use crate::sync::Wait;
use crate::tui::Tui;
use crate::tui::app::DeckLoad;
use crate::tui::services::{DayZone, Services};
use crate::tui::theme::Theme;

pub fn run(cli: &Cli, review: Option<&ReviewArgs>) -> anyhow::Result<ExitCode> {
    let clock = crate::cmd::clock::from_env()?;
    let config_path = paths::config_file(cli.config.clone());
    let config = Config::load(config_path.as_deref())?;
    let data_dir = paths::data_dir(cli.data_dir.clone())?;
    // `sync_dir`: the other machines' reviews come in before the app
    // opens, after each review session, and when it closes.
    let sync_dir = config.sync_dir.clone();
    if let Some(dir) = &sync_dir {
        auto_sync(&data_dir, dir, &config);
    }
    let options = crate::store::OpenOptions {
        clock,
        ..crate::store::OpenOptions::default()
    };
    let store = Store::open_with(&data_dir, &options)?;
    let sources = crate::cmd::library::sources(cli, &config);
    let cache = crate::cmd::library::deck_cache(&data_dir);
    let mut library = crate::cmd::library::load_cached(sources, cache.as_ref());
    if config.hide_bundled {
        library.hide_bundled();
    }
    let failed = library.failed();
    let deck_load = DeckLoad {
        from: None,
        errors: library.loaded.errors(),
        failed_files: failed.len(),
        failed: failed
            .iter()
            .map(|f| f.path.display().to_string())
            .collect(),
    };
    let edit_library = crate::cmd::library::EditLibrary::new(data_dir.clone(), &library);
    let loaded = library.loaded;
    let lang = config.language.clone();
    let mut services = Services::new(clock, config, config_path, DayZone::Local, store);
    services.bench_csv = paths::bench_csv();
    services.editor = Box::new(editor_from_env());
    services.library = Some(Box::new(edit_library));
    if let Some(dir) = sync_dir.clone() {
        services.sync_through(data_dir.clone(), dir);
    }
    let mut app = Tui::new(loaded.decks, services, &lang, Theme::from_env());
    app.deck_load = deck_load;
    if let Some(args) = review {
        let filter = review_filter(args)?;
        if filter.is_empty() {
            crate::tui::open_review(&mut app, args.deck.as_deref(), args.cram)?;
        } else {
            crate::tui::open_filtered_review(&mut app, args.deck.as_deref(), &filter, args.cram)?;
        }
    }
    let ran = crate::tui::run(&mut app);
    let config = app.services.study.config.clone();
    // A sync still running in the background ends before the last one
    // (the data folder's lock makes the last one wait for it).
    drop(app);
    if let Some(dir) = &sync_dir {
        auto_sync(&data_dir, dir, &config);
    }
    ran?;
    Ok(ExitCode::SUCCESS)
}

/// The editor `E` and `A` open: `$VISUAL`, else `$EDITOR`, else `vi`
/// (an empty or blank variable counts as unset), split on whitespace.
fn editor_from_env() -> crate::tui::services::Spawn {
    let set = |name: &str| std::env::var(name).ok().filter(|v| !v.trim().is_empty());
    crate::tui::services::Spawn::from_setting(
        &set("VISUAL").or_else(|| set("EDITOR")).unwrap_or_default(),
    )
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

/// A sync the config asks for: a failure is a warning, never a reason to
/// keep the learner from studying.
fn auto_sync(data_dir: &std::path::Path, dir: &std::path::Path, config: &Config) {
    let done = crate::cmd::clock::now()
        .map_err(anyhow::Error::from)
        .and_then(|now| {
            crate::sync::sync_with(data_dir, dir, config, now, Wait::Up(AUTO_SYNC_WAIT))
                .map_err(anyhow::Error::from)
        });
    match done {
        Ok(outcome) => {
            for w in &outcome.warnings {
                crate::errln!("flipcard: warning: {w}");
            }
        }
        Err(e) => crate::errln!(
            "flipcard: warning: sync through {} failed: {}",
            dir.display(),
            crate::cmd::output::chain_text(&e)
        ),
    }
}

/// How long the app's sync waits for another sync of the same data folder
/// (a background one still running when the app closes).
const AUTO_SYNC_WAIT: std::time::Duration = std::time::Duration::from_secs(60);
