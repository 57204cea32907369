//! The decks built into the binary: the repository's `decks/` and
//! `content/` as they were at build time (see `build.rs`), so flipcard
//! works wherever it is copied.

use std::path::PathBuf;

use crate::deck::files::Memory;
use crate::deck::load::{Loaded, load_tree};

mod embedded {
    include!(concat!(env!("OUT_DIR"), "/bundled.rs"));
}

/// The folder the bundled deck files sit in, as diagnostics name it.
pub const DECKS: &str = "decks";

/// The bundled files, by their path in the repository (`decks/x.toml`,
/// `content/x/en.toml`).
pub fn tree() -> Memory {
    Memory::new(
        embedded::FILES
            .iter()
            .map(|(path, bytes)| (PathBuf::from(path), *bytes)),
    )
}

/// Every bundled deck, loaded and checked.
pub fn load() -> Loaded {
    load_tree(&tree(), &[PathBuf::from(DECKS)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn the_bundled_decks_are_the_repository_files() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        assert!(!embedded::FILES.is_empty());
        for (path, bytes) in embedded::FILES {
            let on_disk = std::fs::read(root.join(path)).unwrap();
            assert_eq!(&on_disk[..], *bytes, "{path}");
        }
        let loaded = load();
        assert_eq!(loaded.errors(), 0, "{}", loaded.render_all());
        let on_disk = crate::deck::load_dir(&root.join(DECKS));
        let ids = |l: &Loaded| l.decks.iter().map(|d| d.id.clone()).collect::<Vec<_>>();
        assert_eq!(ids(&loaded), ids(&on_disk));
    }
}
