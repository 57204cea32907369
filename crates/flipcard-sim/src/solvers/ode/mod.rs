//! Solvers for small systems of ordinary differential equations
//! y' = f(t, y), y ∈ ℝⁿ, written by instructors as equations in a deck.
//!
//! A system implements [`OdeSystem`]; a solver is built over it with
//! [`make`] (or a solver's own constructor) and driven through
//! [`OdeSolver::advance`], which lands exactly on each requested time by
//! dense output, so the steps taken never depend on how often a run is
//! sampled.
//!
//! - [`Dop853`]: explicit Dormand–Prince 8(5,3) with Hairer's stiffness
//!   detection (report and go on, or refuse with [`SolveError::Stiff`]).
//! - [`Radau5`]: implicit Radau IIA of order 5 for stiff systems.
//! - [`Rk4`]: classical fixed-step RK4, for teaching comparisons.
//! - [`Verlet`]: Störmer–Verlet (and its order-4 triple jump), symplectic
//!   and fixed-step, for a separable Hamiltonian the system declares.
//! - [`Auto`]: DOP853 until it detects stiffness, then Radau IIA from that
//!   point on the same trajectory.
//!
//! Every method integrates forward in time only. Errors are values and
//! leave the solver stopped: no state containing NaN or ∞ is ever returned.

mod auto;
pub mod band;
mod choice;
mod dop853;
pub mod fixed;
pub mod lu;
mod radau5;
mod rk4;
pub mod sparse;
mod verlet;

use crate::error::SolveError;
pub use crate::rhs::{OdeSystem, finite_difference_jacobian};
use crate::solvers::control::{self, Arithmetic};

pub use crate::rhs::Split;
pub use auto::Auto;
pub(crate) use choice::REFERENCE_RTOL;
pub use choice::{OdeKind, OdeMethod};
pub use dop853::{Dop853, StiffnessMode};
pub use radau5::Radau5;
pub use rk4::Rk4;
pub(crate) use rk4::rk4_step;
pub use verlet::Verlet;

/// Default cap on the step attempts (accepted and rejected) of one run.
pub(crate) const DEFAULT_MAX_STEPS: u64 = 5_000_000;

/// A state component beyond this magnitude counts as a blow-up: its square
/// would overflow, so no method could go on meaningfully.
pub(crate) const BLOW_UP_LIMIT: f64 = 1e150;

/// Absolute tolerance: one for all components, one each, or one each that
/// follows each component's size over the run.
#[derive(Debug, Clone, PartialEq)]
pub enum Atol {
    Scalar(f64),
    PerComponent(Vec<f64>),
    BySize(BySize),
}

/// Absolute tolerances set as one would set them knowing the solution:
/// each component's is `factor` times its recent size, so a component that
/// lives near 1e-12 is controlled at its own size and not swamped by a
/// tolerance made for components near 1 (E5's y2…y4), a large one wastes
/// no work on digits below its size, and one that decays keeps being
/// controlled as it falls (Robertson's y1 falls from 1 to 2e-8 by t = 1e11:
/// a tolerance made from its largest size swamped it and the run ended 46%
/// off at rtol 1e-4). A component the scene gives its own tolerance
/// (`fixed`) keeps it.
///
/// The recent size is the largest |yᵢ(s)|·(s − t₀)/(t − t₀) over the steps
/// so far: the largest size forgotten in proportion to the time elapsed
/// since the start. A component that decays like a power of t (Robertson's
/// y1 ~ 1/t, E5's y2 and y3) is followed at its own size; one that
/// oscillates through zero keeps the tolerance of its amplitude, since its
/// last peak lies a quarter period back (from the second zero on its
/// recent size is at least two thirds of its amplitude, at the first zero
/// of a cosine about a third): pure relative control would creep near
/// every zero. Every tolerance is
/// at least [`BySize::NOISE`] times the largest size any component has
/// reached, so a component that should be zero but carries rounding noise
/// is not chased to the last bit.
#[derive(Debug, Clone, PartialEq)]
pub struct BySize {
    pub factor: f64,
    /// Each component's own tolerance, if it has one (empty: none has).
    pub fixed: Vec<Option<f64>>,
    /// A bound on each component's tolerance, if it has one (empty: none
    /// has): a reference run follows the sizes within what the scene asks.
    pub cap: Vec<Option<f64>>,
    /// The largest |yᵢ| reached so far (empty: nothing seen yet).
    pub seen: Vec<f64>,
    /// Each component's recent size: the largest |yᵢ(s)|·((s − t₀)/(t − t₀))
    /// over the steps so far (empty: nothing seen yet).
    pub recent: Vec<f64>,
    /// The time the sizes were last taken, and the run's start t₀.
    pub at: Option<(f64, f64)>,
}

impl BySize {
    /// The floor of every tolerance, as a fraction of the largest size any
    /// component reached: about one rounding of it (f64's ε is 2.2e-16).
    /// At a hundred roundings (1e-14) Robertson's y2, which ends near 8e-14
    /// beside y3 near 1, was held to ~1e-14 and the run ended 2.7e-9 off at
    /// rtol 1e-10; at 1e-16 it ends 7e-11 off.
    pub const NOISE: f64 = 1e-16;
    /// Sizes above this count as this: a large component keeps the
    /// tolerance a component of size 1 has. Following the whole size
    /// loosened the control where such a component dips low, and on the
    /// Oregonator (sizes up to 1e5, troughs near 1) the timing of its spikes
    /// drifted: its error grew 80–100× (at rtol 1e-3, 1e-6 and 1e-9).
    const CEILING: f64 = 1.0;
    /// The smallest floor: far enough from f64's least numbers that an
    /// error divided by it, and squared, stays finite.
    const TINY: f64 = 1e-100;

    /// Every component's tolerance at factor `factor`, none fixed.
    pub fn new(factor: f64) -> BySize {
        BySize {
            factor,
            fixed: Vec::new(),
            cap: Vec::new(),
            seen: Vec::new(),
            recent: Vec::new(),
            at: None,
        }
    }

    /// Takes the sizes of `y` at `t` (after those of earlier times) into
    /// those seen and writes each component's tolerance into `atol`.
    pub(crate) fn follow(&mut self, t: f64, y: &[f64], atol: &mut [f64]) {
        let n = y.len();
        if self.seen.len() != n {
            self.seen = vec![0.0; n];
        }
        if self.recent.len() != n {
            self.recent = vec![0.0; n];
        }
        // The recent sizes fade by (last − t₀)/(t − t₀) since the sizes
        // were last taken at `last`; a time not after it fades nothing.
        let (fade, at) = match self.at {
            None => (1.0, (t, t)),
            Some((last, t0)) if t.is_finite() && t > last => {
                let fade = (last - t0) / (t - t0);
                (
                    if fade.is_finite() {
                        fade.clamp(0.0, 1.0)
                    } else {
                        1.0
                    },
                    (t, t0),
                )
            }
            Some(at) => (1.0, at),
        };
        self.at = Some(at);
        let mut top = 0.0f64;
        for ((s, r), v) in self.seen.iter_mut().zip(self.recent.iter_mut()).zip(y) {
            *r *= fade;
            if v.is_finite() {
                *s = s.max(v.abs());
                *r = r.max(v.abs());
            }
            top = top.max(*s);
        }
        let floor = self.floor_of(top);
        for (i, a) in atol.iter_mut().enumerate().take(n) {
            *a = match self.fixed.get(i).copied().flatten() {
                Some(fixed) => fixed,
                None => {
                    let follow = (self.factor * self.recent[i].min(Self::CEILING)).max(floor);
                    match self.cap.get(i).copied().flatten() {
                        Some(cap) => follow.min(cap),
                        None => follow,
                    }
                }
            };
        }
    }

    /// The least tolerance a component that follows its size gets, when the
    /// largest size any component has reached is `top`.
    pub fn floor_of(&self, top: f64) -> f64 {
        // Nothing has a size yet (a start at rest): the tolerance a
        // component of size 1 has, until something moves.
        match top > 0.0 {
            true => (Self::NOISE * top).max(Self::TINY),
            false => self.factor,
        }
    }
}

/// Settings shared by the adaptive methods (RK4 uses only `max_steps`).
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// Relative tolerance (each step's error is measured against
    /// atol + rtol·|y| componentwise, in the RMS norm).
    pub rtol: f64,
    pub atol: Atol,
    /// Cap on step attempts (accepted and rejected) before
    /// [`SolveError::StepBudget`].
    pub max_steps: u64,
    /// First step to try; `None` chooses it by Hairer's heuristic.
    pub h0: Option<f64>,
    /// Largest step allowed; `None` for no limit.
    pub max_step: Option<f64>,
    /// A time the steps never cross (the last step before it is shortened
    /// to land on it): the end of the run, or a point where f is not
    /// smooth. Requests beyond it are refused. The step sequence depends
    /// on it, but never on the sample times.
    pub t_stop: Option<f64>,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            rtol: 1e-6,
            atol: Atol::Scalar(1e-9),
            max_steps: DEFAULT_MAX_STEPS,
            h0: None,
            max_step: None,
            t_stop: None,
        }
    }
}

impl Options {
    pub fn with_tol(rtol: f64, atol: f64) -> Options {
        Options {
            rtol,
            atol: Atol::Scalar(atol),
            ..Options::default()
        }
    }

    /// The absolute tolerance of each component at the start `y0`, and
    /// what makes it follow the sizes when it does, after checking every
    /// setting.
    pub(crate) fn validated_atol(
        &self,
        t0: f64,
        y0: &[f64],
    ) -> Result<(Vec<f64>, Option<BySize>), SolveError> {
        let n = y0.len();
        if !(self.rtol.is_finite() && self.rtol >= 0.0 && self.rtol < 1.0) {
            return Err(SolveError::Invalid(format!(
                "rtol = {} must lie in [0, 1)",
                self.rtol
            )));
        }
        let mut by_size = None;
        let atol = match &self.atol {
            Atol::Scalar(a) => vec![*a; n],
            Atol::PerComponent(v) if v.len() == n => v.clone(),
            Atol::PerComponent(v) => {
                return Err(SolveError::Invalid(format!(
                    "atol has {} components for a system of {n}",
                    v.len()
                )));
            }
            Atol::BySize(b) => {
                if !(b.factor.is_finite() && b.factor > 0.0) {
                    return Err(SolveError::Invalid(format!(
                        "the atol factor {} must be positive and finite",
                        b.factor
                    )));
                }
                let lens = [b.fixed.len(), b.cap.len(), b.seen.len(), b.recent.len()];
                if lens.iter().any(|&l| l != 0 && l != n) {
                    return Err(SolveError::Invalid(format!(
                        "atol has {} components for a system of {n}",
                        lens.iter().max().unwrap_or(&0)
                    )));
                }
                let mut b = b.clone();
                let mut atol = vec![0.0; n];
                b.follow(t0, y0, &mut atol);
                by_size = Some(b);
                atol
            }
        };
        if let Some(a) = atol.iter().find(|a| !(a.is_finite() && **a > 0.0)) {
            return Err(SolveError::Invalid(format!(
                "atol = {a} must be positive and finite"
            )));
        }
        if self.max_steps == 0 {
            return Err(SolveError::Invalid("max_steps must be at least 1".into()));
        }
        for (name, v) in [("h0", self.h0), ("max_step", self.max_step)] {
            if let Some(v) = v
                && !(v.is_finite() && v > 0.0)
            {
                return Err(SolveError::Invalid(format!(
                    "{name} = {v} must be positive and finite"
                )));
            }
        }
        if let Some(v) = self.t_stop
            && !v.is_finite()
        {
            return Err(SolveError::Invalid(format!("t_stop = {v} must be finite")));
        }
        Ok((atol, by_size))
    }
}

/// Work counters of a run so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Work {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected step attempts (error too large, or Newton not converging).
    pub rejected: u64,
    /// Evaluations of f by the solver itself (those made inside
    /// [`OdeSystem::jacobian`] are not seen, so not counted: 2n per
    /// Jacobian for the default finite differences).
    pub rhs_evals: u64,
    /// Evaluations of the Jacobian.
    pub jac_evals: u64,
    /// LU decompositions of the Newton matrices (one real and one complex
    /// count as one, as in RADAU5's statistics).
    pub lu_decomps: u64,
    /// How the Newton matrices were factored, once any was.
    pub lu: Option<lu::LuKind>,
}

impl std::ops::Add for Work {
    type Output = Work;
    fn add(self, o: Work) -> Work {
        Work {
            steps: self.steps + o.steps,
            rejected: self.rejected + o.rejected,
            rhs_evals: self.rhs_evals + o.rhs_evals,
            jac_evals: self.jac_evals + o.jac_evals,
            lu_decomps: self.lu_decomps + o.lu_decomps,
            lu: o.lu.or(self.lu),
        }
    }
}

/// A solver advancing one trajectory forward in time.
pub trait OdeSolver {
    /// Short name of the method now stepping ("dop853", "radau5", "rk4").
    fn name(&self) -> &'static str;

    fn dim(&self) -> usize;

    /// The state at `t`. Requests must not go back before the previous one;
    /// between steps the state comes from the dense output of the step that
    /// covers `t`, so the step sequence does not depend on the requests.
    fn advance(&mut self, t: f64) -> Result<&[f64], SolveError>;

    /// Takes one accepted step and returns its interval [t_old, t_new] (for
    /// event location: search the interval with [`OdeSolver::dense`]).
    fn step(&mut self) -> Result<(f64, f64), SolveError>;

    /// The state at a time within the last step's interval, into `out`.
    fn dense(&mut self, t: f64, out: &mut [f64]) -> Result<(), SolveError>;

    /// Time of the last accepted step (the initial time before any).
    fn t(&self) -> f64;

    fn work(&self) -> Work;

    /// The time stiffness was detected, if it was (DOP853 and auto).
    fn stiffness(&self) -> Option<f64>;

    /// The absolute tolerance of each component now (they may follow the
    /// sizes, [`Atol::BySize`]); `None` for a fixed-step method.
    fn atol(&self) -> Option<&[f64]>;
}

/// Which solver [`make`] builds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    Dop853 {
        stiffness: StiffnessMode,
    },
    Radau5,
    Rk4 {
        dt: f64,
    },
    Auto,
    /// Störmer–Verlet (`order` 2) or its triple jump (4), for a system
    /// with a [`Split`].
    Verlet {
        dt: f64,
        order: u8,
    },
}

/// A boxed solver of the chosen method for `sys` from (t0, y0).
pub fn make<S: OdeSystem + 'static>(
    method: Method,
    sys: S,
    t0: f64,
    y0: &[f64],
    opts: &Options,
) -> Result<Box<dyn OdeSolver>, SolveError> {
    Ok(match method {
        Method::Dop853 { stiffness } => {
            Box::new(Dop853::new(sys, t0, y0, opts)?.with_stiffness(stiffness))
        }
        Method::Radau5 => Box::new(Radau5::new(sys, t0, y0, opts)?),
        Method::Rk4 { dt } => Box::new(Rk4::new(sys, t0, y0, dt, opts)?),
        Method::Auto => Box::new(Auto::new(sys, t0, y0, opts)?),
        Method::Verlet { dt, order } => Box::new(Verlet::new(sys, t0, y0, dt, order, opts)?),
    })
}

/// Checks what every constructor needs: a finite start in a system of the
/// right, nonzero size.
pub(crate) fn check_start<S: OdeSystem>(sys: &S, t0: f64, y0: &[f64]) -> Result<(), SolveError> {
    let n = sys.dim();
    if n == 0 {
        return Err(SolveError::Invalid("the system has no components".into()));
    }
    if y0.len() != n {
        return Err(SolveError::Invalid(format!(
            "the initial state has {} components for a system of {n}",
            y0.len()
        )));
    }
    if !t0.is_finite() {
        return Err(SolveError::Invalid(format!("t0 = {t0} must be finite")));
    }
    if let Some(v) = y0.iter().find(|v| !v.is_finite()) {
        return Err(SolveError::Invalid(format!(
            "the initial state holds {v}, not a finite number"
        )));
    }
    Ok(())
}

/// A step-size collapse is called a blow-up only when the solution has
/// grown past this many times its starting size (at least 1).
pub(crate) const GROWTH: f64 = 1e6;

/// The size a run starts from, for [`collapse`]: the largest |y0ᵢ|, at
/// least 1.
pub(crate) fn start_size(y0: &[f64]) -> f64 {
    y0.iter().fold(1.0f64, |m, v| m.max(v.abs()))
}

/// Why the step size collapsed to `h` near `t` at the state `y` of a run
/// that started at size `start`: a blow-up if the solution has grown past
/// [`GROWTH`] times that size (or is no longer finite), else a step size
/// the tolerance cannot be met with ([`SolveError::StepSize`]).
pub(crate) fn collapse(t: f64, h: f64, y: &[f64], start: f64) -> SolveError {
    let grown = y.iter().any(|v| !v.is_finite() || v.abs() > GROWTH * start);
    if grown || h.is_nan() {
        SolveError::BlowUp { t }
    } else {
        SolveError::StepSize { t, h }
    }
}

/// True when every component is finite and within [`BLOW_UP_LIMIT`].
pub(crate) fn is_sane(y: &[f64]) -> bool {
    y.iter().all(|v| v.abs() <= BLOW_UP_LIMIT)
}

/// Hairer's starting step ([`crate::solvers::control::initial_step`]) at
/// (t, y) with f(t, y) = `f0`: the scale atol + rtol·|y|, and f at t + h.
/// Uses one evaluation of f.
#[allow(clippy::too_many_arguments)]
pub(crate) fn initial_step<S: OdeSystem>(
    sys: &S,
    t: f64,
    y: &[f64],
    f0: &[f64],
    rtol: f64,
    atol: &[f64],
    order: f64,
    h_max: f64,
) -> f64 {
    let scale: Vec<f64> = y
        .iter()
        .zip(atol)
        .map(|(y, a)| a + rtol * y.abs())
        .collect();
    let rhs = |h: f64, y1: &[f64], f1: &mut [f64]| sys.rhs(t + h, y1, f1);
    control::initial_step(Arithmetic::Plain, rhs, y, f0, &scale, order, h_max)
}

/// Bookkeeping shared by the solvers: the monotone request time, the output
/// buffer `advance` lends out, and the error that stopped the run.
#[derive(Debug, Clone)]
pub(crate) struct Requests {
    pub last: f64,
    pub out: Vec<f64>,
    pub failed: Option<SolveError>,
}

impl Requests {
    pub fn new(t0: f64, y0: &[f64]) -> Requests {
        Requests {
            last: t0,
            out: y0.to_vec(),
            failed: None,
        }
    }

    /// Refuses a request before the previous one, or any once the run failed.
    pub(crate) fn admit(&mut self, t: f64, t_stop: Option<f64>) -> Result<(), SolveError> {
        if let Some(e) = &self.failed {
            return Err(e.clone());
        }
        if !t.is_finite() || t < self.last {
            return Err(SolveError::Invalid(format!(
                "time {t} is before the previous request {} (runs only go forward)",
                self.last
            )));
        }
        if let Some(stop) = t_stop
            && t > stop
        {
            return Err(SolveError::Invalid(format!(
                "time {t} is beyond t_stop = {stop}"
            )));
        }
        self.last = t;
        Ok(())
    }

    /// Records a failure so every later call reports it too.
    pub fn fail<T>(&mut self, e: SolveError) -> Result<T, SolveError> {
        self.failed = Some(e.clone());
        Err(e)
    }
}

/// The parts of a one-step method that the shared driver needs; every
/// `Stepper` is an [`OdeSolver`] through the blanket impl below.
pub(crate) trait Stepper {
    /// Short name of the method now stepping.
    fn method_name(&self) -> &'static str;
    fn size(&self) -> usize {
        self.current().len()
    }
    fn work_done(&self) -> Work;
    /// The time stiffness was detected, if the method detects it.
    fn stiff_from(&self) -> Option<f64> {
        None
    }
    /// The absolute tolerances now, for a method with error control.
    fn abs_tol(&self) -> Option<&[f64]> {
        None
    }
    fn requests(&mut self) -> &mut Requests;
    fn t_stop(&self) -> Option<f64>;
    /// (t_old, t_new) of the last accepted step.
    fn window(&self) -> (f64, f64);
    fn current(&self) -> &[f64];
    /// Refuses at once a request the budget clearly cannot reach (fixed-step
    /// methods know their step count in advance).
    fn check_span(&self, t: f64) -> Result<(), SolveError> {
        let _ = t;
        Ok(())
    }
    /// A fixed-step method that serves a time before its next grid point
    /// without stepping (by a partial step from its current point, so a
    /// run never steps past the last time asked for): that grid point.
    fn next_grid(&self) -> Option<f64> {
        None
    }
    fn raw_step(&mut self) -> Result<(), SolveError>;
    /// Dense output at t in the window, or ahead of it up to
    /// [`Stepper::next_grid`] (no checks).
    fn interpolate(&mut self, t: f64, out: &mut [f64]);
}

impl<M: Stepper> OdeSolver for M {
    fn name(&self) -> &'static str {
        Stepper::method_name(self)
    }
    fn dim(&self) -> usize {
        Stepper::size(self)
    }
    fn advance(&mut self, t: f64) -> Result<&[f64], SolveError> {
        drive_advance(self, t)
    }
    fn step(&mut self) -> Result<(f64, f64), SolveError> {
        drive_step(self)
    }
    fn dense(&mut self, t: f64, out: &mut [f64]) -> Result<(), SolveError> {
        drive_dense(self, t, out)
    }
    fn t(&self) -> f64 {
        self.window().1
    }
    fn work(&self) -> Work {
        Stepper::work_done(self)
    }
    fn stiffness(&self) -> Option<f64> {
        Stepper::stiff_from(self)
    }
    fn atol(&self) -> Option<&[f64]> {
        Stepper::abs_tol(self)
    }
}

/// `advance` for every method: step until the request is covered, then read
/// the dense output, so requests never influence the steps.
pub(crate) fn drive_advance<M: Stepper>(m: &mut M, t: f64) -> Result<&[f64], SolveError> {
    let t_stop = m.t_stop();
    m.requests().admit(t, t_stop)?;
    if let Err(e) = m.check_span(t) {
        return m.requests().fail(e);
    }
    while m.window().1 < t && m.next_grid().is_none_or(|g| g <= t) {
        if let Err(e) = m.raw_step() {
            return m.requests().fail(e);
        }
    }
    let (t_old, t_new) = m.window();
    if t == t_new {
        let y = m.current().to_vec();
        let r = m.requests();
        r.out.copy_from_slice(&y);
        return Ok(&m.requests().out);
    }
    if t < t_old {
        return Err(SolveError::Invalid(format!(
            "time {t} lies before the last step [{t_old}, {t_new}] (it was stepped past)"
        )));
    }
    let mut out = std::mem::take(&mut m.requests().out);
    m.interpolate(t, &mut out);
    m.requests().out = out;
    if !is_sane(&m.requests().out) {
        return m.requests().fail(SolveError::BlowUp { t: t_old });
    }
    Ok(&m.requests().out)
}

/// `step` for every method.
pub(crate) fn drive_step<M: Stepper>(m: &mut M) -> Result<(f64, f64), SolveError> {
    if let Some(e) = &m.requests().failed {
        return Err(e.clone());
    }
    if let Some(stop) = m.t_stop()
        && m.window().1 >= stop
    {
        return Err(SolveError::Invalid(format!(
            "the run has reached t_stop = {stop}"
        )));
    }
    match m.raw_step() {
        Ok(()) => Ok(m.window()),
        Err(e) => m.requests().fail(e),
    }
}

/// `dense` for every method.
pub(crate) fn drive_dense<M: Stepper>(
    m: &mut M,
    t: f64,
    out: &mut [f64],
) -> Result<(), SolveError> {
    if let Some(e) = &m.requests().failed {
        return Err(e.clone());
    }
    let (t_old, t_new) = m.window();
    if out.len() != m.current().len() {
        return Err(SolveError::Invalid(format!(
            "dense output needs a buffer of {} components, not {}",
            m.current().len(),
            out.len()
        )));
    }
    if !(t >= t_old && t <= t_new) {
        return Err(SolveError::Invalid(format!(
            "time {t} is outside the last step [{t_old}, {t_new}]"
        )));
    }
    if t == t_new {
        out.copy_from_slice(m.current());
    } else {
        m.interpolate(t, out);
    }
    if !is_sane(out) {
        return Err(SolveError::BlowUp { t: t_old });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Each tolerance follows its component's recent size (sizes above 1
    /// counting as 1), never below the noise floor of the largest size of
    /// all; a fixed one stays; a cap bounds one that follows.
    #[test]
    fn tolerances_follow_the_recent_size() {
        let close = |got: [f64; 4], want: [f64; 4]| {
            for (g, w) in got.iter().zip(want) {
                assert!((g - w).abs() <= 1e-12 * w, "{got:?} against {want:?}");
            }
        };
        let mut b = BySize::new(1e-2);
        let mut atol = [0.0; 4];
        // 1e-9 at its own size; 0 at the noise floor (1e-16 × 5); 5 as 1.
        b.follow(0.0, &[1e-9, 0.0, 5.0, 0.5], &mut atol);
        close(atol, [1e-11, 5e-16, 1e-2, 5e-3]);
        b.follow(1.0, &[1e-9, 0.0, 5.0, 0.5], &mut atol);
        close(atol, [1e-11, 5e-16, 1e-2, 5e-3]);
        // At t = 4 the sizes of t = 1 count a quarter: 0.5 as 0.125, above
        // its 0.1 now; 5 as 1.25, still 1; 1e-9 as 2.5e-10, below 1e-9.
        b.follow(4.0, &[1e-9, 0.0, -0.001, 0.1], &mut atol);
        close(atol, [1e-11, 5e-16, 1e-2, 1.25e-3]);
        // A component that decays like 1/t is followed at its size: its
        // tolerance at t = 400 is that of its size there, not of t = 4's;
        // the sizes of t = 1 count 1/400 (5 as 0.0125, 0.5 as 0.00125).
        b.follow(40.0, &[1e-10, 0.0, 0.0, 0.01], &mut atol);
        b.follow(400.0, &[1e-11, 0.0, 0.0, 0.001], &mut atol);
        close(atol, [1e-13, 5e-16, 1.25e-4, 1.25e-5]);
        // NaN is no size; a time not after the last fades nothing.
        b.follow(400.0, &[f64::NAN, 1e-3, 0.0, 0.001], &mut atol);
        close(atol, [1e-13, 1e-5, 1.25e-4, 1.25e-5]);
        // Beside a component of size 1, one of size 1e-20 is held at the
        // noise floor, not at 1e-22.
        let mut b = BySize {
            fixed: vec![Some(1e-30), None, None, None],
            cap: vec![None, Some(1e-16), None, None],
            ..BySize::new(1e-2)
        };
        b.follow(0.0, &[1.0, 1.0, 1e-20, 0.0], &mut atol);
        close(atol, [1e-30, 1e-16, 1e-16, 1e-16]);
        // Everything still exactly zero (a start at rest): the tolerance of
        // a component of size 1, until something moves.
        let mut b = BySize::new(1e-8);
        b.follow(0.0, &[0.0, 0.0, 0.0, 0.0], &mut atol);
        assert_eq!(atol, [1e-8; 4]);
        b.follow(1.0, &[1e-200, 0.0, 0.0, 0.0], &mut atol);
        assert_eq!(atol, [1e-100; 4]);
    }

    /// A component that oscillates through zero keeps the tolerance of its
    /// amplitude at every zero (no collapse there); one that decays as a
    /// power of t is followed within a small factor of its size.
    #[test]
    fn an_oscillation_keeps_its_amplitude_and_a_decay_is_followed() {
        let mut b = BySize::new(1e-2);
        let mut atol = [0.0; 2];
        let steps = 20_000;
        let mut at_zeros = f64::INFINITY;
        for k in 0..=steps {
            let t = 50.0 * k as f64 / steps as f64;
            // Amplitude 0.5 (below the ceiling), period 2π; 1/(1 + t).
            let y = [0.5 * t.cos(), 1.0 / (1.0 + t)];
            b.follow(t, &y, &mut atol);
            if y[0].abs() < 1e-3 {
                at_zeros = at_zeros.min(atol[0]);
            }
            if t > 1.0 {
                let ratio = atol[1] / (1e-2 * y[1]);
                assert!((1.0..=2.0).contains(&ratio), "t = {t}: {ratio}");
            }
        }
        // A third of the amplitude's tolerance at the first zero, then more.
        assert!(at_zeros >= 1e-2 * 0.5 / 3.0, "{at_zeros:e}");
    }

    /// A `BySize` of the wrong length or factor is refused like any other
    /// atol, and its start is the tolerance of the initial state.
    #[test]
    fn a_by_size_tolerance_is_validated_and_starts_from_y0() {
        let opts = |b: BySize| Options {
            atol: Atol::BySize(b),
            ..Options::default()
        };
        let (atol, b) = opts(BySize::new(1e-8))
            .validated_atol(0.0, &[2.0, 1e-6])
            .unwrap();
        // 2 counts as 1; 1e-6 at its own size, 1e-14 (above the floor 2e-16).
        assert_eq!(atol, vec![1e-8, 1e-14]);
        assert_eq!(b.unwrap().seen, vec![2.0, 1e-6]);
        for bad in [
            BySize::new(0.0),
            BySize::new(f64::NAN),
            BySize {
                fixed: vec![None],
                ..BySize::new(1e-8)
            },
            BySize {
                fixed: vec![Some(-1.0), None],
                ..BySize::new(1e-8)
            },
        ] {
            assert!(
                opts(bad.clone()).validated_atol(0.0, &[2.0, 1e-6]).is_err(),
                "{bad:?}"
            );
        }
    }

    proptest! {
        /// For any finite trajectory (sizes from 1e-300 to 1e300, zeros,
        /// times going forward or standing still) every tolerance that
        /// follows the sizes is positive, finite and never below the noise
        /// floor of the largest size reached so far, nor above the
        /// tolerance of a component of size 1.
        #[test]
        fn the_default_tolerance_is_positive_finite_and_above_the_floor(
            factor_exp in -16i32..-2,
            rows in proptest::collection::vec(
                (0.0f64..10.0, proptest::collection::vec(
                    prop_oneof![
                        Just(0.0),
                        (-300i32..300, -1.0f64..1.0).prop_map(|(e, m)| m * 10f64.powi(e)),
                    ],
                    3,
                )),
                1..60,
            ),
        ) {
            let factor = 10f64.powi(factor_exp);
            let mut b = BySize::new(factor);
            let mut atol = [0.0; 3];
            let (mut t, mut top) = (0.0, 0.0f64);
            for (dt, y) in rows {
                t += dt;
                top = y.iter().fold(top, |m, v| m.max(v.abs()));
                b.follow(t, &y, &mut atol);
                let floor = b.floor_of(top);
                for a in atol {
                    prop_assert!(a.is_finite() && a > 0.0, "{a} at {t}");
                    prop_assert!(a >= floor, "{a} below the floor {floor}");
                    prop_assert!(a <= factor.max(floor), "{a} above {factor}");
                }
            }
        }
    }
}
