//! SQLite storage: schema, migrations, the append-only review log, the
//! card-state cache derived from it, statistics and exports.
//! Never imports ratatui.
//!
//! Every write is one transaction committed to disk (`synchronous=FULL`)
//! before the call returns, so a rating is safe before the next card shows.

pub mod answers;
pub mod attempt;
pub mod backup;
pub(crate) mod backup_files;
pub(crate) mod codec;
pub mod db;
pub mod error;
mod kept;
pub mod log;
pub mod merge;
pub mod restore;
pub mod schema;
pub mod state;
pub mod stats;
pub mod status;
pub mod status_log;
pub mod sync;
pub(crate) mod sync_merge;
pub(crate) mod sync_state;
mod tally;
pub mod today;
pub mod true_retention;
pub(crate) mod write;

pub use attempt::{
    AttemptVerdict, Commitment, Committed, MAX_VARIANT, PromptAttempt, StoredAttempt,
};
pub use db::{OpenOptions, Store};
pub use error::StoreError;
pub use kept::KeptState;
pub use log::LoggedReview;
pub use merge::{IncomingReview, MergeSummary};
pub use state::{CachedState, RebuildReport};
pub use stats::{Stats, StatsScope};
pub use status::{AfterRating, ItemStatus, Recorded, StatusAction, StatusEvent, Undone};
