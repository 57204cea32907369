//! Reader: scrolling, sections, language, search, links.

use crossterm::event::KeyCode;

use super::{key, press, press_all, type_text};
use crate::tui::action::Action;
use crate::tui::i18n::{ENGLISH, HINGLISH};
use crate::tui::keymap::Context;
use crate::tui::screens::Screen;
use crate::tui::screens::reader::ReaderState;
use crate::tui::testkit::{self, TestApp, render};

fn open(lang: &str) -> TestApp {
    let mut app = testkit::app(lang);
    press(&mut app, KeyCode::Char('r'));
    app
}

fn reader(app: &TestApp) -> &ReaderState {
    match app.screen() {
        Screen::Reader(r) => r,
        _ => panic!("not in the reader"),
    }
}

#[test]
fn reader_keys() {
    let app = open(ENGLISH);
    assert_eq!(app.context(), Context::Reader);
    let cases = [
        (KeyCode::Char('j'), Action::Down),
        (KeyCode::Down, Action::Down),
        (KeyCode::Char('k'), Action::Up),
        (KeyCode::PageDown, Action::PageDown),
        (KeyCode::PageUp, Action::PageUp),
        (KeyCode::Char('g'), Action::Top),
        (KeyCode::Char('G'), Action::Bottom),
        (KeyCode::Right, Action::NextSection),
        (KeyCode::Left, Action::PrevSection),
        (KeyCode::Char('/'), Action::StartSearch),
        (KeyCode::Char('n'), Action::NextMatch),
        (KeyCode::Char('N'), Action::PrevMatch),
        (KeyCode::Tab, Action::NextLink),
        (KeyCode::Enter, Action::FollowLink),
        (KeyCode::Char('l'), Action::ToggleLanguage),
        (KeyCode::Esc, Action::Back),
    ];
    for (code, action) in cases {
        assert_eq!(key(&app, code), Some(action), "{code:?}");
    }
}

#[test]
fn scrolling_is_clamped_to_the_text() {
    let mut app = open(ENGLISH);
    // A narrow, short terminal makes the first section longer than the screen.
    app.size = (44, 12);
    press(&mut app, KeyCode::Char('k'));
    assert_eq!(reader(&app).scroll, 0);
    press(&mut app, KeyCode::Char('G'));
    let bottom = reader(&app).scroll;
    assert!(bottom > 0, "the section should not fit in 44×12");
    press(&mut app, KeyCode::Char('j'));
    assert_eq!(reader(&app).scroll, bottom, "no scrolling past the end");
    press(&mut app, KeyCode::Char('k'));
    assert_eq!(reader(&app).scroll, bottom - 1);
    press(&mut app, KeyCode::Char('g'));
    assert_eq!(reader(&app).scroll, 0);
    press(&mut app, KeyCode::PageDown);
    assert!(reader(&app).scroll > 0);
    insta::assert_snapshot!("reader_small", render(&app));
}

#[test]
fn sections_and_language_keep_the_place() {
    let mut app = open(ENGLISH);
    press(&mut app, KeyCode::Right);
    assert_eq!(reader(&app).section, 1);
    assert!(render(&app).contains("Apply the transport theorem"));
    press(&mut app, KeyCode::Char('l'));
    assert_eq!(
        reader(&app).section,
        1,
        "same section in the other language"
    );
    assert!(render(&app).contains("transport theorem lagao"));
    press(&mut app, KeyCode::Left);
    press(&mut app, KeyCode::Left);
    assert_eq!(reader(&app).section, 0);
}

#[test]
fn links_are_followed_and_esc_walks_back() {
    let mut app = open(ENGLISH);
    // `setup` links to `euler` and `stability`.
    press_all(&mut app, &[KeyCode::Tab, KeyCode::Tab]);
    assert_eq!(reader(&app).link, Some(1));
    press(&mut app, KeyCode::Enter);
    assert_eq!(reader(&app).section, 2);
    press(&mut app, KeyCode::Enter);
    assert_eq!(reader(&app).section, 0, "`stability` links back to `setup`");
    press(&mut app, KeyCode::Esc);
    assert_eq!(reader(&app).section, 2);
    press(&mut app, KeyCode::Esc);
    assert_eq!(reader(&app).section, 0);
    press(&mut app, KeyCode::Esc);
    assert!(matches!(app.screen(), Screen::Home(_)));
}

#[test]
fn search_finds_text_in_any_section_and_n_goes_on() {
    let mut app = open(ENGLISH);
    press(&mut app, KeyCode::Char('/'));
    assert_eq!(app.context(), Context::ReaderSearch);
    // `n`, `j`, `q` are text while typing a search.
    type_text(&mut app, "FLIPS");
    assert_eq!(reader(&app).search.as_deref(), Some("FLIPS"));
    insta::assert_snapshot!("reader_search_typing", render(&app));
    press(&mut app, KeyCode::Enter);
    assert_eq!(app.context(), Context::Reader);
    assert_eq!(
        reader(&app).section,
        2,
        "only the stability section says `flips`"
    );
    press(&mut app, KeyCode::Char('/'));
    type_text(&mut app, "transport");
    press(&mut app, KeyCode::Enter);
    assert_eq!(
        reader(&app).section,
        1,
        "search wraps around to the first match"
    );
    // `frame` is only in the first section, on several lines: `n` walks
    // through them although the short section cannot scroll.
    press(&mut app, KeyCode::Char('/'));
    type_text(&mut app, "frame");
    press(&mut app, KeyCode::Enter);
    let first = reader(&app).hit;
    assert_eq!(first.map(|h| h.0), Some(0));
    press(&mut app, KeyCode::Char('n'));
    let second = reader(&app).hit;
    assert!(second > first, "{first:?} → {second:?}");
    press(&mut app, KeyCode::Char('N'));
    assert_eq!(reader(&app).hit, first);
    press(&mut app, KeyCode::Char('/'));
    type_text(&mut app, "zzz");
    press(&mut app, KeyCode::Enter);
    assert_eq!(
        app.status.as_ref().map(|s| s.text.as_str()),
        Some("no match: zzz")
    );
}

#[test]
fn snapshots_in_both_languages() {
    for lang in [ENGLISH, HINGLISH] {
        let mut app = open(lang);
        insta::assert_snapshot!(format!("reader_{lang}"), render(&app));
        press(&mut app, KeyCode::Tab);
        press(&mut app, KeyCode::Char('?'));
        insta::assert_snapshot!(format!("reader_help_{lang}"), render(&app));
    }
}
