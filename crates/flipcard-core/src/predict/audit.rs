//! The author's answers against the simulation: every prompt's scene is run
//! and its expected answer judged as a learner's would be, so that a deck
//! never teaches what its own run does not show. Rigid bodies and systems
//! take the one path: a scene's run becomes a [`Run`] (what it measured,
//! why a measure could not be made, how long it lasted) and [`audit_run`]
//! judges the prompt on it. Besides a plainly wrong answer, overlapping
//! choices and a measure the run cannot make, an answer that holds only
//! because the run stops early is reported too: for a rigid body from its
//! flips (no flip yet, one flip where the body goes on flipping), for a
//! system by running the scene again [`LONGER`] times as long and judging
//! the answer on that run as well.

use std::collections::HashMap;

use crate::deck::diag::{Diagnostic, Severity};
use crate::deck::places::{AnswerPlaces, Place, ScenePlaces, answer_places, scene_places};
use crate::deck::{
    Answer, Choice, Condition, Deck, Loaded, Measure, Prompt, Scene, Stat, SystemScene,
};
use flipcard_sim::Method;
use flipcard_sim::scene::measure::{Measurements, Reading, formula_name};
use flipcard_sim::scene::measure_scene;
use flipcard_sim::scene::system::{RunError, SystemPlan, SystemRun, measure_system};
use flipcard_sim::solvers::ode::{OdeKind, OdeMethod};
use flipcard_sim::system::compile::Source;
use flipcard_text::num::{Num, sig};

use super::variant::{self, Resolved, SceneOf, Undecided};

/// How much longer the second run of a system scene is: an answer that
/// changes when the run goes on this much further holds only because the
/// run ends where it does.
pub(crate) const LONGER: f64 = 1.5;

/// A run of a prompt's scene as the audit reads it, whatever the kind of
/// scene: what it measured and over how long.
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    /// The scene's run length and time unit.
    pub duration: f64,
    pub time_unit: String,
    pub measured: Measurements,
    /// Why a measure is absent from `measured`, where the run says why (a
    /// system's measures: "crosses … once over the run; a period needs
    /// two").
    pub missing: Vec<(Measure, String)>,
    /// The same scene run [`LONGER`] times as long, when that run reaches
    /// its end (a system scene): the answer must hold on it too.
    pub longer: Option<Box<Run>>,
    /// What a reader of a measure's value should know (`period` of a
    /// quantity whose crossings are not evenly spaced).
    pub caveats: Vec<(Measure, String)>,
}

impl Run {
    /// A rigid body's run: its flips tell when an answer would change.
    pub fn rigid(scene: &Scene, measured: Measurements) -> Run {
        Run {
            duration: scene.duration,
            time_unit: scene.time_unit.clone(),
            measured,
            missing: Vec::new(),
            longer: None,
            caveats: Vec::new(),
        }
    }

    /// A system scene run to its end with `method` as `check` runs it
    /// (computing every observable and the sketch, so a scene that passes
    /// plays with any plan), measuring `measures`; then run again
    /// [`LONGER`] times as long for the same measures. The error is why
    /// the first run stopped early; a longer run that stops early (its
    /// budget, a blow-up past the scene's end) is left out.
    pub fn system(
        scene: &SystemScene,
        method: OdeMethod,
        measures: &[Measure],
    ) -> Result<Run, RunError> {
        let plan = SystemPlan {
            sketch: !scene.sketch.is_empty(),
            observables: vec![true; scene.observables.len()],
            ..SystemPlan::for_scene(scene, method, measures).headless()
        };
        let mut run = SystemRun::with_plan(scene, method, plan).map_err(|e| RunError::Domain {
            t: 0.0,
            message: e.to_string(),
            at: None,
        })?;
        run.run_to_end()?;
        let (measured, missing) = system_readings(measures, |m| run.measure(m), scene.duration);
        let caveats = measures
            .iter()
            .filter_map(|&m| run.caveat(m).map(|c| (m, c)))
            .collect();
        let longer_scene = SystemScene {
            duration: scene.duration * LONGER,
            ..scene.clone()
        };
        let longer = measure_system(&longer_scene, method, measures)
            .ok()
            .map(|values| {
                let mut values = values.into_iter();
                let (measured, missing) = system_readings(
                    measures,
                    |_| {
                        values.next().map_or_else(
                            || Err("not measured".to_string()),
                            |v| v.map_err(|e| e.to_string()),
                        )
                    },
                    longer_scene.duration,
                );
                Box::new(Run {
                    duration: longer_scene.duration,
                    time_unit: scene.time_unit.clone(),
                    measured,
                    missing,
                    longer: None,
                    caveats: Vec::new(),
                })
            });
        Ok(Run {
            duration: scene.duration,
            time_unit: scene.time_unit.clone(),
            measured,
            missing,
            longer,
            caveats,
        })
    }

    /// Why the run has no value for `measure`, as the run said it.
    fn why_missing(&self, measure: Measure) -> Option<&str> {
        self.missing
            .iter()
            .find(|(m, _)| *m == measure)
            .map(|(_, why)| why.as_str())
    }
}

/// Each measure's value, or why the run could not make it.
fn system_readings<E: std::fmt::Display>(
    measures: &[Measure],
    mut value: impl FnMut(Measure) -> Result<f64, E>,
    elapsed: f64,
) -> (Measurements, Vec<(Measure, String)>) {
    let mut readings = Vec::new();
    let mut missing = Vec::new();
    for &m in measures {
        match value(m) {
            Ok(v) => readings.push(Reading {
                measure: m,
                value: v,
                formula: None,
            }),
            Err(why) => missing.push((m, why.to_string())),
        }
    }
    (Measurements::from_readings(readings).over(elapsed), missing)
}

/// The measures one prompt's answer uses.
fn prompt_uses(p: &Prompt) -> Vec<Measure> {
    match &p.answer {
        Answer::Choice { choices, .. } => choices.iter().flat_map(|c| c.when.measures()).collect(),
        Answer::Number { measure, .. } => vec![*measure],
        Answer::Formula(_) => Vec::new(),
    }
}

/// The measures the prompts on scene `scene_id` use, in order of first use.
pub fn prompt_measures(deck: &Deck, scene_id: &str) -> Vec<Measure> {
    let mut out = Vec::new();
    for p in deck.prompts.iter().filter(|p| p.scene == scene_id) {
        for m in prompt_uses(p) {
            if !out.contains(&m) {
                out.push(m);
            }
        }
    }
    out
}

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
/// of a run of its rigid `scene` (see [`audit_run`]).
pub fn audit(prompt: &Prompt, scene: &Scene, m: &Measurements) -> Option<Problem> {
    audit_run(prompt, &Run::rigid(scene, m.clone()))
}

/// Judges the author's expected answer on `prompt` with a run of its
/// scene, whatever the kind: contradicted, two choices holding, a measure
/// the run cannot make, or an answer that holds only because the run ends
/// early (a rigid body's flips, or the longer run of a system).
pub fn audit_run(prompt: &Prompt, run: &Run) -> Option<Problem> {
    if let Some(problem) = judge(prompt, run) {
        return Some(problem);
    }
    let longer = run.longer.as_deref()?;
    let message = match &prompt.answer {
        // No run decides a formula (its key is checked by `check`).
        Answer::Formula(_) => return None,
        Answer::Choice { choices, expected } => {
            // A varied prompt's answer is each variant's run's (`decided`
            // writes it in before its audit).
            let expected = expected.as_deref()?;
            let e = choices.iter().position(|c| c.id == expected)?;
            let holding = holding(choices, &longer.measured);
            let said_there = |c: &Choice| said_all(&c.when, longer);
            let shows = if !holding.contains(&e) {
                format!(
                    "{}, where `{expected}` does not hold",
                    said_there(&choices[e])
                )
            } else {
                let other = holding.iter().find(|&&i| i != e)?;
                format!(
                    "{}, where `{}` holds too",
                    said_there(&choices[*other]),
                    choices[*other].id
                )
            };
            format!(
                "expected `{expected}` holds only because {} ends early: a run of {} {} measures {shows}: ask about what every run shows, or make the run longer and change the answer",
                run_name(run),
                Num(longer.duration),
                run.time_unit
            )
        }
        Answer::Number {
            measure,
            unit,
            expected,
            tolerance,
            ..
        } => {
            let expected = &(*expected)?;
            let there = match longer.measured.get(*measure) {
                Some(v) if tolerance.accepts(*expected, v) => return None,
                Some(v) => format!("{} {unit}", sig(v, 4)),
                None => format!(
                    "nothing ({})",
                    longer
                        .why_missing(*measure)
                        .map_or_else(|| format!("no {measure}"), |w| bare(w, *measure))
                ),
            };
            format!(
                "expected {measure} = {} {unit} holds only because {} ends early: a run of {} {} measures {there}: ask about what every run shows (a measure that settles), or make the run longer and change `expected`",
                Num(*expected),
                run_name(run),
                Num(longer.duration),
                run.time_unit
            )
        }
    };
    Some(Problem {
        target: Target::Expected,
        message,
    })
}

/// The known slips of a number prompt that are right answers on `run`:
/// each slip's value (with `measured` the run's value) within the
/// tolerance of what the run measures, so a learner typing it is told it
/// is right and the slip is never said. Each with its index and why.
pub fn audit_slips(prompt: &Prompt, run: &Run) -> Vec<(usize, String)> {
    let Answer::Number {
        measure,
        unit,
        tolerance,
        slips,
        ..
    } = &prompt.answer
    else {
        return Vec::new();
    };
    let Some(measured) = run.measured.get(*measure) else {
        return Vec::new();
    };
    let u = if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    };
    slips
        .iter()
        .enumerate()
        .filter_map(|(i, slip)| {
            let message = match slip.value_for(measured) {
                None => format!(
                    "slip `{}` has no finite value on {}, which measures {measure} = {}{u}: give a formula the run can take",
                    slip.value,
                    run_name(run),
                    sig(measured, 4)
                ),
                Some(w) if tolerance.accepts(w, measured) => format!(
                    "slip `{}` gives {}{u}, within the tolerance of what {} measures ({measure} = {}{u}): a learner who types it is right, so it is never a slip; give the formula of the wrong answer, or narrow `tolerance`",
                    slip.value,
                    sig(w, 4),
                    run_name(run),
                    sig(measured, 4)
                ),
                Some(_) => return None,
            };
            Some((i, message))
        })
        .collect()
}

/// The choices whose condition holds on `m`, in the prompt's order.
fn holding(choices: &[Choice], m: &Measurements) -> Vec<usize> {
    (0..choices.len())
        .filter(|&i| choices[i].when.holds_on(|x| m.get(x)).unwrap_or(false))
        .collect()
}

/// The judgement on the run itself (not yet the longer run).
fn judge(prompt: &Prompt, run: &Run) -> Option<Problem> {
    let m = &run.measured;
    match &prompt.answer {
        Answer::Formula(_) => None,
        Answer::Choice { choices, expected } => audit_choice(choices, expected.as_deref()?, run),
        Answer::Number {
            measure,
            unit,
            expected,
            tolerance,
            ..
        } => {
            let expected = &(*expected)?;
            let name = run_name(run);
            let shown = format!("{measure} = {} {unit}", Num(*expected));
            let message = match m.reading(*measure) {
                None => format!(
                    "expected {shown}, but {name} cannot measure {measure}{}",
                    unmeasured(*measure, run)
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
                        "expected {shown}, but {name} measures {} {unit}{formula}: change `expected` to about {} or widen `tolerance`",
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

fn audit_choice(choices: &[Choice], expected: &str, run: &Run) -> Option<Problem> {
    let m = &run.measured;
    let name = run_name(run);
    let unit = &run.time_unit;
    let e = choices.iter().position(|c| c.id == expected)?;
    let holding = holding(choices, m);
    let when = &choices[e].when;
    let interval = m.evidence().flip_interval;
    let flips = m.get(Measure::Flips).unwrap_or(0.0);
    let flipping = when.single().is_some_and(|(m, ..)| m == Measure::Flips) && interval.is_some();

    if !holding.contains(&e) {
        let missing = when.measures().into_iter().find(|&x| m.get(x).is_none());
        let shows = match missing {
            None => format!("{name} measures {}", said_all(when, run)),
            Some(x) => format!("{name} cannot measure {x}{}", unmeasured(x, run)),
        };
        let fix = match (flipping, interval) {
            (true, Some(t)) => match count_where(when, flips, true) {
                Some(n) => format!(
                    "make the run longer than {} ({} = {} {unit} each) or change the answer",
                    periods(n),
                    formula_name(Measure::FlipPeriod),
                    sig(t, 3),
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
                "choices `{expected}` and `{}` both hold in {name}, which measures {}: make the conditions exclusive",
                choices[other].id,
                said_all(&choices[other].when, run)
            ),
        });
    }
    // The flips go on after the run ends: the answer must hold for every
    // longer run too, or it teaches an accident of the run's length.
    if let (true, Some(t)) = (flipping, interval)
        && let Some(n) = count_where(when, flips, false)
    {
        let times = &m.evidence().flip_times;
        let by = match times.first() {
            Some(first) => first + (n - 1.0) * t,
            None => n * t,
        };
        return Some(Problem {
            target: Target::Expected,
            message: format!(
                "expected `{expected}` holds only because {name} ends early: it measures {}, but the body flips every {} {unit} ({}), so a run of {} {unit} measures flips = {}: ask about what every run shows, or make the run longer and change the answer",
                said(Measure::Flips, run),
                sig(t, 3),
                formula_name(Measure::FlipPeriod),
                sig(by * 1.01, 3),
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
pub(crate) fn run_name(run: &Run) -> String {
    format!("this {} {} run", Num(run.duration), run.time_unit)
}

/// The unit a measure is read in, for a scene in `time_unit`.
pub fn measure_unit(measure: Measure, time_unit: &str) -> String {
    match measure {
        Measure::FlipPeriod
        | Measure::EfoldTime
        | Measure::PrecessionPeriod
        | Measure::Of(Stat::Period | Stat::Beat | Stat::TimeOf(_), _) => time_unit.to_string(),
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
/// 1.08 s)", "efold_time = 0.173 s (formula 1/√k = 0.173 s)",
/// "period(theta) = 2.04".
fn said(measure: Measure, run: &Run) -> String {
    let m = &run.measured;
    let unit = &run.time_unit;
    let Some(r) = m.reading(measure) else {
        return format!("no {measure}");
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
    format!("{measure} = {}{u}{formula}", sig(r.value, 3))
}

/// Every measure a condition names, as the run gave it ("period(a) = 2.04,
/// period(b) = 2.31").
fn said_all(when: &Condition, run: &Run) -> String {
    let all: Vec<String> = when.measures().into_iter().map(|m| said(m, run)).collect();
    all.join(", ")
}

/// The run's reason without the measure's name it starts with
/// ("period(x): x crosses …" → "x crosses …").
fn bare(why: &str, measure: Measure) -> String {
    let head = format!("{measure}: ");
    why.strip_prefix(head.as_str()).unwrap_or(why).to_string()
}

/// Why a run has no value for `measure`, and what would give it one.
fn unmeasured(measure: Measure, run: &Run) -> String {
    let unit = &run.time_unit;
    let interval = run.measured.evidence().flip_interval;
    if let Some(why) = run.why_missing(measure) {
        let fix = match measure {
            Measure::Of(Stat::Period, _) => {
                "make the run longer (two upward crossings at least) or ask about another measure"
            }
            Measure::Of(Stat::Beat, _) => {
                "make the run longer (two beats at least), or measure period() where the peaks do not vary"
            }
            Measure::Of(Stat::TimeOf(_), _) => {
                "make the run longer, or ask about a level the run reaches"
            }
            _ => "change the scene or the measure",
        };
        return format!(" ({}): {fix}", bare(why, measure));
    }
    match (measure, interval) {
        (Measure::FlipPeriod, Some(t)) => format!(
            " (that takes two flips, and it measures {}): make the run longer than three flip periods ({} = {} {unit} each)",
            said(Measure::Flips, run),
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
/// choice that should not hold). Each rigid scene runs once, with the exact
/// solution; each system scene (with prompts or without) runs to its end
/// with the method the app starts with, computing all it can compute, and
/// once more [`LONGER`] times as long for its prompts: a run that stops
/// early is an error at the expression or value to fix, and at each prompt
/// on the scene.
pub fn check_loaded(loaded: &Loaded) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for deck in &loaded.decks {
        let source = loaded.sources.get(&deck.path).map_or("", String::as_str);
        // Reading the file again for places costs as much as loading it:
        // only a deck with prompts has answers to place.
        let places = if deck.prompts.is_empty() {
            HashMap::new()
        } else {
            answer_places(&deck.path, source)
        };
        let scenes = if deck.systems.is_empty() {
            HashMap::new()
        } else {
            scene_places(&deck.path, source)
        };
        out.extend(check_deck(deck, &places, &scenes));
    }
    out
}

/// A scene's run, or why it did not reach its end (and where to say so).
enum Ran {
    Done(Run),
    Stopped { message: String, hint: String },
}

fn check_deck(
    deck: &Deck,
    places: &HashMap<String, AnswerPlaces>,
    scenes: &HashMap<String, ScenePlaces>,
) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let diagnostic = |place: Option<Place>, message: String, hint: String| Diagnostic {
        path: deck.path.clone(),
        line: place.map_or(0, |p| p.line),
        col: place.map_or(0, |p| p.col),
        width: place.map_or(0, |p| p.width),
        severity: Severity::Error,
        message,
        hint: Some(hint),
    };
    let mut ran: HashMap<&str, Ran> = HashMap::new();
    for scene in &deck.scenes {
        if !deck.prompts.iter().any(|p| p.scene == scene.id) {
            continue;
        }
        let run = match measure_scene(scene, Method::Exact) {
            Ok(m) => Ran::Done(Run::rigid(scene, m)),
            Err(e) => Ran::Stopped {
                message: e.to_string(),
                hint: sim_hint(&scene.id),
            },
        };
        ran.insert(scene.id.as_str(), run);
    }
    for scene in &deck.systems {
        let measures = prompt_measures(deck, &scene.id);
        let method = OdeMethod::default_for(OdeKind::Auto, scene.duration);
        let run = match Run::system(scene, method, &measures) {
            Ok(run) => Ran::Done(run),
            Err(e) => {
                let hint = format!(
                    "`flipcard sim --scene {} --samples 20` shows the run up to there",
                    scene.id
                );
                let at = scenes.get(&scene.id);
                let place = at
                    .and_then(|p| match &e {
                        RunError::Domain { at: Some(src), .. } => match *src {
                            Source::Equation(k) => p.equations.get(k).copied(),
                            Source::Observable(k) => p.observables.get(k).copied(),
                            Source::Mark(k) => p.marks.get(k).copied(),
                        },
                        RunError::Work { .. } => p.duration,
                        _ => p.id,
                    })
                    .or_else(|| at.and_then(|p| p.id));
                out.push(diagnostic(
                    place,
                    format!("scene `{}` does not run to its end: {e}", scene.id),
                    hint.clone(),
                ));
                Ran::Stopped {
                    message: e.to_string(),
                    hint,
                }
            }
        };
        ran.insert(scene.id.as_str(), run);
    }
    for prompt in &deck.prompts {
        let Some(run) = ran.get(prompt.scene.as_str()) else {
            continue;
        };
        let at = places.get(&prompt.id);
        if !prompt.vary.is_empty() {
            if let Some((message, hint)) = audit_variants(deck, prompt) {
                out.push(diagnostic(
                    at.and_then(|p| p.vary)
                        .or_else(|| at.and_then(|p| p.expected)),
                    message,
                    hint,
                ));
            }
            continue;
        }
        if let Ran::Done(run) = run {
            let used = prompt_uses(prompt);
            for (m, caveat) in &run.caveats {
                if used.contains(m) {
                    out.push(Diagnostic {
                        severity: Severity::Warning,
                        ..diagnostic(
                            at.and_then(|p| p.expected),
                            caveat.clone(),
                            sim_hint(&prompt.scene),
                        )
                    });
                }
            }
        }
        if let Ran::Done(run) = run {
            for (i, message) in audit_slips(prompt, run) {
                out.push(diagnostic(
                    at.and_then(|p| p.slips.get(i).copied().flatten()),
                    message,
                    sim_hint(&prompt.scene),
                ));
            }
        }
        let (problem, hint) = match run {
            Ran::Done(run) => (audit_run(prompt, run), sim_hint(&prompt.scene)),
            Ran::Stopped { message, hint, .. } => (
                Some(Problem {
                    target: Target::Expected,
                    message: format!(
                        "the answer cannot be checked: scene `{}` does not run to its end ({message})",
                        prompt.scene
                    ),
                }),
                hint.clone(),
            ),
        };
        let Some(problem) = problem else {
            continue;
        };
        let place = match problem.target {
            Target::Expected => at.and_then(|p| p.expected),
            Target::When(i) => at.and_then(|p| p.when.get(i).copied().flatten()),
        };
        out.push(diagnostic(place, problem.message, hint));
    }
    out
}

/// A run of one variant of a prompt's scene, as `check` and `sim
/// --variant` make it: the rigid body's exact solution, a system's auto
/// method to its end (and once more [`LONGER`] times as long).
pub fn variant_run(deck: &Deck, resolved: &Resolved) -> Result<Run, String> {
    match &resolved.scene {
        SceneOf::Rigid(s) => measure_scene(s, Method::Exact)
            .map(|m| Run::rigid(s, m))
            .map_err(|e| e.to_string()),
        SceneOf::System(s) => {
            let measures = prompt_measures(deck, &s.id);
            let method = OdeMethod::default_for(OdeKind::Auto, s.duration);
            Run::system(s, method, &measures).map_err(|e| e.to_string())
        }
    }
}

/// Runs the variants `check` samples of a varied prompt
/// ([`variant::samples`]: the ends and middle of every range, and seeded
/// draws) and judges each on its own run: the run must reach its end, the
/// answer be decided (the measure made, exactly one choice holding, the
/// deck's `expected` choice when it names one), and hold on the longer
/// run. The first variant that fails, named by its numbers, with how many
/// others fail too.
fn audit_variants(deck: &Deck, prompt: &Prompt) -> Option<(String, String)> {
    let mut first: Option<String> = None;
    let mut failing = 0usize;
    let samples = variant::samples(prompt);
    for v in &samples {
        let resolved = variant::resolve(deck, prompt, Some(v))?;
        let why = match variant_run(deck, &resolved) {
            Err(e) => Some(format!("the scene does not run to its end ({e})")),
            Ok(run) => match variant::decided(&resolved.prompt, &run.measured) {
                Err(u) => Some(undecided(&resolved.prompt, &run, &u)),
                Ok(p) => audit_run(&p, &run)
                    // The fixes for one run ("change the answer to …") do
                    // not fit every variant: the help says what does.
                    .map(|problem| match problem.message.split_once(": change ") {
                        Some((what, _)) => what.to_string(),
                        None => problem.message,
                    })
                    .or_else(|| audit_slips(&p, &run).into_iter().next().map(|(_, m)| m)),
            },
        };
        if let Some(why) = why {
            failing += 1;
            first.get_or_insert_with(|| format!("variant {}: {why}", v.describe()));
        }
    }
    let first = first?;
    let more = match failing {
        1 => String::new(),
        n => format!(" ({} of the {} variants checked fail)", n, samples.len()),
    };
    Some((
        format!("{first}{more}"),
        format!(
            "narrow `vary` to numbers whose runs decide the answer; `flipcard sim --scene {} --prompt {} --variant SEED` shows one variant",
            prompt.scene, prompt.id
        ),
    ))
}

/// Why a variant's run does not decide the answer, in words.
fn undecided(prompt: &Prompt, run: &Run, u: &Undecided) -> String {
    match (u, &prompt.answer) {
        (Undecided::NotMeasured, Answer::Number { measure, .. }) => format!(
            "{} cannot measure {measure}{}",
            run_name(run),
            unmeasured(*measure, run)
        ),
        (Undecided::NoChoice, Answer::Choice { choices, .. }) => {
            let said: Vec<String> = choices
                .iter()
                .map(|c| said_all(&c.when, run))
                .collect::<Vec<_>>();
            let mut said = said;
            said.dedup();
            format!(
                "no choice holds: {} measures {}",
                run_name(run),
                said.join("; ")
            )
        }
        (Undecided::Several(ids), _) => format!(
            "choices {} all hold in {}: make the conditions exclusive",
            ids.iter()
                .map(|i| format!("`{i}`"))
                .collect::<Vec<_>>()
                .join(", "),
            run_name(run)
        ),
        _ => "the run does not decide the answer".to_string(),
    }
}

fn sim_hint(scene: &str) -> String {
    format!(
        "the simulation decides the answer; `flipcard sim --scene {scene}` shows every measurement"
    )
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
                expected: Some(expected.into()),
                choices: conditions
                    .iter()
                    .map(|&(id, op, value)| Choice {
                        misconception: None,
                        id: id.into(),
                        label: text(id),
                        when: Condition::compare(Measure::Flips, op, value),
                    })
                    .collect(),
            },
            measured: None,
            vary: Vec::new(),
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
    fn a_slip_that_the_run_makes_a_right_answer_is_reported_and_a_wrong_one_is_not() {
        let sc = scene([0.01, 10.0, 0.01], 2.0);
        let scope = flipcard_sim::scene::quantities::rigid(sc.inertia, sc.omega);
        let slip = |value: &str| crate::deck::Slip {
            misconception: None,
            value: value.to_string(),
            says: text("says"),
            scope: scope.clone(),
        };
        let p = Prompt {
            answer: Answer::Number {
                misconceptions: Vec::new(),
                measure: Measure::EfoldTime,
                unit: "s".into(),
                expected: Some(0.1732),
                tolerance: crate::deck::Tolerance::Rel(0.1),
                formula: None,
                // 1/k is the slip; 1/sqrt(k) and 1.05*measured are right answers.
                slips: vec![
                    slip("1/k"),
                    slip("1/sqrt(k)"),
                    slip("1.05*measured"),
                    slip("1/(k-k)"),
                ],
            },
            ..choice_prompt("x", &[])
        };
        let run = Run::rigid(&sc, measure_scene(&sc, Method::Exact).unwrap());
        let found = audit_slips(&p, &run);
        let which: Vec<usize> = found.iter().map(|(i, _)| *i).collect();
        assert_eq!(which, [1, 2, 3], "{found:?}");
        assert!(
            found[0].1.contains("slip `1/sqrt(k)` gives 0.17"),
            "{found:?}"
        );
        assert!(found[2].1.contains("no finite value"), "{found:?}");
        // The learner's 0.03 s is the slip 1/k, said by the verdict.
        let v =
            crate::predict::verdict(&p, &run.measured, crate::predict::Prediction::Number(0.03));
        assert!(!v.correct);
        let (i, w) = v.slip.unwrap();
        assert_eq!(i, 0);
        assert!((w - 0.03).abs() < 1e-12, "{w}");
        let v = crate::predict::verdict(&p, &run.measured, crate::predict::Prediction::Number(0.5));
        assert_eq!(v.slip, None);
    }

    #[test]
    fn a_measure_the_run_cannot_make_says_what_it_needs() {
        let p = Prompt {
            answer: Answer::Number {
                misconceptions: Vec::new(),
                measure: Measure::FlipPeriod,
                unit: "s".into(),
                expected: Some(1.96),
                tolerance: crate::deck::Tolerance::Rel(0.1),
                formula: None,
                slips: Vec::new(),
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

    /// A system's run as the audit reads it: `values` measured over
    /// `duration`, and the run 1.5× as long.
    fn system_run(duration: f64, values: &[(Measure, f64)], longer: &[(Measure, f64)]) -> Run {
        let made = |d: f64, v: &[(Measure, f64)]| Run {
            duration: d,
            time_unit: "s".into(),
            measured: Measurements::from_readings(
                v.iter()
                    .map(|&(measure, value)| Reading {
                        measure,
                        value,
                        formula: None,
                    })
                    .collect(),
            )
            .over(d),
            missing: Vec::new(),
            caveats: Vec::new(),
            longer: None,
        };
        Run {
            longer: Some(Box::new(made(duration * LONGER, longer))),
            ..made(duration, values)
        }
    }

    fn number_prompt(measure: Measure, expected: f64) -> Prompt {
        Prompt {
            answer: Answer::Number {
                misconceptions: Vec::new(),
                measure,
                unit: "s".into(),
                expected: Some(expected),
                tolerance: crate::deck::Tolerance::Rel(0.02),
                formula: None,
                slips: Vec::new(),
            },
            ..choice_prompt("x", &[])
        }
    }

    #[test]
    fn a_system_answer_that_changes_in_the_longer_run_holds_only_because_the_run_ends() {
        let max_x = Measure::parse("max(x)").unwrap();
        let p = Prompt {
            answer: Answer::Choice {
                expected: Some("bounded".into()),
                choices: [("bounded", Cmp::Lt), ("grows", Cmp::Ge)]
                    .map(|(id, op)| Choice {
                        misconception: None,
                        id: id.into(),
                        label: text(id),
                        when: Condition::compare(max_x, op, 6.0),
                    })
                    .to_vec(),
            },
            ..choice_prompt("x", &[])
        };
        let problem = audit_run(&p, &system_run(10.0, &[(max_x, 3.98)], &[(max_x, 7.05)])).unwrap();
        assert_eq!(problem.target, Target::Expected);
        assert_eq!(
            problem.message,
            "expected `bounded` holds only because this 10 s run ends early: a run of 15 s measures max(x) = 7.05, where `bounded` does not hold: ask about what every run shows, or make the run longer and change the answer"
        );
        // The same in both runs: right.
        assert_eq!(
            audit_run(&p, &system_run(10.0, &[(max_x, 3.98)], &[(max_x, 4.1)])),
            None
        );

        // A number: outside its tolerance in the longer run.
        let fin = Measure::parse("final(x)").unwrap();
        let p = number_prompt(fin, 2.0);
        let problem = audit_run(&p, &system_run(4.0, &[(fin, 2.01)], &[(fin, 3.0)])).unwrap();
        assert!(
            problem.message.starts_with(
                "expected final(x) = 2 s holds only because this 4 s run ends early: a run of 6 s measures 3"
            ),
            "{problem:?}"
        );
        assert_eq!(
            audit_run(&p, &system_run(4.0, &[(fin, 2.01)], &[(fin, 1.99)])),
            None
        );
        // Wrong on the run itself: said as such, not as the run's length.
        let problem = audit_run(&p, &system_run(4.0, &[(fin, 5.0)], &[(fin, 5.0)])).unwrap();
        assert_eq!(
            problem.message,
            "expected final(x) = 2 s, but this 4 s run measures 5.000 s: change `expected` to about 5.000 or widen `tolerance`"
        );
    }

    #[test]
    fn a_system_measure_the_run_cannot_make_says_why() {
        let period = Measure::parse("period(theta)").unwrap();
        let p = number_prompt(period, 4.894);
        let mut run = system_run(6.0, &[], &[(period, 4.894)]);
        run.missing.push((
            period,
            "period(theta): theta crosses the level halfway between its minimum and maximum upwards once over the run; a period needs two".into(),
        ));
        let problem = audit_run(&p, &run).unwrap();
        assert_eq!(
            problem.message,
            "expected period(theta) = 4.894 s, but this 6 s run cannot measure period(theta) (theta crosses the level halfway between its minimum and maximum upwards once over the run; a period needs two): make the run longer (two upward crossings at least) or ask about another measure"
        );
    }

    #[test]
    fn lists_read_as_prose() {
        let s = |v: &[&str]| list_and(&v.iter().map(|x| x.to_string()).collect::<Vec<_>>());
        assert_eq!(s(&[]), "");
        assert_eq!(s(&["1.49"]), "1.49");
        assert_eq!(s(&["1.49", "4.24", "7.00"]), "1.49, 4.24 and 7.00");
    }
}
