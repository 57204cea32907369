//! Suspend, bury and leeches as events of the status log: each change is
//! undoable, the cache always equals what the log alone gives, and cloze
//! items (directions `c1`, `c2`, …) are stored like any other.

use chrono::Duration;
use flipcard::sched::{Direction, ItemKey, Rating, ReviewKind, State};
use flipcard::store::{AfterRating, StatusAction, Store, Undone};
use rusqlite::Connection;

use crate::store_support::{at, back_key, key, review};

fn cloze(deck: &str, card: &str, n: u16) -> ItemKey {
    ItemKey {
        deck: deck.into(),
        card: card.into(),
        direction: Direction::Cloze(n),
    }
}

fn no_follow_up(when: chrono::DateTime<chrono::Utc>) -> AfterRating {
    AfterRating {
        leech_threshold: 0,
        leech_suspend: false,
        bury: Vec::new(),
        bury_until: when,
    }
}

#[test]
fn suspend_and_unsuspend_are_undoable_events_and_survive_a_rebuild() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = Store::open(dir.path()).unwrap();
    let now = at("2026-03-01T10:00:00Z");
    let (a, b) = (key("d", "a"), back_key("d", "a"));
    store
        .set_status(&[a.clone(), b.clone()], StatusAction::Suspend, now, None)
        .unwrap();
    assert!(store.status(&a).unwrap().suspended);
    assert!(store.status(&b).unwrap().suspended);
    store
        .set_status(std::slice::from_ref(&b), StatusAction::Unsuspend, now, None)
        .unwrap();
    assert!(!store.status(&b).unwrap().suspended);

    // Undo takes back the last change only: b is suspended again.
    match store.undo_last_change().unwrap() {
        Some(Undone::Status(events)) => {
            assert_eq!(events.len(), 1);
            assert_eq!(events[0].action, StatusAction::Unsuspend);
            assert!(events[0].undone);
        }
        other => panic!("{other:?}"),
    }
    assert!(store.status(&b).unwrap().suspended);
    // The first change was one call for two items: one undo reverts both.
    assert!(matches!(
        store.undo_last_change().unwrap(),
        Some(Undone::Status(e)) if e.len() == 2
    ));
    assert!(!store.status(&a).unwrap().suspended);
    assert!(store.undo_last_change().unwrap().is_none());

    store
        .set_status(std::slice::from_ref(&a), StatusAction::Suspend, now, None)
        .unwrap();
    let before = store.statuses().unwrap();
    let report = store.rebuild().unwrap();
    assert!(!report.statuses_changed);
    assert_eq!(store.statuses().unwrap(), before);

    // A cache wiped behind the app's back is rebuilt from the log alone.
    drop(store);
    let conn = Connection::open(dir.path().join("flipcard.db")).unwrap();
    conn.execute("DELETE FROM item_status", []).unwrap();
    drop(conn);
    let mut store = Store::open(dir.path()).unwrap();
    assert!(!store.status(&a).unwrap().suspended);
    assert!(store.rebuild().unwrap().statuses_changed);
    assert!(store.status(&a).unwrap().suspended);
    assert_eq!(store.status_history(&a).unwrap().len(), 2);
}

#[test]
fn a_bury_lasts_until_its_end_and_unsuspend_lifts_it() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = Store::open(dir.path()).unwrap();
    let now = at("2026-03-01T10:00:00Z");
    let end = at("2026-03-02T04:00:00Z");
    let a = key("d", "a");
    assert!(
        store
            .set_status(std::slice::from_ref(&a), StatusAction::Bury, now, None)
            .is_err(),
        "a bury without an end is refused"
    );
    store
        .set_status(std::slice::from_ref(&a), StatusAction::Bury, now, Some(end))
        .unwrap();
    let s = store.status(&a).unwrap();
    assert!(s.buried(now) && !s.studyable(now));
    assert!(s.studyable(end), "the bury ends when the next day starts");
    store
        .set_status(std::slice::from_ref(&a), StatusAction::Unsuspend, now, None)
        .unwrap();
    assert!(store.status(&a).unwrap().studyable(now));
}

#[test]
fn leeches_siblings_and_undo_of_the_rating_that_caused_them() {
    let dir = tempfile::tempdir().unwrap();
    let mut store = Store::open(dir.path()).unwrap();
    let mut when = at("2026-03-01T10:00:00Z");
    let c1 = cloze("d", "z", 1);
    let c2 = cloze("d", "z", 2);
    let follow = |when| AfterRating {
        leech_threshold: 3,
        leech_suspend: true,
        bury: vec![c1.clone(), c2.clone()],
        bury_until: when + Duration::hours(12),
    };
    let lapse = |when| {
        review(
            &c1,
            when,
            Rating::Again,
            ReviewKind::Review,
            State::Relearning,
            Duration::minutes(10),
        )
    };
    for i in 0..3 {
        when += Duration::days(2);
        let r = store.record_study(&lapse(when), &follow(when)).unwrap();
        assert_eq!(r.leech, i == 2, "lapse {}", i + 1);
        // The sibling is buried by every answer; the item answered is not.
        assert!(store.status(&c2).unwrap().buried(when));
        assert!(!store.status(&c1).unwrap().buried(when));
    }
    let s = store.status(&c1).unwrap();
    assert!(s.leech && s.suspended);
    assert_eq!(store.cached_state(&c1).unwrap().unwrap().lapses, 3);

    // A rating later than the leech: undo takes back the rating first.
    store
        .set_status(
            std::slice::from_ref(&c1),
            StatusAction::Unsuspend,
            when,
            None,
        )
        .unwrap();
    assert!(matches!(
        store.undo_last_change().unwrap(),
        Some(Undone::Status(_))
    ));
    assert!(matches!(
        store.undo_last_change().unwrap(),
        Some(Undone::Review(r)) if r.record.key == c1
    ));
    let s = store.status(&c1).unwrap();
    assert!(!s.leech && !s.suspended, "{s:?}");
    assert_eq!(store.cached_state(&c1).unwrap().unwrap().lapses, 2);
    assert!(!store.rebuild().unwrap().statuses_changed);

    // Cram answers change no status and bury nothing.
    let d = key("d", "plain");
    let cram = review(
        &d,
        when,
        Rating::Again,
        ReviewKind::Cram,
        State::New,
        Duration::zero(),
    );
    store
        .record_study(
            &cram,
            &AfterRating {
                bury: vec![d.clone(), c2.clone()],
                ..no_follow_up(when + Duration::days(5))
            },
        )
        .unwrap();
    assert!(!store.status(&c2).unwrap().buried(when + Duration::days(4)));
}

#[test]
fn a_version_1_database_keeps_its_log_and_gains_cloze_items() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("flipcard.db");
    let conn = Connection::open(&path).unwrap();
    conn.execute_batch(flipcard::store::schema::MIGRATIONS[0])
        .unwrap();
    conn.pragma_update(None, "user_version", 1).unwrap();
    conn.execute_batch(
        "INSERT INTO session (id, started_at) VALUES (1, 0);
         INSERT INTO review (id, session, deck, card, direction, reviewed_at, rating, kind,
            elapsed_days, scheduled_days, stability, difficulty, state, step, due, last_review,
            duration_ms) VALUES
            (1, 1, 'd', 'a', 'forward', 1000, 3, 'learn', 0, 0, 2.0, 5.0, 'learning', 0, 61000, 1000, 900);
         INSERT INTO card_state VALUES ('d', 'a', 'forward', 'learning', 0, 2.0, 5.0, 61000, 1000, 1, 0, 1);",
    )
    .unwrap();
    drop(conn);
    let mut store = Store::open(dir.path()).unwrap();
    assert_eq!(store.review_count().unwrap(), 1);
    assert_eq!(store.cached_states().unwrap().len(), 1);
    let c3 = cloze("d", "z", 3);
    let when = at("2026-03-01T10:00:00Z");
    store
        .record(&review(
            &c3,
            when,
            Rating::Good,
            ReviewKind::Learn,
            State::Learning,
            Duration::minutes(10),
        ))
        .unwrap();
    assert_eq!(
        store.cached_state(&c3).unwrap().unwrap().key.direction,
        Direction::Cloze(3)
    );
    assert_eq!(store.rebuild().unwrap().changed, 0);
    store
        .set_status(std::slice::from_ref(&c3), StatusAction::Suspend, when, None)
        .unwrap();
    drop(store);
    // The log is still append-only after the copy.
    let conn = Connection::open(&path).unwrap();
    let del = conn.execute("DELETE FROM review", []).unwrap_err();
    assert!(del.to_string().contains("append-only"), "{del}");
    let del = conn.execute("DELETE FROM status_event", []).unwrap_err();
    assert!(del.to_string().contains("append-only"), "{del}");
    let bad = conn
        .execute(
            "INSERT INTO review (session, deck, card, direction, reviewed_at, rating, kind,
             elapsed_days, scheduled_days, state, due, duration_ms)
             VALUES (1, 'd', 'a', 'c0', 0, 3, 'learn', 0, 0, 'learning', 0, 0)",
            [],
        )
        .unwrap_err();
    assert!(bad.to_string().contains("CHECK"), "{bad}");
}
