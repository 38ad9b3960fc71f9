//! Inverse kinematics: one interface, analytic solvers per robot family and a
//! numeric solver for any chain.
//!
//! A solver ([`IkSolver`]) takes a target pose and returns every solution it
//! finds, each as a [`Solution`]: the joint values, a branch label, whether
//! they are within the joint limits, and the residual position/orientation
//! error measured by running forward kinematics on them. A target that cannot
//! be reached is an [`Error::Unreachable`] that says why — never a "solution"
//! with a wrong pose. Solvers never mutate their inputs and give the same
//! answer for the same input (and seed), always.
//!
//! Helpers on the solution list ([`Solutions`]) select all solutions, only
//! those within limits, or the one nearest to a previous configuration.
//!
//! Layout: `solution` (what a solver returns), `target` (what the tool must
//! reach), `solver` (the [`IkSolver`] interface), `closed_form` (the kernel
//! trait of the analytic families, with the solver glue written once),
//! `family` (typed targets and redundancy), `registry` (the families in the
//! order they are tried), `request` (one request as every door makes it),
//! `contract` (what counts as a solution), `admissible` (a test besides the
//! target, such as a scene's collision check), `families/` (one module per
//! closed-form family), `numeric` (the solver for any chain).

use crate::error::{Error, InputError};

mod admissible;
mod batch;
mod closed_form;
pub mod contract;
pub mod families;
pub mod family;
mod joints;
pub mod numeric;
pub mod registry;
mod request;
mod solution;
mod solver;
mod target;
mod two_link;

pub use crate::error::{Closest, Tolerance, Unreachable};
pub use admissible::{Admissible, Assessment, Rejection};
pub use batch::solve_batch;
pub use closed_form::ClosedForm;
pub use contract::{Discarded, IkAnswer, Residual};
pub use families::iiwa::IiwaIk;
pub use families::{geo, iiwa, pieper, rommel, scara, scorbot};
pub use joints::{joint_distance, settle_on_limits, wrap_angle, LIMIT_TOL};
pub(crate) use joints::{limit_margin, nearest_turns, turn_copies, wrap_into_limits};
pub use numeric::{Damping, NumericIk, NumericOptions};
pub use request::{pick_one, solve_request, solve_target, solve_target_with, IkRequest, SolverChoice};
pub use solution::{CandidateSet, Candidates, NumericInfo, Solution, Solutions, Stop};
pub use solver::{
    analytic_solver, check_target, round_trip, round_trip_cases, IkSolver, RoundTripCase, RoundTripReport,
};
pub use target::{Component, IkTarget, Quantity, TypedKind, TypedTarget};
pub(crate) use two_link::{two_link_elbow, two_link_elbow_terms, AnnulusMiss};

/// The error for a task mask that selects no component.
pub(crate) fn no_component() -> Error {
    Error::Input(InputError::TooFew {
        what: "mask".into(),
        got: 0,
        min: 1,
        of: "selected components (of x, y, z, ωx, ωy, ωz)".into(),
    })
}
