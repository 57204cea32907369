//! `flipcard import FILE.csv --deck-id ID [--lang TAG]`: a CSV of cards
//! becomes a deck file on standard output. `--reviews FILE` and Anki
//! packages are handed to their own modules.

use std::io::Write;
use std::path::Path;
use std::process::ExitCode;

use crate::cmd::args::{Cli, ImportArgs};
use crate::cmd::import_file::{print_bad_rows, read_limited};
use crate::deck::csv::{self as csvdeck, DeckHeader};
use crate::text::plural;

pub fn run(cli: &Cli, args: &ImportArgs) -> anyhow::Result<ExitCode> {
    if args.reviews {
        return crate::cmd::import_reviews::run(cli, args);
    }
    if crate::cmd::import_anki::is_anki_file(&args.file) {
        return crate::cmd::import_anki::run(cli, args);
    }
    let Some(deck_id) = &args.deck_id else {
        anyhow::bail!(
            "say which deck to write: --deck-id ID (a CSV of cards), or --reviews for a review log, or give an Anki .apkg/.colpkg"
        );
    };
    if args.out.is_some() {
        anyhow::bail!("--out is for Anki imports; a CSV of cards becomes a deck file on stdout");
    }
    if !crate::deck::validate::is_id(deck_id) {
        anyhow::bail!(
            "--deck-id {:?} is not a deck id: lowercase a-z/0-9 words joined by '-' (e.g. {})",
            deck_id,
            crate::deck::csv::slug(deck_id)
        );
    }
    if !crate::deck::validate::is_lang_tag(&args.lang) {
        anyhow::bail!(
            "--lang {:?} is not a BCP 47 language tag (e.g. en, hi-Latn)",
            args.lang
        );
    }
    // A folder would otherwise open and fail as a "bad row"; a FIFO would
    // block the open. The size is checked before reading a row.
    let bytes = read_limited(&args.file, MAX_CARDS_BYTES)
        .map_err(|why| anyhow::anyhow!("cannot read {}: {why}", args.file.display()))?;
    let cards = match csvdeck::read_cards_csv(&bytes[..]) {
        Ok(cards) => cards,
        Err(errors) => {
            print_bad_rows(
                &args.file,
                errors.iter().map(|e| (e.line, e.message.as_str())),
            );
            crate::errln!(
                "flipcard: error: {} in {}; no deck written",
                plural(errors.len(), "bad row", "bad rows"),
                args.file.display()
            );
            return Ok(ExitCode::FAILURE);
        }
    };
    let header = DeckHeader {
        id: deck_id.clone(),
        title: title_from(&args.file, deck_id),
        lang: args.lang.clone(),
        source: args.file.file_name().map_or_else(
            || args.file.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        ),
    };
    let toml = csvdeck::deck_toml(&header, &cards);
    let mut out = crate::cmd::output::stdout();
    out.write_all(toml.as_bytes())?;
    out.flush()?;
    crate::errln!("{}", placement_note(deck_id, &args.lang, cards.len()));
    Ok(ExitCode::SUCCESS)
}

/// The largest CSV of cards read (some hundred thousand cards).
pub const MAX_CARDS_BYTES: u64 = 64 << 20;

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
