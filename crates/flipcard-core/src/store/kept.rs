//! The states another program left items in (an Anki import), kept as
//! the base each item's answers are replayed from (schema version 7,
//! `kept_state`). Written by `Store::merge_reviews_keeping`; read by every
//! merge's replay (`merge::merge_one`, a sync's included) and, for an
//! item with no answer in the log, by the state readers (`state`).

use rusqlite::{OptionalExtension, Transaction, params};

use super::codec::{self, Ms};
use super::merge::KeptState;
use crate::sched::ItemKey;

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
    let and = if filter.is_empty() { "WHERE" } else { "AND" };
    format!(
        "SELECT k.deck, k.card, k.direction, k.state, k.step, k.stability, k.difficulty, k.due, \
                k.last_review, 0, 0, 0 FROM kept_state AS k {filter} {and} NOT EXISTS \
           (SELECT 1 FROM card_state AS c \
            WHERE c.deck = k.deck AND c.card = k.card AND c.direction = k.direction)"
    )
}
