//! An edited deck that fails its check: the first error at file:line:col,
//! and the choice to edit again (at the error's line) or to put the file
//! back as it was before the edit. Opened by [`crate::tui::edit`].

use crossterm::event::KeyCode::{Char, Esc};
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

use crate::tui::action::Action;
use crate::tui::app::App;
use crate::tui::edit::{Pending, Session, revert};
use crate::tui::i18n::{Msg, Words, edit as words};
use crate::tui::keymap::{Binding, Context};

use super::Nav;

pub const KEYS: &[Binding] = &[
    Binding::new(
        "e",
        Words(
            "edit the file again, at the error",
            "file phir se edit karo, error par",
        ),
        &[(Char('e'), Action::EditItem)],
    ),
    Binding::new(
        "r",
        Words(
            "revert: the file back to what it was before the edit",
            "revert: file ko edit se pehle jaisi wapas karo",
        ),
        &[(Char('r'), Action::Revert)],
    ),
    Binding::new(
        "Esc q",
        Words(
            "keep the file as it is and go back (the deck is left out until fixed)",
            "file jaisi hai waisi rakho aur wapas jao (theek hone tak deck bahar)",
        ),
        &[(Esc, Action::Back), (Char('q'), Action::Back)],
    ),
];

pub struct EditCheckState {
    pub session: Session,
    /// The first error, one line: `file:line:col: error: …`.
    pub error: String,
}

impl EditCheckState {
    pub fn new(session: Session, error: String) -> EditCheckState {
        EditCheckState { session, error }
    }
}

impl super::View for EditCheckState {
    fn context(&self) -> Context {
        Context::EditCheck
    }
    fn apply(&mut self, app: &mut App, action: Action) -> Nav {
        match action {
            Action::EditItem => {
                app.edit = Some(Pending::Again(self.session.clone()));
                Nav::Stay
            }
            Action::Revert => {
                // The status line is cleared by the pop: said after it.
                match revert(&self.session) {
                    Ok(()) => {
                        app.edit_said = Some(words::REVERTED.get(&app.lang).to_string());
                        Nav::Pop
                    }
                    Err(e) => {
                        app.error(e);
                        Nav::Stay
                    }
                }
            }
            Action::Back => {
                app.edit_said = Some(words::KEPT_BROKEN.get(&app.lang).to_string());
                Nav::Pop
            }
            _ => Nav::Stay,
        }
    }
    fn draw(&self, frame: &mut Frame, area: Rect, app: &App) {
        let t = &app.theme;
        let lines = vec![
            Line::from(Span::styled(words::FAILED.get(&app.lang), t.heading())),
            Line::from(""),
            Line::from(Span::styled(self.error.clone(), t.bad())),
            Line::from(""),
            Line::from(Span::styled(words::CHOICES.get(&app.lang), t.dim())),
        ];
        frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), area);
    }
    fn name(&self) -> Msg {
        Msg::DeckCheck
    }
}
