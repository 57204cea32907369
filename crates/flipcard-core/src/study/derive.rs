//! A derivation studied step by step (issue 24 §5): which steps are faded
//! at a review (Renkl's backward fading), the learner's record with the
//! item that decides it, and the verdict on a faded step's ask.
//!
//! Renkl's fading: a worked example first (every step shown with its
//! reason), then completion problems that leave more and more steps to
//! the learner, the last step first ("backward fading": the learner fills
//! in the end of a chain whose beginning is still worked). Each successful
//! review fades one more step; each lapse brings one back.

use crate::deck::{Ask, AskKind, Step};
use crate::sched::{ItemKey, Rating, ReviewKind};
use crate::store::StoreError;

use super::Study;

/// What the item's log says for fading: its successful answers (rated
/// Hard, Good or Easy) and its failed ones (Again), undone and cram
/// answers left out.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Progress {
    pub successes: u32,
    pub lapses: u32,
}

/// Which steps are faded (hidden for the learner to supply), in order:
/// `asks[i]` says whether step `i` has an `ask`.
///
/// The steps that may fade are those with an ask, or every step when
/// none has one. The number faded is `successes − lapses` (never below
/// zero), at most the steps that may fade, taken from the end backwards.
/// So the first time (no success) nothing is faded, more successes never
/// fade fewer steps, a lapse fades one fewer, and no more steps are faded
/// than exist.
pub fn faded_steps(asks: &[bool], progress: Progress) -> Vec<bool> {
    let all = !asks.iter().any(|a| *a);
    let level = progress.successes.saturating_sub(progress.lapses) as usize;
    let mut out = vec![false; asks.len()];
    let mut left = level;
    for (i, ask) in asks.iter().enumerate().rev() {
        if left == 0 {
            break;
        }
        if all || *ask {
            out[i] = true;
            left -= 1;
        }
    }
    out
}

/// [`faded_steps`] for the steps of a derivation.
pub fn faded(steps: &[Step], progress: Progress) -> Vec<bool> {
    let asks: Vec<bool> = steps.iter().map(|s| s.ask.is_some()).collect();
    faded_steps(&asks, progress)
}

/// The learner's answer to a faded step's ask.
#[derive(Debug, Clone, PartialEq)]
pub enum StepAnswer<'a> {
    /// Thought about it, then asked to see (a reveal ask, or a step
    /// without an ask).
    Revealed,
    /// The id of the choice picked.
    Chose(&'a str),
    /// A typed formula.
    Typed(&'a str),
}

/// The verdict on one faded step.
#[derive(Debug, Clone, PartialEq)]
pub enum StepVerdict {
    /// Nothing to check (think, then reveal).
    Seen,
    Right,
    /// Wrong: for a formula, the equivalence check's verdict says how.
    Wrong(Option<flipcard_sim::system::equiv::Verdict>),
}

impl StepVerdict {
    pub fn is_wrong(&self) -> bool {
        matches!(self, StepVerdict::Wrong(_))
    }
}

/// Checks `answer` against the step's `ask`: a choice by its id, a
/// formula by equivalence over its domain (as a formula card is graded).
/// An answer of another kind than the ask is wrong.
pub fn check(ask: Option<&Ask>, answer: &StepAnswer<'_>) -> StepVerdict {
    match (ask.map(|a| &a.kind), answer) {
        (None | Some(AskKind::Reveal), _) => StepVerdict::Seen,
        (Some(AskKind::Choice { answer: right, .. }), StepAnswer::Chose(id)) => {
            if id == right {
                StepVerdict::Right
            } else {
                StepVerdict::Wrong(None)
            }
        }
        (Some(AskKind::Formula(key)), StepAnswer::Typed(text)) => {
            let v = flipcard_sim::system::equiv::grade(key, text);
            if v.is_right() {
                StepVerdict::Right
            } else {
                StepVerdict::Wrong(Some(v))
            }
        }
        _ => StepVerdict::Wrong(None),
    }
}

/// The rating a walk through a derivation suggests: Good when every
/// faded step was right (or only seen), Hard when one was wrong, Again
/// when more were.
pub fn suggested(verdicts: &[StepVerdict]) -> Rating {
    match verdicts.iter().filter(|v| v.is_wrong()).count() {
        0 => Rating::Good,
        1 => Rating::Hard,
        _ => Rating::Again,
    }
}

impl Study {
    /// The fading record of `key`: its live answers that count for
    /// scheduling (cram answers and undone ones left out).
    pub fn progress(&self, key: &ItemKey) -> Result<Progress, StoreError> {
        let mut p = Progress::default();
        for r in self.store.history(key)? {
            if r.undone || r.record.kind == ReviewKind::Cram {
                continue;
            }
            if r.record.rating == Rating::Again {
                p.lapses += 1;
            } else {
                p.successes += 1;
            }
        }
        Ok(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn p(successes: u32, lapses: u32) -> Progress {
        Progress { successes, lapses }
    }

    #[test]
    fn the_first_time_is_a_worked_example_then_steps_fade_from_the_end() {
        let asks = [false, true, true, false, true];
        assert_eq!(faded_steps(&asks, p(0, 0)), [false; 5]);
        assert_eq!(
            faded_steps(&asks, p(1, 0)),
            [false, false, false, false, true]
        );
        assert_eq!(
            faded_steps(&asks, p(2, 0)),
            [false, false, true, false, true]
        );
        // Every step with an ask faded; the others stay worked.
        assert_eq!(
            faded_steps(&asks, p(9, 0)),
            [false, true, true, false, true]
        );
        // A lapse brings one back.
        assert_eq!(
            faded_steps(&asks, p(2, 1)),
            [false, false, false, false, true]
        );
        // Without any ask, every step may fade.
        assert_eq!(faded_steps(&[false; 3], p(2, 0)), [false, true, true]);
        assert!(faded_steps(&[], p(3, 0)).is_empty());
    }

    #[test]
    fn asks_are_checked_by_kind() {
        let choice = Ask {
            question: None,
            kind: AskKind::Choice {
                choices: Vec::new(),
                answer: "minus".into(),
            },
        };
        assert_eq!(
            check(Some(&choice), &StepAnswer::Chose("minus")),
            StepVerdict::Right
        );
        assert!(check(Some(&choice), &StepAnswer::Chose("plus")).is_wrong());
        assert!(check(Some(&choice), &StepAnswer::Revealed).is_wrong());
        let formula = Ask {
            question: None,
            kind: AskKind::Formula(crate::deck::FormulaKey {
                expected: "(I_2 - I_3) omega_2 omega_3 / I_1".into(),
                vars: ["I1", "I2", "I3", "omega2", "omega3"]
                    .into_iter()
                    .map(|n| flipcard_sim::system::equiv::Domain {
                        name: n.into(),
                        lo: 1.0,
                        hi: 3.0,
                    })
                    .collect(),
            }),
        };
        assert_eq!(
            check(Some(&formula), &StepAnswer::Typed("(I2-I3)*ω₂ω₃/I₁")),
            StepVerdict::Right
        );
        match check(Some(&formula), &StepAnswer::Typed("(I3-I2) w2 w3/I1")) {
            StepVerdict::Wrong(Some(v)) => assert!(!v.is_right()),
            other => panic!("{other:?}"),
        }
        assert_eq!(check(None, &StepAnswer::Revealed), StepVerdict::Seen);
        assert_eq!(
            suggested(&[StepVerdict::Seen, StepVerdict::Right]),
            Rating::Good
        );
        assert_eq!(suggested(&[StepVerdict::Wrong(None)]), Rating::Hard);
        assert_eq!(
            suggested(&[StepVerdict::Wrong(None), StepVerdict::Wrong(None)]),
            Rating::Again
        );
    }

    proptest! {
        #[test]
        fn fading_is_monotone_bounded_and_starts_worked(
            asks in proptest::collection::vec(any::<bool>(), 0..50),
            successes in 0u32..80,
            lapses in 0u32..20,
        ) {
            let f = faded_steps(&asks, p(successes, lapses));
            prop_assert_eq!(f.len(), asks.len());
            let n = f.iter().filter(|x| **x).count();
            // Never more than may fade, nor more than the level.
            let fadeable = if asks.iter().any(|a| *a) {
                asks.iter().filter(|a| **a).count()
            } else {
                asks.len()
            };
            prop_assert_eq!(n, fadeable.min(successes.saturating_sub(lapses) as usize));
            // A step with no ask fades only when no step has one.
            if asks.iter().any(|a| *a) {
                for (faded, ask) in f.iter().zip(&asks) {
                    prop_assert!(!faded || *ask);
                }
            }
            // No success: a worked example.
            prop_assert!(faded_steps(&asks, p(0, lapses)).iter().all(|x| !x));
            // One more success fades every step faded now, and maybe one more.
            let more = faded_steps(&asks, p(successes + 1, lapses));
            for (a, b) in f.iter().zip(&more) {
                prop_assert!(!a || *b);
            }
            // One more lapse never fades more.
            let less = faded_steps(&asks, p(successes, lapses + 1));
            for (a, b) in f.iter().zip(&less) {
                prop_assert!(!b || *a);
            }
            // Backward: the faded steps are the last fadeable ones.
            if let Some(first) = f.iter().position(|x| *x) {
                for (i, ask) in asks.iter().enumerate().skip(first) {
                    let may = *ask || !asks.iter().any(|a| *a);
                    prop_assert_eq!(f[i], may);
                }
            }
        }
    }
}
