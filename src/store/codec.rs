//! How the scheduler's vocabulary is spelled in the database: states, kinds
//! and directions as readable words, times as UTC milliseconds.

use chrono::{DateTime, Utc};

use crate::sched::{Direction, ReviewKind, State};

pub fn state_str(s: State) -> &'static str {
    match s {
        State::New => "new",
        State::Learning => "learning",
        State::Review => "review",
        State::Relearning => "relearning",
    }
}

pub fn parse_state(s: &str) -> Option<State> {
    [
        State::New,
        State::Learning,
        State::Review,
        State::Relearning,
    ]
    .into_iter()
    .find(|st| state_str(*st) == s)
}

pub fn parse_kind(s: &str) -> Option<ReviewKind> {
    [
        ReviewKind::Learn,
        ReviewKind::Review,
        ReviewKind::Relearn,
        ReviewKind::Cram,
    ]
    .into_iter()
    .find(|k| k.as_str() == s)
}

pub fn parse_direction(s: &str) -> Option<Direction> {
    Direction::parse(s)
}

/// Times are stored as whole UTC milliseconds (sub-millisecond parts are
/// dropped, so a stored time reads back equal to its truncation).
pub fn to_ms(t: DateTime<Utc>) -> i64 {
    t.timestamp_millis()
}

pub fn from_ms(ms: i64) -> Option<DateTime<Utc>> {
    DateTime::from_timestamp_millis(ms)
}
