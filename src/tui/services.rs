//! The domain services the screens call: the clock, and (as they are wired
//! in) the scheduler, the review store and the config file.

use chrono::{DateTime, Utc};

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

pub struct Services {
    pub clock: Clock,
}

impl Services {
    pub fn now(&self) -> DateTime<Utc> {
        self.clock.now()
    }
}

impl Services {
    /// Today's counts and the last study time of a deck.
    pub fn deck_row(&self, _deck: &crate::deck::Deck) -> super::screens::home::DeckRow {
        super::screens::home::DeckRow {
            counts: None,
            last_studied: None,
        }
    }
}

impl Services {
    /// Remembers the language for the next run.
    pub fn save_language(&mut self, _lang: &str) {}
}
