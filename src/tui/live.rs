//! A scene's simulation as it plays on screen, a rigid body's or a
//! system's: one player. Scene time follows the wall clock (independent of
//! the frame rate) at the chosen speed, and the learner may pause, restart,
//! switch method (`m`) or change the step or tolerance (`[`/`]`). The
//! physics, what it computes for each panel, and the measurements live in
//! the simulator ([`SceneRun`], [`SystemRun`]); what differs between the
//! two here is only which run is the reference (the one a verdict
//! describes: a rigid body's exact solution, a system's auto method at its
//! default tolerance) and what the panels draw.
//!
//! A frame's physics works for at most [`SLICE`] (a [`Slice`]): a scene
//! whose steps cannot keep up with the clock plays slower, and the next key
//! is still read within a frame.

use std::time::Duration;

use crate::deck::{Measure, Scene, SystemScene};
use crate::sim::scene::SceneRun;
use crate::sim::scene::measure::{Measurements, Reading};
use crate::sim::scene::slice::Slice;
use crate::sim::scene::system::{SystemRun, describe, measure_system};
use crate::sim::solvers::ode::{OdeKind, OdeMethod};
use crate::sim::{self, Method};

/// The most one frame's physics may take; the rest of the frame draws and
/// reads keys.
pub const SLICE: Duration = Duration::from_millis(20);

/// What plays.
pub enum Sim {
    /// A torque-free rigid body (its exact solution or a numerical method).
    Rigid(Box<SceneRun>),
    /// A deck's ODE system, with the measures its prompt needs (kept so a
    /// restart plans the same).
    System {
        run: Box<SystemRun>,
        measures: Vec<Measure>,
    },
}

/// A run playing on screen.
pub struct Live {
    sim: Sim,
    /// Speed multiplier (`+`/`-`), a power of two.
    pub speed: f64,
    pub paused: bool,
    /// The last tick stopped at its slice before the time the clock asked
    /// for: the steps cannot keep up, and the run plays slower than its
    /// speed says.
    lagging: bool,
}

/// The method a system scene plays with first and is judged by: auto at
/// its default tolerance.
pub fn system_reference(scene: &SystemScene) -> OdeMethod {
    OdeMethod::default_for(OdeKind::Auto, scene.duration)
}

impl Live {
    /// A rigid body's run of `scene` with `method`.
    pub fn rigid(scene: &Scene, method: Method) -> Result<Live, String> {
        let run = SceneRun::new(scene, method).map_err(|e| e.to_string())?;
        Ok(Live::playing_from(Sim::Rigid(Box::new(run))))
    }

    /// A system's run of `scene` with `method`, planned to measure
    /// `measures`.
    pub fn system(
        scene: &SystemScene,
        method: OdeMethod,
        measures: &[Measure],
    ) -> Result<Live, String> {
        let run = SystemRun::new(scene, method, measures).map_err(|e| e.to_string())?;
        Ok(Live::playing_from(Sim::System {
            run: Box::new(run),
            measures: measures.to_vec(),
        }))
    }

    fn playing_from(sim: Sim) -> Live {
        Live {
            sim,
            speed: 1.0,
            paused: false,
            lagging: false,
        }
    }

    pub fn sim(&self) -> &Sim {
        &self.sim
    }

    /// Scene time shown now.
    pub fn t(&self) -> f64 {
        match &self.sim {
            Sim::Rigid(r) => r.frame().t,
            Sim::System { run, .. } => run.t(),
        }
    }

    pub fn finished(&self) -> bool {
        match &self.sim {
            Sim::Rigid(r) => r.finished(),
            Sim::System { run, .. } => run.finished(),
        }
    }

    pub fn playing(&self) -> bool {
        !self.paused && !self.finished()
    }

    /// Why the run stopped early (a step budget, a diverging step, a
    /// solution leaving its domain).
    pub fn error(&self) -> Option<String> {
        match &self.sim {
            Sim::Rigid(r) => r.error().map(ToString::to_string),
            Sim::System { run, .. } => run.error().map(describe),
        }
    }

    /// The scene's duration and its time unit.
    pub fn timing(&self) -> (f64, &str) {
        match &self.sim {
            Sim::Rigid(r) => (r.scene().duration, &r.scene().time_unit),
            Sim::System { run, .. } => (run.scene().duration, &run.scene().time_unit),
        }
    }

    /// Scene time per wall-clock second at speed 1: a scene in seconds plays
    /// in real time when it lasts 4–12 s, and is stretched or squeezed into
    /// that range otherwise; scenes in other units take about 10 s.
    pub fn base_rate(&self) -> f64 {
        let (duration, unit) = self.timing();
        let d = duration.max(f64::MIN_POSITIVE);
        if unit == "s" {
            d / d.clamp(4.0, 12.0)
        } else {
            d / 10.0
        }
    }

    /// Scene time per wall-clock second now: the base rate times the
    /// learner's speed.
    pub fn rate(&self) -> f64 {
        self.base_rate() * self.speed
    }

    /// Whether the last tick fell behind the clock (see [`Live::tick_within`]).
    pub fn lagging(&self) -> bool {
        self.lagging && self.playing()
    }

    /// Advances by `wall` seconds of wall-clock time, working for at most
    /// [`SLICE`].
    pub fn tick(&mut self, wall: f64) {
        self.tick_within(wall, Slice::lasting(SLICE));
    }

    /// As [`Live::tick`] within `slice`; whether the run reached the time
    /// the clock asked for (false: it stopped at the slice's end, and plays
    /// on from there at the next tick).
    pub fn tick_within(&mut self, wall: f64, slice: Slice) -> bool {
        if !self.playing() {
            return true;
        }
        let target = self.t() + wall * self.rate();
        let reached = match &mut self.sim {
            Sim::Rigid(r) => r.advance_within(target, slice),
            Sim::System { run, .. } => run.advance_within(target, slice),
        };
        self.lagging = !reached;
        reached
    }

    /// The method's label as the status line shows it ("exact",
    /// "rk4 dt 0.01", "auto rtol 1e-8").
    pub fn method_label(&self) -> String {
        match &self.sim {
            Sim::Rigid(r) => r.method().label(),
            Sim::System { run, .. } => run.method().label(),
        }
    }

    /// Whether this is the reference run, the one a verdict describes.
    pub fn is_reference(&self) -> bool {
        match &self.sim {
            Sim::Rigid(r) => r.method() == Method::Exact,
            Sim::System { run, .. } => run.method() == system_reference(run.scene()),
        }
    }

    /// The reference run's label.
    pub fn reference_label(&self) -> String {
        match &self.sim {
            Sim::Rigid(_) => Method::Exact.label(),
            Sim::System { run, .. } => system_reference(run.scene()).label(),
        }
    }

    /// What this run measured so far (the prompt's measures).
    pub fn measurements(&self) -> Measurements {
        match &self.sim {
            Sim::Rigid(r) => r.measurements(),
            Sim::System { run, measures } => run.measurements(measures),
        }
    }

    /// The work of measuring the scene's reference run to its end, to be
    /// done off the UI thread: the physics' answer, whatever method the
    /// learner tried.
    pub fn reference_measurement(
        &self,
    ) -> impl FnOnce() -> Result<Measurements, String> + Send + 'static {
        let sim = match &self.sim {
            Sim::Rigid(r) => Err(r.scene().clone()),
            Sim::System { run, measures } => Ok((run.scene().clone(), measures.clone())),
        };
        move || match sim {
            Err(scene) => {
                crate::sim::scene::measure_scene(&scene, Method::Exact).map_err(|e| e.to_string())
            }
            Ok((scene, measures)) => {
                let values = measure_system(&scene, system_reference(&scene), &measures)
                    .map_err(|e| e.to_string())?;
                // The reference run reaches the scene's end (else it is an
                // error): its evidence covers the whole duration.
                Ok(Measurements::from_readings(
                    measures
                        .iter()
                        .zip(values)
                        .filter_map(|(m, v)| {
                            v.ok().map(|value| Reading {
                                measure: *m,
                                value,
                                formula: None,
                            })
                        })
                        .collect(),
                )
                .over(scene.duration))
            }
        }
    }

    /// The same scene from t = 0 with the same method, at the same speed.
    pub fn restart(&self) -> Result<Live, String> {
        match &self.sim {
            Sim::Rigid(r) => self.with_rigid(r.method()),
            Sim::System { run, .. } => self.with_system(run.method()),
        }
    }

    /// The same scene from t = 0 with the next method family at its default
    /// setting.
    pub fn next_method(&self) -> Result<Live, String> {
        match &self.sim {
            Sim::Rigid(r) => {
                let kind = r.method().kind().next();
                let method =
                    sim::solvers::registry::method(kind, None, None, r.body(), &r.omega0())
                        .map_err(|e| e.to_string())?;
                self.with_rigid(method)
            }
            Sim::System { run, .. } => {
                let kinds = OdeKind::ALL;
                let i = kinds
                    .iter()
                    .position(|k| *k == run.method().kind)
                    .unwrap_or(0);
                let method =
                    OdeMethod::default_for(kinds[(i + 1) % kinds.len()], run.scene().duration);
                self.with_system(method)
            }
        }
    }

    /// The same scene from t = 0 with a larger or smaller step (or a looser
    /// or tighter tolerance); `None` when the method has no step to change
    /// (the exact solution).
    pub fn step(&self, larger: bool) -> Option<Result<Live, String>> {
        match &self.sim {
            Sim::Rigid(r) => r.method().scaled(larger).map(|m| self.with_rigid(m)),
            Sim::System { run, .. } => Some(self.with_system(run.method().finer(!larger))),
        }
    }

    fn with_rigid(&self, method: Method) -> Result<Live, String> {
        let Sim::Rigid(r) = &self.sim else {
            return Err("not a rigid body".into());
        };
        let mut next = Live::rigid(r.scene(), method)?;
        next.speed = self.speed;
        Ok(next)
    }

    fn with_system(&self, method: OdeMethod) -> Result<Live, String> {
        let Sim::System { run, measures } = &self.sim else {
            return Err("not a system".into());
        };
        let mut next = Live::system(run.scene(), method, measures)?;
        next.speed = self.speed;
        Ok(next)
    }
}
