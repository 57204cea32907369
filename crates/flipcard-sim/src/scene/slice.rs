//! How long one call that advances a run may work. The app advances its
//! run once per frame and must answer the next key within a frame, whatever
//! the scene: a run given a [`Slice`] stops at the first step boundary after
//! the deadline, keeps what it computed, and goes on from there at the next
//! call. Commands run to the end in one call ([`Slice::WHOLE`]).

use std::time::{Duration, Instant};

/// A deadline for one call (none for [`Slice::WHOLE`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Slice {
    deadline: Option<Instant>,
}

impl Slice {
    /// No deadline: the call runs to where it was asked to.
    pub const WHOLE: Slice = Slice { deadline: None };

    /// Until `deadline`.
    pub fn until(deadline: Instant) -> Slice {
        Slice {
            deadline: Some(deadline),
        }
    }

    /// For `budget` from now.
    pub fn lasting(budget: Duration) -> Slice {
        Slice::until(Instant::now() + budget)
    }

    /// Whether the deadline has passed (never for [`Slice::WHOLE`]).
    pub fn over(&self) -> bool {
        self.deadline.is_some_and(|d| Instant::now() >= d)
    }

    /// Whether the slice has a deadline.
    pub fn bounded(&self) -> bool {
        self.deadline.is_some()
    }
}
