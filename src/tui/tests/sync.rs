//! The sync after a session: run when a review, an exam share or the
//! browser closes (not when a screen that changes nothing does), before the
//! home screen counts again, and said on the status line in both languages.

use std::cell::RefCell;
use std::rc::Rc;

use crossterm::event::KeyCode;

use super::{press, press_all};
use crate::tui::i18n::{ENGLISH, HINGLISH};
use crate::tui::screens::Screen;
use crate::tui::services::{Synced, Syncer};
use crate::tui::testkit::{self, TestApp, render};

/// A sync that counts its runs and reports `result`: at once, or (when
/// `slow`) only after `finish` is set, as a background sync would.
struct Fake {
    runs: Rc<RefCell<usize>>,
    result: Result<Synced, String>,
    running: bool,
    finish: Option<Rc<RefCell<bool>>>,
}

impl Syncer for Fake {
    fn start(&mut self, _: &crate::sched::Config) {
        *self.runs.borrow_mut() += 1;
        self.running = true;
    }
    fn poll(&mut self) -> Option<Result<Synced, String>> {
        let done = self.finish.as_ref().is_none_or(|f| *f.borrow());
        if self.running && done {
            self.running = false;
            return Some(self.result.clone());
        }
        None
    }
    fn busy(&self) -> bool {
        self.running
    }
}

/// Installs a sync that counts its runs and reports `result`.
fn hook(app: &mut TestApp, result: Result<Synced, String>) -> Rc<RefCell<usize>> {
    let runs = Rc::new(RefCell::new(0));
    app.services.sync = Some(Box::new(Fake {
        runs: Rc::clone(&runs),
        result,
        running: false,
        finish: None,
    }));
    runs
}

/// A session's close never waits for the sync: the home screen is back at
/// once, and what the sync did is said when it ends.
#[test]
fn the_sync_after_a_session_runs_behind_the_screen() {
    let mut app = testkit::app(ENGLISH);
    let runs = Rc::new(RefCell::new(0));
    let finish = Rc::new(RefCell::new(false));
    app.services.sync = Some(Box::new(Fake {
        runs: Rc::clone(&runs),
        result: Ok(Synced {
            written: 1,
            merged: 0,
            warnings: Vec::new(),
        }),
        running: false,
        finish: Some(Rc::clone(&finish)),
    }));
    press_all(
        &mut app,
        &[
            KeyCode::Enter,
            KeyCode::Char(' '),
            KeyCode::Char('3'),
            KeyCode::Esc,
        ],
    );
    assert!(matches!(app.screen(), Screen::Home(_)));
    assert_eq!(*runs.borrow(), 1);
    assert!(app.syncing(), "the sync is still running");
    assert!(!app.poll_sync());
    assert!(!render(&app).contains("Synced"), "{}", render(&app));
    *finish.borrow_mut() = true;
    assert!(app.poll_sync(), "its end changes the screen");
    assert!(!app.syncing());
    assert!(
        render(&app).contains("Synced: 1 sent, 0 received"),
        "{}",
        render(&app)
    );
}

#[test]
fn closing_a_review_syncs_once_and_says_what_came_and_went() {
    for (lang, words) in [
        (ENGLISH, "Synced: 2 sent, 1 received"),
        (HINGLISH, "Sync hua: 2 bheje, 1 aaye"),
    ] {
        let mut app = testkit::app(lang);
        let runs = hook(
            &mut app,
            Ok(Synced {
                written: 2,
                merged: 1,
                warnings: Vec::new(),
            }),
        );
        // Reading an explanation changes nothing: no sync.
        press_all(&mut app, &[KeyCode::Char('e'), KeyCode::Esc]);
        assert!(matches!(app.screen(), Screen::Home(_)));
        assert_eq!(*runs.borrow(), 0);
        press_all(
            &mut app,
            &[KeyCode::Enter, KeyCode::Char(' '), KeyCode::Char('3')],
        );
        assert_eq!(*runs.borrow(), 0, "no sync in the middle of a session");
        press(&mut app, KeyCode::Esc);
        assert!(matches!(app.screen(), Screen::Home(_)));
        assert_eq!(*runs.borrow(), 1);
        assert!(render(&app).contains(words), "{}", render(&app));
    }
}

#[test]
fn a_sync_with_nothing_to_say_stays_quiet_and_a_failed_one_is_an_error() {
    let mut app = testkit::app(ENGLISH);
    let runs = hook(&mut app, Ok(Synced::default()));
    press_all(&mut app, &[KeyCode::Char('b'), KeyCode::Esc]);
    assert_eq!(*runs.borrow(), 1, "the browser may have changed statuses");
    assert!(!render(&app).contains("Synced"), "{}", render(&app));

    let mut app = testkit::app(ENGLISH);
    hook(
        &mut app,
        Err("sync through /gone failed: no such folder".into()),
    );
    press_all(&mut app, &[KeyCode::Enter, KeyCode::Esc]);
    assert!(
        render(&app).contains("sync through /gone failed"),
        "{}",
        render(&app)
    );
    assert!(app.status.as_ref().is_some_and(|s| s.error));
}

/// Syncs `data` through `folder` as the app and the command do.
fn sync_dir(data: &std::path::Path, folder: &std::path::Path, config: &crate::sched::Config) {
    let now = chrono::Utc::now().max(testkit::now() + chrono::TimeDelta::days(1));
    if let Err(e) = crate::sync::sync_with(data, folder, config, now, crate::sync::Wait::No) {
        panic!("sync of {}: {e}", data.display());
    }
}

/// Every item's cached state, by item.
fn states(data: &std::path::Path) -> Vec<(crate::sched::ItemKey, crate::sched::CardState)> {
    let store = match crate::store::Store::open_read_only(data) {
        Ok(s) => s,
        Err(e) => panic!("{e}"),
    };
    let mut s: Vec<_> = store
        .cached_states()
        .unwrap_or_default()
        .into_iter()
        .map(|c| (c.key, c.state))
        .collect();
    s.sort_by(|a, b| a.0.cmp(&b.0));
    s
}

/// Answers given in the app on a clock that moves (microseconds and all,
/// not a frozen `FLIPCARD_NOW`), with the interval fuzz on: a second
/// machine that replays them from the sync folder gets the same due dates.
/// (The fuzz was drawn from the time in microseconds, which the log and the
/// sync file do not keep: about half of these came out a day apart.)
#[test]
fn answers_on_a_moving_clock_replay_to_the_same_due_dates_elsewhere() {
    let folder = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let other = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let mut config = None;
    let mut machines = Vec::new();
    for _ in 0..4 {
        let mut app = testkit::app(ENGLISH);
        app.services.study.config.fuzz = true;
        app.services.study.scheduler = crate::sched::Scheduler::new(&app.services.study.config);
        app.services.clock = crate::tui::services::Clock::System;
        // Every new card, Easy: it graduates to a fuzzed interval of days.
        press(&mut app, KeyCode::Enter);
        for _ in 0..20 {
            if !matches!(app.screen(), Screen::Review(_)) {
                break;
            }
            press_all(&mut app, &[KeyCode::Char(' '), KeyCode::Char('4')]);
        }
        let cfg = app.services.study.config.clone();
        sync_dir(app.dir.path(), folder.path(), &cfg);
        config = Some(cfg);
        machines.push(app);
    }
    let config = config.unwrap_or_default();
    sync_dir(other.path(), folder.path(), &config);
    let replayed = states(other.path());
    let mut given = Vec::new();
    for m in &machines {
        given.extend(states(m.dir.path()));
    }
    assert!(given.len() >= 12, "{} items answered", given.len());
    // Each machine studied the same items: compare each with the replay of
    // all of them (an item's answers from four machines).
    let store = crate::store::Store::open_read_only(other.path()).unwrap_or_else(|e| panic!("{e}"));
    for m in &machines {
        let mine =
            crate::store::Store::open_read_only(m.dir.path()).unwrap_or_else(|e| panic!("{e}"));
        let mut first = std::collections::HashMap::new();
        mine.each_review(|l| -> Result<(), crate::store::StoreError> {
            first.insert(l.record.key.clone(), l.record.after);
            Ok(())
        })
        .unwrap_or_else(|e| panic!("{e}"));
        for (key, after) in first {
            // The replay's row of this machine's answer.
            let rows = store.history(&key).unwrap_or_else(|e| panic!("{e}"));
            let replayed_row = rows
                .iter()
                .find(|r| r.record.reviewed_at == after.last_review.unwrap_or_default())
                .unwrap_or_else(|| panic!("{key:?}: answer not merged"));
            assert_eq!(
                replayed_row.record.after.due, after.due,
                "{key:?}: due differs after the replay"
            );
        }
    }
    assert!(!replayed.is_empty());
}

/// Under a frozen clock (`FLIPCARD_NOW`) the same card answered twice alike
/// is two answers, here and on the machine that merges them.
#[test]
fn two_answers_in_one_frozen_millisecond_are_two_answers() {
    let folder = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let other = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let mut app = testkit::app(ENGLISH);
    // Again in the day's review, then Again in a cram of the same deck.
    press_all(
        &mut app,
        &[
            KeyCode::Enter,
            KeyCode::Char(' '),
            KeyCode::Char('1'),
            KeyCode::Esc,
        ],
    );
    press_all(
        &mut app,
        &[
            KeyCode::Char('c'),
            KeyCode::Char(' '),
            KeyCode::Char('1'),
            KeyCode::Esc,
        ],
    );
    let key = crate::sched::ItemKey {
        deck: "torque-free".into(),
        card: "body-frame-why".into(),
        direction: crate::sched::Direction::Forward,
    };
    let here = app
        .services
        .study
        .store
        .history(&key)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(here.len(), 2, "{here:#?}");
    assert_ne!(here[0].record.reviewed_at, here[1].record.reviewed_at);
    let config = app.services.study.config.clone();
    sync_dir(app.dir.path(), folder.path(), &config);
    sync_dir(other.path(), folder.path(), &config);
    let store = crate::store::Store::open_read_only(other.path()).unwrap_or_else(|e| panic!("{e}"));
    let there = store.history(&key).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(there.iter().filter(|r| !r.undone).count(), 2, "{there:#?}");
}
