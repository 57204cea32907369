//! A class report from learners' exports (`export --reviews`, `export
//! --attempts`, JSON or CSV), without their databases: per card (by its
//! text, cloze items included) the share of learners who lapsed and the
//! mean difficulty; per prompt the share whose first prediction was right,
//! the wrong ones made (numbers in bins around the values typed) beside
//! the right answer and its formula, and the retries apart; the deck's
//! misconceptions behind wrong answers, across prompts; retention by tag,
//! worst first.
//!
//! A learner is a file and is named by its file name only. A file with any
//! problem is left out whole, its first problem given with a line number.
//!
//! The files are the learners', not ours: deck, card and prompt ids must
//! have the deck format's shape and a direction be `forward`, `backward` or
//! `c1` … `c999` ([`ItemKey::parse`]); a time must be from 1970 to the
//! latest clock the app accepts ([`clock::latest`]); a prediction is at
//! most [`MAX_PREDICTION_BYTES`] without control characters. A value
//! quoted in an error is cut short and escaped.

use std::collections::{BTreeMap, HashMap};

use chrono::{DateTime, Utc};
use serde::Deserialize;

use super::export::{ATTEMPT_FIELDS_V1, REVIEW_FIELDS};
use super::import::quoted;
use crate::deck::{Answer, Deck};
use crate::sched::ItemKey;
use crate::sched::clock;

/// The longest prediction read: a choice id or a number typed.
pub(crate) const MAX_PREDICTION_BYTES: usize = 200;

/// A review's item: ids of the deck format's shape, checked together with
/// [`ItemKey::parse`].
#[derive(Debug, Clone, PartialEq)]
pub struct Item {
    pub deck: String,
    pub card: String,
    /// `forward`, `backward` or `c1` … `c999`.
    pub direction: String,
}

/// One review as the report needs it.
#[derive(Debug, Clone, PartialEq)]
pub struct ReviewRow {
    pub item: Item,
    pub reviewed_at: DateTime<Utc>,
    pub rating: u8,
    pub kind: String,
    pub difficulty: Option<f64>,
    pub undone: bool,
}

/// A review's fields as read, before its item is checked.
#[derive(Deserialize)]
struct ReviewFields {
    deck: String,
    card: String,
    direction: String,
    #[serde(deserialize_with = "time")]
    reviewed_at: DateTime<Utc>,
    #[serde(deserialize_with = "rating")]
    rating: u8,
    #[serde(deserialize_with = "kind")]
    kind: String,
    #[serde(default, deserialize_with = "difficulty")]
    difficulty: Option<f64>,
    #[serde(deserialize_with = "flag")]
    undone: bool,
}

impl TryFrom<ReviewFields> for ReviewRow {
    type Error = RowError;
    fn try_from(f: ReviewFields) -> Result<ReviewRow, RowError> {
        let key = ItemKey::parse(&f.deck, &f.card, &f.direction)?;
        Ok(ReviewRow {
            item: Item {
                deck: key.deck,
                card: key.card,
                direction: key.direction.as_str().into_owned(),
            },
            reviewed_at: f.reviewed_at,
            rating: f.rating,
            kind: f.kind,
            difficulty: f.difficulty,
            undone: f.undone,
        })
    }
}

/// One prompt attempt as the report needs it.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct AttemptRow {
    #[serde(deserialize_with = "id")]
    pub deck: String,
    #[serde(deserialize_with = "id")]
    pub prompt: String,
    #[serde(deserialize_with = "time")]
    pub attempted_at: DateTime<Utc>,
    #[serde(deserialize_with = "prediction")]
    pub prediction: String,
    /// The value the run measured, when the verdict was on a number.
    #[serde(default, deserialize_with = "measured")]
    pub measured: Option<f64>,
    /// `None` (null, an empty cell): no verdict, the learner left the run
    /// before its end.
    #[serde(deserialize_with = "maybe_flag")]
    pub correct: Option<bool>,
    /// 1 for a first attempt, 2 … for retries (absent in exports made
    /// before attempts were kept at commitment: the order of the times
    /// says then).
    #[serde(default, deserialize_with = "ordinal")]
    pub attempt: Option<u32>,
    #[serde(default, deserialize_with = "maybe_flag")]
    pub retry: Option<bool>,
    /// The deck's misconception the wrong answer stood for (absent in
    /// exports made before schema version 5; null or an empty cell: none).
    #[serde(default, deserialize_with = "maybe_id")]
    pub misconception: Option<String>,
    /// A varied prompt's seed (absent in exports made before schema
    /// version 6; null or an empty cell: the prompt did not vary).
    #[serde(default, deserialize_with = "seed")]
    pub variant: Option<u64>,
}

/// The largest attempt number read: no learner retries one prompt a
/// million times.
pub(crate) const MAX_ATTEMPT: u32 = 1_000_000;

impl AttemptRow {
    /// Whether this is a retry, by the file's own word (`retry`, else
    /// `attempt`); `None` when the file does not say.
    pub(crate) fn says_retry(&self) -> Option<bool> {
        self.retry.or(self.attempt.map(|n| n > 1))
    }

    /// The checks across fields: `retry` agrees with `attempt`.
    fn check(self) -> Result<AttemptRow, RowError> {
        if let (Some(n), Some(r)) = (self.attempt, self.retry)
            && r != (n > 1)
        {
            return Err(RowError::RetryDisagrees {
                attempt: n,
                retry: r,
            });
        }
        Ok(self)
    }
}

/// Why a record that read well is refused: the checks across its fields.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
enum RowError {
    #[error(transparent)]
    Key(#[from] crate::sched::KeyError),
    #[error(
        "attempt {attempt} {} a retry but `retry` is {retry}",
        if *attempt > 1 { "is" } else { "is not" }
    )]
    RetryDisagrees { attempt: u32, retry: bool },
}

/// What one learner's file holds.
#[derive(Debug, Clone, PartialEq)]
pub enum Export {
    Reviews(Vec<ReviewRow>),
    Attempts(Vec<AttemptRow>),
}

/// The first problem of a file, at a 1-based line.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{line}: {message}")]
pub struct FileError {
    pub line: usize,
    pub message: String,
}

/// A deck or prompt id: the deck format's pattern.
fn id<'de, D: serde::Deserializer<'de>>(d: D) -> Result<String, D::Error> {
    let s = String::deserialize(d)?;
    if !crate::deck::validate::is_id(&s) {
        return Err(serde::de::Error::custom(format!(
            "id {} is not an id (lowercase letters and digits in words joined by -)",
            quoted(&s)
        )));
    }
    Ok(s)
}

/// An id of the deck format's pattern, or nothing (null, an empty cell).
fn maybe_id<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<String>, D::Error> {
    match Option::<String>::deserialize(d)? {
        None => Ok(None),
        Some(s) if s.is_empty() => Ok(None),
        Some(s) if crate::deck::validate::is_id(&s) => Ok(Some(s)),
        Some(s) => Err(serde::de::Error::custom(format!(
            "misconception {} is not an id (lowercase letters and digits in words joined by -)",
            quoted(&s)
        ))),
    }
}

fn prediction<'de, D: serde::Deserializer<'de>>(d: D) -> Result<String, D::Error> {
    let s = String::deserialize(d)?;
    if s.len() > MAX_PREDICTION_BYTES {
        return Err(serde::de::Error::custom(format!(
            "prediction {} is longer than {MAX_PREDICTION_BYTES} bytes",
            quoted(&s)
        )));
    }
    if let Some(c) = s
        .chars()
        .find(|c| flipcard_text::safe::is_unsafe(*c) || c.is_control())
    {
        return Err(serde::de::Error::custom(format!(
            "prediction {} holds the control character U+{:04X}",
            quoted(&s),
            u32::from(c)
        )));
    }
    Ok(s)
}

/// A measured value: a finite number, or nothing (null, an empty cell).
fn measured<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
    match Option::<f64>::deserialize(d)? {
        Some(v) if !v.is_finite() => Err(serde::de::Error::custom(format!(
            "measured value {v} is not a finite number"
        ))),
        v => Ok(v),
    }
}

/// An attempt's number: 1 to [`MAX_ATTEMPT`], or nothing.
/// A variant seed: 0 to 2⁵³ − 1, as the schema keeps it.
fn seed<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<u64>, D::Error> {
    match Option::<i64>::deserialize(d)? {
        None => Ok(None),
        Some(n) if u64::try_from(n).is_ok_and(|n| n <= crate::store::MAX_VARIANT) => {
            Ok(Some(n as u64))
        }
        Some(n) => Err(serde::de::Error::custom(format!(
            "variant {n} is not 0–{}",
            crate::store::MAX_VARIANT
        ))),
    }
}

fn ordinal<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<u32>, D::Error> {
    match Option::<i64>::deserialize(d)? {
        None => Ok(None),
        Some(n) if (1..=i64::from(MAX_ATTEMPT)).contains(&n) => Ok(Some(n as u32)),
        Some(n) => Err(serde::de::Error::custom(format!(
            "attempt {n} is not 1–{MAX_ATTEMPT}"
        ))),
    }
}

fn kind<'de, D: serde::Deserializer<'de>>(d: D) -> Result<String, D::Error> {
    let s = String::deserialize(d)?;
    match s.as_str() {
        "learn" | "review" | "relearn" | "cram" => Ok(s),
        _ => Err(serde::de::Error::custom(format!(
            "kind {} is not learn, review, relearn or cram",
            quoted(&s)
        ))),
    }
}

/// An RFC 3339 time from 1970 to [`clock::latest`]: the report compares
/// times only within a learner's file, so this machine's clock does not
/// bound them, but nothing before the epoch or near the year 10000 is an
/// answer.
fn time<'de, D: serde::Deserializer<'de>>(d: D) -> Result<DateTime<Utc>, D::Error> {
    let s = String::deserialize(d)?;
    let t = DateTime::parse_from_rfc3339(&s)
        .map(|t| t.with_timezone(&Utc))
        .map_err(|e| {
            serde::de::Error::custom(format!("time {} is not RFC 3339: {e}", quoted(&s)))
        })?;
    if t < clock::earliest() {
        return Err(serde::de::Error::custom(format!(
            "time {} is before 1970",
            quoted(&s)
        )));
    }
    if t > clock::latest() {
        return Err(serde::de::Error::custom(format!(
            "time {} is after {}, the latest the app accepts",
            quoted(&s),
            super::export::rfc3339(clock::latest())
        )));
    }
    Ok(t)
}

fn rating<'de, D: serde::Deserializer<'de>>(d: D) -> Result<u8, D::Error> {
    let n = i64::deserialize(d)?;
    u8::try_from(n)
        .ok()
        .filter(|r| (1..=4).contains(r))
        .ok_or_else(|| serde::de::Error::custom(format!("rating {n} is not 1–4")))
}

fn difficulty<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
    match Option::<f64>::deserialize(d)? {
        Some(v) if !(1.0..=10.0).contains(&v) => Err(serde::de::Error::custom(format!(
            "difficulty {} is outside 1–10",
            flipcard_text::num::show(v)
        ))),
        v => Ok(v),
    }
}

#[derive(Deserialize)]
#[serde(untagged)]
enum Flag {
    Bool(bool),
    Text(String),
    Int(i64),
}

impl Flag {
    fn read<E: serde::de::Error>(self) -> Result<bool, E> {
        match self {
            Flag::Bool(b) => Ok(b),
            Flag::Int(0) => Ok(false),
            Flag::Int(1) => Ok(true),
            Flag::Text(t) if t == "true" || t == "1" => Ok(true),
            Flag::Text(t) if t == "false" || t == "0" => Ok(false),
            _ => Err(E::custom("expected true or false")),
        }
    }
}

/// `true`/`false` (JSON and the CSV export) or 1/0.
fn flag<'de, D: serde::Deserializer<'de>>(d: D) -> Result<bool, D::Error> {
    Flag::deserialize(d)?.read()
}

/// A flag, or nothing (null, an empty cell).
fn maybe_flag<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<bool>, D::Error> {
    match Option::<Flag>::deserialize(d)? {
        None => Ok(None),
        Some(Flag::Text(t)) if t.is_empty() => Ok(None),
        Some(f) => f.read().map(Some),
    }
}

/// Reads one exported file, JSON or CSV, reviews or attempts.
pub fn parse(text: &str) -> Result<Export, FileError> {
    let trimmed = text.trim_start_matches('\u{feff}');
    let first = trimmed.trim_start();
    if first.starts_with('[') {
        parse_json(trimmed)
    } else if first.is_empty() {
        Err(FileError {
            line: 1,
            message: "empty file: not an export of reviews or prompt attempts".into(),
        })
    } else {
        parse_csv(trimmed)
    }
}

fn json_error(e: &serde_json::Error) -> FileError {
    let message = e.to_string();
    // serde_json appends " at line L column C"; the line is given apart.
    let message = match message.rfind(" at line ") {
        Some(i) => message[..i].to_string(),
        None => message,
    };
    FileError {
        line: e.line().max(1),
        message,
    }
}

fn parse_json(text: &str) -> Result<Export, FileError> {
    // The records are found without building them (a large file would take
    // ten times its size as JSON values), then read one by one, each error
    // at the line of its record; the first one tells which export this is.
    let values: Vec<&serde_json::value::RawValue> =
        serde_json::from_str(text).map_err(|e| json_error(&e))?;
    let Some(first) = values.first() else {
        // An empty export says nothing about anyone.
        return Ok(Export::Reviews(Vec::new()));
    };
    let first: serde_json::Value = serde_json::from_str(first.get()).map_err(|e| json_error(&e))?;
    if first.get("card").is_some() {
        records(text, &values, |f: ReviewFields| ReviewRow::try_from(f)).map(Export::Reviews)
    } else if first.get("prompt").is_some() {
        records(text, &values, AttemptRow::check).map(Export::Attempts)
    } else {
        Err(FileError {
            line: 2,
            message: "records have neither `card` (reviews) nor `prompt` (prompt attempts)".into(),
        })
    }
}

/// Every record of a JSON array read as `T` and checked by `check`; the
/// first problem at its line.
fn records<T: serde::de::DeserializeOwned, U>(
    text: &str,
    values: &[&serde_json::value::RawValue],
    check: impl Fn(T) -> Result<U, RowError>,
) -> Result<Vec<U>, FileError> {
    let mut lines = super::import::Lines::new(text);
    let mut out = Vec::with_capacity(values.len());
    for raw in values {
        let line = lines.of(raw.get());
        let record = serde_json::from_str::<T>(raw.get()).map_err(|e| {
            let mut at = json_error(&e);
            at.line += line - 1;
            at
        })?;
        out.push(check(record).map_err(|e| FileError {
            line,
            message: e.to_string(),
        })?);
    }
    Ok(out)
}

fn parse_csv(text: &str) -> Result<Export, FileError> {
    let mut reader = csv::ReaderBuilder::new().from_reader(text.as_bytes());
    let headers = reader
        .headers()
        .map_err(|e| FileError {
            line: 1,
            message: format!("not CSV: {e}"),
        })?
        .clone();
    let starts_with = |fields: &[&str]| {
        headers.len() >= fields.len() && fields.iter().zip(headers.iter()).all(|(a, b)| *a == b)
    };
    let line_of = |e: &csv::Error| e.position().map_or(1, |p| p.line() as usize);
    let csv_error = |e: csv::Error| FileError {
        line: line_of(&e),
        message: match e.kind() {
            csv::ErrorKind::Deserialize { err, .. } => match err.field() {
                Some(i) => format!(
                    "field `{}`: {}",
                    headers.get(i as usize).unwrap_or("?"),
                    err.kind()
                ),
                None => err.kind().to_string(),
            },
            _ => e.to_string(),
        },
    };
    if starts_with(&REVIEW_FIELDS) {
        let mut rows = Vec::new();
        let mut record = csv::StringRecord::new();
        while reader.read_record(&mut record).map_err(csv_error)? {
            let line = record.position().map_or(1, |p| p.line() as usize);
            let fields: ReviewFields = record.deserialize(Some(&headers)).map_err(csv_error)?;
            rows.push(ReviewRow::try_from(fields).map_err(|e| FileError {
                line,
                message: e.to_string(),
            })?);
        }
        Ok(Export::Reviews(rows))
    } else if starts_with(ATTEMPT_FIELDS_V1) {
        let mut rows = Vec::new();
        let mut record = csv::StringRecord::new();
        while reader.read_record(&mut record).map_err(csv_error)? {
            let line = record.position().map_or(1, |p| p.line() as usize);
            let row: AttemptRow = record.deserialize(Some(&headers)).map_err(csv_error)?;
            rows.push(row.check().map_err(|e| FileError {
                line,
                message: e.to_string(),
            })?);
        }
        Ok(Export::Attempts(rows))
    } else {
        Err(FileError {
            line: 1,
            message: format!(
                "header is neither `{}` (reviews) nor `{}` (prompt attempts)",
                REVIEW_FIELDS.join(","),
                ATTEMPT_FIELDS_V1.join(",")
            ),
        })
    }
}

/// One card (one direction of it) across the class.
#[derive(Debug, Clone, PartialEq)]
pub struct CardRow {
    pub deck: String,
    pub card: String,
    pub direction: String,
    /// What the learner is asked, in the report's language, math rendered
    /// (a cloze item with its gap as `[…]`), when the deck is loaded.
    pub text: Option<String>,
    /// Learners with at least one review of it.
    pub learners: usize,
    /// Of those, learners who forgot it at least once after learning it
    /// (Again on a review).
    pub lapsed: usize,
    /// Mean over learners of the difficulty after their last review.
    pub mean_difficulty: Option<f64>,
}

/// A choice (or a bin of numbers typed) and how many learners made it.
#[derive(Debug, Clone, PartialEq)]
pub struct Choice {
    /// A choice id, or the value typed that centres a bin of numbers.
    pub prediction: String,
    /// The choice's label in the deck, when it is a choice of it; for a
    /// bin of numbers, the known slip its centre is (`1/k`) and the range
    /// of its numbers when they differ (`1.8–1.86`).
    pub label: Option<String>,
    pub learners: usize,
}

/// Later attempts at a prompt, made after a learner's first.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Retries {
    /// Learners with at least one retry.
    pub learners: usize,
    pub attempts: usize,
    /// Retries with a verdict, and those right.
    pub judged: usize,
    pub right: usize,
}

/// One predict-then-check prompt across the class. Each learner's first
/// attempt counts (later ones come after seeing the simulation); retries
/// are counted apart.
#[derive(Debug, Clone, PartialEq)]
pub struct PromptRow {
    pub deck: String,
    pub prompt: String,
    /// The question, when the deck is loaded.
    pub text: Option<String>,
    /// Learners with a first attempt.
    pub learners: usize,
    /// First attempts right.
    pub right: usize,
    /// First attempts without a verdict (the learner left the run before
    /// its end) that the deck's answer could not grade either.
    pub no_verdict: usize,
    /// The wrong first predictions, most common first; numbers grouped in
    /// bins around the values typed.
    pub wrong: Vec<Choice>,
    /// The right answer: the deck's choice (with its label) or number
    /// (with its unit), when the deck is loaded.
    pub answer: Option<String>,
    /// The formula behind a number's answer, math rendered.
    pub formula: Option<String>,
    /// The median of what the runs measured, for a number prompt.
    pub measured: Option<f64>,
    pub retries: Retries,
}

impl PromptRow {
    /// First attempts with a verdict: the share right is of these.
    pub fn judged(&self) -> usize {
        self.learners - self.no_verdict
    }
}

/// Retention of one tag: Good, Hard or Easy among reviews of cards due for
/// review (learning steps and cramming left out).
#[derive(Debug, Clone, PartialEq)]
pub struct TagRow {
    pub tag: String,
    pub learners: usize,
    pub reviews: usize,
    pub recalled: usize,
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct ClassReport {
    /// Files of reviews and of prompt attempts counted.
    pub review_files: usize,
    pub attempt_files: usize,
    /// Hardest first: by share lapsed, then mean difficulty.
    pub cards: Vec<CardRow>,
    /// Least often right first.
    pub prompts: Vec<PromptRow>,
    /// Worst retention first.
    pub tags: Vec<TagRow>,
    /// The misconceptions wrong answers stood for, across prompts: most
    /// learners first.
    pub misconceptions: Vec<MisconceptionRow>,
}

/// One misconception of a deck across the class: every judged wrong
/// attempt (first or retry) that stood for it, by the learner's file
/// (`misconception`), else by the loaded deck (the choice's, or the slip
/// or range the number falls in).
#[derive(Debug, Clone, PartialEq)]
pub struct MisconceptionRow {
    pub deck: String,
    pub id: String,
    /// Its title in the report's language, when the deck is loaded and
    /// declares it.
    pub title: Option<String>,
    /// Learners with at least one wrong answer standing for it.
    pub learners: usize,
    pub attempts: usize,
    /// The prompts those answers were given at, in id order.
    pub prompts: Vec<String>,
}

/// The tag of cards whose deck is not among those loaded.
pub(crate) const NO_DECK: &str = "(deck not loaded)";
/// The tag of cards without tags.
pub(crate) const NO_TAG: &str = "(no tag)";

/// Per card across the class: learners, lapsed, difficulty sum, learners
/// with a difficulty.
type CardTally = (usize, usize, f64, usize);
/// One learner's card: lapsed, and the last difficulty with its time.
type MyCard = (bool, Option<(DateTime<Utc>, f64)>);

/// Per prompt across the class, as it is gathered.
#[derive(Default)]
struct PromptTally {
    learners: usize,
    right: usize,
    no_verdict: usize,
    /// Wrong first predictions, as typed (trimmed), and how many made each.
    wrong: BTreeMap<String, usize>,
    measured: Vec<f64>,
    retries: Retries,
}

/// Whether a first attempt was right: its verdict, else (the learner left
/// the run) the deck's answer, which `flipcard check` holds to the run;
/// `None` when neither says.
fn graded(a: &AttemptRow, prompt: Option<&crate::deck::Prompt>) -> Option<bool> {
    if a.correct.is_some() {
        return a.correct;
    }
    match &prompt?.answer {
        // A varied prompt's answer was its variant's: only the verdict says.
        Answer::Choice { expected, .. } => Some(a.prediction.trim() == expected.as_deref()?),
        Answer::Number {
            expected,
            tolerance,
            ..
        } => {
            let v = a.prediction.trim().parse::<f64>().ok()?;
            let expected = (*expected)?;
            v.is_finite().then(|| tolerance.accepts(v, expected))
        }
        Answer::Formula(key) => {
            Some(flipcard_sim::system::equiv::grade(key, &a.prediction).is_right())
        }
    }
}

/// Aggregates learners' exports. `decks` give card and prompt texts,
/// choice labels, answers and tags in `lang`; `only` keeps one deck.
pub fn aggregate(
    exports: &[Export],
    decks: &[Deck],
    only: Option<&str>,
    lang: &str,
) -> ClassReport {
    let keep = |deck: &str| only.is_none_or(|o| o == deck);
    let deck_by_id: HashMap<&str, &Deck> = decks.iter().map(|d| (d.id.as_str(), d)).collect();
    let find_prompt = |deck: &str, prompt: &str| {
        deck_by_id
            .get(deck)
            .and_then(|d| d.prompts.iter().find(|p| p.id == prompt))
    };
    let mut report = ClassReport::default();
    // (deck, card, direction) -> (learners, lapsed, difficulty sum, with difficulty)
    let mut cards: BTreeMap<(String, String, String), CardTally> = BTreeMap::new();
    let mut prompts: BTreeMap<(String, String), PromptTally> = BTreeMap::new();
    let mut tags: BTreeMap<String, (usize, usize, usize)> = BTreeMap::new();
    for export in exports {
        match export {
            Export::Reviews(rows) => {
                report.review_files += 1;
                // Per card of this learner: lapsed, last difficulty (by time).
                let mut mine: HashMap<(&str, &str, &str), MyCard> = HashMap::new();
                let mut my_tags: HashMap<String, ()> = HashMap::new();
                for r in rows
                    .iter()
                    .filter(|r| !r.undone && r.kind != "cram" && keep(&r.item.deck))
                {
                    let e = mine
                        .entry((&r.item.deck, &r.item.card, &r.item.direction))
                        .or_insert((false, None));
                    if r.kind == "review" && r.rating == 1 {
                        e.0 = true;
                    }
                    if let Some(d) = r.difficulty
                        && e.1.is_none_or(|(t, _)| t <= r.reviewed_at)
                    {
                        e.1 = Some((r.reviewed_at, d));
                    }
                    if r.kind == "review" {
                        for tag in card_tags(&deck_by_id, &r.item.deck, &r.item.card) {
                            let t = tags.entry(tag.clone()).or_default();
                            t.1 += 1;
                            t.2 += usize::from(r.rating > 1);
                            my_tags.insert(tag, ());
                        }
                    }
                }
                for tag in my_tags.into_keys() {
                    tags.entry(tag).or_default().0 += 1;
                }
                for ((deck, card, dir), (lapsed, last)) in mine {
                    let e = cards
                        .entry((deck.to_string(), card.to_string(), dir.to_string()))
                        .or_default();
                    e.0 += 1;
                    e.1 += usize::from(lapsed);
                    if let Some((_, d)) = last {
                        e.2 += d;
                        e.3 += 1;
                    }
                }
            }
            Export::Attempts(rows) => {
                report.attempt_files += 1;
                let mut mine: BTreeMap<(&str, &str), Vec<&AttemptRow>> = BTreeMap::new();
                for a in rows.iter().filter(|a| keep(&a.deck)) {
                    mine.entry((&a.deck, &a.prompt)).or_default().push(a);
                }
                for ((deck, prompt), mut attempts) in mine {
                    // The first: the one the file does not call a retry,
                    // the earliest (then the lowest number) among those.
                    attempts.sort_by_key(|a| {
                        (
                            a.says_retry().unwrap_or(false),
                            a.attempted_at,
                            a.attempt.unwrap_or(0),
                        )
                    });
                    let Some((first, later)) = attempts.split_first() else {
                        continue;
                    };
                    let e = prompts
                        .entry((deck.to_string(), prompt.to_string()))
                        .or_default();
                    e.learners += 1;
                    match graded(first, find_prompt(deck, prompt)) {
                        Some(true) => e.right += 1,
                        Some(false) => {
                            *e.wrong
                                .entry(first.prediction.trim().to_string())
                                .or_default() += 1;
                        }
                        None => e.no_verdict += 1,
                    }
                    e.measured
                        .extend(attempts.iter().filter_map(|a| a.measured).take(1));
                    if !later.is_empty() {
                        e.retries.learners += 1;
                        e.retries.attempts += later.len();
                        e.retries.judged += later.iter().filter(|a| a.correct.is_some()).count();
                        e.retries.right += later.iter().filter(|a| a.correct == Some(true)).count();
                    }
                }
            }
        }
    }
    report.cards = cards
        .into_iter()
        .map(
            |((deck, card, direction), (learners, lapsed, sum, n))| CardRow {
                text: card_text(&deck_by_id, &deck, &card, &direction, lang),
                deck,
                card,
                direction,
                learners,
                lapsed,
                mean_difficulty: (n > 0).then(|| sum / n as f64),
            },
        )
        .collect();
    report.cards.sort_by(|a, b| {
        let share = |c: &CardRow| c.lapsed as f64 / c.learners as f64;
        share(b)
            .total_cmp(&share(a))
            .then(
                b.mean_difficulty
                    .unwrap_or(0.0)
                    .total_cmp(&a.mean_difficulty.unwrap_or(0.0)),
            )
            .then_with(|| (&a.deck, &a.card, &a.direction).cmp(&(&b.deck, &b.card, &b.direction)))
    });
    report.prompts = prompts
        .into_iter()
        .map(|((deck, prompt), t)| {
            let found = find_prompt(&deck, &prompt);
            prompt_row(deck, prompt, t, found, lang)
        })
        .collect();
    report.prompts.sort_by(|a, b| {
        let share = |p: &PromptRow| p.right as f64 / p.judged().max(1) as f64;
        share(a)
            .total_cmp(&share(b))
            .then_with(|| (&a.deck, &a.prompt).cmp(&(&b.deck, &b.prompt)))
    });
    report.misconceptions = misconceptions(exports, &deck_by_id, &keep, lang);
    report.tags = tags
        .into_iter()
        .map(|(tag, (learners, reviews, recalled))| TagRow {
            tag,
            learners,
            reviews,
            recalled,
        })
        .collect();
    report.tags.sort_by(|a, b| {
        let share = |t: &TagRow| t.recalled as f64 / t.reviews.max(1) as f64;
        share(a)
            .total_cmp(&share(b))
            .then(b.reviews.cmp(&a.reviews))
            .then_with(|| a.tag.cmp(&b.tag))
    });
    report
}

/// What a wrong attempt stood for: the file's word, else what the loaded
/// deck says of its prediction (a choice's `misconception`; for a number,
/// the slip it matches at the attempt's measurement, else the first range
/// holding it).
fn stood_for(a: &AttemptRow, prompt: Option<&crate::deck::Prompt>) -> Option<String> {
    if a.misconception.is_some() {
        return a.misconception.clone();
    }
    match &prompt?.answer {
        Answer::Choice { choices, .. } => choices
            .iter()
            .find(|c| c.id == a.prediction.trim())?
            .misconception
            .clone(),
        Answer::Number {
            slips,
            tolerance,
            misconceptions,
            ..
        } => {
            let v = a
                .prediction
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())?;
            let slip = a.measured.and_then(|m| {
                slips
                    .iter()
                    .find(|s| s.value_for(m).is_some_and(|w| tolerance.accepts(v, w)))
            });
            match slip {
                Some(s) if s.misconception.is_some() => s.misconception.clone(),
                _ => misconceptions
                    .iter()
                    .find(|r| r.contains(v))
                    .map(|r| r.id.clone()),
            }
        }
        // A formula key names no misconception (its slips are named by
        // the grader, not by the deck).
        Answer::Formula(_) => None,
    }
}

/// The misconceptions behind the class's wrong answers, most learners
/// first (then most attempts, then by deck and id).
fn misconceptions(
    exports: &[Export],
    decks: &HashMap<&str, &Deck>,
    keep: &dyn Fn(&str) -> bool,
    lang: &str,
) -> Vec<MisconceptionRow> {
    type Tally = (usize, usize, std::collections::BTreeSet<String>);
    let mut by: BTreeMap<(String, String), Tally> = BTreeMap::new();
    for export in exports {
        let Export::Attempts(rows) = export else {
            continue;
        };
        let mut mine: std::collections::BTreeSet<(String, String)> = Default::default();
        for a in rows.iter().filter(|a| keep(&a.deck)) {
            let prompt = decks.get(a.deck.as_str()).and_then(|d| d.prompt(&a.prompt));
            if graded(a, prompt) != Some(false) {
                continue;
            }
            let Some(id) = stood_for(a, prompt) else {
                continue;
            };
            let e = by.entry((a.deck.clone(), id.clone())).or_default();
            e.1 += 1;
            e.2.insert(a.prompt.clone());
            mine.insert((a.deck.clone(), id));
        }
        for key in mine {
            by.entry(key).or_default().0 += 1;
        }
    }
    let mut out: Vec<MisconceptionRow> = by
        .into_iter()
        .map(
            |((deck, id), (learners, attempts, prompts))| MisconceptionRow {
                title: decks
                    .get(deck.as_str())
                    .and_then(|d| d.misconception(&id))
                    .map(|m| flipcard_text::render(m.title.get(lang)).replace('\n', " ")),
                deck,
                id,
                learners,
                attempts,
                prompts: prompts.into_iter().collect(),
            },
        )
        .collect();
    out.sort_by(|a, b| {
        b.learners
            .cmp(&a.learners)
            .then(b.attempts.cmp(&a.attempts))
            .then_with(|| (&a.deck, &a.id).cmp(&(&b.deck, &b.id)))
    });
    out
}

/// A prompt's row from its tally: its texts in `lang` when the deck is
/// loaded, the wrong numbers binned.
fn prompt_row(
    deck: String,
    prompt: String,
    t: PromptTally,
    found: Option<&crate::deck::Prompt>,
    lang: &str,
) -> PromptRow {
    let one_line = |s: &str| flipcard_text::render(s).replace('\n', " ");
    let label = |choice: &str| match found.map(|p| &p.answer) {
        Some(Answer::Choice { choices, .. }) => choices
            .iter()
            .find(|c| c.id == choice)
            .map(|c| one_line(c.label.get(lang))),
        _ => None,
    };
    let tolerance = match found.map(|p| &p.answer) {
        Some(Answer::Number { tolerance, .. }) => Some(*tolerance),
        Some(Answer::Choice { .. } | Answer::Formula(_)) => None,
        // Without the deck: numbers when every wrong prediction is one.
        None => (!t.wrong.is_empty()
            && t.wrong
                .keys()
                .all(|p| p.parse::<f64>().is_ok_and(f64::is_finite)))
        .then_some(crate::deck::Tolerance::Rel(DEFAULT_BIN)),
    };
    let mut wrong: Vec<Choice> = match tolerance {
        Some(tol) => bins(&t.wrong, tol),
        None => t
            .wrong
            .into_iter()
            .map(|(prediction, learners)| Choice {
                label: label(&prediction),
                prediction,
                learners,
            })
            .collect(),
    };
    // A bin whose centre is a known slip of the prompt is named by it
    // (`1/k`, with its range when the bin has one), its value taken at
    // what the runs measured (else the deck's answer).
    if let Some(Answer::Number {
        slips,
        tolerance,
        expected,
        ..
    }) = found.map(|p| &p.answer)
        && !slips.is_empty()
    {
        let mut measured = t.measured.clone();
        measured.sort_by(f64::total_cmp);
        let at = measured
            .get(measured.len() / 2)
            .copied()
            .or(*expected)
            .unwrap_or(f64::NAN);
        for c in &mut wrong {
            let Some(centre) = c.prediction.parse::<f64>().ok().filter(|v| v.is_finite()) else {
                continue;
            };
            let slip = slips.iter().find(|s| {
                s.value_for(at)
                    .is_some_and(|w| tolerance.accepts(centre, w))
            });
            if let Some(slip) = slip {
                c.label = Some(match &c.label {
                    Some(range) => format!("{}, {range}", slip.value),
                    None => slip.value.clone(),
                });
            }
        }
    }
    wrong.sort_by(|a, b| {
        b.learners
            .cmp(&a.learners)
            .then(a.prediction.cmp(&b.prediction))
    });
    let (answer, formula) = match found.map(|p| &p.answer) {
        Some(Answer::Choice {
            expected: Some(expected),
            ..
        }) => (
            Some(match label(expected) {
                Some(l) => format!("{expected} ({l})"),
                None => expected.clone(),
            }),
            None,
        ),
        // Varied: each learner's variant had its own answer.
        Some(Answer::Choice { expected: None, .. }) => (None, None),
        Some(Answer::Number {
            expected,
            unit,
            formula,
            ..
        }) => (
            expected.map(|e| {
                format!("{} {unit}", flipcard_text::num::show(e))
                    .trim_end()
                    .to_string()
            }),
            formula.as_ref().map(|f| one_line(f.get(lang))),
        ),
        Some(Answer::Formula(key)) => (Some(one_line(&key.expected)), None),
        None => (None, None),
    };
    let mut measured = t.measured;
    measured.sort_by(f64::total_cmp);
    PromptRow {
        text: found.map(|p| one_line(&p.question_listed(lang))),
        deck,
        prompt,
        learners: t.learners,
        right: t.right,
        no_verdict: t.no_verdict,
        wrong,
        answer,
        formula,
        measured: measured.get(measured.len() / 2).copied(),
        retries: t.retries,
    }
}

/// The width of a bin of numbers when the deck (and its tolerance) is not
/// loaded: 5 % of the value.
pub(crate) const DEFAULT_BIN: f64 = 0.05;

/// Wrong numbers typed, grouped: the value typed by most learners (the
/// smaller on a tie) centres a bin holding every value within the
/// prompt's tolerance of it, and so on with the rest. Each bin is named by
/// its centre, a value learners typed, with the range of its values when
/// they differ. Predictions that are not numbers keep a bin of their own.
pub fn bins(wrong: &BTreeMap<String, usize>, tol: crate::deck::Tolerance) -> Vec<Choice> {
    let mut out = Vec::new();
    let mut values: Vec<(f64, &str, usize)> = Vec::new();
    for (p, n) in wrong {
        match p.parse::<f64>() {
            Ok(v) if v.is_finite() => values.push((v, p, *n)),
            _ => out.push(Choice {
                prediction: p.clone(),
                label: None,
                learners: *n,
            }),
        }
    }
    values.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut left: Vec<bool> = vec![true; values.len()];
    let near = |centre: f64, v: f64| tol.accepts(v, centre);
    loop {
        // The centre: the value that most learners typed, within the rest.
        let best = (0..values.len()).filter(|&i| left[i]).max_by(|&i, &j| {
            values[i]
                .2
                .cmp(&values[j].2)
                .then(values[j].0.total_cmp(&values[i].0))
        });
        let Some(c) = best else { break };
        let centre = values[c].0;
        let members: Vec<usize> = (0..values.len())
            .filter(|&i| left[i] && (i == c || near(centre, values[i].0)))
            .collect();
        // Ascending, and never empty: the centre is a member.
        let lo = members.first().map_or(centre, |&i| values[i].0);
        let hi = members.last().map_or(centre, |&i| values[i].0);
        for &i in &members {
            left[i] = false;
        }
        out.push(Choice {
            prediction: values[c].1.to_string(),
            label: (lo != hi).then(|| {
                format!(
                    "{}–{}",
                    flipcard_text::num::show(lo),
                    flipcard_text::num::show(hi)
                )
            }),
            learners: members.iter().map(|&i| values[i].2).sum(),
        });
    }
    out
}

/// What a card's item asks, in `lang`, on one line: the front (forward),
/// the back (backward), or the text with deletion `n` as a gap (`cN`).
fn card_text(
    decks: &HashMap<&str, &Deck>,
    deck: &str,
    card: &str,
    direction: &str,
    lang: &str,
) -> Option<String> {
    let d = decks.get(deck)?;
    let key = ItemKey::parse(deck, card, direction).ok()?;
    let index = match key.direction {
        crate::sched::Direction::Predict => d.prompts.iter().position(|p| p.id == card),
        crate::sched::Direction::Derive => d.derivations.iter().position(|x| x.id == card),
        _ => d.cards.iter().position(|c| c.id == card),
    }?;
    crate::catalog::asked(d, key.direction, index, lang).map(|t| t.replace('\n', " "))
}

fn card_tags(decks: &HashMap<&str, &Deck>, deck: &str, card: &str) -> Vec<String> {
    let Some(d) = decks.get(deck) else {
        return vec![NO_DECK.to_string()];
    };
    let tags = match d.cards.iter().find(|c| c.id == card) {
        Some(c) => Some(&c.tags),
        None => d.derivation(card).map(|x| &x.tags),
    };
    match tags {
        Some(t) if !t.is_empty() => t.clone(),
        _ => vec![NO_TAG.to_string()],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const REVIEWS_JSON: &str = r#"[
{"deck":"d","card":"a","direction":"forward","reviewed_at":"2026-01-01T00:00:00.000Z","rating":3,"kind":"learn","elapsed_days":0,"scheduled_days":0,"stability":1.0,"difficulty":5.0,"state":"review","due":"2026-01-02T00:00:00.000Z","duration_ms":1,"undone":false},
{"deck":"d","card":"a","direction":"forward","reviewed_at":"2026-01-03T00:00:00.000Z","rating":1,"kind":"review","elapsed_days":2,"scheduled_days":1,"stability":1.0,"difficulty":7.0,"state":"relearning","due":"2026-01-03T00:10:00.000Z","duration_ms":1,"undone":false}
]"#;

    #[test]
    fn a_difficulty_far_outside_its_range_is_named_in_short_form() {
        let text = REVIEWS_JSON.replace("\"difficulty\":7.0", "\"difficulty\":1e300");
        let e = parse(&text).err().map(|e| (e.line, e.message));
        assert_eq!(e, Some((3, "difficulty 1e300 is outside 1–10".into())));
    }

    #[test]
    fn json_reviews_are_read_and_a_lapse_counted() {
        let e = parse(REVIEWS_JSON).unwrap();
        let r = aggregate(&[e], &[], None, "en");
        assert_eq!(r.cards.len(), 1);
        assert_eq!(r.cards[0].lapsed, 1);
        assert_eq!(r.cards[0].mean_difficulty, Some(7.0));
        assert_eq!(r.tags[0].tag, NO_DECK);
        assert_eq!((r.tags[0].reviews, r.tags[0].recalled), (1, 0));
    }

    #[test]
    fn csv_reviews_read_their_item_and_refuse_bad_ids_and_times() {
        let header = REVIEW_FIELDS.join(",");
        let row =
            "2026,42,c2,2026-01-01T00:00:00Z,3,learn,0,0,1,5,review,2026-01-02T00:00:00Z,1,false";
        let Export::Reviews(rows) = parse(&format!("{header}\n{row}\n")).unwrap() else {
            panic!("reviews")
        };
        assert_eq!(rows[0].item.card, "42");
        assert_eq!(rows[0].item.direction, "c2");
        for (bad, why) in [
            (
                row.replace("2026,42,", "D,42,"),
                "deck id \"D\" is not an id",
            ),
            (row.replace(",c2,", ",c1000,"), "c999"),
            (row.replace("2026,42,", "2026,42\u{1b}[2J,"), "\\u001b"),
            (
                row.replace("2026-01-01T00:00:00Z", "1969-12-31T23:59:59Z"),
                "before 1970",
            ),
            (
                row.replace("2026-01-01T00:00:00Z", "9999-12-31T23:59:59.999-23:59"),
                "after 9899-12-31",
            ),
        ] {
            let e = parse(&format!("{header}\n{row}\n{bad}\n")).unwrap_err();
            assert_eq!(e.line, 3, "{e}");
            assert!(e.message.contains(why), "{why}: {e}");
            assert!(!e.message.contains('\u{1b}'), "{e}");
        }
    }

    #[test]
    fn attempts_of_every_version_are_read_with_their_retries() {
        // Before attempts were kept at commitment: six fields, always judged.
        let old = "deck,prompt,attempted_at,prediction,measured,correct\n\
                   d,p,2026-01-01T00:00:00Z,a,2,false\n";
        let Export::Attempts(rows) = parse(old).unwrap() else {
            panic!("attempts")
        };
        assert_eq!(
            (rows[0].correct, rows[0].attempt, rows[0].retry),
            (Some(false), None, None)
        );
        // Now: a first attempt left without a verdict, then a retry.
        let new = "deck,prompt,attempted_at,prediction,measured,correct,attempt,retry\n\
                   d,p,2026-01-01T00:00:00Z,1.8,,,1,false\n\
                   d,p,2026-01-01T00:01:00Z,2,2.01,true,2,true\n";
        let Export::Attempts(rows) = parse(new).unwrap() else {
            panic!("attempts")
        };
        assert_eq!(rows[0].correct, None);
        assert_eq!(rows[0].measured, None);
        assert_eq!(
            (rows[1].measured, rows[1].says_retry()),
            (Some(2.01), Some(true))
        );
        let json = r#"[{"deck":"d","prompt":"p","attempted_at":"2026-01-01T00:00:00.000Z","prediction":"1.8","measured":null,"correct":null,"attempt":1,"retry":false}]"#;
        let Export::Attempts(rows) = parse(json).unwrap() else {
            panic!("attempts")
        };
        assert_eq!((rows[0].correct, rows[0].attempt), (None, Some(1)));
        for (bad, why) in [
            (
                json.replace("\"attempt\":1", "\"attempt\":0"),
                "attempt 0 is not 1–",
            ),
            (
                json.replace("\"retry\":false", "\"retry\":true"),
                "attempt 1 is not a retry",
            ),
            (json.replace("\"measured\":null", "\"measured\":1e999"), ""),
        ] {
            let e = parse(&bad).unwrap_err();
            assert_eq!(e.line, 1, "{e}");
            assert!(e.message.contains(why), "{why}: {e}");
        }
    }

    fn attempt(prediction: &str, at: &str, correct: Option<bool>, n: Option<u32>) -> AttemptRow {
        AttemptRow {
            misconception: None,
            variant: None,
            deck: "d".into(),
            prompt: "p".into(),
            attempted_at: DateTime::parse_from_rfc3339(at)
                .unwrap()
                .with_timezone(&Utc),
            prediction: prediction.into(),
            measured: correct.map(|_| 2.0),
            correct,
            attempt: n,
            retry: n.map(|n| n > 1),
        }
    }

    #[test]
    fn the_first_attempt_counts_and_retries_are_apart() {
        let learners = vec![
            // Left the first run, then retried twice: the first counts, unjudged.
            Export::Attempts(vec![
                attempt("1.8", "2026-01-01T00:00:00Z", None, Some(1)),
                attempt("2", "2026-01-01T00:01:00Z", Some(true), Some(2)),
                attempt("2", "2026-01-01T00:02:00Z", Some(true), Some(3)),
            ]),
            // An old export: no numbers, the earliest is the first.
            Export::Attempts(vec![
                attempt("2", "2026-01-02T00:00:00Z", Some(true), None),
                attempt("1.83", "2026-01-01T00:00:00Z", Some(false), None),
            ]),
            Export::Attempts(vec![attempt(
                "2",
                "2026-01-01T00:00:00Z",
                Some(true),
                Some(1),
            )]),
        ];
        let r = aggregate(&learners, &[], None, "en");
        let p = &r.prompts[0];
        assert_eq!((p.learners, p.right, p.no_verdict), (3, 1, 1));
        assert_eq!(p.judged(), 2);
        assert_eq!(
            p.wrong,
            [Choice {
                prediction: "1.83".into(),
                label: None,
                learners: 1
            }]
        );
        assert_eq!(
            p.retries,
            Retries {
                learners: 2,
                attempts: 3,
                judged: 3,
                right: 3
            }
        );
        assert_eq!(p.measured, Some(2.0));
    }

    #[test]
    fn wrong_numbers_gather_around_the_values_typed() {
        let wrong: BTreeMap<String, usize> = [
            ("1.83", 3),
            ("1.8", 1),
            ("1.86", 1),
            ("3.6", 2),
            ("-1.83", 1),
            ("fast", 1),
        ]
        .into_iter()
        .map(|(p, n)| (p.to_string(), n))
        .collect();
        let mut got = bins(&wrong, crate::deck::Tolerance::Rel(0.05));
        got.sort_by(|a, b| {
            b.learners
                .cmp(&a.learners)
                .then(a.prediction.cmp(&b.prediction))
        });
        let got: Vec<(String, Option<String>, usize)> = got
            .into_iter()
            .map(|c| (c.prediction, c.label, c.learners))
            .collect();
        assert_eq!(
            got,
            [
                ("1.83".to_string(), Some("1.8–1.86".to_string()), 5),
                ("3.6".to_string(), None, 2),
                ("-1.83".to_string(), None, 1),
                ("fast".to_string(), None, 1),
            ]
        );
    }

    proptest::proptest! {
        /// Any text is read as an attempts export or refused with a line,
        /// never a panic; a record read back keeps `retry` in agreement
        /// with `attempt`. Run longer with
        /// `PROPTEST_CASES=20000 cargo test -p flipcard-core interop::class`.
        #[test]
        fn attempt_records_are_read_or_refused(
            prediction in "[-a-z0-9., \u{1b}]{0,8}",
            measured in "(|[-0-9.e]{1,6}|inf|NaN)",
            correct in "(|true|false|1|0|maybe)",
            n in "(|[-0-9]{1,8})",
            retry in "(|true|false|x)",
        ) {
            let text = format!(
                "deck,prompt,attempted_at,prediction,measured,correct,attempt,retry\n\
                 d,p,2026-01-01T00:00:00Z,\"{prediction}\",{measured},{correct},{n},{retry}\n"
            );
            match parse(&text) {
                Ok(Export::Attempts(rows)) => {
                    proptest::prop_assert_eq!(rows.len(), 1);
                    let a = &rows[0];
                    if let (Some(n), Some(r)) = (a.attempt, a.retry) {
                        proptest::prop_assert_eq!(r, n > 1);
                    }
                    proptest::prop_assert!(a.attempt.is_none_or(|n| (1..=MAX_ATTEMPT).contains(&n)));
                    proptest::prop_assert!(a.measured.is_none_or(f64::is_finite));
                    let r = aggregate(&rows_of(rows.clone()), &[], None, "en");
                    proptest::prop_assert_eq!(r.prompts.len(), 1);
                }
                Ok(Export::Reviews(_)) => proptest::prop_assert!(false, "read as reviews"),
                Err(e) => proptest::prop_assert!(e.line >= 1 && !e.message.contains('\u{1b}'), "{}", e),
            }
        }

        /// A misconception cell is read as an id, nothing (empty) or
        /// refused at its line, never a panic or a control character in
        /// the message; a wrong attempt that names one is counted once,
        /// a right one never. Run longer with
        /// `PROPTEST_CASES=20000 cargo test --lib interop::class`.
        #[test]
        fn misconception_cells_are_ids_or_refused(
            id in "[-a-zA-Z0-9 \u{1b}]{0,10}",
            correct in proptest::bool::ANY,
        ) {
            let text = format!(
                "deck,prompt,attempted_at,prediction,measured,correct,attempt,retry,misconception\n\
                 d,p,2026-01-01T00:00:00Z,x,,{correct},1,false,\"{id}\"\n"
            );
            match parse(&text) {
                Ok(Export::Attempts(rows)) => {
                    proptest::prop_assert_eq!(rows[0].variant, None);
                    let named = rows[0].misconception.clone();
                    proptest::prop_assert_eq!(named.is_some(), !id.is_empty());
                    proptest::prop_assert!(named.as_deref().is_none_or(crate::deck::validate::is_id));
                    let r = aggregate(&rows_of(rows), &[], None, "en");
                    let counted: usize = r.misconceptions.iter().map(|m| m.attempts).sum();
                    proptest::prop_assert_eq!(counted, usize::from(!correct && !id.is_empty()));
                }
                Ok(Export::Reviews(_)) => proptest::prop_assert!(false, "read as reviews"),
                Err(e) => {
                    proptest::prop_assert!(!id.is_empty() && !crate::deck::validate::is_id(&id));
                    proptest::prop_assert!(e.line == 2 && !e.message.contains('\u{1b}'), "{}", e);
                }
            }
        }

        /// Every wrong number lands in exactly one bin, whose centre is a
        /// value typed and whose members are within the tolerance of it.
        #[test]
        fn bins_hold_every_learner_once(
            values in proptest::collection::vec((-1000i32..1000, 1usize..4), 0..30),
            rel in 0.0f64..0.5,
        ) {
            let wrong: BTreeMap<String, usize> = values
                .iter()
                .map(|(v, n)| (flipcard_text::num::show(f64::from(*v) / 100.0), *n))
                .collect();
            let total: usize = wrong.values().sum();
            let got = bins(&wrong, crate::deck::Tolerance::Rel(rel));
            proptest::prop_assert_eq!(got.iter().map(|c| c.learners).sum::<usize>(), total);
            for c in &got {
                proptest::prop_assert!(wrong.contains_key(&c.prediction), "{:?}", c);
            }
        }
    }

    fn rows_of(rows: Vec<AttemptRow>) -> Vec<Export> {
        vec![Export::Attempts(rows)]
    }

    #[test]
    fn a_bad_record_is_named_by_its_line() {
        let bad = REVIEWS_JSON.replace("\"rating\":1", "\"rating\":9");
        let e = parse(&bad).unwrap_err();
        assert_eq!(e.line, 3, "{e}");
        assert!(e.message.contains("rating 9 is not 1–4"), "{e}");
        let csv = "deck,prompt,attempted_at,prediction,measured,correct\n\
                   d,p,2026-01-01T00:00:00Z,a,,true\n\
                   d,p,yesterday,b,,false\n";
        let e = parse(csv).unwrap_err();
        assert_eq!(e.line, 3, "{e}");
        assert!(
            e.message.contains("time \"yesterday\" is not RFC 3339"),
            "{e}"
        );
    }
}
