//! The solver interface ([`IkSolver`]), the analytic solver a robot gets
//! from the registry, the check every target passes, and the round trip
//! (FK → IK → FK) that tests a solver on any robot.

use super::registry;
use super::{wrap_angle, CandidateSet, Solution, Solutions, Unreachable};
use crate::error::{Error, InputError, Result};
use crate::math::Pose;
use crate::robot::Robot;

/// An inverse-kinematics solver for one robot.
pub trait IkSolver: Send + Sync {
    /// Short name (`numeric`, `scorbot`, `iiwa`, …).
    fn name(&self) -> &'static str;

    /// Every solution the solver finds for `target` (`world_from_tool`),
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

    /// What the request layer hands [`contract::sort_out`](super::contract::sort_out), which measures
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
/// the registry [`registry::FAMILIES`](super::registry::FAMILIES) whose structure test passes. Each
/// checks the robot's structure (not its name), in this order: the iiwa-type SRS arm
/// ([`iiwa::IiwaIk`](super::iiwa::IiwaIk), q3 = 0 by default), 6R arms with a spherical wrist
/// ([`pieper::PieperIk`](super::pieper::PieperIk)), the Scorbot ([`scorbot::ScorbotIk`](super::scorbot::ScorbotIk)), the SCARA on a
/// rail ([`scara::ScaraIk`](super::scara::ScaraIk)), ROMMEL ([`rommel::RommelIk`](super::rommel::RommelIk)), and last the
/// geometric solvers, which read the joint axes of any description
/// ([`geo::GeoIk`](super::geo::GeoIk): spherical wrists from URDF or `general` joints, the UR
/// family's three parallel axes; [`geo::SrsIk`](super::geo::SrsIk): 7R arms of the iiwa's
/// structure in any description, at q3 = 0; [`geo::GeneralIk`](super::geo::GeneralIk): any other 6R arm, by a 2-D search).
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
    registry::fit(robot).map(|f| f as Box<dyn IkSolver>)
}

/// Rejects a target with NaN/inf entries or a rotation block that is not a rotation.
pub fn check_target(target: &Pose) -> Result<()> {
    if let Some(&value) = target.pos.iter().chain(target.rot.iter()).find(|v| !v.is_finite()) {
        return Err(Error::Input(InputError::NotFinite { what: "target".into(), value }));
    }
    let r = &target.rot;
    let orth = (r.transpose() * r - nalgebra::Matrix3::identity()).norm();
    if orth > 1e-6 {
        return Err(Error::Input(InputError::OutOfRange {
            what: "target".into(),
            value: orth,
            expected: "a rotation block: this is its ‖RᵀR − I‖, which must be ≤ 1e-6".into(),
        }));
    }
    if r.determinant() < 0.0 {
        return Err(Error::Input(InputError::OutOfRange {
            what: "target".into(),
            value: r.determinant(),
            expected: "a rotation block: this is its determinant, which must be +1 (not a reflection)".into(),
        }));
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
