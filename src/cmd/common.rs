//! What several commands share: opening the review store and loading the
//! decks the way the command line asks.

use crate::cmd::args::Cli;
use crate::cmd::paths;
use crate::deck::{Deck, Loaded};
use crate::store::Store;

/// The store for commands that only read: nothing is created or written,
/// so they work from a read-only data dir and on a full disk.
pub fn open_store_read_only(cli: &Cli) -> anyhow::Result<Store> {
    // Reading needs no clock, but a FLIPCARD_NOW the app would refuse when
    // writing is refused here too: one rule for every command over the
    // review data, so a script learns of its bad clock on its first call.
    crate::cmd::clock::now()?;
    let dir = paths::data_dir(cli.data_dir.clone())?;
    Ok(Store::open_read_only(&dir)?)
}

pub fn open_store(cli: &Cli) -> anyhow::Result<Store> {
    let clock = crate::cmd::clock::from_env()?;
    let dir = paths::data_dir(cli.data_dir.clone())?;
    let options = crate::store::OpenOptions {
        clock,
        ..crate::store::OpenOptions::default()
    };
    let store = Store::open_with(&dir, &options)?;
    for w in store.warnings() {
        crate::errln!("flipcard: warning: {w}");
    }
    Ok(store)
}

/// The decks of every source (bundled, library, config, `--decks`) as
/// their files have them now. Decks with errors are left out with a
/// warning: their history then shows as orphaned until they are fixed.
pub fn load_decks(cli: &Cli) -> Loaded {
    crate::cmd::library::load_warn(cli).loaded
}

pub fn find_deck<'a>(loaded: &'a Loaded, id: &str) -> anyhow::Result<&'a Deck> {
    loaded.decks.iter().find(|d| d.id == id).ok_or_else(|| {
        let known: Vec<&str> = loaded.decks.iter().map(|d| d.id.as_str()).collect();
        anyhow::anyhow!(
            "no deck `{id}` among the decks loaded; decks: {}",
            if known.is_empty() {
                "none".to_string()
            } else {
                known.join(", ")
            }
        )
    })
}
