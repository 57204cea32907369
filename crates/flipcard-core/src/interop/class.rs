//! A class report from learners' exports (`export --reviews`, `export
//! --attempts`, JSON or CSV), without their databases: per card the share
//! of learners who lapsed and the mean difficulty, per prompt the share who
//! predicted right and the wrong choices made, retention by tag.
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
use std::path::Path;

use chrono::{DateTime, Utc};
use serde::Deserialize;

use super::export::{ATTEMPT_FIELDS, REVIEW_FIELDS};
use super::import::quoted;
use crate::deck::{Answer, Deck};
use crate::sched::ItemKey;
use crate::sched::clock;

/// The longest prediction read: a choice id or a number typed.
pub const MAX_PREDICTION_BYTES: usize = 200;

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
    type Error = String;
    fn try_from(f: ReviewFields) -> Result<ReviewRow, String> {
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
    #[serde(deserialize_with = "flag")]
    pub correct: bool,
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

/// `true`/`false` (JSON and the CSV export) or 1/0.
fn flag<'de, D: serde::Deserializer<'de>>(d: D) -> Result<bool, D::Error> {
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Flag {
        Bool(bool),
        Text(String),
        Int(i64),
    }
    match Flag::deserialize(d)? {
        Flag::Bool(b) => Ok(b),
        Flag::Int(0) => Ok(false),
        Flag::Int(1) => Ok(true),
        Flag::Text(t) if t == "true" || t == "1" => Ok(true),
        Flag::Text(t) if t == "false" || t == "0" => Ok(false),
        _ => Err(serde::de::Error::custom("expected true or false")),
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
        records(text, &values, |a: AttemptRow| Ok(a)).map(Export::Attempts)
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
    check: impl Fn(T) -> Result<U, String>,
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
        out.push(check(record).map_err(|message| FileError { line, message })?);
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
            rows.push(ReviewRow::try_from(fields).map_err(|message| FileError { line, message })?);
        }
        Ok(Export::Reviews(rows))
    } else if starts_with(&ATTEMPT_FIELDS) {
        reader
            .deserialize::<AttemptRow>()
            .collect::<Result<Vec<_>, _>>()
            .map(Export::Attempts)
            .map_err(csv_error)
    } else {
        Err(FileError {
            line: 1,
            message: format!(
                "header is neither `{}` (reviews) nor `{}` (prompt attempts)",
                REVIEW_FIELDS.join(","),
                ATTEMPT_FIELDS.join(",")
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
    /// Learners with at least one review of it.
    pub learners: usize,
    /// Of those, learners who forgot it at least once after learning it
    /// (Again on a review).
    pub lapsed: usize,
    /// Mean over learners of the difficulty after their last review.
    pub mean_difficulty: Option<f64>,
}

/// A choice (or a number typed) and how many learners made it.
#[derive(Debug, Clone, PartialEq)]
pub struct Choice {
    pub prediction: String,
    /// The choice's label in the deck, when it is a choice of it.
    pub label: Option<String>,
    pub learners: usize,
}

/// One predict-then-check prompt across the class. Each learner's first
/// attempt counts: later ones come after seeing the simulation.
#[derive(Debug, Clone, PartialEq)]
pub struct PromptRow {
    pub deck: String,
    pub prompt: String,
    /// The question, when the deck is loaded.
    pub text: Option<String>,
    pub learners: usize,
    pub right: usize,
    /// The wrong first predictions, most common first.
    pub wrong: Vec<Choice>,
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
    pub tags: Vec<TagRow>,
}

/// The tag of cards whose deck is not among those loaded.
pub const NO_DECK: &str = "(deck not loaded)";
/// The tag of cards without tags.
pub const NO_TAG: &str = "(no tag)";

/// Per card across the class: learners, lapsed, difficulty sum, learners
/// with a difficulty.
type CardTally = (usize, usize, f64, usize);
/// Per prompt across the class: learners, right, wrong first predictions.
type PromptTally = (usize, usize, BTreeMap<String, usize>);
/// One learner's card: lapsed, and the last difficulty with its time.
type MyCard = (bool, Option<(DateTime<Utc>, f64)>);

/// Aggregates learners' exports. `decks` give prompt texts, choice labels
/// and tags; `only` keeps one deck.
pub fn aggregate(
    exports: &[Export],
    decks: &[Deck],
    only: Option<&str>,
    lang: &str,
) -> ClassReport {
    let keep = |deck: &str| only.is_none_or(|o| o == deck);
    let deck_by_id: HashMap<&str, &Deck> = decks.iter().map(|d| (d.id.as_str(), d)).collect();
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
                let mut first: HashMap<(&str, &str), &AttemptRow> = HashMap::new();
                for a in rows.iter().filter(|a| keep(&a.deck)) {
                    let e = first.entry((&a.deck, &a.prompt)).or_insert(a);
                    if a.attempted_at < e.attempted_at {
                        *e = a;
                    }
                }
                for ((deck, prompt), a) in first {
                    let e = prompts
                        .entry((deck.to_string(), prompt.to_string()))
                        .or_default();
                    e.0 += 1;
                    if a.correct {
                        e.1 += 1;
                    } else {
                        *e.2.entry(a.prediction.trim().to_string()).or_default() += 1;
                    }
                }
            }
        }
    }
    report.cards = cards
        .into_iter()
        .map(
            |((deck, card, direction), (learners, lapsed, sum, n))| CardRow {
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
        .map(|((deck, prompt), (learners, right, wrong))| {
            let found = deck_by_id
                .get(deck.as_str())
                .and_then(|d| d.prompts.iter().find(|p| p.id == prompt));
            let label = |choice: &str| match found.map(|p| &p.answer) {
                Some(Answer::Choice { choices, .. }) => choices
                    .iter()
                    .find(|c| c.id == choice)
                    .map(|c| flipcard_text::render(c.label.get(lang))),
                _ => None,
            };
            let mut wrong: Vec<Choice> = wrong
                .into_iter()
                .map(|(prediction, learners)| Choice {
                    label: label(&prediction),
                    prediction,
                    learners,
                })
                .collect();
            wrong.sort_by(|a, b| {
                b.learners
                    .cmp(&a.learners)
                    .then(a.prediction.cmp(&b.prediction))
            });
            PromptRow {
                text: found.map(|p| flipcard_text::render(p.question.get(lang))),
                deck,
                prompt,
                learners,
                right,
                wrong,
            }
        })
        .collect();
    report.prompts.sort_by(|a, b| {
        let share = |p: &PromptRow| p.right as f64 / p.learners as f64;
        share(a)
            .total_cmp(&share(b))
            .then_with(|| (&a.deck, &a.prompt).cmp(&(&b.deck, &b.prompt)))
    });
    report.tags = tags
        .into_iter()
        .map(|(tag, (learners, reviews, recalled))| TagRow {
            tag,
            learners,
            reviews,
            recalled,
        })
        .collect();
    report
}

fn card_tags(decks: &HashMap<&str, &Deck>, deck: &str, card: &str) -> Vec<String> {
    let Some(d) = decks.get(deck) else {
        return vec![NO_DECK.to_string()];
    };
    match d.cards.iter().find(|c| c.id == card) {
        Some(c) if !c.tags.is_empty() => c.tags.clone(),
        _ => vec![NO_TAG.to_string()],
    }
}

/// A learner's name: the file name, nothing from inside the file.
pub fn learner_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
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
