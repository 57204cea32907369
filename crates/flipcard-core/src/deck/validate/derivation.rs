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
                    "the card is on line {line}; cards and derivations share one id space, as review history is kept by id"
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

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use proptest::prelude::*;

    use crate::deck::files::Memory;
    use crate::deck::model::{AskKind, Derivation};

    const HEAD: &str = "[deck]\nid = \"d\"\ntitle = 'D'\nlanguages = [\"en\"]\n\n\
                        [[card]]\nid = \"c\"\nfront = 'F'\nback = 'B'\n\n";

    /// The deck `HEAD` + `body`, loaded from memory: its derivations, or
    /// every diagnostic as `line:col: message`.
    fn load(body: &str) -> Result<Vec<Derivation>, Vec<String>> {
        let deck = format!("{HEAD}{body}");
        let bytes: &'static [u8] = Box::leak(deck.into_bytes().into_boxed_slice());
        let content: &'static [u8] = b"[[section]]\nid = \"s\"\ntitle = 'S'\nbody = 'B.'\n";
        let tree = Memory::new([
            (PathBuf::from("/r/decks/d.toml"), bytes),
            (PathBuf::from("/r/content/d/en.toml"), content),
        ]);
        let (loaded, _) = crate::deck::load_sources(&[(&tree, PathBuf::from("/r/decks"))]);
        if loaded.errors() > 0 {
            return Err(loaded
                .diagnostics
                .iter()
                .map(|d| {
                    let hint = d.hint.as_deref().unwrap_or_default();
                    format!("{}:{}: {} ({hint})", d.line, d.col, d.message)
                })
                .collect());
        }
        Ok(loaded.decks[0].derivations.clone())
    }

    /// The errors of `body`, each `line:col: message`; panics when it loads.
    fn errors(body: &str) -> Vec<String> {
        match load(body) {
            Ok(d) => panic!("loaded: {d:?}\n{body}"),
            Err(e) => e,
        }
    }

    fn has(errors: &[String], at: &str, says: &str) {
        assert!(
            errors.iter().any(|e| e.starts_with(at) && e.contains(says)),
            "no `{says}` at {at}: {errors:?}"
        );
    }

    // HEAD has 10 lines: a body starts on line 11.
    const STEP: &str = "[[derivation.step]]\nmath = '$x = 1$'\nwhy = 'Because.'\n";

    #[test]
    fn a_derivation_loads_with_its_steps_and_asks() {
        let d = load(
            "[[derivation]]\nid = \"x\"\ntitle = 'X'\nexplain = \"s\"\ntags = [\"t\"]\n\
             [[derivation.step]]\nmath = '$a$'\nwhy = 'W1'\nask = { kind = \"reveal\" }\n\
             [[derivation.step]]\nmath = '$b$'\nwhy = 'W2'\n\
             ask = { kind = \"choice\", answer = \"y\", choices = [{ id = \"n\", label = 'No' }, { id = \"y\", label = '$y$' }] }\n\
             [[derivation.step]]\nmath = '$c$'\nwhy = 'W3'\n\
             ask = { kind = \"formula\", question = 'Q $k$', expected = \"2 x\", vars = { x = [1, 2] } }\n\
             [[derivation.step]]\nmath = '$d$'\nwhy = 'W4'\n",
        )
        .unwrap();
        assert_eq!(d.len(), 1);
        let x = &d[0];
        assert_eq!((x.id.as_str(), x.steps.len()), ("x", 4));
        assert_eq!(x.tags, ["t"]);
        assert_eq!(x.explain.as_ref().map(|e| e.section.as_str()), Some("s"));
        assert_eq!(x.steps[0].math.get("en"), "$a$");
        assert!(matches!(
            x.steps[0].ask.as_ref().map(|a| &a.kind),
            Some(AskKind::Reveal)
        ));
        match x.steps[1].ask.as_ref().map(|a| &a.kind) {
            Some(AskKind::Choice { choices, answer }) => {
                assert_eq!(answer, "y");
                assert_eq!(choices.len(), 2);
            }
            other => panic!("{other:?}"),
        }
        match x.steps[2].ask.as_ref() {
            Some(a) => {
                assert_eq!(a.question.as_ref().map(|q| q.get("en")), Some("Q $k$"));
                assert!(matches!(&a.kind, AskKind::Formula(k) if k.expected == "2 x"));
            }
            None => panic!("no ask"),
        }
        assert!(x.steps[3].ask.is_none());
    }

    #[test]
    fn problems_are_reported_at_their_place() {
        // Unknown keys, in the derivation, a step and an ask.
        let e = errors(&format!(
            "[[derivation]]\nid = \"x\"\ntitle = 'X'\nsection = \"s\"\n{STEP}reason = 'R'\n\
             ask = {{ kind = \"reveal\", answer = \"a\" }}\n"
        ));
        has(&e, "14:1:", "unknown field `section`");
        has(&e, "18:1:", "unknown field `reason`");
        has(&e, "19:", "`answer` belongs to kind = \"choice\" asks");
        // No steps; duplicate ids; an id that is a card's.
        let e = errors(
            "[[derivation]]\nid = \"x\"\ntitle = 'X'\nstep = []\n\
             [[derivation]]\nid = \"c\"\ntitle = 'C'\n[[derivation.step]]\nmath = '$a$'\nwhy = 'W'\n\
             [[derivation]]\nid = \"c\"\ntitle = 'C'\n[[derivation.step]]\nmath = '$a$'\nwhy = 'W'\n",
        );
        has(&e, "14:8:", "derivation `x` has no steps");
        has(&e, "16:6:", "derivation id `c` is also a card's id");
        has(&e, "22:6:", "duplicate derivation id `c`");
        // A missing step table and a bad id.
        let e = errors("[[derivation]]\nid = \"Bad Id\"\ntitle = 'X'\n");
        has(&e, "11:1:", "missing the required field `step`");
        has(&e, "12:6:", "derivation id `Bad Id` is not a valid id");
        // Asks: unknown kind, an answer none of the choices, one choice.
        let e = errors(&format!(
            "[[derivation]]\nid = \"x\"\ntitle = 'X'\n{STEP}ask = {{ kind = \"guess\" }}\n\
             {STEP}ask = {{ kind = \"choice\", answer = \"z\", choices = [{{ id = \"a\", label = 'A' }}, {{ id = \"b\", label = 'B' }}] }}\n\
             {STEP}ask = {{ kind = \"choice\", answer = \"a\", choices = [{{ id = \"a\", label = 'A' }}] }}\n"
        ));
        has(&e, "17:", "unknown ask kind `guess`");
        has(
            &e,
            "21:",
            "`answer` of the ask of step 2 of derivation `x` is `z`",
        );
        has(&e, "25:", "has 1 choice; a choice needs 2 to 9");
        // A formula key checked as a formula card's: an unknown name at
        // its place, an unused variable.
        let e = errors(&format!(
            "[[derivation]]\nid = \"x\"\ntitle = 'X'\n{STEP}\
             ask = {{ kind = \"formula\", expected = \"2 y\", vars = {{ x = [1, 2] }} }}\n"
        ));
        has(
            &e,
            "17:",
            "`expected` of the ask of step 1 of derivation `x`",
        );
        // Math that does not render; a text in a language not declared.
        let e = errors(
            "[[derivation]]\nid = \"x\"\ntitle = 'X'\n[[derivation.step]]\nmath = '$\\frac{a$'\nwhy = { en = 'W', fr = 'P' }\n",
        );
        has(&e, "15:", "");
        has(&e, "16:", "language `fr` is not declared");
    }

    #[test]
    fn more_than_forty_steps_are_refused() {
        let body = format!(
            "[[derivation]]\nid = \"x\"\ntitle = 'X'\n{}",
            STEP.repeat(super::MAX_STEPS + 1)
        );
        let e = errors(&body);
        // The 41st step's table starts on this line.
        let line = 14 + 3 * super::MAX_STEPS;
        has(
            &e,
            &format!("{line}:"),
            "has 41 steps; a derivation may have at most 40",
        );
        assert_eq!(
            load(&format!(
                "[[derivation]]\nid = \"x\"\ntitle = 'X'\n{}",
                STEP.repeat(super::MAX_STEPS)
            ))
            .unwrap()[0]
                .steps
                .len(),
            super::MAX_STEPS
        );
    }

    fn ask() -> impl Strategy<Value = (String, bool)> {
        prop_oneof![
            Just((String::new(), true)),
            Just(("ask = { kind = \"reveal\" }\n".to_string(), true)),
            Just((
                "ask = { kind = \"choice\", answer = \"a\", choices = [{ id = \"a\", label = 'A' }, { id = \"b\", label = 'B' }] }\n"
                    .to_string(),
                true
            )),
            Just((
                "ask = { kind = \"formula\", expected = \"x^2\", vars = { x = [1, 2] } }\n"
                    .to_string(),
                true
            )),
            Just(("ask = { kind = \"formula\", expected = \"x^2\", vars = { y = [1, 2] } }\n".to_string(), false)),
            Just(("ask = { kind = \"choice\", answer = \"q\", choices = [] }\n".to_string(), false)),
            Just(("ask = \"reveal\"\n".to_string(), false)),
            Just(("ask = { question = 'Q' }\n".to_string(), false)),
        ]
    }

    proptest! {
        /// Any number of steps (0 to 45) with any mix of asks, good and
        /// broken: loaded exactly when every step is sound and the count
        /// is within 1..=40, with every step in order; otherwise refused
        /// with errors, never a panic.
        #[test]
        fn steps_load_in_order_or_are_refused(asks in proptest::collection::vec(ask(), 0..45)) {
            let mut body = "[[derivation]]\nid = \"x\"\ntitle = 'X'\n".to_string();
            if asks.is_empty() {
                body.push_str("step = []\n");
            }
            for (i, (ask, _)) in asks.iter().enumerate() {
                body.push_str(&format!("[[derivation.step]]\nmath = '$s_{{{i}}}$'\nwhy = 'W{i}'\n{ask}"));
            }
            let fine = (1..=super::MAX_STEPS).contains(&asks.len()) && asks.iter().all(|(_, ok)| *ok);
            match load(&body) {
                Ok(d) => {
                    prop_assert!(fine, "loaded: {body}");
                    prop_assert_eq!(d[0].steps.len(), asks.len());
                    for (i, s) in d[0].steps.iter().enumerate() {
                        let math = format!("$s_{{{i}}}$");
                        prop_assert_eq!(s.math.get("en"), math.as_str());
                        prop_assert_eq!(s.ask.is_some(), !asks[i].0.is_empty());
                    }
                }
                Err(e) => {
                    prop_assert!(!fine, "refused: {e:?}\n{body}");
                    prop_assert!(!e.is_empty());
                }
            }
        }
    }
}
