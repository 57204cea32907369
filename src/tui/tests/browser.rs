//! The card browser, the study filter, suspend and bury from the review
//! screen, and cloze cards under review: snapshots in both languages and
//! what each action writes to the store.

use std::collections::BTreeMap;

use crossterm::event::KeyCode;

use super::{press, press_all, type_text};
use crate::deck::{Card, CardKind, Text};
use crate::sched::{Direction, ItemKey};
use crate::store::StatusAction;
use crate::tui::i18n::{ENGLISH, HINGLISH};
use crate::tui::keymap::Context;
use crate::tui::screens::Screen;
use crate::tui::screens::browser::BrowserState;
use crate::tui::testkit::{self, TestApp, render};

fn text(en: &str, hi: &str) -> Text {
    Text(
        BTreeMap::from([
            ("en".to_string(), en.to_string()),
            ("hi-Latn".to_string(), hi.to_string()),
        ])
        .into(),
    )
}

/// The fixture deck with a cloze card added (two numbers, math inside).
fn app(lang: &str) -> TestApp {
    let mut app = testkit::app(lang);
    app.decks[0].cards.push(Card {
        id: "euler-cloze".into(),
        kind: CardKind::Cloze,
        front: text(
            r"{{c1::Euler}}'s equations give $\dot\omega$; the middle axis is {{c2::$\omega_2$::an axis}}.",
            r"{{c1::Euler}} ke equations $\dot\omega$ dete hain; beech ka axis {{c2::$\omega_2$::ek axis}} hai.",
        ),
        back: text("Torque-free.", "Torque-free."),
        accept: Vec::new(),
        accept_by_lang: Default::default(),
        explain: None,
        prompt: None,
        tags: vec!["euler".into()],
        formula: None,
    });
    app
}

fn browser(app: &TestApp) -> &BrowserState {
    match app.screen() {
        Screen::Browser(b) => b,
        _ => panic!("not on the browser"),
    }
}

fn key(card: &str, direction: Direction) -> ItemKey {
    ItemKey {
        deck: "torque-free".into(),
        card: card.into(),
        direction,
    }
}

fn shown_cards(app: &TestApp) -> Vec<String> {
    let b = browser(app);
    b.shown
        .iter()
        .map(|&i| {
            format!(
                "{}:{}",
                b.rows[i].card_id(&app.decks),
                b.rows[i].direction.as_str()
            )
        })
        .collect()
}

#[test]
fn browser_lists_every_item_searches_and_previews() {
    for lang in [ENGLISH, HINGLISH] {
        let mut app = app(lang);
        press(&mut app, KeyCode::Char('b'));
        assert_eq!(app.context(), Context::Browser);
        // Basic, reversed (two), typed, cloze (two numbers), and the two
        // prompts (direction `predict`).
        assert_eq!(browser(&app).rows.len(), 8);
        insta::assert_snapshot!(format!("browser_{lang}"), render(&app));

        press(&mut app, KeyCode::Char('/'));
        assert_eq!(app.context(), Context::BrowserSearch);
        type_text(&mut app, "omega2");
        // Both cards hold $\omega_2$; the others do not.
        let mut found = shown_cards(&app);
        found.sort();
        assert_eq!(
            found,
            [
                "euler-1:backward",
                "euler-1:forward",
                "euler-cloze:c1",
                "euler-cloze:c2"
            ]
        );
        for _ in 0..6 {
            press(&mut app, KeyCode::Backspace);
        }
        type_text(&mut app, "middle axis ω₂");
        assert_eq!(
            shown_cards(&app),
            ["euler-cloze:c1", "euler-cloze:c2"],
            "the rendered ω₂ is found too"
        );
        press(&mut app, KeyCode::Enter);
        press(&mut app, KeyCode::Down);
        press(&mut app, KeyCode::Enter);
        let screen = render(&app);
        assert!(
            screen.contains("[an axis]") || screen.contains("[ek axis]"),
            "{screen}"
        );
        insta::assert_snapshot!(format!("browser_preview_{lang}"), screen);
        press(&mut app, KeyCode::Esc);
        assert!(!browser(&app).preview);

        // A filter that can match nothing says why.
        press(&mut app, KeyCode::Char('/'));
        for _ in 0..20 {
            press(&mut app, KeyCode::Backspace);
        }
        type_text(&mut app, "tag:nosuch");
        let screen = render(&app);
        assert!(screen.contains("no card has tag `nosuch`"), "{screen}");
        insta::assert_snapshot!(format!("browser_bad_query_{lang}"), screen);
    }
}

#[test]
fn browser_sorts_by_any_column() {
    let mut app = app(ENGLISH);
    press(&mut app, KeyCode::Char('b'));
    // Deck, then card: the cards in id order.
    press_all(&mut app, &[KeyCode::Char('o'), KeyCode::Char('o')]);
    let card = |s: &String| s.split(':').next().unwrap_or("").to_string();
    let cards: Vec<String> = shown_cards(&app).iter().map(card).collect();
    let mut sorted = cards.clone();
    sorted.sort();
    assert_eq!(cards, sorted);
    assert_ne!(sorted.first(), sorted.last());
    press(&mut app, KeyCode::Char('O'));
    let mut reversed = sorted.clone();
    reversed.reverse();
    assert_eq!(
        shown_cards(&app).iter().map(card).collect::<Vec<_>>(),
        reversed
    );
    // The question: what each item asks, in text order.
    press(&mut app, KeyCode::Char('o'));
    let b = browser(&app);
    assert_eq!(
        b.sort.map(|s| s.0),
        Some(crate::tui::screens::browser::Column::Question)
    );
    let texts: Vec<String> = b
        .shown
        .iter()
        .map(|&i| b.rows[i].text(&app.decks, "en"))
        .collect();
    let mut in_order = texts.clone();
    in_order.sort();
    assert_eq!(texts, in_order);
    // Lapses: every item has none, so the order is the deck's.
    for _ in 0..8 {
        press(&mut app, KeyCode::Char('o'));
    }
    let Some((col, _)) = browser(&app).sort else {
        panic!("not sorted");
    };
    assert_eq!(col, crate::tui::screens::browser::Column::Lapses);
}

#[test]
fn browser_suspends_buries_unsuspends_and_undoes() {
    let mut app = app(ENGLISH);
    press(&mut app, KeyCode::Char('b'));
    press(&mut app, KeyCode::Char('/'));
    type_text(&mut app, "is:suspended");
    assert!(shown_cards(&app).is_empty());
    for _ in 0.."is:suspended".len() {
        press(&mut app, KeyCode::Backspace);
    }
    press(&mut app, KeyCode::Enter);
    let first = browser(&app).current().map(|r| r.key(&app.decks));
    let Some(first) = first else {
        panic!("no row selected");
    };
    press(&mut app, KeyCode::Char('s'));
    assert!(
        app.services
            .study
            .store
            .status(&first)
            .map(|s| s.suspended)
            .unwrap_or(false)
    );
    insta::assert_snapshot!("browser_suspended_en", render(&app));
    press(&mut app, KeyCode::Char('u'));
    // Said as what it was, not as a rating.
    let screen = render(&app);
    assert!(
        screen.contains("suspend undone") && !screen.contains("rating"),
        "{screen}"
    );
    assert!(
        !app.services
            .study
            .store
            .status(&first)
            .map(|s| s.suspended)
            .unwrap_or(true)
    );

    press(&mut app, KeyCode::Char('b'));
    let now = app.services.now();
    assert!(
        app.services
            .study
            .store
            .status(&first)
            .map(|s| s.buried(now))
            .unwrap_or(false)
    );
    press(&mut app, KeyCode::Char('U'));
    assert!(
        app.services
            .study
            .store
            .status(&first)
            .map(|s| s.studyable(now))
            .unwrap_or(false)
    );
    // Two changes made, two undone, each said as what it was; then
    // nothing is left to undo here.
    press(&mut app, KeyCode::Char('u'));
    assert!(
        render(&app).contains("unsuspend undone"),
        "{}",
        render(&app)
    );
    press(&mut app, KeyCode::Char('u'));
    assert!(render(&app).contains("bury undone"), "{}", render(&app));
    assert!(
        app.services
            .study
            .store
            .status(&first)
            .map(|s| s.studyable(now))
            .unwrap_or(false)
    );
    press(&mut app, KeyCode::Char('u'));
    assert_eq!(browser(&app).marks, 0);
}

#[test]
fn filter_counts_the_matching_items_and_starts_a_session() {
    for lang in [ENGLISH, HINGLISH] {
        let mut app = app(lang);
        press(&mut app, KeyCode::Char('f'));
        assert_eq!(app.context(), Context::Filter);
        let count = |app: &TestApp| match app.screen() {
            Screen::Filter(f) => f.count.clone(),
            _ => panic!("not on the filter"),
        };
        assert_eq!(count(&app), Ok(8), "six card items and two prompts");
        type_text(&mut app, "euler");
        assert_eq!(count(&app), Ok(2), "the cloze card's two numbers");
        press(&mut app, KeyCode::Tab);
        press(&mut app, KeyCode::Right);
        assert_eq!(count(&app), Ok(2), "both are new");
        insta::assert_snapshot!(format!("filter_{lang}"), render(&app));
        press(&mut app, KeyCode::Right);
        assert_eq!(count(&app), Ok(0), "none is learning");
        press(&mut app, KeyCode::Left);
        press(&mut app, KeyCode::Enter);
        let Screen::Review(r) = app.screen() else {
            panic!("the session did not start");
        };
        assert!(r.filtered);
        let shown = r.current.as_ref().map(|(k, _)| k.clone());
        assert_eq!(shown, Some(key("euler-cloze", Direction::Cloze(1))));
        insta::assert_snapshot!(format!("cloze_front_{lang}"), render(&app));
        press(&mut app, KeyCode::Char(' '));
        insta::assert_snapshot!(format!("cloze_back_{lang}"), render(&app));
        press(&mut app, KeyCode::Char('3'));
        let history = app
            .services
            .study
            .store
            .history(&key("euler-cloze", Direction::Cloze(1)));
        assert_eq!(
            history.map(|h| h.len()).unwrap_or(0),
            1,
            "ratings of a filtered session count"
        );
    }
}

#[test]
fn filter_refuses_a_bad_span_and_an_unknown_tag() {
    let mut app = app(ENGLISH);
    press(&mut app, KeyCode::Char('f'));
    type_text(&mut app, "nosuch");
    let Screen::Filter(f) = app.screen() else {
        panic!("not on the filter");
    };
    assert!(matches!(&f.count, Err(e) if e.contains("no card has tag `nosuch`")));
    press(&mut app, KeyCode::Enter);
    assert!(matches!(app.screen(), Screen::Filter(_)), "nothing starts");
    for _ in 0..6 {
        press(&mut app, KeyCode::Backspace);
    }
    press_all(&mut app, &[KeyCode::Tab, KeyCode::Tab]);
    type_text(&mut app, "3x");
    let Screen::Filter(f) = app.screen() else {
        panic!("not on the filter");
    };
    assert!(
        matches!(&f.count, Err(e) if e.contains("not a span")),
        "{:?}",
        f.count
    );
}

#[test]
fn review_suspends_and_buries_with_undo_and_buries_siblings() {
    let mut app = app(ENGLISH);
    app.services.study.config.bury_siblings = true;
    press(&mut app, KeyCode::Enter);
    let current = |app: &TestApp| match app.screen() {
        Screen::Review(r) => r.current.as_ref().map(|(k, _)| k.clone()),
        _ => None,
    };
    let Some(first) = current(&app) else {
        panic!("no card");
    };
    press(&mut app, KeyCode::Char('s'));
    assert!(
        app.services
            .study
            .store
            .status(&first)
            .map(|s| s.suspended)
            .unwrap_or(false)
    );
    assert_ne!(current(&app), Some(first.clone()));
    let screen = render(&app);
    assert!(screen.contains("card suspended"), "{screen}");
    press(&mut app, KeyCode::Char('u'));
    let screen = render(&app);
    assert!(
        screen.contains("suspend undone") && !screen.contains("last rating undone"),
        "{screen}"
    );
    assert_eq!(
        current(&app),
        Some(first.clone()),
        "undo brings the card back"
    );
    assert!(
        !app.services
            .study
            .store
            .status(&first)
            .map(|s| s.suspended)
            .unwrap_or(true)
    );

    // Answer until the reversed card comes up: its other direction is buried.
    let reversed_fwd = key("euler-1", Direction::Forward);
    let reversed_back = key("euler-1", Direction::Backward);
    for _ in 0..6 {
        if current(&app) == Some(reversed_fwd.clone()) {
            break;
        }
        press_all(&mut app, &[KeyCode::Enter, KeyCode::Char('3')]);
    }
    if current(&app) == Some(reversed_fwd.clone()) {
        // A new card's other direction is not among today's new: it would
        // be buried with this answer, and takes no place of the limit.
        match app.screen() {
            Screen::Review(r) => match &r.source {
                crate::tui::screens::review::Source::Daily(q) => {
                    assert!(!q.contains(&reversed_back))
                }
                _ => panic!("not the day's queue"),
            },
            _ => panic!("not reviewing"),
        }
        press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('3')]);
        let now = app.services.now();
        assert!(
            app.services
                .study
                .store
                .status(&reversed_back)
                .map(|s| s.buried(now))
                .unwrap_or(false),
            "the other direction is buried"
        );
        // The counts moved by one: nothing to explain.
        let screen = render(&app);
        assert!(
            !screen.contains("its other direction waits until tomorrow"),
            "{screen}"
        );
        // Undoing the answer unburies it (the next card may be a typed one,
        // where `u` is a letter of the answer: the action is applied).
        crate::tui::update::apply(&mut app, crate::tui::action::Action::Undo);
        let st = app.services.study.store.status(&reversed_back);
        let hist = app.services.study.store.status_history(&reversed_back);
        assert!(
            st.as_ref().map(|s| s.studyable(now)).unwrap_or(false),
            "{st:?} {hist:?} {:?}",
            app.status
        );
    } else {
        panic!("the reversed card never came up");
    }
}

#[test]
fn a_card_suspended_meanwhile_is_not_rated() {
    let mut app = app(ENGLISH);
    press(&mut app, KeyCode::Enter);
    let Screen::Review(r) = app.screen() else {
        panic!("no review");
    };
    let Some((shown, _)) = r.current.clone() else {
        panic!("no card");
    };
    press(&mut app, KeyCode::Char(' '));
    // Another window suspends it.
    let now = app.services.now();
    let done = app.services.study.store.set_status(
        std::slice::from_ref(&shown),
        StatusAction::Suspend,
        now,
        None,
    );
    assert!(done.is_ok());
    press(&mut app, KeyCode::Char('3'));
    assert_eq!(
        app.services
            .study
            .store
            .history(&shown)
            .map(|h| h.len())
            .unwrap_or(9),
        0
    );
    let screen = render(&app);
    assert!(screen.contains("suspended or buried meanwhile"), "{screen}");
}

#[test]
fn typing_narrows_the_last_search_without_losing_rows() {
    let mut app = app(ENGLISH);
    press(&mut app, KeyCode::Char('b'));
    press(&mut app, KeyCode::Char('/'));
    let mut typed = String::new();
    for c in "euler 1".chars() {
        typed.push(c);
        press(&mut app, KeyCode::Char(c));
        super::settle(&mut app);
        // What a fresh search over every row finds, in the same order.
        let b = browser(&app);
        let mut fresh = crate::catalog::Search::new(&app.decks, &b.rows);
        let all: Vec<usize> = (0..b.rows.len()).collect();
        assert_eq!(b.shown, fresh.matching(&typed, &all).best, "{typed:?}");
    }
    // After a suspend, a status filter sees the change.
    for _ in 0..typed.len() {
        press(&mut app, KeyCode::Backspace);
    }
    type_text(&mut app, "is:suspended");
    assert!(shown_cards(&app).is_empty());
    press(&mut app, KeyCode::Enter);
    for _ in 0.."is:suspended".len() {
        press(&mut app, KeyCode::Char('/'));
        press(&mut app, KeyCode::Backspace);
        press(&mut app, KeyCode::Enter);
    }
    press(&mut app, KeyCode::Char('s'));
    press(&mut app, KeyCode::Char('/'));
    type_text(&mut app, "is:suspended");
    assert_eq!(shown_cards(&app).len(), 1);
}

#[test]
fn a_key_typed_before_the_index_is_built_is_drawn_at_once_and_searched_when_it_is() {
    for (lang, searching) in [(ENGLISH, "searching…"), (HINGLISH, "dhoondh rahe…")] {
        let mut app = app(lang);
        press_all(&mut app, &[KeyCode::Char('b'), KeyCode::Char('/')]);
        let decks = app.decks.clone();
        let release = match app.screen_mut() {
            Screen::Browser(b) => b.hold_index(&decks),
            _ => panic!("the browser is not open"),
        };
        let all = browser(&app).shown.clone();
        press(&mut app, KeyCode::Char('e'));
        // The key is on screen, the list as it was, and the loop ticks.
        assert!(browser(&app).waiting);
        assert!(app.animating());
        assert_eq!(browser(&app).shown, all);
        let screen = render(&app);
        assert!(screen.contains(&format!("/ e▏  {searching}")), "{screen}");
        // A tick before the index is ready changes nothing.
        crate::tui::update::apply(
            &mut app,
            crate::tui::action::Action::Tick(Default::default()),
        );
        assert!(browser(&app).waiting);
        let _ = release.send(());
        super::settle(&mut app);
        let b = browser(&app);
        let mut fresh = crate::catalog::Search::new(&app.decks, &b.rows);
        let rows: Vec<usize> = (0..b.rows.len()).collect();
        assert_eq!(b.shown, fresh.matching("e", &rows).best);
        assert_ne!(b.shown, all, "the search narrowed the list");
        assert!(!app.animating());
    }
}

/// The count follows the query ("3 of 9 items"), and the query is read as
/// Anki users type it: `or`, `-`, parentheses, `*`, `is:`, `prop:`; a
/// mistake names its column and the list stays.
#[test]
fn browser_count_follows_an_anki_query() {
    let mut app = app(ENGLISH);
    press(&mut app, KeyCode::Char('b'));
    let total = browser(&app).rows.len();
    assert!(render(&app).contains(&format!("{total} items")));
    press(&mut app, KeyCode::Char('/'));
    type_text(&mut app, "-tag:euler");
    super::settle(&mut app);
    let b = browser(&app);
    let kept = b.shown.len();
    assert!(kept > 0 && kept < total, "{kept} of {total}");
    for &i in &b.shown {
        assert!(!b.rows[i].tags(&app.decks).iter().any(|t| t == "euler"));
    }
    assert!(
        render(&app).contains(&format!("{kept} of {total} items")),
        "{}",
        render(&app)
    );
    // Its complement and it make every item.
    for _ in 0.."-tag:euler".len() {
        press(&mut app, KeyCode::Backspace);
    }
    type_text(&mut app, "(tag:eul* or is:suspended)");
    super::settle(&mut app);
    assert_eq!(browser(&app).shown.len(), total - kept);
    type_text(&mut app, ")");
    super::settle(&mut app);
    let b = browser(&app);
    assert_eq!(b.shown.len(), total - kept, "the list stays");
    assert!(
        b.error
            .as_deref()
            .is_some_and(|e| e.starts_with("at column ")),
        "{:?}",
        b.error
    );
}
