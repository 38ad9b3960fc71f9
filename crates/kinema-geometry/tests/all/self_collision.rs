//! Self-collision of a UR5 made of capsules (one per link, from its joint
//! axis to the next, as in a UR5 the links are round tubes): on seeded random
//! configurations the minimum distance equals a brute force over all pairs
//! with parry directly and the closed form of capsule pairs; `collides` and
//! `contacts` agree with its sign, and with a safety margin.

use kinema::nalgebra::{UnitQuaternion, Vector3};
use kinema::{Pose, Robot};
use kinema_geometry::parry3d_f64::query;
use kinema_geometry::parry3d_f64::shape::Capsule;
use kinema_geometry::{
    collides, contacts, min_distance, place, CollisionPairs, LinkShape, Placement, RobotGeometry, Shape,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::common::{capsule_ends, closest_on_segments};

const RADIUS: f64 = 0.045;
/// The pedestal under the base: radius and length \[m\].
const PEDESTAL: (f64, f64) = (0.04, 0.1);

/// Link i's capsule runs from frame i's origin to frame i−1's origin, a point
/// on joint i's axis and so fixed in link i's frame (standard DH).
fn capsule_arm() -> (Robot, RobotGeometry, Vec<f64>) {
    let robot = Robot::builtin("ur5").unwrap();
    let frames = robot.link_frames(robot.home()).unwrap();
    let (radius, length) = PEDESTAL;
    let pedestal = Shape::Capsule { radius, length };
    let mut shapes = vec![LinkShape::new("pedestal", 0, Pose::translation(0.0, 0.0, -0.1), pedestal).unwrap()];
    let mut lengths = vec![length];
    for i in 1..=robot.dof() {
        let p = frames[i].inverse().transform_point(&frames[i - 1].pos);
        let length = p.norm();
        // z turned onto p (half a turn about x when p points down z).
        let rot = UnitQuaternion::rotation_between(&Vector3::z(), &p)
            .unwrap_or_else(|| UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI));
        let pose = Pose::new(rot.to_rotation_matrix().into_inner(), p / 2.0);
        shapes.push(LinkShape::new(format!("link{i}"), i, pose, Shape::Capsule { radius: RADIUS, length }).unwrap());
        lengths.push(length);
    }
    let geometry = RobotGeometry::new(&robot, shapes).unwrap();
    (robot, geometry, lengths)
}

#[test]
fn capsules_are_rigid_on_their_links() {
    // The end at frame i−1's origin stays there whatever q is.
    let (robot, geometry, lengths) = capsule_arm();
    let mut rng = ChaCha8Rng::seed_from_u64(0xA11);
    for _ in 0..100 {
        let q = robot.random_q(&mut rng);
        let placement = Placement::of(&robot, &geometry, &q).unwrap();
        for (i, length) in lengths.iter().enumerate().skip(1) {
            let (_, far) = capsule_ends(&placement.world_from_shape(&geometry, i), *length);
            assert!((far.coords - placement.frames()[i - 1].pos).norm() < 1e-12, "link {i}");
        }
    }
}

#[test]
fn min_distance_and_collides_agree_with_brute_force() {
    let (robot, geometry, lengths) = capsule_arm();
    let pairs = CollisionPairs::self_collision(&geometry);
    assert_eq!(pairs.len(), 21 - 6);
    let mut placement = Placement::new(&geometry);
    let mut rng = ChaCha8Rng::seed_from_u64(0x5E1F);
    let margin = 0.03;
    let (mut free, mut hit) = (0, 0);
    for _ in 0..3000 {
        let q = robot.random_q(&mut rng);
        place(&robot, &geometry, &q, &mut placement).unwrap();
        // Brute force: every pair, parry called directly on poses built here
        // (its distance is 0 for overlapping shapes, and its penetration
        // depth is inexact for capsules overlapping along a common axis, so
        // depths are checked against the closed form of capsule pairs).
        let mut brute = (f64::INFINITY, (0, 0));
        let mut brute_hit = false;
        let mut closed = f64::INFINITY;
        for (a, b) in pairs.iter() {
            let (pa, pb) = (placement.world_from_shape(&geometry, a), placement.world_from_shape(&geometry, b));
            let (ra, rb) = (if a == 0 { PEDESTAL.0 } else { RADIUS }, if b == 0 { PEDESTAL.0 } else { RADIUS });
            let (ca, cb) = (Capsule::new_z(lengths[a] / 2.0, ra), Capsule::new_z(lengths[b] / 2.0, rb));
            let (ia, ib) = (iso(&pa), iso(&pb));
            let d = query::distance(&ia, &ca, &ib, &cb).unwrap();
            if d < brute.0 {
                brute = (d, (a, b));
            }
            brute_hit |= query::intersection_test(&ia, &ca, &ib, &cb).unwrap();
            let (a0, a1) = capsule_ends(&pa, lengths[a]);
            let (b0, b1) = capsule_ends(&pb, lengths[b]);
            let (x, y) = closest_on_segments(a0, a1, b0, b1);
            closed = closed.min((y - x).norm() - ra - rb);
        }
        let near = min_distance(&geometry, &placement, &pairs).unwrap().unwrap();
        // Parry's GJK stops within ~1e-7 m on round shapes; the closed form is exact.
        assert!((near.distance.max(0.0) - brute.0).abs() < 1e-6, "q = {q:?}: {} ≠ brute {}", near.distance, brute.0);
        assert!((near.distance - closed).abs() < 1e-9, "q = {q:?}: {} ≠ closed form {closed}", near.distance);
        if near.distance > 1e-9 && (near.a, near.b) != brute.1 {
            // Only a tie may name another pair.
            let other = kinema_geometry::pair_distance(&geometry, &placement, brute.1 .0, brute.1 .1).unwrap();
            assert!((other.distance - near.distance).abs() < 1e-6);
        }
        if near.distance.abs() > 1e-9 {
            assert_eq!(brute_hit, near.distance < 0.0, "parry's intersection test, q = {q:?}");
        }
        if near.distance.abs() > 1e-9 {
            let collides_now = collides(&geometry, &placement, &pairs, 0.0).unwrap();
            assert_eq!(collides_now.is_some(), near.distance < 0.0, "q = {q:?}");
            let touching = contacts(&geometry, &placement, &pairs, 0.0).unwrap();
            assert_eq!(!touching.is_empty(), near.distance < 0.0);
            assert!(touching.iter().all(|c| c.distance <= 0.0 && pairs.contains(c.a, c.b)));
            if let Some((a, b)) = collides_now {
                assert!(touching.iter().any(|c| (c.a, c.b) == (a, b)), "the first pair is a contact");
                hit += 1;
            } else {
                free += 1;
            }
        }
        if (near.distance - margin).abs() > 1e-9 {
            let within = collides(&geometry, &placement, &pairs, margin).unwrap();
            assert_eq!(within.is_some(), near.distance < margin, "margin, q = {q:?}");
            let all_within = contacts(&geometry, &placement, &pairs, margin).unwrap();
            assert_eq!(all_within.is_empty(), within.is_none());
        }
    }
    assert!(free > 300 && hit > 300, "{free} free, {hit} in collision");
}

#[test]
fn adjacent_links_are_not_checked() {
    // Neighbouring capsules share an end, so they always touch; the
    // self-collision pairs report exactly the other contacts.
    let (robot, geometry, _) = capsule_arm();
    let mut rng = ChaCha8Rng::seed_from_u64(0xAD1);
    let all = CollisionPairs::all(&geometry);
    let pairs = CollisionPairs::self_collision(&geometry);
    for _ in 0..200 {
        let placement = Placement::of(&robot, &geometry, &robot.random_q(&mut rng)).unwrap();
        let touching = contacts(&geometry, &placement, &all, 0.0).unwrap();
        // Shape i rides on link i.
        for i in 0..robot.dof() {
            let d = kinema_geometry::pair_distance(&geometry, &placement, i, i + 1).unwrap();
            assert!(touching.iter().any(|c| (c.a, c.b) == (i, i + 1)), "{i} and {}: {d:?}", i + 1);
        }
        let others: Vec<(usize, usize)> = touching.iter().filter(|c| c.b > c.a + 1).map(|c| (c.a, c.b)).collect();
        let checked: Vec<(usize, usize)> =
            contacts(&geometry, &placement, &pairs, 0.0).unwrap().iter().map(|c| (c.a, c.b)).collect();
        assert_eq!(checked, others);
    }
    let mut srdf_like = pairs.clone();
    assert_eq!(srdf_like.disable_links(&geometry, "link 6", "link 4"), 1);
    assert!(!srdf_like.contains(4, 6) && pairs.contains(4, 6));
    assert_eq!(srdf_like.len(), pairs.len() - 1);
}

fn iso(p: &Pose) -> kinema::nalgebra::Isometry3<f64> {
    kinema::nalgebra::Isometry3::from_parts(p.pos.into(), p.quaternion())
}
