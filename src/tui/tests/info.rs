//! Card info (`i`): from the review screen and the browser, the item's
//! history as the store has it (each answer's rating, interval, time, the
//! recall at that moment, stability and difficulty after it), its state
//! now; snapshots in both languages, and every size drawn without a panic.

use chrono::TimeDelta;
use crossterm::event::KeyCode;

use super::{key, press, press_all};
use crate::sched::{Rating, ReviewKind};
use crate::tui::action::Action;
use crate::tui::i18n::{ENGLISH, HINGLISH};
use crate::tui::keymap::Context;
use crate::tui::screens::Screen;
use crate::tui::services::Clock;
use crate::tui::testkit::{self, TestApp, render};

fn current(app: &TestApp) -> String {
    match app.screen() {
        Screen::Review(r) => r
            .current
            .as_ref()
            .map(|(k, _)| format!("{}:{}", k.card, k.direction.as_str()))
            .unwrap_or_default(),
        _ => panic!("not on the review screen"),
    }
}

/// The first card answered Good today and Hard the next day, then card
/// info opened on it from the browser.
fn answered_twice(lang: &str) -> TestApp {
    let mut app = testkit::app(lang);
    press(&mut app, KeyCode::Enter);
    assert_eq!(current(&app), "body-frame-why:forward");
    press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('3')]);
    press(&mut app, KeyCode::Esc);
    app.services.clock = Clock::Fixed(testkit::now() + TimeDelta::days(1));
    press(&mut app, KeyCode::Enter);
    assert_eq!(current(&app), "body-frame-why:forward");
    press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('2')]);
    press(&mut app, KeyCode::Esc);
    app.services.clock = Clock::Fixed(testkit::now() + TimeDelta::days(3));
    press(&mut app, KeyCode::Char('b'));
    assert_eq!(app.context(), Context::Browser);
    assert_eq!(key(&app, KeyCode::Char('i')), Some(Action::CardInfo));
    press(&mut app, KeyCode::Char('i'));
    assert_eq!(app.context(), Context::Info);
    app
}

#[test]
fn card_info_shows_the_history_the_store_has() {
    for lang in [ENGLISH, HINGLISH] {
        let app = answered_twice(lang);
        let Screen::Info(info) = app.screen() else {
            panic!("not on card info");
        };
        assert_eq!(info.key.card, "body-frame-why");
        // The log as the store has it, oldest first.
        let logged: Vec<_> = app
            .services
            .study
            .store
            .history(&info.key)
            .unwrap()
            .into_iter()
            .filter(|l| !l.undone)
            .map(|l| l.record)
            .collect();
        assert_eq!(logged.len(), 2);
        let ratings: Vec<Rating> = info.answers.iter().map(|a| a.rating).collect();
        assert_eq!(ratings, [Rating::Good, Rating::Hard]);
        for (a, r) in info.answers.iter().zip(&logged) {
            assert_eq!(a.at, r.reviewed_at);
            assert_eq!(a.interval, r.after.due - r.reviewed_at);
            assert_eq!(a.stability, r.after.stability);
            assert_eq!(a.difficulty, r.after.difficulty);
        }
        assert_eq!(info.answers[0].kind, ReviewKind::Learn);
        // No recall before the first answer; the second one's is the
        // scheduler's, from the state the first left, a day later.
        assert_eq!(info.answers[0].recall, None);
        let expected = app
            .services
            .study
            .scheduler
            .retrievability(&logged[0].after, logged[1].reviewed_at);
        assert_eq!(info.answers[1].recall, Some(expected));
        let now_state = logged[1].after;
        assert_eq!(
            info.recall_now,
            Some(
                app.services
                    .study
                    .scheduler
                    .retrievability(&now_state, testkit::now() + TimeDelta::days(3))
            )
        );
        let screen = render(&app);
        assert!(screen.contains("body-frame-why"), "{screen}");
        let (good, hard) = if lang == ENGLISH {
            ("Good", "Mushkil")
        } else {
            ("Theek", "Mushkil")
        };
        let hard = if lang == ENGLISH { "Hard" } else { hard };
        assert!(screen.contains(good) && screen.contains(hard), "{screen}");
        insta::assert_snapshot!(format!("card_info_{lang}"), screen);
        let mut app = app;
        press(&mut app, KeyCode::Esc);
        assert_eq!(app.context(), Context::Browser);
    }
}

#[test]
fn card_info_opens_from_the_review_screen_and_comes_back() {
    let mut app = testkit::app(ENGLISH);
    press(&mut app, KeyCode::Enter);
    assert_eq!(app.context(), Context::ReviewFront);
    assert_eq!(key(&app, KeyCode::Char('i')), Some(Action::CardInfo));
    press(&mut app, KeyCode::Char('i'));
    let Screen::Info(info) = app.screen() else {
        panic!("not on card info");
    };
    assert_eq!(info.key.card, "body-frame-why");
    assert!(info.answers.is_empty());
    assert!(
        render(&app).contains("Not answered yet"),
        "{}",
        render(&app)
    );
    // `i` again closes it; the card waits as it was, then on the back.
    press(&mut app, KeyCode::Char('i'));
    assert_eq!(app.context(), Context::ReviewFront);
    press(&mut app, KeyCode::Char(' '));
    assert_eq!(app.context(), Context::ReviewBack);
    assert_eq!(key(&app, KeyCode::Char('i')), Some(Action::CardInfo));
    press(&mut app, KeyCode::Char('i'));
    assert_eq!(app.context(), Context::Info);
    press(&mut app, KeyCode::Char('q'));
    assert_eq!(app.context(), Context::ReviewBack);
    // The help lists the key (drawn from the same table).
    press(&mut app, KeyCode::Char('?'));
    assert!(render(&app).contains("card info"), "{}", render(&app));
}

#[test]
fn card_info_draws_at_every_size() {
    let mut app = answered_twice(ENGLISH);
    // Narrow: the date without its year, no time taken, and R, S, D kept.
    app.size = (40, 12);
    let screen = render(&app);
    let hard = screen
        .lines()
        .find(|l| l.contains("03-03 Hard"))
        .unwrap_or_else(|| panic!("{screen}"));
    assert!(hard.contains("95%") && hard.contains("4.8"), "{screen}");
    for (w, h) in [
        (80, 24),
        (40, 12),
        (120, 40),
        (20, 5),
        (1, 1),
        (2, 30),
        (200, 2),
    ] {
        app.size = (w, h);
        let _ = render(&app);
        for k in [
            KeyCode::Char('j'),
            KeyCode::PageDown,
            KeyCode::Char('G'),
            KeyCode::Char('g'),
        ] {
            press(&mut app, k);
            let _ = render(&app);
        }
    }
}
