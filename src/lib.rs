//! flipcard: spaced-repetition flashcards, bilingual explanations and live
//! predict-then-check simulations.
//!
//! Layers, each using only those listed before it: `io` (the one door to
//! the file system), `text` (math and
//! words), `sim` (the simulator), `deck` (TOML into validated decks),
//! `sched` (scheduling), `store` (the review database), `predict` (grading
//! predictions), `sync` (between a learner's machines), `tui` (the terminal
//! app), `cmd` (the subcommands). Only `tui` draws; only `cmd` and `tui`
//! see the command line or print.

pub mod cmd;
pub mod deck;
pub mod io;
pub mod predict;
pub mod sched;
pub mod sim;
pub mod store;
pub mod sync;
pub mod text;
pub mod tui;
