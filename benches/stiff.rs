//! flipcard's Radau IIA (and `auto`) against diffsol's BDF on five stiff
//! problems, at equal achieved error:
//!
//! - Van der Pol, x'' − μ(1 − x²)x' + x = 0, μ = 1000, (x, v)(0) = (2, 0),
//!   t ∈ [0, 3000] (two relaxation jumps); atol = rtol;
//! - Robertson's kinetics, y(0) = (1, 0, 0), t ∈ [0, 10¹¹];
//!   atol = rtol·(10⁻⁴, 10⁻¹⁰, 10⁻⁴) (y₂ lives near 10⁻¹³ late in the run);
//! - HIRES (8 components, Hairer & Wanner's test set), t ∈ [0, 321.8122];
//!   atol = rtol·10⁻⁶ (components down to 6·10⁻⁵ at the end);
//! - the Oregonator, y(0) = (1, 2, 3), t ∈ [0, 360]; atol = rtol;
//! - E5 (chemical pyrolysis: y₁ ≈ 10⁻³ beside y₂…y₄ ≈ 10⁻¹²),
//!   y(0) = (1.76·10⁻³, 0, 0, 0), t ∈ [0, 10⁵] — not the test set's 10¹³,
//!   where SciPy's Radau, BDF and LSODA at rtol 1e-12 disagree in the
//!   leading digit, so no reference could be confirmed; atol = 10⁻²⁴ for
//!   every component at every rtol.
//!
//! Every solver gets the analytic Jacobian (diffsol as Jacobian-vector
//! products, from which it assembles the dense matrix) and the same
//! tolerances. The error of a run is the largest relative error of a
//! component of the final state against the reference in
//! `benches/stiff_reference.txt`: SciPy's Radau at rtol 1e-12, confirmed by
//! SciPy's BDF and LSODA at rtol 1e-12 (their distances are in the file,
//! which `python3 benches/stiff_reference.py` writes); E5's at rtol 1e-13
//! with its invariant y2 = y3 + y4 written out, since in the four-variable
//! form rounding scatters every solver's answer by ~1e-9. This benchmark also
//! prints how far flipcard's Radau at rtol 1e-12 and diffsol at 1e-11 land
//! from it.
//!
//! First every solver sweeps its tolerance; a table of error, time (best of
//! several runs) and steps goes to stderr, then the time of each at the
//! error flipcard's Radau reaches at rtol 1e-6 (the others' read off their
//! sweeps by log-log interpolation) and the ratios. Then criterion times
//! Radau at rtol 1e-6 and diffsol at the loosest tolerance of a finer sweep
//! whose error is no worse. The `for compare_scipy_stiff.py` lines give the
//! arguments for `benches/compare_scipy_stiff.py` (SciPy's Radau, BDF and
//! LSODA on the same problems). Not run by `cargo test`.
//!
//!     cargo bench --bench stiff
//!     cargo bench --bench stiff -- hires     # one problem (criterion's filter)
//!
//! With `--json` it runs instead, for `benches/compare_scipy_stiff.py
//! --table`, every problem of that table (the five above but Van der Pol at
//! μ = 1000, plus Van der Pol at μ = 10⁴ to t = 2·10⁴, the linear system
//! with eigenvalues −1 and −10⁸ and the 200-variable Brusselator of
//! `tests/fixtures/brusselator`) at each rtol 1e-3 … 1e-10 with diffsol's
//! BDF and ESDIRK34 and flipcard's Radau IIA in-process, and prints one JSON
//! object a line: problem, method, rtol, and either the achieved error,
//! accepted steps and the best thread CPU time in ms, or why it failed.
//!
//!     cargo bench --bench stiff -- --json [PROBLEM ...]

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group};
use diffsol::{NalgebraLU, NalgebraMat, OdeBuilder, OdeSolverMethod, OdeSolverStopReason};
use flipcard::sim::solvers::ode::{Atol, Auto, OdeSolver, OdeSystem, Options, Radau5};
use nalgebra::DMatrix;

const MU: f64 = 1000.0;
const MU4: f64 = 1e4;
const RADAU_RTOL: f64 = 1e-6;
const REFERENCE: &str = include_str!("stiff_reference.txt");
const BRUSS_REFERENCE: &str = include_str!("../tests/fixtures/brusselator/reference.csv");
/// The problems criterion times (the table's others run under `--json`).
const CRITERION: [&str; 5] = ["van-der-pol", "robertson", "hires", "oregonator", "e5"];
/// The problems of `benches/stiff_table.md`, in its order.
const TABLE: [&str; 7] = [
    "hires",
    "oregonator",
    "e5",
    "robertson",
    "van-der-pol-1e4",
    "linear",
    "brusselator",
];
/// A diffsol run stops after this many steps (a second-order method at
/// rtol 1e-10 would take hours otherwise).
const DIFFSOL_MAX_STEPS: usize = 200_000;

/// Hands the Jacobian's non-zero entries at a state to a callback as
/// (row, column, value).
type JacFn = fn(&[f64], &mut dyn FnMut(usize, usize, f64));

/// A problem: f, the non-zero entries of its Jacobian (each given to a
/// callback as (row, column, value), from which both the dense Jacobian for
/// flipcard and the Jacobian-vector product for diffsol are built), the
/// initial state, the end time and atol as a function of rtol.
struct Problem {
    name: &'static str,
    dim: usize,
    y0: fn() -> Vec<f64>,
    t_end: f64,
    rhs: fn(&[f64], &mut [f64]),
    jac: JacFn,
    atol: fn(f64) -> Vec<f64>,
}

fn vdp_rhs(x: &[f64], y: &mut [f64]) {
    y[0] = x[1];
    y[1] = MU * (1.0 - x[0] * x[0]) * x[1] - x[0];
}

fn vdp_jac(x: &[f64], j: &mut dyn FnMut(usize, usize, f64)) {
    j(0, 1, 1.0);
    j(1, 0, -2.0 * MU * x[0] * x[1] - 1.0);
    j(1, 1, MU * (1.0 - x[0] * x[0]));
}

fn rober_rhs(x: &[f64], y: &mut [f64]) {
    y[0] = -0.04 * x[0] + 1e4 * x[1] * x[2];
    y[1] = 0.04 * x[0] - 1e4 * x[1] * x[2] - 3e7 * x[1] * x[1];
    y[2] = 3e7 * x[1] * x[1];
}

fn rober_jac(x: &[f64], j: &mut dyn FnMut(usize, usize, f64)) {
    j(0, 0, -0.04);
    j(0, 1, 1e4 * x[2]);
    j(0, 2, 1e4 * x[1]);
    j(1, 0, 0.04);
    j(1, 1, -1e4 * x[2] - 6e7 * x[1]);
    j(1, 2, -1e4 * x[1]);
    j(2, 1, 6e7 * x[1]);
}

fn hires_rhs(x: &[f64], y: &mut [f64]) {
    let r = 280.0 * x[5] * x[7];
    y[0] = -1.71 * x[0] + 0.43 * x[1] + 8.32 * x[2] + 0.0007;
    y[1] = 1.71 * x[0] - 8.75 * x[1];
    y[2] = -10.03 * x[2] + 0.43 * x[3] + 0.035 * x[4];
    y[3] = 8.32 * x[1] + 1.71 * x[2] - 1.12 * x[3];
    y[4] = -1.745 * x[4] + 0.43 * x[5] + 0.43 * x[6];
    y[5] = -r + 0.69 * x[3] + 1.71 * x[4] - 0.43 * x[5] + 0.69 * x[6];
    y[6] = r - 1.81 * x[6];
    y[7] = -r + 1.81 * x[6];
}

fn hires_jac(x: &[f64], j: &mut dyn FnMut(usize, usize, f64)) {
    j(0, 0, -1.71);
    j(0, 1, 0.43);
    j(0, 2, 8.32);
    j(1, 0, 1.71);
    j(1, 1, -8.75);
    j(2, 2, -10.03);
    j(2, 3, 0.43);
    j(2, 4, 0.035);
    j(3, 1, 8.32);
    j(3, 2, 1.71);
    j(3, 3, -1.12);
    j(4, 4, -1.745);
    j(4, 5, 0.43);
    j(4, 6, 0.43);
    j(5, 3, 0.69);
    j(5, 4, 1.71);
    j(5, 5, -280.0 * x[7] - 0.43);
    j(5, 6, 0.69);
    j(5, 7, -280.0 * x[5]);
    j(6, 5, 280.0 * x[7]);
    j(6, 6, -1.81);
    j(6, 7, 280.0 * x[5]);
    j(7, 5, -280.0 * x[7]);
    j(7, 6, 1.81);
    j(7, 7, -280.0 * x[5]);
}

fn oregonator_rhs(x: &[f64], y: &mut [f64]) {
    y[0] = 77.27 * (x[1] + x[0] * (1.0 - 8.375e-6 * x[0] - x[1]));
    y[1] = (x[2] - (1.0 + x[0]) * x[1]) / 77.27;
    y[2] = 0.161 * (x[0] - x[2]);
}

fn oregonator_jac(x: &[f64], j: &mut dyn FnMut(usize, usize, f64)) {
    j(0, 0, 77.27 * (1.0 - 2.0 * 8.375e-6 * x[0] - x[1]));
    j(0, 1, 77.27 * (1.0 - x[0]));
    j(1, 0, -x[1] / 77.27);
    j(1, 1, -(1.0 + x[0]) / 77.27);
    j(1, 2, 1.0 / 77.27);
    j(2, 0, 0.161);
    j(2, 2, -0.161);
}

const E5_A: f64 = 7.89e-10;
const E5_B: f64 = 1.1e7;
const E5_C: f64 = 1.13e3;
const E5_M: f64 = 1e6;

fn e5_rhs(x: &[f64], y: &mut [f64]) {
    let (a, b, c, m) = (E5_A, E5_B, E5_C, E5_M);
    y[0] = -a * x[0] - b * x[0] * x[2];
    y[1] = a * x[0] - m * c * x[1] * x[2];
    y[2] = a * x[0] - b * x[0] * x[2] - m * c * x[1] * x[2] + c * x[3];
    y[3] = b * x[0] * x[2] - c * x[3];
}

fn e5_jac(x: &[f64], j: &mut dyn FnMut(usize, usize, f64)) {
    let (a, b, c, m) = (E5_A, E5_B, E5_C, E5_M);
    j(0, 0, -a - b * x[2]);
    j(0, 2, -b * x[0]);
    j(1, 0, a);
    j(1, 1, -m * c * x[2]);
    j(1, 2, -m * c * x[1]);
    j(2, 0, a - b * x[2]);
    j(2, 1, -m * c * x[2]);
    j(2, 2, -b * x[0] - m * c * x[1]);
    j(2, 3, c);
    j(3, 0, b * x[2]);
    j(3, 2, b * x[0]);
    j(3, 3, -c);
}

fn vdp4_rhs(x: &[f64], y: &mut [f64]) {
    y[0] = x[1];
    y[1] = MU4 * (1.0 - x[0] * x[0]) * x[1] - x[0];
}

fn vdp4_jac(x: &[f64], j: &mut dyn FnMut(usize, usize, f64)) {
    j(0, 1, 1.0);
    j(1, 0, -2.0 * MU4 * x[0] * x[1] - 1.0);
    j(1, 1, MU4 * (1.0 - x[0] * x[0]));
}

/// y' = A y, A = P diag(−1, −1e8) P⁻¹ with P = [[1, 1], [1, −1]] (entries
/// exact in binary), as `benches/stiff_problems.py` writes it.
const LIN_D: f64 = -50000000.5;
const LIN_O: f64 = 49999999.5;

fn linear_rhs(x: &[f64], y: &mut [f64]) {
    y[0] = LIN_D * x[0] + LIN_O * x[1];
    y[1] = LIN_O * x[0] + LIN_D * x[1];
}

fn linear_jac(_x: &[f64], j: &mut dyn FnMut(usize, usize, f64)) {
    j(0, 0, LIN_D);
    j(0, 1, LIN_O);
    j(1, 0, LIN_O);
    j(1, 1, LIN_D);
}

/// The Brusselator of `tests/fixtures/brusselator/make.py`: N = 100 points,
/// u₁…u_N then v₁…v_N, boundary u = 1, v = 3.
const BN: usize = 100;
const BC: f64 = (1.0 / 50.0) * ((BN + 1) * (BN + 1)) as f64;

fn bruss_y0() -> Vec<f64> {
    (0..BN)
        .map(|i| 1.0 + (2.0 * std::f64::consts::PI * (i + 1) as f64 / (BN + 1) as f64).sin())
        .chain(std::iter::repeat_n(3.0, BN))
        .collect()
}

fn bruss_rhs(x: &[f64], y: &mut [f64]) {
    let (u, v) = x.split_at(BN);
    for i in 0..BN {
        let (ul, ur) = (
            if i > 0 { u[i - 1] } else { 1.0 },
            if i + 1 < BN { u[i + 1] } else { 1.0 },
        );
        let (vl, vr) = (
            if i > 0 { v[i - 1] } else { 3.0 },
            if i + 1 < BN { v[i + 1] } else { 3.0 },
        );
        let uuv = u[i] * u[i] * v[i];
        y[i] = 1.0 + uuv - 4.0 * u[i] + BC * (ul - 2.0 * u[i] + ur);
        y[BN + i] = 3.0 * u[i] - uuv + BC * (vl - 2.0 * v[i] + vr);
    }
}

fn bruss_jac(x: &[f64], j: &mut dyn FnMut(usize, usize, f64)) {
    let (u, v) = x.split_at(BN);
    for i in 0..BN {
        j(i, i, 2.0 * u[i] * v[i] - 4.0 - 2.0 * BC);
        j(i, BN + i, u[i] * u[i]);
        j(BN + i, i, 3.0 - 2.0 * u[i] * v[i]);
        j(BN + i, BN + i, -u[i] * u[i] - 2.0 * BC);
        if i > 0 {
            j(i, i - 1, BC);
            j(BN + i, BN + i - 1, BC);
        }
        if i + 1 < BN {
            j(i, i + 1, BC);
            j(BN + i, BN + i + 1, BC);
        }
    }
}

const PROBLEMS: [Problem; 8] = [
    Problem {
        name: "van-der-pol",
        dim: 2,
        y0: || [2.0, 0.0].to_vec(),
        t_end: 3000.0,
        rhs: vdp_rhs,
        jac: vdp_jac,
        atol: |r| vec![r; 2],
    },
    Problem {
        name: "robertson",
        dim: 3,
        y0: || [1.0, 0.0, 0.0].to_vec(),
        t_end: 1e11,
        rhs: rober_rhs,
        jac: rober_jac,
        atol: |r| vec![r * 1e-4, r * 1e-10, r * 1e-4],
    },
    Problem {
        name: "hires",
        dim: 8,
        y0: || [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0057].to_vec(),
        t_end: 321.8122,
        rhs: hires_rhs,
        jac: hires_jac,
        atol: |r| vec![r * 1e-6; 8],
    },
    Problem {
        name: "oregonator",
        dim: 3,
        y0: || [1.0, 2.0, 3.0].to_vec(),
        t_end: 360.0,
        rhs: oregonator_rhs,
        jac: oregonator_jac,
        atol: |r| vec![r; 3],
    },
    Problem {
        name: "e5",
        dim: 4,
        y0: || [1.76e-3, 0.0, 0.0, 0.0].to_vec(),
        t_end: 1e5,
        rhs: e5_rhs,
        jac: e5_jac,
        atol: |_| vec![1e-24; 4],
    },
    Problem {
        name: "van-der-pol-1e4",
        dim: 2,
        y0: || [2.0, 0.0].to_vec(),
        t_end: 2e4,
        rhs: vdp4_rhs,
        jac: vdp4_jac,
        atol: |r| vec![r; 2],
    },
    Problem {
        name: "linear",
        dim: 2,
        y0: || [2.0, 0.0].to_vec(),
        t_end: 10.0,
        rhs: linear_rhs,
        jac: linear_jac,
        // Both components end near 4.5e-5.
        atol: |r| vec![r * 1e-6; 2],
    },
    Problem {
        name: "brusselator",
        dim: 2 * BN,
        y0: bruss_y0,
        t_end: 10.0,
        rhs: bruss_rhs,
        jac: bruss_jac,
        atol: |r| vec![r * 1e-2; 2 * BN],
    },
];

/// A problem as flipcard sees it.
struct Sys(&'static Problem);

impl OdeSystem for Sys {
    fn dim(&self) -> usize {
        self.0.dim
    }
    fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
        (self.0.rhs)(y, dy);
    }
    fn jacobian(&self, _t: f64, y: &[f64], jac: &mut DMatrix<f64>) {
        jac.fill(0.0);
        (self.0.jac)(y, &mut |i, j, v| jac[(i, j)] = v);
    }
}

/// The reference final state of `p` from the fixture (its end time checked;
/// the Brusselator's from its own fixture).
fn reference(p: &Problem) -> Vec<f64> {
    if p.name == "brusselator" {
        let values: Vec<f64> = (BRUSS_REFERENCE.lines().skip(1))
            .map(|l| {
                l.split(',')
                    .nth(1)
                    .expect("name,value")
                    .parse()
                    .expect("a number")
            })
            .collect();
        assert_eq!(values.len(), p.dim, "the Brusselator's reference");
        return values;
    }
    for line in REFERENCE.lines().filter(|l| !l.starts_with('#')) {
        let mut words = line.split_whitespace();
        if words.next() != Some(p.name) {
            continue;
        }
        let values: Vec<f64> = words.map(|w| w.parse().expect("a number")).collect();
        assert_eq!(values[0], p.t_end, "{}: the fixture's end time", p.name);
        assert_eq!(values.len() - 1, p.dim, "{}: the fixture's state", p.name);
        return values[1..].to_vec();
    }
    panic!("{} is not in benches/stiff_reference.txt", p.name)
}

type Outcome = Result<(Vec<f64>, u64), String>;

fn options(p: &Problem, rtol: f64) -> Options {
    Options {
        rtol,
        atol: Atol::PerComponent((p.atol)(rtol)),
        t_stop: Some(p.t_end),
        ..Options::default()
    }
}

fn finish(mut s: impl OdeSolver, t_end: f64) -> Outcome {
    let y = s.advance(t_end).map_err(|e| e.to_string())?.to_vec();
    Ok((y, s.work().steps))
}

/// Final state and accepted steps of flipcard's Radau IIA.
fn radau(p: &'static Problem, rtol: f64) -> Outcome {
    let s = Radau5::new(Sys(p), 0.0, &(p.y0)(), &options(p, rtol)).map_err(|e| e.to_string())?;
    finish(s, p.t_end)
}

/// Final state and accepted steps (both phases) of flipcard's `auto`.
fn auto(p: &'static Problem, rtol: f64) -> Outcome {
    let s = Auto::new(Sys(p), 0.0, &(p.y0)(), &options(p, rtol)).map_err(|e| e.to_string())?;
    finish(s, p.t_end)
}

/// diffsol's implicit methods, dense nalgebra LU.
#[derive(Clone, Copy)]
enum Diffsol {
    Bdf,
    Esdirk34,
}

/// Final state and steps of diffsol's BDF (nalgebra, dense LU).
fn diffsol_bdf(p: &'static Problem, rtol: f64) -> Outcome {
    diffsol_run(p, rtol, Diffsol::Bdf)
}

/// Final state and steps of diffsol's ESDIRK34 (nalgebra, dense LU).
fn diffsol_esdirk34(p: &'static Problem, rtol: f64) -> Outcome {
    diffsol_run(p, rtol, Diffsol::Esdirk34)
}

fn diffsol_run(p: &'static Problem, rtol: f64, method: Diffsol) -> Outcome {
    let n = p.dim;
    let y0 = (p.y0)();
    let problem = OdeBuilder::<NalgebraMat<f64>>::new()
        .rtol(rtol)
        .atol((p.atol)(rtol))
        .rhs_implicit(
            |x: &[f64], _p: &[f64], _t: f64, y: &mut [f64]| (p.rhs)(x, y),
            |x: &[f64], _p: &[f64], _t: f64, v: &[f64], y: &mut [f64]| {
                y.fill(0.0);
                (p.jac)(x, &mut |i, j, a| y[i] += a * v[j]);
            },
        )
        .init(
            move |_p: &[f64], _t: f64, y: &mut [f64]| y.copy_from_slice(&y0),
            n,
        )
        .build()
        .map_err(|e| e.to_string())?;
    fn drive<'a, E, S>(mut solver: S, t_end: f64, n: usize) -> Outcome
    where
        E: diffsol::OdeEquations<T = f64> + 'a,
        S: OdeSolverMethod<'a, E>,
        E::V: std::ops::Index<usize, Output = f64>,
    {
        solver.set_stop_time(t_end).map_err(|e| e.to_string())?;
        let mut steps = 0;
        loop {
            match solver.step() {
                Ok(OdeSolverStopReason::TstopReached) => break,
                Ok(_) => {}
                Err(e) => return Err(format!("diffsol: {e}")),
            }
            steps += 1;
            if steps > DIFFSOL_MAX_STEPS {
                return Err(format!(
                    "over {DIFFSOL_MAX_STEPS} steps (stopped at t = {:.3e})",
                    solver.state().t
                ));
            }
        }
        let y = &solver.state().y;
        Ok(((0..n).map(|i| y[i]).collect(), steps as u64))
    }
    match method {
        Diffsol::Bdf => drive(
            problem
                .bdf::<NalgebraLU<f64>>()
                .map_err(|e| e.to_string())?,
            p.t_end,
            n,
        ),
        Diffsol::Esdirk34 => drive(
            problem
                .esdirk34::<NalgebraLU<f64>>()
                .map_err(|e| e.to_string())?,
            p.t_end,
            n,
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

type Solve = fn(&'static Problem, f64) -> Outcome;

/// (rtol, error, seconds, steps) along a tolerance sweep; a failed run is
/// printed with its reason and left out.
fn sweep(
    p: &'static Problem,
    name: &str,
    solve: Solve,
    reference: &[f64],
    rtols: &[f64],
) -> Vec<(f64, f64, f64, u64)> {
    let mut rows = Vec::new();
    for &rtol in rtols {
        match solve(p, rtol) {
            Ok((y, steps)) => {
                let err = max_rel_error(&y, reference);
                let secs = best_time(|| {
                    let _ = black_box(solve(p, black_box(rtol)));
                })
                .as_secs_f64();
                eprintln!(
                    "  {name:<12} {rtol:>7.0e}  {err:>9.2e}  {:>10.1} µs  {steps:>6}",
                    secs * 1e6
                );
                rows.push((rtol, err, secs, steps));
            }
            Err(e) => eprintln!("  {name:<12} {rtol:>7.0e}  failed: {e}"),
        }
    }
    rows
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

/// The comparison table, and diffsol's loosest rtol matching Radau's error
/// (None if diffsol never reaches it or Radau fails at [`RADAU_RTOL`]).
fn compare(p: &'static Problem) -> Option<(f64, f64)> {
    let reference = reference(p);
    let distance = |r: Outcome| match r {
        Ok((y, _)) => format!("{:.1e}", max_rel_error(&y, &reference)),
        Err(e) => format!("failed ({e})"),
    };
    eprintln!(
        "\n{} to t = {}: reference SciPy Radau rtol 1e-12 (benches/stiff_reference.txt) {reference:?};\n  flipcard radau at rtol 1e-12 differs by {}, diffsol bdf at rtol 1e-11 by {}",
        p.name,
        p.t_end,
        distance(radau(p, 1e-12)),
        distance(diffsol_bdf(p, 1e-11)),
    );
    eprintln!("  method          rtol      error          time   steps");
    let rtols = decades(4, 9, 1);
    let ours = sweep(p, "radau5", radau, &reference, &rtols);
    let autos = sweep(p, "auto", auto, &reference, &rtols);
    let theirs = sweep(
        p,
        "diffsol bdf",
        diffsol_bdf,
        &reference,
        &decades(4, 10, 1),
    );
    let (y, _) = radau(p, RADAU_RTOL).ok()?;
    let err = max_rel_error(&y, &reference);
    let our_time = time_at_error(&ours, err).unwrap_or(f64::NAN);
    let show = |name: &str, rows: &[(f64, f64, f64, u64)]| match time_at_error(rows, err) {
        Some(t) => format!("{name} {:.1} µs ({:.2}×)", t * 1e6, t / our_time),
        None => format!("{name}: sweep does not reach it"),
    };
    eprintln!(
        "  at radau's error {err:.2e} (rtol {RADAU_RTOL:e}): radau {:.1} µs; {}; {}",
        our_time * 1e6,
        show("auto", &autos),
        show("diffsol bdf", &theirs),
    );
    let radau_secs = best_time(|| {
        let _ = black_box(radau(p, RADAU_RTOL));
    });
    eprintln!(
        "  for compare_scipy_stiff.py: --{}-ms {:.4} --{}-error {err:.3e}",
        p.name,
        radau_secs.as_secs_f64() * 1e3,
        p.name,
    );
    // The loosest rtol of a finer sweep whose error is no worse.
    decades(3, 12, 4)
        .into_iter()
        .find(|&r| diffsol_bdf(p, r).is_ok_and(|(y, _)| max_rel_error(&y, &reference) <= err))
        .map(|matched| (matched, err))
}

fn bench(c: &mut Criterion) {
    let filter: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    let mut group = c.benchmark_group("stiff");
    group.measurement_time(Duration::from_secs(3));
    for p in PROBLEMS.iter().filter(|p| CRITERION.contains(&p.name)) {
        if !filter.is_empty() && !filter.iter().any(|f| p.name.contains(f.as_str())) {
            continue;
        }
        let Some((matched, err)) = compare(p) else {
            eprintln!("  no criterion run: radau or diffsol does not reach the error");
            continue;
        };
        eprintln!(
            "  criterion: diffsol bdf at rtol {matched:.2e} (error ≤ {err:.2e}) against radau at rtol {RADAU_RTOL:e}"
        );
        group.bench_function(format!("radau5 {} rtol 1e-6", p.name), |b| {
            b.iter(|| radau(p, black_box(RADAU_RTOL)))
        });
        group.bench_function(format!("diffsol bdf {} at equal error", p.name), |b| {
            b.iter(|| diffsol_bdf(p, black_box(matched)))
        });
    }
    group.finish();
}

/// Best thread CPU time of `f` (at least 3 runs, more within ~0.2 s, at
/// most 20).
fn best_cpu(mut f: impl FnMut()) -> Duration {
    let now = || {
        let t = rustix::time::clock_gettime(rustix::time::ClockId::ThreadCPUTime);
        Duration::new(t.tv_sec as u64, t.tv_nsec as u32)
    };
    let (mut best, start, mut runs) = (Duration::MAX, now(), 0);
    while runs < 3 || (now() - start < Duration::from_millis(200) && runs < 20) {
        let t = now();
        f();
        best = best.min(now() - t);
        runs += 1;
    }
    best
}

/// `--json`: every problem of the table (or those named) × rtol 1e-3 …
/// 1e-10 × diffsol BDF, diffsol ESDIRK34 and flipcard's Radau in-process,
/// one JSON object a line on stdout.
fn json(names: &[String]) {
    let solvers: [(&str, Solve); 3] = [
        ("diffsol-bdf", diffsol_bdf),
        ("diffsol-esdirk34", diffsol_esdirk34),
        ("flipcard-radau", radau),
    ];
    for name in TABLE {
        if !names.is_empty() && !names.iter().any(|n| n == name) {
            continue;
        }
        let p = PROBLEMS.iter().find(|p| p.name == name).expect("a problem");
        let reference = reference(p);
        for k in 3..=10 {
            let rtol = 10f64.powi(-k);
            for (method, solve) in solvers {
                let row = match solve(p, rtol) {
                    Ok((y, steps)) => {
                        let cpu = best_cpu(|| {
                            let _ = black_box(solve(p, black_box(rtol)));
                        });
                        serde_json::json!({
                            "problem": name, "method": method, "rtol": rtol,
                            "error": max_rel_error(&y, &reference), "steps": steps,
                            "ms": cpu.as_secs_f64() * 1e3,
                        })
                    }
                    Err(e) => serde_json::json!({
                        "problem": name, "method": method, "rtol": rtol, "failed": e,
                    }),
                };
                println!("{row}");
            }
        }
    }
}

criterion_group!(benches, bench);

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "--json") {
        let names: Vec<String> = args.into_iter().filter(|a| !a.starts_with('-')).collect();
        json(&names);
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
