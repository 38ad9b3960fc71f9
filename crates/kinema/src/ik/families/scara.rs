//! Closed-form inverse kinematics of the SCARA on a linear rail, Scara5
//! (seed 003 §III-B/C, eq. 1), with the paper's zone rule for the redundant rail.
//!
//! # Model and target
//!
//! Seed 003 eq. 1 (in the world frame, with the base rotation Rx(−90°) of Anexo
//! Tabla 1–2, and an identity tool):
//!
//! ```text
//! x = L1·c2 + L2·c23
//! y = L1·s2 + L2·s23 + q1          (q1: the rail, along world y)
//! z = H1 − H2 − q4
//! R = Rz(q2 + q3 + q5)
//! ```
//!
//! A target is `[Px, Py, Pz, α]`: the tool point \[m\] in the world frame (the frame
//! of [`Robot::fk`]) and the tool angle α \[rad\] about the vertical (α = q2 + q3 + q5
//! for the built-in robot; a tool rotated by ψ about its z axis adds ψ).
//!
//! # Branches
//!
//! For a given rail position there are two solutions: `elbow-right` (q3 ≥ 0: seen
//! from above, z up, the forearm turns counter-clockwise and the elbow lies to the
//! right of the line shoulder → tool) and `elbow-left` (q3 ≤ 0).
//!
//! # Zone rule (seed 003 Fig. 3–4)
//!
//! The rail adds a third unknown to the two equations of eq. 1. For a fixed rail
//! position the reachable points form an annulus around the shoulder; moving the
//! rail sweeps it into a rectangle-shaped zone, and the inner circle becomes
//! reachable by shifting the shoulder along the rail. [`ScaraIk::solve_zone`] picks
//! the rail position as follows (all lengths from the model):
//!
//! * r_lo = reach with the elbow folded to its limit |q3|max (or |L1 − L2| if the
//!   limit allows folding further), r_hi = L1 + L2 (stretched);
//! * the margin m = 0.05·(L1 + L2) keeps the elbow away from its critical angles:
//!   x_max = r_hi − m (stretched elbow), radii ≥ r_lo + m (folded elbow);
//! * a comfortable radius r_c = max(√2·(r_lo + m), r_lo + (x_max − r_lo)/4);
//! * for the flange point (X, Py) (X across the rail, Py along it), the shoulder is
//!   placed Y*(X) = max(r_c − |X|, 0) behind the point along the rail:
//!   **q1 = Py − Y*(X)** — abreast of the point when |X| ≥ r_c; closer to the rail
//!   the shoulder backs off so that the distance shoulder–point,
//!   √(X² + Y*²) ≥ r_c/√2 ≥ r_lo + m, stays away from the folded elbow. Y* is
//!   1-Lipschitz in X, so the rail moves at most as fast as the target;
//! * the elbow side is that of `previous` (sign of its q3), `elbow-right` without one;
//!   q5 is the equivalent of α − q2 − q3 nearest to `previous` (within its limits).
//!
//! The zone in which this rule is guaranteed to work is the rectangle returned by
//! [`ScaraIk::zone`]: X ∈ \[x_min, x_max\], Py ∈ \[q1min + r_c, q1max\] (q1min, q1max the
//! rail limits; x_min ≤ 0 the lowest X at which both elbows keep q2 within its
//! limits, x_max lowered likewise if q2's limits cut in — not for Scara5), and Pz
//! within the stroke of joint 4. Inside it the rule never clamps,
//! every joint is within its limits, and the solution is a smooth function of
//! the target (no jumps).
//!
//! # Outside the zone: the nearest rail that works
//!
//! Seed 003 skips the points outside the zone (Fig. 9), although most of them are
//! reachable from another rail position. Here the zone rule's rail is used
//! wherever every joint is within limits there (inside the zone always); where it
//! is not, the rail positions from which the point lies in the elbow's annulus
//! \[r_in, L1 + L2\] (r_in: the elbow folded to its limit) are computed in closed
//! form — |Py − q1| ∈ \[√(r_in² − X²), √((L1 + L2)² − X²)\], at most two
//! intervals, cut to the rail limits — and searched ([`RAIL_SAMPLES`] samples per
//! interval, bisection at each change) for the one nearest to the zone rule's
//! rail at which q2 and q5 are within limits too. Such a solution can lie on the
//! edge of the reachable set (elbow stretched or at its limit) and jumps where the
//! zone rule's rail stops working; only a point that no rail position reaches is
//! [`Unreachable::OutsideReach`] (with the distance), and one that the arm reaches
//! only outside the limits of q2 or q5 [`Unreachable::JointLimits`].

use std::f64::consts::PI;

use nalgebra::Vector3;

use crate::error::{Error, InputError, Result};
use crate::ik::target::{Component, Quantity, TypedKind, TypedTarget};
use crate::ik::{check_target, wrap_angle, Candidates, Solution, Unreachable};
use crate::math::FastMath;
use crate::math::{rot_z, Pose};
use crate::model::LinkGeometry;
use crate::robot::Robot;

/// The SCARA's typed target (seed 003): the tool point with the tool angle
/// α = q2 + q3 + q5 about the vertical \[rad\], the rail placed by the zone
/// rule; elbow side and q5 follow the request's `q0` when given
/// ([`ScaraIk::solve_zone`], one solution).
pub static TOOL_ANGLE: TypedKind = TypedKind {
    name: "tool-angle",
    components: &[Component { name: "alpha", quantity: Quantity::Angle }],
    summary: "SCARA: position and tool angle alpha",
};

/// Name of the solver in errors.
const NAME: &str = "scara";

/// Positions this close outside the reachable annulus \[m\] are treated as on it.
const REACH_TOL: f64 = 1e-12;

/// Samples of each interval of rail positions searched when the zone rule's rail
/// leaves a joint outside its limits (changes between samples are bisected).
pub const RAIL_SAMPLES: usize = 64;

/// Closed-form solver for the SCARA on a rail (seed 003).
///
/// # Examples
/// ```
/// use kinema::ik::scara::ScaraIk;
/// let robot = kinema::Robot::builtin("scara5")?;
/// let ik = ScaraIk::new(&robot)?;
/// let sols = ik.solve_with_rail([0.4, 0.6, 0.2, 0.3], 0.5)?;
/// assert_eq!(sols.len(), 2);
/// assert!(sols.iter().all(|s| s.position_error < 1e-10 && s.q[0] == 0.5));
/// let s = ik.solve_zone([0.4, 0.6, 0.2, 0.3], None)?;
/// assert!(s.within_limits() && s.position_error < 1e-10);
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct ScaraIk {
    robot: Robot,
    l1: f64,
    l2: f64,
    h1: f64,
    h2: f64,
    /// Tool translation in the flange frame \[m\].
    tool_t: Vector3<f64>,
    /// Tool rotation about the flange z axis \[rad\].
    tool_psi: f64,
    /// Zone: x_min, x_max, y_min, y_max \[m\] (flange point), and r_c.
    zone: [f64; 4],
    r_c: f64,
}

/// Which way the elbow bends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Elbow {
    Right,
    Left,
}

impl Elbow {
    fn sign(self) -> f64 {
        match self {
            Elbow::Right => 1.0,
            Elbow::Left => -1.0,
        }
    }
    fn label(self) -> &'static str {
        match self {
            Elbow::Right => "elbow-right",
            Elbow::Left => "elbow-left",
        }
    }
}

impl ScaraIk {
    /// A solver for `robot`, reading L1, L2 (a of joints 2, 3), H1 (d of joint 2) and
    /// H2 (offset of joint 4) from its DH table and checking with forward kinematics
    /// that the model is seed 003 eq. 1 with these values.
    ///
    /// Errors ([`Error::UnsupportedStructure`]) for a robot that is not PRRPR with DH rows,
    /// whose forward kinematics is not eq. 1 (a base rotation other than Rx(−90°)
    /// included; any base translation is fine), whose tool is tilted (its z axis must
    /// stay vertical), or whose rail is too short for the zone rule.
    pub fn new(robot: &Robot) -> Result<Self> {
        let bad =
            |reason: String| Error::UnsupportedStructure { solver: NAME.into(), robot: robot.name().into(), reason };
        if robot.joint_types() != "PRRPR" {
            return Err(bad(format!(
                "the SCARA solver needs joints PRRPR (rail, shoulder, elbow, z, wrist); `{}` is {}",
                robot.name(),
                robot.joint_types()
            )));
        }
        let dh = |i: usize| match robot.joints()[i].geometry {
            LinkGeometry::Dh { d, a, .. } => Ok((d, a)),
            _ => Err(bad(format!("joint {} is not described by a DH row", i + 1))),
        };
        let (h1, l1) = dh(1)?;
        let (_, l2) = dh(2)?;
        let h2 = robot.joints()[3].offset;
        if !(l1 > 0.0 && l2 > 0.0) {
            return Err(bad(format!("L1 = {l1} m and L2 = {l2} m must be positive")));
        }
        // Check eq. 1 on probe configurations (flange, identity tool).
        let bare = robot.with_tool(Pose::IDENTITY)?;
        let b = robot.base().pos;
        for k in 0..7 {
            let t = k as f64;
            let q = [0.1 * t, 0.7 * t - 2.0, 1.3 - 0.5 * t, 0.03 * t, 0.9 * t - 3.0];
            let fk = bare.fk(&q)?.world_from_tool;
            let phi = q[1] + q[2] + q[4];
            let p = Vector3::new(
                l1 * q[1].cos() + l2 * (q[1] + q[2]).cos(),
                l1 * q[1].sin() + l2 * (q[1] + q[2]).sin() + q[0],
                h1 - h2 - q[3],
            ) + b;
            if (fk.pos - p).norm() > 1e-9 || (fk.rot - rot_z(phi)).norm() > 1e-9 {
                return Err(bad(format!(
                    "forward kinematics of `{}` is not seed 003 eq. 1 with L1 = {l1}, L2 = {l2}, H1 = {h1}, H2 = {h2} m \
                     (the base must rotate by Rx(−90°) and the joints follow Anexo Tabla 1)",
                    robot.name()
                )));
            }
        }
        let tool = robot.tool();
        if (tool.rot[(2, 2)] - 1.0).abs() > 1e-9 {
            return Err(bad(
                "the tool's z axis must stay parallel to the flange z axis (a SCARA cannot tilt it)".into()
            ));
        }
        let tool_psi = tool.rot[(1, 0)].fast_atan2(tool.rot[(0, 0)]);
        let lim = |i: usize| robot.joints()[i].limits;
        let q3max = lim(2).min.abs().min(lim(2).max.abs()).min(PI);
        let r_lo = (l1 * l1 + l2 * l2 + 2.0 * l1 * l2 * q3max.cos()).max(0.0).sqrt().max((l1 - l2).abs());
        let r_hi = l1 + l2;
        let m = 0.05 * r_hi;
        let x_max = r_hi - m;
        let r_c = (std::f64::consts::SQRT_2 * (r_lo + m)).max(r_lo + (x_max - r_lo) / 4.0);
        if r_c / std::f64::consts::SQRT_2 < r_lo + m - 1e-12 || r_c >= x_max {
            return Err(bad(format!(
                "the arm's reachable annulus [{r_lo:.4}, {r_hi:.4}] m is too thin for the zone rule"
            )));
        }
        let (rail_min, rail_max) = (lim(0).min, lim(0).max);
        if !(rail_min.is_finite() && rail_max.is_finite()) || rail_max - rail_min <= r_c {
            return Err(bad(format!(
                "the rail limits [{rail_min}, {rail_max}] m must be finite and longer than the comfortable radius {r_c:.4} m"
            )));
        }
        let mut me = ScaraIk { robot: robot.clone(), l1, l2, h1, h2, tool_t: tool.pos, tool_psi, zone: [0.0; 4], r_c };
        // x_min: step from X = 0 towards −r_c while both elbows keep q2 within limits.
        let q2lim = lim(1);
        let within = |me: &ScaraIk, x: f64| {
            let y = Self::offset(me.r_c, x);
            [Elbow::Right, Elbow::Left].iter().all(|&e| {
                me.planar(x, y, e).is_some_and(|(q2, q3)| {
                    // 2 % margin on the q2 range so the sampled bound is safe in between.
                    let m = 0.02 * (q2lim.max - q2lim.min).min(2.0 * PI);
                    q2 >= q2lim.min + m && q2 <= q2lim.max - m && lim(2).contains(q3)
                })
            })
        };
        if !within(&me, 0.0) {
            return Err(bad("the joint limits of q2/q3 leave no zone for the rail rule at X = 0".into()));
        }
        let mut x_min = 0.0;
        let steps = 400;
        for k in 0..=steps {
            let x = -r_c * k as f64 / steps as f64;
            if !within(&me, x) {
                break;
            }
            x_min = x;
        }
        // Positive X: shrink x_max if q2's limits cut the zone short there (they do
        // not for Scara5; the rule depends on X only, so this 1-D scan covers the zone).
        let mut x_hi = x_max;
        for k in 0..=steps {
            let x = x_max * k as f64 / steps as f64;
            if !within(&me, x) {
                x_hi = (x - x_max / steps as f64).max(0.0);
                break;
            }
        }
        me.zone = [x_min, x_hi, rail_min + r_c, rail_max];
        Ok(me)
    }

    /// The robot this solver was built for.
    pub fn robot(&self) -> &Robot {
        &self.robot
    }

    /// The rectangle \[x_min, x_max, y_min, y_max\] \[m\] in which [`ScaraIk::solve_zone`]
    /// works, for the flange point (tool point minus the tool offset) relative to
    /// the base position (see the module documentation).
    pub fn zone(&self) -> [f64; 4] {
        self.zone
    }

    /// The comfortable radius r_c \[m\] of the zone rule.
    pub fn comfortable_radius(&self) -> f64 {
        self.r_c
    }

    /// The zone rule's offset Y*(X) = max(r_c − |X|, 0) of the point ahead of the shoulder.
    fn offset(r_c: f64, x: f64) -> f64 {
        (r_c - x.abs()).max(0.0)
    }

    /// (q2, q3) putting the flange at (x, y) relative to the shoulder, or None
    /// outside the annulus. q3 by the half-angle form of the law of cosines.
    fn planar(&self, x: f64, y: f64, elbow: Elbow) -> Option<(f64, f64)> {
        let (l1, l2) = (self.l1, self.l2);
        let r = x.fast_hypot(y);
        let e = crate::ik::two_link_elbow(r, l1, l2, REACH_TOL).ok()?;
        let sign = elbow.sign();
        // q2 = ∠(x, y) − ∠(L1 + L2·c3, L2·s3), as one atan2 of cross and dot
        // product; at r = 0 (L1 = L2, folded) q2 is free: 0.
        let (a, b) = (l1 + l2 * e.cos, l2 * sign * e.sin);
        let q2 = if r > 1e-15 { (y * a - x * b).fast_atan2(x * a + y * b) } else { 0.0 };
        Some((q2, sign * e.angle))
    }

    /// Flange point relative to the base position, and the flange angle φ = q2 + q3 + q5.
    fn flange(&self, target: &[f64; 4]) -> (Vector3<f64>, f64) {
        let phi = target[3] - self.tool_psi;
        let p = Vector3::new(target[0], target[1], target[2]) - rot_z(phi) * self.tool_t - self.robot.base().pos;
        (p, phi)
    }

    fn check_typed(target: &[f64; 4], extra: &[f64]) -> Result<()> {
        if let Some(&value) = target.iter().find(|v| !v.is_finite()) {
            return Err(Error::Input(InputError::NotFinite { what: "target".into(), value }));
        }
        if let Some(&value) = extra.iter().find(|v| !v.is_finite()) {
            return Err(Error::Input(InputError::NotFinite { what: "rail position".into(), value }));
        }
        Ok(())
    }

    fn unreachable(by: f64, boundary: String) -> Error {
        Error::Unreachable { solver: NAME.into(), reason: Unreachable::OutsideReach { by, boundary }, closest: None }
    }

    /// Joint values for a flange point, rail position and elbow; None outside the annulus.
    fn joint_values(&self, target: &[f64; 4], q1: f64, elbow: Elbow, q5_near: Option<f64>) -> Option<[f64; 5]> {
        self.joint_values_at(self.flange(target), q1, elbow, q5_near)
    }

    /// As [`ScaraIk::joint_values`], for a flange point and angle already computed.
    fn joint_values_at(
        &self,
        (f, phi): (Vector3<f64>, f64),
        q1: f64,
        elbow: Elbow,
        q5_near: Option<f64>,
    ) -> Option<[f64; 5]> {
        let (q2, q3) = self.planar(f.x, f.y - q1, elbow)?;
        let q4 = self.h1 - self.h2 - f.z;
        let mut q5 = wrap_angle(phi - q2 - q3);
        let lim5 = self.robot.joints()[4].limits;
        if let Some(prev) = q5_near {
            q5 = prev + wrap_angle(q5 - prev);
        }
        while q5 > lim5.max && q5 - 2.0 * PI >= lim5.min {
            q5 -= 2.0 * PI;
        }
        while q5 < lim5.min && q5 + 2.0 * PI <= lim5.max {
            q5 += 2.0 * PI;
        }
        Some([q1, q2, q3, q4, q5])
    }

    /// The pose a typed target (x, y, z \[m\], α \[rad\]) asks for: Rz(α) at P.
    pub fn alpha_pose(position: [f64; 3], alpha: f64) -> Pose {
        Pose::new(rot_z(alpha), Vector3::from(position))
    }

    /// The pose Rz(α) at P of a typed target.
    fn typed_pose(target: &[f64; 4]) -> Pose {
        Pose::new(rot_z(target[3]), Vector3::new(target[0], target[1], target[2]))
    }

    /// Both solutions (elbow right, elbow left) for `target` = \[Px, Py, Pz \[m\], α \[rad\]\]
    /// with the rail at `q1` \[m\] — seed 003 eq. 1 solved in closed form.
    ///
    /// The solutions are flagged for joint limits (the rail position and q4 too)
    /// and evaluated against the pose Rz(α) at P. Errors: non-finite input; the
    /// point outside the annulus \[|L1 − L2|, L1 + L2\] around the shoulder at this
    /// rail position ([`Unreachable::OutsideReach`], by how much).
    ///
    /// # Examples
    /// ```
    /// use kinema::ik::scara::ScaraIk;
    /// let ik = ScaraIk::new(&kinema::Robot::builtin("scara5")?)?;
    /// let sols = ik.solve_with_rail([0.5, 0.3, 0.25, 0.0], 0.3)?;
    /// assert_eq!(sols[0].branch, "elbow-right");
    /// assert!(sols[0].q[2] > 0.0 && sols[1].q[2] < 0.0);
    /// assert!(ik.solve_with_rail([0.9, 0.3, 0.25, 0.0], 0.3).is_err()); // 0.9 m > L1 + L2
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn solve_with_rail(&self, target: [f64; 4], q1: f64) -> Result<Vec<Solution>> {
        self.rail_candidates(target, q1)?.evaluate(&self.robot, &Self::typed_pose(&target))
    }

    /// The closed form of [`ScaraIk::solve_with_rail`] alone: joint vectors and
    /// branch labels, without the FK residual check and without allocating.
    /// Same errors.
    ///
    /// # Examples
    /// ```
    /// use kinema::ik::scara::ScaraIk;
    /// let ik = ScaraIk::new(&kinema::Robot::builtin("scara5")?)?;
    /// let c = ik.rail_candidates([0.5, 0.3, 0.25, 0.0], 0.3)?;
    /// assert_eq!(c.branches(), ["elbow-right", "elbow-left"]);
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn rail_candidates(&self, target: [f64; 4], q1: f64) -> Result<Candidates<5, 2>> {
        Self::check_typed(&target, &[q1])?;
        let mut out = Candidates::default();
        let flange = self.flange(&target);
        for elbow in [Elbow::Right, Elbow::Left] {
            if let Some(q) = self.joint_values_at(flange, q1, elbow, None) {
                out.push_unique(q, elbow.label(), 0.0, false);
            }
        }
        if out.is_empty() {
            let (f, _) = self.flange(&target);
            let r = f.x.fast_hypot(f.y - q1);
            let (outer, inner) = (self.l1 + self.l2, (self.l1 - self.l2).abs());
            return Err(if r > outer {
                Self::unreachable(
                    r - outer,
                    format!("outer circle of radius {outer:.6} m around the shoulder at q1 = {q1} m"),
                )
            } else {
                Self::unreachable(
                    inner - r,
                    format!("inner circle of radius {inner:.6} m around the shoulder at q1 = {q1} m"),
                )
            });
        }
        Ok(out)
    }

    /// One solution within limits for `target` = \[Px, Py, Pz \[m\], α \[rad\]\] with
    /// the rail chosen by the zone rule of the module documentation — or, where
    /// that rail leaves a joint outside its limits, the nearest rail position that
    /// does not — keeping the elbow side of `previous` (a 5-value configuration,
    /// e.g. the last point of a path) and the q5 nearest to it. If that elbow side
    /// has no rail position within limits, the other side is used.
    ///
    /// Errors: non-finite input, a `previous` of the wrong length; a point that no
    /// rail position reaches, or Pz outside the stroke of joint 4
    /// ([`Unreachable::OutsideReach`], with the distance); a point reached only
    /// outside the limits of q2 or q5 ([`Unreachable::JointLimits`]).
    ///
    /// # Examples
    /// ```
    /// use kinema::ik::scara::ScaraIk;
    /// let ik = ScaraIk::new(&kinema::Robot::builtin("scara5")?)?;
    /// let a = ik.solve_zone([0.1, 0.6, 0.2, 0.0], None)?;
    /// let b = ik.solve_zone([0.1, 0.601, 0.2, 0.0], Some(&a.q))?;
    /// assert!(b.q.iter().zip(&a.q).all(|(x, y)| (x - y).abs() < 0.01));
    /// assert!(ik.solve_zone([0.1, 2.0, 0.2, 0.0], None).is_err()); // beyond rail + reach
    /// let c = ik.solve_zone([0.1, 1.3, 0.2, 0.0], None)?; // outside the zone, reachable
    /// assert!(c.within_limits() && c.position_error < 1e-10 && c.q[0] <= 1.0);
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn solve_zone(&self, target: [f64; 4], previous: Option<&[f64]>) -> Result<Solution> {
        Self::check_typed(&target, previous.unwrap_or(&[]))?;
        if let Some(p) = previous {
            if p.len() != 5 {
                return Err(Error::Input(InputError::WrongLength {
                    what: "previous".into(),
                    got: p.len(),
                    expected: 5,
                    of: "one per joint of the SCARA".into(),
                }));
            }
        }
        let elbow = match previous {
            Some(p) if p[2] < 0.0 => Elbow::Left,
            _ => Elbow::Right,
        };
        let other = match elbow {
            Elbow::Right => Elbow::Left,
            Elbow::Left => Elbow::Right,
        };
        let q5_near = previous.map(|p| p[4]);
        let (q, elbow) = match self.zone_q(&target, elbow, q5_near) {
            Ok(q) => (q, elbow),
            Err(e) => (self.zone_q(&target, other, q5_near).map_err(|_| e)?, other),
        };
        Solution::evaluate(&self.robot, q.to_vec(), &Self::typed_pose(&target), elbow.label())
    }

    /// The joint values for a checked typed target and an elbow side: the rail
    /// of the zone rule if every joint is within limits there, else the rail
    /// position nearest to it that puts every joint within limits.
    fn zone_q(&self, target: &[f64; 4], elbow: Elbow, q5_near: Option<f64>) -> Result<[f64; 5]> {
        let (f, _) = self.flange(target);
        self.check_stroke(f.z)?;
        let preferred = f.y - Self::offset(self.r_c, f.x);
        let within =
            |q1: f64| self.joint_values(target, q1, elbow, q5_near).filter(|q| self.robot.limit_flags(q).is_empty());
        if let Some(q) = within(preferred) {
            return Ok(q);
        }
        let intervals = self.rail_intervals(f.x, f.y, elbow);
        if intervals.is_empty() {
            return Err(self.out_of_reach(f.x, f.y, elbow));
        }
        let best = intervals
            .iter()
            .filter_map(|&(lo, hi)| Self::nearest_where(lo, hi, preferred, |q1| within(q1).is_some()))
            .min_by(|a, b| (a - preferred).abs().total_cmp(&(b - preferred).abs()));
        best.and_then(within).ok_or_else(|| Error::Unreachable {
            solver: NAME.into(),
            reason: Unreachable::JointLimits {
                rejected: vec![format!(
                    "{}: a joint limit (q2 or q5) at every rail position from which the arm reaches the point",
                    elbow.label()
                )],
            },
            closest: None,
        })
    }

    /// Pz within the stroke of joint 4, else how far outside.
    fn check_stroke(&self, z: f64) -> Result<()> {
        let q4 = self.h1 - self.h2 - z;
        let l4 = self.robot.joints()[3].limits;
        if l4.contains(q4) {
            return Ok(());
        }
        let by = (l4.min - q4).max(q4 - l4.max);
        Err(Self::unreachable(
            by,
            format!(
                "vertical stroke z ∈ [{:.4}, {:.4}] m of joint 4",
                self.h1 - self.h2 - l4.max,
                self.h1 - self.h2 - l4.min
            ),
        ))
    }

    /// Smallest and largest shoulder–point distance \[m\] of an elbow side: the
    /// inner radius is that of the elbow folded to its limit (nudged inwards by
    /// 1e-9 relative, so that rounding keeps q3 within it).
    fn radii(&self, elbow: Elbow) -> (f64, f64) {
        let lim = self.robot.joints()[2].limits;
        let fold = match elbow {
            Elbow::Right => lim.max,
            Elbow::Left => -lim.min,
        }
        .clamp(0.0, PI);
        let (l1, l2) = (self.l1, self.l2);
        let inner = (l1 * l1 + l2 * l2 + 2.0 * l1 * l2 * fold.cos()).max(0.0).sqrt().max((l1 - l2).abs());
        (inner * (1.0 + 1e-9), l1 + l2)
    }

    /// The rail positions (within the rail limits) from which the flange point
    /// (x, y) lies in the annulus of `elbow`: |y − q1| ∈ \[a, b\] with
    /// a² = r_in² − x², b² = r_out² − x², so at most two intervals.
    fn rail_intervals(&self, x: f64, y: f64, elbow: Elbow) -> Vec<(f64, f64)> {
        let (inner, outer) = self.radii(elbow);
        let lim = self.robot.joints()[0].limits;
        let b2 = (outer - x.abs()) * (outer + x.abs());
        if b2 < 0.0 {
            return Vec::new();
        }
        let (a, b) = (((inner - x.abs()) * (inner + x.abs())).max(0.0).sqrt(), b2.sqrt());
        [(y - b, y - a), (y + a, y + b)]
            .into_iter()
            .map(|(lo, hi)| (lo.max(lim.min), hi.min(lim.max)))
            .filter(|(lo, hi)| lo <= hi)
            .collect()
    }

    /// The point of \[lo, hi\] nearest to `preferred` where `ok` holds, from
    /// [`RAIL_SAMPLES`] samples with each change of `ok` between neighbours
    /// refined by bisection; None if no sample is ok.
    fn nearest_where(lo: f64, hi: f64, preferred: f64, ok: impl Fn(f64) -> bool) -> Option<f64> {
        let n = RAIL_SAMPLES;
        let at = |k: usize| if k == n { hi } else { lo + (hi - lo) * k as f64 / n as f64 };
        let mut found: Vec<f64> = Vec::new();
        let clamped = preferred.clamp(lo, hi);
        if ok(clamped) {
            found.push(clamped);
        }
        let mut prev = ok(lo);
        if prev {
            found.push(lo);
        }
        for k in 1..=n {
            let now = ok(at(k));
            if now {
                found.push(at(k));
            }
            if now != prev {
                found.push(Self::bisect(at(k - 1), at(k), prev, &ok));
            }
            prev = now;
        }
        found.into_iter().min_by(|a, b| (a - preferred).abs().total_cmp(&(b - preferred).abs()))
    }

    /// The edge between `a` (where `ok` is `ok_a`) and `b` (where it is not), on its ok side.
    fn bisect(mut a: f64, mut b: f64, ok_a: bool, ok: impl Fn(f64) -> bool) -> f64 {
        for _ in 0..60 {
            let m = 0.5 * (a + b);
            if m == a || m == b {
                break;
            }
            if ok(m) == ok_a {
                a = m;
            } else {
                b = m;
            }
        }
        if ok_a {
            a
        } else {
            b
        }
    }

    /// Why no rail position puts the flange point (x, y) in the annulus of `elbow`.
    fn out_of_reach(&self, x: f64, y: f64, elbow: Elbow) -> Error {
        let (inner, outer) = self.radii(elbow);
        let lim = self.robot.joints()[0].limits;
        let nearest = x.fast_hypot((lim.min - y).max(y - lim.max).max(0.0));
        if nearest > outer {
            return Self::unreachable(
                nearest - outer,
                format!(
                    "outer circle of radius {outer:.6} m around the shoulder anywhere on the rail [{}, {}] m",
                    lim.min, lim.max
                ),
            );
        }
        let farthest = x.fast_hypot((y - lim.min).abs().max((y - lim.max).abs()));
        Self::unreachable(
            (inner - farthest).max(0.0),
            format!(
                "inner circle of radius {inner:.6} m around the shoulder (elbow folded to its limit) anywhere on the rail [{}, {}] m",
                lim.min, lim.max
            ),
        )
    }
}

impl crate::ik::ClosedForm for ScaraIk {
    const NAME: &'static str = NAME;

    fn robot(&self) -> &Robot {
        &self.robot
    }

    /// Up to two solutions, `elbow-right` then `elbow-left`, each with the rail
    /// where [`ScaraIk::solve_zone`] puts it: the zone rule's rail if every joint
    /// is within limits there, else the rail position nearest to it from which
    /// that elbow keeps every joint within limits. The rail is redundant for a
    /// pose (the solutions form one-parameter families along it); this picks a
    /// finite, deterministic set, every solution within limits. An elbow side
    /// with no such rail position is left out; with neither, the error of the
    /// right elbow. α is the rotation of the target about the vertical. A target
    /// whose z axis is not vertical is [`Unreachable::Orientation`] with the tilt
    /// angle.
    fn kernel(&self, target: &Pose, out: &mut crate::ik::CandidateSet) -> Result<()> {
        let pair = self.zone_pair(target)?;
        out.clear();
        for (q, elbow) in pair {
            out.push(&q, elbow.label());
        }
        Ok(())
    }
}

impl ScaraIk {
    /// The solutions of [`IkSolver::solve`](crate::ik::IkSolver::solve) for a pose: each elbow side at its
    /// rail ([`ScaraIk::zone_q`]), those that have one.
    fn zone_pair(&self, target: &Pose) -> Result<Vec<([f64; 5], Elbow)>> {
        check_target(target)?;
        let r = &target.rot;
        let tilt = r[(0, 2)].fast_hypot(r[(1, 2)]).fast_atan2(r[(2, 2)]);
        if tilt > 1e-9 {
            return Err(Error::Unreachable {
                solver: NAME.into(),
                reason: Unreachable::Orientation {
                    angle: tilt,
                    detail: "a SCARA keeps its tool z axis vertical; it controls only the rotation about it".into(),
                },
                closest: None,
            });
        }
        let alpha = r[(1, 0)].fast_atan2(r[(0, 0)]);
        let t = [target.pos.x, target.pos.y, target.pos.z, alpha];
        Self::check_typed(&t, &[])?;
        let right = self.zone_q(&t, Elbow::Right, None);
        let left = self.zone_q(&t, Elbow::Left, right.as_ref().ok().map(|q| q[4]));
        match (right, left) {
            (Err(e), Err(_)) => Err(e),
            (right, left) => Ok([(right, Elbow::Right), (left, Elbow::Left)]
                .into_iter()
                .filter_map(|(q, elbow)| q.ok().map(|q| (q, elbow)))
                .collect()),
        }
    }
}

impl crate::ik::family::Family for ScaraIk {
    /// The rail, shoulder and elbow place the tool in the plane; joint 4
    /// slides it along the vertical and joint 5 turns it (the "PRRPR" chain
    /// [`ScaraIk::new`] requires).
    fn tool_angle_joints(&self) -> Option<crate::ik::family::ToolAngleJoints> {
        Some(crate::ik::family::ToolAngleJoints { planar: &[0, 1, 2], vertical: 3, roll: 4, kind: &TOOL_ANGLE })
    }

    fn solve_typed(&self, target: &TypedTarget, q0: Option<&[f64]>) -> Result<Vec<Solution>> {
        let [x, y, z] = target.position;
        Ok(vec![self.solve_zone([x, y, z, target.angle("alpha")], q0)?])
    }

    fn typed_orientation_error(&self, target: &TypedTarget, reached: &Pose) -> f64 {
        let wanted = Self::alpha_pose(target.position, target.angle("alpha"));
        crate::math::pose_error(&wanted, reached).rotation_angle()
    }
}
