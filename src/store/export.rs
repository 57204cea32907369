//! `flipcard export --reviews`: the whole review log, one record per row.
//! The field names and their order are a contract with the learner's own
//! scripts and spreadsheets: extend at the end, never rename.

use std::io::Write;

use chrono::{DateTime, SecondsFormat, Utc};
use serde::Serialize;

use super::codec;
use super::db::Store;
use super::error::StoreError;
use super::log::LoggedReview;

/// The exported fields, in order (also the CSV header).
pub const REVIEW_FIELDS: [&str; 14] = [
    "deck",
    "card",
    "direction",
    "reviewed_at",
    "rating",
    "kind",
    "elapsed_days",
    "scheduled_days",
    "stability",
    "difficulty",
    "state",
    "due",
    "duration_ms",
    "undone",
];

#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    #[error(transparent)]
    Store(#[from] StoreError),
    #[error("cannot write the export: {0}")]
    Io(#[from] std::io::Error),
    #[error("cannot write the export as CSV: {0}")]
    Csv(#[from] csv::Error),
    #[error("cannot write the export as JSON: {0}")]
    Json(#[from] serde_json::Error),
}

impl ExportError {
    /// The reader went away (`flipcard export … | head`): not a failure.
    pub fn is_broken_pipe(&self) -> bool {
        let kind = match self {
            ExportError::Io(e) => Some(e.kind()),
            ExportError::Csv(e) => match e.kind() {
                csv::ErrorKind::Io(e) => Some(e.kind()),
                _ => None,
            },
            ExportError::Json(e) => e.io_error_kind(),
            ExportError::Store(_) => None,
        };
        kind == Some(std::io::ErrorKind::BrokenPipe)
    }
}

/// One exported record. Times are RFC 3339 in UTC with milliseconds.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExportedReview {
    pub deck: String,
    pub card: String,
    pub direction: std::borrow::Cow<'static, str>,
    pub reviewed_at: String,
    pub rating: u8,
    pub kind: &'static str,
    pub elapsed_days: i64,
    pub scheduled_days: i64,
    pub stability: Option<f64>,
    pub difficulty: Option<f64>,
    pub state: &'static str,
    pub due: String,
    pub duration_ms: i64,
    pub undone: bool,
}

pub fn rfc3339(t: DateTime<Utc>) -> String {
    t.to_rfc3339_opts(SecondsFormat::Millis, true)
}

impl From<LoggedReview> for ExportedReview {
    fn from(l: LoggedReview) -> Self {
        let r = l.record;
        ExportedReview {
            deck: r.key.deck,
            card: r.key.card,
            direction: r.key.direction.as_str(),
            reviewed_at: rfc3339(r.reviewed_at),
            rating: r.rating as u8,
            kind: r.kind.as_str(),
            elapsed_days: r.elapsed_days,
            scheduled_days: r.scheduled_days,
            stability: r.after.stability,
            difficulty: r.after.difficulty,
            state: codec::state_str(r.after.state),
            due: rfc3339(r.after.due),
            duration_ms: r.duration_ms,
            undone: l.undone,
        }
    }
}

/// Writes the log as a JSON array of records, streaming. Returns the count.
pub fn write_reviews_json(store: &Store, out: &mut dyn Write) -> Result<u64, ExportError> {
    let mut n = 0u64;
    out.write_all(b"[")?;
    store.each_review(|logged| -> Result<(), ExportError> {
        out.write_all(if n == 0 { b"\n" } else { b",\n" })?;
        serde_json::to_writer(&mut *out, &ExportedReview::from(logged))?;
        n += 1;
        Ok(())
    })?;
    out.write_all(if n == 0 { b"]\n" } else { b"\n]\n" })?;
    out.flush()?;
    Ok(n)
}

/// Writes the log as CSV with a header row. Returns the count.
pub fn write_reviews_csv(store: &Store, out: &mut dyn Write) -> Result<u64, ExportError> {
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(out);
    w.write_record(REVIEW_FIELDS)?;
    let mut n = 0u64;
    store.each_review(|logged| -> Result<(), ExportError> {
        w.serialize(ExportedReview::from(logged))?;
        n += 1;
        Ok(())
    })?;
    w.flush()?;
    Ok(n)
}

/// The fields of `flipcard export --attempts`, in order (also the CSV
/// header): a contract like [`REVIEW_FIELDS`].
pub const ATTEMPT_FIELDS: [&str; 6] = [
    "deck",
    "prompt",
    "attempted_at",
    "prediction",
    "measured",
    "correct",
];

/// One exported prompt attempt.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExportedAttempt {
    pub deck: String,
    pub prompt: String,
    pub attempted_at: String,
    pub prediction: String,
    pub measured: Option<f64>,
    pub correct: bool,
}

impl From<super::attempt::PromptAttempt> for ExportedAttempt {
    fn from(a: super::attempt::PromptAttempt) -> Self {
        ExportedAttempt {
            deck: a.deck,
            prompt: a.prompt,
            attempted_at: rfc3339(a.attempted_at),
            prediction: a.prediction,
            measured: a.measured,
            correct: a.correct,
        }
    }
}

/// Writes every prompt attempt as a JSON array, streaming. Returns the count.
pub fn write_attempts_json(store: &Store, out: &mut dyn Write) -> Result<u64, ExportError> {
    let mut n = 0u64;
    out.write_all(b"[")?;
    store.each_attempt(|a| -> Result<(), ExportError> {
        out.write_all(if n == 0 { b"\n" } else { b",\n" })?;
        serde_json::to_writer(&mut *out, &ExportedAttempt::from(a))?;
        n += 1;
        Ok(())
    })?;
    out.write_all(if n == 0 { b"]\n" } else { b"\n]\n" })?;
    out.flush()?;
    Ok(n)
}

/// Writes every prompt attempt as CSV with a header row. Returns the count.
pub fn write_attempts_csv(store: &Store, out: &mut dyn Write) -> Result<u64, ExportError> {
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(out);
    w.write_record(ATTEMPT_FIELDS)?;
    let mut n = 0u64;
    store.each_attempt(|a| -> Result<(), ExportError> {
        w.serialize(ExportedAttempt::from(a))?;
        n += 1;
        Ok(())
    })?;
    w.flush()?;
    Ok(n)
}
