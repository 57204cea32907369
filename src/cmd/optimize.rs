//! `flipcard optimize [--deck ID] [--apply [--force]] [--format json]`: fits
//! FSRS-6 to the learner's own reviews and compares the fit with the
//! defaults and the parameters in use on answers it was not trained on.
//! `--apply` keeps the parameters in use when the fit predicts those
//! answers no better (by log loss, as Anki keeps them), unless `--force`;
//! a fitted parameter pinned at a bound of its range is named.

use std::process::ExitCode;

use serde::Serialize;

use crate::cmd::args::{Cli, OptimizeArgs, ReportFormat};
use crate::cmd::common::open_store_read_only;
use crate::cmd::paths;
use crate::sched::Config;
use crate::sched::DayGrid;
use crate::sched::fit::{self, Evaluation, FitAnswer, FitError};
use crate::text::{num, plural};

#[derive(Serialize)]
struct Scores {
    log_loss: f64,
    rmse_bins: f64,
}

impl From<Evaluation> for Scores {
    fn from(e: Evaluation) -> Self {
        Scores {
            log_loss: e.log_loss,
            rmse_bins: e.rmse_bins,
        }
    }
}

/// The JSON report. The first six fields are the contract.
#[derive(Serialize)]
struct Report {
    reviews: usize,
    cards: usize,
    default: Option<Scores>,
    fitted: Option<Scores>,
    parameters: Option<Vec<f64>>,
    applied: bool,
    deck: Option<String>,
    /// With `--deck` and `--apply`: the preset the parameters went to.
    preset: Option<String>,
    /// Answers predicted (one per review on a later day than the one before).
    items: usize,
    /// Reviews still needed before a fit, when there are too few.
    needed: Option<usize>,
    /// The parameters in use (the config's, else the defaults) on the
    /// answers the fit is judged on.
    current: Option<Scores>,
    /// `--apply` kept the parameters in use: the fit predicts no better.
    kept_current: bool,
    /// Fitted parameters at a bound of the range the fit may put them in.
    pinned: Vec<PinnedJson>,
}

#[derive(Serialize)]
struct PinnedJson {
    index: usize,
    name: &'static str,
    value: f64,
    /// `lower` or `upper`.
    bound: &'static str,
}

pub fn run(cli: &Cli, args: &OptimizeArgs) -> anyhow::Result<ExitCode> {
    let config_path = paths::config_file(cli.config.clone());
    let config = Config::load(config_path.as_deref())?;
    let store = open_store_read_only(cli)?;
    let grid = DayGrid::new(chrono::Local, config.day_starts_at);
    let by_item = store.answers_by_item(args.deck.as_deref())?;
    if let Some(id) = &args.deck
        && by_item.is_empty()
    {
        anyhow::bail!("no reviews of deck `{id}` in the log to fit to");
    }
    let histories: Vec<Vec<FitAnswer>> = by_item
        .iter()
        .map(|(_, answers)| {
            answers
                .iter()
                .map(|(at, rating)| FitAnswer {
                    at: *at,
                    day: grid.day_of(*at),
                    rating: *rating,
                })
                .collect()
        })
        .collect();
    let set = fit::training_set(&histories);
    let mut report = Report {
        reviews: set.reviews,
        cards: set.cards,
        default: None,
        fitted: None,
        parameters: None,
        applied: false,
        deck: args.deck.clone(),
        preset: None,
        items: set.items.len(),
        needed: None,
        current: None,
        kept_current: false,
        pinned: Vec::new(),
    };
    let result = match fit::fit(&set) {
        Ok(f) => f,
        Err(FitError::TooFew { have, need }) => {
            report.needed = Some(need - have);
            match args.format {
                ReportFormat::Json => print_json(&report)?,
                ReportFormat::Text => crate::outln!(
                    "not enough reviews to fit FSRS: {} can be predicted from an earlier one, and the fit needs {need}; {} more (answered on a later day than the card's previous answer) are needed. Nothing changed.",
                    plural(have, "review", "reviews"),
                    need - have
                )?,
            }
            return Ok(ExitCode::SUCCESS);
        }
        Err(e) => return Err(e.into()),
    };
    report.default = Some(result.default.into());
    report.fitted = Some(result.fitted.into());
    report.parameters = Some(result.parameters.to_vec());
    // The parameters in use for these reviews: the deck's preset's when
    // one deck is fitted, else the top level's.
    let in_use = match &args.deck {
        Some(id) => config.for_deck(id).fsrs_parameters,
        None => config.fsrs_parameters,
    };
    let current = match in_use {
        Some(w) => fit::evaluate_held_out(&set, &w.map(|x| x as f32))?,
        None => result.default,
    };
    report.current = Some(current.into());
    let pinned = fit::pinned(&result.parameters);
    report.pinned = pinned
        .iter()
        .map(|p| PinnedJson {
            index: p.index,
            name: fit::PARAMETER_MEANINGS[p.index],
            value: p.value,
            bound: if p.upper { "upper" } else { "lower" },
        })
        .collect();
    let improves = fit::improves(&result.fitted, &current);
    report.kept_current = args.apply && !improves && !args.force;
    if args.apply && !report.kept_current {
        let Some(path) = &config_path else {
            anyhow::bail!("no config file location known; pass --config FILE to apply");
        };
        let mut updated = config.clone();
        match &args.deck {
            // One deck's reviews: its preset's parameters (a deck without
            // one gets a preset of its own, named after it, holding only
            // the parameters: the rest stays the top level's).
            Some(id) => {
                let (name, created) = match config.preset_of(id) {
                    Some(name) => (name.to_string(), false),
                    None => (preset_name_for(&config, id), true),
                };
                updated
                    .presets
                    .entry(name.clone())
                    .or_default()
                    .fsrs_parameters = Some(result.parameters);
                updated.save_preset_key(path, &name, "fsrs_parameters")?;
                if created {
                    updated.decks.entry(id.clone()).or_default().preset = Some(name.clone());
                    updated.save_deck_preset(path, id)?;
                }
                report.preset = Some(name);
            }
            None => {
                updated.fsrs_parameters = Some(result.parameters);
                updated.fsrs_fitted_at = Some(crate::cmd::clock::now()?.fixed_offset());
                updated.save_key(path, "fsrs_parameters")?;
                updated.save_key(path, "fsrs_fitted_at")?;
            }
        }
        report.applied = true;
    }
    match args.format {
        ReportFormat::Json => print_json(&report)?,
        ReportFormat::Text => {
            crate::out!("{}", render(&report, &result, &current, &pinned, &config))?;
            if report.kept_current {
                crate::outln!(
                    "kept the current parameters: the fit predicts the held-out reviews no better (log loss {} against {}); `flipcard optimize --apply --force` writes it anyway",
                    num::rounded(result.fitted.log_loss, 4),
                    num::rounded(current.log_loss, 4)
                )?;
            } else if report.applied
                && let (Some(path), Some(name), Some(id)) =
                    (&config_path, &report.preset, &args.deck)
            {
                let new = if config.preset_of(id).is_none() {
                    format!(
                        " (a new preset, now deck {id}'s: its other settings are the top level's)"
                    )
                } else {
                    String::new()
                };
                crate::outln!(
                    "applied: written to {} as fsrs_parameters of [preset.{name}]{new}; deck {id} and every deck using that preset are scheduled with them from now on",
                    path.display()
                )?;
            } else if report.applied
                && let Some(path) = &config_path
            {
                crate::outln!(
                    "applied: written to {} as fsrs_parameters; the scheduler uses them from now on",
                    path.display()
                )?;
            } else {
                crate::outln!(
                    "not applied: `flipcard optimize --apply` writes them to the config"
                )?;
            }
        }
    }
    if result.fitted.log_loss >= result.default.log_loss && !report.kept_current {
        crate::errln!(
            "flipcard: warning: the fitted parameters predict these reviews no better than the defaults"
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn print_json(report: &Report) -> anyhow::Result<()> {
    let mut out = crate::cmd::output::stdout();
    serde_json::to_writer(&mut out, report)?;
    use std::io::Write as _;
    writeln!(out)?;
    out.flush()?;
    Ok(())
}

fn render(
    r: &Report,
    f: &fit::Fit,
    current: &fit::Evaluation,
    pinned: &[fit::Pinned],
    config: &Config,
) -> String {
    let mut o = format!(
        "fitted FSRS-6 to {} of {} ({} predicted from an earlier one){}\n",
        plural(r.reviews, "review", "reviews"),
        plural(r.cards, "card", "cards"),
        r.items,
        r.deck
            .as_deref()
            .map(|d| format!(" in deck {d}"))
            .unwrap_or_default()
    );
    o.push_str("judged on reviews each fit did not see (time-series split):\n");
    o.push_str(&format!(
        "  {:<10} {:>10} {:>12}\n",
        "", "log loss", "RMSE (bins)"
    ));
    let mut rows = vec![("default", f.default)];
    if config.fsrs_parameters.is_some() {
        rows.push(("current", *current));
    }
    rows.push(("fitted", f.fitted));
    for (name, e) in rows {
        o.push_str(&format!(
            "  {:<10} {:>10} {:>12}\n",
            name,
            num::rounded(e.log_loss, 4),
            num::rounded(e.rmse_bins, 4)
        ));
    }
    let ps: Vec<String> = f.parameters.iter().map(|p| num::show(*p)).collect();
    o.push_str(&format!("parameters: {}\n", ps.join(", ")));
    for p in pinned {
        let (lo, hi) = p.bounds;
        o.push_str(&format!(
            "pinned: w{} ({}) = {} at the {} bound of {}–{}: the reviews push it as far as the fit allows\n",
            p.index,
            fit::PARAMETER_MEANINGS[p.index],
            num::show(p.value),
            if p.upper { "upper" } else { "lower" },
            num::show(lo),
            num::show(hi)
        ));
    }
    o
}

/// A name for a new preset of deck `id`: the id, or the id and a number
/// when a preset already has it.
fn preset_name_for(config: &Config, id: &str) -> String {
    let mut name = id.to_string();
    let mut n = 2;
    while config.presets.contains_key(&name) {
        name = format!("{id}-{n}");
        n += 1;
    }
    name
}
