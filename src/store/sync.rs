//! Sync between a learner's machines through a folder another tool keeps
//! in step (Syncthing, Dropbox, a network drive, a git repository).
//!
//! Each machine owns one file in the folder, `<machine-id>.jsonl`: one
//! review per line, only ever extended (rewritten whole under a temporary
//! name, fsynced, then renamed over the old one, so a reader sees the old
//! file or the new, never half of it). A machine reads every other file and
//! merges its reviews with [`Store::merge_reviews`], the merge of
//! `import --reviews`: a review already in the log is skipped, so syncing
//! twice changes nothing, and each touched card's state is replayed in time
//! order, so both machines end with the same live history and states.
//!
//! A file another tool is still copying may end in a half line, or hold a
//! line cut short: such lines are skipped with a warning and read next time.

use std::collections::{HashMap, HashSet};

use chrono::{DateTime, Utc};
use serde::{Deserialize, Serialize};

use super::db::Store;
use super::error::StoreError;
use super::export::rfc3339;
use super::merge::IncomingReview;
use crate::sched::{Direction, ItemKey, Rating, ReviewKind};

/// One line of a sync file.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SyncEvent {
    /// What the line records; `review` is the only kind written so far.
    pub event: String,
    pub deck: String,
    pub card: String,
    pub direction: String,
    /// RFC 3339, UTC, milliseconds.
    pub reviewed_at: String,
    pub rating: u8,
    pub cram: bool,
    pub duration_ms: i64,
    pub undone: bool,
}

/// A review's identity across machines: item, time (ms) and rating, as
/// the merge has it.
pub type Identity = (String, String, String, i64, u8);

impl SyncEvent {
    pub fn identity(&self) -> Option<Identity> {
        let at = DateTime::parse_from_rfc3339(&self.reviewed_at).ok()?;
        Some((
            self.deck.clone(),
            self.card.clone(),
            self.direction.clone(),
            at.with_timezone(&Utc).timestamp_millis(),
            self.rating,
        ))
    }

    /// The review to merge, or why the line cannot be one.
    pub fn incoming(&self) -> Result<IncomingReview, String> {
        if self.event != "review" {
            return Err(format!("unknown event {:?}", self.event));
        }
        let direction = Direction::parse(&self.direction)
            .ok_or_else(|| format!("direction {:?} is not forward or backward", self.direction))?;
        let rating = Rating::from_number(i64::from(self.rating))
            .ok_or_else(|| format!("rating {} is not 1–4", self.rating))?;
        let at = DateTime::parse_from_rfc3339(&self.reviewed_at)
            .map_err(|e| format!("time {:?}: {e}", self.reviewed_at))?
            .with_timezone(&Utc);
        if self.deck.is_empty() || self.card.is_empty() {
            return Err("empty deck or card id".into());
        }
        if self.duration_ms < 0 {
            return Err(format!("negative duration {} ms", self.duration_ms));
        }
        Ok(IncomingReview {
            key: ItemKey {
                deck: self.deck.clone(),
                card: self.card.clone(),
                direction,
            },
            reviewed_at: at,
            rating,
            cram: self.cram,
            duration_ms: self.duration_ms,
            undone: self.undone,
        })
    }
}

/// A line left out of a sync file, for a warning.
#[derive(Debug, Clone, PartialEq)]
pub struct Skipped {
    pub line: usize,
    pub why: String,
}

/// The complete, well-formed lines of a sync file. A last line without
/// its newline is a write still under way; a line that does not parse was
/// cut short or garbled in transit. Both are skipped and reported.
pub fn read_events(text: &str) -> (Vec<SyncEvent>, Vec<Skipped>) {
    let mut events = Vec::new();
    let mut skipped = Vec::new();
    let complete = text.ends_with('\n');
    let lines: Vec<&str> = text.split('\n').collect();
    let last = lines.len() - 1;
    for (i, line) in lines.iter().enumerate() {
        if i == last {
            if !complete && !line.is_empty() {
                skipped.push(Skipped {
                    line: i + 1,
                    why: "the last line is incomplete (still being copied?)".into(),
                });
            }
            break;
        }
        if line.trim().is_empty() {
            continue;
        }
        match serde_json::from_str::<SyncEvent>(line)
            .map_err(|e| e.to_string())
            .and_then(|e| e.incoming().map(|_| e))
        {
            Ok(e) => events.push(e),
            Err(why) => skipped.push(Skipped { line: i + 1, why }),
        }
    }
    (events, skipped)
}

/// One line, with its newline.
pub fn line(event: &SyncEvent) -> String {
    let mut s = serde_json::to_string(event).unwrap_or_default();
    s.push('\n');
    s
}

impl Store {
    /// Every review of the log once, as a sync event: a review that the
    /// merge re-appended after an earlier one arrived is one review, live.
    pub fn sync_events(&self) -> Result<Vec<SyncEvent>, StoreError> {
        let mut order: Vec<Identity> = Vec::new();
        let mut by_identity: HashMap<Identity, SyncEvent> = HashMap::new();
        self.each_review(|l| -> Result<(), StoreError> {
            let r = &l.record;
            let id: Identity = (
                r.key.deck.clone(),
                r.key.card.clone(),
                r.key.direction.as_str().to_string(),
                r.reviewed_at.timestamp_millis(),
                r.rating as u8,
            );
            match by_identity.get_mut(&id) {
                Some(e) => e.undone &= l.undone,
                None => {
                    order.push(id.clone());
                    by_identity.insert(
                        id,
                        SyncEvent {
                            event: "review".into(),
                            deck: r.key.deck.clone(),
                            card: r.key.card.clone(),
                            direction: r.key.direction.as_str().into(),
                            reviewed_at: rfc3339(r.reviewed_at),
                            rating: r.rating as u8,
                            cram: r.kind == ReviewKind::Cram,
                            duration_ms: r.duration_ms,
                            undone: l.undone,
                        },
                    );
                }
            }
            Ok(())
        })?;
        Ok(order
            .into_iter()
            .filter_map(|id| by_identity.remove(&id))
            .collect())
    }
}

/// The local events no file of the folder holds yet, in log order.
pub fn missing<'a>(local: &'a [SyncEvent], in_folder: &HashSet<Identity>) -> Vec<&'a SyncEvent> {
    local
        .iter()
        .filter(|e| e.identity().is_some_and(|id| !in_folder.contains(&id)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn event(card: &str, ms: i64) -> SyncEvent {
        SyncEvent {
            event: "review".into(),
            deck: "d".into(),
            card: card.into(),
            direction: "forward".into(),
            reviewed_at: rfc3339(DateTime::from_timestamp_millis(ms).unwrap()),
            rating: 3,
            cram: false,
            duration_ms: 10,
            undone: false,
        }
    }

    #[test]
    fn half_lines_and_garbage_are_skipped_and_the_rest_read() {
        let a = line(&event("a", 1000));
        let b = line(&event("b", 2000));
        let text = format!("{a}{}\n{b}{}", &b[..20], &a[..a.len() - 5]);
        let (events, skipped) = read_events(&text);
        assert_eq!(events, [event("a", 1000), event("b", 2000)]);
        assert_eq!(skipped.len(), 2, "{skipped:?}");
        assert_eq!(skipped[0].line, 2);
        assert_eq!(skipped[1].line, 4);
        assert!(skipped[1].why.contains("incomplete"));
        let bad_rating = line(&event("c", 1)).replace("\"rating\":3", "\"rating\":7");
        let (events, skipped) = read_events(&bad_rating);
        assert!(events.is_empty());
        assert!(skipped[0].why.contains("rating 7"), "{skipped:?}");
    }
}
