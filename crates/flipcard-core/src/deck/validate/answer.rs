//! Prompt answers: choices with `when` conditions, or a number with a
//! tolerance.

use std::ops::Range;

use crate::deck::model::{
    Answer, Choice, Cmp, Comparison, Condition, Measure, Measured, Slip, Term, Tolerance,
};
use crate::deck::raw::{RawAnswer, RawChoice, RawSlip, RawTolerance, Str};
use crate::deck::report::FileReport;
use crate::deck::suggest;
use crate::deck::tomlstr;
use flipcard_sim::scene::vocabulary::{self, ParseError, Parsed};
use flipcard_sim::system::Name;
use flipcard_text::num::{Num, sig};

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

/// The numbers of a prompt's scene a slip's formula may name, with their
/// values (see `flipcard_sim::scene::quantities`).
pub type Scope<'a> = &'a [(String, f64)];

pub fn answer(
    rep: &mut FileReport,
    raw: &RawAnswer,
    langs: &Langs,
    owner: &str,
    kind: Option<SceneKind>,
    scope: Option<Scope>,
    varied: bool,
) -> Option<Answer> {
    match raw {
        RawAnswer::Formula(f) => super::formula::key(rep, f, owner).map(Answer::Formula),
        RawAnswer::Choice {
            span,
            expected,
            choices,
            label: _,
            unit: _,
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
            let Some(expected) = expected.as_ref() else {
                // A varied prompt's right choice is the one its variant's
                // run makes hold.
                if !varied {
                    rep.error(
                        span.clone(),
                        format!("the answer of {owner} is missing the required field `expected`"),
                        Some("the id of the choice the physics gives (a prompt with `vary` may leave it out: each variant's run decides)".into()),
                    );
                }
                return (ok && varied).then_some(Answer::Choice {
                    choices: out,
                    expected: None,
                });
            };
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
                expected: Some(expected.value.clone()),
            })
        }
        RawAnswer::Number {
            span,
            measure,
            unit,
            expected,
            computed,
            tolerance: tol,
            formula,
            slips,
            label: _,
            misconceptions,
        } => {
            // `expected = "period(theta)"` names the measure a varied
            // prompt's answer is computed from: `measure` may be left out,
            // and when written it must be the same.
            // On a prompt that does not vary, a string `expected` is a
            // number written in quotes (`"2.04 s"`), said as before.
            if !varied && let Some(c) = computed {
                rep.error(
                    c.span.clone(),
                    "`expected` must be a number, found a string",
                    crate::deck::read::number_in_quotes(&c.value, "`expected`").or_else(|| {
                        Some("a measure as `expected` is for a prompt with `vary`; here write the number the physics gives: expected = 2.04".into())
                    }),
                );
                return None;
            }
            let measure = match (measure, computed) {
                (Some(m), Some(c)) if m.value.trim() != c.value.trim() => {
                    rep.error(
                        c.span.clone(),
                        format!(
                            "`expected` computes `{}` but `measure` is `{}`",
                            c.value, m.value
                        ),
                        Some("leave out `measure`, or make them the same".into()),
                    );
                    None
                }
                (Some(m), _) | (None, Some(m)) => measure_in(rep, m, 0, m.value.len(), kind),
                (None, None) => {
                    rep.error(
                        span.clone(),
                        format!("the answer of {owner} is missing the required field `measure`"),
                        None,
                    );
                    None
                }
            };
            let computed_ok = match (computed, varied) {
                (None, true) if expected.is_none() => {
                    rep.error(
                        span.clone(),
                        format!("the answer of {owner} is missing the required field `expected`"),
                        Some("on a prompt with `vary`, name the measure each variant's answer is: expected = \"period(theta)\"".into()),
                    );
                    false
                }
                _ => true,
            };
            if varied && let Some(e) = expected {
                rep.error(
                    e.span.clone(),
                    "`expected` is one number, but the prompt varies: each variant has its own answer",
                    Some("name the measure instead: expected = \"period(theta)\"".into()),
                );
                return None;
            }
            if !varied && computed.is_none() && expected.is_none() {
                rep.error(
                    span.clone(),
                    format!("the answer of {owner} is missing the required field `expected`"),
                    None,
                );
                return None;
            }
            if varied && let Some(m) = misconceptions {
                rep.error(
                    m.span.clone(),
                    "`misconceptions` ranges are fixed numbers, but the prompt varies: a range right for one variant is wrong for another",
                    Some("name the wrong number as a slip over the scene's numbers instead: slips = [{ value = \"2*pi*sqrt(L/g)\", misconception = \"…\", says = … }]".into()),
                );
                return None;
            }
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
            let slips = match slips {
                None => Some(Vec::new()),
                Some(list) => {
                    let right = expected.zip(tolerance);
                    let mut out = Vec::new();
                    let mut ok = true;
                    for raw in &list.items {
                        match slip(rep, raw, langs, scope, right, unit.as_deref()) {
                            Some(s) => out.push(s),
                            None => ok = false,
                        }
                    }
                    ok.then_some(out)
                }
            };
            let ranges = super::misconception::ranges(
                rep,
                misconceptions.as_ref(),
                expected.zip(tolerance),
                unit.as_deref(),
            );
            if !computed_ok || (!varied && expected.is_none()) {
                return None;
            }
            Some(Answer::Number {
                measure: measure?,
                unit: unit?,
                expected,
                tolerance: tolerance?,
                formula: formula.map_or(Some(None), |f| f.map(Some))?,
                slips: slips?,
                misconceptions: ranges?,
            })
        }
    }
}

/// The deck's words for what a prompt measures (`label`, and a choice
/// answer's `unit`), checked against the answer they name: a choice
/// answer's label names the one measure its conditions read, so choices
/// reading two or more are an error at `label`, as is a `unit` without a
/// `label`. `None` inside: no label; `None` outside: an error.
pub fn measured(
    rep: &mut FileReport,
    raw: &RawAnswer,
    answer: &Answer,
    langs: &Langs,
) -> Option<Option<Measured>> {
    let (label, unit) = match raw {
        RawAnswer::Choice { label, unit, .. } => (label.as_ref(), unit.as_ref()),
        RawAnswer::Number { label, .. } => (label.as_ref(), None),
        RawAnswer::Formula(_) => return Some(None),
    };
    let Some(label) = label else {
        if let Some(u) = unit {
            rep.error(
                u.span.clone(),
                "a choice answer's `unit` is the unit of what its `label` names; this answer has no `label`".to_string(),
                Some("add `label = { en = '…', … }` naming the measured quantity in words, or remove `unit`".to_string()),
            );
            return None;
        }
        return Some(None);
    };
    let (measure, unit) = match answer {
        Answer::Formula(_) => return Some(None),
        Answer::Number { measure, unit, .. } => (*measure, unit.clone()),
        Answer::Choice { choices, .. } => {
            let mut measures: Vec<Measure> =
                choices.iter().flat_map(|c| c.when.measures()).collect();
            measures.sort();
            measures.dedup();
            let [one] = measures.as_slice() else {
                let names: Vec<String> = measures.iter().map(|m| format!("`{m}`")).collect();
                rep.error(
                    label.span(),
                    format!(
                        "`label` names the one measure the choices read, but they read {}: {}",
                        measures.len(),
                        names.join(", ")
                    ),
                    Some("remove `label`; each measure is then named by itself".to_string()),
                );
                return None;
            };
            let unit = match unit {
                Some(u) => text::string(rep, u, Kind::Plain, "`unit`").then(|| u.value.clone())?,
                None => String::new(),
            };
            (*one, unit)
        }
    };
    let label = text::text(rep, label, langs, "`label`")?;
    Some(Some(Measured {
        measure,
        label,
        unit,
    }))
}

/// The longest slip `value` read: a formula, not a program.
pub(crate) const MAX_SLIP_BYTES: usize = 256;

/// One known slip of a number answer: its `value` a formula over the
/// scene's numbers (`scope`, `None` where the scene link is broken) and
/// `measured`, its `says` a text in every language. With the author's
/// answer (`right`: `expected` and the tolerance), the slip's number taken
/// there must not be a right answer: a learner typing it would be told it
/// is right, and the slip would never be said.
fn slip(
    rep: &mut FileReport,
    raw: &RawSlip,
    langs: &Langs,
    scope: Option<Scope>,
    right: Option<(f64, Tolerance)>,
    unit: Option<&str>,
) -> Option<Slip> {
    let says = raw.says.as_ref().and_then(|t| {
        let what = match &raw.value {
            Some(v) => format!(
                "what slip `{}` says",
                flipcard_text::safe::one_line(&v.value)
            ),
            None => "what a slip says".to_string(),
        };
        text::text(rep, t, langs, &what)
    });
    let value = raw.value.as_ref()?;
    if !text::string(rep, value, Kind::Plain, "a slip's `value`") {
        return None;
    }
    if value.value.len() > MAX_SLIP_BYTES {
        rep.error(
            value.span.clone(),
            format!(
                "this slip's `value` is {} bytes long; a formula may be at most {MAX_SLIP_BYTES}",
                value.value.len()
            ),
            None,
        );
        return None;
    }
    let measured = flipcard_sim::scene::quantities::MEASURED;
    let at = |rep: &FileReport, e: &flipcard_sim::system::expr::ExprError| {
        super::system::span_in(rep, value, e.at, e.len)
    };
    let scope = scope?;
    let names: Vec<&str> = scope
        .iter()
        .map(|(n, _)| n.as_str())
        .chain([measured])
        .collect();
    if let Err(e) = flipcard_sim::system::formula::check(&value.value, &|n| names.contains(&n)) {
        let hint = match &e.unknown {
            Some(name) => suggest::did_you_mean(name, names.iter().copied())
                .or_else(|| Some(format!("names here: {}, pi, e", names.join(", ")))),
            None => e.hint.clone(),
        };
        let span = at(rep, &e);
        rep.error(span, format!("slip `value`: {}", e.message), hint);
        return None;
    }
    if let Some((expected, tolerance)) = right {
        let mut with = scope.to_vec();
        with.push((measured.to_string(), expected));
        let unit = unit
            .filter(|u| !u.is_empty())
            .map_or(String::new(), |u| format!(" {u}"));
        match flipcard_sim::system::formula::evaluate(&value.value, &with) {
            Err(e) => {
                rep.error(
                    value.span.clone(),
                    format!(
                        "slip `{}` has no value for this scene: {}",
                        flipcard_text::safe::one_line(&value.value),
                        e.message
                    ),
                    None,
                );
                return None;
            }
            Ok(w) if tolerance.accepts(w, expected) => {
                rep.error(
                    value.span.clone(),
                    format!(
                        "slip `{}` gives {}{unit}, within the tolerance of `expected` {}{unit}: a learner who types it is right, so it is never a slip",
                        flipcard_text::safe::one_line(&value.value),
                        sig(w, 4),
                        Num(expected)
                    ),
                    Some("give the formula of the wrong answer, or narrow `tolerance`".to_string()),
                );
                return None;
            }
            Ok(_) => {}
        }
    }
    Some(Slip {
        value: value.value.clone(),
        says: says?,
        scope: scope.to_vec(),
        misconception: raw.misconception.as_ref().map(|m| m.value.clone()),
    })
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
        misconception: raw.misconception.as_ref().map(|m| m.value.clone()),
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

/// Where byte `offset` of the decoded string `s` is in the file.
fn locator(rep: &FileReport, s: &Str) -> impl Fn(usize) -> usize + use<> {
    let token = rep.source.get(s.span.clone()).unwrap_or("").to_string();
    let start = s.span.start;
    move |offset| start + tomlstr::locate(&token, offset).0
}

/// The longest `when` read (a few dozen comparisons).
const MAX_CONDITION_BYTES: usize = 1024;

/// A token of a condition, with its byte range in the text.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Tok {
    Op(&'static str, Cmp),
    /// A lone `=` (meant `==`).
    Equals,
    Number,
    /// A name, with its `(…)` when it has one.
    Word {
        call: bool,
    },
    And,
    Or,
    Other,
}

/// Splits a condition into tokens.
fn tokens(text: &str) -> Vec<(Tok, Range<usize>)> {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < text.len() {
        let c = text[i..].chars().next().unwrap_or(' ');
        if c.is_whitespace() {
            i += c.len_utf8();
            continue;
        }
        let start = i;
        if let Some(&(op, cmp)) = Cmp::ALL.iter().find(|(o, _)| text[i..].starts_with(o)) {
            i += op.len();
            out.push((Tok::Op(op, cmp), start..i));
            continue;
        }
        if c == '=' {
            i += 1;
            out.push((Tok::Equals, start..i));
            continue;
        }
        let digit_next =
            text[i + c.len_utf8()..].starts_with(|d: char| d.is_ascii_digit() || d == '.');
        if c.is_ascii_digit() || (c == '.' || c == '-' || c == '+') && digit_next {
            i += 1;
            while i < text.len() {
                let d = bytes[i];
                let exp_sign = (d == b'-' || d == b'+') && matches!(bytes[i - 1], b'e' | b'E');
                if d.is_ascii_alphanumeric() || d == b'.' || exp_sign {
                    i += 1;
                } else {
                    break;
                }
            }
            out.push((Tok::Number, start..i));
            continue;
        }
        if c.is_alphabetic() || c == '_' {
            while i < text.len() {
                let d = text[i..].chars().next().unwrap_or(' ');
                if d.is_alphanumeric() || d == '_' || d == '.' {
                    i += d.len_utf8();
                } else {
                    break;
                }
            }
            let word = &text[start..i];
            if text[i..].starts_with('(') {
                // To the matching `)`, or the end.
                let mut depth = 0;
                while i < text.len() {
                    let d = bytes[i];
                    i += 1;
                    if d == b'(' {
                        depth += 1;
                    } else if d == b')' {
                        depth -= 1;
                        if depth == 0 {
                            break;
                        }
                    }
                }
                out.push((Tok::Word { call: true }, start..i));
            } else if word == "and" {
                out.push((Tok::And, start..i));
            } else if word == "or" {
                out.push((Tok::Or, start..i));
            } else {
                out.push((Tok::Word { call: false }, start..i));
            }
            continue;
        }
        // A run of other symbols (`&&`, `||`) is one token.
        i += c.len_utf8();
        while let Some(d) = text[i..].chars().next() {
            if d.is_whitespace() || d.is_alphanumeric() || "()_.=<>!".contains(d) {
                break;
            }
            i += d.len_utf8();
        }
        out.push((Tok::Other, start..i));
    }
    out
}

/// Parses a choice's `when` (see [`Condition`]: `flips > 0`,
/// `0.2 < max(f2) < 0.9`, `period(x1) < period(x2)`, `abs(final(x)) < 0.1
/// or flips > 2`), reporting at the exact character of the string that is
/// wrong.
pub fn condition(rep: &mut FileReport, s: &Str, kind: Option<SceneKind>) -> Option<Condition> {
    let text = s.value.as_str();
    // Work is bounded: each term is placed in the file by walking the
    // string from its start, so a condition thousands of comparisons long
    // would take minutes (20,000 took 44 s). No condition needs that much.
    if text.len() > MAX_CONDITION_BYTES {
        rep.error(
            s.span.clone(),
            format!(
                "this `when` is {} bytes long; a condition may be at most {MAX_CONDITION_BYTES}",
                text.len()
            ),
            Some("split the cases across choices, or ask about fewer measures".to_string()),
        );
        return None;
    }
    let at = locator(rep, s);
    let example = "a condition is `measure op number`, e.g. \"flips > 0\", \"0.2 < max(x) < 0.9\" or \"period(a) < period(b) and max(x) > 1\"";
    let toks = tokens(text);
    let mut k = 0;
    let mut any = Vec::new();
    let mut conj: Vec<Comparison> = Vec::new();
    let found = |k: usize| match toks.get(k) {
        Some((_, r)) => format!("`{}`", &text[r.clone()]),
        None => "nothing".to_string(),
    };
    let place = |k: usize| match toks.get(k) {
        Some((_, r)) => at(r.start)..at(r.end).max(at(r.start) + 1),
        None => at(text.len())..at(text.len()) + 1,
    };
    loop {
        // One chain: term (op term)+.
        let chain_start = k;
        let mut left = term(rep, s, &toks, k, None, kind, example)?;
        k += 1;
        let mut chain = Vec::new();
        while let Some(&(Tok::Op(op_str, op), _)) = toks.get(k) {
            let right = term(rep, s, &toks, k + 1, Some(op_str), kind, example)?;
            chain.push(Comparison { left, op, right });
            left = right;
            k += 2;
        }
        if chain.is_empty() {
            let hint = if matches!(toks.get(k), Some((Tok::Equals, _))) {
                "use `==` to compare".to_string()
            } else {
                "operators: == != < <= > >=".to_string()
            };
            let after = &text[toks[chain_start].1.clone()];
            rep.error(
                place(k),
                format!(
                    "`when = \"{text}\"`: expected a comparison after `{after}`, found {}",
                    found(k)
                ),
                Some(hint),
            );
            return None;
        }
        if chain
            .iter()
            .all(|c| matches!((c.left, c.right), (Term::Number(_), Term::Number(_))))
        {
            let span = toks[chain_start].1.start..toks[k - 1].1.end;
            rep.error(
                at(span.start)..at(span.end),
                format!(
                    "`when = \"{text}\"`: `{}` compares numbers only; name a measure",
                    &text[span.clone()]
                ),
                Some(example.to_string()),
            );
            return None;
        }
        conj.extend(chain);
        match toks.get(k) {
            None => break,
            Some((Tok::And, _)) => k += 1,
            Some((Tok::Or, _)) => {
                any.push(std::mem::take(&mut conj));
                k += 1;
            }
            Some(_) => {
                let before = &text[toks[k - 1].1.clone()];
                rep.error(
                    place(k),
                    format!(
                        "`when = \"{text}\"`: expected `and` or `or` after `{before}`, found {}",
                        found(k)
                    ),
                    Some(match toks.get(k).map(|(_, r)| &text[r.clone()]) {
                        Some("&&" | "&") => "write `and` for `&&`".to_string(),
                        Some("||" | "|") => "write `or` for `||`".to_string(),
                        _ => "join comparisons with `and` or `or`".to_string(),
                    }),
                );
                return None;
            }
        }
    }
    any.push(conj);
    Some(Condition { any })
}

/// The term at token `k` of a condition (`after` the operator before it,
/// if any): a number, a measure, or `abs(measure)`.
fn term(
    rep: &mut FileReport,
    s: &Str,
    toks: &[(Tok, Range<usize>)],
    k: usize,
    after: Option<&str>,
    kind: Option<SceneKind>,
    example: &str,
) -> Option<Term> {
    let text = s.value.as_str();
    let at = locator(rep, s);
    let not_a_number = |rep: &mut FileReport, r: Option<Range<usize>>| {
        let (span, found) = match r {
            Some(r) => (
                at(r.start)..at(r.end).max(at(r.start) + 1),
                format!("`{}`", &text[r]),
            ),
            None => (at(text.len())..at(text.len()) + 1, "nothing".to_string()),
        };
        match after {
            Some(op) => rep.error(
                span,
                format!(
                    "`when = \"{text}\"`: expected a finite number after `{op}`, found {found}"
                ),
                Some(example.to_string()),
            ),
            None => rep.error(
                span,
                format!("`when = \"{text}\"` does not start with a measure name"),
                Some(example.to_string()),
            ),
        }
    };
    let Some((tok, r)) = toks.get(k).cloned() else {
        not_a_number(rep, None);
        return None;
    };
    match tok {
        Tok::Number => match text[r.clone()].parse::<f64>() {
            Ok(v) if v.is_finite() => Some(Term::Number(v)),
            _ => {
                not_a_number(rep, Some(r));
                None
            }
        },
        Tok::Word { call: true } if text[r.clone()].starts_with("abs(") => {
            let inner_start = r.start + "abs(".len();
            let inner_end = if text[r.clone()].ends_with(')') {
                r.end - 1
            } else {
                r.end
            };
            measure_in(rep, s, inner_start, inner_end.max(inner_start), kind).map(Term::Abs)
        }
        Tok::Word { call } => {
            // After an operator a bare word that names no measure was
            // meant as a number.
            if after.is_some() && !call && Measure::from_name(&text[r.clone()]).is_none() {
                not_a_number(rep, Some(r));
                return None;
            }
            measure_in(rep, s, r.start, r.end, kind).map(Term::Measure)
        }
        _ => {
            not_a_number(rep, Some(r));
            None
        }
    }
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
    let at = locator(rep, s);
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
        Err(ParseError::NoRelation { at: inner }) => {
            let stat_name = text[..text.find('(').unwrap_or(0)].trim();
            rep.error(
                at(start + inner.start)..at(start + inner.end.max(inner.start + 1)),
                format!("`{text}`: expected the quantity, a relation and a level"),
                Some(format!(
                    "e.g. {stat_name}(x > 0.5); the relation is =, > or <"
                )),
            );
            return None;
        }
        Err(ParseError::BadLevel { at: level }) => {
            let found = &text[level.clone()];
            rep.error(
                at(start + level.start)..at(start + level.end.max(level.start + 1)),
                format!(
                    "`{text}`: expected a finite number as the level, found {}",
                    if found.is_empty() {
                        "nothing".to_string()
                    } else {
                        format!("`{found}`")
                    }
                ),
                None,
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

/// A whole string that names one measure (a scene's `explore`), checked
/// as a prompt's measure is.
pub(crate) fn measure_text(
    rep: &mut FileReport,
    s: &Str,
    kind: Option<SceneKind>,
) -> Option<Measure> {
    measure_in(rep, s, 0, s.value.len(), kind)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deck::Stat;
    use proptest::prelude::*;

    /// The condition `text` (as a TOML basic string) on a system scene with
    /// quantities x, y; its diagnostics' messages.
    fn parse(text: &str) -> (Option<Condition>, Vec<String>) {
        let source = format!("\"{text}\"");
        let mut rep = FileReport::new(std::path::Path::new("d.toml"), &source);
        let s = Str {
            value: text.to_string(),
            span: 0..source.len(),
        };
        let names = ["x".to_string(), "y".to_string()];
        let c = condition(&mut rep, &s, Some(SceneKind::System(&names)));
        let msgs = rep.finish().into_iter().map(|d| d.message).collect();
        (c, msgs)
    }

    fn of(stat: Stat, name: &str) -> Measure {
        Measure::Of(stat, Name::new(name).unwrap())
    }

    /// One slip `value` (a TOML basic string) with a one-language `says`,
    /// on a scene with k = 100 and `expected` 0.1 (rel 0.1): the slip, and
    /// the diagnostics' messages.
    fn slip_of(value: &str) -> (Option<Slip>, Vec<String>) {
        let source = format!("\"{value}\" 'says'");
        let mut rep = FileReport::new(std::path::Path::new("d.toml"), &source);
        let raw = RawSlip {
            span: 0..source.len(),
            value: Some(Str {
                value: value.to_string(),
                span: 0..value.len() + 2,
            }),
            says: Some(crate::deck::raw::RawText::Plain(Str {
                value: "says".to_string(),
                span: value.len() + 3..source.len(),
            })),
            misconception: None,
        };
        let langs = Langs {
            list: vec!["en".to_string()],
            known: true,
        };
        let scope = [("k".to_string(), 100.0)];
        let s = slip(
            &mut rep,
            &raw,
            &langs,
            Some(&scope),
            Some((0.1, Tolerance::Rel(0.1))),
            Some("s"),
        );
        let msgs = rep.finish().into_iter().map(|d| d.message).collect();
        (s, msgs)
    }

    #[test]
    fn a_slip_reads_its_formula_and_refuses_what_is_no_slip() {
        let (s, msgs) = slip_of("1/k");
        assert!(msgs.is_empty(), "{msgs:?}");
        let s = s.unwrap();
        assert_eq!(s.value_for(0.1), Some(0.01));
        // `measured` is the run's value, given at the verdict.
        let (s, msgs) = slip_of("2*measured");
        assert!(msgs.is_empty(), "{msgs:?}");
        assert_eq!(s.unwrap().value_for(0.25), Some(0.5));
        for (value, says) in [
            ("1/sqrt(k)", "within the tolerance of `expected` 0.1 s"),
            (
                "1/(k-k)",
                "has no value for this scene: the formula is infinite: division by zero",
            ),
            ("1/kk", "unknown name `kk`"),
            ("t", "unknown name `t`"),
            ("1 +", "slip `value`: expected"),
            ("", "empty"),
        ] {
            let (s, msgs) = slip_of(value);
            assert!(s.is_none(), "{value}");
            assert_eq!(msgs.len(), 1, "{value}: {msgs:?}");
            assert!(msgs[0].contains(says), "{value}: {msgs:?}");
        }
        // Hostile input: bounded before it is parsed.
        let long = "k+".repeat(200) + "k";
        let (s, msgs) = slip_of(&long);
        assert!(s.is_none());
        assert!(
            msgs[0].contains("bytes long; a formula may be at most 256"),
            "{msgs:?}"
        );
    }

    #[test]
    fn ranges_comparisons_and_or_abs() {
        let (max_x, min_y) = (of(Stat::Max, "x"), of(Stat::Min, "y"));
        let get = |v: [f64; 2]| {
            move |m: Measure| {
                if m == max_x {
                    Some(v[0])
                } else if m == min_y {
                    Some(v[1])
                } else {
                    None
                }
            }
        };
        let (c, msgs) = parse("0.2 < max(x) < 0.9");
        assert!(msgs.is_empty(), "{msgs:?}");
        let c = c.unwrap();
        assert_eq!(c.holds_on(get([0.5, 0.0])), Some(true));
        assert_eq!(c.holds_on(get([0.95, 0.0])), Some(false));
        assert_eq!(c.holds_on(get([0.2, 0.0])), Some(false));
        assert_eq!(c.to_string(), "0.2 < max(x) < 0.9");

        let c = parse("max(x) > min(y)").0.unwrap();
        assert_eq!(c.measures(), vec![max_x, min_y]);
        assert_eq!(c.holds_on(get([1.0, 0.5])), Some(true));
        assert_eq!(c.holds_on(get([0.1, 0.5])), Some(false));
        assert!(c.single().is_none());

        // `and` binds tighter than `or`.
        let c = parse("max(x) > 1 and min(y) > 1 or abs(min(y)) > 5")
            .0
            .unwrap();
        assert_eq!(c.any.len(), 2);
        assert_eq!(c.holds_on(get([2.0, 2.0])), Some(true));
        assert_eq!(c.holds_on(get([2.0, 0.0])), Some(false));
        assert_eq!(c.holds_on(get([0.0, -6.0])), Some(true));
        // A measure the run could not make: undecided, never true.
        assert_eq!(c.holds_on(|_| None), None);

        // Measures with a relation inside, in a condition.
        let (c, msgs) = parse("time_of(x > 0.5) < 3 and count(y = 0) >= 2");
        assert!(msgs.is_empty(), "{msgs:?}");
        assert_eq!(c.unwrap().measures().len(), 2);
        let (_, msgs) = parse("time_of(x) < 3");
        assert!(
            msgs[0].contains("expected the quantity, a relation and a level"),
            "{msgs:?}"
        );
        let (_, msgs) = parse("count(x > lots) < 3");
        assert!(
            msgs[0].contains("expected a finite number as the level, found `lots`"),
            "{msgs:?}"
        );

        // A rigid-body measure on a system scene is named as such.
        let (c, msgs) = parse("flips > 0 or max(x) > 1");
        assert!(c.is_none());
        assert!(msgs[0].contains("rigid-body measure"), "{msgs:?}");
    }

    #[test]
    fn each_mistake_is_named() {
        let first = |t: &str| parse(t).1.first().cloned().unwrap_or_default();
        assert!(first("1 < 2").contains("compares numbers only"));
        assert!(first("max(x) > 1 && max(x) < 2").contains("found `&&`"));
        assert!(first("max(x) = 1").contains("expected a comparison after `max(x)`"));
        assert!(first("max(x) > many").contains("expected a finite number after `>`"));
        assert!(first("max(x) >").contains("found nothing"));
        assert!(first("max(z) > 1").contains("`z` is not a variable or observable"));
        assert!(first("abs(max(q)) > 1").contains("`q` is not a variable"));
        assert!(first("> 1").contains("does not start with a measure name"));
        assert!(first("max(x) > 1 and").contains("does not start with a measure name"));
        assert!(first("max(x) > 1e999").contains("finite number"));
        assert!(first("µ > 1").contains("unknown measure `µ`"));
        assert!(first("max(x) > µ").contains("expected a finite number after `>`, found `µ`"));
        assert!(first("max(x) > 1 é").contains("found `é`"));
        let long = vec!["max(x) > 1"; 200].join(" and ");
        assert!(first(&long).contains("bytes long; a condition may be at most 1024"));
    }

    fn term() -> impl Strategy<Value = String> {
        prop_oneof![
            (-1e6f64..1e6).prop_map(|v| flipcard_text::num::Num(v).to_string()),
            Just("max(x)".to_string()),
            Just("min(y)".to_string()),
            Just("abs(final(x))".to_string()),
        ]
    }

    proptest! {
        /// Whatever is written, the parser answers (a condition or a
        /// diagnostic) without panicking; a condition it accepts reads
        /// back the same from its own text.
        #[test]
        fn any_text_parses_or_is_reported(text in "([ -~]|[µμ→é∞½])*") {
            let (c, msgs) = parse(&text.replace(['"', '\\'], ""));
            prop_assert!(c.is_some() || !msgs.is_empty());
        }

        #[test]
        fn accepted_conditions_read_back_the_same(
            chains in prop::collection::vec(
                (term(), prop::sample::select(vec!["<", "<=", ">", ">=", "==", "!="]), term()),
                1..4,
            ),
            joins in prop::collection::vec(prop::sample::select(vec!["and", "or"]), 3),
        ) {
            let mut text = String::new();
            for (i, (a, op, b)) in chains.iter().enumerate() {
                if i > 0 {
                    text.push_str(&format!(" {} ", joins[i - 1]));
                }
                text.push_str(&format!("{a} {op} {b}"));
            }
            let (c, _) = parse(&text);
            if let Some(c) = c {
                let (again, msgs) = parse(&c.to_string());
                prop_assert!(msgs.is_empty(), "{msgs:?}");
                prop_assert_eq!(again, Some(c));
            }
        }
    }
}
