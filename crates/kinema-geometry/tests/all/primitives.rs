//! Primitive pairs against closed forms on seeded random poses: the signed
//! distance, witness points on both surfaces and apart by the distance, and
//! `collides` / `contacts` agreeing with the sign (and the safety margin).

use kinema::nalgebra::{Point3, Vector3};
use kinema::{Pose, Robot};
use kinema_geometry::{
    collides, contacts, min_distance, CollisionPairs, LinkShape, Placement, Proximity, RobotGeometry, Shape,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common::{capsule_ends, closest_on_segments, point_segment_distance, random_pose};

const CASES: usize = 3000;

/// Both shapes on the base of a UR5 at home, at the given poses; the pair's
/// proximity, its placement world poses, and whether `collides` said so at
/// margin 0 and at `margin`.
struct Case {
    near: Proximity,
    pose_a: Pose,
    pose_b: Pose,
    hit: bool,
    hit_margin: bool,
    contacts: usize,
}

const MARGIN: f64 = 0.05;

fn case(robot: &Robot, a: (Shape, Pose), b: (Shape, Pose)) -> Case {
    let shapes = vec![LinkShape::new("a", 0, a.1, a.0).unwrap(), LinkShape::new("b", 0, b.1, b.0).unwrap()];
    let geometry = RobotGeometry::new(robot, shapes).unwrap();
    let placement = Placement::of(robot, &geometry, robot.home()).unwrap();
    let pairs = CollisionPairs::from_pairs(&geometry, [(0, 1)]).unwrap();
    let near = min_distance(&geometry, &placement, &pairs).unwrap().unwrap();
    Case {
        near,
        pose_a: placement.world_from_shape(&geometry, 0),
        pose_b: placement.world_from_shape(&geometry, 1),
        hit: collides(&geometry, &placement, &pairs, 0.0).unwrap().is_some(),
        hit_margin: collides(&geometry, &placement, &pairs, MARGIN).unwrap().is_some(),
        contacts: contacts(&geometry, &placement, &pairs, 0.0).unwrap().len(),
    }
}

/// The checks every pair shares, given the closed-form signed distance and
/// each shape's closed-form distance from a point (0 on its surface).
fn check(c: &Case, expected: f64, surface_a: impl Fn(Point3<f64>) -> f64, surface_b: impl Fn(Point3<f64>) -> f64) {
    let tol = if expected > 0.0 { 1e-9 } else { 1e-6 };
    assert!((c.near.distance - expected).abs() < tol, "distance {} ≠ {expected}", c.near.distance);
    if expected.abs() > 1e-6 {
        assert_eq!(c.hit, expected < 0.0, "collides at distance {expected}");
        assert_eq!(c.contacts > 0, expected < 0.0, "contacts at distance {expected}");
    }
    if (expected - MARGIN).abs() > 1e-6 {
        assert_eq!(c.hit_margin, expected < MARGIN, "collides with margin {MARGIN} at distance {expected}");
    }
    assert!(surface_a(c.near.point_a).abs() < tol, "point_a off a's surface by {}", surface_a(c.near.point_a));
    assert!(surface_b(c.near.point_b).abs() < tol, "point_b off b's surface by {}", surface_b(c.near.point_b));
    if expected > 0.0 {
        assert!(((c.near.point_b - c.near.point_a).norm() - expected).abs() < 1e-9, "witnesses not {expected} apart");
        assert!((c.near.normal - (c.near.point_b - c.near.point_a) / expected).norm() < 1e-6, "normal");
    }
}

#[test]
fn sphere_sphere() {
    let robot = Robot::builtin("ur5").unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0x5EED_0001);
    let (mut apart, mut overlapping) = (0, 0);
    for _ in 0..CASES {
        let (ra, rb) = (rng.random_range(0.05..0.5), rng.random_range(0.05..0.5));
        let c = case(
            &robot,
            (Shape::Sphere { radius: ra }, random_pose(&mut rng, 0.6)),
            (Shape::Sphere { radius: rb }, random_pose(&mut rng, 0.6)),
        );
        let (ca, cb) = (Point3::from(c.pose_a.pos), Point3::from(c.pose_b.pos));
        let expected = (cb - ca).norm() - ra - rb;
        check(&c, expected, |p| (p - ca).norm() - ra, |p| (p - cb).norm() - rb);
        if expected > 0.0 {
            apart += 1;
            // The witness points lie on the line of centres.
            let u = (cb - ca).normalize();
            assert!((c.near.point_a - (ca + u * ra)).norm() < 1e-9);
        } else {
            overlapping += 1;
        }
    }
    assert!(apart > CASES / 5 && overlapping > CASES / 5, "{apart} apart, {overlapping} overlapping");
}

/// Signed distance from `p` (box frame) to a box of half extents `h`.
fn box_signed(p: Vector3<f64>, h: Vector3<f64>) -> f64 {
    let q = p.abs() - h;
    let outside = q.map(|v| v.max(0.0)).norm();
    outside + q.max().min(0.0)
}

#[test]
fn box_sphere() {
    let robot = Robot::builtin("ur5").unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0x5EED_0002);
    let (mut apart, mut overlapping) = (0, 0);
    for _ in 0..CASES {
        let size = Vector3::from_fn(|_, _| rng.random_range(0.05..0.8));
        let r = rng.random_range(0.05..0.4);
        let c = case(
            &robot,
            (Shape::Box { size }, random_pose(&mut rng, 0.6)),
            (Shape::Sphere { radius: r }, random_pose(&mut rng, 0.6)),
        );
        let h = size / 2.0;
        let box_from_world = c.pose_a.inverse();
        let centre = Point3::from(c.pose_b.pos);
        let local = box_from_world.transform_point(&centre.coords);
        let expected = box_signed(local, h) - r;
        let on_box = |p: Point3<f64>| box_signed(box_from_world.transform_point(&p.coords), h);
        check(&c, expected, on_box, |p| (p - centre).norm() - r);
        if expected > 0.0 {
            apart += 1;
        } else {
            overlapping += 1;
        }
    }
    assert!(apart > CASES / 5 && overlapping > CASES / 10, "{apart} apart, {overlapping} overlapping");
}

#[test]
fn capsule_capsule() {
    let robot = Robot::builtin("ur5").unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0x5EED_0003);
    let (mut apart, mut overlapping) = (0, 0);
    for i in 0..CASES {
        let (ra, rb) = (rng.random_range(0.03..0.3), rng.random_range(0.03..0.3));
        // Every tenth pair parallel: the closest points are not unique there.
        let (la, lb) = (rng.random_range(0.0..0.8), rng.random_range(0.0..0.8));
        let pose_a = random_pose(&mut rng, 0.6);
        let mut pose_b = random_pose(&mut rng, 0.6);
        if i % 10 == 0 {
            pose_b.rot = pose_a.rot;
        }
        let c = case(
            &robot,
            (Shape::Capsule { radius: ra, length: la }, pose_a),
            (Shape::Capsule { radius: rb, length: lb }, pose_b),
        );
        let (a0, a1) = capsule_ends(&c.pose_a, la);
        let (b0, b1) = capsule_ends(&c.pose_b, lb);
        let (pa, pb) = closest_on_segments(a0, a1, b0, b1);
        let expected = (pb - pa).norm() - ra - rb;
        check(&c, expected, |p| point_segment_distance(p, a0, a1) - ra, |p| point_segment_distance(p, b0, b1) - rb);
        if expected > 0.0 {
            apart += 1;
        } else {
            overlapping += 1;
        }
    }
    assert!(apart > CASES / 5 && overlapping > CASES / 10, "{apart} apart, {overlapping} overlapping");
}

#[test]
fn cylinder_stands_along_z() {
    // A cylinder of length 1 along z, a ball above its top face and one beside it.
    let robot = Robot::builtin("ur5").unwrap();
    let cyl = (Shape::Cylinder { radius: 0.1, length: 1.0 }, Pose::IDENTITY);
    let above = case(&robot, cyl.clone(), (Shape::Sphere { radius: 0.1 }, Pose::translation(0.0, 0.0, 0.8)));
    assert!((above.near.distance - 0.2).abs() < 1e-9, "{}", above.near.distance);
    let beside = case(&robot, cyl, (Shape::Sphere { radius: 0.1 }, Pose::translation(0.5, 0.0, 0.0)));
    assert!((beside.near.distance - 0.3).abs() < 1e-9, "{}", beside.near.distance);
}

#[test]
fn bad_dimensions_are_named() {
    for (shape, says) in [
        (Shape::Sphere { radius: -1.0 }, "radius is -1"),
        (Shape::Box { size: Vector3::new(1.0, f64::NAN, 1.0) }, "box size along y is NaN"),
        (Shape::Cylinder { radius: 0.1, length: 0.0 }, "length is 0"),
        (Shape::Capsule { radius: 0.0, length: 1.0 }, "radius is 0"),
    ] {
        let e = LinkShape::new("bad", 1, Pose::IDENTITY, shape).unwrap_err().to_string();
        assert!(e.contains("shape `bad`") && e.contains(says), "{e}");
    }
}
