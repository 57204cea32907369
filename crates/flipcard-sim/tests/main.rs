//! The simulator's integration tests, in one binary: the integrators
//! against exact and independent references, and the ODE solvers on stiff
//! and hostile systems. They need nothing but this crate, so editing the
//! app or a deck does not rebuild them. Run one file's tests with
//! `cargo test --test main -p flipcard-sim NAME::` (or from this folder).

mod support;

mod ode_solvers;
mod sim_exact;
mod sim_integrators;
mod sparse_lu;
