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

/// The bundled files without the decks `hidden` names (by id: their
/// `decks/<id>.toml`): a library copy of a bundled deck replaces it.
pub fn tree_without(hidden: &[String]) -> Memory {
    Memory::new(
        embedded::FILES
            .iter()
            .filter(|(path, _)| {
                !hidden
                    .iter()
                    .any(|id| *path == format!("{DECKS}/{id}.toml").as_str())
            })
            .map(|(path, bytes)| (PathBuf::from(path), *bytes)),
    )
}

/// A deck's content files: each language with the file's bytes.
pub type ContentFiles = Vec<(String, Vec<u8>)>;

/// The bundled deck `id`'s file and its content files by language, as
/// `decks add` installs a deck; `None` when no bundled deck has that id.
pub fn deck_files(id: &str) -> Option<(Vec<u8>, ContentFiles)> {
    let file = format!("{DECKS}/{id}.toml");
    let deck = embedded::FILES.iter().find(|(p, _)| *p == file)?.1.to_vec();
    let prefix = format!("content/{id}/");
    let content = embedded::FILES
        .iter()
        .filter_map(|(p, bytes)| {
            let lang = p.strip_prefix(&prefix)?.strip_suffix(".toml")?;
            (!lang.contains('/')).then(|| (lang.to_string(), bytes.to_vec()))
        })
        .collect();
    Some((deck, content))
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

    #[test]
    fn a_bundled_decks_files_are_its_deck_file_and_each_language() {
        let (file, content) = deck_files("oscillations").unwrap();
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        assert_eq!(
            file,
            std::fs::read(root.join("decks/oscillations.toml")).unwrap()
        );
        let langs: Vec<&str> = content.iter().map(|(l, _)| l.as_str()).collect();
        assert_eq!(langs, ["en", "hi-Latn"]);
        assert!(deck_files("no-such-deck").is_none());
        let without = load_tree(
            &tree_without(&["oscillations".to_string()]),
            &[PathBuf::from(DECKS)],
        );
        assert!(without.decks.iter().all(|d| d.id != "oscillations"));
        assert_eq!(without.decks.len() + 1, load().decks.len());
    }
}
