//! flipcard's core: what the learner's data is and what may be done with
//! it, below any front end. Layers, each using only those listed before it
//! (and the `flipcard-io`, `flipcard-text`, `flipcard-sim` crates): `deck`
//! (TOML into validated decks), `sched` (scheduling), `store` (the review
//! database), `predict` (grading predictions), `sync` (between a learner's
//! machines). Nothing here prints, reads the command line or draws.

pub mod catalog;
pub mod deck;
pub mod interop;
pub mod predict;
pub mod sched;
pub mod store;
pub mod study;
pub mod sync;
