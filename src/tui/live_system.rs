//! A system scene as it plays on screen: scene time follows the wall clock
//! at the chosen speed, like a rigid body's run; pause, restart, `m` cycles
//! the methods for systems, `[`/`]` tighten or loosen the tolerance (RK4:
//! halve or double the step). The physics is
//! [`crate::sim::scene::system::SystemRun`]'s.
//!
//! A frame's physics works for at most [`SLICE`] (a [`Slice`]): a scene
//! whose steps cannot keep up with the clock plays slower, and the next key
//! is still read within a frame.

use std::time::Duration;

use crate::deck::{Measure, SystemScene};
use crate::sim::scene::slice::Slice;
use crate::sim::scene::system::{StartError, SystemRun, describe};
use crate::sim::solvers::ode::{OdeKind, OdeMethod};

/// The most one frame's physics may take; the rest of the frame draws and
/// reads keys.
pub const SLICE: Duration = Duration::from_millis(20);

pub struct LiveSystem {
    run: SystemRun,
    /// The measures the prompt needs (kept so a restart plans the same).
    measures: Vec<Measure>,
    pub speed: f64,
    pub paused: bool,
}

impl LiveSystem {
    pub fn new(
        scene: &SystemScene,
        method: OdeMethod,
        measures: &[Measure],
    ) -> Result<LiveSystem, StartError> {
        Ok(LiveSystem {
            run: SystemRun::new(scene, method, measures)?,
            measures: measures.to_vec(),
            speed: 1.0,
            paused: false,
        })
    }

    pub fn run(&self) -> &SystemRun {
        &self.run
    }
    pub fn scene(&self) -> &SystemScene {
        self.run.scene()
    }
    pub fn method(&self) -> OdeMethod {
        self.run.method()
    }
    pub fn t(&self) -> f64 {
        self.run.t()
    }
    pub fn finished(&self) -> bool {
        self.run.finished()
    }
    pub fn playing(&self) -> bool {
        !self.paused && !self.finished()
    }
    pub fn error(&self) -> Option<String> {
        self.run.error().map(describe)
    }

    /// Scene time per wall-clock second at speed 1, as for rigid bodies.
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

    /// As [`LiveSystem::tick`] within `slice`; whether the run reached the
    /// time the clock asked for (false: it stopped at the slice's end, and
    /// plays on from there at the next tick).
    pub fn tick_within(&mut self, wall: f64, slice: Slice) -> bool {
        if !self.playing() {
            return true;
        }
        let target = self.t() + wall * self.base_rate() * self.speed;
        self.run.advance_within(target, slice)
    }

    pub fn restart_with(&self, method: OdeMethod) -> Result<LiveSystem, StartError> {
        let mut next = LiveSystem::new(self.run.scene(), method, &self.measures)?;
        next.speed = self.speed;
        Ok(next)
    }

    pub fn restart(&self) -> Result<LiveSystem, StartError> {
        self.restart_with(self.method())
    }

    /// The next method for systems, with its default setting.
    pub fn next_method(&self) -> OdeMethod {
        let kinds = OdeKind::ALL;
        let i = kinds
            .iter()
            .position(|k| *k == self.method().kind)
            .unwrap_or(0);
        OdeMethod::default_for(kinds[(i + 1) % kinds.len()], self.scene().duration)
    }
}
