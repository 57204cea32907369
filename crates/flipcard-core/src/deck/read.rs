//! Reading parsed TOML values with their spans, reporting every wrong type,
//! missing field and unknown field instead of stopping at the first. The
//! values read ([`Str`], [`Num`], [`RawText`], ...) are here too: the raw
//! stage ([`super::raw`]) builds its files from them and re-exports them.

use std::fmt::Display;
use std::ops::Range;

use toml::Spanned;
use toml::de::{DeArray, DeTable, DeValue};

use super::report::FileReport;
use super::suggest;

pub type Value<'i> = Spanned<DeValue<'i>>;

pub type Span = Range<usize>;

/// A string value with the span of its token (quotes included).
#[derive(Debug, Clone, PartialEq)]
pub struct Str {
    pub value: String,
    pub span: Span,
}

/// A number value (integers are widened) with its span.
#[derive(Debug, Clone, PartialEq)]
pub struct Num {
    pub value: f64,
    pub span: Span,
}

/// A boolean with its position.
#[derive(Debug, Clone, PartialEq)]
pub struct Flag {
    pub value: bool,
    pub span: Span,
}

/// An array with the span of the whole array.
#[derive(Debug, Clone, PartialEq)]
pub struct List<T> {
    pub items: Vec<T>,
    pub span: Span,
}

/// A translatable text as written.
#[derive(Debug, Clone, PartialEq)]
pub enum RawText {
    /// A plain string: allowed when the deck declares a single language.
    Plain(Str),
    /// `{ en = '...', hi-Latn = '...' }`: each language key (with the key's
    /// span) and its string.
    ByLang {
        span: Span,
        entries: Vec<(Str, Str)>,
    },
}

impl RawText {
    pub fn span(&self) -> Span {
        match self {
            RawText::Plain(s) => s.span.clone(),
            RawText::ByLang { span, .. } => span.clone(),
        }
    }
}

/// A typed card's accepted answers as written: one list for every
/// language, or `{ en = [...], hi-Latn = [...] }`.
#[derive(Debug, Clone, PartialEq)]
pub enum RawAccept {
    All(List<Str>),
    ByLang {
        span: Span,
        /// Each language key (with its span) and its list.
        entries: Vec<(Str, List<Str>)>,
    },
}

impl RawAccept {
    pub fn span(&self) -> Span {
        match self {
            RawAccept::All(l) => l.span.clone(),
            RawAccept::ByLang { span, .. } => span.clone(),
        }
    }

    /// Every answer, in the order written.
    pub fn items(&self) -> Vec<&Str> {
        match self {
            RawAccept::All(l) => l.items.iter().collect(),
            RawAccept::ByLang { entries, .. } => {
                entries.iter().flat_map(|(_, l)| l.items.iter()).collect()
            }
        }
    }
}

/// "a string", "an integer", ... for type errors.
pub(crate) fn type_name(v: &DeValue) -> &'static str {
    match v {
        DeValue::String(_) => "a string",
        DeValue::Integer(_) => "an integer",
        DeValue::Float(_) => "a float",
        DeValue::Boolean(_) => "a boolean",
        DeValue::Datetime(_) => "a date-time",
        DeValue::Array(_) => "an array",
        DeValue::Table(_) => "a table",
    }
}

fn wrong_type(rep: &mut FileReport, v: &Value, what: impl Display + Copy, expected: &str) {
    rep.error(
        v.span(),
        format!(
            "{what} must be {expected}, found {}",
            type_name(v.get_ref())
        ),
        None,
    );
}

/// The fields of one table: unknown keys are reported when it is opened,
/// missing required ones when asked for.
pub(crate) struct Fields<'a, 'i> {
    table: &'a DeTable<'i>,
    span: Range<usize>,
    /// How the table is named in messages, e.g. "[[card]] `c1`".
    pub what: String,
}

impl<'a, 'i> Fields<'a, 'i> {
    /// Opens `table`, reporting each key not in `known` (with a
    /// did-you-mean, or `hint_for` when it knows better).
    pub fn open(
        rep: &mut FileReport,
        table: &'a DeTable<'i>,
        span: Range<usize>,
        what: &str,
        known: &[&str],
        hint_for: impl Fn(&str) -> Option<String>,
    ) -> Fields<'a, 'i> {
        for (key, _) in table.iter() {
            let name: &str = key.get_ref();
            if known.contains(&name) {
                continue;
            }
            let hint =
                hint_for(name).or_else(|| suggest::did_you_mean(name, known.iter().copied()));
            let hint = hint.or_else(|| Some(format!("known fields: {}", known.join(", "))));
            rep.error(
                key.span(),
                format!("unknown field `{name}` in {what}"),
                hint,
            );
        }
        Fields {
            table,
            span,
            what: what.to_string(),
        }
    }

    /// The same fields, named differently in messages.
    pub fn named(self, what: String) -> Fields<'a, 'i> {
        Fields { what, ..self }
    }

    pub fn get(&self, key: &str) -> Option<&'a Value<'i>> {
        self.table
            .iter()
            .find(|(k, _)| {
                let name: &str = k.get_ref();
                name == key
            })
            .map(|(_, v)| v)
    }

    /// A required field: reported at the table when missing.
    pub fn require(&self, rep: &mut FileReport, key: &str) -> Option<&'a Value<'i>> {
        let v = self.get(key);
        if v.is_none() {
            rep.error(
                self.span.clone(),
                format!("{} is missing the required field `{key}`", self.what),
                None,
            );
        }
        v
    }

    /// The field's value: a missing required field is reported, a missing
    /// optional one is simply absent.
    fn field(&self, rep: &mut FileReport, key: &str, required: bool) -> Option<&'a Value<'i>> {
        if required {
            self.require(rep, key)
        } else {
            self.get(key)
        }
    }

    pub fn string(&self, rep: &mut FileReport, key: &str, required: bool) -> Option<Str> {
        let v = self.field(rep, key, required)?;
        string(rep, v, format_args!("`{key}`"))
    }

    pub fn number(&self, rep: &mut FileReport, key: &str, required: bool) -> Option<Num> {
        let v = self.field(rep, key, required)?;
        number(rep, v, format_args!("`{key}`"))
    }

    pub fn text(&self, rep: &mut FileReport, key: &str, required: bool) -> Option<RawText> {
        let v = self.field(rep, key, required)?;
        text(rep, v, format_args!("`{key}`"))
    }

    /// An optional boolean.
    pub fn flag(&self, rep: &mut FileReport, key: &str) -> Option<Flag> {
        let v = self.get(key)?;
        match v.get_ref() {
            DeValue::Boolean(b) => Some(Flag {
                value: *b,
                span: v.span(),
            }),
            _ => {
                wrong_type(rep, v, format_args!("`{key}`"), "true or false");
                None
            }
        }
    }

    pub fn strings(&self, rep: &mut FileReport, key: &str, required: bool) -> Option<List<Str>> {
        let v = self.field(rep, key, required)?;
        let what = format_args!("`{key}`");
        let arr = array(rep, v, what)?;
        let items = arr
            .iter()
            .filter_map(|item| string(rep, item, format_args!("each item of {what}")))
            .collect();
        Some(List {
            items,
            span: v.span(),
        })
    }

    /// A typed card's `accept`: an array of strings, or a table of such
    /// arrays by language.
    pub fn accept(&self, rep: &mut FileReport, key: &str) -> Option<RawAccept> {
        let v = self.get(key)?;
        let strings = |rep: &mut FileReport, v: &Value, what: &str| -> Option<List<Str>> {
            let arr = array(rep, v, what)?;
            let items = arr
                .iter()
                .filter_map(|item| string(rep, item, &format!("each item of {what}")))
                .collect();
            Some(List {
                items,
                span: v.span(),
            })
        };
        match v.get_ref() {
            DeValue::Table(t) => {
                let mut entries = Vec::new();
                let mut ok = true;
                for (k, value) in t.iter() {
                    let lang = Str {
                        value: k.get_ref().to_string(),
                        span: k.span(),
                    };
                    let what = format!("the `{}` answers of `{key}`", lang.value);
                    match strings(rep, value, &what) {
                        Some(list) => entries.push((lang, list)),
                        None => ok = false,
                    }
                }
                ok.then_some(RawAccept::ByLang {
                    span: v.span(),
                    entries,
                })
            }
            DeValue::Array(_) => strings(rep, v, &format!("`{key}`")).map(RawAccept::All),
            _ => {
                wrong_type(
                    rep,
                    v,
                    &format!("`{key}`"),
                    "an array, or a table of arrays by language",
                );
                None
            }
        }
    }

    pub fn numbers(&self, rep: &mut FileReport, key: &str, required: bool) -> Option<List<Num>> {
        let v = self.field(rep, key, required)?;
        let what = format!("`{key}`");
        let arr = array(rep, v, &what)?;
        let mut items = Vec::new();
        let mut ok = true;
        for item in arr.iter() {
            match number(rep, item, &format!("each item of {what}")) {
                Some(n) => items.push(n),
                None => ok = false,
            }
        }
        ok.then_some(List {
            items,
            span: v.span(),
        })
    }
}

pub fn string(rep: &mut FileReport, v: &Value, what: impl Display + Copy) -> Option<Str> {
    match v.get_ref() {
        DeValue::String(s) => Some(Str {
            value: s.to_string(),
            span: v.span(),
        }),
        _ => {
            wrong_type(rep, v, what, "a string");
            None
        }
    }
}

/// An integer or a float, as f64 (`inf` and `nan` pass here; the checks
/// that need finite numbers report them).
pub fn number(rep: &mut FileReport, v: &Value, what: impl Display + Copy) -> Option<Num> {
    let value = match v.get_ref() {
        DeValue::Integer(i) => match i64::from_str_radix(i.as_str(), i.radix()) {
            Ok(n) => n as f64,
            Err(_) => {
                rep.error(v.span(), format!("{what}: integer out of range"), None);
                return None;
            }
        },
        DeValue::Float(f) => match f.as_str().parse::<f64>() {
            Ok(x) => x,
            Err(_) => {
                rep.error(v.span(), format!("{what}: not a number"), None);
                return None;
            }
        },
        DeValue::String(text) => {
            // "27.39 AU/yr" or "2.04": what was meant, said back.
            let help = number_in_quotes(text, what);
            rep.error(
                v.span(),
                format!("{what} must be a number, found a string"),
                help,
            );
            return None;
        }
        _ => {
            wrong_type(rep, v, what, "a number");
            return None;
        }
    };
    Some(Num {
        value,
        span: v.span(),
    })
}

/// The help for a number written as a string: `10.32` without its quotes,
/// or `27.39 AU/yr` as the number and its unit apart (`unit` is where a
/// number prompt's unit goes). `None` when the text does not start with a
/// number.
pub(crate) fn number_in_quotes(text: &str, what: impl Display) -> Option<String> {
    let text = text.trim();
    let end = text
        .char_indices()
        .find(|&(i, c)| {
            !(c.is_ascii_digit()
                || c == '.'
                || ((c == '-' || c == '+') && (i == 0 || text[..i].ends_with(['e', 'E'])))
                || ((c == 'e' || c == 'E') && i > 0))
        })
        .map_or(text.len(), |(i, _)| i);
    let number: f64 = text[..end].parse().ok().filter(|n: &f64| n.is_finite())?;
    let what = what.to_string();
    let key = what.strip_prefix('`')?.strip_suffix('`')?;
    let unit = text[end..].trim();
    let number = flipcard_text::num::show(number);
    if unit.is_empty() {
        return Some(format!("write it without quotes: {key} = {number}"));
    }
    // Said back only when it reads plainly between quotes.
    let plain = unit.len() <= 32
        && !unit
            .chars()
            .any(|c| c.is_control() || c == '"' || c == '\\');
    plain.then(|| {
        format!("write the number and the unit apart: {key} = {number} and unit = \"{unit}\"")
    })
}

pub fn array<'a, 'i>(
    rep: &mut FileReport,
    v: &'a Value<'i>,
    what: impl Display + Copy,
) -> Option<&'a DeArray<'i>> {
    match v.get_ref() {
        DeValue::Array(a) => Some(a),
        _ => {
            wrong_type(rep, v, what, "an array");
            None
        }
    }
}

pub fn table<'a, 'i>(
    rep: &mut FileReport,
    v: &'a Value<'i>,
    what: impl Display + Copy,
) -> Option<&'a DeTable<'i>> {
    match v.get_ref() {
        DeValue::Table(t) => Some(t),
        _ => {
            wrong_type(rep, v, what, "a table");
            None
        }
    }
}

/// A text: a table with one string per language, or (for a deck with one
/// language) a plain string.
pub fn text(rep: &mut FileReport, v: &Value, what: impl Display + Copy) -> Option<RawText> {
    match v.get_ref() {
        DeValue::String(_) => string(rep, v, what).map(RawText::Plain),
        DeValue::Table(t) => {
            let mut entries = Vec::new();
            let mut ok = true;
            for (key, value) in t.iter() {
                let lang = Str {
                    value: key.get_ref().to_string(),
                    span: key.span(),
                };
                match string(
                    rep,
                    value,
                    format_args!("the `{}` text of {what}", lang.value),
                ) {
                    Some(s) => entries.push((lang, s)),
                    None => ok = false,
                }
            }
            ok.then_some(RawText::ByLang {
                span: v.span(),
                entries,
            })
        }
        _ => {
            rep.error(
                v.span(),
                format!(
                    "{what} must be a text, a table of languages like {{ en = '...' }}, found {}",
                    type_name(v.get_ref())
                ),
                None,
            );
            None
        }
    }
}

/// The tables of an array-of-tables field (`[[card]]`), each with its span.
pub fn tables<'a, 'i>(
    rep: &mut FileReport,
    v: &'a Value<'i>,
    name: &str,
) -> Vec<(&'a DeTable<'i>, Range<usize>)> {
    let Some(arr) = (match v.get_ref() {
        DeValue::Array(a) => Some(a),
        _ => None,
    }) else {
        rep.error(
            v.span(),
            format!(
                "`{name}` must be an array of tables, found {}",
                type_name(v.get_ref())
            ),
            Some(format!("write each one under its own [[{name}]] header")),
        );
        return Vec::new();
    };
    arr.iter()
        .filter_map(|item| {
            table(rep, item, &format!("each item of `{name}`")).map(|t| (t, item.span()))
        })
        .collect()
}
