//! Where URDF links ride (`Robot::from_urdf_str_with_links`): each link's
//! pose, through its kinema link frame, equals a plain walk of the URDF tree
//! from the root with the chain's joints at q and every other joint at 0.

use std::collections::HashMap;
use std::path::Path;

use kinema::nalgebra::{Rotation3, Unit, Vector3};
use kinema::{Pose, Robot, RpyConvention};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// The root-from-link pose of every link of `u`, with `q` by joint name.
fn plain_walk(u: &urdf_rs::Robot, q: &HashMap<String, f64>) -> HashMap<String, Pose> {
    let by_child: HashMap<&str, &urdf_rs::Joint> = u.joints.iter().map(|j| (j.child.link.as_str(), j)).collect();
    let pose_of = |name: &str| {
        let mut pose = Pose::IDENTITY;
        let mut at = name;
        while let Some(j) = by_child.get(at) {
            let origin = Pose::from_xyz_rpy(*j.origin.xyz, *j.origin.rpy, RpyConvention::Zyx);
            let v = q.get(&j.name).copied().unwrap_or(0.0);
            let axis = Unit::new_normalize(Vector3::from(*j.axis.xyz));
            let motion = match j.joint_type {
                urdf_rs::JointType::Prismatic => Pose::new(Rotation3::identity().into_inner(), axis.into_inner() * v),
                urdf_rs::JointType::Fixed => Pose::IDENTITY,
                _ => Pose::new(Rotation3::from_axis_angle(&axis, v).into_inner(), Vector3::zeros()),
            };
            pose = origin * motion * pose;
            at = j.parent.link.as_str();
        }
        pose
    };
    u.links.iter().map(|l| (l.name.clone(), pose_of(&l.name))).collect()
}

#[test]
fn every_link_rides_its_body() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let mut rng = ChaCha8Rng::seed_from_u64(0x11AC);
    for (file, tip) in [
        ("ros-industrial.urdf", None),
        ("off-chain-inertia.urdf", Some("r_tool")),
        ("two-leaves.urdf", Some("leaf_a")),
        ("iiwa14.urdf", None),
        ("kr16-like.urdf", None),
    ] {
        let text = std::fs::read_to_string(dir.join(file)).unwrap();
        let (robot, links) = Robot::from_urdf_str_with_links(&text, file, tip).unwrap();
        assert_eq!(robot, Robot::from_urdf_str(&text, file, tip).unwrap(), "{file}: the same robot");
        let u = urdf_rs::read_from_string(&text).unwrap();
        assert_eq!(links.len(), u.links.len(), "{file}: one entry per <link>");
        for _ in 0..50 {
            let q = robot.random_q(&mut rng);
            let frames = robot.link_frames(&q).unwrap();
            let by_name: HashMap<String, f64> =
                robot.model().joints().iter().zip(&q).map(|(j, v)| (j.name.clone(), *v)).collect();
            let walked = plain_walk(&u, &by_name);
            for l in &links {
                assert!(l.link <= robot.dof(), "{file}: link `{}` on {}", l.name, l.link);
                let ours = frames[l.link] * l.link_from_urdf;
                let plain = walked[&l.name];
                let err = (ours.pos - plain.pos).norm() + (ours.rot - plain.rot).norm();
                assert!(err < 1e-12, "{file}: link `{}` (on body {}) is off by {err:e}", l.name, l.link);
            }
        }
    }
}
