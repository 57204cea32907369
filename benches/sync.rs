//! Sync timing on 100,000 reviews per machine: two data dirs that studied
//! the same 1,000 cards apart (100 answers each, the machines' answers
//! interleaved in time, so every card's history is replayed), with changes
//! of status on a third of the cards (suspend, bury, unsuspend, one of them
//! undone), one folder.
//! Prints the time of each step:
//!
//!     cargo bench --bench sync [-- REVIEWS_PER_MACHINE]

use std::path::Path;
use std::time::Instant;

use chrono::{DateTime, TimeDelta, Utc};
use flipcard::sched::{Config, Direction, ItemKey, Rating, Scheduler};
use flipcard::store::{StatusAction, Store};
use flipcard::sync::{Outcome, Wait};

const CARDS: usize = 1000;

/// `n` answers on `CARDS` cards, `offset` minutes after the other
/// machine's, as the app would record them.
fn study(data: &Path, n: usize, offset: i64, config: &Config) {
    let scheduler = Scheduler::new(config);
    let mut store = Store::open(data).unwrap();
    let start: DateTime<Utc> = DateTime::parse_from_rfc3339("2024-01-01T08:00:00Z")
        .unwrap()
        .with_timezone(&Utc);
    let per_card = n / CARDS;
    let mut batch = Vec::with_capacity(per_card);
    for c in 0..CARDS {
        let key = ItemKey {
            deck: "bench".into(),
            card: format!("card-{c}"),
            direction: Direction::Forward,
        };
        let mut state = None;
        batch.clear();
        for k in 0..per_card {
            let at =
                start + TimeDelta::hours(12 * k as i64) + TimeDelta::minutes(offset + c as i64);
            let rating = [
                Rating::Good,
                Rating::Good,
                Rating::Hard,
                Rating::Again,
                Rating::Easy,
            ][(k + c) % 5];
            let r = scheduler.review(&key, state.as_ref(), rating, at, 3000);
            state = Some(r.after);
            batch.push(r);
        }
        store.record_batch(&batch).unwrap();
    }
    // Changes of status, one transaction each as in the app.
    store.start_session().unwrap();
    for c in (0..CARDS).filter(|c| c % 3 == 0) {
        let key = ItemKey {
            deck: "bench".into(),
            card: format!("card-{c}"),
            direction: Direction::Forward,
        };
        let at = start + TimeDelta::days(10) + TimeDelta::minutes(offset + c as i64);
        let k = std::slice::from_ref(&key);
        store
            .set_status(k, StatusAction::Suspend, at, None)
            .unwrap();
        let later = at + TimeDelta::days(3);
        store
            .set_status(k, StatusAction::Unsuspend, later, None)
            .unwrap();
        let bury = later + TimeDelta::days(1);
        store
            .set_status(k, StatusAction::Bury, bury, Some(bury + TimeDelta::days(1)))
            .unwrap();
        if c % 2 == 0 {
            store.undo_last_change().unwrap();
        }
    }
}

fn sync_with(data: &Path, folder: &Path, config: &Config) -> Result<Outcome, String> {
    flipcard::sync::sync_with(data, folder, config, Utc::now(), Wait::No).map_err(|e| e.to_string())
}

fn timed<T>(what: &str, f: impl FnOnce() -> T) -> T {
    let t0 = Instant::now();
    let out = f();
    println!("{what}: {:.2} s", t0.elapsed().as_secs_f64());
    out
}

fn main() {
    let n: usize = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(100_000);
    let config = Config::default();
    let dir = tempfile::tempdir().unwrap();
    let (laptop, lab, folder) = (
        dir.path().join("laptop"),
        dir.path().join("lab"),
        dir.path().join("Sync"),
    );
    std::fs::create_dir(&folder).unwrap();
    timed("setup: two machines' logs", || {
        study(&laptop, n, 0, &config);
        study(&lab, n, 360, &config);
    });
    println!("{n} reviews per machine, {CARDS} cards");
    let o = timed("laptop, first sync (writes its file)", || {
        sync_with(&laptop, &folder, &config).unwrap()
    });
    println!("  {}", o.summary(&folder));
    let o = timed(
        "lab, first sync (writes its file, merges the laptop's)",
        || sync_with(&lab, &folder, &config).unwrap(),
    );
    println!("  {}", o.summary(&folder));
    let o = timed("laptop, second sync (merges the lab's)", || {
        sync_with(&laptop, &folder, &config).unwrap()
    });
    println!("  {}", o.summary(&folder));
    let o = timed("lab, nothing new", || {
        sync_with(&lab, &folder, &config).unwrap()
    });
    println!("  {}", o.summary(&folder));
    let o = timed("laptop, nothing new", || {
        sync_with(&laptop, &folder, &config).unwrap()
    });
    println!("  {}", o.summary(&folder));
    // What a sync after a session costs: one new answer here, nothing new
    // in the folder (every file is read again; the app does this in the
    // background).
    {
        let mut store = Store::open(&laptop).unwrap();
        let key = ItemKey {
            deck: "bench".into(),
            card: "card-0".into(),
            direction: Direction::Forward,
        };
        let at = Utc::now();
        let state = store.state(&key).unwrap();
        let r = Scheduler::new(&config).review(&key, state.as_ref(), Rating::Good, at, 2000);
        store.record(&r).unwrap();
    }
    let o = timed("laptop, one new answer of its own", || {
        sync_with(&laptop, &folder, &config).unwrap()
    });
    println!("  {}", o.summary(&folder));
    let o = timed("lab, merges that one answer", || {
        sync_with(&lab, &folder, &config).unwrap()
    });
    println!("  {}", o.summary(&folder));
}
