//! Shared by the simulator's integration tests: reference solutions that
//! share no code with the solvers under test.

pub mod taylor_dd;
