//! Headless commands over the store: stats, export, import, db.

use std::io::Write;
use std::path::Path;
use std::process::ExitCode;

use anyhow::Context as _;

use super::csvdeck::{self, DeckHeader};
use super::export::{self, ExportError};
use super::stats::{Ratio, Stats, StatsScope};
use super::{DayGrid, Store};
use crate::cli::{Cli, DbArgs, DbCommand, ExportArgs, ExportFormat, ImportArgs, StatsArgs};
use crate::deck::{Deck, Loaded};
use crate::output::plural;
use crate::sched::{Config, ItemKey, deck_items};

/// The store for commands that only read: nothing is created or written,
/// so they work from a read-only data dir and on a full disk.
fn open_store_read_only(cli: &Cli) -> anyhow::Result<Store> {
    // Reading needs no clock, but a FLIPCARD_NOW the app would refuse when
    // writing is refused here too: one rule for every command over the
    // review data, so a script learns of its bad clock on its first call.
    crate::clock::now()?;
    let dir = crate::paths::data_dir(cli.data_dir.clone())?;
    Ok(Store::open_read_only(&dir)?)
}

fn open_store(cli: &Cli) -> anyhow::Result<Store> {
    let dir = crate::paths::data_dir(cli.data_dir.clone())?;
    let store = Store::open(&dir)?;
    for w in store.warnings() {
        crate::errln!("flipcard: warning: {w}");
    }
    Ok(store)
}

/// The decks as their files have them now (the bundled ones unless
/// `--decks` says otherwise). Decks with errors are left out with a
/// warning: their history then shows as orphaned until they are fixed.
fn load_decks(cli: &Cli) -> Loaded {
    let dir = cli
        .decks
        .clone()
        .unwrap_or_else(crate::paths::bundled_decks);
    let loaded = crate::deck::load_dir(&dir);
    if loaded.errors() > 0 {
        crate::errln!(
            "flipcard: warning: {} in the decks under {}; decks with errors are left out (run `flipcard check {}`)",
            plural(loaded.errors(), "error", "errors"),
            dir.display(),
            dir.display()
        );
    }
    loaded
}

pub fn stats(cli: &Cli, args: &StatsArgs) -> anyhow::Result<ExitCode> {
    let config = Config::load(crate::paths::config_file(cli.config.clone()).as_deref())?;
    let store = open_store_read_only(cli)?;
    let loaded = load_decks(cli);
    if let Some(id) = &args.deck
        && !loaded.decks.iter().any(|d| &d.id == id)
        && store.last_studied(id)?.is_none()
    {
        let known: Vec<&str> = loaded.decks.iter().map(|d| d.id.as_str()).collect();
        anyhow::bail!(
            "no deck `{id}` among the decks loaded and no history for it; decks: {}",
            if known.is_empty() {
                "none".to_string()
            } else {
                known.join(", ")
            }
        );
    }
    let items: Vec<ItemKey> = loaded.decks.iter().flat_map(deck_items).collect();
    let now = crate::clock::now()?;
    let grid = DayGrid::new(chrono::Local, config.day_starts_at);
    let scope = StatsScope {
        deck: args.deck.as_deref(),
        items: &items,
    };
    let stats = store.stats(scope, now, &grid)?;
    let mut out = crate::output::stdout();
    if args.json {
        serde_json::to_writer_pretty(&mut out, &stats)?;
        writeln!(out)?;
    } else {
        out.write_all(render_stats(&stats).as_bytes())?;
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}

fn percent(r: &Ratio) -> String {
    match r.rate {
        Some(rate) => format!("{:.1}% ({}/{})", rate * 100.0, r.passed, r.total),
        None => "– (none yet)".to_string(),
    }
}

/// The stats as text for the terminal.
pub fn render_stats(s: &Stats) -> String {
    let mut o = String::new();
    let mut line = |text: String| {
        o.push_str(&text);
        o.push('\n');
    };
    line(format!(
        "{} — {} (study day {})",
        s.deck.as_deref().unwrap_or("all decks"),
        export::rfc3339(s.now),
        s.today
    ));
    line(String::new());
    let c = &s.cards;
    line(format!(
        "Cards: {} — new {}, learning {}, review {}, relearning {}",
        c.total, c.new, c.learning, c.review, c.relearning
    ));
    let d = &s.due;
    line(format!(
        "Due: today {}, tomorrow {}, next 7 days {}, next 30 days {}",
        d.today, d.tomorrow, d.next_7_days, d.next_30_days
    ));
    line(String::new());
    let total: u32 = s.reviews_per_day.iter().map(|d| d.total).sum();
    line(format!("Reviews per day, last 30 days ({total} in all):"));
    let max = s.reviews_per_day.iter().map(|d| d.total).max().unwrap_or(0);
    for day in &s.reviews_per_day {
        let bar = if max == 0 {
            0
        } else {
            (day.total as usize * 40).div_ceil(max as usize)
        };
        line(format!(
            "  {}  {:>5}  {}",
            day.date,
            day.total,
            "█".repeat(bar)
        ));
    }
    line(String::new());
    line("True retention (review answers not rated Again):".to_string());
    line(format!(
        "  last 30 days {}, all time {}",
        percent(&s.retention.last_30_days),
        percent(&s.retention.all_time)
    ));
    line(format!(
        "Prompt accuracy (predict, then check): {}",
        percent(&s.prompts.overall)
    ));
    for p in &s.prompts.by_prompt {
        line(format!(
            "  {}/{}: {}/{} right",
            p.deck, p.prompt, p.correct, p.attempts
        ));
    }
    if !s.orphans.is_empty() {
        line(String::new());
        line(format!(
            "Orphans: {} with history whose card is no longer in its deck (the history is kept and returns with the card):",
            plural(s.orphans.len(), "item", "items")
        ));
        for o in &s.orphans {
            let whose = if o.deck_present {
                ""
            } else {
                " (deck not loaded)"
            };
            line(format!(
                "  {}/{} {}: {}{whose}",
                o.deck,
                o.card,
                o.direction,
                plural(o.reviews, "review", "reviews")
            ));
        }
    }
    o
}

pub fn export(cli: &Cli, args: &ExportArgs) -> anyhow::Result<ExitCode> {
    let mut out = crate::output::stdout();
    if args.reviews {
        let store = open_store_read_only(cli)?;
        match args.format.unwrap_or(ExportFormat::Json) {
            ExportFormat::Json => export::write_reviews_json(&store, &mut out)?,
            ExportFormat::Csv => export::write_reviews_csv(&store, &mut out)?,
        };
        out.flush()?;
        return Ok(ExitCode::SUCCESS);
    }
    let Some(id) = &args.deck else {
        anyhow::bail!("say what to export: --reviews or --deck ID");
    };
    if args.format == Some(ExportFormat::Json) {
        anyhow::bail!(
            "a deck is exported as CSV only (--format csv); its TOML file is the full form"
        );
    }
    let loaded = load_decks(cli);
    let deck = find_deck(&loaded, id)?;
    csvdeck::write_deck_csv(deck, &mut out).map_err(ExportError::from)?;
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}

fn find_deck<'a>(loaded: &'a Loaded, id: &str) -> anyhow::Result<&'a Deck> {
    loaded.decks.iter().find(|d| d.id == id).ok_or_else(|| {
        let known: Vec<&str> = loaded.decks.iter().map(|d| d.id.as_str()).collect();
        anyhow::anyhow!(
            "no deck `{id}` among the decks loaded; decks: {}",
            if known.is_empty() {
                "none".to_string()
            } else {
                known.join(", ")
            }
        )
    })
}

pub fn import(_cli: &Cli, args: &ImportArgs) -> anyhow::Result<ExitCode> {
    if !crate::deck::validate::is_id(&args.deck_id) {
        anyhow::bail!(
            "--deck-id {:?} is not a deck id: lowercase a-z/0-9 words joined by '-' (e.g. {})",
            args.deck_id,
            crate::store::csvdeck::slug(&args.deck_id)
        );
    }
    if !crate::deck::validate::is_lang_tag(&args.lang) {
        anyhow::bail!(
            "--lang {:?} is not a BCP 47 language tag (e.g. en, hi-Latn)",
            args.lang
        );
    }
    let file = std::fs::File::open(&args.file)
        .with_context(|| format!("cannot read {}", args.file.display()))?;
    // Opening a folder succeeds; reading it would fail as a "bad row".
    if file.metadata().is_ok_and(|m| m.is_dir()) {
        anyhow::bail!(
            "cannot read {}: it is a folder, not a CSV file",
            args.file.display()
        );
    }
    let cards = match csvdeck::read_cards_csv(std::io::BufReader::new(file)) {
        Ok(cards) => cards,
        Err(errors) => {
            for e in &errors {
                crate::errln!("{}:{}: {}", args.file.display(), e.line, e.message);
            }
            crate::errln!(
                "flipcard: error: {} in {}; no deck written",
                plural(errors.len(), "bad row", "bad rows"),
                args.file.display()
            );
            return Ok(ExitCode::FAILURE);
        }
    };
    let header = DeckHeader {
        id: args.deck_id.clone(),
        title: title_from(&args.file, &args.deck_id),
        lang: args.lang.clone(),
        source: args.file.file_name().map_or_else(
            || args.file.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        ),
    };
    let toml = csvdeck::deck_toml(&header, &cards);
    let mut out = crate::output::stdout();
    out.write_all(toml.as_bytes())?;
    out.flush()?;
    crate::errln!("{}", placement_note(&args.deck_id, &args.lang, cards.len()));
    Ok(ExitCode::SUCCESS)
}

/// The deck title: the CSV file's name when it is a valid text, else the id.
fn title_from(file: &Path, id: &str) -> String {
    let stem = file
        .file_stem()
        .map(|s| s.to_string_lossy().trim().to_string())
        .unwrap_or_default();
    let usable = !stem.is_empty()
        && !stem.chars().any(char::is_control)
        && crate::text::check(&stem).is_empty();
    if usable { stem } else { id.to_string() }
}

/// What to do with the deck file, on stderr so stdout stays the file.
pub fn placement_note(id: &str, lang: &str, cards: usize) -> String {
    format!(
        "flipcard: {}. Save the output as decks/{id}.toml and create an empty \
         content/{id}/{lang}.toml beside the decks/ folder (the imported cards link no \
         explanations, so the content file needs no sections). Then run `flipcard check decks/`.",
        plural(cards, "card", "cards")
    )
}

pub fn db(cli: &Cli, args: &DbArgs) -> anyhow::Result<ExitCode> {
    match &args.command {
        DbCommand::Restore(restore) => {
            let dir = crate::paths::data_dir(cli.data_dir.clone())?;
            let done = super::restore::restore(&dir, restore.backup.as_deref(), restore.force)?;
            crate::outln!(
                "restored {} ({}) as {}",
                done.backup.display(),
                plural(done.reviews, "review", "reviews"),
                done.database.display()
            )?;
            for p in &done.set_aside {
                crate::outln!("set aside: {}", p.display())?;
            }
            Ok(ExitCode::SUCCESS)
        }
        DbCommand::Rebuild => {
            let mut store = open_store(cli)?;
            let report = store.rebuild()?;
            crate::outln!(
                "rebuilt {} from {} in {}; {} differed from the cache",
                plural(report.items, "card state", "card states"),
                plural(report.reviews, "log row", "log rows"),
                store.path().display(),
                report.changed
            )?;
            if report.tallies_changed {
                crate::outln!("the answer tallies did not match the log and were recomputed")?;
            }
            Ok(ExitCode::SUCCESS)
        }
    }
}
