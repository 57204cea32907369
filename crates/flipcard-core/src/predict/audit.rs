//! The author's answers against the simulation: every prompt's scene is run
//! and its expected answer judged as a learner's would be, so that a deck
//! never teaches what its own run does not show. Besides a plainly wrong
//! answer, a choice that holds only because the run stops early (no flip
//! yet, one flip where the body goes on flipping) is reported too: a longer
//! run of the same scene would give the other verdict.

use std::collections::HashMap;

use crate::deck::diag::{Diagnostic, Severity};
use crate::deck::places::{AnswerPlaces, Place, answer_places};
use crate::deck::{Answer, Choice, Condition, Deck, Loaded, Measure, Prompt, Scene};
use flipcard_sim::Method;
use flipcard_sim::scene::measure::{Measurements, formula_name};
use flipcard_sim::scene::measure_scene;
use flipcard_text::num::{Num, sig};

/// Which part of the answer a problem is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// The `expected` value.
    Expected,
    /// The `when` condition of choice `i`.
    When(usize),
}

/// Why a prompt's expected answer is not what its scene's run shows.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    pub target: Target,
    /// What the run shows and how to fix the prompt, in one sentence.
    pub message: String,
}

/// Judges the author's expected answer on `prompt` with the measurements
/// of a run of its `scene`.
pub fn audit(prompt: &Prompt, scene: &Scene, m: &Measurements) -> Option<Problem> {
    match &prompt.answer {
        Answer::Choice { choices, expected } => audit_choice(choices, expected, scene, m),
        Answer::Number {
            measure,
            unit,
            expected,
            tolerance,
            ..
        } => {
            let run = run_name(scene);
            let name = measure.name();
            let shown = format!("{name} = {} {unit}", Num(*expected));
            let message = match m.reading(*measure) {
                None => format!(
                    "expected {shown}, but {run} cannot measure {name}{}",
                    unmeasured(*measure, scene, m)
                ),
                Some(r) if !tolerance.accepts(*expected, r.value) => {
                    let formula = r
                        .formula
                        .map(|f| {
                            format!(
                                " (formula {} = {} {unit})",
                                formula_name(*measure),
                                sig(f, 4)
                            )
                        })
                        .unwrap_or_default();
                    format!(
                        "expected {shown}, but {run} measures {} {unit}{formula}: change `expected` to about {} or widen `tolerance`",
                        sig(r.value, 4),
                        sig(r.value, 4)
                    )
                }
                Some(_) => return None,
            };
            Some(Problem {
                target: Target::Expected,
                message,
            })
        }
    }
}

fn audit_choice(
    choices: &[Choice],
    expected: &str,
    scene: &Scene,
    m: &Measurements,
) -> Option<Problem> {
    let run = run_name(scene);
    let e = choices.iter().position(|c| c.id == expected)?;
    let holds = |c: &Condition| m.get(c.measure).is_some_and(|v| c.holds(v));
    let holding: Vec<usize> = (0..choices.len())
        .filter(|&i| holds(&choices[i].when))
        .collect();
    let when = choices[e].when;
    let interval = m.evidence().flip_interval;
    let flips = m.get(Measure::Flips).unwrap_or(0.0);
    let flipping = when.measure == Measure::Flips && interval.is_some();

    if !holding.contains(&e) {
        let shows = match m.get(when.measure) {
            Some(_) => format!("{run} measures {}", said(when.measure, scene, m)),
            None => format!(
                "{run} cannot measure {}{}",
                when.measure.name(),
                unmeasured(when.measure, scene, m)
            ),
        };
        let fix = match (flipping, interval) {
            (true, Some(t)) => match count_where(&when, flips, true) {
                Some(n) => format!(
                    "make the run longer than {} ({} = {} {} each) or change the answer",
                    periods(n),
                    formula_name(Measure::FlipPeriod),
                    sig(t, 3),
                    scene.time_unit
                ),
                None => change_to(choices, &holding),
            },
            _ => change_to(choices, &holding),
        };
        return Some(Problem {
            target: Target::Expected,
            message: format!("expected `{expected}`, but {shows}: {fix}"),
        });
    }
    if let Some(&other) = holding.iter().find(|&&i| i != e) {
        return Some(Problem {
            target: Target::When(other),
            message: format!(
                "choices `{expected}` and `{}` both hold in {run}, which measures {}: make the conditions exclusive",
                choices[other].id,
                said(choices[other].when.measure, scene, m)
            ),
        });
    }
    // The flips go on after the run ends: the answer must hold for every
    // longer run too, or it teaches an accident of the run's length.
    if let (true, Some(t)) = (flipping, interval)
        && let Some(n) = count_where(&when, flips, false)
    {
        let times = &m.evidence().flip_times;
        let by = match times.first() {
            Some(first) => first + (n - 1.0) * t,
            None => n * t,
        };
        return Some(Problem {
            target: Target::Expected,
            message: format!(
                "expected `{expected}` holds only because {run} ends early: it measures {}, but the body flips every {} {} ({}), so a run of {} {} measures flips = {}: ask about what every run shows, or make the run longer and change the answer",
                said(Measure::Flips, scene, m),
                sig(t, 3),
                scene.time_unit,
                formula_name(Measure::FlipPeriod),
                sig(by * 1.01, 3),
                scene.time_unit,
                Num(n)
            ),
        });
    }
    None
}

/// The smallest flip count above `measured` for which `when` holds
/// (`holding`) or fails (`!holding`); `None` when there is none, however
/// long the run.
fn count_where(when: &Condition, measured: f64, holding: bool) -> Option<f64> {
    let far = 1e12;
    (1..=1000)
        .map(|k| measured + f64::from(k))
        .chain([far])
        .find(|&n| when.holds(n) == holding)
}

/// "two flip periods", "3 flip periods".
fn periods(n: f64) -> String {
    let words = ["one flip period", "two flip periods", "three flip periods"];
    match n as usize {
        k @ 1..=3 => words[k - 1].to_string(),
        _ => format!("{} flip periods", Num(n)),
    }
}

fn change_to(choices: &[Choice], holding: &[usize]) -> String {
    match holding.first() {
        Some(&i) => format!("change the answer to `{}`", choices[i].id),
        None => "no choice holds: change the conditions".to_string(),
    }
}

/// "this 3 s run".
pub fn run_name(scene: &Scene) -> String {
    format!("this {} {} run", Num(scene.duration), scene.time_unit)
}

/// The unit a measure is read in, for a scene in `time_unit`.
pub fn measure_unit(measure: Measure, time_unit: &str) -> String {
    match measure {
        Measure::FlipPeriod | Measure::EfoldTime | Measure::PrecessionPeriod => {
            time_unit.to_string()
        }
        Measure::GrowthRate => format!("1/{time_unit}"),
        Measure::OscillationFreq | Measure::PrecessionRate => format!("rad/{time_unit}"),
        Measure::Flips
        | Measure::OmegaChange
        | Measure::EnergyDrift
        | Measure::MomentumDrift
        | Measure::Of(..) => String::new(),
    }
}

/// "a, b and c".
pub fn list_and(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [head @ .., last] => format!("{} and {last}", head.join(", ")),
    }
}

/// A measurement as the run gave it, with its evidence: "flips = 1 (at
/// 1.08 s)", "efold_time = 0.173 s (formula 1/√k = 0.173 s)".
fn said(measure: Measure, scene: &Scene, m: &Measurements) -> String {
    let unit = &scene.time_unit;
    let Some(r) = m.reading(measure) else {
        return format!("no {}", measure.name());
    };
    if measure == Measure::Flips {
        let times: Vec<String> = m.evidence().flip_times.iter().map(|&t| sig(t, 3)).collect();
        return if times.is_empty() {
            "flips = 0".to_string()
        } else {
            format!("flips = {} (at {} {unit})", Num(r.value), list_and(&times))
        };
    }
    let u = measure_unit(measure, unit);
    let u = if u.is_empty() { u } else { format!(" {u}") };
    let formula = r
        .formula
        .map(|f| format!(" (formula {} = {}{u})", formula_name(measure), sig(f, 3)))
        .unwrap_or_default();
    format!("{} = {}{u}{formula}", measure.name(), sig(r.value, 3))
}

/// Why a run has no value for `measure`, and what would give it one.
fn unmeasured(measure: Measure, scene: &Scene, m: &Measurements) -> String {
    let unit = &scene.time_unit;
    let interval = m.evidence().flip_interval;
    match (measure, interval) {
        (Measure::FlipPeriod, Some(t)) => format!(
            " (that takes two flips, and it measures {}): make the run longer than three flip periods ({} = {} {unit} each)",
            said(Measure::Flips, scene, m),
            formula_name(Measure::FlipPeriod),
            sig(t, 3)
        ),
        (Measure::FlipPeriod, None) => {
            " (the body does not flip): change the scene or the measure".to_string()
        }
        (Measure::GrowthRate | Measure::EfoldTime, _) => {
            " (a small disturbance about the middle axis must grow by e² and then by e while still small): start closer to the middle axis, or run longer".to_string()
        }
        (Measure::OscillationFreq, _) => {
            " (a wobble about the largest or smallest axis, two swings at least): run longer".to_string()
        }
        (Measure::PrecessionRate | Measure::PrecessionPeriod, _) => {
            " (it needs a symmetric top, two equal moments)".to_string()
        }
        _ => String::new(),
    }
}

/// The simulation's verdict on every prompt of the loaded decks, as
/// diagnostics at each prompt's `expected` value (or at the `when` of a
/// choice that should not hold). Each scene runs once, with the exact
/// solution.
pub fn check_loaded(loaded: &Loaded) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for deck in &loaded.decks {
        let source = loaded.sources.get(&deck.path).map_or("", String::as_str);
        let places = answer_places(&deck.path, source);
        out.extend(check_deck(deck, &places));
    }
    out
}

fn check_deck(deck: &Deck, places: &HashMap<String, AnswerPlaces>) -> Vec<Diagnostic> {
    let mut measured: HashMap<&str, Result<Measurements, String>> = HashMap::new();
    let mut out = Vec::new();
    for prompt in &deck.prompts {
        let Some(scene) = deck.scene(&prompt.scene) else {
            continue;
        };
        let m = measured
            .entry(scene.id.as_str())
            .or_insert_with(|| measure_scene(scene, Method::Exact).map_err(|e| e.to_string()));
        let problem = match m {
            Ok(m) => audit(prompt, scene, m),
            Err(e) => Some(Problem {
                target: Target::Expected,
                message: format!(
                    "the answer cannot be checked: scene `{}` does not run to its end ({e})",
                    scene.id
                ),
            }),
        };
        let Some(problem) = problem else {
            continue;
        };
        let at = places.get(&prompt.id);
        let place = match problem.target {
            Target::Expected => at.and_then(|p| p.expected),
            Target::When(i) => at.and_then(|p| p.when.get(i).copied().flatten()),
        }
        .unwrap_or(Place {
            line: 0,
            col: 0,
            width: 0,
        });
        out.push(Diagnostic {
            path: deck.path.clone(),
            line: place.line,
            col: place.col,
            severity: Severity::Error,
            message: problem.message,
            hint: Some(format!(
                "the simulation decides the answer; `flipcard sim --scene {}` shows every measurement",
                scene.id
            )),
            width: place.width,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deck::{Cmp, Text};

    fn text(s: &str) -> Text {
        Text([("en".to_string(), s.to_string())].into())
    }

    fn scene(omega: [f64; 3], duration: f64) -> Scene {
        Scene {
            id: "s".into(),
            title: None,
            inertia: [1.0, 2.0, 3.0],
            omega,
            duration,
            show: vec![crate::deck::Panel::Omega],
            time_unit: "s".into(),
        }
    }

    fn choice_prompt(expected: &str, conditions: &[(&str, Cmp, f64)]) -> Prompt {
        Prompt {
            id: "p".into(),
            question: text("?"),
            scene: "s".into(),
            explain: None,
            tags: vec![],
            answer: Answer::Choice {
                expected: expected.into(),
                choices: conditions
                    .iter()
                    .map(|&(id, op, value)| Choice {
                        id: id.into(),
                        label: text(id),
                        when: Condition {
                            measure: Measure::Flips,
                            op,
                            value,
                        },
                    })
                    .collect(),
            },
        }
    }

    fn judge(p: &Prompt, s: &Scene) -> Option<Problem> {
        audit(p, s, &measure_scene(s, Method::Exact).unwrap())
    }

    #[test]
    fn none_yet_is_an_accident_of_the_run_when_the_body_flips() {
        // First flip at about 1.09 s: a 1 s run sees none.
        let p = choice_prompt(
            "steady",
            &[("steady", Cmp::Eq, 0.0), ("flips", Cmp::Gt, 0.0)],
        );
        let problem = judge(&p, &scene([0.1, 10.0, 0.1], 1.0)).unwrap();
        assert!(
            problem
                .message
                .contains("holds only because this 1 s run ends early"),
            "{problem:?}"
        );
        // About the largest axis nothing ever flips: the same answer is right.
        assert_eq!(judge(&p, &scene([0.1, 0.1, 10.0], 1.0)), None);
        // And `flips > 0` stays true however long the run.
        let p = choice_prompt(
            "flips",
            &[("steady", Cmp::Eq, 0.0), ("flips", Cmp::Gt, 0.0)],
        );
        assert_eq!(judge(&p, &scene([0.1, 10.0, 0.1], 3.0)), None);
    }

    #[test]
    fn overlapping_conditions_point_at_the_other_choice() {
        let p = choice_prompt("flips", &[("some", Cmp::Ge, 1.0), ("flips", Cmp::Gt, 0.0)]);
        let problem = judge(&p, &scene([0.1, 10.0, 0.1], 3.0)).unwrap();
        assert_eq!(problem.target, Target::When(0));
        assert!(problem.message.contains("both hold"), "{problem:?}");
    }

    #[test]
    fn a_measure_the_run_cannot_make_says_what_it_needs() {
        let p = Prompt {
            answer: Answer::Number {
                measure: Measure::FlipPeriod,
                unit: "s".into(),
                expected: 1.96,
                tolerance: crate::deck::Tolerance::Rel(0.1),
                formula: None,
            },
            ..choice_prompt("x", &[])
        };
        let problem = judge(&p, &scene([0.1, 10.0, 0.1], 2.0)).unwrap();
        assert!(
            problem
                .message
                .contains("cannot measure flip_period (that takes two flips")
                && problem.message.contains("longer than three flip periods"),
            "{problem:?}"
        );
        assert_eq!(judge(&p, &scene([0.1, 10.0, 0.1], 8.0)), None);
    }

    #[test]
    fn lists_read_as_prose() {
        let s = |v: &[&str]| list_and(&v.iter().map(|x| x.to_string()).collect::<Vec<_>>());
        assert_eq!(s(&[]), "");
        assert_eq!(s(&["1.49"]), "1.49");
        assert_eq!(s(&["1.49", "4.24", "7.00"]), "1.49, 4.24 and 7.00");
    }
}
