//! Torque-free rigid-body rotation: model, solvers, scenes, measurements.
//! Never imports ratatui.

pub mod bench;
pub mod cli;
pub mod model;

pub use model::{Body, ModelError, State};
