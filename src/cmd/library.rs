//! The deck sources, in order: the bundled decks, the learner's library
//! (`<data dir>/decks/`), the config's `deck_paths`, then each `--decks`.
//! Every command that opens decks goes through here, so they all see the
//! same decks.

use std::path::{Path, PathBuf};

use crate::cmd::args::Cli;
use crate::cmd::paths;
use crate::deck::files::{Disk, Tree};
use crate::deck::{FileStatus, Loaded, bundled, load_sources};
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

/// Loads every source's decks.
pub fn load_with(sources: Vec<Source>) -> Library {
    let memory = bundled::tree();
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
    let (loaded, files) = load_sources(&pairs);
    Library {
        sources,
        loaded,
        files,
    }
}

/// Every deck the command line, config and library name.
pub fn load(cli: &Cli) -> Library {
    load_with(sources(cli, &config(cli)))
}

/// [`load`], with a warning naming the deck files left out and the command
/// that shows why.
pub fn load_warn(cli: &Cli) -> Library {
    let lib = load(cli);
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
