//! The solvers: one stepping stack for deck systems and the rigid body.
//!
//! Everything that steps is one [`ode::Stepper`] (a point, one step, the
//! window of the last step and the values inside it), over one right-hand
//! side [`crate::rhs::OdeSystem`] which the rigid body implements too
//! ([`crate::rigid::euler`]). DOP853 has one implementation
//! ([`ode::Dop853`]: the shared tableau `dop853_tableau`, the one step-size
//! controller `control`), RK4 one step (`ode::rk4_step`), and every method
//! stops with the one [`crate::error::SolveError`].
//!
//! A deck's system is driven through [`ode::OdeSolver`] (a vector, its
//! steps and dense output for event location): DOP853 with stiffness
//! detection, Radau IIA, RK4, `auto`. The rigid body is a system with what
//! only it has: its exact solution (no steps at all), the splitting
//! methods (exact flows of (L, q), `splitting`), the orientation, a step
//! budget refused up front from the body's time scales (`budget`), the
//! quaternion renormalised after each RK4 step, norms taken without
//! squares for spins up to ~1e150. [`stepped::RigidStepper`] is what its
//! steppers add, [`stepped::Stepped`] turns one into the rigid body's
//! [`crate::rigid::solver::Solver`] (the state: ω and the orientation), and
//! `registry` builds any of them behind the `guard`. The fixed-step methods
//! of the rigid body (RK4, the splittings) are rules ([`fixed::StepRule`])
//! of one fixed-step stepper ([`fixed::FixedSteps`]).

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
pub(crate) mod stepped;

pub use crate::rigid::solver::{Kind, Method, Needs, Solver, Work};
