//! Screen snapshots and key-map tests, without a terminal: keys become
//! actions through the real key map and are applied to an app on the
//! fixture deck with a temporary review store and a fixed clock.

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

use super::action::Action;
use super::stack::Tui;
use super::update::apply;

mod browser;
mod deck_options;
mod derive;
mod edit;
mod edit_content;
mod edit_typing;
mod exam;
mod explore;
mod formula_answers;
mod formula_sheet;
mod home;
mod info;
mod misconception;
mod predict;
mod predict_attempts;
mod prompt_items;
mod reader;
mod review;
mod sizes;
mod stats;
mod study;
mod sync;
mod system;

pub fn key(app: &Tui, code: KeyCode) -> Option<Action> {
    crate::tui::key_action(app, KeyEvent::new(code, KeyModifiers::NONE))
}

/// Presses a key as the event loop would.
pub fn press(app: &mut Tui, code: KeyCode) {
    if let Some(action) = key(app, code) {
        apply(app, action);
    }
}

pub fn press_all(app: &mut Tui, codes: &[KeyCode]) {
    for &c in codes {
        press(app, c);
    }
}

/// Types text into whatever field has the keyboard; a browser search
/// waiting for its index is let finish, as the event loop's ticks would.
pub fn type_text(app: &mut Tui, text: &str) {
    for c in text.chars() {
        press(app, KeyCode::Char(c));
    }
    settle(app);
}

/// Ticks while the browser waits for its search index (bounded: a build
/// that never ends fails the test instead of hanging it).
pub fn settle(app: &mut Tui) {
    let waiting =
        |app: &Tui| matches!(app.screen(), super::screens::Screen::Browser(b) if b.waiting);
    for _ in 0..30_000 {
        if !waiting(app) {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
        apply(app, Action::Tick(std::time::Duration::from_millis(1)));
    }
    panic!("the browser's search index was never ready");
}
mod formulas;
