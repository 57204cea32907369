//! Sync between a learner's machines through a folder another tool keeps
//! in step (Syncthing, Dropbox, a network drive, a git repository).
//!
//! Each machine owns one file in the folder, `<machine-id>.jsonl`: one
//! event per line, only ever extended (rewritten whole under a temporary
//! name, fsynced, then renamed over the old one, so a reader sees the old
//! file or the new, never half of it). Four kinds of line travel:
//!
//! - `review`: an answer (the only kind of the first version of the format,
//!   whose files still merge as they are), with `balanced_days` when the
//!   load balancer chose its day (a field added later: a line without it
//!   replays with the uniform draw, as before);
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
//! [`Store::merge_sync`](crate::store::Store::merge_sync), the review merge of
//! `import --reviews` extended to status events and undos: what is already
//! in the log is skipped, so syncing twice changes nothing, and each touched
//! card's state is replayed in time order, so both machines end with the
//! same live history, states and statuses.
//!
//! A file another tool is still copying may end in a half line, or hold a
//! line cut short: such lines are skipped with a warning and read next time.

use chrono::{DateTime, Utc};
use serde::{Deserialize, Serialize};

use crate::interop::export::rfc3339;
use crate::sched::{ItemKey, KeyError, Rating, clock};
use crate::store::merge::IncomingReview;
use crate::store::status::StatusAction;
use crate::store::sync_merge::{IncomingStatus, ReviewId, StatusId};
use flipcard_text::safe::one_line;

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
    /// The interval in whole days the load balancer chose for the answer;
    /// absent when it chose none. Another machine takes it only within the
    /// fuzz range the answer allows (`Scheduler::replay`); a value no
    /// interval can have is ignored (the uniform draw, as without it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub balanced_days: Option<i64>,
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

/// The longest line read from a sync file: a line of this format is a few
/// hundred bytes, and a longer one is not parsed at all.
pub(crate) const MAX_LINE_BYTES: usize = 16 * 1024;

fn time(s: &str, now: DateTime<Utc>) -> Result<DateTime<Utc>, LineError> {
    let t = DateTime::parse_from_rfc3339(s)
        .map(|t| t.with_timezone(&Utc))
        .map_err(|e| BadLine::NotRfc3339 {
            quoted: one_line(s).into_owned(),
            reason: e.to_string(),
        })?;
    match clock::check_event_time(t, now) {
        Ok(()) => Ok(t),
        // Dated a little later than this machine's clock allows: it may be
        // read once the clock gets there (another machine's clock runs
        // ahead); further ahead than any clock is wrong, it never will be.
        Err(why) if t > now && t <= now + chrono::TimeDelta::days(LATER_DAYS) => {
            Err(LineError::Later(why))
        }
        Err(why) => Err(LineError::Bad(BadLine::Time(why))),
    }
}

/// How far ahead of this machine's clock a line may be dated and still be
/// waited for (read again at each sync).
const LATER_DAYS: i64 = 30;

/// Why a line is not merged now.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LineError {
    /// It never will be: the line is written and will not change.
    #[error(transparent)]
    Bad(#[from] BadLine),
    /// Dated after this machine's clock (plus the skew allowed): it is read
    /// again at the next sync.
    #[error(transparent)]
    Later(clock::EventTimeError),
}

impl From<KeyError> for LineError {
    fn from(e: KeyError) -> LineError {
        LineError::Bad(BadLine::Key(e))
    }
}

/// Why a line can never be merged. Values are quoted on one line, control
/// characters escaped.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BadLine {
    /// Not JSON of any line kind: serde's words.
    #[error("{0}")]
    Json(String),
    #[error("unknown event \"{0}\" (written by a newer flipcard?)")]
    NewerEvent(String),
    #[error("unknown event \"{0}\"")]
    UnknownEvent(String),
    #[error(transparent)]
    Key(#[from] KeyError),
    #[error("time \"{quoted}\": {reason}")]
    NotRfc3339 { quoted: String, reason: String },
    #[error(transparent)]
    Time(clock::EventTimeError),
    #[error("rating {0} is not 1–4")]
    Rating(u8),
    #[error("duration {0} ms is not between 0 and a day")]
    Duration(i64),
    #[error("action \"{0}\" is not suspend, unsuspend or bury")]
    Action(String),
    #[error("the end of the bury, \"{0}\", is outside 1970 to 9899")]
    BuryEnd(String),
    #[error("a bury, and only a bury, has an end time (until)")]
    UntilWithoutBury,
    #[error("the suspend of a leech is derived on each machine")]
    LeechSuspend,
}

fn rating(n: u8) -> Result<Rating, BadLine> {
    Rating::from_number(i64::from(n)).ok_or(BadLine::Rating(n))
}

fn review_id(
    deck: &str,
    card: &str,
    direction: &str,
    at: &str,
    r: u8,
    now: DateTime<Utc>,
) -> Result<ReviewId, LineError> {
    Ok((
        ItemKey::parse(deck, card, direction)?,
        time(at, now)?.timestamp_millis(),
        rating(r)?,
    ))
}

impl SyncEvent {
    /// The review to merge, or why the line cannot be one.
    pub fn incoming(&self, now: DateTime<Utc>) -> Result<IncomingReview, LineError> {
        if self.event != "review" {
            return Err(BadLine::UnknownEvent(one_line(&self.event).into_owned()).into());
        }
        let key = ItemKey::parse(&self.deck, &self.card, &self.direction)?;
        let rating = rating(self.rating)?;
        let at = time(&self.reviewed_at, now)?;
        if !(0..=MAX_DURATION_MS).contains(&self.duration_ms) {
            return Err(BadLine::Duration(self.duration_ms).into());
        }
        Ok(IncomingReview {
            key,
            reviewed_at: at,
            rating,
            cram: self.cram,
            duration_ms: self.duration_ms,
            undone: self.undone,
            // Never trusted further than an interval can go; the replay
            // bounds it to the answer's fuzz range.
            balanced_days: self
                .balanced_days
                .filter(|d| (1..=clock::MAXIMUM_INTERVAL).contains(d)),
        })
    }
}

/// The longest time spent on one answer a line may give.
const MAX_DURATION_MS: i64 = 24 * 3600 * 1000;

impl SyncLine {
    /// The line checked for the merge (ids of the deck format, times from
    /// 1970 to this machine's clock `now` plus a day), or why it cannot be
    /// merged.
    pub fn check(&self, now: DateTime<Utc>) -> Result<Checked, LineError> {
        match self {
            SyncLine::Review(e) => e.incoming(now).map(Checked::Review),
            SyncLine::Status(s) => {
                let key = ItemKey::parse(&s.deck, &s.card, &s.direction)?;
                let at = time(&s.at, now)?;
                let action = StatusAction::parse(&s.action)
                    .filter(|a| *a != StatusAction::Leech)
                    .ok_or_else(|| BadLine::Action(one_line(&s.action).into_owned()))?;
                let until = match s.until.as_deref() {
                    Some(u) => {
                        let u = DateTime::parse_from_rfc3339(u)
                            .map(|t| t.with_timezone(&Utc))
                            .map_err(|e| BadLine::NotRfc3339 {
                                quoted: one_line(u).into_owned(),
                                reason: e.to_string(),
                            })?;
                        // Any end the log can write back (an unsuspend lifts
                        // a bury, however long).
                        if u < clock::earliest() || u > clock::latest() {
                            return Err(BadLine::BuryEnd(
                                one_line(s.until.as_deref().unwrap_or_default()).into_owned(),
                            )
                            .into());
                        }
                        Some(u)
                    }
                    None => None,
                };
                if (action == StatusAction::Bury) != until.is_some() {
                    return Err(BadLine::UntilWithoutBury.into());
                }
                let cause = match &s.cause {
                    Some(c) => Some(review_id(
                        &s.deck,
                        &c.card,
                        &c.direction,
                        &c.reviewed_at,
                        c.rating,
                        now,
                    )?),
                    None => None,
                };
                if action == StatusAction::Suspend && cause.is_some() {
                    return Err(BadLine::LeechSuspend.into());
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
            SyncLine::UndoReview(u) => review_id(
                &u.deck,
                &u.card,
                &u.direction,
                &u.reviewed_at,
                u.rating,
                now,
            )
            .map(Checked::UndoReview),
            SyncLine::UndoStatus(u) => {
                let key = ItemKey::parse(&u.deck, &u.card, &u.direction)?;
                let at = time(&u.at, now)?;
                let action = StatusAction::parse(&u.action)
                    .filter(|a| *a != StatusAction::Leech)
                    .ok_or_else(|| BadLine::Action(one_line(&u.action).into_owned()))?;
                Ok(Checked::UndoStatus((key, at.timestamp_millis(), action)))
            }
        }
    }

    fn parse(line: &str) -> Result<SyncLine, BadLine> {
        #[derive(Deserialize)]
        struct Kind<'a> {
            #[serde(borrow)]
            event: std::borrow::Cow<'a, str>,
        }
        let kind: Kind = serde_json::from_str(line).map_err(|e| BadLine::Json(e.to_string()))?;
        let e = |e: serde_json::Error| BadLine::Json(e.to_string());
        match kind.event.as_ref() {
            "review" => serde_json::from_str(line).map(SyncLine::Review).map_err(e),
            "status" => serde_json::from_str(line).map(SyncLine::Status).map_err(e),
            "undo_review" => serde_json::from_str(line)
                .map(SyncLine::UndoReview)
                .map_err(e),
            "undo_status" => serde_json::from_str(line)
                .map(SyncLine::UndoStatus)
                .map_err(e),
            other => Err(BadLine::NewerEvent(one_line(other).into_owned())),
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
    /// It may be read later: the last line, still being written, or a line
    /// dated after this machine's clock.
    pub later: bool,
}

/// The complete, well-formed lines of a sync file, checked against the
/// clock `now`. A last line without its newline is a write still under
/// way; a line that does not parse was garbled, or forged. Both are left
/// out and reported.
pub(crate) fn read_lines(text: &str, now: DateTime<Utc>) -> (Vec<Checked>, Vec<Skipped>) {
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
                    later: true,
                });
            }
            break;
        }
        if line.trim().is_empty() {
            continue;
        }
        if line.len() > MAX_LINE_BYTES {
            skipped.push(Skipped {
                line: i + 1,
                why: format!(
                    "the line is {} bytes long (at most {MAX_LINE_BYTES})",
                    line.len()
                ),
                later: false,
            });
            continue;
        }
        match SyncLine::parse(line)
            .map_err(LineError::Bad)
            .and_then(|l| l.check(now))
        {
            Ok(c) => lines_out.push(c),
            Err(e) => skipped.push(Skipped {
                line: i + 1,
                later: matches!(e, LineError::Later(_)),
                why: e.to_string(),
            }),
        }
    }
    (lines_out, skipped)
}

pub(crate) fn review_line(r: &IncomingReview) -> SyncEvent {
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
        balanced_days: r.balanced_days,
    }
}

/// The `undo_review` line of an answer.
pub(crate) fn undo_review_line(r: &IncomingReview) -> UndoReviewLine {
    UndoReviewLine {
        event: "undo_review".into(),
        deck: r.key.deck.clone(),
        card: r.key.card.clone(),
        direction: r.key.direction.as_str().into(),
        reviewed_at: rfc3339(r.reviewed_at),
        rating: r.rating as u8,
    }
}

/// The `status` line of a status event.
pub(crate) fn status_line(s: &IncomingStatus) -> StatusLine {
    StatusLine {
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
            reviewed_at: rfc3339(DateTime::from_timestamp_millis(*ms).unwrap_or_default()),
            rating: *r as u8,
        }),
        undone: s.undone,
    }
}

/// The `undo_status` line of a status event.
pub(crate) fn undo_status_line(s: &IncomingStatus) -> UndoStatusLine {
    UndoStatusLine {
        event: "undo_status".into(),
        deck: s.key.deck.clone(),
        card: s.key.card.clone(),
        direction: s.key.direction.as_str().into(),
        at: rfc3339(s.at),
        action: s.action.as_str().into(),
    }
}

/// One line, with its newline.
pub fn line(event: &SyncEvent) -> String {
    sync_line(&SyncLine::Review(event.clone()))
}

/// One line of any kind, with its newline.
pub(crate) fn sync_line(l: &SyncLine) -> String {
    let mut s = l.json().unwrap_or_default();
    s.push('\n');
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sched::Direction;

    fn now() -> DateTime<Utc> {
        DateTime::parse_from_rfc3339("2026-05-02T00:00:00Z")
            .unwrap()
            .with_timezone(&Utc)
    }

    fn read_events(text: &str) -> (Vec<IncomingReview>, Vec<Skipped>) {
        let (lines, skipped) = read_lines(text, now());
        let reviews = lines
            .into_iter()
            .filter_map(|l| match l {
                Checked::Review(r) => Some(r),
                _ => None,
            })
            .collect();
        (reviews, skipped)
    }

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
            balanced_days: None,
        }
    }

    #[test]
    fn half_lines_and_garbage_are_skipped_and_the_rest_read() {
        let a = line(&event("a", 1000));
        let b = line(&event("b", 2000));
        let text = format!("{a}{}\n{b}{}", &b[..20], &a[..a.len() - 5]);
        let (events, skipped) = read_events(&text);
        let want: Vec<IncomingReview> = [event("a", 1000), event("b", 2000)]
            .iter()
            .map(|e| e.incoming(now()).unwrap())
            .collect();
        assert_eq!(events, want);
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
        let (lines, skipped) = read_lines(ok, now());
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
            let (lines, skipped) = read_lines(&format!("{bad}\n"), now());
            assert!(lines.is_empty(), "{bad}");
            assert!(skipped[0].why.contains(why), "{bad}: {skipped:?}");
        }
    }

    #[test]
    fn a_derivation_is_an_item_a_line_may_name() {
        let mut e = event("derive-euler-equations", 1000);
        e.direction = "derive".into();
        let (events, skipped) = read_events(&line(&e));
        assert!(skipped.is_empty(), "{skipped:?}");
        assert_eq!(events[0].key.direction, Direction::Derive);
        assert_eq!(events[0].key.card, "derive-euler-equations");
        // An id no deck has is read like any other (the merge keeps its
        // history as an orphan's); a direction that is none is skipped.
        e.card = "no-such-derivation".into();
        let (events, _) = read_events(&line(&e));
        assert_eq!(events[0].key.card, "no-such-derivation");
        e.direction = "derived".into();
        let (events, skipped) = read_events(&line(&e));
        assert!(events.is_empty());
        assert!(skipped[0].why.contains("derived"), "{skipped:?}");
    }

    #[test]
    fn a_review_line_carries_the_balanced_day_only_when_there_is_one() {
        // Without one, the line is spelled as before (an older build reads it).
        let plain = line(&event("a", 1000));
        assert!(!plain.contains("balanced_days"), "{plain}");
        let (events, _) = read_events(&plain);
        assert_eq!(events[0].balanced_days, None);
        let mut e = event("a", 1000);
        e.balanced_days = Some(12);
        let text = line(&e);
        assert!(text.contains("\"balanced_days\":12"), "{text}");
        let (events, skipped) = read_events(&text);
        assert!(skipped.is_empty(), "{skipped:?}");
        assert_eq!(events[0].balanced_days, Some(12));
        // A value no interval can have is ignored: the answer is merged,
        // its day drawn as without one.
        for bad in [0, -3, 36_501, i64::MAX] {
            e.balanced_days = Some(bad);
            let (events, skipped) = read_events(&line(&e));
            assert!(skipped.is_empty(), "{skipped:?}");
            assert_eq!(events[0].balanced_days, None, "{bad}");
        }
        // Not a number: the line is not one of this format.
        let text = plain.replace(
            "\"undone\":false",
            "\"undone\":false,\"balanced_days\":\"12\"",
        );
        let (events, skipped) = read_events(&text);
        assert!(events.is_empty());
        assert!(
            skipped[0].why.contains("balanced_days") || skipped[0].why.contains("invalid type"),
            "{skipped:?}"
        );
    }

    proptest::proptest! {
        /// Any balanced day survives a line's write and read when an
        /// interval can have it, and is dropped (never the line) when not;
        /// the rest of the answer reads back the same either way.
        #[test]
        fn the_balanced_day_round_trips_through_a_line(
            day in proptest::option::of(proptest::prop_oneof![
                -10i64..40_000,
                proptest::num::i64::ANY,
            ]),
            ms in 0i64..1_777_000_000_000,
            rating in 1u8..=4,
            cram: bool,
            undone: bool,
        ) {
            let mut e = event("c", ms);
            e.rating = rating;
            e.cram = cram;
            e.undone = undone;
            e.balanced_days = day;
            let text = line(&e);
            let (events, skipped) = read_events(&text);
            proptest::prop_assert!(skipped.is_empty(), "{:?}", skipped);
            let got = &events[0];
            let want = day.filter(|d| (1..=36_500).contains(d));
            proptest::prop_assert_eq!(got.balanced_days, want);
            let mut without = e.clone();
            without.balanced_days = None;
            let (plain, _) = read_events(&line(&without));
            proptest::prop_assert_eq!(
                &IncomingReview { balanced_days: None, ..got.clone() },
                &plain[0]
            );
            // Written back, the line says what was read.
            let again = review_line(got);
            proptest::prop_assert_eq!(again.balanced_days, want);
        }
    }
}
