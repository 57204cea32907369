//! The domain services the screens call: the clock, the learner's config,
//! the scheduler and the review store.

use std::path::PathBuf;

use chrono::{DateTime, Utc};

use crate::sched::{Config, Scheduler};

/// Where "now" comes from: the system clock, or a fixed time
/// (`FLIPCARD_NOW`, tests).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Clock {
    System,
    Fixed(DateTime<Utc>),
}

impl Clock {
    /// The clock the environment asks for (`FLIPCARD_NOW` fixes it).
    pub fn from_env() -> Result<Clock, crate::clock::ClockError> {
        if std::env::var_os(crate::clock::NOW_VAR).is_some() {
            crate::clock::now().map(Clock::Fixed)
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

/// Which time zone the study day's 04:00 boundary is read in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DayZone {
    Local,
    /// For tests: the same day boundary on every machine.
    Utc,
}

pub struct Services {
    pub clock: Clock,
    pub config: Config,
    /// Where the language choice is saved (`None`: nowhere to save).
    pub config_path: Option<PathBuf>,
    pub scheduler: Scheduler,
    pub zone: DayZone,
}

impl Services {
    pub fn new(
        clock: Clock,
        config: Config,
        config_path: Option<PathBuf>,
        zone: DayZone,
    ) -> Services {
        let scheduler = Scheduler::new(&config);
        Services {
            clock,
            config,
            config_path,
            scheduler,
            zone,
        }
    }

    pub fn now(&self) -> DateTime<Utc> {
        self.clock.now()
    }

    /// Today's counts and the last study time of a deck.
    pub fn deck_row(&self, _deck: &crate::deck::Deck) -> super::screens::home::DeckRow {
        super::screens::home::DeckRow {
            counts: None,
            last_studied: None,
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
}
