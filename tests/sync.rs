//! `flipcard sync` through the real binary: two data dirs (a laptop and a
//! lab machine) and one sync folder; interleaved offline sessions on both
//! (ratings, suspends, buries, unsuspends, undos before and after a sync),
//! syncs in every order, repeated syncs, a line cut short by a sync tool
//! mid-copy, and SIGKILL during a sync. The machines' live review logs,
//! card states, status logs and statuses are compared field by field.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

use chrono::{DateTime, TimeDelta, Utc};
use flipcard::interop::export::ExportedReview;
use flipcard::sched::{Config, ItemKey, Rating, Scheduler};
use flipcard::store::state::CachedState;
use flipcard::store::{AfterRating, ItemStatus, StatusAction, Store};

use crate::support::{Flipcard, Output};

pub(crate) const DECK: &str = "torque-free-rotation";
pub(crate) const NOW: &str = "2026-06-01T12:00:00Z";

pub(crate) fn t(s: &str) -> DateTime<Utc> {
    DateTime::parse_from_rfc3339(s).unwrap().with_timezone(&Utc)
}

pub(crate) fn sync_cmd(data: &Path, folder: &Path) -> Flipcard {
    Flipcard::new(data).now(NOW).arg("sync").arg(folder)
}

pub(crate) fn sync(data: &Path, folder: &Path) -> Output {
    sync_cmd(data, folder).run().ok()
}

/// A study session: each (card, rating, minutes after `start`) answered as
/// the app would, with the default config the binary also uses.
pub(crate) fn study(data: &Path, start: &str, answers: &[(&str, Rating, i64)]) {
    let scheduler = Scheduler::new(&Config::default());
    let mut store = Store::open(data).unwrap();
    store.start_session().unwrap();
    for (card, rating, minutes) in answers {
        let key = crate::store_support::key(DECK, card);
        let state = store.state(&key).unwrap();
        let at = t(start) + TimeDelta::minutes(*minutes);
        let record = scheduler.review(&key, state.as_ref(), *rating, at, 2500);
        store.record(&record).unwrap();
    }
}

/// The live log, every exported field, in time order per item.
pub(crate) fn live_log(data: &Path) -> Vec<ExportedReview> {
    let store = Store::open_read_only(data).unwrap();
    let mut rows = Vec::new();
    store
        .each_review(|l| -> Result<(), flipcard::store::StoreError> {
            if !l.undone {
                rows.push(ExportedReview::from(l));
            }
            Ok(())
        })
        .unwrap();
    rows.sort_by(|a, b| {
        (&a.deck, &a.card, &a.direction, &a.reviewed_at).cmp(&(
            &b.deck,
            &b.card,
            &b.direction,
            &b.reviewed_at,
        ))
    });
    rows
}

/// Card states, without the row id they come from (ids differ by machine).
pub(crate) fn states(data: &Path) -> Vec<(ItemKey, flipcard::sched::CardState, u32, u32)> {
    let store = Store::open_read_only(data).unwrap();
    let mut s: Vec<_> = store
        .cached_states()
        .unwrap()
        .into_iter()
        .map(|c: CachedState| (c.key, c.state, c.reps, c.lapses))
        .collect();
    s.sort_by(|a, b| a.0.cmp(&b.0));
    s
}

pub(crate) fn same(a: &Path, b: &Path) {
    let (la, lb) = (live_log(a), live_log(b));
    assert_eq!(la.len(), lb.len(), "live review counts");
    for (x, y) in la.iter().zip(&lb) {
        assert_eq!(x, y, "a review differs between the machines");
    }
    assert_eq!(states(a), states(b), "card states differ");
    let (sa, sb) = (status_log(a), status_log(b));
    assert_eq!(
        sa.len(),
        sb.len(),
        "live status event counts:\n{sa:#?}\n{sb:#?}"
    );
    for (x, y) in sa.iter().zip(&sb) {
        assert_eq!(x, y, "a status event differs between the machines");
    }
    assert_eq!(statuses(a), statuses(b), "statuses differ");
    assert_eq!(
        cards_json(a),
        cards_json(b),
        "`cards list --format json` differs"
    );
    // And each cache is what its own log gives.
    for d in [a, b] {
        let mut store = Store::open(d).unwrap();
        let before = (states(d), statuses(d));
        let report = store.rebuild().unwrap();
        drop(store);
        assert!(!report.statuses_changed, "{report:?}");
        assert_eq!(
            (states(d), statuses(d)),
            before,
            "rebuild disagrees with the cache of {}",
            d.display()
        );
    }
}

/// A live status event, every field that travels, its cause by identity.
pub(crate) type LiveStatus = (
    ItemKey,
    DateTime<Utc>,
    StatusAction,
    Option<DateTime<Utc>>,
    Option<(ItemKey, DateTime<Utc>, Rating)>,
);

/// The live status log of every item, in time order per item.
pub(crate) fn status_log(data: &Path) -> Vec<LiveStatus> {
    let store = Store::open_read_only(data).unwrap();
    let mut reviews = std::collections::HashMap::new();
    store
        .each_review(|l| -> Result<(), flipcard::store::StoreError> {
            reviews.insert(l.id, (l.record.key, l.record.reviewed_at, l.record.rating));
            Ok(())
        })
        .unwrap();
    let mut out = Vec::new();
    for key in store.statuses().unwrap().into_keys() {
        for e in store.status_history(&key).unwrap() {
            if !e.undone {
                let cause = e.cause.map(|id| reviews[&id].clone());
                out.push((e.key, e.at, e.action, e.until, cause));
            }
        }
    }
    out.sort_by(|a, b| (&a.0, a.1, a.2.as_str()).cmp(&(&b.0, b.1, b.2.as_str())));
    out
}

/// Every item's status that is not the default (active).
pub(crate) fn statuses(data: &Path) -> Vec<(ItemKey, ItemStatus)> {
    let store = Store::open_read_only(data).unwrap();
    let mut s: Vec<_> = store
        .statuses()
        .unwrap()
        .into_iter()
        .filter(|(_, s)| *s != ItemStatus::default())
        .collect();
    s.sort_by(|a, b| a.0.cmp(&b.0));
    s
}

pub(crate) fn cards_json(data: &Path) -> serde_json::Value {
    let out = Flipcard::new(data)
        .now(NOW)
        .args(["cards", "list", &format!("deck:{DECK}"), "--format", "json"])
        .run()
        .ok();
    serde_json::from_slice(&out.stdout).unwrap()
}

/// One thing a learner does in a session.
pub(crate) enum Act<'a> {
    /// Rate the forward item of a card at a time; the backward item (its
    /// sibling) is buried until the next day, as the app does.
    Rate(&'a str, Rating, &'a str),
    Suspend(&'a str, &'a str),
    Unsuspend(&'a str, &'a str),
    /// Bury until the second time.
    Bury(&'a str, &'a str, &'a str),
    /// `u` in the app: the last rating or change of status goes.
    Undo,
    /// `flipcard sync` from another terminal, the session still open.
    Sync,
}

/// One session of the app on `data`, the default config's leech rule.
pub(crate) fn session(data: &Path, folder: &Path, acts: &[Act]) {
    let config = Config::default();
    let scheduler = Scheduler::new(&config);
    let mut store = Store::open(data).unwrap();
    store.start_session().unwrap();
    let key = |card: &str| crate::store_support::key(DECK, card);
    for a in acts {
        match a {
            Act::Rate(card, rating, at) => {
                let k = key(card);
                let state = store.state(&k).unwrap();
                let record = scheduler.review(&k, state.as_ref(), *rating, t(at), 2500);
                let after = AfterRating {
                    leech_threshold: config.leech_threshold,
                    leech_suspend: true,
                    bury: vec![crate::store_support::back_key(DECK, card)],
                    bury_until: t(at) + TimeDelta::days(1),
                };
                store.record_study(&record, &after).unwrap();
            }
            Act::Suspend(card, at) | Act::Unsuspend(card, at) => {
                let action = if matches!(a, Act::Suspend(..)) {
                    StatusAction::Suspend
                } else {
                    StatusAction::Unsuspend
                };
                store.set_status(&[key(card)], action, t(at), None).unwrap();
            }
            Act::Bury(card, at, until) => {
                store
                    .set_status(&[key(card)], StatusAction::Bury, t(at), Some(t(until)))
                    .unwrap();
            }
            Act::Undo => {
                assert!(
                    store.undo_last_change().unwrap().is_some(),
                    "nothing to undo"
                );
            }
            Act::Sync => {
                sync(data, folder);
            }
        }
    }
}

pub(crate) struct Pair {
    pub(crate) _dir: tempfile::TempDir,
    pub(crate) laptop: PathBuf,
    pub(crate) lab: PathBuf,
    pub(crate) folder: PathBuf,
}

pub(crate) fn pair() -> Pair {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("Sync");
    std::fs::create_dir(&folder).unwrap();
    Pair {
        laptop: dir.path().join("laptop"),
        lab: dir.path().join("lab"),
        folder,
        _dir: dir,
    }
}

/// Offline sessions on both machines, with syncs between some of them;
/// both rate `torque-free-meaning` while apart.
fn interleaved(p: &Pair) -> usize {
    use Rating::*;
    study(
        &p.laptop,
        "2026-05-01T08:00:00Z",
        &[
            ("torque-free-meaning", Good, 0),
            ("body-frame-why", Again, 1),
            ("body-frame-why", Good, 3),
        ],
    );
    study(
        &p.lab,
        "2026-05-01T09:00:00Z",
        &[
            ("torque-free-meaning", Hard, 0),
            ("l-not-parallel", Good, 2),
        ],
    );
    sync(&p.laptop, &p.folder);
    study(
        &p.laptop,
        "2026-05-03T07:00:00Z",
        &[
            ("torque-free-meaning", Good, 0),
            ("l-not-parallel", Easy, 1),
        ],
    );
    sync(&p.lab, &p.folder);
    study(
        &p.lab,
        "2026-05-02T18:00:00Z",
        &[
            ("torque-free-meaning", Again, 0),
            ("torque-free-meaning", Good, 12),
            ("body-frame-why", Good, 14),
        ],
    );
    study(
        &p.laptop,
        "2026-05-04T07:00:00Z",
        &[("body-frame-why", Good, 0)],
    );
    // Changes of status and undos on both. The lab answers body-frame-why
    // later than the laptop's answer that the laptop then undoes, so the
    // lab's answer is replayed on both; the lab unsuspends
    // l-not-parallel before (in time) the laptop suspends it.
    session(
        &p.lab,
        &p.folder,
        &[
            Act::Rate("body-frame-why", Good, "2026-05-05T09:00:00Z"),
            Act::Unsuspend("l-not-parallel", "2026-05-03T10:00:00Z"),
            Act::Suspend("torque-free-meaning", "2026-05-05T09:05:00Z"),
            Act::Sync,
            Act::Undo,
            Act::Rate("torque-free-meaning", Good, "2026-05-05T09:10:00Z"),
            Act::Sync,
            Act::Undo,
            Act::Suspend("body-frame-why", "2026-05-05T09:20:00Z"),
        ],
    );
    session(
        &p.laptop,
        &p.folder,
        &[
            Act::Suspend("l-not-parallel", "2026-05-04T08:00:00Z"),
            Act::Rate("body-frame-why", Again, "2026-05-04T08:05:00Z"),
            Act::Sync,
            Act::Undo,
            Act::Bury(
                "torque-free-meaning",
                "2026-05-04T08:10:00Z",
                "2026-06-02T04:00:00Z",
            ),
            Act::Suspend("body-frame-why", "2026-05-04T08:15:00Z"),
            Act::Undo,
            Act::Unsuspend("body-frame-why", "2026-05-05T10:00:00Z"),
        ],
    );
    3 + 2 + 2 + 3 + 1 + 1
}

#[test]
fn interleaved_sessions_converge_whatever_the_order_of_syncs() {
    for order in ["ABA", "BAB", "ABAB", "BABA", "AABBA", "BBAAB"] {
        let p = pair();
        let answers = interleaved(&p);
        for m in order.chars() {
            sync(if m == 'A' { &p.laptop } else { &p.lab }, &p.folder);
        }
        same(&p.laptop, &p.lab);
        assert_eq!(
            live_log(&p.laptop).len(),
            answers,
            "{order}: every answer kept, the undone ones gone"
        );
        // What each machine did, whoever synced first: the later of the
        // lab's unsuspend and the laptop's suspend wins, by the hybrid
        // clock: the lab unsuspends after its own answer of 05-05 09:00
        // (its wall clock says 05-03, but an event is timed after every one
        // its machine has seen), so it comes after the laptop's suspend of
        // 05-04. The lab's undone suspend and the laptop's undone one are
        // gone, and so are the sibling buries of the two undone answers.
        let key = |card: &str| crate::store_support::key(DECK, card);
        let back = |card: &str| crate::store_support::back_key(DECK, card);
        let log = status_log(&p.lab);
        let live: Vec<(ItemKey, &str)> = log.iter().map(|e| (e.0.clone(), e.2.as_str())).collect();
        assert_eq!(
            live,
            [
                (key("body-frame-why"), "suspend"),
                (key("body-frame-why"), "unsuspend"),
                (back("body-frame-why"), "bury"),
                (key("l-not-parallel"), "suspend"),
                (key("l-not-parallel"), "unsuspend"),
                (key("torque-free-meaning"), "bury"),
            ],
            "{order}"
        );
        assert_eq!(
            log[2].4,
            Some((
                key("body-frame-why"),
                t("2026-05-05T09:00:00Z"),
                Rating::Good
            )),
            "{order}: a sibling bury keeps its cause"
        );
        assert_eq!(
            statuses(&p.laptop),
            [
                (
                    back("body-frame-why"),
                    ItemStatus {
                        buried_until: Some(t("2026-05-06T09:00:00Z")),
                        ..ItemStatus::default()
                    }
                ),
                (
                    key("torque-free-meaning"),
                    ItemStatus {
                        buried_until: Some(t("2026-06-02T04:00:00Z")),
                        ..ItemStatus::default()
                    }
                ),
            ],
            "{order}"
        );

        // Again, in both orders: nothing changes, files included.
        let files = |p: &Pair| {
            let mut f: Vec<(PathBuf, Vec<u8>)> = std::fs::read_dir(&p.folder)
                .unwrap()
                .flatten()
                .map(|e| (e.path(), std::fs::read(e.path()).unwrap()))
                .collect();
            f.sort();
            f
        };
        let rows = |d: &Path| (review_rows(d), status_rows(d));
        let before = (files(&p), rows(&p.laptop), rows(&p.lab));
        for d in [&p.lab, &p.laptop, &p.lab] {
            let out = sync(d, &p.folder);
            let said = String::from_utf8_lossy(&out.stdout).into_owned();
            assert!(
                (said.contains("0 reviews written") && said.contains("0 reviews merged"))
                    || said.contains("nothing new since the last sync"),
                "{said}"
            );
            assert!(!said.contains("leech"), "{said}");
        }
        assert_eq!(
            (files(&p), rows(&p.laptop), rows(&p.lab)),
            before,
            "{order}: idempotent"
        );
        assert_eq!(files(&p).len(), 2, "one file per machine");
    }
}

/// Rows of the review log, undone ones included.
pub(crate) fn review_rows(d: &Path) -> usize {
    let mut n = 0;
    Store::open_read_only(d)
        .unwrap()
        .each_review(|_| -> Result<(), flipcard::store::StoreError> {
            n += 1;
            Ok(())
        })
        .unwrap();
    n
}

/// Rows of the status log, undone ones included.
pub(crate) fn status_rows(d: &Path) -> usize {
    let store = Store::open_read_only(d).unwrap();
    store
        .statuses()
        .unwrap()
        .keys()
        .map(|k| store.status_history(k).unwrap().len())
        .sum()
}

/// The learner's own suspends (not a leech's): (rows, live rows).
fn own_suspends(d: &Path) -> (usize, usize) {
    let store = Store::open_read_only(d).unwrap();
    let mut n = (0, 0);
    for k in store.statuses().unwrap().keys() {
        for e in store.status_history(k).unwrap() {
            if e.action == StatusAction::Suspend && e.cause.is_none() {
                n.0 += 1;
                n.1 += usize::from(!e.undone);
            }
        }
    }
    n
}

#[test]
fn the_machine_id_is_made_once() {
    let p = pair();
    study(
        &p.laptop,
        "2026-05-01T08:00:00Z",
        &[("torque-free-meaning", Rating::Good, 0)],
    );
    sync(&p.laptop, &p.folder);
    let id = std::fs::read_to_string(p.laptop.join("machine-id")).unwrap();
    assert_eq!(id.trim().len(), 32);
    study(
        &p.laptop,
        "2026-05-02T08:00:00Z",
        &[("torque-free-meaning", Rating::Good, 0)],
    );
    sync(&p.laptop, &p.folder);
    assert_eq!(
        std::fs::read_to_string(p.laptop.join("machine-id")).unwrap(),
        id
    );
    let file = p.folder.join(format!("{}.jsonl", id.trim()));
    assert_eq!(std::fs::read_to_string(file).unwrap().lines().count(), 2);
}

#[test]
fn a_line_cut_short_is_skipped_with_a_warning_and_read_next_time() {
    let p = pair();
    study(
        &p.laptop,
        "2026-05-01T08:00:00Z",
        &[
            ("torque-free-meaning", Rating::Good, 0),
            ("body-frame-why", Rating::Again, 1),
            ("body-frame-why", Rating::Good, 5),
        ],
    );
    sync(&p.laptop, &p.folder);
    let id = std::fs::read_to_string(p.laptop.join("machine-id")).unwrap();
    let file = p.folder.join(format!("{}.jsonl", id.trim()));
    let whole = std::fs::read_to_string(&file).unwrap();
    // The sync tool has copied all but the end of the last line, and
    // garbled the first.
    let cut = whole.len() - 30;
    let garbled = format!(
        "{{\"event\":\"rev{}",
        &whole[whole.find('\n').unwrap()..cut]
    );
    std::fs::write(&file, &garbled).unwrap();
    let out = sync(&p.lab, &p.folder);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    let name = file.display().to_string();
    assert!(
        err.contains(&format!("{name}:3: skipped: the last line is incomplete")),
        "{err}"
    );
    assert!(err.contains("read again at the next sync"), "{err}");
    assert!(err.contains(&format!("{name}:1: skipped: ")), "{err}");
    assert_eq!(err.lines().count(), 2, "one warning of each kind: {err}");
    // Said once: the next sync, with the file unchanged, says nothing.
    let again = sync(&p.lab, &p.folder);
    assert!(
        again.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    assert!(
        String::from_utf8_lossy(&out.stdout).contains("1 review merged"),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert_eq!(live_log(&p.lab).len(), 1);

    std::fs::write(&file, &whole).unwrap();
    let out = sync(&p.lab, &p.folder);
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    sync(&p.laptop, &p.folder);
    same(&p.laptop, &p.lab);
    assert_eq!(live_log(&p.lab).len(), 3);
}

#[test]
fn sigkill_at_any_point_of_a_sync_loses_nothing_and_half_merges_nothing() {
    let p = pair();
    // Enough for a sync to take a while: 40 cards, 30 answers each.
    let answers: Vec<(String, Rating, i64)> = (0..1200)
        .map(|i| {
            (
                format!("card-{}", i % 40),
                [Rating::Good, Rating::Again, Rating::Easy][i % 3],
                i as i64 * 60,
            )
        })
        .collect();
    let refs: Vec<(&str, Rating, i64)> = answers
        .iter()
        .map(|(c, r, m)| (c.as_str(), *r, *m))
        .collect();
    study(&p.laptop, "2026-01-01T08:00:00Z", &refs);
    study(&p.lab, "2026-01-01T08:07:00Z", &refs[..300]);
    // And changes of status: ten suspends, one of them undone.
    let times: Vec<String> = (0..10)
        .map(|i| (t("2026-03-01T08:00:00Z") + TimeDelta::minutes(i)).to_rfc3339())
        .collect();
    let cards: Vec<String> = (0..10).map(|i| format!("card-{i}")).collect();
    let mut acts: Vec<Act> = cards
        .iter()
        .zip(&times)
        .map(|(c, at)| Act::Suspend(c, at))
        .collect();
    acts.push(Act::Undo);
    session(&p.laptop, &p.folder, &acts);
    sync(&p.laptop, &p.folder);
    let lab_own = live_log(&p.lab).len();

    let mut delay_us = 0u64;
    let mut kills = 0;
    while delay_us < 2_000_000 {
        let mut child = sync_cmd(&p.lab, &p.folder)
            .command()
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_micros(delay_us));
        let finished = child.try_wait().unwrap().is_some();
        let _ = child.kill();
        let _ = child.wait();
        if !finished {
            kills += 1;
        }
        // All of the laptop's answers or none of them, and the lab's own
        // answers all there.
        let live = live_log(&p.lab).len();
        assert!(
            live == lab_own || live == lab_own + 1200,
            "after a kill at {delay_us} µs: {live} live reviews"
        );
        // The laptop's suspends come with them, or do not.
        let events = own_suspends(&p.lab);
        assert!(
            (live == lab_own && events == (0, 0)) || (live > lab_own && events == (10, 9)),
            "after a kill at {delay_us} µs: {live} live reviews, {events:?} suspends"
        );
        // The lab's sync file is whole or absent: never a half line.
        for e in std::fs::read_dir(&p.folder).unwrap().flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if !name.starts_with('.') {
                let text = std::fs::read_to_string(e.path()).unwrap();
                assert!(text.ends_with('\n'), "{name} ends in a half line");
            }
        }
        if finished {
            break;
        }
        delay_us = delay_us * 2 + 500;
    }
    assert!(kills > 0, "no sync was interrupted");
    sync(&p.lab, &p.folder);
    sync(&p.laptop, &p.folder);
    same(&p.laptop, &p.lab);
    assert_eq!(live_log(&p.lab).len(), 1200 + 300);
    assert_eq!(own_suspends(&p.lab), (10, 9));
}

#[test]
fn sync_needs_a_folder() {
    let p = pair();
    let out = sync_cmd(&p.laptop, &p.folder.join("missing")).run();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("missing: no such folder"));
    std::fs::write(p.folder.join("a-file"), "").unwrap();
    let out = sync_cmd(&p.laptop, &p.folder.join("a-file")).run();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("a-file: not a folder"));
    let out = Flipcard::new(&p.laptop).arg("sync").run();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("sync_dir"));
}

pub(crate) fn mkfifo(path: &Path) {
    let status = Command::new("mkfifo").arg(path).status().unwrap();
    assert!(status.success(), "mkfifo {}", path.display());
}

/// A FIFO, a folder or a dangling link where a sync file or the machine id
/// should be: named and skipped or refused, never waited on (opening a FIFO
/// blocks until something writes to it).
#[test]
fn a_fifo_or_a_folder_in_the_sync_folder_is_skipped_not_waited_on() {
    let p = pair();
    study(
        &p.laptop,
        "2026-05-01T09:00:00Z",
        &[("euler-component-1", Rating::Good, 0)],
    );
    sync(&p.laptop, &p.folder);
    mkfifo(&p.folder.join("fifo.jsonl"));
    std::fs::create_dir(p.folder.join("folder.jsonl")).unwrap();
    std::os::unix::fs::symlink("/nonexistent", p.folder.join("gone.jsonl")).unwrap();
    let mut child = sync_cmd(&p.lab, &p.folder)
        .command()
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(30) {
            let _ = child.kill();
            panic!("sync waits on the FIFO");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("fifo.jsonl: is a FIFO, not a regular file"),
        "{stderr}"
    );
    assert!(stderr.contains("folder.jsonl: is a directory"), "{stderr}");
    assert!(stderr.contains("gone.jsonl:"), "{stderr}");
    assert!(
        stdout.contains("1 review merged") && stdout.contains("3 files skipped"),
        "{stdout}"
    );
    assert_eq!(live_log(&p.lab).len(), 1);

    // The machine id: a FIFO there is one line and exit 1, at once.
    let other = p.folder.parent().unwrap().join("third");
    std::fs::create_dir(&other).unwrap();
    mkfifo(&other.join("machine-id"));
    let out = sync_cmd(&other, &p.folder).run();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("machine-id: is a FIFO, not a regular file"),
        "{stderr}"
    );
}

/// `n` lapses of one card (a Good that graduates it, then Again and Good
/// `gap_days` apart), starting `start`; times as RFC 3339 strings.
fn lapse_times(start: &str, n: i64, gap_days: i64) -> Vec<(Rating, String)> {
    let t0 = t(start);
    let mut out = vec![(Rating::Easy, t0.to_rfc3339())];
    for k in 1..=n {
        let again = t0 + TimeDelta::days(k * gap_days);
        out.push((Rating::Again, again.to_rfc3339()));
        out.push((Rating::Good, (again + TimeDelta::hours(1)).to_rfc3339()));
    }
    out
}

fn rate_all<'a>(card: &'a str, times: &'a [(Rating, String)]) -> Vec<Act<'a>> {
    times
        .iter()
        .map(|(r, at)| Act::Rate(card, *r, at.as_str()))
        .collect()
}

/// The live leech and leech-suspend events of one item: (action, time).
fn leech_events(data: &Path, key: &ItemKey) -> Vec<(StatusAction, DateTime<Utc>)> {
    Store::open_read_only(data)
        .unwrap()
        .status_history(key)
        .unwrap()
        .into_iter()
        .filter(|e| !e.undone && e.action != StatusAction::Bury)
        .map(|e| (e.action, e.at))
        .collect()
}

#[test]
fn lapses_made_apart_give_one_leech_on_both_machines() {
    // The default leech rule: 8 lapses, then suspended.
    let card = "torque-free-meaning";
    let key = crate::store_support::key(DECK, card);
    let lapses = |d: &Path| {
        Store::open_read_only(d)
            .unwrap()
            .cached_state(&key)
            .unwrap()
            .unwrap()
            .lapses
    };

    // Four lapses on each, interleaved in time: neither is a leech alone.
    let p = pair();
    let laptop = lapse_times("2026-01-01T08:00:00Z", 4, 10);
    let lab = lapse_times("2026-01-06T08:00:00Z", 4, 10);
    session(&p.laptop, &p.folder, &rate_all(card, &laptop));
    session(&p.lab, &p.folder, &rate_all(card, &lab));
    assert_eq!((lapses(&p.laptop), lapses(&p.lab)), (4, 4));
    assert!(leech_events(&p.laptop, &key).is_empty());
    for d in [&p.laptop, &p.lab, &p.laptop, &p.lab] {
        sync(d, &p.folder);
    }
    same(&p.laptop, &p.lab);
    // The eighth lapse is the lab's fourth Again.
    let eighth = t(&lab[7].1);
    for d in [&p.laptop, &p.lab] {
        assert_eq!(lapses(d), 8);
        assert_eq!(
            leech_events(d, &key),
            [
                (StatusAction::Leech, eighth),
                (StatusAction::Suspend, eighth)
            ],
            "{}",
            d.display()
        );
        let s = Store::open_read_only(d).unwrap().status(&key).unwrap();
        assert!(s.leech && s.suspended, "{s:?}");
    }
    // Syncing again changes nothing.
    let out = sync(&p.lab, &p.folder);
    assert!(
        !String::from_utf8_lossy(&out.stdout).contains("leech"),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );

    // A leech on one machine alone moves to where the merged lapses reach
    // eight, on both, and is not doubled: the laptop's eight lapses and
    // two earlier ones of the lab.
    let p = pair();
    let laptop = lapse_times("2026-01-01T08:00:00Z", 8, 10);
    let lab = lapse_times("2026-01-03T08:00:00Z", 2, 10);
    session(&p.laptop, &p.folder, &rate_all(card, &laptop));
    session(&p.lab, &p.folder, &rate_all(card, &lab));
    assert_eq!(
        leech_events(&p.laptop, &key),
        [
            (StatusAction::Leech, t(&laptop[15].1)),
            (StatusAction::Suspend, t(&laptop[15].1))
        ]
    );
    for d in [&p.lab, &p.laptop, &p.lab] {
        sync(d, &p.folder);
    }
    same(&p.laptop, &p.lab);
    // Merged: laptop Again 1 (day 10), lab 1 (day 12), laptop 2 (20), lab 2
    // (22), then the laptop's 3rd to 6th: the eighth is the laptop's 6th.
    let eighth = t(&laptop[11].1);
    for d in [&p.laptop, &p.lab] {
        assert_eq!(lapses(d), 10);
        assert_eq!(
            leech_events(d, &key),
            [
                (StatusAction::Leech, eighth),
                (StatusAction::Suspend, eighth)
            ],
            "{}",
            d.display()
        );
    }
}

#[test]
fn a_file_of_the_first_format_still_merges() {
    // Review lines only, as the first version of sync wrote them, one of
    // them undone.
    let p = pair();
    let other = p.folder.join("0123456789abcdef0123456789abcdef.jsonl");
    std::fs::copy("tests/fixtures/sync/reviews-only.jsonl", &other).unwrap();
    let out = sync(&p.laptop, &p.folder);
    let said = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        said.contains("4 reviews merged from 1 other machine"),
        "{said}"
    );
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let live = live_log(&p.laptop);
    let cards: Vec<(&str, u8)> = live.iter().map(|r| (r.card.as_str(), r.rating)).collect();
    assert_eq!(
        cards,
        [
            ("body-frame-why", 3),
            ("torque-free-meaning", 3),
            ("torque-free-meaning", 4)
        ]
    );
    let history = Store::open_read_only(&p.laptop)
        .unwrap()
        .history(&crate::store_support::key(DECK, "body-frame-why"))
        .unwrap();
    assert_eq!(history.len(), 2);
    assert!(history[0].undone && history[0].record.rating == Rating::Again);
    // The states are the replay of the live answers.
    let scheduler = Scheduler::new(&Config::default());
    let k = crate::store_support::key(DECK, "torque-free-meaning");
    let first = scheduler.review(&k, None, Rating::Good, t("2026-04-20T08:00:00Z"), 2500);
    let second = scheduler.review(
        &k,
        Some(&first.after),
        Rating::Easy,
        t("2026-04-22T07:30:00.123Z"),
        1800,
    );
    let store = Store::open_read_only(&p.laptop).unwrap();
    assert_eq!(store.state(&k).unwrap(), Some(second.after));
    drop(store);
    // Nothing of it is written back (another machine's answers are never
    // published as this one's); a second sync has nothing new to do.
    let out = sync(&p.laptop, &p.folder);
    let said = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(said.contains("nothing new since the last sync"), "{said}");
    assert_eq!(
        std::fs::read_dir(&p.folder).unwrap().count(),
        1,
        "no file of its own: nothing to write"
    );
}

#[test]
fn sync_dir_in_the_config_may_start_with_a_tilde() {
    let p = pair();
    study(
        &p.laptop,
        "2026-05-01T08:00:00Z",
        &[("torque-free-meaning", Rating::Good, 0)],
    );
    // $HOME is the folder that holds `Sync`.
    let home = p.folder.parent().unwrap();
    let config = p.laptop.join("config.toml");
    let run = |text: &str| {
        std::fs::write(&config, text).unwrap();
        Flipcard::new(&p.laptop)
            .config(&config)
            .now(NOW)
            .env("HOME", home)
            .arg("sync")
            .run()
    };
    let out = run("sync_dir = \"~/Sync\"\n");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let said = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        said.starts_with(&format!(
            "synced through {}: 1 review written",
            p.folder.display()
        )),
        "{said}"
    );
    assert_eq!(std::fs::read_dir(&p.folder).unwrap().count(), 1);

    // Another user's home is not guessed at.
    let out = run("leech_threshold = 8\nsync_dir = \"~lab/Sync\"\n");
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains(&format!("{}:2:12: `sync_dir`", config.display()))
            && err.contains("`~user` is not expanded"),
        "{err}"
    );
}
