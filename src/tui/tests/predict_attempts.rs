//! Attempts kept at the moment of commitment, through the predict screen's
//! keys: the attempt is on disk before the run starts; a learner who leaves
//! the run and answers again has both kept, the first as the first attempt
//! (without a verdict), the second as a retry (with its verdict); a write
//! that fails keeps the screen on the question.

use crossterm::event::KeyCode;

use super::{press, press_all};
use crate::store::{Store, StoredAttempt};
use crate::tui::action::Action;
use crate::tui::keymap::Context;
use crate::tui::screens::Screen;
use crate::tui::screens::predict::Phase;
use crate::tui::testkit::{self, TestApp, render};

fn tick(app: &mut TestApp, ms: u64) {
    crate::tui::update::apply(app, Action::Tick(std::time::Duration::from_millis(ms)));
}

/// Every attempt on disk, read through a connection of its own (what a
/// killed app leaves is what another process finds).
pub(super) fn on_disk(app: &TestApp) -> Vec<StoredAttempt> {
    let store = Store::open_read_only(app.dir.path()).expect("the store opens");
    let mut out = Vec::new();
    store
        .each_attempt(|a| {
            out.push(a);
            Ok::<_, crate::store::StoreError>(())
        })
        .expect("attempts read");
    out
}

/// The middle-axis choice prompt (the first of the list).
fn open_choice_prompt() -> TestApp {
    let mut app = testkit::app(crate::tui::i18n::ENGLISH);
    press(&mut app, KeyCode::Char('p'));
    press(&mut app, KeyCode::Enter);
    assert_eq!(app.context(), Context::PredictChoice);
    app
}

#[test]
fn the_attempt_is_on_disk_when_the_run_starts() {
    let mut app = open_choice_prompt();
    assert!(on_disk(&app).is_empty());
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    assert_eq!(app.context(), Context::PredictRun, "the run started");
    // Not one frame of the run has played: the commitment is already kept.
    let rows = on_disk(&app);
    assert_eq!(rows.len(), 1, "{rows:?}");
    assert_eq!(
        (rows[0].prompt.as_str(), rows[0].prediction.as_str()),
        ("middle-axis", "stable")
    );
    assert_eq!(rows[0].attempt, 1);
    assert!(!rows[0].is_retry());
    assert_eq!(rows[0].verdict, None, "no verdict before the run ends");
}

#[test]
fn esc_mid_run_then_answering_again_keeps_both_the_second_as_a_retry() {
    let mut app = open_choice_prompt();
    // First commitment: "stable" (wrong), then Esc half a second in.
    press_all(&mut app, &[KeyCode::Char('1'), KeyCode::Enter]);
    for _ in 0..5 {
        tick(&mut app, 100);
    }
    press(&mut app, KeyCode::Esc);
    assert_eq!(app.context(), Context::Prompts, "back on the prompt list");
    // Again, now "flips" (right), watched to the end at ×8.
    press(&mut app, KeyCode::Enter);
    press_all(&mut app, &[KeyCode::Char('2'), KeyCode::Enter]);
    press_all(
        &mut app,
        &[KeyCode::Char('+'), KeyCode::Char('+'), KeyCode::Char('+')],
    );
    for _ in 0..7 {
        tick(&mut app, 100);
    }
    assert_eq!(app.context(), Context::PredictVerdict);
    // Watching again writes nothing more.
    press(&mut app, KeyCode::Char('r'));
    for _ in 0..10 {
        tick(&mut app, 100);
    }
    let rows = on_disk(&app);
    let got: Vec<(&str, u32, bool, Option<bool>)> = rows
        .iter()
        .map(|a| {
            (
                a.prediction.as_str(),
                a.attempt,
                a.is_retry(),
                a.verdict.map(|v| v.correct),
            )
        })
        .collect();
    assert_eq!(
        got,
        [("stable", 1, false, None), ("flips", 2, true, Some(true))],
        "the first prediction is the first attempt; the second a retry"
    );
    // The export says the same: the first without a verdict, the second a retry.
    let store = Store::open_read_only(app.dir.path()).unwrap();
    let mut json = Vec::new();
    crate::interop::export::write_attempts_json(&store, &mut json).unwrap();
    let v: serde_json::Value = serde_json::from_slice(&json).unwrap();
    assert_eq!(v[0]["correct"], serde_json::Value::Null, "{v}");
    assert_eq!(
        (v[0]["attempt"].as_u64(), v[0]["retry"].as_bool()),
        (Some(1), Some(false))
    );
    assert_eq!(v[1]["correct"], serde_json::Value::Bool(true), "{v}");
    assert_eq!(
        (v[1]["attempt"].as_u64(), v[1]["retry"].as_bool()),
        (Some(2), Some(true))
    );
}

#[test]
fn a_commitment_that_cannot_be_written_keeps_the_question_on_screen() {
    let mut app = open_choice_prompt();
    // Another program makes every new attempt fail (as a full disk would).
    let conn = rusqlite::Connection::open(app.dir.path().join("flipcard.db")).unwrap();
    conn.execute_batch(
        "CREATE TRIGGER refuse BEFORE INSERT ON prompt_attempt \
         BEGIN SELECT RAISE(ABORT, 'database or disk is full'); END;",
    )
    .unwrap();
    drop(conn);
    press_all(&mut app, &[KeyCode::Char('2'), KeyCode::Enter]);
    assert_eq!(
        app.context(),
        Context::PredictChoice,
        "the run does not start without its attempt kept"
    );
    assert!(!app.animating(), "nothing runs");
    let Screen::Predict(p) = app.screen() else {
        panic!("left the predict screen");
    };
    assert!(
        matches!(p.phase, Phase::Ask { selected: 1, .. }),
        "the choice stays"
    );
    let screen = render(&app);
    assert!(
        screen.contains("disk is full"),
        "the screen says why: {screen}"
    );
    assert!(on_disk(&app).is_empty());
}
