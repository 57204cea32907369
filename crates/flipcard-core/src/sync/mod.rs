//! Sync between a learner's machines through a folder another tool keeps
//! in step (Syncthing, Dropbox, a network drive, a git repository): what
//! `flipcard sync` and the app (when it opens, after each session, when it
//! closes) do. The line format and the merge are the store's
//! (`store::sync`, `store::sync_merge`); the rules of who may change what
//! are [`plan`]'s.
//!
//! One sync, under the data folder's lock ([`machine::Lock`]):
//!
//! 1. The folder's files and the log are fingerprinted; when both are as
//!    the last complete sync left them, there is nothing to do.
//! 2. Every `*.jsonl` file is read (this machine's own included: a restored
//!    database gets its answers back from it), each line checked: ids of the
//!    deck format, times from 1970 to this machine's clock plus a day. A
//!    line that cannot be read is said once (per file, with a count), not at
//!    every sync.
//! 3. When this machine's file holds what its log never wrote, the data
//!    folder was copied (or the database restored): this machine takes a
//!    new id, and reads its old file as another machine's.
//! 4. The plan is merged in one transaction, then the lines the folder
//!    lacks are added to this machine's file (written whole under a
//!    temporary name, fsynced, renamed over the old one).

pub mod background;
pub mod error;
pub mod line;
pub mod machine;
pub mod plan;

use std::path::{Path, PathBuf};

use chrono::{DateTime, Utc};

use self::line::SyncLine;
use crate::sched::clock::Clock;
use crate::sched::config::LeechAction;
use crate::sched::{Config, Schedulers};
use crate::store::sync_merge::LeechRule;
use crate::store::{OpenOptions, Store};
use flipcard_io::{self as disk, Durability};
use flipcard_text::plural;

pub use error::SyncError;
pub use machine::Wait;
use plan::FileLines;

/// The largest sync file read: a machine's file grows by about 200 bytes an
/// answer, so this is millions of answers.
pub(crate) const MAX_FILE_BYTES: u64 = 1 << 30;

/// How many answers one sync may take back before it says so loudly.
pub(crate) const LOUD_UNDOS: usize = 5;

/// What one sync did.
#[derive(Debug, Default)]
pub struct Outcome {
    pub machine: String,
    /// Review lines written to this machine's file.
    pub written: usize,
    pub written_statuses: usize,
    pub written_undos: usize,
    pub machines: usize,
    /// Reviews merged from the folder.
    pub merged: usize,
    pub merged_statuses: usize,
    /// Answers and status events taken back because the machine they came
    /// from undid them.
    pub merged_undos: usize,
    /// Items whose leech mark was added, moved or taken back.
    pub leeches: usize,
    /// Lines left out this time (said in `warnings` the first time only).
    pub skipped_lines: usize,
    /// Files that could not be read (gone, a FIFO, a folder).
    pub skipped_files: usize,
    /// Nothing changed in the folder or the log since the last sync.
    pub unchanged: bool,
    /// The id this machine had before this sync gave it a new one.
    pub previous_machine: Option<String>,
    /// What the caller should say (a terminal line each, or the app's
    /// status line): files and lines left out, a new machine id, many
    /// answers taken back.
    pub warnings: Vec<String>,
}

fn counts(reviews: usize, statuses: usize, undos: usize) -> String {
    let mut s = plural(reviews, "review", "reviews");
    if statuses > 0 {
        s.push_str(&format!(
            ", {}",
            plural(statuses, "status change", "status changes")
        ));
    }
    if undos > 0 {
        s.push_str(&format!(", {}", plural(undos, "undo", "undos")));
    }
    s
}

impl Outcome {
    pub fn summary(&self, dir: &Path) -> String {
        if self.unchanged {
            return format!(
                "synced through {}: nothing new since the last sync ({}.jsonl)",
                dir.display(),
                self.machine
            );
        }
        let mut s = format!(
            "synced through {}: {} written to {}.jsonl; {} merged from {}",
            dir.display(),
            counts(self.written, self.written_statuses, self.written_undos),
            self.machine,
            counts(self.merged, self.merged_statuses, self.merged_undos),
            plural(self.machines, "other machine", "other machines"),
        );
        if self.leeches > 0 {
            s.push_str(&format!(
                "; {} updated",
                plural(self.leeches, "leech mark", "leech marks")
            ));
        }
        if self.skipped_files > 0 {
            s.push_str(&format!(
                "; {} skipped",
                plural(self.skipped_files, "file", "files")
            ));
        }
        if self.skipped_lines > 0 {
            s.push_str(&format!(
                "; {} left out",
                plural(self.skipped_lines, "line", "lines")
            ));
        }
        s
    }
}

/// One sync of the data folder `data` through `dir`, at `now`, on a
/// connection of its own.
pub fn sync_with(
    data: &Path,
    dir: &Path,
    config: &Config,
    now: DateTime<Utc>,
    wait: Wait,
) -> Result<Outcome, SyncError> {
    let lock = machine::Lock::take(data, wait)?;
    let options = OpenOptions {
        daily_backup: false,
        clock: Clock::Fixed(now),
        ..OpenOptions::default()
    };
    let mut store = Store::open_with(data, &options)?;
    let warnings: Vec<String> = store.warnings().iter().map(|w| w.to_string()).collect();
    let mut outcome = locked(&mut store, data, dir, config, now)?;
    drop(lock);
    outcome.warnings.splice(0..0, warnings);
    Ok(outcome)
}

/// One file of the folder, as found.
struct Found {
    path: PathBuf,
    name: String,
    /// What changes when the file does (size, time, inode); `None` when it
    /// is not a file to read.
    stamp: Option<String>,
}

/// The sync files of `dir`: `*.jsonl`, not hidden (temporary files are),
/// by name.
fn sync_files(dir: &Path) -> Result<Vec<Found>, SyncError> {
    use std::os::unix::fs::MetadataExt;
    let files = disk::visible_files(dir, "jsonl").map_err(|source| SyncError::ReadFolder {
        path: dir.to_path_buf(),
        source,
    })?;
    Ok(files
        .into_iter()
        .map(|(path, name)| {
            let stamp = match disk::metadata(&path) {
                Ok(m) if m.is_file() => Some(format!(
                    "{}.{}.{}.{}",
                    m.len(),
                    m.mtime(),
                    m.mtime_nsec(),
                    m.ino()
                )),
                // Not a regular file, or gone: read as "unreadable".
                _ => None,
            };
            Found { path, name, stamp }
        })
        .collect())
}

fn fingerprint(
    me: &str,
    leech: LeechRule,
    store: &Store,
    files: &[Found],
) -> Result<String, SyncError> {
    let mut fp = format!(
        "v1 {me} {} {} {}",
        leech.threshold,
        leech.suspend,
        store.log_fingerprint()?
    );
    for f in files {
        fp.push_str(&format!(
            " {}={}",
            f.name,
            f.stamp.as_deref().unwrap_or("unreadable")
        ));
    }
    Ok(fp)
}

/// A sync file's text, or the error its warning says.
fn read_file(path: &Path) -> std::io::Result<String> {
    disk::read_regular_limited(path, MAX_FILE_BYTES)
        .map(|bytes| String::from_utf8_lossy(&bytes).into_owned())
}

/// Why a sync file was not read, for its warning.
fn unread(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::Other => e.to_string(),
        _ => disk::cannot_read(e),
    }
}

fn locked(
    store: &mut Store,
    data: &Path,
    dir: &Path,
    config: &Config,
    now: DateTime<Utc>,
) -> Result<Outcome, SyncError> {
    if !dir.is_dir() {
        if dir.exists() {
            return Err(SyncError::NotAFolder(dir.to_path_buf()));
        }
        return Err(SyncError::NoFolder(dir.to_path_buf()));
    }
    let dir_key = dir
        .canonicalize()
        .unwrap_or_else(|_| dir.to_path_buf())
        .display()
        .to_string();
    let mut me = machine::id(data)?;
    let leech = LeechRule {
        threshold: config.leech_threshold,
        suspend: config.leech_action == LeechAction::Suspend,
    };
    let mut outcome = Outcome {
        machine: me.clone(),
        ..Outcome::default()
    };

    let found = sync_files(dir)?;
    let before = fingerprint(&me, leech, store, &found)?;
    if store.sync_fingerprint(&dir_key)?.as_deref() == Some(before.as_str()) {
        outcome.unchanged = true;
        return Ok(outcome);
    }

    // Everything the folder holds, by file.
    let reported = store.reported_through(&dir_key)?;
    let mut files: Vec<FileLines> = Vec::new();
    let mut mine_text = String::new();
    let mut read_again = false;
    let mut reported_now: Vec<(String, usize)> = Vec::new();
    for f in &found {
        let text = match read_file(&f.path) {
            Ok(text) => text,
            Err(e) => {
                outcome.warnings.push(format!(
                    "{}: {}; skipped, to be read next time",
                    f.path.display(),
                    unread(&e)
                ));
                outcome.skipped_files += 1;
                read_again = true;
                continue;
            }
        };
        let (lines, skipped) = line::read_lines(&text, now);
        outcome.skipped_lines += skipped.len();
        read_again |= skipped.iter().any(|s| s.later);
        // Each problem said once: a written line never changes. Lines that
        // can never be read, and lines to be read again (the last one, still
        // being copied; one dated after this machine's clock), apart.
        let said = reported.get(&f.name).copied().unwrap_or(0);
        let mut through = said;
        for later in [false, true] {
            let new: Vec<_> = skipped
                .iter()
                .filter(|s| s.line > said && s.later == later)
                .collect();
            let Some(first) = new.first() else {
                continue;
            };
            let more = match (new.len(), later) {
                (1, _) => String::new(),
                (n, _) => format!(" (and {} more)", n - 1),
            };
            let what = if later {
                "read again at the next sync"
            } else if new.len() == 1 {
                "the line is left out"
            } else {
                "the lines are left out"
            };
            outcome.warnings.push(format!(
                "{}:{}: skipped: {}{more}; {what}",
                f.path.display(),
                first.line,
                first.why,
            ));
            through = through.max(new.iter().map(|s| s.line).max().unwrap_or(said));
        }
        if through > said {
            reported_now.push((f.name.clone(), through));
        }
        let machine = plan::machine_of(&f.name).to_string();
        if f.name == format!("{me}.jsonl") {
            // Only whole lines are kept when the file is extended.
            let end = text.rfind('\n').map_or(0, |i| i + 1);
            mine_text = text[..end].to_string();
        } else if machine != me {
            outcome.machines += 1;
        }
        files.push(FileLines { machine, lines });
    }

    let local = store.sync_local()?;
    let mut previous = store.previous_machine_ids()?;
    let foreign = plan::foreign_in_own(&me, &files, &local);
    if foreign > 0 {
        let old = me.clone();
        // Kept before the new id is: its rows found in the old file then
        // come from there, whenever this sync is cut short.
        store.add_previous_machine_id(&old)?;
        previous.push(old.clone());
        me = machine::renew(data)?;
        outcome.warnings.push(format!(
            "{old}.jsonl, this machine's sync file, holds {} this database never wrote: \
             the database was restored from a backup, or this data folder was copied to \
             another machine that syncs under the same id. This machine now syncs as {me}, \
             and reads {old}.jsonl like another machine's file.",
            plural(foreign, "line", "lines")
        ));
        outcome.previous_machine = Some(old);
        outcome.machine = me.clone();
        outcome.machines += 1;
        mine_text.clear();
    }

    let plan = plan::plan(&me, &previous, &files, &local);
    let undone = plan.undos_of_answers();
    if undone > LOUD_UNDOS {
        let by: Vec<String> = plan
            .undone_by
            .iter()
            .map(|(m, n)| format!("{n} by {m}.jsonl"))
            .collect();
        outcome.warnings.push(format!(
            "this sync takes back {} that other machines undid ({}). If the learner did not \
             undo them, a sync file was damaged or forged: `flipcard db restore` brings the \
             database back to a daily copy; remove the file from the folder first.",
            plural(undone, "answer", "answers"),
            by.join(", ")
        ));
    }
    let merged = store.merge_sync(&plan.incoming, &Schedulers::new(config), leech)?;
    outcome.merged = merged.reviews;
    outcome.merged_statuses = merged.statuses;
    outcome.merged_undos = merged.undos;
    outcome.leeches = merged.leeches;
    for (name, line) in &reported_now {
        store.set_reported_through(&dir_key, name, *line)?;
    }

    if !plan.write.is_empty() {
        let mine = dir.join(format!("{me}.jsonl"));
        for l in &plan.write {
            mine_text.push_str(&line::sync_line(l));
            match l {
                SyncLine::Review(_) => outcome.written += 1,
                SyncLine::Status(_) => outcome.written_statuses += 1,
                SyncLine::UndoReview(_) | SyncLine::UndoStatus(_) => outcome.written_undos += 1,
            }
        }
        // Temporary files of an interrupted sync of this machine go first
        // (the lock says no other sync of it runs).
        for stale in disk::entries_starting_with(dir, &format!(".{me}.jsonl.")) {
            let _ = disk::remove_file(stale);
        }
        if let Err(source) = disk::write_atomic(&mine, mine_text.as_bytes(), Durability::Synced) {
            return Err(SyncError::Write { path: mine, source });
        }
    }

    // What the next sync compares with: the folder and the log as this one
    // leaves them (not kept when a line is to be read again).
    let after = (!read_again)
        .then(|| fingerprint(&me, leech, store, &sync_files(dir)?))
        .transpose()?;
    store.set_sync_fingerprint(&dir_key, after.as_deref())?;
    Ok(outcome)
}
