//! The reference trajectory that scenes play by default and that every
//! error figure is measured against: the exact solver.

use nalgebra::Vector3;

use super::model::Body;
use super::run::make;
use super::solver::{Method, Needs, SimError, Solver};

/// The exact solution for `body` and `omega0`, with q only when `needs` asks.
pub fn exact(body: Body, omega0: Vector3<f64>, needs: Needs) -> Result<Box<dyn Solver>, SimError> {
    match make(Method::Exact, body, omega0, needs) {
        // TEMPORARY until the closed form lands: a tight adaptive run.
        Err(SimError::Invalid(msg)) if msg.contains("not part of this build") => {
            make(Method::Adaptive { tol: 1e-13 }, body, omega0, needs)
        }
        other => other,
    }
}
