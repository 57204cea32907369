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

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use proptest::prelude::*;

    use crate::deck::files::Memory;

    /// A deck whose number prompt (right at 5.774 ± 5 %) maps `range` to a
    /// misconception, loaded from memory: its misconceptions' ranges, or
    /// the diagnostics' lines and messages.
    fn load(range: &str) -> Result<Vec<crate::deck::model::WrongRange>, Vec<String>> {
        let deck = format!(
            "[deck]\nid = \"d\"\ntitle = 'D'\nlanguages = [\"en\"]\n\n\
             [[prompt]]\nid = \"p\"\nquestion = 'How fast?'\nscene = \"s\"\n\n\
             [prompt.answer]\nkind = \"number\"\nmeasure = \"growth_rate\"\nunit = \"1/s\"\n\
             expected = 5.774\ntolerance = {{ rel = 0.05 }}\n\
             misconceptions = [{{ range = {range}, id = \"m\" }}]\n\n\
             [[scene]]\nid = \"s\"\ninertia = [1.0, 2.0, 3.0]\nflat = true\n\
             omega = [0.001, 10.0, 0.001]\nduration = 4.0\nshow = [\"omega\"]\n\n\
             [[misconception]]\nid = \"m\"\ntitle = 'T'\nwhy_it_seems_right = 'W'\nfix = 'F'\n"
        );
        let bytes: &'static [u8] = Box::leak(deck.into_bytes().into_boxed_slice());
        let tree = Memory::new([
            (PathBuf::from("/r/decks/d.toml"), bytes),
            (PathBuf::from("/r/content/d/en.toml"), &b""[..]),
        ]);
        let (loaded, _) = crate::deck::load_sources(&[(&tree, PathBuf::from("/r/decks"))]);
        if loaded.errors() > 0 {
            return Err(loaded
                .diagnostics
                .iter()
                .map(|d| format!("{}:{}: {}", d.line, d.col, d.message))
                .collect());
        }
        let d = loaded.decks.first().expect("a deck without errors loads");
        match &d.prompts[0].answer {
            crate::deck::model::Answer::Number { misconceptions, .. } => Ok(misconceptions.clone()),
            _ => unreachable!(),
        }
    }

    fn toml_number(v: f64) -> String {
        if v.is_nan() {
            "nan".into()
        } else if v.is_infinite() {
            if v > 0.0 { "inf".into() } else { "-inf".into() }
        } else {
            format!("{v:?}")
        }
    }

    fn end() -> impl Strategy<Value = f64> {
        prop_oneof![
            8 => -20.0f64..20.0,
            1 => Just(f64::INFINITY),
            1 => Just(f64::NEG_INFINITY),
            1 => Just(f64::NAN),
            2 => Just(5.774 * 0.95),
            2 => Just(5.774 * 1.05),
        ]
    }

    proptest! {
        /// Any two numbers as a range are loaded as written exactly when
        /// both are finite, low first, and clear of the right answer's
        /// tolerance; otherwise one error, on the range's line, and no
        /// deck. Run longer with
        /// `PROPTEST_CASES=20000 cargo test --lib validate::misconception`.
        #[test]
        fn a_range_is_loaded_or_refused_by_its_numbers(lo in end(), hi in end()) {
            let radius = 0.05 * 5.774f64;
            let fine = lo.is_finite()
                && hi.is_finite()
                && lo <= hi
                && !(lo <= 5.774 + radius && hi >= 5.774 - radius);
            let got = load(&format!("[{}, {}]", toml_number(lo), toml_number(hi)));
            match got {
                Ok(ranges) => {
                    prop_assert!(fine, "[{lo}, {hi}] was loaded");
                    prop_assert_eq!(ranges.len(), 1);
                    prop_assert_eq!((ranges[0].lo, ranges[0].hi), (lo, hi));
                    prop_assert_eq!(&ranges[0].id, "m");
                }
                Err(errors) => {
                    prop_assert!(!fine, "[{lo}, {hi}] refused: {errors:?}");
                    prop_assert!(
                        errors.iter().all(|e| e.starts_with("17:")),
                        "{errors:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_range_of_one_or_three_numbers_is_refused_at_the_range() {
        for range in ["[1.0]", "[1.0, 2.0, 3.0]", "[]"] {
            let errors = load(range).unwrap_err();
            assert!(
                errors
                    .iter()
                    .any(|e| e.starts_with("17:") && e.contains("two numbers, [low, high]")),
                "{range}: {errors:?}"
            );
        }
    }
}
