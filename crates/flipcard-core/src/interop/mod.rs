//! Ways in and out that are not sync: Anki packages (read: `anki`; written:
//! `apkg`), review logs as CSV
//! or JSON (import and export), and the class report an instructor builds
//! from learners' exports. Each reads files flipcard did not write, so each
//! validates and bounds what it reads before anything reaches the store.

pub mod anki;
pub mod apkg;
pub mod class;
pub mod export;
pub mod import;
