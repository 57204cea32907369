//! The solvers. Shared by both stacks: the DOP853 tableau and its
//! step-size controller (`control`). The rigid body's: the adaptive DOP853,
//! RK4, the splitting methods, and the registry that builds any of them behind the guard, all
//! behind the interface of [`crate::rigid::solver`] (so scenes, the
//! CLI, the bench and the terminal view can switch methods freely). `ode`:
//! the same family, with Radau IIA and stiffness detection, for systems of
//! any size written in a deck.

pub mod budget;
pub mod control;
pub mod dop853;
pub mod dop853_tableau;
pub mod fixed;
pub mod forward;
pub mod guard;
pub mod ode;
pub mod registry;
pub mod rk4;
pub mod splitting;

pub use crate::rigid::solver::{Kind, Method, Needs, Solver, Work};
