//! `flipcard import FILE.apkg|FILE.colpkg [--out DIR]`: an Anki collection
//! becomes a deck folder (`DIR/decks/<id>.toml` and an empty
//! `DIR/content/<id>/en.toml` per Anki deck), and its review history joins
//! the log, replayed through FSRS so the intervals continue.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context as _;

use crate::cmd::args::{Cli, ImportArgs};
use crate::cmd::common::open_store;
use crate::cmd::paths;
use crate::interop::anki::{AnkiImport, read_package};
use crate::sched::{Config, Scheduler};
use crate::text::plural;

/// Whether `file` is named as an Anki package.
pub fn is_anki_file(file: &Path) -> bool {
    file.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("apkg") || e.eq_ignore_ascii_case("colpkg"))
}

pub fn run(cli: &Cli, args: &ImportArgs) -> anyhow::Result<ExitCode> {
    if crate::io::metadata(&args.file).is_ok_and(|m| m.is_dir()) {
        anyhow::bail!("cannot read {}: it is a folder", args.file.display());
    }
    let now = crate::cmd::clock::now()?;
    let mut import = read_package(&args.file, true, now)?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("anki-import"));
    // Everything is checked before anything is written.
    for d in &import.decks {
        let file = deck_file(&out, &d.id);
        if file.exists() {
            anyhow::bail!(
                "{} already exists; nothing imported (choose another --out, or move it away)",
                file.display()
            );
        }
    }
    let config = Config::load(paths::config_file(cli.config.clone()).as_deref())?;
    let mut store = open_store(cli)?;
    let mut written = write_decks(&out, &import)?;
    let mut loaded = crate::deck::load_dir(&out.join("decks"));
    if loaded.errors() > 0 && cloze_unknown(&loaded) {
        // Decks without cloze cards: the Cloze notes are left out (and
        // said so) rather than the whole collection.
        remove(&written);
        import = read_package(&args.file, false, now)?;
        written = write_decks(&out, &import)?;
        loaded = crate::deck::load_dir(&out.join("decks"));
    }
    if loaded.errors() > 0 {
        let problems: Vec<String> = loaded
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .take(3)
            .map(|d| d.headline())
            .collect();
        remove(&written);
        anyhow::bail!(
            "the decks made from {} do not pass `flipcard check` ({}); nothing imported",
            args.file.display(),
            problems.join("; ")
        );
    }
    let summary = match store.merge_reviews(&import.reviews, &Scheduler::new(&config)) {
        Ok(s) => s,
        Err(e) => {
            remove(&written);
            return Err(e.into());
        }
    };
    crate::outln!(
        "imported {} from {} ({}) into {}:",
        plural(import.notes, "note", "notes"),
        args.file.display(),
        import.entry,
        out.display()
    )?;
    for d in &import.decks {
        crate::outln!(
            "  {}  {} ({})",
            deck_file(&out, &d.id).display(),
            plural(d.cards, "card", "cards"),
            d.name
        )?;
    }
    crate::outln!(
        "review history: {} added, {} already present, {} left out (manual reschedules); {} rebuilt",
        summary.added,
        summary.duplicates,
        import.reviews_skipped,
        plural(summary.items, "card state", "card states")
    )?;
    if import.cloze_left_out > 0 {
        crate::outln!(
            "{} left out: these decks have no cloze cards",
            plural(import.cloze_left_out, "cloze note", "cloze notes")
        )?;
    }
    if import.media_files + import.media_refs > 0 {
        crate::outln!(
            "media skipped: {} in the package, {} in the notes",
            plural(import.media_files, "file", "files"),
            plural(import.media_refs, "reference", "references")
        )?;
    }
    crate::outln!(
        "open them with `flipcard --decks {}`",
        out.join("decks").display()
    )?;
    Ok(ExitCode::SUCCESS)
}

/// Whether the check refused the cards written as `kind = "cloze"`.
fn cloze_unknown(loaded: &crate::deck::Loaded) -> bool {
    loaded
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .any(|d| d.headline().contains("card kind `cloze`"))
}

fn deck_file(out: &Path, id: &str) -> PathBuf {
    out.join("decks").join(format!("{id}.toml"))
}

/// Writes every deck and its (empty) content file; returns what it wrote.
fn write_decks(out: &Path, import: &AnkiImport) -> anyhow::Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let result = (|| -> anyhow::Result<()> {
        for d in &import.decks {
            let file = deck_file(out, &d.id);
            crate::io::write_atomic(&file, d.toml.as_bytes(), crate::io::Durability::Synced)
                .with_context(|| format!("cannot write {}", file.display()))?;
            written.push(file);
            let content = out.join("content").join(&d.id);
            let en = content.join("en.toml");
            if !en.exists() {
                crate::io::write_atomic(
                    &en,
                    b"# Explanations of the imported cards go here.\n",
                    crate::io::Durability::Synced,
                )
                .with_context(|| format!("cannot write {}", en.display()))?;
                written.push(en);
            }
        }
        Ok(())
    })();
    if let Err(e) = result {
        remove(&written);
        return Err(e);
    }
    Ok(written)
}

fn remove(files: &[PathBuf]) {
    for f in files {
        let _ = crate::io::remove_file(f);
        if let Some(dir) = f.parent() {
            let _ = crate::io::remove_dir(dir);
        }
    }
}
