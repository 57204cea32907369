//! `flipcard decks`, `flipcard decks add PATH`, `flipcard decks remove ID`:
//! the deck library. Adding copies a deck that passes `check` into
//! `<data dir>/decks/` (content into `<data dir>/content/<id>/`); removing
//! deletes those files only, so the deck's review history stays in the log
//! (as orphans) and comes back with the deck.

use std::fs;
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
        rows.push([
            id,
            lib.source_of(f).origin.name().to_string(),
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
    if fs::symlink_metadata(path).is_err() {
        bail!("{}: no such file or directory", path.display());
    }
    let checked = load_paths(&[deck_files_in(path)]);
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
        install(&data, deck).with_context(|| format!("cannot add deck `{}`", deck.id))?;
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

/// Copies a deck file and its content files into the library: everything
/// is written under a staging folder in the data dir first, then renamed
/// into place (content first, the deck file last), so an interrupted add
/// leaves either the old deck or the new one.
fn install(data: &Path, deck: &Deck) -> anyhow::Result<()> {
    let decks_dir = library::library_dir(data);
    let content_root = data.join("content");
    fs::create_dir_all(&decks_dir)?;
    fs::create_dir_all(&content_root)?;
    let staging = data.join(format!(".decks-add-{}", std::process::id()));
    if staging.exists() {
        fs::remove_dir_all(&staging)?;
    }
    let staged_content = staging.join("content");
    fs::create_dir_all(&staged_content)?;
    let source_content = content_dir(&deck.path, &deck.id);
    for lang in &deck.languages {
        let from = source_content.join(format!("{lang}.toml"));
        copy_synced(&from, &staged_content.join(format!("{lang}.toml")))?;
    }
    let staged_deck = staging.join("deck.toml");
    copy_synced(&deck.path, &staged_deck)?;

    let content = content_root.join(&deck.id);
    let old = staging.join("old-content");
    if content.exists() {
        fs::rename(&content, &old)?;
    }
    fs::rename(&staged_content, &content)?;
    fs::rename(&staged_deck, decks_dir.join(format!("{}.toml", deck.id)))?;
    sync_dir(&decks_dir);
    sync_dir(&content_root);
    fs::remove_dir_all(&staging)?;
    Ok(())
}

fn copy_synced(from: &Path, to: &Path) -> anyhow::Result<()> {
    let bytes = fs::read(from).with_context(|| format!("cannot read {}", from.display()))?;
    let mut file = fs::File::create(to)?;
    std::io::Write::write_all(&mut file, &bytes)?;
    file.sync_all()?;
    Ok(())
}

/// Makes a rename in `dir` durable (best effort: not every file system
/// lets a folder be synced).
fn sync_dir(dir: &Path) {
    if let Ok(d) = fs::File::open(dir) {
        let _ = d.sync_all();
    }
}

fn remove(cli: &Cli, id: &str) -> anyhow::Result<ExitCode> {
    let data = paths::data_dir(cli.data_dir.clone())?;
    let lib = library::load(cli);
    let deck_file = library::library_dir(&data).join(format!("{id}.toml"));
    if fs::symlink_metadata(&deck_file).is_err() {
        if let Some((f, _)) = lib.files.iter().find_map(|f| {
            let d = &lib.loaded.decks[f.deck?];
            (d.id == id).then_some((f, d))
        }) {
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
    // The deck file goes first: without it the deck is gone, whatever
    // happens to its content files next.
    fs::remove_file(&deck_file)
        .with_context(|| format!("cannot remove {}", deck_file.display()))?;
    sync_dir(&library::library_dir(&data));
    let content = data.join("content").join(id);
    if content.exists() {
        fs::remove_dir_all(&content)
            .with_context(|| format!("cannot remove {}", content.display()))?;
    }
    crate::outln!(
        "removed {id} from the library; its review history is kept and comes back if the deck returns"
    )?;
    Ok(ExitCode::SUCCESS)
}
