//! The geometric kernel: every exact predicate and construction (filters,
//! intervals, rationals) and the measures in doubles. The one place where
//! a geometric decision is made.

mod dyadic;
mod exact;
mod measure;
mod running;
mod simplices;

pub use dyadic::*;
pub use exact::*;
pub use measure::*;
pub use running::*;
pub use simplices::*;

/// Reproducible pseudo-random doubles in [0, 1) (xorshift): the kernel's
/// tests and `generate` (which re-exports it) draw from it.
pub fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed.max(1);
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}
