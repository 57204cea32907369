//! Systems written as equations in a deck: the expressions (checked with
//! positions, [`expr`]), their compilation into the right-hand side,
//! observables and Jacobian ([`compile`]), and short names for measures.

pub mod compile;
pub mod equiv;
pub mod expr;
pub mod formula;
pub(crate) mod name;
pub(crate) mod spec;
pub mod sums;

pub use compile::System;
pub use name::Name;
