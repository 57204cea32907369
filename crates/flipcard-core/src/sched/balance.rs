//! Load balancing and easy days, after Anki 24.11's load balancer
//! (`rslib/src/scheduler/states/load_balancer.rs`).
//!
//! When fuzz is on, a review interval of at most [`MAX_BALANCED`] days is
//! not drawn uniformly over its fuzz range: each day of the range is
//! weighted by how few items are already due on it, slightly favouring
//! earlier days, and by the learner's easy days, and the day is drawn by
//! that weight with the same number the uniform fuzz would use (fixed by
//! the item and the answer's time). So the same answer over the same due
//! counts always lands on the same day, and the day is always one the
//! fuzz could have given.
//!
//! The weight of a day `k` days away with `c` items due is
//! `(1 / (c + 1))^2.15 × (1 / k)^3 × e`, Anki's weights with the count
//! shifted by one so an empty day needs no special case (Anki gives an
//! empty day the weight 1 whatever its easy-day setting), and `e` the
//! easy-day factor: 1 on a normal day, 0.0001 on a day set to 0 (so a
//! range made only of such days still balances), and on a day set to a
//! share `p` between, 1 while its count divided by `p` stays at or below
//! the range's other days' count per unit of share, else 0.0001 (Anki's
//! rule for its "reduced" days, for any share).

use chrono::{Datelike, NaiveDate};

/// Intervals longer than this are fuzzed uniformly: the need to balance
/// is low that far out (Anki's `MAX_LOAD_BALANCE_INTERVAL`).
pub const MAX_BALANCED: i64 = 90;

/// Days of due counts a [`Load`] holds: the longest balanced interval's
/// fuzz range ends before this (90 days fuzz to at most 96).
pub const LOAD_DAYS: usize = 100;

/// The weight of a day set to 0 (not zero, so that a range of such days
/// still has weights to draw from).
const MINIMUM: f64 = 0.0001;

/// How many items are due on each of the next [`LOAD_DAYS`] study days,
/// and the share of a normal day's reviews each of those days should get.
#[derive(Debug, Clone, PartialEq)]
pub struct Load {
    /// `counts[k]`: items due in the study day `k` days after the answer's.
    counts: Vec<u32>,
    /// `shares[k]`: the easy-day share of that day, 0–1.
    shares: Vec<f64>,
}

/// The learner's easy days: for each weekday, Monday first, the share of
/// a normal day's reviews it should get (1 normal, 0 as few as can be).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EasyDays(pub [f64; 7]);

impl Default for EasyDays {
    fn default() -> Self {
        EasyDays([1.0; 7])
    }
}

/// The config's spelling of the weekdays, Monday first.
pub const WEEKDAYS: [&str; 7] = ["mon", "tue", "wed", "thu", "fri", "sat", "sun"];

impl EasyDays {
    /// The share of `day`'s weekday.
    pub fn share(&self, day: NaiveDate) -> f64 {
        self.0[day.weekday().num_days_from_monday() as usize]
    }

    /// Every day normal.
    pub fn is_default(&self) -> bool {
        self.0 == [1.0; 7]
    }
}

impl Load {
    /// The due counts of the study days from the answer's (`counts[0]`)
    /// on, and the study day of the answer (for the weekday of each).
    /// Only the first [`LOAD_DAYS`] counts are kept.
    pub fn new(mut counts: Vec<u32>, today: NaiveDate, easy: &EasyDays) -> Load {
        counts.resize(LOAD_DAYS, 0);
        let shares = (0..LOAD_DAYS)
            .map(|k| {
                today
                    .checked_add_days(chrono::Days::new(k as u64))
                    .map_or(1.0, |d| easy.share(d))
            })
            .collect();
        Load { counts, shares }
    }

    /// Items due `k` days after the answer's study day.
    pub fn count(&self, k: i64) -> u32 {
        usize::try_from(k)
            .ok()
            .and_then(|k| self.counts.get(k))
            .copied()
            .unwrap_or(0)
    }

    /// One more item due `k` days on (what an answer just placed).
    pub fn add(&mut self, k: i64) {
        if let Some(c) = usize::try_from(k).ok().and_then(|k| self.counts.get_mut(k)) {
            *c = c.saturating_add(1);
        }
    }

    /// The day in `lo..=hi` (the fuzz range of an interval of `days`) the
    /// balancer places the item on, drawn by weight with `u` in [0, 1);
    /// `None` when the interval is too long to balance (then the fuzz
    /// draws uniformly).
    pub fn pick(&self, lo: i64, hi: i64, days: i64, u: f64) -> Option<i64> {
        if !balances(lo, hi, days) {
            return None;
        }
        let (lo_i, hi_i) = (usize::try_from(lo).ok()?, usize::try_from(hi).ok()?);
        let counts = &self.counts[lo_i..=hi_i];
        let shares = &self.shares[lo_i..=hi_i];
        let easy = easy_factors(counts, shares);
        let weights: Vec<f64> = counts
            .iter()
            .zip(easy)
            .zip(lo..=hi)
            .map(|((c, e), k)| {
                (1.0 / (f64::from(*c) + 1.0)).powf(2.15) * (1.0 / k as f64).powi(3) * e
            })
            .collect();
        let total: f64 = weights.iter().sum();
        if !(total.is_finite() && total > 0.0) {
            return None;
        }
        let target = u.clamp(0.0, 1.0) * total;
        let mut sum = 0.0;
        for (w, k) in weights.iter().zip(lo..=hi) {
            sum += w;
            if target < sum {
                return Some(k);
            }
        }
        Some(hi)
    }
}

/// Whether the balancer places an interval of `days` fuzzed into
/// `lo..=hi` (else the fuzz draws uniformly): the day it chose for an
/// answer, replayed, is taken only where this holds.
pub fn balances(lo: i64, hi: i64, days: i64) -> bool {
    days <= MAX_BALANCED && (1..=MAX_BALANCED).contains(&lo) && lo <= hi && hi < LOAD_DAYS as i64
}

/// The easy-day factor of each day of a range (see the module's text).
fn easy_factors(counts: &[u32], shares: &[f64]) -> Vec<f64> {
    let total: f64 = counts.iter().map(|c| f64::from(*c)).sum();
    let share_of = |p: f64| if p <= 0.0 { MINIMUM } else { p.min(1.0) };
    let total_share: f64 = shares.iter().map(|p| share_of(*p)).sum();
    counts
        .iter()
        .zip(shares)
        .map(|(c, p)| {
            if *p >= 1.0 {
                1.0
            } else if *p <= 0.0 {
                MINIMUM
            } else {
                let others = total - f64::from(*c);
                let others_share = total_share - p;
                if others_share <= 0.0 || f64::from(*c) / p <= others / others_share {
                    1.0
                } else {
                    MINIMUM
                }
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn day() -> NaiveDate {
        // A Monday.
        NaiveDate::from_ymd_opt(2026, 3, 2).unwrap()
    }

    #[test]
    fn an_empty_day_is_preferred_to_a_full_one() {
        let mut counts = vec![0u32; 20];
        for c in counts.iter_mut().take(13).skip(8) {
            *c = 30;
        }
        counts[10] = 0;
        let load = Load::new(counts, day(), &EasyDays::default());
        let picks: std::collections::BTreeMap<i64, usize> =
            (0..1000).fold(Default::default(), |mut m, i| {
                *m.entry(load.pick(8, 12, 10, i as f64 / 1000.0).unwrap())
                    .or_default() += 1;
                m
            });
        assert!(picks[&10] > 990, "{picks:?}");
    }

    #[test]
    fn equal_counts_lean_early_and_every_pick_is_in_range() {
        let load = Load::new(vec![5; LOAD_DAYS], day(), &EasyDays::default());
        let mut seen = Vec::new();
        for i in 0..1000 {
            let k = load.pick(27, 33, 30, i as f64 / 1000.0).unwrap();
            assert!((27..=33).contains(&k));
            seen.push(k);
        }
        let early = seen.iter().filter(|k| **k <= 29).count();
        let late = seen.iter().filter(|k| **k >= 31).count();
        assert!(early > late, "{early} vs {late}");
    }

    #[test]
    fn too_long_or_out_of_range_is_left_to_the_fuzz() {
        let load = Load::new(vec![1; LOAD_DAYS], day(), &EasyDays::default());
        assert_eq!(load.pick(95, 105, 100, 0.5), None);
        assert_eq!(load.pick(0, 2, 1, 0.5), None);
        assert_eq!(load.pick(90, 120, 90, 0.5), None);
    }

    #[test]
    fn a_day_set_to_zero_is_avoided() {
        // 2026-03-07 is a Saturday, 2026-03-08 a Sunday: 5 and 6 days on.
        let mut easy = EasyDays::default();
        easy.0[5] = 0.0;
        easy.0[6] = 0.0;
        let load = Load::new(vec![3; LOAD_DAYS], day(), &easy);
        for i in 0..200 {
            let k = load.pick(4, 8, 6, i as f64 / 200.0).unwrap();
            assert!(k != 5 && k != 6, "{k}");
        }
    }

    #[test]
    fn a_reduced_day_takes_items_only_while_under_its_share() {
        let mut easy = EasyDays::default();
        easy.0[5] = 0.5; // Saturday, 5 days on.
        let mut counts = vec![10; LOAD_DAYS];
        counts[5] = 4; // under half of 10: open
        let open = Load::new(counts.clone(), day(), &easy);
        assert!((0..100).any(|i| open.pick(4, 6, 5, i as f64 / 100.0) == Some(5)));
        counts[5] = 6; // over half: closed
        let closed = Load::new(counts, day(), &easy);
        assert!((0..100).all(|i| closed.pick(4, 6, 5, i as f64 / 100.0) != Some(5)));
    }
}
