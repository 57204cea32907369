//! Deck presets: `[preset.NAME]` tables of the config, and `[deck.ID]
//! preset = "NAME"` choosing one for a deck (Anki's deck options presets).
//!
//! It also holds the checks of the values both the top level and a preset
//! take (steps, limits, retention, FSRS parameters), below `config`.
//!
//! Every key of a preset is optional: what a preset leaves out is the
//! config's top-level value. [`crate::sched::Config::for_deck`] gives the settings a deck
//! studies with, which its queue, its scheduler and its limits all read.

use std::collections::BTreeMap;
use std::ops::Range;

use chrono::TimeDelta;
use serde::Deserialize;
use toml::Spanned;

/// The highest `desired_retention` a preset may ask for (Anki allows up
/// to 0.99; the top-level value stays within 0.97).
pub const PRESET_RETENTION_MAX: f64 = 0.99;

/// The longest `maximum_interval`, in days (and the default): the
/// scheduler's own bound.
pub const MAX_INTERVAL_DAYS: u32 = super::clock::MAXIMUM_INTERVAL as u32;

/// The keys a `[preset.NAME]` table may hold, in the order they are written.
pub const PRESET_KEYS: [&str; 7] = [
    "new_per_day",
    "reviews_per_day",
    "learning_steps",
    "relearning_steps",
    "desired_retention",
    "maximum_interval",
    "fsrs_parameters",
];

/// Allowed range of `desired_retention`.
pub const RETENTION_RANGE: (f64, f64) = (0.70, 0.97);

/// The longest learning or relearning step accepted.
pub(crate) const MAX_STEP: TimeDelta = TimeDelta::days(365);

/// The range the `fsrs` crate clamps each FSRS-6 parameter to while fitting
/// (its `parameter_clipper`, with one relearning step and the short-term
/// terms enabled): parameters outside it were not produced by a fit.
pub const PARAMETER_BOUNDS: [(f64, f64); 21] = [
    (0.001, 100.0),
    (0.001, 100.0),
    (0.001, 100.0),
    (0.001, 100.0),
    (1.0, 10.0),
    (0.001, 4.0),
    (0.001, 4.0),
    (0.001, 0.75),
    (0.0, 4.5),
    (0.0, 0.8),
    (0.001, 3.5),
    (0.001, 5.0),
    (0.001, 0.25),
    (0.001, 0.9),
    (0.0, 4.0),
    (0.0, 1.0),
    (1.0, 6.0),
    (0.0, 2.0),
    (0.0, 2.0),
    (0.0, 0.8),
    (0.1, 0.8),
];
/// Longest preset name accepted.
const NAME_MAX: usize = 64;

/// One preset: each `None` is the config's top-level value.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Preset {
    pub new_per_day: Option<u32>,
    pub reviews_per_day: Option<u32>,
    pub learning_steps: Option<Vec<TimeDelta>>,
    pub relearning_steps: Option<Vec<TimeDelta>>,
    pub desired_retention: Option<f64>,
    /// Days.
    pub maximum_interval: Option<u32>,
    pub fsrs_parameters: Option<[f64; 21]>,
}

/// What the config says of one deck (`[deck.ID]`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DeckSettings {
    /// The name of a `[preset.NAME]` table.
    pub preset: Option<String>,
}

/// A preset as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawPreset {
    new_per_day: Option<Spanned<i64>>,
    reviews_per_day: Option<Spanned<i64>>,
    learning_steps: Option<Vec<Spanned<String>>>,
    relearning_steps: Option<Vec<Spanned<String>>>,
    desired_retention: Option<Spanned<f64>>,
    maximum_interval: Option<Spanned<i64>>,
    fsrs_parameters: Option<Spanned<Vec<Spanned<f64>>>>,
}

/// A deck's table as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawDeckSettings {
    preset: Option<Spanned<String>>,
}

/// A value refused: the key (as the learner would find it), where, and why.
pub(crate) type Refusal = (String, Range<usize>, String);

/// Whether `name` may name a preset: letters, digits, `_` and `-` (a bare
/// TOML key), at most 64.
pub fn is_preset_name(name: &str) -> bool {
    !name.is_empty()
        && name.len() <= NAME_MAX
        && name
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-')
}

/// A limit: a whole number within 0–`max`.
pub(crate) fn limit(key: &str, n: &Spanned<i64>, max: u32) -> Result<u32, Refusal> {
    let v = *n.get_ref();
    u32::try_from(v)
        .ok()
        .filter(|v| *v <= max)
        .ok_or_else(|| (key.to_string(), n.span(), format!("{v} is outside 0–{max}")))
}

/// Learning or relearning steps.
pub(crate) fn steps(key: &str, raw: &[Spanned<String>]) -> Result<Vec<TimeDelta>, Refusal> {
    raw.iter()
        .enumerate()
        .map(|(i, s)| {
            parse_step(s.get_ref()).map_err(|m| (format!("{key}[{i}]"), s.span(), m.to_string()))
        })
        .collect()
}

/// `desired_retention` within `lo`–`hi`.
pub(crate) fn retention(key: &str, r: &Spanned<f64>, (lo, hi): (f64, f64)) -> Result<f64, Refusal> {
    let v = *r.get_ref();
    if !v.is_finite() || !(lo..=hi).contains(&v) {
        return Err((
            key.to_string(),
            r.span(),
            format!("{v} is outside {lo:.2}–{hi:.2}"),
        ));
    }
    Ok(v)
}

/// `maximum_interval`: whole days, 1–36500.
pub(crate) fn maximum_interval(key: &str, n: &Spanned<i64>) -> Result<u32, Refusal> {
    let v = *n.get_ref();
    u32::try_from(v)
        .ok()
        .filter(|v| (1..=MAX_INTERVAL_DAYS).contains(v))
        .ok_or_else(|| {
            (
                key.to_string(),
                n.span(),
                format!("{v} is outside 1–{MAX_INTERVAL_DAYS} days"),
            )
        })
}

/// 21 FSRS-6 parameters, each within the range a fit gives it.
pub(crate) fn parameters(key: &str, ps: &Spanned<Vec<Spanned<f64>>>) -> Result<[f64; 21], Refusal> {
    let values = ps.get_ref();
    if values.len() != 21 {
        return Err((
            key.to_string(),
            ps.span(),
            format!("{} numbers; FSRS-6 has 21", values.len()),
        ));
    }
    let mut w = [0.0; 21];
    for (i, (v, (lo, hi))) in values.iter().zip(PARAMETER_BOUNDS).enumerate() {
        let x = *v.get_ref();
        if !x.is_finite() || !(lo..=hi).contains(&x) {
            return Err((
                format!("{key}[{i}]"),
                v.span(),
                format!("{x} is outside {lo}–{hi}, the range FSRS fits it in"),
            ));
        }
        w[i] = x;
    }
    Ok(w)
}

/// Reads the `[preset.NAME]` tables.
pub(crate) fn read_presets(
    raw: BTreeMap<String, Spanned<RawPreset>>,
) -> Result<BTreeMap<String, Preset>, Refusal> {
    let mut out = BTreeMap::new();
    for (name, table) in raw {
        let span = table.span();
        if !is_preset_name(&name) {
            return Err((
                format!("preset.{}", flipcard_text::safe::one_line(&name)),
                span,
                format!(
                    "\"{}\" is not a preset name: use letters, digits, `_` and `-` (at most {NAME_MAX})",
                    flipcard_text::safe::one_line(&name)
                ),
            ));
        }
        let p = table.into_inner();
        let key = |k: &str| format!("preset.{name}.{k}");
        let preset = Preset {
            new_per_day: p
                .new_per_day
                .map(|n| limit(&key("new_per_day"), &n, 10_000))
                .transpose()?,
            reviews_per_day: p
                .reviews_per_day
                .map(|n| limit(&key("reviews_per_day"), &n, 100_000))
                .transpose()?,
            learning_steps: p
                .learning_steps
                .map(|s| steps(&key("learning_steps"), &s))
                .transpose()?,
            relearning_steps: p
                .relearning_steps
                .map(|s| steps(&key("relearning_steps"), &s))
                .transpose()?,
            desired_retention: p
                .desired_retention
                .map(|r| {
                    retention(
                        &key("desired_retention"),
                        &r,
                        (RETENTION_RANGE.0, PRESET_RETENTION_MAX),
                    )
                })
                .transpose()?,
            maximum_interval: p
                .maximum_interval
                .map(|n| maximum_interval(&key("maximum_interval"), &n))
                .transpose()?,
            fsrs_parameters: p
                .fsrs_parameters
                .map(|w| parameters(&key("fsrs_parameters"), &w))
                .transpose()?,
        };
        out.insert(name, preset);
    }
    Ok(out)
}

/// Reads the `[deck.ID]` tables; every preset named must be defined.
pub(crate) fn read_decks(
    raw: BTreeMap<String, Spanned<RawDeckSettings>>,
    presets: &BTreeMap<String, Preset>,
) -> Result<BTreeMap<String, DeckSettings>, Refusal> {
    let mut out = BTreeMap::new();
    for (id, table) in raw {
        let span = table.span();
        if !crate::deck::id::is_id(&id) {
            return Err((
                format!("deck.{}", flipcard_text::safe::one_line(&id)),
                span,
                "not a deck id: `[a-z0-9]` words joined by single `-`".to_string(),
            ));
        }
        let d = table.into_inner();
        let preset = match d.preset {
            None => None,
            Some(p) => {
                let name = p.get_ref();
                if !presets.contains_key(name) {
                    let known: Vec<&str> = presets.keys().map(String::as_str).collect();
                    return Err((
                        format!("deck.{id}.preset"),
                        p.span(),
                        format!(
                            "no preset \"{}\"; {}",
                            flipcard_text::safe::one_line(name),
                            if known.is_empty() {
                                "define it as a [preset.NAME] table".to_string()
                            } else {
                                format!("defined: {}", known.join(", "))
                            }
                        ),
                    ));
                }
                Some(name.clone())
            }
        };
        out.insert(id, DeckSettings { preset });
    }
    Ok(out)
}

impl Preset {
    /// The value of `key` (one of [`PRESET_KEYS`]) as written, `None` when
    /// the preset leaves it to the top level.
    pub fn value_of(&self, key: &str) -> Option<toml::Value> {
        let steps = |s: &[TimeDelta]| {
            toml::Value::Array(
                s.iter()
                    .map(|d| toml::Value::String(format_step(*d)))
                    .collect(),
            )
        };
        match key {
            "new_per_day" => self.new_per_day.map(|n| toml::Value::Integer(n.into())),
            "reviews_per_day" => self.reviews_per_day.map(|n| toml::Value::Integer(n.into())),
            "learning_steps" => self.learning_steps.as_deref().map(steps),
            "relearning_steps" => self.relearning_steps.as_deref().map(steps),
            "desired_retention" => self.desired_retention.map(toml::Value::Float),
            "maximum_interval" => self
                .maximum_interval
                .map(|n| toml::Value::Integer(n.into())),
            "fsrs_parameters" => self
                .fsrs_parameters
                .map(|w| toml::Value::Array(w.iter().map(|x| toml::Value::Float(*x)).collect())),
            _ => None,
        }
    }

    /// The preset as the body of its table, one `key = value` line each.
    pub fn to_toml(&self) -> String {
        let mut out = String::new();
        for key in PRESET_KEYS {
            if let Some(v) = self.value_of(key) {
                out.push_str(&format!("{key} = {v}\n"));
            }
        }
        out
    }
}

/// Adds the (empty) table at `path` when the text lacks it.
pub(crate) fn ensure_table(text: &str, path: &[&str]) -> Result<String, String> {
    let mut doc: toml_edit::DocumentMut = text
        .parse()
        .map_err(|e: toml_edit::TomlError| e.to_string().trim_end().to_string())?;
    table_at(&mut doc, path)?;
    Ok(doc.to_string())
}

/// The table at `path`, made when missing (the outer levels implicit).
fn table_at<'d>(
    doc: &'d mut toml_edit::DocumentMut,
    path: &[&str],
) -> Result<&'d mut toml_edit::Table, String> {
    let mut table = doc.as_table_mut();
    for (depth, part) in path.iter().enumerate() {
        let entry = table.entry(part).or_insert_with(|| {
            let mut t = toml_edit::Table::new();
            // The outer level (`preset`) has no header of its own.
            t.set_implicit(depth + 1 < path.len());
            toml_edit::Item::Table(t)
        });
        table = match entry {
            toml_edit::Item::Table(t) => t,
            _ => return Err(format!("`{}` is not a table", path[..=depth].join("."))),
        };
    }
    Ok(table)
}

/// Sets `key` in the table at `path` (`["preset", "fast"]`) of TOML text,
/// keeping every other line and comment; creates the table (after the
/// others) when missing. `preset` and `deck` stay implicit (no `[preset]`
/// line of their own).
pub(crate) fn set_table_key(
    text: &str,
    path: &[&str],
    key: &str,
    value: &toml::Value,
) -> Result<String, String> {
    let mut doc: toml_edit::DocumentMut = text
        .parse()
        .map_err(|e: toml_edit::TomlError| e.to_string().trim_end().to_string())?;
    let value: toml_edit::Value = value
        .to_string()
        .parse()
        .map_err(|e: toml_edit::TomlError| e.to_string())?;
    let table = table_at(&mut doc, path)?;
    match table.get_mut(key) {
        Some(toml_edit::Item::Value(v)) => {
            // Keep the comment after the value and the spacing before it.
            let decor = v.decor().clone();
            *v = value;
            *v.decor_mut() = decor;
        }
        _ => {
            table.insert(key, toml_edit::Item::Value(value));
        }
    }
    Ok(doc.to_string())
}

/// Sets a top-level `key`: in place where it is; else before the first
/// table, so that it does not land inside a `[preset.NAME]`.
pub(crate) fn set_top_key(text: &str, key: &str, value: &toml::Value) -> Result<String, String> {
    set_table_key(text, &[], key, value)
}

/// A learning step as written in the config: a whole number and a unit,
/// `30s`, `1m`, `10m`, `1h`, `1d`.
pub(crate) fn parse_step(text: &str) -> Result<TimeDelta, StepError> {
    let t = text.trim();
    let split = t.find(|c: char| !c.is_ascii_digit()).unwrap_or(t.len());
    let (number, unit) = t.split_at(split);
    let n: i64 = number
        .parse()
        .map_err(|_| StepError::NotADuration(text.to_string()))?;
    let step = match unit {
        "s" => TimeDelta::try_seconds(n),
        "m" => TimeDelta::try_minutes(n),
        "h" => TimeDelta::try_hours(n),
        "d" => TimeDelta::try_days(n),
        _ => return Err(StepError::NoUnit(text.to_string())),
    }
    .ok_or_else(|| StepError::TooLong(text.to_string()))?;
    if step <= TimeDelta::zero() || step > MAX_STEP {
        return Err(StepError::OutOfRange(text.to_string()));
    }
    Ok(step)
}

/// Why [`parse_step`] refused a step; each holds the text as written.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub(crate) enum StepError {
    #[error("{0:?} is not a duration; {STEP_HINT}")]
    NotADuration(String),
    #[error("{0:?} has no known unit; {STEP_HINT}")]
    NoUnit(String),
    #[error("{0:?} is too long")]
    TooLong(String),
    #[error("{0:?} must be between 1s and 365d")]
    OutOfRange(String),
}

const STEP_HINT: &str = "write a whole number and a unit: 30s, 1m, 10m, 1h, 1d";

/// The inverse of [`parse_step`]: the largest unit that divides the step.
pub(crate) fn format_step(d: TimeDelta) -> String {
    let s = d.num_seconds();
    for (unit, size) in [("d", 86_400), ("h", 3_600), ("m", 60)] {
        if s != 0 && s % size == 0 {
            return format!("{}{unit}", s / size);
        }
    }
    format!("{s}s")
}

#[cfg(test)]
mod tests;
