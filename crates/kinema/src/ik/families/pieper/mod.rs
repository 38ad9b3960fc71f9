//! Analytic inverse kinematics for 6R arms with a spherical wrist (Pieper's
//! case): the last three joint axes meet in one point, the wrist centre, so
//! the position of the wrist centre depends on the first three joints only.
//!
//! The solve runs in three steps (closed forms except for the θ3 root of the
//! general shoulder arrangement):
//!
//! 1. **Wrist centre.** The base and tool transforms are stripped from the
//!    target, giving the flange pose T06; the wrist centre is the point of
//!    link 6 that lies on all three wrist axes (for a standard DH table it is
//!    o5 = T06 · Rx(−α6)·(−a6, 0, −d6), i.e. d6 back along the approach axis
//!    for the usual a6 = α6 = 0).
//! 2. **Arm (q1, q2, q3).** The wrist centre p as a function of θ1…θ3 is
//!    p = A1·A2·A3·(0, 0, d4). Four arrangements of the first axes are
//!    handled (see [`ArmKind`]):
//!    * *shoulder-plane* (α1 = ±90°, α2 ∈ {0, 180°}; PUMA 560, KUKA KR,
//!      ABB, Fanuc, …; any a1, d2, d3, a2, a3): the component of p along
//!      axis 2 is the constant lateral offset, which gives θ1 (two shoulder
//!      branches); in the plane of the arm, the distance from axis 2 to p
//!      gives θ3 (two elbow branches) and then θ2;
//!    * *intersecting shoulder* (a1 = 0, α1 ≠ 0 mod 180°, any α2): |p − o1|
//!      depends on θ3 only (two roots), the height of p along axis 1 then
//!      gives θ2 (two roots), and θ1 follows;
//!    * *parallel shoulder* (α1 ∈ {0, 180°}, a1 ≠ 0, α2 ≠ 0 mod 180°): the
//!      height along axis 1 depends on θ3 only (two roots), |p − o1| then
//!      gives θ2 (two roots), and θ1 follows;
//!    * *general* (a1 ≠ 0 and α1 ≠ 0 mod 180°, not of the first kind, e.g.
//!      α1 = α2 = 90° with a1 ≠ 0): eliminating θ2 from the two equations
//!      leaves one equation in θ3, of degree 2 in cos θ3 and sin θ3 (a
//!      quartic in tan(θ3/2), up to 4 roots), whose coefficients five samples
//!      give exactly; its real roots are found to rounding level, and θ2 and
//!      θ1 follow in closed form.
//!
//!    The first two are solved by the geometric arm kernel the geometric
//!    solvers share (`geo/spherical_arm.rs`: axes 2 ∥ 3, or axes 1 and 2
//!    meeting), built once from the axes of the table at θ = 0; this
//!    solver labels its branches from the returned angles (`geo_arm.rs`) and
//!    words its misses. The last two are this solver's own formulas.
//!
//!    Degenerate shoulders (axes 1 and 2 coincident, or axes 1, 2, 3 all
//!    parallel) are rejected by [`PieperIk::new`].
//! 3. **Wrist (q4, q5, q6).** With R36 = R03ᵀ·R06·Rx(α6)ᵀ = Rz(θ4)·Rx(α4)·
//!    Rz(θ5)·Rx(α5)·Rz(θ6) and an orthogonal wrist (α4, α5 = ±90°), the
//!    wrist's axes in frame 3 (ẑ, Rx(α4)·ẑ, Rx(α4)·Rx(α5)·ẑ, read once from
//!    the table) go to the spherical-wrist solve the geometric solvers share
//!    (`geo/wrist.rs`): θ5 = ±atan2 of the third column of R36 off and
//!    along ẑ (two branches, *flip* with sin θ5 > 0 and *noflip* with
//!    sin θ5 < 0 — the names Corke's toolbox gives the PUMA 560's wrist, `f`
//!    and `n` of `ikine_a`, checked against roboticstoolbox-python 1.5.0),
//!    then θ4 and θ6 as the rotations about their axes that remain. Every
//!    angle comes from `atan2`, never `acos` of a rotation entry, so
//!    residuals stay at rounding level.
//!
//! Robots described by general (URDF-style) transforms are rejected; the
//! solver reads the DH table. Up to 4 arm × 2 wrist = 8 solutions. Joint values are θ − offset wrapped to
//! (−π, π], moved by ±2π when that brings them within the joint limits.
//!
//! ## Singular configurations (conventions)
//!
//! * **Wrist singularity** (axes 4 and 6 aligned, sin θ5 = 0): only θ4 + θ6
//!   (or θ4 − θ6) is determined. The *noflip* branch takes q4 = 0 and the
//!   *flip* branch q4 = π (wrapped into the limits when possible); q6 takes
//!   the rest. Detected when the wrist axis-6 direction is within 1e-12 of
//!   axis 4.
//! * **Shoulder singularity** (wrist centre on axis 1, possible only without
//!   lateral offset): θ1 is free; the solver takes q1 = 0 (and q1 = π for the
//!   other shoulder branch of the *shoulder-plane* arrangement).
//! * **Wrist centre on axis 2** (the elbow folded back onto the shoulder): θ2
//!   is free; the solver takes q2 = 0.
//! * **Stretched or folded elbow, wrist centre on the lateral-offset
//!   cylinder**: the two branches coincide; both are returned (with their
//!   labels), so the list may contain equal configurations. Targets beyond
//!   the boundary by less than 1e-12 (relative) are treated as on it.
//!
//! Branch labels: `shoulder-{right,left}/elbow-{up,down}/wrist-{noflip,flip}`
//! for the *shoulder-plane* arrangement (right = the wrist centre lies ahead
//! of the shoulder along link 1's x axis — the PUMA's right-arm
//! configuration; elbow up = the elbow is above the shoulder–wrist-centre
//! line, measured along the base z axis),
//! `shoulder-{1,2}/elbow-{1,2}/wrist-{noflip,flip}` (root indices) for the
//! intersecting and parallel shoulders, and `arm-{1…4}/wrist-{noflip,flip}`
//! (roots in θ3 order) for the general case.

use nalgebra::{Matrix3, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::error::{Error, Result};
use crate::ik::wrap_into_limits;
use crate::ik::{check_target, IkSolver, Solution, Unreachable};
use crate::math::FastMath;
use crate::math::Pose;
use crate::model::{DhConvention, LinkGeometry};
use crate::robot::Robot;

mod general;
mod geo_arm;
#[cfg(test)]
mod reference;
mod rows;
#[cfg(test)]
mod tests;
use general::GeneralShoulder;
use rows::{arm_g, intersecting_coeffs, mul, rzrx, theta1, tmul, M3};

use super::geo::spherical_arm::SphericalArm;
use super::geo::wrist::{SphericalWrist, WristRoots};

/// Tolerance on DH lengths \[m\] and on sines/cosines of twists when deciding
/// the geometry.
const GEOM_TOL: f64 = 1e-9;

/// Relative tolerance for targets just outside a boundary (treated as on it).
const BOUNDARY_TOL: f64 = 1e-12;

/// Below this distance \[m\] the wrist centre is treated as on axis 1 (or 2).
const AXIS_TOL: f64 = 1e-12;

/// Labels of the parallel and intersecting shoulders: root indices, by
/// shoulder then elbow.
const ROOT_LABELS: [[&str; 2]; 2] =
    [["shoulder-1/elbow-1", "shoulder-1/elbow-2"], ["shoulder-2/elbow-1", "shoulder-2/elbow-2"]];

/// Which closed form solves the first three joints.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ArmKind {
    /// α1 = ±90°, α2 ∈ {0, 180°}: axes 2 and 3 parallel and perpendicular to
    /// axis 1 (PUMA 560 and most industrial arms). Any a1, d2, d3, a2, a3.
    ShoulderPlane,
    /// a1 = 0 and α1 ≠ 0 mod 180°: axes 1 and 2 intersect. Any α2.
    IntersectingShoulder,
    /// α1 ∈ {0, 180°} and a1 ≠ 0: axes 1 and 2 parallel; α2 ≠ 0 mod 180°.
    ParallelShoulder,
    /// Any other arrangement with a1 ≠ 0 and α1 ≠ 0 mod 180° (Pieper's
    /// general case): θ3 from a trigonometric equation of degree 2, a
    /// quartic in tan(θ3/2) whose real roots are isolated between the
    /// roots of its derivatives and refined to rounding level.
    General,
}

/// Standard-DH parameters of one link (after converting a modified table).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Link {
    d: f64,
    a: f64,
    ca: f64,
    sa: f64,
    offset: f64,
}

/// Rx(αi) from the link's exact cosine and sine.
fn rx(l: Link) -> Matrix3<f64> {
    Matrix3::new(1.0, 0.0, 0.0, 0.0, l.ca, -l.sa, 0.0, l.sa, l.ca)
}

/// The wrist axes in DH frame 3 with θ4 = θ5 = 0 — ẑ, Rx(α4)·ẑ and
/// Rx(α4)·Rx(α5)·ẑ, so that Rz(θ4)·Rx(α4)·Rz(θ5)·Rx(α5)·Rz(θ6) is
/// rot(h4, θ4)·rot(h5, θ5)·rot(h6, θ6)·Rx(α4)·Rx(α5) — followed by the
/// shared solve's vector u ⊥ h6 turned back by (Rx(α4)·Rx(α5))ᵀ.
fn wrist_axes(l4: Link, l5: Link) -> [Vector3<f64>; 4] {
    let post = rx(l4) * rx(l5);
    let (h5, h6) = (rx(l4) * Vector3::z(), post * Vector3::z());
    let u = SphericalWrist::new([Vector3::z(), h5, h6], 0.0).u();
    [Vector3::z(), h5, h6, post.transpose() * u]
}

/// Snaps the cosine and sine of a twist to exact 0/±1 when within tolerance.
fn twist(alpha: f64) -> (f64, f64) {
    let (s, c) = alpha.fast_sin_cos();
    let snap = |v: f64| {
        if v.abs() < 1e-12 {
            0.0
        } else if (v.abs() - 1.0).abs() < 1e-12 {
            v.signum()
        } else {
            v
        }
    };
    (snap(c), snap(s))
}

/// The analytic solver for 6R arms with a spherical wrist.
///
/// # Examples
/// ```
/// use kinema::ik::{IkSolver, pieper::PieperIk};
/// let robot = kinema::Robot::builtin("puma560")?;
/// let ik = PieperIk::new(&robot)?;
/// let q = [0.3, 0.6, -2.5, 0.4, 0.7, -0.2];
/// let target = robot.fk(&q)?.world_from_tool;
/// let sols = ik.solve(&target)?;
/// assert_eq!(sols.len(), 8);
/// assert!(sols.iter().all(|s| s.position_error < 1e-10 && s.orientation_error < 1e-10));
/// // The configuration we started from is one of the eight.
/// assert!(sols.iter().any(|s| s.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9)));
/// // A robot whose wrist axes do not meet is rejected.
/// assert!(PieperIk::new(&kinema::Robot::builtin("ur5")?).is_err());
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct PieperIk {
    robot: Robot,
    links: [Link; 6],
    /// Inverse of `world_from_dh0` (the robot's base, followed for a
    /// modified table by the first row's Rx(α0)·Tx(a0)).
    dh0_from_world: Pose,
    /// Inverse of the robot's tool transform.
    tool_from_flange: Pose,
    /// Wrist centre in the flange (link 6) frame \[m\].
    wc_in_flange: Vector3<f64>,
    arm: ArmKind,
    /// The products of the general shoulder's θ3 condition (used by [`ArmKind::General`]).
    general: GeneralShoulder,
    /// The geometric arm kernel of the shoulder-plane and intersecting
    /// shoulders (axes 2 ∥ 3, axes 1 and 2 meeting), from the table's axes.
    geo_arm: Option<SphericalArm>,
    /// The wrist centre at θ1 = θ2 = θ3 = 0, in the DH base frame \[m\].
    w0: Vector3<f64>,
    /// Axes 4, 5, 6 in DH frame 3 at θ = 0: the wrist's orientation solve.
    wrist: SphericalWrist,
    /// The wrist's vector ⊥ axis 6, carried back to DH frame 5 (Rz(θ6)'s frame).
    wrist_u: Vector3<f64>,
}

impl PieperIk {
    /// Checks that `robot` is a 6R arm with a spherical, orthogonal wrist and
    /// a supported shoulder arrangement ([`ArmKind`]), described by a
    /// standard or modified DH table, and prepares the solver.
    ///
    /// Detection rule (on the equivalent standard-DH table; a modified table
    /// is regrouped into one, its first row's Rx(α0)·Tx(a0) joining the
    /// base): a4 = a5 = 0 and d5 = 0 (within 1e-9 m) — axes 4, 5 and 6 then
    /// meet in one point —, α4, α5 = ±90° (within 1e-9 in sine and cosine);
    /// verified numerically: the computed wrist centre must not move when
    /// q4…q6 change, at a few seeded configurations. The shoulder
    /// arrangement ([`ArmKind`]) is classified with the same tolerances.
    ///
    /// Errors ([`Error::UnsupportedStructure`]) say which condition fails.
    pub fn new(robot: &Robot) -> Result<Self> {
        let name = robot.name();
        let reject =
            |reason: String| Err(Error::UnsupportedStructure { solver: "pieper".into(), robot: name.into(), reason });
        let types = robot.joint_types();
        if robot.dof() != 6 || types != "RRRRRR" {
            return reject(format!(
                "{name}: the pieper solver needs exactly 6 revolute joints; this robot has {} ({types})",
                robot.dof()
            ));
        }
        // The DH rows, converted to standard DH.
        let mut conv = None;
        let mut rows = [(0.0, 0.0, 0.0); 6];
        for (i, j) in robot.joints().iter().enumerate() {
            match j.geometry {
                LinkGeometry::Dh { convention, d, a, alpha, .. } => {
                    if conv.is_some_and(|c| c != convention) {
                        return reject(format!("{name}: the DH table mixes standard and modified rows"));
                    }
                    conv = Some(convention);
                    rows[i] = (d, a, alpha);
                }
                LinkGeometry::General { .. } => {
                    return reject(format!(
                        "{name}: joint {} is described by a general transform; the pieper solver needs a standard or modified DH table",
                        i + 1
                    ))
                }
            }
        }
        let offsets: Vec<f64> = robot.joints().iter().map(|j| j.offset).collect();
        let (std_rows, world_from_dh0) = match conv {
            Some(DhConvention::Modified) => {
                // X0·Z1·X1·Z2·…·X5·Z6 with Xk = Rx(αk)·Tx(ak) (row k + 1) and
                // Zi = Rz(θi)·Tz(di) regroups into X0·(Z1·X1)·…·(Z5·X5)·Z6:
                // standard rows (di, ai, αi) taken from row i + 1, and a6 = α6 = 0.
                let mut s = [(0.0, 0.0, 0.0); 6];
                for i in 0..6 {
                    let (a, alpha) = if i < 5 { (rows[i + 1].1, rows[i + 1].2) } else { (0.0, 0.0) };
                    s[i] = (rows[i].0, a, alpha);
                }
                // X0 = Rx(α0)·Tx(a0), with the exact cosine and sine the chain uses.
                let (ca, sa) = twist(rows[0].2);
                let x0 = Pose::new(rx(Link { d: 0.0, a: 0.0, ca, sa, offset: 0.0 }), Vector3::new(rows[0].1, 0.0, 0.0));
                (s, *robot.base() * x0)
            }
            _ => (rows, *robot.base()),
        };
        let mut links = [Link { d: 0.0, a: 0.0, ca: 1.0, sa: 0.0, offset: 0.0 }; 6];
        for i in 0..6 {
            let (d, a, alpha) = std_rows[i];
            let (ca, sa) = twist(alpha);
            links[i] = Link { d, a, ca, sa, offset: offsets[i] };
        }
        let [l1, l2, l3, l4, l5, l6] = links;
        let offset = l4.a.abs().max(l5.a.abs()).max(l5.d.abs());
        if offset > GEOM_TOL {
            return reject(format!(
                "{name}: axes 4, 5, 6 do not intersect (offset {offset:.4} m: a4 = {:.4} m, a5 = {:.4} m, d5 = {:.4} m in standard DH), not a spherical wrist",
                l4.a, l5.a, l5.d
            ));
        }
        for (k, l) in [(4, l4), (5, l5)] {
            if l.sa.abs() <= GEOM_TOL {
                return reject(format!(
                    "{name}: axes {k} and {} are parallel (α{k} = {:.1}°), a degenerate wrist",
                    k + 1,
                    l.sa.fast_atan2(l.ca).to_degrees()
                ));
            }
            if l.ca.abs() > GEOM_TOL {
                return reject(format!(
                    "{name}: the wrist is not orthogonal (α{k} = {:.3}°); the pieper solver supports α4, α5 = ±90°",
                    l.sa.fast_atan2(l.ca).to_degrees()
                ));
            }
        }
        let arm = if l1.ca.abs() <= GEOM_TOL && l2.sa.abs() <= GEOM_TOL {
            ArmKind::ShoulderPlane
        } else if l1.a.abs() <= GEOM_TOL && l1.sa.abs() > GEOM_TOL {
            ArmKind::IntersectingShoulder
        } else if l1.sa.abs() <= GEOM_TOL && l1.a.abs() > GEOM_TOL && l2.sa.abs() > GEOM_TOL {
            ArmKind::ParallelShoulder
        } else if l1.sa.abs() > GEOM_TOL && l1.a.abs() > GEOM_TOL {
            ArmKind::General
        } else {
            return reject(format!(
                "{name}: degenerate shoulder (a1 = {:.4} m, α1 = {:.3}°, α2 = {:.3}°): axes 1 and 2 coincide, or axes 1, 2 and 3 \
                 are all parallel, so the wrist centre cannot reach a 3-D region",
                l1.a,
                l1.sa.fast_atan2(l1.ca).to_degrees(),
                l2.sa.fast_atan2(l2.ca).to_degrees()
            ));
        };
        // Reach of the elbow must depend on θ3.
        let elbow = match arm {
            ArmKind::ShoulderPlane => l2.a.abs() * l3.a.fast_hypot(l4.d * l3.sa),
            ArmKind::IntersectingShoulder => {
                let (a, b) = intersecting_coeffs(&links).1;
                a.fast_hypot(b)
            }
            ArmKind::ParallelShoulder => l2.sa.abs() * l3.a.fast_hypot(l4.d * l3.sa),
            ArmKind::General => {
                let (a, b) = intersecting_coeffs(&links).1;
                a.fast_hypot(b) + l2.sa.abs() * l3.a.fast_hypot(l4.d * l3.sa)
            }
        };
        if elbow <= GEOM_TOL {
            return reject(format!(
                "{name}: joint 3 does not change the wrist centre's distance from the shoulder (degenerate arm: a2 = {:.4} m, a3 = {:.4} m, d4 = {:.4} m)",
                l2.a, l3.a, l4.d
            ));
        }
        // Wrist centre in the flange frame: o5 in frame 6 = Rx(−α6)·(−a6, 0, −d6).
        let wc_in_dh6 = rx(l6).transpose() * Vector3::new(-l6.a, 0.0, -l6.d);
        let tool = robot.tool();
        let wc_in_flange = wc_in_dh6;
        let wrist_axes = wrist_axes(l4, l5);
        let mut ik = PieperIk {
            robot: robot.clone(),
            links,
            dh0_from_world: world_from_dh0.inverse(),
            tool_from_flange: robot.tool().inverse(),
            wc_in_flange,
            arm,
            general: GeneralShoulder::new(&links),
            geo_arm: geo_arm::kernel(&links, arm),
            w0: Vector3::zeros(),
            wrist: SphericalWrist::new(wrist_axes[..3].try_into().unwrap_or([Vector3::z(); 3]), l4.offset),
            wrist_u: wrist_axes[3],
        };
        ik.w0 = ik.arm_point([0.0; 3]);
        // Numeric check: the wrist centre must not move with q4…q6.
        let mut rng = ChaCha8Rng::seed_from_u64(0x5049_4550);
        for _ in 0..3 {
            let mut q = robot.random_q(&mut rng);
            let w0 = ik.wrist_centre(&robot.fk(&q)?.world_from_tool);
            for v in &mut q[3..] {
                *v += 0.7;
            }
            let w1 = ik.wrist_centre(&robot.fk(&q)?.world_from_tool);
            let scale = 1.0 + w0.norm() + tool.pos.norm();
            if (w1 - w0).norm() > 1e-9 * scale {
                return reject(format!(
                    "{name}: the wrist centre found from the DH table moves by {:.3e} m when q4…q6 change; not a spherical wrist",
                    (w1 - w0).norm()
                ));
            }
        }
        Ok(ik)
    }

    /// The arrangement of the first three axes that was detected.
    pub fn arm_kind(&self) -> ArmKind {
        self.arm
    }

    /// The robot this solver was built for.
    pub fn robot(&self) -> &Robot {
        &self.robot
    }

    /// The flange pose in the DH base frame (frame 0 of the standard table).
    fn dh0_from_flange(&self, target: &Pose) -> Pose {
        self.dh0_from_world * *target * self.tool_from_flange
    }

    /// The wrist centre of a target pose (`world_from_tool`), in the DH base
    /// frame \[m\].
    fn wrist_centre(&self, target: &Pose) -> Vector3<f64> {
        self.dh0_from_flange(target).transform_point(&self.wc_in_flange)
    }

    /// Joint value for angle θ of joint `i`: θ − offset wrapped to (−π, π],
    /// moved by ±2π when that brings it within the limits.
    fn joint_value(&self, i: usize, theta: f64) -> f64 {
        wrap_into_limits(&self.robot.joints()[i].limits, theta - self.links[i].offset)
    }

    /// The arm solutions (θ1, θ2, θ3, label) for wrist centre `p`.
    fn solve_arm(&self, p: &Vector3<f64>) -> std::result::Result<Vec<([f64; 3], &'static str)>, Unreachable> {
        if let Some(kernel) = &self.geo_arm {
            return self.arm_by_kernel(kernel, p);
        }
        match self.arm {
            ArmKind::General => self.arm_general(p),
            _ => self.arm_parallel(p),
        }
    }

    /// The parallel shoulder (axes 1 ∥ 2): the height along axis 1 depends
    /// on θ3 only (two roots), |p − o1| then gives θ2 (two roots), and θ1
    /// follows.
    fn arm_parallel(&self, p: &Vector3<f64>) -> std::result::Result<Vec<([f64; 3], &'static str)>, Unreachable> {
        let [l1, l2, l3, l4, ..] = self.links;
        let z = p.z - l1.d;
        let r2 = p.x * p.x + p.y * p.y + z * z;
        // θ3 from g3 = cα1·z (sα1 = 0): sα2·(a3 s3 − d4 sα3 c3) + cα2 f3 + d2 = cα1 z.
        let f3 = l3.d + l4.d * l3.ca;
        let (a, b, c) = (-l2.sa * l4.d * l3.sa, l2.sa * l3.a, l1.ca * z - l2.ca * f3 - l2.d);
        let r = a.fast_hypot(b);
        let mut cosd = c / r;
        if cosd.is_nan() || cosd.abs() > 1.0 {
            let by = c.abs() - r;
            if by > BOUNDARY_TOL * (1.0 + r2.sqrt() + r) {
                // cα1·(z − d1) = g3 ∈ [g3₀ − R, g3₀ + R] with g3₀ = cα2·f3 + d2.
                let g30 = l2.ca * f3 + l2.d;
                let (lo, hi) = (l1.ca * (g30 - r) + l1.d, l1.ca * (g30 + r) + l1.d);
                let (lo, hi) = (lo.min(hi), lo.max(hi));
                let boundary = format!("slab {lo:.4} m ≤ z ≤ {hi:.4} m (along axis 1) that the wrist centre can reach");
                return Err(Unreachable::OutsideReach { by, boundary });
            }
            cosd = cosd.clamp(-1.0, 1.0);
        }
        let phi3 = b.fast_atan2(a);
        let delta = cosd.acos();
        let mut out = Vec::with_capacity(4);
        for (e, t3) in [(1, phi3 + delta), (2, phi3 - delta)] {
            let g = arm_g(&self.links, t3);
            let h = g.x.fast_hypot(g.y);
            let psi = g.y.fast_atan2(g.x);
            // θ2 from H·cos(θ2 + ψ) = P.
            let val = (r2 - g.norm_squared() - l1.a * l1.a) / (2.0 * l1.a);
            let t2s = if h <= AXIS_TOL {
                [l2.offset, l2.offset]
            } else {
                let mut x = val / h;
                if x.is_nan() || x.abs() > 1.0 {
                    if val.abs() - h > BOUNDARY_TOL * (1.0 + h + val.abs()) {
                        continue;
                    }
                    x = x.clamp(-1.0, 1.0);
                }
                let s = x.acos();
                [s - psi, -s - psi]
            };
            for (sh, t2) in t2s.into_iter().enumerate() {
                // θ1 from (px, py) = Rz(θ1)·(w1, w2).
                let t1 = theta1(l1, &g, t2, p);
                out.push(([t1, t2, t3], ROOT_LABELS[sh][e - 1]));
            }
        }
        if out.is_empty() {
            // How far |val| exceeds h is a mismatch of the arm equation (in m²
            // / m), not a distance: no figure.
            return Err(Unreachable::NotReached {
                detail: "the wrist centre is outside the region it can reach at the required distance from the \
                         shoulder"
                    .into(),
            });
        }
        Ok(out)
    }
    /// Pieper's general case: with P = c2·g1 − s2·g2 from |p − o1|² and
    /// Q = s2·g1 + c2·g2 from the height along axis 1, P² + Q² = g1² + g2²
    /// is an equation in θ3 alone (a quartic in tan(θ3/2)).
    fn arm_general(&self, p: &Vector3<f64>) -> std::result::Result<Vec<([f64; 3], &'static str)>, Unreachable> {
        let [l1, ..] = self.links;
        let z = p.z - l1.d;
        let r2 = p.x * p.x + p.y * p.y + z * z;
        // P and Q at θ3 (F = P² + Q² − g_x² − g_y², module general).
        let pq = |t3: f64| {
            let g = arm_g(&self.links, t3);
            let pp = (r2 - g.norm_squared() - l1.a * l1.a) / (2.0 * l1.a);
            let qq = (z - l1.ca * g.z) / l1.sa;
            (g, pp, qq)
        };
        let mut roots = [0.0; 4];
        let n = general::roots(&self.general.condition(r2, z), &mut roots);
        let mut out = Vec::with_capacity(4);
        for (e, &t3) in roots[..n].iter().enumerate() {
            let (g, pp, qq) = pq(t3);
            let t2 = if g.x.fast_hypot(g.y) <= AXIS_TOL {
                self.links[1].offset
            } else {
                qq.fast_atan2(pp) - g.y.fast_atan2(g.x)
            };
            let t1 = theta1(l1, &g, t2, p);
            // Keep only exact solutions (a near-double root may be a rounding artefact of a complex pair).
            let wc = self.arm_point([t1, t2, t3]);
            if (wc - p).norm() <= 1e-9 * (1.0 + p.norm()) {
                const LABELS: [&str; 4] = ["arm-1", "arm-2", "arm-3", "arm-4"];
                out.push(([t1, t2, t3], LABELS[e]));
            }
        }
        if out.is_empty() {
            // The arm equations' mismatch over θ3 is in m², not a distance: no figure.
            return Err(Unreachable::NotReached {
                detail: "the wrist centre is outside the region the arm reaches (general Pieper arm: the arm \
                         equations' condition on θ3 has no real root)"
                    .into(),
            });
        }
        Ok(out)
    }

    /// The wrist centre for θ1…θ3, in the DH base frame \[m\].
    fn arm_point(&self, t: [f64; 3]) -> Vector3<f64> {
        let mut p = Vector3::new(0.0, 0.0, self.links[3].d);
        for i in (0..3).rev() {
            let l = self.links[i];
            let (s, c) = t[i].fast_sin_cos();
            let v = Vector3::new(p.x + l.a, l.ca * p.y - l.sa * p.z, l.sa * p.y + l.ca * p.z + l.d);
            p = Vector3::new(c * v.x - s * v.y, s * v.x + c * v.y, v.z);
        }
        p
    }

    /// The two wrist solutions (θ4, θ5, θ6) for M = R03ᵀ·R06·Rx(α6)ᵀ, by
    /// the shared spherical-wrist solve, the *flip* branch first.
    fn solve_wrist(&self, m: &M3) -> [([f64; 3], &'static str); 2] {
        // M·ẑ, and M·u for the wrist's u carried back to frame 5 (see `wrist_axes`).
        let mh = Vector3::new(m[0][2], m[1][2], m[2][2]);
        let u = &self.wrist_u;
        let mu = Vector3::from_fn(|i, _| m[i][0] * u.x + m[i][1] * u.y + m[i][2] * u.z);
        // An orthogonal wrist always has its two branches (never subproblem 2's miss).
        let roots = self.wrist.solve(&mh, &mu).unwrap_or(WristRoots { q: [[f64::NAN; 3]; 2], n: 2, singular: false });
        // Labels as Corke's `ikine_a` names the PUMA 560's wrist (`n`/`f`): the
        // branch with sin θ5 > 0 is the flipped one; at the singularity the
        // one half a turn from θ4's offset.
        let flip_first = if roots.singular { 1 } else { usize::from(roots.q[0][1] < 0.0) };
        [(roots.q[flip_first], "wrist-flip"), (roots.q[1 - flip_first], "wrist-noflip")]
    }
}

/// "{arm}/{wrist}" as a static string: the labels form a small fixed set, each
/// built once and kept for the life of the program (so a solve does not
/// format strings).
fn combined_label(arm: &'static str, wrist: &'static str) -> &'static str {
    use std::sync::{Mutex, OnceLock};
    type LabelTable = Mutex<Vec<(&'static str, &'static str, &'static str)>>;
    static TABLE: OnceLock<LabelTable> = OnceLock::new();
    let table = TABLE.get_or_init(|| Mutex::new(Vec::new()));
    let mut t = table.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(&(_, _, c)) = t.iter().find(|(a, w, _)| *a == arm && *w == wrist) {
        return c;
    }
    let c: &'static str = Box::leak(format!("{arm}/{wrist}").into_boxed_str());
    t.push((arm, wrist, c));
    c
}

impl IkSolver for PieperIk {
    fn name(&self) -> &'static str {
        "pieper"
    }

    /// All (up to 8) solutions: each arm branch × {noflip, flip}, labelled
    /// as described in the [module documentation](self).
    fn solve(&self, target: &Pose) -> Result<Vec<Solution>> {
        let mut set = crate::ik::CandidateSet::new();
        self.candidates_into(target, &mut set)?;
        (0..set.len()).map(|i| set.evaluate(i, &self.robot, target)).collect()
    }

    fn propose(&self, target: &Pose) -> Result<Vec<Solution>> {
        let mut set = crate::ik::CandidateSet::new();
        self.candidates_into(target, &mut set)?;
        Ok(set.unmeasured())
    }

    fn candidates_into(&self, target: &Pose, out: &mut crate::ik::CandidateSet) -> Result<()> {
        check_target(target)?;
        out.clear();
        let unreachable = |reason| Error::Unreachable { solver: "pieper".into(), reason, closest: None };
        let t06 = self.dh0_from_flange(target);
        let p = t06.transform_point(&self.wc_in_flange);
        if !p.iter().all(|v| v.is_finite()) || p.norm() > 1e100 {
            return Err(unreachable(Unreachable::NotReached {
                detail: "the target is absurdly far away (over 1e100 m, or not finite once the tool is stripped)"
                    .into(),
            }));
        }
        let arms = self.solve_arm(&p).map_err(unreachable)?;
        let l6 = self.links[5];
        // R06·Rx(α6)ᵀ as rows.
        let r = t06.rot * rx(l6).transpose();
        let r06: M3 =
            [[r[(0, 0)], r[(0, 1)], r[(0, 2)]], [r[(1, 0)], r[(1, 1)], r[(1, 2)]], [r[(2, 0)], r[(2, 1)], r[(2, 2)]]];
        for (th, label) in arms {
            let r03 = mul(&mul(&rzrx(th[0], self.links[0]), &rzrx(th[1], self.links[1])), &rzrx(th[2], self.links[2]));
            let m = tmul(&r03, &r06);
            for (w, wl) in self.solve_wrist(&m) {
                let thetas = [th[0], th[1], th[2], w[0], w[1], w[2]];
                let q: [f64; 6] = std::array::from_fn(|i| self.joint_value(i, thetas[i]));
                if !q.iter().all(|v| v.is_finite()) {
                    continue;
                }
                out.push(&q, combined_label(label, wl));
            }
        }
        if out.is_empty() {
            return Err(unreachable(Unreachable::NotReached {
                detail: "the closed form gives no finite joint values for it".into(),
            }));
        }
        Ok(())
    }
}

impl crate::ik::family::Family for PieperIk {}
