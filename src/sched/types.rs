//! The vocabulary shared by the scheduler and the store.

use chrono::{DateTime, Utc};

/// The learner's answer to a card.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Rating {
    Again = 1,
    Hard = 2,
    Good = 3,
    Easy = 4,
}

impl Rating {
    pub const ALL: [Rating; 4] = [Rating::Again, Rating::Hard, Rating::Good, Rating::Easy];
    pub fn from_number(n: i64) -> Option<Rating> {
        Rating::ALL.into_iter().find(|r| *r as i64 == n)
    }
}

/// Where a card is in its life. `New` means never reviewed (no log row).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum State {
    New = 0,
    Learning = 1,
    Review = 2,
    Relearning = 3,
}

/// Which way a card is asked. Basic and typed cards have only `Forward`;
/// reversed cards are two review items with separate state; each deletion
/// number of a cloze card is its own item (`c1`, `c2`, …).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Direction {
    /// front → back
    Forward,
    /// back → front
    Backward,
    /// The text with deletion number `n` hidden.
    Cloze(u16),
}

impl Direction {
    pub fn as_str(self) -> std::borrow::Cow<'static, str> {
        match self {
            Direction::Forward => "forward".into(),
            Direction::Backward => "backward".into(),
            Direction::Cloze(n) => format!("c{n}").into(),
        }
    }
    pub fn parse(s: &str) -> Option<Direction> {
        match s {
            "forward" => Some(Direction::Forward),
            "backward" => Some(Direction::Backward),
            _ => {
                let digits = s.strip_prefix('c')?;
                // One spelling per number: `c01` would be a second key for `c1`.
                if digits.starts_with('0') || !digits.bytes().all(|b| b.is_ascii_digit()) {
                    return None;
                }
                digits.parse().ok().filter(|n| *n > 0).map(Direction::Cloze)
            }
        }
    }
}

/// One review item: history is keyed by deck id + card id (+ direction).
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ItemKey {
    pub deck: String,
    pub card: String,
    pub direction: Direction,
}

/// What kind of answer a review-log row records.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ReviewKind {
    Learn,
    Review,
    Relearn,
    /// Exam cramming: logged, but does not change the scheduling state.
    Cram,
}

impl ReviewKind {
    pub fn as_str(self) -> &'static str {
        match self {
            ReviewKind::Learn => "learn",
            ReviewKind::Review => "review",
            ReviewKind::Relearn => "relearn",
            ReviewKind::Cram => "cram",
        }
    }
}

/// The scheduling state of one review item, as py-fsrs's `Card` holds it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CardState {
    pub state: State,
    /// Index into the learning or relearning steps (None in Review / New).
    pub step: Option<u32>,
    pub stability: Option<f64>,
    pub difficulty: Option<f64>,
    pub due: DateTime<Utc>,
    pub last_review: Option<DateTime<Utc>>,
}

/// One row of the append-only review log, as the scheduler produces it and
/// the store writes it. The state after the review is stored in full, so the
/// card states can be rebuilt from the log alone.
#[derive(Debug, Clone, PartialEq)]
pub struct ReviewRecord {
    pub key: ItemKey,
    pub reviewed_at: DateTime<Utc>,
    pub rating: Rating,
    pub kind: ReviewKind,
    /// Days since the previous review of this item (0 for the first).
    pub elapsed_days: i64,
    /// Days from this review to the next due date.
    pub scheduled_days: i64,
    /// The item's state after this review (for `Cram`, the unchanged state).
    pub after: CardState,
    /// How long the learner took to answer.
    pub duration_ms: i64,
}
