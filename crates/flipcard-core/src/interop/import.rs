//! Reading what `flipcard export --reviews` writes (JSON or CSV) back into
//! reviews to merge. Only what identifies and replays an answer is read
//! (deck, card, direction, reviewed_at, rating; kind for cram answers,
//! duration_ms and undone when present); the stored states are recomputed
//! by the merge. Every bad row is reported with its line, and a file with
//! any bad row gives no reviews at all.
//!
//! The file is someone else's: ids must have the deck format's shape
//! ([`ItemKey::parse`]), an answer must be dated from 1970 to a day after
//! this machine's clock ([`check_event_time`]), and a value quoted in an
//! error is cut short and has its control characters escaped.

use chrono::{DateTime, Utc};
use serde_json::value::RawValue;

use crate::sched::clock::check_event_time;
use crate::sched::{ItemKey, Rating, ReviewKind};
use crate::store::merge::IncomingReview;

/// A problem with one row (or with the file as a whole, at its line).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RowError {
    pub line: usize,
    pub message: String,
}

/// The fields a row must have.
const REQUIRED: [&str; 5] = ["deck", "card", "direction", "reviewed_at", "rating"];

/// One row's fields as text (CSV) or JSON values, looked up by name.
trait Fields {
    fn text(&self, name: &str) -> Result<Option<String>, String>;
    fn integer(&self, name: &str) -> Result<Option<i64>, String>;
    fn boolean(&self, name: &str) -> Result<Option<bool>, String>;
}

/// The line of each record of a JSON array, in one pass over the text:
/// records come in order, so the count goes on from the last one (counting
/// from the start for each record took minutes for 100,000 records).
pub struct Lines<'a> {
    text: &'a str,
    /// Bytes counted so far, and the line they end on.
    at: usize,
    line: usize,
}

impl<'a> Lines<'a> {
    pub fn new(text: &'a str) -> Lines<'a> {
        Lines {
            text,
            at: 0,
            line: 1,
        }
    }

    /// The 1-based line on which `part` (a slice of the text, at or after
    /// the last one asked about) starts.
    pub fn of(&mut self, part: &str) -> usize {
        let offset = (part.as_ptr() as usize)
            .saturating_sub(self.text.as_ptr() as usize)
            .min(self.text.len());
        if offset > self.at {
            self.line += self.text.as_bytes()[self.at..offset]
                .iter()
                .filter(|&&b| b == b'\n')
                .count();
            self.at = offset;
        }
        self.line
    }
}

/// A value from a file quoted in a message: on one line, control
/// characters escaped, at most 40 characters.
pub fn quoted(s: &str) -> String {
    let short = match s.char_indices().nth(40) {
        Some((i, _)) => format!("{}…", &s[..i]),
        None => s.to_string(),
    };
    format!("\"{}\"", flipcard_text::safe::one_line(&short))
}

/// A JSON value quoted in a message: its JSON text, on one line and cut
/// short (a string keeps its quotes).
fn shown(v: &serde_json::Value) -> String {
    let text = v.to_string();
    let short = match text.char_indices().nth(40) {
        Some((i, _)) => format!("{}…", &text[..i]),
        None => text,
    };
    flipcard_text::safe::one_line(&short).into_owned()
}

/// Why one record is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
enum RecordError {
    /// A field of the wrong type, or a record that is not one: the reader's
    /// own words.
    #[error("{0}")]
    Field(String),
    #[error("missing {}", .0.join(", "))]
    Missing(Vec<&'static str>),
    #[error(transparent)]
    Key(#[from] crate::sched::KeyError),
    #[error("reviewed_at {quoted} is not an RFC 3339 time ({reason})")]
    NotRfc3339 { quoted: String, reason: String },
    #[error("reviewed_at {0}")]
    Time(#[from] crate::sched::clock::EventTimeError),
    #[error("rating {0} is not 1–4")]
    Rating(i64),
    #[error("kind {0} is not one of learn, review, relearn, cram")]
    Kind(String),
    #[error("duration_ms {0} is negative")]
    NegativeDuration(i64),
}

impl From<String> for RecordError {
    fn from(s: String) -> RecordError {
        RecordError::Field(s)
    }
}

fn row_from(f: &dyn Fields, now: DateTime<Utc>) -> Result<IncomingReview, RecordError> {
    let mut missing = Vec::new();
    let mut texts = Vec::new();
    for name in &REQUIRED[..4] {
        match f.text(name)? {
            Some(v) if !v.is_empty() => texts.push(v),
            _ => {
                missing.push(*name);
                texts.push(String::new());
            }
        }
    }
    let rating = f.integer("rating")?;
    if rating.is_none() {
        missing.push("rating");
    }
    if !missing.is_empty() {
        return Err(RecordError::Missing(missing));
    }
    let [deck, card, direction, reviewed_at]: [String; 4] = texts
        .try_into()
        .map_err(|_| RecordError::Field("missing fields".to_string()))?;
    let key = ItemKey::parse(&deck, &card, &direction)?;
    let reviewed_at = DateTime::parse_from_rfc3339(&reviewed_at)
        .map_err(|e| RecordError::NotRfc3339 {
            quoted: quoted(&reviewed_at),
            reason: e.to_string(),
        })?
        .with_timezone(&Utc);
    check_event_time(reviewed_at, now)?;
    let n = rating.unwrap_or(0);
    let rating = Rating::from_number(n).ok_or(RecordError::Rating(n))?;
    let cram = match f.text("kind")? {
        None => false,
        Some(k) if k.is_empty() => false,
        Some(k) => {
            let kinds = [
                ReviewKind::Learn,
                ReviewKind::Review,
                ReviewKind::Relearn,
                ReviewKind::Cram,
            ];
            let kind = kinds
                .into_iter()
                .find(|x| x.as_str() == k)
                .ok_or_else(|| RecordError::Kind(quoted(&k)))?;
            kind == ReviewKind::Cram
        }
    };
    let duration_ms = f.integer("duration_ms")?.unwrap_or(0);
    if duration_ms < 0 {
        return Err(RecordError::NegativeDuration(duration_ms));
    }
    Ok(IncomingReview {
        key,
        reviewed_at,
        rating,
        cram,
        duration_ms,
        undone: f.boolean("undone")?.unwrap_or(false),
        balanced_days: None,
    })
}

struct JsonRow<'a>(&'a serde_json::Map<String, serde_json::Value>);

impl Fields for JsonRow<'_> {
    fn text(&self, name: &str) -> Result<Option<String>, String> {
        match self.0.get(name) {
            None | Some(serde_json::Value::Null) => Ok(None),
            Some(serde_json::Value::String(s)) => Ok(Some(s.clone())),
            Some(other) => Err(format!("{name} is {}, not a string", shown(other))),
        }
    }
    fn integer(&self, name: &str) -> Result<Option<i64>, String> {
        match self.0.get(name) {
            None | Some(serde_json::Value::Null) => Ok(None),
            Some(v) => v
                .as_i64()
                .map(Some)
                .ok_or_else(|| format!("{name} is {}, not a whole number", shown(v))),
        }
    }
    fn boolean(&self, name: &str) -> Result<Option<bool>, String> {
        match self.0.get(name) {
            None | Some(serde_json::Value::Null) => Ok(None),
            Some(v) => v
                .as_bool()
                .map(Some)
                .ok_or_else(|| format!("{name} is {}, not true or false", shown(v))),
        }
    }
}

/// Reads a JSON array of exported records; `now` is this machine's clock.
pub fn read_reviews_json(
    text: &str,
    now: DateTime<Utc>,
) -> Result<Vec<IncomingReview>, Vec<RowError>> {
    let items: Vec<&RawValue> = serde_json::from_str(text).map_err(|e| {
        vec![RowError {
            line: e.line().max(1),
            message: format!("not a JSON array of reviews: {e}"),
        }]
    })?;
    let mut rows = Vec::with_capacity(items.len());
    let mut errors = Vec::new();
    let mut lines = Lines::new(text);
    for raw in items {
        let line = lines.of(raw.get());
        let parsed = match serde_json::from_str::<serde_json::Value>(raw.get()) {
            Ok(serde_json::Value::Object(map)) => row_from(&JsonRow(&map), now),
            Ok(other) => Err(RecordError::Field(format!(
                "{} is not an object of review fields",
                shown(&other)
            ))),
            Err(e) => Err(RecordError::Field(e.to_string())),
        };
        match parsed {
            Ok(r) => rows.push(r),
            Err(e) => errors.push(RowError {
                line,
                message: e.to_string(),
            }),
        }
    }
    if errors.is_empty() {
        Ok(rows)
    } else {
        Err(errors)
    }
}

struct CsvRow<'a> {
    header: &'a csv::StringRecord,
    record: &'a csv::StringRecord,
}

impl CsvRow<'_> {
    fn field(&self, name: &str) -> Option<&str> {
        let i = self.header.iter().position(|h| h == name)?;
        self.record.get(i)
    }
}

impl Fields for CsvRow<'_> {
    fn text(&self, name: &str) -> Result<Option<String>, String> {
        Ok(self.field(name).map(str::to_string))
    }
    fn integer(&self, name: &str) -> Result<Option<i64>, String> {
        match self.field(name).map(str::trim) {
            None | Some("") => Ok(None),
            Some(v) => v
                .parse()
                .map(Some)
                .map_err(|_| format!("{name} {} is not a whole number", quoted(v))),
        }
    }
    fn boolean(&self, name: &str) -> Result<Option<bool>, String> {
        match self.field(name).map(str::trim) {
            None | Some("") => Ok(None),
            Some("true") => Ok(Some(true)),
            Some("false") => Ok(Some(false)),
            Some(v) => Err(format!("{name} {} is not true or false", quoted(v))),
        }
    }
}

/// Reads CSV with the export's header row (columns found by name); `now`
/// is this machine's clock.
pub fn read_reviews_csv(
    text: &str,
    now: DateTime<Utc>,
) -> Result<Vec<IncomingReview>, Vec<RowError>> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .flexible(true)
        .from_reader(text.as_bytes());
    let header = reader.headers().cloned().map_err(|e| {
        vec![RowError {
            line: 1,
            message: format!("cannot read the header row: {e}"),
        }]
    })?;
    let absent: Vec<&str> = REQUIRED
        .into_iter()
        .filter(|f| !header.iter().any(|h| h == *f))
        .collect();
    if absent.is_empty() && header.is_empty() {
        return Ok(Vec::new());
    }
    if !absent.is_empty() {
        return Err(vec![RowError {
            line: 1,
            message: format!(
                "the header row lacks {} (expected the header `flipcard export --reviews --format csv` writes)",
                absent.join(", ")
            ),
        }]);
    }
    let mut rows = Vec::new();
    let mut errors = Vec::new();
    let mut record = csv::StringRecord::new();
    loop {
        let line = reader.position().line() as usize;
        match reader.read_record(&mut record) {
            Ok(false) => break,
            Ok(true) => {
                let line = record.position().map_or(line, |p| p.line() as usize);
                if record.len() != header.len() {
                    errors.push(RowError {
                        line,
                        message: format!(
                            "{} fields where the header has {}",
                            record.len(),
                            header.len()
                        ),
                    });
                    continue;
                }
                match row_from(
                    &CsvRow {
                        header: &header,
                        record: &record,
                    },
                    now,
                ) {
                    Ok(r) => rows.push(r),
                    Err(e) => errors.push(RowError {
                        line,
                        message: e.to_string(),
                    }),
                }
            }
            Err(e) => {
                let line = e.position().map_or(line, |p| p.line() as usize);
                errors.push(RowError {
                    line,
                    message: e.to_string(),
                });
                // A broken quote swallows the rest: one error is enough.
                if !matches!(e.kind(), csv::ErrorKind::Utf8 { .. }) {
                    break;
                }
            }
        }
    }
    if errors.is_empty() {
        Ok(rows)
    } else {
        Err(errors)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn now() -> DateTime<Utc> {
        crate::sched::clock::parse("2026-06-01T00:00:00Z").unwrap()
    }

    #[test]
    fn json_errors_name_every_bad_row() {
        let text = "[\n{\"deck\":\"d\",\"card\":\"c\",\"direction\":\"forward\",\"reviewed_at\":\"2026-01-01T00:00:00.000Z\",\"rating\":3},\n{\"deck\":\"d\",\"card\":\"c\",\"direction\":\"sideways\",\"reviewed_at\":\"2026-01-01T00:00:00.000Z\",\"rating\":3},\n{\"deck\":\"d\",\"direction\":\"forward\",\"reviewed_at\":\"x\",\"rating\":9}\n]\n";
        let errs = read_reviews_json(text, now()).unwrap_err();
        let lines: Vec<_> = errs.iter().map(|e| e.line).collect();
        assert_eq!(lines, [3, 4], "{errs:?}");
        assert!(errs[0].message.contains("sideways"));
        assert!(errs[1].message.contains("missing card"), "{errs:?}");
    }

    #[test]
    fn csv_reads_by_header_and_reports_lines() {
        let ok = "deck,card,direction,reviewed_at,rating,kind,undone\nd,c,backward,2026-01-01T00:00:00Z,4,cram,true\n";
        let rows = read_reviews_csv(ok, now()).unwrap();
        assert_eq!(rows.len(), 1);
        assert!(rows[0].cram && rows[0].undone);
        assert_eq!(rows[0].key.direction, crate::sched::Direction::Backward);
        let bad = "deck,card,direction,reviewed_at,rating\nd,c,forward,2026-01-01T00:00:00Z,3\nd,c,forward,2026-01-01T00:00:00Z,0\nd,c,forward,yesterday,3\n";
        let errs = read_reviews_csv(bad, now()).unwrap_err();
        assert_eq!(errs.iter().map(|e| e.line).collect::<Vec<_>>(), [3, 4]);
        let headless = read_reviews_csv("a,b\n1,2\n", now()).unwrap_err();
        assert_eq!(headless[0].line, 1);
        assert!(headless[0].message.contains("lacks deck"), "{headless:?}");
    }

    fn row_strategy() -> impl proptest::strategy::Strategy<Value = (String, String, String, i64)> {
        use proptest::prelude::*;
        let id = prop_oneof![
            "[a-z0-9]{1,6}",
            "[a-z]{1,3}-[a-z0-9]{1,3}",
            "[A-Za-z0-9./ ,\"\u{1b}-]{0,5}",
        ];
        let direction = prop_oneof![
            Just("forward".to_string()),
            Just("backward".to_string()),
            Just("c1".to_string()),
            Just("c999".to_string()),
            Just("c1000".to_string()),
            Just("c0".to_string()),
            "[a-z0-9\u{1b}]{0,4}",
        ];
        // From before 1970 to past the year 10000, around now.
        let ms = prop_oneof![
            -100_000_000_000i64..100_000_000_000,
            1_780_000_000_000i64..1_781_000_000_000,
            253_000_000_000_000i64..253_500_000_000_000,
        ];
        (id.clone(), id, direction, ms)
    }

    proptest::proptest! {
        /// A file is read exactly when every row has ids of the deck
        /// format and a time from 1970 to a day after now; otherwise every
        /// bad row, and only those, is named at its line. Run longer with
        /// `PROPTEST_CASES=100000 cargo test --lib interop::import`.
        #[test]
        fn rows_are_taken_exactly_when_ids_and_times_are_valid(
            rows in proptest::collection::vec(row_strategy(), 1..8),
        ) {
            let now = now();
            let time = |ms: i64| {
                DateTime::from_timestamp_millis(ms)
                    .unwrap()
                    .to_rfc3339_opts(chrono::SecondsFormat::Millis, true)
            };
            let valid: Vec<bool> = rows
                .iter()
                .map(|(d, c, dir, ms)| {
                    let t = time(*ms);
                    ItemKey::parse(d, c, dir).is_ok()
                        && DateTime::parse_from_rfc3339(&t)
                            .is_ok_and(|t| check_event_time(t.with_timezone(&Utc), now).is_ok())
                })
                .collect();
            let bad_lines: Vec<usize> = valid
                .iter()
                .enumerate()
                .filter(|(_, ok)| !**ok)
                .map(|(i, _)| i + 2)
                .collect();
            let mut w = csv::Writer::from_writer(Vec::new());
            w.write_record(["deck", "card", "direction", "reviewed_at", "rating"]).unwrap();
            let mut json = String::from("[\n");
            for (i, (d, c, dir, ms)) in rows.iter().enumerate() {
                w.write_record([d.as_str(), c, dir, &time(*ms), "3"]).unwrap();
                if i > 0 {
                    json.push_str(",\n");
                }
                json.push_str(
                    &serde_json::json!({
                        "deck": d, "card": c, "direction": dir,
                        "reviewed_at": time(*ms), "rating": 3
                    })
                    .to_string(),
                );
            }
            json.push_str("\n]\n");
            let csv_text = String::from_utf8(w.into_inner().unwrap()).unwrap();
            for result in [read_reviews_csv(&csv_text, now), read_reviews_json(&json, now)] {
                match result {
                    Ok(read) => {
                        proptest::prop_assert!(bad_lines.is_empty());
                        proptest::prop_assert_eq!(read.len(), rows.len());
                    }
                    Err(errors) => {
                        let lines: Vec<usize> = errors.iter().map(|e| e.line).collect();
                        proptest::prop_assert_eq!(&lines, &bad_lines);
                        for e in &errors {
                            proptest::prop_assert!(!e.message.contains('\u{1b}'), "{}", e.message);
                        }
                    }
                }
            }
        }
    }
}
