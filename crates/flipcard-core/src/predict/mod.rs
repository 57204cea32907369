//! Predict, then check: a learner's committed answer judged against what a
//! scene's run measured. The measuring is the simulator's; the grading is
//! here, between the deck's prompt and the measurements.

pub mod audit;
pub mod variant;
/// How a typed number and its unit are read (in `flipcard-text`, below
/// the deck, which declares units).
pub use flipcard_text::units as typed;

use crate::deck::{Answer, Measure, Prompt};
use flipcard_sim::scene::measure::{Evidence, Measurements, Reading};

/// What the learner committed to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Prediction {
    /// Index into the prompt's choices.
    Choice(usize),
    Number(f64),
    /// A typed formula (the text and its verdict are the `Verdict`'s
    /// `formula`, see [`formula`]).
    Formula,
}

impl Prediction {
    /// The answer the deck's author gives (`expected`), as a prediction; `None`
    /// when the expected choice id names no choice.
    pub fn expected(prompt: &Prompt) -> Option<Prediction> {
        match &prompt.answer {
            Answer::Choice { choices, expected } => choices
                .iter()
                .position(|c| Some(&c.id) == expected.as_ref())
                .map(Prediction::Choice),
            Answer::Number { expected, .. } => expected.map(Prediction::Number),
            // A typed formula is graded by `formula`, never by a run.
            Answer::Formula(_) => None,
        }
    }
}

/// What the measurements say about a prediction.
#[derive(Debug, Clone, PartialEq)]
pub struct Verdict {
    pub correct: bool,
    /// Choice prompts: the choices whose condition holds (exactly one for a
    /// well-posed prompt), in the prompt's order.
    pub holding: Vec<usize>,
    /// Choice prompts: the choice the measurements make right (the first
    /// that holds).
    pub right_choice: Option<usize>,
    /// The readings the prompt depends on (its conditions' measures, or the
    /// number's measure), with their formula values.
    pub readings: Vec<Reading>,
    /// What the run showed besides the numbers (its length, the flip
    /// times), so the verdict says no more than that.
    pub evidence: Evidence,
    /// A wrong number that is a known slip of the prompt: its index in the
    /// answer's `slips` and its value on this run (the first slip whose
    /// value is within the prompt's tolerance of the learner's number).
    pub slip: Option<(usize, f64)>,
    /// A wrong answer that stands for one of the deck's misconceptions:
    /// its id (a wrong choice's `misconception`; for a number, the matched
    /// slip's `misconception`, else the first of the answer's
    /// `misconceptions` ranges that holds the number). Never on a right
    /// answer.
    pub misconception: Option<String>,
    /// Formula prompts: the formula typed and its verdict (no measurement
    /// decides it, see [`formula`]).
    pub formula: Option<Box<(String, flipcard_sim::system::equiv::Verdict)>>,
}

/// Judges `prediction` against the measurements of the prompt's scene: a
/// choice is right when its `when` condition holds (a condition on a
/// measure the run could not make never holds); a number when it is within
/// the prompt's tolerance of the measured value.
pub fn verdict(prompt: &Prompt, m: &Measurements, prediction: Prediction) -> Verdict {
    match &prompt.answer {
        Answer::Choice { choices, .. } => {
            let holding: Vec<usize> = choices
                .iter()
                .enumerate()
                .filter(|(_, c)| c.when.holds_on(|x| m.get(x)).unwrap_or(false))
                .map(|(i, _)| i)
                .collect();
            let mut measures: Vec<Measure> =
                choices.iter().flat_map(|c| c.when.measures()).collect();
            measures.sort();
            measures.dedup();
            let correct = matches!(prediction, Prediction::Choice(i) if holding.contains(&i));
            let misconception = match prediction {
                Prediction::Choice(i) if !correct => {
                    choices.get(i).and_then(|c| c.misconception.clone())
                }
                _ => None,
            };
            Verdict {
                correct,
                right_choice: holding.first().copied(),
                holding,
                readings: measures
                    .into_iter()
                    .filter_map(|x| m.reading(x).copied())
                    .collect(),
                evidence: m.evidence().clone(),
                slip: None,
                misconception,
                formula: None,
            }
        }
        Answer::Number {
            measure,
            tolerance,
            slips,
            misconceptions,
            ..
        } => {
            let reading = m.reading(*measure).copied();
            let correct = match (prediction, reading) {
                (Prediction::Number(given), Some(r)) => tolerance.accepts(given, r.value),
                _ => false,
            };
            // A wrong number that a known slip gives, taken on this run.
            let slip = match (correct, prediction, reading) {
                (false, Prediction::Number(given), Some(r)) => {
                    slips.iter().enumerate().find_map(|(i, s)| {
                        let w = s.value_for(r.value)?;
                        tolerance.accepts(given, w).then_some((i, w))
                    })
                }
                _ => None,
            };
            let misconception = match prediction {
                Prediction::Number(given) if !correct => slip
                    .and_then(|(i, _)| slips.get(i)?.misconception.clone())
                    .or_else(|| {
                        misconceptions
                            .iter()
                            .find(|r| r.contains(given))
                            .map(|r| r.id.clone())
                    }),
                _ => None,
            };
            Verdict {
                correct,
                holding: Vec::new(),
                right_choice: None,
                readings: reading.into_iter().collect(),
                evidence: m.evidence().clone(),
                slip,
                misconception,
                formula: None,
            }
        }
        // A formula is graded by [`formula`], not by measurements: no
        // prediction of a run is one.
        Answer::Formula(_) => Verdict {
            correct: false,
            holding: Vec::new(),
            right_choice: None,
            readings: Vec::new(),
            evidence: m.evidence().clone(),
            slip: None,
            misconception: None,
            formula: None,
        },
    }
}

/// The verdict on a formula prompt's typed prediction: right when it
/// equals the key's `expected` over its domain (with the slip it makes
/// when it does not), decided without a run. `None` when the prompt's
/// answer is no formula.
pub fn formula(prompt: &Prompt, typed: &str) -> Option<Verdict> {
    let Answer::Formula(key) = &prompt.answer else {
        return None;
    };
    let v = flipcard_sim::system::equiv::grade(key, typed);
    Some(Verdict {
        correct: v.is_right(),
        holding: Vec::new(),
        right_choice: None,
        readings: Vec::new(),
        evidence: Measurements::from_readings(Vec::new()).evidence().clone(),
        slip: None,
        misconception: None,
        formula: Some(Box::new((typed.to_string(), v))),
    })
}
