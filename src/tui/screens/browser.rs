//! The card browser: every item of every deck as a table, sortable by any
//! column, searched as you type (free text matched fuzzily over the front
//! and back in both languages, plus `deck:`, `tag:`, `state:`, `due:<3d`,
//! `is:leech`, `is:suspended`), with suspend, bury and unsuspend on the
//! selected item. Only the rows in view are drawn, so the frame costs the
//! same with fifty or fifty thousand items.

use std::cmp::Ordering;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering as AtomicOrdering};

use chrono::{DateTime, Utc};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Margin, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Cell, Paragraph, Row, Table, TableState, Wrap};

use crate::catalog::search::{self, Search, SearchIndex, SearchTexts};
use crate::catalog::{self, Filter, ItemRow};
use crate::deck::Deck;
use crate::sched::{Direction, ItemKey};
use crate::study::Mark;
use crate::tui::action::Action;
use crate::tui::app::App;
use crate::tui::i18n::{Msg, Words};
use crate::tui::keymap::{Binding, Context};
use crate::tui::services::SearchCache;
use crate::tui::wrap::{Run, wrap};

use super::Nav;
use crossterm::event::KeyCode::{
    Backspace, Char, Down, End, Enter, Esc, Home, PageDown, PageUp, Up,
};

pub const KEYS: &[Binding] = &[
    Binding::new(
        "↑↓ j k",
        Words("choose an item", "item chuno"),
        &[
            (Up, Action::Up),
            (Down, Action::Down),
            (Char('j'), Action::Down),
            (Char('k'), Action::Up),
        ],
    ),
    Binding::new(
        "PgUp PgDn g G",
        Words("a page / top / bottom", "ek page / shuru / ant"),
        &[
            (PageUp, Action::PageUp),
            (PageDown, Action::PageDown),
            (Char('g'), Action::Top),
            (Char('G'), Action::Bottom),
            (Home, Action::Top),
            (End, Action::Bottom),
        ],
    ),
    Binding::new(
        "/",
        Words(
            "search: text deck: tag: is:due|new|leech rated:7 prop:ivl>30 or - ()",
            "khojo: text deck: tag: is:due|new|leech rated:7 prop:ivl>30 or - ()",
        ),
        &[(Char('/'), Action::StartSearch)],
    ),
    Binding::new(
        "o O",
        Words(
            "sort by the next column / reverse",
            "agle column se sort / ulta",
        ),
        &[
            (Char('o'), Action::NextSort),
            (Char('O'), Action::ReverseSort),
        ],
    ),
    Binding::new(
        "Enter",
        Words("preview the item", "item dekho"),
        &[(Enter, Action::Open)],
    ),
    Binding::new(
        "e",
        Words("open its explanation", "uska samjhaav kholo"),
        &[(Char('e'), Action::Explain)],
    ),
    super::info::OPEN,
    Binding::new(
        "s b U",
        Words(
            "suspend / bury until tomorrow / unsuspend",
            "suspend / kal tak hatao / unsuspend",
        ),
        &[
            (Char('s'), Action::Suspend),
            (Char('b'), Action::Bury),
            (Char('U'), Action::Unsuspend),
        ],
    ),
    Binding::new(
        "E A",
        Words(
            "edit the item in its deck file / add a card of its kind",
            "item uski deck file mein badlo / uski kind ka naya card jodo",
        ),
        &[(Char('E'), Action::EditItem), (Char('A'), Action::AddCard)],
    ),
    Binding::new(
        "u",
        Words(
            "undo the last suspend, bury or unsuspend",
            "pichhla suspend, bury ya unsuspend wapas lo",
        ),
        &[(Char('u'), Action::Undo)],
    ),
    Binding::new(
        "Esc q",
        Words("close the preview / back", "preview band karo / wapas"),
        &[(Esc, Action::Back), (Char('q'), Action::Back)],
    ),
];

/// While the query is typed.
pub const SEARCH_KEYS: &[Binding] = &[
    Binding::typing(Words(
        "the query (the list follows each key)",
        "query (har key ke saath list badalti hai)",
    )),
    Binding::new(
        "Enter Esc",
        Words("done: back to the list", "ho gaya: list par wapas"),
        &[(Enter, Action::Submit), (Esc, Action::Submit)],
    ),
    Binding::new(
        "Backspace",
        Words("delete a character", "ek akshar mitao"),
        &[(Backspace, Action::Backspace)],
    ),
    Binding::new(
        "↑↓",
        Words("choose an item", "item chuno"),
        &[(Up, Action::Up), (Down, Action::Down)],
    ),
];

/// The table's columns, in order; each can be sorted by.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Column {
    Deck,
    Card,
    /// What the item asks, rendered, in the app's language.
    Question,
    Direction,
    State,
    Due,
    Stability,
    Difficulty,
    Retrievability,
    Reviews,
    Lapses,
    Status,
}

impl Column {
    pub const ALL: [Column; 12] = [
        Column::Deck,
        Column::Card,
        Column::Question,
        Column::Direction,
        Column::State,
        Column::Due,
        Column::Stability,
        Column::Difficulty,
        Column::Retrievability,
        Column::Reviews,
        Column::Lapses,
        Column::Status,
    ];

    fn title(self) -> Msg {
        match self {
            Column::Deck => Msg::ColDeck,
            Column::Card => Msg::ColCard,
            Column::Question => Msg::ColQuestion,
            Column::Direction => Msg::ColDirection,
            Column::State => Msg::ColState,
            Column::Due => Msg::ColDue,
            Column::Stability => Msg::ColStability,
            Column::Difficulty => Msg::ColDifficulty,
            Column::Retrievability => Msg::ColRetrievability,
            Column::Reviews => Msg::ColReviews,
            Column::Lapses => Msg::ColLapses,
            Column::Status => Msg::ColStatus,
        }
    }

    /// The least room the column needs (a name column: enough to tell
    /// names apart).
    fn min_width(self) -> u16 {
        match self.width() {
            Constraint::Length(n) => n,
            _ if self == Column::Card => 12,
            _ if self == Column::Question => 16,
            _ => 8,
        }
    }

    fn width(self) -> Constraint {
        match self {
            Column::Deck => Constraint::Fill(1),
            Column::Card => Constraint::Fill(2),
            Column::Question => Constraint::Fill(4),
            Column::Direction => Constraint::Length(8),
            Column::State => Constraint::Length(10),
            Column::Due => Constraint::Length(6),
            Column::Stability | Column::Difficulty | Column::Retrievability => {
                Constraint::Length(6)
            }
            Column::Reviews => Constraint::Length(4),
            Column::Lapses => Constraint::Length(6),
            Column::Status => Constraint::Length(6),
        }
    }
}

/// The columns that fit in `width` cells, in table order: the card's name
/// first, then what says where it stands, the rest as room allows
/// (columns left out can still be sorted by).
fn fitting_columns(width: u16) -> Vec<Column> {
    const PRIORITY: [Column; 12] = [
        Column::Card,
        Column::State,
        Column::Due,
        Column::Status,
        Column::Question,
        Column::Deck,
        Column::Direction,
        Column::Retrievability,
        Column::Reviews,
        Column::Lapses,
        Column::Stability,
        Column::Difficulty,
    ];
    // The selection mark takes two cells; each column one more to part it.
    let mut room = width.saturating_sub(2);
    let mut keep = Vec::new();
    for c in PRIORITY {
        let need = c.min_width() + 1;
        if need <= room || keep.is_empty() {
            room = room.saturating_sub(need);
            keep.push(c);
        }
    }
    Column::ALL
        .into_iter()
        .filter(|c| keep.contains(c))
        .collect()
}

/// The search index: built on a thread of its own when the browser opens
/// (rendering the math of every card is the slow part), so the first frame
/// does not wait for it; the first search that needs it does.
enum Index {
    Building {
        thread: Option<std::thread::JoinHandle<Option<Arc<SearchIndex>>>>,
        cancel: Arc<AtomicBool>,
        card_of_row: Vec<u32>,
    },
    Ready(Search),
}

impl Index {
    fn open(decks: &[Deck], rows: &[ItemRow], cache: &SearchCache) -> Index {
        let texts = SearchTexts::new(decks);
        let card_of_row = search::card_of_row(decks, rows);
        if let Some(index) = cache.get(&texts) {
            return Index::Ready(Search::with_index(index, card_of_row));
        }
        let cancel = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&cancel);
        let cache = cache.clone();
        let thread = std::thread::Builder::new()
            .name("search-index".into())
            .spawn(move || {
                let index = Arc::new(texts.build(&flag, search::threads())?);
                cache.put(texts, Arc::clone(&index));
                Some(index)
            })
            .ok();
        Index::Building {
            thread,
            cancel,
            card_of_row,
        }
    }

    /// Whether a search can run now without waiting for the build.
    fn ready(&self) -> bool {
        match self {
            Index::Ready(_) => true,
            Index::Building { thread, .. } => thread.as_ref().is_none_or(|t| t.is_finished()),
        }
    }

    fn get(&mut self, decks: &[Deck]) -> &mut Search {
        if let Index::Building {
            thread,
            card_of_row,
            ..
        } = self
        {
            let built = thread.take().and_then(|t| t.join().ok()).flatten();
            let card_of_row = std::mem::take(card_of_row);
            // A thread that could not start (or failed) leaves the index
            // to be built here.
            let index = built.unwrap_or_else(|| {
                let never = AtomicBool::new(false);
                Arc::new(
                    SearchTexts::new(decks)
                        .build(&never, search::threads())
                        .unwrap_or_default(),
                )
            });
            *self = Index::Ready(Search::with_index(index, card_of_row));
        }
        match self {
            Index::Ready(s) => s,
            Index::Building { .. } => unreachable!("the index was made ready above"),
        }
    }
}

impl Drop for Index {
    /// Leaving the browser before the index is built stops building it.
    fn drop(&mut self) {
        if let Index::Building { cancel, .. } = self {
            cancel.store(true, AtomicOrdering::Relaxed);
        }
    }
}

/// A query typed and what it found: a query that only adds to its text
/// can match among the rows it matched at all, no others; Backspace comes
/// back to it without searching again.
struct Step {
    query: String,
    filter: Filter,
    any: Vec<usize>,
    /// The rows shown, best match first (before any sort by column).
    best: Vec<usize>,
}

/// Steps kept for Backspace (each holds up to two lists of every row).
const STEPS: usize = 64;

/// The order of every row by one column, as a rank a row (ties in deck
/// order): sorting the rows shown is then sorting numbers.
struct Ranks {
    column: Column,
    rank: Vec<u32>,
}

pub struct BrowserState {
    pub rows: Vec<ItemRow>,
    index: Index,
    /// The queries typed, the last on top.
    steps: Vec<Step>,
    ranks: Option<Ranks>,
    /// The query as typed.
    pub query: String,
    /// Typing the query (`/`).
    pub typing: bool,
    /// Rows shown, as indices into `rows`, in display order.
    pub shown: Vec<usize>,
    pub selected: usize,
    /// `None`: deck order, or best match first while searching.
    pub sort: Option<(Column, bool)>,
    /// What is wrong with the query, shown instead of a silent empty list.
    pub error: Option<String>,
    pub preview: bool,
    /// Suspends, buries and unsuspends made here, for undo.
    pub marks: usize,
    /// When the rows were read: due times and retrievability are as of then.
    pub now: DateTime<Utc>,
    /// Table rows in view at the last draw (for PgUp / PgDn).
    pub page: std::cell::Cell<usize>,
    /// A query with text typed before the search index was built (the
    /// first opening): the key is drawn at once, the search runs on the
    /// tick that finds the index ready.
    pub waiting: bool,
}

impl BrowserState {
    pub fn open(app: &App) -> Result<BrowserState, String> {
        let now = app.services.now();
        let rows = catalog::rows(
            &app.decks,
            &app.services.study.store,
            &app.services.study.schedulers(),
            now,
        )
        .map_err(|e| e.to_string())?;
        let index = Index::open(&app.decks, &rows, &app.services.browser_index);
        let mut state = BrowserState {
            shown: (0..rows.len()).collect(),
            rows,
            index,
            steps: Vec::new(),
            ranks: None,
            query: String::new(),
            typing: false,
            selected: 0,
            sort: None,
            error: None,
            preview: false,
            marks: 0,
            now,
            page: std::cell::Cell::new(10),
            waiting: false,
        };
        state.refilter(&app.decks);
        Ok(state)
    }

    /// Applies the query and the sort again (after each key of the search).
    pub fn refilter(&mut self, decks: &[Deck]) {
        // Steps of queries this one does not extend are done with; one
        // equal to it is its answer (Backspace).
        while let Some(top) = self.steps.last() {
            if top.query == self.query {
                self.error = None;
                self.waiting = false;
                self.shown = top.best.clone();
                self.sort_rows(decks);
                self.selected = self.selected.min(self.shown.len().saturating_sub(1));
                return;
            }
            if self.query.starts_with(&top.query) {
                break;
            }
            self.steps.pop();
        }
        let filter = Filter::parse(&self.query).and_then(|f| {
            f.check_names(decks)?;
            Ok(f)
        });
        match filter {
            Ok(f) => {
                self.error = None;
                self.waiting = f.needs_index() && !self.index.ready();
                if self.waiting {
                    return;
                }
                let step = self.select(decks, f);
                self.shown = step.best.clone();
                if self.steps.len() == STEPS {
                    self.steps.remove(0);
                }
                self.steps.push(step);
            }
            // The list stays as it was while the query is being written.
            Err(e) => {
                self.error = Some(e.0);
                self.waiting = false;
            }
        }
        self.sort_rows(decks);
        self.selected = self.selected.min(self.shown.len().saturating_sub(1));
    }

    /// The rows `f` selects, narrowing the last search when it can.
    fn select(&mut self, decks: &[Deck], f: Filter) -> Step {
        let text = f.text.clone();
        let fields = Filter {
            text: String::new(),
            ..f.clone()
        };
        let narrowed = self.steps.last().and_then(|last| {
            let same = Filter {
                text: String::new(),
                ..last.filter.clone()
            } == fields
                && text.starts_with(&last.filter.text);
            same.then(|| last.any.clone())
        });
        let candidates = narrowed.unwrap_or_else(|| {
            if fields.is_empty() {
                (0..self.rows.len()).collect()
            } else {
                let hits = if fields.needs_index() {
                    search::Hits::find(&fields, self.index.get(decks), self.rows.len())
                } else {
                    search::Hits::default()
                };
                (0..self.rows.len())
                    .filter(|&i| fields.keeps(i, &self.rows, decks, self.now, &hits))
                    .collect()
            }
        });
        let query = self.query.clone();
        if text.trim().is_empty() {
            return Step {
                query,
                filter: f,
                best: candidates.clone(),
                any: candidates,
            };
        }
        let found = self.index.get(decks).matching(&text, &candidates);
        Step {
            query,
            filter: f,
            any: found.any,
            best: found.best,
        }
    }

    /// Sorts the rows shown by the chosen column (nothing to do without).
    fn sort_rows(&mut self, decks: &[Deck]) {
        let Some((col, reverse)) = self.sort else {
            return;
        };
        if self.ranks.as_ref().is_none_or(|r| r.column != col) {
            self.ranks = Some(Ranks {
                column: col,
                rank: ranks(&self.rows, decks, col, self.now),
            });
        }
        let Some(ranks) = &self.ranks else {
            return;
        };
        let rank = &ranks.rank;
        if reverse {
            self.shown
                .sort_unstable_by_key(|&i| std::cmp::Reverse(rank[i]));
        } else {
            self.shown.sort_unstable_by_key(|&i| rank[i]);
        }
    }

    /// A change of status: searches and ranks made before may now be wrong.
    fn forget(&mut self) {
        self.steps.clear();
        self.ranks = None;
    }

    /// For tests: the search index is "being built" until the sender
    /// returned is used (or dropped).
    #[cfg(test)]
    pub(crate) fn hold_index(&mut self, decks: &[Deck]) -> std::sync::mpsc::Sender<()> {
        let (tx, rx) = std::sync::mpsc::channel::<()>();
        let thread = std::thread::spawn(move || {
            let _ = rx.recv();
            None
        });
        self.index = Index::Building {
            thread: Some(thread),
            cancel: Arc::new(AtomicBool::new(false)),
            card_of_row: search::card_of_row(decks, &self.rows),
        };
        self.steps.clear();
        tx
    }

    pub fn current(&self) -> Option<&ItemRow> {
        self.shown.get(self.selected).map(|&i| &self.rows[i])
    }

    /// A deck was edited and reloaded (`E`, `A`): the rows are read again
    /// (their places in the decks may have moved), with the same query
    /// and sort, on the item edited (or the card added) when it is shown.
    pub fn deck_edited(&mut self, app: &App, edited: &crate::tui::edit::Edited) {
        let want = match (&edited.new_card, &edited.target) {
            (Some(id), _) => app.decks.get(edited.deck).and_then(|d| {
                crate::sched::deck_items(d)
                    .into_iter()
                    .find(|k| &k.card == id)
            }),
            (None, crate::tui::edit::Target::Item(key)) => Some(key.clone()),
            _ => None,
        }
        .or_else(|| self.current().map(|r| r.key(&app.decks)));
        let Ok(mut fresh) = BrowserState::open(app) else {
            return;
        };
        fresh.query = self.query.clone();
        fresh.sort = self.sort;
        fresh.refilter(&app.decks);
        fresh.selected = want
            .and_then(|k| {
                fresh
                    .shown
                    .iter()
                    .position(|&i| fresh.rows[i].key(&app.decks) == k)
            })
            .unwrap_or(self.selected.min(fresh.shown.len().saturating_sub(1)));
        *self = fresh;
    }
}

/// The rank of each row in the order of `col` (ties in deck order).
fn ranks(rows: &[ItemRow], decks: &[Deck], col: Column, now: DateTime<Utc>) -> Vec<u32> {
    let f = |x: Option<f64>| x.unwrap_or(f64::NEG_INFINITY);
    let mut order: Vec<usize> = (0..rows.len()).collect();
    let by = |key: &dyn Fn(&ItemRow, &ItemRow) -> Ordering, order: &mut Vec<usize>| {
        order.sort_by(|&i, &j| key(&rows[i], &rows[j]).then(i.cmp(&j)));
    };
    match col {
        Column::Deck => by(&|a, b| a.deck_id(decks).cmp(b.deck_id(decks)), &mut order),
        Column::Card => by(&|a, b| a.card_id(decks).cmp(b.card_id(decks)), &mut order),
        Column::Question => {
            // In each deck's first language: the order does not change
            // with the language shown.
            let texts: Vec<String> = rows
                .iter()
                .map(|r| {
                    let lang = decks[r.deck].languages.first().map_or("en", |l| l.as_str());
                    r.text(decks, lang)
                })
                .collect();
            order.sort_by(|&i, &j| texts[i].cmp(&texts[j]).then(i.cmp(&j)));
        }
        Column::Direction => by(&|a, b| a.direction.cmp(&b.direction), &mut order),
        Column::State => by(&|a, b| a.state_name().cmp(b.state_name()), &mut order),
        Column::Due => by(&|a, b| a.due().cmp(&b.due()), &mut order),
        Column::Stability => by(
            &|a, b| {
                f(a.state.and_then(|s| s.stability))
                    .total_cmp(&f(b.state.and_then(|s| s.stability)))
            },
            &mut order,
        ),
        Column::Difficulty => by(
            &|a, b| {
                f(a.state.and_then(|s| s.difficulty))
                    .total_cmp(&f(b.state.and_then(|s| s.difficulty)))
            },
            &mut order,
        ),
        Column::Retrievability => by(
            &|a, b| f(a.retrievability).total_cmp(&f(b.retrievability)),
            &mut order,
        ),
        Column::Reviews => by(&|a, b| a.reviews.cmp(&b.reviews), &mut order),
        Column::Lapses => by(&|a, b| a.lapses.cmp(&b.lapses), &mut order),
        Column::Status => by(
            &|a, b| status_key(a, now).cmp(&status_key(b, now)),
            &mut order,
        ),
    }
    let mut rank = vec![0; rows.len()];
    for (r, &i) in order.iter().enumerate() {
        rank[i] = r as u32;
    }
    rank
}

/// The status column's text as bytes, padded with zeros: compares as the
/// text does, without making it.
fn status_key(row: &ItemRow, now: DateTime<Utc>) -> [u8; 3] {
    let mut k = [0; 3];
    let mut n = 0;
    for (on, c) in [
        (row.status.suspended, b'S'),
        (row.buried(now), b'B'),
        (row.status.leech, b'L'),
    ] {
        if on {
            k[n] = c;
            n += 1;
        }
    }
    k
}

/// `S` suspended, `B` buried, `L` leech.
fn status_text(row: &ItemRow, now: DateTime<Utc>) -> String {
    let mut s = String::new();
    if row.status.suspended {
        s.push('S');
    }
    if row.buried(now) {
        s.push('B');
    }
    if row.status.leech {
        s.push('L');
    }
    s
}

impl super::View for BrowserState {
    fn ends_session(&self) -> bool {
        true
    }

    fn context(&self) -> Context {
        if self.typing {
            Context::BrowserSearch
        } else {
            Context::Browser
        }
    }
    fn apply(&mut self, app: &mut App, action: Action) -> Nav {
        apply(app, self, action)
    }
    fn draw(&self, frame: &mut Frame, area: Rect, app: &App) {
        draw(frame, area, app, self)
    }
    fn name(&self) -> Msg {
        Msg::Browser
    }
    fn animating(&self) -> bool {
        self.waiting
    }
}

pub fn apply(app: &mut App, s: &mut BrowserState, action: Action) -> Nav {
    let last = s.shown.len().saturating_sub(1);
    let page = s.page.get().max(1);
    match action {
        Action::Up => s.selected = s.selected.saturating_sub(1),
        Action::Down => s.selected = (s.selected + 1).min(last),
        Action::PageUp => s.selected = s.selected.saturating_sub(page),
        Action::PageDown => s.selected = (s.selected + page).min(last),
        Action::Top => s.selected = 0,
        Action::Bottom => s.selected = last,
        Action::StartSearch => s.typing = true,
        Action::Submit => s.typing = false,
        Action::Input(c) => {
            s.query.push(c);
            s.selected = 0;
            s.refilter(&app.decks);
        }
        Action::Backspace => {
            s.query.pop();
            s.selected = 0;
            s.refilter(&app.decks);
        }
        Action::NextSort => {
            let next = match s.sort {
                None => Column::ALL[0],
                Some((c, _)) => {
                    let i = Column::ALL.iter().position(|x| *x == c).unwrap_or(0);
                    Column::ALL[(i + 1) % Column::ALL.len()]
                }
            };
            s.sort = Some((next, false));
            s.sort_rows(&app.decks);
        }
        Action::ReverseSort => {
            let (c, r) = s.sort.unwrap_or((Column::Deck, false));
            s.sort = Some((c, !r));
            s.sort_rows(&app.decks);
        }
        Action::Open => s.preview = !s.preview && s.current().is_some(),
        Action::Back if s.preview => s.preview = false,
        Action::Back => return Nav::Pop,
        Action::Explain => return explain(app, s),
        Action::CardInfo => {
            if let Some(row) = s.current() {
                let key = row.key(&app.decks);
                match super::info::InfoState::open(app, row.deck, key) {
                    Ok(i) => return Nav::Push(super::Screen::Info(Box::new(i))),
                    Err(e) => app.error(e),
                }
            }
        }
        Action::Suspend | Action::Bury | Action::Unsuspend => mark(app, s, action),
        Action::Undo => undo(app, s),
        Action::EditItem | Action::AddCard => edit(app, s, action),
        Action::Tick(_) if s.waiting && s.index.ready() => s.refilter(&app.decks),
        _ => {}
    }
    Nav::Stay
}

/// `E` and `A` on the selected item: its deck file in the editor.
fn edit(app: &mut App, s: &BrowserState, action: Action) {
    use crate::tui::edit::Target;
    let Some(row) = s.current() else {
        app.info(crate::tui::i18n::edit::NOTHING_TO_EDIT.get(&app.lang));
        return;
    };
    let target = if action == Action::AddCard {
        let kind = match row.direction {
            Direction::Predict | Direction::Derive => crate::deck::CardKind::Basic,
            _ => app
                .decks
                .get(row.deck)
                .and_then(|d| d.cards.get(row.card))
                .map_or(crate::deck::CardKind::Basic, |c| c.kind),
        };
        Target::NewCard(kind)
    } else {
        Target::Item(row.key(&app.decks))
    };
    app.request_edit(row.deck, target);
}

fn explain(app: &mut App, s: &BrowserState) -> Nav {
    let Some(row) = s.current() else {
        return Nav::Stay;
    };
    let section = app.decks.get(row.deck).and_then(|d| match row.direction {
        Direction::Predict => d.prompts.get(row.card)?.explain.clone(),
        Direction::Derive => d.derivations.get(row.card)?.explain.clone(),
        _ => d.cards.get(row.card)?.explain.clone(),
    });
    match section {
        Some(id) => super::reader::open_at(app, row.deck, &id),
        None => {
            app.info(app.tr(Msg::NoExplanation));
            Nav::Stay
        }
    }
}

/// Reads the status of `keys` again into the table.
fn refresh(app: &mut App, s: &mut BrowserState, keys: &[ItemKey]) {
    let statuses = match app.services.study.store.statuses() {
        Ok(st) => st,
        Err(e) => {
            app.error(e.to_string());
            return;
        }
    };
    let decks = &app.decks;
    for row in s.rows.iter_mut() {
        let named = |k: &&ItemKey| {
            k.direction == row.direction
                && k.card == row.card_id(decks)
                && k.deck == row.deck_id(decks)
        };
        if let Some(key) = keys.iter().find(named) {
            row.status = statuses.get(key).copied().unwrap_or_default();
        }
    }
    // A status filter may now select other rows: the next search starts
    // from every row again.
    s.forget();
    // Rows stay where they are until the query changes, so the learner
    // sees what the action did.
}

fn mark(app: &mut App, s: &mut BrowserState, action: Action) {
    let Some(row) = s.current() else {
        return;
    };
    let key = row.key(&app.decks);
    let now = app.services.now();
    let (mark, msg) = match action {
        Action::Suspend => (Mark::Suspend, Msg::CardSuspended),
        Action::Bury => (Mark::Bury, Msg::CardBuried),
        _ => (Mark::Unsuspend, Msg::CardUnsuspended),
    };
    if let Err(e) = app
        .services
        .study
        .mark(std::slice::from_ref(&key), mark, now)
    {
        app.error(e.to_string());
        return;
    }
    s.marks += 1;
    // Status is judged at the time of the action: a bury made now must
    // show as buried.
    s.now = s.now.max(now);
    refresh(app, s, &[key]);
    app.info(app.tr(msg));
}

fn undo(app: &mut App, s: &mut BrowserState) {
    if s.marks == 0 {
        app.info(app.tr(Msg::NothingToUndo));
        return;
    }
    match app.services.study.undo() {
        Ok(Some(crate::store::Undone::Status(events))) => {
            s.marks -= 1;
            let msg = super::review::status::undone_msg(&events);
            let keys: Vec<ItemKey> = events.into_iter().map(|e| e.key).collect();
            refresh(app, s, &keys);
            app.info(app.tr(msg));
        }
        Ok(Some(crate::store::Undone::Review(_))) | Ok(None) => {
            app.info(app.tr(Msg::NothingToUndo));
        }
        Err(e) => app.error(e.to_string()),
    }
}

fn fmt_opt(x: Option<f64>, digits: usize) -> String {
    x.map(|v| crate::text::num::rounded(v, digits))
        .unwrap_or_else(|| "–".into())
}

pub fn draw(frame: &mut Frame, area: Rect, app: &App, s: &BrowserState) {
    let t = &app.theme;
    let preview_h = if s.preview { area.height / 2 } else { 0 };
    let [query_area, table_area, preview_area, keys_area] = Layout::vertical([
        Constraint::Length(1),
        Constraint::Fill(1),
        Constraint::Length(preview_h),
        Constraint::Length(1),
    ])
    .areas(area);

    let mut q = vec![Span::styled("/ ", t.key())];
    q.push(Span::styled(
        format!("{}{}", s.query, if s.typing { "▏" } else { "" }),
        t.strong(),
    ));
    if s.waiting {
        q.push(Span::styled(
            format!("  {}", crate::tui::i18n::browser::SEARCHING.get(&app.lang)),
            t.dim(),
        ));
    } else {
        // What the query keeps, of every item.
        let count = if s.shown.len() == s.rows.len() {
            format!("{} {}", s.shown.len(), app.tr(Msg::Items))
        } else {
            crate::tui::i18n::browser::MATCHES
                .get(&app.lang)
                .replace("{n}", &s.shown.len().to_string())
                .replace("{total}", &s.rows.len().to_string())
        };
        q.push(Span::styled(format!("  {count}"), t.dim()));
    }
    if let Some((c, rev)) = s.sort {
        q.push(Span::styled(
            format!(
                " · {} {}{}",
                app.tr(Msg::SortedBy),
                app.tr(c.title()),
                if rev { " ↓" } else { " ↑" }
            ),
            t.dim(),
        ));
    }
    frame.render_widget(Paragraph::new(Line::from(q)), query_area);

    if let Some(e) = &s.error {
        frame.render_widget(
            Paragraph::new(e.as_str())
                .style(t.warn())
                .wrap(Wrap { trim: true }),
            table_area,
        );
    } else if s.shown.is_empty() {
        frame.render_widget(
            Paragraph::new(app.tr(Msg::NothingMatches)).style(t.warn()),
            table_area,
        );
    } else {
        draw_table(frame, table_area, app, s);
    }
    if s.preview {
        draw_preview(frame, preview_area, app, s);
    }
    let hint = app.tr(if s.typing {
        Msg::SearchHint
    } else {
        Msg::BrowserKeys
    });
    let hint = crate::tui::wrap::ellipsize(hint, usize::from(keys_area.width));
    frame.render_widget(Paragraph::new(Span::styled(hint, t.dim())), keys_area);
}

fn draw_table(frame: &mut Frame, area: Rect, app: &App, s: &BrowserState) {
    let t = &app.theme;
    // Header row and the highlight symbol's line: the rest holds rows.
    let visible = (area.height as usize).saturating_sub(1).max(1);
    s.page.set(visible);
    let offset = if s.selected >= visible {
        s.selected + 1 - visible
    } else {
        0
    };
    let columns = fitting_columns(area.width);
    let header = Row::new(
        columns
            .iter()
            .map(|c| {
                let mut title = app.tr(c.title()).to_string();
                if let Some((sc, rev)) = s.sort
                    && sc == *c
                {
                    title.push(if rev { '↓' } else { '↑' });
                }
                Cell::from(title)
            })
            .collect::<Vec<_>>(),
    )
    .style(t.heading());
    let rows = s.shown[offset..(offset + visible).min(s.shown.len())]
        .iter()
        .map(|&i| {
            let r = &s.rows[i];
            let due = match r.due() {
                Some(d) if d > s.now => crate::sched::format_interval(d - s.now),
                Some(_) => app.tr(Msg::Due).to_string(),
                None => "–".into(),
            };
            let status = status_text(r, s.now);
            let status_style = if status.is_empty() { t.dim() } else { t.warn() };
            Row::new(columns.iter().map(|c| match c {
                Column::Deck => Cell::from(app.decks[r.deck].id.clone()),
                Column::Card => Cell::from(r.card_id(&app.decks)),
                Column::Question => Cell::from(
                    crate::text::safe::one_line(&r.text(&app.decks, &app.lang)).into_owned(),
                ),
                Column::Direction => Cell::from(r.direction.as_str().into_owned()),
                Column::State => Cell::from(r.state_name()),
                Column::Due => Cell::from(due.clone()),
                Column::Stability => Cell::from(fmt_opt(r.state.and_then(|s| s.stability), 3)),
                Column::Difficulty => Cell::from(fmt_opt(r.state.and_then(|s| s.difficulty), 3)),
                Column::Retrievability => Cell::from(fmt_opt(r.retrievability, 2)),
                Column::Reviews => Cell::from(r.reviews.to_string()),
                Column::Lapses => Cell::from(r.lapses.to_string()),
                Column::Status => Cell::from(status.clone()).style(status_style),
            }))
        });
    let widths: Vec<Constraint> = columns.iter().map(|c| c.width()).collect();
    let table = Table::new(rows, widths)
        .header(header)
        .row_highlight_style(t.selected())
        .highlight_symbol("› ");
    let mut ts = TableState::default().with_selected(Some(s.selected - offset));
    frame.render_stateful_widget(table, area, &mut ts);
}

fn draw_preview(frame: &mut Frame, area: Rect, app: &App, s: &BrowserState) {
    let t = &app.theme;
    let Some(row) = s.current() else {
        return;
    };
    let Some(deck) = app.decks.get(row.deck) else {
        return;
    };
    let card = deck.cards.get(row.card);
    let derivation = deck.derivations.get(row.card);
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(t.border())
        .title(format!(
            " {}/{}/{} ",
            app.decks[row.deck].id,
            row.card_id(&app.decks),
            row.direction.as_str()
        ));
    let inner = block.inner(area).inner(Margin::new(1, 0));
    frame.render_widget(block, area);
    let width = inner.width as usize;
    let lang = &app.lang;
    use crate::tui::wrap::math_runs;
    let segs = |segs: Vec<crate::deck::cloze::Segment>| -> Vec<Run> {
        segs.into_iter()
            .flat_map(|seg| {
                let style = if seg.asked { t.highlight() } else { t.text() };
                crate::tui::wrap::math_runs(&seg.text, style)
            })
            .collect()
    };
    // A prompt (a `predict` item): its question, and the scene that
    // answers it.
    if row.direction == Direction::Predict {
        let Some(p) = deck.prompts.get(row.card) else {
            return;
        };
        let scene = deck
            .system(&p.scene)
            .and_then(|s| s.title.as_ref())
            .or_else(|| deck.scene(&p.scene).and_then(|s| s.title.as_ref()))
            .map(|t| t.get(lang).to_string())
            .unwrap_or_else(|| p.scene.clone());
        let blank = Run::new("", t.text());
        let mut lines = wrap(
            &math_runs(&p.question_listed(lang), t.strong()),
            width,
            blank.clone(),
            blank.clone(),
        );
        lines.push(Line::styled("─".repeat(width.min(40)), t.dim()));
        lines.extend(wrap(
            &[Run::new(
                format!("{}: {}", app.tr(Msg::PredictItem), scene),
                t.text(),
            )],
            width,
            blank.clone(),
            blank,
        ));
        frame.render_widget(Paragraph::new(lines), inner);
        return;
    }
    let (question, answer): (Vec<Run>, Vec<Run>) = match (row.direction, card) {
        // A derivation: its title, then each step's math.
        (Direction::Derive, _) => {
            let Some(d) = derivation else {
                return;
            };
            let mut steps = Vec::new();
            for (i, step) in d.steps.iter().enumerate() {
                if i > 0 {
                    steps.push(Run::new("  ", t.text()));
                }
                steps.push(Run::new(format!("{}. ", i + 1), t.dim()));
                steps.extend(math_runs(step.math.get(lang), t.text()));
            }
            (math_runs(d.title.get(lang), t.strong()), steps)
        }
        (Direction::Predict, _) | (_, None) => return,
        (Direction::Cloze(n), Some(card)) => {
            let text = card.front.get(lang);
            let mut back = segs(crate::deck::cloze::back(text, n));
            let extra = card.back.get(lang);
            if !extra.is_empty() {
                back.push(Run::new(
                    format!("  {}", crate::text::render(extra)),
                    t.dim(),
                ));
            }
            (segs(crate::deck::cloze::front(text, n)), back)
        }
        (Direction::Forward, Some(card)) => (
            math_runs(card.front.get(lang), t.strong()),
            math_runs(card.back.get(lang), t.text()),
        ),
        (Direction::Backward, Some(card)) => (
            math_runs(card.back.get(lang), t.strong()),
            math_runs(card.front.get(lang), t.text()),
        ),
    };
    let blank = Run::new("", t.text());
    let mut lines = wrap(&question, width, blank.clone(), blank.clone());
    lines.push(Line::styled("─".repeat(width.min(40)), t.dim()));
    lines.extend(wrap(&answer, width, blank.clone(), blank));
    let tags = row.tags(&app.decks);
    if !tags.is_empty() {
        lines.push(Line::styled(format!("# {}", tags.join(" ")), t.dim()));
    }
    frame.render_widget(Paragraph::new(lines), inner);
}
