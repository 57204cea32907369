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
    // Nothing chosen yet: Enter chooses the link on screen, and only the
    // second Enter, with the choice shown, follows it.
    press(&mut app, KeyCode::Enter);
    assert_eq!(reader(&app).section, 2);
    assert_eq!(reader(&app).link, Some(0));
    assert!(render(&app).contains("1/1 → Setup: why the body frame"));
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

/// An app on the bundled torque-free deck (the real concept map), in the
/// reader at the concept map.
fn bundled(lang: &str, size: (u16, u16)) -> TestApp {
    let loaded = crate::bundled::load();
    let mut app = testkit::app(lang);
    app.decks = loaded
        .decks
        .into_iter()
        .filter(|d| d.id == "torque-free-rotation")
        .collect();
    app.size = size;
    press(&mut app, KeyCode::Char('r'));
    while reader(&app).section < 1 {
        press(&mut app, KeyCode::Right);
    }
    app
}

fn deck_of(app: &TestApp) -> &crate::deck::Deck {
    &app.decks[reader(app).deck]
}

#[test]
fn every_concept_map_link_is_chosen_on_screen_and_opens_what_was_shown() {
    use crate::tui::screens::reader::{areas, page};
    for size in [(40, 12), (80, 24), (160, 48)] {
        for lang in [ENGLISH, HINGLISH] {
            let mut app = bundled(lang, size);
            let map = deck_of(&app).sections[1].id.clone();
            assert_eq!(map, "concept-map");
            let (_, text, _) = areas(crate::tui::layout::body_rect(size));
            let links = page(&app, deck_of(&app), 1, text.width as usize, None).links;
            assert!(links.len() >= 16, "{} links", links.len());
            for i in 0..links.len() {
                press(&mut app, KeyCode::Tab);
                let r = reader(&app);
                assert_eq!(r.link, Some(i));
                let line = links[i].line;
                assert!(
                    line >= r.scroll && line < r.scroll + text.height as usize,
                    "{size:?} {lang}: link {i} on line {line}, screen from {}",
                    r.scroll
                );
                let screen = render(&app);
                assert!(
                    screen.contains(&format!("{}/{} →", i + 1, links.len())),
                    "{screen}"
                );
            }
            // The fifth: the status line names it, Enter opens it.
            press(&mut app, KeyCode::Tab);
            for _ in 0..4 {
                press(&mut app, KeyCode::Tab);
            }
            assert_eq!(reader(&app).link, Some(4));
            let target = links[4].target.clone();
            press(&mut app, KeyCode::Enter);
            let r = reader(&app);
            assert_eq!(deck_of(&app).sections[r.section].id, target);
            press(&mut app, KeyCode::Esc);
            assert_eq!(reader(&app).section, 1);
        }
    }
}

#[test]
fn a_chosen_link_scrolled_away_is_dropped_and_enter_then_only_chooses() {
    let mut app = bundled(ENGLISH, (80, 24));
    press(&mut app, KeyCode::Tab);
    assert_eq!(reader(&app).link, Some(0));
    press(&mut app, KeyCode::Char('G'));
    assert_eq!(reader(&app).link, None, "the first link is off screen now");
    press(&mut app, KeyCode::Enter);
    assert_eq!(reader(&app).section, 1, "Enter chose, did not follow");
    assert!(reader(&app).link.is_some());
}

#[test]
fn inline_math_is_never_broken_across_lines() {
    for width in [40, 44, 52, 80, 100] {
        let app = bundled(ENGLISH, (width, 30));
        let screen = render(&app);
        assert!(
            screen.contains("diag(I₁, I₂, I₃)"),
            "width {width}:\n{screen}"
        );
    }
}

#[test]
fn search_shows_the_match_count_and_marks_the_current_match() {
    let mut app = bundled(ENGLISH, (100, 30));
    press(&mut app, KeyCode::Char('/'));
    type_text(&mut app, "polhode");
    press(&mut app, KeyCode::Enter);
    let screen = render(&app);
    let total = screen
        .split("match 1/")
        .nth(1)
        .and_then(|s| s.split(|c: char| !c.is_ascii_digit()).next())
        .and_then(|n| n.parse::<usize>().ok());
    assert!(total.is_some_and(|n| n > 3), "{screen}");
    assert!(
        screen.contains('›'),
        "the current match is marked:\n{screen}"
    );
    press(&mut app, KeyCode::Char('n'));
    assert!(render(&app).contains("match 2/"));
    press(&mut app, KeyCode::Char('N'));
    press(&mut app, KeyCode::Char('N'));
    let n = total.unwrap_or(0);
    assert!(
        render(&app).contains(&format!("match {n}/{n}")),
        "wraps back to the last"
    );
}

#[test]
fn wide_terminals_widen_the_list_and_cut_titles_with_an_ellipsis() {
    let narrow = render(&bundled(ENGLISH, (80, 24)));
    assert!(narrow.contains('…'), "{narrow}");
    let wide = bundled(ENGLISH, (160, 48));
    let (list, text, _) =
        crate::tui::screens::reader::areas(crate::tui::layout::body_rect(wide.size));
    assert!(list.width > 30);
    assert!(text.width <= crate::tui::layout::MEASURE);
    let screen = render(&wide);
    assert!(
        screen.contains("The transport theorem, and deriving Euler’s equations"),
        "{screen}"
    );
}

#[test]
fn a_list_ends_with_a_blank_line_before_the_next_paragraph() {
    let mut app = testkit::app(ENGLISH);
    let deck = &mut app.decks[0];
    let text = |s: &str| {
        let mut m = std::collections::BTreeMap::new();
        m.insert("en".to_string(), s.to_string());
        crate::text::Text(m.into())
    };
    deck.sections.insert(
        0,
        crate::deck::Section {
            id: "list".into(),
            title: text("A list"),
            body: text("Before.\n\n- one\n- two\n\nAfter the list."),
            see: vec![],
        },
    );
    let deck = app.decks[0].clone();
    let page = crate::tui::screens::reader::page(&app, &deck, 0, 60, None);
    let lines: Vec<String> = page.lines.iter().map(crate::tui::wrap::line_text).collect();
    let two = lines.iter().position(|l| l.contains("• two")).unwrap();
    assert_eq!(lines[two + 1].trim(), "", "{lines:#?}");
    assert_eq!(lines[two + 2], "After the list.", "{lines:#?}");
}

#[test]
fn search_folds_the_micro_sign_and_the_greek_mu() {
    let mut app = testkit::app(ENGLISH);
    let text = |s: &str| {
        let mut m = std::collections::BTreeMap::new();
        m.insert("en".to_string(), s.to_string());
        crate::text::Text(m.into())
    };
    app.decks[0].sections.insert(
        0,
        crate::deck::Section {
            id: "muon".into(),
            title: text("Muons"),
            body: text("A muon lives 2.2 \u{b5}s; the \u{3bc} of its mass is a different \u{3bc}."),
            see: vec![],
        },
    );
    press(&mut app, KeyCode::Char('r'));
    assert_eq!(reader(&app).section, 0);
    press(&mut app, KeyCode::Char('/'));
    type_text(&mut app, "\u{3bc}");
    press(&mut app, KeyCode::Enter);
    let screen = render(&app);
    assert!(screen.contains("match 1/3"), "{screen}");
}

#[test]
fn code_in_a_bundled_section_is_shown_without_its_backticks() {
    // The oscillations deck's stiffness section names a command in code.
    let app = testkit::app(ENGLISH);
    let deck = crate::bundled::load()
        .decks
        .into_iter()
        .find(|d| d.id == "oscillations")
        .expect("the oscillations deck");
    let mut found = false;
    for i in 0..deck.sections.len() {
        let page = crate::tui::screens::reader::page(&app, &deck, i, 100, None);
        let text: String = page
            .lines
            .iter()
            .map(crate::tui::wrap::line_text)
            .collect::<Vec<_>>()
            .join("\n");
        assert!(
            !text.contains('`'),
            "a backtick shown in section {i}:\n{text}"
        );
        found |= text.contains("flipcard sim --scene vdp-stiff --method adaptive")
            || text.contains("flipcard sim --scene vdp-stiff --method\nadaptive");
    }
    assert!(found, "the command in code is shown");
}
