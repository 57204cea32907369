//! The home screen: the decks, with how much is waiting in each.

use chrono::{DateTime, Utc};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Cell, Paragraph, Row, Table, TableState, Wrap};

use crate::deck::{Deck, DeckTree};
use crate::tui::action::Action;
use crate::tui::app::App;
use crate::tui::i18n::{Msg, Noun};
use crate::tui::services::Services;

use super::{Nav, Screen};
use crate::tui::i18n::Words;
use crate::tui::keymap::Binding;
use crossterm::event::KeyCode::{Char, Enter, Esc};

pub const KEYS: &[Binding] = &[
    Binding::choose(Words("choose a deck", "deck chuno")),
    Binding::new(
        "Enter",
        Words("review the due cards", "baaki cards review karo"),
        &[(Enter, Action::OpenReview)],
    ),
    Binding::new(
        "c",
        Words("cram: review everything now", "cram: sab abhi review karo"),
        &[(Char('c'), Action::OpenCram)],
    ),
    Binding::new(
        "r",
        Words("read the explanations", "explanations padho"),
        &[(Char('r'), Action::OpenReader)],
    ),
    Binding::new(
        "p",
        Words("prompts and simulations", "prompts aur simulations"),
        &[(Char('p'), Action::OpenPrompts)],
    ),
    Binding::new(
        "x",
        Words(
            "exam: plan for a date, study today's share",
            "exam: tareekh ka plan, aaj ka hissa padho",
        ),
        &[(Char('x'), Action::OpenExam)],
    ),
    Binding::new(
        "t",
        Words("statistics", "statistics"),
        &[(Char('t'), Action::OpenStats)],
    ),
    Binding::new(
        "b f",
        Words(
            "card browser / study with a filter",
            "card browser / filter ke saath padho",
        ),
        &[
            (Char('b'), Action::OpenBrowser),
            (Char('f'), Action::OpenFilter),
        ],
    ),
    Binding::new(
        "q",
        Words("quit", "band karo"),
        &[(Char('q'), Action::Quit), (Esc, Action::Back)],
    ),
];

/// What is waiting in one deck today.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Counts {
    pub new: usize,
    pub learning: usize,
    pub due: usize,
}

#[derive(Debug, Clone, PartialEq)]
pub struct DeckRow {
    /// The deck's index in `app.decks`, and how deep it sits in the tree
    /// of decks (0: at the top).
    pub deck: usize,
    pub depth: usize,
    /// Today's counts of the deck and every deck below it, within each
    /// one's limits.
    pub counts: Option<Counts>,
    pub last_studied: Option<DateTime<Utc>>,
}

impl DeckRow {
    /// Today's counts of deck `i` with its subdecks, and its last study
    /// time (blank when the store cannot say).
    pub fn of(
        services: &Services,
        decks: &[Deck],
        tree: &DeckTree,
        i: usize,
        depth: usize,
    ) -> DeckRow {
        let now = services.now();
        let sub: Vec<(&Deck, Option<usize>)> = tree
            .subtree(i)
            .into_iter()
            .map(|(d, up)| (&decks[d], up))
            .collect();
        let counts = services.study.counts_tree(&sub, now).ok().map(|c| Counts {
            new: c.new,
            learning: c.learning,
            due: c.due,
        });
        DeckRow {
            deck: i,
            depth,
            counts,
            last_studied: services
                .study
                .store
                .last_studied(&decks[i].id)
                .ok()
                .flatten(),
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct HomeState {
    /// The row selected (rows are in tree order: see [`DeckRow::deck`]).
    pub selected: usize,
    pub rows: Vec<DeckRow>,
}

impl HomeState {
    pub fn new(app: &App) -> HomeState {
        let tree = DeckTree::new(&app.decks);
        let rows = tree
            .order
            .iter()
            .map(|&(i, depth)| DeckRow::of(&app.services, &app.decks, &tree, i, depth))
            .collect();
        HomeState { selected: 0, rows }
    }

    /// Takes fresh counts, keeping the selection.
    pub fn refresh(&mut self, fresh: HomeState) {
        self.rows = fresh.rows;
        self.selected = self.selected.min(self.rows.len().saturating_sub(1));
    }

    /// The deck of the selected row (its index in `app.decks`).
    pub fn deck(&self) -> usize {
        self.rows
            .get(self.selected)
            .map_or(self.selected, |r| r.deck)
    }

    /// Selects the row of deck `i` (an index in `app.decks`).
    pub fn select_deck(&mut self, i: usize) {
        if let Some(at) = self.rows.iter().position(|r| r.deck == i) {
            self.selected = at;
        }
    }
}

impl super::View for HomeState {
    fn context(&self) -> crate::tui::keymap::Context {
        crate::tui::keymap::Context::Home
    }
    fn apply(&mut self, app: &mut App, action: Action) -> Nav {
        apply(app, self, action)
    }
    fn draw(&self, frame: &mut Frame, area: Rect, app: &App) {
        draw(frame, area, app, self)
    }
    fn name(&self) -> Msg {
        Msg::Decks
    }
}

pub fn apply(app: &mut App, state: &mut HomeState, action: Action) -> Nav {
    let n = app.decks.len();
    let deck = state.deck().min(n.saturating_sub(1));
    match action {
        Action::Up => state.selected = state.selected.saturating_sub(1),
        Action::Down => state.selected = (state.selected + 1).min(n.saturating_sub(1)),
        Action::Top => state.selected = 0,
        Action::Bottom => state.selected = n.saturating_sub(1),
        // Esc backs out of every other screen: here, where there is
        // nothing to back out of, it says how to quit rather than closing
        // the app under a learner who pressed it once too often.
        Action::Back => app.info(app.tr(Msg::EscOnHome)),
        _ if n == 0 => {}
        Action::OpenPrompts => {
            return Nav::Push(Screen::Prompts(super::prompts::PromptsState::new(deck)));
        }
        Action::OpenReader => {
            return Nav::Push(Screen::Reader(super::reader::ReaderState::new(deck)));
        }
        Action::OpenExam => {
            return Nav::Push(Screen::Exam(Box::new(super::exam::ExamState::new(
                app, deck,
            ))));
        }
        Action::OpenStats => {
            return Nav::Push(Screen::Stats(Box::new(super::stats::StatsState::open(
                app, deck,
            ))));
        }
        Action::OpenBrowser | Action::OpenFilter => {
            return super::filter::open_from_home(app, deck, action);
        }
        Action::OpenReview | Action::OpenCram => {
            match super::review::ReviewState::open(app, deck, action == Action::OpenCram) {
                Ok(r) => return Nav::Push(Screen::Review(Box::new(r))),
                Err(e) => app.error(e),
            }
        }
        _ => {}
    }
    Nav::Stay
}

/// "3 h ago", "2 d ago", "never".
pub fn ago(app: &App, then: Option<DateTime<Utc>>) -> String {
    let Some(then) = then else {
        return app.tr(Msg::Never).to_string();
    };
    crate::tui::i18n::ago(&app.lang, (app.services.now() - then).num_seconds())
}

pub fn draw(frame: &mut Frame, area: Rect, app: &App, state: &HomeState) {
    let t = &app.theme;
    if app.decks.is_empty() {
        let p = Paragraph::new(crate::tui::i18n::no_decks(
            &app.lang,
            app.deck_load.from.as_deref(),
            app.deck_load.failed_files,
        ))
        .style(t.warn())
        .wrap(Wrap { trim: true });
        frame.render_widget(p, area);
        return;
    }
    // The keys wrap rather than run off a narrow screen.
    let groups = [
        ("Enter", Msg::KeyReview),
        ("c", Msg::KeyCram),
        ("r", Msg::KeyRead),
        ("p", Msg::KeyPredict),
        ("t", Msg::KeyStats),
    ]
    .into_iter()
    .map(|(k, what)| {
        vec![
            Span::styled(k, t.key()),
            Span::styled(format!(" {}", app.tr(what)), t.dim()),
        ]
    })
    .collect();
    let keys = crate::tui::wrap::pack(groups, usize::from(area.width), 2);
    // Narrow: the deck titles alone in the list, their counts below.
    let narrow = area.width < 60;
    let details = details(app, state, narrow, area.width);
    // The deck list keeps its header and up to five decks before the
    // details get a row (at 40×12 the selected deck's details hid every
    // other deck): the details are cut from their end, the description.
    // Decks that failed to load are named above the list (with how to see
    // why), so one broken file hides none of the others.
    let warn_rows = u16::from(!app.deck_load.failed.is_empty()) * 2;
    let list_rows = 1 + app.decks.len().clamp(1, 5) as u16;
    let room = area
        .height
        .saturating_sub(keys.len() as u16 + list_rows + warn_rows);
    let [warn_area, table_area, detail_area, keys_area] = Layout::vertical([
        Constraint::Length(warn_rows),
        Constraint::Fill(1),
        Constraint::Length((details.len() as u16).min(room)),
        Constraint::Length(keys.len() as u16),
    ])
    .areas(area);
    if warn_rows > 0 {
        let p = Paragraph::new(crate::tui::i18n::decks_left_out(
            &app.lang,
            &app.deck_load.failed,
        ))
        .style(t.warn())
        .wrap(Wrap { trim: true });
        frame.render_widget(p, warn_area);
    }
    frame.render_widget(Paragraph::new(keys), keys_area);
    frame.render_widget(Paragraph::new(details), detail_area);

    if narrow {
        draw_narrow(frame, table_area, app, state);
    } else {
        draw_table(frame, table_area, app, state);
    }
}

fn details(app: &App, state: &HomeState, narrow: bool, width: u16) -> Vec<Line<'static>> {
    use crate::tui::wrap::{Run, wrap};
    let t = &app.theme;
    let width = usize::from(width.max(1));
    let mut out: Vec<Line<'static>> = Vec::new();
    if let Some(deck) = app.decks.get(state.deck()) {
        // The counts in the table are review items: a card asked both ways
        // is two, which is said here so that the numbers add up (each
        // prompt is one more, counted beside it).
        let items = crate::sched::deck_items(deck).len() - deck.prompts.len();
        let cards = if items == deck.cards.len() {
            app.count(deck.cards.len(), Noun::Card)
        } else {
            format!(
                "{} ({items} {})",
                app.count(deck.cards.len(), Noun::Card),
                crate::tui::i18n::study::REVIEW_ITEMS.get(&app.lang)
            )
        };
        let mut lines = Vec::new();
        if narrow && let Some(row) = state.rows.get(state.selected) {
            let c = row.counts.unwrap_or_default();
            lines.push(Line::from(vec![
                Span::styled(format!("{} {}", c.due, app.tr(Msg::Due)), t.good()),
                Span::styled(" · ", t.dim()),
                Span::styled(
                    format!("{} {}", c.learning, app.tr(Msg::Learning)),
                    t.warn(),
                ),
                Span::styled(" · ", t.dim()),
                Span::styled(
                    crate::tui::i18n::count(&app.lang, c.new, Noun::New),
                    t.title(),
                ),
                Span::styled(
                    format!(
                        " · {} {}",
                        app.tr(Msg::LastStudied),
                        ago(app, row.last_studied)
                    ),
                    t.dim(),
                ),
            ]));
        }
        lines.push(Line::from(vec![Span::styled(
            format!(
                "{cards} · {} · {}",
                app.count(deck.prompts.len(), Noun::Prompt),
                app.count(deck.sections.len(), Noun::Section)
            ),
            t.dim(),
        )]));
        if let Some(desc) = &deck.description {
            lines.push(Line::from(crate::text::render(desc.get(&app.lang))));
        }
        if app.deck_load.errors > 0 {
            lines.push(Line::styled(
                app.count(app.deck_load.errors, Noun::DeckProblem),
                t.warn(),
            ));
        }
        let none = || Run::new("", t.text());
        for line in lines {
            let runs: Vec<Run> = line
                .spans
                .iter()
                .map(|s| Run::new(s.content.to_string(), s.style))
                .collect();
            out.extend(wrap(&runs, width, none(), none()));
        }
    }
    out
}

/// One row per deck: due, learning and new review items, last studied.
fn draw_table(frame: &mut Frame, area: Rect, app: &App, state: &HomeState) {
    let rows = rows_of(app, state);
    let t = &app.theme;
    // What the fixed columns, their spacing and the "› " leave.
    let title_w = usize::from(area.width).saturating_sub(7 + 11 + 6 + 16 + 4 + 2);
    let header = Row::new(vec![
        Cell::from(app.tr(Msg::Decks)),
        Cell::from(app.tr(Msg::Due)),
        Cell::from(app.tr(Msg::Learning)),
        Cell::from(app.tr(Msg::New)),
        Cell::from(app.tr(Msg::LastStudied)),
    ])
    .style(t.heading());
    let rows = rows.iter().filter_map(|row| {
        let deck = app.decks.get(row.deck)?;
        let count = |f: fn(&Counts) -> usize| {
            row.counts
                .map(|c| f(&c).to_string())
                .unwrap_or_else(|| "–".into())
        };
        Some(Row::new(vec![
            Cell::from(titled(app, deck, row.depth, title_w)),
            Cell::from(count(|c| c.due)).style(t.good()),
            Cell::from(count(|c| c.learning)).style(t.warn()),
            Cell::from(count(|c| c.new)).style(t.title()),
            Cell::from(ago(app, row.last_studied)).style(t.dim()),
        ]))
    });
    let widths = [
        Constraint::Fill(1),
        Constraint::Length(7),
        Constraint::Length(11),
        Constraint::Length(6),
        Constraint::Length(16),
    ];
    let table = Table::new(rows, widths)
        .header(header)
        .row_highlight_style(t.selected())
        .highlight_symbol("› ");
    let mut ts = TableState::default().with_selected(Some(state.selected));
    frame.render_stateful_widget(table, area, &mut ts);
}

/// A narrow screen: the deck titles alone; the selected deck's counts go
/// in the details below.
fn draw_narrow(frame: &mut Frame, area: Rect, app: &App, state: &HomeState) {
    let rows = rows_of(app, state);
    let t = &app.theme;
    let title_w = usize::from(area.width.saturating_sub(2));
    let rows = rows.iter().filter_map(|row| {
        let deck = app.decks.get(row.deck)?;
        Some(Row::new(vec![Cell::from(titled(
            app, deck, row.depth, title_w,
        ))]))
    });
    let table = Table::new(rows, [Constraint::Fill(1)])
        .header(Row::new(vec![Cell::from(app.tr(Msg::Decks))]).style(t.heading()))
        .row_highlight_style(t.selected())
        .highlight_symbol("› ");
    let mut ts = TableState::default().with_selected(Some(state.selected));
    frame.render_stateful_widget(table, area, &mut ts);
}

/// A deck's title in its row: indented two spaces per level under its
/// parent (at most four levels, so a deep tree leaves room for the title).
fn titled(app: &App, deck: &Deck, depth: usize, width: usize) -> String {
    let indent = "  ".repeat(depth.min(4));
    let title = crate::tui::wrap::ellipsize(
        deck.title.get(&app.lang),
        width.saturating_sub(indent.len()),
    );
    format!("{indent}{title}")
}

/// The rows to draw: the state's, or (when the decks changed since it was
/// counted) every deck in tree order without counts, so no deck is left
/// off the list.
fn rows_of<'s>(app: &App, state: &'s HomeState) -> std::borrow::Cow<'s, [DeckRow]> {
    if state.rows.len() == app.decks.len() {
        return std::borrow::Cow::Borrowed(&state.rows);
    }
    let tree = DeckTree::new(&app.decks);
    std::borrow::Cow::Owned(
        tree.order
            .iter()
            .map(|&(deck, depth)| DeckRow {
                deck,
                depth,
                counts: None,
                last_studied: None,
            })
            .collect(),
    )
}
