//! Prompt answers: choices with `when` conditions, or a number with a
//! tolerance.

use std::ops::Range;

use crate::deck::model::{Answer, Choice, Cmp, Condition, Measure, Tolerance};
use crate::deck::raw::{RawAnswer, RawChoice, RawTolerance, Str};
use crate::deck::report::FileReport;
use crate::deck::suggest;
use crate::deck::tomlstr;
use flipcard_sim::scene::vocabulary::{self, ParseError, Parsed};
use flipcard_sim::system::Name;
use flipcard_text::num::Num;

use super::text::{self, Kind, Langs};
use super::{Targets, id, unique};

/// What a prompt's scene can measure: a rigid body's measures, or the
/// statistics of a system's variables and observables (named here). `None`
/// where the scene link is broken (its own error says so).
#[derive(Debug, Clone, Copy)]
pub enum SceneKind<'a> {
    Rigid,
    System(&'a [String]),
}

pub fn answer(
    rep: &mut FileReport,
    raw: &RawAnswer,
    langs: &Langs,
    owner: &str,
    kind: Option<SceneKind>,
) -> Option<Answer> {
    match raw {
        RawAnswer::Choice {
            span: _,
            expected,
            choices,
        } => {
            let list = choices.as_ref()?;
            if list.items.len() < 2 {
                rep.error(
                    list.span.clone(),
                    format!(
                        "the answer of {owner} has {}; a choice answer needs at least 2",
                        flipcard_text::plural(list.items.len(), "choice", "choices")
                    ),
                    None,
                );
            }
            let ids: Vec<&Str> = list.items.iter().filter_map(|c| c.id.as_ref()).collect();
            unique(rep, &ids, "choice");
            let mut ok = list.items.len() >= 2;
            let mut out = Vec::new();
            for c in &list.items {
                match choice(rep, c, langs, kind) {
                    Some(c) => out.push(c),
                    None => ok = false,
                }
            }
            let expected = expected.as_ref()?;
            let known: Vec<&str> = ids.iter().map(|s| s.value.as_str()).collect();
            let targets = Targets::of(list.items.iter().map(|c| c.id.as_ref()));
            if !targets.contains(&expected.value) && targets.may_mean(&expected.value) {
                // A choice's broken id is reported; this may be that one.
                ok = false;
            } else if !known.contains(&expected.value.as_str()) {
                let hint = suggest::did_you_mean(&expected.value, known.iter().copied())
                    .or_else(|| Some(format!("choices: {}", known.join(", "))));
                rep.error(
                    expected.span.clone(),
                    format!(
                        "`expected` is `{}`, which is not a choice id",
                        expected.value
                    ),
                    hint,
                );
                ok = false;
            }
            ok.then(|| Answer::Choice {
                choices: out,
                expected: expected.value.clone(),
            })
        }
        RawAnswer::Number {
            span: _,
            measure,
            unit,
            expected,
            tolerance: tol,
            formula,
        } => {
            let measure = measure
                .as_ref()
                .and_then(|m| measure_in(rep, m, 0, m.value.len(), kind));
            let unit = match unit {
                Some(u) => text::string(rep, u, Kind::Plain, "`unit`").then(|| u.value.clone()),
                None => Some(String::new()),
            };
            let expected = expected.as_ref().and_then(|e| {
                if e.value.is_finite() {
                    Some(e.value)
                } else {
                    rep.error(
                        e.span.clone(),
                        format!("`expected` {} is not finite", Num(e.value)),
                        None,
                    );
                    None
                }
            });
            let tolerance = tol.as_ref().and_then(|t| tolerance(rep, t));
            let formula = formula
                .as_ref()
                .map(|f| text::text(rep, f, langs, "`formula`"));
            Some(Answer::Number {
                measure: measure?,
                unit: unit?,
                expected: expected?,
                tolerance: tolerance?,
                formula: formula.map_or(Some(None), |f| f.map(Some))?,
            })
        }
    }
}

fn choice(
    rep: &mut FileReport,
    raw: &RawChoice,
    langs: &Langs,
    kind: Option<SceneKind>,
) -> Option<Choice> {
    let id_ok = raw.id.as_ref().is_some_and(|i| id(rep, i, "choice"));
    let what = match &raw.id {
        Some(i) if id_ok => format!("the label of choice `{}`", i.value),
        _ => "the label of a choice".to_string(),
    };
    let label = raw
        .label
        .as_ref()
        .and_then(|l| text::text(rep, l, langs, &what));
    let when = raw.when.as_ref().and_then(|w| condition(rep, w, kind));
    Some(Choice {
        id: raw.id.as_ref().filter(|_| id_ok)?.value.clone(),
        label: label?,
        when: when?,
    })
}

fn tolerance(rep: &mut FileReport, t: &RawTolerance) -> Option<Tolerance> {
    let (value, make): (_, fn(f64) -> Tolerance) = match (&t.abs, &t.rel) {
        (Some(a), None) => (a, Tolerance::Abs),
        (None, Some(r)) => (r, Tolerance::Rel),
        (Some(_), Some(_)) => {
            rep.error(
                t.span.clone(),
                "`tolerance` gives both `abs` and `rel`; give one",
                None,
            );
            return None;
        }
        (None, None) => {
            rep.error(
                t.span.clone(),
                "`tolerance` needs `abs` or `rel`",
                Some("tolerance = { rel = 0.1 } (10 %) or { abs = 0.02 }".to_string()),
            );
            return None;
        }
    };
    if !(value.value.is_finite() && value.value > 0.0) {
        rep.error(
            value.span.clone(),
            format!(
                "tolerance {} must be a positive finite number",
                Num(value.value)
            ),
            None,
        );
        return None;
    }
    Some(make(value.value))
}

/// Parses `measure op number` (e.g. `flips > 0`), reporting at the exact
/// character of the string that is wrong.
pub fn condition(rep: &mut FileReport, s: &Str, kind: Option<SceneKind>) -> Option<Condition> {
    let text = s.value.as_str();
    let token = rep.source.get(s.span.clone()).unwrap_or("").to_string();
    let at = |offset: usize| s.span.start + tomlstr::locate(&token, offset).0;
    let example = "a condition is `measure op number`, e.g. \"flips > 0\"";

    let name_start = text.len() - text.trim_start().len();
    let mut name_len = text[name_start..]
        .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == '.'))
        .unwrap_or(text.len() - name_start);
    // A system measure runs to its closing parenthesis: `period(theta)`.
    if text[name_start + name_len..].starts_with('(') {
        name_len = text[name_start..]
            .find(')')
            .map_or(text.len() - name_start, |i| i + 1);
    }
    if name_len == 0 {
        rep.error(
            at(name_start)..at(name_start) + 1,
            format!("`when = \"{text}\"` does not start with a measure name"),
            Some(example.to_string()),
        );
        return None;
    }
    let name = &text[name_start..name_start + name_len];
    let measure = measure_in(rep, s, name_start, name_start + name_len, kind);

    let op_start = name_start
        + name_len
        + (text[name_start + name_len..].len() - text[name_start + name_len..].trim_start().len());
    let rest = &text[op_start..];
    let Some(&(op_str, op)) = Cmp::ALL.iter().find(|(o, _)| rest.starts_with(o)) else {
        let hint = if rest.starts_with('=') {
            "use `==` to compare".to_string()
        } else {
            "operators: == != < <= > >=".to_string()
        };
        let found = if rest.is_empty() {
            "nothing".to_string()
        } else {
            format!("`{}`", rest.chars().next().unwrap_or(' '))
        };
        rep.error(
            at(op_start)..at(op_start) + 1,
            format!("`when = \"{text}\"`: expected a comparison after `{name}`, found {found}"),
            Some(hint),
        );
        return None;
    };
    let num_start = op_start + op_str.len();
    let num_text = text[num_start..].trim();
    let num_at = num_start + (text[num_start..].len() - text[num_start..].trim_start().len());
    let value = match num_text.parse::<f64>() {
        Ok(v) if v.is_finite() => v,
        _ => {
            let found = if num_text.is_empty() {
                "nothing".to_string()
            } else {
                format!("`{num_text}`")
            };
            rep.error(
                at(num_at)..at(num_at) + num_text.len().max(1),
                format!(
                    "`when = \"{text}\"`: expected a finite number after `{op_str}`, found {found}"
                ),
                Some(example.to_string()),
            );
            return None;
        }
    };
    Some(Condition {
        measure: measure?,
        op,
        value,
    })
}

/// The measure written in bytes `start..end` of `s` (`flips`, or
/// `period(theta)` on a system scene), reported at the character that is
/// wrong.
fn measure_in(
    rep: &mut FileReport,
    s: &Str,
    start: usize,
    end: usize,
    kind: Option<SceneKind>,
) -> Option<Measure> {
    let token = rep.source.get(s.span.clone()).unwrap_or("").to_string();
    let at = |offset: usize| s.span.start + tomlstr::locate(&token, offset).0;
    let text = &s.value[start..end];
    let lead = text.len() - text.trim_start().len();
    let text = text.trim();
    let start = start + lead;
    let span = at(start)..at(start + text.len().max(1));
    let stats = || vocabulary::stat_rows().map(|(r, _)| r.name);
    let system_example = vocabulary::system_hint();
    let (stat, quantity, q_at) = match vocabulary::parse(text) {
        Ok(Parsed::Of { stat, quantity, at }) => (stat, quantity, at),
        Ok(Parsed::Rigid(_)) | Err(ParseError::UnknownName(_)) => {
            // A whole `measure = "…"` string is pointed at as a whole.
            let span = if lead == 0 && end - start == s.value.len() {
                s.span.clone()
            } else {
                span
            };
            let m = measure_name(rep, text, span.clone())?;
            if let Some(SceneKind::System(_)) = kind {
                rep.error(
                    span,
                    format!("`{text}` is a rigid-body measure, but the prompt's scene is a system"),
                    Some(system_example),
                );
                return None;
            }
            return Some(m);
        }
        Err(ParseError::UnknownStat { stat, at: stat_at }) => {
            let hint = suggest::did_you_mean(stat, stats()).unwrap_or(system_example);
            rep.error(
                at(start)..at(start + stat_at.end.max(1)),
                format!("unknown measure `{stat}`"),
                Some(hint),
            );
            return None;
        }
        Err(ParseError::NoClose) => {
            let stat_name = text[..text.find('(').unwrap_or(0)].trim();
            rep.error(
                at(start + text.len())..at(start + text.len()) + 1,
                format!("`{text}`: expected `)`"),
                Some(format!("write {stat_name}(N), N a variable or observable")),
            );
            return None;
        }
        Err(ParseError::Trailing { close }) => {
            rep.error(
                at(start + close + 1)..at(start + text.len()),
                format!("unexpected text after `{}`", &text[..=close]),
                None,
            );
            return None;
        }
    };
    let q_span = at(start + q_at.start)..at(start + q_at.start + quantity.len().max(1));
    match kind {
        Some(SceneKind::Rigid) => {
            rep.error(
                span,
                format!("`{text}` is a system measure, but the prompt's scene is a rigid body"),
                Some(vocabulary::rigid_hint()),
            );
            return None;
        }
        Some(SceneKind::System(names)) if !names.iter().any(|n| n == quantity) => {
            let hint = suggest::did_you_mean(quantity, names.iter().map(String::as_str))
                .or_else(|| Some(format!("variables and observables: {}", names.join(", "))));
            rep.error(
                q_span,
                format!("`{quantity}` is not a variable or observable of the prompt's scene"),
                hint,
            );
            return None;
        }
        _ => {}
    }
    match Name::new(quantity) {
        Some(name) if !quantity.is_empty() => Some(Measure::Of(stat, name)),
        _ => {
            rep.error(
                q_span,
                format!("`{quantity}` is not a variable or observable name"),
                None,
            );
            None
        }
    }
}

/// A measure by name, reported at `span` when unknown.
fn measure_name(rep: &mut FileReport, name: &str, span: Range<usize>) -> Option<Measure> {
    if let Some(m) = Measure::from_name(name) {
        return Some(m);
    }
    let names = || vocabulary::rigid_rows().map(|(r, _)| r.name);
    let bare = name.strip_prefix("measure.").unwrap_or(name);
    let hint = if bare != name && Measure::from_name(bare).is_some() {
        format!("write just `{bare}`")
    } else {
        suggest::did_you_mean(name, names())
            .unwrap_or_else(|| format!("measures: {}", names().collect::<Vec<_>>().join(", ")))
    };
    rep.error(span, format!("unknown measure `{name}`"), Some(hint));
    None
}
