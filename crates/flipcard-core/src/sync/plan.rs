//! What one sync does, decided from what the folder's files hold and what
//! this machine's log holds, without touching either: which answers and
//! status events to merge (with the machine each came from), which to take
//! back, and which lines to add to this machine's file. Pure, so the rules
//! are tested (and property-tested) apart from files and SQLite.
//!
//! The rules that keep a forged or stale file from doing harm:
//!
//! - **Every event has an origin**, the machine whose file it came from
//!   (`None` in the log: this machine). An answer is the same answer when
//!   its item, time (to the millisecond), rating *and origin* agree: two
//!   machines answering alike in one millisecond (a frozen clock on both)
//!   gave two answers. A machine writes only its own events to its file,
//!   never another's, so a file speaks only for the machine that owns it.
//! - **Only the origin can take an event back.** An `undo_review` line, or
//!   `"undone": true` on a line, counts only in the file of the machine the
//!   event came from; a copy of another machine's line in a forged file is
//!   that file's own (undone, it changes nothing). An event is live or
//!   undone as its origin's file says: one undone here that its file shows
//!   live (taken back by a forged line before origins were kept) is brought
//!   back.
//! - **A machine's own file is read like any other.** When it holds what
//!   this log never wrote (the database was restored from a backup, or the
//!   data folder was copied to a second machine that writes under the same
//!   id), [`foreign_in_own`] says so, and the caller gives this machine a
//!   new id before planning: the old file is then another machine's, and
//!   everything in it comes back.
//! - This machine's rows that its own file does not hold but the file of one
//!   of its previous ids does, or (rows written before origins were kept)
//!   another machine's file does, came from there: they are stamped with
//!   that machine, once.
//!
//! Everything is ordered (by identity and origin) so that every machine
//! merges the same events in the same order.

use std::collections::{BTreeMap, HashMap, HashSet};
use std::hash::Hash;

use super::line::{
    Checked, SyncLine, review_line, status_line, undo_review_line, undo_status_line,
};
use crate::store::IncomingReview;
use crate::store::sync::Local;
use crate::store::sync_merge::{IncomingStatus, ReviewId, StatusId, SyncIncoming};

/// The checked lines of one file of the folder, and the machine that owns
/// it (the file's name up to its first dot).
#[derive(Debug, Clone)]
pub struct FileLines {
    pub machine: String,
    pub lines: Vec<Checked>,
}

/// What one sync does.
#[derive(Debug, Default)]
pub struct Plan {
    pub incoming: SyncIncoming,
    /// Lines for this machine's file, in the log's order (reviews first, so
    /// a status line follows the answer that caused it; undos last).
    pub write: Vec<SyncLine>,
    /// Answers live here that their machine undid: how many, by machine.
    pub undone_by: BTreeMap<String, usize>,
}

impl Plan {
    pub(crate) fn undos_of_answers(&self) -> usize {
        self.undone_by.values().sum()
    }
}

/// What one machine's files say of one event.
#[derive(Debug)]
struct One<'a, T> {
    /// Its first line (none when only an undo names it).
    line: Option<&'a T>,
    undone: bool,
}

impl<T> Default for One<'_, T> {
    fn default() -> Self {
        One {
            line: None,
            undone: false,
        }
    }
}

/// What the folder holds of one kind of event, by identity and machine
/// (machines by their index in `names`).
#[derive(Debug)]
struct Seen<'a, Id, T> {
    names: &'a [&'a str],
    by_machine: HashMap<(Id, usize), One<'a, T>>,
    /// The machines whose files hold each identity's line.
    holders: HashMap<Id, Vec<&'a str>>,
}

impl<'a, Id: Clone + Eq + Hash, T> Seen<'a, Id, T> {
    fn new(names: &'a [&'a str]) -> Self {
        Seen {
            names,
            by_machine: HashMap::new(),
            holders: HashMap::new(),
        }
    }
    fn line(&mut self, id: Id, machine: usize, line: &'a T, undone: bool) {
        let one = self.by_machine.entry((id.clone(), machine)).or_default();
        if one.line.is_none() {
            one.line = Some(line);
            let h = self.holders.entry(id).or_default();
            let name = self.names[machine];
            if !h.contains(&name) {
                h.push(name);
            }
        }
        one.undone |= undone;
    }
    fn undo(&mut self, id: Id, machine: usize) {
        self.by_machine.entry((id, machine)).or_default().undone = true;
    }
    fn get(&self, id: &Id, machine: Option<usize>) -> Option<&One<'a, T>> {
        self.by_machine.get(&(id.clone(), machine?))
    }
}

/// Whether two lines with one identity say the same thing. Two copies of
/// a data folder syncing under one id can make two different events with
/// one identity (a sibling bury on one and a bury by hand on the other, in
/// the same millisecond after the same answer): they must not pass for one.
trait Same {
    fn same(&self, other: &Self) -> bool;
}

impl Same for IncomingStatus {
    fn same(&self, other: &Self) -> bool {
        self.until == other.until && self.cause == other.cause
    }
}

impl Same for IncomingReview {
    fn same(&self, other: &Self) -> bool {
        self.cram == other.cram && self.duration_ms == other.duration_ms
    }
}

/// Where one of this machine's rows came from, when the log does not say:
/// this machine, unless its own file lacks it and the file of one of its
/// previous ids (or, for a row written before origins were kept, of any
/// other machine) holds it, the same (`holds`: whether that machine's
/// line says what the row says).
fn origin_of<'a>(
    me: &'a str,
    previous: &[String],
    legacy: bool,
    holders: Option<&Vec<&'a str>>,
    holds: impl Fn(&str) -> bool,
) -> (&'a str, bool) {
    let Some(holders) = holders else {
        return (me, false);
    };
    if holders.contains(&me) {
        return (me, false);
    }
    let mut from: Vec<&str> = holders
        .iter()
        .copied()
        .filter(|m| legacy || previous.iter().any(|p| p == m))
        .filter(|m| holds(m))
        .collect();
    from.sort_unstable();
    match from.first() {
        Some(m) => (m, true),
        None => (me, false),
    }
}

/// How many lines of `me`'s own files this log never wrote: an answer or a
/// status event it does not have as its own (or has, under the same
/// identity, saying something else), or one it has live shown undone. Zero
/// unless the database was restored from a backup or the data folder was
/// copied to a machine that writes under the same id.
pub(crate) fn foreign_in_own(me: &str, files: &[FileLines], local: &Local) -> usize {
    let reviews: HashMap<ReviewId, &IncomingReview> = local
        .reviews
        .iter()
        .filter(|r| r.origin.as_deref().is_none_or(|o| o == me))
        .map(|r| (r.review.review_id(), &r.review))
        .collect();
    let statuses: HashMap<StatusId, &IncomingStatus> = local
        .statuses
        .iter()
        .filter(|s| s.origin.as_deref().is_none_or(|o| o == me))
        .map(|s| (s.status.status_id(), &s.status))
        .collect();
    let mut foreign = 0;
    for file in files.iter().filter(|f| f.machine == me) {
        for line in &file.lines {
            let never_written = match line {
                Checked::Review(r) => match reviews.get(&r.review_id()) {
                    None => true,
                    Some(mine) => !r.same(mine) || (r.undone && !mine.undone),
                },
                Checked::UndoReview(id) => reviews.get(id).is_none_or(|mine| !mine.undone),
                Checked::Status(s) => match statuses.get(&s.status_id()) {
                    None => true,
                    Some(mine) => !s.same(mine) || (s.undone && !mine.undone),
                },
                Checked::UndoStatus(id) => statuses.get(id).is_none_or(|mine| !mine.undone),
            };
            foreign += usize::from(never_written);
        }
    }
    foreign
}

/// The sync of this machine, `me` (which synced as `previous` before),
/// given the folder's `files` and its log `local`. Call [`foreign_in_own`]
/// first: when `me`'s file holds what the log never wrote, plan under a new
/// id.
pub fn plan(me: &str, previous: &[String], files: &[FileLines], local: &Local) -> Plan {
    // Each machine once (a sync tool's copy of a file is its machine's).
    let mut names: Vec<&str> = files.iter().map(|f| f.machine.as_str()).collect();
    names.sort_unstable();
    names.dedup();
    let index: HashMap<&str, usize> = names.iter().enumerate().map(|(i, n)| (*n, i)).collect();
    let mut reviews: Seen<ReviewId, IncomingReview> = Seen::new(&names);
    let mut statuses: Seen<StatusId, IncomingStatus> = Seen::new(&names);
    for file in files {
        let m = index[file.machine.as_str()];
        for line in &file.lines {
            match line {
                Checked::Review(r) => reviews.line(r.review_id(), m, r, r.undone),
                Checked::UndoReview(id) => reviews.undo(id.clone(), m),
                Checked::Status(s) => statuses.line(s.status_id(), m, s, s.undone),
                Checked::UndoStatus(id) => statuses.undo(id.clone(), m),
            }
        }
    }
    let mut out = Plan::default();
    let incoming = &mut out.incoming;
    let mut write_undos = Vec::new();

    let mut known: HashSet<(ReviewId, String)> = HashSet::with_capacity(local.reviews.len());
    let mut write_reviews = Vec::new();
    for l in &local.reviews {
        let id = l.review.review_id();
        let origin: String = match &l.origin {
            Some(o) => o.clone(),
            None => {
                let holds = |m: &str| {
                    let line = reviews.get(&id, index.get(m).copied()).and_then(|o| o.line);
                    line.is_some_and(|line| line.same(&l.review))
                };
                let (o, stamp) = origin_of(me, previous, l.legacy, reviews.holders.get(&id), holds);
                if stamp {
                    incoming.stamp_reviews.push((id.clone(), o.to_string()));
                }
                o.to_string()
            }
        };
        if origin == me {
            let mine = reviews.get(&id, index.get(me).copied());
            let held = mine.is_some_and(|o| o.line.is_some());
            let shown_undone = mine.is_some_and(|o| o.undone);
            if !held {
                write_reviews.push(SyncLine::Review(review_line(&l.review)));
            } else if l.review.undone && !shown_undone {
                write_undos.push(SyncLine::UndoReview(undo_review_line(&l.review)));
            }
            if l.review.undone && !shown_undone {
                incoming.replay.push(id.clone());
            }
        } else if let Some(theirs) = reviews.get(&id, index.get(origin.as_str()).copied()) {
            if !l.review.undone && theirs.undone {
                incoming.undo_reviews.insert((id.clone(), origin.clone()));
                *out.undone_by.entry(origin.clone()).or_default() += 1;
            } else if l.review.undone
                && !theirs.undone
                && let Some(line) = theirs.line
            {
                // Its machine's file has it live: so it is (undone here by
                // a forged line before origins were kept, or by this
                // machine under an id it has since left).
                incoming.revive_reviews.push((line.clone(), origin.clone()));
            }
        }
        known.insert((id, origin));
    }
    for ((id, m), one) in &reviews.by_machine {
        let Some(line) = one.line else {
            continue;
        };
        let m = names[*m];
        if m == me || known.contains(&(id.clone(), m.to_string())) {
            continue;
        }
        incoming.reviews.push((
            IncomingReview {
                undone: one.undone,
                ..line.clone()
            },
            m.to_string(),
        ));
    }
    incoming
        .reviews
        .sort_by(|a, b| (a.0.review_id(), &a.1).cmp(&(b.0.review_id(), &b.1)));

    let mut known: HashSet<(StatusId, String)> = HashSet::with_capacity(local.statuses.len());
    let mut write_statuses = Vec::new();
    for l in &local.statuses {
        let id = l.status.status_id();
        let origin: String = match &l.origin {
            Some(o) => o.clone(),
            None => {
                let holds = |m: &str| {
                    let line = statuses
                        .get(&id, index.get(m).copied())
                        .and_then(|o| o.line);
                    line.is_some_and(|line| line.same(&l.status))
                };
                let (o, stamp) =
                    origin_of(me, previous, l.legacy, statuses.holders.get(&id), holds);
                if stamp {
                    incoming.stamp_statuses.push((id.clone(), o.to_string()));
                }
                o.to_string()
            }
        };
        if origin == me {
            let mine = statuses.get(&id, index.get(me).copied());
            let held = mine.is_some_and(|o| o.line.is_some());
            if !held {
                write_statuses.push(SyncLine::Status(status_line(&l.status)));
            } else if l.status.undone && !mine.is_some_and(|o| o.undone) {
                write_undos.push(SyncLine::UndoStatus(undo_status_line(&l.status)));
            }
        } else if let Some(theirs) = statuses.get(&id, index.get(origin.as_str()).copied()) {
            if !l.status.undone && theirs.undone {
                incoming.undo_statuses.insert((id.clone(), origin.clone()));
            } else if l.status.undone
                && !theirs.undone
                && let Some(line) = theirs.line
            {
                incoming
                    .revive_statuses
                    .push((line.clone(), origin.clone()));
            }
        }
        known.insert((id, origin));
    }
    for ((id, m), one) in &statuses.by_machine {
        let Some(line) = one.line else {
            continue;
        };
        let m = names[*m];
        if m == me || known.contains(&(id.clone(), m.to_string())) {
            continue;
        }
        incoming.statuses.push((
            IncomingStatus {
                undone: one.undone,
                ..line.clone()
            },
            m.to_string(),
        ));
    }
    incoming
        .statuses
        .sort_by(|a, b| (a.0.status_id(), &a.1).cmp(&(b.0.status_id(), &b.1)));

    out.write = write_reviews;
    out.write.extend(write_statuses);
    out.write.extend(write_undos);
    out
}

/// The machine a sync file belongs to: its name up to the first dot (a
/// copy a sync tool made of a conflicting version, `<id>.sync-conflict-….jsonl`,
/// belongs to the same machine).
pub(crate) fn machine_of(file_name: &str) -> &str {
    file_name.split('.').next().unwrap_or(file_name)
}
