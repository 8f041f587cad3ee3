//! Progress of long runs, for a caller that shows it.

/// A progress callback: (stage, done, of).
pub type Progress = fn(&str, usize, usize);
