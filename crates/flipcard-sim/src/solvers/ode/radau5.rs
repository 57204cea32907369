//! Radau IIA of order 5 (three stages) for stiff systems, after Hairer &
//! Wanner's RADAU5 (*Solving ODEs II*, §IV.8).
//!
//! The stage equations Z = h (A ⊗ I) F(Z) are solved by simplified Newton
//! iterations in the coordinates W = (T⁻¹ ⊗ I) Z that diagonalise A⁻¹ into
//! one real eigenvalue γ and a complex pair α ± iβ, so each iteration needs
//! one real n×n solve with γ/h − J and one complex n×n solve with
//! (α + iβ)/h − J instead of one 3n×3n solve. The complex system is kept
//! complex: an n×n complex LU costs about half the flops of the equivalent
//! 2n×2n real one and half its storage, and is what RADAU5 does.
//!
//! Following RADAU5:
//! - tolerances are mapped to rtol' = 0.1·rtol^(2/3), atol' = rtol'·atol/rtol
//!   (the method's local error is O(h⁴) in the estimate but its global error
//!   O(h⁵), and this map makes the global error track the tolerance);
//! - Newton starts from the previous step's collocation polynomial, stops
//!   when the estimated remaining error is below fnewt = max(10ε/rtol',
//!   min(0.03, √rtol')), and gives up (shrinking h) when its observed
//!   contraction θ reaches 0.99 or when at most 7 iterations cannot reach
//!   fnewt at the observed rate;
//! - the Jacobian is kept across steps while Newton converges in one step
//!   or with θ ≤ 0.001, and the LU factors are kept while the new step lies
//!   within [1, 1.2] times the old one;
//! - the error estimate filters the embedded difference through
//!   (γ/h − J)⁻¹ (one extra real solve), and on the first step or after a
//!   rejection, when that estimate fails, refines it with one more
//!   evaluation of f and solve;
//! - the step size follows Gustafsson's predictive controller, with
//!   h_new/h within [1/8, 5].
//!
//! Unlike RADAU5, the dense output is error-controlled too. The collocation
//! polynomial is exact at the step's ends to the method's order but only
//! O(h⁴) between them, and on a stiff problem the filtered estimate above
//! lets h grow far past what a cubic can follow: on Prothero–Robinson
//! (x' = −k(x − cos t) − sin t, k = 1e6) seven steps cover t ∈ [0, 10]
//! with exact ends and values 0.6 off in between. After each step the
//! interpolant's error is estimated as |y⁽⁴⁾|·h⁴·max|ω|/4!, with ω the
//! node polynomial s(s − c₁)(s − c₂)(s − 1) on [0, 1] (max 0.01825) and
//! y⁽⁴⁾ from how far the previous step's polynomial, extrapolated, misses
//! this step's end, measured against the user's tolerance (not the map
//! above: an interpolation error does not accumulate). A step whose
//! estimate exceeds [`DENSE_REJECT`] is retried shorter, and every next
//! step is capped where the estimate would reach [`DENSE_TARGET`]. On
//! Prothero–Robinson at k = 1e6 and 1e12 the samples then stay within
//! 3.8× the tolerance at every rtol from 1e-3 to 1e-10
//! (`tests/system_hostile.rs`).

use crate::error::SolveError;
use nalgebra::{Complex, DMatrix, DVector};

use super::fixed::Held;
use super::lu::{Factors, LuKind, LuPlan, Reuse};

use super::{BySize, OdeSystem, Options, Requests, Stepper, Work, initial_step, is_sane};

/// T and T⁻¹ with T⁻¹ A⁻¹ T = [[γ, 0, 0], [0, α, −β], [0, β, α]] (RADAU5's
/// published digits; the unit test rebuilds A⁻¹ from them).
#[allow(clippy::excessive_precision)]
const T: [[f64; 3]; 3] = [
    [
        9.1232394870892942792e-2,
        -1.4125529502095420843e-1,
        -3.0029194105147424492e-2,
    ],
    [
        2.4171793270710701896e-1,
        2.0412935229379993199e-1,
        3.8294211275726193779e-1,
    ],
    [9.6604818261509293619e-1, 1.0, 0.0],
];
#[allow(clippy::excessive_precision)]
const TI: [[f64; 3]; 3] = [
    [
        4.3255798900631553510,
        3.3919925181580986954e-1,
        5.4177053993587487119e-1,
    ],
    [
        -4.1787185915519047273,
        -3.2768282076106238708e-1,
        4.7662355450055045196e-1,
    ],
    [
        -5.0287263494578687595e-1,
        2.5719269498556054292,
        -5.9603920482822492497e-1,
    ],
];

/// Newton iterations allowed per step.
const NIT: u32 = 7;
/// Above this contraction the Jacobian is recomputed after a step.
const THET: f64 = 0.001;
const SAFE: f64 = 0.9;
/// Keep h (and the LU factors) while h_new/h lies in [QUOT1, QUOT2].
const QUOT1: f64 = 1.0;
const QUOT2: f64 = 1.2;
/// h_new/h ∈ [1/FACL, 1/FACR] = [1/5, 8].
const FACL: f64 = 5.0;
const FACR: f64 = 0.125;
/// Singular Newton matrices tolerated in a run before giving up.
const MAX_SINGULAR: u32 = 5;
/// max |s(s − c₁)(s − c₂)(s − 1)| over [0, 1]: how far the collocation
/// polynomial's node product reaches between its nodes.
const DENSE_NODE_MAX: f64 = 0.018_253_578_690_16;
/// A step whose dense-output estimate exceeds this many tolerances is
/// retried shorter rather than only capping the next one (the estimate is
/// rough: a factor of a few either way is within its own error).
const DENSE_REJECT: f64 = 3.0;
/// Where the next step is capped, in tolerances. Measured on
/// Prothero–Robinson (k = 1e6, 1e12, 2001 samples) and on the bundled Van
/// der Pol μ = 1000 scene (1435 steps without the cap): at 1.0 the worst
/// sample was within 6.1× the tolerance (radau 4.1×, auto 6.1×) at rtol
/// 1e-3 and 1e-6…1e-10, for 1872 steps (0.8: 1981 steps); the misses at
/// 1e-4 and 1e-5 were [`DENSE_REJECT`]'s.
const DENSE_TARGET: f64 = 1.0;

/// Nodes, the error-estimate weights and the transformed eigenvalues.
#[derive(Debug, Clone, Copy)]
struct Consts {
    c1: f64,
    c2: f64,
    dd: [f64; 3],
    gamma: f64,
    alpha: f64,
    beta: f64,
}

impl Consts {
    fn new() -> Consts {
        let sq6 = 6f64.sqrt();
        let p1 = 81f64.cbrt();
        let p2 = 9f64.cbrt();
        let alph = (12.0 - p1 + p2) / 60.0;
        let beta = (p1 + p2) * 3f64.sqrt() / 60.0;
        let cno = alph * alph + beta * beta;
        Consts {
            c1: (4.0 - sq6) / 10.0,
            c2: (4.0 + sq6) / 10.0,
            dd: [
                -(13.0 + 7.0 * sq6) / 3.0,
                (-13.0 + 7.0 * sq6) / 3.0,
                -1.0 / 3.0,
            ],
            gamma: 30.0 / (6.0 + p1 - p2),
            alpha: alph / cno,
            beta: beta / cno,
        }
    }
}

/// How a step attempt ended when it did not produce a step.
enum Failure {
    /// Error estimate too large: retry with this step.
    Error(f64),
    /// Newton diverged, stalled, or met a non-finite f: halve h.
    Newton,
    /// Newton converges, but too slowly for this h: scale h by the factor.
    Slow(f64),
}

pub struct Radau5<S> {
    sys: S,
    n: usize,
    k: Consts,
    rtol: f64,
    atol: Vec<f64>,
    user_rtol: f64,
    user_atol: Vec<f64>,
    /// What `user_atol` follows, when it follows the sizes.
    by_size: Option<BySize>,
    fnewt: f64,
    max_steps: u64,
    max_step: f64,
    t_stop: Option<f64>,
    fixed: Option<f64>,
    /// The sums of the variables the equations keep fixed, held against
    /// rounding at each accepted step ([`super::fixed`]).
    held: Option<Held>,
    t: f64,
    y: Vec<f64>,
    /// The size the run started from ([`super::start_size`]).
    start: f64,
    /// f(t, y) at the current point.
    f0: Vec<f64>,
    h: f64,
    /// Size of the last accepted step (dense output, Newton start).
    h_old: f64,
    /// A step has been accepted since this solver started (the
    /// dense-output estimate needs a previous polynomial).
    dense_ready: bool,
    t_old: f64,
    /// Collocation polynomial of the last step: y_new and three divided
    /// differences.
    cont: Vec<f64>,
    z: [Vec<f64>; 3],
    /// The last stage's Newton start: the previous polynomial extrapolated
    /// to the step's end (the dense-output estimate compares it with z₃).
    z3_start: Vec<f64>,
    w: [Vec<f64>; 3],
    fz: [Vec<f64>; 3],
    scal: Vec<f64>,
    tmp: Vec<f64>,
    jac: DMatrix<f64>,
    /// How the Newton matrices are factored: dense, banded or sparse,
    /// chosen from the Jacobian's pattern ([`LuPlan::choose`]).
    plan: LuPlan,
    lu: Option<Factors>,
    /// Sparse factorisations that reused the last ones' pivots, and not.
    lu_reuse: Reuse,
    rhs_real: DVector<f64>,
    rhs_complex: DVector<Complex<f64>>,
    /// The right-hand sides reordered, for banded and sparse solves.
    band_real: Vec<f64>,
    band_complex: Vec<Complex<f64>>,
    /// The Jacobian was computed at the current point.
    jac_fresh: bool,
    need_jac: bool,
    /// Step size the LU factors belong to (0 when there are none).
    h_lu: f64,
    first: bool,
    reject: bool,
    faccon: f64,
    theta: f64,
    dynold: f64,
    thqold: f64,
    /// Gustafsson's controller: last accepted h and its error.
    h_acc: f64,
    err_acc: f64,
    singular: u32,
    requests: Requests,
    work: Work,
}

impl<S: OdeSystem> Radau5<S> {
    pub fn new(sys: S, t0: f64, y0: &[f64], opts: &Options) -> Result<Radau5<S>, SolveError> {
        super::check_start(&sys, t0, y0)?;
        let n = sys.dim();
        let (user_atol, by_size) = opts.validated_atol(t0, y0)?;
        if opts.rtol <= 10.0 * f64::EPSILON {
            return Err(SolveError::Invalid(format!(
                "radau5 needs rtol above {:e}, not {}",
                10.0 * f64::EPSILON,
                opts.rtol
            )));
        }
        let rtol = 0.1 * opts.rtol.powf(2.0 / 3.0);
        let atol: Vec<f64> = user_atol.iter().map(|a| rtol * a / opts.rtol).collect();
        let fnewt = (10.0 * f64::EPSILON / rtol).max(0.03f64.min(rtol.sqrt()));
        let mut f0 = vec![0.0; n];
        sys.rhs(t0, y0, &mut f0);
        let mut s = Radau5 {
            n,
            k: Consts::new(),
            rtol,
            atol,
            user_rtol: opts.rtol,
            user_atol,
            by_size,
            fnewt,
            max_steps: opts.max_steps,
            max_step: opts.max_step.unwrap_or(f64::INFINITY),
            t_stop: opts.t_stop,
            fixed: None,
            held: Held::new(sys.fixed_sums(t0, y0), y0),
            t: t0,
            y: y0.to_vec(),
            start: super::start_size(y0),
            f0,
            h: opts.h0.unwrap_or(0.0),
            h_old: 0.0,
            dense_ready: false,
            t_old: t0,
            cont: vec![0.0; 4 * n],
            z: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            z3_start: vec![0.0; n],
            w: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            fz: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            scal: vec![0.0; n],
            tmp: vec![0.0; n],
            jac: DMatrix::zeros(n, n),
            plan: LuPlan::choose(n, sys.sparsity().as_deref()),
            lu: None,
            lu_reuse: Reuse::default(),
            rhs_real: DVector::zeros(n),
            rhs_complex: DVector::zeros(n),
            band_real: Vec::new(),
            band_complex: Vec::new(),
            jac_fresh: false,
            need_jac: true,
            h_lu: 0.0,
            first: true,
            reject: false,
            faccon: 1.0,
            theta: THET,
            dynold: 0.0,
            thqold: 0.0,
            h_acc: 0.0,
            err_acc: 0.01,
            singular: 0,
            requests: Requests::new(t0, y0),
            work: Work {
                rhs_evals: 1,
                ..Work::default()
            },
            sys,
        };
        s.cont[..n].copy_from_slice(y0);
        s.update_scale();
        Ok(s)
    }

    /// Steps of exactly `h`, each with a fresh Jacobian and Newton iterated
    /// to convergence, without error control: the bare collocation method,
    /// for convergence studies.
    pub fn new_fixed(sys: S, t0: f64, y0: &[f64], h: f64) -> Result<Radau5<S>, SolveError> {
        if !(h.is_finite() && h > 0.0) {
            return Err(SolveError::Invalid(format!(
                "step h = {h} must be positive"
            )));
        }
        let mut s = Radau5::new(sys, t0, y0, &Options::default())?;
        s.fixed = Some(h);
        s.h = h;
        // Newton increments are measured against 1e-12·(1 + |y|).
        s.rtol = 1e-12;
        s.atol = vec![1e-12; s.n];
        s.fnewt = 1.0;
        s.update_scale();
        Ok(s)
    }

    /// Factors the Newton matrices in the form `kind` whatever its cost,
    /// from the next factorisation on (to compare the forms on one
    /// problem); false, keeping the chosen form, when the system's pattern
    /// does not allow it.
    pub fn force_lu(&mut self, kind: LuKind) -> bool {
        match LuPlan::forced(kind, self.n, self.sys.sparsity().as_deref()) {
            Some(plan) => {
                self.plan = plan;
                self.lu = None;
                self.h_lu = 0.0;
                true
            }
            None => false,
        }
    }

    /// The form the Newton matrices are factored in.
    pub fn lu_kind(&self) -> LuKind {
        self.plan.kind()
    }

    /// How many sparse factorisations reused the previous pivots and
    /// patterns, and how many were done afresh ([`LuPlan::refactor`]).
    pub fn lu_reuse(&self) -> Reuse {
        self.lu_reuse
    }

    /// Hands the system, the current point and the next step size over
    /// (for `auto`, going back to the explicit method).
    /// The absolute tolerance of each component now (the user's, before
    /// RADAU5's map).
    pub(crate) fn atol_now(&self) -> &[f64] {
        &self.user_atol
    }

    /// The sizes the tolerances follow, when they do.
    pub(crate) fn by_size(&self) -> Option<&BySize> {
        self.by_size.as_ref()
    }

    /// The system it steps.
    pub(crate) fn system(&self) -> &S {
        &self.sys
    }

    pub(crate) fn into_parts(self) -> (S, f64, Vec<f64>, Work, f64) {
        (self.sys, self.t, self.y, self.work, self.h)
    }

    fn update_scale(&mut self) {
        for i in 0..self.n {
            self.scal[i] = self.atol[i] + self.rtol * self.y[i].abs();
        }
    }

    fn budget_error(&self) -> SolveError {
        SolveError::StepBudget {
            t: self.t,
            steps: self.max_steps,
            reason: format!(
                "radau5: {} step attempts reached at t = {} without finishing",
                self.max_steps, self.t
            ),
        }
    }

    fn compute_jacobian(&mut self) -> Result<(), SolveError> {
        self.sys.jacobian(self.t, &self.y, &mut self.jac);
        self.work.jac_evals += 1;
        if self.jac.nrows() != self.n || self.jac.ncols() != self.n {
            return Err(SolveError::Invalid(format!(
                "the Jacobian is {}×{} for a system of {}",
                self.jac.nrows(),
                self.jac.ncols(),
                self.n
            )));
        }
        if !self.jac.as_slice().iter().all(|v| v.is_finite()) {
            return Err(SolveError::Invalid(format!(
                "the Jacobian of f is not finite at t = {}",
                self.t
            )));
        }
        self.jac_fresh = true;
        self.need_jac = false;
        self.h_lu = 0.0;
        Ok(())
    }

    /// LU factors of γ/h − J and (α + iβ)/h − J; false when either is
    /// singular.
    fn decompose(&mut self, h: f64) -> bool {
        let fac1 = self.k.gamma / h;
        let (alphn, betan) = (self.k.alpha / h, self.k.beta / h);
        let (lu, reuse) = self
            .plan
            .refactor(self.lu.take(), &self.jac, fac1, alphn, betan);
        self.lu_reuse += reuse;
        self.work.lu_decomps += 1;
        self.work.lu = Some(self.plan.kind());
        let ok = lu.is_invertible();
        self.lu = Some(lu);
        self.h_lu = if ok { h } else { 0.0 };
        ok
    }

    /// The step the next attempt uses: within max_step, and landing on
    /// t_stop rather than stopping just short of it.
    fn clipped(&self, h: f64) -> f64 {
        let mut h = h.min(self.max_step);
        if let Some(stop) = self.t_stop
            && self.t + 1.0001 * h >= stop
        {
            h = stop - self.t;
        }
        h
    }

    /// One accepted step, after as many rejected attempts as it takes.
    fn try_step(&mut self) -> Result<(), SolveError> {
        if self.h == 0.0 {
            let h_max = self
                .max_step
                .min(self.t_stop.map_or(f64::INFINITY, |s| s - self.t));
            self.h = initial_step(
                &self.sys,
                self.t,
                &self.y,
                &self.f0,
                self.user_rtol,
                &self.user_atol,
                4.0,
                h_max,
            );
            self.work.rhs_evals += 1;
        }
        loop {
            let h = self.clipped(self.h);
            self.h = h;
            if h.is_nan() || 0.1 * h <= self.t.abs() * f64::EPSILON {
                return Err(super::collapse(self.t, h, &self.y, self.start));
            }
            if self.fixed.is_some() && !self.jac_fresh {
                self.need_jac = true;
            }
            if self.need_jac {
                self.compute_jacobian()?;
            }
            if self.h_lu != h && !self.decompose(h) {
                self.singular += 1;
                if self.singular >= MAX_SINGULAR {
                    return Err(SolveError::Invalid(format!(
                        "radau5: the Newton matrix is repeatedly singular near t = {}",
                        self.t
                    )));
                }
                self.reject_with(0.5)?;
                continue;
            }
            if self.work.steps + self.work.rejected >= self.max_steps {
                return Err(self.budget_error());
            }
            match self.attempt(h) {
                Ok(()) => return Ok(()),
                Err(Failure::Error(h_new)) => {
                    self.reject = true;
                    self.work.rejected += 1;
                    self.h = if self.first { 0.1 * h } else { h_new };
                    if !self.jac_fresh {
                        self.need_jac = true;
                    }
                }
                Err(Failure::Newton) => self.reject_with(0.5)?,
                Err(Failure::Slow(factor)) => self.reject_with(factor)?,
            }
        }
    }

    /// Rejects the attempt and scales h, refreshing the Jacobian unless it
    /// is already the current point's.
    fn reject_with(&mut self, factor: f64) -> Result<(), SolveError> {
        if self.fixed.is_some() {
            return Err(SolveError::Invalid(format!(
                "radau5: Newton does not converge with the fixed step h = {} at t = {}",
                self.h, self.t
            )));
        }
        self.h *= factor;
        self.reject = true;
        self.work.rejected += 1;
        if !self.jac_fresh {
            self.need_jac = true;
        }
        Ok(())
    }

    /// Newton starting values: zero on the first step, else the previous
    /// collocation polynomial extrapolated to the new stages.
    fn start_values(&mut self, h: f64) {
        let n = self.n;
        if self.first {
            for v in self.z.iter_mut().chain(self.w.iter_mut()) {
                v.fill(0.0);
            }
            return;
        }
        let Consts { c1, c2, .. } = self.k;
        let (c1m1, c2m1) = (c1 - 1.0, c2 - 1.0);
        let c3q = h / self.h_old;
        let q = [c1 * c3q, c2 * c3q, c3q];
        for i in 0..n {
            let (a1, a2, a3) = (self.cont[n + i], self.cont[2 * n + i], self.cont[3 * n + i]);
            let mut zi = [0.0; 3];
            for s in 0..3 {
                zi[s] = q[s] * (a1 + (q[s] - c2m1) * (a2 + (q[s] - c1m1) * a3));
                self.z[s][i] = zi[s];
            }
            for (r, w) in self.w.iter_mut().enumerate() {
                w[i] = TI[r][0] * zi[0] + TI[r][1] * zi[1] + TI[r][2] * zi[2];
            }
            self.z3_start[i] = zi[2];
        }
    }

    /// Evaluates f at the three stages into `fz`; false if any value is
    /// not finite.
    fn stage_values(&mut self, h: f64) -> bool {
        let nodes = [self.k.c1, self.k.c2, 1.0];
        for ((c, z), f) in nodes.iter().zip(&self.z).zip(self.fz.iter_mut()) {
            for ((tmp, y), z) in self.tmp.iter_mut().zip(&self.y).zip(z) {
                *tmp = y + z;
            }
            self.sys.rhs(self.t + c * h, &self.tmp, f);
        }
        self.work.rhs_evals += 3;
        self.fz.iter().all(|f| f.iter().all(|v| v.is_finite()))
    }

    /// One simplified Newton increment ΔW into `rhs_real` (first
    /// coordinate) and `rhs_complex` (second + i·third); false when a solve
    /// meets a singular factor.
    fn newton_increment(&mut self, h: f64) -> bool {
        let fac1 = self.k.gamma / h;
        let (alphn, betan) = (self.k.alpha / h, self.k.beta / h);
        for i in 0..self.n {
            let a = [self.fz[0][i], self.fz[1][i], self.fz[2][i]];
            let t = |r: usize| TI[r][0] * a[0] + TI[r][1] * a[1] + TI[r][2] * a[2];
            let (s2, s3) = (-self.w[1][i], -self.w[2][i]);
            self.rhs_real[i] = t(0) - fac1 * self.w[0][i];
            self.rhs_complex[i] = Complex::new(
                t(1) + s2 * alphn - s3 * betan,
                t(2) + s3 * alphn + s2 * betan,
            );
        }
        let Some(lu) = &self.lu else {
            return false;
        };
        lu.solve_real(&mut self.rhs_real, &mut self.band_real)
            && lu.solve_complex(&mut self.rhs_complex, &mut self.band_complex)
    }

    /// One attempt at a step of size h with the current factors.
    fn attempt(&mut self, h: f64) -> Result<(), Failure> {
        let n = self.n;
        let fixed = self.fixed.is_some();
        let nit = if fixed { 60 } else { NIT };
        self.start_values(h);
        let mut newt = 0;
        self.faccon = self.faccon.max(f64::EPSILON).powf(0.8);
        self.theta = THET;
        loop {
            if newt >= nit {
                return Err(Failure::Newton);
            }
            if !self.stage_values(h) || !self.newton_increment(h) {
                return Err(Failure::Newton);
            }
            newt += 1;
            let mut sum = 0.0;
            for i in 0..n {
                let s = self.scal[i];
                let d = [
                    self.rhs_real[i],
                    self.rhs_complex[i].re,
                    self.rhs_complex[i].im,
                ];
                sum += d.iter().map(|d| (d / s).powi(2)).sum::<f64>();
            }
            let dyno = (sum / (3 * n) as f64).sqrt();
            if !dyno.is_finite() {
                return Err(Failure::Newton);
            }
            if newt > 1 && newt < nit {
                let thq = dyno / self.dynold;
                self.theta = if newt == 2 {
                    thq
                } else {
                    (thq * self.thqold).sqrt()
                };
                self.thqold = thq;
                if self.theta < 0.99 {
                    self.faccon = self.theta / (1.0 - self.theta);
                    let dyth =
                        self.faccon * dyno * self.theta.powi((nit - 1 - newt) as i32) / self.fnewt;
                    if dyth >= 1.0 && !fixed {
                        let qnewt = dyth.clamp(1e-4, 20.0);
                        let exponent = -1.0 / (4.0 + nit as f64 - 1.0 - newt as f64);
                        return Err(Failure::Slow(0.8 * qnewt.powf(exponent)));
                    }
                } else if fixed && dyno < 10.0 {
                    // Increments at the rounding floor stop contracting;
                    // the iteration has converged as far as it can.
                    self.apply_increment();
                    break;
                } else {
                    return Err(Failure::Newton);
                }
            }
            self.dynold = dyno.max(f64::EPSILON);
            self.apply_increment();
            if self.faccon * dyno <= self.fnewt {
                break;
            }
        }
        let err = if fixed { 0.0 } else { self.error_estimate(h) };
        self.conclude(h, err, newt)
    }

    /// W += ΔW, Z = (T ⊗ I) W.
    fn apply_increment(&mut self) {
        for i in 0..self.n {
            self.w[0][i] += self.rhs_real[i];
            self.w[1][i] += self.rhs_complex[i].re;
            self.w[2][i] += self.rhs_complex[i].im;
            let w = [self.w[0][i], self.w[1][i], self.w[2][i]];
            for (z, t) in self.z.iter_mut().zip(&T) {
                z[i] = t[0] * w[0] + t[1] * w[1] + t[2] * w[2];
            }
        }
    }

    /// Scaled RMS of the embedded error, filtered through (γ/h − J)⁻¹.
    fn error_estimate(&mut self, h: f64) -> f64 {
        let n = self.n;
        let hee = [self.k.dd[0] / h, self.k.dd[1] / h, self.k.dd[2] / h];
        for i in 0..n {
            let e = hee[0] * self.z[0][i] + hee[1] * self.z[1][i] + hee[2] * self.z[2][i];
            self.tmp[i] = e;
            self.rhs_real[i] = e + self.f0[i];
        }
        let Some(lu1) = &self.lu else {
            return f64::INFINITY;
        };
        lu1.solve_real(&mut self.rhs_real, &mut self.band_real);
        let mut err = self.scaled_rms_real();
        if err >= 1.0 && (self.first || self.reject) {
            // A stiff component can make the first estimate pessimistic;
            // one more evaluation of f at the perturbed point corrects it.
            let probe: Vec<f64> = (0..n).map(|i| self.y[i] + self.rhs_real[i]).collect();
            let mut f = vec![0.0; n];
            self.sys.rhs(self.t, &probe, &mut f);
            self.work.rhs_evals += 1;
            for (i, f) in f.iter().enumerate() {
                self.rhs_real[i] = f + self.tmp[i];
            }
            lu1.solve_real(&mut self.rhs_real, &mut self.band_real);
            err = self.scaled_rms_real();
        }
        err
    }

    /// The dense output's estimated error on a step of size h, in the
    /// user's tolerances (RMS over components); 0 before there is a previous
    /// step to compare with, or on fixed steps.
    ///
    /// The previous step's polynomial, extrapolated to this step's end (the
    /// Newton start of the last stage), misses y_new by y⁽⁴⁾·h_old⁴·ω(1 + r)/4!
    /// with r = h/h_old and ω that polynomial's node product; this step's
    /// own polynomial is off between its nodes by y⁽⁴⁾·h⁴·max|ω|/4!. The
    /// ratio of the two turns the miss, which is measured, into the
    /// estimate. Unlike a difference of third derivatives, the miss is not
    /// divided by h³, so the Newton iteration's leftover error in the stage
    /// values stays at its own size (tried first: on E5 at rtol 1e-10 it
    /// held the estimate at 0.83 while h shrank to nothing).
    fn dense_error(&self, h: f64) -> f64 {
        if !self.dense_ready || self.fixed.is_some() || self.h_old <= 0.0 {
            return 0.0;
        }
        let Consts { c1, c2, .. } = self.k;
        let r = h / self.h_old;
        let s = 1.0 + r;
        let node_product = s * (s - c1) * (s - c2) * r;
        let ratio = DENSE_NODE_MAX * r.powi(4) / node_product;
        let mut sum = 0.0;
        for i in 0..self.n {
            let miss = self.z3_start[i] - self.z[2][i];
            let size = self.y[i].abs().max((self.y[i] + self.z[2][i]).abs());
            let scale = self.user_atol[i] + self.user_rtol * size;
            let e = miss * ratio / scale;
            sum += e * e;
        }
        let est = (sum / self.n as f64).sqrt();
        if est.is_finite() { est } else { 0.0 }
    }

    /// The factor on h that brings a dense-output estimate to about
    /// [`DENSE_TARGET`].
    fn dense_factor(est: f64) -> f64 {
        (DENSE_TARGET / est).powf(0.25).max(FACR)
    }

    fn scaled_rms_real(&self) -> f64 {
        let n = self.n;
        let sum: f64 = (0..n)
            .map(|i| (self.rhs_real[i] / self.scal[i]).powi(2))
            .sum();
        let err = (sum / n as f64).sqrt().max(1e-10);
        if err.is_nan() { f64::INFINITY } else { err }
    }

    /// Accepts the step or says how to retry it.
    fn conclude(&mut self, h: f64, err: f64, newt: u32) -> Result<(), Failure> {
        let n = self.n;
        let cfac = SAFE * (1 + 2 * NIT) as f64;
        let fac = SAFE.min(cfac / (newt + 2 * NIT) as f64);
        let mut quot = FACR.max(FACL.min(err.powf(0.25) / fac));
        let mut h_new = h / quot;
        if err >= 1.0 {
            return Err(Failure::Error(h_new));
        }
        let dense = self.dense_error(h);
        if dense > DENSE_REJECT {
            return Err(Failure::Error(h * Self::dense_factor(dense)));
        }
        let t_new = self.t + h;
        for i in 0..n {
            self.tmp[i] = self.y[i] + self.z[2][i];
        }
        if let Some(held) = &self.held {
            held.hold(&mut self.tmp, |i, _| self.scal[i]);
        }
        if !is_sane(&self.tmp) {
            return Err(Failure::Newton);
        }
        // The stage values are spent, so their buffer takes f(t_new, y_new).
        self.sys.rhs(t_new, &self.tmp, &mut self.fz[0]);
        self.work.rhs_evals += 1;
        if !self.fz[0].iter().all(|v| v.is_finite()) {
            return Err(Failure::Newton);
        }
        if self.fixed.is_none() {
            if self.work.steps >= 1 {
                let facgus = (self.h_acc / h) * (err * err / self.err_acc).powf(0.25) / SAFE;
                quot = quot.max(FACR.max(FACL.min(facgus)));
                h_new = h / quot;
            }
            self.h_acc = h;
            self.err_acc = err.max(0.01);
        }
        self.first = false;
        self.work.steps += 1;
        let Consts { c1, c2, .. } = self.k;
        let (c1m1, c2m1, c1mc2) = (c1 - 1.0, c2 - 1.0, c1 - c2);
        for i in 0..n {
            let (z1, z2, z3) = (self.z[0][i], self.z[1][i], self.z[2][i]);
            let d1 = (z2 - z3) / c2m1;
            let ak = (z1 - z2) / c1mc2;
            let acont3 = (ak - z1 / c1) / c2;
            let d2 = (ak - d1) / c1m1;
            self.cont[i] = self.tmp[i];
            self.cont[n + i] = d1;
            self.cont[2 * n + i] = d2;
            self.cont[3 * n + i] = d2 - acont3;
        }
        self.t_old = self.t;
        self.h_old = h;
        self.t = t_new;
        self.y.copy_from_slice(&self.tmp);
        std::mem::swap(&mut self.f0, &mut self.fz[0]);
        self.jac_fresh = false;
        if let Some(b) = &mut self.by_size {
            b.follow(self.t, &self.y, &mut self.user_atol);
            for (a, u) in self.atol.iter_mut().zip(&self.user_atol) {
                *a = self.rtol * u / self.user_rtol;
            }
        }
        self.update_scale();
        if let Some(fixed) = self.fixed {
            self.h = fixed;
            return Ok(());
        }
        if self.dense_ready && dense > 0.0 {
            h_new = h_new.min(h * Self::dense_factor(dense));
        }
        self.dense_ready = true;
        if self.reject {
            h_new = h_new.min(h);
        }
        self.reject = false;
        let qt = h_new / h;
        if self.theta <= THET && (QUOT1..=QUOT2).contains(&qt) {
            // Same h: the factors stay valid, and so does the Jacobian.
            return Ok(());
        }
        self.h = h_new;
        if self.theta > THET {
            self.need_jac = true;
        }
        Ok(())
    }
}

impl<S: OdeSystem> Stepper for Radau5<S> {
    fn abs_tol(&self) -> Option<&[f64]> {
        Some(&self.user_atol)
    }
    fn method_name(&self) -> &'static str {
        "radau5"
    }
    fn work_done(&self) -> Work {
        self.work
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
        self.try_step()
    }
    fn interpolate(&mut self, t: f64, out: &mut [f64]) {
        let n = self.n;
        let Consts { c1, c2, .. } = self.k;
        let (c1m1, c2m1) = (c1 - 1.0, c2 - 1.0);
        let s = (t - self.t) / self.h_old;
        for (i, o) in out.iter_mut().enumerate() {
            let c = |r: usize| self.cont[r * n + i];
            *o = c(0) + s * (c(1) + (s - c2m1) * (c(2) + (s - c1m1) * c(3)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn radau_a() -> [[f64; 3]; 3] {
        let s = 6f64.sqrt();
        [
            [
                (88.0 - 7.0 * s) / 360.0,
                (296.0 - 169.0 * s) / 1800.0,
                (-2.0 + 3.0 * s) / 225.0,
            ],
            [
                (296.0 + 169.0 * s) / 1800.0,
                (88.0 + 7.0 * s) / 360.0,
                (-2.0 - 3.0 * s) / 225.0,
            ],
            [(16.0 - s) / 36.0, (16.0 + s) / 36.0, 1.0 / 9.0],
        ]
    }

    fn mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
        let mut c = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                c[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
            }
        }
        c
    }

    /// T·Λ·T⁻¹ must be A⁻¹ with Λ built from γ, α, β: this ties the
    /// transcribed digits of T and T⁻¹ to the eigenvalues used in the
    /// Newton matrices.
    #[test]
    fn transformation_diagonalises_a_inverse() {
        let k = Consts::new();
        let lambda = [
            [k.gamma, 0.0, 0.0],
            [0.0, k.alpha, -k.beta],
            [0.0, k.beta, k.alpha],
        ];
        let a_inv_rebuilt = mul(&mul(&T, &lambda), &TI);
        let a = radau_a();
        let identity = mul(&a, &a_inv_rebuilt);
        for (i, row) in identity.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((v - want).abs() < 1e-13, "A·(TΛT⁻¹)[{i}][{j}] = {v}");
            }
        }
        let ti_t = mul(&TI, &T);
        for (i, row) in ti_t.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((v - want).abs() < 1e-14, "T⁻¹T[{i}][{j}] = {v}");
            }
        }
    }

    /// The last row of A gives the weights (stiffly accurate), and the
    /// nodes are its row sums.
    #[test]
    fn nodes_are_row_sums() {
        let k = Consts::new();
        let a = radau_a();
        let sums: Vec<f64> = a.iter().map(|r| r.iter().sum()).collect();
        assert!((sums[0] - k.c1).abs() < 1e-15);
        assert!((sums[1] - k.c2).abs() < 1e-15);
        assert!((sums[2] - 1.0).abs() < 1e-15);
    }
}
