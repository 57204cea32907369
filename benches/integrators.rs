//! Run time of the step-based solvers on the notes' case (a):
//! I = (1, 2, 3), ω₀ = (0.01, 10, 0.01), t ∈ [0, 100] (about 36 flips).
//! Each iteration builds the solver and runs the whole span.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use flipcard::sim::{Body, Method, Needs, make};
use nalgebra::Vector3;

const T_END: f64 = 100.0;

fn case_a() -> (Body, Vector3<f64>) {
    (
        Body::new([1.0, 2.0, 3.0]).expect("physical"),
        Vector3::new(0.01, 10.0, 0.01),
    )
}

/// Runs [0, T_END] and returns the final ω₁ (so nothing is optimised away).
fn run(method: Method, orientation: bool, samples: usize) -> f64 {
    let (body, w0) = case_a();
    let mut solver = make(method, body, w0, Needs { orientation }).expect("valid run");
    let mut last = 0.0;
    for k in 1..=samples {
        let t = T_END * k as f64 / samples as f64;
        last = solver.advance(black_box(t)).expect("within budget").omega[0];
    }
    last
}

fn adaptive(c: &mut Criterion) {
    let tol = Method::Adaptive { tol: 1e-10 };
    c.bench_function("adaptive tol 1e-10, case a, omega only", |b| {
        b.iter(|| run(black_box(tol), false, 1))
    });
    c.bench_function("adaptive tol 1e-10, case a, omega and q", |b| {
        b.iter(|| run(black_box(tol), true, 1))
    });
    c.bench_function("adaptive tol 1e-10, case a, omega only, 101 samples", |b| {
        b.iter(|| run(black_box(tol), false, 101))
    });
}

fn fixed_step(c: &mut Criterion) {
    for (name, method) in [
        ("rk4 dt 1e-3", Method::Rk4 { dt: 1e-3 }),
        ("splitting dt 1e-3", Method::Splitting { dt: 1e-3 }),
        ("splitting4 dt 1e-3", Method::Splitting4 { dt: 1e-3 }),
    ] {
        c.bench_function(&format!("{name}, case a, omega only"), |b| {
            b.iter(|| run(black_box(method), false, 1))
        });
        c.bench_function(&format!("{name}, case a, omega and q"), |b| {
            b.iter(|| run(black_box(method), true, 1))
        });
    }
}

criterion_group!(benches, adaptive, fixed_step);
criterion_main!(benches);
