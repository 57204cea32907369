//! `flipcard decks`, `flipcard decks add PATH`, `flipcard decks remove ID`:
//! the deck library. Adding copies a deck that passes `check` (its
//! validation and its simulations: every prompt's answer against its
//! scene's run, rigid or system, as `check` judges it) into
//! `<data dir>/decks/` (content into `<data dir>/content/<id>/`); removing
//! deletes those files only, so the deck's review history stays in the log
//! (as orphans) and comes back with the deck. Both take a deck id only and
//! touch nothing outside those two folders; the moves themselves, and their
//! recovery after a kill, are `cmd::library`'s.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, bail};

use crate::cmd::args::{Cli, DecksArgs, DecksCommand};
use crate::cmd::library::{self, Origin};
use crate::cmd::paths;
use crate::deck::{Deck, content_dir, load_paths};
use crate::text::plural;

pub fn run(cli: &Cli, args: &DecksArgs) -> anyhow::Result<ExitCode> {
    match &args.command {
        None => list(cli),
        Some(DecksCommand::Add(a)) => add(cli, &a.path),
        Some(DecksCommand::Remove(r)) => remove(cli, &r.id),
    }
}

fn counts(deck: &Deck) -> String {
    format!(
        "{}, {}, {}, {}",
        plural(deck.cards.len(), "card", "cards"),
        plural(deck.prompts.len(), "prompt", "prompts"),
        plural(deck.scenes.len() + deck.systems.len(), "scene", "scenes"),
        plural(deck.sections.len(), "section", "sections"),
    )
}

/// One row per deck file of every source: id, source, file, counts and
/// `check` status, in aligned columns.
fn list(cli: &Cli) -> anyhow::Result<ExitCode> {
    let lib = library::load(cli);
    // `hide_bundled`: the bundled decks are listed, marked as off home.
    let hidden = crate::sched::Config::load(paths::config_file(cli.config.clone()).as_deref())
        .is_ok_and(|c| c.hide_bundled);
    let mut rows: Vec<[String; 5]> = vec![[
        "DECK".into(),
        "SOURCE".into(),
        "FILE".into(),
        "CONTENTS".into(),
        "CHECK".into(),
    ]];
    for f in &lib.files {
        let deck = f.deck.map(|i| &lib.loaded.decks[i]);
        let id = deck.map_or_else(
            || {
                f.path
                    .file_stem()
                    .map_or_else(String::new, |s| s.to_string_lossy().into_owned())
            },
            |d| d.id.clone(),
        );
        let status = if f.errors > 0 {
            format!(
                "{}: run `flipcard check {}`",
                plural(f.errors, "error", "errors"),
                f.path.display()
            )
        } else if f.warnings > 0 {
            format!("ok, {}", plural(f.warnings, "warning", "warnings"))
        } else {
            "ok".to_string()
        };
        let origin = lib.source_of(f).origin;
        rows.push([
            id,
            if hidden && origin == Origin::Bundled {
                format!("{} (hidden)", origin.name())
            } else {
                origin.name().to_string()
            },
            f.path.display().to_string(),
            deck.map_or_else(|| "-".to_string(), counts),
            status,
        ]);
    }
    let mut widths = [0usize; 5];
    for row in &rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(unicode_width::UnicodeWidthStr::width(cell.as_str()));
        }
    }
    let mut out = String::new();
    for row in &rows {
        let mut line = String::new();
        for (i, cell) in row.iter().enumerate() {
            line.push_str(cell);
            if i + 1 < row.len() {
                let pad = widths[i] - unicode_width::UnicodeWidthStr::width(cell.as_str());
                line.push_str(&" ".repeat(pad + 2));
            }
        }
        out.push_str(line.trim_end());
        out.push('\n');
    }
    crate::out!("{out}")?;
    Ok(ExitCode::SUCCESS)
}

/// The deck files PATH names: a deck file, a folder of deck files, or a
/// folder holding `decks/` (with `content/` beside it).
fn deck_files_in(path: &Path) -> PathBuf {
    let inner = path.join("decks");
    if path.is_dir() && inner.is_dir() {
        inner
    } else {
        path.to_path_buf()
    }
}

fn add(cli: &Cli, path: &Path) -> anyhow::Result<ExitCode> {
    if !crate::io::exists_no_follow(path) {
        bail!("{}: no such file or directory", path.display());
    }
    let mut checked = load_paths(&[deck_files_in(path)]);
    if checked.errors() == 0 {
        // As `check` judges it: every prompt's answer against its scene's
        // run, and every system scene run to its end.
        let judged = crate::predict::audit::check_loaded(&checked);
        checked.diagnostics.extend(judged);
    }
    if checked.errors() > 0 || checked.decks.is_empty() {
        if !checked.diagnostics.is_empty() {
            crate::errln!("{}", checked.render_all());
        }
        crate::errln!(
            "flipcard: error: {} does not pass `check` ({}); nothing added",
            path.display(),
            if checked.decks.is_empty() && checked.errors() == 0 {
                "no deck files".to_string()
            } else {
                plural(checked.errors(), "error", "errors")
            }
        );
        return Ok(ExitCode::FAILURE);
    }
    let data = paths::data_dir(cli.data_dir.clone())?;
    // An unfinished change first (its error, if any, once and alone).
    if let Err(e) = library::recover(&data) {
        bail!("{}; nothing added", crate::cmd::output::chain_text(&e));
    }
    // A deck id may live in one source only; the library's own copy is
    // the one being replaced.
    let lib = library::load(cli);
    for deck in &checked.decks {
        for f in &lib.files {
            let Some(i) = f.deck else { continue };
            let other = &lib.loaded.decks[i];
            if other.id == deck.id && lib.source_of(f).origin != Origin::Library {
                bail!(
                    "deck id `{}` of {} is also used by {} ({}); nothing added",
                    deck.id,
                    deck.path.display(),
                    other.path.display(),
                    lib.source_of(f).origin.name()
                );
            }
        }
    }
    for deck in &checked.decks {
        if let Err(e) = library::check_id(&deck.id) {
            bail!("{}: {e}; nothing added", deck.path.display());
        }
    }
    for deck in &checked.decks {
        let new = read_deck(deck).with_context(|| format!("cannot add deck `{}`", deck.id))?;
        library::install(&data, &new).with_context(|| format!("cannot add deck `{}`", deck.id))?;
        crate::outln!(
            "added {} ({}) to the library: {}",
            deck.id,
            counts(deck),
            library::library_dir(&data)
                .join(format!("{}.toml", deck.id))
                .display()
        )?;
    }
    Ok(ExitCode::SUCCESS)
}

/// The bytes of a checked deck's file and content files, read without
/// waiting on anything that is not a regular file.
fn read_deck(deck: &Deck) -> anyhow::Result<library::NewDeck> {
    let read = |path: &Path| {
        crate::deck::files::read_regular(path)
            .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
    };
    let source_content = content_dir(&deck.path, &deck.id);
    let mut content = Vec::new();
    for lang in &deck.languages {
        let bytes = read(&source_content.join(format!("{lang}.toml")))?;
        content.push((lang.clone(), bytes));
    }
    Ok(library::NewDeck {
        id: deck.id.clone(),
        file: read(&deck.path)?,
        content,
    })
}

fn remove(cli: &Cli, id: &str) -> anyhow::Result<ExitCode> {
    if let Err(e) = library::check_id(id) {
        bail!("{e}; nothing removed");
    }
    let data = paths::data_dir(cli.data_dir.clone())?;
    if let Err(e) = library::recover(&data) {
        bail!("{}; nothing removed", crate::cmd::output::chain_text(&e));
    }
    match library::uninstall(&data, id) {
        Ok(()) => {}
        Err(library::RemoveError::Other(e)) => return Err(e),
        Err(library::RemoveError::NotInLibrary) => {
            let lib = library::load(cli);
            if let Some(f) = lib
                .files
                .iter()
                .find(|f| f.deck.is_some_and(|i| lib.loaded.decks[i].id == id))
            {
                bail!(
                    "deck `{id}` is not in the library but in {} ({}); only library decks can be removed",
                    f.path.display(),
                    lib.source_of(f).origin.name()
                );
            }
            let in_library: Vec<String> = lib
                .files
                .iter()
                .filter(|f| lib.source_of(f).origin == Origin::Library)
                .filter_map(|f| f.path.file_stem().map(|s| s.to_string_lossy().into_owned()))
                .collect();
            bail!(
                "no deck `{id}` in the library; library decks: {}",
                if in_library.is_empty() {
                    "none".to_string()
                } else {
                    in_library.join(", ")
                }
            );
        }
    }
    crate::outln!(
        "removed {id} from the library; its review history is kept and comes back if the deck returns"
    )?;
    Ok(ExitCode::SUCCESS)
}
