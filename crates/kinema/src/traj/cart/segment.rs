//! The geometric pieces of a Cartesian motion — a straight line or a
//! circular arc, with a SLERP or roll-pitch-yaw rotation — and the time law
//! each one gets from the Cartesian limits.

use nalgebra::{Matrix3, Vector3};

use super::{CartesianLimits, CartesianMotion, Orientation, Waypoint};
use crate::error::{Error, InputError, Result};
use crate::math::{
    axis_angle_to_rot, rot_to_axis_angle, rot_to_rpy_near, rot_x, rot_y, rot_z, rpy_to_rot, Pose, RpyConvention,
};
use crate::traj::law::{MotionLimits, Profile, TimeLaw};

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
        Some(&value) => Err(Error::Input(InputError::NotFinite { what: format!("{what} pose"), value })),
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
            return Err(Error::Input(InputError::NotFinite { what: "aux".into(), value }));
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
            return Err(Error::Input(InputError::NotFinite { what: what.into(), value }));
        }
        let local = centre.inverse().transform_point(start);
        let r = local.x.hypot(local.y);
        if r == 0.0 || local.z.abs() > 1e-9 * r.max(1.0) {
            return Err(Error::Input(InputError::DoesNotFit {
                what: "start".into(),
                reason: format!(
                    "the start point must lie in the xy plane of the centre frame, away from its origin (local {:.6}, {:.6}, {:.6})",
                    local.x, local.y, local.z
                ),
            }));
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
    pub(super) fn point(&self, u: f64, ud: f64, udd: f64) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
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
    pub(super) fn increment(&self, u: f64, ud: f64, udd: f64) -> RotState {
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
pub(super) fn segment_law(
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
