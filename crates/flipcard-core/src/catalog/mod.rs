//! Every item of every deck with its schedule and status, and the query
//! language that selects among them, as Anki's browser reads it
//! ([`self::query`]: `deck:`, `tag:`, `state:`, `is:due`, `rated:`,
//! `prop:ivl>30`, `flag:`, `or`, `-`, parentheses, `*`, and free text
//! matched fuzzily over the front and back in every language, which
//! [`self::search`] matches). The card browser, `flipcard cards` and the
//! filtered review all read items through this.

pub mod query;
pub mod search;

use std::collections::{BTreeSet, HashMap};

use chrono::{DateTime, TimeDelta, Utc};

use crate::deck::{CardKind, Deck};
use crate::sched::scheduler::ForDeck;
use crate::sched::{CardState, Direction, ItemKey, State};
use crate::store::db::Store;
use crate::store::error::StoreError;
use crate::store::status::ItemStatus;

pub use self::search::{Found, Search, SearchIndex, SearchTexts};

/// One item as the browser and `flipcard cards list` show it. Its names
/// and tags are read from the decks it was made from (fifty thousand rows
/// copy no strings).
#[derive(Debug, Clone, PartialEq)]
pub struct ItemRow {
    /// Positions of the deck in the list given and of the card in its deck
    /// (of the derivation in `Deck::derivations`, for a `derive` item).
    pub deck: usize,
    pub card: usize,
    pub direction: Direction,
    /// `None`: never rated (new).
    pub state: Option<CardState>,
    pub retrievability: Option<f64>,
    pub reviews: u32,
    pub lapses: u32,
    pub status: ItemStatus,
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
    /// The id of its deck (`decks`: those the rows were made from).
    pub fn deck_id<'a>(&self, decks: &'a [Deck]) -> &'a str {
        &decks[self.deck].id
    }
    /// The id of its card (of its prompt, for a `predict` item, or its
    /// derivation, for a `derive` item: `card` is then the position among
    /// the deck's prompts or derivations).
    pub fn card_id<'a>(&self, decks: &'a [Deck]) -> &'a str {
        match self.direction {
            Direction::Predict => &decks[self.deck].prompts[self.card].id,
            Direction::Derive => &decks[self.deck].derivations[self.card].id,
            _ => &decks[self.deck].cards[self.card].id,
        }
    }
    /// The tags of its card (or prompt, or derivation).
    pub fn tags<'a>(&self, decks: &'a [Deck]) -> &'a [String] {
        match self.direction {
            Direction::Predict => &decks[self.deck].prompts[self.card].tags,
            Direction::Derive => &decks[self.deck].derivations[self.card].tags,
            _ => &decks[self.deck].cards[self.card].tags,
        }
    }
    /// What the item asks, in `lang`, math rendered, on one line: a
    /// card's front (its back, asked backwards; the text with deletion
    /// `n` as a gap), a prompt's question (a varied one's numbers as `…`),
    /// a derivation's title. Control characters are the caller's to
    /// escape.
    pub fn text(&self, decks: &[Deck], lang: &str) -> String {
        asked(&decks[self.deck], self.direction, self.card, lang)
            .unwrap_or_default()
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ")
    }
    pub fn key(&self, decks: &[Deck]) -> ItemKey {
        ItemKey {
            deck: self.deck_id(decks).to_string(),
            card: self.card_id(decks).to_string(),
            direction: self.direction,
        }
    }
}

/// What the item `direction` of entry `index` of `deck` asks, in `lang`,
/// math rendered (line breaks kept): a card's front, its back when asked
/// backwards, the text with deletion `n` as a gap; a prompt's question (a
/// varied one's numbers as `…`); a derivation's title. `index` counts in
/// the deck's cards, prompts or derivations, as the direction says; `None`
/// past their end.
pub fn asked(deck: &Deck, direction: Direction, index: usize, lang: &str) -> Option<String> {
    let raw = match direction {
        Direction::Predict => deck.prompts.get(index)?.question_listed(lang).into_owned(),
        Direction::Derive => deck.derivations.get(index)?.title.get(lang).to_string(),
        Direction::Forward => deck.cards.get(index)?.front.get(lang).to_string(),
        Direction::Backward => deck.cards.get(index)?.back.get(lang).to_string(),
        Direction::Cloze(n) => crate::deck::cloze::front(deck.cards.get(index)?.front.get(lang), n)
            .into_iter()
            .map(|s| s.text)
            .collect(),
    };
    Some(flipcard_text::render(&raw))
}

/// What the item `key` of `deck` asks, in `lang` (the deck's first
/// language when it has not that one), math rendered, on one line; `None`
/// when the deck has no such item. Control characters are the caller's to
/// escape.
pub fn asked_item(deck: &Deck, key: &ItemKey, lang: &str) -> Option<String> {
    let index = match key.direction {
        Direction::Predict => deck.prompts.iter().position(|p| p.id == key.card),
        Direction::Derive => deck.derivations.iter().position(|x| x.id == key.card),
        _ => deck.cards.iter().position(|c| c.id == key.card),
    }?;
    let lang = if deck.languages.iter().any(|l| l.as_str() == lang) {
        lang
    } else {
        deck.languages.first().map_or("en", |l| l.as_str())
    };
    let text = asked(deck, key.direction, index, lang)?;
    Some(text.split_whitespace().collect::<Vec<_>>().join(" "))
}

/// Fills in what each leech asks ([`asked_item`]), from the deck loaded
/// that has it, control characters escaped.
pub fn name_leeches(leeches: &mut [crate::store::stats::Leech], decks: &[Deck], lang: &str) {
    for l in leeches {
        let Some(direction) = Direction::parse(&l.direction) else {
            continue;
        };
        let key = ItemKey {
            deck: l.deck.clone(),
            card: l.card.clone(),
            direction,
        };
        l.front = decks
            .iter()
            .find(|d| d.id == l.deck)
            .and_then(|d| asked_item(d, &key, lang))
            .map(|t| flipcard_text::safe::one_line(&t).into_owned());
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
        CardKind::Basic | CardKind::Typed | CardKind::Formula => vec![Direction::Forward],
    }
}

/// The items of `decks`, with their states and statuses at `now`; each
/// item's retrievability by its deck's scheduler (its preset's FSRS
/// parameters: [`crate::sched::Schedulers`]).
pub fn rows(
    decks: &[Deck],
    store: &Store,
    scheduler: &dyn ForDeck,
    now: DateTime<Utc>,
) -> Result<Vec<ItemRow>, StoreError> {
    let cached = store.cached_states()?;
    let statuses = store.statuses()?;
    let mut out = Vec::new();
    // Where the rows of each card start (cards of every deck in order),
    // then one past the last.
    let mut starts = Vec::with_capacity(decks.iter().map(|d| d.cards.len()).sum::<usize>() + 1);
    for (di, deck) in decks.iter().enumerate() {
        for (ci, card) in deck.cards.iter().enumerate() {
            starts.push(out.len());
            for direction in card_directions(card) {
                out.push(ItemRow {
                    deck: di,
                    card: ci,
                    direction,
                    state: None,
                    retrievability: None,
                    reviews: 0,
                    lapses: 0,
                    status: ItemStatus::default(),
                });
            }
        }
    }
    starts.push(out.len());
    // Then every deck's prompts, each one item (direction `predict`).
    let mut prompt_starts = Vec::with_capacity(decks.len());
    for (di, deck) in decks.iter().enumerate() {
        prompt_starts.push(out.len());
        for pi in 0..deck.prompts.len() {
            out.push(ItemRow {
                deck: di,
                card: pi,
                direction: Direction::Predict,
                state: None,
                retrievability: None,
                reviews: 0,
                lapses: 0,
                status: ItemStatus::default(),
            });
        }
    }
    // Each deck's derivations after every card, one row each.
    let mut derive_rows: Vec<HashMap<&str, usize>> = Vec::with_capacity(decks.len());
    for (di, deck) in decks.iter().enumerate() {
        let mut m = HashMap::with_capacity(deck.derivations.len());
        for (i, d) in deck.derivations.iter().enumerate() {
            m.entry(d.id.as_str()).or_insert(out.len());
            out.push(ItemRow {
                deck: di,
                card: i,
                direction: Direction::Derive,
                state: None,
                retrievability: None,
                reviews: 0,
                lapses: 0,
                status: ItemStatus::default(),
            });
        }
        derive_rows.push(m);
    }
    // The store's items are found among the rows by name: a map of the
    // card ids of a deck is made when the store first names that deck.
    let mut find = RowFinder::new(decks, &starts, derive_rows);
    find.prompt_starts = prompt_starts;
    for c in &cached {
        if let Some(row) = find.row(&out, &c.key) {
            let state = c.state;
            let row = &mut out[row];
            row.state = Some(state);
            row.retrievability = (state.state != State::New)
                .then(|| scheduler.for_deck(&c.key.deck).retrievability(&state, now));
            row.reviews = c.reps;
            row.lapses = c.lapses;
        }
    }
    for (key, status) in &statuses {
        if let Some(row) = find.row(&out, key) {
            out[row].status = *status;
        }
    }
    Ok(out)
}

/// Finds the row of an item named by the store.
struct RowFinder<'a> {
    decks: &'a [Deck],
    starts: &'a [usize],
    /// Per deck: its position among every card of `decks`, and its cards
    /// by id (made when first needed).
    first: Vec<usize>,
    cards: Vec<Option<HashMap<&'a str, usize>>>,
    /// Per deck: the row of its first prompt.
    prompt_starts: Vec<usize>,
    /// Per deck: the row of each derivation, by id.
    derivations: Vec<HashMap<&'a str, usize>>,
}

impl<'a> RowFinder<'a> {
    fn new(
        decks: &'a [Deck],
        starts: &'a [usize],
        derivations: Vec<HashMap<&'a str, usize>>,
    ) -> RowFinder<'a> {
        let mut first = Vec::with_capacity(decks.len());
        let mut n = 0;
        for d in decks {
            first.push(n);
            n += d.cards.len();
        }
        RowFinder {
            decks,
            starts,
            first,
            cards: vec![None; decks.len()],
            prompt_starts: Vec::new(),
            derivations,
        }
    }

    fn row(&mut self, rows: &[ItemRow], key: &ItemKey) -> Option<usize> {
        let d = self.decks.iter().position(|d| d.id == key.deck)?;
        if key.direction == Direction::Derive {
            return self.derivations[d].get(key.card.as_str()).copied();
        }
        let deck = &self.decks[d];
        if key.direction == Direction::Predict {
            let i = deck.prompts.iter().position(|p| p.id == key.card)?;
            return Some(self.prompt_starts.get(d)? + i);
        }
        let cards = self.cards[d].get_or_insert_with(|| {
            let mut m = HashMap::with_capacity(deck.cards.len());
            for (i, c) in deck.cards.iter().enumerate() {
                m.entry(c.id.as_str()).or_insert(i);
            }
            m
        });
        let g = self.first[d] + *cards.get(key.card.as_str())?;
        (self.starts[g]..self.starts[g + 1]).find(|&r| rows[r].direction == key.direction)
    }
}

/// A parsed query: every condition must hold.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Filter {
    /// Deck patterns (`deck:`, see [`query::deck_matches`]): any of them.
    pub decks: Vec<String>,
    /// Tag patterns (`tag:`, see [`query::tag_matches`]): all of them.
    pub tags: Vec<String>,
    /// `new`, `learning`, `review`, `relearning`, `suspended`, `leech`,
    /// `buried`: any of them.
    pub states: Vec<String>,
    pub due_within: Option<TimeDelta>,
    /// Free text, matched fuzzily (best match first).
    pub text: String,
    /// Every other term of a typed query (`is:`, `rated:`, `prop:`,
    /// `flag:`, `or`, `-`, parentheses, text with `*` or in quotes): all
    /// of them.
    pub terms: Vec<query::Expr>,
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

pub use self::query::FIELDS;

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
    /// Parses a query ([`query::parse`]): the terms at its top level that
    /// the fields hold go there (plain words into the fuzzy text), the rest
    /// into `terms`. Errors name the column.
    pub fn parse(text: &str) -> Result<Filter, QueryError> {
        use query::Expr;
        let mut f = Filter::default();
        let top = match query::parse(text)? {
            Expr::All(xs) => xs,
            x => vec![x],
        };
        let mut words = Vec::new();
        for x in top {
            match x {
                Expr::Text {
                    text,
                    quoted: false,
                } if !text.contains('*') => words.push(text),
                Expr::Deck(d) => f.decks.push(d),
                Expr::Tag(t) => f.tags.push(t),
                Expr::State(s) => f.states.push(s),
                Expr::DueWithin(d) if f.due_within.is_none() => f.due_within = Some(d),
                other => f.terms.push(other),
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

    /// Whether the filter asks for suspended items (by `state:` or an `is:`
    /// that must hold).
    pub fn asks_suspended(&self) -> bool {
        self.states.iter().any(|s| s == "suspended")
            || self
                .terms
                .iter()
                .any(|t| matches!(t, query::Expr::Is(s) if s == "suspended"))
    }

    /// The text terms in `terms` (each matched by the search before the
    /// rows are kept: see [`search::select`]).
    pub fn text_terms(&self) -> Vec<(&str, bool)> {
        let mut out = Vec::new();
        for t in &self.terms {
            t.texts(&mut out);
        }
        out
    }

    /// Whether the filter needs the search index (it has text).
    pub fn needs_index(&self) -> bool {
        !self.text.trim().is_empty() || !self.text_terms().is_empty()
    }

    /// Names in the filter no deck knows (a deck or tag pattern that
    /// matches none): a filter that can never match is an error the learner
    /// should see, not an empty list.
    pub fn check_names(&self, decks: &[Deck]) -> Result<(), QueryError> {
        for d in &self.decks {
            if !(0..decks.len()).any(|i| query::deck_matches(d, decks, i)) {
                let ids: Vec<&str> = decks.iter().map(|x| x.id.as_str()).collect();
                return Err(QueryError(format!(
                    "no deck `{d}`; decks are {}",
                    ids.join(", ")
                )));
            }
        }
        // The tags of every card and derivation.
        let tagged = || {
            decks.iter().flat_map(|d| {
                d.cards
                    .iter()
                    .map(|c| &c.tags)
                    .chain(d.derivations.iter().map(|x| &x.tags))
                    .chain(d.prompts.iter().map(|x| &x.tags))
            })
        };
        for t in &self.tags {
            // Checked item by item, stopping at the first that has it: the
            // list of every tag is made only for the error.
            if tagged().any(|tags| tags.iter().any(|x| query::tag_matches(t, x))) {
                continue;
            }
            let known: BTreeSet<&str> = tagged()
                .flat_map(|tags| tags.iter().map(String::as_str))
                .collect();
            let list: Vec<&str> = known.into_iter().collect();
            return Err(QueryError(if list.is_empty() {
                format!("no card has tag `{t}` (no card has any tag)")
            } else {
                format!("no card has tag `{t}`; tags are {}", list.join(", "))
            }));
        }
        Ok(())
    }

    /// Whether row `i` of `rows` passes every condition but the free text;
    /// `hits` answers the text terms (`query::NoText` when there are none).
    pub fn keeps(
        &self,
        i: usize,
        rows: &[ItemRow],
        decks: &[Deck],
        now: DateTime<Utc>,
        hits: &dyn query::TextHits,
    ) -> bool {
        let row = &rows[i];
        if !self.decks.is_empty()
            && !self
                .decks
                .iter()
                .any(|d| query::deck_matches(d, decks, row.deck))
        {
            return false;
        }
        if !self
            .tags
            .iter()
            .all(|t| row.tags(decks).iter().any(|x| query::tag_matches(t, x)))
        {
            return false;
        }
        if !self.states.is_empty() && !self.states.iter().any(|s| query::state_holds(s, row, now)) {
            return false;
        }
        if let Some(within) = self.due_within {
            match row.due() {
                Some(due) if due <= now + within => {}
                _ => return false,
            }
        }
        if !self.terms.is_empty() {
            let cx = query::Ctx {
                rows,
                decks,
                now,
                hits,
            };
            return self.terms.iter().all(|t| t.holds(i, &cx));
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::catalog::search::Search;

    #[test]
    fn queries_parse_into_fields_and_free_text() {
        let f = Filter::parse("deck:rot tag:euler  omega2 due:<3d is:leech state:new").unwrap();
        assert_eq!(f.decks, ["rot"]);
        assert_eq!(f.tags, ["euler"]);
        assert_eq!(f.states, ["new"]);
        assert_eq!(f.terms, [query::Expr::Is("leech".into())]);
        assert_eq!(f.due_within, Some(TimeDelta::days(3)));
        assert_eq!(f.text, "omega2");
        for (bad, says) in [
            ("state:sleeping", "at column 7: unknown state `sleeping`"),
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
            "/../../tests/decks/study/decks"
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
        let sched = crate::sched::Scheduler::new(&crate::sched::Config::default());
        let now = chrono::Utc::now();
        let rows = rows(decks, &store, &sched, now).unwrap();
        assert_eq!(rows.len(), 6, "3 cloze numbers, 2 directions, 1 basic");
        let mut search = Search::new(decks, &rows);
        let all: Vec<usize> = (0..rows.len()).collect();
        let cards = |search: &mut Search, q: &str| -> BTreeSet<String> {
            search
                .matching(q, &all)
                .best
                .into_iter()
                .map(|i| rows[i].card_id(decks).to_string())
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
