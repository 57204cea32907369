//! The torque-free rigid body: its model, Euler's equations as a system for
//! the stepping solvers, the interface every solver of it offers
//! (`solver`), the exact Jacobi-elliptic solution, the polhode,
//! the closed-form formulas the measurements are checked against, and the
//! limits of what f64 can resolve.

pub mod elliptic;
pub mod euler;
pub mod exact;
pub mod formula;
pub mod limits;
pub mod model;
pub mod polhode;
pub mod reference;
pub mod scales;
pub mod solver;
pub mod trig;
