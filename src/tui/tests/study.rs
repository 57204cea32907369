//! Filtered study across decks: the filter's decks field and its live
//! count, each card shown and rated against its own deck, undo across the
//! boundary between decks, and a (re)learning card coming back at its step.

use crossterm::event::KeyCode;

use super::{press, press_all, type_text};
use crate::deck::{Card, CardKind, Deck, Text};
use crate::sched::{Direction, ItemKey, Rating, State};
use crate::tui::i18n::{ENGLISH, HINGLISH};
use crate::tui::screens::Screen;
use crate::tui::screens::review::{ReviewState, Source};
use crate::tui::services::Clock;
use crate::tui::testkit::{self, TestApp, render};

fn text(en: &str, hi: &str) -> Text {
    Text(
        std::collections::BTreeMap::from([
            ("en".to_string(), en.to_string()),
            ("hi-Latn".to_string(), hi.to_string()),
        ])
        .into(),
    )
}

/// A second deck: one card sharing the fixture's tag `frames`, one with a
/// tag of its own, and its own explanation section.
fn springs() -> Deck {
    let mut d = testkit::deck();
    d.id = "springs".into();
    d.title = text("Springs", "Springs (Hinglish)");
    let card = |id: &str, tags: &[&str], front: Text| Card {
        id: id.into(),
        kind: CardKind::Basic,
        front,
        back: text("$F = -kx$", "$F = -kx$"),
        accept: Vec::new(),
        accept_by_lang: Default::default(),
        explain: Some("hooke-law".into()),
        prompt: None,
        tags: tags.iter().map(|t| t.to_string()).collect(),
        formula: None,
    };
    d.cards = vec![
        card(
            "hooke",
            &["frames", "springs"],
            text(
                "Hooke's law in the lab frame?",
                "Lab frame mein Hooke ka niyam?",
            ),
        ),
        card(
            "period",
            &["springs"],
            text(
                "Period of a mass on a spring?",
                "Spring par mass ka period?",
            ),
        ),
    ];
    let mut section = d.sections[0].clone();
    section.id = "hooke-law".into();
    section.title = text("Hooke's law", "Hooke ka niyam");
    d.sections = vec![section];
    d.prompts.clear();
    d
}

fn app(lang: &str) -> TestApp {
    let mut app = testkit::app(lang);
    app.decks.push(springs());
    app
}

fn item(deck: &str, card: &str) -> ItemKey {
    ItemKey {
        deck: deck.into(),
        card: card.into(),
        direction: Direction::Forward,
    }
}

fn review(app: &TestApp) -> &ReviewState {
    match app.screen() {
        Screen::Review(r) => r,
        _ => panic!("not on the review screen"),
    }
}

fn shown(app: &TestApp) -> Option<ItemKey> {
    review(app).current.as_ref().map(|(k, _)| k.clone())
}

fn count(app: &TestApp) -> Result<usize, String> {
    match app.screen() {
        Screen::Filter(f) => f.count.clone(),
        _ => panic!("not on the filter"),
    }
}

/// Ratings of `key` not undone.
fn ratings(app: &TestApp, key: &ItemKey) -> usize {
    app.services
        .study
        .store
        .history(key)
        .map(|h| h.iter().filter(|r| !r.undone).count())
        .unwrap_or(0)
}

#[test]
fn the_filter_offers_every_deck_and_counts_across_them() {
    for lang in [ENGLISH, HINGLISH] {
        let mut app = app(lang);
        press(&mut app, KeyCode::Char('f'));
        type_text(&mut app, "frames");
        assert_eq!(count(&app), Ok(1), "the selected deck only");
        // The decks field: the selected deck, the next one, then all decks.
        press_all(&mut app, &[KeyCode::Tab; 4]);
        press(&mut app, KeyCode::Right);
        assert_eq!(count(&app), Ok(1), "the second deck only");
        press(&mut app, KeyCode::Right);
        assert_eq!(count(&app), Ok(2), "every deck");
        insta::assert_snapshot!(format!("filter_all_decks_{lang}"), render(&app));
        // A tag of the second deck alone: an error for the first deck, a
        // count over every deck.
        press_all(&mut app, &[KeyCode::Tab]);
        for _ in 0.."frames".len() {
            press(&mut app, KeyCode::Backspace);
        }
        type_text(&mut app, "springs");
        assert_eq!(count(&app), Ok(2));
        press_all(&mut app, &[KeyCode::BackTab, KeyCode::Right]);
        assert!(
            matches!(count(&app), Err(e) if e.contains("no card has tag `springs`; tags are frames")),
            "{:?}",
            count(&app)
        );
    }
}

#[test]
fn a_filter_over_every_deck_rates_each_card_against_its_own_deck() {
    for lang in [ENGLISH, HINGLISH] {
        let mut app = app(lang);
        press(&mut app, KeyCode::Char('f'));
        type_text(&mut app, "frames");
        press_all(&mut app, &[KeyCode::BackTab, KeyCode::Left]);
        assert_eq!(count(&app), Ok(2));
        press(&mut app, KeyCode::Enter);
        let (first, second) = (
            item("torque-free", "body-frame-why"),
            item("springs", "hooke"),
        );
        assert_eq!(review(&app).decks, vec![0, 1]);
        assert_eq!(shown(&app), Some(first.clone()));
        assert_eq!(review(&app).deck, 0);

        // `e` opens the explanation of the card's own deck.
        press(&mut app, KeyCode::Char('e'));
        match app.screen() {
            Screen::Reader(r) => assert_eq!((r.deck, r.section), (0, 0)),
            _ => panic!("no explanation opened"),
        }
        press(&mut app, KeyCode::Esc);
        press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('4')]);
        assert_eq!(shown(&app), Some(second.clone()));
        assert_eq!(review(&app).deck, 1);
        insta::assert_snapshot!(format!("review_second_deck_{lang}"), render(&app));
        press(&mut app, KeyCode::Char('e'));
        match app.screen() {
            Screen::Reader(r) => {
                assert_eq!(r.deck, 1);
                assert_eq!(app.decks[1].sections[r.section].id, "hooke-law");
            }
            _ => panic!("no explanation opened"),
        }
        press(&mut app, KeyCode::Esc);
        press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('4')]);
        assert_eq!(shown(&app), None, "Easy graduates both: nothing comes back");
        assert_eq!(review(&app).session.reviewed, 2);
        assert_eq!((ratings(&app, &first), ratings(&app, &second)), (1, 1));
        let springs = app
            .services
            .study
            .store
            .states("springs")
            .unwrap_or_default();
        assert_eq!(
            springs.get(&second).map(|s| s.state),
            Some(State::Review),
            "the rating is stored against its own deck"
        );

        // Undo walks back over the boundary between the decks.
        press(&mut app, KeyCode::Char('u'));
        assert_eq!((shown(&app), review(&app).deck), (Some(second.clone()), 1));
        press(&mut app, KeyCode::Char('u'));
        assert_eq!((shown(&app), review(&app).deck), (Some(first.clone()), 0));
        assert_eq!((ratings(&app, &first), ratings(&app, &second)), (0, 0));
        assert_eq!(review(&app).session.reviewed, 0);
        // Rated again, the session ends with its summary over both decks.
        press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('4')]);
        press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('4')]);
        assert_eq!(shown(&app), None);
        let next = review(&app).what_next(&app);
        // The cards left unseen: two of the fixture deck, one of springs.
        assert_eq!(next.new_cards, 3);
        assert_eq!((ratings(&app, &first), ratings(&app, &second)), (1, 1));
    }
}

#[test]
fn a_lapse_in_a_filtered_session_comes_back_at_its_step_not_at_the_end() {
    let mut app = app(ENGLISH);
    let now = testkit::now();
    let first = item("torque-free", "body-frame-why");
    // A card learnt a month ago: Again makes it relearning.
    let learnt = app.services.study.scheduler.review(
        &first,
        None,
        Rating::Easy,
        now - chrono::TimeDelta::days(30),
        0,
    );
    assert!(app.services.study.store.record(&learnt).is_ok());
    press_all(&mut app, &[KeyCode::Char('f'), KeyCode::Enter]);
    assert_eq!(shown(&app), Some(first.clone()));
    press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('1')]);
    let step = app
        .services
        .study
        .store
        .state(&first)
        .ok()
        .flatten()
        .filter(|s| s.state == State::Relearning)
        .map(|s| s.due);
    let Some(step) = step else {
        panic!("Again did not start relearning");
    };
    assert!(step > now);
    // Before its step the list goes on.
    let euler = item("torque-free", "euler-1");
    assert_eq!(shown(&app), Some(euler.clone()));
    assert!(review(&app).progress(&app).contains("1 learning"));
    press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('4')]);
    // At its step it comes before the rest of the list (the typed card).
    app.services.clock = Clock::Fixed(step);
    press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('4')]);
    assert_eq!(shown(&app), Some(first.clone()));
    let Source::Filtered(q) = &review(&app).source else {
        panic!("a filtered session is a queue over its list");
    };
    // The rest of the list: two cards and the deck's two prompts.
    assert_eq!(q.counts().total(), 4);
}

#[test]
fn cram_over_a_filter_puts_again_at_the_back() {
    let mut app = app(ENGLISH);
    press(&mut app, KeyCode::Char('f'));
    type_text(&mut app, "frames");
    // Cram on, every deck.
    press_all(&mut app, &[KeyCode::Tab, KeyCode::Tab, KeyCode::Tab]);
    press_all(&mut app, &[KeyCode::Right, KeyCode::Tab, KeyCode::Left]);
    press(&mut app, KeyCode::Enter);
    assert!(review(&app).cram);
    let first = item("torque-free", "body-frame-why");
    press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('1')]);
    assert_eq!(shown(&app), Some(item("springs", "hooke")));
    press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('3')]);
    assert_eq!(shown(&app), Some(first.clone()), "Again comes round again");
    press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('3')]);
    assert_eq!(shown(&app), None);
    // Cram answers leave the schedule as it was.
    assert_eq!(app.services.study.store.state(&first).ok().flatten(), None);
}

/// Four leeches of the fixture deck (one with two lapses, the rest with
/// one; threshold 1, suspended), and a card buried.
fn leeches(app: &mut TestApp) {
    let now = testkit::now();
    let day = chrono::TimeDelta::days(1);
    let back = ItemKey {
        direction: Direction::Backward,
        ..item("torque-free", "euler-1")
    };
    let keys = [
        item("torque-free", "body-frame-why"),
        item("torque-free", "euler-1"),
        back,
        item("torque-free", "unstable-axis"),
    ];
    for (i, key) in keys.iter().enumerate() {
        let lapses: u32 = if i == 0 { 2 } else { 1 };
        let s = &app.services.study.scheduler;
        let mut rec = s.review(key, None, Rating::Easy, now - day * 40, 0);
        let mut records = vec![rec.clone()];
        for n in 0..lapses {
            let at = now - day * (20 - 4 * n as i32);
            if n > 0 {
                // Back to review first: a lapse is an Again on a review.
                let after = rec.after;
                rec = s.review(key, Some(&after), Rating::Easy, at - day, 0);
                records.push(rec.clone());
            }
            let after = rec.after;
            rec = s.review(key, Some(&after), Rating::Again, at, 0);
            records.push(rec.clone());
        }
        for r in &records {
            let follow = crate::store::AfterRating {
                leech_threshold: lapses,
                leech_suspend: true,
                bury: Vec::new(),
                bury_until: r.reviewed_at,
            };
            assert!(app.services.study.store.record_study(r, &follow).is_ok());
        }
    }
    let bury = app.services.study.store.set_status(
        &[item("springs", "period")],
        crate::store::StatusAction::Bury,
        now,
        Some(now + day),
    );
    assert!(bury.is_ok());
}

#[test]
fn the_stats_screen_lists_the_leeches_with_their_lapses() {
    for lang in [ENGLISH, HINGLISH] {
        for (w, h) in [(80, 24), (40, 12)] {
            let mut app = app(lang);
            app.size = (w, h);
            app.services.bench_csv = None;
            leeches(&mut app);
            press(&mut app, KeyCode::Char('t'));
            let Screen::Stats(s) = app.screen() else {
                panic!("stats not open");
            };
            let stats = s.stats.as_ref().map_err(|e| e.clone());
            let named: Vec<(String, String, u32)> = stats
                .map(|s| {
                    s.leeches
                        .iter()
                        .map(|l| (l.card.clone(), l.direction.clone(), l.lapses))
                        .collect()
                })
                .unwrap_or_default();
            assert_eq!(
                named,
                [
                    ("body-frame-why".to_string(), "forward".to_string(), 2),
                    ("euler-1".to_string(), "forward".to_string(), 1),
                    ("euler-1".to_string(), "backward".to_string(), 1),
                    ("unstable-axis".to_string(), "forward".to_string(), 1),
                ]
            );
            let frame = render(&app);
            if w == 80 {
                // The springs deck's bury is not this deck's.
                assert!(frame.contains("suspended 4"), "{frame}");
                assert!(frame.contains("body-frame-why/forward 2"), "{frame}");
                assert!(frame.contains("+1"), "{frame}");
            }
            insta::assert_snapshot!(format!("stats_leeches_{lang}_{w}x{h}"), frame);
        }
    }
}

#[test]
fn cram_at_the_end_of_a_filtered_session_crams_its_own_cards_over_every_deck() {
    let mut app = app(ENGLISH);
    press(&mut app, KeyCode::Char('f'));
    type_text(&mut app, "frames");
    press_all(&mut app, &[KeyCode::BackTab, KeyCode::Left, KeyCode::Enter]);
    let (first, second) = (
        item("torque-free", "body-frame-why"),
        item("springs", "hooke"),
    );
    for _ in 0..2 {
        press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('4')]);
    }
    assert_eq!(shown(&app), None, "the session is done");
    press(&mut app, KeyCode::Char('c'));
    let r = review(&app);
    assert!(r.cram && r.filtered);
    assert_eq!(r.decks, vec![0, 1]);
    let Source::Cram(c) = &r.source else {
        panic!("`c` did not open a cram session");
    };
    assert_eq!(c.remaining(), 2, "the filter's two cards, not a whole deck");
    assert_eq!(shown(&app), Some(first));
    press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('3')]);
    assert_eq!(shown(&app), Some(second));
}
