//! Random arms of every joint kind the model has, for the tests that compare
//! the fast path with an independent computation.

use std::f64::consts::{FRAC_PI_2, PI};

use kinema::nalgebra::{Matrix3, Rotation3, Unit, Vector3};
use kinema::{DhConvention, GeometryKind, Joint, JointType, Limits, LinkGeometry, Model, Pose, Robot};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

pub fn random_rotation(rng: &mut ChaCha8Rng) -> Matrix3<f64> {
    let axis = Vector3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
    let axis = if axis.norm() < 1e-3 { Vector3::z() } else { axis };
    *Rotation3::from_axis_angle(&Unit::new_normalize(axis), rng.random_range(-PI..PI)).matrix()
}

/// The identity (40 %) or a random rotation with a translation of up to 0.5 m per axis.
pub fn random_pose(rng: &mut ChaCha8Rng) -> Pose {
    if rng.random_bool(0.4) {
        return Pose::IDENTITY;
    }
    let pos = Vector3::new(rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5));
    Pose::new(random_rotation(rng), pos)
}

/// A twist that hits each of the chain's forms: 0, ±90°, ±180°, or any angle.
pub fn random_twist(rng: &mut ChaCha8Rng) -> f64 {
    match rng.random_range(0..7) {
        0 => 0.0,
        1 => FRAC_PI_2,
        2 => -FRAC_PI_2,
        3 => PI,
        4 => -PI,
        _ => rng.random_range(-PI..PI),
    }
}

/// A random joint; with `uniform`, a revolute joint of that DH convention
/// with an exact twist (0, ±90°, ±180°), so that a chain of them is one of
/// the compiled chain's uniform straight-line shapes.
pub fn random_joint(rng: &mut ChaCha8Rng, i: usize, uniform: Option<DhConvention>) -> Joint {
    let kind = if uniform.is_none() && rng.random_bool(0.25) { JointType::Prismatic } else { JointType::Revolute };
    let len = |rng: &mut ChaCha8Rng| if rng.random_bool(0.3) { 0.0 } else { rng.random_range(-0.6..0.6) };
    let dh = |convention, rng: &mut ChaCha8Rng| LinkGeometry::Dh {
        convention,
        d: len(rng),
        a: len(rng),
        alpha: if uniform.is_some() {
            [0.0, FRAC_PI_2, -FRAC_PI_2, PI, -PI][rng.random_range(0..5)]
        } else {
            random_twist(rng)
        },
        theta: if rng.random_bool(0.5) { 0.0 } else { rng.random_range(-PI..PI) },
    };
    let geometry = match uniform {
        Some(convention) => dh(convention, rng),
        None => random_geometry(rng, dh),
    };
    let offset = if rng.random_bool(0.5) { 0.0 } else { rng.random_range(-1.0..1.0) };
    Joint { name: format!("j{}", i + 1), kind, geometry, offset, limits: Limits::position(-PI, PI) }
}

/// A DH row of either convention (from `dh`) or a general joint about or
/// along +z, −z or any axis.
pub fn random_geometry(
    rng: &mut ChaCha8Rng,
    dh: impl Fn(DhConvention, &mut ChaCha8Rng) -> LinkGeometry,
) -> LinkGeometry {
    match rng.random_range(0..5) {
        0 | 1 => dh(DhConvention::Standard, rng),
        2 | 3 => dh(DhConvention::Modified, rng),
        _ => {
            let axis = match rng.random_range(0..3) {
                0 => Vector3::z(),
                1 => -Vector3::z(),
                _ => random_rotation(rng) * Vector3::z(),
            };
            LinkGeometry::General { origin: random_pose(rng), axis }
        }
    }
}

/// A robot of `joints` with the given base and tool transforms (limits ±π, home at 0).
pub fn robot_of(joints: Vec<Joint>, base: Pose, tool: Pose) -> Robot {
    let n = joints.len();
    Model::builder("random", GeometryKind::Standard)
        .joints(joints)
        .base(base)
        .tool(tool)
        .pose("home", vec![0.0; n])
        .build()
        .map(Robot::new)
        .expect("random robot is valid")
}

/// A random arm of `n` joints (see [`random_joint`] for `uniform`) with a
/// random base and tool.
pub fn random_arm(rng: &mut ChaCha8Rng, n: usize, uniform: Option<DhConvention>) -> Robot {
    let joints: Vec<Joint> = (0..n).map(|i| random_joint(rng, i, uniform)).collect();
    let base = random_pose(rng);
    robot_of(joints, base, random_pose(rng))
}

/// A random arm: mostly arm-sized (1 to 8 joints), some longer than one
/// eight-joint block (9 to 20); a third are uniform chains of standard or of
/// modified DH revolute joints with exact twists (the catalogue's arms are
/// such chains), the others mix every kind.
pub fn random_robot(rng: &mut ChaCha8Rng) -> Robot {
    let n = if rng.random_bool(0.8) { rng.random_range(1..=8) } else { rng.random_range(9..=20) };
    let uniform = match rng.random_range(0..6) {
        0 => Some(DhConvention::Standard),
        1 => Some(DhConvention::Modified),
        _ => None,
    };
    random_arm(rng, n, uniform)
}

/// `n` joint values drawn from [−π, π).
pub fn random_q(rng: &mut ChaCha8Rng, n: usize) -> Vec<f64> {
    (0..n).map(|_| rng.random_range(-PI..PI)).collect()
}

/// One joint of every kind the model describes: both DH conventions,
/// revolute and prismatic, the twists the chain treats apart (0, ±90°, 180°)
/// and another, with and without a fixed θ; general joints, revolute and
/// prismatic, about or along +z, −z, x and a skew axis, behind a fixed
/// transform. All with a joint offset.
pub fn every_joint_kind() -> Vec<Joint> {
    let mut geometries = Vec::new();
    for convention in [DhConvention::Standard, DhConvention::Modified] {
        for alpha in [0.0, FRAC_PI_2, -FRAC_PI_2, PI, 0.7] {
            for theta in [0.0, 0.3] {
                geometries.push(LinkGeometry::Dh { convention, d: 0.2, a: -0.1, alpha, theta });
            }
        }
    }
    let origin = Pose::rot_x(0.4) * Pose::translation(0.1, -0.2, 0.3);
    let skew = Vector3::new(0.3, -0.5, 0.2).normalize();
    for axis in [Vector3::z(), -Vector3::z(), Vector3::x(), skew] {
        geometries.push(LinkGeometry::General { origin, axis });
    }
    let mut joints = Vec::new();
    for geometry in geometries {
        for kind in [JointType::Revolute, JointType::Prismatic] {
            joints.push(Joint { name: "j".into(), kind, geometry, offset: 0.1, limits: Limits::position(-PI, PI) });
        }
    }
    joints
}
