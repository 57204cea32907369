//! How close `flipcard optimize`'s fit gets to a synthetic learner's true
//! FSRS parameters, and the log loss of the defaults, the fit and the truth
//! on the answers the fit is judged on (time-series split).
//!
//!     python3 tests/golden/gen_synthetic_learner.py --cards 2000 \
//!         --new-per-day 20 --days 365 --truth truth.txt > big.csv
//!     cargo bench --bench synthetic_fit -- big.csv truth.txt
//!
//! Without arguments it runs on the small committed log
//! (`tests/golden/synthetic_learner.csv`) and its generator's parameters.

use chrono::{NaiveTime, Utc};
use flipcard::interop::import::read_reviews_csv;
use flipcard::sched::DayGrid;
use flipcard::sched::fit::{self, FitAnswer};
use std::collections::BTreeMap;

fn main() {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    let root = env!("CARGO_MANIFEST_DIR");
    let csv_path = args
        .first()
        .cloned()
        .unwrap_or_else(|| format!("{root}/tests/golden/synthetic_learner.csv"));
    let truth: Vec<f64> = match args.get(1) {
        Some(p) => std::fs::read_to_string(p)
            .expect("truth file")
            .lines()
            .map(|l| l.trim().parse().expect("a number"))
            .collect(),
        None => {
            // The generator's TRUE_PARAMETERS, read from its source.
            let src =
                std::fs::read_to_string(format!("{root}/tests/golden/gen_synthetic_learner.py"))
                    .expect("generator");
            let start = src.find("TRUE_PARAMETERS = [").expect("TRUE_PARAMETERS") + 19;
            let end = start + src[start..].find(']').expect("]");
            src[start..end]
                .split(',')
                .filter(|s| !s.trim().is_empty())
                .map(|s| s.trim().parse().expect("a number"))
                .collect()
        }
    };
    assert_eq!(truth.len(), 21, "21 true parameters");
    let text = std::fs::read_to_string(&csv_path).expect("review log CSV");
    // The log is synthetic and may run ahead of this clock: any time the
    // app accepts.
    let rows = read_reviews_csv(&text, flipcard::sched::clock::latest())
        .unwrap_or_else(|e| panic!("{csv_path}: {e:?}"));
    let grid = DayGrid::new(Utc, NaiveTime::from_hms_opt(4, 0, 0).expect("04:00"));
    let mut by_card: BTreeMap<String, Vec<FitAnswer>> = BTreeMap::new();
    for r in &rows {
        by_card
            .entry(r.key.card.clone())
            .or_default()
            .push(FitAnswer {
                at: r.reviewed_at,
                day: grid.day_of(r.reviewed_at),
                rating: r.rating,
            });
    }
    let mut histories: Vec<Vec<FitAnswer>> = by_card.into_values().collect();
    for h in &mut histories {
        h.sort_by_key(|a| a.at);
    }
    let set = fit::training_set(&histories);
    let started = std::time::Instant::now();
    let fitted = fit::fit(&set).expect("fit");
    let took = started.elapsed();
    let truth32: Vec<f32> = truth.iter().map(|x| *x as f32).collect();
    let true_eval = fit::evaluate_held_out(&set, &truth32).expect("truth evaluates");
    println!(
        "{csv_path}: {} reviews, {} cards, {} predicted; fit and evaluation took {:.1} s",
        set.reviews,
        set.cards,
        set.items.len(),
        took.as_secs_f64()
    );
    println!("{:<8} {:>9} {:>9}", "", "log loss", "RMSE");
    for (name, e) in [
        ("default", fitted.default),
        ("fitted", fitted.fitted),
        ("true", true_eval),
    ] {
        println!("{name:<8} {:>9.4} {:>9.4}", e.log_loss, e.rmse_bins);
    }
    println!("{:<4} {:>9} {:>9} {:>9}", "w", "true", "fitted", "default");
    let defaults = flipcard::sched::scheduler::default_parameters();
    for i in 0..21 {
        println!(
            "w{i:<3} {:>9.4} {:>9.4} {:>9.4}",
            truth[i], fitted.parameters[i], defaults[i]
        );
    }
}
