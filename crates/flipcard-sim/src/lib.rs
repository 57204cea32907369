//! The simulator: `method` (the one vocabulary of method names), `solvers`
//! (every integrator and the registry that builds them), `rigid` (the torque-free rigid body and its exact solution),
//! `scene` (a deck scene's run and measurements) and `bench` (error against
//! run time). Never imports ratatui, never prints.

pub mod bench;
pub mod error;
pub mod method;
pub mod rhs;
pub mod rigid;
pub mod scene;
pub mod solvers;
pub mod system;

pub use error::{ModelError, SolveError};
pub use rigid::model::{Body, State};
pub use solvers::registry::{Kind, Options, make, make_with};
pub use solvers::{Method, Needs, Solver, Work};
