//! Closed forms and small helpers shared by the test modules.

use kinema::nalgebra::{Point3, UnitQuaternion, Vector3};
use kinema::Pose;
use rand::Rng;

/// A random pose: position in a cube of ±`reach` m, rotation uniform.
pub fn random_pose(rng: &mut impl Rng, reach: f64) -> Pose {
    let pos = Vector3::from_fn(|_, _| rng.random_range(-reach..reach));
    // A normalised 4-vector of normal-ish components is a uniform rotation; a
    // uniform cube is close enough for coverage here.
    let q = kinema::nalgebra::Quaternion::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    );
    let rot = UnitQuaternion::from_quaternion(q).to_rotation_matrix().into_inner();
    Pose::new(rot, pos)
}

/// The closest points of segments p1–q1 and p2–q2 (Ericson, Real-Time
/// Collision Detection, §5.1.9).
pub fn closest_on_segments(
    p1: Point3<f64>,
    q1: Point3<f64>,
    p2: Point3<f64>,
    q2: Point3<f64>,
) -> (Point3<f64>, Point3<f64>) {
    let d1 = q1 - p1;
    let d2 = q2 - p2;
    let r = p1 - p2;
    let a = d1.dot(&d1);
    let e = d2.dot(&d2);
    let f = d2.dot(&r);
    let eps = 1e-15;
    let (s, t);
    if a <= eps && e <= eps {
        return (p1, p2);
    }
    if a <= eps {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(&r);
        if e <= eps {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(&d2);
            let denom = a * e - b * b;
            let mut s0 = if denom > eps { ((b * f - c * e) / denom).clamp(0.0, 1.0) } else { 0.0 };
            let mut t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t0 = 0.0;
                s0 = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t0 = 1.0;
                s0 = ((b - c) / a).clamp(0.0, 1.0);
            }
            s = s0;
            t = t0;
        }
    }
    (p1 + d1 * s, p2 + d2 * t)
}

/// Distance from point `x` to segment p–q.
pub fn point_segment_distance(x: Point3<f64>, p: Point3<f64>, q: Point3<f64>) -> f64 {
    let d = q - p;
    let len2 = d.dot(&d);
    let t = if len2 > 0.0 { ((x - p).dot(&d) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (x - (p + d * t)).norm()
}

/// The two end points (sphere centres) of a capsule of `length` along z of `pose`.
pub fn capsule_ends(pose: &Pose, length: f64) -> (Point3<f64>, Point3<f64>) {
    let half = Vector3::new(0.0, 0.0, length / 2.0);
    (Point3::from(pose.transform_point(&-half)), Point3::from(pose.transform_point(&half)))
}

/// The root-from-link pose of every link of a URDF, walking the tree from
/// the root with joint values by name (0 for joints not named).
pub fn urdf_walk(
    u: &urdf_rs::Robot,
    q: &std::collections::HashMap<String, f64>,
) -> std::collections::HashMap<String, Pose> {
    use kinema::nalgebra::{Rotation3, Unit};
    let pose_of = |name: &str| {
        let mut pose = Pose::IDENTITY;
        let mut at = name.to_string();
        while let Some(j) = u.joints.iter().find(|j| j.child.link == at) {
            let origin = Pose::from_xyz_rpy(*j.origin.xyz, *j.origin.rpy, kinema::RpyConvention::Zyx);
            let v = q.get(&j.name).copied().unwrap_or(0.0);
            let axis = Unit::new_normalize(Vector3::from(*j.axis.xyz));
            let motion = match j.joint_type {
                urdf_rs::JointType::Prismatic => Pose::new(Rotation3::identity().into_inner(), axis.into_inner() * v),
                urdf_rs::JointType::Fixed => Pose::IDENTITY,
                _ => Pose::new(Rotation3::from_axis_angle(&axis, v).into_inner(), Vector3::zeros()),
            };
            pose = origin * motion * pose;
            at = j.parent.link.clone();
        }
        pose
    };
    u.links.iter().map(|l| (l.name.clone(), pose_of(&l.name))).collect()
}

/// Whether samples every `step` \[rad, m\] (largest joint motion) along
/// the straight segment a → b, ends included, are all clear of `check`'s
/// pairs by its margin, on the exact shapes.
pub fn densely_clear(check: &kinema_geometry::CollisionCheck, a: &[f64], b: &[f64], step: f64) -> bool {
    let longest = a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    let n = (longest / step).ceil().max(1.0) as usize;
    let mut placement = check.placement();
    (0..=n).all(|k| {
        let s = k as f64 / n as f64;
        let q: Vec<f64> = a.iter().zip(b).map(|(x, y)| x + s * (y - x)).collect();
        check.place(&q, &mut placement).unwrap();
        kinema_geometry::collides(check.geometry(), &placement, check.pairs(), check.margin()).unwrap().is_none()
    })
}
