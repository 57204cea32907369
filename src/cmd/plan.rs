//! `flipcard plan [--exam DATE] [--deck ID] [--retention R] [--max-per-day N]
//! [--format json]`. The exam date is remembered in the config
//! (`exam_date`) until it passes: without `--exam`, the remembered one.

use std::process::ExitCode;

use anyhow::Context as _;
use chrono::{Duration, NaiveDate};
use serde_json::json;
use unicode_width::UnicodeWidthStr;

use crate::cmd::args::{Cli, PlanArgs, PlanFormat};
use crate::cmd::common::{find_deck, load_decks, open_store_read_only};
use crate::cmd::paths;
use crate::sched::DayGrid;
use crate::sched::plan::{self, Plan};
use crate::sched::scheduler::ForDeck;
use crate::sched::{Config, ItemKey, Schedulers, States, deck_items};
use crate::text::num::rounded;
use crate::text::plural;
use crate::{out, outln};

pub fn run(cli: &Cli, args: &PlanArgs) -> anyhow::Result<ExitCode> {
    let config_path = paths::config_file(cli.config.clone());
    let mut config = Config::load(config_path.as_deref())?;
    let now = crate::cmd::clock::now()?;
    let grid = DayGrid::new(chrono::Local, config.day_starts_at);
    let today = grid.day_of(now);
    let exam = match (&args.exam, config.exam_date) {
        (Some(text), _) => parse_date(text)?,
        (None, Some(day)) if day >= today => day,
        (None, Some(day)) => anyhow::bail!(
            "the remembered exam date {day} has passed (today is {today}); give the next one with --exam DATE"
        ),
        (None, None) => anyhow::bail!(
            "no exam date: give one with --exam DATE (YYYY-MM-DD); it is remembered until the exam"
        ),
    };
    let asked = match &args.retention {
        Some(text) => Some(parse_retention(text)?),
        None => None,
    };
    let target = asked.unwrap_or(config.desired_retention);
    let cap = match &args.max_per_day {
        Some(text) => parse_cap(text)?,
        None => config.reviews_per_day as usize,
    };
    let loaded = load_decks(cli);
    let decks = match &args.deck {
        Some(id) => vec![find_deck(&loaded, id)?],
        None => loaded.decks.iter().collect(),
    };
    let store = open_store_read_only(cli)?;
    let mut keys: Vec<ItemKey> = Vec::new();
    let mut states = States::default();
    for deck in &decks {
        keys.extend(deck_items(deck));
        states.extend(store.states(&deck.id)?);
    }
    // A suspended item is out of every queue: no plan schedules it.
    let statuses = store.statuses()?;
    keys.retain(|k| !statuses.get(k).is_some_and(|s| s.suspended));
    let day_of = |t| grid.day_of(t);
    // Each item with its deck's preset: its FSRS parameters, and its
    // desired retention unless --retention asks for one target.
    let schedulers = Schedulers::new(&config);
    let each: Vec<plan::ItemModel> = keys
        .iter()
        .map(|k| plan::ItemModel {
            scheduler: schedulers.for_deck(&k.deck),
            target: asked.unwrap_or_else(|| config.for_deck(&k.deck).desired_retention),
        })
        .collect();
    let problem = plan::exam_problem(&keys, &states, today, exam, &day_of, target, cap)?;
    let plan = plan::plan_each(&each, &problem)?;
    // A date the planner took (not past, not too far) is remembered.
    let remembered = match &config_path {
        Some(path) if config.exam_date != Some(exam) => {
            config.save_exam_date(path, exam)?;
            true
        }
        _ => false,
    };
    let cap_needed = plan::cap_needed_each(&each, &problem)?;
    let now_r: Vec<f64> = keys
        .iter()
        .map(|k| {
            states
                .get(k)
                .map_or(0.0, |s| schedulers.for_deck(&k.deck).retrievability(s, now))
        })
        .collect();
    let asks: Vec<String> = keys
        .iter()
        .map(|k| {
            decks
                .iter()
                .find(|d| d.id == k.deck)
                .and_then(|d| crate::catalog::asked_item(d, k, &config.language))
                .map(|t| crate::text::safe::one_line(&t).into_owned())
                .unwrap_or_default()
        })
        .collect();
    let report = Report {
        asks: &asks,
        today,
        exam,
        deck: args.deck.as_deref(),
        keys: &keys,
        now_r: &now_r,
        plan: &plan,
        cap_needed,
    };
    match args.format {
        PlanFormat::Json => {
            outln!("{}", serde_json::to_string_pretty(&report.json())?)?;
        }
        PlanFormat::Text => {
            out!("{}", report.text())?;
            if remembered {
                outln!("exam date {exam} remembered: `flipcard plan` plans for it until then")?;
            }
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// The widest the text table's "Asks" column gets, in terminal cells.
const ASKS: usize = 32;

/// `text` cut to `width` cells, a cut marked with `…`.
fn cut(text: &str, width: usize) -> String {
    if text.width() <= width {
        return text.to_string();
    }
    let mut s = String::new();
    let mut used = 0;
    for c in text.chars() {
        let w = unicode_width::UnicodeWidthChar::width(c).unwrap_or(0);
        if used + w + 1 > width {
            break;
        }
        used += w;
        s.push(c);
    }
    s.push('…');
    s
}

fn parse_date(text: &str) -> anyhow::Result<NaiveDate> {
    let day = NaiveDate::parse_from_str(text.trim(), "%Y-%m-%d").with_context(|| {
        format!("--exam {text:?} is not a date as YYYY-MM-DD (example: 2026-11-22)")
    })?;
    crate::sched::config::parse_exam_date(text).map_err(|m| anyhow::anyhow!("--exam: {m}"))?;
    Ok(day)
}

fn parse_retention(text: &str) -> anyhow::Result<f64> {
    match text.trim().parse::<f64>() {
        Ok(r) if r > 0.0 && r < 1.0 => Ok(r),
        _ => anyhow::bail!(
            "--retention {text:?} is not a probability between 0 and 1 (exclusive); example: 0.9"
        ),
    }
}

fn parse_cap(text: &str) -> anyhow::Result<usize> {
    match text.trim().parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => anyhow::bail!("--max-per-day {text:?} is not a whole number of reviews, 1 or more"),
    }
}

struct Report<'a> {
    today: NaiveDate,
    exam: NaiveDate,
    deck: Option<&'a str>,
    keys: &'a [ItemKey],
    /// What each item asks, on one line, escaped.
    asks: &'a [String],
    now_r: &'a [f64],
    plan: &'a Plan,
    cap_needed: Option<usize>,
}

impl Report<'_> {
    fn date(&self, day: i64) -> NaiveDate {
        self.today + Duration::days(day)
    }

    fn json(&self) -> serde_json::Value {
        let p = self.plan;
        let days: Vec<_> = p
            .per_day
            .iter()
            .enumerate()
            .map(|(d, n)| json!({"date": self.date(d as i64).to_string(), "reviews": n}))
            .collect();
        let per_item: Vec<_> = self
            .keys
            .iter()
            .zip(&p.items)
            .zip(self.now_r)
            .zip(self.asks)
            .map(|(((k, i), now), front)| {
                json!({
                    "deck": k.deck,
                    "card": k.card,
                    "direction": k.direction.as_str(),
                    "front": front,
                    "retrievability_now": now,
                    "retrievability_without_plan": i.without,
                    "retrievability_with_plan": i.with,
                    "target": i.target,
                    "reviews": i.reviews.iter().map(|&d| self.date(d).to_string()).collect::<Vec<_>>(),
                })
            })
            .collect();
        json!({
            "exam": self.exam.to_string(),
            "today": self.today.to_string(),
            "deck": self.deck,
            "items": p.items.len(),
            "retention": p.target,
            "max_per_day": p.cap,
            "expected_recalled_without_plan": p.expected_without(),
            "expected_recalled_with_plan": p.expected_with(),
            "shortfall": p.shortfall(),
            "reviews": p.reviews(),
            "cap_needed": self.cap_needed,
            "days": days,
            "per_item": per_item,
        })
    }

    fn text(&self) -> String {
        let p = self.plan;
        let n = p.items.len();
        let mut o = String::new();
        let mut line = |s: String| {
            o.push_str(&s);
            o.push('\n');
        };
        let when = match p.days {
            0 => "today".to_string(),
            1 => "tomorrow".to_string(),
            d => format!("in {d} days"),
        };
        // Decks with presets of their own may each have their target.
        let (lo, hi) = p
            .items
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), i| {
                (lo.min(i.target), hi.max(i.target))
            });
        let (lo, hi) = if n == 0 {
            (p.target, p.target)
        } else {
            (lo, hi)
        };
        let target = if lo == hi {
            rounded(lo, 4)
        } else {
            format!(
                "{} to {} (each deck's preset)",
                rounded(lo, 4),
                rounded(hi, 4)
            )
        };
        line(format!(
            "Exam on {} ({when}) · {} · {} · target recall {target} · at most {} a day",
            self.exam,
            self.deck.unwrap_or("all decks"),
            plural(n, "card", "cards"),
            plural(p.cap, "review", "reviews"),
        ));
        line(String::new());
        line(format!(
            "Expected recalled on the exam day: {} of {n} with no more reviews, {} with the plan.",
            rounded(p.expected_without(), 4),
            rounded(p.expected_with(), 4)
        ));
        let short = p.shortfall();
        line(format!(
            "The plan: {} over {}.",
            plural(p.reviews(), "review", "reviews"),
            plural(p.per_day.len(), "day", "days")
        ));
        if short == 0 {
            line(format!("Every card reaches {target} on the exam day."));
        } else {
            let why = match self.cap_needed {
                Some(c) => format!(
                    "the daily cap holds it back: {} a day would do (--max-per-day {c})",
                    plural(c, "review", "reviews")
                ),
                None => "too little time is left for them at any daily cap".to_string(),
            };
            line(format!(
                "Short: {} of {n} stay below {target} on the exam day; {why}.",
                plural(short, "card", "cards"),
            ));
        }
        if !p.per_day.is_empty() {
            line(String::new());
            line(format!("{:<10}  {:>7}", "Day", "Reviews"));
            for (d, r) in p.per_day.iter().enumerate() {
                line(format!("{:<10}  {r:>7}", self.date(d as i64).to_string()));
            }
        }
        if n > 0 {
            line(String::new());
            let names: Vec<String> = self
                .keys
                .iter()
                .map(|k| format!("{}/{} {}", k.deck, k.card, k.direction.as_str()))
                .collect();
            let w = names
                .iter()
                .map(|s| s.chars().count())
                .max()
                .unwrap_or(4)
                .max(4);
            // What each item asks, cut to a column.
            let asks: Vec<String> = self.asks.iter().map(|a| cut(a, ASKS)).collect();
            let a = asks.iter().map(|s| s.width()).max().unwrap_or(4).max(4);
            // Padded by the cells it takes (`L⃗` is two characters, one cell).
            let pad = |s: &str| format!("{s}{}", " ".repeat(a - s.width().min(a)));
            line(format!(
                "{:<w$}  {:<a$}  {:>6}  {:>12}  {:>9}  Reviews on",
                "Card", "Asks", "Now", "Exam, as is", "With plan"
            ));
            for (((name, i), now), asks) in names.iter().zip(&p.items).zip(self.now_r).zip(&asks) {
                let asks = pad(asks);
                let on: Vec<String> = i
                    .reviews
                    .iter()
                    .map(|&d| self.date(d).format("%m-%d").to_string())
                    .collect();
                let mark = if i.with < i.target { " (short)" } else { "" };
                line(format!(
                    "{name:<w$}  {asks}  {:>6}  {:>12}  {:>9}  {}{mark}",
                    rounded(*now, 3),
                    rounded(i.without, 3),
                    rounded(i.with, 3),
                    if on.is_empty() {
                        "–".to_string()
                    } else {
                        on.join(" ")
                    }
                ));
            }
        }
        o
    }
}
