//! A deck's scene as the simulator runs it: what it computes (`plan`), the
//! run itself as the view plays it (`run`), and what it measures
//! (`measure`).

pub mod measure;
pub mod plan;
pub mod run;
pub mod spec;
pub mod system;

pub use run::*;
