//! A scene's run as the terminal view plays it, without any drawing: the
//! solver advanced to the time the view asks for, the current frame (ω, q
//! when the body is drawn, the polhode point when the polhode is drawn), a
//! trace of ω for the plot sized to what is drawn, the measurements the
//! verdict needs, and the diagnostics when they are shown.
//!
//! Per frame it evaluates the solver at the measurement and trace grid
//! points the frame passed plus the frame time itself, a few dozen
//! evaluations of a closed form for the bundled scenes.
//!
//! ```no_run
//! # use flipcard_sim::{Method, scene::SceneRun};
//! # fn demo(scene: &flipcard_sim::scene::spec::Scene) -> Result<(), flipcard_sim::SolveError> {
//! let mut run = SceneRun::new(scene, Method::Exact)?;
//! while !run.finished() {
//!     let frame = run.advance_to(run.frame().t + 1.0 / 30.0);
//!     let _ = (frame.omega, frame.q, frame.polhode); // draw
//! }
//! let measured = run.measurements();
//! # Ok(()) }
//! ```

use nalgebra::{UnitQuaternion, Vector3};

use crate::error::SolveError;
use crate::rigid::formula;
use crate::rigid::limits;
use crate::rigid::model::{self, Body, State};
use crate::rigid::polhode::Polhode;
use crate::rigid::reference;
use crate::rigid::scales::scales;
use crate::scene::measure::{Measurements, Meter};
use crate::scene::plan::Plan;
use crate::scene::slice::Slice;
use crate::scene::spec::Scene;
use crate::solvers::registry::make;
use crate::solvers::{Method, Needs, Solver, Work};
use flipcard_text::num::{Num, below};

/// Default number of points of the ω trace (about the width of a wide
/// Braille plot in dots).
pub(crate) const DEFAULT_TRACE_LEN: usize = 512;
/// The measurement grid has at least this many points over the run...
const MIN_METER_POINTS: usize = 2048;
/// ...and this many per radian of the nutation phase λt. ω is a function of
/// λt whose period is at least 2π, so a flip, a wobble or an e-folding
/// (1/√k ≥ 1/λ) spans at least 16 points and is resolved whatever the
/// duration: sparser samples alias a fast motion into a slow one.
pub(crate) const METER_POINTS_PER_RADIAN: f64 = 16.0;
/// The most points a measurement takes (a few seconds of evaluations for
/// the slowest method): a scene whose nutation turns by more than
/// `MAX_METER_POINTS / METER_POINTS_PER_RADIAN` = 65536 rad is refused,
/// not sampled too sparsely.
pub(crate) const MAX_METER_POINTS: usize = 1 << 20;

/// Which input of a scene a refusal is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SceneField {
    Inertia,
    Omega,
    Duration,
}

/// Why the simulator will not run a scene, and which input to fix.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneProblem {
    pub field: SceneField,
    pub error: SolveError,
}

/// The longest duration whose measurements resolve the motion:
/// [`MAX_METER_POINTS`] at [`METER_POINTS_PER_RADIAN`] of the nutation.
pub(crate) fn max_measured_duration(body: &Body, omega0: &Vector3<f64>) -> f64 {
    let rate = scales(body, omega0).nutation;
    if rate > 0.0 {
        MAX_METER_POINTS as f64 / (METER_POINTS_PER_RADIAN * rate)
    } else {
        f64::INFINITY
    }
}

/// Points of the measurement grid over `duration`.
fn meter_points(body: &Body, omega0: &Vector3<f64>, duration: f64) -> Result<usize, SolveError> {
    let rate = scales(body, omega0).nutation;
    let needed = (METER_POINTS_PER_RADIAN * rate * duration).ceil();
    if needed > MAX_METER_POINTS as f64 {
        return Err(SolveError::Invalid(format!(
            "duration {} is longer than the measurements can resolve: they sample ω {} times per radian of its nutation at {} rad/s, at most {} times, which covers {} time units",
            Num(duration),
            Num(METER_POINTS_PER_RADIAN),
            Num(below(rate, 4)),
            MAX_METER_POINTS,
            Num(below(max_measured_duration(body, omega0), 4))
        )));
    }
    Ok((needed as usize).max(MIN_METER_POINTS))
}

/// Every test the simulator puts a scene through before running it, and
/// the same that `flipcard check` reports on a deck: physical moments, a
/// finite ω whose invariants f64 can hold, a positive duration within the
/// span f64 resolves the phase over, and within what the measurements
/// resolve. `orientation`: whether the body is drawn (its spin then counts
/// for the span).
pub fn check_scene(
    inertia: [f64; 3],
    omega: [f64; 3],
    duration: f64,
    orientation: bool,
) -> Result<(Body, Vector3<f64>), SceneProblem> {
    let at = |field: SceneField| move |error: SolveError| SceneProblem { field, error };
    let body = Body::new(inertia)
        .map_err(SolveError::from)
        .map_err(at(SceneField::Inertia))?;
    let omega0 = model::omega(omega)
        .map_err(SolveError::from)
        .map_err(at(SceneField::Omega))?;
    limits::check_start(&body, &omega0).map_err(at(SceneField::Omega))?;
    if !(duration.is_finite() && duration > 0.0) {
        return Err(at(SceneField::Duration)(SolveError::Invalid(format!(
            "duration must be a positive number, got {}",
            Num(duration)
        ))));
    }
    let rates = scales(&body, &omega0);
    limits::check_span(&rates, orientation, duration, "duration")
        .map_err(at(SceneField::Duration))?;
    meter_points(&body, &omega0, duration).map_err(at(SceneField::Duration))?;
    Ok((body, omega0))
}

/// What the view draws now.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    pub t: f64,
    /// Body-frame angular velocity.
    pub omega: Vector3<f64>,
    /// Body → space orientation; only when the scene draws the body.
    pub q: Option<UnitQuaternion<f64>>,
    /// L/|L| in the body frame, on the unit momentum sphere; only when the
    /// scene draws the polhode.
    pub polhode: Option<Vector3<f64>>,
}

/// One point of the ω trace.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub t: f64,
    pub omega: Vector3<f64>,
}

/// Invariant drift so far (largest relative deviation), and the error
/// against the exact solution when the run is not the exact one.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Diagnostics {
    pub energy_drift: f64,
    /// Relative drift of |L|².
    pub momentum_drift: f64,
    /// Largest |ω − ω_exact| / |ω_exact|; `None` for the exact run itself.
    pub error: Option<f64>,
    /// Drift of the space-frame L = q(Iω)q⁻¹ relative to |L|; only with q.
    pub lspace_drift: Option<f64>,
    /// Largest ||q| − 1|; only with q.
    pub qnorm_drift: Option<f64>,
}

/// An evenly spaced grid of `len` times over [0, duration].
#[derive(Debug, Clone, Copy)]
struct Grid {
    len: usize,
    duration: f64,
    next: usize,
}

impl Grid {
    fn time(&self, k: usize) -> f64 {
        if self.len <= 1 {
            0.0
        } else if k + 1 == self.len {
            self.duration
        } else {
            self.duration * k as f64 / (self.len - 1) as f64
        }
    }

    fn peek(&self) -> f64 {
        if self.next < self.len {
            self.time(self.next)
        } else {
            f64::INFINITY
        }
    }
}

pub struct SceneRun {
    scene: Scene,
    plan: Plan,
    body: Body,
    omega0: Vector3<f64>,
    method: Method,
    solver: Box<dyn Solver>,
    reference: Option<Box<dyn Solver>>,
    polhode: Option<Polhode>,
    meter: Meter,
    meter_grid: Grid,
    trace_grid: Grid,
    trace: Vec<Sample>,
    diagnostics: Option<Diagnostics>,
    frame: Frame,
    /// Time of the last state the solver handed out.
    evaluated: f64,
    error: Option<SolveError>,
    energy0: f64,
    l2_0: f64,
    lspace0: Vector3<f64>,
}

impl SceneRun {
    /// A run of `scene` with `method` ([`Plan::default_method`] is the
    /// closed form) and a trace of [`DEFAULT_TRACE_LEN`] points.
    pub fn new(scene: &Scene, method: Method) -> Result<SceneRun, SolveError> {
        SceneRun::with_trace_len(scene, method, DEFAULT_TRACE_LEN)
    }

    /// As [`SceneRun::new`], with a trace of `trace_len` points over the
    /// whole scene (two per Braille column of the plot is plenty).
    pub fn with_trace_len(
        scene: &Scene,
        method: Method,
        trace_len: usize,
    ) -> Result<SceneRun, SolveError> {
        let body = Body::new(scene.inertia)?;
        let plan = Plan::for_scene(scene, &body);
        SceneRun::build(scene, plan, body, method, trace_len)
    }

    /// A run that only measures: no orientation, polhode, diagnostics or
    /// trace, whatever the scene shows.
    pub fn headless(scene: &Scene, method: Method) -> Result<SceneRun, SolveError> {
        let body = Body::new(scene.inertia)?;
        let mut plan = Plan::for_scene(scene, &body);
        plan.needs = Needs { orientation: false };
        plan.polhode = false;
        plan.diagnostics = false;
        SceneRun::build(scene, plan, body, method, 0)
    }

    fn build(
        scene: &Scene,
        plan: Plan,
        body: Body,
        method: Method,
        trace_len: usize,
    ) -> Result<SceneRun, SolveError> {
        let (_, omega0) = check_scene(
            scene.inertia,
            scene.omega,
            scene.duration,
            plan.needs.orientation,
        )
        .map_err(|p| match p.error {
            SolveError::Invalid(m) => SolveError::Invalid(format!("scene {}: {m}", scene.id)),
            other => other,
        })?;
        let mut solver = make(method, body, omega0, plan.needs)?;
        let mut error = solver.plan(scene.duration).err();
        let reference = if plan.reference_run(&method) {
            Some(reference::exact(
                body,
                omega0,
                Needs { orientation: false },
            )?)
        } else {
            None
        };
        let polhode = if plan.polhode {
            let mut exact = reference::exact(body, omega0, Needs { orientation: false })?;
            match Polhode::new(
                &body,
                &omega0,
                exact.as_mut(),
                orbit_span(&body, &omega0, scene.duration),
            ) {
                Ok(p) => Some(p),
                Err(e) => {
                    error.get_or_insert(e);
                    None
                }
            }
        } else {
            None
        };
        let meter_points = meter_points(&body, &omega0, scene.duration)?;
        let frame = Frame {
            t: 0.0,
            omega: omega0,
            q: plan.needs.orientation.then(UnitQuaternion::identity),
            polhode: polhode.as_ref().map(|p| p.point(&body, &omega0)),
        };
        let mut run = SceneRun {
            scene: scene.clone(),
            plan,
            body,
            omega0,
            method,
            solver,
            reference,
            polhode,
            meter: Meter::new(&body, &omega0),
            meter_grid: Grid {
                len: meter_points + 1,
                duration: scene.duration,
                next: 0,
            },
            trace_grid: Grid {
                len: trace_len,
                duration: scene.duration,
                next: 0,
            },
            trace: Vec::with_capacity(trace_len),
            diagnostics: plan.diagnostics.then(|| Diagnostics {
                error: plan.reference_run(&method).then_some(0.0),
                lspace_drift: plan.needs.orientation.then_some(0.0),
                qnorm_drift: plan.needs.orientation.then_some(0.0),
                ..Diagnostics::default()
            }),
            frame,
            evaluated: -1.0,
            error,
            energy0: body.energy(&omega0),
            l2_0: body.l2(&omega0),
            lspace0: body.momentum(&omega0),
        };
        if run.error.is_none() {
            run.advance_to(0.0);
        }
        Ok(run)
    }

    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    #[cfg(test)]
    pub(crate) fn plan(&self) -> &Plan {
        &self.plan
    }

    pub fn body(&self) -> &Body {
        &self.body
    }

    pub fn omega0(&self) -> Vector3<f64> {
        self.omega0
    }

    pub fn method(&self) -> Method {
        self.method
    }

    /// The frame at the last time reached.
    pub fn frame(&self) -> &Frame {
        &self.frame
    }

    /// ω at the trace's grid times reached so far.
    pub fn trace(&self) -> &[Sample] {
        &self.trace
    }

    pub fn polhode(&self) -> Option<&Polhode> {
        self.polhode.as_ref()
    }

    pub fn diagnostics(&self) -> Option<&Diagnostics> {
        self.diagnostics.as_ref()
    }

    /// Whether an exact run goes along for the error figure.
    #[cfg(test)]
    pub(crate) fn has_reference(&self) -> bool {
        self.reference.is_some()
    }

    /// Why the run stopped early (a step budget, a diverging step).
    pub fn error(&self) -> Option<&SolveError> {
        self.error.as_ref()
    }

    pub fn finished(&self) -> bool {
        self.frame.t >= self.scene.duration || self.error.is_some()
    }

    pub fn work(&self) -> Work {
        self.solver.work()
    }

    /// Times of the flips the run has seen so far, for a live count.
    pub fn flip_times(&self) -> &[f64] {
        self.meter.flips()
    }

    /// What the run has measured so far (everything, once finished).
    pub fn measurements(&self) -> Measurements {
        self.meter.finish()
    }

    /// Advances to scene time `t` (clamped to the scene; earlier times are
    /// ignored) and returns the frame there. After an error the frame stays
    /// at the last good state.
    pub fn advance_to(&mut self, t: f64) -> &Frame {
        self.advance_within(t, Slice::WHOLE);
        &self.frame
    }

    /// As [`SceneRun::advance_to`], stopping at the first grid point after
    /// `slice` ends (at least one is evaluated); the frame is then there,
    /// and the next call goes on. Returns whether the run reached `t` (or
    /// stopped for good).
    pub fn advance_within(&mut self, t: f64, slice: Slice) -> bool {
        if t.is_nan() {
            return true;
        }
        let t = t.min(self.scene.duration);
        if self.error.is_some() || t < self.frame.t || (t == self.frame.t && t > 0.0) {
            return true;
        }
        let mut evaluated = false;
        loop {
            let next = self.meter_grid.peek().min(self.trace_grid.peek());
            if next > t {
                break;
            }
            if evaluated && slice.over() {
                return false;
            }
            evaluated = true;
            let Some(state) = self.evaluate(next) else {
                return true;
            };
            if self.meter_grid.peek() == next {
                self.meter.record(next, &state.omega);
                self.meter_grid.next += 1;
            }
            if self.trace_grid.peek() == next {
                self.trace.push(Sample {
                    t: next,
                    omega: state.omega,
                });
                self.trace_grid.next += 1;
            }
            self.set_frame(next, &state);
        }
        if t > self.evaluated
            && let Some(state) = self.evaluate(t)
        {
            self.set_frame(t, &state);
        }
        true
    }

    fn set_frame(&mut self, t: f64, state: &State) {
        self.frame = Frame {
            t,
            omega: state.omega,
            q: self.plan.needs.orientation.then_some(state.q),
            polhode: self
                .polhode
                .as_ref()
                .map(|p| p.point(&self.body, &state.omega)),
        };
    }

    fn evaluate(&mut self, t: f64) -> Option<State> {
        if t <= self.evaluated {
            // The same time twice (a grid point shared by both grids).
            return Some(State {
                omega: self.frame.omega,
                q: self.frame.q.unwrap_or_else(UnitQuaternion::identity),
            });
        }
        match self.solver.advance(t) {
            Ok(state) => {
                self.evaluated = t;
                self.diagnose(t, &state);
                Some(state)
            }
            Err(e) => {
                self.error = Some(e);
                None
            }
        }
    }

    fn diagnose(&mut self, t: f64, state: &State) {
        let Some(d) = self.diagnostics.as_mut() else {
            return;
        };
        let rel = |x: f64, x0: f64| {
            if x0 != 0.0 {
                ((x - x0) / x0).abs()
            } else {
                x.abs()
            }
        };
        d.energy_drift = d
            .energy_drift
            .max(rel(self.body.energy(&state.omega), self.energy0));
        d.momentum_drift = d
            .momentum_drift
            .max(rel(self.body.l2(&state.omega), self.l2_0));
        if self.plan.needs.orientation {
            let l = self.l2_0.sqrt().max(f64::MIN_POSITIVE);
            let drift = (self.body.momentum_in_space(state) - self.lspace0).norm() / l;
            let qn = (state.q.quaternion().norm() - 1.0).abs();
            d.lspace_drift = d.lspace_drift.map(|x| x.max(drift));
            d.qnorm_drift = d.qnorm_drift.map(|x| x.max(qn));
        }
        if let Some(reference) = self.reference.as_mut() {
            match reference.advance(t) {
                Ok(exact) => {
                    let norm = exact.omega.norm().max(f64::MIN_POSITIVE);
                    let err = (state.omega - exact.omega).norm() / norm;
                    d.error = d.error.map(|x| x.max(err));
                }
                Err(_) => d.error = None,
            }
        }
    }
}

/// The span the polhode's closed curve is drawn over: one period of ω, or
/// the scene's duration when ω has none.
fn orbit_span(body: &Body, omega0: &Vector3<f64>, duration: f64) -> f64 {
    formula::period(body, omega0)
        .filter(|p| p.is_finite() && *p > 0.0)
        .unwrap_or(duration)
}

/// Runs `scene` to its end with `method` and measures it; an error when the
/// run cannot reach the end (a step budget).
pub fn measure_scene(scene: &Scene, method: Method) -> Result<Measurements, SolveError> {
    let mut run = SceneRun::headless(scene, method)?;
    run.advance_to(scene.duration);
    match run.error {
        Some(e) => Err(e),
        None => Ok(run.meter.finish()),
    }
}

#[cfg(test)]
mod tests;
