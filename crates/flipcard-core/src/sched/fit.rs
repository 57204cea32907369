//! Fitting FSRS-6 to one learner's reviews with the `fsrs` crate, and
//! judging the fit on reviews it was not trained on.
//!
//! The training set is built as the crate (and Anki) builds it: for each
//! item, its answers in time order; one training item per answer after the
//! first, holding the whole history up to that answer, with `delta_t` the
//! number of study days since the previous answer. Same-day answers stay in
//! the history with `delta_t = 0` (the short-term model learns from them),
//! but only answers on a later day are predicted, since the forgetting
//! curve says nothing about minutes.

use chrono::{DateTime, NaiveDate, Utc};
use fsrs::{
    ComputeParametersInput, FSRS, FSRSItem, FSRSReview, ModelEvaluation,
    evaluate_with_time_series_splits,
};

use super::config::PARAMETER_BOUNDS;
use super::types::Rating;

/// The crate trains the full model only from this many training items;
/// with fewer it returns the defaults or fits the first four only.
pub(crate) const MIN_ITEMS: usize = 64;

/// Folds of the time-series split (the crate's own choice).
const SPLITS: usize = 5;

/// One answer of an item as the fit sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitAnswer {
    pub at: DateTime<Utc>,
    /// The study day it belongs to (the day start and time zone applied).
    pub day: NaiveDate,
    pub rating: Rating,
}

/// The training set: items in the time order of the answer they predict,
/// each with the index of the history it comes from.
#[derive(Debug, Clone, Default)]
pub struct TrainingSet {
    pub items: Vec<FSRSItem>,
    pub card_ids: Vec<i64>,
    /// Answers of the histories that gave at least one item.
    pub reviews: usize,
    /// Histories that gave at least one item.
    pub cards: usize,
}

/// Builds the training set from each item's answers (each history in time
/// order; cram and undone answers already left out).
pub fn training_set(histories: &[Vec<FitAnswer>]) -> TrainingSet {
    let mut keyed: Vec<(DateTime<Utc>, i64, FSRSItem)> = Vec::new();
    let mut set = TrainingSet::default();
    for (card, answers) in histories.iter().enumerate() {
        let mut reviews: Vec<FSRSReview> = Vec::with_capacity(answers.len());
        let mut made = 0;
        for (i, a) in answers.iter().enumerate() {
            let delta_t = if i == 0 {
                0
            } else {
                (a.day - answers[i - 1].day).num_days().max(0) as u32
            };
            reviews.push(FSRSReview {
                rating: a.rating as u32,
                delta_t,
            });
            if i > 0 && delta_t > 0 {
                keyed.push((
                    a.at,
                    card as i64,
                    FSRSItem {
                        reviews: reviews.clone(),
                    },
                ));
                made += 1;
            }
        }
        if made > 0 {
            set.cards += 1;
            set.reviews += answers.len();
        }
    }
    keyed.sort_by_key(|(at, card, _)| (*at, *card));
    for (_, card, item) in keyed {
        set.card_ids.push(card);
        set.items.push(item);
    }
    set
}

/// How well a set of parameters predicts the answers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Evaluation {
    pub log_loss: f64,
    pub rmse_bins: f64,
}

impl From<ModelEvaluation> for Evaluation {
    fn from(e: ModelEvaluation) -> Self {
        Evaluation {
            log_loss: f64::from(e.log_loss),
            rmse_bins: f64::from(e.rmse_bins),
        }
    }
}

/// The outcome of a fit.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// The fitted parameters as the shortest decimals of the crate's `f32`s.
    pub parameters: [f64; 21],
    /// The default parameters on the answers the fit is judged on.
    pub default: Evaluation,
    /// The fitted model on the same answers, each fold trained only on the
    /// answers before it (the crate's time-series split).
    pub fitted: Evaluation,
}

#[derive(Debug, thiserror::Error)]
pub enum FitError {
    #[error("not enough reviews to fit: {have} of the {need} needed")]
    TooFew { have: usize, need: usize },
    #[error("the FSRS optimizer failed: {0}")]
    Fsrs(String),
}

fn fsrs_err(e: fsrs::FSRSError) -> FitError {
    FitError::Fsrs(format!("{e:?}"))
}

/// The shortest decimal that reads back as the crate's `f32`: the number
/// the crate means, as the scheduler and py-fsrs read it.
pub fn widen(p: f32) -> f64 {
    p.to_string().parse().unwrap_or(f64::from(p))
}

/// Fits parameters to `set` and evaluates them against the defaults.
pub fn fit(set: &TrainingSet) -> Result<Fit, FitError> {
    if set.items.len() < MIN_ITEMS {
        return Err(FitError::TooFew {
            have: set.items.len(),
            need: MIN_ITEMS,
        });
    }
    let input = || ComputeParametersInput {
        train_set: set.items.clone(),
        card_ids: Some(set.card_ids.clone()),
        progress: None,
        enable_short_term: true,
        num_relearning_steps: None,
        training_config: None,
    };
    let fitted = fsrs::compute_parameters(input()).map_err(fsrs_err)?;
    let mut parameters = [0.0; 21];
    if fitted.len() != 21 || fitted.iter().any(|p| !p.is_finite()) {
        return Err(FitError::Fsrs(format!(
            "{} parameters, not 21 finite ones",
            fitted.len()
        )));
    }
    for (slot, p) in parameters.iter_mut().zip(&fitted) {
        *slot = widen(*p);
    }
    let fitted_eval = evaluate_with_time_series_splits(input(), |_| true).map_err(fsrs_err)?;
    let default_eval = evaluate_held_out(set, &fsrs::DEFAULT_PARAMETERS)?;
    Ok(Fit {
        parameters,
        default: default_eval,
        fitted: fitted_eval.into(),
    })
}

/// Fixed parameters judged on the answers a fit is judged on: every fold's
/// test part, i.e. all but the first of the SPLITS + 1 segments.
pub fn evaluate_held_out(set: &TrainingSet, parameters: &[f32]) -> Result<Evaluation, FitError> {
    let segment = set.items.len() / (SPLITS + 1);
    let tested = set.items[segment..].to_vec();
    let model = FSRS::new(parameters).map_err(fsrs_err)?;
    Ok(model.evaluate(tested, |_| true).map_err(fsrs_err)?.into())
}

/// What each FSRS-6 parameter stands for, to name one in a message.
pub const PARAMETER_MEANINGS: [&str; 21] = [
    "initial stability after Again",
    "initial stability after Hard",
    "initial stability after Good",
    "initial stability after Easy",
    "initial difficulty",
    "how the first rating moves the initial difficulty",
    "how much a rating changes difficulty",
    "pull of difficulty back to its start",
    "growth of stability after a recall",
    "how stability slows its own growth",
    "how forgetting more boosts the growth",
    "stability after a lapse",
    "effect of difficulty on stability after a lapse",
    "effect of stability on stability after a lapse",
    "effect of recall probability on stability after a lapse",
    "Hard's penalty on stability growth",
    "Easy's bonus on stability growth",
    "same-day stability change",
    "same-day stability offset",
    "how stability damps same-day changes",
    "decay of the forgetting curve",
];

/// A fitted parameter at one end of the range the fit may put it in
/// ([`PARAMETER_BOUNDS`]): the data pushed it as far as it may go.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pinned {
    pub index: usize,
    pub value: f64,
    /// `true`: at the upper bound; `false`: at the lower.
    pub upper: bool,
    pub bounds: (f64, f64),
}

/// The parameters of `w` that sit at a bound of [`PARAMETER_BOUNDS`]
/// (within the `f32` the fit computes in).
pub fn pinned(w: &[f64; 21]) -> Vec<Pinned> {
    let at = |x: f64, b: f64| (x - b).abs() <= 1e-6 * b.abs().max(1e-3);
    w.iter()
        .zip(PARAMETER_BOUNDS)
        .enumerate()
        .filter_map(|(index, (&value, (lo, hi)))| {
            let upper = at(value, hi);
            (upper || at(value, lo)).then_some(Pinned {
                index,
                value,
                upper,
                bounds: (lo, hi),
            })
        })
        .collect()
}

/// Whether fitted parameters should replace the current ones: only when
/// they predict the held-out answers better, by log loss (Anki keeps its
/// current parameters when their log loss is not above the fit's).
pub fn improves(fitted: &Evaluation, current: &Evaluation) -> bool {
    fitted.log_loss < current.log_loss
}

#[cfg(test)]
mod tests {
    use super::*;

    fn answer(day: u32, hour: u32, rating: Rating) -> FitAnswer {
        let date = NaiveDate::from_ymd_opt(2026, 1, 1).unwrap() + chrono::Days::new(day.into());
        FitAnswer {
            at: date.and_hms_opt(hour, 0, 0).unwrap().and_utc(),
            day: date,
            rating,
        }
    }

    #[test]
    fn items_hold_the_history_and_predict_later_days_only() {
        let histories = vec![
            vec![
                answer(0, 9, Rating::Good),
                answer(0, 10, Rating::Good),
                answer(3, 9, Rating::Again),
                answer(3, 10, Rating::Good),
                answer(10, 8, Rating::Hard),
            ],
            vec![answer(1, 9, Rating::Easy)],
            vec![answer(1, 9, Rating::Good), answer(2, 9, Rating::Good)],
        ];
        let set = training_set(&histories);
        assert_eq!((set.cards, set.reviews), (2, 7));
        let shapes: Vec<Vec<(u32, u32)>> = set
            .items
            .iter()
            .map(|i| i.reviews.iter().map(|r| (r.rating, r.delta_t)).collect())
            .collect();
        assert_eq!(
            shapes,
            vec![
                vec![(3, 0), (3, 1)],
                vec![(3, 0), (3, 0), (1, 3)],
                vec![(3, 0), (3, 0), (1, 3), (3, 0), (2, 7)],
            ]
        );
        assert_eq!(set.card_ids, [2, 0, 0]);
    }

    #[test]
    fn too_few_items_fit_nothing() {
        let set = training_set(&[vec![answer(0, 9, Rating::Good), answer(2, 9, Rating::Good)]]);
        assert!(matches!(
            fit(&set),
            Err(FitError::TooFew {
                have: 1,
                need: MIN_ITEMS
            })
        ));
    }

    #[test]
    fn pinned_parameters_are_found_at_either_bound() {
        let mut w = crate::sched::scheduler::default_parameters();
        // FSRS-6's own defaults hold w7 at its lower bound.
        let at = |w: &[f64; 21]| -> Vec<usize> { pinned(w).iter().map(|p| p.index).collect() };
        assert_eq!(at(&w), [7]);
        w[16] = 6.0;
        w[14] = f64::from(0.0f32);
        let p = pinned(&w);
        let found: Vec<(usize, bool)> = p.iter().map(|p| (p.index, p.upper)).collect();
        assert_eq!(found, [(7, false), (14, false), (16, true)]);
        w[7] = 0.0011;
        assert!(pinned(&w).iter().all(|p| p.index != 7));
    }

    #[test]
    fn only_a_lower_log_loss_replaces_the_current_parameters() {
        let e = |log_loss, rmse_bins| Evaluation {
            log_loss,
            rmse_bins,
        };
        assert!(improves(&e(0.30, 0.05), &e(0.31, 0.04)));
        assert!(!improves(&e(0.31, 0.04), &e(0.31, 0.05)));
        assert!(!improves(&e(0.32, 0.01), &e(0.31, 0.05)));
    }
}
