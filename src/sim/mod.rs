//! Torque-free rigid-body rotation: model, solvers, scenes, measurements.
//! Never imports ratatui.

pub mod bench;
pub mod cli;
pub mod elliptic;
pub mod exact;
pub mod model;
pub mod solver;

pub use model::{Body, ModelError, State};
pub use solver::{Method, Needs, SimError, Solver, Work};
