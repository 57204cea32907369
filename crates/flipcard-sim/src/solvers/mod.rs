//! The solvers. Shared by both stacks: the DOP853 tableau and its
//! step-size controller (`control`). The rigid body's: the adaptive DOP853,
//! RK4, the splitting methods, and the registry that builds any of them behind the guard, all
//! behind the interface of [`crate::rigid::solver`] (so scenes, the
//! CLI, the bench and the terminal view can switch methods freely). `ode`:
//! the same family, with Radau IIA and stiffness detection, for systems of
//! any size written in a deck.
//!
//! Both stacks step one kind of thing: a right-hand side
//! [`crate::rhs::OdeSystem`], which the rigid body implements too
//! ([`crate::rigid::euler`]), so the solvers of deck systems integrate a
//! rigid body as well. Two stepping interfaces stay apart, on purpose:
//! [`crate::rigid::solver::Solver`] gives the physical state (ω and the
//! orientation) and has a member that takes no steps at all (the exact
//! solution), while [`ode::OdeSolver`] gives a vector and exposes its steps
//! and dense output for event location. The rigid body's stepping solvers
//! are not the systems' ones over its equations either: they keep their own
//! numerics (a starting step computed in logarithms for |ω| up to ~1e150,
//! a step budget refused up front from the body's time scales, the
//! quaternion renormalised after each RK4 step), and the printed numbers of
//! every rigid scene depend on them bit for bit. What they share is below:
//! the tableau, the step-size controller, the RK4 step, the error type.

pub mod budget;
pub(crate) mod control;
pub(crate) mod dop853;
pub(crate) mod dop853_tableau;
pub(crate) mod fixed;
pub(crate) mod forward;
pub(crate) mod guard;
pub mod ode;
pub mod registry;
pub(crate) mod rk4;
pub(crate) mod splitting;

pub use crate::rigid::solver::{Kind, Method, Needs, Solver, Work};
