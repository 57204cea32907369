//! The key of a formula answer (a `kind = "formula"` card or prompt
//! answer): `expected` read by the deck's expression language in its
//! formula form, `vars` an interval per variable, and the two checked
//! together by `flipcard_sim::system::equiv::check` (every name a
//! variable, every variable used, every range sound, the formula finite
//! at enough points of the domain), each problem at its place in the file.

use crate::deck::raw::RawFormula;
use crate::deck::report::FileReport;
use crate::deck::suggest;
use flipcard_sim::system::equiv::{self, Domain, Key, KeyProblem};
use flipcard_text::num::Num;

use super::text::{self, Kind};

/// The longest `expected` formula read (bytes): the same bound as a
/// learner's answer.
const MAX_EXPECTED: usize = equiv::MAX_ANSWER;

/// The key `raw` writes, or `None` with each problem reported.
pub fn key(rep: &mut FileReport, raw: &RawFormula, what: &str) -> Option<Key> {
    let expected = raw.expected.as_ref()?;
    let vars = raw.vars.as_ref()?;
    if !text::string(rep, expected, Kind::Plain, "`expected`") {
        return None;
    }
    if expected.value.len() > MAX_EXPECTED {
        rep.error(
            expected.span.clone(),
            format!(
                "`expected` of {what} is {} bytes long; a formula may be at most {MAX_EXPECTED}",
                expected.value.len()
            ),
            None,
        );
        return None;
    }
    if vars.entries.is_empty() {
        rep.error(
            vars.span.clone(),
            format!("`vars` of {what} declares no variable"),
            Some(
                "vars = { x = [1, 2] }: each variable with the interval its values are drawn from"
                    .to_string(),
            ),
        );
        return None;
    }
    let mut domains = Vec::new();
    let mut ok = true;
    for e in &vars.entries {
        match e.value.items.as_slice() {
            [lo, hi] => domains.push(Domain {
                name: e.key.value.clone(),
                lo: lo.value,
                hi: hi.value,
            }),
            _ => {
                rep.error(
                    e.value.span.clone(),
                    format!(
                        "the range of `{}` has {}; a range is [low, high]",
                        e.key.value,
                        flipcard_text::plural(e.value.items.len(), "number", "numbers")
                    ),
                    None,
                );
                ok = false;
            }
        }
    }
    if !ok {
        return None;
    }
    let key = Key {
        expected: expected.value.clone(),
        vars: domains,
    };
    let problems = equiv::check(&key);
    for p in &problems {
        match p {
            KeyProblem::Expected(e) => {
                let hint = match &e.unknown {
                    Some(name) => {
                        suggest::did_you_mean(name, key.vars.iter().map(|v| v.name.as_str()))
                            .or_else(|| {
                                let names: Vec<&str> =
                                    key.vars.iter().map(|v| v.name.as_str()).collect();
                                Some(format!(
                                    "add it to `vars`, or use one of: {}, pi, e",
                                    names.join(", ")
                                ))
                            })
                    }
                    None => e.hint.clone(),
                };
                let span = super::system::span_in(rep, expected, e.at, e.len);
                rep.error(span, format!("`expected` of {what}: {}", e.message), hint);
            }
            KeyProblem::Unused(k) => {
                let entry = &vars.entries[*k];
                rep.error(
                    entry.key.span.clone(),
                    format!(
                        "`{}` is in `vars`, but the expected formula does not use it",
                        entry.key.value
                    ),
                    Some("remove it: an answer cannot depend on it".to_string()),
                );
            }
            KeyProblem::Range(k) => {
                let (entry, d) = (&vars.entries[*k], &key.vars[*k]);
                rep.error(
                    entry.value.span.clone(),
                    format!(
                        "the range of `{}` is [{}, {}]; it needs two finite numbers, the low one first",
                        d.name,
                        Num(d.lo),
                        Num(d.hi)
                    ),
                    None,
                );
            }
            KeyProblem::Twice(k) => {
                let entry = &vars.entries[*k];
                rep.error(
                    entry.key.span.clone(),
                    format!(
                        "`{}` is the same variable as `{}` (a subscript may be written with or without `_`)",
                        entry.key.value,
                        equiv::canonical(&entry.key.value)
                    ),
                    Some("declare each variable once".to_string()),
                );
            }
            KeyProblem::Constant(k) => {
                let entry = &vars.entries[*k];
                rep.error(
                    entry.key.span.clone(),
                    format!("`{}` is a constant, not a variable", entry.key.value),
                    Some("name the variable otherwise".to_string()),
                );
            }
            KeyProblem::Undefined { found, drawn } => {
                rep.error(
                    expected.span.clone(),
                    format!(
                        "`expected` of {what} is finite at {found} of {drawn} points drawn from `vars`; a verdict needs {}",
                        equiv::MIN_POINTS
                    ),
                    Some("narrow the ranges to where the formula is defined".to_string()),
                );
            }
        }
    }
    problems.is_empty().then_some(key)
}
