//! Decks: raw TOML with positions → validated domain types, with diagnostics.
//!
//! Two stages: [`raw`] reads the TOML into types that keep every value's
//! span (reporting wrong types, missing and unknown fields), then
//! [`validate`] checks ids, languages, links, texts and physics and builds
//! the [`model`] types. Every problem of every file is collected in one run.

pub mod cache;
mod chunked;
pub mod cloze;
pub mod csv;
pub mod diag;
pub mod files;
pub mod id;
pub mod load;
pub mod model;
pub mod places;
pub mod raw;
pub mod raw_derivation;
pub mod raw_formula;
pub mod raw_knob;
pub mod raw_misconception;
pub mod raw_vary;
mod read;
pub mod report;
pub mod schema;
mod suggest;
mod syntax;
pub mod template;
pub(crate) mod tomlstr;
pub mod tree;
pub mod validate;

pub use cache::DeckCache;
pub use diag::{Diagnostic, Severity};
pub use load::{
    FileStatus, Loaded, content_dir, load_dir, load_paths, load_sources, load_sources_cached,
    load_tree,
};
pub use model::*;
pub use tree::DeckTree;
