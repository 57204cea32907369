//! Exam planning: how much of a deck will be remembered on an exam day, and
//! the fewest reviews, day by day, that bring every item to a target
//! retrievability on that day without exceeding a daily cap.
//!
//! Time is counted in whole study days: day 0 is today, the exam is on day
//! `days`, and reviews can be planned on days `0..days` (the exam day itself
//! is for the exam). An item's retrievability on the exam day is FSRS's
//! forgetting curve at the number of study days since its last review.
//! Every planned review is assumed answered Good, at most one per item per
//! day (a new item's learning steps belong to its one review of that day).
//!
//! The planner rests on two facts of the FSRS-6 memory model (unit tests
//! check both on a grid): a later single review leaves more on the exam day
//! (longer spacing grows stability more, and less time is left to forget),
//! and after a Good answer the stability is an increasing function of the
//! stability before. Answered Good, an item's difficulty depends only on
//! how many answers it has had, so the best way to spend `k` reviews on an
//! item is found by keeping, for each day, the highest stability `k`
//! reviews can leave on that day (dynamic programming). Items compete for
//! the days only through the cap: the planner places the items that need a
//! late review first, each on the earliest days that still reach the
//! target, so that the late days stay free for those that need them.

use crate::sched::States;

use chrono::{DateTime, NaiveDate, Utc};

use super::scheduler::Scheduler;
use super::types::{CardState, ItemKey, Rating};

/// The most reviews planned for one item: an item that needs more is
/// reported short rather than drilled.
pub(crate) const MAX_REVIEWS_PER_ITEM: usize = 8;

/// Multi-review schedules are searched over this many of the last free
/// days before the exam: earlier reviews are forgotten by then anyway, and
/// the search grows with the square of the days.
pub(crate) const SEARCH_WINDOW: usize = 64;

/// The longest planning horizon, in days.
pub const MAX_DAYS: i64 = 3650;

/// What an item's memory is today, in study days.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Memory {
    pub stability: f64,
    pub difficulty: f64,
    /// The study day of the last review, relative to today (0: today,
    /// negative: earlier).
    pub last_day: i64,
}

impl Memory {
    /// The memory a cached state holds (`None` for an item never reviewed),
    /// with `day_of` naming the study day of a time and `today` the current one.
    pub fn of(
        state: Option<&CardState>,
        today: NaiveDate,
        day_of: &dyn Fn(DateTime<Utc>) -> NaiveDate,
    ) -> Option<Memory> {
        let state = state?;
        match (state.stability, state.difficulty, state.last_review) {
            (Some(stability), Some(difficulty), Some(last)) => Some(Memory {
                stability,
                difficulty,
                last_day: (day_of(last) - today).num_days().min(0),
            }),
            _ => None,
        }
    }
}

/// What to plan: the items' memories, the days to the exam, the target and
/// the daily cap.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// One per item; `None` for an item never reviewed.
    pub items: Vec<Option<Memory>>,
    /// Days from today to the exam (0: the exam is today).
    pub days: i64,
    /// Retrievability every item should have on the exam day.
    pub target: f64,
    /// Most reviews planned on one day.
    pub cap: usize,
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlanError {
    #[error("the exam date {exam} is in the past (today is {today})")]
    ExamInPast { exam: NaiveDate, today: NaiveDate },
    #[error(
        "the exam date {exam} is more than {MAX_DAYS} days away (today is {today}); plan for a nearer date"
    )]
    ExamTooFar { exam: NaiveDate, today: NaiveDate },
    #[error("retention {0} is not between 0 and 1 (exclusive); example: 0.9")]
    Retention(f64),
    #[error("the daily cap must be at least 1 review")]
    Cap,
    #[error("{models} item models given for {items} items")]
    Items { items: usize, models: usize },
}

/// How one item is planned: the scheduler of its deck (its preset's FSRS
/// parameters, else the config's) and the recall it should reach on the
/// exam day (its preset's desired retention, unless the learner asked for
/// one target).
#[derive(Debug, Clone, Copy)]
pub struct ItemModel<'a> {
    pub scheduler: &'a Scheduler,
    pub target: f64,
}

/// The plan for one item.
#[derive(Debug, Clone, PartialEq)]
pub struct ItemPlan {
    /// Retrievability on the exam day with no more reviews.
    pub without: f64,
    /// Retrievability on the exam day after the planned reviews.
    pub with: f64,
    /// The days (0: today) of the planned reviews, ascending.
    pub reviews: Vec<i64>,
    /// The recall it should reach on the exam day.
    pub target: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    pub target: f64,
    pub cap: usize,
    /// Days from today to the exam.
    pub days: i64,
    /// In the order of the problem's items.
    pub items: Vec<ItemPlan>,
    /// Planned reviews on each day from today to the day before the exam.
    pub per_day: Vec<usize>,
}

impl Plan {
    /// Expected number of items recalled on the exam day with no more reviews.
    pub fn expected_without(&self) -> f64 {
        self.items.iter().map(|i| i.without).sum()
    }

    /// Expected number of items recalled on the exam day following the plan.
    pub fn expected_with(&self) -> f64 {
        self.items.iter().map(|i| i.with).sum()
    }

    /// Items the plan leaves below the target.
    pub fn shortfall(&self) -> usize {
        self.items.iter().filter(|i| i.with < i.target).count()
    }

    pub fn reviews(&self) -> usize {
        self.per_day.iter().sum()
    }

    /// The items to review on `day` (0: today), by index.
    pub fn due_on(&self, day: i64) -> Vec<usize> {
        (0..self.items.len())
            .filter(|&i| self.items[i].reviews.contains(&day))
            .collect()
    }
}

impl Problem {
    pub fn check(&self) -> Result<(), PlanError> {
        if !(self.target > 0.0 && self.target < 1.0) {
            return Err(PlanError::Retention(self.target));
        }
        if self.cap == 0 {
            return Err(PlanError::Cap);
        }
        Ok(())
    }
}

/// The days from `today` to `exam`, refused when the exam is past or too far.
pub fn days_to(today: NaiveDate, exam: NaiveDate) -> Result<i64, PlanError> {
    let days = (exam - today).num_days();
    if days < 0 {
        return Err(PlanError::ExamInPast { exam, today });
    }
    if days > MAX_DAYS {
        return Err(PlanError::ExamTooFar { exam, today });
    }
    Ok(days)
}

/// The memory model as the planner uses it: every answer Good.
pub struct Model<'a> {
    scheduler: &'a Scheduler,
    days: i64,
}

impl<'a> Model<'a> {
    pub fn new(scheduler: &'a Scheduler, days: i64) -> Model<'a> {
        Model { scheduler, days }
    }

    /// Retrievability on the exam day of an item last reviewed on `last_day`
    /// with `stability` left.
    pub(crate) fn on_exam(&self, stability: f64, last_day: i64) -> f64 {
        self.scheduler
            .forgetting_curve((self.days - last_day) as f64, stability)
    }

    /// Retrievability on the exam day with no more reviews (0 when new).
    pub fn without(&self, item: Option<&Memory>) -> f64 {
        item.map_or(0.0, |m| self.on_exam(m.stability, m.last_day))
    }

    /// Retrievability on the exam day after reviews on `days` (ascending).
    pub fn after(&self, item: Option<&Memory>, days: &[i64]) -> f64 {
        let mut memory = item.map(|m| (m.stability, m.difficulty));
        let mut last = item.map(|m| m.last_day);
        for &d in days {
            let gap = last.map_or(0, |l| (d - l).max(0));
            memory = Some(self.scheduler.next_memory(memory, gap, Rating::Good));
            last = Some(d);
        }
        match (memory, last) {
            (Some((s, _)), Some(l)) => self.on_exam(s, l),
            _ => 0.0,
        }
    }
}

/// The fewest reviews, at most `max_k`, on the days marked free, that bring
/// `item` to `target` on the exam day; among those, the schedule whose last
/// review is earliest. `None` when no such schedule exists.
fn cheapest(
    model: &Model,
    item: Option<&Memory>,
    free: &[bool],
    target: f64,
    max_k: usize,
) -> Option<Vec<i64>> {
    if model.without(item) >= target {
        return Some(Vec::new());
    }
    let all: Vec<i64> = (0..free.len() as i64)
        .filter(|&d| free[d as usize])
        .collect();
    // One review: the earliest free day that suffices.
    if let Some(&d) = all.iter().find(|&&d| model.after(item, &[d]) >= target) {
        return Some(vec![d]);
    }
    if max_k < 2 || all.len() < 2 {
        return None;
    }
    let days = &all[all.len().saturating_sub(SEARCH_WINDOW)..];
    let n = days.len();
    // best[i]: the highest stability the reviews so far can leave when the
    // last is on days[i], with the difficulty they leave (the same for
    // every day: Good answers move it by count, not by timing) and the
    // day of the previous review, to read the schedule back.
    type Cell = Option<(f64, f64, Option<usize>)>;
    let first = |d: i64| {
        let memory = item.map(|m| (m.stability, m.difficulty));
        let gap = item.map_or(0, |m| (d - m.last_day).max(0));
        model.scheduler.next_memory(memory, gap, Rating::Good)
    };
    let mut layers: Vec<Vec<Cell>> = vec![
        days.iter()
            .map(|&d| {
                let (s, diff) = first(d);
                Some((s, diff, None))
            })
            .collect(),
    ];
    for _ in 2..=max_k.min(n) {
        let prev = layers.last().map(Vec::as_slice).unwrap_or(&[]);
        let mut next: Vec<Cell> = vec![None; n];
        for b in 1..n {
            for a in 0..b {
                let Some((s, diff, _)) = prev[a] else {
                    continue;
                };
                let (s2, d2) =
                    model
                        .scheduler
                        .next_memory(Some((s, diff)), days[b] - days[a], Rating::Good);
                if next[b].is_none_or(|(best, _, _)| s2 > best) {
                    next[b] = Some((s2, d2, Some(a)));
                }
            }
        }
        let reached =
            (0..n).find(|&b| next[b].is_some_and(|(s, _, _)| model.on_exam(s, days[b]) >= target));
        layers.push(next);
        if let Some(b) = reached {
            let mut schedule = Vec::new();
            let mut at = Some(b);
            for layer in layers.iter().rev() {
                let Some(i) = at else { break };
                schedule.push(days[i]);
                at = layer[i].and_then(|(_, _, p)| p);
            }
            schedule.reverse();
            return Some(schedule);
        }
    }
    None
}

/// The most schedules tried for one item when the one the dynamic
/// programme finds would crowd out the single reviews already promised.
const ALTERNATIVES: usize = 2_000;

/// The most exchanges tried between an item left short and a promised
/// single review.
const REPAIRS: usize = 256;

/// Single reviews promised so far: each needs one free slot on or after its
/// earliest useful day. They are placed on days only at the end, so an item
/// that needs several reviews can still take a day one of them would have
/// had, as long as every promise can still be kept.
struct Singles {
    /// How many promised single reviews have each earliest useful day.
    earliest: Vec<usize>,
}

impl Singles {
    /// Whether every promise can be kept with `free` slots per day: each
    /// suffix of days has at least as many slots as promises that need it
    /// (Hall's condition; all windows end the day before the exam).
    fn fit(&self, free: &[usize]) -> bool {
        let (mut slots, mut need) = (0usize, 0usize);
        for d in (0..free.len()).rev() {
            slots += free[d];
            need += self.earliest[d];
            if need > slots {
                return false;
            }
        }
        true
    }
}

/// The plan: the fewest reviews that bring every item to the target on
/// the exam day within the daily cap; when the cap (or the time left) makes
/// that impossible, the items that cannot be brought there get no reviews
/// and are counted in [`Plan::shortfall`].
///
/// Items that one review suffices for are promised first (a single review
/// brings an item to the target more cheaply than any other), then those
/// that need several, fewest first, then the single-review items the cap
/// left out, with several earlier reviews if that gets them there. The
/// single reviews go on the latest days the cap leaves, so they count most.
pub fn plan(scheduler: &Scheduler, problem: &Problem) -> Result<Plan, PlanError> {
    let each = vec![
        ItemModel {
            scheduler,
            target: problem.target,
        };
        problem.items.len()
    ];
    plan_each(&each, problem)
}

/// [`plan`], each item with its own scheduler and target (`each[i]` for
/// `problem.items[i]`: an item of a deck with a preset is planned with that
/// preset's parameters and retention; `each` has one per item).
/// `problem.target` is the target shown beside the plan.
pub fn plan_each(each: &[ItemModel], problem: &Problem) -> Result<Plan, PlanError> {
    problem.check()?;
    for m in each {
        if !(m.target > 0.0 && m.target < 1.0) {
            return Err(PlanError::Retention(m.target));
        }
    }
    let n = problem.items.len();
    if each.len() != n {
        return Err(PlanError::Items {
            items: n,
            models: each.len(),
        });
    }
    let models: Vec<Model> = each
        .iter()
        .map(|m| Model::new(m.scheduler, problem.days))
        .collect();
    let targets: Vec<f64> = each.iter().map(|m| m.target).collect();
    let days = usize::try_from(problem.days).unwrap_or(0);

    // Each item alone, every day free.
    let alone: Vec<Option<Vec<i64>>> = problem
        .items
        .iter()
        .enumerate()
        .map(|(i, item)| {
            cheapest(
                &models[i],
                item.as_ref(),
                &vec![true; days],
                targets[i],
                MAX_REVIEWS_PER_ITEM,
            )
        })
        .collect();

    let mut free = vec![problem.cap; days];
    let mut singles = Singles {
        earliest: vec![0; days],
    };
    let mut single_of: Vec<Option<usize>> = vec![None; n];
    let mut schedules: Vec<Vec<i64>> = vec![Vec::new(); n];

    // Single reviews, the most flexible first: which ones fit does not
    // depend on the order (they form a matroid), but these leave the late
    // days to the items that need them.
    // When the cap leaves some out, it should be those that several
    // earlier reviews can still bring to the target most cheaply: each is
    // ranked by what that would cost (nothing can: most expensive).
    let mut by_earliest: Vec<(std::cmp::Reverse<usize>, usize, usize)> = alone
        .iter()
        .enumerate()
        .filter_map(|(i, s)| match s.as_deref() {
            Some([d]) => {
                let before: Vec<bool> = (0..days as i64).map(|e| e < *d).collect();
                let rescue = cheapest(
                    &models[i],
                    problem.items[i].as_ref(),
                    &before,
                    targets[i],
                    MAX_REVIEWS_PER_ITEM,
                )
                .map_or(usize::MAX, |s| s.len());
                Some((std::cmp::Reverse(rescue), *d as usize, i))
            }
            _ => None,
        })
        .collect();
    by_earliest.sort();
    let mut rescue_cost = vec![usize::MAX; n];
    for &(std::cmp::Reverse(cost), _, i) in &by_earliest {
        rescue_cost[i] = cost;
    }
    let mut left_out = Vec::new();
    for &(_, d, i) in &by_earliest {
        singles.earliest[d] += 1;
        if singles.fit(&free) {
            single_of[i] = Some(d);
        } else {
            singles.earliest[d] -= 1;
            left_out.push(i);
        }
    }

    // Items that need several reviews, fewest first, then those that must
    // end latest; then the single-review items left out above.
    let mut multi: Vec<(usize, std::cmp::Reverse<i64>, usize)> = alone
        .iter()
        .enumerate()
        .filter_map(|(i, s)| match s.as_deref() {
            Some(s) if s.len() > 1 => s.last().map(|&l| (s.len(), std::cmp::Reverse(l), i)),
            _ => None,
        })
        .collect();
    multi.sort();
    let order: Vec<usize> = multi
        .into_iter()
        .map(|(_, _, i)| i)
        .chain(left_out)
        .collect();
    for &i in &order {
        if let Some(schedule) = place(
            &models[i],
            problem.items[i].as_ref(),
            &free,
            &singles,
            targets[i],
        ) {
            for &d in &schedule {
                free[d as usize] -= 1;
            }
            schedules[i] = schedule;
        }
    }

    // One exchange at a time: an item still short may get there if a
    // promised single review gives up its day and that item is brought to
    // the target with several earlier reviews instead.
    let mut budget = REPAIRS;
    let promised = |s: &Singles| s.earliest.iter().sum::<usize>();
    for &x in &order {
        if !schedules[x].is_empty() {
            continue;
        }
        // An exchange frees one promised slot: if even all of them freed
        // would not make room for this item, no exchange will.
        let none = Singles {
            earliest: vec![0; days],
        };
        let Some(alone_here) = place(
            &models[x],
            problem.items[x].as_ref(),
            &free,
            &none,
            targets[x],
        ) else {
            continue;
        };
        if free.iter().sum::<usize>() < promised(&singles) + alone_here.len() {
            continue;
        }
        // Promised single reviews with the same earliest day free the same
        // room when they give it up: of each, only the one cheapest to
        // bring to the target another way is tried.
        let mut candidates: Vec<usize> = Vec::new();
        for y in (0..n).filter(|&y| single_of[y].is_some()) {
            match candidates
                .iter_mut()
                .find(|c| single_of[**c] == single_of[y])
            {
                Some(c) if rescue_cost[y] < rescue_cost[*c] => *c = y,
                Some(_) => {}
                None => candidates.push(y),
            }
        }
        for y in candidates {
            if budget == 0 {
                break;
            }
            budget -= 1;
            let Some(a) = single_of[y] else { continue };
            singles.earliest[a] -= 1;
            let then = |first: usize, first_free: &[usize], second: usize| {
                let s1 = place(
                    &models[first],
                    problem.items[first].as_ref(),
                    first_free,
                    &singles,
                    targets[first],
                )?;
                let mut after = free.clone();
                for &d in &s1 {
                    after[d as usize] -= 1;
                }
                let s2 = place(
                    &models[second],
                    problem.items[second].as_ref(),
                    &after,
                    &singles,
                    targets[second],
                )?;
                Some((s1, s2))
            };
            // The short item first; or the displaced one first, on the days
            // before its single review's (the days it gives up are the point).
            let before: Vec<usize> = free
                .iter()
                .enumerate()
                .map(|(d, &f)| if d < a { f } else { 0 })
                .collect();
            let swapped =
                then(x, &free, y).or_else(|| then(y, &before, x).map(|(sy, sx)| (sx, sy)));
            match swapped {
                Some((sx, sy)) => {
                    for &d in sx.iter().chain(&sy) {
                        free[d as usize] -= 1;
                    }
                    schedules[x] = sx;
                    schedules[y] = sy;
                    single_of[y] = None;
                    break;
                }
                None => singles.earliest[a] += 1,
            }
        }
    }

    // The promised single reviews, spread. Each may go on any day from its
    // earliest useful one to the day before the exam (a later review only
    // leaves more on the exam day), so the count of reviews is settled; of
    // the ways to place them, those with the smallest largest day's load
    // (the reviews already placed included) are kept, and among them each
    // day, from today on, takes as many as it may: reviews as early as the
    // lightest load allows.
    let used: Vec<usize> = free.iter().map(|f| problem.cap - f).collect();
    let level = spread_level(&used, &singles, problem.cap);
    let mut promised: Vec<(usize, usize)> = single_of
        .iter()
        .enumerate()
        .filter_map(|(i, d)| d.map(|d| (d, i)))
        .collect();
    promised.sort();
    let mut waiting = std::collections::VecDeque::new();
    let mut next = promised.into_iter().peekable();
    for d in 0..days {
        while let Some(&(earliest, i)) = next.peek() {
            if earliest > d {
                break;
            }
            waiting.push_back(i);
            next.next();
        }
        let room = level.saturating_sub(used[d]).min(free[d]);
        for _ in 0..room {
            let Some(i) = waiting.pop_front() else { break };
            free[d] -= 1;
            schedules[i] = vec![d as i64];
        }
    }
    debug_assert!(waiting.is_empty() && next.peek().is_none());

    let items = problem
        .items
        .iter()
        .zip(schedules)
        .enumerate()
        .map(|(i, (item, reviews))| ItemPlan {
            without: models[i].without(item.as_ref()),
            with: models[i].after(item.as_ref(), &reviews),
            reviews,
            target: targets[i],
        })
        .collect();
    Ok(Plan {
        target: problem.target,
        cap: problem.cap,
        days: problem.days,
        items,
        per_day: free.iter().map(|f| problem.cap - f).collect(),
    })
}

/// The smallest daily load, at most `cap`, at which the promised single
/// reviews all fit beside the reviews already `used` on each day: each
/// suffix of days has at least as many slots under that load as promises
/// that need it (Hall's condition, as [`Singles::fit`]). The promises were
/// kept within the cap, so `cap` always fits.
fn spread_level(used: &[usize], singles: &Singles, cap: usize) -> usize {
    let fits = |level: usize| {
        let room: Vec<usize> = used.iter().map(|u| level.saturating_sub(*u)).collect();
        singles.fit(&room)
    };
    let (mut lo, mut hi) = (used.iter().copied().max().unwrap_or(0), cap);
    if lo >= hi {
        return cap;
    }
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if fits(mid) { hi = mid } else { lo = mid + 1 }
    }
    lo
}

/// The fewest reviews on days with a slot left that bring `item` to the
/// target and keep every promised single review possible.
fn place(
    model: &Model,
    item: Option<&Memory>,
    free: &[usize],
    singles: &Singles,
    target: f64,
) -> Option<Vec<i64>> {
    let keeps = |schedule: &[i64]| {
        let mut after = free.to_vec();
        for &d in schedule {
            after[d as usize] -= 1;
        }
        singles.fit(&after)
    };
    let open: Vec<bool> = free.iter().map(|&f| f > 0).collect();
    let first = cheapest(model, item, &open, target, MAX_REVIEWS_PER_ITEM)?;
    // Where no day of it would be filled, nothing is crowded out.
    let roomy = first.iter().all(|&d| free[d as usize] > 1);
    if (first.len() < 2 || roomy) && keeps(&first) {
        return Some(first);
    }
    alternative(model, item, free, target, first.len(), &keeps)
        .or_else(|| keeps(&first).then_some(first))
}

/// Another schedule of `from` reviews or more on days with a slot left
/// that reaches the target and `keeps` the promises: the fewest reviews,
/// and among those the one on the least crowded days (the most slots left
/// on its fullest day, then in all), then the earliest last day. Tried exhaustively up
/// to [`ALTERNATIVES`] schedules.
fn alternative(
    model: &Model,
    item: Option<&Memory>,
    free: &[usize],
    target: f64,
    from: usize,
    keeps: &dyn Fn(&[i64]) -> bool,
) -> Option<Vec<i64>> {
    let all: Vec<i64> = (0..free.len() as i64)
        .filter(|&d| free[d as usize] > 0)
        .collect();
    let days = &all[all.len().saturating_sub(SEARCH_WINDOW)..];
    let score = |s: &[i64]| {
        let room = s.iter().map(|&d| free[d as usize]).min().unwrap_or(0);
        let total: usize = s.iter().map(|&d| free[d as usize]).sum();
        (
            std::cmp::Reverse(room),
            std::cmp::Reverse(total),
            s.last().copied(),
        )
    };
    let mut tried = 0usize;
    for k in from..=MAX_REVIEWS_PER_ITEM.min(days.len()) {
        let mut best: Option<Vec<i64>> = None;
        let mut pick = (0..k).collect::<Vec<usize>>();
        loop {
            tried += 1;
            if tried > ALTERNATIVES {
                return best;
            }
            let schedule: Vec<i64> = pick.iter().map(|&p| days[p]).collect();
            let better = best.as_ref().is_none_or(|b| score(&schedule) < score(b));
            if better && model.after(item, &schedule) >= target && keeps(&schedule) {
                best = Some(schedule);
            }
            // The next k-combination in lexicographic order.
            let Some(at) = (0..k).rev().find(|&j| pick[j] < days.len() - k + j) else {
                break;
            };
            pick[at] += 1;
            for j in at + 1..k {
                pick[j] = pick[j - 1] + 1;
            }
        }
        if best.is_some() {
            return best;
        }
    }
    None
}

/// The smallest daily cap with which the plan leaves no more items short
/// than it would with no cap at all (`None` when the cap is not what holds
/// the plan back).
pub fn cap_needed(scheduler: &Scheduler, problem: &Problem) -> Result<Option<usize>, PlanError> {
    let each = vec![
        ItemModel {
            scheduler,
            target: problem.target,
        };
        problem.items.len()
    ];
    cap_needed_each(&each, problem)
}

/// [`cap_needed`], each item with its own scheduler and target (see
/// [`plan_each`]).
pub fn cap_needed_each(each: &[ItemModel], problem: &Problem) -> Result<Option<usize>, PlanError> {
    let plan = |p: &Problem| plan_each(each, p);
    let with_cap = plan(problem)?;
    let unlimited = Problem {
        cap: problem.items.len().max(1),
        ..problem.clone()
    };
    let best = plan(&unlimited)?.shortfall();
    if with_cap.shortfall() <= best {
        return Ok(None);
    }
    let (mut lo, mut hi) = (problem.cap + 1, unlimited.cap);
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        let p = plan(&Problem {
            cap: mid,
            ..problem.clone()
        })?;
        if p.shortfall() <= best {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    Ok(Some(lo))
}

/// The memories of `keys` from the cached states, for a [`Problem`].
pub fn memories(
    keys: &[ItemKey],
    states: &States,
    today: NaiveDate,
    day_of: &dyn Fn(DateTime<Utc>) -> NaiveDate,
) -> Vec<Option<Memory>> {
    keys.iter()
        .map(|k| Memory::of(states.get(k), today, day_of))
        .collect()
}

/// The problem for `keys` with an exam on `exam`, checked.
#[allow(clippy::too_many_arguments)]
pub fn exam_problem(
    keys: &[ItemKey],
    states: &States,
    today: NaiveDate,
    exam: NaiveDate,
    day_of: &dyn Fn(DateTime<Utc>) -> NaiveDate,
    target: f64,
    cap: usize,
) -> Result<Problem, PlanError> {
    let problem = Problem {
        items: memories(keys, states, today, day_of),
        days: days_to(today, exam)?,
        target,
        cap,
    };
    problem.check()?;
    Ok(problem)
}
