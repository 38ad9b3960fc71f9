//! What a solver returns: [`Solution`]s (joint values, branch, limit flags,
//! residual), the helpers that select among them ([`Solutions`]), and the
//! buffers the closed-form kernels fill before the FK check
//! ([`CandidateSet`], [`Candidates`]).

use std::borrow::Cow;
use std::fmt;

use super::joints::{joint_distance, nearest_turns};
use crate::error::{Closest, Result};
use crate::math::{pose_error, Pose};
use crate::model::JointSet;
use crate::robot::Robot;

/// How a numeric solve ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// Position and orientation errors below the tolerances.
    Converged,
    /// The iteration limit of the last restart was reached.
    MaxIterations,
    /// The error stopped decreasing (a local minimum or a joint limit).
    Stalled,
}

impl fmt::Display for Stop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Stop::Converged => "converged",
            Stop::MaxIterations => "max-iterations",
            Stop::Stalled => "stalled",
        })
    }
}

/// What a numeric solver did to find a solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NumericInfo {
    /// Iterations of the successful (or last) attempt.
    pub iterations: usize,
    /// Restarts before it (0 = the first start succeeded).
    pub restarts: usize,
    /// Why it stopped.
    pub stop: Stop,
}

/// One inverse-kinematics solution.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// Joint values \[rad or m\].
    pub q: Vec<f64>,
    /// Branch label, e.g. `elbow-up`, `shoulder-left/elbow-up/wrist-flip`, or
    /// `numeric` (static for the built-in solvers, so building a solution
    /// does not allocate a string).
    pub branch: Cow<'static, str>,
    /// Joints whose value is outside their position limits.
    pub out_of_limits: JointSet,
    /// |p_target − p(q)| \[m\], from forward kinematics on `q`.
    pub position_error: f64,
    /// Angle of R_target·R(q)ᵀ \[rad\], from forward kinematics on `q`. For
    /// robots that cannot control every rotation, this includes the part of
    /// the target they cannot reach (see the solver's documentation).
    pub orientation_error: f64,
    /// Present for numeric solutions.
    pub numeric: Option<NumericInfo>,
}

impl Solution {
    /// Builds a solution from joint values, measuring its residual with FK
    /// against `target`.
    pub fn evaluate(
        robot: &Robot,
        q: Vec<f64>,
        target: &Pose,
        branch: impl Into<Cow<'static, str>>,
    ) -> Result<Solution> {
        let fk = robot.fk(&q)?;
        let e = pose_error(target, &fk.world_from_tool);
        Ok(Solution {
            q,
            branch: branch.into(),
            out_of_limits: fk.out_of_limits,
            position_error: e.position_norm(),
            orientation_error: e.rotation_angle(),
            numeric: None,
        })
    }

    /// A candidate not yet measured: NaN residuals and no limit flags, until
    /// [`contract::sort_out`](super::contract::sort_out) measures it by FK (see [`IkSolver::propose`](super::IkSolver::propose)).
    pub fn unmeasured(q: Vec<f64>, branch: impl Into<Cow<'static, str>>) -> Solution {
        Solution {
            q,
            branch: branch.into(),
            out_of_limits: JointSet::default(),
            position_error: f64::NAN,
            orientation_error: f64::NAN,
            numeric: None,
        }
    }

    /// Whether every joint value is within its limits.
    pub fn within_limits(&self) -> bool {
        self.out_of_limits.is_empty()
    }
}

// Built here, where solutions are; defined with the error that carries it.
impl Closest {
    /// The configuration and residuals of `s`.
    pub fn of(s: &Solution) -> Closest {
        Closest { q: s.q.clone(), position_error: s.position_error, orientation_error: s.orientation_error }
    }
}

/// Selection helpers on a list of solutions.
pub trait Solutions {
    /// Only the solutions within the joint limits.
    fn within_limits(self) -> Vec<Solution>;
    /// The solution nearest to `q_prev` (Euclidean distance in joint space,
    /// revolute differences wrapped to (−π, π] when the joint is unbounded),
    /// preferring solutions within limits. `None` for an empty list.
    fn nearest(&self, robot: &Robot, q_prev: &[f64]) -> Option<&Solution>;
}

impl Solutions for Vec<Solution> {
    fn within_limits(self) -> Vec<Solution> {
        self.into_iter().filter(Solution::within_limits).collect()
    }

    fn nearest(&self, robot: &Robot, q_prev: &[f64]) -> Option<&Solution> {
        let dist = |s: &Solution| joint_distance(robot, &s.q, q_prev);
        // total_cmp: a NaN distance (a NaN in q_prev) sorts last instead of panicking.
        self.iter().min_by(|a, b| (!a.within_limits()).cmp(&!b.within_limits()).then(dist(a).total_cmp(&dist(b))))
    }
}

/// Joint vectors of any length before their FK check, in reusable buffers
/// (see [`IkSolver::candidates_into`](super::IkSolver::candidates_into)).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CandidateSet {
    dof: usize,
    q: Vec<f64>,
    branch: Vec<Cow<'static, str>>,
}

impl CandidateSet {
    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// Removes every candidate (keeps the buffers).
    pub fn clear(&mut self) {
        self.q.clear();
        self.branch.clear();
        self.dof = 0;
    }

    /// Appends a candidate; every candidate must have the same length.
    pub fn push(&mut self, q: &[f64], branch: impl Into<Cow<'static, str>>) {
        debug_assert!(self.branch.is_empty() || q.len() == self.dof);
        self.dof = q.len();
        self.q.extend_from_slice(q);
        self.branch.push(branch.into());
    }

    /// Number of candidates.
    pub fn len(&self) -> usize {
        self.branch.len()
    }

    /// Whether there is none.
    pub fn is_empty(&self) -> bool {
        self.branch.is_empty()
    }

    /// Joint values of candidate `i`.
    pub fn q(&self, i: usize) -> &[f64] {
        &self.q[i * self.dof..(i + 1) * self.dof]
    }

    /// Branch label of candidate `i`.
    pub fn branch(&self, i: usize) -> &str {
        &self.branch[i]
    }

    /// Candidate `i` as a [`Solution`], its residual measured by FK on `robot` against `target`.
    pub fn evaluate(&self, i: usize, robot: &Robot, target: &Pose) -> Result<Solution> {
        Solution::evaluate(robot, self.q(i).to_vec(), target, self.branch[i].clone())
    }

    /// Every candidate as a [`Solution::unmeasured`], in order.
    pub fn unmeasured(&self) -> Vec<Solution> {
        (0..self.len()).map(|i| Solution::unmeasured(self.q(i).to_vec(), self.branch[i].clone())).collect()
    }

    /// Index of the candidate within `robot`'s limits nearest to `q_prev`
    /// ([`joint_distance`]); `None` if none is within limits. Each candidate
    /// is first moved by whole turns to its copy within limits nearest
    /// `q_prev`, and onto a limit it passes by at most [`LIMIT_TOL`](super::LIMIT_TOL).
    pub fn nearest_within_limits(&mut self, robot: &Robot, q_prev: &[f64]) -> Option<usize> {
        let dof = self.dof;
        for q in self.q.chunks_exact_mut(dof.max(1)) {
            nearest_turns(robot, q, q_prev);
        }
        (0..self.len())
            .filter(|&i| robot.limit_flags(self.q(i)).is_empty())
            .map(|i| (i, joint_distance(robot, self.q(i), q_prev)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i)
    }
}

impl<const N: usize, const M: usize> Candidates<N, M> {
    /// Copies the candidates into a [`CandidateSet`] (cleared first).
    pub fn write_into(&self, out: &mut CandidateSet) {
        out.clear();
        for (q, b) in self.iter() {
            out.push(q, b);
        }
    }
}

/// Joint vectors from a closed form before any FK check: up to `M`
/// candidates of `N` joints each with their branch labels, in a fixed-size
/// buffer (no allocation). The analytic solvers' kernels
/// (e.g. [`iiwa::IiwaIk::solve_q3_candidates`](super::iiwa::IiwaIk::solve_q3_candidates)) fill one; [`Candidates::evaluate`]
/// turns each entry into a [`Solution`] with its FK residual.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Candidates<const N: usize, const M: usize> {
    q: [[f64; N]; M],
    branch: [&'static str; M],
    len: usize,
}

impl<const N: usize, const M: usize> Default for Candidates<N, M> {
    fn default() -> Self {
        Candidates { q: [[0.0; N]; M], branch: [""; M], len: 0 }
    }
}

impl<const N: usize, const M: usize> Candidates<N, M> {
    /// Number of candidates.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether there is none.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The joint vectors, in the solver's order.
    pub fn qs(&self) -> &[[f64; N]] {
        &self.q[..self.len]
    }

    /// The branch labels, parallel to [`Candidates::qs`].
    pub fn branches(&self) -> &[&'static str] {
        &self.branch[..self.len]
    }

    /// (joint vector, branch label) pairs.
    pub fn iter(&self) -> impl Iterator<Item = (&[f64; N], &'static str)> + '_ {
        self.qs().iter().zip(self.branches().iter().copied())
    }

    /// Appends `q` unless it equals a candidate already present (every joint
    /// within `tol`, angles compared modulo 2π when `angular`) or the buffer
    /// is full. Returns whether it was added.
    pub(crate) fn push_unique(&mut self, q: [f64; N], branch: &'static str, tol: f64, angular: bool) -> bool {
        let same = |a: &[f64; N]| {
            a.iter().zip(&q).all(|(x, y)| {
                let d = (x - y).abs();
                d < tol || (angular && (d - std::f64::consts::TAU).abs() < tol)
            })
        };
        if self.len == M || self.qs().iter().any(same) {
            return false;
        }
        self.q[self.len] = q;
        self.branch[self.len] = branch;
        self.len += 1;
        true
    }

    /// Every candidate as a [`Solution`], its residual measured by FK on
    /// `robot` against `target`.
    pub fn evaluate(&self, robot: &Robot, target: &Pose) -> Result<Vec<Solution>> {
        self.iter().map(|(q, b)| Solution::evaluate(robot, q.to_vec(), target, b)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn candidates_drop_duplicates_modulo_a_turn() {
        let mut c = Candidates::<2, 3>::default();
        assert!(c.push_unique([0.1, std::f64::consts::PI], "a", 1e-12, true));
        assert!(!c.push_unique([0.1, -std::f64::consts::PI], "b", 1e-12, true));
        assert!(c.push_unique([0.1, -std::f64::consts::PI], "b", 1e-12, false));
        assert!(c.push_unique([0.2, 0.0], "c", 1e-12, true));
        assert!(!c.push_unique([0.3, 0.0], "d", 1e-12, true), "full");
        assert_eq!(c.branches(), ["a", "b", "c"]);
    }
}
