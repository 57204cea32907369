//! Prompts as review items (issue 24 §2): they come in the day's queue
//! after the cards, open on their own screen, and their verdict rates them
//! (wrong Again, right Good, `2` lowers Good to Hard), through the path the
//! app takes; a varied prompt comes back days later with other numbers.

use crossterm::event::KeyCode;

use super::{press, press_all, type_text};
use crate::sched::{Direction, ItemKey, Rating};
use crate::tui::i18n::ENGLISH;
use crate::tui::keymap::Context;
use crate::tui::screens::Screen;
use crate::tui::testkit::{self, render};

/// The rows of the review log: item, rating, undone.
fn log(app: &testkit::TestApp) -> Vec<(String, Rating, bool)> {
    let mut out = Vec::new();
    app.services
        .study
        .store
        .each_review(|r| {
            out.push((
                format!("{}:{}", r.record.key.card, r.record.key.direction.as_str()),
                r.record.rating,
                r.undone,
            ));
            Ok::<(), crate::store::StoreError>(())
        })
        .unwrap();
    out
}

fn current(app: &testkit::TestApp) -> Option<String> {
    match app.screen() {
        Screen::Review(r) => r
            .current
            .as_ref()
            .map(|(k, _)| format!("{}:{}", k.card, k.direction.as_str())),
        _ => None,
    }
}

#[test]
fn prompts_come_in_the_queue_and_their_verdict_rates_them() {
    let mut app = testkit::app(ENGLISH);
    press(&mut app, KeyCode::Enter);
    // The four card items first (Easy), then the deck's prompts.
    for _ in 0..3 {
        press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('4')]);
    }
    type_text(&mut app, "middle");
    press_all(&mut app, &[KeyCode::Enter, KeyCode::Char('4')]);
    assert_eq!(current(&app).as_deref(), Some("middle-axis:predict"));
    let front = render(&app);
    assert!(front.contains("Predict, then check"), "{front}");
    assert!(front.contains("the verdict rates it"), "{front}");
    // Enter opens the prompt on its own screen; the right choice commits.
    press(&mut app, KeyCode::Enter);
    assert_eq!(app.context(), Context::PredictChoice);
    press_all(&mut app, &[KeyCode::Char('2'), KeyCode::Enter]);
    super::predict::play_to_the_end(&mut app);
    // Right: Good, on disk with the verdict, and said as the verdict's
    // last line.
    let rows = log(&app);
    assert_eq!(
        rows.last(),
        Some(&("middle-axis:predict".to_string(), Rating::Good, false))
    );
    let screen = render(&app);
    assert!(screen.contains("prediction scheduled: Good"), "{screen}");
    // `2`: right but hard. The Good is undone, Hard recorded.
    press(&mut app, KeyCode::Char('2'));
    let rows = log(&app);
    let n = rows.len();
    assert_eq!(
        rows[n - 2..],
        [
            ("middle-axis:predict".to_string(), Rating::Good, true),
            ("middle-axis:predict".to_string(), Rating::Hard, false)
        ]
    );
    assert!(render(&app).contains("prediction scheduled: Hard"));
    // Back on the review, the queue moved on to the next prompt.
    press(&mut app, KeyCode::Esc);
    assert_eq!(current(&app).as_deref(), Some("growth:predict"));
    let key = ItemKey {
        deck: "torque-free".into(),
        card: "middle-axis".into(),
        direction: Direction::Predict,
    };
    let state = app.services.study.store.state(&key).unwrap();
    assert!(
        state.is_some_and(|s| s.state == crate::sched::State::Learning),
        "{state:?}"
    );
}

#[test]
fn a_varied_prompt_comes_back_days_later_with_other_numbers() {
    let mut app = super::predict::bundled_prompt_in(
        "oscillations",
        ENGLISH,
        "pendulum-period-varied",
        (100, 30),
    );
    let first = match app.screen() {
        Screen::Predict(p) => p.variant.clone().expect("a varied prompt draws a variant"),
        _ => panic!("not on the predict screen"),
    };
    let question = first.prompt.question.get(ENGLISH).to_string();
    assert!(!question.contains("{theta0}"), "{question}");
    let values = first.variant.clone().unwrap();
    let theta0 = values.values.iter().find(|(n, _)| n == "theta0").unwrap().1;
    assert!(question.contains(&format!("{theta0}°")), "{question}");
    // The answer its run gives, typed: right, so Good.
    let run = crate::predict::audit::variant_run(&app.decks[0], &first).unwrap();
    let decided = crate::predict::variant::decided(&first.prompt, &run.measured).unwrap();
    let crate::deck::Answer::Number {
        expected: Some(t), ..
    } = decided.answer
    else {
        panic!("a number prompt")
    };
    type_text(&mut app, &format!("{t:.3}"));
    press(&mut app, KeyCode::Enter);
    super::predict::play_to_the_end(&mut app);
    assert_eq!(app.context(), Context::PredictVerdict);
    let key = ItemKey {
        deck: "oscillations".into(),
        card: "pendulum-period-varied".into(),
        direction: Direction::Predict,
    };
    let after = app.services.study.store.state(&key).unwrap().unwrap();
    // The seed is stored with the attempt.
    let mut seeds = Vec::new();
    app.services
        .study
        .store
        .each_attempt(|a| {
            seeds.push(a.variant);
            Ok::<(), crate::store::StoreError>(())
        })
        .unwrap();
    assert_eq!(seeds, [values.seed]);
    press(&mut app, KeyCode::Esc);
    // Three days later it is due again, and opens with other numbers.
    let later = testkit::now() + chrono::TimeDelta::days(3);
    assert!(after.due <= later, "due {}", after.due);
    app.services.clock = crate::sched::clock::Clock::Fixed(later);
    let state = crate::tui::screens::predict::PredictState::new(&app, 0, {
        app.decks[0]
            .prompts
            .iter()
            .position(|p| p.id == "pendulum-period-varied")
            .unwrap()
    });
    let second = state.variant.clone().unwrap();
    assert_ne!(
        second.variant.as_ref().unwrap().values,
        values.values,
        "a return draws other numbers"
    );
    assert_ne!(second.prompt.question, first.prompt.question);
}
