//! `flipcard export --reviews [--format json|csv]`,
//! `flipcard export --attempts [--format json|csv]` and
//! `flipcard export --deck ID --format csv`.

use std::io::Write;
use std::process::ExitCode;

use crate::cmd::args::{Cli, ExportArgs, ExportFormat};
use crate::cmd::common::{find_deck, load_decks, open_store_read_only};
use crate::deck::csv as csvdeck;
use crate::store::export::{self, ExportError};

pub fn run(cli: &Cli, args: &ExportArgs) -> anyhow::Result<ExitCode> {
    let mut out = crate::cmd::output::stdout();
    if args.reviews {
        let store = open_store_read_only(cli)?;
        match args.format.unwrap_or(ExportFormat::Json) {
            ExportFormat::Json => export::write_reviews_json(&store, &mut out)?,
            ExportFormat::Csv => export::write_reviews_csv(&store, &mut out)?,
        };
        out.flush()?;
        return Ok(ExitCode::SUCCESS);
    }
    if args.attempts {
        let store = open_store_read_only(cli)?;
        match args.format.unwrap_or(ExportFormat::Json) {
            ExportFormat::Json => export::write_attempts_json(&store, &mut out)?,
            ExportFormat::Csv => export::write_attempts_csv(&store, &mut out)?,
        };
        out.flush()?;
        return Ok(ExitCode::SUCCESS);
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
