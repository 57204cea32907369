//! The learner's settings, read from `config.toml`.
//!
//! A missing file means the defaults. Unknown keys and out-of-range values are
//! errors that name the file, the line and the key: a typo must not silently
//! fall back to a default. Saving one key edits the file in place, so the
//! learner's comments and other keys survive.

use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};

use chrono::{NaiveTime, TimeDelta, Timelike};
use serde::Deserialize;
use toml::Spanned;

/// The languages the app speaks (decks may declare these).
pub const LANGUAGES: [&str; 2] = ["en", "hi-Latn"];

/// Allowed range of `desired_retention`.
pub const RETENTION_RANGE: (f64, f64) = (0.70, 0.97);

/// The longest learning or relearning step accepted.
const MAX_STEP: TimeDelta = TimeDelta::days(365);

/// Every key a config file may hold, in the order `save` writes them.
pub const KEYS: [&str; 11] = [
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
];

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
    /// When one item of a card is answered, its other items (the other
    /// direction, the other cloze numbers) wait until the next day.
    pub bury_siblings: bool,
    /// Lapses at which an item becomes a leech (0: never).
    pub leech_threshold: u32,
    pub leech_action: LeechAction,
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
            bury_siblings: true,
            leech_threshold: 8,
            leech_action: LeechAction::Suspend,
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
    #[error("`{0}` is not a config key; known keys: {keys}", keys = KEYS.join(", "))]
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
    bury_siblings: Option<bool>,
    leech_threshold: Option<Spanned<i64>>,
    leech_action: Option<Spanned<String>>,
}

impl Config {
    /// Reads the config file. `None` (no config location known) and a file
    /// that does not exist both give the defaults.
    pub fn load(path: Option<&Path>) -> Result<Config, ConfigError> {
        let Some(path) = path else {
            return Ok(Config::default());
        };
        match std::fs::read_to_string(path) {
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
                            .map_err(|m| invalid(&format!("{key}[{i}]"), s.span(), m))
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
                .map_err(|m| invalid("day_starts_at", t.span(), m))?;
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
        Ok(config)
    }

    /// The value of `key` as it is written in a config file.
    pub fn value_of(&self, key: &str) -> Result<toml::Value, ConfigError> {
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
            "bury_siblings" => toml::Value::Boolean(self.bury_siblings),
            "leech_threshold" => toml::Value::Integer(i64::from(self.leech_threshold)),
            "leech_action" => toml::Value::String(self.leech_action.as_str().to_string()),
            other => return Err(ConfigError::UnknownKey(other.to_string())),
        })
    }

    /// Writes this config's value of `key` into the file at `path`, keeping
    /// every other line (comments included) as it is. Creates the file and
    /// its directory when missing.
    pub fn save_key(&self, path: &Path, key: &str) -> Result<(), ConfigError> {
        let value = self.value_of(key)?;
        let text = read_or_empty(path)?;
        let updated =
            set_key_in_text(&text, key, &value).map_err(|message| ConfigError::Parse {
                path: path.to_path_buf(),
                message,
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
                text =
                    set_key_in_text(&text, key, &mine).map_err(|message| ConfigError::Parse {
                        path: path.to_path_buf(),
                        message,
                    })?;
            }
        }
        if text == original && path.exists() {
            return Ok(());
        }
        write_atomically(path, &text)
    }
}

/// A learning step as written in the config: a whole number and a unit,
/// `30s`, `1m`, `10m`, `1h`, `1d`.
pub fn parse_step(text: &str) -> Result<TimeDelta, String> {
    let t = text.trim();
    let split = t.find(|c: char| !c.is_ascii_digit()).unwrap_or(t.len());
    let (number, unit) = t.split_at(split);
    let hint = "write a whole number and a unit: 30s, 1m, 10m, 1h, 1d";
    let n: i64 = number
        .parse()
        .map_err(|_| format!("{text:?} is not a duration; {hint}"))?;
    let step = match unit {
        "s" => TimeDelta::try_seconds(n),
        "m" => TimeDelta::try_minutes(n),
        "h" => TimeDelta::try_hours(n),
        "d" => TimeDelta::try_days(n),
        _ => return Err(format!("{text:?} has no known unit; {hint}")),
    }
    .ok_or_else(|| format!("{text:?} is too long"))?;
    if step <= TimeDelta::zero() || step > MAX_STEP {
        return Err(format!("{text:?} must be between 1s and 365d"));
    }
    Ok(step)
}

/// The inverse of [`parse_step`]: the largest unit that divides the step.
pub fn format_step(d: TimeDelta) -> String {
    let s = d.num_seconds();
    for (unit, size) in [("d", 86_400), ("h", 3_600), ("m", 60)] {
        if s != 0 && s % size == 0 {
            return format!("{}{unit}", s / size);
        }
    }
    format!("{s}s")
}

fn parse_time_of_day(text: &str) -> Result<NaiveTime, String> {
    let bad = || format!("{text:?} is not a time of day; write HH:MM, e.g. \"04:00\"");
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

fn read_or_empty(path: &Path) -> Result<String, ConfigError> {
    match std::fs::read_to_string(path) {
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
fn set_key_in_text(text: &str, key: &str, value: &toml::Value) -> Result<String, String> {
    let doc = toml::de::DeTable::parse(text).map_err(|e| e.to_string().trim_end().to_string())?;
    let existing = doc
        .get_ref()
        .iter()
        .find(|(k, _)| k.get_ref().as_ref() == key)
        .map(|(_, v)| v.span());
    let rendered = value.to_string();
    Ok(match existing {
        Some(span) => format!("{}{rendered}{}", &text[..span.start], &text[span.end..]),
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

/// Write to a sibling temporary file and rename it over the target, so a
/// crash never leaves a half-written config. A symbolic link (a config kept
/// in a dotfiles repository) is written through: the file it points to is
/// replaced, the link stays.
fn write_atomically(path: &Path, text: &str) -> Result<(), ConfigError> {
    let err = |source| ConfigError::Write {
        path: path.to_path_buf(),
        source,
    };
    let target = resolve_links(path).map_err(err)?;
    if let Some(dir) = target.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(err)?;
    }
    let mut tmp = target.as_os_str().to_owned();
    tmp.push(format!(".tmp-{}", std::process::id()));
    let tmp = PathBuf::from(tmp);
    let written = (|| {
        use std::io::Write as _;
        let mut file = std::fs::File::create(&tmp)?;
        file.write_all(text.as_bytes())?;
        file.sync_all()?;
        std::fs::rename(&tmp, &target)
    })();
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    written.map_err(err)
}

/// The file `path` finally names once every symbolic link on the way is
/// followed (the last target need not exist yet).
fn resolve_links(path: &Path) -> std::io::Result<PathBuf> {
    let mut current = path.to_path_buf();
    // Linux's own limit on links followed while resolving one path.
    for _ in 0..40 {
        match std::fs::symlink_metadata(&current) {
            Ok(m) if m.file_type().is_symlink() => {
                let next = std::fs::read_link(&current)?;
                current = match current.parent() {
                    Some(dir) if next.is_relative() => dir.join(next),
                    _ => next,
                };
            }
            _ => return Ok(current),
        }
    }
    Err(std::io::Error::other("too many levels of symbolic links"))
}

impl fmt::Display for Config {
    /// The config as a complete TOML file.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for key in KEYS {
            if let Ok(v) = self.value_of(key) {
                writeln!(f, "{key} = {v}")?;
            }
        }
        Ok(())
    }
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
}
