//! The raw stage of a prompt's variants (issue 24 §2), apart from `raw` so
//! the prompt reader grows by a call: `vary = { theta0 = [20.0, 80.0],
//! L = { values = [0.5, 1.0, 2.0] }, a = { range = [5, 80], step = 5,
//! target = "initial.theta", scale = 0.0174533 } }`, each value with its
//! span.

use toml::de::DeValue;

use super::read::{self, Fields, List, Num, Span, Str};
use super::report::FileReport;

/// The keys of one varied number written as a table.
pub const VARY_FIELDS: &[&str] = &["range", "values", "step", "target", "scale"];

/// One varied number as written.
#[derive(Debug, Clone, PartialEq)]
pub struct RawVaried {
    /// Its name (the key), as the question's `{name}` shows it.
    pub name: Str,
    /// The span of its value.
    pub span: Span,
    /// `[lo, hi]`: drawn uniformly.
    pub range: Option<List<Num>>,
    /// `values = [...]`: one of these.
    pub values: Option<List<Num>>,
    pub step: Option<Num>,
    /// What it sets in the scene (a parameter, `initial.VAR`,
    /// `inertia[i]`, `omega[i]`); the name itself when absent.
    pub target: Option<Str>,
    pub scale: Option<Num>,
}

/// A prompt's `vary`, when it has one.
#[derive(Debug, Clone, PartialEq)]
pub struct RawVary {
    pub span: Span,
    pub items: Vec<RawVaried>,
}

/// A prompt's `vary` table.
pub(crate) fn read_vary(rep: &mut FileReport, f: &Fields) -> Option<RawVary> {
    let v = f.get("vary")?;
    let t = read::table(rep, v, "`vary`")?;
    let mut items = Vec::new();
    for (key, value) in t.iter() {
        let name = Str {
            value: key.get_ref().to_string(),
            span: key.span(),
        };
        let what = format!("`vary.{}`", name.value);
        match value.get_ref() {
            DeValue::Array(_) => {
                let range = numbers(rep, value, &what);
                items.push(RawVaried {
                    name,
                    span: value.span(),
                    range,
                    values: None,
                    step: None,
                    target: None,
                    scale: None,
                });
            }
            DeValue::Table(t) => {
                let f = Fields::open(
                    rep,
                    t,
                    value.span(),
                    &what,
                    VARY_FIELDS,
                    |name| match name {
                        "min" | "max" | "from" | "to" => {
                            Some("write `range = [lo, hi]`".to_string())
                        }
                        "list" | "choices" | "one_of" => Some("did you mean `values`?".to_string()),
                        "name" | "param" | "var" => Some("did you mean `target`?".to_string()),
                        _ => None,
                    },
                );
                items.push(RawVaried {
                    name,
                    span: value.span(),
                    range: f.get("range").and_then(|r| numbers(rep, r, "`range`")),
                    values: f.get("values").and_then(|r| numbers(rep, r, "`values`")),
                    step: f.number(rep, "step", false),
                    target: f.string(rep, "target", false),
                    scale: f.number(rep, "scale", false),
                });
            }
            _ => {
                rep.error(
                    value.span(),
                    format!("{what} must be a range `[lo, hi]` or a table"),
                    Some("theta0 = [20.0, 80.0], or L = { values = [0.5, 1.0, 2.0] }".into()),
                );
            }
        }
    }
    Some(RawVary {
        span: v.span(),
        items,
    })
}

fn numbers(rep: &mut FileReport, v: &read::Value, what: &str) -> Option<List<Num>> {
    let arr = read::array(rep, v, what)?;
    let mut items = Vec::new();
    let mut ok = true;
    for item in arr.iter() {
        match read::number(rep, item, &format!("each item of {what}")) {
            Some(n) => items.push(n),
            None => ok = false,
        }
    }
    ok.then_some(List {
        items,
        span: v.span(),
    })
}
