//! The torque-free rigid body: its model, Euler's equations as a system for
//! the stepping solvers, the interface every solver of it offers
//! (`solver`), the exact Jacobi-elliptic solution, the polhode,
//! the closed-form formulas the measurements are checked against, and the
//! limits of what f64 can resolve.

pub(crate) mod elliptic;
pub mod euler;
pub mod exact;
pub mod formula;
pub(crate) mod limits;
pub mod model;
pub mod polhode;
pub(crate) mod reference;
pub mod scales;
pub(crate) mod solver;
pub(crate) mod trig;
