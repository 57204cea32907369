//! The raw stage of a scene's knobs (issue 24 §1), apart from `raw` so the
//! scene reader grows by a call: `knobs = [{ name = "theta0", min = 5.0,
//! max = 179.0, step = 5.0, scale = …, label = { en = "…", … } }]` and
//! `explore = "period(theta)"`, each value with its span.

use super::read::{self, Fields, List, Num, RawText, Span, Str};
use super::report::FileReport;

/// The keys of one knob.
pub const KNOB_FIELDS: &[&str] = &["name", "min", "max", "step", "scale", "label"];

/// A knob as written.
#[derive(Debug, Clone, PartialEq)]
pub struct RawKnob {
    pub span: Span,
    pub name: Option<Str>,
    pub min: Option<Num>,
    pub max: Option<Num>,
    pub step: Option<Num>,
    pub scale: Option<Num>,
    pub label: Option<RawText>,
}

/// A scene's `knobs`, when it has them.
pub(crate) fn read_knobs(rep: &mut FileReport, f: &Fields) -> Option<List<RawKnob>> {
    let v = f.get("knobs")?;
    let arr = read::array(rep, v, "`knobs`")?;
    let items = arr
        .iter()
        .filter_map(|item| {
            let t = read::table(rep, item, "each knob")?;
            let f = Fields::open(
                rep,
                t,
                item.span(),
                "a knob",
                KNOB_FIELDS,
                |name| match name {
                    "param" | "var" | "variable" | "target" => {
                        Some("did you mean `name`?".to_string())
                    }
                    "from" | "lo" | "low" => Some("did you mean `min`?".to_string()),
                    "to" | "hi" | "high" => Some("did you mean `max`?".to_string()),
                    "by" | "increment" => Some("did you mean `step`?".to_string()),
                    _ => None,
                },
            );
            Some(RawKnob {
                span: item.span(),
                name: f.string(rep, "name", true),
                min: f.number(rep, "min", true),
                max: f.number(rep, "max", true),
                step: f.number(rep, "step", true),
                scale: f.number(rep, "scale", false),
                label: f.text(rep, "label", true),
            })
        })
        .collect();
    Some(List {
        items,
        span: v.span(),
    })
}
