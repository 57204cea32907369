//! `flipcard check [PATH...]`: validate decks, print every diagnostic to
//! stderr, and a one-line summary. Unless `--no-simulate`, every prompt's
//! answer is judged against its scene's run, rigid body or system alike
//! (`predict::audit`: contradicted, two choices holding, a measure the run
//! cannot make, an answer that holds only because the run ends early), and
//! every system scene is run to its end as the app and `sim --scene` run
//! it: a scene that leaves its domain (a NaN, a division by zero) or takes
//! more work than a scene may is refused at the expression or value to
//! fix, and at each prompt on it, so that a deck that passes always plays.
//!
//! Exit codes: 0 when there is no error (warnings allowed), 1 when there is
//! any error, 2 for a usage error (a path that does not exist; clap exits 2
//! on bad flags itself).

use std::path::PathBuf;
use std::process::ExitCode;

use crate::cmd::args::{CheckArgs, Cli};
use crate::deck::load::{Loaded, load_paths};
use crate::text::plural;

pub fn run(cli: &Cli, args: &CheckArgs) -> anyhow::Result<ExitCode> {
    if args.paths.is_empty() {
        // Every deck source: what the app would open.
        return report(crate::cmd::library::load(cli).loaded, args.no_simulate);
    }
    let paths = args.paths.clone();
    // A dangling link is there; the loader says where it points.
    let missing: Vec<&PathBuf> = paths
        .iter()
        .filter(|p| !crate::io::exists_no_follow(p))
        .collect();
    if !missing.is_empty() {
        for p in missing {
            crate::errln!(
                "flipcard: error: {}: no such file or directory",
                p.display()
            );
        }
        return Ok(ExitCode::from(2));
    }
    for p in paths.iter().filter(|p| p.is_dir()) {
        let has_decks = crate::io::entries(p).is_ok_and(|entries| {
            entries
                .iter()
                .any(|e| e.extension().is_some_and(|x| x == "toml"))
        });
        if !has_decks {
            crate::errln!(
                "flipcard: warning: no deck files (*.toml) in {}",
                p.display()
            );
        }
    }
    report(load_paths(&paths), args.no_simulate)
}

/// Every diagnostic on stderr (with each prompt's answer judged against its
/// scene's run unless `no_simulate`), then the summary or the error count.
fn report(mut loaded: Loaded, no_simulate: bool) -> anyhow::Result<ExitCode> {
    if !no_simulate {
        // Each prompt's answer against its scene's run, where the author
        // looks: at the prompt's `expected` line; and each system scene
        // run to its end.
        let judged = crate::predict::audit::check_loaded(&loaded);
        loaded.diagnostics.extend(judged);
    }
    if !loaded.diagnostics.is_empty() {
        crate::errln!("{}", loaded.render_all());
    }
    let code = if loaded.errors() > 0 {
        crate::errln!(
            "{}, {}",
            plural(loaded.errors(), "error", "errors"),
            plural(loaded.warnings(), "warning", "warnings")
        );
        ExitCode::from(1)
    } else {
        crate::outln!("{}", summary(&loaded))?;
        ExitCode::SUCCESS
    };
    // The process ends here: freeing every card of a large deck one by
    // one would only delay the exit (a tenth of `check`'s time at 50,000
    // cards); the system takes the memory back at once.
    std::mem::forget(loaded);
    Ok(code)
}

/// `N decks, M cards, P prompts, S scenes, X sections: ok` (`1 deck`, `1
/// card`...), with `D derivations, ` before the sections when there are
/// any; a section counts once however many languages it is written in.
pub fn summary(loaded: &Loaded) -> String {
    let count = |f: fn(&crate::deck::Deck) -> usize| loaded.decks.iter().map(f).sum::<usize>();
    let derivations = count(|d| d.derivations.len());
    format!(
        "{}, {}, {}, {}, {}{}: ok",
        plural(loaded.decks.len(), "deck", "decks"),
        plural(count(|d| d.cards.len()), "card", "cards"),
        plural(count(|d| d.prompts.len()), "prompt", "prompts"),
        plural(
            count(|d| d.scenes.len() + d.systems.len()),
            "scene",
            "scenes"
        ),
        if derivations > 0 {
            format!("{}, ", plural(derivations, "derivation", "derivations"))
        } else {
            String::new()
        },
        plural(count(|d| d.sections.len()), "section", "sections"),
    )
}
