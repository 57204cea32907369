//! Review statistics: cards by state, the due forecast, reviews per day,
//! true retention, prompt accuracy, orphans, and the items taken out of the
//! queues (suspended, buried, leeches).

use std::collections::{BTreeMap, HashMap, HashSet};

use chrono::{DateTime, Duration, NaiveDate, Utc};
use rusqlite::params_from_iter;
use serde::Serialize;

use super::codec::to_ms;
use super::db::Store;
use super::error::StoreError;
use super::state::CachedState;
use crate::sched::DayOf;
use crate::sched::{CardState, ItemKey, Rating, ReviewKind, State};

/// Days covered by the forecast and by the reviews-per-day history.
pub(crate) const WINDOW_DAYS: usize = 30;

/// What the statistics are about.
#[derive(Debug, Clone, Copy)]
pub struct StatsScope<'a> {
    /// One deck, or every deck in the log.
    pub deck: Option<&'a str>,
    /// The items of the decks as the deck files have them now: an item here
    /// without a state is new; an item in the log but not here is an orphan.
    pub items: &'a [ItemKey],
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Stats {
    pub deck: Option<String>,
    pub now: DateTime<Utc>,
    /// The learning day `now` falls in.
    pub today: NaiveDate,
    pub cards: StateCounts,
    pub due: Forecast,
    /// The last 30 learning days, oldest first, today last.
    pub reviews_per_day: Vec<DayReviews>,
    pub retention: Retention,
    pub prompts: PromptAccuracy,
    /// Items with history whose card is no longer in its deck.
    pub orphans: Vec<Orphan>,
    /// Anki's true-retention table (young and mature review answers).
    pub true_retention: super::true_retention::TrueRetention,
    /// Items suspended now (leeches suspended by `leech_action` among them).
    pub suspended: u32,
    /// Items buried until a later study day.
    pub buried: u32,
    /// Items whose lapses reached `leech_threshold`, by deck, card and
    /// direction.
    pub leeches: Vec<Leech>,
    /// Answers by rating, per kind of answer, over the whole log.
    pub answer_buttons: AnswerButtons,
    /// The current intervals of the items past learning (from the last
    /// review to the due date), counted in ranges.
    pub intervals: Vec<Bucket>,
    /// FSRS difficulty (1–10) of the items with a memory state, counted
    /// by whole number (Anki's ease distribution, for FSRS).
    pub difficulty: Vec<Bucket>,
}

/// How many answers of one kind were rated each way.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct Buttons {
    pub again: u64,
    pub hard: u64,
    pub good: u64,
    pub easy: u64,
}

/// Answers by rating, as Anki's answer-buttons graph: learning and
/// relearning steps, reviews of young items (asked less than 21 days after
/// the answer before) and of mature ones, and crams.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct AnswerButtons {
    pub learn: Buttons,
    pub relearn: Buttons,
    pub young: Buttons,
    pub mature: Buttons,
    pub cram: Buttons,
}

/// Items whose value is at most `up_to` (and above the bucket before);
/// `up_to` absent: above every bound.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Bucket {
    pub up_to: Option<f64>,
    pub items: u32,
}

/// The upper bounds (days) of the interval ranges.
pub const INTERVAL_BOUNDS: [f64; 8] = [1.0, 3.0, 7.0, 14.0, 30.0, 90.0, 180.0, 365.0];

/// Days since the last answer from which a review counts as mature.
pub const MATURE_DAYS: i64 = 21;

/// Days of the longer due forecast.
pub const FORECAST_LONG_DAYS: usize = 90;

/// An item marked as a leech, with its lapses (review answers rated Again)
/// as the log has them now.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Leech {
    pub deck: String,
    pub card: String,
    pub direction: String,
    pub lapses: u32,
    /// What the item asks, on one line (`catalog::name_leeches` fills it
    /// from the decks; `None` for an item no deck loaded has).
    pub front: Option<String>,
}

/// The current items of the scope by state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct StateCounts {
    pub new: u32,
    pub learning: u32,
    pub review: u32,
    pub relearning: u32,
    pub total: u32,
}

/// Items coming due (new items are not counted: the new-card limit decides
/// when they appear). Overdue items count as due today; `next_7_days` and
/// `next_30_days` are cumulative from today.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Forecast {
    pub today: u32,
    pub tomorrow: u32,
    pub next_7_days: u32,
    pub next_30_days: u32,
    /// Today first.
    pub per_day: Vec<DayDue>,
    /// Cumulative from today, as `next_30_days`.
    pub next_90_days: u32,
    /// The next 90 days, today first.
    pub per_day_90: Vec<DayDue>,
}

#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct DayDue {
    pub date: NaiveDate,
    pub due: u32,
}

/// Answers of one learning day (undone ones excluded).
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct DayReviews {
    pub date: NaiveDate,
    pub total: u32,
    pub learn: u32,
    pub review: u32,
    pub relearn: u32,
    pub cram: u32,
    /// Answers rated Again, of any kind.
    pub again: u32,
    /// Time spent answering that day, in seconds (each answer from the
    /// card shown to the rating).
    pub seconds: f64,
}

/// True retention: the share of review-kind answers not rated Again.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Retention {
    pub last_30_days: Ratio,
    pub all_time: Ratio,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Ratio {
    pub total: u64,
    pub passed: u64,
    /// `passed / total`, absent when there is nothing to divide.
    pub rate: Option<f64>,
}

impl Ratio {
    fn new(total: u64, passed: u64) -> Ratio {
        Ratio {
            total,
            passed,
            rate: (total > 0).then(|| passed as f64 / total as f64),
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PromptAccuracy {
    pub overall: Ratio,
    pub by_prompt: Vec<PromptLine>,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PromptLine {
    pub deck: String,
    pub prompt: String,
    pub attempts: u64,
    pub correct: u64,
    /// Accuracy over time: the judged attempts of each week (UTC, from
    /// Monday) that has any, oldest first.
    pub weeks: Vec<PromptWeek>,
}

/// A prompt's judged attempts in one week.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct PromptWeek {
    /// The Monday the week starts on (`2026-11-23`).
    pub week: String,
    pub attempts: u64,
    pub correct: u64,
}

/// A week's number counted from the Monday before 1970-01-01 (a Thursday).
const WEEK_MS: i64 = 7 * 86_400_000;
const MONDAY_MS: i64 = 3 * 86_400_000;

#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Orphan {
    pub deck: String,
    pub card: String,
    pub direction: String,
    /// Answers in the log (undone ones excluded).
    pub reviews: u64,
    /// Whether the orphan's deck is among the decks loaded at all.
    pub deck_present: bool,
}

impl Store {
    pub fn stats(
        &self,
        scope: StatsScope<'_>,
        now: DateTime<Utc>,
        grid: &dyn DayOf,
    ) -> Result<Stats, StoreError> {
        let today = grid.day_of(now);
        let items: Vec<&ItemKey> = scope
            .items
            .iter()
            .filter(|k| scope.deck.is_none_or(|d| k.deck == d))
            .collect();

        let cached = self.cached_states_in(scope.deck)?;
        let states: HashMap<&ItemKey, &CardState> =
            cached.iter().map(|c| (&c.key, &c.state)).collect();
        let (cards, due) = states_and_forecast(&items, &states, today, grid);
        let (reviews_per_day, last_30_days) = self.recent_days(scope.deck, today, grid)?;
        let (total, passed) =
            super::tally::review_answers(&self.conn, scope.deck).map_err(|e| self.err(e))?;
        let retention = Retention {
            last_30_days,
            all_time: Ratio::new(total, passed),
        };
        let prompts = self.prompt_accuracy(scope.deck)?;
        let orphans = self.orphans(scope.deck, &items, &cached)?;
        let true_retention = self.true_retention(scope.deck, now, grid)?;
        let (suspended, buried, leeches) = self.marks(scope.deck, &cached, now)?;
        let answer_buttons = self.answer_buttons(scope.deck)?;
        let (intervals, difficulty) = distributions(&items, &states);
        Ok(Stats {
            answer_buttons,
            intervals,
            difficulty,
            deck: scope.deck.map(str::to_string),
            now,
            today,
            cards,
            due,
            reviews_per_day,
            retention,
            prompts,
            orphans,
            true_retention,
            suspended,
            buried,
            leeches,
        })
    }

    /// Suspended and buried counts and the leeches of the scope, whether or
    /// not their cards are still in the deck files (a status outlives an
    /// edit, as the history does).
    fn marks(
        &self,
        deck: Option<&str>,
        cached: &[CachedState],
        now: DateTime<Utc>,
    ) -> Result<(u32, u32, Vec<Leech>), StoreError> {
        let lapses: HashMap<&ItemKey, u32> = cached.iter().map(|c| (&c.key, c.lapses)).collect();
        let mut marks: Vec<_> = self
            .statuses()?
            .into_iter()
            .filter(|(k, _)| deck.is_none_or(|d| k.deck == d))
            .collect();
        marks.sort_by(|a, b| a.0.cmp(&b.0));
        let suspended = marks.iter().filter(|(_, s)| s.suspended).count() as u32;
        let buried = marks.iter().filter(|(_, s)| s.buried(now)).count() as u32;
        let leeches = marks
            .iter()
            .filter(|(_, s)| s.leech)
            .map(|(k, _)| Leech {
                deck: k.deck.clone(),
                card: k.card.clone(),
                direction: k.direction.as_str().to_string(),
                lapses: lapses.get(k).copied().unwrap_or(0),
                front: None,
            })
            .collect();
        Ok((suspended, buried, leeches))
    }

    /// Answers per day over the last 30 learning days, and the retention of
    /// their review-kind answers.
    fn recent_days(
        &self,
        deck: Option<&str>,
        today: NaiveDate,
        grid: &dyn DayOf,
    ) -> Result<(Vec<DayReviews>, Ratio), StoreError> {
        let days: Vec<NaiveDate> = (0..WINDOW_DAYS as i64)
            .rev()
            .map(|back| today - Duration::days(back))
            .collect();
        let starts: Vec<i64> = days.iter().map(|d| to_ms(grid.start_of(*d))).collect();
        let end = to_ms(grid.start_of(today + Duration::days(1)));
        let mut out: Vec<DayReviews> = days
            .iter()
            .map(|d| DayReviews {
                date: *d,
                ..DayReviews::default()
            })
            .collect();
        let (mut review_total, mut review_passed) = (0u64, 0u64);
        let (filter, args) = deck_filter(deck, vec![starts[0].into(), end.into()], "AND");
        let sql = format!(
            "SELECT reviewed_at, kind, rating, duration_ms FROM review \
             WHERE reviewed_at >= ?1 AND reviewed_at < ?2 AND undone = 0 {filter}"
        );
        let mut st = self.conn.prepare_cached(&sql).map_err(|e| self.err(e))?;
        let mut rows = st.query(params_from_iter(args)).map_err(|e| self.err(e))?;
        while let Some(row) = rows.next().map_err(|e| self.err(e))? {
            let at: i64 = row.get(0).map_err(|e| self.err(e))?;
            let kind: ReviewKind = row.get(1).map_err(|e| self.err(e))?;
            let again = row.get::<_, Rating>(2).map_err(|e| self.err(e))? == Rating::Again;
            let ms: i64 = row.get(3).map_err(|e| self.err(e))?;
            let i = starts.partition_point(|s| *s <= at).saturating_sub(1);
            let day = &mut out[i];
            day.total += 1;
            day.seconds += ms.max(0) as f64 / 1000.0;
            match kind {
                ReviewKind::Learn => day.learn += 1,
                ReviewKind::Review => {
                    day.review += 1;
                    review_total += 1;
                    review_passed += u64::from(!again);
                }
                ReviewKind::Relearn => day.relearn += 1,
                ReviewKind::Cram => day.cram += 1,
            }
            day.again += u32::from(again);
        }
        Ok((out, Ratio::new(review_total, review_passed)))
    }

    /// Answers by kind and rating over the whole log (undone ones left
    /// out); a review is mature when at least [`MATURE_DAYS`] passed since
    /// the answer before.
    fn answer_buttons(&self, deck: Option<&str>) -> Result<AnswerButtons, StoreError> {
        let (filter, args) = deck_filter(deck, Vec::new(), "AND");
        let sql = format!(
            "SELECT kind, rating, elapsed_days >= {MATURE_DAYS}, count(*) FROM review \
             WHERE undone = 0 {filter} GROUP BY 1, 2, 3"
        );
        let mut st = self.conn.prepare_cached(&sql).map_err(|e| self.err(e))?;
        let mut rows = st.query(params_from_iter(args)).map_err(|e| self.err(e))?;
        let mut out = AnswerButtons::default();
        while let Some(row) = rows.next().map_err(|e| self.err(e))? {
            let kind: ReviewKind = row.get(0).map_err(|e| self.err(e))?;
            let rating: Rating = row.get(1).map_err(|e| self.err(e))?;
            let mature: bool = row.get(2).map_err(|e| self.err(e))?;
            let n: i64 = row.get(3).map_err(|e| self.err(e))?;
            let b = match kind {
                ReviewKind::Learn => &mut out.learn,
                ReviewKind::Relearn => &mut out.relearn,
                ReviewKind::Review if mature => &mut out.mature,
                ReviewKind::Review => &mut out.young,
                ReviewKind::Cram => &mut out.cram,
            };
            let slot = match rating {
                Rating::Again => &mut b.again,
                Rating::Hard => &mut b.hard,
                Rating::Good => &mut b.good,
                Rating::Easy => &mut b.easy,
            };
            *slot += n.max(0) as u64;
        }
        Ok(out)
    }

    fn prompt_accuracy(&self, deck: Option<&str>) -> Result<PromptAccuracy, StoreError> {
        let (filter, args) = deck_filter(deck, Vec::new(), "WHERE");
        let sql = format!(
            "SELECT deck, prompt, count(correct), coalesce(sum(correct), 0) FROM prompt_attempt \
             {filter} GROUP BY deck, prompt ORDER BY deck, prompt"
        );
        let mut st = self.conn.prepare_cached(&sql).map_err(|e| self.err(e))?;
        let lines: Vec<PromptLine> = st
            .query_map(params_from_iter(args), |r| {
                Ok(PromptLine {
                    deck: r.get(0)?,
                    prompt: r.get(1)?,
                    attempts: r.get::<_, i64>(2)? as u64,
                    correct: r.get::<_, i64>(3)? as u64,
                    weeks: Vec::new(),
                })
            })
            .and_then(|rows| rows.collect())
            .map_err(|e| self.err(e))?;
        let mut lines = lines;
        let (filter, args) = deck_filter(deck, Vec::new(), "AND");
        let sql = format!(
            "SELECT deck, prompt, (attempted_at + {MONDAY_MS}) / {WEEK_MS} AS w, count(correct), \
             coalesce(sum(correct), 0) FROM prompt_attempt WHERE correct IS NOT NULL {filter} \
             GROUP BY deck, prompt, w ORDER BY deck, prompt, w"
        );
        let mut st = self.conn.prepare_cached(&sql).map_err(|e| self.err(e))?;
        let weeks: Vec<(String, String, i64, u64, u64)> = st
            .query_map(params_from_iter(args), |r| {
                Ok((
                    r.get(0)?,
                    r.get(1)?,
                    r.get(2)?,
                    r.get::<_, i64>(3)? as u64,
                    r.get::<_, i64>(4)? as u64,
                ))
            })
            .and_then(|rows| rows.collect())
            .map_err(|e| self.err(e))?;
        for (d, p, w, attempts, correct) in weeks {
            let Some(line) = lines.iter_mut().find(|l| l.deck == d && l.prompt == p) else {
                continue;
            };
            let start = w
                .checked_mul(WEEK_MS)
                .and_then(|ms| ms.checked_sub(MONDAY_MS))
                .and_then(chrono::DateTime::from_timestamp_millis)
                .map_or_else(|| "?".to_string(), |t| t.format("%Y-%m-%d").to_string());
            line.weeks.push(PromptWeek {
                week: start,
                attempts,
                correct,
            });
        }
        let attempts = lines.iter().map(|l| l.attempts).sum();
        let correct = lines.iter().map(|l| l.correct).sum();
        Ok(PromptAccuracy {
            overall: Ratio::new(attempts, correct),
            by_prompt: lines,
        })
    }

    /// Items with answers in the log that are not among the current items:
    /// those with a state (their count of scheduling answers is in the
    /// cache) and those only ever crammed.
    fn orphans(
        &self,
        deck: Option<&str>,
        items: &[&ItemKey],
        cached: &[CachedState],
    ) -> Result<Vec<Orphan>, StoreError> {
        let current: HashSet<&ItemKey> = items.iter().copied().collect();
        let decks: HashSet<&str> = items.iter().map(|k| k.deck.as_str()).collect();
        let mut answers: BTreeMap<(String, String, std::borrow::Cow<'static, str>), u64> =
            BTreeMap::new();
        for c in cached.iter().filter(|c| !current.contains(&c.key)) {
            let k = &c.key;
            answers.insert(
                (k.deck.clone(), k.card.clone(), k.direction.as_str()),
                u64::from(c.reps),
            );
        }
        let (filter, args) = deck_filter(deck, Vec::new(), "AND");
        let sql = format!(
            "SELECT deck, card, direction, count(*) FROM review \
             WHERE kind = 'cram' AND undone = 0 {filter} GROUP BY deck, card, direction"
        );
        let mut st = self.conn.prepare_cached(&sql).map_err(|e| self.err(e))?;
        let mut rows = st.query(params_from_iter(args)).map_err(|e| self.err(e))?;
        while let Some(row) = rows.next().map_err(|e| self.err(e))? {
            let deck: String = row.get(0).map_err(|e| self.err(e))?;
            let card: String = row.get(1).map_err(|e| self.err(e))?;
            let direction: crate::sched::Direction = row.get(2).map_err(|e| self.err(e))?;
            let n: i64 = row.get(3).map_err(|e| self.err(e))?;
            let key = ItemKey {
                deck,
                card,
                direction,
            };
            if current.contains(&key) {
                continue;
            }
            *answers
                .entry((key.deck, key.card, direction.as_str()))
                .or_insert(0) += n as u64;
        }
        Ok(answers
            .into_iter()
            .map(|((deck, card, direction), reviews)| Orphan {
                deck_present: decks.contains(deck.as_str()),
                deck,
                card,
                direction: direction.to_string(),
                reviews,
            })
            .collect())
    }
}

/// `<joiner> deck = ?n` with its argument appended, when a deck is given.
fn deck_filter(
    deck: Option<&str>,
    mut args: Vec<rusqlite::types::Value>,
    joiner: &str,
) -> (String, Vec<rusqlite::types::Value>) {
    match deck {
        Some(d) => {
            args.push(d.to_string().into());
            (format!("{joiner} deck = ?{}", args.len()), args)
        }
        None => (String::new(), args),
    }
}

fn states_and_forecast(
    items: &[&ItemKey],
    states: &HashMap<&ItemKey, &CardState>,
    today: NaiveDate,
    grid: &dyn DayOf,
) -> (StateCounts, Forecast) {
    // ends[i]: when day i (0 = today) ends.
    let ends: Vec<DateTime<Utc>> = (1..=FORECAST_LONG_DAYS as i64)
        .map(|i| grid.start_of(today + Duration::days(i)))
        .collect();
    let mut per_day = [0u32; FORECAST_LONG_DAYS];
    let mut counts = StateCounts::default();
    for key in items {
        counts.total += 1;
        let Some(st) = states.get(*key).filter(|s| s.state != State::New) else {
            counts.new += 1;
            continue;
        };
        match st.state {
            State::Learning => counts.learning += 1,
            State::Review => counts.review += 1,
            State::Relearning => counts.relearning += 1,
            State::New => {}
        }
        let day = ends.partition_point(|end| *end <= st.due);
        if let Some(slot) = per_day.get_mut(day) {
            *slot += 1;
        }
    }
    let sum = |n: usize| per_day.iter().take(n).sum();
    let forecast = Forecast {
        today: per_day[0],
        tomorrow: per_day[1],
        next_7_days: sum(7),
        next_30_days: sum(WINDOW_DAYS),
        next_90_days: sum(FORECAST_LONG_DAYS),
        per_day_90: per_day
            .iter()
            .enumerate()
            .map(|(i, n)| DayDue {
                date: today + Duration::days(i as i64),
                due: *n,
            })
            .collect(),
        per_day: per_day
            .iter()
            .take(WINDOW_DAYS)
            .enumerate()
            .map(|(i, n)| DayDue {
                date: today + Duration::days(i as i64),
                due: *n,
            })
            .collect(),
    };
    (counts, forecast)
}

/// The interval ranges ([`INTERVAL_BOUNDS`]) of the items past learning
/// (review and relearning, from the last review to the due date) and the
/// difficulty (by whole number, 1 to 10) of every item with one.
fn distributions(
    items: &[&ItemKey],
    states: &HashMap<&ItemKey, &CardState>,
) -> (Vec<Bucket>, Vec<Bucket>) {
    let mut intervals: Vec<Bucket> = INTERVAL_BOUNDS
        .iter()
        .map(|b| Bucket {
            up_to: Some(*b),
            items: 0,
        })
        .chain([Bucket {
            up_to: None,
            items: 0,
        }])
        .collect();
    let mut difficulty: Vec<Bucket> = (1..=10)
        .map(|d| Bucket {
            up_to: Some(f64::from(d)),
            items: 0,
        })
        .collect();
    for key in items {
        let Some(st) = states.get(*key).filter(|s| s.state != State::New) else {
            continue;
        };
        if matches!(st.state, State::Review | State::Relearning)
            && let Some(last) = st.last_review
        {
            let days = (st.due - last).num_seconds() as f64 / 86_400.0;
            let i = INTERVAL_BOUNDS.partition_point(|b| *b < days);
            intervals[i].items += 1;
        }
        if let Some(d) = st.difficulty.filter(|d| d.is_finite()) {
            // 1–10; a value on a whole number counts below it (1.0 in the
            // first, 2.0 in the second).
            let i = (d.ceil() as i64 - 1).clamp(0, 9) as usize;
            difficulty[i].items += 1;
        }
    }
    (intervals, difficulty)
}
