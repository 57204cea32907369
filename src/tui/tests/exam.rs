//! Exam mode: the date prompt, its errors, and today's share studied with
//! the expected recall on exam day rising as cards are answered.

use crossterm::event::KeyCode;

use super::{press, press_all, type_text};
use crate::tui::i18n::{ENGLISH, HINGLISH};
use crate::tui::keymap::Context;
use crate::tui::screens::Screen;
use crate::tui::screens::exam::{ExamState, Phase};
use crate::tui::testkit::{self, render};

fn exam(app: &crate::tui::Tui) -> &ExamState {
    match app.screen() {
        Screen::Exam(e) => e,
        _ => panic!("the exam screen is not open"),
    }
}

/// (expected recall on exam day now, planned for today, all items).
fn progress(app: &crate::tui::Tui) -> (f64, usize, usize) {
    match &exam(app).phase {
        Phase::Study(s) => (s.now, s.share, s.keys.len()),
        Phase::Date { .. } => panic!("still asking for the date"),
    }
}

#[test]
fn a_wrong_date_is_said_in_the_screen_and_can_be_corrected() {
    let mut app = testkit::app(ENGLISH);
    press(&mut app, KeyCode::Char('x'));
    assert_eq!(app.context(), Context::ExamDate);
    type_text(&mut app, "2026-13-01");
    press(&mut app, KeyCode::Enter);
    assert!(render(&app).contains("Not a date"), "{}", render(&app));
    for _ in 0..10 {
        press(&mut app, KeyCode::Backspace);
    }
    // Today is 2026-03-02 on the test clock.
    type_text(&mut app, "2026-03-01");
    press(&mut app, KeyCode::Enter);
    assert!(
        render(&app).contains("That day has passed"),
        "{}",
        render(&app)
    );
    assert_eq!(app.context(), Context::ExamDate);
    press(&mut app, KeyCode::Esc);
    assert!(matches!(app.screen(), Screen::Home(_)));
}

#[test]
fn studying_todays_share_raises_the_expected_recall_on_exam_day() {
    for lang in [ENGLISH, HINGLISH] {
        let mut app = testkit::app(lang);
        press(&mut app, KeyCode::Char('x'));
        insta::assert_snapshot!(format!("exam_date_{lang}"), render(&app));
        // The exam is tomorrow: every card must be reviewed today.
        type_text(&mut app, "2026-03-03");
        press(&mut app, KeyCode::Enter);
        let (before, share, items) = progress(&app);
        assert_eq!(before, 0.0, "nothing reviewed yet");
        assert_eq!(share, items, "everything is planned for today");
        assert_eq!(app.context(), Context::ReviewFront);
        let mut last = before;
        for _ in 0..2 {
            press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('3')]);
            let (now, _, _) = progress(&app);
            assert!(
                now > last + 0.5,
                "each Good answer adds most of a card: {last} → {now}"
            );
            last = now;
        }
        insta::assert_snapshot!(format!("exam_study_{lang}"), render(&app));
        // Undo takes the gain back.
        press(&mut app, KeyCode::Char('u'));
        let (undone, _, _) = progress(&app);
        assert!(undone < last, "{undone} after undo, {last} before");
        press(&mut app, KeyCode::Char('?'));
        insta::assert_snapshot!(format!("exam_study_help_{lang}"), render(&app));
        press_all(&mut app, &[KeyCode::Char('?'), KeyCode::Esc]);
        assert!(matches!(app.screen(), Screen::Home(_)));
    }
}

/// The card on screen in today's share.
fn shown(app: &crate::tui::Tui) -> Option<crate::sched::ItemKey> {
    match &exam(app).phase {
        Phase::Study(s) => s.review.current.as_ref().map(|(k, _)| k.clone()),
        Phase::Date { .. } => panic!("still asking for the date"),
    }
}

#[test]
fn an_again_in_todays_share_comes_back_at_its_step_not_at_the_end() {
    let mut app = testkit::app(ENGLISH);
    press(&mut app, KeyCode::Char('x'));
    type_text(&mut app, "2026-03-03");
    press(&mut app, KeyCode::Enter);
    let (_, share, _) = progress(&app);
    assert!(
        share >= 3,
        "the fixture plans at least three items: {share}"
    );
    let Some(first) = shown(&app) else {
        panic!("no card in today's share");
    };
    press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('1')]);
    let step = app
        .services
        .study
        .store
        .state(&first)
        .ok()
        .flatten()
        .map(|s| s.due);
    let Some(step) = step else {
        panic!("Again stored no state");
    };
    // Before its step the plan goes on with another card.
    let second = shown(&app);
    assert!(second.is_some() && second.as_ref() != Some(&first));
    press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('3')]);
    // At its step it comes before the rest of the plan.
    app.services.clock = crate::tui::services::Clock::Fixed(step);
    press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('3')]);
    assert_eq!(shown(&app), Some(first));
}

/// The date planned for is remembered in the config and the exam screen
/// opens with it filled in, until the day has passed.
#[test]
fn the_exam_date_is_remembered_and_offered_until_it_passes() {
    let mut app = testkit::app(ENGLISH);
    let config = app.dir.path().join("config.toml");
    app.services.config_path = Some(config.clone());
    let input = |app: &crate::tui::Tui| match &exam(app).phase {
        Phase::Date { input, .. } => input.clone(),
        Phase::Study(_) => panic!("not asking for the date"),
    };
    press(&mut app, KeyCode::Char('x'));
    assert_eq!(input(&app), "", "nothing remembered yet");
    type_text(&mut app, "2026-03-20");
    press(&mut app, KeyCode::Enter);
    assert!(matches!(exam(&app).phase, Phase::Study(_)));
    let written = std::fs::read_to_string(&config).unwrap_or_default();
    assert_eq!(written, "exam_date = \"2026-03-20\"\n");
    for _ in 0..3 {
        if matches!(app.screen(), Screen::Home(_)) {
            break;
        }
        press(&mut app, KeyCode::Esc);
    }
    assert!(matches!(app.screen(), Screen::Home(_)));

    // Opened again: the date is there, Enter plans for it.
    press(&mut app, KeyCode::Char('x'));
    assert_eq!(input(&app), "2026-03-20");
    assert!(render(&app).contains("2026-03-20"), "{}", render(&app));
    press(&mut app, KeyCode::Enter);
    match &exam(&app).phase {
        Phase::Study(s) => assert_eq!(s.exam.to_string(), "2026-03-20"),
        Phase::Date { .. } => panic!("the remembered date was not taken"),
    }

    // A remembered date that has passed (today is 2026-03-02) is not offered.
    app.services.study.config.exam_date = chrono::NaiveDate::from_ymd_opt(2026, 3, 1);
    let state = ExamState::new(&app, 0);
    assert!(matches!(state.phase, Phase::Date { ref input, .. } if input.is_empty()));
}
