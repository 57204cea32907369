//! Automatic choice between the explicit and the implicit method: DOP853
//! while the problem is not stiff, Radau IIA from the first point where
//! DOP853's stiffness test fires, on the same trajectory.
//!
//! The handover happens lazily, at the first step after the detection, so
//! requests inside the last explicit step are still served by DOP853's
//! dense output and the trajectory has no gap. The switch is one-way: a
//! problem stiff once usually stays stiff, and Radau IIA is accurate (if
//! costlier per step) on non-stiff stretches too.

use super::{
    Dop853, OdeSolver, OdeSystem, Options, Radau5, Requests, Stepper, StiffnessMode, Work,
};
use crate::error::SolveError;

enum Phase<S> {
    Explicit(Box<Dop853<S>>),
    Implicit(Box<Radau5<S>>),
    /// Only while the system moves from one solver to the other.
    Moving,
}

pub struct Auto<S> {
    phase: Phase<S>,
    opts: Options,
    switched_at: Option<f64>,
    /// Work of the explicit phase, once it is over.
    explicit_work: Work,
    requests: Requests,
}

impl<S: OdeSystem> Auto<S> {
    pub fn new(sys: S, t0: f64, y0: &[f64], opts: &Options) -> Result<Auto<S>, SolveError> {
        let dop = Dop853::new(sys, t0, y0, opts)?.with_stiffness(StiffnessMode::Report);
        // Radau's own checks, so a bad setting shows now and not at the switch.
        if opts.rtol <= 10.0 * f64::EPSILON {
            return Err(SolveError::Invalid(format!(
                "auto needs rtol above {:e} (for radau5), not {}",
                10.0 * f64::EPSILON,
                opts.rtol
            )));
        }
        Ok(Auto {
            phase: Phase::Explicit(Box::new(dop)),
            opts: opts.clone(),
            switched_at: None,
            explicit_work: Work::default(),
            requests: Requests::new(t0, y0),
        })
    }

    /// When the switch to Radau IIA happened (the time DOP853 found the
    /// problem stiff), if it did.
    pub fn switched_at(&self) -> Option<f64> {
        self.switched_at
    }

    fn switch(&mut self) -> Result<(), SolveError> {
        let Phase::Explicit(dop) = std::mem::replace(&mut self.phase, Phase::Moving) else {
            return Err(SolveError::Invalid(
                "auto: no explicit phase to leave".into(),
            ));
        };
        let h = dop.next_step_size();
        let (sys, t, y, work) = dop.into_parts();
        self.explicit_work = work;
        let mut opts = self.opts.clone();
        // DOP853's last step is bounded by stability, so it is a safe start;
        // Radau's step control lengthens it within a few steps.
        if h > 0.0 && h.is_finite() {
            opts.h0 = Some(h);
        }
        let radau = Radau5::new(sys, t, &y, &opts)?;
        self.phase = Phase::Implicit(Box::new(radau));
        Ok(())
    }
}

impl<S: OdeSystem> Stepper for Auto<S> {
    fn method_name(&self) -> &'static str {
        match &self.phase {
            Phase::Explicit(_) => "dop853",
            Phase::Implicit(_) => "radau5",
            Phase::Moving => "auto",
        }
    }
    fn size(&self) -> usize {
        self.requests.out.len()
    }
    fn work_done(&self) -> Work {
        match &self.phase {
            Phase::Explicit(d) => d.work(),
            Phase::Implicit(r) => self.explicit_work + r.work(),
            Phase::Moving => self.explicit_work,
        }
    }
    fn stiff_from(&self) -> Option<f64> {
        match &self.phase {
            Phase::Explicit(d) => d.stiffness(),
            _ => self.switched_at,
        }
    }
    fn requests(&mut self) -> &mut Requests {
        &mut self.requests
    }
    fn t_stop(&self) -> Option<f64> {
        self.opts.t_stop
    }
    fn window(&self) -> (f64, f64) {
        match &self.phase {
            Phase::Explicit(d) => d.window(),
            Phase::Implicit(r) => r.window(),
            Phase::Moving => (f64::NAN, f64::NAN),
        }
    }
    fn current(&self) -> &[f64] {
        match &self.phase {
            Phase::Explicit(d) => d.current(),
            Phase::Implicit(r) => r.current(),
            Phase::Moving => &[],
        }
    }
    fn raw_step(&mut self) -> Result<(), SolveError> {
        if let Phase::Explicit(d) = &self.phase
            && let Some(t) = d.stiffness()
        {
            self.switched_at = Some(t);
            self.switch()?;
        }
        match &mut self.phase {
            Phase::Explicit(d) => d.raw_step(),
            Phase::Implicit(r) => r.raw_step(),
            Phase::Moving => Err(SolveError::Invalid("auto: lost its solver".into())),
        }
    }
    fn interpolate(&mut self, t: f64, out: &mut [f64]) {
        match &mut self.phase {
            Phase::Explicit(d) => d.interpolate(t, out),
            Phase::Implicit(r) => r.interpolate(t, out),
            Phase::Moving => out.fill(f64::NAN),
        }
    }
}
