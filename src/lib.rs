//! flipcard: spaced-repetition flashcards, bilingual explanations and live
//! predict-then-check simulations of torque-free rigid-body rotation.
//!
//! `deck`, `text`, `sim`, `sched` and `store` never import ratatui; only
//! `tui` draws.

pub mod cli;
pub mod clock;
pub mod deck;
pub mod num;
pub mod paths;
pub mod sched;
pub mod sim;
pub mod store;
pub mod text;
pub mod tui;
