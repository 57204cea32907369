//! Formula answers through the keys: a formula card is typed like a typed
//! card and graded by equivalence, with the slip named on the answer side;
//! a formula prompt takes a typed formula as its prediction, refuses one
//! that does not read (the field stays), stores the text as the attempt's
//! prediction and judges it at the commitment, without waiting for the
//! run.

use crossterm::event::KeyCode;

use super::{press, type_text};
use crate::deck::{Answer, Card, CardKind, Deck, FormulaKey, Prompt, Text};
use crate::sched::Rating;
use crate::sim::system::equiv::{Domain, Slip, Verdict as Equiv};
use crate::tui::i18n::{ENGLISH, HINGLISH};
use crate::tui::keymap::Context;
use crate::tui::screens::Screen;
use crate::tui::screens::predict::{Phase as Ask, Prediction};
use crate::tui::screens::review::Phase;
use crate::tui::stack::Tui;
use crate::tui::testkit::{self, TestApp, render};
use crate::tui::theme::Theme;

fn text(en: &str, hi: &str) -> Text {
    Text(
        [("en", en), ("hi-Latn", hi)]
            .into_iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect(),
    )
}

fn euler() -> FormulaKey {
    let d = |name: &str, lo: f64, hi: f64| Domain {
        name: name.into(),
        lo,
        hi,
    };
    FormulaKey {
        expected: "(I_2 - I_3) omega_2 omega_3 / I_1".into(),
        vars: vec![
            d("I1", 1.0, 3.0),
            d("I2", 1.0, 3.0),
            d("I3", 1.0, 3.0),
            d("omega2", -2.0, 2.0),
            d("omega3", -2.0, 2.0),
        ],
    }
}

/// The fixture deck with one formula card and one formula prompt only.
fn formula_deck() -> Deck {
    let mut deck = testkit::deck();
    deck.cards = vec![Card {
        id: "omega1-dot".into(),
        kind: CardKind::Formula,
        front: text("Type ω̇1.", "ω̇1 type karo."),
        back: text(
            "$\\dot\\omega_1 = (I_2 - I_3)\\omega_2\\omega_3/I_1$",
            "$\\dot\\omega_1 = (I_2 - I_3)\\omega_2\\omega_3/I_1$",
        ),
        accept: vec![],
        accept_by_lang: Default::default(),
        explain: None,
        prompt: None,
        tags: vec![],
        formula: Some(euler()),
    }];
    deck.prompts = vec![Prompt {
        id: "omega1-dot-prompt".into(),
        question: text("Type ω̇1 as a formula.", "ω̇1 ka formula type karo."),
        scene: "tennis-racket".into(),
        explain: None,
        answer: Answer::Formula(euler()),
        tags: vec![],
        measured: None,
        vary: Vec::new(),
    }];
    deck
}

fn app(lang: &str) -> TestApp {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = Tui::new(
        vec![formula_deck()],
        testkit::services(&dir),
        lang,
        Theme::PLAIN,
    );
    app.size = (80, 24);
    TestApp { app, dir }
}

fn review_phase(app: &TestApp) -> &Phase {
    match app.screen() {
        Screen::Review(r) => &r.phase,
        _ => panic!("not on the review screen"),
    }
}

fn card_answered(lang: &str, typed: &str) -> TestApp {
    let mut app = app(lang);
    press(&mut app, KeyCode::Enter);
    assert_eq!(app.context(), Context::ReviewTyping);
    type_text(&mut app, typed);
    press(&mut app, KeyCode::Enter);
    assert_eq!(app.context(), Context::ReviewBack);
    app
}

#[test]
fn a_formula_card_is_graded_by_equivalence() {
    let app = card_answered(ENGLISH, "(I2-I3)w2 w3/I1");
    let Phase::Back { typed: Some(t), .. } = review_phase(&app) else {
        panic!("not graded");
    };
    assert_eq!(t.formula, Some(Equiv::Right));
    assert_eq!(t.check.suggested, Rating::Good);
    let screen = render(&app);
    assert!(screen.contains("✓"), "{screen}");
    assert!(!screen.contains("the sign is wrong"), "{screen}");
}

#[test]
fn a_formula_card_names_the_slip_in_the_learners_language() {
    let app = card_answered(ENGLISH, "(I3-I2)*w2*w3/I1");
    let Phase::Back { typed: Some(t), .. } = review_phase(&app) else {
        panic!("not graded");
    };
    assert_eq!(t.formula, Some(Equiv::Wrong(Some(Slip::Sign))));
    assert_eq!(t.check.suggested, Rating::Again);
    let screen = render(&app);
    assert!(screen.contains("the sign is wrong"), "{screen}");
    assert!(
        screen.contains("(I_2 - I_3) omega_2 omega_3 / I_1"),
        "{screen}"
    );
    let app = card_answered(HINGLISH, "2(I2-I3)*w2*w3/I1");
    let screen = render(&app);
    assert!(screen.contains("2 guna"), "{screen}");
}

#[test]
fn a_typed_control_character_never_reaches_the_terminal() {
    // ratatui drops C0 controls itself, but not a bidirectional override,
    // which reorders what the learner reads: both are shown escaped.
    let app = card_answered(ENGLISH, "w2\u{1b}[2J\u{202e}I1");
    let screen = render(&app);
    assert!(!screen.contains('\u{202e}'), "{screen:?}");
    assert!(screen.contains("w2\\u001b[2J\\u202eI1"), "{screen}");
}

fn open_prompt(lang: &str) -> TestApp {
    let mut app = app(lang);
    press(&mut app, KeyCode::Char('p'));
    press(&mut app, KeyCode::Enter);
    assert_eq!(app.context(), Context::PredictFormula);
    app
}

fn predict_phase(app: &TestApp) -> &Ask {
    match app.screen() {
        Screen::Predict(p) => &p.phase,
        _ => panic!("not on the predict screen"),
    }
}

/// Every attempt on disk (read as `predict_attempts` reads them).
fn attempts(app: &TestApp) -> Vec<crate::store::StoredAttempt> {
    super::predict_attempts::on_disk(app)
}

#[test]
fn a_formula_prompt_refuses_what_does_not_read_and_keeps_the_field() {
    let mut app = open_prompt(ENGLISH);
    // `p`, `q`, `j` are text here, not keys.
    type_text(&mut app, "(I2-I3)*w2*w3/");
    press(&mut app, KeyCode::Enter);
    let Ask::Ask { input, error, .. } = predict_phase(&app) else {
        panic!("committed an unreadable formula");
    };
    assert_eq!(input, "(I2-I3)*w2*w3/");
    assert!(
        error
            .as_deref()
            .is_some_and(|e| e.contains("cannot read this formula")),
        "{error:?}"
    );
    assert!(attempts(&app).is_empty(), "nothing stored");
    assert!(render(&app).contains("cannot read this formula"));
}

#[test]
fn a_formula_prompt_stores_the_text_and_judges_it_at_the_commitment() {
    let mut app = open_prompt(ENGLISH);
    type_text(&mut app, "I1/((I2-I3)*w2*w3)");
    press(&mut app, KeyCode::Enter);
    let Ask::Play {
        prediction,
        verdict: Some(v),
        ..
    } = predict_phase(&app)
    else {
        panic!("no verdict at the commitment");
    };
    assert_eq!(*prediction, Prediction::Formula);
    assert!(!v.correct);
    assert_eq!(
        v.formula.as_ref().map(|f| &f.1),
        Some(&Equiv::Wrong(Some(Slip::Reciprocal)))
    );
    let rows = attempts(&app);
    assert_eq!(rows.len(), 1, "{rows:?}");
    assert_eq!(rows[0].prediction, "I1/((I2-I3)*w2*w3)");
    assert_eq!(rows[0].verdict.as_ref().map(|v| v.correct), Some(false));
    let screen = render(&app);
    assert!(screen.contains("upside down"), "{screen}");
    // The deck's answer as the reader shows math, not as the key is typed.
    assert!(screen.contains("(I₂ − I₃)ω₂ω₃/I₁"), "{screen}");
    assert!(!screen.contains("omega_2"), "{screen}");
    // A right one, in Hinglish.
    let mut app = open_prompt(HINGLISH);
    type_text(&mut app, "(I_2-I_3) omega2 omega3/I_1");
    press(&mut app, KeyCode::Enter);
    let rows = attempts(&app);
    assert_eq!(rows[0].verdict.as_ref().map(|v| v.correct), Some(true));
    assert!(render(&app).contains("Sahi"), "{}", render(&app));
}
