//! Scheduling: FSRS-6 with short-term learning steps, the daily queue,
//! typed-answer checking and the learner's settings. Never imports ratatui.

pub mod balance;
pub mod clock;
pub mod config;
pub mod day;
pub mod fit;
pub mod plan;
pub mod preset;
pub mod queue;
pub mod scheduler;
pub mod typed;
pub mod types;

pub use config::{Config, ConfigError};
pub use day::{DayGrid, DayOf, DayZone, Days};
pub use queue::{
    Counts, CramQueue, DoneToday, Queue, QueueKind, cram_item_refs, cram_items, deck_item_refs,
    deck_items, study_day,
};
pub use scheduler::{Preview, Scheduler, Schedulers, format_interval};
pub use types::*;
