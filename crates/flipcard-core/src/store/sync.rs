//! What this machine has to send: each answer and each status event that
//! travels, once per identity and origin, read from the log for the sync
//! layer (`crate::sync`), which writes them as lines.

use std::collections::HashMap;

use super::codec::{BalancedDays, Ms};
use super::db::Store;
use super::error::StoreError;
use super::merge::IncomingReview;
use super::sync_merge::{LocalStatus, ReviewId};
use crate::sched::{ItemKey, ReviewKind};

/// One answer of this machine's log, once per identity and origin, with
/// the machine it came from (`None`: this one).
#[derive(Debug, Clone)]
pub struct LocalReview {
    /// Undone when every row with its identity and origin is.
    pub review: IncomingReview,
    pub origin: Option<String>,
    /// Written before origins were kept: without one, it may still have
    /// come from another machine.
    pub legacy: bool,
}

/// This machine's history as sync lines: each review and each status
/// event that travels once, live when any of its rows is (a review the
/// merge re-appended after an earlier one arrived is one review), in the
/// log's order.
#[derive(Debug, Default)]
pub struct Local {
    pub reviews: Vec<LocalReview>,
    pub statuses: Vec<LocalStatus>,
}

impl Store {
    /// Every review and every status event that travels, once each, with
    /// where each came from.
    pub(crate) fn sync_local(&self) -> Result<Local, StoreError> {
        let mut order: Vec<(ReviewId, Option<String>)> = Vec::new();
        let mut by_identity: HashMap<(ReviewId, Option<String>), LocalReview> = HashMap::new();
        let mut st = self
            .conn
            .prepare(
                "SELECT deck, card, direction, reviewed_at, rating, kind, duration_ms, undone, \
                 origin, id <= (SELECT review_max FROM sync_legacy), balanced_days \
                 FROM review ORDER BY id",
            )
            .map_err(|e| self.err(e))?;
        let mut rows = st.query([]).map_err(|e| self.err(e))?;
        while let Some(row) = rows.next().map_err(|e| self.err(e))? {
            let read = || -> rusqlite::Result<LocalReview> {
                Ok(LocalReview {
                    review: IncomingReview {
                        key: ItemKey {
                            deck: row.get(0)?,
                            card: row.get(1)?,
                            direction: row.get(2)?,
                        },
                        reviewed_at: row.get::<_, Ms>(3)?.0,
                        rating: row.get(4)?,
                        cram: row.get::<_, ReviewKind>(5)? == ReviewKind::Cram,
                        duration_ms: row.get(6)?,
                        undone: row.get::<_, i64>(7)? != 0,
                        balanced_days: row.get::<_, Option<BalancedDays>>(10)?.map(|d| d.0),
                    },
                    origin: row.get(8)?,
                    legacy: row.get::<_, Option<bool>>(9)?.unwrap_or(false),
                })
            };
            let l = read().map_err(|e| self.err(e))?;
            let id = (l.review.review_id(), l.origin.clone());
            match by_identity.get_mut(&id) {
                Some(e) => e.review.undone &= l.review.undone,
                None => {
                    order.push(id.clone());
                    by_identity.insert(id, l);
                }
            }
        }
        let reviews = order
            .into_iter()
            .filter_map(|id| by_identity.remove(&id))
            .collect();
        Ok(Local {
            reviews,
            statuses: self.travelling_statuses()?,
        })
    }
}
