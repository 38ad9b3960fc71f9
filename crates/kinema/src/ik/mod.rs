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

use std::borrow::Cow;
use std::fmt;

use crate::error::{Error, Result};
use crate::math::FastMath;
use crate::math::{pose_error, Pose};
use crate::model::JointSet;
use crate::robot::Robot;

mod batch;
mod closed_form;
pub mod contract;
pub mod family;
pub mod geo;
pub mod iiwa;
pub mod numeric;
pub mod pieper;
mod request;
pub mod rommel;
pub mod scara;
pub mod scorbot;

pub use crate::error::{Closest, Tolerance, Unreachable};
pub use batch::solve_batch;
pub use closed_form::ClosedForm;
pub use contract::{Discarded, IkAnswer, Residual};
pub use iiwa::IiwaIk;
pub use numeric::{Damping, NumericIk, NumericOptions};
pub use request::{pick_one, solve_request, solve_target, solve_target_with, IkRequest, IkTarget, SolverChoice};

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
    /// [`contract::sort_out`] measures it by FK (see [`IkSolver::propose`]).
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

/// Distance between two configurations: Euclidean over joints, with the
/// difference of unbounded revolute joints wrapped to (−π, π].
pub fn joint_distance(robot: &Robot, a: &[f64], b: &[f64]) -> f64 {
    robot
        .joints()
        .iter()
        .zip(a.iter().zip(b))
        .map(|(j, (x, y))| {
            let mut d = x - y;
            let unbounded = !(j.limits.min.is_finite() && j.limits.max.is_finite());
            if j.kind == crate::JointType::Revolute && unbounded {
                d = wrap_angle(d);
            }
            d * d
        })
        .sum::<f64>()
        .sqrt()
}

/// The smallest distance of `q` to a joint limit of `robot` \[rad or m\],
/// negative outside; −∞ for a non-finite value (which `f64::min` would
/// skip). The redundancy searches maximise it.
pub(crate) fn limit_margin(robot: &Robot, q: &[f64]) -> f64 {
    let margin = |(j, v): (&crate::model::Joint, &f64)| {
        if v.is_finite() {
            (v - j.limits.min).min(j.limits.max - v)
        } else {
            f64::NEG_INFINITY
        }
    };
    robot.joints().iter().zip(q).map(margin).fold(f64::INFINITY, f64::min)
}

/// How far past a joint limit \[rad or m\] a solver's value may lie and still
/// count as on the limit. The closed forms recover a joint that sits exactly
/// on its limit 1e-16 to 3e-14 rad past it (rounding in atan2 and the
/// subproblems); 1e-9 is four orders of magnitude above that and moves the
/// tool by at most 1e-9 × its distance from the joint axis (≈ 3e-9 m on a 3 m
/// arm), far inside the contract's default 1e-6 m / 1e-6 rad.
pub const LIMIT_TOL: f64 = 1e-9;

/// Moves every value of `q` that lies at most [`LIMIT_TOL`] past one of its
/// joint's limits onto that limit, and returns the joints still outside. Every
/// IK answer goes through it (the contract, path following), so a solution
/// with a joint on its limit is accepted and reported strictly within limits.
pub fn settle_on_limits(robot: &Robot, q: &mut [f64]) -> JointSet {
    for (v, j) in q.iter_mut().zip(robot.joints()) {
        let l = &j.limits;
        if *v < l.min && *v >= l.min - LIMIT_TOL {
            *v = l.min;
        } else if *v > l.max && *v <= l.max + LIMIT_TOL {
            *v = l.max;
        }
    }
    robot.limit_flags(q)
}

/// The values `v + k·2π` of revolute joint `j` within its limits (up to
/// [`LIMIT_TOL`] past one, moved onto it), the one nearest `v` first, into
/// `out` (cleared first); empty when no turn of `v` is within the limits. A
/// joint unbounded on a side has no finite list: it gets the one copy nearest
/// `reference` that is within limits (for a continuous joint, the copy
/// nearest `reference`).
pub(crate) fn turn_copies(j: &crate::model::Joint, v: f64, reference: f64, out: &mut Vec<f64>) {
    use std::f64::consts::TAU;
    out.clear();
    let l = &j.limits;
    if j.kind != crate::JointType::Revolute || !v.is_finite() {
        if v >= l.min - LIMIT_TOL && v <= l.max + LIMIT_TOL {
            out.push(v.clamp(l.min, l.max));
        }
        return;
    }
    let (lo, hi) = (l.min - LIMIT_TOL, l.max + LIMIT_TOL);
    if !(l.min.is_finite() && l.max.is_finite()) {
        let reference = if reference.is_finite() { reference } else { v };
        let mut c = v + ((reference - v) / TAU).round() * TAU;
        if c < lo {
            c += ((lo - c) / TAU).ceil() * TAU;
        } else if c > hi {
            c -= ((c - hi) / TAU).ceil() * TAU;
        }
        if c >= lo && c <= hi {
            out.push(c.clamp(l.min, l.max));
        }
        return;
    }
    let (k_lo, k_hi) = (((lo - v) / TAU).ceil(), ((hi - v) / TAU).floor());
    // A range of more than a few thousand turns is not a joint range; keep the list bounded.
    if !(k_hi - k_lo < 4096.0) {
        return;
    }
    let mut k = k_lo;
    while k <= k_hi {
        out.push((v + k * TAU).clamp(l.min, l.max));
        k += 1.0;
    }
    out.sort_by(|a, b| (a - v).abs().total_cmp(&(b - v).abs()));
}

/// Shifts each revolute joint of `q` by whole turns to the copy within its
/// limits nearest `reference` (see [`turn_copies`]); a joint with no copy
/// within its limits is left as it is. Then [`settle_on_limits`]: returns the
/// joints still outside.
pub(crate) fn nearest_turns(robot: &Robot, q: &mut [f64], reference: &[f64]) -> JointSet {
    let mut copies = Vec::new();
    for ((v, j), r) in q.iter_mut().zip(robot.joints()).zip(reference) {
        turn_copies(j, *v, *r, &mut copies);
        if let Some(c) = copies.iter().copied().min_by(|a, b| (a - r).abs().total_cmp(&(b - r).abs())) {
            *v = c;
        }
    }
    settle_on_limits(robot, q)
}

/// `a` wrapped to (−π, π].
#[inline]
pub fn wrap_angle(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    // Fast path for |a| ≤ 3π (every angle the solvers produce): a ∓ 2π is
    // exact there (Sterbenz), so the result equals the remainder below bit for bit.
    if a > -PI && a <= PI {
        return a;
    }
    if a > PI && a <= 3.0 * PI {
        return a - TAU;
    }
    if a <= -PI && a > -3.0 * PI {
        return a + TAU;
    }
    let r = a.rem_euclid(TAU);
    if r > PI {
        r - TAU
    } else {
        r
    }
}

/// Joint vectors of any length before their FK check, in reusable buffers
/// (see [`IkSolver::candidates_into`]).
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
    /// `q_prev`, and onto a limit it passes by at most [`LIMIT_TOL`].
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
/// (e.g. [`iiwa::IiwaIk::solve_q3_candidates`]) fill one; [`Candidates::evaluate`]
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

/// An inverse-kinematics solver for one robot.
pub trait IkSolver: Send + Sync {
    /// Short name (`numeric`, `scorbot`, `iiwa`, …).
    fn name(&self) -> &'static str;

    /// Every solution the solver finds for `target` (`base_from_tool`),
    /// including those outside the joint limits (flagged). Errors for a
    /// non-finite target and for an unreachable one ([`Error::Unreachable`]).
    fn solve(&self, target: &Pose) -> Result<Vec<Solution>>;

    /// The joint vectors of [`IkSolver::solve`] without their FK residual
    /// check, written into `out` (cleared first; its buffers are reused, so a
    /// loop over many targets does not allocate per solution). For path
    /// following, which checks only the solution it picks. The analytic
    /// solvers override the default, which calls `solve`.
    fn candidates_into(&self, target: &Pose, out: &mut CandidateSet) -> Result<()> {
        let sols = self.solve(target)?;
        out.clear();
        for s in sols {
            out.push(&s.q, s.branch);
        }
        Ok(())
    }

    /// What the request layer hands [`contract::sort_out`], which measures
    /// every candidate by FK and sets its residual and limit flags: by
    /// default [`IkSolver::solve`]'s solutions; solvers with a closed-form
    /// kernel return its candidates [`Solution::unmeasured`], so that each is
    /// measured once, by the contract.
    fn propose(&self, target: &Pose) -> Result<Vec<Solution>> {
        self.solve(target)
    }

    /// Solutions within the joint limits; if there are none although the pose
    /// is reachable, an [`Unreachable::JointLimits`] error listing them.
    fn solve_within_limits(&self, target: &Pose) -> Result<Vec<Solution>> {
        let all = self.solve(target)?;
        if all.iter().any(Solution::within_limits) {
            return Ok(all.within_limits());
        }
        Err(Error::Unreachable {
            solver: self.name().to_string(),
            reason: Unreachable::JointLimits {
                rejected: all
                    .iter()
                    .map(|s| {
                        let joints: Vec<String> = s.out_of_limits.indices().map(|i| format!("q{}", i + 1)).collect();
                        format!("{} ({})", s.branch, joints.join(", "))
                    })
                    .collect(),
            },
            closest: None,
        })
    }
}

/// The analytic solver that fits `robot`, if one does: the first family of
/// the registry [`family::FAMILIES`] whose structure test passes. Each
/// checks the robot's structure (not its name), in this order: the iiwa-type SRS arm
/// ([`iiwa::IiwaIk`], q3 = 0 by default), 6R arms with a spherical wrist
/// ([`pieper::PieperIk`]), the Scorbot ([`scorbot::ScorbotIk`]), the SCARA on a
/// rail ([`scara::ScaraIk`]), ROMMEL ([`rommel::RommelIk`]), and last the
/// geometric solvers, which read the joint axes of any description
/// ([`geo::GeoIk`]: spherical wrists from URDF or `general` joints, the UR
/// family's three parallel axes; [`geo::SrsIk`]: 7R arms of the iiwa's
/// structure in any description, at q3 = 0; [`geo::GeneralIk`]: any other 6R arm, by a 2-D search).
///
/// # Examples
/// ```
/// let puma = kinema::Robot::builtin("puma560")?;
/// assert_eq!(kinema::ik::analytic_solver(&puma).map(|s| s.name()), Some("pieper"));
/// let ur5 = kinema::Robot::builtin("ur5")?;
/// assert_eq!(kinema::ik::analytic_solver(&ur5).map(|s| s.name()), Some("geo-three-parallel"));
/// let panda = kinema::Robot::builtin("panda")?;
/// assert!(kinema::ik::analytic_solver(&panda).is_none());
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn analytic_solver(robot: &Robot) -> Option<Box<dyn IkSolver>> {
    family::fit(robot).map(|f| f as Box<dyn IkSolver>)
}

/// A point outside the annulus \[|l1 − l2|, l1 + l2\] a planar two-link arm reaches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct AnnulusMiss {
    /// How far outside \[m\].
    pub by: f64,
    /// Radius of the boundary missed \[m\].
    pub radius: f64,
    /// Whether it is the outer boundary (else the inner one).
    pub outer: bool,
}

/// The elbow angle θ ∈ \[0, π\] of a planar two-link arm, with its sine and cosine.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ElbowAngle {
    pub angle: f64,
    pub sin: f64,
    pub cos: f64,
}

/// |Elbow angle| of a planar two-link arm with link lengths `l1`, `l2` whose
/// tip lies at distance `r` from the shoulder, by the half-angle form of the
/// law of cosines, tan²(θ/2) = ((l1+l2)² − r²)/(r² − (l1−l2)²), which stays
/// accurate near the stretched and folded arm where acos loses half the digits.
/// sin θ and cos θ come from the same half-angle tangent, without a further
/// sine/cosine evaluation. A point outside the annulus by more than `tol` is
/// an [`AnnulusMiss`].
pub(crate) fn two_link_elbow(r: f64, l1: f64, l2: f64, tol: f64) -> std::result::Result<ElbowAngle, AnnulusMiss> {
    let t = two_link_elbow_terms(r, l1, l2, tol)?;
    Ok(ElbowAngle { angle: 2.0 * t.half_y.fast_atan2(t.half_x), sin: t.sin, cos: t.cos })
}

/// [`two_link_elbow`] without its one `atan2`: the angle is
/// 2·atan2(`half_y`, `half_x`), left to the caller (a kernel that gathers
/// several angles into one [`crate::math::atan2_lanes`] call).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ElbowTerms {
    pub half_y: f64,
    pub half_x: f64,
    pub sin: f64,
    pub cos: f64,
}

/// The terms of [`two_link_elbow`] (same arguments, same misses).
#[inline]
pub(crate) fn two_link_elbow_terms(r: f64, l1: f64, l2: f64, tol: f64) -> std::result::Result<ElbowTerms, AnnulusMiss> {
    let (outer, inner) = (l1 + l2, (l1 - l2).abs());
    if r > outer + tol {
        return Err(AnnulusMiss { by: r - outer, radius: outer, outer: true });
    }
    if r < inner - tol {
        return Err(AnnulusMiss { by: inner - r, radius: inner, outer: false });
    }
    let num = ((outer - r) * (outer + r)).max(0.0);
    let den = ((r - inner) * (r + inner)).max(0.0);
    let sum = num + den;
    if sum == 0.0 {
        return Ok(ElbowTerms { half_y: 0.0, half_x: 1.0, sin: 0.0, cos: 1.0 });
    }
    // With t = tan(θ/2) = √(num/den): cos θ = (1 − t²)/(1 + t²), sin θ = 2t/(1 + t²).
    Ok(ElbowTerms {
        half_y: num.sqrt(),
        half_x: den.sqrt(),
        sin: 2.0 * (num * den).sqrt() / sum,
        cos: (den - num) / sum,
    })
}

/// The error for a task mask that selects no component.
pub(crate) fn no_component() -> Error {
    Error::TooFew { what: "mask".into(), got: 0, min: 1, of: "selected components (of x, y, z, ωx, ωy, ωz)".into() }
}

/// Rejects a target with NaN/inf entries or a rotation block that is not a rotation.
pub fn check_target(target: &Pose) -> Result<()> {
    if let Some(&value) = target.pos.iter().chain(target.rot.iter()).find(|v| !v.is_finite()) {
        return Err(Error::NotFinite { what: "target".into(), value });
    }
    let r = &target.rot;
    let orth = (r.transpose() * r - nalgebra::Matrix3::identity()).norm();
    if orth > 1e-6 {
        return Err(Error::OutOfRange {
            what: "target".into(),
            value: orth,
            expected: "a rotation block: this is its ‖RᵀR − I‖, which must be ≤ 1e-6".into(),
        });
    }
    if r.determinant() < 0.0 {
        return Err(Error::OutOfRange {
            what: "target".into(),
            value: r.determinant(),
            expected: "a rotation block: this is its determinant, which must be +1 (not a reflection)".into(),
        });
    }
    Ok(())
}

/// Result of [`round_trip`]: configuration → FK → IK → back (seed 004 §V-C,
/// for any solver).
#[derive(Debug, Clone, PartialEq)]
pub struct RoundTripReport {
    /// Configurations tried.
    pub cases: usize,
    /// Cases where the solver returned at least one solution.
    pub solved: usize,
    /// Largest |Δq| (max over joints, wrapped angles) between the original
    /// configuration and the nearest returned solution \[rad or m\].
    pub max_error: f64,
    /// Mean of that error over the solved cases.
    pub mean_error: f64,
    /// Fraction of cases whose original configuration was recovered (error ≤ 1e-9).
    pub recovered_fraction: f64,
    /// Largest FK position residual of any returned solution \[m\].
    pub max_position_residual: f64,
}

/// Round trip over `n` seeded random within-limit configurations: FK, then
/// `solver`, then the distance from the original to the nearest solution.
/// A solver that picks among several equally valid answers (the SCARA's rail,
/// the iiwa's q3) need not recover the original; the residual still shows
/// that every answer reaches its target.
pub fn round_trip(robot: &Robot, solver: &dyn IkSolver, n: usize, seed: u64) -> Result<RoundTripReport> {
    let cases = round_trip_cases(robot, solver, n, seed)?;
    let (mut solved, mut recovered, mut max_error, mut sum, mut max_res) = (0, 0, 0.0f64, 0.0, 0.0f64);
    for c in cases.iter().flatten() {
        solved += 1;
        max_res = max_res.max(c.position_residual);
        max_error = max_error.max(c.error);
        sum += c.error;
        if c.error <= 1e-9 {
            recovered += 1;
        }
    }
    Ok(RoundTripReport {
        cases: n,
        solved,
        max_error,
        mean_error: if solved > 0 { sum / solved as f64 } else { 0.0 },
        recovered_fraction: if n > 0 { recovered as f64 / n as f64 } else { 0.0 },
        max_position_residual: max_res,
    })
}

/// One solved case of [`round_trip_cases`].
#[derive(Debug, Clone, PartialEq)]
pub struct RoundTripCase {
    /// The random configuration.
    pub q: Vec<f64>,
    /// Largest |Δq| (wrapped angles) to the nearest returned solution \[rad or m\].
    pub error: f64,
    /// Largest FK position residual of the returned solutions \[m\].
    pub position_residual: f64,
}

/// The cases of [`round_trip`] one by one, in order: `None` where the solver
/// returned an error or no solution.
pub fn round_trip_cases(
    robot: &Robot,
    solver: &dyn IkSolver,
    n: usize,
    seed: u64,
) -> Result<Vec<Option<RoundTripCase>>> {
    use rand::SeedableRng;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut out = Vec::with_capacity(n);
    for _ in 0..n {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q)?.world_from_tool;
        let sols = match solver.solve(&target) {
            Ok(s) if !s.is_empty() => s,
            _ => {
                out.push(None);
                continue;
            }
        };
        let err = |s: &Solution| {
            s.q.iter()
                .zip(&q)
                .zip(robot.joints())
                .map(|((a, b), j)| {
                    let d = a - b;
                    (if j.kind == crate::JointType::Revolute { wrap_angle(d) } else { d }).abs()
                })
                .fold(0.0f64, f64::max)
        };
        let error = sols.iter().map(err).fold(f64::INFINITY, f64::min);
        let position_residual = sols.iter().map(|s| s.position_error).fold(0.0, f64::max);
        out.push(Some(RoundTripCase { q, error, position_residual }));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn two_link_elbow_sine_and_cosine_match_the_angle_and_the_law_of_cosines() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        for k in 0..20_000 {
            let (l1, l2): (f64, f64) = (rng.random_range(0.05..1.0), rng.random_range(0.05..1.0));
            let (inner, outer) = ((l1 - l2).abs(), l1 + l2);
            // Every fifth case on a boundary, where the half-angle form matters most.
            let r = match k % 5 {
                0 => outer,
                1 => inner,
                _ => rng.random_range(inner..outer),
            };
            let e = two_link_elbow(r, l1, l2, 1e-12).unwrap();
            let (s, c) = e.angle.sin_cos();
            assert!((e.sin - s).abs() < 1e-14 && (e.cos - c).abs() < 1e-14, "{l1} {l2} {r}: {e:?}");
            assert!(e.sin >= 0.0 && (0.0..=std::f64::consts::PI).contains(&e.angle));
            // The elbow puts the tip at distance r: r² = l1² + l2² + 2·l1·l2·cos θ.
            let r2 = l1 * l1 + l2 * l2 + 2.0 * l1 * l2 * e.cos;
            assert!((r2.max(0.0).sqrt() - r).abs() < 1e-7 * outer, "{l1} {l2} {r}: {r2}");
        }
        let miss = two_link_elbow(2.1, 1.0, 1.0, 1e-12).unwrap_err();
        assert!(miss.outer && (miss.by - 0.1).abs() < 1e-12);
        let miss = two_link_elbow(0.1, 1.0, 0.5, 1e-12).unwrap_err();
        assert!(!miss.outer && (miss.by - 0.4).abs() < 1e-12);
    }

    #[test]
    fn wrap_angle_fast_path_equals_the_remainder() {
        use std::f64::consts::{PI, TAU};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(12);
        for _ in 0..100_000 {
            let a: f64 = rng.random_range(-4.0 * PI..4.0 * PI);
            let r = a.rem_euclid(TAU);
            let want = if r > PI { r - TAU } else { r };
            let got = wrap_angle(a);
            assert!((got - want).abs() <= 4.0 * f64::EPSILON, "{a}: {got} vs {want}");
            assert!(got > -PI && got <= PI);
        }
        assert_eq!(wrap_angle(-PI), PI);
        assert_eq!(wrap_angle(PI), PI);
        assert_eq!(wrap_angle(3.0 * PI), PI);
        assert!(wrap_angle(f64::NAN).is_nan());
    }

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
