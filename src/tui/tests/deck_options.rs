//! Deck options through the screens: a deck's preset schedules the rating
//! the review screen stores and bounds the home counts; a card whose other
//! direction would be buried does not take a place of the new-card limit;
//! decks under a parent show indented with the counts of their subtree,
//! and Enter on the parent studies the subtree within every deck's limits.

use chrono::TimeDelta;
use crossterm::event::KeyCode;

use super::press;
use crate::deck::{Card, CardKind, Deck, Text};
use crate::sched::preset::{DeckSettings, Preset};
use crate::sched::{Config, Direction, ItemKey, Scheduler, State};
use crate::tui::i18n::ENGLISH;
use crate::tui::screens::Screen;
use crate::tui::screens::home::HomeState;
use crate::tui::testkit::{self, TestApp, render};

fn text(en: &str) -> Text {
    Text(
        std::collections::BTreeMap::from([
            ("en".to_string(), en.to_string()),
            ("hi-Latn".to_string(), en.to_string()),
        ])
        .into(),
    )
}

/// A deck of `n` reversed cards (two items each), basic-only prompts none.
fn reversed(id: &str, n: usize) -> Deck {
    let mut d = testkit::deck();
    d.id = id.into();
    d.title = text(&format!("Deck {id}"));
    d.prompts.clear();
    d.cards = (0..n)
        .map(|i| Card {
            id: format!("c{i:02}"),
            kind: CardKind::Reversed,
            front: text(&format!("front {i}")),
            back: text(&format!("back {i}")),
            accept: Vec::new(),
            accept_by_lang: Default::default(),
            explain: None,
            prompt: None,
            tags: Vec::new(),
            formula: None,
        })
        .collect();
    d
}

fn set_config(app: &mut TestApp, config: Config) {
    app.services.study.scheduler = Scheduler::new(&config);
    app.services.study.config = config;
    refresh_home(app);
}

fn refresh_home(app: &mut TestApp) {
    let fresh = HomeState::new(app);
    if let Screen::Home(h) = app.screen_mut() {
        h.refresh(fresh);
    }
}

fn home(app: &TestApp) -> &HomeState {
    match app.screen() {
        Screen::Home(h) => h,
        _ => panic!("not on home"),
    }
}

/// The new count of home's row of deck `id`.
fn new_on_home(app: &TestApp, id: &str) -> usize {
    let i = app.decks.iter().position(|d| d.id == id).unwrap();
    let row = home(app).rows.iter().find(|r| r.deck == i).unwrap();
    row.counts.unwrap().new
}

/// Answers every new item the review offers with Easy (each graduates at
/// once); the items answered, in order.
fn answer_new_with_easy(app: &mut TestApp) -> Vec<ItemKey> {
    press(app, KeyCode::Enter);
    let mut answered = Vec::new();
    for _ in 0..200 {
        let Screen::Review(r) = app.screen() else {
            panic!("not reviewing")
        };
        let Some((key, _)) = r.current.clone() else {
            break;
        };
        press(app, KeyCode::Char(' '));
        press(app, KeyCode::Char('4'));
        answered.push(key);
    }
    press(app, KeyCode::Esc);
    answered
}

fn preset_config(preset: Preset, deck: &str) -> Config {
    Config {
        fuzz: false,
        bury_siblings: false,
        presets: [("short".to_string(), preset)].into(),
        decks: [(
            deck.to_string(),
            DeckSettings {
                preset: Some("short".into()),
            },
        )]
        .into(),
        ..Config::default()
    }
}

#[test]
fn a_presets_limits_and_scheduling_reach_the_rating_stored() {
    let mut app = testkit::app(ENGLISH);
    app.decks = vec![reversed("capped", 5), reversed("plain", 5)];
    let preset = Preset {
        new_per_day: Some(3),
        learning_steps: Some(Vec::new()),
        maximum_interval: Some(2),
        ..Preset::default()
    };
    set_config(&mut app, preset_config(preset, "capped"));
    assert_eq!(new_on_home(&app, "capped"), 3, "the preset's limit");
    assert_eq!(new_on_home(&app, "plain"), 10, "the top level's 20");

    let now = testkit::now();
    let answered = answer_new_with_easy(&mut app);
    assert_eq!(answered.len(), 3);
    for key in &answered {
        let s = app.services.study.store.state(key).unwrap().unwrap();
        assert_eq!(s.state, State::Review);
        // Easy on a new card is about 8 days by default: capped at 2.
        assert_eq!(s.due - now, TimeDelta::days(2), "{key:?}");
    }
    refresh_home(&mut app);
    assert_eq!(new_on_home(&app, "capped"), 0);

    // The other deck: the top level's scheduling (no cap, 0.9).
    if let Screen::Home(h) = app.screen_mut() {
        h.select_deck(1);
    }
    let plain = answer_new_with_easy(&mut app);
    assert_eq!(plain.len(), 10);
    let s = app.services.study.store.state(&plain[0]).unwrap().unwrap();
    assert!(s.due - now > TimeDelta::days(2), "{:?}", s.due - now);
}

#[test]
fn buried_siblings_do_not_use_up_the_new_limit() {
    let mut app = testkit::app(ENGLISH);
    app.decks = vec![reversed("both-ways", 30)];
    set_config(
        &mut app,
        Config {
            fuzz: false,
            bury_siblings: true,
            ..Config::default()
        },
    );
    // Twenty cards, one direction each (the other is buried once it is
    // answered).
    assert_eq!(new_on_home(&app, "both-ways"), 20);
    let answered = answer_new_with_easy(&mut app);
    assert_eq!(answered.len(), 20);
    let cards: std::collections::HashSet<&str> = answered.iter().map(|k| k.card.as_str()).collect();
    assert_eq!(cards.len(), 20, "twenty notes introduced, not ten");
    assert!(answered.iter().all(|k| k.direction == Direction::Forward));
    // The backward items are buried, and the limit is used up: home says
    // 0 new and means it.
    refresh_home(&mut app);
    assert_eq!(new_on_home(&app, "both-ways"), 0);
    let statuses = app.services.study.store.statuses().unwrap();
    let buried = statuses
        .iter()
        .filter(|(k, s)| k.direction == Direction::Backward && !s.studyable(testkit::now()))
        .count();
    assert_eq!(buried, 20);
}

#[test]
fn a_partly_used_limit_is_counted_in_notes() {
    let mut app = testkit::app(ENGLISH);
    app.decks = vec![reversed("both-ways", 30)];
    set_config(
        &mut app,
        Config {
            fuzz: false,
            bury_siblings: true,
            new_per_day: 8,
            ..Config::default()
        },
    );
    // Five answered, then the session left: three cards left today.
    press(&mut app, KeyCode::Enter);
    for _ in 0..5 {
        press(&mut app, KeyCode::Char(' '));
        press(&mut app, KeyCode::Char('4'));
    }
    press(&mut app, KeyCode::Esc);
    assert_eq!(new_on_home(&app, "both-ways"), 3);
    assert_eq!(answer_new_with_easy(&mut app).len(), 3);
}

#[test]
fn a_parent_shows_its_subtree_and_studies_it_within_each_limit() {
    let mut app = testkit::app(ENGLISH);
    let parent = reversed("mech", 2);
    let mut child = reversed("mech-springs", 6);
    child.parent = Some("mech".into());
    let other = reversed("optics", 1);
    // Listed child first: home puts it under its parent (the top-level
    // decks keep their order).
    app.decks = vec![child, other, parent];
    let preset = Preset {
        new_per_day: Some(3),
        ..Preset::default()
    };
    let mut config = preset_config(preset, "mech-springs");
    config.new_per_day = 4;
    set_config(&mut app, config);

    let rows: Vec<(String, usize, usize)> = home(&app)
        .rows
        .iter()
        .map(|r| (app.decks[r.deck].id.clone(), r.depth, r.counts.unwrap().new))
        .collect();
    assert_eq!(
        rows,
        [
            // The parent's 4 (its own 4 items, then the child's, bounded by
            // the parent's limit); the child alone: its preset's 3.
            ("optics".to_string(), 0, 2),
            ("mech".to_string(), 0, 4),
            ("mech-springs".to_string(), 1, 3),
        ]
    );
    let screen = render(&app);
    let parent_line = screen
        .lines()
        .position(|l| l.contains("Deck mech "))
        .unwrap();
    let child_line = screen.lines().nth(parent_line + 1).unwrap();
    assert!(child_line.contains("  Deck mech-springs"), "{screen}");

    // The parent studied with a limit of 6: its own 4 items, then 2 of the
    // child (whose own limit, 3, is not reached).
    let mut config = app.services.study.config.clone();
    config.new_per_day = 6;
    set_config(&mut app, config);
    assert_eq!(new_on_home(&app, "mech"), 6);
    if let Screen::Home(h) = app.screen_mut() {
        h.select_deck(2);
    }
    let answered = answer_new_with_easy(&mut app);
    let decks: Vec<&str> = answered.iter().map(|k| k.deck.as_str()).collect();
    assert_eq!(
        decks,
        [
            "mech",
            "mech",
            "mech",
            "mech",
            "mech-springs",
            "mech-springs"
        ]
    );
    // The child has one left of its 3; the parent none.
    refresh_home(&mut app);
    assert_eq!(new_on_home(&app, "mech-springs"), 1);
    assert_eq!(new_on_home(&app, "mech"), 0);
}

#[test]
fn a_due_review_whose_other_direction_is_due_too_is_set_aside_and_said() {
    let mut app = testkit::app(ENGLISH);
    app.decks = vec![reversed("both-ways", 1)];
    set_config(
        &mut app,
        Config {
            fuzz: false,
            bury_siblings: true,
            ..Config::default()
        },
    );
    // Both directions learnt long ago and due now.
    let now = testkit::now();
    let then = now - TimeDelta::days(10);
    let sched = app.services.study.scheduler.clone();
    for direction in [Direction::Forward, Direction::Backward] {
        let key = ItemKey {
            deck: "both-ways".into(),
            card: "c00".into(),
            direction,
        };
        let rec = sched.review(&key, None, crate::sched::Rating::Easy, then, 0);
        let after = crate::store::AfterRating {
            leech_threshold: 0,
            leech_suspend: false,
            bury: Vec::new(),
            bury_until: then,
        };
        app.services.study.store.record_study(&rec, &after).unwrap();
    }
    refresh_home(&mut app);
    let row = home(&app).rows[0].counts.unwrap();
    assert_eq!((row.due, row.new), (2, 0));
    press(&mut app, KeyCode::Enter);
    press(&mut app, KeyCode::Char(' '));
    press(&mut app, KeyCode::Char('3'));
    // The other direction left the queue with the answer, and that is said.
    let screen = render(&app);
    assert!(
        screen.contains("its other direction waits until tomorrow"),
        "{screen}"
    );
    let Screen::Review(r) = app.screen() else {
        panic!("not reviewing")
    };
    assert!(r.current.is_none(), "nothing left today");
}
