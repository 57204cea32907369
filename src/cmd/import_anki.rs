//! `flipcard import FILE.apkg|FILE.colpkg [--out DIR]`: an Anki collection
//! becomes a deck folder (`DIR/decks/<id>.toml` and an empty
//! `DIR/content/<id>/en.toml` per Anki deck), and its review history joins
//! the log, replayed through FSRS, each card ending with the due date,
//! interval and memory state Anki gave it. Suspended, buried and leech
//! cards are marked so here; the decks' options are written to
//! `DIR/anki-deck-options.toml`. The summary says every change of meaning.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context as _;

use crate::cmd::args::{Cli, ImportArgs};
use crate::cmd::common::open_store;
use crate::cmd::paths;
use std::collections::HashSet;

use crate::interop::anki::{AnkiImport, DeckOptions, read_package};
use crate::sched::{Config, Scheduler};
use crate::store::StatusAction;
use crate::study::{DayZone, Mark, Study};
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
    // No imported deck takes a bundled deck's id.
    let reserved: HashSet<String> = crate::bundled::load()
        .decks
        .iter()
        .map(|d| d.id.clone())
        .collect();
    let mut import = read_package(&args.file, true, &reserved, now)?;
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
        import = read_package(&args.file, false, &reserved, now)?;
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
    let options_file = out.join("anki-deck-options.toml");
    let options = options_text(&import);
    if let Some(text) = &options {
        if let Err(e) = crate::io::write_atomic(
            &options_file,
            text.as_bytes(),
            crate::io::Durability::Synced,
        ) {
            remove(&written);
            return Err(
                anyhow::Error::new(e).context(format!("cannot write {}", options_file.display()))
            );
        }
        written.push(options_file.clone());
    }
    let summary = match store.merge_reviews_keeping(
        &import.reviews,
        &Scheduler::new(&config),
        &import.states.due,
    ) {
        Ok(s) => s,
        Err(e) => {
            remove(&written);
            return Err(e.into());
        }
    };
    // The states Anki had: leech marks, then suspensions and burials as
    // the learner's own marks (a bury lasts to the next study day).
    let states = &import.states;
    if !states.leeches.is_empty() {
        store.set_status(&states.leeches, StatusAction::Leech, now, None)?;
    }
    let mut study = Study::new(config.clone(), DayZone::Local, store);
    if !states.suspended.is_empty() {
        study.mark(&states.suspended, Mark::Suspend, now)?;
    }
    if !states.buried.is_empty() {
        study.mark(&states.buried, Mark::Bury, now)?;
    }
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
    let kept_due = import.states.due.len();
    let without_history = import
        .states
        .due
        .keys()
        .filter(|k| !import.reviews.iter().any(|r| &r.key == *k))
        .count();
    crate::outln!(
        "states kept: suspended {}, buried {}, flagged {} (as flag: tags), leeches {}; due dates and intervals as Anki had them: {}{}",
        states.suspended.len(),
        states.buried.len(),
        states.flagged,
        states.leeches.len(),
        plural(kept_due, "card", "cards"),
        if without_history > 0 {
            format!(
                " ({without_history} with no review history: scheduled as Anki had them, their answers not in the package)"
            )
        } else {
            String::new()
        }
    )?;
    if !import.note_types.is_empty() {
        crate::outln!("note types mapped:")?;
        for t in &import.note_types {
            crate::outln!(
                "  {} ({}) → {}",
                t.name,
                plural(t.notes, "note", "notes"),
                t.becomes
            )?;
        }
    }
    if !import.skipped.is_empty() {
        crate::outln!(
            "{} not imported:",
            plural(import.skipped.len(), "note", "notes")
        )?;
        for n in &import.skipped {
            crate::outln!("  note {} ({}): {}", n.note, n.note_type, n.why)?;
        }
    }
    if !import.math_not_rendered.is_empty() {
        crate::outln!(
            "math not rendered (kept as text) in {}:",
            plural(import.math_not_rendered.len(), "field", "fields")
        )?;
        for m in &import.math_not_rendered {
            crate::outln!("  {}/{} {}", m.deck, m.card, m.field)?;
        }
    }
    for r in &import.renamed {
        crate::outln!(
            "deck {:?} is {} (the bundled deck {} has the id {})",
            r.name,
            r.id,
            r.wanted,
            r.wanted
        )?;
    }
    if options.is_some() {
        for d in &import.decks {
            if let Some(o) = &d.options {
                crate::outln!("deck options of {}: {}", d.id, describe(o))?;
            }
        }
        crate::outln!(
            "  written to {} (presets per deck are not read yet: copy what you want into your config)",
            options_file.display()
        )?;
    }
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
    crate::outln!(
        "add them for good with `flipcard decks add {}`",
        out.display()
    )?;
    Ok(ExitCode::SUCCESS)
}

/// Deck options in words, for the summary.
fn describe(o: &DeckOptions) -> String {
    let mut parts = vec![format!("Anki preset {:?}", o.preset)];
    if let Some(n) = o.new_per_day {
        parts.push(format!("{n} new/day"));
    }
    if let Some(n) = o.reviews_per_day {
        parts.push(format!("{n} reviews/day"));
    }
    let minutes = |v: &[f64]| {
        v.iter()
            .map(|m| format!("{m}m"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    if !o.learning_steps.is_empty() {
        parts.push(format!("steps {}", minutes(&o.learning_steps)));
    }
    if !o.relearning_steps.is_empty() {
        parts.push(format!("relearning steps {}", minutes(&o.relearning_steps)));
    }
    if let Some(r) = o.desired_retention {
        parts.push(format!("desired retention {}", round(r)));
    }
    if !o.fsrs_parameters.is_empty() {
        parts.push(format!("{} FSRS parameters", o.fsrs_parameters.len()));
    }
    parts.join(", ")
}

/// A value read as f32, written as the shortest decimal that reads back.
fn round(x: f64) -> String {
    format!("{}", x as f32)
}

/// The decks' options as TOML, one `[anki_deck.ID]` table each, with the
/// config's own key names (`None` when no deck has options).
fn options_text(import: &AnkiImport) -> Option<String> {
    let mut text = String::from(
        "# Deck options of the Anki decks imported, with the config's key names.\n\
         # flipcard does not read this file: copy what you want into your config.\n",
    );
    let mut any = false;
    for d in &import.decks {
        let Some(o) = &d.options else { continue };
        any = true;
        text.push_str(&format!("\n[anki_deck.{}]\n", d.id));
        text.push_str(&format!(
            "anki_preset = {}\n",
            toml::Value::String(o.preset.clone())
        ));
        if let Some(n) = o.new_per_day {
            text.push_str(&format!("new_per_day = {n}\n"));
        }
        if let Some(n) = o.reviews_per_day {
            text.push_str(&format!("reviews_per_day = {n}\n"));
        }
        let steps = |v: &[f64]| {
            v.iter()
                .map(|m| format!("\"{}m\"", round(*m)))
                .collect::<Vec<_>>()
                .join(", ")
        };
        if !o.learning_steps.is_empty() {
            text.push_str(&format!(
                "learning_steps = [{}]\n",
                steps(&o.learning_steps)
            ));
        }
        if !o.relearning_steps.is_empty() {
            text.push_str(&format!(
                "relearning_steps = [{}]\n",
                steps(&o.relearning_steps)
            ));
        }
        if let Some(r) = o.desired_retention {
            text.push_str(&format!("desired_retention = {}\n", round(r)));
        }
        if !o.fsrs_parameters.is_empty() {
            let w: Vec<String> = o.fsrs_parameters.iter().map(|w| round(*w)).collect();
            text.push_str(&format!("fsrs_parameters = [{}]\n", w.join(", ")));
        }
    }
    any.then_some(text)
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
