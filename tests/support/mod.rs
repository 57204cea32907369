//! Reference solutions shared by the simulator tests.

pub mod taylor_dd;
