//! `flipcard stats [--deck ID] [--json]`.

use std::io::Write;
use std::process::ExitCode;

use crate::cmd::args::{Cli, StatsArgs};
use crate::cmd::common::{load_decks, open_store_read_only};
use crate::cmd::paths;
use crate::interop::export;
use crate::sched::DayGrid;
use crate::sched::{Config, ItemKey, deck_items};
use crate::store::stats::{Ratio, Stats, StatsScope};
use crate::text::plural;

pub fn run(cli: &Cli, args: &StatsArgs) -> anyhow::Result<ExitCode> {
    let config = Config::load(paths::config_file(cli.config.clone()).as_deref())?;
    let store = open_store_read_only(cli)?;
    let loaded = load_decks(cli);
    if let Some(id) = &args.deck
        && !loaded.decks.iter().any(|d| &d.id == id)
        && store.last_studied(id)?.is_none()
    {
        let known: Vec<&str> = loaded.decks.iter().map(|d| d.id.as_str()).collect();
        anyhow::bail!(
            "no deck `{id}` among the decks loaded and no history for it; decks: {}",
            if known.is_empty() {
                "none".to_string()
            } else {
                known.join(", ")
            }
        );
    }
    let items: Vec<ItemKey> = loaded.decks.iter().flat_map(deck_items).collect();
    let now = crate::cmd::clock::now()?;
    let grid = DayGrid::new(chrono::Local, config.day_starts_at);
    let scope = StatsScope {
        deck: args.deck.as_deref(),
        items: &items,
    };
    let mut stats = store.stats(scope, now, &grid)?;
    crate::catalog::name_leeches(&mut stats.leeches, &loaded.decks, &config.language);
    // One deck's statistics name its preset's parameters, when it has one.
    let in_use = match args.deck.as_deref() {
        Some(id) => ParametersInUse::of_deck(&config, id),
        None => ParametersInUse::of(&config),
    };
    let mut out = crate::cmd::output::stdout();
    if args.json {
        let mut value = serde_json::to_value(&stats)?;
        if let Some(map) = value.as_object_mut() {
            map.insert("fsrs_parameters".into(), serde_json::to_value(&in_use)?);
        }
        serde_json::to_writer_pretty(&mut out, &value)?;
        writeln!(out)?;
    } else {
        out.write_all(render_stats(&stats).as_bytes())?;
        out.write_all(in_use.line().as_bytes())?;
        out.write_all(render_marks(&stats).as_bytes())?;
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}

fn percent(r: &Ratio) -> String {
    match r.rate {
        Some(rate) => format!("{:.1}% ({}/{})", rate * 100.0, r.passed, r.total),
        None => "– (none yet)".to_string(),
    }
}

/// The stats as text for the terminal.
pub fn render_stats(s: &Stats) -> String {
    let mut o = String::new();
    let mut line = |text: String| {
        o.push_str(&text);
        o.push('\n');
    };
    line(format!(
        "{} — {} (study day {})",
        s.deck.as_deref().unwrap_or("all decks"),
        export::rfc3339(s.now),
        s.today
    ));
    line(String::new());
    let c = &s.cards;
    line(format!(
        "Cards: {} — new {}, learning {}, review {}, relearning {}",
        c.total, c.new, c.learning, c.review, c.relearning
    ));
    let d = &s.due;
    line(format!(
        "Due: today {}, tomorrow {}, next 7 days {}, next 30 days {}, next 90 days {}",
        d.today, d.tomorrow, d.next_7_days, d.next_30_days, d.next_90_days
    ));
    for l in forecast_lines(&d.per_day_90) {
        line(l);
    }
    line(String::new());
    let total: u32 = s.reviews_per_day.iter().map(|d| d.total).sum();
    line(format!("Reviews per day, last 30 days ({total} in all):"));
    let max = s.reviews_per_day.iter().map(|d| d.total).max().unwrap_or(0);
    for day in &s.reviews_per_day {
        let bar = if max == 0 {
            0
        } else {
            (day.total as usize * 40).div_ceil(max as usize)
        };
        line(format!(
            "  {}  {:>5}  {}",
            day.date,
            day.total,
            "█".repeat(bar)
        ));
    }
    let seconds: f64 = s.reviews_per_day.iter().map(|d| d.seconds).sum();
    let studied: Vec<&crate::store::stats::DayReviews> =
        s.reviews_per_day.iter().filter(|d| d.total > 0).collect();
    line(format!(
        "Time spent, last 30 days: {} in all{}",
        duration(seconds),
        if studied.is_empty() {
            String::new()
        } else {
            format!(
                ", {} a study day on average",
                duration(seconds / studied.len() as f64)
            )
        }
    ));
    for day in studied {
        line(format!("  {}  {:>8}", day.date, duration(day.seconds)));
    }
    line(String::new());
    line(
        "Answer buttons (all answers; young: asked within 21 days of the answer before):"
            .to_string(),
    );
    line(format!(
        "  {:<8} {:>7} {:>7} {:>7} {:>7}  {}",
        "", "Again", "Hard", "Good", "Easy", "correct"
    ));
    let b = &s.answer_buttons;
    for (name, x) in [
        ("learn", b.learn),
        ("relearn", b.relearn),
        ("young", b.young),
        ("mature", b.mature),
        ("cram", b.cram),
    ] {
        let n = x.again + x.hard + x.good + x.easy;
        line(format!(
            "  {name:<8} {:>7} {:>7} {:>7} {:>7}  {}",
            x.again,
            x.hard,
            x.good,
            x.easy,
            if n == 0 {
                "–".to_string()
            } else {
                format!("{:.1}%", (n - x.again) as f64 * 100.0 / n as f64)
            }
        ));
    }
    line(String::new());
    line("Intervals (review and relearning items, last review to due date):".to_string());
    line(buckets(&s.intervals, "d"));
    line("Difficulty (FSRS, 1 easiest to 10 hardest):".to_string());
    line(buckets(&s.difficulty, ""));
    line(String::new());
    line("True retention (review answers not rated Again):".to_string());
    line(format!(
        "  last 30 days {}, all time {}",
        percent(&s.retention.last_30_days),
        percent(&s.retention.all_time)
    ));
    for l in true_retention_lines(&s.true_retention) {
        line(l);
    }
    line(format!(
        "Prompt accuracy (predict, then check): {}",
        percent(&s.prompts.overall)
    ));
    for p in &s.prompts.by_prompt {
        // Accuracy over time: each week's judged attempts right.
        let weeks: Vec<String> = p
            .weeks
            .iter()
            .map(|w| format!("{} {}/{}", w.week, w.correct, w.attempts))
            .collect();
        let weeks = if weeks.is_empty() {
            String::new()
        } else {
            format!(" · by week: {}", weeks.join(", "))
        };
        line(format!(
            "  {}/{}: {}/{} right{weeks}",
            p.deck, p.prompt, p.correct, p.attempts
        ));
    }
    if !s.orphans.is_empty() {
        line(String::new());
        line(format!(
            "Orphans: {} with history whose card is no longer in its deck (the history is kept and returns with the card):",
            plural(s.orphans.len(), "item", "items")
        ));
        for o in &s.orphans {
            let whose = if o.deck_present {
                ""
            } else {
                " (deck not loaded)"
            };
            line(format!(
                "  {}/{} {}: {}{whose}",
                o.deck,
                o.card,
                o.direction,
                plural(o.reviews, "review", "reviews")
            ));
        }
    }
    o
}

/// Seconds as `45s`, `12m 5s`, `2h 3m`.
fn duration(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    match s {
        0..60 => format!("{s}s"),
        60..3600 => format!("{}m {}s", s / 60, s % 60),
        _ => format!("{}h {}m", s / 3600, s % 3600 / 60),
    }
}

/// Counted ranges on one line: `≤1d 3 · ≤3d 0 · … · >365d 1`.
fn buckets(b: &[crate::store::stats::Bucket], unit: &str) -> String {
    let mut last = 0.0;
    let cells: Vec<String> = b
        .iter()
        .map(|x| match x.up_to {
            Some(up) => {
                last = up;
                format!("≤{}{unit} {}", crate::text::num::rounded(up, 3), x.items)
            }
            None => format!(">{}{unit} {}", crate::text::num::rounded(last, 3), x.items),
        })
        .collect();
    format!("  {}", cells.join(" · "))
}

/// The 90-day forecast by week (days 1–7, 8–14, …): reviews coming due.
fn forecast_lines(per_day: &[crate::store::stats::DayDue]) -> Vec<String> {
    let weeks: Vec<String> = per_day
        .chunks(7)
        .map(|w| {
            let n: u32 = w.iter().map(|d| d.due).sum();
            format!("{} {n}", w[0].date.format("%m-%d"))
        })
        .collect();
    vec![format!("  by week (first day, due): {}", weeks.join(" · "))]
}

/// Anki's true-retention table as text lines.
pub fn true_retention_lines(t: &crate::store::true_retention::TrueRetention) -> Vec<String> {
    let cell = |p: crate::store::true_retention::PassFail| match p.rate {
        Some(rate) => format!(
            "{}% ({}/{})",
            crate::text::num::rounded(rate * 100.0, 3),
            p.passed,
            p.passed + p.failed
        ),
        None => "–".to_string(),
    };
    let mut out = vec![format!(
        "True retention by maturity (young: stability under {} days; mature: {} or more):",
        crate::store::true_retention::MATURE_DAYS,
        crate::store::true_retention::MATURE_DAYS
    )];
    out.push(format!("  {:<10} {:<22} {}", "", "young", "mature"));
    for ((name, young), (_, mature)) in t.young.rows().into_iter().zip(t.mature.rows()) {
        out.push(format!("  {name:<10} {:<22} {}", cell(young), cell(mature)));
    }
    out
}

/// Which FSRS parameters schedule the cards: the defaults, or the ones
/// `flipcard optimize --apply` fitted, and when.
#[derive(serde::Serialize)]
pub struct ParametersInUse {
    /// "default" or "fitted".
    pub source: &'static str,
    pub fitted_at: Option<String>,
    pub values: Vec<f64>,
    /// The deck's preset, when its own parameters schedule the deck.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub preset: Option<String>,
}

impl ParametersInUse {
    pub fn of(config: &Config) -> ParametersInUse {
        match config.fsrs_parameters {
            Some(w) => ParametersInUse {
                source: "fitted",
                fitted_at: config.fsrs_fitted_at.map(|t| t.to_rfc3339()),
                values: w.to_vec(),
                preset: None,
            },
            None => ParametersInUse {
                source: "default",
                fitted_at: None,
                values: crate::sched::scheduler::default_parameters().to_vec(),
                preset: None,
            },
        }
    }

    /// The parameters deck `id` is scheduled with: its preset's
    /// (`[preset.NAME] fsrs_parameters`, fitted by `optimize --deck`), else
    /// the config's.
    pub fn of_deck(config: &Config, id: &str) -> ParametersInUse {
        let name = config.preset_of(id);
        match name
            .and_then(|n| config.presets.get(n))
            .and_then(|p| p.fsrs_parameters)
        {
            Some(w) => ParametersInUse {
                source: "fitted",
                fitted_at: None,
                values: w.to_vec(),
                preset: name.map(str::to_string),
            },
            None => ParametersInUse::of(config),
        }
    }

    fn line(&self) -> String {
        match (&self.fitted_at, self.source) {
            (_, "default") => {
                "FSRS parameters: the defaults (`flipcard optimize` fits your own)\n".to_string()
            }
            _ if self.preset.is_some() => format!(
                "FSRS parameters: the deck's preset {}'s (fsrs_parameters of [preset.{0}])\n",
                crate::text::safe::one_line(self.preset.as_deref().unwrap_or_default())
            ),
            (Some(at), _) => format!("FSRS parameters: fitted to your reviews on {at}\n"),
            (None, _) => "FSRS parameters: your own (fsrs_parameters in the config)\n".to_string(),
        }
    }
}

/// Suspended and buried counts and the leeches by name, with their lapses.
pub fn render_marks(s: &Stats) -> String {
    let mut o = format!(
        "\nSuspended: {}; buried today: {}; leeches: {}\n",
        s.suspended,
        s.buried,
        s.leeches.len()
    );
    for l in &s.leeches {
        o.push_str(&format!(
            "  leech {}/{}/{} ({}){}\n",
            l.deck,
            l.card,
            l.direction,
            plural(l.lapses, "lapse", "lapses"),
            l.front
                .as_deref()
                .filter(|f| !f.is_empty())
                .map_or(String::new(), |f| format!(": {f}"))
        ));
    }
    o
}
