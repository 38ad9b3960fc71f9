//! Closed-form inverse kinematics of the Scorbot-ER V Plus (seed 000 §II-C,
//! eq. 13–23), with the seed's printing errors corrected.
//!
//! # Model and target
//!
//! The arm is the standard-DH chain of seed 000 Tabla I (`robots/scorbot-er-v-plus.toml`).
//! Writing θi for the angles of eq. 3–4 (θi = qi, the joint values; the DH angle of
//! joint 4 is q4 + π/2), the flange (frame 5) sits at
//!
//! ```text
//! u = a1 + a2·c2 + a3·c23 + d5·c234        (radial, in the vertical plane at azimuth θ1)
//! z = d1 + a2·s2 + a3·s23 + d5·s234
//! ```
//!
//! and the "tool frame" of eq. 8–9 has orientation R·R_h = Rz(θ1)·Ry(−θ234)·Rx(θ5).
//! The arm controls position, **pitch** β and **roll** γ (seed 000 eq. 13):
//!
//! * β = −θ234 = −(θ2 + θ3 + θ4) — positive pitch points the approach axis downwards,
//! * γ = θ5,
//! * yaw α = θ1 is *not* controllable: it follows from the position.
//!
//! This is the [`RpyConvention::Zyx`] triple of R·R_h: `rot_to_rpy(R·R_h, Zyx)` =
//! (roll, pitch, yaw) = (θ5, −θ234, θ1) whenever |θ234| ≤ π/2.
//!
//! # Solutions
//!
//! For a typed target ([`ScorbotIk::solve_xyz_pitch_roll`]) there are up to four:
//! the arm reaching to the front (θ1 = atan2(y, x), seed 000 eq. 15) or over its
//! back (θ1 + π, omitted by the seed), each elbow up or elbow down. Labels:
//! `front/elbow-up`, `front/elbow-down`, `back/elbow-up`, `back/elbow-down`.
//! "Elbow up" means the elbow lies above the line shoulder–wrist as seen from the
//! side the arm reaches to: θ3 ≤ 0 in front (the seed's "codo arriba (θ3 < 0)"),
//! θ3 ≥ 0 at the back (mirror image).
//!
//! # Conventions at singular targets
//!
//! * Position on the base axis (x = y = 0): θ1 is free; the solver uses θ1 = 0 for
//!   the front branch of a typed target, and the target's yaw for a full [`Pose`]
//!   (so the yaw error vanishes there).
//! * Wrist point on the shoulder (only possible if a2 = a3): θ2 is free; θ2 = 0.
//! * Stretched or folded elbow (wrist on the boundary of the reachable annulus):
//!   both elbow solutions coincide and both are returned.
//! * Approach vertical (pitch ±π/2) in a full [`Pose`]: roll and yaw act about the
//!   same axis, so θ5 absorbs the yaw and the orientation is reached exactly.
//!
//! Joint 5 (roll) is returned as given (γ, no 2π multiples added); θ1…θ4 are
//! wrapped to (−π, π].
//!
//! # Base and tool
//!
//! `robot.base()` may be any rigid transform. The tool transform may rotate
//! arbitrarily, but its translation must lie along the flange z axis (the approach;
//! it lengthens d5) — otherwise the position would depend on the uncontrollable yaw
//! and [`ScorbotIk::new`] refuses the model. Pitch and roll are always those of the
//! flange (R·R_h, frame 5), measured about the axes of the robot's base frame 0.
//!
//! # Corrections of seed 000 (each also commented at the code)
//!
//! * eq. 17: the denominator is 2·a2·a3, not 2·a2²·a3²;
//! * eq. 19: k1 = A·c2 − B·s2, k2 = B·c2 + A·s2 (printed k1 = c2·B + s2·(−A), k2 = c2·B + s2·A);
//!   eq. 20 is right;
//! * §II-C text: eq. 17's θ3 = +acos(…) ≥ 0 is elbow *down* (in front), not "codo arriba";
//! * eq. 23: θ2 = −atan(s2, c2) is wrong; θ2 is recomputed from eq. 20 with θ3' = −θ3;
//! * eq. 15 gives only θ1 = atan2(y, x); θ1 + π (reaching over the back) also solves.

use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::{Matrix3, Vector3};

use crate::error::{Error, InputError, Result};
use crate::ik::target::{Component, Quantity, TypedKind, TypedTarget};
use crate::ik::{check_target, wrap_angle, Candidates, Solution, Unreachable};
use crate::math::FastMath;
use crate::math::{rot_x, rot_y, Pose, RpyConvention};
use crate::model::{DhConvention, LinkGeometry};
use crate::robot::Robot;

/// The Scorbot's typed target (seed 000 eq. 13): the tool point with pitch
/// β = −(θ2 + θ3 + θ4) (positive points the approach downwards) and roll
/// γ = θ5, angles \[rad\]; the yaw follows from the position
/// ([`ScorbotIk::solve_xyz_pitch_roll`], up to four solutions).
pub static PITCH_ROLL: TypedKind = TypedKind {
    name: "pitch-roll",
    components: &[
        Component { name: "pitch", quantity: Quantity::Angle },
        Component { name: "roll", quantity: Quantity::Angle },
    ],
    summary: "Scorbot: position, pitch and roll",
};

/// Name of the solver in errors.
const NAME: &str = "scorbot";

/// Positions this close outside the reachable annulus \[m\] are treated as on it.
const REACH_TOL: f64 = 1e-12;

/// Horizontal distance from the base axis \[m\] below which θ1 is undetermined.
const AXIS_TOL: f64 = 1e-12;

/// R_h of seed 000 eq. 9: flange frame 5 → the "tool frame" aligned with the base at home.
pub const R_H: Matrix3<f64> = Matrix3::new(0.0, 0.0, 1.0, 0.0, -1.0, 0.0, 1.0, 0.0, 0.0);

/// Closed-form solver for Scorbot-ER V Plus-like arms (seed 000 §II-C).
///
/// # Examples
/// ```
/// use kinema::ik::scorbot::ScorbotIk;
/// let robot = kinema::Robot::builtin("scorbot-er-v-plus")?;
/// let ik = ScorbotIk::new(&robot)?;
/// let q = [0.3, 1.2, -1.0, -0.6, 0.4];
/// let p = robot.fk(&q)?.world_from_tool.pos;
/// // pitch β = −(θ2 + θ3 + θ4), roll γ = θ5 (seed 000 eq. 13)
/// let sols = ik.solve_xyz_pitch_roll([p.x, p.y, p.z], -(1.2 - 1.0 - 0.6), 0.4)?;
/// assert_eq!(sols.len(), 2); // front elbow up/down; the back branch is out of reach here
/// assert!(sols.iter().all(|s| s.position_error < 1e-10));
/// assert!(sols.iter().any(|s| s.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9)));
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct ScorbotIk {
    robot: Robot,
    d1: f64,
    a1: f64,
    a2: f64,
    a3: f64,
    /// d5 plus the tool's translation along the approach \[m\].
    d5: f64,
    /// q_i = θ_i + shift_i (θ the angles of eq. 3–4).
    shift: [f64; 5],
    /// Inverse of the robot's base transform.
    base_inv: Pose,
}

/// Why a branch missed: the annulus boundary and on which side (front/back).
#[derive(Debug, Clone, Copy)]
struct Miss {
    annulus: crate::ik::AnnulusMiss,
    side: &'static str,
}

/// The branch labels: side × elbow, then the same for the second
/// (roll, pitch, yaw) triple of a full pose (`/flip`).
const LABELS: [[&str; 4]; 2] = [
    ["front/elbow-up", "front/elbow-down", "back/elbow-up", "back/elbow-down"],
    ["front/elbow-up/flip", "front/elbow-down/flip", "back/elbow-up/flip", "back/elbow-down/flip"],
];

/// Candidates of the Scorbot kernels: up to 2 sides × 2 elbows × 2 (roll, pitch, yaw) triples.
pub type ScorbotCandidates = Candidates<5, 8>;

impl ScorbotIk {
    /// A solver for `robot`, reading d1, a1, a2, a3, d5 and the joint offsets from
    /// its DH table.
    ///
    /// Errors ([`Error::UnsupportedStructure`]) unless the robot has five revolute
    /// standard-DH joints with twists (π/2, 0, 0, π/2, 0), d2 = d3 = d4 = 0,
    /// a4 = a5 = 0, a2 > 0, a3 > 0, and a tool whose translation lies along the
    /// flange z axis.
    pub fn new(robot: &Robot) -> Result<Self> {
        let bad =
            |reason: String| Error::UnsupportedStructure { solver: NAME.into(), robot: robot.name().into(), reason };
        if robot.dof() != 5 || robot.joint_types() != "RRRRR" {
            return Err(bad(format!(
                "the Scorbot solver needs 5 revolute joints (RRRRR); `{}` has {} ({})",
                robot.name(),
                robot.dof(),
                robot.joint_types()
            )));
        }
        let mut rows = [(0.0, 0.0, 0.0); 5];
        for (i, j) in robot.joints().iter().enumerate() {
            match j.geometry {
                LinkGeometry::Dh { convention: DhConvention::Standard, d, a, alpha, .. } => rows[i] = (d, a, alpha),
                _ => return Err(bad(format!("joint {} is not described by a standard-DH row", i + 1))),
            }
        }
        let twists = [FRAC_PI_2, 0.0, 0.0, FRAC_PI_2, 0.0];
        for (i, (row, want)) in rows.iter().zip(twists).enumerate() {
            if (wrap_angle(row.2 - want)).abs() > 1e-9 {
                return Err(bad(format!(
                    "joint {} has twist α = {:.6} rad; the Scorbot structure needs {want:.6} rad",
                    i + 1,
                    row.2
                )));
            }
        }
        for (i, what, v) in
            [(2, "d", rows[1].0), (3, "d", rows[2].0), (4, "d", rows[3].0), (4, "a", rows[3].1), (5, "a", rows[4].1)]
        {
            if v.abs() > 1e-12 {
                return Err(bad(format!("{what}{i} = {v} m; the Scorbot structure needs {what}{i} = 0")));
            }
        }
        let (a2, a3) = (rows[1].1, rows[2].1);
        if !(a2 > 0.0 && a3 > 0.0) {
            return Err(bad(format!("the arm links must have positive lengths (a2 = {a2} m, a3 = {a3} m)")));
        }
        let tool = robot.tool();
        if tool.pos.x.abs() > 1e-12 || tool.pos.y.abs() > 1e-12 {
            return Err(bad(format!(
                "the tool translation ({}, {}, {}) m leaves the flange z axis; a 5-DOF Scorbot cannot place such a tool point independently of its uncontrollable yaw",
                tool.pos.x, tool.pos.y, tool.pos.z
            )));
        }
        // Seed 000 eq. 3–4 use θ4 = q4 while the DH angle is q4 + π/2 (Tabla I),
        // so the reference offsets are (0, 0, 0, π/2, 0).
        let reference = [0.0, 0.0, 0.0, FRAC_PI_2, 0.0];
        let mut shift = [0.0; 5];
        for (i, j) in robot.joints().iter().enumerate() {
            shift[i] = reference[i] - j.offset;
        }
        Ok(ScorbotIk {
            robot: robot.clone(),
            d1: rows[0].0,
            a1: rows[0].1,
            a2,
            a3,
            d5: rows[4].0 + tool.pos.z,
            shift,
            base_inv: robot.base().inverse(),
        })
    }

    /// The robot this solver was built for.
    pub fn robot(&self) -> &Robot {
        &self.robot
    }

    /// Every solution for a tool point `p` \[m\] (world frame, i.e. the frame of
    /// [`Robot::fk`]) with pitch β = `pitch` and roll γ = `roll` \[rad\] (seed 000
    /// eq. 13, measured about the axes of the robot's base frame 0: β = −θ234, γ = θ5).
    ///
    /// Returns up to four solutions (front/back × elbow up/down), each flagged for
    /// joint limits and evaluated against the pose they reach, i.e.
    /// Rz(θ1)·Ry(β)·Rx(γ)·R_hᵀ with the yaw θ1 that the position imposes — so their
    /// residuals are ~0. Errors: non-finite input ([`InputError::NotFinite`]); the
    /// wrist point outside the annulus \[|a2 − a3|, a2 + a3\] around the shoulder for
    /// both the front and the back branch ([`Unreachable::OutsideReach`], with the
    /// smaller miss).
    ///
    /// # Examples
    /// ```
    /// use kinema::ik::scorbot::ScorbotIk;
    /// let robot = kinema::Robot::builtin("scorbot-er-v-plus")?;
    /// let ik = ScorbotIk::new(&robot)?;
    /// let sols = ik.solve_xyz_pitch_roll([0.4, 0.1, 0.3], 0.5, 0.0)?;
    /// assert!(sols.iter().any(|s| s.branch == "front/elbow-up" && s.within_limits()));
    /// assert!(ik.solve_xyz_pitch_roll([2.0, 0.0, 0.3], 0.0, 0.0).is_err());
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn solve_xyz_pitch_roll(&self, p: [f64; 3], pitch: f64, roll: f64) -> Result<Vec<Solution>> {
        let raw = self.xyz_pitch_roll_candidates(p, pitch, roll)?;
        raw.iter()
            .map(|(q, label)| {
                // The target of this solution is position p with the orientation it
                // reaches (the yaw the position imposes): one FK gives both, and the
                // orientation error is zero by construction.
                let fk = self.robot.fk(q)?;
                Ok(Solution {
                    q: q.to_vec(),
                    branch: label.into(),
                    out_of_limits: fk.out_of_limits,
                    position_error: (fk.world_from_tool.pos - Vector3::from(p)).norm(),
                    orientation_error: 0.0,
                    numeric: None,
                })
            })
            .collect()
    }

    /// The closed form of [`ScorbotIk::solve_xyz_pitch_roll`] alone: joint
    /// vectors and branch labels (up to four), without the FK residual check
    /// and without allocating. Same errors.
    ///
    /// # Examples
    /// ```
    /// use kinema::ik::scorbot::ScorbotIk;
    /// let robot = kinema::Robot::builtin("scorbot-er-v-plus")?;
    /// let ik = ScorbotIk::new(&robot)?;
    /// let c = ik.xyz_pitch_roll_candidates([0.4, 0.1, 0.3], 0.5, 0.0)?;
    /// assert_eq!(c.branches(), ["front/elbow-up", "front/elbow-down"]);
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn xyz_pitch_roll_candidates(&self, p: [f64; 3], pitch: f64, roll: f64) -> Result<ScorbotCandidates> {
        let named = p.iter().map(|&v| ("position", v)).chain([("pitch", pitch), ("roll", roll)]);
        if let Some((what, value)) = named.into_iter().find(|(_, v)| !v.is_finite()) {
            return Err(Error::Input(InputError::NotFinite { what: what.into(), value }));
        }
        let pb = self.base_inv.transform_point(&Vector3::from(p));
        let mut out = ScorbotCandidates::default();
        let mut miss = [None; 4];
        self.branches_with(&pb, pitch, |_| roll, 0.0, 0, &mut out, &mut miss[..2]);
        if out.is_empty() {
            return Err(self.unreachable(&miss));
        }
        Ok(out)
    }

    /// The yaw error \[rad\] any solution of `target` must have: the angle between the
    /// target orientation and the nearest orientation the arm can take at that
    /// position (its yaw is fixed by θ1). It equals the smallest
    /// `orientation_error` among the solutions of [`IkSolver::solve`](crate::ik::IkSolver::solve). 0 when the
    /// position is on the base axis or the approach is vertical; `f64::INFINITY`
    /// for a non-finite or invalid target.
    ///
    /// # Examples
    /// ```
    /// use kinema::ik::scorbot::ScorbotIk;
    /// use kinema::{Pose, RpyConvention};
    /// let robot = kinema::Robot::builtin("scorbot-er-v-plus")?;
    /// let ik = ScorbotIk::new(&robot)?;
    /// let reached = robot.fk(&[0.2, 1.0, -0.5, -0.3, 0.1])?.world_from_tool;
    /// assert!(ik.yaw_error(&reached) < 1e-12);
    /// let turned = Pose::new(kinema::math::rot_z(0.25) * reached.rot, reached.pos);
    /// assert!((ik.yaw_error(&turned) - 0.25).abs() < 1e-9);
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn yaw_error(&self, target: &Pose) -> f64 {
        if check_target(target).is_err() {
            return f64::INFINITY;
        }
        let (p, m) = self.local_target(target);
        let (_, _, yaw, vertical) = decompose(&m);
        if vertical || p.x.fast_hypot(p.y) <= AXIS_TOL {
            return 0.0;
        }
        let e = wrap_angle(yaw - p.y.fast_atan2(p.x)).abs();
        e.min(PI - e)
    }

    /// How far \[rad\] the orientation of `reached` (a tool pose in the world
    /// frame) is from every orientation with pitch β = `pitch` and roll γ =
    /// `roll` (seed 000 eq. 13), whatever its yaw: with M = R·R_h of the
    /// flange in frame 0, M = Rz(α)·Ry(β)·Rx(γ) for some α exactly when
    /// N = M·Rx(γ)ᵀ·Ry(β)ᵀ turns about z alone, so the error is the angle
    /// between N·z and z.
    pub fn pitch_roll_error(&self, reached: &Pose, pitch: f64, roll: f64) -> f64 {
        let (_, m) = self.local_target(reached);
        let n = m * rot_x(roll).transpose() * rot_y(pitch).transpose();
        let z = n.column(2);
        z.xy().norm().atan2(z.z)
    }

    /// Target in the robot's base frame 0: tool-point position and R·R_h of the flange.
    fn local_target(&self, target: &Pose) -> (Vector3<f64>, Matrix3<f64>) {
        let local = self.base_inv.mul(target);
        let flange_rot = local.rot * self.robot.tool().rot.transpose();
        (local.pos, flange_rot * R_H)
    }

    fn unreachable(&self, miss: &[Option<Miss>]) -> Error {
        let (by, boundary) = miss
            .iter()
            .flatten()
            .min_by(|a, b| a.annulus.by.total_cmp(&b.annulus.by))
            .map(|m| {
                let which = if m.annulus.outer { "outer" } else { "inner" };
                (
                    m.annulus.by,
                    format!(
                        "{which} circle of radius {:.6} m around the shoulder ({} branch, wrist point)",
                        m.annulus.radius, m.side
                    ),
                )
            })
            .unwrap_or((f64::NAN, "reachable annulus (no branch evaluated)".into()));
        // A NaN figure is not quoted (see `Unreachable`'s Display).
        Error::Unreachable { solver: NAME.into(), reason: Unreachable::OutsideReach { by, boundary }, closest: None }
    }

    /// Front and back branches, both elbows, for a tool point `p` in frame 0,
    /// θ234 = −β, θ5 = `roll_for(θ1)` (the roll is constant unless the approach
    /// is vertical and the roll absorbs the yaw). `axis_yaw` is θ1 of the
    /// front branch when `p` is on the base axis; `set` picks the labels (0 for
    /// the first (roll, pitch, yaw) triple, 1 for `/flip`). Candidates go to
    /// `out`, the front and back misses to `miss[0]` and `miss[1]`.
    #[allow(clippy::too_many_arguments)]
    fn branches_with(
        &self,
        p: &Vector3<f64>,
        beta: f64,
        roll_for: impl Fn(f64) -> f64,
        axis_yaw: f64,
        set: usize,
        out: &mut ScorbotCandidates,
        miss: &mut [Option<Miss>],
    ) {
        let (a1, a2, a3, d1, d5) = (self.a1, self.a2, self.a3, self.d1, self.d5);
        let rxy = p.x.fast_hypot(p.y);
        let on_axis = rxy <= AXIS_TOL;
        let (sp, cp) = if on_axis { axis_yaw.fast_sin_cos() } else { (p.y / rxy, p.x / rxy) };
        let th234 = -beta; // seed 000 eq. 13
        let (s234, c234) = th234.fast_sin_cos();
        // The seven angles of the four solutions are independent once the
        // sines and cosines are known; they are gathered into one
        // `atan2_lanes` call (lane 0: θ1 of the front; 1–2: the elbow
        // half-angles of front and back; 3–6: θ2 of each branch; 7 unused).
        let (mut ys, mut xs) = ([0.0; 8], [1.0; 8]);
        (ys[0], xs[0]) = (p.y, p.x);
        let mut elbows = [None; 2];
        for (k, side) in ["front", "back"].into_iter().enumerate() {
            // Seed 000 eq. 15 gives only θ1 = atan2(y, x); θ1 + π reaches over the back.
            let back = k == 1;
            let (s1, c1) = if back { (-sp, -cp) } else { (sp, cp) };
            // Seed 000 eq. 18: the wrist point relative to the shoulder, in the arm plane.
            let k1 = p.x * c1 + p.y * s1 - a1 - d5 * c234;
            let k2 = p.z - d1 - d5 * s234;
            let rho = k1.fast_hypot(k2);
            // |θ3| from the law of cosines. Seed 000 eq. 17 prints the denominator as
            // 2·a2²·a3²; it is 2·a2·a3: cos θ3 = (k1² + k2² − a2² − a3²)/(2·a2·a3).
            // Evaluated in the equivalent half-angle form (`two_link_elbow`),
            // accurate near the stretched and folded arm where acos loses half the digits.
            let elbow = match crate::ik::two_link_elbow_terms(rho, a2, a3, REACH_TOL) {
                Ok(e) => e,
                Err(annulus) => {
                    miss[k] = Some(Miss { annulus, side });
                    continue;
                }
            };
            elbows[k] = Some(elbow);
            (ys[1 + k], xs[1 + k]) = (elbow.half_y, elbow.half_x);
            // Seed 000 claims eq. 17 (θ3 = +acos ≥ 0) is "codo arriba" while defining
            // codo arriba as θ3 < 0: with θ2 from eq. 20, θ3 > 0 puts the elbow *below*
            // the shoulder–wrist line when the wrist is in front, above it at the back.
            let up_sign = if back { 1.0 } else { -1.0 };
            for (e, sign) in [up_sign, -up_sign].into_iter().enumerate() {
                // Seed 000 eq. 19 is misprinted (k1 = c2·B − s2·A, k2 = c2·B + s2·A);
                // correctly k1 = A·c2 − B·s2, k2 = B·c2 + A·s2 with A = a2 + a3·c3,
                // B = a3·s3, which eq. 20 inverts (eq. 20 itself is right).
                // Seed 000 eq. 23 (θ2 = −atan(s2, c2) for the other elbow) is wrong:
                // θ2 is recomputed from eq. 20 with the new θ3 (B changes sign).
                let (a, b) = (a2 + a3 * elbow.cos, a3 * sign * elbow.sin);
                if rho > 1e-15 {
                    (ys[3 + 2 * k + e], xs[3 + 2 * k + e]) = (a * k2 - b * k1, a * k1 + b * k2);
                }
            }
        }
        let angles = crate::math::atan2_x8(ys, xs);
        let phi = if on_axis { axis_yaw } else { angles[0] };
        for (k, elbow) in elbows.iter().enumerate() {
            if elbow.is_none() {
                continue;
            }
            let back = k == 1;
            let th1 = if back { wrap_angle(phi + PI) } else { phi };
            let up_sign = if back { 1.0 } else { -1.0 };
            let th3_abs = 2.0 * angles[1 + k];
            for (e, sign) in [up_sign, -up_sign].into_iter().enumerate() {
                let th3 = sign * th3_abs;
                let th2 = angles[3 + 2 * k + e];
                let th4 = wrap_angle(th234 - th2 - th3); // seed 000 eq. 22
                let th5 = roll_for(th1);
                let theta = [th1, th2, th3, th4, th5];
                let mut q = [0.0; 5];
                for i in 0..5 {
                    q[i] = theta[i] + self.shift[i];
                    if i < 4 && self.shift[i] != 0.0 {
                        q[i] = wrap_angle(q[i]);
                    }
                }
                out.push_unique(q, LABELS[set][2 * k + e], 0.0, false);
            }
        }
    }
}

/// (roll, pitch, yaw, vertical) of R·R_h in seed 000 eq. 6 (Zyx): pitch in
/// \[−π/2, π/2\]; `vertical` when cos(pitch) ≈ 0 (roll and yaw share one axis;
/// roll = 0 is returned then).
fn decompose(m: &Matrix3<f64>) -> (f64, f64, f64, bool) {
    let cp = m[(2, 1)].fast_hypot(m[(2, 2)]);
    let [roll, pitch, yaw] = crate::math::rot_to_rpy(m, RpyConvention::Zyx);
    (roll, pitch, yaw, cp <= 1e-12)
}

impl crate::ik::ClosedForm for ScorbotIk {
    const NAME: &'static str = NAME;

    fn robot(&self) -> &Robot {
        &self.robot
    }

    /// Solutions for a full pose: the position, pitch and roll are taken from the
    /// target (pitch and roll of R·R_h of the flange in frame 0, seed 000 eq. 11–13),
    /// yaw is whatever θ1 the position imposes.
    ///
    /// A rotation has two (roll, pitch, yaw) triples — (γ, β, α) and
    /// (γ + π, π − β, α + π) — and each gives its own arm configurations, so up to
    /// eight solutions are returned: the four of [`ScorbotIk::solve_xyz_pitch_roll`]
    /// for (β, γ) and four more labelled `…/flip` for (π − β, γ + π). Their
    /// `orientation_error` is the uncontrollable yaw error (see
    /// [`ScorbotIk::yaw_error`]); [`IkSolver::solve`](crate::ik::IkSolver::solve) sorts the list by it,
    /// smallest first.
    fn kernel(&self, target: &Pose, out: &mut crate::ik::CandidateSet) -> Result<()> {
        self.pose_candidates(target)?.write_into(out);
        Ok(())
    }

    fn order(&self, solutions: &mut [Solution]) {
        solutions.sort_by(|a, b| a.orientation_error.total_cmp(&b.orientation_error));
    }
}

impl ScorbotIk {
    /// The closed form of [`IkSolver::solve`](crate::ik::IkSolver::solve) alone: joint vectors and branch
    /// labels (up to eight), unsorted, without the FK residual check and without
    /// allocating. Same errors.
    pub fn pose_candidates(&self, target: &Pose) -> Result<ScorbotCandidates> {
        check_target(target)?;
        let (p, m) = self.local_target(target);
        let (roll, pitch, yaw, vertical) = decompose(&m);
        let mut out = ScorbotCandidates::default();
        let mut miss = [None; 4];
        for (set, (beta, gamma, yaw_rep)) in
            [(pitch, roll, yaw), (PI - pitch, wrap_angle(roll + PI), wrap_angle(yaw + PI))].into_iter().enumerate()
        {
            let miss = &mut miss[2 * set..2 * set + 2];
            if vertical {
                // Rz(a)·Ry(±π/2)·Rx(g) = Rz(a ∓ g)·Ry(±π/2): the roll takes up the yaw.
                let s = beta.sin().signum();
                self.branches_with(&p, beta, |th1| wrap_angle(s * (th1 - yaw_rep)), yaw_rep, set, &mut out, miss);
            } else {
                self.branches_with(&p, beta, |_| gamma, yaw_rep, set, &mut out, miss);
            }
        }
        if out.is_empty() {
            return Err(self.unreachable(&miss));
        }
        Ok(out)
    }
}

impl crate::ik::family::Family for ScorbotIk {
    fn solve_typed(&self, target: &TypedTarget, _q0: Option<&[f64]>) -> Result<Vec<Solution>> {
        self.solve_xyz_pitch_roll(target.position, target.angle("pitch"), target.angle("roll"))
    }

    fn typed_orientation_error(&self, target: &TypedTarget, reached: &Pose) -> f64 {
        self.pitch_roll_error(reached, target.angle("pitch"), target.angle("roll"))
    }
}
