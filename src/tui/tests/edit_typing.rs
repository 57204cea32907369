//! Editing while an answer is typed (issue 25 §5): there `E` and `A` are
//! letters, so `F4` edits and `F7` adds, through the real key tables (the
//! help and the footer show them), and what was typed is still there when
//! the editor closes: a typed card, a derivation step's formula, a
//! prompt's number.

use std::path::{Path, PathBuf};

use crossterm::event::KeyCode::{Backspace, Char, Enter, Esc, F};

use super::edit::{Scripted, fixture, item, replace, shown, status};
use super::{press, press_all};
use crate::sched::{Direction, ItemKey};
use crate::tui::edit::NoTerminal;
use crate::tui::edit_run::run_pending;
use crate::tui::keymap::Context;
use crate::tui::screens::Screen;
use crate::tui::screens::review::Phase;
use crate::tui::stack::Tui;
use crate::tui::testkit::{render, services};
use crate::tui::theme::Theme;

/// A key code, then the edit it asked for, as the event loop carries it
/// out.
fn code(app: &mut Tui, c: crossterm::event::KeyCode) {
    press(app, c);
    run_pending(app, &mut NoTerminal);
}

fn typed(app: &Tui) -> String {
    match app.screen() {
        Screen::Review(r) => match &r.phase {
            Phase::Front { input } => input.clone(),
            _ => panic!("not on a front:\n{}", render(app)),
        },
        Screen::Predict(p) => match &p.phase {
            crate::tui::screens::predict::Phase::Ask { input, .. } => input.clone(),
            _ => panic!("not asking:\n{}", render(app)),
        },
        _ => panic!("nothing typed here:\n{}", render(app)),
    }
}

fn type_keys(app: &mut Tui, text: &str) {
    for c in text.chars() {
        code(app, Char(c));
    }
}

#[test]
fn f4_while_typing_edits_the_card_and_keeps_the_answer_typed() {
    let mut f = fixture(vec![replace("The unit of force?", "The SI unit of force?")]);
    press_all(&mut f.app, &[Char(' '), Char('3')]);
    assert_eq!(shown(&f.app), Some(item("unit")));
    assert_eq!(f.app.context(), Context::ReviewTyping);
    // `E` and `A` are letters of the answer here.
    type_keys(&mut f.app, "newtEA");
    assert_eq!(typed(&f.app), "newtEA");
    assert!(f.editor.opened.borrow().is_empty());
    press_all(&mut f.app, &[Backspace, Backspace]);
    // The footer offers the keys that work while typing, from the table.
    let screen = render(&f.app);
    let footer = screen.lines().last().unwrap();
    assert!(footer.contains("F4 edit"), "{footer}");
    assert!(footer.contains("F7 add card"), "{footer}");
    code(&mut f.app, F(4));
    assert_eq!(*f.editor.opened.borrow(), [(f.file.clone(), 12)]);
    assert_eq!(f.app.context(), Context::ReviewTyping);
    assert_eq!(typed(&f.app), "newt");
    let screen = render(&f.app);
    assert!(screen.contains("The SI unit of force?"), "{screen}");
    assert!(status(&f.app).contains("reloaded"), "{}", status(&f.app));
    // Finished and checked as if never interrupted.
    type_keys(&mut f.app, "on");
    press(&mut f.app, Enter);
    let Screen::Review(r) = f.app.screen() else {
        panic!("left the review");
    };
    let Phase::Back {
        typed: Some(answer),
        ..
    } = &r.phase
    else {
        panic!("not checked:\n{}", render(&f.app));
    };
    assert_eq!(answer.text, "newton");
    assert_eq!(answer.check.suggested, crate::sched::Rating::Good);
}

#[test]
fn f7_while_typing_adds_a_card_that_comes_after_the_answer_typed() {
    let mut f = fixture(vec![replace(
        "'''The question.'''",
        "'''The unit of power?'''",
    )]);
    press_all(&mut f.app, &[Char(' '), Char('3')]);
    type_keys(&mut f.app, "newt");
    code(&mut f.app, F(7));
    assert!(f.app.decks[0].card("new-card-1").is_some());
    assert!(
        status(&f.app).contains("card added `new-card-1`"),
        "{}",
        status(&f.app)
    );
    // Still the card being answered, with its answer so far.
    assert_eq!(shown(&f.app), Some(item("unit")));
    assert_eq!(typed(&f.app), "newt");
    type_keys(&mut f.app, "on");
    press_all(&mut f.app, &[Enter, Enter]);
    // Then the new card.
    assert_eq!(shown(&f.app), Some(item("new-card-1")));
    assert!(render(&f.app).contains("The unit of power?"));
}

/// The derive test deck copied to a folder of its own (it is edited).
fn derive_app(editor: &Scripted) -> (Tui, PathBuf, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let from = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/decks/derive"));
    for rel in [
        "decks/derive.toml",
        "content/derive/en.toml",
        "content/derive/hi-Latn.toml",
    ] {
        let to = dir.path().join(rel);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(from.join(rel), &to).unwrap();
    }
    let loaded = crate::deck::load_paths(&[dir.path().join("decks")]);
    assert_eq!(loaded.errors(), 0, "{}", loaded.render_all());
    let mut app = Tui::new(loaded.decks, services(&dir), "en", Theme::PLAIN);
    app.size = (90, 40);
    app.services.editor = Box::new(editor.clone());
    (app, dir.path().join("decks/derive.toml"), dir)
}

fn derivation() -> ItemKey {
    ItemKey {
        deck: "derive".into(),
        card: "euler".into(),
        direction: Direction::Derive,
    }
}

/// Opens today's review from home and goes past the card to the
/// derivation.
fn to_derivation(app: &mut Tui) {
    press(app, Enter);
    if shown(app).is_some_and(|k| k.direction != Direction::Derive) {
        press_all(app, &[Char(' '), Char('3')]);
    }
    assert_eq!(shown(app), Some(derivation()), "{}", render(app));
}

#[test]
fn f4_at_a_derivation_steps_formula_keeps_the_walk_and_the_formula_typed() {
    let editor = Scripted::default();
    editor.steps.borrow_mut().push(replace(
        "why = { en = 'Set the torque to zero.'",
        "why = { en = 'No torque: set it to zero.'",
    ));
    let (mut app, file, _dir) = derive_app(&editor);
    // Worked once, then a day later its formula step is faded.
    to_derivation(&mut app);
    press_all(&mut app, &[Char(' '), Enter, Char('3'), Esc]);
    app.services.clock =
        crate::tui::services::Clock::Fixed(crate::tui::testkit::now() + chrono::TimeDelta::days(1));
    to_derivation(&mut app);
    press(&mut app, Char(' '));
    assert_eq!(app.context(), Context::ReviewTyping);
    type_keys(&mut app, "(I2-I3)");
    let walked = match app.screen() {
        Screen::Review(r) => r.walk.clone().unwrap(),
        _ => unreachable!(),
    };
    code(&mut app, F(4));
    assert_eq!(*editor.opened.borrow(), [(file, 12)]);
    assert_eq!(app.context(), Context::ReviewTyping);
    assert_eq!(typed(&app), "(I2-I3)");
    let Screen::Review(r) = app.screen() else {
        panic!("left the review");
    };
    assert_eq!(r.walk.as_ref(), Some(&walked));
    let screen = render(&app);
    assert!(
        screen.contains("hint: No torque: set it to zero."),
        "{screen}"
    );
    type_keys(&mut app, " w2 w3/I1");
    press(&mut app, Enter);
    assert_eq!(app.context(), Context::ReviewBack);
    let Screen::Review(r) = app.screen() else {
        panic!("left the review");
    };
    let verdicts = &r.walk.as_ref().unwrap().verdicts;
    assert_eq!(
        verdicts.last().cloned().flatten(),
        Some(crate::study::derive::StepVerdict::Right)
    );
}

#[test]
fn f4_in_a_prompts_number_entry_edits_the_prompt_and_keeps_the_number_typed() {
    let dir = tempfile::tempdir().unwrap();
    let from = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/decks/valid/full"
    ));
    for rel in [
        "decks/spinning-top.toml",
        "content/spinning-top/en.toml",
        "content/spinning-top/hi-Latn.toml",
    ] {
        let to = dir.path().join(rel);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(from.join(rel), &to).unwrap();
    }
    let file = dir.path().join("decks/spinning-top.toml");
    let loaded = crate::deck::load_paths(&[dir.path().join("decks")]);
    assert_eq!(loaded.errors(), 0, "{}", loaded.render_all());
    let mut app = Tui::new(loaded.decks, services(&dir), "en", Theme::PLAIN);
    app.size = (100, 30);
    let editor = Scripted::default();
    editor.steps.borrow_mut().push(replace(
        "How long until a small wobble grows $e$-fold?",
        "How many seconds until a small wobble grows $e$-fold?",
    ));
    app.services.editor = Box::new(editor.clone());
    let i = app.decks[0]
        .prompts
        .iter()
        .position(|p| p.id == "racket-efold")
        .unwrap();
    let predict = crate::tui::screens::predict::PredictState::new(&app, 0, i);
    app.push(Screen::Predict(Box::new(predict)));
    assert_eq!(app.context(), Context::PredictNumber);
    // `A` is a unit's letter here (the ampere), `E` an exponent's.
    type_keys(&mut app, "0.1E");
    assert_eq!(typed(&app), "0.1E");
    press(&mut app, Backspace);
    code(&mut app, F(4));
    let text = std::fs::read_to_string(&file).unwrap();
    let line = text
        .lines()
        .position(|l| l == "id = \"racket-efold\"")
        .unwrap()
        + 1;
    assert_eq!(*editor.opened.borrow(), [(file.clone(), line)]);
    assert_eq!(app.context(), Context::PredictNumber);
    assert_eq!(typed(&app), "0.1");
    let screen = render(&app);
    assert!(
        screen.contains("How many seconds until a small wobble"),
        "{screen}"
    );
    type_keys(&mut app, "7 s");
    press(&mut app, Enter);
    let Screen::Predict(p) = app.screen() else {
        panic!("left the prompt");
    };
    let crate::tui::screens::predict::Phase::Play { prediction, .. } = &p.phase else {
        panic!("not committed:\n{}", render(&app));
    };
    assert_eq!(
        *prediction,
        crate::tui::screens::predict::Prediction::Number(0.17)
    );
}
