//! The list of a deck's predict-then-check prompts.

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{List, ListItem, ListState, Paragraph, Wrap};

use crate::text::num::{self, Num};
use crate::tui::action::Action;
use crate::tui::app::App;
use crate::tui::i18n::Msg;

use super::Nav;
use crate::tui::i18n::Words;
use crate::tui::keymap::Binding;
use crossterm::event::KeyCode::{Char, Enter, Esc};

pub const KEYS: &[Binding] = &[
    Binding::choose(Words("choose a prompt", "prompt chuno")),
    Binding::new(
        "Enter",
        Words("predict, then check", "andaaza lagao, phir jaancho"),
        &[(Enter, Action::Open)],
    ),
    Binding::new(
        "x",
        Words(
            "explore the scene with its knobs",
            "scene ko uske knobs se explore karo",
        ),
        &[(Char('x'), Action::Explore)],
    ),
    Binding::new(
        "Esc q",
        Words("back", "wapas"),
        &[(Esc, Action::Back), (Char('q'), Action::Back)],
    ),
];

#[derive(Debug, Clone, PartialEq)]
pub struct PromptsState {
    pub deck: usize,
    pub selected: usize,
}

impl PromptsState {
    pub fn new(deck: usize) -> PromptsState {
        PromptsState { deck, selected: 0 }
    }
}

impl super::View for PromptsState {
    fn context(&self) -> crate::tui::keymap::Context {
        crate::tui::keymap::Context::Prompts
    }
    fn apply(&mut self, app: &mut App, action: Action) -> Nav {
        apply(app, self, action)
    }
    fn draw(&self, frame: &mut Frame, area: Rect, app: &App) {
        draw(frame, area, app, self)
    }
    fn name(&self) -> Msg {
        Msg::Prompts
    }
    fn deck(&self) -> Option<usize> {
        Some(self.deck)
    }
}

pub fn apply(app: &mut App, state: &mut PromptsState, action: Action) -> Nav {
    let n = app.decks.get(state.deck).map_or(0, |d| d.prompts.len());
    match action {
        Action::Up => state.selected = state.selected.saturating_sub(1),
        Action::Down => state.selected = (state.selected + 1).min(n.saturating_sub(1)),
        Action::Top => state.selected = 0,
        Action::Bottom => state.selected = n.saturating_sub(1),
        Action::Back => return Nav::Pop,
        Action::Open if n > 0 => {
            let p = super::predict::PredictState::new(app, state.deck, state.selected.min(n - 1));
            return Nav::Push(super::Screen::Predict(Box::new(p)));
        }
        Action::Explore if n > 0 => {
            match super::predict::PredictState::exploring(
                app,
                state.deck,
                state.selected.min(n - 1),
            ) {
                Ok(p) => return Nav::Push(super::Screen::Predict(Box::new(p))),
                Err(e) => app.info(e),
            }
        }
        _ => {}
    }
    Nav::Stay
}

pub fn draw(frame: &mut Frame, area: Rect, app: &App, state: &PromptsState) {
    let t = &app.theme;
    let Some(deck) = app.decks.get(state.deck) else {
        return;
    };
    if deck.prompts.is_empty() {
        frame.render_widget(
            Paragraph::new(app.tr(Msg::NoPrompts)).wrap(Wrap { trim: true }),
            area,
        );
        return;
    }
    let [list_area, detail] =
        Layout::vertical([Constraint::Fill(1), Constraint::Length(7)]).areas(area);
    // The last attempt at each prompt: ✓ right, ✗ wrong, · not tried.
    let last = app
        .services
        .study
        .store
        .last_attempts(&deck.id)
        .unwrap_or_default();
    let room = usize::from(list_area.width).saturating_sub(2 + 4 + 2);
    let items = deck.prompts.iter().enumerate().map(|(i, p)| {
        // The question's first line names the prompt (its id is for authors).
        let question = crate::text::render(&p.question_listed(&app.lang));
        let title = question
            .lines()
            .map(str::trim)
            .find(|l| !l.is_empty())
            .map_or_else(|| p.id.clone(), str::to_string);
        let (mark, style) = match last.get(&p.id) {
            Some(true) => ("✓ ", t.good()),
            Some(false) => ("✗ ", t.bad()),
            None => ("· ", t.dim()),
        };
        ListItem::new(Line::from(vec![
            Span::styled(format!("{:>2}. ", i + 1), t.dim()),
            Span::styled(mark, style),
            Span::raw(crate::tui::wrap::ellipsize(&title, room)),
        ]))
    });
    let list = List::new(items)
        .highlight_style(t.selected())
        .highlight_symbol("› ");
    let mut ls = ListState::default().with_selected(Some(state.selected));
    frame.render_stateful_widget(list, list_area, &mut ls);

    if let Some(p) = deck.prompts.get(state.selected) {
        let scene = deck.scene(&p.scene);
        let question = crate::text::render(&p.question_listed(&app.lang));
        let mut lines = crate::tui::wrap::wrap_plain(&question, t.strong(), detail.width as usize);
        lines.truncate(4);
        lines.push(Line::from(vec![
            Span::styled(format!("{}: ", app.tr(Msg::Scene)), t.dim()),
            Span::styled(
                scene
                    .and_then(|s| s.title.as_ref())
                    .map(|title| title.get(&app.lang).to_string())
                    .unwrap_or_else(|| p.scene.clone()),
                t.heading(),
            ),
        ]));
        if let Some(s) = scene {
            lines.push(Line::styled(
                format!(
                    "I = ({})  ω₀ = ({})  {} {}",
                    num::triple(&s.inertia, ", "),
                    num::triple(&s.omega, ", "),
                    Num(s.duration),
                    s.time_unit
                ),
                t.dim(),
            ));
        }
        frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: true }), detail);
    }
}
