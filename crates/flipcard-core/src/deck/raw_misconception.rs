//! The raw stage of named misconceptions (issue 24 §3), apart from `raw`
//! so the deck reader grows by a call per place: a deck's
//! `[[misconception]]` tables, and a number answer's
//! `misconceptions = [{ range = [lo, hi], id = "…" }]`. A choice's and a
//! slip's `misconception = "id"` are plain strings read where they sit.

use toml::de::DeTable;

use super::read::{self, Fields, List, Num, RawText, Span, Str};
use super::report::FileReport;

/// The keys of a `[[misconception]]` table.
pub const MISCONCEPTION_FIELDS: &[&str] = &["id", "title", "why_it_seems_right", "fix", "explain"];
/// The keys of one range of a number answer's `misconceptions`.
pub const RANGE_FIELDS: &[&str] = &["range", "id"];

/// A misconception as written: what it is called, why it seems right (the
/// steel-man), the fix, and where the reader explains it.
#[derive(Debug, Clone, PartialEq)]
pub struct RawMisconception {
    pub span: Span,
    pub id: Option<Str>,
    pub title: Option<RawText>,
    pub why_it_seems_right: Option<RawText>,
    pub fix: Option<RawText>,
    pub explain: Option<Str>,
}

/// Wrong numbers from `range[0]` to `range[1]` stand for misconception `id`.
#[derive(Debug, Clone, PartialEq)]
pub struct RawRange {
    pub span: Span,
    pub range: Option<List<Num>>,
    pub id: Option<Str>,
}

pub(crate) fn read_misconception(
    rep: &mut FileReport,
    t: &DeTable,
    span: Span,
) -> RawMisconception {
    let probe = Fields::open(
        rep,
        t,
        span.clone(),
        "[[misconception]]",
        MISCONCEPTION_FIELDS,
        |name| match name {
            "why" | "steel_man" | "steelman" | "seems_right" => {
                Some("did you mean `why_it_seems_right`?".to_string())
            }
            "label" | "name" => Some("did you mean `title`?".to_string()),
            _ => None,
        },
    );
    let what = match probe.get("id").map(|v| v.get_ref()) {
        Some(toml::de::DeValue::String(s)) if super::id::is_id(s) => {
            format!("misconception `{s}`")
        }
        _ => "[[misconception]]".to_string(),
    };
    let f = probe.named(what);
    RawMisconception {
        span,
        id: f.string(rep, "id", true),
        title: f.text(rep, "title", true),
        why_it_seems_right: f.text(rep, "why_it_seems_right", true),
        fix: f.text(rep, "fix", true),
        explain: f.string(rep, "explain", false),
    }
}

/// A number answer's `misconceptions`, when it has them.
pub(crate) fn read_ranges(rep: &mut FileReport, f: &Fields) -> Option<List<RawRange>> {
    let v = f.get("misconceptions")?;
    let arr = read::array(rep, v, "`misconceptions`")?;
    let items = arr
        .iter()
        .filter_map(|item| {
            let t = read::table(rep, item, "each item of `misconceptions`")?;
            let f = Fields::open(
                rep,
                t,
                item.span(),
                "a range of `misconceptions`",
                RANGE_FIELDS,
                |name| match name {
                    "misconception" => Some("did you mean `id`?".to_string()),
                    "from" | "to" | "min" | "max" | "values" => {
                        Some("write `range = [low, high]`".to_string())
                    }
                    _ => None,
                },
            );
            Some(RawRange {
                span: item.span(),
                range: f.numbers(rep, "range", true),
                id: f.string(rep, "id", true),
            })
        })
        .collect();
    Some(List {
        items,
        span: v.span(),
    })
}
