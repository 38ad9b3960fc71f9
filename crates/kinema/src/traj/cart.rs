//! Cartesian motions (seed 004 §VIII-C/D): straight lines (LIN), circular
//! arcs (CIRC) and chains of them blended through via points, each timed by
//! a [`TimeLaw`].
//!
//! A [`Segment`] is a geometric piece p(u), R(u), u ∈ \[0, 1\]. A
//! [`CartesianMotion`] runs segments one after another; with blending the
//! next one starts before the previous ends and the two are superposed
//! (seed 004 eq. 41: P(t) = P_ini + s(t)·(P_obj − P_ini) + s′(t − t_s)·(P_sig − P_obj)),
//! which rounds the corner and keeps the velocity continuous. Orientations
//! superpose the same way as world-frame increments, R(t) = Δ_n(t)⋯Δ_1(t)·R_0.
//!
//! Each segment's law is the fastest of its family with ṡ ≤ min(v/L, ω/θ),
//! s̈ ≤ min(a/L, α/θ) (and jerk likewise), L the path length and θ the
//! rotation angle — the larger of the translational and rotational
//! requirements, decided per limit — and with the limits holding for the
//! real vectors: on an arc the centripetal acceleration shares the
//! acceleration budget, and with RPY interpolation |ω| (not each angle's
//! rate) is what `rot_vel` bounds. Where two blended segments overlap, their
//! velocities and accelerations add; where the sum would exceed a limit the
//! blend is shortened (bisection on its length, down to a full stop at the
//! via point), so every limit holds and a blended motion is never slower
//! than stopping at every point. With the trapezoid, whose accelerations are
//! constant, a corner sharper than 60° cannot be blended at full
//! acceleration (|a₂ − a₁| = 2·a·sin(angle/2) > a): it becomes a stop; the
//! S-curve blends more corners.

use nalgebra::{Matrix3, Vector3};

use super::law::{MotionLimits, Profile, TimeLaw};
use super::MAX_SAMPLES;
use crate::error::{Error, Result};
use crate::math::{
    axis_angle_to_rot, rot_to_axis_angle, rot_to_rpy_near, rot_x, rot_y, rot_z, rpy_to_rot, Pose, RpyConvention,
};

/// How a LIN segment interpolates orientation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Orientation {
    /// Spherical linear interpolation of the rotation (constant angular
    /// velocity axis; the default).
    #[default]
    Slerp,
    /// Linear interpolation of roll-pitch-yaw angles in the given convention
    /// (seed 004 eq. 40).
    Rpy(RpyConvention),
}

/// A point a LIN motion goes to: its pose, and the roll-pitch-yaw triple it
/// was written as, if it was written as one.
///
/// Seed 004 eq. 40 interpolates the triples as written. A triple read back
/// from the rotation matrix may be another triple of the same rotation (a
/// pitch past π/2 comes back mirrored, roll and yaw turned by π), and
/// interpolating towards that one turns the tool the long way round.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Waypoint {
    pose: Pose,
    rpy: Option<([f64; 3], RpyConvention)>,
}

impl Waypoint {
    /// A waypoint written as a position \[m\] and a roll-pitch-yaw triple \[rad\].
    pub fn from_xyz_rpy(xyz: [f64; 3], rpy: [f64; 3], conv: RpyConvention) -> Waypoint {
        Waypoint { pose: Pose::from_xyz_rpy(xyz, rpy, conv), rpy: Some((rpy, conv)) }
    }

    /// The pose.
    pub fn pose(&self) -> &Pose {
        &self.pose
    }

    /// The triple it was written as in `conv`, if it was.
    fn written_rpy(&self, conv: RpyConvention) -> Option<[f64; 3]> {
        self.rpy.filter(|(_, c)| *c == conv).map(|(t, _)| t)
    }
}

impl From<Pose> for Waypoint {
    fn from(pose: Pose) -> Waypoint {
        Waypoint { pose, rpy: None }
    }
}

/// Cartesian limits of a motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CartesianLimits {
    /// Tool-point speed \[m/s\].
    pub vel: f64,
    /// Tool-point acceleration \[m/s²\].
    pub acc: f64,
    /// Tool-point jerk \[m/s³\] (S-curve).
    pub jerk: Option<f64>,
    /// Angular speed |ω| of the tool \[rad/s\], whatever the interpolation.
    pub rot_vel: f64,
    /// Angular acceleration \[rad/s²\].
    pub rot_acc: f64,
    /// Angular jerk \[rad/s³\] (S-curve).
    pub rot_jerk: Option<f64>,
}

impl CartesianLimits {
    /// Translational limits, with rotational ones of the same numbers per radian.
    pub fn new(vel: f64, acc: f64) -> Self {
        CartesianLimits { vel, acc, jerk: None, rot_vel: vel, rot_acc: acc, rot_jerk: None }
    }
}

/// Position, velocity and acceleration of the tool along a motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CartesianState {
    /// Tool pose.
    pub pose: Pose,
    /// Linear velocity \[m/s\].
    pub vel: Vector3<f64>,
    /// Angular velocity (world frame) \[rad/s\].
    pub omega: Vector3<f64>,
    /// Linear acceleration \[m/s²\].
    pub acc: Vector3<f64>,
    /// Angular acceleration \[rad/s²\].
    pub alpha: Vector3<f64>,
}

/// The rotation part of a segment.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Rot {
    /// R(u) = exp(u·θ·k)·R0, k a unit world axis.
    Slerp { r0: Matrix3<f64>, axis: Vector3<f64>, angle: f64 },
    /// R(u) = R(Φ0 + u·ΔΦ).
    Rpy { conv: RpyConvention, phi0: [f64; 3], dphi: [f64; 3] },
}

/// The path of the position.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Path {
    /// p(u) = p0 + u·(p1 − p0).
    Line { p0: Vector3<f64>, p1: Vector3<f64> },
    /// p(u) = c + r·(cos(φu)·e1 + sin(φu)·e2).
    Arc { c: Vector3<f64>, e1: Vector3<f64>, e2: Vector3<f64>, r: f64, phi: f64 },
}

/// A geometric piece of a Cartesian motion, parametrised by u ∈ \[0, 1\].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    path: Path,
    rot: Rot,
}

/// (R, ω, α) of a world-frame rotation increment at u with u̇, ü.
type RotState = (Matrix3<f64>, Vector3<f64>, Vector3<f64>);

fn finite_pose(what: &str, p: &Pose) -> Result<()> {
    match p.pos.iter().chain(p.rot.iter()).find(|v| !v.is_finite()) {
        None => Ok(()),
        Some(&value) => Err(Error::NotFinite { what: format!("{what} pose"), value }),
    }
}

impl Segment {
    /// A straight line from `from` to `to` (seed 004 §VIII-C1, eq. 39–40).
    /// With [`Orientation::Rpy`] the end triple is read from `to`'s rotation
    /// and the start's is the one nearest it; [`Segment::lin_between`] keeps
    /// triples the user wrote.
    pub fn lin(from: &Pose, to: &Pose, orientation: Orientation) -> Result<Segment> {
        Segment::lin_between(&Waypoint::from(*from), &Waypoint::from(*to), orientation)
    }

    /// A straight line between two waypoints. With [`Orientation::Rpy`] the
    /// triples are those the waypoints were written as (seed 004 eq. 40:
    /// Φ(t) = Φ_ini + s(t)·(Φ_obj − Φ_ini)); an end given only as a pose gets
    /// the triple of its rotation nearest the other end's.
    pub fn lin_between(from: &Waypoint, to: &Waypoint, orientation: Orientation) -> Result<Segment> {
        finite_pose("from", &from.pose)?;
        finite_pose("to", &to.pose)?;
        Ok(Segment { path: Path::Line { p0: from.pose.pos, p1: to.pose.pos }, rot: Self::rot(from, to, orientation) })
    }

    /// LIN segments from `start` through each of `points` in turn.
    pub fn lin_chain(start: &Pose, points: &[Waypoint], orientation: Orientation) -> Result<Vec<Segment>> {
        let mut from = Waypoint::from(*start);
        let mut segments = Vec::with_capacity(points.len());
        for to in points {
            segments.push(Segment::lin_between(&from, to, orientation)?);
            from = *to;
        }
        Ok(segments)
    }

    fn rot(from: &Waypoint, to: &Waypoint, orientation: Orientation) -> Rot {
        let (r0, r1) = (&from.pose.rot, &to.pose.rot);
        match orientation {
            Orientation::Slerp => {
                let w = rot_to_axis_angle(&(r1 * r0.transpose()));
                let angle = w.norm();
                let axis = if angle > 0.0 { w / angle } else { Vector3::z() };
                Rot::Slerp { r0: *r0, axis, angle }
            }
            Orientation::Rpy(conv) => {
                let (a, b) = match (from.written_rpy(conv), to.written_rpy(conv)) {
                    (Some(a), Some(b)) => (a, b),
                    (Some(a), None) => (a, rot_to_rpy_near(r1, conv, a)),
                    (None, Some(b)) => (rot_to_rpy_near(r0, conv, b), b),
                    (None, None) => {
                        let b = to.pose.rpy(conv);
                        (rot_to_rpy_near(r0, conv, b), b)
                    }
                };
                Rot::Rpy { conv, phi0: a, dphi: [b[0] - a[0], b[1] - a[1], b[2] - a[2]] }
            }
        }
    }

    /// The industrial CIRC: an arc from `from` through the point `aux` to
    /// `to` (KUKA CIRC, ABB MoveC). The orientation goes from `from`'s to
    /// `to`'s by SLERP. Errors: three points on a line or two coinciding.
    pub fn circ_through(from: &Pose, aux: &Vector3<f64>, to: &Pose) -> Result<Segment> {
        finite_pose("from", from)?;
        finite_pose("to", to)?;
        if let Some(&value) = aux.iter().find(|v| !v.is_finite()) {
            return Err(Error::NotFinite { what: "aux".into(), value });
        }
        let (a, b, c) = (from.pos, *aux, to.pos);
        let (ab, ac) = (b - a, c - a);
        let n = ab.cross(&ac);
        let scale = ab.norm().max(ac.norm());
        if n.norm() <= 1e-9 * scale * scale || scale == 0.0 {
            return Err(Error::Infeasible {
                what: "aux".into(),
                reason: "start, auxiliary and end points are (nearly) on one line or coincide; no circle passes \
                         through them"
                    .into(),
            });
        }
        // Circumcentre: a + (|ab|²·(ac × n) + |ac|²·(n × ab)) / (2|n|²).
        let centre =
            a + (ab.norm_squared() * ac.cross(&n) + ac.norm_squared() * n.cross(&ab)) / (2.0 * n.norm_squared());
        let r = (a - centre).norm();
        let nz = n.normalize();
        let e1 = (a - centre) / r;
        let e2 = nz.cross(&e1);
        let angle_of = |p: &Vector3<f64>| {
            let d = p - centre;
            let t = d.dot(&e2).atan2(d.dot(&e1));
            if t < 0.0 {
                t + std::f64::consts::TAU
            } else {
                t
            }
        };
        // With the normal of (ab × ac), the arc a → b → c turns positively about it.
        let phi = angle_of(&c);
        Ok(Segment {
            path: Path::Arc { c: centre, e1, e2, r, phi },
            rot: Self::rot(&(*from).into(), &(*to).into(), Orientation::Slerp),
        })
    }

    /// Seed 004 §VIII-D: an arc about the z axis of the frame `centre`,
    /// starting at the point `start` (which must lie in the frame's xy plane)
    /// and turning by `angle` \[rad\] (positive about z), the tool keeping
    /// the orientation `rot`.
    pub fn circ_about(centre: &Pose, start: &Vector3<f64>, angle: f64, rot: &Matrix3<f64>) -> Result<Segment> {
        finite_pose("centre", centre)?;
        let not_finite = (start.iter().map(|&v| ("start", v)))
            .chain([("angle", angle)])
            .chain(rot.iter().map(|&v| ("rot", v)))
            .find(|(_, v)| !v.is_finite());
        if let Some((what, value)) = not_finite {
            return Err(Error::NotFinite { what: what.into(), value });
        }
        let local = centre.inverse().transform_point(start);
        let r = local.x.hypot(local.y);
        if r == 0.0 || local.z.abs() > 1e-9 * r.max(1.0) {
            return Err(Error::DoesNotFit {
                what: "start".into(),
                reason: format!(
                    "the start point must lie in the xy plane of the centre frame, away from its origin (local {:.6}, {:.6}, {:.6})",
                    local.x, local.y, local.z
                ),
            });
        }
        let e1 = centre.rot * Vector3::new(local.x / r, local.y / r, 0.0);
        let z = centre.rot.column(2).into_owned();
        let (e2, phi) = if angle >= 0.0 { (z.cross(&e1), angle) } else { (-z.cross(&e1), -angle) };
        let p = Pose::new(*rot, *start);
        Ok(Segment {
            path: Path::Arc { c: centre.pos, e1, e2, r, phi },
            rot: Self::rot(&p.into(), &p.into(), Orientation::Slerp),
        })
    }

    /// Path length \[m\] and rotation "length": the angle \[rad\] for SLERP, the
    /// largest change of one angle for RPY interpolation.
    pub fn lengths(&self) -> (f64, f64) {
        let l = match self.path {
            Path::Line { p0, p1 } => (p1 - p0).norm(),
            Path::Arc { r, phi, .. } => r * phi,
        };
        let th = match self.rot {
            Rot::Slerp { angle, .. } => angle,
            Rot::Rpy { dphi, .. } => dphi.iter().fold(0.0f64, |m, d| m.max(d.abs())),
        };
        (l, th)
    }

    /// The largest angular speed \[rad\] per unit of u̇: the angle for
    /// SLERP; for RPY angles, the largest |ω| their constant rates give along
    /// the segment (sampled; a rounding between samples is caught by the
    /// law's final check).
    fn peak_angular_rate(&self) -> f64 {
        match self.rot {
            Rot::Slerp { angle, .. } => angle,
            Rot::Rpy { .. } => (0..=64).map(|k| self.increment(k as f64 / 64.0, 1.0, 0.0).1.norm()).fold(0.0, f64::max),
        }
    }

    /// Start pose.
    pub fn start(&self) -> Pose {
        self.pose(0.0)
    }

    /// End pose.
    pub fn end(&self) -> Pose {
        self.pose(1.0)
    }

    /// Pose at u.
    pub fn pose(&self, u: f64) -> Pose {
        let (p, _, _) = self.point(u, 0.0, 0.0);
        let (d, _, _) = self.increment(u, 0.0, 0.0);
        Pose::new(d * self.rot0(), p)
    }

    fn rot0(&self) -> Matrix3<f64> {
        match self.rot {
            Rot::Slerp { r0, .. } => r0,
            Rot::Rpy { conv, phi0, .. } => rpy_to_rot(phi0, conv),
        }
    }

    /// p, ṗ, p̈ at u with u̇, ü.
    fn point(&self, u: f64, ud: f64, udd: f64) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
        match self.path {
            Path::Line { p0, p1 } => {
                let d = p1 - p0;
                (p0 + d * u, d * ud, d * udd)
            }
            Path::Arc { c, e1, e2, r, phi } => {
                let (s, co) = (phi * u).sin_cos();
                let radial = e1 * co + e2 * s;
                let tangent = e2 * co - e1 * s;
                (
                    c + radial * r,
                    tangent * (r * phi * ud),
                    tangent * (r * phi * udd) - radial * (r * phi * phi * ud * ud),
                )
            }
        }
    }

    /// World-frame rotation increment Δ(u) = R(u)·R(0)ᵀ with its angular velocity and acceleration.
    fn increment(&self, u: f64, ud: f64, udd: f64) -> RotState {
        match self.rot {
            Rot::Slerp { axis, angle, .. } => {
                (axis_angle_to_rot(&(axis * (angle * u))), axis * (angle * ud), axis * (angle * udd))
            }
            Rot::Rpy { conv, phi0, dphi } => {
                let phi = [phi0[0] + u * dphi[0], phi0[1] + u * dphi[1], phi0[2] + u * dphi[2]];
                let r = rpy_to_rot(phi, conv);
                // R is a product of three elementary rotations, angle i about axis i
                // (x, y, z for indices 0, 1, 2): Rz(yaw)·Ry(pitch)·Rx(roll) for Zyx
                // (rpy = [roll, pitch, yaw]), Rx(a)·Ry(b)·Rz(c) for Xyz.
                let order = match conv {
                    RpyConvention::Zyx => [2usize, 1, 0],
                    RpyConvention::Xyz => [0usize, 1, 2],
                };
                // ω = Σ_k φ̇_k·w_k with w_k = (R_1⋯R_{k−1})·e_k, and
                // α = Σ_k φ̈_k·w_k + φ̇_k·(ω_{<k} × w_k).
                let (mut partial, mut omega, mut alpha) = (Matrix3::identity(), Vector3::zeros(), Vector3::zeros());
                for i in order {
                    let w = partial * Vector3::ith(i, 1.0);
                    alpha += w * (dphi[i] * udd) + omega.cross(&w) * (dphi[i] * ud);
                    omega += w * (dphi[i] * ud);
                    partial *= match i {
                        0 => rot_x(phi[i]),
                        1 => rot_y(phi[i]),
                        _ => rot_z(phi[i]),
                    };
                }
                (r * rpy_to_rot(phi0, conv).transpose(), omega, alpha)
            }
        }
    }
}

/// The fastest law of `profile` for `seg` alone whose tool speed, tool
/// acceleration, angular speed and angular acceleration — the real vectors,
/// not their components along the path — stay within `limits`.
///
/// The tangential limits give ṡ ≤ min(v/L, ω/Θ), s̈ ≤ min(a/L, α/Θ), with
/// Θ the largest |ω| per unit of s (the angle for SLERP; for RPY angles
/// their rates mapped to ω). On an arc of radius r the centripetal
/// acceleration L·φ·ṡ² shares the budget: (L·s̈)² + (L·φ·ṡ²)² ≤ a², and the
/// peak ṡ is chosen to make the law shortest (the bound holds at every
/// instant, as |s̈| ≤ s̈_max and ṡ ≤ V throughout). With RPY angles, whose
/// angular acceleration has terms the tangential limits do not see, the
/// peaks are measured over the law and removed by a uniform slow-down.
fn segment_law(
    seg: &Segment,
    profile: Profile,
    limits: &CartesianLimits,
    lin_jerk: Option<f64>,
    rot_jerk: Option<f64>,
) -> Result<TimeLaw> {
    let (l, _) = seg.lengths();
    let th = seg.peak_angular_rate();
    let mut shared = MotionLimits { vel: f64::INFINITY, acc: f64::INFINITY, jerk: None };
    for (len, v, a, j) in [(l, limits.vel, limits.acc, lin_jerk), (th, limits.rot_vel, limits.rot_acc, rot_jerk)] {
        if len > 0.0 {
            shared.vel = shared.vel.min(v / len);
            shared.acc = shared.acc.min(a / len);
            if let Some(j) = j {
                shared.jerk = Some(shared.jerk.unwrap_or(f64::INFINITY).min(j / len));
            }
        }
    }
    if !shared.vel.is_finite() {
        return TimeLaw::from_limits(profile, 0.0, &MotionLimits::with_jerk(1.0, 1.0, 1.0));
    }
    let mut law = match seg.path {
        Path::Arc { phi, .. } if l > 0.0 => arc_law(profile, &shared, limits.acc / l, phi)?,
        _ => TimeLaw::from_limits(profile, 1.0, &shared)?,
    };
    // A line or an arc with SLERP meets the limits by construction; RPY's
    // angular acceleration has terms the tangential limits do not see.
    if matches!(seg.rot, Rot::Rpy { .. }) {
        let alone = CartesianMotion::assemble(vec![*seg], vec![law], vec![0.0], law.duration());
        let k = alone.peak_ratio(limits, 0.0, law.duration());
        if k > 1.0 {
            law = law.stretched_to(law.duration() * k * (1.0 + 1e-12))?;
        }
    }
    Ok(law)
}

/// The shortest law on an arc turning `phi` \[rad\] whose normalised
/// tangential acceleration s̈ and centripetal φ·ṡ² share the acceleration
/// budget `acc` (a/L): s̈_max = √(acc² − (φ·V²)²) for a peak ṡ of V, V
/// searched by golden section up to the velocity limit and √(acc/φ).
fn arc_law(profile: Profile, shared: &MotionLimits, acc: f64, phi: f64) -> Result<TimeLaw> {
    let with_peak = |v: f64| {
        let tangential = (acc * acc - (phi * v * v).powi(2)).max(0.0).sqrt().min(shared.acc);
        TimeLaw::from_limits(profile, 1.0, &MotionLimits { vel: v, acc: tangential, jerk: shared.jerk })
    };
    let (mut lo, mut hi) = (0.0, shared.vel.min((acc / phi).sqrt()));
    const G: f64 = 0.618_033_988_749_894_9;
    let duration = |v: f64| with_peak(v).map_or(f64::INFINITY, |l| l.duration());
    for _ in 0..50 {
        let (m1, m2) = (hi - G * (hi - lo), lo + G * (hi - lo));
        if duration(m1) <= duration(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    with_peak(0.5 * (lo + hi))
}

/// Sampled maxima of a motion's limit ratio refined by golden section, the
/// largest first (each refinement costs 120 evaluations).
const MAX_REFINED_PEAKS: usize = 8;

/// How consecutive segments join.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Blend {
    /// Stop at every via point.
    None,
    /// Seed 004 (t_s = T1): the next segment starts when the previous one
    /// begins to decelerate (the default).
    #[default]
    Deceleration,
    /// The next segment starts this long \[s\] before the previous ends
    /// (clamped to half the duration of either).
    Time(f64),
    /// The next segment starts when the previous has this much path \[m\]
    /// left (clamped as for `Time`).
    Distance(f64),
}

/// A timed sequence of segments.
#[derive(Debug, Clone, PartialEq)]
pub struct CartesianMotion {
    segments: Vec<Segment>,
    laws: Vec<TimeLaw>,
    starts: Vec<f64>,
    duration: f64,
    finished: Finished,
}

/// The pose after the first k segments have all run to their end, for every
/// k, so that [`CartesianMotion::at`] composes only the segments running at
/// `t` and costs the same on a chain of two segments or of thousands.
#[derive(Debug, Clone, PartialEq)]
struct Finished {
    /// `by[k]`: when segments 0..=k have all ended \[s\] (non-decreasing).
    by: Vec<f64>,
    /// `poses[k]`: the pose once segments 0..k have ended (`poses[0]` is the start).
    poses: Vec<Pose>,
}

impl Finished {
    fn new(segments: &[Segment], laws: &[TimeLaw], starts: &[f64]) -> Finished {
        let mut by = Vec::with_capacity(segments.len());
        let mut poses = Vec::with_capacity(segments.len() + 1);
        let first = segments[0].start();
        let (mut p, mut r) = (first.pos, first.rot);
        poses.push(first);
        let mut latest = f64::NEG_INFINITY;
        for ((seg, law), start) in segments.iter().zip(laws).zip(starts) {
            latest = latest.max(start + law.duration());
            by.push(latest);
            // As `at_reference` adds a segment at its end: the same operations in
            // the same order, so that both give the same bits.
            p += seg.point(1.0, 0.0, 0.0).0 - seg.point(0.0, 0.0, 0.0).0;
            r = seg.increment(1.0, 0.0, 0.0).0 * r;
            poses.push(Pose::new(r, p));
        }
        Finished { by, poses }
    }
}

impl CartesianMotion {
    /// The motion of `segments` timed by `laws` from `starts`, lasting `duration`.
    fn assemble(segments: Vec<Segment>, laws: Vec<TimeLaw>, starts: Vec<f64>, duration: f64) -> CartesianMotion {
        let finished = Finished::new(&segments, &laws, &starts);
        CartesianMotion { segments, laws, starts, duration, finished }
    }

    /// Times `segments` (each must start where the previous ends, within
    /// 1e-9 m and 1e-9 rad) with laws of `profile` under `limits`, joined as
    /// `blend` says.
    ///
    /// Errors: no segment; segments that do not join; invalid limits.
    pub fn new(segments: Vec<Segment>, profile: Profile, limits: &CartesianLimits, blend: Blend) -> Result<Self> {
        Self::new_until(segments, profile, limits, blend, &|| false)
    }

    /// [`CartesianMotion::new`] that looks at `stop` between segments and
    /// returns [`Error::Cancelled`] once it says so: a chain of thousands of
    /// blended segments takes seconds to time.
    pub fn new_until(
        segments: Vec<Segment>,
        profile: Profile,
        limits: &CartesianLimits,
        blend: Blend,
        stop: &dyn Fn() -> bool,
    ) -> Result<Self> {
        if segments.is_empty() {
            return Err(Error::TooFew { what: "segments".into(), got: 0, min: 1, of: "segments".into() });
        }
        for (i, w) in segments.windows(2).enumerate() {
            let (a, b) = (w[0].end(), w[1].start());
            let dp = (a.pos - b.pos).norm();
            let dr = rot_to_axis_angle(&(a.rot * b.rot.transpose())).norm();
            if dp > 1e-9 || dr > 1e-9 {
                return Err(Error::DoesNotFit {
                    what: "segments".into(),
                    reason: format!(
                        "segment {} does not start where segment {} ends (off by {dp:.3e} m, {dr:.3e} rad)",
                        i + 2,
                        i + 1
                    ),
                });
            }
        }
        let lin_jerk = match (profile, limits.jerk) {
            (Profile::SCurve, None) => {
                return Err(Error::MissingLimit {
                    limit: "jerk".into(),
                    option: "jmax".into(),
                    needed_by: "the scurve profile".into(),
                })
            }
            (_, j) => j,
        };
        let rot_jerk = limits.rot_jerk.or(lin_jerk);
        let named =
            [("vel", limits.vel), ("acc", limits.acc), ("rot_vel", limits.rot_vel), ("rot_acc", limits.rot_acc)];
        if let Some((what, value)) = named.into_iter().find(|(_, v)| !(v.is_finite() && *v > 0.0)) {
            return Err(Error::OutOfRange { what: what.into(), value, expected: "a positive finite limit".into() });
        }
        let laws = segments
            .iter()
            .map(|seg| segment_law(seg, profile, limits, lin_jerk, rot_jerk))
            .collect::<Result<Vec<_>>>()?;
        let mut starts = vec![0.0];
        let mut overlaps = Vec::with_capacity(segments.len().saturating_sub(1));
        for i in 1..segments.len() {
            if stop() {
                return Err(Error::Cancelled);
            }
            let (prev, next) = (&laws[i - 1], &laws[i]);
            let requested = match blend {
                Blend::None => 0.0,
                Blend::Deceleration => decel_time(prev),
                Blend::Time(t) => t.max(0.0),
                Blend::Distance(d) => {
                    let (l, _) = segments[i - 1].lengths();
                    if l <= 0.0 || d <= 0.0 {
                        0.0
                    } else {
                        // Latest t with l·(1 − s(t)) ≥ d, by bisection on the monotone law.
                        let target = 1.0 - (d / l).min(1.0);
                        let (mut lo, mut hi) = (0.0, prev.duration());
                        for _ in 0..100 {
                            let mid = 0.5 * (lo + hi);
                            if prev.at(mid).s < target {
                                lo = mid;
                            } else {
                                hi = mid;
                            }
                        }
                        prev.duration() - lo
                    }
                }
            }
            .min(0.5 * prev.duration())
            .min(0.5 * next.duration());
            // The two segments alone, the second starting `o` before the first ends.
            let pair = |o: f64| {
                CartesianMotion::assemble(
                    vec![segments[i - 1], segments[i]],
                    vec![*prev, *next],
                    vec![0.0, prev.duration() - o],
                    prev.duration() + next.duration() - o,
                )
            };
            let fits = |o: f64| {
                let p = pair(o);
                o <= 0.0 || p.peak_ratio(limits, prev.duration() - o, prev.duration()) <= 1.0 + 1e-10
            };
            // Where the sum of the two would break a limit, blend less (down to a stop).
            let overlap = if fits(requested) {
                requested
            } else {
                let (mut lo, mut hi) = (0.0, requested);
                for _ in 0..40 {
                    let mid = 0.5 * (lo + hi);
                    if fits(mid) {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                lo
            };
            overlaps.push(overlap);
            starts.push(starts[i - 1] + prev.duration() - overlap);
        }
        let duration = starts.iter().zip(&laws).map(|(s, l)| s + l.duration()).fold(0.0, f64::max);
        Ok(CartesianMotion::assemble(segments, laws, starts, duration))
    }

    /// The largest ratio of a velocity to its limit, or of an acceleration to
    /// its limit (as a square root, the factor a uniform slow-down would
    /// need), over \[t0, t1\]: sampled at 501 points, then every sampled
    /// local maximum above 0.999 refined by golden-section search between its
    /// neighbours (exact to ~1e-12 where the peak lies between two samples).
    fn peak_ratio(&self, limits: &CartesianLimits, t0: f64, t1: f64) -> f64 {
        let ratio = |t: f64| {
            let st = self.at(t);
            (st.vel.norm() / limits.vel)
                .max((st.acc.norm() / limits.acc).sqrt())
                .max(st.omega.norm() / limits.rot_vel)
                .max((st.alpha.norm() / limits.rot_acc).sqrt())
        };
        const N: usize = 500;
        let h = (t1 - t0) / N as f64;
        let vals: Vec<f64> = (0..=N).map(|k| ratio(t0 + h * k as f64)).collect();
        let mut best = vals.iter().copied().fold(0.0, f64::max);
        // Sampled local maxima near the limit, the largest first. Rounding makes
        // a plateau at the limit ripple, so a maximum must stand out by more
        // than that, and only the few largest are refined.
        let noise = 1e-12;
        let mut peaks: Vec<usize> = (0..=N)
            .filter(|&k| {
                let (a, b) = (k.saturating_sub(1), (k + 1).min(N));
                vals[k] > 1.0 - 1e-3 && (k == 0 || vals[k] > vals[a] + noise) && vals[k] >= vals[b]
            })
            .collect();
        peaks.sort_by(|&x, &y| vals[y].total_cmp(&vals[x]));
        for &k in peaks.iter().take(MAX_REFINED_PEAKS) {
            let (a, b) = (k.saturating_sub(1), (k + 1).min(N));
            let (mut lo, mut hi) = (t0 + h * a as f64, t0 + h * b as f64);
            const G: f64 = 0.618_033_988_749_894_9;
            for _ in 0..60 {
                let (m1, m2) = (hi - G * (hi - lo), lo + G * (hi - lo));
                if ratio(m1) < ratio(m2) {
                    lo = m1;
                } else {
                    hi = m2;
                }
            }
            best = best.max(ratio(0.5 * (lo + hi)));
        }
        best
    }

    /// The same motion slowed down uniformly to last `duration` \[s\] (at least
    /// its own): every time scaled by k = T′/T, so velocities shrink by k,
    /// accelerations by k², jerks by k³, and every limit still holds.
    pub fn stretched_to(&self, duration: f64) -> Result<Self> {
        if !(duration.is_finite() && duration >= self.duration) {
            return Err(Error::OutOfRange {
                what: "duration".into(),
                value: duration,
                expected: format!(
                    "at least the motion's own duration, {} s (a motion is only stretched)",
                    self.duration
                ),
            });
        }
        if self.duration == 0.0 {
            return Ok(self.clone());
        }
        let k = duration / self.duration;
        Ok(CartesianMotion::assemble(
            self.segments.clone(),
            self.laws.iter().map(|l| l.stretched_to(l.duration() * k)).collect::<Result<_>>()?,
            self.starts.iter().map(|s| s * k).collect(),
            duration,
        ))
    }

    /// Duration \[s\].
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// How long each blend lasts \[s\] (segment i + 1 starts this long before
    /// segment i ends), after any reduction needed to respect the limits.
    pub fn blend_times(&self) -> Vec<f64> {
        (1..self.laws.len()).map(|i| self.starts[i - 1] + self.laws[i - 1].duration() - self.starts[i]).collect()
    }

    /// Start times \[s\] of the segments.
    pub fn segment_starts(&self) -> &[f64] {
        &self.starts
    }

    /// The segments' time laws.
    pub fn laws(&self) -> &[TimeLaw] {
        &self.laws
    }

    /// Pose, velocity and acceleration at time `t` \[s\] (clamped to the motion).
    pub fn at(&self, t: f64) -> CartesianState {
        // Segments 0..done have ended by t, segments from `started` on not
        // begun: only those between move (one, or two in a blend).
        let done = self.finished.by.partition_point(|&end| end <= t);
        let started = done + self.starts[done..].partition_point(|&start| start <= t);
        self.compose(&self.finished.poses[done], done..started, t)
    }

    /// [`CartesianMotion::at`] the plain way, every segment composed at `t`:
    /// the reference the fast path is tested against.
    #[doc(hidden)]
    pub fn at_reference(&self, t: f64) -> CartesianState {
        self.compose(&self.segments[0].start(), 0..self.segments.len(), t)
    }

    /// The state at `t` of segments `range` composed onto `from`, the pose
    /// the segments before them have reached.
    fn compose(&self, from: &Pose, range: std::ops::Range<usize>, t: f64) -> CartesianState {
        let (mut p, mut v, mut a) = (from.pos, Vector3::zeros(), Vector3::zeros());
        let (mut r, mut w, mut al) = (from.rot, Vector3::zeros(), Vector3::zeros());
        let running = self.segments[range.clone()].iter().zip(&self.laws[range.clone()]).zip(&self.starts[range]);
        for ((seg, law), start) in running {
            let s = law.at(t - start);
            let (pp, pv, pa) = seg.point(s.s, s.sd, s.sdd);
            p += pp - seg.point(0.0, 0.0, 0.0).0;
            v += pv;
            a += pa;
            let (d, dw, da) = seg.increment(s.s, s.sd, s.sdd);
            // Compose Δ·(R, ω, α): ω' = ω_Δ + Δ·ω, α' = α_Δ + Δ·α + ω_Δ × (Δ·ω).
            let (rw, ra) = (d * w, d * al);
            al = da + ra + dw.cross(&rw);
            w = dw + rw;
            r = d * r;
        }
        CartesianState { pose: Pose::new(r, p), vel: v, omega: w, acc: a, alpha: al }
    }

    /// Poses split so that consecutive ones are at most `max_step` \[m\]
    /// apart along the path and `max_angle` \[rad\] apart in orientation (seed
    /// 000 used 1 cm for its controller), from start to end: the times at
    /// which to sample.
    pub fn resample_times(&self, max_step: f64, max_angle: f64) -> Result<Vec<f64>> {
        for (what, value, unit) in [("max_step", max_step, "m"), ("max_angle", max_angle, "rad")] {
            if !(value > 0.0) {
                return Err(Error::OutOfRange {
                    what: what.into(),
                    value,
                    expected: format!("a positive step [{unit}]"),
                });
            }
        }
        let n = 20_000usize;
        let coarse: Vec<Pose> = (0..=n).map(|k| self.at(self.duration * k as f64 / n as f64).pose).collect();
        let far = |q: &Pose, last: &Pose| {
            (q.pos - last.pos).norm() > max_step
                || rot_to_axis_angle(&(q.rot * last.rot.transpose())).norm() > max_angle
        };
        // How many samples the limits ask for, from the coarse poses (each step of the result
        // spans max_step or max_angle, but for the last): a path that needs far more than can
        // be held is refused now, not after minutes of bisection.
        let (mut needed, mut by_angle) = (1.0, 0.0);
        for w in coarse.windows(2) {
            let angle = rot_to_axis_angle(&(w[1].rot * w[0].rot.transpose())).norm() / max_angle;
            let step = (w[1].pos - w[0].pos).norm() / max_step;
            needed += step.max(angle);
            if angle > step {
                by_angle += angle;
            }
        }
        // Named after the limit that asks for most of the samples.
        let (what, value) = if by_angle > 0.5 * needed { ("max_angle", max_angle) } else { ("max_step", max_step) };
        let too_many = |about: String| Error::OutOfRange {
            what: what.into(),
            value,
            expected: format!(
                "larger steps: {} m / {} rad would split this path into {about} samples (at most {MAX_SAMPLES})",
                crate::error::number_text(max_step),
                crate::error::number_text(max_angle)
            ),
        };
        if needed > 1.01 * MAX_SAMPLES as f64 {
            let about = if needed.is_finite() { format!("about {needed:.3e}") } else { "more than 10^308".into() };
            return Err(too_many(about));
        }
        let mut out = vec![0.0];
        let mut last = coarse[0];
        // A time whose pose is within reach of `last`: where the bisections start.
        let mut within = 0.0;
        for (k, pose) in coarse.iter().enumerate().skip(1) {
            let t = self.duration * k as f64 / n as f64;
            // One coarse step may span several max_steps (a long path, a small step):
            // as many samples as it needs, each the last time within reach of the one
            // before, found by bisection between `within` and t.
            while far(pose, &last) {
                let (mut lo, mut hi) = (within, t);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if far(&self.at(mid).pose, &last) {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                if lo <= *out.last().expect("non-empty") {
                    return Err(Error::OutOfRange {
                        what: "max_step".into(),
                        value: max_step,
                        expected: "a step above the sampling resolution of this path [m]".into(),
                    });
                }
                // Room for this sample and the end's.
                if out.len() + 2 > MAX_SAMPLES {
                    return Err(too_many(format!("more than {MAX_SAMPLES}")));
                }
                out.push(lo);
                last = self.at(lo).pose;
                within = lo;
            }
            within = t;
        }
        if self.duration > *out.last().expect("non-empty") {
            out.push(self.duration);
        }
        Ok(out)
    }
}

/// How long `law` decelerates at its end (its last phases with s̈ < 0).
fn decel_time(law: &TimeLaw) -> f64 {
    let t = law.duration();
    match law.profile() {
        Profile::Trapezoid => law.phase_times().last().copied().unwrap_or(0.0),
        Profile::SCurve => {
            let p = law.phase_times();
            // Phases after the cruise (or after the acceleration when there is none).
            let half = if p.len() == 7 || p.len() == 5 { p.len() / 2 + 1 } else { p.len() / 2 };
            p[half.min(p.len())..].iter().sum()
        }
        _ => t / 2.0,
    }
}
