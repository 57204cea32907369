//! What the daily queue needs from the log: how much was done since the day
//! began, and when a deck was last studied.

use chrono::{DateTime, Utc};
use rusqlite::params;

use super::codec::{from_ms, to_ms};
use super::db::Store;
use super::error::StoreError;
use crate::sched::DoneToday;

impl Store {
    /// What counts against the daily limits of `deck` in the study day that
    /// began at `day_start`: items first rated since then (their first
    /// rating that counts), and review-kind answers (learning and
    /// relearning steps do not count against the review limit). Undone and
    /// cram answers do not count.
    pub fn reviews_today(
        &self,
        deck: &str,
        day_start: DateTime<Utc>,
    ) -> Result<DoneToday, StoreError> {
        let since = to_ms(day_start);
        let reviews: i64 = self
            .conn
            .prepare_cached(
                "SELECT count(*) FROM review \
                 WHERE deck = ?1 AND reviewed_at >= ?2 AND undone = 0 AND kind = 'review'",
            )
            .and_then(|mut st| st.query_row(params![deck, since], |r| r.get(0)))
            .map_err(|e| self.err(e))?;
        // An item is new today when all its answers that count are from
        // today: as many as its cached count of them.
        let new_items: i64 = self
            .conn
            .prepare_cached(
                "SELECT count(*) FROM \
                   (SELECT r.card, r.direction, count(*) AS n FROM review AS r \
                    WHERE r.deck = ?1 AND r.reviewed_at >= ?2 AND r.undone = 0 \
                      AND r.kind <> 'cram' \
                    GROUP BY r.card, r.direction) AS t \
                 JOIN card_state AS c \
                   ON c.deck = ?1 AND c.card = t.card AND c.direction = t.direction \
                 WHERE c.reps = t.n AND NOT EXISTS (SELECT 1 FROM kept_state AS k \
                   WHERE k.deck = ?1 AND k.card = t.card AND k.direction = t.direction)",
            )
            .and_then(|mut st| st.query_row(params![deck, since], |r| r.get(0)))
            .map_err(|e| self.err(e))?;
        Ok(DoneToday {
            new: u32::try_from(new_items).unwrap_or(u32::MAX),
            reviews: u32::try_from(reviews).unwrap_or(u32::MAX),
        })
    }

    /// When `deck` was last studied (its latest answer not undone, cram
    /// included), or `None` if never.
    pub fn last_studied(&self, deck: &str) -> Result<Option<DateTime<Utc>>, StoreError> {
        let ms: Option<i64> = self
            .conn
            .prepare_cached("SELECT max(reviewed_at) FROM review WHERE deck = ?1 AND undone = 0")
            .and_then(|mut st| st.query_row([deck], |r| r.get(0)))
            .map_err(|e| self.err(e))?;
        Ok(ms.and_then(from_ms))
    }
}

impl Store {
    /// How many review items (of every deck, suspended ones left out) are
    /// due in each of the `days` spans of 24 hours from `start`: the load
    /// the balancer evens (`sched::balance`). One grouped query over the
    /// card states; the answer has `days` entries.
    pub fn due_per_day(&self, start: DateTime<Utc>, days: usize) -> Result<Vec<u32>, StoreError> {
        const DAY_MS: i64 = 86_400_000;
        let from = to_ms(start);
        let span = i64::try_from(days).unwrap_or(i64::MAX / DAY_MS);
        let to = from.saturating_add(span.saturating_mul(DAY_MS));
        let mut out = vec![0u32; days];
        let mut st = self
            .conn
            .prepare_cached(
                "SELECT (c.due - ?1) / ?3 AS day, count(*) FROM card_state AS c \
                 LEFT JOIN item_status AS s \
                   ON s.deck = c.deck AND s.card = c.card AND s.direction = c.direction \
                 WHERE c.state = 'review' AND c.due >= ?1 AND c.due < ?2 \
                   AND coalesce(s.suspended, 0) = 0 \
                 GROUP BY day",
            )
            .map_err(|e| self.err(e))?;
        let rows = st
            .query_map(params![from, to, DAY_MS], |r| {
                Ok((r.get::<_, i64>(0)?, r.get::<_, i64>(1)?))
            })
            .map_err(|e| self.err(e))?;
        for row in rows {
            let (day, n) = row.map_err(|e| self.err(e))?;
            if let Some(slot) = usize::try_from(day).ok().and_then(|d| out.get_mut(d)) {
                *slot = u32::try_from(n).unwrap_or(u32::MAX);
            }
        }
        Ok(out)
    }
}
