//! The learner's settings, read from `config.toml`.
//!
//! A missing file means the defaults. Unknown keys and out-of-range values are
//! errors that name the file, the line and the key: a typo must not silently
//! fall back to a default. Saving one key edits the file in place, so the
//! learner's comments and other keys survive.

use std::collections::BTreeMap;
use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};

use chrono::{NaiveTime, TimeDelta, Timelike};
use serde::Deserialize;
use toml::Spanned;

use super::balance::{EasyDays, WEEKDAYS};
pub use super::preset::PARAMETER_BOUNDS;
use super::preset::{DeckSettings, Preset, RawDeckSettings, RawPreset};
pub(crate) use super::preset::{RETENTION_RANGE, format_step, parse_step};

/// The languages the app speaks (decks may declare these).
pub(crate) const LANGUAGES: [&str; 2] = ["en", "hi-Latn"];

/// Every key a config file may hold, in the order `save` writes them.
pub const KEYS: [&str; 13] = [
    "desired_retention",
    "learning_steps",
    "relearning_steps",
    "fuzz",
    "new_per_day",
    "reviews_per_day",
    "day_starts_at",
    "language",
    "bury_siblings",
    "leech_threshold",
    "leech_action",
    "maximum_interval",
    "hide_bundled",
];

/// Keys written only once they have a value: FSRS parameters fitted to the
/// learner's own reviews (`flipcard optimize --apply`) and when.
pub const FITTED_KEYS: [&str; 2] = ["fsrs_parameters", "fsrs_fitted_at"];

/// What happens to an item whose lapses reach `leech_threshold`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LeechAction {
    /// It is marked a leech and suspended.
    Suspend,
    /// It is only marked a leech (the browser and stats list it).
    Tag,
}

impl LeechAction {
    pub fn as_str(self) -> &'static str {
        match self {
            LeechAction::Suspend => "suspend",
            LeechAction::Tag => "tag",
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// Probability of recall the scheduler aims for at the due time.
    pub desired_retention: f64,
    /// Short steps of a new card before it graduates to review.
    pub learning_steps: Vec<TimeDelta>,
    /// Short steps of a lapsed card before it returns to review.
    pub relearning_steps: Vec<TimeDelta>,
    /// Spread review intervals a little so cards learnt together part ways.
    pub fuzz: bool,
    pub new_per_day: u32,
    pub reviews_per_day: u32,
    /// Local time at which a new study day begins.
    pub day_starts_at: NaiveTime,
    /// Language of explanations and of the interface.
    pub language: String,
    /// FSRS-6 parameters fitted to this learner (`None`: the defaults).
    pub fsrs_parameters: Option<[f64; 21]>,
    /// When `fsrs_parameters` were fitted (RFC 3339).
    pub fsrs_fitted_at: Option<chrono::DateTime<chrono::FixedOffset>>,
    /// When one item of a card is answered, its other items (the other
    /// direction, the other cloze numbers) wait until the next day.
    pub bury_siblings: bool,
    /// Lapses at which an item becomes a leech (0: never).
    pub leech_threshold: u32,
    pub leech_action: LeechAction,
    /// Folders of decks opened besides the bundled ones and the library,
    /// relative ones taken from the config file's folder.
    pub deck_paths: Vec<PathBuf>,
    /// A folder another tool keeps in step between the learner's machines
    /// (`flipcard sync`), relative to the config file's folder.
    pub sync_dir: Option<PathBuf>,
    /// The longest interval the scheduler gives, in days (Anki's maximum
    /// interval).
    pub maximum_interval: u32,
    /// Leave the bundled decks off home and the deck lists.
    pub hide_bundled: bool,
    /// `[preset.NAME]` tables (see [`super::preset`]).
    pub presets: BTreeMap<String, Preset>,
    /// `[deck.ID]` tables: which preset each deck uses.
    pub decks: BTreeMap<String, DeckSettings>,
    /// With fuzz on, a review's day is chosen within its fuzz range to even
    /// the daily load (`sched::balance`). On by default: the day it picks
    /// depends on the other cards due then, which a replay (a sync on
    /// another machine, a merge) cannot know, so the day is kept with the
    /// answer (`ReviewRecord::balanced_days`, a sync line's
    /// `balanced_days`) and the replay takes it within the answer's fuzz
    /// range (`Scheduler::replay`).
    pub load_balance: bool,
    /// The share of a normal day's reviews each weekday gets, Monday
    /// first (`easy_days = { sat = 0.5, sun = 0 }`).
    pub easy_days: EasyDays,
    /// The exam `flipcard plan --exam DATE` (or the exam screen) last
    /// planned for, remembered until it passes.
    pub exam_date: Option<chrono::NaiveDate>,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            desired_retention: 0.9,
            learning_steps: vec![TimeDelta::minutes(1), TimeDelta::minutes(10)],
            relearning_steps: vec![TimeDelta::minutes(10)],
            fuzz: true,
            new_per_day: 20,
            reviews_per_day: 200,
            day_starts_at: NaiveTime::from_hms_opt(4, 0, 0).unwrap_or(NaiveTime::MIN),
            language: "en".to_string(),
            fsrs_parameters: None,
            fsrs_fitted_at: None,
            bury_siblings: true,
            leech_threshold: 8,
            leech_action: LeechAction::Suspend,
            deck_paths: Vec::new(),
            sync_dir: None,
            maximum_interval: super::preset::MAX_INTERVAL_DAYS,
            hide_bundled: false,
            presets: BTreeMap::new(),
            decks: BTreeMap::new(),
            load_balance: true,
            easy_days: EasyDays::default(),
            exam_date: None,
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    #[error("cannot read config file {path}: {source}")]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("cannot write config file {path}: {source}")]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
    /// Not TOML, a wrong type, or an unknown key (the message names it).
    #[error("{path}: {message}")]
    Parse { path: PathBuf, message: String },
    /// A known key with a value outside what it accepts.
    #[error("{path}:{line}:{column}: `{key}`: {message}")]
    Invalid {
        path: PathBuf,
        line: usize,
        column: usize,
        key: String,
        message: String,
    },
    #[error("`{0}` is not a config key (or has no value to write); known keys: {keys}, {fitted}", keys = KEYS.join(", "), fitted = FITTED_KEYS.join(", "))]
    UnknownKey(String),
}

/// The file as written, with positions for error messages.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawConfig {
    desired_retention: Option<Spanned<f64>>,
    learning_steps: Option<Vec<Spanned<String>>>,
    relearning_steps: Option<Vec<Spanned<String>>>,
    fuzz: Option<bool>,
    new_per_day: Option<Spanned<i64>>,
    reviews_per_day: Option<Spanned<i64>>,
    day_starts_at: Option<Spanned<String>>,
    language: Option<Spanned<String>>,
    fsrs_parameters: Option<Spanned<Vec<Spanned<f64>>>>,
    fsrs_fitted_at: Option<Spanned<String>>,
    bury_siblings: Option<bool>,
    leech_threshold: Option<Spanned<i64>>,
    leech_action: Option<Spanned<String>>,
    deck_paths: Option<Vec<Spanned<String>>>,
    sync_dir: Option<Spanned<String>>,
    maximum_interval: Option<Spanned<i64>>,
    hide_bundled: Option<bool>,
    preset: Option<BTreeMap<String, Spanned<RawPreset>>>,
    deck: Option<BTreeMap<String, Spanned<RawDeckSettings>>>,
    load_balance: Option<bool>,
    easy_days: Option<Spanned<std::collections::BTreeMap<String, Spanned<toml::Value>>>>,
    exam_date: Option<Spanned<String>>,
}

impl Config {
    /// Reads the config file. `None` (no config location known) and a file
    /// that does not exist both give the defaults.
    pub fn load(path: Option<&Path>) -> Result<Config, ConfigError> {
        let Some(path) = path else {
            return Ok(Config::default());
        };
        match read_file(path) {
            Ok(text) => Config::parse(&text, path),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Config::default()),
            Err(source) => Err(ConfigError::Read {
                path: path.to_path_buf(),
                source,
            }),
        }
    }

    /// Parses config text; `path` only labels the errors.
    pub fn parse(text: &str, path: &Path) -> Result<Config, ConfigError> {
        let raw: RawConfig = toml::from_str(text).map_err(|e| ConfigError::Parse {
            path: path.to_path_buf(),
            message: e.to_string().trim_end().to_string(),
        })?;
        let invalid = |key: &str, span: Range<usize>, message: String| {
            let (line, column) = line_column(text, span.start);
            ConfigError::Invalid {
                path: path.to_path_buf(),
                line,
                column,
                key: key.to_string(),
                message,
            }
        };

        let mut config = Config::default();
        if let Some(r) = raw.desired_retention {
            let (lo, hi) = RETENTION_RANGE;
            let v = *r.get_ref();
            if !(lo..=hi).contains(&v) {
                return Err(invalid(
                    "desired_retention",
                    r.span(),
                    format!("{v} is outside {lo:.2}–{hi:.2}"),
                ));
            }
            config.desired_retention = v;
        }
        for (key, raw_steps, target) in [
            (
                "learning_steps",
                raw.learning_steps,
                &mut config.learning_steps,
            ),
            (
                "relearning_steps",
                raw.relearning_steps,
                &mut config.relearning_steps,
            ),
        ] {
            if let Some(steps) = raw_steps {
                *target = steps
                    .iter()
                    .enumerate()
                    .map(|(i, s)| {
                        parse_step(s.get_ref())
                            .map_err(|m| invalid(&format!("{key}[{i}]"), s.span(), m.to_string()))
                    })
                    .collect::<Result<_, _>>()?;
            }
        }
        if let Some(f) = raw.fuzz {
            config.fuzz = f;
        }
        for (key, raw_limit, max, target) in [
            (
                "new_per_day",
                raw.new_per_day,
                10_000,
                &mut config.new_per_day,
            ),
            (
                "reviews_per_day",
                raw.reviews_per_day,
                100_000,
                &mut config.reviews_per_day,
            ),
        ] {
            if let Some(n) = raw_limit {
                let v = *n.get_ref();
                *target = u32::try_from(v)
                    .ok()
                    .filter(|v| *v <= max)
                    .ok_or_else(|| invalid(key, n.span(), format!("{v} is outside 0–{max}")))?;
            }
        }
        if let Some(t) = raw.day_starts_at {
            config.day_starts_at = parse_time_of_day(t.get_ref())
                .map_err(|m| invalid("day_starts_at", t.span(), m.to_string()))?;
        }
        if let Some(l) = raw.language {
            let lang = l.get_ref();
            if !LANGUAGES.contains(&lang.as_str()) {
                return Err(invalid(
                    "language",
                    l.span(),
                    format!("{lang:?} is not one of {}", LANGUAGES.join(", ")),
                ));
            }
            config.language = lang.clone();
        }
        if let Some(ps) = raw.fsrs_parameters {
            let values = ps.get_ref();
            if values.len() != 21 {
                return Err(invalid(
                    "fsrs_parameters",
                    ps.span(),
                    format!("{} numbers; FSRS-6 has 21", values.len()),
                ));
            }
            let mut w = [0.0; 21];
            for (i, (v, (lo, hi))) in values.iter().zip(PARAMETER_BOUNDS).enumerate() {
                let x = *v.get_ref();
                if !x.is_finite() || !(lo..=hi).contains(&x) {
                    return Err(invalid(
                        &format!("fsrs_parameters[{i}]"),
                        v.span(),
                        format!("{x} is outside {lo}–{hi}, the range FSRS fits it in"),
                    ));
                }
                w[i] = x;
            }
            config.fsrs_parameters = Some(w);
        }
        if let Some(t) = raw.fsrs_fitted_at {
            config.fsrs_fitted_at = Some(
                chrono::DateTime::parse_from_rfc3339(t.get_ref()).map_err(|e| {
                    invalid(
                        "fsrs_fitted_at",
                        t.span(),
                        format!("{:?} is not an RFC 3339 time ({e})", t.get_ref()),
                    )
                })?,
            );
        }
        if let Some(b) = raw.bury_siblings {
            config.bury_siblings = b;
        }
        if let Some(n) = raw.leech_threshold {
            let v = *n.get_ref();
            config.leech_threshold =
                u32::try_from(v)
                    .ok()
                    .filter(|v| *v <= 1000)
                    .ok_or_else(|| {
                        invalid(
                            "leech_threshold",
                            n.span(),
                            format!("{v} is outside 0–1000"),
                        )
                    })?;
        }
        if let Some(a) = raw.leech_action {
            config.leech_action = [LeechAction::Suspend, LeechAction::Tag]
                .into_iter()
                .find(|x| x.as_str() == a.get_ref())
                .ok_or_else(|| {
                    invalid(
                        "leech_action",
                        a.span(),
                        format!("{:?} is not one of \"suspend\", \"tag\"", a.get_ref()),
                    )
                })?;
        }
        let base = path.parent().unwrap_or(Path::new(""));
        let home = std::env::var_os("HOME");
        for (i, p) in raw.deck_paths.iter().flatten().enumerate() {
            if p.get_ref().trim().is_empty() {
                return Err(invalid(
                    &format!("deck_paths[{i}]"),
                    p.span(),
                    "an empty path names no folder".to_string(),
                ));
            }
            let dir = expand_home(p.get_ref(), home.as_deref())
                .map_err(|m| invalid(&format!("deck_paths[{i}]"), p.span(), m.to_string()))?;
            config.deck_paths.push(base.join(dir));
        }
        if let Some(d) = raw.sync_dir {
            if d.get_ref().trim().is_empty() {
                return Err(invalid(
                    "sync_dir",
                    d.span(),
                    "an empty path names no folder".to_string(),
                ));
            }
            let dir = expand_home(d.get_ref(), home.as_deref())
                .map_err(|m| invalid("sync_dir", d.span(), m.to_string()))?;
            config.sync_dir = Some(base.join(dir));
        }
        if let Some(n) = raw.maximum_interval {
            config.maximum_interval = super::preset::maximum_interval("maximum_interval", &n)
                .map_err(|(k, s, m)| invalid(&k, s, m))?;
        }
        if let Some(b) = raw.hide_bundled {
            config.hide_bundled = b;
        }
        config.presets = super::preset::read_presets(raw.preset.unwrap_or_default())
            .map_err(|(k, s, m)| invalid(&k, s, m))?;
        config.decks = super::preset::read_decks(raw.deck.unwrap_or_default(), &config.presets)
            .map_err(|(k, s, m)| invalid(&k, s, m))?;
        if let Some(b) = raw.load_balance {
            config.load_balance = b;
        }
        if let Some(t) = raw.easy_days {
            config.easy_days = parse_easy_days(&t, &invalid)?;
        }
        if let Some(d) = raw.exam_date {
            config.exam_date =
                Some(parse_exam_date(d.get_ref()).map_err(|m| invalid("exam_date", d.span(), m))?);
        }
        Ok(config)
    }

    /// The remembered exam date while it is still ahead (`today` or later).
    pub fn exam_ahead(&self, today: chrono::NaiveDate) -> Option<chrono::NaiveDate> {
        self.exam_date.filter(|d| *d >= today)
    }

    /// Remembers `exam` in the config file at `path` (`exam_date`), keeping
    /// every other line as it is.
    pub fn save_exam_date(
        &mut self,
        path: &Path,
        exam: chrono::NaiveDate,
    ) -> Result<(), ConfigError> {
        self.exam_date = Some(exam);
        let value = toml::Value::String(exam.format("%Y-%m-%d").to_string());
        let text = read_or_empty(path)?;
        let updated =
            set_key_in_text(&text, "exam_date", &value).map_err(|e| ConfigError::Parse {
                path: path.to_path_buf(),
                message: e.to_string(),
            })?;
        write_atomically(path, &updated)
    }

    /// The value of `key` as it is written in a config file.
    pub(crate) fn value_of(&self, key: &str) -> Result<toml::Value, ConfigError> {
        let steps = |s: &[TimeDelta]| {
            toml::Value::Array(
                s.iter()
                    .map(|d| toml::Value::String(format_step(*d)))
                    .collect(),
            )
        };
        Ok(match key {
            "desired_retention" => toml::Value::Float(self.desired_retention),
            "learning_steps" => steps(&self.learning_steps),
            "relearning_steps" => steps(&self.relearning_steps),
            "fuzz" => toml::Value::Boolean(self.fuzz),
            "new_per_day" => toml::Value::Integer(i64::from(self.new_per_day)),
            "reviews_per_day" => toml::Value::Integer(i64::from(self.reviews_per_day)),
            "day_starts_at" => toml::Value::String(format!(
                "{:02}:{:02}",
                self.day_starts_at.hour(),
                self.day_starts_at.minute()
            )),
            "language" => toml::Value::String(self.language.clone()),
            "fsrs_parameters" | "fsrs_fitted_at" => {
                return self
                    .fitted_value_of(key)
                    .ok_or_else(|| ConfigError::UnknownKey(key.to_string()));
            }
            "bury_siblings" => toml::Value::Boolean(self.bury_siblings),
            "leech_threshold" => toml::Value::Integer(i64::from(self.leech_threshold)),
            "leech_action" => toml::Value::String(self.leech_action.as_str().to_string()),
            "maximum_interval" => toml::Value::Integer(i64::from(self.maximum_interval)),
            "hide_bundled" => toml::Value::Boolean(self.hide_bundled),
            other => return Err(ConfigError::UnknownKey(other.to_string())),
        })
    }

    /// The value of one of [`FITTED_KEYS`], `None` while unset.
    pub(crate) fn fitted_value_of(&self, key: &str) -> Option<toml::Value> {
        match key {
            "fsrs_parameters" => self
                .fsrs_parameters
                .map(|w| toml::Value::Array(w.iter().map(|x| toml::Value::Float(*x)).collect())),
            "fsrs_fitted_at" => self
                .fsrs_fitted_at
                .map(|t| toml::Value::String(t.to_rfc3339_opts(chrono::SecondsFormat::Secs, true))),
            _ => None,
        }
    }

    /// Writes this config's value of `key` into the file at `path`, keeping
    /// every other line (comments included) as it is. Creates the file and
    /// its directory when missing.
    pub fn save_key(&self, path: &Path, key: &str) -> Result<(), ConfigError> {
        let value = self.value_of(key)?;
        let text = read_or_empty(path)?;
        let updated = set_key_in_text(&text, key, &value).map_err(|e| ConfigError::Parse {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        write_atomically(path, &updated)
    }

    /// Writes every key whose value differs from the file (or, for keys the
    /// file lacks, from the default), keeping comments and layout.
    pub fn save(&self, path: &Path) -> Result<(), ConfigError> {
        let original = read_or_empty(path)?;
        let on_file = if original.trim().is_empty() {
            Config::default()
        } else {
            Config::parse(&original, path)?
        };
        let mut text = original.clone();
        for key in KEYS {
            let (mine, theirs) = (self.value_of(key)?, on_file.value_of(key)?);
            if mine != theirs {
                text = set_key_in_text(&text, key, &mine).map_err(|e| ConfigError::Parse {
                    path: path.to_path_buf(),
                    message: e.to_string(),
                })?;
            }
        }
        for key in FITTED_KEYS {
            if let Some(mine) = self.fitted_value_of(key)
                && Some(&mine) != on_file.fitted_value_of(key).as_ref()
            {
                text = set_key_in_text(&text, key, &mine).map_err(|e| ConfigError::Parse {
                    path: path.to_path_buf(),
                    message: e.to_string(),
                })?;
            }
        }
        text = self
            .set_tables_in_text(&text, &on_file)
            .map_err(|message| ConfigError::Parse {
                path: path.to_path_buf(),
                message,
            })?;
        if text == original && path.exists() {
            return Ok(());
        }
        write_atomically(path, &text)
    }

    /// Writes the preset and deck tables that differ from `on_file` into
    /// `text` (a key a preset no longer has is left as it is).
    fn set_tables_in_text(&self, text: &str, on_file: &Config) -> Result<String, String> {
        let mut text = text.to_string();
        for (name, preset) in &self.presets {
            let theirs = on_file.presets.get(name);
            if theirs.is_none() {
                // A preset with no key of its own is still a preset.
                text = super::preset::ensure_table(&text, &["preset", name])?;
            }
            for key in super::preset::PRESET_KEYS {
                if let Some(mine) = preset.value_of(key)
                    && theirs.and_then(|p| p.value_of(key)) != Some(mine.clone())
                {
                    text = super::preset::set_table_key(&text, &["preset", name], key, &mine)?;
                }
            }
        }
        for (id, deck) in &self.decks {
            if let Some(mine) = &deck.preset
                && on_file.preset_of(id) != Some(mine.as_str())
            {
                let value = toml::Value::String(mine.clone());
                text = super::preset::set_table_key(&text, &["deck", id], "preset", &value)?;
            }
        }
        Ok(text)
    }

    /// Writes one preset's `key` (one of [`super::preset::PRESET_KEYS`])
    /// into the file, creating the `[preset.NAME]` table when missing,
    /// keeping every other line.
    pub fn save_preset_key(&self, path: &Path, name: &str, key: &str) -> Result<(), ConfigError> {
        let value = self
            .presets
            .get(name)
            .and_then(|p| p.value_of(key))
            .ok_or_else(|| ConfigError::UnknownKey(format!("preset.{name}.{key}")))?;
        let text = read_or_empty(path)?;
        let updated = super::preset::set_table_key(&text, &["preset", name], key, &value).map_err(
            |message| ConfigError::Parse {
                path: path.to_path_buf(),
                message,
            },
        )?;
        write_atomically(path, &updated)
    }

    /// Writes which preset deck `id` uses into the file (`[deck.ID]
    /// preset = "NAME"`), keeping every other line.
    pub fn save_deck_preset(&self, path: &Path, id: &str) -> Result<(), ConfigError> {
        let name = self
            .preset_of(id)
            .ok_or_else(|| ConfigError::UnknownKey(format!("deck.{id}.preset")))?;
        let text = read_or_empty(path)?;
        let value = toml::Value::String(name.to_string());
        let updated = super::preset::set_table_key(&text, &["deck", id], "preset", &value)
            .map_err(|message| ConfigError::Parse {
                path: path.to_path_buf(),
                message,
            })?;
        write_atomically(path, &updated)
    }
}

impl Config {
    /// The settings deck `id` studies with: its preset's values over the
    /// top-level ones (the config itself when it has no preset).
    pub fn for_deck(&self, id: &str) -> Config {
        let Some(p) = self.preset_of(id).and_then(|n| self.presets.get(n)) else {
            return self.clone();
        };
        let mut c = self.clone();
        if let Some(v) = p.new_per_day {
            c.new_per_day = v;
        }
        if let Some(v) = p.reviews_per_day {
            c.reviews_per_day = v;
        }
        if let Some(v) = &p.learning_steps {
            c.learning_steps = v.clone();
        }
        if let Some(v) = &p.relearning_steps {
            c.relearning_steps = v.clone();
        }
        if let Some(v) = p.desired_retention {
            c.desired_retention = v;
        }
        if let Some(v) = p.maximum_interval {
            c.maximum_interval = v;
        }
        if let Some(v) = p.fsrs_parameters {
            c.fsrs_parameters = Some(v);
        }
        c
    }

    /// The name of the preset deck `id` uses, if any.
    pub fn preset_of(&self, id: &str) -> Option<&str> {
        self.decks.get(id).and_then(|d| d.preset.as_deref())
    }
}

/// A `day_starts_at` that is not `HH:MM`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0:?} is not a time of day; write HH:MM, e.g. \"04:00\"")]
struct NotATimeOfDay(String);

fn parse_time_of_day(text: &str) -> Result<NaiveTime, NotATimeOfDay> {
    let bad = || NotATimeOfDay(text.to_string());
    let (h, m) = text.trim().split_once(':').ok_or_else(bad)?;
    if h.is_empty() || h.len() > 2 || m.len() != 2 {
        return Err(bad());
    }
    let h: u32 = h.parse().map_err(|_| bad())?;
    let m: u32 = m.parse().map_err(|_| bad())?;
    NaiveTime::from_hms_opt(h, m, 0).ok_or_else(bad)
}

fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rfind('\n').map_or(before.chars().count(), |nl| {
        before[nl + 1..].chars().count()
    }) + 1;
    (line, column)
}

/// The config's text, opened as every file flipcard reads is (a FIFO at
/// its path is refused by name instead of blocking the app before it
/// starts).
fn read_file(path: &Path) -> std::io::Result<String> {
    flipcard_io::read_text(path)
}

fn read_or_empty(path: &Path) -> Result<String, ConfigError> {
    match read_file(path) {
        Ok(text) => Ok(text),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(String::new()),
        Err(source) => Err(ConfigError::Read {
            path: path.to_path_buf(),
            source,
        }),
    }
}

/// Replaces the value of a top-level `key` in TOML text, or appends the key.
/// Only the value's bytes change, so comments and the rest stay put.
/// A config file that is not TOML, in the parser's words.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
struct NotToml(String);

fn set_key_in_text(text: &str, key: &str, value: &toml::Value) -> Result<String, NotToml> {
    let doc = toml::de::DeTable::parse(text)
        .map_err(|e| NotToml(e.to_string().trim_end().to_string()))?;
    let existing = doc
        .get_ref()
        .iter()
        .find(|(k, _)| k.get_ref().as_ref() == key)
        .map(|(_, v)| v.span());
    let rendered = value.to_string();
    Ok(match existing {
        Some(span) => format!("{}{rendered}{}", &text[..span.start], &text[span.end..]),
        // After a table a new line would belong to it: the key goes
        // before the first table.
        None if doc
            .get_ref()
            .iter()
            .any(|(_, v)| matches!(v.get_ref(), toml::de::DeValue::Table(_))) =>
        {
            super::preset::set_top_key(text, key, value).map_err(NotToml)?
        }
        None => {
            let sep = if text.is_empty() || text.ends_with('\n') {
                ""
            } else {
                "\n"
            };
            format!("{text}{sep}{key} = {rendered}\n")
        }
    })
}

/// Replaces the config whole (a crash never leaves half of it), through a
/// symbolic link (a config kept in a dotfiles repository stays a link).
fn write_atomically(path: &Path, text: &str) -> Result<(), ConfigError> {
    flipcard_io::write_atomic(path, text.as_bytes(), flipcard_io::Durability::Synced).map_err(
        |source| ConfigError::Write {
            path: path.to_path_buf(),
            source,
        },
    )
}

/// `exam_date`: a day as `YYYY-MM-DD`, between the years 2000 and 9999.
pub fn parse_exam_date(text: &str) -> Result<chrono::NaiveDate, String> {
    let day = chrono::NaiveDate::parse_from_str(text.trim(), "%Y-%m-%d").map_err(|_| {
        format!(
            "\"{}\" is not a date as YYYY-MM-DD (example: 2026-11-22)",
            flipcard_text::safe::one_line(text)
        )
    })?;
    use chrono::Datelike as _;
    if !(2000..=9999).contains(&day.year()) {
        return Err(format!("{day} is outside the years 2000–9999"));
    }
    Ok(day)
}

/// `easy_days`: a table of weekdays (`mon` … `sun`), each the share of a
/// normal day's reviews that day should get, from 0 (as few as can be) to
/// 1 (normal, the default of a day not named).
fn parse_easy_days(
    table: &Spanned<std::collections::BTreeMap<String, Spanned<toml::Value>>>,
    invalid: &dyn Fn(&str, Range<usize>, String) -> ConfigError,
) -> Result<EasyDays, ConfigError> {
    let mut easy = EasyDays::default();
    for (day, value) in table.get_ref() {
        let Some(i) = WEEKDAYS.iter().position(|d| d == day) else {
            return Err(invalid(
                "easy_days",
                table.span(),
                format!(
                    "\"{}\" is not a weekday: one of {}",
                    flipcard_text::safe::one_line(day),
                    WEEKDAYS.join(", ")
                ),
            ));
        };
        let key = format!("easy_days.{day}");
        let share = match value.get_ref() {
            toml::Value::Float(x) => *x,
            toml::Value::Integer(n) => *n as f64,
            other => {
                return Err(invalid(
                    &key,
                    value.span(),
                    format!("a {} where a share from 0 to 1 goes", other.type_str()),
                ));
            }
        };
        if !(0.0..=1.0).contains(&share) {
            return Err(invalid(
                &key,
                value.span(),
                format!("{share} is outside 0–1 (the share of a normal day's reviews)"),
            ));
        }
        easy.0[i] = share;
    }
    Ok(easy)
}

impl fmt::Display for Config {
    /// The config as a complete TOML file.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for key in KEYS {
            if let Ok(v) = self.value_of(key) {
                writeln!(f, "{key} = {v}")?;
            }
        }
        for key in FITTED_KEYS {
            if let Some(v) = self.fitted_value_of(key) {
                writeln!(f, "{key} = {v}")?;
            }
        }
        for (name, preset) in &self.presets {
            write!(f, "\n[preset.{name}]\n{}", preset.to_toml())?;
        }
        for (id, deck) in &self.decks {
            writeln!(f, "\n[deck.{id}]")?;
            if let Some(p) = &deck.preset {
                writeln!(f, "preset = {}", toml::Value::String(p.clone()))?;
            }
        }
        Ok(())
    }
}

/// A config path as a shell would take it: a leading `~` or `~/` is the
/// home folder. `~user` is refused rather than looked up (and never taken
/// as a folder named `~user`), and so is `~` without `$HOME`.
fn expand_home(raw: &str, home: Option<&std::ffi::OsStr>) -> Result<PathBuf, HomeError> {
    let Some(rest) = raw.strip_prefix('~') else {
        return Ok(PathBuf::from(raw));
    };
    let rest = match rest.strip_prefix('/') {
        Some(rest) => rest,
        None if rest.is_empty() => "",
        None => return Err(HomeError::OtherUser(raw.to_string())),
    };
    match home.filter(|h| !h.is_empty()) {
        Some(h) => Ok(Path::new(h).join(rest)),
        None => Err(HomeError::NoHome(raw.to_string())),
    }
}

/// Why [`expand_home`] refused a path; each holds the path as written.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
enum HomeError {
    #[error("{0:?}: `~user` is not expanded; write the full path (or `~/…` for your own home)")]
    OtherUser(String),
    #[error("{0:?} starts with `~` but $HOME is not set; write the full path")]
    NoHome(String),
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Config, ConfigError> {
        Config::parse(text, Path::new("config.toml"))
    }

    #[test]
    fn empty_file_gives_defaults() {
        let c = parse("").unwrap();
        assert_eq!(c, Config::default());
        assert_eq!(
            c.learning_steps,
            vec![TimeDelta::minutes(1), TimeDelta::minutes(10)]
        );
        assert_eq!(c.relearning_steps, vec![TimeDelta::minutes(10)]);
        assert_eq!(c.day_starts_at, NaiveTime::from_hms_opt(4, 0, 0).unwrap());
        assert!(c.fuzz);
        assert_eq!((c.new_per_day, c.reviews_per_day), (20, 200));
    }

    #[test]
    fn every_key_is_read() {
        let c = parse(
            r#"
# my settings
desired_retention = 0.85
learning_steps = ["30s", "5m", "1h"]
relearning_steps = []
fuzz = false
new_per_day = 5
reviews_per_day = 50
day_starts_at = "23:30"
language = "hi-Latn"
"#,
        )
        .unwrap();
        assert_eq!(c.desired_retention, 0.85);
        assert_eq!(
            c.learning_steps,
            vec![
                TimeDelta::seconds(30),
                TimeDelta::minutes(5),
                TimeDelta::hours(1)
            ]
        );
        assert!(c.relearning_steps.is_empty());
        assert!(!c.fuzz);
        assert_eq!((c.new_per_day, c.reviews_per_day), (5, 50));
        assert_eq!(c.day_starts_at, NaiveTime::from_hms_opt(23, 30, 0).unwrap());
        assert_eq!(c.language, "hi-Latn");
    }

    #[test]
    fn deck_paths_and_sync_dir_are_taken_from_the_config_folder() {
        let c = Config::parse(
            "deck_paths = ['course/decks', '/srv/decks']\nsync_dir = 'Sync'\n",
            Path::new("/home/a/.config/flipcard/config.toml"),
        )
        .unwrap();
        assert_eq!(
            c.deck_paths,
            [
                PathBuf::from("/home/a/.config/flipcard/course/decks"),
                PathBuf::from("/srv/decks")
            ]
        );
        assert_eq!(
            c.sync_dir,
            Some(PathBuf::from("/home/a/.config/flipcard/Sync"))
        );
        let e = parse("deck_paths = ['ok', ' ']\n").unwrap_err().to_string();
        assert!(e.contains("`deck_paths[1]`: an empty path"), "{e}");
        let e = parse("sync_dir = 3\n").unwrap_err().to_string();
        assert!(e.contains("sync_dir"), "{e}");
    }

    #[test]
    fn a_leading_tilde_is_the_home_folder() {
        let home = Some(std::ffi::OsStr::new("/home/asha"));
        for (raw, want) in [
            ("~/Sync/flipcard", "/home/asha/Sync/flipcard"),
            ("~", "/home/asha"),
            ("~/", "/home/asha/"),
            ("Sync/~", "Sync/~"),
            ("/srv/~/decks", "/srv/~/decks"),
        ] {
            assert_eq!(
                expand_home(raw, home).unwrap(),
                PathBuf::from(want),
                "{raw}"
            );
        }
        let e = expand_home("~asha/Sync", home).unwrap_err().to_string();
        assert!(e.contains("`~user` is not expanded"), "{e}");
        let e = expand_home("~/Sync", None).unwrap_err().to_string();
        assert!(e.contains("$HOME is not set"), "{e}");
        // In a file, the error names the key and where it is.
        let e = parse("deck_paths = ['decks', '~bob/decks']\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("config.toml:1:24: `deck_paths[1]`: \"~bob/decks\": `~user`"),
            "{e}"
        );
        if let Some(h) = std::env::var_os("HOME").filter(|h| !h.is_empty()) {
            let c = parse("sync_dir = '~/Sync'\ndeck_paths = ['~/decks']\n").unwrap();
            assert_eq!(c.sync_dir, Some(Path::new(&h).join("Sync")));
            assert_eq!(c.deck_paths, [Path::new(&h).join("decks")]);
        }
    }

    #[test]
    fn load_balance_and_easy_days_are_read_and_checked() {
        let c = parse("").unwrap();
        assert!(c.load_balance, "on unless turned off");
        assert!(!parse("load_balance = false\n").unwrap().load_balance);
        assert!(c.easy_days.is_default());
        let c = parse("load_balance = true\neasy_days = { sat = 0.5, sun = 0 }\n").unwrap();
        assert!(c.load_balance);
        assert_eq!(c.easy_days.0, [1.0, 1.0, 1.0, 1.0, 1.0, 0.5, 0.0]);
        let c = parse("[easy_days]\nmon = 1\nwed = 0.25\n").unwrap();
        assert_eq!(c.easy_days.0[2], 0.25);
        for (text, want) in [
            (
                "easy_days = { sat = 1.5 }",
                "config.toml:1:21: `easy_days.sat`: 1.5 is outside 0–1",
            ),
            (
                "fuzz = true\neasy_days = { sun = -1 }",
                "config.toml:2:21: `easy_days.sun`: -1 is outside 0–1",
            ),
            (
                "easy_days = { sat = \"half\" }",
                "config.toml:1:21: `easy_days.sat`: a string where a share",
            ),
            (
                "easy_days = { saturday = 0.5 }",
                "config.toml:1:13: `easy_days`: \"saturday\" is not a weekday: one of mon, tue",
            ),
            (
                "easy_days = { \"s\\u001b[2Jat\" = 0.5 }",
                "`easy_days`: \"s\\u001b[2Jat\" is not a weekday",
            ),
        ] {
            let e = parse(text).unwrap_err().to_string();
            assert!(e.contains(want), "{text}: {e}");
            assert!(!e.contains('\u{1b}'), "{e}");
        }
        let e = parse("easy_days = 0.5").unwrap_err().to_string();
        assert!(e.contains("easy_days"), "{e}");
        let e = parse("load_balance = 1").unwrap_err().to_string();
        assert!(e.contains("load_balance"), "{e}");
    }

    #[test]
    fn the_exam_date_is_read_checked_and_remembered() {
        let c = parse("exam_date = \"2026-11-22\"\n").unwrap();
        let day = |s| chrono::NaiveDate::parse_from_str(s, "%Y-%m-%d").unwrap();
        assert_eq!(c.exam_date, Some(day("2026-11-22")));
        assert_eq!(c.exam_ahead(day("2026-11-22")), Some(day("2026-11-22")));
        assert_eq!(c.exam_ahead(day("2026-11-23")), None);
        for (text, want) in [
            (
                "exam_date = \"22/11/2026\"",
                "config.toml:1:13: `exam_date`: \"22/11/2026\" is not a date",
            ),
            (
                "exam_date = \"1999-12-31\"",
                "`exam_date`: 1999-12-31 is outside the years 2000–9999",
            ),
            ("exam_date = \"2026-02-30\"", "is not a date"),
        ] {
            let e = parse(text).unwrap_err().to_string();
            assert!(e.contains(want), "{text}: {e}");
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("config.toml");
        std::fs::write(&path, "# mine\nnew_per_day = 5\n").unwrap();
        let mut c = Config::load(Some(&path)).unwrap();
        c.save_exam_date(&path, day("2027-01-15")).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            text,
            "# mine\nnew_per_day = 5\nexam_date = \"2027-01-15\"\n"
        );
        c.save_exam_date(&path, day("2027-02-01")).unwrap();
        let again = Config::load(Some(&path)).unwrap();
        assert_eq!(again.exam_date, Some(day("2027-02-01")));
        assert_eq!(again.new_per_day, 5);
    }

    #[test]
    fn unknown_key_is_named() {
        let e = parse("desired_retention = 0.9\nnew_per_dya = 3\n").unwrap_err();
        let msg = e.to_string();
        assert!(msg.starts_with("config.toml:"), "{msg}");
        assert!(msg.contains("new_per_dya"), "{msg}");
        assert!(msg.contains("line 2"), "{msg}");
    }

    #[test]
    fn out_of_range_values_name_file_line_and_key() {
        let cases = [
            (
                "desired_retention = 0.99",
                "config.toml:1:21: `desired_retention`",
            ),
            (
                "fuzz = true\ndesired_retention = 0.5",
                "config.toml:2:21: `desired_retention`",
            ),
            ("new_per_day = -1", "`new_per_day`: -1 is outside"),
            ("reviews_per_day = 1000000", "`reviews_per_day`"),
            (
                "learning_steps = [\"1m\", \"10x\"]",
                "config.toml:1:25: `learning_steps[1]`",
            ),
            ("relearning_steps = [\"0m\"]", "`relearning_steps[0]`"),
            ("learning_steps = [\"400d\"]", "between 1s and 365d"),
            ("learning_steps = [\"m\"]", "not a duration"),
            ("day_starts_at = \"25:00\"", "`day_starts_at`"),
            ("day_starts_at = \"4\"", "HH:MM"),
            (
                "language = \"fr\"",
                "`language`: \"fr\" is not one of en, hi-Latn",
            ),
        ];
        for (text, want) in cases {
            let msg = parse(text).unwrap_err().to_string();
            assert!(msg.contains(want), "{text:?} gave {msg:?}, wanted {want:?}");
            assert!(msg.starts_with("config.toml:"), "{msg}");
        }
    }

    #[test]
    fn wrong_types_and_broken_toml_are_parse_errors() {
        for text in [
            "fuzz = \"yes\"",
            "new_per_day = 2.5",
            "learning_steps = 3",
            "x = = 1",
        ] {
            let e = parse(text).unwrap_err();
            assert!(matches!(e, ConfigError::Parse { .. }), "{text}: {e}");
        }
    }

    #[test]
    fn steps_round_trip_through_text() {
        for (text, d) in [
            ("45s", TimeDelta::seconds(45)),
            ("1m", TimeDelta::minutes(1)),
            ("90m", TimeDelta::minutes(90)),
            ("1h", TimeDelta::hours(1)),
            ("2d", TimeDelta::days(2)),
        ] {
            assert_eq!(parse_step(text), Ok(d));
            assert_eq!(parse_step(&format_step(d)), Ok(d));
        }
        assert_eq!(format_step(TimeDelta::seconds(3600)), "1h");
        assert_eq!(format_step(TimeDelta::seconds(61)), "61s");
    }

    #[test]
    fn missing_file_gives_defaults_and_none_too() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("nope.toml");
        assert_eq!(Config::load(Some(&path)).unwrap(), Config::default());
        assert_eq!(Config::load(None).unwrap(), Config::default());
    }

    #[test]
    fn unreadable_path_is_a_read_error() {
        let dir = tempfile::tempdir().unwrap();
        // A directory where the file should be.
        let e = Config::load(Some(dir.path())).unwrap_err();
        assert!(matches!(e, ConfigError::Read { .. }), "{e}");
        assert!(e.to_string().contains(&dir.path().display().to_string()));
    }

    #[test]
    fn save_key_keeps_comments_and_other_keys() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("config.toml");
        let original = "# study settings\nlanguage = \"en\"  # switch with l\n\nlearning_steps = [\n  \"1m\",\n  \"10m\",\n]\nnew_per_day = 7\n";
        std::fs::write(&path, original).unwrap();
        let mut c = Config::load(Some(&path)).unwrap();
        c.language = "hi-Latn".into();
        c.save_key(&path, "language").unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text, original.replace("\"en\"", "\"hi-Latn\""));
        assert_eq!(Config::load(Some(&path)).unwrap(), c);

        c.learning_steps = vec![TimeDelta::minutes(2)];
        c.save_key(&path, "learning_steps").unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.contains("learning_steps = [\"2m\"]\nnew_per_day = 7\n"),
            "{text}"
        );
        assert!(text.starts_with("# study settings\nlanguage = \"hi-Latn\"  # switch with l\n"));
        assert_eq!(Config::load(Some(&path)).unwrap(), c);
    }

    #[test]
    fn save_key_writes_through_a_symbolic_link() {
        let dir = tempfile::tempdir().unwrap();
        let dotfiles = dir.path().join("dotfiles");
        std::fs::create_dir(&dotfiles).unwrap();
        let real = dotfiles.join("flipcard.toml");
        std::fs::write(&real, "# mine\nlanguage = \"en\"\n").unwrap();
        // A link to a link, the second one relative.
        let hop = dir.path().join("hop.toml");
        std::os::unix::fs::symlink("dotfiles/flipcard.toml", &hop).unwrap();
        let link = dir.path().join("config.toml");
        std::os::unix::fs::symlink(&hop, &link).unwrap();

        let mut c = Config::load(Some(&link)).unwrap();
        c.language = "hi-Latn".into();
        c.save_key(&link, "language").unwrap();
        assert!(
            std::fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert!(
            std::fs::symlink_metadata(&hop)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(
            std::fs::read_to_string(&real).unwrap(),
            "# mine\nlanguage = \"hi-Latn\"\n"
        );
        let leftovers = std::fs::read_dir(&dotfiles).unwrap().count();
        assert_eq!(leftovers, 1, "no temporary file left behind");

        // A loop is an error, not a hang.
        let a = dir.path().join("a.toml");
        let b = dir.path().join("b.toml");
        std::os::unix::fs::symlink(&b, &a).unwrap();
        std::os::unix::fs::symlink(&a, &b).unwrap();
        let e = c.save_key(&a, "language").unwrap_err();
        assert!(e.to_string().contains("symbolic links"), "{e}");
    }

    #[test]
    fn save_key_creates_missing_file_and_dir() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sub").join("config.toml");
        let c = Config {
            language: "hi-Latn".into(),
            ..Config::default()
        };
        c.save_key(&path, "language").unwrap();
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "language = \"hi-Latn\"\n"
        );
        assert!(matches!(
            c.save_key(&path, "colour"),
            Err(ConfigError::UnknownKey(k)) if k == "colour"
        ));
    }

    #[test]
    fn save_writes_only_changed_keys() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("config.toml");
        std::fs::write(&path, "# mine\nfuzz = false\n").unwrap();
        let mut c = Config::load(Some(&path)).unwrap();
        c.new_per_day = 30;
        c.day_starts_at = NaiveTime::from_hms_opt(5, 15, 0).unwrap();
        c.save(&path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            text,
            "# mine\nfuzz = false\nnew_per_day = 30\nday_starts_at = \"05:15\"\n"
        );
        assert_eq!(Config::load(Some(&path)).unwrap(), c);
    }

    #[test]
    fn display_is_a_loadable_file() {
        let c = Config {
            desired_retention: 0.8,
            learning_steps: vec![TimeDelta::seconds(30), TimeDelta::days(1)],
            fuzz: false,
            ..Config::default()
        };
        assert_eq!(parse(&c.to_string()).unwrap(), c);
    }

    fn fitted_line(w: &[f64]) -> String {
        let items: Vec<String> = w.iter().map(|x| format!("{x:?}")).collect();
        format!("fsrs_parameters = [{}]", items.join(", "))
    }

    #[test]
    fn fitted_parameters_are_read_and_checked() {
        let w = crate::sched::scheduler::default_parameters();
        let c = parse(&format!(
            "{}\nfsrs_fitted_at = \"2026-11-20T08:00:00Z\"\n",
            fitted_line(&w)
        ))
        .unwrap();
        assert_eq!(c.fsrs_parameters, Some(w));
        assert_eq!(
            c.fsrs_fitted_at.map(|t| t.to_rfc3339()),
            Some("2026-11-20T08:00:00+00:00".to_string())
        );
        assert_eq!(parse(&c.to_string()).unwrap(), c);

        let short = parse(&format!("# mine\n{}", fitted_line(&w[..20]))).unwrap_err();
        assert_eq!(
            short.to_string(),
            "config.toml:2:19: `fsrs_parameters`: 20 numbers; FSRS-6 has 21"
        );
        let mut bad = w;
        bad[20] = 0.05;
        let msg = parse(&fitted_line(&bad)).unwrap_err().to_string();
        assert!(msg.starts_with("config.toml:1:"), "{msg}");
        assert!(
            msg.contains("`fsrs_parameters[20]`: 0.05 is outside 0.1–0.8"),
            "{msg}"
        );
        let nan = fitted_line(&w).replacen("0.212", "nan", 1);
        let msg = parse(&nan).unwrap_err().to_string();
        assert!(msg.contains("`fsrs_parameters[0]`: NaN"), "{msg}");
        let when = parse("fsrs_fitted_at = \"last week\"")
            .unwrap_err()
            .to_string();
        assert!(
            when.starts_with("config.toml:1:18: `fsrs_fitted_at`"),
            "{when}"
        );
        assert!(parse("fsrs_parameters = [\"a\"]").is_err());
    }

    #[test]
    fn fitted_parameters_are_saved_keeping_comments() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("config.toml");
        let original = "# my settings\nlanguage = \"hi-Latn\" # chosen\n";
        std::fs::write(&path, original).unwrap();
        let mut c = Config::load(Some(&path)).unwrap();
        let mut w = crate::sched::scheduler::default_parameters();
        w[0] = 0.5;
        c.fsrs_parameters = Some(w);
        c.fsrs_fitted_at = chrono::DateTime::parse_from_rfc3339("2026-11-20T08:00:00Z").ok();
        c.save_key(&path, "fsrs_parameters").unwrap();
        c.save_key(&path, "fsrs_fitted_at").unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.starts_with(original), "{text}");
        assert!(text.contains("fsrs_parameters = [0.5, 1.2931,"), "{text}");
        assert_eq!(Config::load(Some(&path)).unwrap(), c);
        // Fitted again: the value is replaced in place.
        w[0] = 0.7;
        c.fsrs_parameters = Some(w);
        c.save_key(&path, "fsrs_parameters").unwrap();
        let again = std::fs::read_to_string(&path).unwrap();
        assert_eq!(again.matches("fsrs_parameters").count(), 1, "{again}");
        assert_eq!(Config::load(Some(&path)).unwrap(), c);
    }
}
