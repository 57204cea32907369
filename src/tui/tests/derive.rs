//! Derivations step by step (issue 24 §5) through the real review screen:
//! a worked example the first time, rated through `Study::rate` and stored
//! with direction `derive`; on a later day (the app's clock moved) the last
//! steps faded, a faded formula checked by equivalence and a faded choice
//! by its answer, the rating suggested from the verdicts; the reader's
//! page of each derivation; both languages and every size.

use crossterm::event::KeyCode::{self, Char, Enter, Esc};

use super::{press, press_all, type_text};
use crate::deck::Deck;
use crate::sched::{Direction, ItemKey, Rating};
use crate::tui::i18n::{ENGLISH, HINGLISH};
use crate::tui::keymap::Context;
use crate::tui::screens::Screen;
use crate::tui::screens::review::ReviewState;
use crate::tui::services::Clock;
use crate::tui::stack::Tui;
use crate::tui::testkit::{self, TestApp, render};
use crate::tui::theme::Theme;

/// The test deck: one card, then a derivation of three steps (the second
/// asks a choice, the third a formula).
fn deck() -> Deck {
    let loaded = crate::deck::load_dir(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/decks/derive/decks"
    )));
    let errors: Vec<&str> = loaded
        .diagnostics
        .iter()
        .map(|d| d.message.as_str())
        .collect();
    assert!(errors.is_empty(), "{errors:?}");
    loaded
        .decks
        .into_iter()
        .next()
        .expect("the derive deck loads")
}

fn app(lang: &str) -> TestApp {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = Tui::new(vec![deck()], testkit::services(&dir), lang, Theme::PLAIN);
    app.size = (90, 40);
    TestApp { app, dir }
}

fn key() -> ItemKey {
    ItemKey {
        deck: "derive".into(),
        card: "euler".into(),
        direction: Direction::Derive,
    }
}

fn review(app: &TestApp) -> &ReviewState {
    match app.screen() {
        Screen::Review(r) => r,
        _ => panic!("not on the review screen:\n{}", render(app)),
    }
}

fn shown(app: &TestApp) -> Option<ItemKey> {
    review(app).current.as_ref().map(|(k, _)| k.clone())
}

/// Ratings of the derivation in the log, oldest first, as stored.
fn ratings(app: &TestApp) -> Vec<(String, i64)> {
    let history = app
        .services
        .study
        .store
        .history(&key())
        .expect("the log reads");
    history
        .iter()
        .filter(|r| !r.undone)
        .map(|r| {
            (
                r.record.key.direction.as_str().into_owned(),
                r.record.rating as i64,
            )
        })
        .collect()
}

/// Opens today's review from the home screen, rates the card that comes
/// first with Good, and stops at the derivation.
fn to_derivation(app: &mut TestApp) {
    press(app, Enter);
    if shown(app).is_some_and(|k| k.direction != Direction::Derive) {
        press_all(app, &[Char(' '), Char('3')]);
    }
    assert_eq!(shown(app), Some(key()), "{}", render(app));
}

/// A day later on the app's clock.
fn next_day(app: &mut TestApp, days: i64) {
    app.services.clock = Clock::Fixed(testkit::now() + chrono::TimeDelta::days(days));
}

#[test]
fn a_derivation_is_worked_first_then_faded_and_checked_on_later_days() {
    let mut app = app(ENGLISH);
    to_derivation(&mut app);
    // The first time: a worked example, one step at a time.
    assert_eq!(app.context(), Context::ReviewDerive);
    let first = render(&app);
    assert!(first.contains("Worked example"), "{first}");
    assert!(first.contains("why: The transport theorem."), "{first}");
    assert!(!first.contains("Cross product by components"), "{first}");
    assert!(!first.contains("your step"), "{first}");
    press(&mut app, Char(' '));
    let second = render(&app);
    assert!(
        second.contains("why: Cross product by components."),
        "{second}"
    );
    assert!(second.contains("(I₃ − I₂) ω₂ω₃"), "{second}");
    assert!(!second.contains("Set the torque to zero"), "{second}");
    // The last step shown, the rating is asked.
    press(&mut app, Enter);
    assert_eq!(app.context(), Context::ReviewBack);
    let all = render(&app);
    assert!(all.contains("why: Set the torque to zero."), "{all}");
    assert!(all.contains("I₁ω̇₁ = (I₂ − I₃) ω₂ω₃"), "{all}");
    assert!(all.contains("3 Good"), "{all}");
    press(&mut app, Char('3'));
    assert_eq!(ratings(&app), [("derive".to_string(), 3)]);

    // A day later: the last step with an ask (the formula) is faded.
    press(&mut app, Esc);
    next_day(&mut app, 1);
    to_derivation(&mut app);
    let faded = render(&app);
    assert!(
        faded.contains("Your turn: steps to supply: 1 of 3"),
        "{faded}"
    );
    press(&mut app, Char(' '));
    assert_eq!(app.context(), Context::ReviewTyping);
    let asked = render(&app);
    assert!(asked.contains("[ your step ]"), "{asked}");
    assert!(asked.contains("hint: Set the torque to zero."), "{asked}");
    assert!(asked.contains("Type ω̇₁."), "{asked}");
    assert!(
        !asked.contains("I₁ω̇₁ = (I₂ − I₃)"),
        "the math is hidden:\n{asked}"
    );
    // The wrong sign: checked by equivalence, and the slip named.
    type_text(&mut app, "(I3-I2) w2 w3/I1");
    press(&mut app, Enter);
    assert_eq!(app.context(), Context::ReviewBack);
    let verdict = render(&app);
    assert!(verdict.contains("✗ not quite"), "{verdict}");
    assert!(verdict.contains("you typed: (I3-I2) w2 w3/I1"), "{verdict}");
    assert!(verdict.contains("sign"), "{verdict}");
    assert!(
        verdict.contains("I₁ω̇₁ = (I₂ − I₃) ω₂ω₃"),
        "revealed:\n{verdict}"
    );
    assert!(
        verdict.contains("steps you supplied right: 0/1"),
        "{verdict}"
    );
    // Enter takes the suggested rating: Hard, one faded step wrong.
    assert!(verdict.contains("Hard"), "{verdict}");
    press(&mut app, Enter);
    assert_eq!(
        ratings(&app),
        [("derive".to_string(), 3), ("derive".to_string(), 2)]
    );

    // Later still: the choice fades too, from the end backwards.
    press(&mut app, Esc);
    next_day(&mut app, 10);
    to_derivation(&mut app);
    assert!(render(&app).contains("2 of 3"), "{}", render(&app));
    // Step 1 is worked; step 2 asks its choice.
    assert_eq!(app.context(), Context::ReviewDerive);
    let choice = render(&app);
    assert!(
        choice.contains("hint: Cross product by components."),
        "{choice}"
    );
    assert!(choice.contains("1 (I₂ + I₃)"), "{choice}");
    assert!(
        !choice.contains("(ω⃗ × L⃗)₁"),
        "the math is hidden:\n{choice}"
    );
    // Enter before a choice says to choose; nothing is checked.
    press(&mut app, Enter);
    assert_eq!(app.context(), Context::ReviewDerive);
    press(&mut app, Char('2'));
    assert!(render(&app).contains("▸ 2"), "{}", render(&app));
    press(&mut app, Enter);
    let right = render(&app);
    assert!(right.contains("✓ right · you chose: (I₃ − I₂)"), "{right}");
    assert!(right.contains("(ω⃗ × L⃗)₁"), "revealed:\n{right}");
    assert_eq!(app.context(), Context::ReviewTyping);
    type_text(&mut app, "(I_2 - I_3) ω₂ ω₃ / I₁");
    press(&mut app, Enter);
    let done = render(&app);
    assert!(done.contains("steps you supplied right: 2/2"), "{done}");
    press(&mut app, Enter);
    let stored = ratings(&app);
    assert_eq!(
        stored.last(),
        Some(&("derive".to_string(), Rating::Good as i64))
    );

    // The catalog (the browser, `cards list`) has the row, named derive.
    let rows = crate::catalog::rows(
        &app.decks,
        &app.services.study.store,
        &app.services.study.scheduler,
        app.services.now(),
    )
    .expect("rows");
    let row = rows
        .iter()
        .find(|r| r.direction == Direction::Derive)
        .expect("a derive row");
    assert_eq!(row.card_id(&app.decks), "euler");
    assert_eq!(row.reviews, 3);
    assert_eq!(row.key(&app.decks), key());
}

#[test]
fn a_lapse_brings_a_faded_step_back() {
    let mut app = app(ENGLISH);
    to_derivation(&mut app);
    press_all(&mut app, &[Char(' '), Char(' '), Char('3')]);
    press(&mut app, Esc);
    next_day(&mut app, 1);
    to_derivation(&mut app);
    assert!(render(&app).contains("1 of 3"));
    // Forgot it: Again.
    press(&mut app, Char(' '));
    type_text(&mut app, "1");
    press_all(&mut app, &[Enter, Char('1')]);
    press(&mut app, Esc);
    next_day(&mut app, 2);
    to_derivation(&mut app);
    let back = render(&app);
    assert!(back.contains("Worked example"), "{back}");
}

#[test]
fn hinglish_and_every_size() {
    let mut app = app(HINGLISH);
    to_derivation(&mut app);
    let hi = render(&app);
    assert!(hi.contains("Worked example: har step"), "{hi}");
    assert!(hi.contains("kyun: Transport theorem."), "{hi}");
    press(&mut app, Char('l'));
    assert!(render(&app).contains("why: The transport theorem."));
    let routes: [&[KeyCode]; 3] = [&[], &[Char(' ')], &[Char(' '), Char(' ')]];
    for route in routes {
        let mut app = self::app(ENGLISH);
        to_derivation(&mut app);
        press_all(&mut app, route);
        for (w, h) in [
            (1, 1),
            (2, 1),
            (1, 5),
            (20, 6),
            (40, 12),
            (60, 14),
            (200, 50),
        ] {
            app.size = (w, h);
            render(&app);
            app.help = true;
            render(&app);
            app.help = false;
        }
    }
}

#[test]
fn the_reader_lists_derivations_after_the_sections_as_worked_examples() {
    let mut app = app(ENGLISH);
    press(&mut app, Char('r'));
    let list = render(&app);
    assert!(list.contains("∴ Euler from the"), "{list}");
    press(&mut app, KeyCode::Right);
    // One step at a time: the first with its reason, then Enter for each
    // next one, until every step is there with its reason.
    let page = render(&app);
    for said in [
        "Worked example",
        "1. (dL⃗/dt)_(body) + ω⃗ × L⃗ = N⃗",
        "why: The transport theorem.",
        "Enter: the next step",
        "(1/3)",
    ] {
        assert!(page.contains(said), "{said}:\n{page}");
    }
    assert!(!page.contains("Cross product by components"), "{page}");
    press(&mut app, Enter);
    let page = render(&app);
    assert!(page.contains("why: Cross product by components."), "{page}");
    assert!(page.contains("(2/3)"), "{page}");
    assert!(!page.contains("Set the torque to zero"), "{page}");
    press(&mut app, Enter);
    let page = render(&app);
    for said in [
        "why: The transport theorem.",
        "why: Cross product by components.",
        "why: Set the torque to zero.",
    ] {
        assert!(page.contains(said), "{said}:\n{page}");
    }
    assert!(!page.contains("Enter: the next step"), "{page}");
    assert!(!page.contains("your step"), "{page}");
    // Another page and back: one step again.
    press_all(&mut app, &[KeyCode::Left, KeyCode::Right]);
    assert!(!render(&app).contains("Set the torque to zero"));
}
