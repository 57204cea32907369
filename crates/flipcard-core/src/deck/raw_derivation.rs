//! The raw stage of derivations (issue 24 §5), apart from `raw` so the
//! deck reader grows by a call: a deck's `[[derivation]]` tables, each with
//! its ordered `[[derivation.step]]` entries, and a step's `ask` (think,
//! then reveal; a choice; a formula). `validate::derivation` checks them.

use toml::de::{DeTable, DeValue};

use super::raw_formula::{RawFormula, read_formula};
use super::read::{self, Fields, List, RawText, Span, Str};
use super::report::FileReport;
use super::suggest;

/// The keys of a `[[derivation]]` table.
pub const DERIVATION_FIELDS: &[&str] = &["id", "title", "explain", "tags", "step"];
/// The keys of one `[[derivation.step]]`.
pub const STEP_FIELDS: &[&str] = &["math", "why", "ask"];
/// The kinds of a step's `ask`.
pub const ASK_KINDS: &[&str] = &["reveal", "choice", "formula"];
/// The keys of an `ask` of each kind.
pub const REVEAL_ASK_FIELDS: &[&str] = &["kind", "question"];
pub const CHOICE_ASK_FIELDS: &[&str] = &["kind", "question", "choices", "answer"];
pub const FORMULA_ASK_FIELDS: &[&str] = &["kind", "question", "expected", "vars"];
/// The keys of one choice of a choice ask.
pub const ASK_CHOICE_FIELDS: &[&str] = &["id", "label"];

/// A derivation as written.
#[derive(Debug, Clone, PartialEq)]
pub struct RawDerivation {
    pub span: Span,
    pub id: Option<Str>,
    pub title: Option<RawText>,
    pub explain: Option<Str>,
    pub tags: Option<List<Str>>,
    /// The steps in order; `None` when `step` is missing or not an array
    /// of tables (reported).
    pub steps: Option<List<RawStep>>,
}

/// One step as written.
#[derive(Debug, Clone, PartialEq)]
pub struct RawStep {
    pub span: Span,
    pub math: Option<RawText>,
    pub why: Option<RawText>,
    pub ask: Option<RawAsk>,
    /// `ask` was written but could not be read (reported).
    pub ask_unread: bool,
}

/// What a step asks the learner before its math is shown, as written.
#[derive(Debug, Clone, PartialEq)]
pub struct RawAsk {
    pub span: Span,
    pub question: Option<RawText>,
    pub kind: RawAskKind,
}

#[derive(Debug, Clone, PartialEq)]
pub enum RawAskKind {
    /// Think, then reveal.
    Reveal,
    Choice {
        choices: Option<List<RawAskChoice>>,
        answer: Option<Str>,
    },
    Formula(RawFormula),
}

#[derive(Debug, Clone, PartialEq)]
pub struct RawAskChoice {
    pub span: Span,
    pub id: Option<Str>,
    pub label: Option<RawText>,
}

pub(crate) fn read_derivation(rep: &mut FileReport, t: &DeTable, span: Span) -> RawDerivation {
    let probe = Fields::open(
        rep,
        t,
        span.clone(),
        "[[derivation]]",
        DERIVATION_FIELDS,
        |name| match name {
            "steps" => Some("write each step under its own [[derivation.step]] header".to_string()),
            "section" | "see" => Some("did you mean `explain`?".to_string()),
            "name" | "label" => Some("did you mean `title`?".to_string()),
            _ => None,
        },
    );
    let what = match probe.get("id").map(|v| v.get_ref()) {
        Some(DeValue::String(s)) if super::id::is_id(s) => format!("derivation `{s}`"),
        _ => "[[derivation]]".to_string(),
    };
    let f = probe.named(what);
    let steps = f.require(rep, "step").and_then(|v| {
        let written = match v.get_ref() {
            DeValue::Array(a) => a.len(),
            _ => usize::MAX,
        };
        let items: Vec<RawStep> = read::tables(rep, v, "derivation.step")
            .into_iter()
            .map(|(t, span)| read_step(rep, t, span, &f.what))
            .collect();
        (items.len() == written).then_some(List {
            items,
            span: v.span(),
        })
    });
    RawDerivation {
        span,
        id: f.string(rep, "id", true),
        title: f.text(rep, "title", true),
        explain: f.string(rep, "explain", false),
        tags: f.strings(rep, "tags", false),
        steps,
    }
}

fn read_step(rep: &mut FileReport, t: &DeTable, span: Span, owner: &str) -> RawStep {
    let f = Fields::open(
        rep,
        t,
        span.clone(),
        &format!("a step of {owner}"),
        STEP_FIELDS,
        |name| match name {
            "reason" | "because" | "hint" => Some("did you mean `why`?".to_string()),
            "text" | "formula" | "expr" => Some("did you mean `math`?".to_string()),
            "question" | "choices" | "expected" | "vars" | "kind" => Some(format!(
                "`{name}` belongs in the step's `ask`, e.g. ask = {{ kind = \"reveal\" }}"
            )),
            _ => None,
        },
    );
    let ask_value = f.get("ask");
    let ask = ask_value.and_then(|v| {
        let t = read::table(rep, v, "`ask`")?;
        read_ask(rep, t, v.span(), owner)
    });
    RawStep {
        span,
        math: f.text(rep, "math", true),
        why: f.text(rep, "why", true),
        ask_unread: ask_value.is_some() && ask.is_none(),
        ask,
    }
}

fn read_ask(rep: &mut FileReport, t: &DeTable, span: Span, owner: &str) -> Option<RawAsk> {
    let kind_value = t.iter().find(|(k, _)| {
        let name: &str = k.get_ref();
        name == "kind"
    });
    let Some((_, kind_value)) = kind_value else {
        rep.error(
            span,
            format!("the `ask` of a step of {owner} is missing the required field `kind`"),
            Some("kind = \"reveal\", kind = \"choice\" or kind = \"formula\"".to_string()),
        );
        return None;
    };
    let kind = read::string(rep, kind_value, "`kind`")?;
    let what = format!("the `ask` of a step of {owner}");
    let fields = match kind.value.as_str() {
        "reveal" => REVEAL_ASK_FIELDS,
        "choice" => CHOICE_ASK_FIELDS,
        "formula" => FORMULA_ASK_FIELDS,
        other => {
            rep.error(
                kind.span.clone(),
                format!("unknown ask kind `{other}`"),
                suggest::did_you_mean(other, ASK_KINDS.iter().copied()).or_else(|| {
                    Some("kind = \"reveal\", kind = \"choice\" or kind = \"formula\"".to_string())
                }),
            );
            return None;
        }
    };
    let k = kind.value.clone();
    let f = Fields::open(rep, t, span.clone(), &what, fields, |name| {
        let owner = if CHOICE_ASK_FIELDS.contains(&name) {
            Some("choice")
        } else if FORMULA_ASK_FIELDS.contains(&name) {
            Some("formula")
        } else {
            None
        }?;
        (owner != k).then(|| format!("`{name}` belongs to kind = \"{owner}\" asks"))
    });
    let question = f.text(rep, "question", false);
    let kind = match kind.value.as_str() {
        "reveal" => RawAskKind::Reveal,
        "choice" => RawAskKind::Choice {
            choices: f.require(rep, "choices").and_then(|v| {
                let arr = read::array(rep, v, "`choices`")?;
                let items = arr
                    .iter()
                    .filter_map(|item| {
                        let t = read::table(rep, item, "each choice")?;
                        let cf = Fields::open(
                            rep,
                            t,
                            item.span(),
                            "a choice",
                            ASK_CHOICE_FIELDS,
                            |name| {
                                (name == "when").then(|| {
                                    "a step's choice has no `when`: the ask's `answer` names the right one"
                                        .to_string()
                                })
                            },
                        );
                        Some(RawAskChoice {
                            span: item.span(),
                            id: cf.string(rep, "id", true),
                            label: cf.text(rep, "label", true),
                        })
                    })
                    .collect();
                Some(List {
                    items,
                    span: v.span(),
                })
            }),
            answer: f.string(rep, "answer", true),
        },
        _ => RawAskKind::Formula(read_formula(rep, &f, span.clone())),
    };
    Some(RawAsk {
        span,
        question,
        kind,
    })
}
