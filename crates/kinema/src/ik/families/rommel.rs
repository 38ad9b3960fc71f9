//! Closed-form inverse kinematics of ROMMEL (seed 001 §3.2), derived here from the
//! modified-DH model of `robots/rommel.toml` (the seed only sketches θ1…θ5).
//!
//! # Geometry (derived from the DH table, checked against FK in [`RommelIk::new`])
//!
//! The vertical axis is world **y** (joint 1 turns about +y). With the joint
//! values q (offsets of the table included) and lengths d1 = l0 + l1y (joint-1
//! row d), a1 = l1x (joint-2 row a), a2 = l2 (joint-3 row a), d4 = l3 + l4
//! (joint-4 row d):
//!
//! * horizontal direction of the arm plane u = (−cos q1, 0, sin q1), joint-2/3 axis
//!   w = (−sin q1, 0, −cos q1) (normal to the plane);
//! * in the plane (ρ along u, h along y) the wrist — which is the tool point, d5 = 0 —
//!   is at ρ = a1 − a2·sin q2 − d4·sin(q2+q3), h = d1 + a2·cos q2 + d4·cos(q2+q3);
//!   world p = (−ρ·cos q1, h, ρ·sin q1);
//! * joint 4 rolls about the forearm f = (sin q23·cos q1, cos q23, −sin q23·sin q1);
//!   the approach (tool z) is z5 = cos q4·w + sin q4·(f × w), always ⟂ f;
//! * joint 5 turns the tool about its approach (it does not move it).
//!
//! So the position fixes q1, q2, q3 (up to four ways), the approach then fixes q4 —
//! **if** it is perpendicular to the forearm. A 5-DOF arm of this kind cannot point
//! its tool along any other direction at that position: such a target is
//! [`Unreachable::Orientation`] with the angle asin|a·f| between the approach and
//! the nearest reachable one.
//!
//! # Solutions and labels
//!
//! * `front` (ρ = +√(px² + pz²), the side of the home pose) / `back` (ρ = −…, over the
//!   top of joint 1): q1 = atan2(pz, −px) or atan2(−pz, px);
//! * `elbow-pos` / `elbow-neg`: sign of q3 (law of cosines for the planar 2-link
//!   a2, d4: X' = h − d1, Y' = a1 − ρ, X' = a2·c2 + d4·c23, Y' = a2·s2 + d4·s23).
//!
//! Conventions: wrist on the vertical axis (the position does not fix q1): q1 is
//! chosen so the forearm is perpendicular to the approach (two ways, labels
//! `axis/elbow-…/a` and `/b`; q1 = 0 if q1 does not matter either); wrist on the
//! shoulder (a2 = d4, folded): q2 = 0; q5 = 0 for a position + approach target
//! ([`RommelIk::solve_position_approach`]); for a full pose ([`IkSolver::solve`](crate::ik::IkSolver::solve)) q5
//! turns the tool x axis onto the target's. Angles are wrapped to (−π, π].
//!
//! # Base and tool
//!
//! Any base transform. The tool may be moved along and turned about the flange z
//! axis only (otherwise the tool point would depend on the free roll q5).

use std::f64::consts::PI;

use nalgebra::Vector3;

use crate::error::{Error, InputError, Result};
use crate::ik::target::{Component, Quantity, TypedKind, TypedTarget};
use crate::ik::{check_target, wrap_angle, Solution, Unreachable};
use crate::math::FastMath;
use crate::math::Pose;
use crate::model::{DhConvention, LinkGeometry};
use crate::robot::Robot;

/// ROMMEL's typed target (seed 001): the tool point with the tool z axis
/// along `approach` (any non-zero vector, normalised), q5 = 0
/// ([`RommelIk::solve_position_approach`], up to four solutions).
pub static APPROACH: TypedKind = TypedKind {
    name: "approach",
    components: &[Component { name: "approach", quantity: Quantity::Direction }],
    summary: "ROMMEL: position and approach direction",
};

/// Name of the solver in errors.
const NAME: &str = "rommel";

/// Positions this close outside the reachable annulus \[m\] are treated as on it.
const REACH_TOL: f64 = 1e-12;

/// Approaches within this angle \[rad\] of a reachable one are accepted (and projected).
pub const APPROACH_TOL: f64 = 1e-9;

/// Closed-form solver for ROMMEL-like arms (seed 001).
///
/// # Examples
/// ```
/// use kinema::ik::rommel::RommelIk;
/// let robot = kinema::Robot::builtin("rommel")?;
/// let ik = RommelIk::new(&robot)?;
/// let q = [0.3, 0.4, 0.5, 0.6, 0.0];
/// let fk = robot.fk(&q)?.world_from_tool;
/// let a = fk.rot.column(2);
/// let sols = ik.solve_position_approach([fk.pos.x, fk.pos.y, fk.pos.z], [a[0], a[1], a[2]])?;
/// assert!(sols.iter().any(|s| s.q.iter().zip(&q).all(|(x, y)| (x - y).abs() < 1e-9)));
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct RommelIk {
    robot: Robot,
    d1: f64,
    a1: f64,
    a2: f64,
    /// l3 + l4 \[m\].
    d4: f64,
    /// Tool translation along the flange z axis \[m\].
    tool_z: f64,
}

/// A candidate before evaluation.
struct Raw {
    q: Vec<f64>,
    label: String,
}

impl RommelIk {
    /// The angle \[rad\] between the tool z axis of `reached` and `approach`
    /// (world frame, any length; π for a zero or non-finite approach).
    pub fn approach_error(reached: &Pose, approach: [f64; 3]) -> f64 {
        let a = Vector3::from(approach);
        let z = reached.rot.column(2).into_owned();
        let n = a.norm();
        if !(n > 1e-12 && n.is_finite()) {
            return std::f64::consts::PI;
        }
        // atan2 of |z × a| and z·a stays accurate near 0 and π, where acos does not.
        z.cross(&a).norm().atan2(z.dot(&a))
    }

    /// A solver for `robot`, reading d1, a1, a2, d4 from its modified-DH table and
    /// checking with forward kinematics that the geometry of the module
    /// documentation holds.
    ///
    /// Errors ([`Error::UnsupportedStructure`]) for a robot that is not five revolute
    /// modified-DH joints with that geometry, or a tool that leaves the flange z axis.
    pub fn new(robot: &Robot) -> Result<Self> {
        let bad =
            |reason: String| Error::UnsupportedStructure { solver: NAME.into(), robot: robot.name().into(), reason };
        if robot.joint_types() != "RRRRR" {
            return Err(bad(format!(
                "the ROMMEL solver needs 5 revolute joints; `{}` is {}",
                robot.name(),
                robot.joint_types()
            )));
        }
        let row = |i: usize| match robot.joints()[i].geometry {
            LinkGeometry::Dh { convention: DhConvention::Modified, d, a, .. } => Ok((d, a)),
            _ => Err(bad(format!("joint {} is not described by a modified-DH row", i + 1))),
        };
        let (d1, _) = row(0)?;
        let (_, a1) = row(1)?;
        let (_, a2) = row(2)?;
        let (d4, _) = row(3)?;
        if !(a2 > 0.0 && d4 > 0.0) {
            return Err(bad(format!("the arm links must have positive lengths (l2 = {a2} m, l3 + l4 = {d4} m)")));
        }
        let tool = robot.tool();
        if tool.pos.x.abs() > 1e-12 || tool.pos.y.abs() > 1e-12 || (tool.rot[(2, 2)] - 1.0).abs() > 1e-12 {
            return Err(bad("the tool may only move along and turn about the flange z axis".into()));
        }
        let me = RommelIk { robot: robot.clone(), d1, a1, a2, d4, tool_z: tool.pos.z };
        // Check the derived geometry against FK (robot frame, bare flange).
        let bare = robot.with_tool(Pose::IDENTITY)?.with_base(Pose::IDENTITY)?;
        for k in 0..7 {
            let t = k as f64;
            let q = [0.9 * t - 3.0, 0.5 * t - 1.4, 1.2 - 0.4 * t, 0.7 * t - 2.0, 0.3 * t];
            let fk = bare.fk(&q)?.world_from_tool;
            let (p, z) = me.forward(&q);
            if (fk.pos - p).norm() > 1e-9 || (fk.rot.column(2) - z).norm() > 1e-9 {
                return Err(bad(format!(
                    "forward kinematics of `{}` does not have the ROMMEL geometry (seed 001 Tabla 1) with \
                     d1 = {d1}, a1 = {a1}, a2 = {a2}, d4 = {d4} m",
                    robot.name()
                )));
            }
        }
        Ok(me)
    }

    /// The robot this solver was built for.
    pub fn robot(&self) -> &Robot {
        &self.robot
    }

    /// Wrist point and approach of the bare flange in the robot frame (the closed
    /// forms of the module documentation).
    fn forward(&self, q: &[f64; 5]) -> (Vector3<f64>, Vector3<f64>) {
        let (s1, c1) = q[0].fast_sin_cos();
        let (s2, c2) = q[1].fast_sin_cos();
        let (s23, c23) = (q[1] + q[2]).fast_sin_cos();
        let rho = self.a1 - self.a2 * s2 - self.d4 * s23;
        let h = self.d1 + self.a2 * c2 + self.d4 * c23;
        let p = Vector3::new(-rho * c1, h, rho * s1);
        let w = Vector3::new(-s1, 0.0, -c1);
        let f = Vector3::new(s23 * c1, c23, -s23 * s1);
        let (s4, c4) = q[3].fast_sin_cos();
        (p, c4 * w + s4 * f.cross(&w))
    }

    /// Every solution placing the tool point at `p` \[m\] (world frame) with the tool
    /// z axis along `approach` (any non-zero vector; normalised), q5 = 0.
    ///
    /// Up to four solutions (front/back × elbow-pos/neg), each evaluated against
    /// the pose it reaches with the target position (the roll about the approach is
    /// not part of this target), flagged for joint limits. Errors: non-finite input
    /// ([`InputError::NotFinite`]) or a zero approach ([`InputError::OutOfRange`]); the position out of reach
    /// ([`Unreachable::OutsideReach`]); no position branch whose forearm is
    /// perpendicular to the approach ([`Unreachable::Orientation`], with the smallest
    /// angle to a reachable approach).
    ///
    /// # Examples
    /// ```
    /// use kinema::ik::rommel::RommelIk;
    /// let ik = RommelIk::new(&kinema::Robot::builtin("rommel")?)?;
    /// // Home: p = (−0.05, 0.743, 0) m, tool pointing along −z.
    /// let sols = ik.solve_position_approach([-0.05, 0.743, 0.0], [0.0, 0.0, -1.0])?;
    /// assert!(sols.iter().any(|s| s.q.iter().all(|v| v.abs() < 1e-7)));
    /// // Pointing along the (vertical) forearm is impossible there.
    /// assert!(ik.solve_position_approach([-0.05, 0.743, 0.0], [0.0, 1.0, 0.0]).is_err());
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn solve_position_approach(&self, p: [f64; 3], approach: [f64; 3]) -> Result<Vec<Solution>> {
        let named = p.iter().map(|&v| ("position", v)).chain(approach.iter().map(|&v| ("approach", v)));
        if let Some((what, value)) = named.into_iter().find(|(_, v)| !v.is_finite()) {
            return Err(Error::Input(InputError::NotFinite { what: what.into(), value }));
        }
        let a = Vector3::from(approach);
        let n = a.norm();
        if n <= 1e-12 {
            return Err(Error::Input(InputError::OutOfRange {
                what: "approach".into(),
                value: n,
                expected: "a direction of non-zero length (this is its length)".into(),
            }));
        }
        let a = a / n;
        let base = self.robot.base();
        let pl = base.inverse().transform_point(&Vector3::from(p));
        let al = base.rot.transpose() * a;
        let raw = self.branches(&pl, &al, |_| 0.0)?;
        raw.into_iter()
            .map(|r| {
                let reached = self.robot.fk(&r.q)?.world_from_tool;
                Solution::evaluate(&self.robot, r.q, &Pose::new(reached.rot, Vector3::from(p)), r.label)
            })
            .collect()
    }

    /// All branches for a tool point `p` and unit approach `a` in the robot frame;
    /// `q5_for(q)` picks q5 from the first four joint values.
    fn branches(&self, p: &Vector3<f64>, a: &Vector3<f64>, q5_for: impl Fn(&[f64; 4]) -> f64) -> Result<Vec<Raw>> {
        let wrist = p - self.tool_z * a;
        let s = wrist.x.fast_hypot(wrist.z);
        let mut out = Vec::with_capacity(4);
        let mut miss_pos: Vec<(f64, String)> = Vec::new();
        let mut miss_rot: Option<f64> = None;
        let on_axis = s <= 1e-12;
        for (side, sign) in [("front", 1.0), ("back", -1.0)] {
            if on_axis && sign < 0.0 {
                break; // ρ = 0: both sides are the same; q1 comes from the approach below.
            }
            let rho = sign * s;
            let side = if on_axis { "axis" } else { side };
            // Planar 2-link (a2, d4) in X' = h − d1 (up), Y' = a1 − ρ.
            let (x, y) = (wrist.y - self.d1, self.a1 - rho);
            let r = x.fast_hypot(y);
            // Law of cosines, half-angle form (see `two_link_elbow`).
            let q3abs = match crate::ik::two_link_elbow(r, self.a2, self.d4, REACH_TOL) {
                Ok(e) => e.angle,
                Err(miss) => {
                    let which = if miss.outer { "outer" } else { "inner" };
                    let radius = miss.radius;
                    miss_pos.push((
                        miss.by,
                        format!("{which} sphere of radius {radius:.6} m around the shoulder ({side} branch)"),
                    ));
                    continue;
                }
            };
            for (elbow, es) in [("elbow-pos", 1.0), ("elbow-neg", -1.0)] {
                let q3 = es * q3abs;
                let q2 = if r > 1e-15 {
                    wrap_angle(y.fast_atan2(x) - (self.d4 * q3.sin()).fast_atan2(self.a2 + self.d4 * q3.cos()))
                } else {
                    0.0
                };
                let (s23, c23) = (q2 + q3).fast_sin_cos();
                // q1 from the position; on the vertical axis (position independent of q1)
                // from the approach instead: a·f = s23·(ax·c1 − az·s1) + ay·c23 = 0, i.e.
                // s23·h·cos(q1 + φ) = −ay·c23 with h = |(ax, az)|, φ = atan2(az, ax).
                let mut q1s: Vec<(f64, &str)> = Vec::with_capacity(2);
                if !on_axis {
                    // Seed 001 §3.2 prints θ1 = tan⁻¹(z5/x5); in the model of its Tabla 1
                    // (θ1 = q1 + π) tan q1 = −z/x, so q1 = atan2(z/ρ, −x/ρ): front
                    // atan2(z, −x), back atan2(−z, x). The printed ratio has the wrong sign.
                    q1s.push(((wrist.z / rho).fast_atan2(-wrist.x / rho), ""));
                } else {
                    let h = a.x.fast_hypot(a.z);
                    let (lhs, rhs) = (s23 * h, -a.y * c23);
                    if lhs.abs() <= 1e-12 {
                        q1s.push((0.0, "")); // q1 does not move the approach either: q1 = 0
                    } else if (rhs / lhs).abs() <= 1.0 + 1e-12 {
                        let k = (rhs / lhs).clamp(-1.0, 1.0).acos();
                        let phi = a.z.fast_atan2(a.x);
                        q1s.push((wrap_angle(k - phi), "/a"));
                        q1s.push((wrap_angle(-k - phi), "/b"));
                    } else {
                        let off = ((rhs.abs() - lhs.abs()).clamp(0.0, 1.0)).asin();
                        miss_rot = Some(miss_rot.map_or(off, |m: f64| m.min(off)));
                    }
                }
                for (q1, tag) in q1s {
                    let (s1, c1) = q1.fast_sin_cos();
                    let w = Vector3::new(-s1, 0.0, -c1);
                    let f = Vector3::new(s23 * c1, c23, -s23 * s1);
                    let af = a.dot(&f).clamp(-1.0, 1.0);
                    let off = af.abs().asin();
                    if off > APPROACH_TOL {
                        miss_rot = Some(miss_rot.map_or(off, |m: f64| m.min(off)));
                        continue;
                    }
                    let q4 = a.dot(&f.cross(&w)).fast_atan2(a.dot(&w));
                    let q4 = if q4 == -PI { PI } else { q4 };
                    // Seed 001 §3.2 gives θ5 = −arccos(z4·n); here the approach is always
                    // perpendicular to z4 (the forearm, joint 4's axis), so z4·n = 0 and that
                    // formula cannot fix θ5: q5 turns the tool about its approach, and is
                    // taken from the target's x axis (or 0 for a position + approach target).
                    let q5 = q5_for(&[q1, q2, q3, q4]);
                    out.push(Raw {
                        q: vec![wrap_angle(q1), q2, wrap_angle(q3), q4, q5],
                        label: format!("{side}/{elbow}{tag}"),
                    });
                }
            }
        }
        if out.is_empty() {
            let reason = if let Some(angle) = miss_rot {
                Unreachable::Orientation {
                    angle,
                    detail: "ROMMEL's approach must be perpendicular to its forearm (joint 4 rolls about the forearm, \
                             joint 5 about the approach); this approach is not, at any arm configuration reaching the position"
                        .into(),
                }
            } else {
                let (by, boundary) = miss_pos
                    .into_iter()
                    .min_by(|a, b| a.0.total_cmp(&b.0))
                    .unwrap_or((f64::NAN, "reachable region".into()));
                Unreachable::OutsideReach { by, boundary }
            };
            return Err(Error::Unreachable { solver: NAME.into(), reason, closest: None });
        }
        Ok(out)
    }
}

impl crate::ik::ClosedForm for RommelIk {
    const NAME: &'static str = NAME;

    fn robot(&self) -> &Robot {
        &self.robot
    }

    /// Solutions for the target's position and z axis (approach), with q5 turning
    /// the tool x axis onto the target's — so the reported `orientation_error` is
    /// ~0 whenever the approach is reachable. An approach that is not is
    /// [`Unreachable::Orientation`] (see [`RommelIk::solve_position_approach`]).
    fn kernel(&self, target: &Pose, out: &mut crate::ik::CandidateSet) -> Result<()> {
        check_target(target)?;
        let local = self.robot.base().inverse().mul(target);
        let flange_rot = local.rot * self.robot.tool().rot.transpose();
        let a = flange_rot.column(2).into_owned();
        let x_target = flange_rot.column(0).into_owned();
        let bare = self.robot.with_base(Pose::IDENTITY)?.with_tool(Pose::IDENTITY)?;
        let raw = self.branches(&local.pos, &a, |q| {
            // q5: the angle about the approach from the x axis at q5 = 0 to the target's.
            let r0 =
                bare.fk(&[q[0], q[1], q[2], q[3], 0.0]).map(|f| f.world_from_tool.rot).unwrap_or_else(|_| flange_rot);
            let (x0, z0) = (r0.column(0).into_owned(), r0.column(2).into_owned());
            x0.cross(&x_target).dot(&z0).fast_atan2(x0.dot(&x_target))
        })?;
        out.clear();
        for r in raw {
            out.push(&r.q, r.label);
        }
        Ok(())
    }
}

impl crate::ik::family::Family for RommelIk {
    fn solve_typed(&self, target: &TypedTarget, _q0: Option<&[f64]>) -> Result<Vec<Solution>> {
        self.solve_position_approach(target.position, target.direction("approach"))
    }

    fn typed_orientation_error(&self, target: &TypedTarget, reached: &Pose) -> f64 {
        Self::approach_error(reached, target.direction("approach"))
    }
}
