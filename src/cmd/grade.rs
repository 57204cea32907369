//! `flipcard grade --deck ID --prompt P|--card C ANSWER`: a formula answer
//! graded headless, by the comparison the app makes
//! (`sim::system::equiv`), so an instructor can test a deck's answer keys
//! in CI. It prints `right`, or `wrong` with the slip the answer makes,
//! and exits 0 when right, 1 when wrong, 2 when the command line or the
//! deck is at fault (no such deck or item, an item that takes no formula,
//! a key that cannot decide).

use std::process::ExitCode;

use crate::cmd::args::{Cli, GradeArgs};
use crate::deck::{Answer, CardKind, FormulaKey};
use crate::sim::system::equiv::{self, Verdict};
use crate::text::safe::one_line;
use crate::tui::i18n::{ENGLISH, formula_words};

/// The exit status of a usage or deck error (as clap's).
const USAGE: u8 = 2;

pub fn run(cli: &Cli, args: &GradeArgs) -> anyhow::Result<ExitCode> {
    let key = match key(cli, args) {
        Ok(k) => k,
        Err(why) => {
            crate::errln!("flipcard: error: {why}");
            return Ok(ExitCode::from(USAGE));
        }
    };
    let verdict = equiv::grade(&key, &args.answer);
    let said = formula_words::feedback(&verdict, ENGLISH);
    match verdict {
        Verdict::Right => {
            crate::outln!("right")?;
            Ok(ExitCode::SUCCESS)
        }
        Verdict::Undecided(_) => {
            crate::errln!("flipcard: error: {}", said.unwrap_or_default());
            Ok(ExitCode::from(USAGE))
        }
        Verdict::Wrong(_) | Verdict::Unreadable(_) => {
            match said {
                Some(s) => crate::outln!("wrong: {s}")?,
                None => crate::outln!("wrong")?,
            }
            crate::outln!("expected: {}", one_line(&key.expected))?;
            Ok(ExitCode::FAILURE)
        }
    }
}

/// The key of the card or prompt named, or why there is none.
fn key(cli: &Cli, args: &GradeArgs) -> Result<FormulaKey, String> {
    let loaded = crate::cmd::library::load(cli).loaded;
    let deck = super::common::find_deck(&loaded, &args.deck).map_err(|e| {
        if loaded.errors() > 0 {
            format!("{e} (some deck files have errors: run `flipcard check`)")
        } else {
            e.to_string()
        }
    })?;
    let quoted = |s: &str| one_line(s).into_owned();
    if let Some(id) = &args.card {
        let card = deck
            .card(id)
            .ok_or_else(|| format!("deck {} has no card `{}`", deck.id, quoted(id)))?;
        return match (&card.formula, card.kind) {
            (Some(k), CardKind::Formula) => Ok(k.clone()),
            _ => Err(format!(
                "card `{}` of deck {} is a {} card, not a formula card",
                card.id,
                deck.id,
                card.kind.as_str()
            )),
        };
    }
    let id = args.prompt.as_deref().unwrap_or_default();
    let prompt = deck
        .prompt(id)
        .ok_or_else(|| format!("deck {} has no prompt `{}`", deck.id, quoted(id)))?;
    match &prompt.answer {
        Answer::Formula(k) => Ok(k.clone()),
        _ => Err(format!(
            "prompt `{}` of deck {} does not take a formula",
            prompt.id, deck.id
        )),
    }
}
