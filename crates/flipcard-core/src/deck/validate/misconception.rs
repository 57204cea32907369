//! Named misconceptions (issue 24 §3): the deck's `[[misconception]]`
//! entries (an id, a title, why it seems right and the fix, in every
//! language, and an optional `explain` link checked like a card's), the
//! links to them from choices, slips and a number answer's ranges, and the
//! ranges themselves. Apart from `answer` and the deck's body so that the
//! checks of one feature sit together.

use crate::deck::model::{Misconception, Tolerance, WrongRange};
use crate::deck::raw::{List, RawAnswer, RawDeckFile, RawRange, Str};
use crate::deck::report::FileReport;
use flipcard_text::num::Num;

use super::text::Langs;
use super::{Anchors, Targets, explain_link, id, link, unique};

/// The deck's misconceptions, each checked: ids of the id shape and
/// unique, every text in every language, `explain` a section (and anchor)
/// that exists. `None` when one is wrong.
pub fn declared(
    rep: &mut FileReport,
    raw: &RawDeckFile,
    langs: &Langs,
    sections: (Option<&Targets>, &Anchors),
) -> Option<Vec<Misconception>> {
    let ids: Vec<&Str> = raw
        .misconceptions
        .iter()
        .filter_map(|m| m.id.as_ref())
        .collect();
    let mut ok = true;
    for s in &ids {
        ok &= id(rep, s, "misconception");
    }
    ok &= unique(rep, &ids, "misconception");
    let mut out = Vec::new();
    for m in &raw.misconceptions {
        let what = match &m.id {
            Some(s) if crate::deck::id::is_id(&s.value) => format!("misconception `{}`", s.value),
            _ => "a misconception".to_string(),
        };
        let mut text = |t: &Option<crate::deck::raw::RawText>, part: &str| {
            t.as_ref()
                .and_then(|t| super::text::text(rep, t, langs, &format!("{part} of {what}")))
        };
        let title = text(&m.title, "the title");
        let why = text(&m.why_it_seems_right, "why it seems right");
        let fix = text(&m.fix, "the fix");
        let explain = explain_link(rep, &m.explain, sections);
        match (|| {
            Some(Misconception {
                id: m.id.as_ref()?.value.clone(),
                title: title?,
                why_it_seems_right: why?,
                fix: fix?,
                explain: explain?,
            })
        })() {
            Some(m) => out.push(m),
            None => ok = false,
        }
    }
    ok.then_some(out)
}

/// Every link to a misconception (a choice's or a slip's `misconception`,
/// a range's `id`) names one the deck declares; a choice that is the
/// expected answer stands for none; a declared one nothing links to is a
/// warning at its id. False when a link is wrong.
pub fn uses(rep: &mut FileReport, raw: &RawDeckFile) -> bool {
    let targets = Targets::of(raw.misconceptions.iter().map(|m| m.id.as_ref()));
    let mut used: Vec<String> = Vec::new();
    let mut ok = true;
    for p in &raw.prompts {
        let mut links: Vec<&Str> = Vec::new();
        match &p.answer {
            Some(RawAnswer::Choice {
                choices: Some(list),
                expected,
                ..
            }) => {
                for c in &list.items {
                    let Some(m) = &c.misconception else { continue };
                    links.push(m);
                    if let (Some(e), Some(cid)) = (expected, &c.id)
                        && e.value == cid.value
                    {
                        rep.error(
                            m.span.clone(),
                            format!(
                                "choice `{}` is the expected answer, so it stands for no misconception",
                                cid.value
                            ),
                            Some("put `misconception` on the wrong choice it explains".to_string()),
                        );
                        ok = false;
                    }
                }
            }
            Some(RawAnswer::Number {
                slips,
                misconceptions,
                ..
            }) => {
                links.extend(
                    slips
                        .iter()
                        .flat_map(|l| &l.items)
                        .filter_map(|s| s.misconception.as_ref()),
                );
                links.extend(
                    misconceptions
                        .iter()
                        .flat_map(|l| &l.items)
                        .filter_map(|r| r.id.as_ref()),
                );
            }
            _ => {}
        }
        for s in links {
            ok &= link(rep, s, Some(&targets), "misconception", "misconception");
            used.push(s.value.clone());
        }
    }
    for m in &raw.misconceptions {
        let Some(s) = &m.id else { continue };
        if !used.contains(&s.value) {
            rep.warning(
                s.span.clone(),
                format!(
                    "misconception `{}` is declared but no choice, slip or range stands for it",
                    s.value
                ),
                Some(format!(
                    "add misconception = \"{}\" to the wrong choice it explains, or remove it",
                    s.value
                )),
            );
        }
    }
    ok
}

/// A number answer's `misconceptions`: each range two finite numbers, low
/// then high, none holding a number within the tolerance of `expected`
/// (`right`; such a number is a right answer and never stands for a
/// misconception). `None` when one is wrong.
pub fn ranges(
    rep: &mut FileReport,
    list: Option<&List<RawRange>>,
    right: Option<(f64, Tolerance)>,
    unit: Option<&str>,
) -> Option<Vec<WrongRange>> {
    let Some(list) = list else {
        return Some(Vec::new());
    };
    let unit = unit
        .filter(|u| !u.is_empty())
        .map_or(String::new(), |u| format!(" {u}"));
    let mut out = Vec::new();
    let mut ok = true;
    for r in &list.items {
        let (Some(range), Some(mid)) = (&r.range, &r.id) else {
            ok = false;
            continue;
        };
        let [lo, hi] = range.items.as_slice() else {
            rep.error(
                range.span.clone(),
                format!(
                    "`range` has {}; it is two numbers, [low, high]",
                    flipcard_text::plural(range.items.len(), "number", "numbers")
                ),
                None,
            );
            ok = false;
            continue;
        };
        let mut finite = true;
        for n in [lo, hi] {
            if !n.value.is_finite() {
                rep.error(
                    n.span.clone(),
                    format!("`range` bound {} is not finite", Num(n.value)),
                    Some("a range of wrong numbers has finite ends".to_string()),
                );
                finite = false;
            }
        }
        if !finite {
            ok = false;
            continue;
        }
        if lo.value > hi.value {
            rep.error(
                range.span.clone(),
                format!(
                    "`range` [{}, {}] is reversed: its low end is above its high end",
                    Num(lo.value),
                    Num(hi.value)
                ),
                Some(format!(
                    "write range = [{}, {}]",
                    Num(hi.value),
                    Num(lo.value)
                )),
            );
            ok = false;
            continue;
        }
        if let Some((expected, tolerance)) = right {
            let radius = match tolerance {
                Tolerance::Abs(a) => a,
                Tolerance::Rel(q) => q * expected.abs(),
            };
            if lo.value <= expected + radius && hi.value >= expected - radius {
                rep.error(
                    range.span.clone(),
                    format!(
                        "`range` [{}, {}]{unit} holds numbers within the tolerance of `expected` {}{unit}: a learner who types them is right, so they never stand for misconception `{}`",
                        Num(lo.value),
                        Num(hi.value),
                        Num(expected),
                        mid.value
                    ),
                    Some("narrow the range to wrong numbers only, or narrow `tolerance`".to_string()),
                );
                ok = false;
                continue;
            }
        }
        out.push(WrongRange {
            lo: lo.value,
            hi: hi.value,
            id: mid.value.clone(),
        });
    }
    ok.then_some(out)
}
