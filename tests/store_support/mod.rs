//! Review records for the store tests: hand-made ones and random histories.
//! The store takes the scheduler's output as given, so the values here only
//! need to be well-formed, not what FSRS would compute.

#![allow(dead_code)]

use chrono::{DateTime, Duration, Utc};
use flipcard::sched::{CardState, Direction, ItemKey, Rating, ReviewKind, ReviewRecord, State};
use rand::Rng;

pub fn at(s: &str) -> DateTime<Utc> {
    DateTime::parse_from_rfc3339(s)
        .expect("test time")
        .with_timezone(&Utc)
}

pub fn key(deck: &str, card: &str) -> ItemKey {
    ItemKey {
        deck: deck.into(),
        card: card.into(),
        direction: Direction::Forward,
    }
}

pub fn back_key(deck: &str, card: &str) -> ItemKey {
    ItemKey {
        direction: Direction::Backward,
        ..key(deck, card)
    }
}

/// A rating at `when` leaving the item in `state`, due `due_in` later.
pub fn review(
    key: &ItemKey,
    when: DateTime<Utc>,
    rating: Rating,
    kind: ReviewKind,
    state: State,
    due_in: Duration,
) -> ReviewRecord {
    ReviewRecord {
        key: key.clone(),
        reviewed_at: when,
        rating,
        kind,
        elapsed_days: 0,
        scheduled_days: due_in.num_days(),
        after: CardState {
            state,
            step: matches!(state, State::Learning | State::Relearning).then_some(0),
            stability: Some(2.5),
            difficulty: Some(5.0),
            due: when + due_in,
            last_review: Some(when),
        },
        duration_ms: 4_000,
    }
}

/// A well-formed rating with random values (millisecond times, as stored).
pub fn random_review(rng: &mut impl Rng, key: &ItemKey, when: DateTime<Utc>) -> ReviewRecord {
    let rating = Rating::ALL[rng.random_range(0..4)];
    let kind = [
        ReviewKind::Learn,
        ReviewKind::Review,
        ReviewKind::Relearn,
        ReviewKind::Cram,
    ][rng.random_range(0..4)];
    let state = [State::Learning, State::Review, State::Relearning][rng.random_range(0..3)];
    let due = when + Duration::milliseconds(rng.random_range(60_000..90 * 86_400_000));
    ReviewRecord {
        key: key.clone(),
        reviewed_at: when,
        rating,
        kind,
        elapsed_days: rng.random_range(0..40),
        scheduled_days: rng.random_range(0..90),
        after: CardState {
            state,
            step: (state != State::Review).then(|| rng.random_range(0..3)),
            stability: Some(rng.random_range(0.1..300.0)),
            difficulty: Some(rng.random_range(1.0..10.0)),
            due,
            last_review: Some(when),
        },
        duration_ms: rng.random_range(300..60_000),
    }
}
