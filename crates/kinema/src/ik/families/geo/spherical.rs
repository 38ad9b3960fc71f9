//! 6R arms whose last three axes meet in one point, the wrist centre w.
//!
//! E₄E₅E₆ fix w, so the target's wrist centre W = G(w) (G = T·T₀⁻¹) depends
//! on q₁…q₃ only: W = E₁E₂E₃(w).
//!
//! **Arm** (q₁, q₂, q₃: the arm's closed form, `geo/spherical_arm.rs`):
//! with axes 2 ∥ 3 ([`ShoulderKind::Parallel23`]) subproblem 4 gives q₁
//! (*shoulder* 1, 2), subproblem 3 q₃ (*elbow* 1, 2) and subproblem 1 q₂;
//! with axes 1 and 2 meeting ([`ShoulderKind::Intersecting12`]) subproblem 3
//! gives q₃ (*elbow* 1, 2) and subproblem 2 (q₁, q₂) (*shoulder* 1, 2).
//!
//! **Wrist.** M = (R₁R₂R₃)ᵀ·R_G = R₄R₅R₆ gives q₄, q₅, q₆ by the shared
//! spherical-wrist solve (`geo/wrist.rs`, *wrist* 1, 2), the one
//! the DH solver `pieper` uses too. At its
//! singularity (axes 4 and 6 aligned) *wrist-1* takes q₄ = 0 and *wrist-2*
//! q₄ = π (wrapped into the limits when possible).
//! **Shoulder singularity** (W on axis 1): q₁ is free. For axes 2 ∥ 3 both
//! shoulder branches are returned, q₁ = 0 and q₁ = π (the arm reaching
//! either way), each with its elbow and wrist branches; for axes 1 and 2
//! meeting, q₁ = 0. E₃(w) on axis 2 leaves q₂ free: q₂ = 0. Coinciding
//! branches of a target on a reach boundary are both returned.

use nalgebra::Vector3;

use super::kin::{distance_to_line, intersection, parallel};
use super::spherical_arm::{ArmMiss, SphericalArm};
use super::subproblems::rotate_sc;
use super::wrist::SphericalWrist;
use super::{candidates_with, label, reject, too_far, Common, GEOM_TOL};
use crate::error::Result;
use crate::ik::{CandidateSet, Candidates, ClosedForm, Unreachable};
use crate::math::{FastMath, Pose};
use crate::robot::Robot;

type V3 = Vector3<f64>;

/// How the first three axes are arranged.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ShoulderKind {
    /// Axes 2 and 3 parallel, axis 1 not parallel to them.
    Parallel23,
    /// Axes 1 and 2 meet at the point `c` (world frame, q = 0) \[m\].
    Intersecting12 {
        /// The intersection point.
        c: V3,
    },
}

/// The geometric solver for 6R arms with a spherical wrist (see the
/// [module documentation](self)). Name `geo-spherical-wrist`.
///
/// # Examples
/// ```
/// use kinema::ik::{IkSolver, geo::SphericalWristIk};
/// let robot = kinema::Robot::from_file(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/puma560.urdf"), None)?;
/// let ik = SphericalWristIk::new(&robot)?;
/// let q = [0.3, 0.6, -2.5, 0.4, 0.7, -0.2];
/// let sols = ik.solve(&robot.fk(&q)?.world_from_tool)?;
/// assert_eq!(sols.len(), 8);
/// assert!(sols.iter().all(|s| s.position_error < 1e-10 && s.orientation_error < 1e-10));
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct SphericalWristIk {
    common: Common,
    /// Axes 1, 2, 3: the arm's closed form.
    arm: SphericalArm,
    /// The wrist centre at q = 0 \[m\].
    w: V3,
    /// Axes 4, 5, 6: the wrist's orientation solve.
    wrist: SphericalWrist,
}

impl SphericalWristIk {
    /// Checks the structure (tolerance [`GEOM_TOL`]) and prepares the
    /// solver: six revolute joints; axes 4 and 5 meet, axis 6 passes through
    /// that point and is not parallel to axis 5; axes 2 ∥ 3 (with axis 1 not
    /// parallel to them and axis 3 not through the wrist centre, nor
    /// coincident with axis 2) or axes 1 and 2 meet (with axis 3 through
    /// neither that point nor the wrist centre). Errors say which fails.
    pub fn new(robot: &Robot) -> Result<Self> {
        let common = Common::new(robot, "geo-spherical-wrist")?;
        let (h, p) = (|i| common.h(i), |i| common.p(i));
        let Some(w) = intersection(&p(3), &h(3), &p(4), &h(4), GEOM_TOL) else {
            return reject(
                "geo-spherical-wrist",
                robot,
                "axes 4 and 5 do not meet (or are parallel): no spherical wrist".into(),
            );
        };
        if parallel(&h(4), &h(5), GEOM_TOL) || distance_to_line(&w, &p(5), &h(5)) > GEOM_TOL {
            return reject("geo-spherical-wrist", robot, "axis 6 does not pass through the point where axes 4 and 5 meet (or is parallel to axis 5): no spherical wrist".into());
        }
        let shoulder = if parallel(&h(1), &h(2), GEOM_TOL) {
            if parallel(&h(0), &h(1), GEOM_TOL) {
                return reject(
                    "geo-spherical-wrist",
                    robot,
                    "axes 1, 2 and 3 are all parallel: the wrist centre cannot reach a 3-D region".into(),
                );
            }
            if distance_to_line(&p(1), &p(2), &h(2)) <= GEOM_TOL {
                return reject("geo-spherical-wrist", robot, "axes 2 and 3 coincide".into());
            }
            ShoulderKind::Parallel23
        } else if let Some(c) = intersection(&p(0), &h(0), &p(1), &h(1), GEOM_TOL) {
            if distance_to_line(&c, &p(2), &h(2)) <= GEOM_TOL {
                return reject(
                    "geo-spherical-wrist",
                    robot,
                    "axis 3 passes through the point where axes 1 and 2 meet: joint 3 cannot change the reach".into(),
                );
            }
            ShoulderKind::Intersecting12 { c }
        } else {
            return reject(
                "geo-spherical-wrist",
                robot,
                "axes 2 and 3 are not parallel and axes 1 and 2 do not meet: no closed form for the arm".into(),
            );
        };
        if distance_to_line(&w, &p(2), &h(2)) <= GEOM_TOL {
            return reject(
                "geo-spherical-wrist",
                robot,
                "the wrist centre lies on axis 3: joint 3 cannot change the reach".into(),
            );
        }
        let wrist = SphericalWrist::new([h(3), h(4), h(5)], 0.0);
        let arm = SphericalArm::new([h(0), h(1), h(2)], [p(0), p(1), p(2)], shoulder, [0.0; 2]);
        Ok(SphericalWristIk { common, arm, w, wrist })
    }

    /// The arrangement of the first three axes that was detected.
    pub fn shoulder_kind(&self) -> ShoulderKind {
        self.arm.shoulder()
    }

    /// The robot this solver was built for.
    pub fn robot(&self) -> &Robot {
        &self.common.robot
    }

    /// The allocation-free kernel: every candidate (joint values and branch
    /// label) for `target`, without FK checks, or why there is none.
    pub fn solve_candidates(&self, target: &Pose, out: &mut Candidates<6, 8>) -> std::result::Result<(), Unreachable> {
        let c = &self.common;
        let h = |i| c.h(i);
        let g = c.motion(target);
        let wt = g.transform_point(&self.w);
        if let Some(u) = too_far(&wt) {
            return Err(u);
        }
        let mut arms = [([0.0; 3], 0, 0); 4];
        let n = self.arm.solve(&self.w, &wt, &mut arms).map_err(arm_unreachable)?;
        let mut worst_wrist = f64::INFINITY;
        let (gh6, gu6) = (g.rot * h(5), g.rot * self.wrist.u());
        for &(q, si, ei) in &arms[..n] {
            // M = (R₁R₂R₃)ᵀ·R_G on h₆ and u₆: turned back about axes 1, 2, 3.
            let turns = q.map(|v| (-v).fast_sin_cos());
            let back = |v: V3| (0..3).fold(v, |v, j| rotate_sc(&h(j), turns[j], &v));
            let roots = match self.wrist.solve(&back(gh6), &back(gu6)) {
                Ok(roots) => roots,
                Err(miss) => {
                    worst_wrist = worst_wrist.min(miss);
                    continue;
                }
            };
            for (wi, &[q4, q5, q6]) in roots.q[..roots.n].iter().enumerate() {
                c.push(out, [q[0], q[1], q[2], q4, q5, q6], label(si, ei, wi));
            }
        }
        if out.is_empty() {
            return Err(Unreachable::Orientation {
                // The miss is a chord between unit vectors; as an angle:
                angle: 2.0 * (0.5 * worst_wrist).min(1.0).asin(),
                detail: "the wrist cannot turn the approach axis (axis 6) to the direction asked for".into(),
            });
        }
        Ok(())
    }
}

/// The arm's miss in this solver's words: each case an [`Unreachable::OutsideReach`]
/// with the arm kernel's figure.
pub(super) fn arm_unreachable(miss: ArmMiss) -> Unreachable {
    let boundary = match miss {
        ArmMiss::LateralOffset { .. } => {
            "cylinder around axis 1 the wrist centre cannot enter (the arm's lateral offset)"
        }
        ArmMiss::Elbow { .. } => "region the wrist centre reaches at the required distance from axis 2",
        ArmMiss::Shell { .. } | ArmMiss::Shoulder { .. } => {
            "spherical shell around the shoulder point that the wrist centre reaches"
        }
    };
    Unreachable::OutsideReach { by: miss.by(), boundary: boundary.into() }
}

impl ClosedForm for SphericalWristIk {
    const NAME: &'static str = "geo-spherical-wrist";

    fn robot(&self) -> &Robot {
        &self.common.robot
    }

    /// All (up to 8) solutions, labelled as in the [module documentation](self).
    fn kernel(&self, target: &Pose, out: &mut CandidateSet) -> Result<()> {
        candidates_with(Self::NAME, target, out, |t, c| self.solve_candidates(t, c))
    }
}

impl crate::ik::family::Family for SphericalWristIk {}
