//! `flipcard sim`: the simulator headless.

pub use crate::sim::cli::run;
