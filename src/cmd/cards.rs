//! `flipcard cards list [QUERY] [--format csv|json]` and `flipcard cards
//! suspend|unsuspend|bury ITEM…`: the card browser's rows and actions for
//! scripts.

use std::collections::{HashMap, HashSet};
use std::io::Write;
use std::process::ExitCode;

use serde::Serialize;

use crate::catalog::search::select;
use crate::catalog::{self, Filter, ItemRow, Search};
use crate::cmd::args::{CardsArgs, CardsCommand, CardsFormat, CardsListArgs, Cli};
use crate::cmd::common::{load_decks, open_store, open_store_read_only};
use crate::cmd::paths;
use crate::deck::Deck;
use crate::interop::export::{MAX_NAMED, rfc3339_with};
use crate::sched::{Config, Direction, ItemKey, Schedulers};
use crate::study::{DayZone, Mark, Study};
use crate::text::{num, plural};

/// The CSV header, one column per field of [`Listed`]; columns are only
/// ever added at the end (`front` came with issue 25).
pub const HEADER: [&str; 15] = [
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
    "front",
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
    /// What the item asks, math rendered, on one line, in the learner's
    /// language (the config's `language`, else the deck's first).
    front: String,
}

/// One row to print, and why its due date is left blank when it cannot be
/// written (a due date stored outside the years 0–9999: RFC 3339 has four
/// digits for the year).
fn listed(
    decks: &[Deck],
    row: &ItemRow,
    now: chrono::DateTime<chrono::Utc>,
    lang: &str,
) -> (Listed, Option<String>) {
    let opt = |x: Option<f64>| x.map(num::show).unwrap_or_default();
    let (due, bad_due) = match row
        .due()
        .map(|d| rfc3339_with(d, chrono::SecondsFormat::Secs))
    {
        None => (String::new(), None),
        Some(Ok(text)) => (text, None),
        Some(Err(year)) => (String::new(), Some(year)),
    };
    let listed = Listed {
        deck: row.deck_id(decks).to_string(),
        card: row.card_id(decks).to_string(),
        direction: row.direction.as_str().into_owned(),
        state: row.state_name(),
        due,
        stability: opt(row.state.and_then(|s| s.stability)),
        difficulty: opt(row.state.and_then(|s| s.difficulty)),
        retrievability: opt(row.retrievability),
        reviews: row.reviews,
        lapses: row.lapses,
        suspended: row.status.suspended,
        buried: row.buried(now),
        leech: row.status.leech,
        tags: row.tags(decks).join(" "),
        front: crate::text::safe::one_line(&row.text(decks, lang)).into_owned(),
    };
    let why = bad_due.map(|year| {
        format!(
            "{}/{}/{}: its due date is stored in the year {year}, which RFC 3339 cannot write; left blank",
            listed.deck, listed.card, listed.direction
        )
    });
    (listed, why)
}

/// The query's words and the format. A query may start with `-` (`cards
/// list -tag:T`), and then clap takes every word after it as the query's,
/// flags too: a `--format F` among them is the flag (given once), and any
/// other word that starts with `--` is refused, never searched for.
fn query_and_format(list: &CardsListArgs) -> anyhow::Result<(Vec<String>, CardsFormat)> {
    use clap::ValueEnum as _;
    let mut words = Vec::new();
    let mut format = None;
    let mut it = list.query.iter();
    while let Some(w) = it.next() {
        let value = match w.strip_prefix("--format") {
            Some("") => Some(it.next().map(String::as_str).unwrap_or_default()),
            Some(v) if v.starts_with('=') => Some(&v[1..]),
            _ => None,
        };
        if let Some(v) = value {
            let f = CardsFormat::from_str(v, false).map_err(|_| {
                anyhow::anyhow!(
                    "--format {}: expected csv or json",
                    crate::text::safe::one_line(v)
                )
            })?;
            if format.replace(f).is_some() || list.format != CardsFormat::Csv {
                anyhow::bail!("--format is given twice");
            }
            continue;
        }
        if w.starts_with("--") && w.len() > 2 {
            anyhow::bail!(
                "{} after a query that starts with `-` is read as part of the query; give flags first: flipcard [OPTIONS] cards list [--format F] QUERY",
                crate::text::safe::one_line(w)
            );
        }
        words.push(w.clone());
    }
    Ok((words, format.unwrap_or(list.format)))
}

pub fn run(cli: &Cli, args: &CardsArgs) -> anyhow::Result<ExitCode> {
    let config = Config::load(paths::config_file(cli.config.clone()).as_deref())?;
    let now = crate::cmd::clock::now()?;
    let loaded = load_decks(cli);
    let decks = &loaded.decks;
    match &args.command {
        CardsCommand::List(list) => {
            let (query, format) = query_and_format(list)?;
            let query = query.join(" ");
            let filter = Filter::parse(&query)?;
            filter.check_names(decks)?;
            let store = open_store_read_only(cli)?;
            let rows = catalog::rows(decks, &store, &Schedulers::new(&config), now)?;
            let mut search = Search::for_filter(&filter, decks, &rows);
            let picked = select(decks, &rows, &mut search, &filter, now);
            if picked.is_empty() && !query.trim().is_empty() {
                crate::errln!("flipcard: no item matches `{}`", query.trim());
            }
            let mut out = crate::cmd::output::stdout();
            let mut bad = Vec::new();
            let mut each = picked.iter().map(|&i| {
                let deck = &decks[rows[i].deck];
                let lang = if deck.languages.iter().any(|l| l.as_str() == config.language) {
                    config.language.as_str()
                } else {
                    deck.languages.first().map_or("en", |l| l.as_str())
                };
                let (row, why) = listed(decks, &rows[i], now, lang);
                bad.extend(why);
                row
            });
            match format {
                CardsFormat::Csv => {
                    let mut w = csv::WriterBuilder::new()
                        .has_headers(false)
                        .from_writer(&mut out);
                    w.write_record(HEADER)?;
                    for row in &mut each {
                        w.serialize(row)?;
                    }
                    w.flush()?;
                }
                CardsFormat::Json => {
                    let all: Vec<Listed> = each.collect();
                    serde_json::to_writer_pretty(&mut out, &all)?;
                    writeln!(out)?;
                }
            }
            out.flush()?;
            drop(out);
            if bad.is_empty() {
                return Ok(ExitCode::SUCCESS);
            }
            for why in bad.iter().take(MAX_NAMED) {
                crate::errln!("flipcard: {why}");
            }
            if bad.len() > MAX_NAMED {
                crate::errln!("flipcard: … and {} more", bad.len() - MAX_NAMED);
            }
            crate::errln!(
                "flipcard: error: {} with a due date that cannot be written (stored by an import before dates were checked)",
                plural(bad.len(), "item", "items")
            );
            Ok(ExitCode::FAILURE)
        }
        CardsCommand::Suspend(items)
        | CardsCommand::Unsuspend(items)
        | CardsCommand::Bury(items) => {
            let (mark, done) = match &args.command {
                CardsCommand::Suspend(_) => (Mark::Suspend, "suspended"),
                CardsCommand::Unsuspend(_) => (Mark::Unsuspend, "unsuspended"),
                _ => (Mark::Bury, "buried until the next day starts"),
            };
            // Every item is resolved before anything is written: one
            // unknown item and nothing changes. An item named twice (or a
            // card and one of its directions) is changed once: each change
            // is an event, and each event of an item makes the next one
            // slower to apply.
            let index = Index::new(decks);
            let mut keys = Vec::new();
            let mut seen = HashSet::new();
            let mut named = HashSet::new();
            for item in &items.items {
                if !named.insert(item.as_str()) {
                    continue;
                }
                for key in index.resolve(item)? {
                    if seen.insert(key.clone()) {
                        keys.push(key);
                    }
                }
            }
            let mut study = Study::new(config, DayZone::Local, open_store(cli)?);
            study.mark(&keys, mark, now)?;
            crate::outln!("{done}: {}", plural(keys.len(), "item", "items"))?;
            Ok(ExitCode::SUCCESS)
        }
    }
}

/// The cards of the decks by deck and card id, so that a long list of
/// items is resolved in time linear in its length.
struct Index<'a> {
    /// Per deck, each card's (and derivation's) id with its directions.
    decks: HashMap<&'a str, HashMap<&'a str, Vec<Direction>>>,
}

impl<'a> Index<'a> {
    fn new(decks: &'a [Deck]) -> Index<'a> {
        let mut index: HashMap<&str, HashMap<&str, Vec<Direction>>> = HashMap::new();
        for d in decks {
            let cards = index.entry(d.id.as_str()).or_default();
            for c in &d.cards {
                cards
                    .entry(c.id.as_str())
                    .or_insert_with(|| catalog::card_directions(c));
            }
            for x in &d.derivations {
                cards
                    .entry(x.id.as_str())
                    .or_insert_with(|| vec![Direction::Derive]);
            }
            // A prompt is one item, `DECK/ID/predict` (its id may also be
            // a card's: `DECK/ID` then names both).
            for p in &d.prompts {
                cards
                    .entry(p.id.as_str())
                    .or_default()
                    .push(Direction::Predict);
            }
        }
        Index { decks: index }
    }

    /// `DECK/CARD` (every item of the card) or `DECK/CARD/DIRECTION`; a
    /// derivation or a prompt is named as a card is (`DECK/ID`,
    /// `DECK/ID/derive`, `DECK/ID/predict`).
    fn resolve(&self, item: &str) -> anyhow::Result<Vec<ItemKey>> {
        let parts: Vec<&str> = item.split('/').collect();
        let (deck_id, card_id, direction) = match parts.as_slice() {
            [d, c] => (*d, *c, None),
            [d, c, dir] => (*d, *c, Some(*dir)),
            _ => anyhow::bail!("`{item}` is not an item: write DECK/CARD or DECK/CARD/DIRECTION"),
        };
        let cards = self
            .decks
            .get(deck_id)
            .ok_or_else(|| anyhow::anyhow!("unknown item `{item}`: no deck `{deck_id}`"))?;
        let all = cards.get(card_id).cloned().ok_or_else(|| {
            anyhow::anyhow!("unknown item `{item}`: deck `{deck_id}` has no card `{card_id}`")
        })?;
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
}
