//! The last line between a solver and a user: every solver built by
//! [`crate::solvers::registry::make_with`] hands out its states through a [`Guard`],
//! which refuses a time beyond the span f64 resolves and any state that
//! cannot belong to the motion, so no caller (the CLI, a scene, the
//! terminal view, the bench) prints a non-finite number or one that only
//! looks like an answer.
//!
//! A state belongs to the motion when it is finite and close to the orbit
//! its start fixes: the energy and |L|² within a factor of two of their
//! initial values, and each |ωᵢ| inside the range the two invariants allow
//! it on the orbit, widened by a quarter of the largest |ω|. An honest but
//! coarse run (a phase behind, an energy off by some percent) stays well
//! inside; a step that diverges, or a splitting whose ω of a needle's thin
//! axis is its rounding error divided by a tiny moment, does not.

use crate::error::SolveError;
use nalgebra::Vector3;

use crate::rigid::limits;
use crate::rigid::model::{Body, State};
use crate::rigid::scales::Scales;
use crate::solvers::{Method, Solver, Work};
use flipcard_text::num::Num;

/// How far outside its range on the orbit a component may stray, as a
/// fraction of the largest |ω| on the orbit.
pub(crate) const SLACK: f64 = 0.25;
/// The largest factor by which the energy or |L|² may drift.
const INVARIANT_FACTOR: f64 = 2.0;

pub(crate) struct Guard {
    inner: Box<dyn Solver>,
    body: Body,
    scales: Scales,
    orientation: bool,
    energy0: f64,
    l2_0: f64,
}

impl Guard {
    pub(crate) fn new(
        inner: Box<dyn Solver>,
        body: Body,
        omega0: &Vector3<f64>,
        scales: Scales,
        orientation: bool,
    ) -> Guard {
        Guard {
            inner,
            body,
            scales,
            orientation,
            energy0: body.energy(omega0),
            l2_0: body.l2(omega0),
        }
    }

    fn advice(&self) -> String {
        match self.inner.method() {
            Method::Exact => "the closed form lost its precision here".to_string(),
            Method::Adaptive { tol } => format!(
                "tol = {} is too loose for this motion: use a smaller tol or the exact method",
                Num(tol)
            ),
            Method::Splitting { dt } | Method::Splitting4 { dt } | Method::Rk4 { dt } => format!(
                "dt = {} is too coarse for this motion: use a smaller dt or the exact method",
                Num(dt)
            ),
        }
    }

    fn check(&self, t: f64, state: &State) -> Result<(), SolveError> {
        let name = self.inner.method().name();
        let w = state.omega;
        let finite = w.iter().all(|v| v.is_finite())
            && (!self.orientation || state.q.coords.iter().all(|v| v.is_finite()));
        if !finite {
            return Err(SolveError::Invalid(format!(
                "{name} diverged before t = {}: ω is no longer a finite number; {}",
                Num(t),
                self.advice()
            )));
        }
        let slack = SLACK * self.scales.spin;
        for k in 0..3 {
            let (lo, hi) = (self.scales.floor[k] - slack, self.scales.extent[k] + slack);
            let v = w[k].abs();
            if v > hi || v < lo {
                return Err(SolveError::Invalid(format!(
                    "{name} left the motion at t = {}: ω{} = {}, but on this orbit |ω{}| stays within [{}, {}]; {}",
                    Num(t),
                    k + 1,
                    Num(w[k]),
                    k + 1,
                    Num(self.scales.floor[k]),
                    Num(self.scales.extent[k]),
                    self.advice()
                )));
            }
        }
        let off = |x: f64, x0: f64| !(x <= x0 * INVARIANT_FACTOR && x >= x0 / INVARIANT_FACTOR);
        let (energy, l2) = (self.body.energy(&w), self.body.l2(&w));
        if self.energy0 > 0.0 && (off(energy, self.energy0) || off(l2, self.l2_0)) {
            return Err(SolveError::Invalid(format!(
                "{name} left the motion at t = {}: energy {} and |L|² {} against {} and {} at the start; {}",
                Num(t),
                Num(energy),
                Num(l2),
                Num(self.energy0),
                Num(self.l2_0),
                self.advice()
            )));
        }
        Ok(())
    }
}

impl Solver for Guard {
    fn method(&self) -> Method {
        self.inner.method()
    }

    fn advance(&mut self, t: f64) -> Result<State, SolveError> {
        limits::check_span(&self.scales, self.orientation, t, "t =")?;
        let state = self.inner.advance(t)?;
        self.check(t, &state)?;
        Ok(state)
    }

    fn work(&self) -> Work {
        self.inner.work()
    }

    fn plan(&mut self, t_end: f64) -> Result<(), SolveError> {
        limits::check_span(&self.scales, self.orientation, t_end, "t =")?;
        self.inner.plan(t_end)
    }
}
