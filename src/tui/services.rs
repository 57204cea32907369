//! What the screens call: the clock and the stopwatch, the learner's study
//! (`crate::study`: config, scheduler, store, and what each action does),
//! the background sync, and caches kept between screens.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use chrono::{DateTime, Utc};

use crate::catalog::{SearchIndex, SearchTexts};
use crate::sched::Config;
use crate::store::Store;
pub use crate::study::DayZone;
use crate::study::Study;

/// Where "now" comes from (the command builds it from `FLIPCARD_NOW`).
pub use crate::sched::clock::Clock;

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
/// closes (a screen whose [`super::app::Screen::ends_session`] says so),
/// run in the background so the screen never waits for it.
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

pub struct Services {
    pub clock: Clock,
    pub stopwatch: Stopwatch,
    /// The config, the scheduler, the store, and every action on them.
    pub study: Study,
    /// Where the language choice is saved (`None`: nowhere to save).
    pub config_path: Option<PathBuf>,
    /// The work–precision table of `flipcard bench`, if one was written.
    pub bench_csv: Option<PathBuf>,
    /// The sync the app starts when a screen that ends a study session
    /// closes (`None`: no `sync_dir`).
    pub sync: Option<Box<dyn Syncer>>,
    /// The card browser's search index, kept between its openings.
    pub browser_index: SearchCache,
    /// The most one frame's simulation may work ([`super::live::SLICE`]),
    /// so a key is always read within a frame; `None` lets each frame's run
    /// reach its time however long that takes (tests, so that snapshots do
    /// not depend on how fast the machine is).
    pub physics_slice: Option<std::time::Duration>,
    /// The editor `E` and `A` open a deck file in ([`super::edit`]).
    pub editor: Box<dyn EditorRun>,
    /// The learner's deck library, where a bundled deck is copied before
    /// it is edited (`None`: no library, bundled decks cannot be edited).
    pub library: Option<Box<dyn DeckLibrary>>,
}

impl Services {
    pub fn new(
        clock: Clock,
        config: Config,
        config_path: Option<PathBuf>,
        zone: DayZone,
        store: Store,
    ) -> Services {
        Services {
            clock,
            stopwatch: Stopwatch::Real,
            study: Study::new(config, zone, store),
            config_path,
            bench_csv: None,
            sync: None,
            browser_index: Default::default(),
            physics_slice: Some(super::live::SLICE),
            editor: Box::new(Spawn::vi()),
            library: None,
        }
    }

    /// Syncs the data folder through `dir` in the background whenever a
    /// study session ends.
    pub fn sync_through(&mut self, data_dir: PathBuf, dir: PathBuf) {
        let background = crate::sync::background::Background::new(data_dir, dir, self.clock);
        self.sync = Some(Box::new(background));
    }

    /// The slice a frame's simulation works within.
    pub fn physics_slice(&self) -> crate::sim::scene::slice::Slice {
        use crate::sim::scene::slice::Slice;
        self.physics_slice.map_or(Slice::WHOLE, Slice::lasting)
    }

    pub fn now(&self) -> DateTime<Utc> {
        self.clock.now()
    }

    /// Remembers the exam date planned for (`exam_date` in the config),
    /// so the exam screen and `flipcard plan` offer it until it passes.
    pub fn remember_exam(&mut self, exam: chrono::NaiveDate) -> Result<(), String> {
        if self.study.config.exam_date == Some(exam) {
            return Ok(());
        }
        match &self.config_path {
            Some(path) => self
                .study
                .config
                .save_exam_date(path, exam)
                .map_err(|e| e.to_string()),
            None => {
                self.study.config.exam_date = Some(exam);
                Ok(())
            }
        }
    }

    /// Remembers the language for the next run.
    pub fn save_language(&mut self, lang: &str) -> Result<(), String> {
        self.study.config.language = lang.to_string();
        match &self.config_path {
            Some(path) => self
                .study
                .config
                .save_key(path, "language")
                .map_err(|e| e.to_string()),
            None => Ok(()),
        }
    }
}

/// Runs the learner's editor on a deck file, waiting for it to close.
pub trait EditorRun {
    /// Opens `file` at `line`; an error is one line saying why the editor
    /// could not run (or that it failed).
    fn run(&mut self, file: &Path, line: usize) -> Result<(), String>;
}

/// The real editor: a command and its arguments (`$VISUAL`, else
/// `$EDITOR`, else `vi`, split on whitespace), run without a
/// shell as `ARGS… +LINE FILE`, so nothing in the file's name is ever
/// read as shell syntax.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Spawn {
    pub argv: Vec<String>,
}

impl Spawn {
    pub fn vi() -> Spawn {
        Spawn {
            argv: vec!["vi".to_string()],
        }
    }

    /// The editor a setting names (`$VISUAL` or `$EDITOR`): its words;
    /// `vi` when it is empty or blank.
    pub fn from_setting(setting: &str) -> Spawn {
        let argv: Vec<String> = setting.split_whitespace().map(str::to_string).collect();
        if argv.is_empty() {
            Spawn::vi()
        } else {
            Spawn { argv }
        }
    }
}

impl EditorRun for Spawn {
    fn run(&mut self, file: &Path, line: usize) -> Result<(), String> {
        let name = crate::text::safe::one_line(&self.argv[0]);
        let status = std::process::Command::new(&self.argv[0])
            .args(&self.argv[1..])
            .arg(format!("+{}", line.max(1)))
            .arg(file)
            .status()
            .map_err(|e| {
                format!("cannot start the editor `{name}`: {e} (set $VISUAL or $EDITOR)")
            })?;
        if status.success() {
            Ok(())
        } else {
            Err(format!("the editor `{name}` failed ({status})"))
        }
    }
}

/// What the app needs of the learner's deck library to edit a deck.
pub trait DeckLibrary {
    /// Whether the deck `id` is one of the bundled decks (its file is in
    /// the binary, not on disk).
    fn is_bundled(&self, id: &str) -> bool;
    /// Copies the bundled deck `id` (its file and explanations) into the
    /// library, where it replaces the bundled one; returns the copy's
    /// deck file.
    fn copy_bundled(&mut self, id: &str) -> Result<PathBuf, String>;
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
