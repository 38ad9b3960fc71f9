//! Analytic inverse kinematics from the geometry of the joint axes, for any
//! description (DH table, TOML `general` joints, URDF), after IK-Geo (Elias
//! and Wen): the axes are read at q = 0 ([`Kinematics`]), the family is
//! recognised from them (parallel and intersecting axes, tested to
//! [`GEOM_TOL`], never from names or DH fields), and the joints follow from
//! the Paden–Kahan [`subproblems`].
//!
//! Families (six revolute joints each):
//!
//! * [`SphericalWristIk`] (`geo-spherical-wrist`): axes 4, 5, 6 meet in one
//!   point, and axes 2 ∥ 3 (PUMA, ABB IRB 140, KUKA KR) or axes 1 and 2
//!   intersect. Up to 8 solutions.
//! * [`ThreeParallelIk`] (`geo-three-parallel`): axes 2 ∥ 3 ∥ 4 and axes 5
//!   and 6 intersect (the UR family). Up to 8 solutions.
//! * [`ThreeParallelSearchIk`] (`geo-three-parallel-search`): axes 2 ∥ 3 ∥ 4
//!   with axes 5 and 6 skew: a 1-D search over q₆, every other joint in
//!   closed form for each q₆.
//! * [`TwoIntersectingSearchIk`] (`geo-two-intersecting-search`): axes 5
//!   and 6 meet off axis 4 (an offset wrist), with the spherical-wrist
//!   family's shoulder: a 1-D search over q₄.
//!
//! Any other 6R arm: [`GeneralIk`] (`geo-general`), a 2-D search over
//! (q₁, q₂) with subproblem 5 for q₃…q₅ and Newton's method polishing the
//! seeds; up to 16 solutions. Not a [`GeoIk`] variant: it registers after
//! the closed forms and the 1-D searches, so it only takes arms none fits.
//!
//! Seven revolute joints: [`SrsIk`] (`geo-srs`), axes 1, 2, 3 meeting and
//! axes 5, 6, 7 meeting (the iiwa's SRS structure), closed form for a given
//! q₃ and a search over q₃ within the limits; not a [`GeoIk`] variant, since
//! its [`IkSolver::solve`] fixes q₃ = 0.
//!
//! Each family is its own entry in the one registry, [`FAMILIES`];
//! [`GeoIk`] is the six-joint ones as one type, and [`GeoIk::new`] picks the
//! first that fits, in the registry's order. Joint values are wrapped to
//! (−π, π] and moved by ±2π when that brings them within the joint limits;
//! solutions outside the limits are returned and flagged. Branch labels are
//! `shoulder-{1,2}/elbow-{1,2}/wrist-{1,2}`: the root index of each step's
//! subproblem (documented per family).

pub mod general;
pub mod kin;
pub mod parallel;
pub mod parallel_search;
pub mod search;
pub mod spherical;
pub(crate) mod spherical_arm;
pub mod srs;
pub(crate) mod srs_kernel;
pub mod subproblems;
pub(crate) mod wrist;
pub mod wrist_search;

use nalgebra::Vector3;

pub use general::GeneralIk;
pub use kin::Kinematics;
pub use parallel::ThreeParallelIk;
pub use parallel_search::ThreeParallelSearchIk;
pub use spherical::{ShoulderKind, SphericalWristIk};
pub use srs::SrsIk;
pub use wrist_search::TwoIntersectingSearchIk;

use crate::error::{Error, Result};
use crate::ik::registry::FAMILIES;
use crate::ik::wrap_into_limits;
use crate::ik::{check_target, CandidateSet, Candidates, ClosedForm, IkSolver, Solution, Unreachable};
use crate::math::Pose;
use crate::robot::Robot;

/// Tolerance for the structure tests: unit axis directions whose cross
/// product is below it are parallel, lines closer than it \[m\] intersect.
pub const GEOM_TOL: f64 = 1e-9;

/// Every branch label, indexed by shoulder·4 + elbow·2 + wrist.
const LABELS: [&str; 8] = [
    "shoulder-1/elbow-1/wrist-1",
    "shoulder-1/elbow-1/wrist-2",
    "shoulder-1/elbow-2/wrist-1",
    "shoulder-1/elbow-2/wrist-2",
    "shoulder-2/elbow-1/wrist-1",
    "shoulder-2/elbow-1/wrist-2",
    "shoulder-2/elbow-2/wrist-1",
    "shoulder-2/elbow-2/wrist-2",
];

fn label(shoulder: usize, elbow: usize, wrist: usize) -> &'static str {
    LABELS[(shoulder & 1) * 4 + (elbow & 1) * 2 + (wrist & 1)]
}

/// What every family keeps: the robot, its axes, and the inverse of the
/// tool pose at q = 0.
#[derive(Debug, Clone)]
struct Common {
    robot: Robot,
    kin: Kinematics,
    tool0_inv: Pose,
}

impl Common {
    /// Checks for six revolute joints and reads the axes.
    fn new(robot: &Robot, solver: &str) -> Result<Self> {
        Self::with_dof(robot, solver, 6)
    }

    /// Checks for `dof` revolute joints and reads the axes.
    fn with_dof(robot: &Robot, solver: &str, dof: usize) -> Result<Self> {
        if robot.dof() != dof {
            return reject(
                solver,
                robot,
                format!("it needs exactly {dof} revolute joints; this robot has {}", robot.dof()),
            );
        }
        let kin = Kinematics::new(robot)?;
        let tool0_inv = kin.tool.inverse();
        Ok(Common { robot: robot.clone(), kin, tool0_inv })
    }

    fn h(&self, i: usize) -> Vector3<f64> {
        self.kin.h[i]
    }

    fn p(&self, i: usize) -> Vector3<f64> {
        self.kin.p[i]
    }

    /// G = T·T₀⁻¹ = E₁(q₁)·…·E₆(q₆): the motion the joints must produce.
    fn motion(&self, target: &Pose) -> Pose {
        *target * self.tool0_inv
    }

    /// Joint value for angle θ of joint `i`: wrapped to (−π, π], moved by
    /// ±2π when that brings it within the limits.
    fn joint_value(&self, i: usize, theta: f64) -> f64 {
        wrap_into_limits(&self.robot.joints()[i].limits, theta)
    }

    /// Adds the joint values for angles `t` (unless one is not finite).
    fn push<const N: usize, const M: usize>(&self, out: &mut Candidates<N, M>, t: [f64; N], branch: &'static str) {
        let mut q = [0.0; N];
        for (i, v) in q.iter_mut().enumerate() {
            *v = self.joint_value(i, t[i]);
        }
        if q.iter().all(|v| v.is_finite()) {
            // A negative tolerance keeps coinciding branches (a target on a boundary), as `pieper` does.
            out.push_unique(q, branch, -1.0, false);
        }
    }
}

fn reject<T>(solver: &str, robot: &Robot, reason: String) -> Result<T> {
    Err(Error::UnsupportedStructure { solver: solver.into(), robot: robot.name().into(), reason })
}

/// A target whose motion is absurdly large (or not finite after the tool is
/// stripped) cannot be reached; saying so early keeps overflow out of the
/// subproblems.
fn too_far(point: &Vector3<f64>) -> Option<Unreachable> {
    (!(point.norm() <= 1e100)).then(|| Unreachable::NotReached {
        detail: "the target is absurdly far away (over 1e100 m, or not finite once the tool is stripped)".into(),
    })
}

/// Checks the target and runs a kernel, naming the solver in its refusal.
fn run_kernel<const M: usize>(
    name: &'static str,
    target: &Pose,
    kernel: impl Fn(&Pose, &mut Candidates<6, M>) -> std::result::Result<(), Unreachable>,
) -> Result<Candidates<6, M>> {
    check_target(target)?;
    let mut c = Candidates::<6, M>::default();
    kernel(target, &mut c).map_err(|reason| Error::Unreachable { solver: name.into(), reason, closest: None })?;
    Ok(c)
}

/// The kernel's candidates into `out`, for [`ClosedForm::kernel`](crate::ik::ClosedForm::kernel).
fn candidates_with<const M: usize>(
    name: &'static str,
    target: &Pose,
    out: &mut CandidateSet,
    kernel: impl Fn(&Pose, &mut Candidates<6, M>) -> std::result::Result<(), Unreachable>,
) -> Result<()> {
    run_kernel(name, target, kernel)?.write_into(out);
    Ok(())
}

/// The geometric solver that fits a robot: one of the families.
///
/// # Examples
/// ```
/// use kinema::ik::{IkSolver, geo::GeoIk};
/// let robot = kinema::Robot::builtin("ur5")?;
/// let ik = GeoIk::new(&robot)?;
/// assert_eq!(ik.name(), "geo-three-parallel");
/// let q = [0.3, -1.1, 1.4, -0.6, 0.9, 2.0];
/// let sols = ik.solve(&robot.fk(&q)?.world_from_tool)?;
/// assert_eq!(sols.len(), 8);
/// assert!(sols.iter().all(|s| s.position_error < 1e-10 && s.orientation_error < 1e-10));
/// assert!(sols.iter().any(|s| s.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9)));
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone)]
pub enum GeoIk {
    /// A spherical wrist ([`SphericalWristIk`]).
    SphericalWrist(SphericalWristIk),
    /// Three parallel axes ([`ThreeParallelIk`]).
    ThreeParallel(ThreeParallelIk),
    /// Three parallel axes, axes 5 and 6 skew: a 1-D search ([`ThreeParallelSearchIk`]).
    ThreeParallelSearch(ThreeParallelSearchIk),
    /// Axes 5 and 6 meet off axis 4: a 1-D search ([`TwoIntersectingSearchIk`]).
    TwoIntersectingSearch(TwoIntersectingSearchIk),
}

/// How a [`FAMILIES`] entry becomes a [`GeoIk`] variant: the entry's name and the variant's constructor.
type Variant = (&'static str, fn(&Robot) -> Result<GeoIk>);

/// The registry entries that are [`GeoIk`] variants; the order they are
/// tried in is the registry's.
const VARIANTS: [Variant; 4] = [
    (SphericalWristIk::NAME, |r| SphericalWristIk::new(r).map(GeoIk::SphericalWrist)),
    (ThreeParallelIk::NAME, |r| ThreeParallelIk::new(r).map(GeoIk::ThreeParallel)),
    (ThreeParallelSearchIk::NAME, |r| ThreeParallelSearchIk::new(r).map(GeoIk::ThreeParallelSearch)),
    (TwoIntersectingSearchIk::NAME, |r| TwoIntersectingSearchIk::new(r).map(GeoIk::TwoIntersectingSearch)),
];

impl GeoIk {
    /// The first six-joint geometric family that fits `robot`, in the order
    /// of [`FAMILIES`] (closed forms first: spherical wrist, three parallel
    /// axes, then the two searches); the error lists why each one refused.
    pub fn new(robot: &Robot) -> Result<Self> {
        let mut refusals = Vec::with_capacity(VARIANTS.len());
        let fits = FAMILIES.iter().filter_map(|e| VARIANTS.iter().find(|(name, _)| *name == e.name));
        for (_, fit) in fits {
            match fit(robot) {
                Ok(geo) => return Ok(geo),
                Err(e) => refusals.push(e.to_string()),
            }
        }
        Err(Error::UnsupportedStructure {
            solver: "geometric".into(),
            robot: robot.name().into(),
            reason: format!("no geometric IK family fits: {}", refusals.join("; ")),
        })
    }

    fn solver(&self) -> &dyn IkSolver {
        match self {
            GeoIk::SphericalWrist(s) => s,
            GeoIk::ThreeParallel(s) => s,
            GeoIk::ThreeParallelSearch(s) => s,
            GeoIk::TwoIntersectingSearch(s) => s,
        }
    }
}

impl IkSolver for GeoIk {
    fn name(&self) -> &'static str {
        self.solver().name()
    }

    fn solve(&self, target: &Pose) -> Result<Vec<Solution>> {
        self.solver().solve(target)
    }

    fn propose(&self, target: &Pose) -> Result<Vec<Solution>> {
        self.solver().propose(target)
    }

    fn candidates_into(&self, target: &Pose, out: &mut CandidateSet) -> Result<()> {
        self.solver().candidates_into(target, out)
    }
}

impl crate::ik::family::Family for GeoIk {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_variant_is_a_registry_entry_and_fits_as_the_registry_does() {
        for (name, _) in VARIANTS {
            assert!(FAMILIES.iter().any(|e| e.name == name), "{name} is not in FAMILIES");
        }
        for name in crate::builtin_names() {
            let robot = Robot::builtin(name).unwrap();
            let fitted = crate::ik::registry::fit(&robot).map(|f| f.name());
            let is_variant = fitted.is_some_and(|f| VARIANTS.iter().any(|(n, _)| *n == f));
            if is_variant {
                assert_eq!(GeoIk::new(&robot).unwrap().name(), fitted.unwrap(), "{name}");
            }
        }
    }
}
