//! Each item's answers that count for scheduling, in time order: what the
//! FSRS fit learns from.

use chrono::{DateTime, Utc};

use super::codec::Ms;
use super::db::Store;
use super::error::StoreError;
use crate::sched::{ItemKey, Rating};

/// One item with its answers (time, rating) in time order.
pub(crate) type ItemAnswers = (ItemKey, Vec<(DateTime<Utc>, Rating)>);

impl Store {
    /// Every item's live, non-cram answers (time, rating) in time order, for
    /// one deck or all, items ordered by deck, card, direction.
    pub fn answers_by_item(&self, deck: Option<&str>) -> Result<Vec<ItemAnswers>, StoreError> {
        let mut st = self
            .conn
            .prepare(
                "SELECT deck, card, direction, reviewed_at, rating FROM review \
                 WHERE undone = 0 AND kind <> 'cram' AND (?1 IS NULL OR deck = ?1) \
                 ORDER BY deck, card, direction, reviewed_at, id",
            )
            .map_err(|e| self.err(e))?;
        let mut rows = st.query([deck]).map_err(|e| self.err(e))?;
        let mut out: Vec<ItemAnswers> = Vec::new();
        while let Some(row) = rows.next().map_err(|e| self.err(e))? {
            let read = (|| -> rusqlite::Result<(ItemKey, DateTime<Utc>, Rating)> {
                Ok((
                    ItemKey {
                        deck: row.get(0)?,
                        card: row.get(1)?,
                        direction: row.get(2)?,
                    },
                    row.get::<_, Ms>(3)?.0,
                    row.get(4)?,
                ))
            })();
            let (key, at, rating) = read.map_err(|e| self.err(e))?;
            match out.last_mut() {
                Some((k, answers)) if *k == key => answers.push((at, rating)),
                _ => out.push((key, vec![(at, rating)])),
            }
        }
        Ok(out)
    }
}
