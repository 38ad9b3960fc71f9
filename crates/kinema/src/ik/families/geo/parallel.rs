//! 6R arms with three parallel axes h₂ ∥ h₃ ∥ h₄ and axes 5 and 6 meeting
//! at a point x (the UR family: UR3/5/10/16, and their URDF descriptions).
//!
//! With G = T·T₀⁻¹ = E₁…E₆ and R_G its rotation:
//!
//! 1. E₅, E₆ fix x and E₂E₃E₄ (turns about lines ∥ h₂) keep the component
//!    along h₂, so h₂ᵀ·E₁⁻¹(G(x)) = h₂ᵀ·x: subproblem 4 in q₁ (*shoulder*
//!    1, 2).
//! 2. With M = R₁ᵀ·R_G = R₂₃₄·R₅·R₆ and R₂₃₄ᵀh₂ = h₂:
//!    h₂ᵀ·rot(h₅, q₅)·h₆ = h₂ᵀ·M·h₆, subproblem 4 in q₅ (*wrist* 1, 2).
//! 3. rot(h₆, q₆)·Mᵀh₂ = rot(h₅, −q₅)·h₂: subproblem 1 in q₆. When
//!    Mᵀh₂ ∥ h₆ (axis 6 parallel to axes 2–4, within 1e-12; the UR's wrist
//!    singularity) q₆ is free and the arm redundant. Convention: q₆ = 0 when
//!    the planar arm then reaches; else the q₆ (subproblem 3 about axis 6)
//!    that puts axis 4 at the middle of the distances from axis 2 the planar
//!    arm reaches, or as near to it as the wrist allows.
//! 4. K = E₁⁻¹·G·E₆⁻¹·E₅⁻¹ = E₂E₃E₄ is now known: a planar 3R problem. Its
//!    rotation gives the signed sum of q₂, q₃, q₄ (subproblem 1), the point
//!    P = K(p₄) = E₂E₃(p₄) gives q₃ by subproblem 3 (|E₃(p₄) − p₂| = |P − p₂|,
//!    *elbow* 1, 2) and q₂ by subproblem 1; q₄ is the rest of the sum.
//!
//! **Shoulder singularity** (G(x) placed so that its height along h₂ does
//! not depend on q₁, e.g. on axis 1 when h₁ ⊥ h₂): q₁ is free; q₁ = 0, one
//! shoulder branch. Coinciding branches of a target on a reach boundary or
//! at a double root of step 2 are both returned.

use nalgebra::Vector3;

use super::kin::{distance_to_line, intersection, parallel, screw};
use super::subproblems::{rot, rotate, sp1, sp3, sp4, Angles};
use super::{candidates_with, label, reject, too_far, Common, GEOM_TOL};
use crate::error::Result;
use crate::ik::{CandidateSet, Candidates, ClosedForm, Unreachable};
use crate::math::Pose;
use crate::robot::Robot;

type V3 = Vector3<f64>;

/// Below this |h₆ × Mᵀh₂| axis 6 is treated as parallel to axes 2–4.
const SING_TOL: f64 = 1e-12;

/// The geometric solver for 6R arms with three parallel axes (see the
/// [module documentation](self)). Name `geo-three-parallel`.
///
/// # Examples
/// ```
/// use kinema::ik::{IkSolver, geo::ThreeParallelIk};
/// let robot = kinema::Robot::from_file(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/ur5.urdf"), None)?;
/// let ik = ThreeParallelIk::new(&robot)?;
/// let q = [0.3, -1.1, 1.4, -0.6, 0.9, 2.0];
/// let sols = ik.solve(&robot.fk(&q)?.world_from_tool)?;
/// assert_eq!(sols.len(), 8);
/// assert!(sols.iter().all(|s| s.position_error < 1e-10 && s.orientation_error < 1e-10));
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct ThreeParallelIk {
    common: Common,
    /// Where axes 5 and 6 meet at q = 0 \[m\].
    x: V3,
    /// ±1: the direction of h₃ and h₄ relative to h₂.
    sign3: f64,
    sign4: f64,
    /// A unit vector ⊥ h₂, for the sum of q₂…q₄.
    u2: V3,
    /// The middle of the range of |E₃(p₄) − p₂| \[m\].
    mid_reach: f64,
}

impl ThreeParallelIk {
    /// Checks the structure (tolerance [`GEOM_TOL`]) and prepares the
    /// solver: six revolute joints; axes 2, 3, 4 parallel and distinct
    /// (axis 3 through neither a point of axis 2 nor of axis 4); axis 1 and
    /// axis 5 not parallel to them; axes 5 and 6 meet and are not parallel.
    /// Errors say which condition fails.
    pub fn new(robot: &Robot) -> Result<Self> {
        let common = Common::new(robot, "geo-three-parallel")?;
        let (h, p) = (|i| common.h(i), |i| common.p(i));
        if !(parallel(&h(1), &h(2), GEOM_TOL) && parallel(&h(1), &h(3), GEOM_TOL)) {
            return reject("geo-three-parallel", robot, "axes 2, 3 and 4 are not parallel".into());
        }
        if parallel(&h(0), &h(1), GEOM_TOL) || parallel(&h(4), &h(1), GEOM_TOL) {
            return reject(
                "geo-three-parallel",
                robot,
                "axis 1 or axis 5 is parallel to axes 2–4: a degenerate arm".into(),
            );
        }
        if distance_to_line(&p(1), &p(2), &h(2)) <= GEOM_TOL || distance_to_line(&p(3), &p(2), &h(2)) <= GEOM_TOL {
            return reject(
                "geo-three-parallel",
                robot,
                "axis 3 coincides with axis 2 or axis 4: a degenerate planar arm".into(),
            );
        }
        let Some(x) = intersection(&p(4), &h(4), &p(5), &h(5), GEOM_TOL) else {
            return reject(
                "geo-three-parallel",
                robot,
                "axes 5 and 6 do not meet (or are parallel); the three-parallel closed form needs them to".into(),
            );
        };
        let h2 = h(1);
        let seed = if h2.x.abs() < 0.9 { V3::x() } else { V3::y() };
        let u2 = (seed - h2 * h2.dot(&seed)).normalize();
        // |E3(p4) − p2| over q3: √(S ± 2r), S and r from the subproblem-3 terms.
        let (a, b) = (p(3) - p(2), p(1) - p(2));
        let ap = a - h(2) * h(2).dot(&a);
        let r = b.dot(&ap).hypot(b.dot(&h(2).cross(&ap)));
        let sum = a.norm_squared() + b.norm_squared() - 2.0 * h(2).dot(&a) * h(2).dot(&b);
        let mid_reach = 0.5 * ((sum - 2.0 * r).max(0.0).sqrt() + (sum + 2.0 * r).sqrt());
        Ok(ThreeParallelIk { x, sign3: h2.dot(&h(2)).signum(), sign4: h2.dot(&h(3)).signum(), u2, mid_reach, common })
    }

    /// q3 of the planar arm for K = E₂E₃E₄: |E₃(p₄) − p₂| = |K(p₄) − p₂|.
    fn planar(&self, k: &Pose) -> Angles {
        let c = &self.common;
        let (h, p) = (|i| c.h(i), |i| c.p(i));
        sp3(&h(2), &(p(3) - p(2)), &(p(1) - p(2)), (k.transform_point(&p(3)) - p(1)).norm())
    }

    /// The robot this solver was built for.
    pub fn robot(&self) -> &Robot {
        &self.common.robot
    }

    /// The allocation-free kernel: every candidate (joint values and branch
    /// label) for `target`, without FK checks, or why there is none.
    pub fn solve_candidates(&self, target: &Pose, out: &mut Candidates<6, 8>) -> std::result::Result<(), Unreachable> {
        let c = &self.common;
        let (h, p) = (|i| c.h(i), |i| c.p(i));
        let g = c.motion(target);
        let xt = g.transform_point(&self.x);
        if let Some(u) = too_far(&xt) {
            return Err(u);
        }
        let s1 = sp4(&h(1), &h(0), &(xt - p(0)), h(1).dot(&(self.x - p(0))));
        if !s1.exact {
            return Err(Unreachable::OutsideReach {
                by: s1.miss,
                boundary: "cylinder around axis 1 that the wrist cannot enter (the arm's lateral offset)".into(),
            });
        }
        let mut miss = f64::INFINITY;
        let mut orientation_miss = f64::INFINITY;
        for (si, &t1) in s1.as_slice().iter().enumerate() {
            let q1 = -t1;
            let m = rot(&h(0), q1).transpose() * g.rot;
            let s5 = sp4(&h(1), &h(4), &h(5), h(1).dot(&(m * h(5))));
            if !s5.exact {
                orientation_miss = orientation_miss.min(s5.miss);
                continue;
            }
            let e1_inv_g = screw(&h(0), &p(0), t1) * g;
            for (wi, &q5) in s5.as_slice().iter().enumerate() {
                let mt_h2 = m.transpose() * h(1);
                let e5_inv = screw(&h(4), &p(4), -q5);
                let mut q6 = 0.0;
                let mut s3 = None;
                if h(5).cross(&mt_h2).norm() <= SING_TOL {
                    // Axis 6 ∥ axes 2–4: q6 is free. q6 = 0 if the planar arm then reaches;
                    // else the q6 that puts axis 4 mid-way across the arm's annulus (or
                    // as near to it as the wrist allows).
                    let s = self.planar(&(e1_inv_g * e5_inv));
                    if s.exact {
                        s3 = Some(s);
                    } else {
                        // P(q6) = H(E6(−q6)(y)) with H = E1⁻¹·G and y = E5⁻¹(p4).
                        let hinv_p2 = e1_inv_g.inverse().transform_point(&p(1));
                        let y = e5_inv.transform_point(&p(3));
                        let sa = sp3(&h(5), &(y - p(5)), &(hinv_p2 - p(5)), self.mid_reach);
                        q6 = -sa.first();
                    }
                } else {
                    q6 = sp1(&h(5), &mt_h2, &rotate(&h(4), -q5, &h(1))).first();
                }
                let k = e1_inv_g * screw(&h(5), &p(5), -q6) * e5_inv;
                let sum = sp1(&h(1), &self.u2, &(k.rot * self.u2)).first();
                let pt = k.transform_point(&p(3));
                let s3 = s3.unwrap_or_else(|| self.planar(&k));
                if !s3.exact {
                    miss = miss.min(s3.miss);
                    continue;
                }
                for (ei, &q3) in s3.as_slice().iter().enumerate() {
                    let y = p(2) + rotate(&h(2), q3, &(p(3) - p(2)));
                    let q2 = sp1(&h(1), &(y - p(1)), &(pt - p(1))).first();
                    // sum = q2 + sign3·q3 + sign4·q4 (angles about h2).
                    let q4 = self.sign4 * (sum - q2 - self.sign3 * q3);
                    c.push(out, [q1, q2, q3, q4, q5, q6], label(si, ei, wi));
                }
            }
        }
        if out.is_empty() {
            if miss.is_finite() || !orientation_miss.is_finite() {
                return Err(Unreachable::OutsideReach {
                    by: miss,
                    boundary: "annulus the planar arm (axes 2–4) reaches around axis 2".into(),
                });
            }
            return Err(Unreachable::Orientation {
                angle: orientation_miss,
                detail: "joint 5 cannot tilt axis 6 to the angle asked for against axes 2–4".into(),
            });
        }
        Ok(())
    }
}

impl ClosedForm for ThreeParallelIk {
    const NAME: &'static str = "geo-three-parallel";

    fn robot(&self) -> &Robot {
        &self.common.robot
    }

    /// All (up to 8) solutions, labelled as in the [module documentation](self).
    fn kernel(&self, target: &Pose, out: &mut CandidateSet) -> Result<()> {
        candidates_with(Self::NAME, target, out, |t, c| self.solve_candidates(t, c))
    }
}

impl crate::ik::family::Family for ThreeParallelIk {}
