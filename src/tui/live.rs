//! A scene's simulation as it plays on screen: the solver advanced in scene
//! time that follows the wall clock (independent of the frame rate), the
//! samples the plots draw, and the invariant drift and error the
//! diagnostics line shows. Computes only what the scene shows: no
//! orientation without a body panel, no reference solution without
//! diagnostics.

use nalgebra::Vector3;

use crate::deck::{Panel, Scene};
use crate::sim::{self, Body, Kind, Method, Needs, SimError, Solver, State};

/// Samples kept for the plots over one run.
const SAMPLES: f64 = 600.0;

/// The methods `m` cycles through, in order.
pub const KINDS: [Kind; 5] = [
    Kind::Exact,
    Kind::Adaptive,
    Kind::Splitting,
    Kind::Splitting4,
    Kind::Rk4,
];

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub t: f64,
    pub omega: Vector3<f64>,
}

/// The largest drifts and errors seen so far (relative).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Drift {
    pub energy: f64,
    pub momentum: f64,
    /// Largest |ω − ω_exact| / |ω_exact|; `None` when not computed (the
    /// exact method itself, or no diagnostics panel).
    pub error: Option<f64>,
}

pub struct LiveRun {
    pub scene: Scene,
    pub body: Body,
    pub omega0: Vector3<f64>,
    pub needs: Needs,
    pub method: Method,
    solver: Box<dyn Solver>,
    reference: Option<Box<dyn Solver>>,
    /// Scene time shown now.
    pub t: f64,
    pub state: State,
    pub samples: Vec<Sample>,
    pub drift: Drift,
    /// Speed multiplier (`+`/`-`), a power of two.
    pub speed: f64,
    pub paused: bool,
    /// Why the run stopped early (a step budget, an invalid setting).
    pub error: Option<String>,
    energy0: f64,
    l0: f64,
}

impl LiveRun {
    /// A run of `scene` with `method` (default settings of the exact
    /// solver when `None`).
    pub fn new(scene: &Scene, method: Option<Method>) -> Result<LiveRun, SimError> {
        let body = Body::new(scene.inertia)?;
        let omega0 = sim::model::omega(scene.omega)?;
        let needs = Needs {
            orientation: scene.shows(Panel::Body),
        };
        let method = method.unwrap_or(Method::Exact);
        let mut solver = make_solver(method, body, omega0, needs)?;
        let mut error = None;
        if let Err(e) = solver.plan(scene.duration) {
            error = Some(e.to_string());
        }
        let reference = if scene.shows(Panel::Diagnostics) && method != Method::Exact {
            Some(make_solver(
                Method::Exact,
                body,
                omega0,
                Needs { orientation: false },
            )?)
        } else {
            None
        };
        let state = State::new(omega0);
        Ok(LiveRun {
            scene: scene.clone(),
            body,
            omega0,
            needs,
            method,
            solver,
            reference,
            t: 0.0,
            state,
            samples: vec![Sample {
                t: 0.0,
                omega: omega0,
            }],
            drift: Drift {
                error: if method == Method::Exact || !scene.shows(Panel::Diagnostics) {
                    None
                } else {
                    Some(0.0)
                },
                ..Drift::default()
            },
            speed: 1.0,
            paused: false,
            error,
            energy0: body.energy(&omega0),
            l0: body.l2(&omega0).sqrt(),
        })
    }

    pub fn finished(&self) -> bool {
        self.t >= self.scene.duration || self.error.is_some()
    }

    pub fn playing(&self) -> bool {
        !self.paused && !self.finished()
    }

    /// Scene time per wall-clock second at speed 1: a scene in seconds plays
    /// in real time when it lasts 4–12 s, and is stretched or squeezed into
    /// that range otherwise; scenes in other units take about 10 s.
    pub fn base_rate(&self) -> f64 {
        let d = self.scene.duration.max(f64::MIN_POSITIVE);
        if self.scene.time_unit == "s" {
            d / d.clamp(4.0, 12.0)
        } else {
            d / 10.0
        }
    }

    /// Advances by `wall` seconds of wall-clock time.
    pub fn tick(&mut self, wall: f64) {
        if !self.playing() {
            return;
        }
        let target = (self.t + wall * self.base_rate() * self.speed).min(self.scene.duration);
        self.advance_to(target);
    }

    /// Advances the scene time to `target`, sampling on the way.
    pub fn advance_to(&mut self, target: f64) {
        let step = self.scene.duration / SAMPLES;
        let mut next = self.samples.last().map_or(0.0, |s| s.t) + step;
        while next < target && self.error.is_none() {
            self.step(next);
            next += step;
        }
        if self.error.is_none() && target > self.t {
            self.step(target);
        }
    }

    fn step(&mut self, t: f64) {
        match self.solver.advance(t) {
            Ok(state) => {
                self.t = t;
                self.state = state;
                self.samples.push(Sample {
                    t,
                    omega: state.omega,
                });
                self.measure(t, &state);
            }
            Err(e) => self.error = Some(e.to_string()),
        }
    }

    fn measure(&mut self, t: f64, state: &State) {
        let rel = |a: f64, b: f64| {
            if b != 0.0 {
                (a - b).abs() / b.abs()
            } else {
                (a - b).abs()
            }
        };
        let e = rel(self.body.energy(&state.omega), self.energy0);
        let l = rel(self.body.l2(&state.omega).sqrt(), self.l0);
        self.drift.energy = self.drift.energy.max(e);
        self.drift.momentum = self.drift.momentum.max(l);
        if let Some(reference) = &mut self.reference {
            match reference.advance(t) {
                Ok(exact) => {
                    let norm = exact.omega.norm();
                    let err = (state.omega - exact.omega).norm() / norm.max(f64::MIN_POSITIVE);
                    let prev = self.drift.error.unwrap_or(0.0);
                    self.drift.error = Some(prev.max(err));
                }
                Err(_) => self.drift.error = None,
            }
        }
    }

    /// The same scene from t = 0 with another method.
    pub fn restart_with(&self, method: Method) -> Result<LiveRun, SimError> {
        let mut run = LiveRun::new(&self.scene, Some(method))?;
        run.speed = self.speed;
        Ok(run)
    }

    pub fn restart(&self) -> Result<LiveRun, SimError> {
        self.restart_with(self.method)
    }

    /// The next method in [`KINDS`], with its default setting.
    pub fn next_method(&self) -> Result<Method, SimError> {
        let i = KINDS
            .iter()
            .position(|k| kind_of(&self.method) == *k)
            .unwrap_or(0);
        let kind = KINDS[(i + 1) % KINDS.len()];
        sim::run::method(kind, None, None, &self.body, &self.omega0)
    }

    /// The method with its step (or tolerance) made larger or smaller;
    /// `None` for the exact solver, which has no step.
    pub fn scaled_method(&self, larger: bool) -> Option<Method> {
        let f = if larger { 2.0 } else { 0.5 };
        match self.method {
            Method::Exact => None,
            Method::Adaptive { tol } => {
                let tol = if larger { tol * 100.0 } else { tol / 100.0 };
                Some(Method::Adaptive {
                    tol: tol.clamp(sim::run::MIN_TOL, 1e-2),
                })
            }
            Method::Splitting { dt } => Some(Method::Splitting { dt: dt * f }),
            Method::Splitting4 { dt } => Some(Method::Splitting4 { dt: dt * f }),
            Method::Rk4 { dt } => Some(Method::Rk4 { dt: dt * f }),
        }
    }

    /// A bound on every |ωᵢ| along the orbit, for the plot's range:
    /// |ωᵢ| ≤ √(2T/Iᵢ) and |ωᵢ| ≤ |L|/Iᵢ.
    pub fn omega_bound(&self) -> f64 {
        let two_t = 2.0 * self.energy0;
        (0..3)
            .map(|i| {
                let ii = self.body.inertia[i];
                (two_t / ii).sqrt().min(self.l0 / ii)
            })
            .fold(0.0, f64::max)
    }

    /// |L|, the radius of the momentum sphere.
    pub fn momentum(&self) -> f64 {
        self.l0
    }
}

/// The closed form for the exact method, the factory for the others.
fn make_solver(
    method: Method,
    body: Body,
    omega0: Vector3<f64>,
    needs: Needs,
) -> Result<Box<dyn Solver>, SimError> {
    match method {
        Method::Exact => Ok(Box::new(sim::exact::Exact::new(body, omega0, needs)?)),
        other => sim::make(other, body, omega0, needs),
    }
}

pub fn kind_of(method: &Method) -> Kind {
    match method {
        Method::Exact => Kind::Exact,
        Method::Adaptive { .. } => Kind::Adaptive,
        Method::Splitting { .. } => Kind::Splitting,
        Method::Splitting4 { .. } => Kind::Splitting4,
        Method::Rk4 { .. } => Kind::Rk4,
    }
}

/// "rk4 dt=2.5e-3", "adaptive tol=1e-10", "exact".
pub fn describe(method: &Method) -> String {
    match method {
        Method::Exact => "exact".into(),
        Method::Adaptive { tol } => format!("adaptive tol={tol:.0e}"),
        Method::Splitting { dt } | Method::Splitting4 { dt } | Method::Rk4 { dt } => {
            format!("{} dt={dt:.1e}", method.name())
        }
    }
}
