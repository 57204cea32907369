//! The deck sources, in order: the bundled decks, the learner's library
//! (`<data dir>/decks/`), the config's `deck_paths`, then each `--decks`.
//! Every command that opens decks goes through here, so they all see the
//! same decks. Changes to the library (`decks add`, `decks remove`) are
//! made here too, journaled so that a run killed part way is finished by
//! the next one.

use std::io;

use crate::io as disk;
use std::path::{Path, PathBuf};

use anyhow::Context;

use crate::bundled;
use crate::cmd::args::Cli;
use crate::cmd::paths;
use crate::deck::files::{Disk, Tree};
use crate::deck::{DeckCache, FileStatus, Loaded, load_sources_cached};
use crate::sched::Config;
use crate::text::plural;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Origin {
    Bundled,
    Library,
    Config,
    CommandLine,
}

impl Origin {
    pub fn name(self) -> &'static str {
        match self {
            Origin::Bundled => "bundled",
            Origin::Library => "library",
            Origin::Config => "config",
            Origin::CommandLine => "--decks",
        }
    }
}

#[derive(Debug, Clone)]
pub struct Source {
    pub origin: Origin,
    /// The folder (for the bundled decks, their folder in the repository).
    pub path: PathBuf,
}

/// Every deck of every source, with what became of each deck file.
pub struct Library {
    pub sources: Vec<Source>,
    pub loaded: Loaded,
    pub files: Vec<FileStatus>,
}

impl Library {
    /// Deck files that failed to load (their decks are left out).
    pub fn failed(&self) -> Vec<&FileStatus> {
        self.files.iter().filter(|f| f.deck.is_none()).collect()
    }

    pub fn source_of(&self, file: &FileStatus) -> &Source {
        &self.sources[file.source]
    }

    /// Leaves the bundled decks out of `loaded.decks` (`hide_bundled`);
    /// a deck elsewhere that names one as its parent then sits at the top.
    pub fn hide_bundled(&mut self) {
        let bundled: Vec<usize> = self
            .files
            .iter()
            .filter(|f| self.sources[f.source].origin == Origin::Bundled)
            .filter_map(|f| f.deck)
            .collect();
        let mut index = 0;
        let mut new_index = vec![None; self.loaded.decks.len()];
        self.loaded.decks = std::mem::take(&mut self.loaded.decks)
            .into_iter()
            .enumerate()
            .filter_map(|(i, d)| {
                (!bundled.contains(&i)).then(|| {
                    new_index[i] = Some(index);
                    index += 1;
                    d
                })
            })
            .collect();
        for f in &mut self.files {
            f.deck = f.deck.and_then(|i| new_index.get(i).copied().flatten());
        }
        self.files
            .retain(|f| self.sources[f.source].origin != Origin::Bundled);
    }
}

/// The library folder: `<data dir>/decks/` (content in `<data dir>/content/`).
pub fn library_dir(data_dir: &Path) -> PathBuf {
    data_dir.join("decks")
}

/// The config, for its deck sources; a config that cannot be read is a
/// warning here (the commands that need the rest of it refuse it).
fn config(cli: &Cli) -> Config {
    match Config::load(paths::config_file(cli.config.clone()).as_deref()) {
        Ok(c) => c,
        Err(e) => {
            crate::errln!("flipcard: warning: {e}; its deck_paths are not used");
            Config::default()
        }
    }
}

/// The sources in order; folders that do not exist are left out, except
/// those named on the command line (a typo there must show).
pub fn sources(cli: &Cli, config: &Config) -> Vec<Source> {
    let mut out = vec![Source {
        origin: Origin::Bundled,
        path: PathBuf::from(bundled::DECKS),
    }];
    if let Ok(data) = paths::data_dir(cli.data_dir.clone()) {
        // A change a killed `decks add` or `decks remove` left half done
        // is finished before anything reads the library.
        if let Err(e) = recover(&data) {
            crate::errln!(
                "flipcard: warning: an unfinished change to the deck library could not be finished: {}",
                crate::cmd::output::chain_text(&e)
            );
        }
        let dir = library_dir(&data);
        if dir.is_dir() {
            out.push(Source {
                origin: Origin::Library,
                path: dir,
            });
        }
    }
    for p in &config.deck_paths {
        out.push(Source {
            origin: Origin::Config,
            path: p.clone(),
        });
    }
    for p in &cli.decks {
        out.push(Source {
            origin: Origin::CommandLine,
            path: p.clone(),
        });
    }
    out
}

/// The ids of the library's deck files (`<id>.toml`) that are also
/// bundled decks' ids: the library's copy (made by editing a bundled deck
/// in the app) replaces the bundled deck.
fn copies_of_bundled(sources: &[Source]) -> Vec<String> {
    let Some(lib) = sources.iter().find(|s| s.origin == Origin::Library) else {
        return Vec::new();
    };
    let Ok(entries) = crate::io::entries(&lib.path) else {
        return Vec::new();
    };
    entries
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .filter_map(|p| p.file_stem()?.to_str().map(str::to_string))
        .filter(|id| bundled::deck_files(id).is_some())
        .collect()
}

/// Loads every source's decks.
pub fn load_with(sources: Vec<Source>) -> Library {
    load_cached(sources, None)
}

/// The cache of validated decks in the data folder `data`, for this build
/// of flipcard (see `deck::cache`): its version and the executable's size
/// and modification time, so a rebuilt binary validates every deck afresh.
/// `None` (no cache) when the executable cannot be looked at: a stamp of
/// the version alone could take a deck another build validated.
pub fn deck_cache(data: &Path) -> Option<DeckCache> {
    let exe = disk::metadata(std::env::current_exe().ok()?).ok()?;
    let modified = exe
        .modified()
        .ok()?
        .duration_since(std::time::UNIX_EPOCH)
        .ok()?
        .as_nanos();
    Some(DeckCache::new(
        data.join("cache").join("decks"),
        format!(
            "flipcard {} {} {modified}",
            env!("CARGO_PKG_VERSION"),
            exe.len()
        ),
    ))
}

/// [`load_with`], taking large decks that have not changed from `cache`.
pub fn load_cached(sources: Vec<Source>, cache: Option<&DeckCache>) -> Library {
    let memory = bundled::tree_without(&copies_of_bundled(&sources));
    let pairs: Vec<(&dyn Tree, PathBuf)> = sources
        .iter()
        .map(|s| {
            let tree: &dyn Tree = match s.origin {
                Origin::Bundled => &memory,
                _ => &Disk,
            };
            (tree, s.path.clone())
        })
        .collect();
    let (loaded, files) = load_sources_cached(&pairs, cache);
    Library {
        sources,
        loaded,
        files,
    }
}

/// What the app needs of the library to edit a deck (`E`, `A`): which
/// decks are bundled, and copying one into the library first.
pub struct EditLibrary {
    data_dir: PathBuf,
    bundled: Vec<String>,
}

impl EditLibrary {
    /// The library of `data_dir`, over the decks `library` loaded.
    pub fn new(data_dir: PathBuf, library: &Library) -> EditLibrary {
        let bundled = library
            .files
            .iter()
            .filter(|f| library.source_of(f).origin == Origin::Bundled)
            .filter_map(|f| f.deck.map(|i| library.loaded.decks[i].id.clone()))
            .collect();
        EditLibrary { data_dir, bundled }
    }
}

impl crate::tui::services::DeckLibrary for EditLibrary {
    fn is_bundled(&self, id: &str) -> bool {
        self.bundled.iter().any(|b| b == id)
    }

    fn copy_bundled(&mut self, id: &str) -> Result<PathBuf, String> {
        let (file, content) =
            bundled::deck_files(id).ok_or_else(|| format!("no bundled deck `{id}`"))?;
        install(
            &self.data_dir,
            &NewDeck {
                id: id.to_string(),
                file,
                content,
            },
        )
        .map_err(|e| {
            format!(
                "cannot copy the bundled deck `{id}` into the library: {}",
                crate::cmd::output::chain_text(&e)
            )
        })?;
        self.bundled.retain(|b| b != id);
        Ok(library_dir(&self.data_dir).join(format!("{id}.toml")))
    }
}

/// Every deck the command line, config and library name.
pub fn load(cli: &Cli) -> Library {
    load_with(sources(cli, &config(cli)))
}

/// [`load`], with a warning naming the deck files left out and the command
/// that shows why.
pub fn load_warn(cli: &Cli) -> Library {
    let cache = paths::data_dir(cli.data_dir.clone())
        .ok()
        .and_then(|d| deck_cache(&d));
    let lib = load_cached(sources(cli, &config(cli)), cache.as_ref());
    let failed = lib.failed();
    if !failed.is_empty() {
        let names: Vec<String> = failed
            .iter()
            .map(|f| f.path.display().to_string())
            .collect();
        crate::errln!(
            "flipcard: warning: {} left out with errors: {} (run `flipcard decks` or `flipcard check` to see why)",
            plural(failed.len(), "deck file", "deck files"),
            names.join(", ")
        );
    }
    lib
}

// ---------------------------------------------------------------------------
// Changes to the library: `decks add` and `decks remove`.
//
// A deck in the library is two entries in two folders: `decks/<id>.toml`
// and `content/<id>/`. No single rename moves both, so every change is
// prepared in one staging folder, `decks/.staging/`, with a journal (the
// file `intent`, `add <id>` or `remove <id>`) written before anything live
// is touched. The live entries then move in an order that keeps one rule
// at every instant: a deck file in `decks/` has its own content beside it
// (the old deck's file leaves before its content, the new deck's content
// arrives before its file). A run killed part way leaves the journal; the
// next command that opens the library finishes the change (`recover`).
//
// Only deck ids (the deck format's pattern) name entries, and the library's
// folders and the staging folder must be folders, not links, so nothing
// outside `<data dir>/decks` and `<data dir>/content` is ever touched.
// Entries are moved by rename and deleted with `remove_dir_all`, neither of
// which follows a symbolic link: a link planted at `decks/<id>.toml` or
// `content/<id>` is removed, its target kept.
// ---------------------------------------------------------------------------

/// Where a change to the library is prepared, with its journal.
pub fn staging_dir(data_dir: &Path) -> PathBuf {
    library_dir(data_dir).join(".staging")
}

/// The content folders of library decks: `<data dir>/content/`.
pub fn content_root(data_dir: &Path) -> PathBuf {
    data_dir.join("content")
}

/// For tests only: `FLIPCARD_TEST_LIBRARY_KILL=N` makes the process send
/// itself SIGKILL just before the Nth change it makes to the files of the
/// library (counted from 1 over the whole run, recovery included), so the
/// durability test can stop `decks add` and `decks remove` at every point.
pub const TEST_KILL_ENV: &str = "FLIPCARD_TEST_LIBRARY_KILL";

/// Counts one change to the library's files (see [`TEST_KILL_ENV`]).
fn step() {
    use std::sync::OnceLock;
    use std::sync::atomic::{AtomicU64, Ordering};
    static KILL_AT: OnceLock<Option<u64>> = OnceLock::new();
    static DONE: AtomicU64 = AtomicU64::new(0);
    let kill_at = KILL_AT.get_or_init(|| {
        std::env::var(TEST_KILL_ENV)
            .ok()
            .and_then(|s| s.parse().ok())
    });
    if let Some(n) = kill_at
        && DONE.fetch_add(1, Ordering::SeqCst) + 1 == *n
    {
        let _ = signal_hook::low_level::raise(signal_hook::consts::SIGKILL);
    }
}

/// A deck to install: its id, the bytes of its deck file and of each of
/// its content files (by language).
pub struct NewDeck {
    pub id: String,
    pub file: Vec<u8>,
    pub content: Vec<(String, Vec<u8>)>,
}

/// Why `uninstall` did nothing.
#[derive(Debug)]
pub enum RemoveError {
    /// No `decks/<id>.toml` in the library.
    NotInLibrary,
    Other(anyhow::Error),
}

impl From<anyhow::Error> for RemoveError {
    fn from(e: anyhow::Error) -> Self {
        RemoveError::Other(e)
    }
}

/// Refuses what is not a deck id (a path, `..`, an empty name).
pub fn check_id(id: &str) -> anyhow::Result<()> {
    if crate::deck::validate::is_id(id) {
        Ok(())
    } else {
        anyhow::bail!(
            "`{}` is not a deck id (lowercase letters and digits, joined by single hyphens, e.g. `my-deck`)",
            crate::text::safe::one_line(id)
        )
    }
}

/// Installs `deck` as `decks/<id>.toml` with `content/<id>/`, replacing the
/// library's copy of that id if there is one.
pub fn install(data_dir: &Path, deck: &NewDeck) -> anyhow::Result<()> {
    check_id(&deck.id)?;
    for (lang, _) in &deck.content {
        let plain = !lang.is_empty()
            && !lang.starts_with('-')
            && lang.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'-');
        if !plain {
            anyhow::bail!(
                "`{}` is not a language tag",
                crate::text::safe::one_line(lang)
            );
        }
    }
    let _lock = Lock::take(data_dir, true)?.expect("a waiting lock is always taken");
    real_dir(&content_root(data_dir), true)?;
    recover_locked(data_dir)?;
    let live = library_dir(data_dir).join(format!("{}.toml", deck.id));
    if disk::metadata_no_follow(&live).is_ok_and(|m| m.is_dir()) {
        anyhow::bail!("{} is a folder, not a deck file", live.display());
    }
    let st = staging_dir(data_dir);
    step();
    disk::create_dir(&st).with_context(|| format!("cannot create {}", st.display()))?;
    for sub in ["new", "new/content", "old"] {
        step();
        disk::create_dir(st.join(sub))?;
    }
    for (lang, bytes) in &deck.content {
        step();
        write_new(&st.join("new/content").join(format!("{lang}.toml")), bytes)?;
    }
    step();
    write_new(&st.join("new/deck.toml"), &deck.file)?;
    sync_dir(&st.join("new/content"));
    sync_dir(&st.join("new"));
    write_intent(&st, &Intent::Add(deck.id.clone()))?;
    finish(data_dir, &Intent::Add(deck.id.clone()))
}

/// Removes `decks/<id>.toml` and `content/<id>/` from the library.
pub fn uninstall(data_dir: &Path, id: &str) -> Result<(), RemoveError> {
    check_id(id)?;
    let decks = library_dir(data_dir);
    match disk::metadata_no_follow(&decks) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Err(RemoveError::NotInLibrary),
        _ => {}
    }
    let _lock = Lock::take(data_dir, true)?.expect("a waiting lock is always taken");
    recover_locked(data_dir)?;
    let file = decks.join(format!("{id}.toml"));
    match disk::metadata_no_follow(&file) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Err(RemoveError::NotInLibrary),
        Err(e) => return Err(anyhow::anyhow!("cannot look at {}: {e}", file.display()).into()),
        Ok(m) if m.is_dir() => {
            return Err(anyhow::anyhow!(
                "{} is a folder, not a deck file; nothing removed",
                file.display()
            )
            .into());
        }
        Ok(_) => {}
    }
    let st = staging_dir(data_dir);
    step();
    disk::create_dir(&st).with_context(|| format!("cannot create {}", st.display()))?;
    step();
    disk::create_dir(st.join("old")).context("cannot prepare the removal")?;
    write_intent(&st, &Intent::Remove(id.to_string()))?;
    finish(data_dir, &Intent::Remove(id.to_string()))?;
    Ok(())
}

/// Finishes (or, when it never started, drops) a change to the library
/// that a killed run left in the staging folder. Does nothing while another
/// run holds the library's lock: that change is still under way.
pub fn recover(data_dir: &Path) -> anyhow::Result<()> {
    match disk::metadata_no_follow(staging_dir(data_dir)) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(()),
        _ => {}
    }
    let Some(_lock) = Lock::take(data_dir, false)? else {
        return Ok(());
    };
    recover_locked(data_dir)
}

/// What a journal says is under way.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Intent {
    Add(String),
    Remove(String),
}

impl Intent {
    fn id(&self) -> &str {
        match self {
            Intent::Add(id) | Intent::Remove(id) => id,
        }
    }

    fn text(&self) -> String {
        match self {
            Intent::Add(id) => format!("add {id}\n"),
            Intent::Remove(id) => format!("remove {id}\n"),
        }
    }

    fn parse(text: &str) -> Option<Intent> {
        let (verb, id) = text.strip_suffix('\n')?.split_once(' ')?;
        if !crate::deck::validate::is_id(id) {
            return None;
        }
        match verb {
            "add" => Some(Intent::Add(id.to_string())),
            "remove" => Some(Intent::Remove(id.to_string())),
            _ => None,
        }
    }
}

/// The journal, written whole or not at all (a temporary name renamed).
fn write_intent(st: &Path, intent: &Intent) -> anyhow::Result<()> {
    let tmp = st.join("intent.tmp");
    step();
    write_new(&tmp, intent.text().as_bytes())?;
    step();
    disk::rename(&tmp, st.join("intent"))?;
    sync_dir(st);
    Ok(())
}

fn recover_locked(data_dir: &Path) -> anyhow::Result<()> {
    let st = staging_dir(data_dir);
    match disk::metadata_no_follow(&st) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(()),
        Err(e) => anyhow::bail!("cannot look at {}: {e}", st.display()),
        Ok(m) if !m.is_dir() => anyhow::bail!(
            "{} should be flipcard's staging folder but is not a folder; move it away",
            st.display()
        ),
        Ok(_) => {}
    }
    let journal = st.join("intent");
    let intent = match disk::metadata_no_follow(&journal) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => None,
        Err(e) => anyhow::bail!("cannot look at {}: {e}", journal.display()),
        Ok(m) if !m.is_file() => None,
        Ok(_) => {
            let bytes = crate::deck::files::read_regular(&journal)
                .map_err(|e| anyhow::anyhow!("{}: {e}", journal.display()))?;
            Intent::parse(&String::from_utf8_lossy(&bytes))
        }
    };
    match intent {
        // Nothing live was touched (the journal comes first), or all of it
        // was (the journal goes before the staging folder): drop the rest.
        None => {
            step();
            disk::remove_tree(&st).with_context(|| format!("cannot remove {}", st.display()))?;
            sync_dir(&library_dir(data_dir));
            Ok(())
        }
        Some(intent) => finish(data_dir, &intent),
    }
}

/// Carries out a journaled change from wherever it stands, then clears
/// the staging folder. Each move is made only if it has not been.
fn finish(data_dir: &Path, intent: &Intent) -> anyhow::Result<()> {
    let st = staging_dir(data_dir);
    let id = intent.id();
    let decks = library_dir(data_dir);
    let contents = content_root(data_dir);
    let live_file = decks.join(format!("{id}.toml"));
    let live_content = contents.join(id);
    let new_file = st.join("new/deck.toml");
    let new_content = st.join("new/content");
    let old = st.join("old");
    let exists = |p: &Path| disk::metadata_no_follow(p).is_ok();
    let aside = |live: &Path, name: &str| -> anyhow::Result<()> {
        if exists(live) {
            let to = unused(&old.join(name));
            step();
            disk::rename(live, &to)
                .with_context(|| format!("cannot move {} aside", live.display()))?;
        }
        Ok(())
    };
    let add = matches!(intent, Intent::Add(_));
    // Both folders are checked again: a link put there since would lead
    // the moves outside the library.
    real_dir(&decks, false)?;
    real_dir(&contents, add)?;
    // The new deck file still waits (or this is a removal): the old deck
    // leaves, file first.
    if !add || exists(&new_file) {
        if !add || exists(&new_content) {
            aside(&live_file, "deck.toml")?;
            sync_dir(&decks);
            aside(&live_content, "content")?;
            sync_dir(&contents);
            if add {
                step();
                disk::rename(&new_content, &live_content)
                    .with_context(|| format!("cannot move in {}", live_content.display()))?;
                sync_dir(&contents);
            }
        } else {
            // The new content is in; nothing but the new file may follow.
            aside(&live_file, "deck.toml")?;
        }
        if add {
            step();
            disk::rename(&new_file, &live_file)
                .with_context(|| format!("cannot move in {}", live_file.display()))?;
            sync_dir(&decks);
        }
    }
    // Done: the journal goes first, then what is left.
    step();
    disk::remove_file(st.join("intent"))?;
    sync_dir(&st);
    step();
    disk::remove_tree(&st).with_context(|| format!("cannot remove {}", st.display()))?;
    sync_dir(&decks);
    Ok(())
}

/// `path`, or `path` with a number added when something is already there.
fn unused(path: &Path) -> PathBuf {
    let mut candidate = path.to_path_buf();
    let mut n = 1;
    while disk::metadata_no_follow(&candidate).is_ok() {
        candidate = path.with_file_name(format!(
            "{}-{n}",
            path.file_name().unwrap_or_default().to_string_lossy()
        ));
        n += 1;
    }
    candidate
}

/// A library folder that must be a real folder (not a link to one, not a
/// file) if it is there at all; created when missing if `create`.
fn real_dir(path: &Path, create: bool) -> anyhow::Result<()> {
    match disk::metadata_no_follow(path) {
        Ok(m) if m.is_dir() => Ok(()),
        Ok(m) if m.file_type().is_symlink() => anyhow::bail!(
            "{} is a symbolic link; the library's folders must be folders, not links (nothing changed)",
            path.display()
        ),
        Ok(_) => anyhow::bail!(
            "{} is not a folder; the library needs a folder there (nothing changed)",
            path.display()
        ),
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            if create {
                step();
                disk::create_dir_all(path)
                    .with_context(|| format!("cannot create {}", path.display()))?;
            }
            Ok(())
        }
        Err(e) => anyhow::bail!("cannot look at {}: {e}", path.display()),
    }
}

/// Writes a new file (never through something already at `path`) and
/// makes it durable.
fn write_new(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    disk::write_new(path, bytes).with_context(|| format!("cannot write {}", path.display()))
}

/// Makes renames in `dir` durable.
fn sync_dir(dir: &Path) {
    disk::sync_dir(dir);
}

/// One change to the library at a time: an advisory lock on
/// `decks/.lock`, released when the process ends however it ends.
struct Lock {
    _lock: disk::Lock,
}

impl Lock {
    /// Takes the lock, waiting for it if `wait`; `None` when not waiting
    /// and another run holds it. Creates the library folder when missing.
    fn take(data_dir: &Path, wait: bool) -> anyhow::Result<Option<Lock>> {
        let decks = library_dir(data_dir);
        if wait {
            disk::create_dir_all(data_dir)
                .with_context(|| format!("cannot create {}", data_dir.display()))?;
            real_dir(&decks, true)?;
        } else {
            real_dir(&decks, false)?;
        }
        let path = decks.join(".lock");
        let how = if wait {
            disk::Wait::Forever
        } else {
            disk::Wait::No
        };
        let lock = disk::Lock::take(&path, how)
            .with_context(|| format!("cannot lock the library's {}", path.display()))?;
        Ok(lock.map(|l| Lock { _lock: l }))
    }
}
