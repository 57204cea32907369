//! `flipcard bench`: error against run time for every solver.

pub use crate::sim::bench::run;
