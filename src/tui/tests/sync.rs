//! The sync after a session: run when a review, an exam share or the
//! browser closes (not when a screen that changes nothing does), before the
//! home screen counts again, and said on the status line in both languages.

use std::cell::RefCell;
use std::rc::Rc;

use crossterm::event::KeyCode;

use super::{press, press_all};
use crate::tui::i18n::{ENGLISH, HINGLISH};
use crate::tui::screens::Screen;
use crate::tui::services::Synced;
use crate::tui::testkit::{self, TestApp, render};

/// Installs a sync that counts its runs and reports `result`.
fn hook(app: &mut TestApp, result: Result<Synced, String>) -> Rc<RefCell<usize>> {
    let runs = Rc::new(RefCell::new(0));
    let seen = Rc::clone(&runs);
    app.services.after_session = Some(Box::new(move |_, _| {
        *seen.borrow_mut() += 1;
        result.clone()
    }));
    runs
}

#[test]
fn closing_a_review_syncs_once_and_says_what_came_and_went() {
    for (lang, words) in [
        (ENGLISH, "Synced: 2 sent, 1 received"),
        (HINGLISH, "Sync hua: 2 bheje, 1 aaye"),
    ] {
        let mut app = testkit::app(lang);
        let runs = hook(
            &mut app,
            Ok(Synced {
                written: 2,
                merged: 1,
                warnings: Vec::new(),
            }),
        );
        // Reading an explanation changes nothing: no sync.
        press_all(&mut app, &[KeyCode::Char('e'), KeyCode::Esc]);
        assert!(matches!(app.screen(), Screen::Home(_)));
        assert_eq!(*runs.borrow(), 0);
        press_all(
            &mut app,
            &[KeyCode::Enter, KeyCode::Char(' '), KeyCode::Char('3')],
        );
        assert_eq!(*runs.borrow(), 0, "no sync in the middle of a session");
        press(&mut app, KeyCode::Esc);
        assert!(matches!(app.screen(), Screen::Home(_)));
        assert_eq!(*runs.borrow(), 1);
        assert!(render(&app).contains(words), "{}", render(&app));
    }
}

#[test]
fn a_sync_with_nothing_to_say_stays_quiet_and_a_failed_one_is_an_error() {
    let mut app = testkit::app(ENGLISH);
    let runs = hook(&mut app, Ok(Synced::default()));
    press_all(&mut app, &[KeyCode::Char('b'), KeyCode::Esc]);
    assert_eq!(*runs.borrow(), 1, "the browser may have changed statuses");
    assert!(!render(&app).contains("Synced"), "{}", render(&app));

    let mut app = testkit::app(ENGLISH);
    hook(
        &mut app,
        Err("sync through /gone failed: no such folder".into()),
    );
    press_all(&mut app, &[KeyCode::Enter, KeyCode::Esc]);
    assert!(
        render(&app).contains("sync through /gone failed"),
        "{}",
        render(&app)
    );
    assert!(app.status.as_ref().is_some_and(|s| s.error));
}
