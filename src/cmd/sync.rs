//! `flipcard sync [DIR]` (and `sync_dir` in the config, run when the app
//! opens and when it closes): merges every other machine's file into the
//! local log, then writes this machine's reviews, status events and undos
//! that the folder lacks to `DIR/<machine-id>.jsonl`. See `store::sync`
//! for the rules.

use std::collections::HashSet;
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, bail};

use crate::cmd::args::{Cli, SyncArgs};
use crate::cmd::paths;
use crate::deck::files::read_regular;
use crate::sched::config::LeechAction;
use crate::sched::{Config, Scheduler};
use crate::store::Store;
use crate::store::sync::{self, Checked, Known, SyncLine};
use crate::store::sync_merge::{LeechRule, SyncIncoming};
use crate::text::plural;

pub fn run(cli: &Cli, args: &SyncArgs) -> anyhow::Result<ExitCode> {
    crate::sched::clock::now()?;
    let config = Config::load(paths::config_file(cli.config.clone()).as_deref())?;
    let Some(dir) = args.dir.clone().or_else(|| config.sync_dir.clone()) else {
        bail!(
            "say which folder to sync through: flipcard sync DIR, or sync_dir = \"…\" in the config"
        );
    };
    let data = paths::data_dir(cli.data_dir.clone())?;
    let outcome = sync_with(&data, &dir, &config)?;
    for w in &outcome.warnings {
        crate::errln!("flipcard: warning: {w}");
    }
    crate::outln!("{}", outcome.summary(&dir))?;
    Ok(ExitCode::SUCCESS)
}

/// What one sync did.
#[derive(Debug, Default)]
pub struct Outcome {
    pub machine: String,
    /// Review lines written to this machine's file.
    pub written: usize,
    pub written_statuses: usize,
    pub written_undos: usize,
    pub machines: usize,
    /// Reviews merged from the other machines.
    pub merged: usize,
    pub merged_statuses: usize,
    /// Answers and status events taken back because another machine undid
    /// them.
    pub merged_undos: usize,
    /// Items whose leech mark was added, moved or taken back.
    pub leeches: usize,
    pub skipped_lines: usize,
    /// Files that could not be read (gone, a FIFO, a folder).
    pub skipped_files: usize,
    /// Files and lines skipped, and what the store warned of: said by the
    /// caller (a terminal line, or the app's status line).
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
                "; {} skipped, to be read next time",
                plural(self.skipped_lines, "line", "lines")
            ));
        }
        s
    }
}

/// This machine's id: made once (random, 128 bits) and kept in the data
/// dir, so renaming the host or copying the data dir keeps it.
pub fn machine_id(data: &Path) -> anyhow::Result<String> {
    let path = data.join("machine-id");
    let read = match fs::metadata(&path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        // A FIFO or a directory there is refused, never waited on.
        _ => Some(
            read_regular(&path)
                .map(|b| String::from_utf8_lossy(&b).into_owned())
                .map_err(|why| anyhow::anyhow!("{}: {why}", path.display())),
        ),
    };
    match read {
        Some(Ok(text)) => {
            let id = text.trim();
            if id.len() == 32 && id.bytes().all(|b| b.is_ascii_hexdigit()) {
                return Ok(id.to_ascii_lowercase());
            }
            bail!(
                "{}: not a machine id (32 hexadecimal digits); remove it to make a new one",
                path.display()
            );
        }
        Some(Err(e)) => return Err(e),
        None => {}
    }
    fs::create_dir_all(data).with_context(|| format!("cannot create {}", data.display()))?;
    let id = format!("{:032x}", rand::random::<u128>());
    let tmp = data.join(format!(".machine-id.{}.tmp", std::process::id()));
    write_synced(&tmp, id.as_bytes())?;
    // Two processes making an id at once: the first rename wins for both.
    match fs::hard_link(&tmp, &path) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
        Err(e) => return Err(e).with_context(|| format!("cannot write {}", path.display())),
    }
    let _ = fs::remove_file(&tmp);
    sync_folder(data);
    machine_id(data)
}

fn write_synced(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let mut f =
        fs::File::create(path).with_context(|| format!("cannot write {}", path.display()))?;
    f.write_all(bytes)
        .and_then(|()| f.sync_all())
        .with_context(|| format!("cannot write {}", path.display()))
}

fn sync_folder(dir: &Path) {
    if let Ok(d) = fs::File::open(dir) {
        let _ = d.sync_all();
    }
}

/// The sync files in `dir`: `*.jsonl` not hidden (temporary files are).
fn sync_files(dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut files: Vec<PathBuf> = fs::read_dir(dir)
        .with_context(|| format!("cannot read the sync folder {}", dir.display()))?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "jsonl"))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| !n.starts_with('.'))
        })
        .collect();
    files.sort();
    Ok(files)
}

/// One sync: merge the other machines' files, then write what the folder
/// lacks. The merge comes first so that an undo of an answer others have
/// seen is replayed here, in the merge's transaction, before it is
/// published; a sync killed between the two replays it again (a no-op) and
/// writes it next time.
pub fn sync_with(data: &Path, dir: &Path, config: &Config) -> anyhow::Result<Outcome> {
    let mut store = Store::open(data)?;
    let warnings: Vec<String> = store.warnings().iter().map(|w| w.to_string()).collect();
    let mut outcome = sync_store(&mut store, data, dir, config)?;
    outcome.warnings.splice(0..0, warnings);
    Ok(outcome)
}

/// [`sync_with`] through a store already open: the app's own connection,
/// when it syncs after a review session.
pub fn sync_store(
    store: &mut Store,
    data: &Path,
    dir: &Path,
    config: &Config,
) -> anyhow::Result<Outcome> {
    if !dir.is_dir() {
        if dir.exists() {
            bail!(
                "{}: not a folder (sync goes through a folder another tool keeps in step)",
                dir.display()
            );
        }
        bail!(
            "{}: no such folder (create it, or point the sync tool's folder there)",
            dir.display()
        );
    }
    let machine = machine_id(data)?;
    let mine = dir.join(format!("{machine}.jsonl"));
    let mut outcome = Outcome {
        machine: machine.clone(),
        ..Outcome::default()
    };

    // Everything the folder holds, by file.
    let mut known = Known::default();
    let mut others: Vec<Checked> = Vec::new();
    let mut mine_text = String::new();
    for file in sync_files(dir)? {
        let text = match read_regular(&file) {
            Ok(b) => String::from_utf8_lossy(&b).into_owned(),
            Err(why) => {
                outcome.warnings.push(format!(
                    "{}: {why}; skipped, to be read next time",
                    file.display()
                ));
                outcome.skipped_files += 1;
                continue;
            }
        };
        let (lines, skipped) = sync::read_lines(&text);
        for s in &skipped {
            outcome.warnings.push(format!(
                "{}:{}: skipped: {}; it is read again next time",
                file.display(),
                s.line,
                s.why
            ));
        }
        outcome.skipped_lines += skipped.len();
        for l in &lines {
            known.add(l);
        }
        if file == mine {
            // Only whole lines are kept when the file is extended.
            let end = text.rfind('\n').map_or(0, |i| i + 1);
            mine_text = text[..end].to_string();
        } else {
            outcome.machines += 1;
            others.extend(lines);
        }
    }

    let local = store.sync_local()?;
    let incoming = {
        let reviews = local.review_ids();
        let statuses = local.status_ids();
        let mut incoming = SyncIncoming::default();
        let mut seen_reviews = HashSet::new();
        let mut seen_statuses = HashSet::new();
        for l in others {
            match l {
                // Undone anywhere in the folder: it comes undone.
                Checked::Review(mut r) => {
                    let id = r.review_id();
                    r.undone |= known.undone_reviews.contains(&id);
                    if !reviews.contains_key(&id) && seen_reviews.insert(id) {
                        incoming.reviews.push(r);
                    }
                }
                Checked::Status(mut s) => {
                    let id = s.status_id();
                    s.undone |= known.undone_statuses.contains(&id);
                    if !statuses.contains_key(&id) && seen_statuses.insert(id) {
                        incoming.statuses.push(s);
                    }
                }
                Checked::UndoReview(_) | Checked::UndoStatus(_) => {}
            }
        }
        for (id, undone) in &reviews {
            match (undone, known.undone_reviews.contains(id)) {
                (false, true) => {
                    incoming.undo_reviews.insert(id.clone());
                }
                (true, false) => incoming.replay.push(id.clone()),
                _ => {}
            }
        }
        for (id, undone) in &statuses {
            if !undone && known.undone_statuses.contains(id) {
                incoming.undo_statuses.insert(id.clone());
            }
        }
        incoming
    };
    let leech = LeechRule {
        threshold: config.leech_threshold,
        suspend: config.leech_action == LeechAction::Suspend,
    };
    let merged = store.merge_sync(&incoming, &Scheduler::new(config), leech)?;
    outcome.merged = merged.reviews;
    outcome.merged_statuses = merged.statuses;
    outcome.merged_undos = merged.undos;
    outcome.leeches = merged.leeches;

    // The history read before the merge is enough: what the merge brought
    // is in the folder already, answers it re-appended keep their identity,
    // and leech events do not travel.
    let missing = local.missing(&known);
    if !missing.is_empty() {
        for l in &missing {
            mine_text.push_str(&sync::sync_line(l));
            match l {
                SyncLine::Review(_) => outcome.written += 1,
                SyncLine::Status(_) => outcome.written_statuses += 1,
                SyncLine::UndoReview(_) | SyncLine::UndoStatus(_) => outcome.written_undos += 1,
            }
        }
        // Stale temporary files of an interrupted sync go first.
        let prefix = format!(".{machine}.jsonl.");
        if let Ok(entries) = fs::read_dir(dir) {
            for e in entries.flatten() {
                if e.file_name().to_string_lossy().starts_with(&prefix) {
                    let _ = fs::remove_file(e.path());
                }
            }
        }
        let tmp = dir.join(format!("{prefix}{}.tmp", std::process::id()));
        write_synced(&tmp, mine_text.as_bytes())?;
        fs::rename(&tmp, &mine).with_context(|| format!("cannot write {}", mine.display()))?;
        sync_folder(dir);
    }
    Ok(outcome)
}
