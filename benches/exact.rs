//! Cost of one evaluation of the exact solution: ω(t) alone, and ω with the
//! orientation q(t), for the regimes the solver distinguishes, and the cost
//! of setting one up. Targets: ≤ 100 ns per ω(t), ≤ 1 µs per ω and q.
//!
//! Besides criterion's statistics (means, which grow when other processes
//! share the cores), a first table reports the minimum over many short
//! batches: the uncontended cost of an evaluation.

use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, criterion_group};
use flipcard::sim::rigid::exact::Exact;
use flipcard::sim::{Body, Needs};
use nalgebra::Vector3;

const CASES: &[(&str, [f64; 3], [f64; 3])] = &[
    ("generic", [1.0, 2.0, 2.5], [0.3, 1.0, -0.8]),
    ("smallest-axis", [2.5, 2.0, 1.0], [0.1, 0.4, 1.2]),
    ("notes-case", [1.0, 2.0, 3.0], [0.01, 10.0, 0.01]),
    (
        "near-separatrix-1e-12",
        [3.0, 4.0, 6.0],
        [2.0, 0.5, 1.0 + 1e-12],
    ),
    ("separatrix", [3.0, 4.0, 6.0], [2.0, 0.5, 1.0]),
    ("symmetric", [2.0, 2.0, 3.0], [0.7, -0.2, 1.5]),
    ("needle-1e6", [1e-6, 1.0, 1.0 + 5e-7], [1e-3, 0.4, 1.0]),
];

fn solver(inertia: [f64; 3], omega: [f64; 3]) -> Exact {
    Exact::new(
        Body::new(inertia).expect("valid body"),
        Vector3::from(omega),
        Needs { orientation: true },
    )
    .expect("valid state")
}

/// Times spread over many periods so no evaluation repeats the last one.
fn times(exact: &Exact) -> Vec<f64> {
    let span = exact.period().unwrap_or(10.0 / exact.rate().max(1e-3));
    (0..1024).map(|k| span * 37.0 * k as f64 / 1024.0).collect()
}

fn evaluation(c: &mut Criterion) {
    for &(name, inertia, omega) in CASES {
        let exact = solver(inertia, omega);
        let ts = times(&exact);
        let mut group = c.benchmark_group(format!("exact/{name}"));
        let mut i = 0usize;
        group.bench_function("omega", |b| {
            b.iter(|| {
                i = (i + 1) & 1023;
                exact.omega_at(black_box(ts[i]))
            })
        });
        let mut i = 0usize;
        group.bench_function("omega+q", |b| {
            b.iter(|| {
                i = (i + 1) & 1023;
                exact.state_at(black_box(ts[i]))
            })
        });
        group.finish();
    }
}

fn construction(c: &mut Criterion) {
    let mut group = c.benchmark_group("exact/new");
    for &(name, inertia, omega) in CASES {
        let body = Body::new(inertia).expect("valid body");
        let w = Vector3::from(omega);
        group.bench_function(format!("{name}/omega-only"), |b| {
            b.iter(|| Exact::new(black_box(body), black_box(w), Needs { orientation: false }))
        });
        group.bench_function(format!("{name}/with-q"), |b| {
            b.iter(|| Exact::new(black_box(body), black_box(w), Needs { orientation: true }))
        });
    }
    group.finish();
}

/// Minimum over `batches` batches of the mean time per call within a batch.
fn minimum_per_call(mut call: impl FnMut(usize) -> f64) -> f64 {
    const BATCH: usize = 2_000;
    let mut best = f64::INFINITY;
    let mut sink = 0.0;
    for _ in 0..400 {
        let start = Instant::now();
        for i in 0..BATCH {
            sink += call(i & 1023);
        }
        best = best.min(start.elapsed().as_secs_f64() / BATCH as f64);
    }
    black_box(sink);
    best
}

fn minimum_report() {
    println!("exact solver, minimum over 400 batches of 2000 calls (ns per call):");
    println!("{:>24} {:>8} {:>8}", "case", "omega", "omega+q");
    for &(name, inertia, omega) in CASES {
        let exact = solver(inertia, omega);
        let ts = times(&exact);
        let w = minimum_per_call(|i| exact.omega_at(black_box(ts[i]))[0]);
        let q = minimum_per_call(|i| exact.state_at(black_box(ts[i])).q.w);
        println!("{name:>24} {:>8.1} {:>8.1}", w * 1e9, q * 1e9);
    }
}

criterion_group!(benches, evaluation, construction);

fn main() {
    minimum_report();
    benches();
    Criterion::default().configure_from_args().final_summary();
}
