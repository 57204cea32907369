//! `flipcard export --reviews`: the whole review log, one record per row.
//! The field names and their order are a contract with the learner's own
//! scripts and spreadsheets: extend at the end, never rename.
//!
//! Every time written is RFC 3339, whose year has four digits. A row
//! stored with a time outside the years 0–9999 (only an import from before
//! dates were checked could write one) is left out rather than written as
//! `+10000-…`: the export names it and counts it ([`Written`]), and the
//! command ends in failure after writing the rest.

use std::io::Write;

use chrono::{DateTime, SecondsFormat, Utc};
use serde::Serialize;

use crate::store::codec;
use crate::store::db::Store;
use crate::store::error::StoreError;
use crate::store::log::LoggedReview;

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

/// `t` in RFC 3339, UTC, with milliseconds. For a time that may lie
/// outside the years 0–9999 (any time read back from a database) use
/// [`rfc3339_checked`].
pub fn rfc3339(t: DateTime<Utc>) -> String {
    t.to_rfc3339_opts(SecondsFormat::Millis, true)
}

/// `t` in RFC 3339 with `precision`, or its year when RFC 3339 cannot write
/// it (outside 0–9999: chrono would write `+10000-…` or `-0001-…`).
pub fn rfc3339_with(t: DateTime<Utc>, precision: SecondsFormat) -> Result<String, i32> {
    use chrono::Datelike;
    if (0..=9999).contains(&t.year()) {
        Ok(t.to_rfc3339_opts(precision, true))
    } else {
        Err(t.year())
    }
}

/// [`rfc3339`], or the year when RFC 3339 cannot write it.
pub(crate) fn rfc3339_checked(t: DateTime<Utc>) -> Result<String, i32> {
    rfc3339_with(t, SecondsFormat::Millis)
}

/// What an export wrote, and what it left out.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Written {
    pub rows: u64,
    /// Rows not written, because a time of theirs cannot be written.
    pub left_out: u64,
    /// The first of them, in words ([`MAX_NAMED`] at most).
    pub named: Vec<String>,
}

/// How many rows left out are named one by one.
pub const MAX_NAMED: usize = 20;

impl Written {
    fn leave_out(&mut self, why: Unwritable) {
        self.left_out += 1;
        if self.named.len() < MAX_NAMED {
            self.named.push(why.to_string());
        }
    }
}

/// Why a row cannot be written: its first time outside RFC 3339's years.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{row}: its {field} is in the year {year}, which RFC 3339 cannot write")]
pub struct Unwritable {
    /// The row in words (`review 12`, `attempt 3 (deck/prompt)`).
    pub row: String,
    pub field: &'static str,
    pub year: i32,
}

/// The first time of `times` that RFC 3339 cannot write.
fn unwritable(row: &str, times: &[(&'static str, DateTime<Utc>)]) -> Option<Unwritable> {
    times.iter().find_map(|(field, t)| {
        rfc3339_checked(*t).err().map(|year| Unwritable {
            row: row.to_string(),
            field,
            year,
        })
    })
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

impl ExportedReview {
    /// The record, or why it cannot be written.
    pub fn checked(l: LoggedReview) -> Result<ExportedReview, Unwritable> {
        let r = &l.record;
        match unwritable(
            &format!("review {}", l.id),
            &[("reviewed_at", r.reviewed_at), ("due", r.after.due)],
        ) {
            Some(why) => Err(why),
            None => Ok(ExportedReview::from(l)),
        }
    }
}

/// Each record of a store's table, or why it cannot be written, handed to
/// a writer (the row counted as left out when it cannot).
type Records<'a, R> = dyn FnOnce(
        &mut dyn FnMut(Result<R, Unwritable>) -> Result<(), ExportError>,
    ) -> Result<(), ExportError>
    + 'a;

/// Writes records as a JSON array, one a line, streaming.
fn write_json<R: Serialize>(
    out: &mut dyn Write,
    records: Box<Records<'_, R>>,
) -> Result<Written, ExportError> {
    let mut written = Written::default();
    out.write_all(b"[")?;
    records(&mut |record| {
        match record {
            Ok(r) => {
                out.write_all(if written.rows == 0 { b"\n" } else { b",\n" })?;
                serde_json::to_writer(&mut *out, &r)?;
                written.rows += 1;
            }
            Err(why) => written.leave_out(why),
        }
        Ok(())
    })?;
    out.write_all(if written.rows == 0 { b"]\n" } else { b"\n]\n" })?;
    out.flush()?;
    Ok(written)
}

/// Writes records as CSV after the `header` row.
fn write_csv<R: Serialize>(
    out: &mut dyn Write,
    header: &[&str],
    records: Box<Records<'_, R>>,
) -> Result<Written, ExportError> {
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(out);
    w.write_record(header)?;
    let mut written = Written::default();
    records(&mut |record| {
        match record {
            Ok(r) => {
                w.serialize(r)?;
                written.rows += 1;
            }
            Err(why) => written.leave_out(why),
        }
        Ok(())
    })?;
    w.flush()?;
    Ok(written)
}

/// Every review of the log, checked.
fn reviews(store: &Store) -> Box<Records<'_, ExportedReview>> {
    Box::new(move |write| store.each_review(|l| write(ExportedReview::checked(l))))
}

/// Writes the log as a JSON array of records, streaming.
pub fn write_reviews_json(store: &Store, out: &mut dyn Write) -> Result<Written, ExportError> {
    write_json(out, reviews(store))
}

/// Writes the log as CSV with a header row.
pub fn write_reviews_csv(store: &Store, out: &mut dyn Write) -> Result<Written, ExportError> {
    write_csv(out, &REVIEW_FIELDS, reviews(store))
}

/// The fields of `flipcard export --attempts`, in order (also the CSV
/// header): a contract like [`REVIEW_FIELDS`]. The first six are those of
/// every version; `attempt` and `retry` came with attempts kept at
/// commitment (schema version 4), `misconception` with named
/// misconceptions (schema version 5), `variant` (a varied prompt's seed)
/// with version 6.
pub(crate) const ATTEMPT_FIELDS: [&str; 10] = [
    "deck",
    "prompt",
    "attempted_at",
    "prediction",
    "measured",
    "correct",
    "attempt",
    "retry",
    "misconception",
    "variant",
];

/// The fields every attempts export has had, first in every version's
/// header: the first six of [`ATTEMPT_FIELDS`].
pub(crate) const ATTEMPT_FIELDS_V1: &[&str] = ATTEMPT_FIELDS.split_at(6).0;
/// One exported prompt attempt.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct ExportedAttempt {
    pub deck: String,
    pub prompt: String,
    /// When the learner committed to the prediction.
    pub attempted_at: String,
    pub prediction: String,
    pub measured: Option<f64>,
    /// `None` (null, an empty CSV cell): the learner left the run before
    /// its end, so there is no verdict.
    pub correct: Option<bool>,
    /// 1 for the first attempt at the prompt; 2, 3 … for retries.
    pub attempt: u32,
    /// `attempt > 1`: made after an earlier attempt at the same prompt.
    pub retry: bool,
    /// The deck's misconception a wrong answer stands for (null, an empty
    /// CSV cell: none named, or no verdict).
    pub misconception: Option<String>,
    /// A varied prompt's seed (`flipcard sim --scene … --prompt … --variant
    /// SEED` shows its numbers); null, an empty CSV cell, for a prompt
    /// asked the same way every time.
    pub variant: Option<u64>,
}

impl From<crate::store::StoredAttempt> for ExportedAttempt {
    fn from(a: crate::store::StoredAttempt) -> Self {
        ExportedAttempt {
            retry: a.is_retry(),
            deck: a.deck,
            prompt: a.prompt,
            attempted_at: rfc3339(a.attempted_at),
            prediction: a.prediction,
            measured: a.verdict.as_ref().and_then(|v| v.measured),
            correct: a.verdict.as_ref().map(|v| v.correct),
            misconception: a.verdict.and_then(|v| v.misconception),
            attempt: a.attempt,
            variant: a.variant,
        }
    }
}

/// The attempt, or why it cannot be written; `n` counts attempts from 1 in
/// the order they are stored.
fn checked_attempt(a: crate::store::StoredAttempt, n: u64) -> Result<ExportedAttempt, Unwritable> {
    let row = format!("attempt {n} ({}/{})", a.deck, a.prompt);
    match unwritable(&row, &[("attempted_at", a.attempted_at)]) {
        Some(why) => Err(why),
        None => Ok(ExportedAttempt::from(a)),
    }
}

/// Every prompt attempt, checked.
fn attempts(store: &Store) -> Box<Records<'_, ExportedAttempt>> {
    Box::new(move |write| {
        let mut n = 0;
        store.each_attempt(|a| {
            n += 1;
            write(checked_attempt(a, n))
        })
    })
}

/// Writes every prompt attempt as a JSON array, streaming.
pub fn write_attempts_json(store: &Store, out: &mut dyn Write) -> Result<Written, ExportError> {
    write_json(out, attempts(store))
}

/// Writes every prompt attempt as CSV with a header row.
pub fn write_attempts_csv(store: &Store, out: &mut dyn Write) -> Result<Written, ExportError> {
    write_csv(out, &ATTEMPT_FIELDS, attempts(store))
}
