//! Building the day's queue over 100,000 review items (target ≤ 50 ms), and
//! the per-answer costs of the scheduler and the queue.

use std::hint::black_box;

use chrono::{DateTime, FixedOffset, TimeDelta, TimeZone, Utc};
use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use flipcard::sched::{
    CardState, Config, Direction, DoneToday, ItemKey, Queue, Rating, Scheduler, State, States,
};

const ITEMS: usize = 100_000;

/// A deck of 100,000 items: 60 % in review with due dates spread over two
/// months either side of now, 5 % (re)learning, 35 % never seen.
fn collection(now: DateTime<Utc>) -> (Vec<ItemKey>, States) {
    let mut items = Vec::with_capacity(ITEMS);
    let mut states = States::with_capacity_and_hasher(ITEMS, Default::default());
    // A fixed linear congruential sequence: the same collection every run.
    let mut x: u64 = 0x2545_f491_4f6c_dd1d;
    let mut next = || {
        x = x
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        x >> 33
    };
    for i in 0..ITEMS {
        let key = ItemKey {
            deck: "bench".into(),
            card: format!("card-{:06}", i / 2),
            direction: if i % 2 == 0 {
                Direction::Forward
            } else {
                Direction::Backward
            },
        };
        let roll = next() % 100;
        let offset = TimeDelta::minutes((next() % (120 * 24 * 60)) as i64 - 60 * 24 * 60);
        let state = match roll {
            0..60 => Some(State::Review),
            60..63 => Some(State::Learning),
            63..65 => Some(State::Relearning),
            _ => None,
        };
        if let Some(state) = state {
            let learning = state != State::Review;
            let due = if learning {
                now + offset / (24 * 60)
            } else {
                now + offset
            };
            states.insert(
                key.clone(),
                CardState {
                    state,
                    step: learning.then_some(0),
                    stability: Some(10.0),
                    difficulty: Some(5.0),
                    due,
                    last_review: Some(due - TimeDelta::days(10)),
                },
            );
        }
        items.push(key);
    }
    (items, states)
}

fn bench(c: &mut Criterion) {
    let now = Utc.with_ymd_and_hms(2026, 3, 10, 6, 30, 0).unwrap();
    let (items, states) = collection(now);
    let config = Config::default();
    let ist = FixedOffset::east_opt(5 * 3600 + 1800).unwrap();
    let done = DoneToday {
        new: 3,
        reviews: 40,
    };

    c.bench_function("queue build, 100k items", |b| {
        b.iter(|| {
            Queue::build(
                black_box(&items),
                black_box(&states),
                done,
                now,
                &config,
                &ist,
            )
        })
    });
    c.bench_function("queue build_local, 100k items", |b| {
        b.iter(|| Queue::build_local(black_box(&items), black_box(&states), done, now, &config))
    });

    let scheduler = Scheduler::new(&config);
    let card = states.values().next().copied();
    c.bench_function("scheduler review + queue answered", |b| {
        let queue = Queue::build(&items, &states, done, now, &config, &ist);
        b.iter_batched_ref(
            || queue.clone(),
            |q| {
                let key = q.next(now).map(|(k, _)| k.clone());
                if let Some(key) = key {
                    let rec = scheduler.review(&key, card.as_ref(), Rating::Good, now, 0);
                    q.answered(black_box(&rec));
                }
            },
            BatchSize::SmallInput,
        )
    });
    c.bench_function("scheduler preview", |b| {
        b.iter(|| scheduler.preview(black_box(&items[0]), card.as_ref(), now))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
