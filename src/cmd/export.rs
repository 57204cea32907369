//! `flipcard export --reviews [--format json|csv]`,
//! `flipcard export --attempts [--format json|csv]` and
//! `flipcard export --deck ID --format csv` and
//! `flipcard export --apkg FILE [--deck ID]` (an Anki package).

use std::io::Write;
use std::process::ExitCode;

use crate::cmd::args::{Cli, ExportArgs, ExportFormat};
use crate::cmd::common::{find_deck, load_decks, open_store_read_only};
use crate::deck::csv as csvdeck;
use crate::interop::export::{self, ExportError, Written};
use crate::text::plural;

pub fn run(cli: &Cli, args: &ExportArgs) -> anyhow::Result<ExitCode> {
    let mut out = crate::cmd::output::stdout();
    if args.reviews {
        let store = open_store_read_only(cli)?;
        let written = match args.format.unwrap_or(ExportFormat::Json) {
            ExportFormat::Json => export::write_reviews_json(&store, &mut out)?,
            ExportFormat::Csv => export::write_reviews_csv(&store, &mut out)?,
        };
        out.flush()?;
        return Ok(verdict(&written, "review", "reviews"));
    }
    if args.attempts {
        let store = open_store_read_only(cli)?;
        let written = match args.format.unwrap_or(ExportFormat::Json) {
            ExportFormat::Json => export::write_attempts_json(&store, &mut out)?,
            ExportFormat::Csv => export::write_attempts_csv(&store, &mut out)?,
        };
        out.flush()?;
        return Ok(verdict(&written, "attempt", "attempts"));
    }
    if let Some(file) = &args.apkg {
        return apkg(cli, file, args.deck.as_deref());
    }
    let Some(id) = &args.deck else {
        anyhow::bail!("say what to export: --reviews, --attempts or --deck ID");
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

/// Success when every row was written; else each row left out is named
/// (the first few) and the export fails: it is not the whole log.
fn verdict(written: &Written, one: &str, many: &str) -> ExitCode {
    if written.left_out == 0 {
        return ExitCode::SUCCESS;
    }
    for why in &written.named {
        crate::errln!("flipcard: {why}; left out");
    }
    let unnamed = written.left_out - written.named.len() as u64;
    if unnamed > 0 {
        crate::errln!("flipcard: … and {unnamed} more left out");
    }
    crate::errln!(
        "flipcard: error: {} not exported (a time stored outside the years 0–9999, which RFC 3339 cannot write; such rows came from an import before dates were checked); the other {} were written",
        plural(written.left_out, one, many),
        written.rows
    );
    ExitCode::FAILURE
}

/// `export --apkg FILE [--deck ID]`: the decks loaded (or one), their states
/// and history as an Anki package, written atomically.
fn apkg(cli: &Cli, file: &std::path::Path, deck: Option<&str>) -> anyhow::Result<ExitCode> {
    let loaded = load_decks(cli);
    let decks: Vec<&crate::deck::Deck> = match deck {
        Some(id) => vec![find_deck(&loaded, id)?],
        None => loaded.decks.iter().collect(),
    };
    if decks.is_empty() {
        anyhow::bail!("no decks loaded: nothing to export");
    }
    let store = open_store_read_only(cli)?;
    let now = crate::cmd::clock::now()?;
    let (bytes, summary) = crate::interop::apkg::write_apkg(&decks, &store, "en", now)?;
    crate::io::write_atomic(file, &bytes, crate::io::Durability::Synced)
        .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", file.display()))?;
    crate::outln!(
        "wrote {}: {}, {}, {}, {}",
        file.display(),
        plural(summary.decks, "deck", "decks"),
        plural(summary.notes, "note", "notes"),
        plural(summary.cards, "card", "cards"),
        plural(summary.reviews, "review", "reviews")
    )?;
    Ok(ExitCode::SUCCESS)
}
