//! The planner a `PTP … AVOID` asks for a path around obstacles. The
//! language knows no shapes: whoever gives the program its collision check
//! (a scene) gives the planner with it.

use std::fmt;

/// Finds a collision-free joint-space path between two configurations.
pub trait PathPlanner: Send + Sync {
    /// Via points from `from` to `to` (both included, \[rad, m\]) joined by
    /// collision-free straight segments: `[from, to]` exactly when the
    /// straight motion is free. The same `seed` gives the same path.
    /// `Err`: why no path was found, in words.
    fn path(&self, from: &[f64], to: &[f64], seed: u64) -> Result<Vec<Vec<f64>>, String>;
}

impl fmt::Debug for dyn PathPlanner + '_ {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("PathPlanner")
    }
}
