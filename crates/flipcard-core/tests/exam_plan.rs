//! The exam planner against an exhaustive search over every review schedule
//! on small cases, with every schedule replayed through the scheduler
//! itself (card states, review times and all), not the planner's model.

use chrono::{DateTime, Duration, TimeZone, Utc};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

use flipcard_core::sched::plan::{self, Memory, Problem};
use flipcard_core::sched::{CardState, Config, Direction, ItemKey, Rating, Scheduler, State};

fn scheduler() -> Scheduler {
    Scheduler::new(&Config {
        fuzz: false,
        ..Config::default()
    })
}

/// Midnight UTC of study day `d` (0: today).
fn day(d: i64) -> DateTime<Utc> {
    Utc.with_ymd_and_hms(2026, 6, 1, 0, 0, 0).unwrap() + Duration::days(d)
}

fn key() -> ItemKey {
    ItemKey {
        deck: "d".into(),
        card: "c".into(),
        direction: Direction::Forward,
    }
}

/// Retrievability on exam day `days` after Good answers on `reviews`, by
/// the scheduler: the state a review log would hold, rated at midnight.
fn replay(s: &Scheduler, item: Option<&Memory>, reviews: &[i64], days: i64) -> f64 {
    let mut card = item.map(|m| CardState {
        state: State::Review,
        step: None,
        stability: Some(m.stability),
        difficulty: Some(m.difficulty),
        due: day(m.last_day),
        last_review: Some(day(m.last_day)),
    });
    for &d in reviews {
        card = Some(
            s.review(&key(), card.as_ref(), Rating::Good, day(d), 0)
                .after,
        );
    }
    card.map_or(0.0, |c| s.retrievability(&c, day(days)))
}

/// The best any schedule can do: most items at the target, then fewest
/// reviews. Every subset of the review days for every item, within the cap.
fn brute_force(s: &Scheduler, p: &Problem) -> (usize, usize) {
    let (met, reviews, _) = brute_force_load(s, p);
    (met, reviews)
}

/// [`brute_force`], and the smallest largest day's load of the schedules
/// that do that best.
fn brute_force_load(s: &Scheduler, p: &Problem) -> (usize, usize, usize) {
    let days = p.days as usize;
    let masks = 1usize << days;
    // reach[i][m]: whether item i reaches the target after reviews on mask m.
    let reach: Vec<Vec<bool>> = p
        .items
        .iter()
        .map(|item| {
            (0..masks)
                .map(|m| {
                    let reviews: Vec<i64> = (0..days as i64).filter(|d| m >> d & 1 == 1).collect();
                    replay(s, item.as_ref(), &reviews, p.days) >= p.target
                })
                .collect()
        })
        .collect();
    let mut best = (0usize, usize::MAX, usize::MAX);
    let mut load = vec![0usize; days];
    search(p, &reach, 0, &mut load, 0, 0, &mut best);
    best
}

fn search(
    p: &Problem,
    reach: &[Vec<bool>],
    i: usize,
    load: &mut [usize],
    met: usize,
    reviews: usize,
    best: &mut (usize, usize, usize),
) {
    if i == reach.len() {
        let most = load.iter().copied().max().unwrap_or(0);
        if (std::cmp::Reverse(met), reviews, most) < (std::cmp::Reverse(best.0), best.1, best.2) {
            *best = (met, reviews, most);
        }
        return;
    }
    for m in 0..reach[i].len() {
        let bits: Vec<usize> = (0..load.len()).filter(|d| m >> d & 1 == 1).collect();
        if bits.iter().any(|&d| load[d] >= p.cap) {
            continue;
        }
        for &d in &bits {
            load[d] += 1;
        }
        let ok = usize::from(reach[i][m]);
        search(p, reach, i + 1, load, met + ok, reviews + bits.len(), best);
        for &d in &bits {
            load[d] -= 1;
        }
    }
}

fn random_problem(rng: &mut StdRng) -> Problem {
    let n = rng.random_range(1..=4usize);
    let days = rng.random_range(0..=if n >= 4 { 4 } else { 5 });
    let items = (0..n)
        .map(|_| {
            (rng.random_range(0..4) != 0).then(|| Memory {
                stability: 0.05 * 1200f64.powf(rng.random_range(0.0..1.0)),
                difficulty: rng.random_range(1.0..10.0),
                last_day: -rng.random_range(0..=40),
            })
        })
        .collect();
    let targets = [0.8, 0.85, 0.9, 0.93, 0.95, 0.97, 0.99];
    Problem {
        items,
        days,
        target: targets[rng.random_range(0..targets.len())],
        cap: rng.random_range(1..=n),
    }
}

/// Checks that the plan keeps its promises (cap, days, the retrievability
/// it reports) and returns (items at the target, reviews).
fn checked(s: &Scheduler, p: &Problem, plan: &plan::Plan) -> (usize, usize) {
    assert_eq!(plan.per_day.len(), p.days as usize);
    assert!(plan.per_day.iter().all(|&l| l <= p.cap), "{plan:?}");
    let mut load = vec![0; p.days as usize];
    for (item, ip) in p.items.iter().zip(&plan.items) {
        assert!(ip.reviews.windows(2).all(|w| w[0] < w[1]), "{ip:?}");
        for &d in &ip.reviews {
            assert!((0..p.days).contains(&d), "{ip:?}");
            load[d as usize] += 1;
        }
        let real = replay(s, item.as_ref(), &ip.reviews, p.days);
        assert!((real - ip.with).abs() < 1e-12, "{real} vs {}", ip.with);
        let none = replay(s, item.as_ref(), &[], p.days);
        assert!((none - ip.without).abs() < 1e-12);
    }
    assert_eq!(load, plan.per_day);
    let met = plan.items.len() - plan.shortfall();
    (met, plan.reviews())
}

/// Without a binding cap (as many slots a day as items) every item is
/// planned alone, and the plan must be exactly optimal.
#[test]
fn without_a_binding_cap_the_plan_is_optimal() {
    let s = scheduler();
    let mut rng = StdRng::seed_from_u64(14);
    let (mut multi, mut heavier) = (0, 0);
    for _ in 0..1500 {
        let mut p = random_problem(&mut rng);
        p.cap = p.items.len();
        let plan = plan::plan(&s, &p).unwrap();
        let (met, reviews, least) = brute_force_load(&s, &p);
        assert_eq!(checked(&s, &p, &plan), (met, reviews), "{p:?}: {plan:?}");
        let most = plan.per_day.iter().copied().max().unwrap_or(0);
        assert!(most >= least, "{p:?}: {plan:?}");
        if most > least {
            heavier += 1;
        }
        multi += usize::from(plan.items.iter().any(|i| i.reviews.len() > 1));
    }
    // The single reviews are spread to the lightest largest load there is;
    // reviews of items that need several are placed before them, which in
    // a few cases leaves a day one review heavier than the best.
    eprintln!("{heavier} of 1500 plans have a heavier largest day than the lightest optimal plan");
    assert!(heavier * 100 <= 1500, "{heavier}");
    assert!(
        multi >= 100,
        "items that need several reviews are covered: {multi}"
    );
}

/// Under a binding cap the planner is a greedy with exchanges, not an
/// exhaustive search: on 20 000 cases of another seed it matched the
/// optimum in all but 6 (4 with one item fewer at the target, 2 with one
/// review more). Here: never better than the optimum (which would mean a
/// broken search or plan), never more than one item or review off, and
/// optimal in at least 99.8% of the cases.
#[test]
fn under_a_binding_cap_the_plan_is_optimal_in_nearly_every_case() {
    let s = scheduler();
    let mut rng = StdRng::seed_from_u64(2027);
    let (mut cases, mut off, mut short, mut multi) = (0, 0, 0, 0);
    while cases < 3000 {
        let p = random_problem(&mut rng);
        let unlimited = Problem {
            cap: p.items.len(),
            ..p.clone()
        };
        if plan::plan(&s, &unlimited).unwrap().reviews() == 0 || p.cap == p.items.len() {
            continue;
        }
        let plan = plan::plan(&s, &p).unwrap();
        let (met, reviews) = checked(&s, &p, &plan);
        let (best_met, best_reviews) = brute_force(&s, &p);
        assert!(met <= best_met, "{p:?}: {plan:?}");
        if met == best_met {
            assert!(reviews >= best_reviews, "{p:?}: {plan:?}");
            assert!(reviews <= best_reviews + 1, "{p:?}: {plan:?}");
        } else {
            assert_eq!(met + 1, best_met, "{p:?}: {plan:?}");
        }
        if (met, reviews) != (best_met, best_reviews) {
            eprintln!("not optimal: ({met}, {reviews}) vs ({best_met}, {best_reviews}) for {p:?}");
            off += 1;
        }
        cases += 1;
        short += usize::from(plan.shortfall() > 0);
        multi += usize::from(plan.items.iter().any(|i| i.reviews.len() > 1));
    }
    eprintln!(
        "{cases} capped cases: {off} not optimal, {short} short, {multi} with repeated reviews"
    );
    assert!(off * 500 <= cases, "{off} of {cases} not optimal");
    assert!(short >= 300 && multi >= 300, "{short} {multi}");
}

/// Cases an earlier, simpler greedy got wrong: the cap forces a choice of
/// which item gets the late day and which is brought to the target with
/// several earlier reviews.
#[test]
fn the_exchanges_that_make_the_difference() {
    let s = scheduler();
    let m = |stability, difficulty, last_day| {
        Some(Memory {
            stability,
            difficulty,
            last_day,
        })
    };
    let cases = [
        // A late single review for one, several early ones for the other.
        Problem {
            items: vec![None, m(1.0856466345198525, 2.6161215697234734, -17)],
            days: 5,
            target: 0.99,
            cap: 1,
        },
        Problem {
            items: vec![
                m(48.76686102984759, 4.967279909195083, -6),
                m(0.3072678601793248, 6.718645514907826, -22),
                m(0.7876636361042058, 3.4229902428213634, 0),
            ],
            days: 4,
            target: 0.97,
            cap: 1,
        },
        // Three new cards, two reviews each, six slots: spread them.
        Problem {
            items: vec![None, None, None],
            days: 3,
            target: 0.95,
            cap: 2,
        },
        Problem {
            items: vec![
                m(1.6960481214012093, 2.1393378998578996, -9),
                None,
                m(12.51452596869521, 7.00630648541102, -32),
                m(0.07223209991663694, 2.0966757895864108, -28),
            ],
            days: 2,
            target: 0.97,
            cap: 3,
        },
    ];
    for p in cases {
        let plan = plan::plan(&s, &p).unwrap();
        let best = brute_force(&s, &p);
        assert_eq!(checked(&s, &p, &plan), best, "{p:?}: {plan:?}");
        assert_eq!(plan.shortfall(), 0, "all reach the target: {plan:?}");
    }
}

/// The facts of the memory model the planner rests on, for the default
/// parameters: a later single review leaves more on the exam day, and a
/// higher stability before a Good answer leaves a higher one after.
#[test]
fn the_memory_model_is_monotone_where_the_planner_needs_it() {
    let s = scheduler();
    let model = plan::Model::new(&s, 30);
    for stability in [0.01, 0.1, 0.5, 1.0, 2.3, 10.0, 100.0] {
        for difficulty in [1.0, 5.0, 10.0] {
            for last_day in [-60, -5, 0] {
                let m = Memory {
                    stability,
                    difficulty,
                    last_day,
                };
                let r: Vec<f64> = (0..30).map(|d| model.after(Some(&m), &[d])).collect();
                assert!(r.windows(2).all(|w| w[0] <= w[1]), "{m:?}: {r:?}");
            }
            for gap in [0, 1, 3, 30] {
                let a = s
                    .next_memory(Some((stability, difficulty)), gap, Rating::Good)
                    .0;
                let b = s
                    .next_memory(Some((stability * 1.1, difficulty)), gap, Rating::Good)
                    .0;
                assert!(a <= b, "S={stability} D={difficulty} gap={gap}: {a} > {b}");
            }
        }
    }
    let new: Vec<f64> = (0..30).map(|d| model.after(None, &[d])).collect();
    assert!(new.windows(2).all(|w| w[0] <= w[1]), "{new:?}");
}

#[test]
fn bad_problems_are_refused() {
    let s = scheduler();
    let p = Problem {
        items: vec![None],
        days: 3,
        target: 0.9,
        cap: 1,
    };
    for target in [0.0, 1.0, -0.1, 1.5, f64::NAN, f64::INFINITY] {
        let bad = Problem {
            target,
            ..p.clone()
        };
        assert!(plan::plan(&s, &bad).is_err(), "{target}");
    }
    assert!(
        plan::plan(
            &s,
            &Problem {
                cap: 0,
                ..p.clone()
            }
        )
        .is_err()
    );
    let today = chrono::NaiveDate::from_ymd_opt(2026, 6, 1).unwrap();
    assert!(plan::days_to(today, today - Duration::days(1)).is_err());
    assert_eq!(plan::days_to(today, today), Ok(0));
    assert!(plan::days_to(today, today + Duration::days(plan::MAX_DAYS + 1)).is_err());
}

/// The shape of the collection: 202 cards two weeks before an
/// exam, each brought to the target by one review, with a cap of 200 a
/// day. Single reviews used to go on the latest days with room (200 on the
/// day before the exam, 2 the day before that); now the largest day's load
/// is the least any placement of the same reviews allows, and no review
/// sits later than a lighter earlier day it could have taken.
#[test]
fn a_202_card_plan_spreads_its_reviews() {
    let s = scheduler();
    let mut rng = StdRng::seed_from_u64(202);
    let items: Vec<Option<Memory>> = (0..202)
        .map(|_| {
            Some(Memory {
                stability: rng.random_range(2.0..15.0),
                difficulty: rng.random_range(3.0..8.0),
                last_day: -rng.random_range(1..=10),
            })
        })
        .collect();
    let p = Problem {
        items,
        days: 14,
        target: 0.9,
        cap: 200,
    };
    let plan = plan::plan(&s, &p).unwrap();
    checked(&s, &p, &plan);
    let model = plan::Model::new(&s, p.days);
    let days = p.days as usize;
    // Each item planned once, on or after the first day one review there
    // reaches the target.
    let mut singles = Vec::new();
    let mut other = vec![0usize; days];
    for (item, ip) in p.items.iter().zip(&plan.items) {
        match ip.reviews.as_slice() {
            [d] => {
                let earliest = (0..p.days)
                    .find(|&e| model.after(item.as_ref(), &[e]) >= p.target)
                    .unwrap();
                assert!(*d >= earliest);
                singles.push((earliest as usize, *d as usize));
            }
            more => more.iter().for_each(|&d| other[d as usize] += 1),
        }
    }
    assert!(singles.len() >= 150, "{} single reviews", singles.len());
    assert_eq!(plan.shortfall(), 0);

    // Before: each single review on the latest day with room, those that
    // need the latest days first.
    let mut before = other.clone();
    let mut by_latest: Vec<usize> = singles.iter().map(|(e, _)| *e).collect();
    by_latest.sort_by(|a, b| b.cmp(a));
    for e in by_latest {
        let d = (e..days).rev().find(|&d| before[d] < p.cap).unwrap();
        before[d] += 1;
    }
    // The least largest load: the smallest level at which every suffix of
    // days has room for the single reviews that must fall in it.
    let least = (0..=p.cap)
        .find(|&level| {
            (0..days).all(|d| {
                let room: usize = (d..days).map(|j| level.saturating_sub(other[j])).sum();
                let need = singles.iter().filter(|(e, _)| *e >= d).count();
                level >= other[d] && room >= need
            })
        })
        .unwrap();
    let most = *plan.per_day.iter().max().unwrap();
    eprintln!(
        "202 cards, 14 days, cap 200: largest day {} before, {most} now (least possible {least}); before {:?}, now {:?}",
        before.iter().max().unwrap(),
        before,
        plan.per_day
    );
    assert_eq!(most, least);
    assert!(*before.iter().max().unwrap() >= 150);
    // Earlier when equal: no single review after a day below the level
    // that it could have taken.
    for &(e, d) in &singles {
        for earlier in e..d {
            assert_eq!(
                plan.per_day[earlier], most,
                "day {earlier} had room for a review of day {d}"
            );
        }
    }
}

/// Items of decks with different presets: each planned with its own
/// scheduler and target. Without a binding cap every item is planned
/// alone, so each must get what a plan of it alone, with its own model
/// and target, gives; the retrievability reported is its own model's
/// replay; and with one model for all, the plan is the one-model plan.
#[test]
fn each_item_is_planned_with_its_own_model_and_target() {
    let plain = scheduler();
    let mut w = flipcard_core::sched::scheduler::default_parameters();
    w[20] = 0.5;
    w[8] = 1.2;
    let other = Scheduler::new(&Config {
        fuzz: false,
        fsrs_parameters: Some(w),
        ..Config::default()
    });
    let mut rng = StdRng::seed_from_u64(25);
    let mut differ = 0;
    for _ in 0..400 {
        let mut p = random_problem(&mut rng);
        p.cap = p.items.len();
        let each: Vec<plan::ItemModel> = (0..p.items.len())
            .map(|_| {
                let s = if rng.random_bool(0.5) { &plain } else { &other };
                let target = [0.8, 0.9, 0.95][rng.random_range(0..3)];
                plan::ItemModel {
                    scheduler: s,
                    target,
                }
            })
            .collect();
        let got = plan::plan_each(&each, &p).unwrap();
        let mut short = 0;
        for (i, (item, m)) in p.items.iter().zip(&each).enumerate() {
            let alone = Problem {
                items: vec![*item],
                target: m.target,
                cap: 1,
                ..p.clone()
            };
            let want = plan::plan(m.scheduler, &alone).unwrap();
            let ip = &got.items[i];
            assert_eq!(ip.target, m.target);
            assert_eq!(ip.reviews.len(), want.items[0].reviews.len(), "{p:?} {i}");
            let real = replay(m.scheduler, item.as_ref(), &ip.reviews, p.days);
            assert!((real - ip.with).abs() < 1e-12, "{real} vs {}", ip.with);
            short += usize::from(ip.with < m.target);
            if m.scheduler.forgetting_curve(3.0, 5.0) != plain.forgetting_curve(3.0, 5.0) {
                let as_plain = replay(&plain, item.as_ref(), &ip.reviews, p.days);
                differ += usize::from((as_plain - ip.with).abs() > 1e-6);
            }
        }
        assert_eq!(got.shortfall(), short);
        // One model for all: the one-model plan.
        let same: Vec<plan::ItemModel> = (0..p.items.len())
            .map(|_| plan::ItemModel {
                scheduler: &plain,
                target: p.target,
            })
            .collect();
        assert_eq!(
            plan::plan_each(&same, &p).unwrap(),
            plan::plan(&plain, &p).unwrap()
        );
    }
    assert!(differ > 50, "the models differ on the plans: {differ}");
    // A model per item, no fewer.
    let p = random_problem(&mut rng);
    assert!(plan::plan_each(&[], &p).is_err() || p.items.is_empty());
}
