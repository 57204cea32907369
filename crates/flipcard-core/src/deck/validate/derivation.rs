//! Derivations step by step (issue 24 §5): the deck's `[[derivation]]`
//! entries (an id of the card id space, a title in every language, an
//! optional `explain` link checked like a card's, tags) and their ordered
//! steps (the math, why the step is taken, and an optional `ask`: think
//! then reveal, a choice with its right `answer`, or a formula whose key
//! is checked by `formula::key` exactly as a formula card's). Every
//! problem at its place in the file.

use crate::deck::model::{Ask, AskChoice, AskKind, Derivation, Step, Text};
use crate::deck::raw::{RawAsk, RawAskKind, RawDeckFile, RawDerivation, RawStep, RawText, Str};
use crate::deck::report::FileReport;
use crate::deck::suggest;

use super::text::{self, Kind, Langs};
use super::{Anchors, Targets, explain_link, id, unique};

/// The most steps a derivation may have: a derivation longer than this
/// is several (and a screen of them would not be read).
pub const MAX_STEPS: usize = 40;
/// The most choices of a choice ask: each is chosen by a digit key.
pub const MAX_CHOICES: usize = 9;

/// The deck's derivations, each checked; `None` when one is wrong.
pub fn derivations(
    rep: &mut FileReport,
    raw: &RawDeckFile,
    langs: &Langs,
    sections: (Option<&Targets>, &Anchors),
) -> Option<Vec<Derivation>> {
    let ids: Vec<&Str> = raw
        .derivations
        .iter()
        .filter_map(|d| d.id.as_ref())
        .collect();
    let mut ok = true;
    for s in &ids {
        ok &= id(rep, s, "derivation");
    }
    ok &= unique(rep, &ids, "derivation");
    // A derivation's reviews are kept under its id like a card's: one
    // name must not stand for both.
    for s in &ids {
        if let Some(card) = raw
            .cards
            .iter()
            .filter_map(|c| c.id.as_ref())
            .find(|c| c.value == s.value)
        {
            let line = rep.line_of(card.span.start);
            rep.error(
                s.span.clone(),
                format!("derivation id `{}` is also a card's id", s.value),
                Some(format!(
                    "the card is on line {line}; cards and derivations share one id space (review history is kept by id)"
                )),
            );
            ok = false;
        }
    }
    let mut out = Vec::new();
    for d in &raw.derivations {
        match derivation(rep, d, langs, sections) {
            Some(d) => out.push(d),
            None => ok = false,
        }
    }
    ok.then_some(out)
}

fn derivation(
    rep: &mut FileReport,
    raw: &RawDerivation,
    langs: &Langs,
    sections: (Option<&Targets>, &Anchors),
) -> Option<Derivation> {
    let what = match &raw.id {
        Some(s) if crate::deck::id::is_id(&s.value) => format!("derivation `{}`", s.value),
        _ => "a derivation".to_string(),
    };
    let title = raw
        .title
        .as_ref()
        .and_then(|t| text::text(rep, t, langs, &format!("the title of {what}")));
    let explain = explain_link(rep, &raw.explain, sections);
    let tags = super::tags(rep, &raw.tags);
    let steps = raw.steps.as_ref().and_then(|list| {
        if list.items.is_empty() {
            rep.error(
                list.span.clone(),
                format!("{what} has no steps"),
                Some("give each step under its own [[derivation.step]] header".to_string()),
            );
            return None;
        }
        if list.items.len() > MAX_STEPS {
            rep.error(
                list.items[MAX_STEPS].span.clone(),
                format!(
                    "{what} has {} steps; a derivation may have at most {MAX_STEPS}",
                    list.items.len()
                ),
                Some("split it into derivations of one idea each".to_string()),
            );
            return None;
        }
        let mut ok = true;
        let mut steps = Vec::new();
        for (i, s) in list.items.iter().enumerate() {
            match step(rep, s, langs, &format!("step {} of {what}", i + 1)) {
                Some(s) => steps.push(s),
                None => ok = false,
            }
        }
        ok.then_some(steps)
    });
    Some(Derivation {
        id: raw.id.as_ref()?.value.clone(),
        title: title?,
        explain: explain?,
        tags: tags?,
        steps: steps?,
    })
}

fn step(rep: &mut FileReport, raw: &RawStep, langs: &Langs, what: &str) -> Option<Step> {
    let math = raw
        .math
        .as_ref()
        .and_then(|t| math(rep, t, langs, &format!("the math of {what}")));
    let why = raw
        .why
        .as_ref()
        .and_then(|t| text::text(rep, t, langs, &format!("why of {what}")));
    let ask = match &raw.ask {
        Some(a) => ask(rep, a, langs, what).map(Some),
        None if raw.ask_unread => None,
        None => Some(None),
    };
    Some(Step {
        math: math?,
        why: why?,
        ask: ask?,
    })
}

/// A step's math: one string for every language (math reads the same in
/// each), or a table by language like any text.
fn math(rep: &mut FileReport, raw: &RawText, langs: &Langs, what: &str) -> Option<Text> {
    match raw {
        RawText::Plain(s) => {
            let ok = text::string(rep, s, Kind::Math, what);
            (ok && langs.known).then(|| {
                Text(
                    langs
                        .list
                        .iter()
                        .map(|l| (l.clone(), s.value.clone()))
                        .collect(),
                )
            })
        }
        RawText::ByLang { .. } => text::text(rep, raw, langs, what),
    }
}

fn ask(rep: &mut FileReport, raw: &RawAsk, langs: &Langs, what: &str) -> Option<Ask> {
    let question = match &raw.question {
        Some(t) => text::text(rep, t, langs, &format!("the question of {what}")).map(Some),
        None => Some(None),
    };
    let kind = match &raw.kind {
        RawAskKind::Reveal => Some(AskKind::Reveal),
        RawAskKind::Formula(f) => {
            super::formula::key(rep, f, &format!("the ask of {what}")).map(AskKind::Formula)
        }
        RawAskKind::Choice { choices, answer } => choice(rep, choices, answer, langs, what),
    };
    Some(Ask {
        question: question?,
        kind: kind?,
    })
}

fn choice(
    rep: &mut FileReport,
    choices: &Option<crate::deck::raw::List<crate::deck::raw::RawAskChoice>>,
    answer: &Option<Str>,
    langs: &Langs,
    what: &str,
) -> Option<AskKind> {
    let list = choices.as_ref()?;
    let mut ok = true;
    if list.items.len() < 2 || list.items.len() > MAX_CHOICES {
        rep.error(
            list.span.clone(),
            format!(
                "the ask of {what} has {}; a choice needs 2 to {MAX_CHOICES}",
                flipcard_text::plural(list.items.len(), "choice", "choices")
            ),
            None,
        );
        ok = false;
    }
    let ids: Vec<&Str> = list.items.iter().filter_map(|c| c.id.as_ref()).collect();
    for s in &ids {
        ok &= id(rep, s, "choice");
    }
    ok &= unique(rep, &ids, "choice");
    let mut out = Vec::new();
    for c in &list.items {
        let label = c
            .label
            .as_ref()
            .and_then(|t| text::text(rep, t, langs, &format!("a choice of {what}")));
        match (&c.id, label) {
            (Some(id), Some(label)) => out.push(AskChoice {
                id: id.value.clone(),
                label,
            }),
            _ => ok = false,
        }
    }
    let answer = answer.as_ref()?;
    if !ids.iter().any(|s| s.value == answer.value) {
        let names: Vec<&str> = ids.iter().map(|s| s.value.as_str()).collect();
        rep.error(
            answer.span.clone(),
            format!(
                "`answer` of the ask of {what} is `{}`, which is none of its choices",
                flipcard_text::safe::one_line(&answer.value)
            ),
            suggest::did_you_mean(&answer.value, names.iter().copied())
                .or_else(|| Some(format!("choices: {}", names.join(", ")))),
        );
        ok = false;
    }
    ok.then(|| AskKind::Choice {
        choices: out,
        answer: answer.value.clone(),
    })
}

/// The texts of the derivations written as tables of languages (for the
/// check that the declared languages are the ones the texts give).
pub(super) fn texts(raw: &RawDeckFile) -> Vec<&RawText> {
    let mut out = Vec::new();
    for d in &raw.derivations {
        out.extend(&d.title);
        for s in d.steps.iter().flat_map(|l| &l.items) {
            out.extend(s.math.iter().chain(&s.why));
            if let Some(a) = &s.ask {
                out.extend(&a.question);
                if let RawAskKind::Choice {
                    choices: Some(l), ..
                } = &a.kind
                {
                    out.extend(l.items.iter().filter_map(|c| c.label.as_ref()));
                }
            }
        }
    }
    out
}
