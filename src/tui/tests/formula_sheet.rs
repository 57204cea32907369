//! The formula sheet: `F` in the reader lists every formula of the deck's
//! cards and sections, once each, in the language on screen; it scrolls,
//! and Esc, `F` or `q` go back to the reader where it was.

use crossterm::event::KeyCode;
use ratatui::style::Style;

use super::{key, press, press_all};
use crate::tui::action::Action;
use crate::tui::i18n::{ENGLISH, HINGLISH};
use crate::tui::keymap::Context;
use crate::tui::screens::Screen;
use crate::tui::screens::formulas::{self, FormulaSheet, Source};
use crate::tui::testkit::{self, TestApp, render};
use crate::tui::wrap::{columns, line_text};

/// The reader open on the fixture deck, then its formula sheet.
fn sheet(lang: &str, size: (u16, u16)) -> TestApp {
    let mut app = testkit::app(lang);
    app.size = size;
    press(&mut app, KeyCode::Char('r'));
    assert_eq!(app.context(), Context::Reader);
    press(&mut app, KeyCode::Char('F'));
    assert_eq!(app.context(), Context::Formulas);
    app
}

fn state(app: &TestApp) -> &FormulaSheet {
    match app.screen() {
        Screen::Formulas(s) => s,
        _ => panic!("not on the formula sheet"),
    }
}

/// The fixture's Euler equation, on a card's back and (spaced otherwise)
/// in section `euler`.
const EULER: &str = "$I_1 \\dot\\omega_1 = (I_2 - I_3)\\,\\omega_2 \\omega_3$";
/// The growth of the wobble, only in section `stability`.
const GROWTH: &str = "$e^{\\sqrt{k} t}$";

fn squash(s: &str) -> String {
    s.split_whitespace().collect()
}

/// The screen with every space removed, so that a formula is found however
/// the sheet spaced or wrapped it.
fn squashed_screen(app: &TestApp) -> String {
    squash(&render(app).replace("\"\n\"", ""))
}

#[test]
fn sheet_keys() {
    let app = sheet(ENGLISH, (80, 24));
    let cases = [
        (KeyCode::Char('j'), Action::Down),
        (KeyCode::Down, Action::Down),
        (KeyCode::Char('k'), Action::Up),
        (KeyCode::PageDown, Action::PageDown),
        (KeyCode::PageUp, Action::PageUp),
        (KeyCode::Char('g'), Action::Top),
        (KeyCode::Char('G'), Action::Bottom),
        (KeyCode::Esc, Action::Back),
        (KeyCode::Char('F'), Action::Back),
        (KeyCode::Char('q'), Action::Back),
        (KeyCode::Char('l'), Action::ToggleLanguage),
    ];
    for (code, action) in cases {
        assert_eq!(key(&app, code), Some(action), "{code:?}");
    }
}

#[test]
fn f_is_in_the_readers_help() {
    let mut app = testkit::app(ENGLISH);
    press(&mut app, KeyCode::Char('r'));
    press(&mut app, KeyCode::Char('?'));
    let screen = render(&app);
    let row = screen
        .lines()
        .find(|l| l.contains("formula sheet"))
        .unwrap_or_else(|| panic!("no formula sheet in the help:\n{screen}"));
    assert!(row.contains("│ F "), "{row}");
}

#[test]
fn the_sheet_lists_a_cards_and_a_sections_formulas_in_both_languages() {
    for (lang, card, section) in [
        (
            ENGLISH,
            "Card · Euler's equation for component 1",
            "Section · The tennis-racket theorem",
        ),
        (
            HINGLISH,
            "Card · Component 1 ka Euler equation",
            "Section · Tennis-racket theorem",
        ),
    ] {
        let app = sheet(lang, (100, 30));
        let screen = render(&app);
        assert!(screen.contains(card), "{lang}:\n{screen}");
        assert!(screen.contains(section), "{lang}:\n{screen}");
        let all = squashed_screen(&app);
        for f in [EULER, GROWTH] {
            let shown = squash(&crate::text::render(f));
            assert!(all.contains(&shown), "{lang}: {shown} missing:\n{screen}");
        }
        // The header names the sheet.
        assert!(
            screen
                .lines()
                .next()
                .unwrap_or("")
                .contains("Formula sheet")
        );
    }
}

#[test]
fn the_language_key_switches_the_sheet() {
    let mut app = sheet(ENGLISH, (100, 30));
    assert!(render(&app).contains("Card · Why use the body frame"));
    press(&mut app, KeyCode::Char('l'));
    let screen = render(&app);
    assert!(
        screen.contains("Card · Rotation ke liye body frame kyun?"),
        "{screen}"
    );
    assert!(!screen.contains("Why use the body frame"), "{screen}");
}

#[test]
fn a_formula_is_listed_once_under_the_first_place_that_writes_it() {
    let app = sheet(ENGLISH, (100, 30));
    let deck = &app.decks[0];
    let euler = squash(&crate::text::render(EULER));
    let groups = formulas::groups(deck, ENGLISH);
    let holding: Vec<&formulas::Group> = groups
        .iter()
        .filter(|g| g.formulas.iter().any(|f| squash(f) == euler))
        .collect();
    assert_eq!(holding.len(), 1, "{groups:#?}");
    // The card comes before section `euler`, which writes it too.
    assert_eq!(holding[0].from, Source::Card);
    assert!(
        deck.sections[1]
            .body
            .get(ENGLISH)
            .contains("I_1\\dot\\omega_1")
    );
    let all = squashed_screen(&app);
    assert_eq!(all.matches(&euler).count(), 1, "{}", render(&app));
    // Section `euler` still lists what only it writes.
    let own = groups
        .iter()
        .find(|g| g.heading == "Euler's equations")
        .unwrap_or_else(|| panic!("section `euler` left out: {groups:#?}"));
    assert!(own.formulas.contains(&crate::text::render("$\\vec N = 0$")));
}

#[test]
fn esc_f_and_q_go_back_to_the_reader_where_it_was() {
    for close in [KeyCode::Esc, KeyCode::Char('F'), KeyCode::Char('q')] {
        let mut app = testkit::app(ENGLISH);
        app.size = (44, 12);
        press_all(
            &mut app,
            &[KeyCode::Char('r'), KeyCode::Right, KeyCode::Left],
        );
        press_all(&mut app, &[KeyCode::Char('j'), KeyCode::Char('j')]);
        let before = match app.screen() {
            Screen::Reader(r) => r.clone(),
            _ => panic!("not in the reader"),
        };
        assert!(before.scroll > 0 && before.section == 0, "{before:?}");
        press_all(&mut app, &[KeyCode::Char('F'), KeyCode::PageDown, close]);
        match app.screen() {
            Screen::Reader(r) => assert_eq!(*r, before, "{close:?}"),
            _ => panic!("{close:?} did not go back to the reader"),
        }
    }
}

#[test]
fn the_sheet_scrolls_and_stops_at_its_end() {
    let mut app = sheet(ENGLISH, (40, 12));
    press(&mut app, KeyCode::Char('k'));
    assert_eq!(state(&app).scroll, 0);
    press(&mut app, KeyCode::Char('j'));
    assert_eq!(state(&app).scroll, 1);
    press(&mut app, KeyCode::Char('G'));
    let bottom = state(&app).scroll;
    assert!(bottom > 1, "the fixture's sheet should not fit in 40×12");
    press(&mut app, KeyCode::Char('j'));
    press(&mut app, KeyCode::PageDown);
    assert_eq!(state(&app).scroll, bottom, "no scrolling past the end");
    press(&mut app, KeyCode::PageUp);
    assert!(state(&app).scroll < bottom);
    press(&mut app, KeyCode::Char('g'));
    assert_eq!(state(&app).scroll, 0);
    insta::assert_snapshot!("formula_sheet_small", render(&app));
    // Laid out again for a larger terminal, where it all fits: the end is
    // the top.
    press(&mut app, KeyCode::Char('G'));
    app.size = (100, 30);
    press(&mut app, KeyCode::Char('j'));
    assert_eq!(state(&app).scroll, 0);
    assert!(render(&app).contains("Section · The tennis-racket theorem"));
}

#[test]
fn snapshots_in_both_languages() {
    for lang in [ENGLISH, HINGLISH] {
        let app = sheet(lang, (80, 24));
        insta::assert_snapshot!(format!("formula_sheet_{lang}"), render(&app));
    }
}

/// Every bundled deck's sheet, at the text widths of 100×30, 80×24 and
/// 40×12, in both languages, drawn from top to bottom: no panic, no line wider than
/// the text, and a formula broken across lines only at its spaces (never
/// inside a symbol with its scripts or a number) unless one of its
/// symbols is wider than the line.
#[test]
fn bundled_sheets_fit_every_size_without_tearing_a_formula() {
    let loaded = crate::bundled::load();
    assert!(!loaded.decks.is_empty());
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("temp dir: {e}"));
    let mut app = crate::tui::stack::Tui::new(
        loaded.decks.clone(),
        testkit::services(&dir),
        ENGLISH,
        crate::tui::theme::Theme::PLAIN,
    );
    let mut checked = 0;
    for (d, deck) in loaded.decks.iter().enumerate() {
        for lang in [ENGLISH, HINGLISH] {
            let groups = formulas::groups(deck, lang);
            assert!(
                groups.iter().any(|g| g.from == Source::Card)
                    && groups.iter().any(|g| g.from == Source::Section),
                "{}: {groups:#?}",
                deck.id
            );
            for size in [(100, 30), (80, 24), (40, 12)] {
                app.size = size;
                app.lang = lang.to_string();
                let width = formulas::text_width(size);
                for g in &groups {
                    for f in &g.formulas {
                        for row in f.lines() {
                            let lines = formulas::formula_lines(row, Style::new(), width);
                            let texts: Vec<String> = lines.iter().map(line_text).collect();
                            let longest = row.split_whitespace().map(columns).max().unwrap_or(0);
                            if longest + 4 > width {
                                continue;
                            }
                            for t in &texts {
                                assert!(columns(t) <= width, "{t:?} wider than {width}");
                            }
                            assert_eq!(
                                squash_words(&texts.join(" ")),
                                squash_words(row),
                                "{}: a break inside a token at {width}:\n{}",
                                deck.id,
                                texts.join("\n")
                            );
                            checked += 1;
                        }
                    }
                }
                // The screen itself: its first pages, its end, and back up.
                app.stack.truncate(1);
                app.push(Screen::Formulas(FormulaSheet::new(d)));
                for code in [KeyCode::PageDown; 4].into_iter().chain([
                    KeyCode::Char('G'),
                    KeyCode::Char('j'),
                    KeyCode::PageUp,
                ]) {
                    let _ = render(&app);
                    press(&mut app, code);
                }
                let screen = render(&app);
                assert!(screen.contains(" formulas"), "{screen}");
            }
        }
    }
    assert!(checked > 1000, "{checked}");
}

fn squash_words(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[test]
fn a_deck_without_formulas_says_so() {
    let mut deck = testkit::deck();
    deck.sections.clear();
    for c in &mut deck.cards {
        for t in [&mut c.front, &mut c.back] {
            for v in t.0.values_mut() {
                *v = v.replace('$', "");
            }
        }
    }
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("temp dir: {e}"));
    let mut app = crate::tui::stack::Tui::new(
        vec![deck],
        testkit::services(&dir),
        ENGLISH,
        crate::tui::theme::Theme::PLAIN,
    );
    app.size = (40, 12);
    press_all(&mut app, &[KeyCode::Char('r'), KeyCode::Char('F')]);
    assert_eq!(app.context(), Context::Formulas);
    press_all(&mut app, &[KeyCode::Char('G'), KeyCode::PageDown]);
    let screen = render(&app);
    assert!(screen.contains("This deck has no formulas."), "{screen}");
    assert!(screen.contains(" 0 formulas"), "{screen}");
}
