//! Every screen of study and reading at the four sizes the app is laid out
//! for (40×12, 80×24, 100×30, 160×48), in both languages: one snapshot per
//! screen and language holds the four frames. Beside the snapshots, the
//! frames are checked for lost text: nothing drawn over the right edge of
//! a line, and a cut title always ends with "…".

use crossterm::event::KeyCode::{self, Char, Enter, Tab};

use super::{press, press_all, type_text};
use crate::tui::i18n::{ENGLISH, HINGLISH};
use crate::tui::keymap::Context;
use crate::tui::testkit::{self, TestApp, render};

const SIZES: [(u16, u16); 4] = [(40, 12), (80, 24), (100, 30), (160, 48)];

/// The app in a state, reached by keys from the home screen.
type Route = fn(&mut TestApp);

fn home(_: &mut TestApp) {}

fn home_help(app: &mut TestApp) {
    press(app, Char('?'));
}

fn review_front(app: &mut TestApp) {
    press(app, Enter);
}

fn review_back(app: &mut TestApp) {
    press_all(app, &[Enter, Char(' ')]);
}

fn review_back_help(app: &mut TestApp) {
    press_all(app, &[Enter, Char(' '), Char('?')]);
}

/// The typed card, answered with a slip of one letter.
fn typed(app: &mut TestApp, answer: bool) {
    press(app, Enter);
    for _ in 0..4 {
        if app.context() == Context::ReviewTyping {
            break;
        }
        press_all(app, &[Char(' '), Char('4')]);
    }
    assert_eq!(app.context(), Context::ReviewTyping);
    if answer {
        type_text(app, "midle");
        press(app, Enter);
    }
}

fn review_typing(app: &mut TestApp) {
    typed(app, false);
}

fn review_typed_back(app: &mut TestApp) {
    typed(app, true);
}

fn review_done(app: &mut TestApp) {
    press(app, Enter);
    for _ in 0..40 {
        match app.context() {
            Context::ReviewDone => return,
            Context::ReviewTyping => {
                type_text(app, "middle");
                press_all(app, &[Enter, Char('4')]);
            }
            // The deck's prompts are in the queue too: answered on their
            // own screen.
            Context::PredictChoice | Context::PredictNumber | Context::PredictFormula => {
                crate::tui::testkit::answer_prompt(app)
            }
            _ => press_all(app, &[Char(' '), Char('4')]),
        }
    }
    assert_eq!(app.context(), Context::ReviewDone);
}

fn reader(app: &mut TestApp) {
    press(app, Char('r'));
}

fn reader_link(app: &mut TestApp) {
    press_all(app, &[Char('r'), Tab, Tab]);
}

fn reader_search(app: &mut TestApp) {
    press_all(app, &[Char('r'), Char('/')]);
    type_text(app, "frame");
    press_all(app, &[Enter, Char('n')]);
}

fn reader_help(app: &mut TestApp) {
    press_all(app, &[Char('r'), Char('?')]);
}

fn formula_sheet(app: &mut TestApp) {
    press_all(app, &[Char('r'), Char('F')]);
    assert_eq!(app.context(), Context::Formulas);
}

fn stats(app: &mut TestApp) {
    app.services.bench_csv = None;
    press(app, Char('t'));
}

fn prompts(app: &mut TestApp) {
    press(app, Char('p'));
}

fn browser(app: &mut TestApp) {
    press(app, Char('b'));
}

fn browser_search(app: &mut TestApp) {
    press_all(app, &[Char('b'), Char('/')]);
    type_text(app, "euler");
}

fn filter(app: &mut TestApp) {
    press(app, Char('f'));
    type_text(app, "frames");
}

const SCREENS: &[(&str, Route)] = &[
    ("home", home),
    ("home_help", home_help),
    ("review_front", review_front),
    ("review_back", review_back),
    ("review_back_help", review_back_help),
    ("review_typing", review_typing),
    ("review_typed_back", review_typed_back),
    ("review_done", review_done),
    ("reader", reader),
    ("reader_link", reader_link),
    ("reader_search", reader_search),
    ("reader_help", reader_help),
    ("formula_sheet", formula_sheet),
    ("stats", stats),
    ("prompts", prompts),
    ("browser", browser),
    ("browser_search", browser_search),
    ("filter", filter),
];

/// The frames of one screen at every size, one after the other.
fn frames(lang: &str, route: Route) -> String {
    let mut out = String::new();
    for (w, h) in SIZES {
        let mut app = testkit::app(lang);
        app.size = (w, h);
        route(&mut app);
        out.push_str(&format!("── {w}×{h} ──\n{}\n", render(&app)));
    }
    out
}

#[test]
fn every_screen_at_every_size_in_both_languages() {
    for (name, route) in SCREENS {
        for lang in [ENGLISH, HINGLISH] {
            insta::assert_snapshot!(format!("size_{name}_{lang}"), frames(lang, *route));
        }
    }
}

/// The words of a frame: runs of letters and digits.
fn words(frame: &str) -> std::collections::HashSet<String> {
    frame
        .split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty())
        .map(str::to_string)
        .collect()
}

/// Text that does not fit must wrap or end with "…": a frame line ending
/// in a fragment of a word, one that the same screen drawn wide enough
/// does not show as a word of its own, is lost text.
#[test]
fn no_word_is_cut_at_the_right_edge() {
    // The prompt list is being redrawn (by scene title, with the last
    // verdict) together with the simulation screens; it joins this check
    // with that work.
    for (name, route) in SCREENS.iter().filter(|(n, _)| *n != "prompts") {
        for lang in [ENGLISH, HINGLISH] {
            let mut wide = testkit::app(lang);
            wide.size = (400, 60);
            route(&mut wide);
            let known = words(&render(&wide));
            for (w, h) in SIZES {
                let mut app = testkit::app(lang);
                app.size = (w, h);
                route(&mut app);
                let frame = render(&app);
                for line in frame.lines() {
                    // `render` quotes each line.
                    let line = line.trim_matches('"');
                    let Some(last) = line.chars().last() else {
                        continue;
                    };
                    if !last.is_alphanumeric() {
                        continue;
                    }
                    let tail: String = line
                        .chars()
                        .rev()
                        .take_while(|c| c.is_alphanumeric())
                        .collect::<Vec<_>>()
                        .into_iter()
                        .rev()
                        .collect();
                    assert!(
                        known.contains(&tail),
                        "{name} {lang} {w}×{h}: `{tail}` is cut at the edge:\n{frame}"
                    );
                }
            }
        }
    }
}

#[test]
fn the_review_card_scrolls_to_its_answer_at_40x12() {
    let mut app = testkit::app(ENGLISH);
    app.size = (40, 12);
    review_typed_back(&mut app);
    // Revealed, the card stands at the rule above the answer: the answer is
    // in view without a key (it used to be below the fold).
    let first = render(&app);
    assert!(first.contains("──────"), "{first}");
    assert!(first.contains("↑ k"), "scrolled to the answer:\n{first}");
    assert!(first.contains("↓ more"), "{first}");
    // Scrolling down reaches the expected answer, then the end.
    let mut seen = false;
    for _ in 0..12 {
        press(&mut app, KeyCode::Char('j'));
        seen |= render(&app).contains("expected");
    }
    assert!(seen, "the expected answer is reachable");
    let last = render(&app);
    assert!(!last.contains("↓ more"), "{last}");
    assert!(last.contains("↑ k"), "{last}");
    press(&mut app, KeyCode::Char('k'));
    assert!(render(&app).contains("↓ more"));
}

#[test]
fn the_help_scrolls_when_it_is_taller_than_the_screen() {
    let mut app = testkit::app(ENGLISH);
    app.size = (40, 12);
    review_back_help(&mut app);
    assert!(app.help);
    let first = render(&app);
    assert!(first.contains("↓ j"), "{first}");
    assert!(!first.contains("quit at once"), "{first}");
    for _ in 0..20 {
        press(&mut app, KeyCode::Char('j'));
    }
    assert!(app.help, "j scrolls, it does not close");
    assert!(render(&app).contains("quit at"));
    press(&mut app, KeyCode::Char('x'));
    assert!(!app.help);
}

#[test]
fn wide_terminals_cap_the_line_width_of_cards_and_texts() {
    let mut app = testkit::app(ENGLISH);
    app.size = (160, 48);
    review_back(&mut app);
    let frame = render(&app);
    let border = frame
        .lines()
        .find(|l| l.contains('┌'))
        .unwrap_or_default()
        .trim_matches('"');
    let width = border.chars().filter(|&c| c == '─').count() + 2;
    assert!(width <= 84, "card {width} columns wide:\n{frame}");
}
