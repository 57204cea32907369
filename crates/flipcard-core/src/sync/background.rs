//! A sync on a thread of its own, with a connection of its own, so that
//! closing a review never waits for it (a sync of a large log reads every
//! file of the folder). The app starts one when a session closes and looks
//! for its end on each tick; a start while one runs asks for one more
//! after it (what the running one read may miss the newest answers).

use std::path::PathBuf;
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::time::Duration;

use crate::sched::Config;
use crate::sched::clock::Clock;

use super::{Outcome, SyncError, Wait};

/// How long a background sync waits for another sync of the same data
/// folder (the `flipcard sync` command, another app).
const WAIT: Duration = Duration::from_secs(30);

/// Syncs of one data folder through one folder, one at a time.
#[derive(Debug)]
pub struct Background {
    data: PathBuf,
    dir: PathBuf,
    /// The time each sync runs at.
    clock: Clock,
    running: Option<Receiver<Result<Outcome, SyncError>>>,
    /// The config of a sync asked for while one ran.
    again: Option<Config>,
}

impl Background {
    pub fn new(data: PathBuf, dir: PathBuf, clock: Clock) -> Background {
        Background {
            data,
            dir,
            clock,
            running: None,
            again: None,
        }
    }

    pub fn dir(&self) -> &std::path::Path {
        &self.dir
    }

    /// Starts a sync, or asks for one more when one runs.
    pub fn start(&mut self, config: &Config) {
        if self.running.is_some() {
            self.again = Some(config.clone());
            return;
        }
        let (tx, rx) = mpsc::channel();
        let (data, dir, config) = (self.data.clone(), self.dir.clone(), config.clone());
        let now = self.clock.now();
        let spawned = std::thread::Builder::new()
            .name("sync".into())
            .spawn(move || {
                let done = super::sync_with(&data, &dir, &config, now, Wait::Up(WAIT));
                let _ = tx.send(done);
            });
        match spawned {
            Ok(_) => self.running = Some(rx),
            Err(e) => {
                let (tx, rx) = mpsc::channel();
                let _ = tx.send(Err(SyncError::Spawn(e)));
                self.running = Some(rx);
            }
        }
    }

    /// The result of a sync that ended since the last call.
    pub fn poll(&mut self) -> Option<Result<Outcome, SyncError>> {
        let rx = self.running.as_ref()?;
        let done = match rx.try_recv() {
            Ok(done) => done,
            Err(TryRecvError::Empty) => return None,
            Err(TryRecvError::Disconnected) => Err(SyncError::Stopped),
        };
        self.running = None;
        if let Some(config) = self.again.take() {
            self.start(&config);
        }
        Some(done)
    }

    /// Waits for the running sync (if any) to end, and returns its result.
    pub fn wait(&mut self) -> Option<Result<Outcome, SyncError>> {
        let rx = self.running.take()?;
        self.again = None;
        Some(rx.recv().unwrap_or(Err(SyncError::Stopped)))
    }

    pub fn busy(&self) -> bool {
        self.running.is_some()
    }
}
