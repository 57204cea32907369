//! Anki's true retention: the pass rate of answers to cards in review, for
//! young cards (stability before the answer under 21 days) and mature ones,
//! over today, yesterday and the last 7, 30 and 365 learning days.

use chrono::{DateTime, Duration, Utc};
use serde::Serialize;

use super::codec::to_ms;
use super::db::Store;
use super::error::StoreError;
use crate::sched::DayOf;
use crate::sched::Rating;

/// Stability (days) from which a card counts as mature.
pub const MATURE_DAYS: f64 = 21.0;

#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct PassFail {
    pub passed: u64,
    pub failed: u64,
    /// `passed / (passed + failed)`; null when there were no answers.
    pub rate: Option<f64>,
}

impl PassFail {
    fn add(&mut self, passed: bool) {
        if passed {
            self.passed += 1;
        } else {
            self.failed += 1;
        }
        self.rate = Some(self.passed as f64 / (self.passed + self.failed) as f64);
    }
}

/// One maturity's answers over the periods, each period ending now.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Periods {
    pub today: PassFail,
    pub yesterday: PassFail,
    /// The last 7 learning days, today included.
    pub week: PassFail,
    /// The last 30 learning days, today included.
    pub month: PassFail,
    /// The last 365 learning days, today included.
    pub year: PassFail,
}

impl Periods {
    /// The periods in table order, with their names.
    pub fn rows(&self) -> [(&'static str, PassFail); 5] {
        [
            ("today", self.today),
            ("yesterday", self.yesterday),
            ("week", self.week),
            ("month", self.month),
            ("year", self.year),
        ]
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct TrueRetention {
    pub young: Periods,
    pub mature: Periods,
}

impl Store {
    /// True retention of review answers (not undone) of one deck or all.
    pub fn true_retention(
        &self,
        deck: Option<&str>,
        now: DateTime<Utc>,
        grid: &dyn DayOf,
    ) -> Result<TrueRetention, StoreError> {
        let today = grid.day_of(now);
        let start = |back: i64| to_ms(grid.start_of(today - Duration::days(back)));
        let (today_start, yesterday_start, week, month, year) =
            (start(0), start(1), start(6), start(29), start(364));
        let end = to_ms(grid.start_of(today + Duration::days(1)));
        // The stability before an answer is the one the item's previous
        // answer that counts left it with.
        let mut st = self
            .conn
            .prepare_cached(
                "SELECT reviewed_at, rating, prev_s FROM ( \
                   SELECT reviewed_at, rating, kind, \
                          lag(stability) OVER (PARTITION BY deck, card, direction \
                                               ORDER BY reviewed_at, id) AS prev_s \
                   FROM review \
                   WHERE undone = 0 AND kind <> 'cram' AND (?3 IS NULL OR deck = ?3) \
                     AND reviewed_at < ?2) \
                 WHERE kind = 'review' AND reviewed_at >= ?1",
            )
            .map_err(|e| self.err(e))?;
        let mut rows = st
            .query(rusqlite::params![year, end, deck])
            .map_err(|e| self.err(e))?;
        let mut out = TrueRetention::default();
        while let Some(row) = rows.next().map_err(|e| self.err(e))? {
            let at: i64 = row.get(0).map_err(|e| self.err(e))?;
            let rating: Rating = row.get(1).map_err(|e| self.err(e))?;
            let before: Option<f64> = row.get(2).map_err(|e| self.err(e))?;
            let passed = rating != Rating::Again;
            let p = if before.is_some_and(|s| s >= MATURE_DAYS) {
                &mut out.mature
            } else {
                &mut out.young
            };
            p.year.add(passed);
            if at >= month {
                p.month.add(passed);
            }
            if at >= week {
                p.week.add(passed);
            }
            if at >= today_start {
                p.today.add(passed);
            } else if at >= yesterday_start {
                p.yesterday.add(passed);
            }
        }
        Ok(out)
    }

    /// Answers (not undone) per learning day from `days` days back to today,
    /// oldest first: the calendar's counts.
    pub fn answers_per_day(
        &self,
        deck: Option<&str>,
        now: DateTime<Utc>,
        grid: &dyn DayOf,
        days: usize,
    ) -> Result<Vec<(chrono::NaiveDate, u32)>, StoreError> {
        let today = grid.day_of(now);
        let dates: Vec<chrono::NaiveDate> = (0..days as i64)
            .rev()
            .map(|back| today - Duration::days(back))
            .collect();
        let starts: Vec<i64> = dates.iter().map(|d| to_ms(grid.start_of(*d))).collect();
        let end = to_ms(grid.start_of(today + Duration::days(1)));
        let mut counts = vec![0u32; dates.len()];
        let Some(first) = starts.first().copied() else {
            return Ok(Vec::new());
        };
        let mut st = self
            .conn
            .prepare_cached(
                "SELECT reviewed_at FROM review WHERE undone = 0 AND reviewed_at >= ?1 \
                 AND reviewed_at < ?2 AND (?3 IS NULL OR deck = ?3)",
            )
            .map_err(|e| self.err(e))?;
        let mut rows = st
            .query(rusqlite::params![first, end, deck])
            .map_err(|e| self.err(e))?;
        while let Some(row) = rows.next().map_err(|e| self.err(e))? {
            let at: i64 = row.get(0).map_err(|e| self.err(e))?;
            let i = starts.partition_point(|s| *s <= at).saturating_sub(1);
            counts[i] += 1;
        }
        Ok(dates.into_iter().zip(counts).collect())
    }
}
