//! Torque-free rigid-body rotation: model, solvers, scenes, measurements.
//! Never imports ratatui.

pub mod bench;
pub mod budget;
pub mod cli;
pub mod dop853_tableau;
pub mod dopri;
pub mod elliptic;
pub mod exact;
pub mod formula;
pub mod guard;
pub mod limits;
pub mod measure;
pub mod model;
pub mod ode;
pub mod plan;
pub mod polhode;
pub mod reference;
pub mod rk4;
pub mod run;
pub mod scales;
pub mod scene;
pub mod scene_cli;
pub mod solver;
pub mod splitting;
pub mod system;
pub mod trig;

pub use model::{Body, ModelError, State};
pub use run::{Kind, Options, make, make_with};
pub use solver::{Method, Needs, SimError, Solver, Work};
