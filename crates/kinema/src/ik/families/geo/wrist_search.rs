//! 6R arms whose axes 5 and 6 meet at a point x but whose axis 4 misses it
//! (an offset wrist), with the shoulder of the spherical-wrist family (axes
//! 2 ∥ 3, or axes 1 and 2 meeting): a 1-D search over q₄.
//!
//! E₅, E₆ fix x, so for a fixed q₄ the first three joints must carry the
//! point x₄ = E₄(q₄)(x) to G(x): the arm of
//! [`SphericalWristIk`](super::SphericalWristIk) with x₄ as its wrist
//! centre (up to 4 branches, *shoulder* and *elbow*). Then
//! M = (R₁R₂R₃R₄)ᵀ·R_G = R₅R₆ and R₆h₆ = h₆ give M·h₆ = R₅·h₆, whose
//! component along h₅ must equal h₅ᵀh₆: the mismatch e(q₄) is the residual
//! searched for zeros per arm branch ([`search`](super::search)). At a zero,
//! q₅ by subproblem 1 (h₆ onto M·h₆) and q₆ by subproblem 1 on a vector ⊥ h₆.
//! Every solution is checked by the product-of-exponentials FK (1e-9,
//! relative). Labels: `shoulder-{1,2}/elbow-{1,2}/root-{1…4}` (zeros in q₄
//! order per branch).

use nalgebra::Vector3;

use super::kin::{distance_to_line, intersection, parallel, screw};
use super::search::{find_zeros, LABELS};
use super::spherical::ShoulderKind;
use super::spherical_arm::SphericalArm;
use super::subproblems::{rot, sp1};
use super::{candidates_with, reject, too_far, Common, GEOM_TOL};
use crate::error::Result;
use crate::ik::{CandidateSet, Candidates, ClosedForm, Unreachable};
use crate::math::Pose;
use crate::robot::Robot;

type V3 = Vector3<f64>;

/// The search-based solver for offset wrists whose last two axes meet (see
/// the [module documentation](self)). Name `geo-two-intersecting-search`.
///
/// # Examples
/// ```
/// use kinema::ik::{IkSolver, geo::TwoIntersectingSearchIk};
/// // The PUMA 560's DH table with axis 4 moved 3 cm off the wrist centre (a4).
/// let rows = [(0.6718, 0.0, 90.0), (0.0, 0.4318, 0.0), (0.15, 0.0203, -90.0),
///             (0.4318, 0.03, 90.0), (0.0, 0.0, -90.0), (0.0, 0.0, 0.0)];
/// let mut toml = String::from("name = \"puma-offset\"\nsource = \"the PUMA 560 with a4 = 3 cm\"\nconvention = \"standard\"\n[units]\nlength = \"m\"\nangle = \"deg\"\n");
/// for (i, (d, a, alpha)) in rows.iter().enumerate() {
///     toml += &format!("[[joint]]\nname = \"j{i}\"\nd = {d}\na = {a}\nalpha = {alpha}\nmin = -180\nmax = 180\n");
/// }
/// toml += "[poses]\nhome = [0, 45, -180, 0, 45, 0]\n";
/// let robot = kinema::Robot::from_toml_str(&toml, "puma-offset.toml")?;
/// let ik = TwoIntersectingSearchIk::new(&robot)?;
/// let q = [0.3, 0.6, -2.5, 0.4, 0.7, -0.2];
/// let sols = ik.solve(&robot.fk(&q)?.world_from_tool)?;
/// assert!(sols.iter().all(|s| s.position_error < 1e-9 && s.orientation_error < 1e-9));
/// assert!(sols.iter().any(|s| s.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9)));
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct TwoIntersectingSearchIk {
    common: Common,
    /// Axes 1, 2, 3: the arm's closed form.
    arm: SphericalArm,
    /// Where axes 5 and 6 meet at q = 0 \[m\].
    x: V3,
    /// A unit vector ⊥ h₆, for q₆.
    u6: V3,
}

impl TwoIntersectingSearchIk {
    /// Checks the structure (tolerance [`GEOM_TOL`]): six revolute joints;
    /// axes 5 and 6 meet (not parallel) and axis 4 does not pass through
    /// that point (else the wrist is spherical); axes 2 ∥ 3 (axis 1 not
    /// parallel to them, axes 2 and 3 distinct) or axes 1 and 2 meet (axis 3
    /// not through that point).
    pub fn new(robot: &Robot) -> Result<Self> {
        let common = Common::new(robot, "geo-two-intersecting-search")?;
        let (h, p) = (|i| common.h(i), |i| common.p(i));
        let Some(x) = intersection(&p(4), &h(4), &p(5), &h(5), GEOM_TOL) else {
            return reject("geo-two-intersecting-search", robot, "axes 5 and 6 do not meet (or are parallel)".into());
        };
        if distance_to_line(&x, &p(3), &h(3)) <= GEOM_TOL {
            return reject(
                "geo-two-intersecting-search",
                robot,
                "axis 4 passes through the point where axes 5 and 6 meet: a spherical wrist".into(),
            );
        }
        let shoulder = if parallel(&h(1), &h(2), GEOM_TOL) {
            if parallel(&h(0), &h(1), GEOM_TOL) || distance_to_line(&p(1), &p(2), &h(2)) <= GEOM_TOL {
                return reject(
                    "geo-two-intersecting-search",
                    robot,
                    "axes 1, 2, 3 are all parallel, or axes 2 and 3 coincide".into(),
                );
            }
            ShoulderKind::Parallel23
        } else if let Some(c) = intersection(&p(0), &h(0), &p(1), &h(1), GEOM_TOL) {
            if distance_to_line(&c, &p(2), &h(2)) <= GEOM_TOL {
                return reject(
                    "geo-two-intersecting-search",
                    robot,
                    "axis 3 passes through the point where axes 1 and 2 meet".into(),
                );
            }
            ShoulderKind::Intersecting12 { c }
        } else {
            return reject(
                "geo-two-intersecting-search",
                robot,
                "axes 2 and 3 are not parallel and axes 1 and 2 do not meet".into(),
            );
        };
        let h6 = h(5);
        let seed = if h6.x.abs() < 0.9 { V3::x() } else { V3::y() };
        let u6 = (seed - h6 * h6.dot(&seed)).normalize();
        let arm = SphericalArm::new([h(0), h(1), h(2)], [p(0), p(1), p(2)], shoulder, [0.0; 2]);
        Ok(TwoIntersectingSearchIk { common, arm, x, u6 })
    }

    /// The robot this solver was built for.
    pub fn robot(&self) -> &Robot {
        &self.common.robot
    }

    /// For q₄ and arm branch `b` (shoulder·2 + elbow): (e(q₄), q₁…q₃), or
    /// the arm's miss where that branch does not exist.
    fn residual(&self, g: &Pose, q4: f64, b: usize) -> std::result::Result<(f64, [f64; 3]), f64> {
        let c = &self.common;
        let h = |i| c.h(i);
        let x4 = screw(&h(3), &c.p(3), q4).transform_point(&self.x);
        let mut arms = [([0.0; 3], 0, 0); 4];
        let n = self.arm.solve(&x4, &g.transform_point(&self.x), &mut arms).map_err(|miss| miss.by())?;
        let Some(&(q, ..)) = arms[..n].iter().find(|(_, si, ei)| si * 2 + ei == b) else { return Err(0.0) };
        let m = self.m(g, q, q4);
        Ok((h(4).dot(&(m * h(5))) - h(4).dot(&h(5)), q))
    }

    /// M = (R₁R₂R₃R₄)ᵀ·R_G.
    fn m(&self, g: &Pose, q: [f64; 3], q4: f64) -> nalgebra::Matrix3<f64> {
        let h = |i| self.common.h(i);
        (rot(&h(0), q[0]) * rot(&h(1), q[1]) * rot(&h(2), q[2]) * rot(&h(3), q4)).transpose() * g.rot
    }

    /// The allocation-free kernel: every candidate (joint values and branch
    /// label) for `target`, without FK checks, or why there is none.
    pub fn solve_candidates(&self, target: &Pose, out: &mut Candidates<6, 16>) -> std::result::Result<(), Unreachable> {
        let c = &self.common;
        let h = |i| c.h(i);
        let g = c.motion(target);
        if let Some(u) = too_far(&g.transform_point(&self.x)) {
            return Err(u);
        }
        let mut roots = [0; 4];
        let scale = 1.0 + g.pos.norm();
        let seen = find_zeros(4, &|q4, b| self.residual(&g, q4, b).map(|r| r.0), &mut |q4, b| {
            let Ok((_, q)) = self.residual(&g, q4, b) else { return };
            let m = self.m(&g, q, q4);
            let q5 = sp1(&h(4), &h(5), &(m * h(5))).first();
            let q6 = sp1(&h(5), &self.u6, &(rot(&h(4), q5).transpose() * m * self.u6)).first();
            let t = [q[0], q[1], q[2], q4, q5, q6];
            let f = c.kin.fk(&t) * c.tool0_inv;
            if ((f.pos - g.pos).norm() / scale).max((f.rot - g.rot).norm()) <= 1e-9 {
                c.push(out, t, LABELS[b * 4 + roots[b].min(3)]);
                roots[b] += 1;
            }
        });
        if out.is_empty() {
            if seen.any_defined {
                // The smallest residual of the search is not a distance: no figure.
                return Err(Unreachable::NotReached {
                    detail: "a search over q4 finds no configuration of the arm that meets it".into(),
                });
            }
            return Err(Unreachable::OutsideReach {
                by: seen.min_miss,
                boundary: "region the point where axes 5 and 6 meet reaches, for every q4".into(),
            });
        }
        Ok(())
    }
}

impl ClosedForm for TwoIntersectingSearchIk {
    const NAME: &'static str = "geo-two-intersecting-search";

    fn robot(&self) -> &Robot {
        &self.common.robot
    }

    /// Every solution the search finds (see the [module documentation](self)).
    fn kernel(&self, target: &Pose, out: &mut CandidateSet) -> Result<()> {
        candidates_with(Self::NAME, target, out, |t, c| self.solve_candidates(t, c))
    }
}

impl crate::ik::family::Family for TwoIntersectingSearchIk {}
