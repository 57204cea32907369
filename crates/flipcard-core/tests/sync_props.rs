//! Property: whatever three (and more) machines do between syncs —
//! answers (leeches and sibling buries with them, each review day placed
//! by the load balancer over that machine's own due counts) on clocks that move,
//! stand still or run ahead, suspends, unsuspends, buries, undos, a
//! database restored from an older copy, a data folder copied to a new
//! machine, forged files that try to undo others' answers — after every
//! machine has synced a few times:
//!
//! - every machine holds the same live answers, card states (due dates
//!   included) and statuses;
//! - the live answers are exactly those the machines published in their
//!   own files and did not undo there (nothing published is lost, a forged
//!   undo changes nothing);
//! - `db rebuild` changes nothing on any machine.
//!
//! In-process, through `flipcard_core::sync::sync_with` and the store calls the
//! app makes (`answer_time`, `record_study`, `set_status`,
//! `undo_last_change`). Runs `PROPTEST_CASES` sequences (default 24); for a
//! longer search: `PROPTEST_CASES=500 cargo test --test main sync_props::`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use chrono::{DateTime, TimeDelta, Utc};
use flipcard_core::sched::balance::{EasyDays, LOAD_DAYS, Load};
use flipcard_core::sched::config::LeechAction;
use flipcard_core::sched::{CardState, Config, Direction, ItemKey, Rating, Scheduler};
use flipcard_core::store::{AfterRating, ItemStatus, StatusAction, Store, StoreError};
use flipcard_core::sync::{Wait, sync_with};
use proptest::prelude::*;

const DECK: &str = "props";
const CARDS: u8 = 5;
const FORGER: &str = "ffffffffffffffffffffffffffffffff";

#[derive(Debug, Clone)]
enum Op {
    /// Machine `m` answers a card (cards 0 and 1 are reversed: the other
    /// direction is buried).
    Answer {
        m: u8,
        card: u8,
        back: bool,
        rating: u8,
    },
    Status {
        m: u8,
        card: u8,
        action: u8,
    },
    Undo {
        m: u8,
    },
    Sync {
        m: u8,
    },
    /// The clock moves on by this many milliseconds (0: stands still).
    Tick {
        ms: u32,
    },
    /// Machine `m`'s clock runs ahead of (or behind) the others by minutes.
    Skew {
        m: u8,
        minutes: i16,
    },
    Backup {
        m: u8,
    },
    /// Machine `m`'s database is put back to its last copy.
    Restore {
        m: u8,
    },
    /// Machine `m`'s whole data folder is copied to a new machine.
    Copy {
        m: u8,
    },
    /// A forged file undoes some answers it finds in the folder.
    Forge {
        every: u8,
    },
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        6 => (0u8..4, 0..CARDS, any::<bool>(), 1u8..=4)
            .prop_map(|(m, card, back, rating)| Op::Answer { m, card, back, rating }),
        2 => (0u8..4, 0..CARDS, 0u8..3).prop_map(|(m, card, action)| Op::Status { m, card, action }),
        2 => (0u8..4).prop_map(|m| Op::Undo { m }),
        4 => (0u8..4).prop_map(|m| Op::Sync { m }),
        3 => prop_oneof![Just(0u32), 1u32..3, 60_000u32..90_000_000].prop_map(|ms| Op::Tick { ms }),
        1 => (0u8..4, -120i16..120).prop_map(|(m, minutes)| Op::Skew { m, minutes }),
        1 => (0u8..4).prop_map(|m| Op::Backup { m }),
        1 => (0u8..4).prop_map(|m| Op::Restore { m }),
        1 => (0u8..4).prop_map(|m| Op::Copy { m }),
        1 => (1u8..4).prop_map(|every| Op::Forge { every }),
    ]
}

struct Machine {
    data: PathBuf,
    store: Option<Store>,
    skew: TimeDelta,
    backup: Option<PathBuf>,
}

impl Machine {
    fn store(&mut self) -> &mut Store {
        if self.store.is_none() {
            self.store = Some(Store::open(&self.data).unwrap());
        }
        self.store.as_mut().unwrap()
    }
}

fn config() -> Config {
    Config {
        leech_threshold: 3,
        leech_action: LeechAction::Suspend,
        ..Config::default()
    }
}

fn key(card: u8, back: bool) -> ItemKey {
    ItemKey {
        deck: DECK.into(),
        card: format!("card-{card}"),
        direction: if back && card < 2 {
            Direction::Backward
        } else {
            Direction::Forward
        },
    }
}

struct World {
    _dir: tempfile::TempDir,
    root: PathBuf,
    folder: PathBuf,
    machines: Vec<Machine>,
    clock: DateTime<Utc>,
}

impl World {
    fn new() -> World {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().to_path_buf();
        let folder = root.join("Sync");
        std::fs::create_dir(&folder).unwrap();
        let machines = (0..3)
            .map(|i| Machine {
                data: root.join(format!("m{i}")),
                store: None,
                skew: TimeDelta::zero(),
                backup: None,
            })
            .collect();
        World {
            _dir: dir,
            root,
            folder,
            machines,
            clock: DateTime::parse_from_rfc3339("2026-03-01T08:00:00.000Z")
                .unwrap()
                .with_timezone(&Utc),
        }
    }

    /// Machine `m` (of those there are).
    fn at(&mut self, m: u8) -> usize {
        usize::from(m) % self.machines.len()
    }

    fn now(&self, i: usize) -> DateTime<Utc> {
        self.clock + self.machines[i].skew
    }

    fn sync(&mut self, i: usize) {
        let now = self.now(i);
        let m = &mut self.machines[i];
        // The app syncs on its own connection; the store's session (for
        // undo) stays open as it would. It waits a little for the lock: a
        // child process another test forks inherits the lock's file until
        // it execs, and this test is about what converges, not the lock.
        let wait = Wait::Up(std::time::Duration::from_secs(5));
        if let Err(e) = sync_with(&m.data, &self.folder, &config(), now, wait) {
            panic!("sync of machine {i}: {e}");
        }
    }

    fn apply(&mut self, op: &Op) {
        let scheduler = Scheduler::new(&config());
        match *op {
            Op::Answer {
                m,
                card,
                back,
                rating,
            } => {
                let i = self.at(m);
                let now = self.now(i);
                let k = key(card, back);
                let store = self.machines[i].store();
                let at = store.answer_time(&k, now).unwrap();
                let before = store.state(&k).unwrap();
                let rating = Rating::from_number(i64::from(rating)).unwrap();
                // Balanced over this machine's due counts, which the others
                // cannot know: they replay the day the answer keeps.
                let day = at.date_naive();
                let start = day.and_hms_opt(0, 0, 0).unwrap().and_utc();
                let counts = store.due_per_day(start, LOAD_DAYS).unwrap();
                let load = Load::new(counts, day, &EasyDays::default());
                let record =
                    scheduler.review_with(&k, before.as_ref(), rating, at, 1500, Some(&load));
                let sibling = (card < 2).then(|| key(card, !back));
                let after = AfterRating {
                    leech_threshold: 3,
                    leech_suspend: true,
                    bury: sibling.into_iter().collect(),
                    bury_until: at + TimeDelta::hours(20),
                };
                store.record_study(&record, &after).unwrap();
            }
            Op::Status { m, card, action } => {
                let i = self.at(m);
                let now = self.now(i);
                let k = key(card, false);
                let (action, until) = match action {
                    0 => (StatusAction::Suspend, None),
                    1 => (StatusAction::Unsuspend, None),
                    _ => (StatusAction::Bury, Some(now + TimeDelta::hours(20))),
                };
                self.machines[i]
                    .store()
                    .set_status(&[k], action, now, until)
                    .unwrap();
            }
            Op::Undo { m } => {
                let i = self.at(m);
                self.machines[i].store().undo_last_change().unwrap();
            }
            Op::Sync { m } => {
                let i = self.at(m);
                self.sync(i);
            }
            Op::Tick { ms } => self.clock += TimeDelta::milliseconds(i64::from(ms)),
            Op::Skew { m, minutes } => {
                let i = self.at(m);
                self.machines[i].skew = TimeDelta::minutes(i64::from(minutes));
            }
            Op::Backup { m } => {
                let i = self.at(m);
                let to = self
                    .root
                    .join(format!("backup-{i}-{}.db", self.clock.timestamp_millis()));
                let _ = std::fs::remove_file(&to);
                self.machines[i].store();
                let mm = &mut self.machines[i];
                let db = mm.data.join("flipcard.db");
                let conn = rusqlite::Connection::open(&db).unwrap();
                conn.execute("VACUUM INTO ?1", [to.to_str().unwrap()])
                    .unwrap();
                mm.backup = Some(to);
            }
            Op::Restore { m } => {
                let i = self.at(m);
                let mm = &mut self.machines[i];
                let Some(backup) = mm.backup.clone() else {
                    return;
                };
                mm.store = None;
                for ext in ["-wal", "-shm"] {
                    let _ = std::fs::remove_file(mm.data.join(format!("flipcard.db{ext}")));
                }
                std::fs::copy(&backup, mm.data.join("flipcard.db")).unwrap();
            }
            Op::Copy { m } => {
                if self.machines.len() >= 5 {
                    return;
                }
                let i = self.at(m);
                if !self.machines[i].data.exists() {
                    return;
                }
                self.machines[i].store = None;
                let to = self.root.join(format!("m{}", self.machines.len()));
                let ok = std::process::Command::new("cp")
                    .arg("-a")
                    .arg(&self.machines[i].data)
                    .arg(&to)
                    .status()
                    .unwrap()
                    .success();
                assert!(ok);
                let skew = self.machines[i].skew;
                self.machines.push(Machine {
                    data: to,
                    store: None,
                    skew,
                    backup: None,
                });
            }
            Op::Forge { every } => {
                let mut forged = String::new();
                for (name, text) in files(&self.folder) {
                    if name.starts_with(FORGER) {
                        continue;
                    }
                    for (n, line) in text.lines().enumerate() {
                        if n % usize::from(every) != 0 || !line.contains("\"review\"") {
                            continue;
                        }
                        let v: serde_json::Value = serde_json::from_str(line).unwrap();
                        forged.push_str(&format!(
                            "{{\"event\":\"undo_review\",\"deck\":{},\"card\":{},\"direction\":{},\"reviewed_at\":{},\"rating\":{}}}\n",
                            v["deck"], v["card"], v["direction"], v["reviewed_at"], v["rating"]
                        ));
                        forged.push_str(&line.replace("\"undone\":false", "\"undone\":true"));
                        forged.push('\n');
                    }
                }
                let path = self.folder.join(format!("{FORGER}.jsonl"));
                let mut old = std::fs::read_to_string(&path).unwrap_or_default();
                old.push_str(&forged);
                std::fs::write(path, old).unwrap();
            }
        }
    }
}

fn files(folder: &Path) -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = std::fs::read_dir(folder)
        .unwrap()
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            (name.ends_with(".jsonl") && !name.starts_with('.'))
                .then(|| (name, std::fs::read_to_string(e.path()).unwrap()))
        })
        .collect();
    out.sort();
    out
}

type Identity = (String, String, String, i64, u8);

fn identity(v: &serde_json::Value, at_field: &str) -> Identity {
    let at = DateTime::parse_from_rfc3339(v[at_field].as_str().unwrap())
        .unwrap()
        .timestamp_millis();
    (
        v["deck"].as_str().unwrap().into(),
        v["card"].as_str().unwrap().into(),
        v["direction"].as_str().unwrap().into(),
        at,
        v["rating"].as_u64().unwrap() as u8,
    )
}

/// The answers the machines' own files hold and do not undo (forged files
/// left out): what every machine must hold live.
fn published(folder: &Path) -> BTreeSet<Identity> {
    // Holders of each answer, and who shows it undone.
    let mut holders: BTreeMap<Identity, BTreeSet<String>> = BTreeMap::new();
    let mut undone: BTreeMap<Identity, BTreeSet<String>> = BTreeMap::new();
    for (name, text) in files(folder) {
        if name.starts_with(FORGER) {
            continue;
        }
        let machine = name.split('.').next().unwrap().to_string();
        for line in text.lines() {
            let v: serde_json::Value = serde_json::from_str(line).unwrap();
            match v["event"].as_str().unwrap() {
                "review" => {
                    let id = identity(&v, "reviewed_at");
                    if v["undone"].as_bool().unwrap() {
                        undone
                            .entry(id.clone())
                            .or_default()
                            .insert(machine.clone());
                    }
                    holders.entry(id).or_default().insert(machine.clone());
                }
                "undo_review" => {
                    undone
                        .entry(identity(&v, "reviewed_at"))
                        .or_default()
                        .insert(machine.clone());
                }
                _ => {}
            }
        }
    }
    holders
        .into_iter()
        .filter(|(id, h)| !undone.get(id).is_some_and(|u| h.is_subset(u)))
        .map(|(id, _)| id)
        .collect()
}

fn live(data: &Path) -> BTreeSet<Identity> {
    let store = Store::open_read_only(data).unwrap();
    let mut out = BTreeSet::new();
    store
        .each_review(|l| -> Result<(), StoreError> {
            if !l.undone {
                let r = &l.record;
                out.insert((
                    r.key.deck.clone(),
                    r.key.card.clone(),
                    r.key.direction.as_str().into_owned(),
                    r.reviewed_at.timestamp_millis(),
                    r.rating as u8,
                ));
            }
            Ok(())
        })
        .unwrap();
    out
}

fn states(data: &Path) -> Vec<(ItemKey, CardState, u32, u32)> {
    let store = Store::open_read_only(data).unwrap();
    let mut s: Vec<_> = store
        .cached_states()
        .unwrap()
        .into_iter()
        .map(|c| (c.key, c.state, c.reps, c.lapses))
        .collect();
    s.sort_by(|a, b| a.0.cmp(&b.0));
    s
}

fn statuses(data: &Path) -> Vec<(ItemKey, ItemStatus)> {
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

fn run(ops: &[Op]) -> Result<(), TestCaseError> {
    let mut w = World::new();
    for op in ops {
        w.apply(op);
    }
    // Every machine syncs, a few rounds, on one clock (a machine whose
    // data folder was copied learns of it in the first round and publishes
    // under its new id in the next).
    for m in &mut w.machines {
        m.skew = TimeDelta::zero();
    }
    w.clock += TimeDelta::days(1);
    for _ in 0..3 {
        for i in 0..w.machines.len() {
            w.sync(i);
        }
    }
    let want = published(&w.folder);
    let first = &w.machines[0].data;
    for m in &w.machines {
        let got = live(&m.data);
        prop_assert_eq!(&got, &want, "live answers of {}", m.data.display());
        prop_assert_eq!(
            states(&m.data),
            states(first),
            "states of {}",
            m.data.display()
        );
        prop_assert_eq!(
            statuses(&m.data),
            statuses(first),
            "statuses of {}",
            m.data.display()
        );
    }
    for m in &mut w.machines {
        m.store = None;
        let mut store = Store::open(&m.data).unwrap();
        let before = (states(&m.data), statuses(&m.data));
        let report = store.rebuild().unwrap();
        drop(store);
        prop_assert!(!report.statuses_changed, "{report:?}");
        prop_assert_eq!(report.changed, 0, "{:?}", report);
        prop_assert_eq!((states(&m.data), statuses(&m.data)), before);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: std::env::var("PROPTEST_CASES").ok().and_then(|c| c.parse().ok()).unwrap_or(24),
        ..ProptestConfig::default()
    })]

    #[test]
    fn machines_converge_on_what_was_published(ops in proptest::collection::vec(op(), 1..40)) {
        run(&ops)?;
    }
}

/// A sequence the property search once found failing (under CI's case
/// count): an answer, a machine copied from a synced one, a bury, then an
/// answer on the copy with its clock a minute behind.
#[test]
fn a_copied_machine_a_minute_behind_converges() {
    let ops = [
        Op::Answer {
            m: 0,
            card: 0,
            back: false,
            rating: 1,
        },
        Op::Sync { m: 3 },
        Op::Copy { m: 3 },
        Op::Status {
            m: 0,
            card: 0,
            action: 2,
        },
        Op::Skew { m: 3, minutes: -1 },
        Op::Answer {
            m: 3,
            card: 0,
            back: true,
            rating: 1,
        },
    ];
    if let Err(e) = run(&ops) {
        panic!("{e}");
    }
}
