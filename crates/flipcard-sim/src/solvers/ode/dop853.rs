//! Dormand–Prince 8(5,3) for systems of any size, with Hairer's error
//! estimator, step control, 7th-degree dense output and stiffness detection
//! (Hairer, Nørsett & Wanner, *Solving ODEs I*, code DOP853).
//!
//! The coefficients, with the nodes c (f may depend on t), are the shared
//! tableau (`dop853_tableau`); the step size is the shared controller's
//! (`control`), as in the rigid-body solver.
//!
//! Stiffness detection estimates |hλ| for the dominant eigenvalue from two
//! evaluations of f at t + h, at the 12th stage and at the new point:
//! h·‖f(y₁₂) − f(y_new)‖ / ‖y₁₂ − y_new‖. DOP853 is stable up to about
//! |hλ| = 6.1 on the negative real axis, so a step size pinned there by
//! stability rather than accuracy shows as 15 such values above 6.1 in a
//! row; 6 below reset the count. Hairer runs the test every 1000 steps
//! until it first fires; here it runs after every step (two norms, no
//! evaluation of f), so `auto` hands over to the implicit method early.

use super::fixed::Held;
use super::{BLOW_UP_LIMIT, BySize, OdeSystem, Options, Requests, Stepper, Work, initial_step};
use crate::error::SolveError;
use crate::solvers::control::{self, Arithmetic, StepControl, norm};
use crate::solvers::dop853_tableau::{self as tab, C, C_DENSE, Row};

/// DOP853's order (the step-size control's exponent is its inverse).
const ORDER: f64 = 8.0;
/// |hλ| on DOP853's stability boundary along the negative real axis.
const STIFF_RATIO: f64 = 6.1;
const STIFF_POSITIVE: u32 = 15;
const STIFF_NEGATIVE: u32 = 6;

/// What DOP853 does when its stiffness test fires.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StiffnessMode {
    /// Record the time ([`OdeSolver::stiffness`]) and go on.
    #[default]
    Report,
    /// Stop with [`SolveError::Stiff`].
    Refuse,
}

/// `N` is the system's size when it is known when compiling (the rigid
/// body's 3 or 7, so that the loops over components unroll), or 0 for a
/// size known only at run time (a deck's system).
pub struct Dop853<S, const N: usize = 0> {
    sys: S,
    n: usize,
    rtol: f64,
    atol: Vec<f64>,
    /// What `atol` follows, when it follows the sizes.
    by_size: Option<BySize>,
    max_steps: u64,
    max_step: f64,
    t_stop: Option<f64>,
    fixed: Option<f64>,
    /// The sums the equations keep fixed, held at each accepted step
    /// ([`super::fixed`]); none on the rigid body's stepper.
    held: Option<Held>,
    mode: StiffnessMode,
    /// How the error norm and the starting step are taken: Hairer's sums of
    /// squares, or without squares (the rigid body, whose spins may be
    /// past 1e140).
    arithmetic: Arithmetic,
    /// Components beyond this magnitude end the run (the systems' cap; the
    /// rigid body, whose size is bounded by its energy, has none).
    limit: f64,
    /// The size the run started from ([`super::start_size`]).
    start: f64,
    t: f64,
    y: Vec<f64>,
    /// Stages, 16 rows of n: k[0] = f(t, y) ... k[12] = f at the new point,
    /// k[13..16] the dense-output stages.
    k: Vec<f64>,
    y_new: Vec<f64>,
    /// Argument of the 12th stage (for the stiffness test).
    y12: Vec<f64>,
    /// The two weighted error estimates (for the unsquared norm).
    d5: Vec<f64>,
    d3: Vec<f64>,
    /// One tableau row's weighted sum of the stages.
    acc: Vec<f64>,
    scratch: Vec<f64>,
    h: f64,
    control: StepControl,
    t_old: f64,
    h_last: f64,
    y_old: Vec<f64>,
    /// Dense-output coefficients of the last step, once computed.
    dense: Vec<f64>,
    dense_ready: bool,
    stiff_count: u32,
    nonstiff_count: u32,
    stiff_at: Option<f64>,
    /// |hλ| of the stiffness test on the last accepted step (0 when the
    /// test could not tell).
    h_lambda: f64,
    requests: Requests,
    work: Work,
}

impl<S: OdeSystem> Dop853<S> {
    /// An adaptive solver from (t0, y0); the first step is chosen when the
    /// run starts.
    pub fn new(sys: S, t0: f64, y0: &[f64], opts: &Options) -> Result<Dop853<S>, SolveError> {
        super::check_start(&sys, t0, y0)?;
        let (atol, by_size) = opts.validated_atol(t0, y0)?;
        let held = Held::new(sys.fixed_sums(t0, y0), y0);
        let mut s = Dop853::checked(sys, t0, y0, opts, atol);
        s.by_size = by_size;
        s.held = held;
        Ok(s)
    }

    /// Steps of exactly `h`, without error control (for convergence
    /// studies; the dense output still works).
    pub fn new_fixed(sys: S, t0: f64, y0: &[f64], h: f64) -> Result<Dop853<S>, SolveError> {
        if !(h.is_finite() && h > 0.0) {
            return Err(SolveError::Invalid(format!(
                "step h = {h} must be positive"
            )));
        }
        let mut s = Dop853::new(sys, t0, y0, &Options::default())?;
        s.fixed = Some(h);
        s.h = h;
        Ok(s)
    }
}

impl<S: OdeSystem, const N: usize> Dop853<S, N> {
    /// The size of the system.
    #[inline(always)]
    fn n(&self) -> usize {
        if N == 0 { self.n } else { N }
    }

    /// The rigid body's stepper: `rtol` with the body's own absolute
    /// tolerances (ω against its initial size, q against 1), norms taken
    /// without squares and no magnitude cap. Its caller keeps the budget
    /// and drives the trials ([`Dop853::trial`]).
    pub(crate) fn rigid(sys: S, y0: &[f64], rtol: f64, atol: Vec<f64>) -> Dop853<S, N> {
        debug_assert_eq!(sys.dim(), N);
        let opts = Options {
            rtol,
            ..Options::default()
        };
        let mut s = Dop853::checked(sys, 0.0, y0, &opts, atol);
        s.arithmetic = Arithmetic::Logarithmic;
        s.limit = f64::INFINITY;
        s
    }

    fn checked(sys: S, t0: f64, y0: &[f64], opts: &Options, atol: Vec<f64>) -> Dop853<S, N> {
        let n = sys.dim();
        let mut k = vec![0.0; 16 * n];
        sys.rhs(t0, y0, &mut k[..n]);
        Dop853 {
            n,
            rtol: opts.rtol,
            atol,
            by_size: None,
            max_steps: opts.max_steps,
            max_step: opts.max_step.unwrap_or(f64::INFINITY),
            t_stop: opts.t_stop,
            fixed: None,
            held: None,
            mode: StiffnessMode::Report,
            arithmetic: Arithmetic::Plain,
            limit: BLOW_UP_LIMIT,
            start: super::start_size(y0),
            t: t0,
            y: y0.to_vec(),
            k,
            y_new: vec![0.0; n],
            y12: vec![0.0; n],
            d5: vec![0.0; n],
            d3: vec![0.0; n],
            acc: vec![0.0; n],
            scratch: vec![0.0; n],
            h: opts.h0.unwrap_or(0.0),
            control: StepControl::new(ORDER),
            t_old: t0,
            h_last: 0.0,
            y_old: y0.to_vec(),
            dense: vec![0.0; 7 * n],
            dense_ready: false,
            stiff_count: 0,
            nonstiff_count: 0,
            stiff_at: None,
            h_lambda: 0.0,
            requests: Requests::new(t0, y0),
            work: Work {
                rhs_evals: 1,
                ..Work::default()
            },
            sys,
        }
    }

    pub fn with_stiffness(mut self, mode: StiffnessMode) -> Dop853<S, N> {
        self.mode = mode;
        self
    }

    /// Hands the system and the current point over (for `auto`).
    /// The absolute tolerance of each component now.
    pub(crate) fn atol_now(&self) -> &[f64] {
        &self.atol
    }

    /// The sizes the tolerances follow, when they do.
    pub(crate) fn by_size(&self) -> Option<&BySize> {
        self.by_size.as_ref()
    }

    pub(crate) fn into_parts(self) -> (S, f64, Vec<f64>, Work) {
        (self.sys, self.t, self.y, self.work)
    }

    /// Stage `stage` of a trial step of size `h` from (t, y): its argument
    /// y + h Σⱼ aⱼ kⱼ over `row`, and f there.
    #[inline(always)]
    fn stage<const M: usize>(&mut self, stage: usize, t: f64, h: f64, row: &Row<M>) {
        let n = self.n();
        weigh_all(&self.k, n, row, &mut self.acc);
        let (scratch, y, acc) = (&mut self.scratch[..n], &self.y[..n], &self.acc[..n]);
        for i in 0..n {
            scratch[i] = y[i] + h * acc[i];
        }
        let (_, rest) = self.k.split_at_mut(stage * n);
        self.sys
            .rhs(t + C[stage] * h, &self.scratch, &mut rest[..n]);
    }

    /// The error of a trial step relative to the tolerance (accept when
    /// ≤ 1), from the 5th- and 3rd-order estimates, in the run's arithmetic.
    fn error_norm(&mut self, h: f64) -> f64 {
        match self.arithmetic {
            Arithmetic::Plain => self.error_norm_plain(h),
            Arithmetic::Logarithmic => self.error_norm_unsquared(h),
        }
    }

    /// h·e5²/√(n(e5² + 0.01·e3²)) with e5, e3 the 2-norms of the two
    /// weighted estimates, arranged so that no norm is squared (a NaN
    /// stays NaN: the controller shrinks the step for it).
    fn error_norm_unsquared(&mut self, h: f64) -> f64 {
        let n = self.n();
        weigh_all(&self.k, n, &tab::E5, &mut self.d5);
        weigh_all(&self.k, n, &tab::E3, &mut self.d3);
        for i in 0..n {
            let sk = self.atol[i] + self.rtol * self.y[i].abs().max(self.y_new[i].abs());
            self.d5[i] /= sk;
            self.d3[i] /= sk;
        }
        let (e5, e3) = (norm(&self.d5), norm(&self.d3));
        let denominator = e5.hypot(0.1 * e3);
        if denominator <= 0.0 {
            return 0.0;
        }
        h.abs() * e5 * (e5 / denominator) / (n as f64).sqrt()
    }

    fn error_norm_plain(&self, h: f64) -> f64 {
        let n = self.n();
        let (mut e5, mut e3) = (0.0, 0.0);
        for i in 0..n {
            let sk = self.atol[i] + self.rtol * self.y[i].abs().max(self.y_new[i].abs());
            let d5 = weigh(&self.k, n, &tab::E5, i);
            let d3 = weigh(&self.k, n, &tab::E3, i);
            e5 += (d5 / sk).powi(2);
            e3 += (d3 / sk).powi(2);
        }
        let mut den = e5 + 0.01 * e3;
        if den <= 0.0 {
            den = 1.0;
        }
        let err = h.abs() * e5 * (1.0 / (n as f64 * den)).sqrt();
        // A stage that overflowed makes err NaN; count it as a failure so
        // the step shrinks.
        if err.is_nan() { f64::INFINITY } else { err }
    }

    fn budget_error(&self) -> SolveError {
        SolveError::StepBudget {
            t: self.t,
            steps: self.max_steps,
            reason: format!(
                "dop853: {} step attempts reached at t = {} without finishing; \
                 if the problem is stiff, radau or auto suits it better",
                self.max_steps, self.t
            ),
        }
    }

    /// One accepted step, after as many rejected trials as it takes.
    fn try_step(&mut self) -> Result<(), SolveError> {
        loop {
            if self.work.steps + self.work.rejected >= self.max_steps {
                return Err(self.budget_error());
            }
            let mut h = self.step_to_try().min(self.max_step);
            if let Some(stop) = self.t_stop
                && self.t + 1.01 * h >= stop
            {
                h = stop - self.t;
            }
            if h.is_nan() || h <= 10.0 * f64::EPSILON * self.t.abs() {
                return Err(super::collapse(self.t, h, &self.y, self.start));
            }
            if self.trial(h)? {
                return self.stiffness_test(h);
            }
            if self.fixed.is_some() {
                return Err(SolveError::BlowUp { t: self.t });
            }
        }
    }

    /// |hλ| on the last accepted step, from the stiffness test.
    pub(crate) fn h_lambda(&self) -> f64 {
        self.h_lambda
    }

    /// The suggested size of the next step (0 before the first).
    pub(crate) fn next_step_size(&self) -> f64 {
        self.h
    }

    /// The step to try next: Hairer's guess before the first (one more
    /// evaluation of f), then the controller's.
    pub(crate) fn step_to_try(&mut self) -> f64 {
        if self.h == 0.0 {
            let n = self.n();
            let h_max = self
                .max_step
                .min(self.t_stop.map_or(f64::INFINITY, |s| s - self.t));
            let f0 = self.k[..n].to_vec();
            self.h = match self.arithmetic {
                Arithmetic::Plain => initial_step(
                    &self.sys, self.t, &self.y, &f0, self.rtol, &self.atol, ORDER, h_max,
                ),
                Arithmetic::Logarithmic => {
                    let scale: Vec<f64> = (self.y.iter().zip(&self.atol))
                        .map(|(y, a)| a + self.rtol * y.abs())
                        .collect();
                    let (sys, t) = (&self.sys, self.t);
                    let rhs = |h: f64, y1: &[f64], f1: &mut [f64]| sys.rhs(t + h, y1, f1);
                    control::initial_step(
                        Arithmetic::Logarithmic,
                        rhs,
                        &self.y,
                        &f0,
                        &scale,
                        ORDER,
                        h_max,
                    )
                }
            };
            self.work.rhs_evals += 1;
        }
        self.h
    }

    /// One trial step of size `h` from the current point: accepted (the
    /// point moves on, `true`) or rejected (`false`); either way the
    /// controller sets the next step size. The caller owns the budget.
    pub(crate) fn trial(&mut self, h: f64) -> Result<bool, SolveError> {
        let n = self.n();
        let t = self.t;
        self.stage(1, t, h, &tab::A1);
        self.stage(2, t, h, &tab::A2);
        self.stage(3, t, h, &tab::A3);
        self.stage(4, t, h, &tab::A4);
        self.stage(5, t, h, &tab::A5);
        self.stage(6, t, h, &tab::A6);
        self.stage(7, t, h, &tab::A7);
        self.stage(8, t, h, &tab::A8);
        self.stage(9, t, h, &tab::A9);
        self.stage(10, t, h, &tab::A10);
        self.stage(11, t, h, &tab::A11);
        self.y12.copy_from_slice(&self.scratch);
        weigh_all(&self.k, n, &tab::B, &mut self.acc);
        let (y_new, y, acc) = (&mut self.y_new[..n], &self.y[..n], &self.acc[..n]);
        for i in 0..n {
            y_new[i] = y[i] + h * acc[i];
        }
        self.work.rhs_evals += 11;

        let mut err = if self.fixed.is_some() {
            0.0
        } else {
            self.error_norm(h)
        };
        let limit = self.limit;
        let sane = self.y_new.iter().all(|v| v.is_finite() && v.abs() <= limit);
        // An accurate step to finite values past the magnitude cap: the
        // solution grows out of what f64 can carry; shrinking the step
        // would only spend the budget getting there (x' = 1000x took
        // 5e6 attempts).
        if err <= 1.0 && !sane && self.y_new.iter().all(|v| v.is_finite()) {
            return Err(SolveError::BlowUp { t: self.t });
        }
        let mut accept = err <= 1.0 && sane;
        let t_new = t + h;
        if accept && let Some(held) = &self.held {
            let (atol, rtol) = (&self.atol, self.rtol);
            held.hold(&mut self.y_new, |i, v| atol[i] + rtol * v.abs());
        }
        if accept {
            let (_, tail) = self.k.split_at_mut(12 * n);
            self.sys.rhs(t_new, &self.y_new, &mut tail[..n]);
            self.work.rhs_evals += 1;
            // With f not finite at the new point no step could start
            // there: treat it as a failed trial, so the step shrinks.
            if !tail[..n].iter().all(|v| v.is_finite()) {
                accept = false;
                err = f64::NAN;
            }
        }
        if accept {
            let h_new = self.control.accept(h, err);
            self.work.steps += 1;
            self.t_old = t;
            self.h_last = h;
            self.y_old.copy_from_slice(&self.y);
            self.y.copy_from_slice(&self.y_new);
            self.t = t_new;
            self.dense_ready = false;
            if let Some(b) = &mut self.by_size {
                b.follow(self.t, &self.y, &mut self.atol);
            }
            // The dense stages need k[0] of this step: the new f moves
            // there only when the next step starts.
            self.h = self.fixed.unwrap_or(h_new);
            return Ok(true);
        }
        self.h = self.control.reject(h, err);
        self.work.rejected += 1;
        Ok(false)
    }

    /// Hairer's test on the step just accepted, ending at `self.t`.
    fn stiffness_test(&mut self, h: f64) -> Result<(), SolveError> {
        let n = self.n();
        let (mut num, mut den) = (0.0, 0.0);
        for i in 0..n {
            num += (self.k[12 * n + i] - self.k[11 * n + i]).powi(2);
            den += (self.y[i] - self.y12[i]).powi(2);
        }
        if den <= 0.0 {
            self.h_lambda = 0.0;
            return Ok(());
        }
        let hlamb = h.abs() * (num / den).sqrt();
        self.h_lambda = hlamb;
        if hlamb > STIFF_RATIO {
            self.nonstiff_count = 0;
            self.stiff_count += 1;
            if self.stiff_count == STIFF_POSITIVE && self.stiff_at.is_none() {
                self.stiff_at = Some(self.t);
                if self.mode == StiffnessMode::Refuse {
                    return Err(SolveError::Stiff { t: self.t });
                }
            }
        } else {
            self.nonstiff_count += 1;
            if self.nonstiff_count == STIFF_NEGATIVE {
                self.stiff_count = 0;
            }
        }
        Ok(())
    }

    /// The three extra stages and the coefficients of the interpolant on
    /// the last step, once per step that is asked for a dense value.
    fn dense_coefficients(&mut self) {
        if self.dense_ready {
            return;
        }
        let n = self.n();
        let h = self.h_last;
        let t = self.t_old;
        let extra: [&[(usize, f64)]; 3] = [&tab::A13, &tab::A14, &tab::A15];
        for (s, row) in extra.iter().enumerate() {
            for i in 0..n {
                self.scratch[i] = self.y_old[i] + h * weigh(&self.k, n, row, i);
            }
            let (_, rest) = self.k.split_at_mut((13 + s) * n);
            self.sys
                .rhs(t + C_DENSE[s] * h, &self.scratch, &mut rest[..n]);
        }
        self.work.rhs_evals += 3;
        for i in 0..n {
            let dy = self.y[i] - self.y_old[i];
            let (f_old, f_new) = (self.k[i], self.k[12 * n + i]);
            self.dense[i] = dy;
            self.dense[n + i] = h * f_old - dy;
            self.dense[2 * n + i] = 2.0 * dy - h * (f_new + f_old);
            for (r, row) in tab::D.iter().enumerate() {
                self.dense[(3 + r) * n + i] = h * weigh(&self.k, n, row, i);
            }
        }
        self.dense_ready = true;
    }

    /// Moves f at the new point into k[0] before the next step (which
    /// ends the dense output of the finished one).
    pub(crate) fn start_next(&mut self) {
        let n = self.n();
        if self.work.steps > 0 {
            self.k.copy_within(12 * n..13 * n, 0);
            self.dense_ready = false;
        }
    }
}

/// Σⱼ aⱼ kⱼ over one sparse row, for every component at once (the same
/// sums, term by term, as [`weigh`]).
#[inline(always)]
fn weigh_all<const M: usize>(k: &[f64], n: usize, row: &Row<M>, acc: &mut [f64]) {
    let acc = &mut acc[..n];
    acc.fill(0.0);
    for &(j, a) in row {
        let kj = &k[j * n..j * n + n];
        for i in 0..n {
            acc[i] += a * kj[i];
        }
    }
}

/// Σⱼ aⱼ kⱼ[i] over one sparse row.
#[inline(always)]
fn weigh(k: &[f64], n: usize, row: &[(usize, f64)], i: usize) -> f64 {
    let mut acc = 0.0;
    for &(j, a) in row {
        acc += a * k[j * n + i];
    }
    acc
}

impl<S: OdeSystem, const N: usize> Stepper for Dop853<S, N> {
    fn abs_tol(&self) -> Option<&[f64]> {
        Some(&self.atol)
    }
    fn method_name(&self) -> &'static str {
        "dop853"
    }
    fn work_done(&self) -> Work {
        self.work
    }
    fn stiff_from(&self) -> Option<f64> {
        self.stiff_at
    }
    fn requests(&mut self) -> &mut Requests {
        &mut self.requests
    }
    fn t_stop(&self) -> Option<f64> {
        self.t_stop
    }
    fn window(&self) -> (f64, f64) {
        (self.t_old, self.t)
    }
    fn current(&self) -> &[f64] {
        &self.y
    }
    fn raw_step(&mut self) -> Result<(), SolveError> {
        self.start_next();
        self.try_step()
    }
    fn interpolate(&mut self, t: f64, out: &mut [f64]) {
        self.dense_coefficients();
        let n = self.n();
        let x = (t - self.t_old) / self.h_last;
        let x1 = 1.0 - x;
        let d = &self.dense;
        for i in 0..n {
            let mut p = d[6 * n + i] * x;
            p = (p + d[5 * n + i]) * x1;
            p = (p + d[4 * n + i]) * x;
            p = (p + d[3 * n + i]) * x1;
            p = (p + d[2 * n + i]) * x;
            p = (p + d[n + i]) * x1;
            p = (p + d[i]) * x;
            out[i] = self.y_old[i] + p;
        }
    }
}
