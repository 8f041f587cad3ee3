//! The geometric kernel: every exact predicate and construction (filters,
//! intervals, rationals) and the measures in doubles. The one place where
//! a geometric decision is made.

mod exact;
mod measure;
mod simplices;

pub use exact::*;
pub use measure::*;
pub use simplices::*;
