//! The states another program left items in (an Anki import), kept as
//! the base each item's answers are replayed from (schema version 7,
//! `kept_state`). Written by `Store::merge_reviews_keeping`; read by every
//! merge's replay (`merge::merge_one`, a sync's included) and, for an
//! item with no answer in the log, by the state readers (`state`).

use chrono::{DateTime, Utc};
use rusqlite::{OptionalExtension, Transaction, params};

use super::codec::{self, Ms};
use crate::sched::{CardState, ItemKey, State};

/// The state another program left an item in, kept instead of the
/// replayed one (an Anki import: the due date and interval Anki gave, not
/// a replay re-fuzzed here). It holds from `at`, that program's last
/// answer of the item: written into the row of the last answer up to
/// then, so the card-state cache and `flipcard db rebuild` end with it;
/// answers after it are replayed from it. It is kept in the store
/// (`kept_state`), so a later merge (a sync bringing an earlier answer)
/// replays from it again rather than away from it; and an item with no
/// answer in the log at all (Anki gave it a schedule, its review history
/// did not come along) takes it as its state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KeptState {
    /// From when it holds: that program's last answer of the item, or its
    /// last review when none of its answers is in the log.
    pub at: DateTime<Utc>,
    /// Learning, review or relearning (a new item keeps nothing).
    pub state: State,
    pub due: DateTime<Utc>,
    /// The memory state that program had (FSRS), when it had one.
    pub stability: Option<f64>,
    pub difficulty: Option<f64>,
    /// When it was last reviewed there, if known.
    pub last_review: Option<DateTime<Utc>>,
}

impl KeptState {
    /// The item's state when no answer of the log comes before: this one
    /// whole (a learning state at its first step; a memory state out of
    /// range left out, as the first answer's then is).
    pub fn base(&self) -> CardState {
        let state = if self.state == State::New {
            State::Review
        } else {
            self.state
        };
        CardState {
            state,
            step: matches!(state, State::Learning | State::Relearning).then_some(0),
            stability: self.stability.filter(|s| s.is_finite() && *s > 0.0),
            difficulty: self
                .difficulty
                .filter(|d| d.is_finite() && (1.0..=10.0).contains(d)),
            due: self.due,
            last_review: self.last_review.filter(|t| *t <= self.at.max(self.due)),
        }
    }

    /// The kept state read back from its base.
    pub(super) fn from_base(at: DateTime<Utc>, base: CardState) -> KeptState {
        KeptState {
            at,
            state: base.state,
            due: base.due,
            stability: base.stability,
            difficulty: base.difficulty,
            last_review: base.last_review,
        }
    }

    /// `record` (the replay of the last answer) with this due date, its
    /// interval and memory state. A due before the answer is left as
    /// replayed (that program's clock and this one disagree).
    pub(super) fn apply(&self, record: &mut crate::sched::ReviewRecord) {
        if self.due < record.reviewed_at {
            return;
        }
        let base = self.base();
        record.after.state = base.state;
        record.after.step = base.step;
        // Its memory dates from that program's last review, when known.
        if let Some(t) = base.last_review {
            record.after.last_review = Some(t.max(record.reviewed_at));
        }
        record.after.due = self.due;
        // The due date is that program's, not a balanced day.
        record.balanced_days = None;
        record.scheduled_days = (self.due - record.reviewed_at).num_days();
        if let Some(s) = self.stability.filter(|s| s.is_finite() && *s > 0.0) {
            record.after.stability = Some(s);
        }
        if let Some(d) = self
            .difficulty
            .filter(|d| d.is_finite() && (1.0..=10.0).contains(d))
        {
            record.after.difficulty = Some(d);
        }
    }
}

/// Keeps `kept` as `key`'s base (replacing an earlier one).
pub(super) fn put(tx: &Transaction<'_>, key: &ItemKey, kept: &KeptState) -> rusqlite::Result<()> {
    let base = kept.base();
    tx.prepare_cached(
        "INSERT INTO kept_state (deck, card, direction, at, state, step, stability, difficulty, \
         due, last_review) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10) \
         ON CONFLICT (deck, card, direction) DO UPDATE SET at = excluded.at, \
           state = excluded.state, step = excluded.step, stability = excluded.stability, \
           difficulty = excluded.difficulty, due = excluded.due, \
           last_review = excluded.last_review",
    )?
    .execute(params![
        key.deck,
        key.card,
        key.direction,
        Ms(kept.at),
        base.state,
        base.step.map(i64::from),
        base.stability,
        base.difficulty,
        Ms(base.due),
        base.last_review.map(Ms),
    ])?;
    Ok(())
}

/// The base kept for `key`, if any.
pub(super) fn get(tx: &Transaction<'_>, key: &ItemKey) -> rusqlite::Result<Option<KeptState>> {
    tx.prepare_cached(
        "SELECT at, state, step, stability, difficulty, due, last_review FROM kept_state \
         WHERE deck = ?1 AND card = ?2 AND direction = ?3",
    )?
    .query_row(params![key.deck, key.card, key.direction], |row| {
        let at = row.get::<_, Ms>(0)?.0;
        let state = codec::card_state(row, [1, 2, 3, 4, 5, 6])?;
        Ok(KeptState::from_base(at, state))
    })
    .optional()
}

/// The kept states of items with no cached state (no answer of theirs
/// counts), as the state readers add them: the columns of `card_state`,
/// with no counts and no row (`review_id` 0). `filter` is `""` or a
/// `WHERE` on `k.deck`.
pub(super) fn as_cached_sql(filter: &str) -> String {
    kept_sql(
        "k.deck, k.card, k.direction, k.state, k.step, k.stability, k.difficulty, k.due, \
         k.last_review, 0, 0, 0",
        filter,
    )
}

/// The kept states no answer counts for, as [`as_cached_sql`], with only
/// the `columns` (of `kept_state AS k`, or constants) selected.
pub(super) fn kept_sql(columns: &str, filter: &str) -> String {
    let and = if filter.is_empty() { "WHERE" } else { "AND" };
    format!(
        "SELECT {columns} FROM kept_state AS k {filter} {and} NOT EXISTS \
           (SELECT 1 FROM card_state AS c \
            WHERE c.deck = k.deck AND c.card = k.card AND c.direction = k.direction)"
    )
}
