//! Decks: raw TOML with positions → validated domain types, with diagnostics.

pub mod check;
pub mod model;

pub use model::*;
