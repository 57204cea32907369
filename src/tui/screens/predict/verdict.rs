//! The verdict under the finished run: a banner that cannot be misread
//! (✓ Right / ✗ Wrong, the symbol carrying it without colour), the
//! learner's prediction on its own line, and what this run measured with
//! its evidence, claiming nothing beyond the run.

use ratatui::style::Modifier;
use ratatui::text::{Line, Span};

use crate::deck::{Answer, Measure, Prompt, Stat};
use crate::predict::audit::measure_unit;
use crate::sim::scene::measure::{Reading, formula_name};
use crate::text::num::{Num, sig};
use crate::tui::app::App;
use crate::tui::i18n::{Msg, Words, sim_words as w};
use crate::tui::live::Live;
use crate::tui::wrap::{Run, wrap};

use super::{Prediction, Verdict};

/// "a, b and c" in the app's language.
fn list_and(lang: &str, items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [head @ .., last] => format!("{} {} {last}", head.join(", "), w::AND.get(lang)),
    }
}

fn fill(words: Words, lang: &str, pairs: &[(&str, &str)]) -> String {
    pairs
        .iter()
        .fold(words.get(lang).to_string(), |s, (k, v)| s.replace(k, v))
}

/// "in this 8 s run: flipped 3 times: at 1.49, 4.24 and 7.00 s; …": every
/// reading the verdict rests on, with the flip times or the formula value
/// beside it.
pub fn evidence(lang: &str, unit: &str, v: &Verdict, prompt: &Prompt) -> String {
    let run = fill(
        w::IN_THIS_RUN,
        lang,
        &[("{d}", &format!("{} {unit}", Num(v.evidence.elapsed)))],
    );
    format!("{run}: {}", readings(lang, unit, v, prompt))
}

/// The verdict's lines for `run`, the run on screen: the verdict's own
/// lines and, when the learner played another method (or step) than the
/// reference run the verdict describes, what the run on screen showed. The
/// same for a rigid body and a system.
pub fn for_run(
    app: &App,
    prompt: &Prompt,
    prediction: Prediction,
    v: &Verdict,
    run: &Live,
    width: usize,
) -> Vec<Line<'static>> {
    let (_, unit) = run.timing();
    let mut out = lines(app, prompt, unit, prediction, v, width);
    if !run.is_reference() {
        let shown = on_screen(run.error(), run.finished(), || {
            crate::predict::verdict(prompt, &run.measurements(), prediction)
        });
        out.extend(run_on_screen(
            app,
            prompt,
            unit,
            (v, &run.reference_label()),
            (shown, &run.method_label()),
            width,
        ));
    }
    out
}

/// The run on screen, to set beside a reference verdict: why it stopped,
/// its own verdict (`judge`) once it reached its end, or `None` before
/// (Esc asked for the verdict: nothing whole to compare).
fn on_screen(
    error: Option<String>,
    finished: bool,
    judge: impl FnOnce() -> Verdict,
) -> Option<Result<Verdict, String>> {
    match error {
        Some(e) => Some(Err(e)),
        None if finished => Some(Ok(judge())),
        None => None,
    }
}

/// What the learner's own run on screen showed, when the verdict came from
/// the reference run because the learner played another method (or step):
/// said plainly, so a run that flies apart on screen is never mistaken for
/// the physics. `on_screen` is the verdict on the run on screen, or why
/// that run stopped (`None`: it has not reached its end).
fn run_on_screen(
    app: &App,
    prompt: &Prompt,
    unit: &str,
    reference: (&Verdict, &str),
    on_screen: (Option<Result<Verdict, String>>, &str),
    width: usize,
) -> Vec<Line<'static>> {
    let t = &app.theme;
    let lang = app.lang.as_str();
    let (v, ref_method) = reference;
    let (shown, method) = on_screen;
    let mut said = vec![fill(w::VERDICT_OF_REFERENCE, lang, &[("{m}", ref_method)])];
    let Some(shown) = shown else {
        return wrap(
            &[Run::new(said.join(" "), t.dim())],
            width.saturating_sub(1),
            Run::new(" ", t.dim()),
            Run::new("   ", t.dim()),
        );
    };
    said.push(match &shown {
        Err(why) => fill(w::ON_SCREEN_STOPPED, lang, &[("{m}", method), ("{e}", why)]),
        Ok(mine) => {
            let ours = readings(lang, unit, mine, prompt);
            let theirs = readings(lang, unit, v, prompt);
            if ours == theirs && mine.correct == v.correct {
                fill(w::ON_SCREEN_AGREES, lang, &[("{m}", method)])
            } else {
                fill(
                    w::ON_SCREEN_DIFFERS,
                    lang,
                    &[("{m}", method), ("{said}", &ours), ("{ref}", &theirs)],
                )
            }
        }
    });
    let style = if matches!(&shown, Ok(mine) if mine.correct == v.correct) {
        t.dim()
    } else {
        t.bad()
    };
    wrap(
        &[Run::new(said.join(" "), style)],
        width.saturating_sub(1),
        Run::new(" ", style),
        Run::new("   ", style),
    )
}

/// The readings a verdict rests on, joined ("period(x) = 4.894 s; …").
fn readings(lang: &str, unit: &str, v: &Verdict, prompt: &Prompt) -> String {
    let answer = &prompt.answer;
    let mut said: Vec<String> = v
        .readings
        .iter()
        .map(|r| reading(lang, unit, v, r, prompt))
        .collect();
    if said.is_empty() {
        let measure = match answer {
            Answer::Formula(_) => None,
            Answer::Number { measure, .. } => Some(*measure),
            Answer::Choice { choices, .. } => choices.first().map(|c| c.when.measure()),
        };
        if let Some(m) = measure {
            let name = match &prompt.measured {
                Some(d) if d.measure == m => crate::text::render(d.label.get(lang)),
                _ => crate::tui::i18n::measure_label(m, lang),
            };
            said.push(format!("{name} {}", w::NOT_MEASURED.get(lang)));
        }
    }
    said.join("; ")
}

/// One measurement as the verdict reads it: named in words ("time for B
/// to get within 1% of rest", the deck's `label` when it gives one, else
/// the measure with the variable it is of: "period of θ"), then its value
/// with its unit: the label's, the measure's own, a period's time unit, or
/// the prompt's unit when the prompt asks for this very number.
fn reading(lang: &str, unit: &str, v: &Verdict, r: &Reading, prompt: &Prompt) -> String {
    let answer = &prompt.answer;
    if r.measure == Measure::Flips {
        let times: Vec<String> = v.evidence.flip_times.iter().map(|&t| sig(t, 3)).collect();
        let times = format!("{} {unit}", list_and(lang, &times));
        return match v.evidence.flip_times.len() {
            0 => w::FLIPPED_NONE.get(lang).to_string(),
            1 => fill(w::FLIPPED_ONCE, lang, &[("{times}", &times)]),
            n => fill(
                w::FLIPPED_MANY,
                lang,
                &[("{n}", &n.to_string()), ("{times}", &times)],
            ),
        };
    }
    let mut u = measure_unit(r.measure, unit);
    if u.is_empty() {
        u = match (r.measure, answer) {
            (Measure::Of(Stat::Period | Stat::Beat | Stat::TimeOf(_), _), _) => unit.to_string(),
            (m, Answer::Number { measure, unit, .. }) if m == *measure => unit.clone(),
            _ => String::new(),
        };
    }
    let labelled = prompt.measured.as_ref().filter(|d| d.measure == r.measure);
    if let Some(d) = labelled
        && !d.unit.is_empty()
    {
        u = d.unit.clone();
    }
    let u = if u.is_empty() { u } else { format!(" {u}") };
    let name = match labelled {
        Some(d) => crate::text::render(d.label.get(lang)),
        None => crate::tui::i18n::measure_label(r.measure, lang),
    };
    let value = sig(r.value, 3);
    let fname = formula_name(r.measure);
    match r.formula {
        // A named expectation ("steady spin", "invariant") rather than a
        // formula: what it expects, without an equation.
        Some(f) if fname.chars().all(|c| c.is_ascii_alphabetic() || c == ' ') => {
            format!("{name}: {value}{u} ({fname}: {}{u})", sig(f, 3))
        }
        Some(f) => format!(
            "{name}: {value}{u}, {} {fname} = {}{u}",
            w::FORMULA.get(lang),
            sig(f, 3)
        ),
        None => format!("{name}: {value}{u}"),
    }
}

/// What the learner committed to, as the prompt words it.
pub fn prediction_text(app: &App, prompt: &Prompt, p: Prediction) -> String {
    match (p, &prompt.answer) {
        (Prediction::Choice(i), Answer::Choice { choices, .. }) => choices
            .get(i)
            .map(|c| crate::text::render(c.label.get(&app.lang)))
            .unwrap_or_default(),
        (Prediction::Number(v), Answer::Number { unit, .. }) => format!("{} {unit}", Num(v)),
        _ => String::new(),
    }
}

/// A formula prompt's verdict lines: the banner, the formula typed
/// (escaped: it is the learner's text), the slip it makes, and the
/// deck's formula. No measurement is said: none decided it.
fn formula_lines(
    app: &App,
    (typed, v): (&str, &crate::sim::system::equiv::Verdict),
    prompt: &Prompt,
    labelled: &dyn Fn(&str, String, ratatui::style::Style) -> Vec<Line<'static>>,
) -> Vec<Line<'static>> {
    let t = &app.theme;
    let lang = app.lang.as_str();
    let mut out = labelled(
        app.tr(Msg::YourPrediction),
        crate::text::safe::one_line(typed).into_owned(),
        t.strong(),
    );
    if let Some(said) = crate::tui::i18n::formula_words::feedback(v, lang) {
        out.extend(labelled(w::WHERE_WRONG.get(lang), said, t.bad()));
    }
    if let Answer::Formula(key) = &prompt.answer {
        out.extend(labelled(
            w::DECK_ANSWER.get(lang),
            // As the reader shows math; as written if it does not read.
            match crate::sim::system::equiv::latex(&key.expected) {
                Some(tex) => crate::text::render(&format!("${tex}$")),
                None => crate::text::safe::one_line(&key.expected).into_owned(),
            },
            t.text(),
        ));
    }
    out
}

/// The verdict's lines, wrapped to `width`: banner, prediction, evidence,
/// then the right choice (when the prediction missed it) or, for a number,
/// the formula's value beside the deck's answer and the author's working.
pub fn lines(
    app: &App,
    prompt: &Prompt,
    time_unit: &str,
    prediction: Prediction,
    v: &Verdict,
    width: usize,
) -> Vec<Line<'static>> {
    let t = &app.theme;
    let lang = app.lang.as_str();
    let (mark, word, style) = if v.correct {
        ("✓", w::RIGHT, t.good())
    } else {
        ("✗", w::WRONG, t.bad())
    };
    let banner = format!(" {mark} {} {mark}", word.get(lang));
    let pad = width.saturating_sub(unicode_width::UnicodeWidthStr::width(banner.as_str()));
    let mut out = vec![Line::from(vec![Span::styled(
        format!("{banner}{}", " ".repeat(pad)),
        style.add_modifier(Modifier::REVERSED | Modifier::BOLD),
    )])];
    let labelled = |label: &str, text: String, style| {
        wrap(
            &[
                Run::new(format!("{label}: "), t.dim()),
                Run::new(text, style),
            ],
            width.saturating_sub(1),
            Run::new(" ", t.dim()),
            Run::new("   ", t.dim()),
        )
    };
    if let Some(f) = &v.formula {
        let (typed, fv) = &**f;
        out.extend(formula_lines(app, (typed, fv), prompt, &labelled));
        return out;
    }
    out.extend(labelled(
        app.tr(Msg::YourPrediction),
        prediction_text(app, prompt, prediction),
        t.strong(),
    ));
    let said = evidence(lang, time_unit, v, prompt);
    out.extend(wrap(
        &[Run::new(said, t.text())],
        width.saturating_sub(1),
        Run::new(" ", t.text()),
        Run::new("   ", t.text()),
    ));
    // The slip a wrong number matches, beside what the run measured: what
    // that number is, and what it means.
    if let (Answer::Number { slips, unit, .. }, Some((i, value))) = (&prompt.answer, v.slip)
        && let Some(slip) = slips.get(i)
    {
        let u = if unit.is_empty() {
            String::new()
        } else {
            format!(" {unit}")
        };
        let mut runs = vec![
            Run::new(format!("{} ", w::YOUR_NUMBER_IS.get(lang)), t.dim()),
            Run::new(
                format!("{} = {}{u}: ", readable(&slip.value), sig(value, 3)),
                t.bad(),
            ),
        ];
        runs.extend(crate::tui::wrap::math_runs(slip.says.get(lang), t.strong()));
        out.extend(wrap(
            &runs,
            width.saturating_sub(1),
            Run::new(" ", t.dim()),
            Run::new("   ", t.dim()),
        ));
    }
    out.extend(misconception(app, prompt, v, width));
    match &prompt.answer {
        Answer::Formula(_) => {}
        Answer::Choice { choices, .. } => {
            let right = v.right_choice.and_then(|i| choices.get(i));
            if let (false, Some(c)) = (v.correct, right) {
                out.extend(labelled(
                    w::RIGHT_IN_RUN.get(lang),
                    crate::text::render(c.label.get(lang)),
                    t.strong(),
                ));
            }
        }
        Answer::Number {
            expected,
            unit,
            formula,
            ..
        } => {
            let closed = v
                .readings
                .iter()
                .find_map(|r| r.formula.map(|f| (formula_name(r.measure), f)));
            // The formula's value beside the deck's answer; without a
            // closed form, the deck's answer alone (no empty "formula:").
            // A varied prompt's answer is what this variant's run measured
            // (said above): no deck answer to show beside it.
            match (closed, expected) {
                (Some((name, f)), Some(expected)) => {
                    let text = format!(
                        "{name} = {} {unit} · {}: {} {unit}",
                        sig(f, 3),
                        w::DECK_ANSWER.get(lang),
                        Num(*expected)
                    );
                    out.extend(labelled(w::FORMULA.get(lang), text, t.text()));
                }
                (Some((name, f)), None) => {
                    let text = format!("{name} = {} {unit}", sig(f, 3));
                    out.extend(labelled(w::FORMULA.get(lang), text, t.text()));
                }
                (None, Some(expected)) => out.extend(labelled(
                    w::DECK_ANSWER.get(lang),
                    format!("{} {unit}", Num(*expected)),
                    t.text(),
                )),
                (None, None) => {}
            }
            if let Some(f) = formula {
                // The author's working, its formulas kept whole.
                let mut runs = vec![Run::new(format!("{}: ", w::WORKED.get(lang)), t.dim())];
                runs.extend(crate::tui::wrap::math_runs(f.get(lang), t.math()));
                out.extend(wrap(
                    &runs,
                    width.saturating_sub(1),
                    Run::new(" ", t.dim()),
                    Run::new("   ", t.dim()),
                ));
            }
        }
    }
    out
}

/// The misconception a wrong answer stands for, beside the evidence: its
/// title, why it seems right (the steel-man) and the fix, each whole and
/// in the learner's language, and the section `e` opens when the deck
/// explains it. Nothing for an answer that names none.
fn misconception(app: &App, prompt: &Prompt, v: &Verdict, width: usize) -> Vec<Line<'static>> {
    let t = &app.theme;
    let lang = app.lang.as_str();
    // The deck whose prompt this is (the screen draws the deck's own).
    let Some(deck) = app
        .decks
        .iter()
        .find(|d| d.prompts.iter().any(|p| std::ptr::eq(p, prompt)))
        .or_else(|| {
            app.decks
                .iter()
                .find(|d| d.prompt(&prompt.id) == Some(prompt))
        })
    else {
        return Vec::new();
    };
    let Some(m) = v
        .misconception
        .as_deref()
        .and_then(|id| deck.misconception(id))
    else {
        return Vec::new();
    };
    let block = |label: &str, text: &str, style| {
        let mut runs = vec![Run::new(format!("{label}: "), t.dim())];
        runs.extend(crate::tui::wrap::math_runs(text, style));
        wrap(
            &runs,
            width.saturating_sub(1),
            Run::new(" ", t.dim()),
            Run::new("   ", t.dim()),
        )
    };
    let mut out = block(w::MISCONCEPTION.get(lang), m.title.get(lang), t.bad());
    out.extend(block(
        w::WHY_IT_SEEMS_RIGHT.get(lang),
        m.why_it_seems_right.get(lang),
        t.text(),
    ));
    out.extend(block(w::FIX.get(lang), m.fix.get(lang), t.strong()));
    if let Some(section) = m.explain.as_ref().and_then(|e| deck.section(&e.section)) {
        let title = crate::text::render(section.title.get(lang));
        out.extend(wrap(
            &[Run::new(
                fill(w::READ_MORE, lang, &[("{s}", &title)]),
                t.dim(),
            )],
            width.saturating_sub(1),
            Run::new(" ", t.dim()),
            Run::new("   ", t.dim()),
        ));
    }
    out
}

/// A slip's formula as a reader writes it: `2*pi*sqrt(L/g)` → `2·π·√(L/g)`
/// (Greek names as letters, `sqrt` as √, `*` as ·); the deck's text is the
/// system scenes' expression syntax.
fn readable(formula: &str) -> String {
    let mut out = String::new();
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        if !word.is_empty() {
            out.push_str(&match word.as_str() {
                "sqrt" => "√".to_string(),
                w => crate::text::variable_name(w),
            });
            word.clear();
        }
    };
    for c in formula.chars() {
        if c.is_ascii_alphanumeric() || c == '_' || c == '.' {
            word.push(c);
            continue;
        }
        flush(&mut word, &mut out);
        match c {
            '*' => out.push('·'),
            ' ' => {}
            c => out.push(c),
        }
    }
    flush(&mut word, &mut out);
    out
}

#[cfg(test)]
mod readable_tests {
    #[test]
    fn a_slip_formula_reads_as_written_mathematics() {
        assert_eq!(super::readable("2*pi*sqrt(L/g)"), "2·π·√(L/g)");
        assert_eq!(super::readable("1/(2*zeta*w0)"), "1/(2·ζ·w0)");
        assert_eq!(super::readable("1/k"), "1/k");
    }
}
