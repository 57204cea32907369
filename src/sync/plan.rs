//! What one sync does, decided from what the folder's files hold and what
//! this machine's log holds, without touching either: which answers and
//! status events to merge (with the machine each came from), which to take
//! back, and which lines to add to this machine's file. Pure, so the rules
//! are tested (and property-tested) apart from files and SQLite.
//!
//! The rules that keep a forged or stale file from doing harm:
//!
//! - **Every event has an origin**, the machine whose file it first came
//!   from (`None` in the log: this machine). A machine writes only its own
//!   events to its file, never another's, so a file speaks only for the
//!   machine that owns it.
//! - **Only the origin can take an event back.** An `undo_review` line, or
//!   `"undone": true` on a copy of a line, counts only in the file of the
//!   machine the event came from. An event seen first in several files at
//!   once comes undone only if every one of them shows it undone.
//! - **A machine's own file is read like any other.** When it holds what
//!   this log never wrote (the database was restored from a backup, or the
//!   data folder was copied to a second machine that writes under the same
//!   id), [`foreign_in_own`] says so, and the caller gives this machine a
//!   new id before planning: the old file is then another machine's, and
//!   everything in it comes back.
//! - This machine's rows that another file holds and its own does not were
//!   merged before origins were kept (or written under its previous id):
//!   they are stamped with that machine, once.
//!
//! Everything is ordered (by identity) so that every machine merges the
//! same events in the same order.

use std::collections::{BTreeMap, HashMap, HashSet};

use crate::store::IncomingReview;
use crate::store::sync::{
    Checked, Local, SyncLine, review_line, status_line, undo_review_line, undo_status_line,
};
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
    pub fn undos_of_answers(&self) -> usize {
        self.undone_by.values().sum()
    }
}

/// What the folder says of one event.
#[derive(Debug)]
struct Seen<'a, T> {
    /// Each machine whose file holds the event's line, with its first line.
    lines: BTreeMap<&'a str, &'a T>,
    /// Each machine whose file shows the event undone.
    undone_by: HashSet<&'a str>,
}

impl<T> Default for Seen<'_, T> {
    fn default() -> Self {
        Seen {
            lines: BTreeMap::new(),
            undone_by: HashSet::new(),
        }
    }
}

impl<'a, T> Seen<'a, T> {
    fn holds(&self, machine: &str) -> bool {
        self.lines.contains_key(machine)
    }
    /// The first machine (by id) holding the event, other than `me`.
    fn other_holder(&self, me: &str) -> Option<&'a str> {
        self.lines.keys().copied().find(|m| *m != me)
    }
    /// Who the event came from when this log has not seen it: its one
    /// holder, or the first of several (which then must all show it undone
    /// to take it back). Returns (origin, undone).
    fn origin_and_undone(&self) -> Option<(&'a str, bool)> {
        let first = *self.lines.keys().next()?;
        let undone = self.lines.keys().all(|m| self.undone_by.contains(m));
        Some((first, undone))
    }
}

/// What the folder holds, by identity.
#[derive(Debug, Default)]
struct Folder<'a> {
    reviews: HashMap<ReviewId, Seen<'a, IncomingReview>>,
    statuses: HashMap<StatusId, Seen<'a, IncomingStatus>>,
}

impl<'a> Folder<'a> {
    fn of(files: &'a [FileLines]) -> Folder<'a> {
        let mut f = Folder::default();
        for file in files {
            let m = file.machine.as_str();
            for line in &file.lines {
                match line {
                    Checked::Review(r) => {
                        let seen = f.reviews.entry(r.review_id()).or_default();
                        seen.lines.entry(m).or_insert(r);
                        if r.undone {
                            seen.undone_by.insert(m);
                        }
                    }
                    Checked::UndoReview(id) => {
                        f.reviews.entry(id.clone()).or_default().undone_by.insert(m);
                    }
                    Checked::Status(s) => {
                        let seen = f.statuses.entry(s.status_id()).or_default();
                        seen.lines.entry(m).or_insert(s);
                        if s.undone {
                            seen.undone_by.insert(m);
                        }
                    }
                    Checked::UndoStatus(id) => {
                        f.statuses
                            .entry(id.clone())
                            .or_default()
                            .undone_by
                            .insert(m);
                    }
                }
            }
        }
        f
    }
}

/// How many lines of `me`'s own files this log never wrote: an answer or a
/// status event it does not have, or one it has live shown undone. Zero
/// unless the database was restored from a backup or the data folder was
/// copied to a machine that writes under the same id.
pub fn foreign_in_own(me: &str, files: &[FileLines], local: &Local) -> usize {
    let reviews: HashMap<ReviewId, bool> = local
        .reviews
        .iter()
        .map(|r| (r.review.review_id(), r.review.undone))
        .collect();
    let statuses: HashMap<StatusId, bool> = local
        .statuses
        .iter()
        .map(|s| (s.status.status_id(), s.status.undone))
        .collect();
    let mut foreign = 0;
    for file in files.iter().filter(|f| f.machine == me) {
        for line in &file.lines {
            let never_written = match line {
                Checked::Review(r) => match reviews.get(&r.review_id()) {
                    None => true,
                    Some(undone) => r.undone && !undone,
                },
                Checked::UndoReview(id) => reviews.get(id).is_none_or(|undone| !undone),
                Checked::Status(s) => match statuses.get(&s.status_id()) {
                    None => true,
                    Some(undone) => s.undone && !undone,
                },
                Checked::UndoStatus(id) => statuses.get(id).is_none_or(|undone| !undone),
            };
            foreign += usize::from(never_written);
        }
    }
    foreign
}

/// The sync of this machine, `me`, given the folder's `files` and its log
/// `local`. Call [`foreign_in_own`] first: when `me`'s file holds what the
/// log never wrote, plan under a new id.
pub fn plan(me: &str, files: &[FileLines], local: &Local) -> Plan {
    let folder = Folder::of(files);
    let mut out = Plan::default();
    let incoming = &mut out.incoming;

    let mut local_reviews: HashSet<ReviewId> = HashSet::with_capacity(local.reviews.len());
    let mut write_reviews = Vec::new();
    let mut write_undos = Vec::new();
    for l in &local.reviews {
        let id = l.review.review_id();
        let seen = folder.reviews.get(&id);
        let held_by_me = seen.is_some_and(|s| s.holds(me));
        let origin: &str = match &l.origin {
            Some(o) => o,
            None => match seen.and_then(|s| s.other_holder(me)) {
                Some(other) if !held_by_me => {
                    incoming.stamp_reviews.push((id.clone(), other.to_string()));
                    other
                }
                _ => me,
            },
        };
        let shown_undone_by = |m: &str| seen.is_some_and(|s| s.undone_by.contains(m));
        if origin == me {
            let shown_undone = shown_undone_by(me);
            if !held_by_me {
                write_reviews.push(SyncLine::Review(review_line(&l.review)));
            } else if l.review.undone && !shown_undone {
                write_undos.push(SyncLine::UndoReview(undo_review_line(&l.review)));
            }
            if l.review.undone && !shown_undone {
                incoming.replay.push(id.clone());
            }
        } else if !l.review.undone && shown_undone_by(origin) {
            incoming.undo_reviews.insert(id.clone());
            *out.undone_by.entry(origin.to_string()).or_default() += 1;
        }
        local_reviews.insert(id);
    }
    for (id, seen) in &folder.reviews {
        if local_reviews.contains(id) {
            continue;
        }
        let Some((origin, undone)) = seen.origin_and_undone() else {
            continue;
        };
        let line = seen.lines[origin];
        incoming.reviews.push((
            IncomingReview {
                undone,
                ..line.clone()
            },
            origin.to_string(),
        ));
    }
    incoming.reviews.sort_by_key(|r| r.0.review_id());

    let mut local_statuses: HashSet<StatusId> = HashSet::with_capacity(local.statuses.len());
    let mut write_statuses = Vec::new();
    for l in &local.statuses {
        let id = l.status.status_id();
        let seen = folder.statuses.get(&id);
        let held_by_me = seen.is_some_and(|s| s.holds(me));
        let origin: &str = match &l.origin {
            Some(o) => o,
            None => match seen.and_then(|s| s.other_holder(me)) {
                Some(other) if !held_by_me => {
                    incoming
                        .stamp_statuses
                        .push((id.clone(), other.to_string()));
                    other
                }
                _ => me,
            },
        };
        let shown_undone_by = |m: &str| seen.is_some_and(|s| s.undone_by.contains(m));
        if origin == me {
            if !held_by_me {
                write_statuses.push(SyncLine::Status(status_line(&l.status)));
            } else if l.status.undone && !shown_undone_by(me) {
                write_undos.push(SyncLine::UndoStatus(undo_status_line(&l.status)));
            }
        } else if !l.status.undone && shown_undone_by(origin) {
            incoming.undo_statuses.insert(id.clone());
        }
        local_statuses.insert(id);
    }
    for (id, seen) in &folder.statuses {
        if local_statuses.contains(id) {
            continue;
        }
        let Some((origin, undone)) = seen.origin_and_undone() else {
            continue;
        };
        let line = seen.lines[origin];
        incoming.statuses.push((
            IncomingStatus {
                undone,
                ..line.clone()
            },
            origin.to_string(),
        ));
    }
    incoming.statuses.sort_by_key(|s| s.0.status_id());

    out.write = write_reviews;
    out.write.extend(write_statuses);
    out.write.extend(write_undos);
    out
}

/// The machine a sync file belongs to: its name up to the first dot (a
/// copy a sync tool made of a conflicting version, `<id>.sync-conflict-….jsonl`,
/// belongs to the same machine).
pub fn machine_of(file_name: &str) -> &str {
    file_name.split('.').next().unwrap_or(file_name)
}
