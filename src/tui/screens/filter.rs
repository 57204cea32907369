//! The study filter (`f` on home): the fields of `flipcard review [DECK]
//! --tag --state --due-within --cram` as a form over the selected deck or
//! every deck, with the number of items that match before the session
//! starts.

use ratatui::Frame;
use ratatui::layout::{Margin, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

use crate::catalog::{self, Filter};
use crate::tui::action::Action;
use crate::tui::app::App;
use crate::tui::i18n::{Msg, Words, marks};
use crate::tui::keymap::{Binding, Context};

use super::{Nav, Screen};
use crossterm::event::KeyCode::{BackTab, Backspace, Down, Enter, Esc, Left, Right, Tab, Up};

pub const KEYS: &[Binding] = &[
    Binding::typing(Words(
        "the tags (separated by spaces) or the span (3d, 12h)",
        "tags (space se alag) ya samay (3d, 12h)",
    )),
    Binding::new(
        "Tab ↑↓",
        Words("next / previous field", "agla / pichhla field"),
        &[
            (Tab, Action::NextField),
            (Down, Action::NextField),
            (BackTab, Action::PrevField),
            (Up, Action::PrevField),
        ],
    ),
    Binding::new(
        "← → Space",
        Words(
            "change the state, cram or the decks",
            "state, cram ya decks badlo",
        ),
        &[(Left, Action::PrevSection), (Right, Action::NextSection)],
    ),
    Binding::new(
        "Backspace",
        Words("delete a character", "ek akshar mitao"),
        &[(Backspace, Action::Backspace)],
    ),
    Binding::new(
        "Enter",
        Words("start the session", "session shuru karo"),
        &[(Enter, Action::Submit)],
    ),
    Binding::new("Esc", Words("back", "wapas"), &[(Esc, Action::Back)]),
];

/// The form's fields, in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Field {
    Tag,
    State,
    DueWithin,
    Cram,
    /// The selected deck, another one, or every deck.
    Decks,
}

const FIELDS: [Field; 5] = [
    Field::Tag,
    Field::State,
    Field::DueWithin,
    Field::Cram,
    Field::Decks,
];

#[derive(Debug, Clone, PartialEq)]
pub struct FilterState {
    /// The deck searched, `None` for every deck (as `flipcard review`
    /// without DECK).
    pub deck: Option<usize>,
    pub field: usize,
    pub tags: String,
    /// Index into [`catalog::STATES`], `None` for any state.
    pub state: Option<usize>,
    pub due_within: String,
    pub cram: bool,
    /// How many items the session would show, or why it cannot start.
    pub count: Result<usize, String>,
}

/// `b` and `f` on home: the browser over every deck, the filter over the
/// selected one.
pub fn open_from_home(app: &mut App, deck: usize, action: Action) -> Nav {
    if action == Action::OpenBrowser {
        return match super::browser::BrowserState::open(app) {
            Ok(b) => Nav::Push(Screen::Browser(Box::new(b))),
            Err(e) => {
                app.error(e);
                Nav::Stay
            }
        };
    }
    let mut f = FilterState {
        deck: Some(deck),
        field: 0,
        tags: String::new(),
        state: None,
        due_within: String::new(),
        cram: false,
        count: Ok(0),
    };
    f.recount(app);
    Nav::Push(Screen::Filter(Box::new(f)))
}

impl FilterState {
    pub fn filter(&self) -> Result<Filter, String> {
        let mut f = Filter {
            tags: self.tags.split_whitespace().map(str::to_string).collect(),
            ..Filter::default()
        };
        if let Some(i) = self.state {
            f.add_state(catalog::STATES[i]).map_err(|e| e.0)?;
        }
        if !self.due_within.trim().is_empty() {
            f.due_within = Some(catalog::parse_span(self.due_within.trim()).map_err(|e| e.0)?);
        }
        Ok(f)
    }

    pub fn recount(&mut self, app: &App) {
        self.count = self.filter().and_then(|f| {
            super::review::filtered_items(app, self.deck, &f, self.cram).map(|v| v.len())
        });
    }

    /// The next (or previous) value of a field chosen from a list; `decks`
    /// is how many decks there are.
    fn cycle(&mut self, forward: bool, decks: usize) {
        match FIELDS[self.field] {
            Field::State => {
                let n = catalog::STATES.len();
                self.state = match (self.state, forward) {
                    (None, true) => Some(0),
                    (None, false) => Some(n - 1),
                    (Some(i), true) if i + 1 < n => Some(i + 1),
                    (Some(i), false) if i > 0 => Some(i - 1),
                    _ => None,
                };
            }
            Field::Cram => self.cram = !self.cram,
            Field::Decks => {
                let n = decks;
                self.deck = match (self.deck, forward) {
                    _ if n == 0 => None,
                    (None, true) => Some(0),
                    (None, false) => n.checked_sub(1),
                    (Some(i), true) if i + 1 < n => Some(i + 1),
                    (Some(i), false) if i > 0 => Some(i - 1),
                    _ => None,
                };
            }
            Field::Tag | Field::DueWithin => {}
        }
    }
}

impl super::View for FilterState {
    fn context(&self) -> Context {
        Context::Filter
    }
    fn apply(&mut self, app: &mut App, action: Action) -> Nav {
        apply(app, self, action)
    }
    fn draw(&self, frame: &mut Frame, area: Rect, app: &App) {
        draw(frame, area, app, self)
    }
    fn name(&self) -> Msg {
        Msg::FilterTitle
    }
    fn deck(&self) -> Option<usize> {
        self.deck
    }
}

pub fn apply(app: &mut App, s: &mut FilterState, action: Action) -> Nav {
    match action {
        Action::NextField => s.field = (s.field + 1) % FIELDS.len(),
        Action::PrevField => s.field = (s.field + FIELDS.len() - 1) % FIELDS.len(),
        Action::NextSection => s.cycle(true, app.decks.len()),
        Action::PrevSection => s.cycle(false, app.decks.len()),
        Action::Input(c) => match FIELDS[s.field] {
            Field::Tag => s.tags.push(c),
            Field::DueWithin if !c.is_whitespace() => s.due_within.push(c),
            Field::DueWithin => {}
            Field::State | Field::Cram | Field::Decks if c == ' ' => s.cycle(true, app.decks.len()),
            Field::State | Field::Cram | Field::Decks => {}
        },
        Action::Backspace => match FIELDS[s.field] {
            Field::Tag => {
                s.tags.pop();
            }
            Field::DueWithin => {
                s.due_within.pop();
            }
            Field::State | Field::Cram | Field::Decks => {}
        },
        Action::Back => return Nav::Pop,
        Action::Submit => return start(app, s),
        _ => return Nav::Stay,
    }
    s.recount(app);
    Nav::Stay
}

fn start(app: &mut App, s: &mut FilterState) -> Nav {
    // The items are chosen once, now (the count shown may be a little old),
    // and the session opens on exactly those.
    let items = s
        .filter()
        .and_then(|f| super::review::filtered_items(app, s.deck, &f, s.cram));
    s.count = items.as_ref().map(Vec::len).map_err(Clone::clone);
    match items {
        Ok(items) if items.is_empty() => app.info(app.tr(Msg::NothingMatches)),
        Ok(items) => match super::review::ReviewState::open_listed(app, s.deck, items, s.cram) {
            Ok(r) => return Nav::Replace(Screen::Review(Box::new(r))),
            Err(e) => app.error(e),
        },
        Err(e) => app.error(e),
    }
    Nav::Stay
}

pub fn draw(frame: &mut Frame, area: Rect, app: &App, s: &FilterState) {
    let t = &app.theme;
    let inner = area.inner(Margin::new(2, 1));
    let mut lines = Vec::new();
    let value = |f: Field| -> String {
        match f {
            Field::Tag => s.tags.clone(),
            Field::State => s
                .state
                .map_or(app.tr(Msg::AnyState), |i| catalog::STATES[i])
                .to_string(),
            Field::DueWithin => s.due_within.clone(),
            Field::Cram => app.tr(if s.cram { Msg::Yes } else { Msg::No }).to_string(),
            Field::Decks => match s.deck.and_then(|i| app.decks.get(i)) {
                Some(d) => d.title.get(&app.lang).to_string(),
                None => marks::ALL_DECKS.get(&app.lang).to_string(),
            },
        }
    };
    for (i, f) in FIELDS.iter().enumerate() {
        let label = match f {
            Field::Tag => app.tr(Msg::FieldTag),
            Field::State => app.tr(Msg::FieldState),
            Field::DueWithin => app.tr(Msg::FieldDueWithin),
            Field::Cram => app.tr(Msg::FieldCram),
            Field::Decks => marks::FIELD_DECKS.get(&app.lang),
        };
        let focused = i == s.field;
        let mut v = value(*f);
        if focused {
            v.push_str(match f {
                Field::Tag | Field::DueWithin => "▏",
                Field::State | Field::Cram | Field::Decks => " ‹›",
            });
        }
        lines.push(Line::from(vec![
            Span::styled(if focused { "› " } else { "  " }, t.key()),
            Span::styled(format!("{label:<16}"), t.heading()),
            Span::styled(v, if focused { t.selected() } else { t.text() }),
        ]));
    }
    lines.push(Line::default());
    match &s.count {
        Ok(n) => {
            lines.push(Line::from(vec![
                Span::styled(format!("{n} "), if *n == 0 { t.warn() } else { t.good() }),
                Span::styled(app.tr(Msg::Matching), t.text()),
            ]));
            lines.push(Line::styled(app.tr(Msg::StartFiltered), t.dim()));
        }
        Err(e) => lines.push(Line::styled(e.clone(), t.warn())),
    }
    frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), inner);
}
