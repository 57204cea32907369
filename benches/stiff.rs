//! flipcard's Radau IIA against diffsol's BDF on two stiff problems, at
//! equal error:
//!
//! - Van der Pol, x'' − μ(1 − x²)x' + x = 0, μ = 1000, (x, v)(0) = (2, 0),
//!   t ∈ [0, 3000] (two relaxation jumps);
//! - Robertson's kinetics, y(0) = (1, 0, 0), t ∈ [0, 10¹¹].
//!
//! Both solvers get the analytic Jacobian (diffsol as Jacobian-vector
//! products, from which it assembles the dense matrix) and the same
//! tolerances: rtol, with atol = rtol for Van der Pol and
//! atol = rtol·(10⁻⁴, 10⁻¹⁰, 10⁻⁴) for Robertson (y₂ lives near 10⁻¹³ late
//! in the run). The error of a run is the largest relative error of a
//! component of the final state against a reference from flipcard's Radau
//! at rtol 1e-12 (checked against diffsol at rtol 1e-11).
//!
//! First both solvers sweep their tolerance; a table of error, time
//! (best of several runs) and steps goes to stderr, then the time of each
//! at the error flipcard's Radau reaches at rtol 1e-6 (diffsol's read off
//! its sweep by log-log interpolation). Then criterion times Radau at
//! rtol 1e-6 and diffsol at the loosest tolerance of a fine sweep whose
//! error is no worse. The last lines give the arguments for
//! `benches/compare_scipy_stiff.py`.
//!
//!     cargo bench --bench stiff

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use diffsol::{NalgebraLU, NalgebraMat, OdeBuilder, OdeSolverMethod, OdeSolverStopReason};
use flipcard::sim::solvers::ode::{Atol, OdeSolver, OdeSystem, Options, Radau5};
use nalgebra::DMatrix;

const MU: f64 = 1000.0;
const VDP_END: f64 = 3000.0;
const ROB_END: f64 = 1e11;
const RADAU_RTOL: f64 = 1e-6;

struct VanDerPol;

impl OdeSystem for VanDerPol {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = MU * (1.0 - y[0] * y[0]) * y[1] - y[0];
    }
    fn jacobian(&self, _t: f64, y: &[f64], jac: &mut DMatrix<f64>) {
        jac[(0, 0)] = 0.0;
        jac[(0, 1)] = 1.0;
        jac[(1, 0)] = -2.0 * MU * y[0] * y[1] - 1.0;
        jac[(1, 1)] = MU * (1.0 - y[0] * y[0]);
    }
}

struct Robertson;

impl OdeSystem for Robertson {
    fn dim(&self) -> usize {
        3
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = -0.04 * y[0] + 1e4 * y[1] * y[2];
        dy[1] = 0.04 * y[0] - 1e4 * y[1] * y[2] - 3e7 * y[1] * y[1];
        dy[2] = 3e7 * y[1] * y[1];
    }
    fn jacobian(&self, _t: f64, y: &[f64], jac: &mut DMatrix<f64>) {
        jac[(0, 0)] = -0.04;
        jac[(0, 1)] = 1e4 * y[2];
        jac[(0, 2)] = 1e4 * y[1];
        jac[(1, 0)] = 0.04;
        jac[(1, 1)] = -1e4 * y[2] - 6e7 * y[1];
        jac[(1, 2)] = -1e4 * y[1];
        jac[(2, 0)] = 0.0;
        jac[(2, 1)] = 6e7 * y[1];
        jac[(2, 2)] = 0.0;
    }
}

#[derive(Clone, Copy, PartialEq)]
enum Problem {
    VanDerPol,
    Robertson,
}

impl Problem {
    fn name(self) -> &'static str {
        match self {
            Problem::VanDerPol => "van der pol",
            Problem::Robertson => "robertson",
        }
    }
    fn atol(self, rtol: f64) -> Vec<f64> {
        match self {
            Problem::VanDerPol => vec![rtol; 2],
            Problem::Robertson => vec![rtol * 1e-4, rtol * 1e-10, rtol * 1e-4],
        }
    }
}

/// Final state and step count of flipcard's Radau IIA.
fn radau(p: Problem, rtol: f64) -> (Vec<f64>, u64) {
    let opts = Options {
        rtol,
        atol: Atol::PerComponent(p.atol(rtol)),
        t_stop: Some(match p {
            Problem::VanDerPol => VDP_END,
            Problem::Robertson => ROB_END,
        }),
        ..Options::default()
    };
    let (y, steps) = match p {
        Problem::VanDerPol => {
            let mut s = Radau5::new(VanDerPol, 0.0, &[2.0, 0.0], &opts).expect("valid");
            let y = s.advance(VDP_END).expect("runs").to_vec();
            (y, s.work().steps)
        }
        Problem::Robertson => {
            let mut s = Radau5::new(Robertson, 0.0, &[1.0, 0.0, 0.0], &opts).expect("valid");
            let y = s.advance(ROB_END).expect("runs").to_vec();
            (y, s.work().steps)
        }
    };
    (y, steps)
}

/// Final state and step count of diffsol's BDF (nalgebra, dense LU).
fn diffsol_bdf(p: Problem, rtol: f64) -> (Vec<f64>, u64) {
    type M = NalgebraMat<f64>;
    let atol = p.atol(rtol);
    macro_rules! run {
        ($problem:expr, $n:expr, $end:expr) => {{
            let problem = $problem;
            let mut solver = problem.bdf::<NalgebraLU<f64>>().expect("bdf");
            solver.set_stop_time($end).expect("stop time");
            loop {
                match solver.step() {
                    Ok(OdeSolverStopReason::TstopReached) => break,
                    Ok(_) => {}
                    Err(e) => panic!("diffsol: {e}"),
                }
            }
            let y = &solver.state().y;
            let out: Vec<f64> = (0..$n).map(|i| y[i]).collect();
            (out, solver.get_statistics().number_of_steps as u64)
        }};
    }
    match p {
        Problem::VanDerPol => run!(
            OdeBuilder::<M>::new()
                .rtol(rtol)
                .atol(atol)
                .rhs_implicit(
                    |x: &[f64], _p: &[f64], _t: f64, y: &mut [f64]| {
                        y[0] = x[1];
                        y[1] = MU * (1.0 - x[0] * x[0]) * x[1] - x[0];
                    },
                    |x: &[f64], _p: &[f64], _t: f64, v: &[f64], y: &mut [f64]| {
                        y[0] = v[1];
                        y[1] = (-2.0 * MU * x[0] * x[1] - 1.0) * v[0]
                            + MU * (1.0 - x[0] * x[0]) * v[1];
                    },
                )
                .init(
                    |_p: &[f64], _t: f64, y: &mut [f64]| {
                        y[0] = 2.0;
                        y[1] = 0.0;
                    },
                    2,
                )
                .build()
                .expect("problem"),
            2,
            VDP_END
        ),
        Problem::Robertson => run!(
            OdeBuilder::<M>::new()
                .rtol(rtol)
                .atol(atol)
                .rhs_implicit(
                    |x: &[f64], _p: &[f64], _t: f64, y: &mut [f64]| {
                        y[0] = -0.04 * x[0] + 1e4 * x[1] * x[2];
                        y[1] = 0.04 * x[0] - 1e4 * x[1] * x[2] - 3e7 * x[1] * x[1];
                        y[2] = 3e7 * x[1] * x[1];
                    },
                    |x: &[f64], _p: &[f64], _t: f64, v: &[f64], y: &mut [f64]| {
                        y[0] = -0.04 * v[0] + 1e4 * v[1] * x[2] + 1e4 * x[1] * v[2];
                        y[1] =
                            0.04 * v[0] - 1e4 * v[1] * x[2] - 1e4 * x[1] * v[2] - 6e7 * x[1] * v[1];
                        y[2] = 6e7 * x[1] * v[1];
                    },
                )
                .init(
                    |_p: &[f64], _t: f64, y: &mut [f64]| {
                        y[0] = 1.0;
                        y[1] = 0.0;
                        y[2] = 0.0;
                    },
                    3,
                )
                .build()
                .expect("problem"),
            3,
            ROB_END
        ),
    }
}

fn max_rel_error(y: &[f64], reference: &[f64]) -> f64 {
    y.iter()
        .zip(reference)
        .map(|(a, b)| (a - b).abs() / b.abs())
        .fold(0.0, f64::max)
}

/// Best wall time of `f` over enough repetitions to fill ~0.3 s (at least 3).
fn best_time(mut f: impl FnMut()) -> Duration {
    let mut best = Duration::MAX;
    let start = Instant::now();
    let mut runs = 0;
    while runs < 3 || (start.elapsed() < Duration::from_millis(300) && runs < 1000) {
        let t = Instant::now();
        f();
        best = best.min(t.elapsed());
        runs += 1;
    }
    best
}

type Solve = fn(Problem, f64) -> (Vec<f64>, u64);

/// (rtol, error, seconds, steps) along a tolerance sweep.
fn sweep(p: Problem, solve: Solve, reference: &[f64], rtols: &[f64]) -> Vec<(f64, f64, f64, u64)> {
    rtols
        .iter()
        .map(|&rtol| {
            let (y, steps) = solve(p, rtol);
            let err = max_rel_error(&y, reference);
            let secs = best_time(|| {
                black_box(solve(p, black_box(rtol)));
            })
            .as_secs_f64();
            (rtol, err, secs, steps)
        })
        .collect()
}

/// Time at `error` by log-log interpolation along a sweep (errors are
/// made monotone first, keeping the best error reached so far); None
/// outside the sweep's range.
fn time_at_error(points: &[(f64, f64, f64, u64)], error: f64) -> Option<f64> {
    let mut pts: Vec<(f64, f64)> = points.iter().map(|p| (p.1, p.2)).collect();
    pts.sort_by(|a, b| b.0.total_cmp(&a.0));
    for w in pts.windows(2) {
        let ((e0, t0), (e1, t1)) = (w[0], w[1]);
        if error <= e0 && error >= e1 && e0 > e1 {
            let x = (error.ln() - e0.ln()) / (e1.ln() - e0.ln());
            return Some((t0.ln() + x * (t1.ln() - t0.ln())).exp());
        }
    }
    None
}

fn decades(from: i32, to: i32, per_decade: i32) -> Vec<f64> {
    (from * per_decade..=to * per_decade)
        .map(|k| 10f64.powf(-(k as f64) / per_decade as f64))
        .collect()
}

/// The comparison table, and diffsol's loosest rtol matching Radau's error.
fn compare(p: Problem) -> (f64, f64) {
    let (reference, _) = radau(p, 1e-12);
    let (check, _) = diffsol_bdf(p, 1e-11);
    eprintln!(
        "\n{}: reference (radau rtol 1e-12) {reference:?}; diffsol bdf at rtol 1e-11 differs by {:.1e}",
        p.name(),
        max_rel_error(&check, &reference)
    );
    let rtols = decades(4, 9, 1);
    let ours = sweep(p, radau, &reference, &rtols);
    let theirs = sweep(p, diffsol_bdf, &reference, &decades(4, 10, 1));
    eprintln!("  method        rtol     error      time        steps");
    for (name, rows) in [("radau5", &ours), ("diffsol bdf", &theirs)] {
        for (rtol, err, secs, steps) in rows.iter() {
            eprintln!(
                "  {name:<12} {rtol:>7.0e}  {err:>9.2e}  {:>9.1} µs  {steps:>6}",
                secs * 1e6
            );
        }
    }
    let (y, _) = radau(p, RADAU_RTOL);
    let err = max_rel_error(&y, &reference);
    let our_time = time_at_error(&ours, err).unwrap_or(f64::NAN);
    match time_at_error(&theirs, err) {
        Some(t) => eprintln!(
            "  at radau's error {err:.2e} (rtol {RADAU_RTOL:e}): radau {:.1} µs, diffsol bdf {:.1} µs (ratio {:.2})",
            our_time * 1e6,
            t * 1e6,
            t / our_time
        ),
        None => eprintln!("  diffsol's sweep does not reach radau's error {err:.2e}"),
    }
    // The loosest rtol of a fine sweep whose error is no worse.
    let matched = decades(3, 12, 8)
        .into_iter()
        .find(|&r| max_rel_error(&diffsol_bdf(p, r).0, &reference) <= err)
        .unwrap_or(1e-12);
    let radau_secs = best_time(|| {
        black_box(radau(p, RADAU_RTOL));
    });
    eprintln!(
        "  for compare_scipy_stiff.py: --{}-ms {:.4} --{}-error {err:.3e}",
        p.name().replace(' ', "-"),
        radau_secs.as_secs_f64() * 1e3,
        p.name().replace(' ', "-"),
    );
    (matched, err)
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("stiff");
    group.measurement_time(Duration::from_secs(4));
    for p in [Problem::VanDerPol, Problem::Robertson] {
        let (matched, err) = compare(p);
        eprintln!(
            "  criterion: diffsol bdf at rtol {matched:.2e} (error ≤ {err:.2e}) against radau at rtol {RADAU_RTOL:e}"
        );
        group.bench_function(format!("radau5 {} rtol 1e-6", p.name()), |b| {
            b.iter(|| radau(p, black_box(RADAU_RTOL)))
        });
        group.bench_function(format!("diffsol bdf {} at equal error", p.name()), |b| {
            b.iter(|| diffsol_bdf(p, black_box(matched)))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
