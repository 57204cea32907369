//! Every item of every deck with its schedule and status, and the query
//! language that selects among them (`deck:`, `tag:`, `state:`, `due:<3d`,
//! `is:leech`, `is:suspended`, `is:buried`, and free text matched fuzzily
//! over the front and back in every language). The card browser, `flipcard
//! cards` and the filtered review all read items through this.

use std::collections::{BTreeSet, HashMap};

use chrono::{DateTime, TimeDelta, Utc};
use nucleo_matcher::pattern::{CaseMatching, Normalization, Pattern};
use nucleo_matcher::{Matcher, Utf32String};

use super::db::Store;
use super::error::StoreError;
use super::status::ItemStatus;
use crate::deck::{CardKind, Deck};
use crate::sched::{CardState, Direction, ItemKey, Scheduler, State};

/// One item as the browser and `flipcard cards list` show it.
#[derive(Debug, Clone)]
pub struct ItemRow {
    pub key: ItemKey,
    /// Positions of the deck in the list given and of the card in its deck.
    pub deck: usize,
    pub card: usize,
    /// `None`: never rated (new).
    pub state: Option<CardState>,
    pub retrievability: Option<f64>,
    pub reviews: u32,
    pub lapses: u32,
    pub status: ItemStatus,
    pub tags: Vec<String>,
}

impl ItemRow {
    pub fn state_name(&self) -> &'static str {
        state_name(self.state.map_or(State::New, |s| s.state))
    }
    pub fn due(&self) -> Option<DateTime<Utc>> {
        self.state.filter(|s| s.state != State::New).map(|s| s.due)
    }
    pub fn buried(&self, now: DateTime<Utc>) -> bool {
        self.status.buried(now)
    }
}

pub fn state_name(s: State) -> &'static str {
    match s {
        State::New => "new",
        State::Learning => "learning",
        State::Review => "review",
        State::Relearning => "relearning",
    }
}

/// The items of a card in order (as the queue asks them).
pub fn card_directions(card: &crate::deck::Card) -> Vec<Direction> {
    match card.kind {
        CardKind::Cloze => card
            .cloze_numbers()
            .into_iter()
            .map(Direction::Cloze)
            .collect(),
        CardKind::Reversed => vec![Direction::Forward, Direction::Backward],
        CardKind::Basic | CardKind::Typed => vec![Direction::Forward],
    }
}

/// What free text is searched in for each card, as written, one field
/// each: its id, then per language its front and back together. A match
/// must lie within one field: letters strewn over a whole card in both
/// languages are no match.
pub fn card_fields(card: &crate::deck::Card) -> Vec<String> {
    let mut fields = vec![card.id.clone()];
    let langs: BTreeSet<&String> = card.front.0.keys().chain(card.back.0.keys()).collect();
    for lang in langs {
        let front = card.front.0.get(lang).map_or("", String::as_str);
        let front = if card.kind == CardKind::Cloze {
            crate::deck::cloze::revealed(front)
        } else {
            front.to_string()
        };
        let back = card.back.0.get(lang).map_or("", String::as_str);
        fields.push(format!("{front} {back}"));
    }
    fields
}

/// A field as searched: rendered (`ω₂`) and, when it holds math, also as
/// written (`\omega_2`), so that `omega2` and `ω₂` both find it.
fn searched(written: &str) -> Utf32String {
    let mut field = crate::text::render(written);
    if written.contains('$') {
        field.push(' ');
        field.push_str(written);
    }
    Utf32String::from(field)
}

/// The least score (per character of the query) a fuzzy match needs: a
/// run of letters scores about 25 a character, letters strewn over a long
/// text far less.
const MIN_SCORE_PER_CHAR: u32 = 10;

/// The items of `decks`, with their states and statuses at `now`.
pub fn rows(
    decks: &[Deck],
    store: &Store,
    scheduler: &Scheduler,
    now: DateTime<Utc>,
) -> Result<Vec<ItemRow>, StoreError> {
    let cached: HashMap<ItemKey, super::CachedState> = store
        .cached_states()?
        .into_iter()
        .map(|c| (c.key.clone(), c))
        .collect();
    let statuses = store.statuses()?;
    let mut out = Vec::new();
    for (di, deck) in decks.iter().enumerate() {
        for (ci, card) in deck.cards.iter().enumerate() {
            for direction in card_directions(card) {
                let key = ItemKey {
                    deck: deck.id.clone(),
                    card: card.id.clone(),
                    direction,
                };
                let c = cached.get(&key);
                let state = c.map(|c| c.state);
                out.push(ItemRow {
                    deck: di,
                    card: ci,
                    retrievability: state
                        .filter(|s| s.state != State::New)
                        .map(|s| scheduler.retrievability(&s, now)),
                    reviews: c.map_or(0, |c| c.reps),
                    lapses: c.map_or(0, |c| c.lapses),
                    status: statuses.get(&key).copied().unwrap_or_default(),
                    tags: card.tags.clone(),
                    state,
                    key,
                });
            }
        }
    }
    Ok(out)
}

/// A parsed query: every condition must hold.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Filter {
    pub decks: Vec<String>,
    pub tags: Vec<String>,
    /// `new`, `learning`, `review`, `relearning`, `suspended`, `leech`,
    /// `buried`: any of them.
    pub states: Vec<String>,
    pub due_within: Option<TimeDelta>,
    /// Free text, matched fuzzily.
    pub text: String,
}

/// The values `state:` (and `--state`) accepts.
pub const STATES: [&str; 7] = [
    "new",
    "learning",
    "review",
    "relearning",
    "suspended",
    "leech",
    "buried",
];

/// The filter fields of the query language.
pub const FIELDS: [&str; 5] = ["deck:", "tag:", "state:", "due:", "is:"];

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct QueryError(pub String);

/// `3d`, `12h`, `30m`, `2w`: a span of time.
pub fn parse_span(text: &str) -> Result<TimeDelta, QueryError> {
    let bad = || {
        QueryError(format!(
            "`{text}` is not a span of time: write a whole number and a unit, as 3d, 12h, 2w"
        ))
    };
    let split = text.find(|c: char| !c.is_ascii_digit()).ok_or_else(bad)?;
    let (n, unit) = text.split_at(split);
    let n: i64 = n.parse().map_err(|_| bad())?;
    if n > 100_000 {
        return Err(bad());
    }
    match unit {
        "m" => Ok(TimeDelta::minutes(n)),
        "h" => Ok(TimeDelta::hours(n)),
        "d" => Ok(TimeDelta::days(n)),
        "w" => Ok(TimeDelta::weeks(n)),
        _ => Err(bad()),
    }
}

impl Filter {
    /// Parses a query. Unknown fields, states and malformed spans are
    /// errors naming what is accepted.
    pub fn parse(query: &str) -> Result<Filter, QueryError> {
        let mut f = Filter::default();
        let mut words = Vec::new();
        for word in query.split_whitespace() {
            let Some((field, value)) = word.split_once(':') else {
                words.push(word);
                continue;
            };
            if field.is_empty() || !field.chars().all(|c| c.is_ascii_alphabetic()) {
                words.push(word);
                continue;
            }
            let need = |what: &str| {
                if value.is_empty() {
                    Err(QueryError(format!("`{field}:` needs {what}")))
                } else {
                    Ok(value.to_string())
                }
            };
            match field {
                "deck" => f.decks.push(need("a deck id")?),
                "tag" => f.tags.push(need("a tag")?),
                "state" | "is" => {
                    let v = need("a state")?;
                    f.add_state(&v)?;
                }
                "due" => {
                    let span = value.strip_prefix('<').ok_or_else(|| {
                        QueryError(format!(
                            "`due:{value}`: write due:<3d for items due within three days"
                        ))
                    })?;
                    f.due_within = Some(parse_span(span)?);
                }
                other => {
                    return Err(QueryError(format!(
                        "unknown filter `{other}:`; filters are {}",
                        FIELDS.join(" ")
                    )));
                }
            }
        }
        f.text = words.join(" ");
        Ok(f)
    }

    pub fn add_state(&mut self, v: &str) -> Result<(), QueryError> {
        if !STATES.contains(&v) {
            return Err(QueryError(format!(
                "unknown state `{v}`; states are {}",
                STATES.join(", ")
            )));
        }
        self.states.push(v.to_string());
        Ok(())
    }

    /// Whether the filter asks for anything at all.
    pub fn is_empty(&self) -> bool {
        *self == Filter::default()
    }

    /// Names in the filter no deck knows (a deck id or tag): a filter that
    /// can never match is an error the learner should see, not an empty
    /// list.
    pub fn check_names(&self, decks: &[Deck]) -> Result<(), QueryError> {
        for d in &self.decks {
            if !decks.iter().any(|x| &x.id == d) {
                let ids: Vec<&str> = decks.iter().map(|x| x.id.as_str()).collect();
                return Err(QueryError(format!(
                    "no deck `{d}`; decks are {}",
                    ids.join(", ")
                )));
            }
        }
        let known: BTreeSet<&str> = decks
            .iter()
            .flat_map(|d| {
                d.cards
                    .iter()
                    .flat_map(|c| c.tags.iter().map(String::as_str))
            })
            .collect();
        for t in &self.tags {
            if !known.contains(t.as_str()) {
                let list: Vec<&str> = known.iter().copied().collect();
                return Err(QueryError(if list.is_empty() {
                    format!("no card has tag `{t}` (no card has any tag)")
                } else {
                    format!("no card has tag `{t}`; tags are {}", list.join(", "))
                }));
            }
        }
        Ok(())
    }

    /// Whether `row` passes every condition but the free text.
    pub fn keeps(&self, row: &ItemRow, decks: &[Deck], now: DateTime<Utc>) -> bool {
        if !self.decks.is_empty() && !self.decks.iter().any(|d| decks[row.deck].id == *d) {
            return false;
        }
        if !self.tags.iter().all(|t| row.tags.contains(t)) {
            return false;
        }
        if !self.states.is_empty()
            && !self.states.iter().any(|s| match s.as_str() {
                "suspended" => row.status.suspended,
                "leech" => row.status.leech,
                "buried" => row.buried(now),
                name => row.state_name() == name,
            })
        {
            return false;
        }
        if let Some(within) = self.due_within {
            match row.due() {
                Some(due) if due <= now + within => {}
                _ => return false,
            }
        }
        true
    }
}

/// The texts a [`Search`] is built from, gathered from the decks (cheap);
/// building renders the math of every card (the costly part, which the
/// browser does on a thread of its own while its first frame shows).
pub struct SearchTexts {
    cards: Vec<Vec<String>>,
    card_of_row: Vec<u32>,
}

impl SearchTexts {
    pub fn new(decks: &[Deck], rows: &[ItemRow]) -> SearchTexts {
        let mut index: HashMap<(usize, usize), u32> = HashMap::new();
        let mut cards = Vec::new();
        let card_of_row = rows
            .iter()
            .map(|r| {
                *index.entry((r.deck, r.card)).or_insert_with(|| {
                    cards.push(card_fields(&decks[r.deck].cards[r.card]));
                    (cards.len() - 1) as u32
                })
            })
            .collect();
        SearchTexts { cards, card_of_row }
    }

    /// The search index; `None` when `cancel` was set meanwhile.
    pub fn build(self, cancel: &std::sync::atomic::AtomicBool) -> Option<Search> {
        let mut cards = Vec::with_capacity(self.cards.len());
        for fields in self.cards {
            if cancel.load(std::sync::atomic::Ordering::Relaxed) {
                return None;
            }
            cards.push(fields.iter().map(|f| searched(f)).collect());
        }
        Some(Search {
            cards,
            card_of_row: self.card_of_row,
            matcher: Matcher::new(nucleo_matcher::Config::DEFAULT),
        })
    }
}

/// Free-text search over many items: each card's fields are converted
/// once, then every query is a pass of the fuzzy matcher over the cards
/// (an item shares its card's score).
pub struct Search {
    cards: Vec<Vec<Utf32String>>,
    card_of_row: Vec<u32>,
    matcher: Matcher,
}

/// What [`Search::matching`] found.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Found {
    /// The rows that match well enough, best first.
    pub best: Vec<usize>,
    /// Every row the pattern matches at all, in the order given: a query
    /// that extends this one can only match among these.
    pub any: Vec<usize>,
}

impl Search {
    pub fn new(decks: &[Deck], rows: &[ItemRow]) -> Search {
        let never = std::sync::atomic::AtomicBool::new(false);
        SearchTexts::new(decks, rows)
            .build(&never)
            .unwrap_or_else(|| Search {
                cards: Vec::new(),
                card_of_row: Vec::new(),
                matcher: Matcher::new(nucleo_matcher::Config::DEFAULT),
            })
    }

    /// The rows among `candidates` whose text matches `text`.
    pub fn matching(&mut self, text: &str, candidates: &[usize]) -> Found {
        if text.trim().is_empty() {
            return Found {
                best: candidates.to_vec(),
                any: candidates.to_vec(),
            };
        }
        let pattern = Pattern::parse(text, CaseMatching::Ignore, Normalization::Smart);
        let chars = text.chars().filter(|c| !c.is_whitespace()).count() as u32;
        let least = MIN_SCORE_PER_CHAR * chars;
        let matcher = &mut self.matcher;
        let mut last: Option<(u32, Option<u32>)> = None;
        let mut any = Vec::new();
        let mut scored: Vec<(u32, usize)> = Vec::new();
        for &i in candidates {
            let card = self.card_of_row[i];
            // The items of a card come one after another: score it once.
            let score = match last {
                Some((c, s)) if c == card => s,
                _ => {
                    let s = self.cards[card as usize]
                        .iter()
                        .filter_map(|h| pattern.score(h.slice(..), matcher))
                        .max();
                    last = Some((card, s));
                    s
                }
            };
            if let Some(s) = score {
                any.push(i);
                if s >= least {
                    scored.push((s, i));
                }
            }
        }
        scored.sort_unstable_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
        Found {
            best: scored.into_iter().map(|(_, i)| i).collect(),
            any,
        }
    }
}

/// The rows a query selects, best match first when it has free text.
pub fn select(
    decks: &[Deck],
    rows: &[ItemRow],
    search: &mut Search,
    filter: &Filter,
    now: DateTime<Utc>,
) -> Vec<usize> {
    let kept: Vec<usize> = (0..rows.len())
        .filter(|&i| filter.keeps(&rows[i], decks, now))
        .collect();
    search.matching(&filter.text, &kept).best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn queries_parse_into_fields_and_free_text() {
        let f = Filter::parse("deck:rot tag:euler  omega2 due:<3d is:leech state:new").unwrap();
        assert_eq!(f.decks, ["rot"]);
        assert_eq!(f.tags, ["euler"]);
        assert_eq!(f.states, ["leech", "new"]);
        assert_eq!(f.due_within, Some(TimeDelta::days(3)));
        assert_eq!(f.text, "omega2");
        for (bad, says) in [
            ("state:sleeping", "unknown state `sleeping`"),
            ("colour:red", "unknown filter `colour:`"),
            ("due:3d", "due:<3d"),
            ("due:<3x", "not a span"),
            ("tag:", "needs a tag"),
        ] {
            let e = Filter::parse(bad).unwrap_err();
            assert!(e.0.contains(says), "{bad}: {e}");
        }
        // A colon after something that is not a field name is text.
        assert_eq!(Filter::parse("L_z:1 x").unwrap().text, "L_z:1 x");
    }

    fn deck() -> Deck {
        let loaded = crate::deck::load_dir(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/decks/study/decks"
        )));
        loaded
            .decks
            .into_iter()
            .next()
            .expect("the study deck loads")
    }

    #[test]
    fn search_finds_math_as_written_and_as_rendered_within_one_field() {
        let d = deck();
        let decks = std::slice::from_ref(&d);
        let dir = tempfile::tempdir().unwrap();
        let store = Store::open(dir.path()).unwrap();
        let sched = Scheduler::new(&crate::sched::Config::default());
        let now = crate::sched::clock::now().unwrap();
        let rows = rows(decks, &store, &sched, now).unwrap();
        assert_eq!(rows.len(), 6, "3 cloze numbers, 2 directions, 1 basic");
        let mut search = Search::new(decks, &rows);
        let all: Vec<usize> = (0..rows.len()).collect();
        let cards = |search: &mut Search, q: &str| -> BTreeSet<String> {
            search
                .matching(q, &all)
                .best
                .into_iter()
                .map(|i| rows[i].key.card.clone())
                .collect()
        };
        for q in ["omega2", "ω₂", "omega_2", "vec L"] {
            assert_eq!(
                cards(&mut search, q),
                BTreeSet::from(["torque-rate".to_string()]),
                "{q}"
            );
        }
        // Letters of `spin` strewn over the long cloze text are no match.
        assert_eq!(
            cards(&mut search, "spin"),
            BTreeSet::from(["spin-axis".to_string(), "middle".to_string()])
        );
        assert!(cards(&mut search, "zzqx").is_empty());
        assert_eq!(Filter::parse("L_z:1 x").unwrap().text, "L_z:1 x");
    }
}
