//! flipcard: spaced-repetition flashcards, bilingual explanations and live
//! predict-then-check simulations.
//!
//! A Cargo workspace whose crates are the layers, each using only those
//! before it: `flipcard-io` (the one door to the file system),
//! `flipcard-text` (math and words), `flipcard-sim` (the simulator),
//! `flipcard-core` (`deck`, `sched`, `store`, `predict`, `sync`), and this
//! crate, the app: `tui` (the terminal app), `cmd` (the subcommands) and the
//! bundled decks. Only `tui` draws; only `cmd` and `tui` see the command
//! line or print. The layers are re-exported under their old names so a
//! path reads the same from every crate (`flipcard::deck::…`).

pub use flipcard_core::{catalog, deck, interop, predict, sched, store, study, sync};
pub use flipcard_io as io;
pub use flipcard_sim as sim;
pub use flipcard_text as text;

pub mod bundled;
pub mod cmd;
pub mod tui;
