//! A deck's scene as the simulator runs it: what it computes (`plan`), the
//! run itself as the view plays it (`run`), what it measures (`measure`),
//! and how long one call may advance it (`slice`).

pub mod measure;
pub mod plan;
pub mod run;
pub mod slice;
pub mod spec;
pub mod system;

pub use run::*;
