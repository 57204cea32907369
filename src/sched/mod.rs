//! Scheduling: FSRS-6 with short-term learning steps, the daily queue.
//! Never imports ratatui.

pub mod types;

pub use types::*;
