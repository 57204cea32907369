//! `flipcard import FILE.apkg|FILE.colpkg [--out DIR]`: an Anki collection
//! becomes a deck folder (`DIR/decks/<id>.toml` and an empty
//! `DIR/content/<id>/en.toml` per Anki deck), and its review history joins
//! the log, replayed through FSRS, each card ending with the due date,
//! interval and memory state Anki gave it. Suspended, buried and leech
//! cards are marked so here; the decks' options become presets, written to
//! `DIR/anki-presets.toml` as `[preset.NAME]` and `[deck.ID]` tables (and
//! merged into `config.toml` with `--merge-presets`); an Anki deck `A::B`
//! sits under `A` (`parent`). The summary says every change of meaning.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context as _;

use crate::cmd::args::{Cli, ImportArgs};
use crate::cmd::common::open_store;
use crate::cmd::paths;
use std::collections::HashSet;

use crate::interop::anki::{AnkiImport, DeckOptions, read_package};
use crate::sched::preset::Preset;
use crate::sched::{Config, Schedulers};
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
    // The decks' options as presets, checked as the config would read
    // them, written beside the decks; merged into the config on request.
    let presets = Presets::of(&import, &config);
    let presets_file = out.join("anki-presets.toml");
    if !presets.decks.is_empty() {
        let text = presets.text();
        if let Err(e) = Config::parse(&text, &presets_file) {
            remove(&written);
            anyhow::bail!(
                "the presets made from the decks' options do not load ({e}); nothing imported"
            );
        }
        if let Err(e) = crate::io::write_atomic(
            &presets_file,
            text.as_bytes(),
            crate::io::Durability::Synced,
        ) {
            remove(&written);
            return Err(
                anyhow::Error::new(e).context(format!("cannot write {}", presets_file.display()))
            );
        }
        written.push(presets_file.clone());
    }
    let summary = match store.merge_reviews_keeping(
        &import.reviews,
        &Schedulers::new(&config),
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
    if !presets.decks.is_empty() {
        for d in &import.decks {
            if let Some(o) = &d.options {
                crate::outln!("deck options of {}: {}", d.id, describe(o))?;
            }
        }
        for (deck, left_out) in &presets.left_out {
            crate::outln!("  {deck}: not kept: {}", left_out.join("; "))?;
        }
        let config_path = paths::config_file(cli.config.clone());
        match (&config_path, args.merge_presets) {
            (Some(path), true) => {
                let merged = presets.merge_into(&config);
                merged.save(path)?;
                crate::outln!(
                    "  merged into {} as presets: {}; decks: {}",
                    path.display(),
                    presets.names_said(),
                    presets.decks_said()
                )?;
            }
            (None, true) => anyhow::bail!(
                "no config file location known; pass --config FILE to merge the presets (the decks are imported; the presets are in {})",
                presets_file.display()
            ),
            (_, false) => crate::outln!(
                "  written to {} as presets {} and the decks' [deck.ID] tables ({}); the config does not read that file: paste them into your config.toml, or import with --merge-presets",
                presets_file.display(),
                presets.names_said(),
                presets.decks_said()
            )?,
        }
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
    if let Some(d) = o.maximum_interval {
        parts.push(format!("maximum interval {d}d"));
    }
    parts.join(", ")
}

/// A value read as f32, written as the shortest decimal that reads back.
fn round(x: f64) -> String {
    format!("{}", x as f32)
}

/// The decks' options as flipcard presets: one `[preset.NAME]` per
/// distinct set of options (named after Anki's preset), and which deck
/// uses which.
struct Presets {
    /// Name, preset, in order of first use.
    presets: Vec<(String, Preset)>,
    /// Deck id, preset name.
    decks: Vec<(String, String)>,
    /// Deck id, options Anki had that a preset cannot hold.
    left_out: Vec<(String, Vec<String>)>,
}

impl Presets {
    fn of(import: &AnkiImport, config: &Config) -> Presets {
        let mut out = Presets {
            presets: Vec::new(),
            decks: Vec::new(),
            left_out: Vec::new(),
        };
        for d in &import.decks {
            let Some(o) = &d.options else { continue };
            let (preset, left_out) = preset_of(o);
            if !left_out.is_empty() {
                out.left_out.push((d.id.clone(), left_out));
            }
            let name = match out.presets.iter().find(|(_, p)| *p == preset) {
                Some((name, _)) => name.clone(),
                None => {
                    // A name neither taken here nor, for something else,
                    // in the config.
                    let base = preset_name(&o.preset);
                    let mut name = base.clone();
                    let mut n = 2;
                    while out.presets.iter().any(|(m, _)| *m == name)
                        || config.presets.get(&name).is_some_and(|p| *p != preset)
                    {
                        name = format!("{base}-{n}");
                        n += 1;
                    }
                    out.presets.push((name.clone(), preset));
                    name
                }
            };
            out.decks.push((d.id.clone(), name));
        }
        out
    }

    /// The presets and deck tables as config TOML.
    fn text(&self) -> String {
        let mut text = String::from(
            "# The Anki decks' options as flipcard presets. Paste these tables into\n\
             # config.toml (or import with --merge-presets): what a preset leaves out\n\
             # is the config's top-level value.\n",
        );
        for (name, p) in &self.presets {
            text.push_str(&format!("\n[preset.{name}]\n{}", p.to_toml()));
        }
        for (deck, name) in &self.decks {
            text.push_str(&format!(
                "\n[deck.{deck}]\npreset = {}\n",
                toml::Value::String(name.clone())
            ));
        }
        text
    }

    /// `config` with these presets and deck tables added.
    fn merge_into(&self, config: &Config) -> Config {
        let mut c = config.clone();
        for (name, p) in &self.presets {
            c.presets.insert(name.clone(), p.clone());
        }
        for (deck, name) in &self.decks {
            c.decks.entry(deck.clone()).or_default().preset = Some(name.clone());
        }
        c
    }

    fn names_said(&self) -> String {
        self.presets
            .iter()
            .map(|(n, _)| format!("[preset.{n}]"))
            .collect::<Vec<_>>()
            .join(", ")
    }

    fn decks_said(&self) -> String {
        self.decks
            .iter()
            .map(|(d, n)| format!("{d} → {n}"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// Anki's options as a preset, and what of them a preset cannot hold.
fn preset_of(o: &DeckOptions) -> (Preset, Vec<String>) {
    let mut left_out = Vec::new();
    let mut steps = |v: &[f64], what: &str| -> Option<Vec<chrono::TimeDelta>> {
        if v.is_empty() {
            return None;
        }
        let mut out = Vec::new();
        for m in v {
            let secs = (m * 60.0).round();
            let step = chrono::TimeDelta::try_seconds(secs as i64).filter(|s| {
                *s >= chrono::TimeDelta::seconds(1) && *s <= chrono::TimeDelta::days(365)
            });
            match step {
                Some(s) if secs.is_finite() => out.push(s),
                _ => {
                    left_out.push(format!("{what} {}m (flipcard takes 1s to 365d)", round(*m)));
                    return None;
                }
            }
        }
        Some(out)
    };
    let learning_steps = steps(&o.learning_steps, "learning step");
    let relearning_steps = steps(&o.relearning_steps, "relearning step");
    let limit = |v: Option<u32>, max: u32, what: &str, left_out: &mut Vec<String>| {
        v.filter(|n| {
            let ok = *n <= max;
            if !ok {
                left_out.push(format!("{what} {n} (at most {max})"));
            }
            ok
        })
    };
    let new_per_day = limit(o.new_per_day, 10_000, "new/day", &mut left_out);
    let reviews_per_day = limit(o.reviews_per_day, 100_000, "reviews/day", &mut left_out);
    // Anki keeps retention as an f32: the shortest decimal that reads back.
    let desired_retention = o.desired_retention.and_then(|r| {
        let r: f64 = round(r).parse().unwrap_or(r);
        let (lo, hi) = (0.70, crate::sched::preset::PRESET_RETENTION_MAX);
        if (lo..=hi).contains(&r) {
            Some(r)
        } else {
            left_out.push(format!("desired retention {r} (flipcard takes {lo}–{hi})"));
            None
        }
    });
    let fsrs_parameters = match o.fsrs_parameters.len() {
        0 => None,
        21 => {
            let mut w = [0.0; 21];
            let mut ok = true;
            for (i, (x, (lo, hi))) in o
                .fsrs_parameters
                .iter()
                .zip(crate::sched::config::PARAMETER_BOUNDS)
                .enumerate()
            {
                let x: f64 = round(*x).parse().unwrap_or(*x);
                ok &= (lo..=hi).contains(&x);
                w[i] = x;
            }
            if ok {
                Some(w)
            } else {
                left_out.push("FSRS parameters outside the range a fit gives".to_string());
                None
            }
        }
        n => {
            left_out.push(format!("{n} FSRS parameters (FSRS-6 has 21: run `flipcard optimize --deck ID --apply` after a few weeks)"));
            None
        }
    };
    (
        Preset {
            new_per_day,
            reviews_per_day,
            learning_steps,
            relearning_steps,
            desired_retention,
            maximum_interval: o.maximum_interval,
            fsrs_parameters,
        },
        left_out,
    )
}

/// A preset name from Anki's: letters and digits kept, the rest `-`.
fn preset_name(anki: &str) -> String {
    let mut name = String::new();
    for c in anki.chars() {
        if c.is_ascii_alphanumeric() {
            name.push(c.to_ascii_lowercase());
        } else if !name.ends_with('-') && !name.is_empty() {
            name.push('-');
        }
    }
    let name = name.trim_end_matches('-');
    let name: String = name.chars().take(48).collect();
    if name.is_empty() {
        "anki".to_string()
    } else {
        format!("anki-{name}")
    }
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
