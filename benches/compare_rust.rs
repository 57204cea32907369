//! flipcard's adaptive solver against `ode_solvers`' Dop853 (the same
//! Dormand–Prince 8(5,3) pair) on case (a): I = (1, 2, 3),
//! ω₀ = (0.01, 10, 0.01), t ∈ [0, 100], ω only, 1001 dense output points.
//!
//! The comparison is at equal error, not at equal tolerance (the two scale
//! their error norms differently): first both sweep their tolerance and the
//! error of ω over the 1001 points is measured against the exact solution;
//! the table goes to stderr. Then criterion times flipcard at tol 1e-10 and
//! ode_solvers at the loosest tolerance whose error is no worse.
//!
//!     cargo bench --bench compare_rust

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use flipcard::sim::rigid::exact::Exact;
use flipcard::sim::{Body, Method, Needs, make};
use nalgebra::Vector3;
use ode_solvers::{Dop853, System, Vector3 as OdeVector3};

const T_END: f64 = 100.0;
const POINTS: usize = 1001;
const FLIPCARD_TOL: f64 = 1e-10;

fn case_a() -> (Body, Vector3<f64>) {
    (
        Body::new([1.0, 2.0, 3.0]).expect("physical"),
        Vector3::new(0.01, 10.0, 0.01),
    )
}

fn times() -> Vec<f64> {
    (0..POINTS)
        .map(|k| T_END * k as f64 / (POINTS - 1) as f64)
        .collect()
}

fn flipcard_run(tol: f64) -> Vec<Vector3<f64>> {
    let (body, w0) = case_a();
    let mut solver = make(
        Method::Adaptive { tol },
        body,
        w0,
        Needs { orientation: false },
    )
    .expect("valid run");
    times()
        .into_iter()
        .map(|t| solver.advance(t).expect("within budget").omega)
        .collect()
}

/// Euler's equations for ode_solvers, with the same coefficients.
#[derive(Clone, Copy)]
struct Euler {
    a: [f64; 3],
}

impl System<f64, OdeVector3<f64>> for Euler {
    fn system(&self, _t: f64, w: &OdeVector3<f64>, dw: &mut OdeVector3<f64>) {
        dw[0] = self.a[0] * w[1] * w[2];
        dw[1] = self.a[1] * w[2] * w[0];
        dw[2] = self.a[2] * w[0] * w[1];
    }
}

fn ode_solvers_run(tol: f64) -> Vec<Vector3<f64>> {
    let (body, w0) = case_a();
    let i = body.inertia;
    let euler = Euler {
        a: [
            (i[1] - i[2]) / i[0],
            (i[2] - i[0]) / i[1],
            (i[0] - i[1]) / i[2],
        ],
    };
    let y0 = OdeVector3::new(w0[0], w0[1], w0[2]);
    let dx = T_END / (POINTS - 1) as f64;
    // Same error weights as flipcard: relative tol, absolute tol·|ω₀|.
    let mut stepper = Dop853::new(euler, 0.0, T_END, dx, y0, tol, tol * w0.norm());
    stepper
        .integrate()
        .expect("ode_solvers integrates case (a)");
    stepper
        .y_out()
        .iter()
        .map(|y| Vector3::new(y[0], y[1], y[2]))
        .collect()
}

/// Largest |ω − ω_exact| / |ω_exact| over the points.
fn error(omega: &[Vector3<f64>], exact: &[Vector3<f64>]) -> f64 {
    assert_eq!(omega.len(), exact.len(), "one value per output point");
    omega
        .iter()
        .zip(exact)
        .map(|(w, x)| (w - x).norm() / x.norm())
        .fold(0.0, f64::max)
}

/// Sweeps both tolerances, prints the errors, and returns the ode_solvers
/// tolerance that matches flipcard's error at tol 1e-10.
fn matched_tolerance() -> f64 {
    let (body, w0) = case_a();
    let exact = Exact::new(body, w0, Needs { orientation: false }).expect("exact");
    let reference: Vec<Vector3<f64>> = times().into_iter().map(|t| exact.omega_at(t)).collect();
    let target = error(&flipcard_run(FLIPCARD_TOL), &reference);
    eprintln!("case (a), omega only, error over {POINTS} points against the exact solution:");
    for e in 6..=13 {
        let tol = 10f64.powi(-e);
        eprintln!(
            "  tol {tol:.0e}: flipcard {:.2e}   ode_solvers {:.2e}",
            error(&flipcard_run(tol), &reference),
            error(&ode_solvers_run(tol), &reference)
        );
    }
    let mut tol = 1e-6;
    let mut matched = None;
    while tol >= 1e-14 {
        let e = error(&ode_solvers_run(tol), &reference);
        if e <= target {
            matched = Some((tol, e));
            break;
        }
        tol /= 10f64.powf(0.25);
    }
    let (tol, e) = matched.expect("ode_solvers reaches flipcard's error");
    eprintln!(
        "flipcard at tol {FLIPCARD_TOL:.0e}: error {target:.2e}; ode_solvers matches it at tol {tol:.2e} (error {e:.2e})"
    );
    let best = (0..50)
        .map(|_| {
            let start = Instant::now();
            black_box(flipcard_run(black_box(FLIPCARD_TOL)));
            start.elapsed()
        })
        .min()
        .unwrap_or_default();
    eprintln!(
        "for SciPy: python3 benches/compare_scipy.py --flipcard-ms {:.4} --flipcard-error {target:.3e}",
        best.as_secs_f64() * 1e3
    );
    tol
}

fn compare(c: &mut Criterion) {
    let ode_tol = matched_tolerance();
    let mut group = c.benchmark_group("case a, omega only, 1001 dense points");
    group.measurement_time(Duration::from_secs(4));
    group.bench_function("flipcard adaptive tol 1e-10", |b| {
        b.iter(|| flipcard_run(black_box(FLIPCARD_TOL)))
    });
    group.bench_function("ode_solvers Dop853 at equal error", |b| {
        b.iter(|| ode_solvers_run(black_box(ode_tol)))
    });
    group.finish();
}

criterion_group!(benches, compare);
criterion_main!(benches);
