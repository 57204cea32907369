//! The domain services the screens call: the clock, the learner's config,
//! the scheduler and the review store.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::Instant;

use chrono::{DateTime, Utc};

use crate::deck::Deck;
use crate::sched::{CardState, Config, ItemKey, Queue, Scheduler};
use crate::store::search::{SearchIndex, SearchTexts};
use crate::store::{AfterRating, PromptAttempt, Store, StoreError};

/// Where "now" comes from: the system clock, or a fixed time
/// (`FLIPCARD_NOW`, tests).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Clock {
    System,
    Fixed(DateTime<Utc>),
}

impl Clock {
    /// The clock the environment asks for (`FLIPCARD_NOW` fixes it).
    pub fn from_env() -> Result<Clock, crate::sched::clock::ClockError> {
        if std::env::var_os(crate::sched::clock::NOW_VAR).is_some() {
            crate::sched::clock::now().map(Clock::Fixed)
        } else {
            Ok(Clock::System)
        }
    }

    pub fn now(&self) -> DateTime<Utc> {
        match self {
            Clock::System => Utc::now(),
            Clock::Fixed(t) => *t,
        }
    }
}

/// How long the learner took: real elapsed time, or always zero (tests,
/// so that snapshots do not depend on how fast the machine is).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stopwatch {
    Real,
    Frozen,
}

/// A moment on the stopwatch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Stamp(Option<Instant>);

impl Stopwatch {
    pub fn stamp(&self) -> Stamp {
        match self {
            Stopwatch::Real => Stamp(Some(Instant::now())),
            Stopwatch::Frozen => Stamp(None),
        }
    }

    pub fn elapsed_ms(&self, since: Stamp) -> i64 {
        since.0.map_or(0, |t| {
            i64::try_from(t.elapsed().as_millis()).unwrap_or(i64::MAX)
        })
    }
}

/// Which time zone the study day's boundary (04:00 by default) is read in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DayZone {
    Local,
    /// For tests: the same day boundary on every machine.
    Utc,
}

/// What a sync after a review session did, for the status line.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Synced {
    /// Reviews, status changes and undos written to this machine's file.
    pub written: usize,
    /// Reviews, status changes and undos merged from the other machines.
    pub merged: usize,
    /// Lines and files skipped, to be read next time.
    pub warnings: Vec<String>,
}

/// The sync of `sync_dir` when a session that may have changed the log
/// closes (a review, an exam share, the browser), run in the background so
/// the screen never waits for it; given by the command that opened the app.
pub trait Syncer {
    /// Starts a sync (or asks for one more when one is running).
    fn start(&mut self, config: &Config);
    /// What a sync that ended since the last call did.
    fn poll(&mut self) -> Option<Result<Synced, String>>;
    /// Whether a sync is running (the app then ticks, to look for its end).
    fn busy(&self) -> bool;
}

/// The real one: [`crate::sync::background::Background`].
impl Syncer for crate::sync::background::Background {
    fn start(&mut self, config: &Config) {
        crate::sync::background::Background::start(self, config);
    }
    fn poll(&mut self) -> Option<Result<Synced, String>> {
        let dir = self.dir().display().to_string();
        crate::sync::background::Background::poll(self).map(|done| {
            done.map(|o| Synced {
                written: o.written + o.written_statuses + o.written_undos,
                merged: o.merged + o.merged_statuses + o.merged_undos,
                warnings: o.warnings,
            })
            .map_err(|e| format!("sync through {dir} failed: {e}"))
        })
    }
    fn busy(&self) -> bool {
        crate::sync::background::Background::busy(self)
    }
}

pub type AfterSession = Box<dyn Syncer>;

pub struct Services {
    pub clock: Clock,
    pub stopwatch: Stopwatch,
    pub config: Config,
    /// Where the language choice is saved (`None`: nowhere to save).
    pub config_path: Option<PathBuf>,
    pub scheduler: Scheduler,
    pub zone: DayZone,
    pub store: Store,
    /// The work–precision table of `flipcard bench`, if one was written.
    pub bench_csv: Option<PathBuf>,
    pub after_session: Option<AfterSession>,
    /// The card browser's search index, kept between its openings.
    pub browser_index: SearchCache,
    /// The most one frame's simulation may work ([`super::live_system::SLICE`]),
    /// so a key is always read within a frame; `None` lets each frame's run
    /// reach its time however long that takes (tests, so that snapshots do
    /// not depend on how fast the machine is).
    pub physics_slice: Option<std::time::Duration>,
}

impl Services {
    pub fn new(
        clock: Clock,
        config: Config,
        config_path: Option<PathBuf>,
        zone: DayZone,
        store: Store,
    ) -> Services {
        let scheduler = Scheduler::new(&config);
        Services {
            clock,
            stopwatch: Stopwatch::Real,
            config,
            config_path,
            scheduler,
            zone,
            store,
            bench_csv: None,
            after_session: None,
            browser_index: Default::default(),
            physics_slice: Some(super::live_system::SLICE),
        }
    }

    /// The slice a frame's simulation works within.
    pub fn physics_slice(&self) -> crate::sim::scene::slice::Slice {
        use crate::sim::scene::slice::Slice;
        self.physics_slice.map_or(Slice::WHOLE, Slice::lasting)
    }

    pub fn now(&self) -> DateTime<Utc> {
        self.clock.now()
    }

    /// The study day containing `now`: (start, end).
    pub fn study_day(&self, now: DateTime<Utc>) -> (DateTime<Utc>, DateTime<Utc>) {
        let starts = self.config.day_starts_at;
        match self.zone {
            DayZone::Local => crate::sched::study_day(now, starts, &chrono::Local),
            DayZone::Utc => crate::sched::study_day(now, starts, &Utc),
        }
    }

    /// The day's queue of a deck, and the item states it was built from.
    pub fn queue(
        &self,
        deck: &Deck,
        now: DateTime<Utc>,
    ) -> Result<(Queue, HashMap<ItemKey, CardState>), StoreError> {
        let states = self.store.states(&deck.id)?;
        let (day_start, _) = self.study_day(now);
        let done = self.store.reviews_today(&deck.id, day_start)?;
        // Suspended and buried items leave the queue.
        let statuses = self.store.statuses()?;
        let mut items = crate::sched::deck_items(deck);
        items.retain(|k| statuses.get(k).is_none_or(|s| s.studyable(now)));
        let queue = match self.zone {
            DayZone::Local => {
                Queue::build(&items, &states, done, now, &self.config, &chrono::Local)
            }
            DayZone::Utc => Queue::build(&items, &states, done, now, &self.config, &Utc),
        };
        Ok((queue, states))
    }

    /// What follows a rating of `key` in `deck`: leech detection as the
    /// config says, and its siblings buried until the next study day.
    pub fn after_rating(&self, deck: &Deck, key: &ItemKey, now: DateTime<Utc>) -> AfterRating {
        let c = &self.config;
        let bury = match deck.card(&key.card) {
            Some(card) if c.bury_siblings => crate::store::catalog::card_directions(card)
                .into_iter()
                .filter(|d| *d != key.direction)
                .map(|direction| ItemKey {
                    direction,
                    ..key.clone()
                })
                .collect(),
            _ => Vec::new(),
        };
        AfterRating {
            leech_threshold: c.leech_threshold,
            leech_suspend: c.leech_action == crate::sched::config::LeechAction::Suspend,
            bury,
            bury_until: self.study_day(now).1,
        }
    }

    /// Remembers the language for the next run.
    pub fn save_language(&mut self, lang: &str) -> Result<(), String> {
        self.config.language = lang.to_string();
        match &self.config_path {
            Some(path) => self
                .config
                .save_key(path, "language")
                .map_err(|e| e.to_string()),
            None => Ok(()),
        }
    }

    pub fn record_attempt(&mut self, attempt: &PromptAttempt) -> Result<i64, StoreError> {
        self.store.record_attempt(attempt)
    }
}

/// The search index kept between openings of the browser, with the texts
/// it was built from: while the decks say the same, opening the browser
/// again finds it ready.
#[derive(Clone, Default)]
pub struct SearchCache(Arc<Mutex<Option<Kept>>>);

/// An index and the texts it was built from.
type Kept = (SearchTexts, Arc<SearchIndex>);

impl SearchCache {
    /// The index kept, when it was built from `texts`.
    pub fn get(&self, texts: &SearchTexts) -> Option<Arc<SearchIndex>> {
        let slot = self.0.lock().ok()?;
        let (t, index) = slot.as_ref()?;
        (t == texts).then(|| Arc::clone(index))
    }

    /// Keeps `index`, built from `texts`.
    pub fn put(&self, texts: SearchTexts, index: Arc<SearchIndex>) {
        if let Ok(mut slot) = self.0.lock() {
            *slot = Some((texts, index));
        }
    }
}
