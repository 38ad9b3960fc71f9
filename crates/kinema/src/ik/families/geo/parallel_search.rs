//! 6R arms with three parallel axes h₂ ∥ h₃ ∥ h₄ whose axes 5 and 6 do not
//! meet (a UR-like arm with an offset wrist): a 1-D search over q₆, as
//! IK-Geo does for its search-based families.
//!
//! For a fixed q₆, G₆ = G·E₆(q₆)⁻¹ = E₁…E₅, and with y = p₅ on axis 5 (fixed
//! by E₅) the steps of the closed form apply: h₂ᵀ·E₁⁻¹(G₆(y)) = h₂ᵀ·y gives
//! q₁ by subproblem 4 (*shoulder* 1, 2). With M = R₁ᵀ·R_{G₆} = R₂₃₄·R₅, the
//! component h₂ᵀ·M·h₅ must equal h₂ᵀ·h₅ (R₂₃₄ keeps h₂, R₅ keeps h₅): its
//! mismatch e(q₆) is the residual searched for zeros per shoulder branch
//! ([`search`](super::search): grid, bisection, close pairs). At a zero,
//! q₅ = −sp1(h₅, h₂, Mᵀh₂) and the planar 3R arm (axes 2–4) follows as in
//! [`ThreeParallelIk`](super::ThreeParallelIk) (*elbow* 1, 2).
//!
//! Every solution is checked by the product-of-exponentials FK (1e-9,
//! relative), so a zero the search reports near a singular target is kept
//! only if it reproduces the target.
//! Labels: `shoulder-{1,2}/elbow-{1,2}/root-{1…4}` (zeros in q₆ order).

use nalgebra::Vector3;

use super::kin::{distance_to_line, intersection, parallel, screw};
use super::search::{find_zeros, LABELS};
use super::subproblems::{rot, sp1, sp3, sp4};
use super::{candidates_with, reject, too_far, Common, GEOM_TOL};
use crate::error::Result;
use crate::ik::{wrap_angle, CandidateSet, Candidates, ClosedForm, Unreachable};
use crate::math::Pose;
use crate::robot::Robot;

type V3 = Vector3<f64>;

/// The search-based solver for three parallel axes with skew axes 5 and 6
/// (see the [module documentation](self)). Name `geo-three-parallel-search`.
///
/// # Examples
/// ```
/// use kinema::ik::{IkSolver, geo::ThreeParallelSearchIk};
/// // The UR5's DH table with a 2 cm link length a5 between axes 5 and 6.
/// let rows = [(0.08946, 0.0, 90.0), (0.0, -0.425, 0.0), (0.0, -0.3922, 0.0),
///             (0.1091, 0.0, 90.0), (0.09465, 0.02, -90.0), (0.0823, 0.0, 0.0)];
/// let mut toml = String::from("name = \"ur5-offset\"\nsource = \"the UR5 with a5 = 2 cm\"\nconvention = \"standard\"\n[units]\nlength = \"m\"\nangle = \"deg\"\n");
/// for (i, (d, a, alpha)) in rows.iter().enumerate() {
///     toml += &format!("[[joint]]\nname = \"j{i}\"\nd = {d}\na = {a}\nalpha = {alpha}\nmin = -360\nmax = 360\n");
/// }
/// toml += "[poses]\nhome = [0, -90, 90, -90, -90, 0]\n";
/// let robot = kinema::Robot::from_toml_str(&toml, "ur5-offset.toml")?;
/// let ik = ThreeParallelSearchIk::new(&robot)?;
/// let q = [0.3, -1.1, 1.4, -0.6, 0.9, 2.0];
/// let sols = ik.solve(&robot.fk(&q)?.world_from_tool)?;
/// assert!(sols.iter().all(|s| s.position_error < 1e-9 && s.orientation_error < 1e-9));
/// assert!(sols.iter().any(|s| s.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9)));
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct ThreeParallelSearchIk {
    common: Common,
    sign3: f64,
    sign4: f64,
    /// A unit vector ⊥ h₂, for the sum of q₂…q₄.
    u2: V3,
}

impl ThreeParallelSearchIk {
    /// Checks the structure (tolerance [`GEOM_TOL`]): six revolute joints;
    /// axes 2, 3, 4 parallel and distinct; axes 1 and 5 not parallel to them;
    /// axis 6 not parallel to axis 5; axes 5 and 6 not meeting (then the
    /// closed form [`ThreeParallelIk`](super::ThreeParallelIk) applies).
    pub fn new(robot: &Robot) -> Result<Self> {
        let common = Common::new(robot, "geo-three-parallel-search")?;
        let (h, p) = (|i| common.h(i), |i| common.p(i));
        if !(parallel(&h(1), &h(2), GEOM_TOL) && parallel(&h(1), &h(3), GEOM_TOL)) {
            return reject("geo-three-parallel-search", robot, "axes 2, 3 and 4 are not parallel".into());
        }
        if parallel(&h(0), &h(1), GEOM_TOL) || parallel(&h(4), &h(1), GEOM_TOL) || parallel(&h(4), &h(5), GEOM_TOL) {
            return reject(
                "geo-three-parallel-search",
                robot,
                "axis 1 or 5 is parallel to axes 2–4, or axis 6 to axis 5: a degenerate arm".into(),
            );
        }
        if distance_to_line(&p(1), &p(2), &h(2)) <= GEOM_TOL || distance_to_line(&p(3), &p(2), &h(2)) <= GEOM_TOL {
            return reject(
                "geo-three-parallel-search",
                robot,
                "axis 3 coincides with axis 2 or axis 4: a degenerate planar arm".into(),
            );
        }
        if intersection(&p(4), &h(4), &p(5), &h(5), GEOM_TOL).is_some() {
            return reject(
                "geo-three-parallel-search",
                robot,
                "axes 5 and 6 meet: the closed form applies, not the search".into(),
            );
        }
        let h2 = h(1);
        let seed = if h2.x.abs() < 0.9 { V3::x() } else { V3::y() };
        let u2 = (seed - h2 * h2.dot(&seed)).normalize();
        Ok(ThreeParallelSearchIk { sign3: h2.dot(&h(2)).signum(), sign4: h2.dot(&h(3)).signum(), u2, common })
    }

    /// The robot this solver was built for.
    pub fn robot(&self) -> &Robot {
        &self.common.robot
    }

    /// For q₆ and shoulder branch `b`: (e(q₆), t₁ = −q₁, G₆), or the miss of
    /// subproblem 4 where it has no exact root for that branch.
    fn residual(&self, g: &Pose, q6: f64, b: usize) -> std::result::Result<(f64, f64, Pose), f64> {
        let c = &self.common;
        let (h, p) = (|i| c.h(i), |i| c.p(i));
        let g6 = *g * screw(&h(5), &p(5), -q6);
        let yt = g6.transform_point(&p(4));
        let s1 = sp4(&h(1), &h(0), &(yt - p(0)), h(1).dot(&(p(4) - p(0))));
        if !s1.exact {
            return Err(s1.miss);
        }
        // A free q1 (the shoulder singularity) has one root: no second branch.
        let t1 = *s1.as_slice().get(b).ok_or(0.0)?;
        let m = rot(&h(0), t1) * g6.rot;
        Ok((h(1).dot(&(m * h(4))) - h(1).dot(&h(4)), t1, g6))
    }

    /// The allocation-free kernel: every candidate (joint values and branch
    /// label) for `target`, without FK checks, or why there is none.
    pub fn solve_candidates(&self, target: &Pose, out: &mut Candidates<6, 16>) -> std::result::Result<(), Unreachable> {
        let g = self.common.motion(target);
        if let Some(u) = too_far(&g.pos) {
            return Err(u);
        }
        let mut roots = [0; 2];
        let seen = find_zeros(2, &|q6, b| self.residual(&g, q6, b).map(|r| r.0), &mut |q6, b| {
            if self.finish(&g, b, q6, roots[b], out) {
                roots[b] += 1;
            }
        });
        if out.is_empty() {
            if !seen.any_defined {
                return Err(Unreachable::OutsideReach {
                    by: seen.min_miss,
                    boundary: "cylinder around axis 1 that axis 5 cannot enter, for every q6".into(),
                });
            }
            // The smallest residual of the search is not a distance: no figure.
            return Err(Unreachable::NotReached {
                detail: "a search over q6 finds no configuration of the arm that meets it".into(),
            });
        }
        Ok(())
    }

    /// The closed-form rest at a zero q₆ of branch `b`; pushes the (up to 2)
    /// solutions that reproduce the target. Returns whether any did.
    fn finish(&self, g: &Pose, b: usize, q6: f64, root: usize, out: &mut Candidates<6, 16>) -> bool {
        let c = &self.common;
        let (h, p) = (|i| c.h(i), |i| c.p(i));
        let Ok((_, t1, g6)) = self.residual(g, q6, b) else { return false };
        let m = rot(&h(0), t1) * g6.rot;
        let q5 = -sp1(&h(4), &h(1), &(m.transpose() * h(1))).first();
        let k = screw(&h(0), &p(0), t1) * g6 * screw(&h(4), &p(4), -q5);
        let sum = sp1(&h(1), &self.u2, &(k.rot * self.u2)).first();
        let pt = k.transform_point(&p(3));
        let s3 = sp3(&h(2), &(p(3) - p(2)), &(p(1) - p(2)), (pt - p(1)).norm());
        if !s3.exact {
            return false;
        }
        let mut any = false;
        let scale = 1.0 + g.pos.norm();
        for (e, &q3) in s3.as_slice().iter().enumerate() {
            let y = p(2) + super::subproblems::rotate(&h(2), q3, &(p(3) - p(2)));
            let q2 = sp1(&h(1), &(y - p(1)), &(pt - p(1))).first();
            let q4 = self.sign4 * (sum - q2 - self.sign3 * q3);
            let t = [-t1, q2, q3, wrap_angle(q4), q5, q6];
            // A sign change of e across a branch switch is not a zero: keep only exact solutions.
            let f = c.kin.fk(&t) * c.tool0_inv;
            let err = ((f.pos - g.pos).norm() / scale).max((f.rot - g.rot).norm());
            if err <= 1e-9 {
                c.push(out, t, LABELS[b * 8 + e * 4 + root.min(3)]);
                any = true;
            }
        }
        any
    }
}

impl ClosedForm for ThreeParallelSearchIk {
    const NAME: &'static str = "geo-three-parallel-search";

    fn robot(&self) -> &Robot {
        &self.common.robot
    }

    /// Every solution the search finds (see the [module documentation](self)).
    fn kernel(&self, target: &Pose, out: &mut CandidateSet) -> Result<()> {
        candidates_with(Self::NAME, target, out, |t, c| self.solve_candidates(t, c))
    }
}

impl crate::ik::family::Family for ThreeParallelSearchIk {}
