//! The home screen: the decks, with how much is waiting in each.

use chrono::{DateTime, Utc};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Cell, Paragraph, Row, Table, TableState, Wrap};

use crate::tui::action::Action;
use crate::tui::app::App;
use crate::tui::i18n::{Msg, Noun};

use super::{Nav, Screen};
use crate::tui::i18n::Words;
use crate::tui::keymap::Binding;
use crossterm::event::KeyCode::{Char, Down, Enter, Esc, Up};

pub const KEYS: &[Binding] = &[
    Binding::new(
        "↑↓ j k",
        Words("choose a deck", "deck chuno"),
        &[
            (Up, Action::Up),
            (Down, Action::Down),
            (Char('j'), Action::Down),
            (Char('k'), Action::Up),
        ],
    ),
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
        &[(Char('q'), Action::Quit), (Esc, Action::Quit)],
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
    pub counts: Option<Counts>,
    pub last_studied: Option<DateTime<Utc>>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct HomeState {
    pub selected: usize,
    pub rows: Vec<DeckRow>,
}

impl HomeState {
    pub fn new(app: &App) -> HomeState {
        let rows = app
            .decks
            .iter()
            .map(|deck| app.services.deck_row(deck))
            .collect();
        HomeState { selected: 0, rows }
    }

    /// Takes fresh counts, keeping the selection.
    pub fn refresh(&mut self, fresh: HomeState) {
        self.rows = fresh.rows;
        self.selected = self.selected.min(self.rows.len().saturating_sub(1));
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
    let deck = state.selected.min(n.saturating_sub(1));
    match action {
        Action::Up => state.selected = state.selected.saturating_sub(1),
        Action::Down => state.selected = (state.selected + 1).min(n.saturating_sub(1)),
        Action::Top => state.selected = 0,
        Action::Bottom => state.selected = n.saturating_sub(1),
        Action::Back => app.quit = true,
        _ if n == 0 => {}
        Action::OpenPrompts => {
            return Nav::Push(Screen::Prompts(super::prompts::PromptsState::new(deck)));
        }
        Action::OpenReader => {
            return Nav::Push(Screen::Reader(super::reader::ReaderState::new(deck)));
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
        let p = Paragraph::new(crate::tui::i18n::no_decks(&app.lang, &app.deck_load))
            .style(t.warn())
            .wrap(Wrap { trim: true });
        frame.render_widget(p, area);
        return;
    }
    let [table_area, detail_area, keys_area] = Layout::vertical([
        Constraint::Fill(1),
        Constraint::Length(4),
        Constraint::Length(1),
    ])
    .areas(area);
    let mut keys = vec![Span::raw(" ")];
    for (k, what) in [
        ("Enter", Msg::KeyReview),
        ("c", Msg::KeyCram),
        ("r", Msg::KeyRead),
        ("p", Msg::KeyPredict),
        ("t", Msg::KeyStats),
    ] {
        keys.push(Span::styled(k, t.key()));
        keys.push(Span::styled(format!(" {}  ", app.tr(what)), t.dim()));
    }
    frame.render_widget(Paragraph::new(Line::from(keys)), keys_area);

    let header = Row::new(vec![
        Cell::from(app.tr(Msg::Decks)),
        Cell::from(app.tr(Msg::Due)),
        Cell::from(app.tr(Msg::Learning)),
        Cell::from(app.tr(Msg::New)),
        Cell::from(app.tr(Msg::LastStudied)),
    ])
    .style(t.heading());
    let rows = app.decks.iter().zip(&state.rows).map(|(deck, row)| {
        let count = |f: fn(&Counts) -> usize| {
            row.counts
                .map(|c| f(&c).to_string())
                .unwrap_or_else(|| "–".into())
        };
        Row::new(vec![
            Cell::from(deck.title.get(&app.lang).to_string()),
            Cell::from(count(|c| c.due)).style(t.good()),
            Cell::from(count(|c| c.learning)).style(t.warn()),
            Cell::from(count(|c| c.new)).style(t.title()),
            Cell::from(ago(app, row.last_studied)).style(t.dim()),
        ])
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
    frame.render_stateful_widget(table, table_area, &mut ts);

    if let Some(deck) = app.decks.get(state.selected) {
        let mut lines = vec![Line::from(vec![Span::styled(
            format!(
                "{} · {} · {}",
                app.count(deck.cards.len(), Noun::Card),
                app.count(deck.prompts.len(), Noun::Prompt),
                app.count(deck.sections.len(), Noun::Section)
            ),
            t.dim(),
        )])];
        if let Some(desc) = &deck.description {
            lines.push(Line::from(crate::text::render(desc.get(&app.lang))));
        }
        if app.deck_load.errors > 0 {
            lines.push(Line::styled(
                app.count(app.deck_load.errors, Noun::DeckProblem),
                t.warn(),
            ));
        }
        frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: true }), detail_area);
    }
}
