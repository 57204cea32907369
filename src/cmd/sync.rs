//! `flipcard sync [DIR]` (and `sync_dir` in the config, run when the app
//! opens and when it closes): writes this machine's reviews that the
//! folder lacks to `DIR/<machine-id>.jsonl`, then merges every other
//! machine's file into the local log. See `store::sync` for the rules.

use std::collections::HashSet;
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, bail};

use crate::cmd::args::{Cli, SyncArgs};
use crate::cmd::paths;
use crate::sched::{Config, Scheduler};
use crate::store::Store;
use crate::store::sync::{self, Identity, SyncEvent};
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
    crate::outln!("{}", outcome.summary(&dir))?;
    Ok(ExitCode::SUCCESS)
}

/// What one sync did.
#[derive(Debug, Default)]
pub struct Outcome {
    pub machine: String,
    pub written: usize,
    pub machines: usize,
    pub merged: usize,
    pub duplicates: usize,
    pub skipped_lines: usize,
}

impl Outcome {
    pub fn summary(&self, dir: &Path) -> String {
        let mut s = format!(
            "synced through {}: {} written to {}.jsonl; {} merged from {}",
            dir.display(),
            plural(self.written, "review", "reviews"),
            self.machine,
            plural(self.merged, "review", "reviews"),
            plural(self.machines, "other machine", "other machines"),
        );
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
    match fs::read_to_string(&path) {
        Ok(text) => {
            let id = text.trim();
            if id.len() == 32 && id.bytes().all(|b| b.is_ascii_hexdigit()) {
                return Ok(id.to_ascii_lowercase());
            }
            bail!(
                "{}: not a machine id (32 hexadecimal digits); remove it to make a new one",
                path.display()
            );
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(e).with_context(|| format!("cannot read {}", path.display())),
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

/// One sync: write what the folder lacks, then merge the other machines'.
pub fn sync_with(data: &Path, dir: &Path, config: &Config) -> anyhow::Result<Outcome> {
    if !dir.is_dir() {
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
    let mut in_folder: HashSet<Identity> = HashSet::new();
    let mut others: Vec<SyncEvent> = Vec::new();
    let mut mine_text = String::new();
    for file in sync_files(dir)? {
        let text = match fs::read(&file) {
            Ok(b) => String::from_utf8_lossy(&b).into_owned(),
            Err(e) => {
                crate::errln!(
                    "flipcard: warning: {}: cannot be read ({e}); skipped, to be read next time",
                    file.display()
                );
                outcome.skipped_lines += 1;
                continue;
            }
        };
        let (events, skipped) = sync::read_events(&text);
        for s in &skipped {
            crate::errln!(
                "flipcard: warning: {}:{}: skipped: {}; it is read again next time",
                file.display(),
                s.line,
                s.why
            );
        }
        outcome.skipped_lines += skipped.len();
        in_folder.extend(events.iter().filter_map(SyncEvent::identity));
        if file == mine {
            // Only whole lines are kept when the file is extended.
            let end = text.rfind('\n').map_or(0, |i| i + 1);
            mine_text = text[..end].to_string();
        } else {
            outcome.machines += 1;
            others.extend(events);
        }
    }

    let mut store = Store::open(data)?;
    for w in store.warnings() {
        crate::errln!("flipcard: warning: {w}");
    }
    let local = store.sync_events()?;
    let missing = sync::missing(&local, &in_folder);
    if !missing.is_empty() {
        for e in &missing {
            mine_text.push_str(&sync::line(e));
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
        outcome.written = missing.len();
    }

    let local_ids: HashSet<Identity> = local.iter().filter_map(SyncEvent::identity).collect();
    let mut seen: HashSet<Identity> = HashSet::new();
    let incoming: Vec<_> = others
        .iter()
        .filter(|e| {
            e.identity()
                .is_some_and(|id| !local_ids.contains(&id) && seen.insert(id))
        })
        .filter_map(|e| e.incoming().ok())
        .collect();
    if !incoming.is_empty() {
        let summary = store.merge_reviews(&incoming, &Scheduler::new(config))?;
        outcome.merged = summary.added;
        outcome.duplicates = summary.duplicates;
    }
    Ok(outcome)
}
