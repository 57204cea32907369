//! The reference trajectory that scenes play by default and that every
//! error figure is measured against: the exact solver.

use crate::error::SolveError;
use nalgebra::Vector3;

use crate::rigid::exact::Exact;
use crate::rigid::model::Body;
use crate::rigid::solver::{Needs, Solver};

/// The exact solution for `body` and `omega0`, with q only when `needs` asks.
pub(crate) fn exact(
    body: Body,
    omega0: Vector3<f64>,
    needs: Needs,
) -> Result<Box<dyn Solver>, SolveError> {
    Ok(Box::new(Exact::new(body, omega0, needs)?))
}
