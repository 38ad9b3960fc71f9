//! Why an inverse-kinematics target was refused: the data
//! [`Error::Unreachable`](super::Error::Unreachable) carries. Defined here,
//! below `ik`, so the error type depends on nothing above it; `ik` re-exports
//! these types and builds them.

use std::fmt;

/// How close forward kinematics of a returned solution must come to the
/// target, on the components the request constrains.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    /// Position \[m\].
    pub position: f64,
    /// Orientation \[rad\].
    pub orientation: f64,
}

impl Default for Tolerance {
    /// 1e-6 m and 1e-6 rad: the numeric solver's convergence test, and far
    /// above the rounding level of the closed forms.
    fn default() -> Self {
        Tolerance { position: 1e-6, orientation: 1e-6 }
    }
}

impl fmt::Display for Tolerance {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:.1e} m, {:.1e} rad", self.position, self.orientation)
    }
}

/// The configuration that came closest to an unreachable target, with its
/// residual on the constrained components.
#[derive(Debug, Clone, PartialEq)]
pub struct Closest {
    /// Joint values \[rad or m\].
    pub q: Vec<f64>,
    /// Position error \[m\].
    pub position_error: f64,
    /// Orientation error \[rad\].
    pub orientation_error: f64,
}

/// Why a target cannot be reached.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq)]
pub enum Unreachable {
    /// The position lies outside the reachable sphere/annulus/region.
    OutsideReach {
        /// How far outside \[m\].
        by: f64,
        /// Which boundary (e.g. "outer sphere of radius 0.59 m around the shoulder").
        boundary: String,
    },
    /// The position lies inside a region the arm cannot enter (e.g. the
    /// cylinder around axis 1 that a lateral offset keeps the wrist out of).
    InsideExcluded {
        /// How far inside \[m\].
        by: f64,
        /// Which region (e.g. "cylinder of radius 0.15 m around axis 1 …").
        region: String,
    },
    /// No configuration reaches the target, found by a test or a search that
    /// measures no distance to the workspace (so none is quoted).
    NotReached {
        /// What was searched or why (e.g. "the search over q4 finds no configuration of the arm that meets it").
        detail: String,
    },
    /// The orientation asked for is not one this arm can take at that position.
    Orientation {
        /// The smallest orientation error achievable \[rad\].
        angle: f64,
        /// What the arm can and cannot control.
        detail: String,
    },
    /// Solutions exist but every one violates a joint limit.
    JointLimits {
        /// One entry per rejected solution: its branch and the violated joints.
        rejected: Vec<String>,
    },
    /// Candidates were found, but forward kinematics of every one misses the
    /// target by more than the tolerance on a constrained component (e.g. a
    /// full pose given to an arm with fewer than six joints).
    Missed {
        /// How many candidates were measured and discarded.
        candidates: usize,
        /// Position error of the closest candidate \[m\].
        position_error: f64,
        /// Orientation error of the closest candidate \[rad\].
        orientation_error: f64,
        /// The tolerance they were measured against.
        tolerance: Tolerance,
        /// Joints of the robot.
        dof: usize,
    },
    /// Solutions meet the target, but the request's admissibility test (a
    /// scene's collision check) rejects every one.
    Rejected {
        /// How many solutions were rejected.
        candidates: usize,
        /// The first rejection, e.g. `collision: link_4 – bench`.
        first: String,
        /// The self-motion parameter searched for an admissible solution
        /// (`q3` or `psi`), if the arm is redundant and the request left it free.
        searched: Option<String>,
    },
    /// The numeric solver found no solution within its restarts.
    NoConvergence {
        /// Best position error reached \[m\].
        position_error: f64,
        /// Best orientation error reached \[rad\].
        orientation_error: f64,
        /// Restarts tried.
        restarts: usize,
        /// Iterations spent, all starts together (the budget, or nearly).
        iterations: usize,
    },
}

impl fmt::Display for Unreachable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            // A figure only where it is a distance: never ∞, NaN or negative.
            Unreachable::OutsideReach { by, boundary } if *by >= 0.0 && by.is_finite() => {
                write!(f, "the position is {by:.6} m outside the {boundary}")
            }
            Unreachable::OutsideReach { boundary, .. } => write!(f, "the position is outside the {boundary}"),
            Unreachable::InsideExcluded { by, region } if *by >= 0.0 && by.is_finite() => {
                write!(f, "the position is {by:.6} m inside the {region}")
            }
            Unreachable::InsideExcluded { region, .. } => write!(f, "the position is inside the {region}"),
            Unreachable::NotReached { detail } => write!(f, "no configuration reaches the target: {detail}"),
            Unreachable::Orientation { angle, detail } => {
                write!(f, "the orientation is not achievable: off by at least {angle:.6} rad ({detail})")
            }
            Unreachable::JointLimits { rejected } => {
                write!(f, "every solution violates a joint limit: {}", rejected.join("; "))
            }
            Unreachable::Missed { candidates: 0, .. } => f.write_str("the solver proposed no candidate"),
            Unreachable::Missed { candidates, position_error, orientation_error, tolerance, dof } => {
                write!(
                    f,
                    "no candidate meets the target within {tolerance}: the closest misses it by \
                     {position_error:.3e} m and {orientation_error:.3e} rad ({candidates} candidate(s) discarded)"
                )?;
                if *dof < 6 && *orientation_error > tolerance.orientation {
                    write!(
                        f,
                        "; an arm with {dof} joints cannot take every orientation at a position: give a pose on its \
                         reachable set, or a task mask that frees the components it cannot control"
                    )?;
                }
                Ok(())
            }
            Unreachable::Rejected { candidates, first, searched } => {
                write!(f, "every solution is rejected ({candidates} in all; the first: {first})")?;
                if let Some(p) = searched {
                    write!(f, "; no value of {p} over its range gives one that is not")?;
                }
                Ok(())
            }
            Unreachable::NoConvergence { position_error, orientation_error, restarts, iterations } => write!(
                f,
                "no solution found with the budget spent: {iterations} iterations over {restarts} restarts \
                 (best residual {position_error:.3e} m, {orientation_error:.3e} rad)"
            ),
        }
    }
}
