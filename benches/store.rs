//! Store benchmarks: a rating committed to disk (fsync included), the reads
//! the daily queue makes, statistics and opening over a 1,000,000-review log.
//!
//! Targets: a rating committed ≤ 5 ms at the median; stats over 1,000,000
//! reviews ≤ 200 ms.

use std::hint::black_box;

use chrono::{DateTime, Duration, NaiveTime, Utc};
use criterion::{Criterion, criterion_group, criterion_main};
use flipcard::sched::DayGrid;
use flipcard::sched::{CardState, Direction, ItemKey, Rating, ReviewKind, ReviewRecord, State};
use flipcard::store::stats::StatsScope;
use flipcard::store::{OpenOptions, Store};

const CARDS: usize = 5_000;
const REVIEWS: usize = 1_000_000;

fn items(deck: &str) -> Vec<ItemKey> {
    (0..CARDS)
        .flat_map(|i| {
            [Direction::Forward, Direction::Backward].map(|direction| ItemKey {
                deck: deck.to_string(),
                card: format!("card-{i:05}"),
                direction,
            })
        })
        .collect()
}

fn rating(key: &ItemKey, when: DateTime<Utc>, n: usize) -> ReviewRecord {
    let rating = Rating::ALL[[2, 2, 2, 0, 1, 2, 3, 2, 2, 2][n % 10]];
    let state = if rating == Rating::Again {
        State::Relearning
    } else {
        State::Review
    };
    ReviewRecord {
        key: key.clone(),
        reviewed_at: when,
        rating,
        kind: if n.is_multiple_of(17) {
            ReviewKind::Learn
        } else {
            ReviewKind::Review
        },
        elapsed_days: (n % 30) as i64,
        scheduled_days: (n % 45) as i64,
        after: CardState {
            state,
            step: (state == State::Relearning).then_some(0),
            stability: Some(1.0 + (n % 97) as f64),
            difficulty: Some(1.0 + (n % 9) as f64),
            due: when + Duration::hours((n % 1_000) as i64),
            last_review: Some(when),
        },
        duration_ms: 2_000 + (n % 5_000) as i64,
        balanced_days: None,
    }
}

fn now() -> DateTime<Utc> {
    DateTime::parse_from_rfc3339("2026-06-01T12:00:00Z")
        .map(|t| t.with_timezone(&Utc))
        .unwrap_or_else(|_| Utc::now())
}

fn no_backup() -> OpenOptions {
    OpenOptions {
        daily_backup: false,
        ..OpenOptions::default()
    }
}

fn record_committed(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut store = Store::open_with(dir.path(), &no_backup()).expect("open");
    let keys = items("bench");
    let start = now();
    let mut n = 0usize;
    c.bench_function("record: one rating committed (fsync)", |b| {
        b.iter(|| {
            n += 1;
            let r = rating(
                &keys[n % keys.len()],
                start + Duration::seconds(n as i64),
                n,
            );
            black_box(store.record(&r).expect("record"))
        })
    });
    c.bench_function("undo_last: one rating reverted (fsync)", |b| {
        b.iter(|| black_box(store.undo_last().expect("undo")))
    });
}

/// 1,000,000 ratings over 10,000 items, spread over the two years before now.
fn big_store(dir: &std::path::Path) -> Store {
    let mut store = Store::open_with(dir, &no_backup()).expect("open");
    let keys = items("bench");
    let span_ms = 2 * 365 * 86_400_000i64;
    let first = now() - Duration::milliseconds(span_ms);
    let step = span_ms / REVIEWS as i64;
    let mut batch = Vec::with_capacity(50_000);
    for n in 0..REVIEWS {
        let when = first + Duration::milliseconds(step * n as i64);
        batch.push(rating(&keys[(n * 7_919) % keys.len()], when, n));
        if batch.len() == batch.capacity() {
            store.record_batch(&batch).expect("batch");
            batch.clear();
        }
    }
    store.record_batch(&batch).expect("batch");
    store
}

fn over_a_million_reviews(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temp dir");
    let store = big_store(dir.path());
    let keys = items("bench");
    let grid = DayGrid::new(
        chrono::Local,
        NaiveTime::from_hms_opt(4, 0, 0).expect("time"),
    );
    let at = now();
    let mut g = c.benchmark_group("1M reviews");
    g.sample_size(20);
    g.bench_function("stats (one deck)", |b| {
        b.iter(|| {
            let scope = StatsScope {
                deck: Some("bench"),
                items: &keys,
            };
            black_box(store.stats(scope, at, &grid).expect("stats"))
        })
    });
    g.bench_function("stats (all decks)", |b| {
        b.iter(|| {
            let scope = StatsScope {
                deck: None,
                items: &keys,
            };
            black_box(store.stats(scope, at, &grid).expect("stats"))
        })
    });
    g.bench_function("states (10,000 items)", |b| {
        b.iter(|| black_box(store.states("bench").expect("states")))
    });
    g.bench_function("reviews_today", |b| {
        b.iter(|| {
            black_box(
                store
                    .reviews_today("bench", at - Duration::hours(8))
                    .expect("today"),
            )
        })
    });
    g.bench_function("due_per_day (the load balancer's 100 days)", |b| {
        b.iter(|| {
            black_box(
                store
                    .due_per_day(at - Duration::hours(8), 100)
                    .expect("due per day"),
            )
        })
    });
    g.bench_function("last_studied", |b| {
        b.iter(|| black_box(store.last_studied("bench").expect("last")))
    });
    drop(store);
    g.bench_function("open (checks made on every open)", |b| {
        b.iter(|| black_box(Store::open_with(dir.path(), &no_backup()).expect("open")))
    });
    g.finish();
}

criterion_group!(benches, record_committed, over_a_million_reviews);
criterion_main!(benches);
