//! Adaptive Dormand–Prince 8(5,3) with error control and 7th-degree dense
//! output.
//!
//! The step sequence depends only on the trajectory and the tolerance: sample
//! times are served from the dense output of the step that covers them, so
//! asking for more or fewer samples never changes the steps taken. The three
//! extra stages of the dense output are computed only for steps that contain
//! a sample.
//!
//! Error control follows Hairer's DOP853: the error is measured per component
//! against `atol + tol·|y|` (atol relative to |ω₀| for ω, to 1 for q) with
//! the 5th- and 3rd-order estimates combined; the step size is the shared
//! controller's ([`crate::solvers::control`]).

use crate::error::SolveError;
use nalgebra::Vector3;

use crate::rigid::euler::RigidSystem;
use crate::rigid::model::State;
use crate::rigid::scales::Scales;
use crate::solvers::budget::Budget;
use crate::solvers::control::{self, Arithmetic, StepControl, norm};
use crate::solvers::dop853_tableau::{self as tab, Row};
use crate::solvers::forward::Forward;
use crate::solvers::{Method, Solver, Work};
use flipcard_text::num::Num;

/// DOP853's order (the exponent of the step-size control is its inverse).
const ORDER: f64 = 8.0;
const ORDER_EXPONENT: f64 = 1.0 / ORDER;
/// The projected step count is checked this often during a long advance.
const PROJECTION_EVERY: u64 = 256;
/// ...once this many steps give the projection some footing.
const PROJECTION_AFTER: u64 = 1000;

/// Steps per radian of the fastest rate at tolerance `tol`: 2–6 times fewer
/// than DOP853 takes on Euler's equations (measured on flipping, precessing
/// and needle-like bodies, tol 1e-6 to 1e-12), so that the up-front check
/// refuses only spans clearly beyond the budget; the count during the run
/// is exact.
fn steps_per_radian(tol: f64) -> f64 {
    0.05 * tol.powf(-ORDER_EXPONENT)
}

/// Expected steps to cover `span` at `tol` when the fastest rate is `rate`.
pub(crate) fn estimated_steps(rate: f64, span: f64, tol: f64) -> f64 {
    rate * span * steps_per_radian(tol)
}

pub(crate) struct Dop853<S, const N: usize> {
    sys: S,
    tol: f64,
    atol: [f64; N],
    budget: Budget,
    scales: Scales,
    orientation: bool,
    /// The last accepted point, and f there (first stage of the next step).
    t: f64,
    y: [f64; N],
    f: [f64; N],
    /// Next step to try; zero before the first step.
    h: f64,
    control: StepControl,
    /// The last accepted step [t_old, t] and its stages, for dense output.
    t_old: f64,
    h_last: f64,
    y_old: [f64; N],
    k: [[f64; N]; 16],
    dense: Option<[[f64; N]; 7]>,
    horizon: f64,
    forward: Forward,
    work: Work,
}

impl<S: RigidSystem<N>, const N: usize> Dop853<S, N> {
    pub(crate) fn new(
        sys: S,
        omega0: &Vector3<f64>,
        tol: f64,
        budget: Budget,
        scales: Scales,
        orientation: bool,
    ) -> Dop853<S, N> {
        let y = sys.initial(omega0);
        let f = sys.f(&y);
        Dop853 {
            sys,
            tol,
            atol: sys.atol(tol),
            budget,
            scales,
            orientation,
            t: 0.0,
            y,
            f,
            h: 0.0,
            control: StepControl::new(ORDER),
            t_old: 0.0,
            h_last: 0.0,
            y_old: y,
            k: [[0.0; N]; 16],
            dense: None,
            horizon: 0.0,
            forward: Forward::default(),
            work: Work {
                rhs_evals: 1,
                ..Work::default()
            },
        }
    }

    fn attempts(&self) -> u64 {
        self.work.steps + self.work.rejected
    }

    fn stiff(&self, steps: f64) -> SolveError {
        SolveError::StepBudget {
            t: self.t,
            steps: self.attempts(),
            reason: self
                .budget
                .stiff(&self.scales.describe(self.orientation), steps),
        }
    }

    /// Refuses up front a span the budget clearly cannot cover.
    fn check_estimate(&self, end: f64) -> Result<(), SolveError> {
        let more = estimated_steps(
            self.scales.fastest(self.orientation),
            end - self.t,
            self.tol,
        );
        if self.budget.exceeded(self.attempts(), more) {
            return Err(self.stiff(self.attempts() as f64 + more));
        }
        Ok(())
    }

    /// During the run: extrapolates the steps taken so far to the end of the
    /// span, and stops at the hard cap whatever the projection says.
    fn check_progress(&self, end: f64) -> Result<(), SolveError> {
        let taken = self.attempts();
        let projected = if self.t > 0.0 {
            taken as f64 * (end / self.t).max(1.0)
        } else {
            f64::INFINITY
        };
        if taken > self.budget.max_steps {
            return Err(self.stiff(projected));
        }
        if taken >= PROJECTION_AFTER
            && taken.is_multiple_of(PROJECTION_EVERY)
            && projected > 1.25 * self.budget.max_steps as f64
        {
            return Err(self.stiff(projected));
        }
        Ok(())
    }

    fn scale(&self, i: usize, a: f64, b: f64) -> f64 {
        self.atol[i] + self.tol * a.abs().max(b.abs())
    }

    /// Hairer's starting step, in logarithms (|ω| may be past ~1e140).
    fn initial_step(&mut self) -> f64 {
        let mut sk = [0.0; N];
        for (i, s) in sk.iter_mut().enumerate() {
            *s = self.scale(i, self.y[i], self.y[i]);
        }
        let sys = self.sys;
        let rhs = |_: f64, y: &[f64], f: &mut [f64]| sys.rhs(0.0, y, f);
        self.work.rhs_evals += 1;
        control::initial_step(
            Arithmetic::Logarithmic,
            rhs,
            &self.y,
            &self.f,
            &sk,
            ORDER,
            f64::INFINITY,
        )
    }

    /// Error of a trial step relative to the tolerance (accept when ≤ 1):
    /// h·e5²/√(N(e5² + 0.01·e3²)) with e5, e3 the 2-norms of the two
    /// weighted estimates, arranged so that no norm is squared.
    fn error_norm(&self, y_new: &[f64; N], h: f64) -> f64 {
        let (mut d5, mut d3) = ([0.0; N], [0.0; N]);
        for (i, &y_new) in y_new.iter().enumerate() {
            let sk = self.scale(i, self.y[i], y_new);
            d5[i] = weigh(&self.k, &tab::E5, i) / sk;
            d3[i] = weigh(&self.k, &tab::E3, i) / sk;
        }
        let (e5, e3) = (norm(&d5), norm(&d3));
        let denominator = e5.hypot(0.1 * e3);
        if denominator <= 0.0 {
            return 0.0;
        }
        h.abs() * e5 * (e5 / denominator) / (N as f64).sqrt()
    }

    /// One accepted step (after as many rejected trials as it takes).
    fn step(&mut self, end: f64) -> Result<(), SolveError> {
        loop {
            let h = self.h;
            let resolvable = h > 4.0 * f64::EPSILON * self.t.abs();
            if !resolvable || !self.y.iter().all(|v| v.is_finite()) {
                return Err(SolveError::Invalid(format!(
                    "adaptive: step size underflow at t = {} (the solution is not resolvable at tol = {})",
                    Num(self.t),
                    Num(self.tol)
                )));
            }
            let y = self.y;
            let sys = self.sys;
            let k = &mut self.k;
            k[0] = self.f;
            k[1] = sys.f(&stage(&y, h, k, &tab::A1));
            k[2] = sys.f(&stage(&y, h, k, &tab::A2));
            k[3] = sys.f(&stage(&y, h, k, &tab::A3));
            k[4] = sys.f(&stage(&y, h, k, &tab::A4));
            k[5] = sys.f(&stage(&y, h, k, &tab::A5));
            k[6] = sys.f(&stage(&y, h, k, &tab::A6));
            k[7] = sys.f(&stage(&y, h, k, &tab::A7));
            k[8] = sys.f(&stage(&y, h, k, &tab::A8));
            k[9] = sys.f(&stage(&y, h, k, &tab::A9));
            k[10] = sys.f(&stage(&y, h, k, &tab::A10));
            k[11] = sys.f(&stage(&y, h, k, &tab::A11));
            let y_new = stage(&y, h, k, &tab::B);
            self.work.rhs_evals += 11;
            self.dense = None;

            let err = self.error_norm(&y_new, h);
            if err <= 1.0 {
                let h_new = self.control.accept(h, err);
                let f_new = sys.f(&y_new);
                self.work.rhs_evals += 1;
                self.work.steps += 1;
                self.k[12] = f_new;
                self.t_old = self.t;
                self.y_old = y;
                self.h_last = h;
                self.t += h;
                self.y = y_new;
                self.f = f_new;
                self.h = h_new;
                return self.check_progress(end);
            }
            self.h = self.control.reject(h, err);
            self.work.rejected += 1;
            self.check_progress(end)?;
        }
    }

    /// Coefficients of the interpolant on the last step (three more stages,
    /// computed once per step that holds a sample).
    fn dense_coefficients(&mut self) -> [[f64; N]; 7] {
        if let Some(d) = self.dense {
            return d;
        }
        let (h, y_old, sys) = (self.h_last, self.y_old, self.sys);
        let k = &mut self.k;
        k[13] = sys.f(&stage(&y_old, h, k, &tab::A13));
        k[14] = sys.f(&stage(&y_old, h, k, &tab::A14));
        k[15] = sys.f(&stage(&y_old, h, k, &tab::A15));
        self.work.rhs_evals += 3;
        let mut d = [[0.0; N]; 7];
        for i in 0..N {
            let dy = self.y[i] - y_old[i];
            let (f_old, f_new) = (k[0][i], k[12][i]);
            d[0][i] = dy;
            d[1][i] = h * f_old - dy;
            d[2][i] = 2.0 * dy - h * (f_new + f_old);
            for (r, row) in tab::D.iter().enumerate() {
                d[3 + r][i] = h * weigh(k, row, i);
            }
        }
        self.dense = Some(d);
        d
    }

    fn interpolate(&mut self, t: f64) -> [f64; N] {
        let d = self.dense_coefficients();
        let x = (t - self.t_old) / self.h_last;
        let x1 = 1.0 - x;
        let mut y = self.y_old;
        for i in 0..N {
            let mut p = d[6][i] * x;
            p = (p + d[5][i]) * x1;
            p = (p + d[4][i]) * x;
            p = (p + d[3][i]) * x1;
            p = (p + d[2][i]) * x;
            p = (p + d[1][i]) * x1;
            p = (p + d[0][i]) * x;
            y[i] += p;
        }
        y
    }
}

/// y + h Σⱼ aⱼ kⱼ over the nonzero entries of one tableau row.
#[inline(always)]
fn stage<const N: usize, const M: usize>(
    y: &[f64; N],
    h: f64,
    k: &[[f64; N]; 16],
    row: &Row<M>,
) -> [f64; N] {
    let mut out = *y;
    for (i, o) in out.iter_mut().enumerate() {
        *o += h * weigh(k, row, i);
    }
    out
}

/// Σⱼ aⱼ kⱼ[i] over one row.
#[inline(always)]
fn weigh<const N: usize, const M: usize>(k: &[[f64; N]; 16], row: &Row<M>, i: usize) -> f64 {
    let mut acc = 0.0;
    for &(j, a) in row {
        acc += a * k[j][i];
    }
    acc
}

impl<S: RigidSystem<N>, const N: usize> Solver for Dop853<S, N> {
    fn method(&self) -> Method {
        Method::Adaptive { tol: self.tol }
    }

    fn advance(&mut self, t: f64) -> Result<State, SolveError> {
        self.forward.accept(t)?;
        if t > self.t {
            let end = t.max(self.horizon);
            self.check_estimate(end)?;
            if self.h == 0.0 {
                self.h = self.initial_step();
            }
            while self.t < t {
                self.step(end)?;
            }
        }
        let y = if t == self.t {
            self.y
        } else {
            self.interpolate(t)
        };
        Ok(self.sys.state(&y))
    }

    fn work(&self) -> Work {
        self.work
    }

    fn plan(&mut self, t_end: f64) -> Result<(), SolveError> {
        self.horizon = self.horizon.max(t_end);
        self.check_estimate(self.horizon.max(self.t))
    }
}
