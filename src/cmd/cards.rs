//! `flipcard cards list [QUERY] [--format csv|json]` and `flipcard cards
//! suspend|unsuspend|bury ITEM…`: the card browser's rows and actions for
//! scripts.

use std::io::Write;
use std::process::ExitCode;

use serde::Serialize;

use crate::cmd::args::{CardsArgs, CardsCommand, CardsFormat, Cli};
use crate::cmd::common::{load_decks, open_store, open_store_read_only};
use crate::cmd::paths;
use crate::deck::Deck;
use crate::sched::{Config, Direction, ItemKey, Scheduler};
use crate::store::StatusAction;
use crate::store::catalog::{self, Filter, ItemRow, Search};
use crate::text::{num, plural};

/// The CSV header, one column per field of [`Listed`].
pub const HEADER: [&str; 14] = [
    "deck",
    "card",
    "direction",
    "state",
    "due",
    "stability",
    "difficulty",
    "retrievability",
    "reviews",
    "lapses",
    "suspended",
    "buried",
    "leech",
    "tags",
];

/// One row as printed; numbers in shortest form, blank when unknown.
#[derive(Debug, Serialize)]
struct Listed {
    deck: String,
    card: String,
    direction: String,
    state: &'static str,
    due: String,
    stability: String,
    difficulty: String,
    retrievability: String,
    reviews: u32,
    lapses: u32,
    suspended: bool,
    buried: bool,
    leech: bool,
    tags: String,
}

fn listed(decks: &[Deck], row: &ItemRow, now: chrono::DateTime<chrono::Utc>) -> Listed {
    let opt = |x: Option<f64>| x.map(num::show).unwrap_or_default();
    Listed {
        deck: row.deck_id(decks).to_string(),
        card: row.card_id(decks).to_string(),
        direction: row.direction.as_str().into_owned(),
        state: row.state_name(),
        due: row
            .due()
            .map(|d| d.to_rfc3339_opts(chrono::SecondsFormat::Secs, true))
            .unwrap_or_default(),
        stability: opt(row.state.and_then(|s| s.stability)),
        difficulty: opt(row.state.and_then(|s| s.difficulty)),
        retrievability: opt(row.retrievability),
        reviews: row.reviews,
        lapses: row.lapses,
        suspended: row.status.suspended,
        buried: row.buried(now),
        leech: row.status.leech,
        tags: row.tags(decks).join(" "),
    }
}

pub fn run(cli: &Cli, args: &CardsArgs) -> anyhow::Result<ExitCode> {
    let config = Config::load(paths::config_file(cli.config.clone()).as_deref())?;
    let now = crate::sched::clock::now()?;
    let loaded = load_decks(cli);
    let decks = &loaded.decks;
    match &args.command {
        CardsCommand::List(list) => {
            let query = list.query.join(" ");
            let filter = Filter::parse(&query)?;
            filter.check_names(decks)?;
            let store = open_store_read_only(cli)?;
            let rows = catalog::rows(decks, &store, &Scheduler::new(&config), now)?;
            let mut search = Search::for_text(&filter.text, decks, &rows);
            let picked = catalog::select(decks, &rows, &mut search, &filter, now);
            if picked.is_empty() && !query.trim().is_empty() {
                crate::errln!("flipcard: no item matches `{}`", query.trim());
            }
            let mut out = crate::cmd::output::stdout();
            match list.format {
                CardsFormat::Csv => {
                    let mut w = csv::WriterBuilder::new()
                        .has_headers(false)
                        .from_writer(&mut out);
                    w.write_record(HEADER)?;
                    for &i in &picked {
                        w.serialize(listed(decks, &rows[i], now))?;
                    }
                    w.flush()?;
                }
                CardsFormat::Json => {
                    let all: Vec<Listed> = picked
                        .iter()
                        .map(|&i| listed(decks, &rows[i], now))
                        .collect();
                    serde_json::to_writer_pretty(&mut out, &all)?;
                    writeln!(out)?;
                }
            }
            out.flush()?;
            Ok(ExitCode::SUCCESS)
        }
        CardsCommand::Suspend(items)
        | CardsCommand::Unsuspend(items)
        | CardsCommand::Bury(items) => {
            let (action, done) = match &args.command {
                CardsCommand::Suspend(_) => (StatusAction::Suspend, "suspended"),
                CardsCommand::Unsuspend(_) => (StatusAction::Unsuspend, "unsuspended"),
                _ => (StatusAction::Bury, "buried until the next day starts"),
            };
            // Every item is resolved before anything is written: one
            // unknown item and nothing changes.
            let mut keys = Vec::new();
            for item in &items.items {
                keys.extend(resolve(decks, item)?);
            }
            let until = (action == StatusAction::Bury)
                .then(|| crate::sched::study_day(now, config.day_starts_at, &chrono::Local).1);
            let mut store = open_store(cli)?;
            store.set_status(&keys, action, now, until)?;
            crate::outln!("{done}: {}", plural(keys.len(), "item", "items"))?;
            Ok(ExitCode::SUCCESS)
        }
    }
}

/// `DECK/CARD` (every item of the card) or `DECK/CARD/DIRECTION`.
pub fn resolve(decks: &[Deck], item: &str) -> anyhow::Result<Vec<ItemKey>> {
    let parts: Vec<&str> = item.split('/').collect();
    let (deck_id, card_id, direction) = match parts.as_slice() {
        [d, c] => (*d, *c, None),
        [d, c, dir] => (*d, *c, Some(*dir)),
        _ => anyhow::bail!("`{item}` is not an item: write DECK/CARD or DECK/CARD/DIRECTION"),
    };
    let deck = decks
        .iter()
        .find(|d| d.id == deck_id)
        .ok_or_else(|| anyhow::anyhow!("unknown item `{item}`: no deck `{deck_id}`"))?;
    let card = deck.card(card_id).ok_or_else(|| {
        anyhow::anyhow!("unknown item `{item}`: deck `{deck_id}` has no card `{card_id}`")
    })?;
    let all = catalog::card_directions(card);
    let key = |direction| ItemKey {
        deck: deck_id.to_string(),
        card: card_id.to_string(),
        direction,
    };
    match direction {
        None => Ok(all.into_iter().map(key).collect()),
        Some(text) => match Direction::parse(text).filter(|d| all.contains(d)) {
            Some(d) => Ok(vec![key(d)]),
            None => {
                let names: Vec<String> = all.iter().map(|d| d.as_str().into_owned()).collect();
                anyhow::bail!(
                    "unknown item `{item}`: card `{card_id}` has no direction `{text}`; it has {}",
                    names.join(", ")
                )
            }
        },
    }
}
