//! A scene's simulation as it plays on screen: scene time follows the wall
//! clock (independent of the frame rate) at the chosen speed, and the
//! learner may pause, restart, switch method or change the step. The
//! physics, what it computes for each panel, and the measurements live in
//! [`crate::sim::scene::SceneRun`]. A frame's physics works for at most
//! [`crate::tui::live_system::SLICE`], so a key is read within a frame.

use crate::deck::Scene;
use crate::sim::rigid::polhode::Polhode;
use crate::sim::scene::measure::Measurements;
use crate::sim::scene::slice::Slice;
use crate::sim::scene::{Diagnostics, Frame, Sample, SceneRun};
use crate::sim::{self, Body, Method, SolveError};
use crate::tui::live_system::SLICE;

pub struct LiveRun {
    run: SceneRun,
    /// Speed multiplier (`+`/`-`), a power of two.
    pub speed: f64,
    pub paused: bool,
}

impl LiveRun {
    /// A run of `scene` with `method` (the closed form when `None`).
    pub fn new(scene: &Scene, method: Option<Method>) -> Result<LiveRun, SolveError> {
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
    /// ω at t = 0.
    pub fn omega0(&self) -> nalgebra::Vector3<f64> {
        self.run.omega0()
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
    /// Times of the flips seen so far, for the live count and the marks.
    pub fn flip_times(&self) -> &[f64] {
        self.run.flip_times()
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

    /// Advances by `wall` seconds of wall-clock time, working for at most
    /// [`SLICE`].
    pub fn tick(&mut self, wall: f64) {
        self.tick_within(wall, Slice::lasting(SLICE));
    }

    /// As [`LiveRun::tick`] within `slice`; whether the run reached the time
    /// the clock asked for.
    pub fn tick_within(&mut self, wall: f64, slice: Slice) -> bool {
        if !self.playing() {
            return true;
        }
        let target = self.t() + wall * self.base_rate() * self.speed;
        self.run.advance_within(target, slice)
    }

    /// The same scene from t = 0 with another method, at the same speed.
    pub fn restart_with(&self, method: Method) -> Result<LiveRun, SolveError> {
        let mut run = LiveRun::new(self.run.scene(), Some(method))?;
        run.speed = self.speed;
        Ok(run)
    }

    pub fn restart(&self) -> Result<LiveRun, SolveError> {
        self.restart_with(self.method())
    }

    /// The next method family, with its default setting.
    pub fn next_method(&self) -> Result<Method, SolveError> {
        let kind = self.method().kind().next();
        sim::solvers::registry::method(kind, None, None, self.run.body(), &self.run.omega0())
    }

    /// A bound on every |ωᵢ| of this run, for the plot's range.
    pub fn omega_bound(&self) -> f64 {
        self.run.body().omega_bound(&self.run.omega0())
    }
}
