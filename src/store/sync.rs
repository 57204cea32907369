//! Sync between a learner's machines through a folder another tool keeps
//! in step (Syncthing, Dropbox, a network drive, a git repository).
//!
//! Each machine owns one file in the folder, `<machine-id>.jsonl`: one
//! event per line, only ever extended (rewritten whole under a temporary
//! name, fsynced, then renamed over the old one, so a reader sees the old
//! file or the new, never half of it). Four kinds of line travel:
//!
//! - `review`: an answer (the only kind of the first version of the format,
//!   whose files still merge as they are);
//! - `status`: a suspend, unsuspend or bury of an item, the learner's own
//!   or a sibling bury that a rating brought about (`cause` names it);
//! - `undo_review`, `undo_status`: an answer or status event undone after
//!   its line was written, named by its identity, since a written line is
//!   never changed.
//!
//! Leech events (and the suspend of a new leech) do not travel: each
//! machine derives them from the merged answers, where an item's lapses
//! first reach `leech_threshold`, so two machines that both saw part of a
//! card's lapses agree on one leech event instead of each sending its own.
//!
//! A machine reads every other file and merges what its log lacks with
//! [`Store::merge_sync`](super::db::Store::merge_sync), the review merge of
//! `import --reviews` extended to status events and undos: what is already
//! in the log is skipped, so syncing twice changes nothing, and each touched
//! card's state is replayed in time order, so both machines end with the
//! same live history, states and statuses.
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
use super::status::StatusAction;
use super::sync_merge::{IncomingStatus, ReviewId, StatusId};
use crate::sched::{Direction, ItemKey, Rating, ReviewKind};

/// A `review` line, spelled as the first version of the format wrote it.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SyncEvent {
    /// `review`.
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

/// A `status` line: a change of an item's status.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StatusLine {
    /// `status`.
    pub event: String,
    pub deck: String,
    pub card: String,
    pub direction: String,
    /// RFC 3339, UTC, milliseconds.
    pub at: String,
    /// `suspend`, `unsuspend` or `bury`.
    pub action: String,
    /// The end of a bury.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub until: Option<String>,
    /// The rating (of an item of the same deck) that brought it about.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cause: Option<CauseLine>,
    pub undone: bool,
}

/// The answer a status event follows from, by its identity.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CauseLine {
    pub card: String,
    pub direction: String,
    pub reviewed_at: String,
    pub rating: u8,
}

/// An `undo_review` line: the answer with this identity was undone.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UndoReviewLine {
    /// `undo_review`.
    pub event: String,
    pub deck: String,
    pub card: String,
    pub direction: String,
    pub reviewed_at: String,
    pub rating: u8,
}

/// An `undo_status` line: the status event with this identity was undone.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UndoStatusLine {
    /// `undo_status`.
    pub event: String,
    pub deck: String,
    pub card: String,
    pub direction: String,
    pub at: String,
    pub action: String,
}

/// One line of a sync file.
#[derive(Debug, Clone, PartialEq)]
pub enum SyncLine {
    Review(SyncEvent),
    Status(StatusLine),
    UndoReview(UndoReviewLine),
    UndoStatus(UndoStatusLine),
}

/// A line as the merge takes it, checked.
#[derive(Debug, Clone, PartialEq)]
pub enum Checked {
    Review(IncomingReview),
    Status(IncomingStatus),
    UndoReview(ReviewId),
    UndoStatus(StatusId),
}

/// A review's identity across machines: item, time (ms) and rating, as
/// the merge has it.
pub type Identity = (String, String, String, i64, u8);

fn time(s: &str) -> Result<DateTime<Utc>, String> {
    DateTime::parse_from_rfc3339(s)
        .map(|t| t.with_timezone(&Utc))
        .map_err(|e| format!("time {s:?}: {e}"))
}

fn item(deck: &str, card: &str, direction: &str) -> Result<ItemKey, String> {
    let direction = Direction::parse(direction)
        .ok_or_else(|| format!("direction {direction:?} is not forward, backward or c1, c2, …"))?;
    if deck.is_empty() || card.is_empty() {
        return Err("empty deck or card id".into());
    }
    Ok(ItemKey {
        deck: deck.into(),
        card: card.into(),
        direction,
    })
}

fn rating(n: u8) -> Result<Rating, String> {
    Rating::from_number(i64::from(n)).ok_or_else(|| format!("rating {n} is not 1–4"))
}

fn review_id(deck: &str, card: &str, direction: &str, at: &str, r: u8) -> Result<ReviewId, String> {
    Ok((
        item(deck, card, direction)?,
        time(at)?.timestamp_millis(),
        rating(r)?,
    ))
}

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
        let key = item(&self.deck, &self.card, &self.direction)?;
        let rating = rating(self.rating)?;
        let at = time(&self.reviewed_at)?;
        if self.duration_ms < 0 {
            return Err(format!("negative duration {} ms", self.duration_ms));
        }
        Ok(IncomingReview {
            key,
            reviewed_at: at,
            rating,
            cram: self.cram,
            duration_ms: self.duration_ms,
            undone: self.undone,
        })
    }
}

impl SyncLine {
    /// The line checked for the merge, or why it cannot be merged.
    pub fn check(&self) -> Result<Checked, String> {
        match self {
            SyncLine::Review(e) => e.incoming().map(Checked::Review),
            SyncLine::Status(s) => {
                let key = item(&s.deck, &s.card, &s.direction)?;
                let at = time(&s.at)?;
                let action = StatusAction::parse(&s.action)
                    .filter(|a| *a != StatusAction::Leech)
                    .ok_or_else(|| {
                        format!("action {:?} is not suspend, unsuspend or bury", s.action)
                    })?;
                let until = s.until.as_deref().map(time).transpose()?;
                if (action == StatusAction::Bury) != until.is_some() {
                    return Err("a bury, and only a bury, has an end time (until)".into());
                }
                let cause = match &s.cause {
                    Some(c) => Some(review_id(
                        &s.deck,
                        &c.card,
                        &c.direction,
                        &c.reviewed_at,
                        c.rating,
                    )?),
                    None => None,
                };
                if action == StatusAction::Suspend && cause.is_some() {
                    return Err("the suspend of a leech is derived on each machine".into());
                }
                Ok(Checked::Status(IncomingStatus {
                    key,
                    at,
                    action,
                    until,
                    cause,
                    undone: s.undone,
                }))
            }
            SyncLine::UndoReview(u) => {
                review_id(&u.deck, &u.card, &u.direction, &u.reviewed_at, u.rating)
                    .map(Checked::UndoReview)
            }
            SyncLine::UndoStatus(u) => {
                let key = item(&u.deck, &u.card, &u.direction)?;
                let at = time(&u.at)?;
                let action = StatusAction::parse(&u.action)
                    .filter(|a| *a != StatusAction::Leech)
                    .ok_or_else(|| {
                        format!("action {:?} is not suspend, unsuspend or bury", u.action)
                    })?;
                Ok(Checked::UndoStatus((key, at.timestamp_millis(), action)))
            }
        }
    }

    fn parse(line: &str) -> Result<SyncLine, String> {
        #[derive(Deserialize)]
        struct Kind<'a> {
            #[serde(borrow)]
            event: std::borrow::Cow<'a, str>,
        }
        let kind: Kind = serde_json::from_str(line).map_err(|e| e.to_string())?;
        let e = |e: serde_json::Error| e.to_string();
        match kind.event.as_ref() {
            "review" => serde_json::from_str(line).map(SyncLine::Review).map_err(e),
            "status" => serde_json::from_str(line).map(SyncLine::Status).map_err(e),
            "undo_review" => serde_json::from_str(line)
                .map(SyncLine::UndoReview)
                .map_err(e),
            "undo_status" => serde_json::from_str(line)
                .map(SyncLine::UndoStatus)
                .map_err(e),
            other => Err(format!(
                "unknown event {other:?} (written by a newer flipcard?)"
            )),
        }
    }

    fn json(&self) -> serde_json::Result<String> {
        match self {
            SyncLine::Review(e) => serde_json::to_string(e),
            SyncLine::Status(e) => serde_json::to_string(e),
            SyncLine::UndoReview(e) => serde_json::to_string(e),
            SyncLine::UndoStatus(e) => serde_json::to_string(e),
        }
    }
}

/// A line left out of a sync file, for a warning.
#[derive(Debug, Clone, PartialEq)]
pub struct Skipped {
    pub line: usize,
    pub why: String,
}

/// The complete, well-formed lines of a sync file, checked. A last line
/// without its newline is a write still under way; a line that does not
/// parse was cut short or garbled in transit. Both are skipped and reported.
pub fn read_lines(text: &str) -> (Vec<Checked>, Vec<Skipped>) {
    let mut lines_out = Vec::new();
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
        match SyncLine::parse(line).and_then(|l| l.check()) {
            Ok(c) => lines_out.push(c),
            Err(why) => skipped.push(Skipped { line: i + 1, why }),
        }
    }
    (lines_out, skipped)
}

/// The review lines of a sync file (the other kinds are left out), as
/// [`read_lines`] reads them.
pub fn read_events(text: &str) -> (Vec<SyncEvent>, Vec<Skipped>) {
    let (checked, skipped) = read_lines(text);
    let events = checked
        .into_iter()
        .filter_map(|c| match c {
            Checked::Review(r) => Some(review_line(&r)),
            _ => None,
        })
        .collect();
    (events, skipped)
}

fn review_line(r: &IncomingReview) -> SyncEvent {
    SyncEvent {
        event: "review".into(),
        deck: r.key.deck.clone(),
        card: r.key.card.clone(),
        direction: r.key.direction.as_str().into(),
        reviewed_at: rfc3339(r.reviewed_at),
        rating: r.rating as u8,
        cram: r.cram,
        duration_ms: r.duration_ms,
        undone: r.undone,
    }
}

/// One line, with its newline.
pub fn line(event: &SyncEvent) -> String {
    sync_line(&SyncLine::Review(event.clone()))
}

/// One line of any kind, with its newline.
pub fn sync_line(l: &SyncLine) -> String {
    let mut s = l.json().unwrap_or_default();
    s.push('\n');
    s
}

/// What the files of a folder hold, by identity.
#[derive(Debug, Default)]
pub struct Known {
    pub reviews: HashSet<ReviewId>,
    pub undone_reviews: HashSet<ReviewId>,
    pub statuses: HashSet<StatusId>,
    pub undone_statuses: HashSet<StatusId>,
}

impl Known {
    pub fn add(&mut self, line: &Checked) {
        match line {
            Checked::Review(r) => {
                let id = r.review_id();
                if r.undone {
                    self.undone_reviews.insert(id.clone());
                }
                self.reviews.insert(id);
            }
            Checked::Status(s) => {
                let id = s.status_id();
                if s.undone {
                    self.undone_statuses.insert(id.clone());
                }
                self.statuses.insert(id);
            }
            Checked::UndoReview(id) => {
                self.undone_reviews.insert(id.clone());
            }
            Checked::UndoStatus(id) => {
                self.undone_statuses.insert(id.clone());
            }
        }
    }
}

/// This machine's history as sync lines: each review and each status
/// event that travels once, live when any of its rows is (a review the
/// merge re-appended after an earlier one arrived is one review).
#[derive(Debug, Default)]
pub struct Local {
    pub reviews: Vec<IncomingReview>,
    pub statuses: Vec<IncomingStatus>,
}

impl Local {
    pub fn review_ids(&self) -> HashMap<ReviewId, bool> {
        self.reviews
            .iter()
            .map(|r| (r.review_id(), r.undone))
            .collect()
    }
    pub fn status_ids(&self) -> HashMap<StatusId, bool> {
        self.statuses
            .iter()
            .map(|s| (s.status_id(), s.undone))
            .collect()
    }

    /// The lines the folder lacks: each review or status event no file
    /// holds, and an undo for each one undone here that no file shows
    /// undone. The order is the log's, reviews first, so a status line
    /// follows the answer that caused it.
    pub fn missing(&self, known: &Known) -> Vec<SyncLine> {
        let mut out = Vec::new();
        let mut undos = Vec::new();
        for r in &self.reviews {
            let id = r.review_id();
            if !known.reviews.contains(&id) {
                out.push(SyncLine::Review(review_line(r)));
            } else if r.undone && !known.undone_reviews.contains(&id) {
                undos.push(SyncLine::UndoReview(UndoReviewLine {
                    event: "undo_review".into(),
                    deck: r.key.deck.clone(),
                    card: r.key.card.clone(),
                    direction: r.key.direction.as_str().into(),
                    reviewed_at: rfc3339(r.reviewed_at),
                    rating: r.rating as u8,
                }));
            }
        }
        for s in &self.statuses {
            let id = s.status_id();
            if !known.statuses.contains(&id) {
                out.push(SyncLine::Status(StatusLine {
                    event: "status".into(),
                    deck: s.key.deck.clone(),
                    card: s.key.card.clone(),
                    direction: s.key.direction.as_str().into(),
                    at: rfc3339(s.at),
                    action: s.action.as_str().into(),
                    until: s.until.map(rfc3339),
                    cause: s.cause.as_ref().map(|(k, ms, r)| CauseLine {
                        card: k.card.clone(),
                        direction: k.direction.as_str().into(),
                        reviewed_at: rfc3339(
                            DateTime::from_timestamp_millis(*ms).unwrap_or_default(),
                        ),
                        rating: *r as u8,
                    }),
                    undone: s.undone,
                }));
            } else if s.undone && !known.undone_statuses.contains(&id) {
                undos.push(SyncLine::UndoStatus(UndoStatusLine {
                    event: "undo_status".into(),
                    deck: s.key.deck.clone(),
                    card: s.key.card.clone(),
                    direction: s.key.direction.as_str().into(),
                    at: rfc3339(s.at),
                    action: s.action.as_str().into(),
                }));
            }
        }
        out.extend(undos);
        out
    }
}

impl Store {
    /// Every review and every status event that travels, once each.
    pub fn sync_local(&self) -> Result<Local, StoreError> {
        let mut order: Vec<ReviewId> = Vec::new();
        let mut by_identity: HashMap<ReviewId, IncomingReview> = HashMap::new();
        self.each_review(|l| -> Result<(), StoreError> {
            let r = &l.record;
            let id: ReviewId = (r.key.clone(), r.reviewed_at.timestamp_millis(), r.rating);
            match by_identity.get_mut(&id) {
                Some(e) => e.undone &= l.undone,
                None => {
                    order.push(id.clone());
                    by_identity.insert(
                        id,
                        IncomingReview {
                            key: r.key.clone(),
                            reviewed_at: r.reviewed_at,
                            rating: r.rating,
                            cram: r.kind == ReviewKind::Cram,
                            duration_ms: r.duration_ms,
                            undone: l.undone,
                        },
                    );
                }
            }
            Ok(())
        })?;
        let reviews = order
            .into_iter()
            .filter_map(|id| by_identity.remove(&id))
            .collect();
        Ok(Local {
            reviews,
            statuses: self.travelling_statuses()?,
        })
    }

    /// Every review of the log once, as a `review` line.
    pub fn sync_events(&self) -> Result<Vec<SyncEvent>, StoreError> {
        Ok(self.sync_local()?.reviews.iter().map(review_line).collect())
    }
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

    #[test]
    fn status_and_undo_lines_are_checked() {
        let ok = concat!(
            r#"{"event":"status","deck":"d","card":"c","direction":"backward","at":"2026-05-01T08:00:00.000Z","action":"bury","until":"2026-05-02T04:00:00.000Z","cause":{"card":"c","direction":"forward","reviewed_at":"2026-05-01T08:00:00.000Z","rating":3},"undone":false}"#,
            "\n",
            r#"{"event":"undo_review","deck":"d","card":"c","direction":"forward","reviewed_at":"2026-05-01T08:00:00.000Z","rating":3}"#,
            "\n",
            r#"{"event":"undo_status","deck":"d","card":"c","direction":"forward","at":"2026-05-01T08:00:00.000Z","action":"suspend"}"#,
            "\n",
        );
        let (lines, skipped) = read_lines(ok);
        assert!(skipped.is_empty(), "{skipped:?}");
        assert_eq!(lines.len(), 3);
        let Checked::Status(s) = &lines[0] else {
            panic!("{:?}", lines[0])
        };
        assert_eq!(s.action, StatusAction::Bury);
        assert_eq!(s.cause.as_ref().unwrap().0.direction, Direction::Forward);
        for (bad, why) in [
            (
                r#"{"event":"status","deck":"d","card":"c","direction":"forward","at":"2026-05-01T08:00:00Z","action":"bury","undone":false}"#,
                "end time",
            ),
            (
                r#"{"event":"status","deck":"d","card":"c","direction":"forward","at":"2026-05-01T08:00:00Z","action":"leech","undone":false}"#,
                "\"leech\"",
            ),
            (
                r#"{"event":"undo_status","deck":"d","card":"c","direction":"forward","at":"x","action":"suspend"}"#,
                "time \"x\"",
            ),
            (
                r#"{"event":"teleport","deck":"d"}"#,
                "unknown event \"teleport\"",
            ),
            (
                r#"{"event":"undo_review","deck":"d","card":"c","direction":"forward","reviewed_at":"2026-05-01T08:00:00Z","rating":3,"extra":1}"#,
                "extra",
            ),
        ] {
            let (lines, skipped) = read_lines(&format!("{bad}\n"));
            assert!(lines.is_empty(), "{bad}");
            assert!(skipped[0].why.contains(why), "{bad}: {skipped:?}");
        }
    }
}
