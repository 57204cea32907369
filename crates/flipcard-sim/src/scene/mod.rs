//! A deck's scene as the simulator runs it: what it computes (`plan`), the
//! run itself as the view plays it (`run`), what it measures (`measure`, whose names, help,
//! parsing and dispatch sit in one table, `vocabulary`),
//! how long one call may advance it (`slice`), and the knobs a learner
//! turns to explore it (`knob`).

pub mod knob;
pub mod measure;
pub(crate) mod plan;
pub mod quantities;
pub(crate) mod run;
pub mod slice;
pub mod spec;
pub mod system;
pub mod vocabulary;

pub use run::*;
