//! A scene's simulation as it plays on screen: scene time follows the wall
//! clock (independent of the frame rate) at the chosen speed, and the
//! learner may pause, restart, switch method or change the step. The
//! physics, what it computes for each panel, and the measurements live in
//! [`crate::sim::scene::SceneRun`].

use nalgebra::Vector3;

use crate::deck::Scene;
use crate::sim::rigid::polhode::Polhode;
use crate::sim::scene::measure::Measurements;
use crate::sim::scene::{Diagnostics, Frame, Sample, SceneRun};
use crate::sim::{self, Body, Kind, Method, SimError};

/// The methods `m` cycles through, in order.
pub const KINDS: [Kind; 5] = [
    Kind::Exact,
    Kind::Adaptive,
    Kind::Splitting,
    Kind::Splitting4,
    Kind::Rk4,
];

pub struct LiveRun {
    run: SceneRun,
    /// Speed multiplier (`+`/`-`), a power of two.
    pub speed: f64,
    pub paused: bool,
}

impl LiveRun {
    /// A run of `scene` with `method` (the closed form when `None`).
    pub fn new(scene: &Scene, method: Option<Method>) -> Result<LiveRun, SimError> {
        Ok(LiveRun {
            run: SceneRun::new(scene, method.unwrap_or(Method::Exact))?,
            speed: 1.0,
            paused: false,
        })
    }

    pub fn scene(&self) -> &Scene {
        self.run.scene()
    }
    pub fn body(&self) -> &Body {
        self.run.body()
    }
    pub fn method(&self) -> Method {
        self.run.method()
    }
    /// Scene time shown now.
    pub fn t(&self) -> f64 {
        self.run.frame().t
    }
    pub fn frame(&self) -> &Frame {
        self.run.frame()
    }
    /// ω at the plot's grid times reached so far.
    pub fn trace(&self) -> &[Sample] {
        self.run.trace()
    }
    pub fn polhode(&self) -> Option<&Polhode> {
        self.run.polhode()
    }
    pub fn diagnostics(&self) -> Option<&Diagnostics> {
        self.run.diagnostics()
    }
    /// Why the run stopped early (a step budget, a diverging step).
    pub fn error(&self) -> Option<String> {
        self.run.error().map(ToString::to_string)
    }
    pub fn measurements(&self) -> Measurements {
        self.run.measurements()
    }

    pub fn finished(&self) -> bool {
        self.run.finished()
    }

    pub fn playing(&self) -> bool {
        !self.paused && !self.finished()
    }

    /// Scene time per wall-clock second at speed 1: a scene in seconds plays
    /// in real time when it lasts 4–12 s, and is stretched or squeezed into
    /// that range otherwise; scenes in other units take about 10 s.
    pub fn base_rate(&self) -> f64 {
        let scene = self.run.scene();
        let d = scene.duration.max(f64::MIN_POSITIVE);
        if scene.time_unit == "s" {
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
        let target = self.t() + wall * self.base_rate() * self.speed;
        self.run.advance_to(target);
    }

    /// The same scene from t = 0 with another method, at the same speed.
    pub fn restart_with(&self, method: Method) -> Result<LiveRun, SimError> {
        let mut run = LiveRun::new(self.run.scene(), Some(method))?;
        run.speed = self.speed;
        Ok(run)
    }

    pub fn restart(&self) -> Result<LiveRun, SimError> {
        self.restart_with(self.method())
    }

    /// The next method in [`KINDS`], with its default setting.
    pub fn next_method(&self) -> Result<Method, SimError> {
        let i = KINDS
            .iter()
            .position(|k| kind_of(&self.method()) == *k)
            .unwrap_or(0);
        let kind = KINDS[(i + 1) % KINDS.len()];
        sim::solvers::registry::method(kind, None, None, self.run.body(), &self.run.omega0())
    }

    /// The method with its step doubled or halved (tolerance ×/÷ 100);
    /// `None` for the exact solver, which has no step.
    pub fn scaled_method(&self, larger: bool) -> Option<Method> {
        let f = if larger { 2.0 } else { 0.5 };
        match self.method() {
            Method::Exact => None,
            Method::Adaptive { tol } => {
                let tol = if larger { tol * 100.0 } else { tol / 100.0 };
                Some(Method::Adaptive {
                    tol: tol.clamp(sim::solvers::registry::MIN_TOL, 1e-2),
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
        let body = self.run.body();
        let w0: Vector3<f64> = self.run.omega0();
        let two_t = 2.0 * body.energy(&w0);
        let l = body.l2(&w0).sqrt();
        (0..3)
            .map(|i| {
                let ii = body.inertia[i];
                (two_t / ii).sqrt().min(l / ii)
            })
            .fold(0.0, f64::max)
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
