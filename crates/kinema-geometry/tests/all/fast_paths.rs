//! The fast paths answer as their plain references do: `min_distance`
//! (pairs by box gap, a bound that skips the rest, convex meshes measured as
//! their hulls) against `min_distance_reference` (every pair in full), and
//! `collides_fast` and `collides` against each other, over thousands of
//! seeded configurations of capsule arms and arms carrying convex and
//! non-convex triangle meshes.

use std::sync::Arc;

use kinema::nalgebra::{Point3, UnitQuaternion, Vector3};
use kinema::{Pose, Robot};
use kinema_geometry::{
    collides, collides_fast, min_distance, min_distance_reference, pair_distance, CollisionPairs, LinkShape, Mesh,
    Placement, RobotGeometry, Shape, Spheres,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common::random_pose;

/// How far the fast and the reference distance may differ \[m\].
const TOLERANCE: f64 = 1e-9;

/// A UV sphere stretched along the axes: a closed convex surface.
fn ellipsoid(rng: &mut impl Rng) -> Arc<Mesh> {
    let stretch = Vector3::new(rng.random_range(0.02..0.2), rng.random_range(0.02..0.1), rng.random_range(0.02..0.1));
    let (rings, around) = (rng.random_range(3..7u32), rng.random_range(4..10u32));
    let mut vertices = vec![Point3::new(0.0, 0.0, -stretch.z), Point3::new(0.0, 0.0, stretch.z)];
    for r in 1..rings {
        let polar = std::f64::consts::PI * r as f64 / rings as f64;
        for k in 0..around {
            let azimuth = std::f64::consts::TAU * k as f64 / around as f64;
            let unit = Vector3::new(polar.sin() * azimuth.cos(), polar.sin() * azimuth.sin(), -polar.cos());
            vertices.push(Point3::from(unit.component_mul(&stretch)));
        }
    }
    let at = |r: u32, k: u32| 2 + (r - 1) * around + k % around;
    let mut triangles = Vec::new();
    for k in 0..around {
        triangles.push([0, at(1, k + 1), at(1, k)]);
        triangles.push([1, at(rings - 1, k), at(rings - 1, k + 1)]);
        for r in 1..rings - 1 {
            triangles.push([at(r, k), at(r, k + 1), at(r + 1, k + 1)]);
            triangles.push([at(r, k), at(r + 1, k + 1), at(r + 1, k)]);
        }
    }
    Arc::new(Mesh::new(vertices, triangles, "ellipsoid").unwrap())
}

/// A strip of random triangles: a surface that is not convex.
fn strip(rng: &mut impl Rng) -> Arc<Mesh> {
    let n = rng.random_range(6..14);
    let vertices = (0..n).map(|_| Point3::from(Vector3::from_fn(|_, _| rng.random_range(-0.08..0.08)))).collect();
    Arc::new(Mesh::new(vertices, (0..n as u32 - 2).map(|i| [i, i + 1, i + 2]).collect(), "strip").unwrap())
}

fn random_shape(rng: &mut impl Rng) -> Shape {
    match rng.random_range(0..6) {
        0 => Shape::Sphere { radius: rng.random_range(0.01..0.1) },
        1 => Shape::Box { size: Vector3::from_fn(|_, _| rng.random_range(0.02..0.2)) },
        2 => Shape::Capsule { radius: rng.random_range(0.01..0.06), length: rng.random_range(0.0..0.3) },
        3 => Shape::TriangleMesh(strip(rng)),
        _ => Shape::TriangleMesh(ellipsoid(rng)),
    }
}

/// A built-in arm with a random shape or two on every link, meshes most often.
fn random_arm(rng: &mut impl Rng) -> (Robot, RobotGeometry) {
    let robot = Robot::builtin(["ur5", "panda", "lbr-iiwa-14-r820"][rng.random_range(0..3)]).unwrap();
    let mut shapes = Vec::new();
    for link in 0..=robot.dof() {
        for k in 0..rng.random_range(1..3) {
            let shape = random_shape(rng);
            shapes.push(LinkShape::new(format!("l{link}_{k}"), link, random_pose(rng, 0.12), shape).unwrap());
        }
    }
    (robot.clone(), RobotGeometry::new(&robot, shapes).unwrap())
}

/// The built-in Panda with a capsule along every link.
fn capsule_panda() -> (Robot, RobotGeometry) {
    let robot = Robot::builtin("panda").unwrap();
    let frames = robot.link_frames(robot.home()).unwrap();
    let shapes = (1..=robot.dof())
        .map(|i| {
            let p = frames[i].inverse().transform_point(&frames[i - 1].pos);
            let rot = UnitQuaternion::rotation_between(&Vector3::z(), &p).unwrap_or_else(UnitQuaternion::identity);
            let pose = Pose::new(rot.to_rotation_matrix().into_inner(), p / 2.0);
            LinkShape::new(format!("link{i}"), i, pose, Shape::Capsule { radius: 0.05, length: p.norm() }).unwrap()
        })
        .collect();
    (robot.clone(), RobotGeometry::new(&robot, shapes).unwrap())
}

/// Asserts that `min_distance` finds the reference's distance, at the
/// reference's pair or at a pair exactly as close.
pub fn assert_same_closest(geometry: &RobotGeometry, placement: &Placement, pairs: &CollisionPairs, what: &str) {
    let fast = min_distance(geometry, placement, pairs).unwrap();
    let reference = min_distance_reference(geometry, placement, pairs).unwrap();
    let (Some(fast), Some(reference)) = (fast, reference) else {
        assert_eq!(fast.is_none(), reference.is_none(), "{what}");
        return;
    };
    let kinds = |a: usize, b: usize| [a, b].map(|i| geometry.shapes()[i].shape().kind());
    let (fk, rk) = (kinds(fast.a, fast.b), kinds(reference.a, reference.b));
    assert!(
        (fast.distance - reference.distance).abs() <= TOLERANCE,
        "{what}: {fast:?} ({fk:?}) against {reference:?} ({rk:?})"
    );
    if (fast.a, fast.b) != (reference.a, reference.b) {
        let there = pair_distance(geometry, placement, fast.a, fast.b).unwrap().distance;
        assert!((there - reference.distance).abs() <= TOLERANCE, "{what}: pair {fast:?} is not the closest");
    }
}

/// The reference verdict: the first pair whose full distance (no hulls, no
/// boxes) is below `margin`, or that touches.
pub fn first_closer(
    geometry: &RobotGeometry,
    placement: &Placement,
    pairs: &CollisionPairs,
    margin: f64,
) -> Option<(usize, usize)> {
    pairs.iter().find(|&(a, b)| {
        let d = pair_distance(geometry, placement, a, b).unwrap().distance;
        d < margin || d <= 0.0
    })
}

#[test]
fn convex_surfaces_are_found_and_strips_are_not() {
    let mut rng = ChaCha8Rng::seed_from_u64(37);
    for _ in 0..50 {
        let convex = LinkShape::new("e", 0, Pose::IDENTITY, Shape::TriangleMesh(ellipsoid(&mut rng))).unwrap();
        let strip = LinkShape::new("s", 0, Pose::IDENTITY, Shape::TriangleMesh(strip(&mut rng))).unwrap();
        assert!(convex.is_convex_mesh() && !strip.is_convex_mesh());
    }
}

#[test]
fn min_distance_matches_the_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(37);
    let (robot, geometry) = capsule_panda();
    let pairs = CollisionPairs::self_collision(&geometry);
    for _ in 0..2000 {
        let q = robot.random_q(&mut rng);
        assert_same_closest(
            &geometry,
            &Placement::of(&robot, &geometry, &q).unwrap(),
            &pairs,
            &format!("capsules {q:?}"),
        );
    }
    let mut overlapping = 0;
    for arm in 0..40 {
        let (robot, geometry) = random_arm(&mut rng);
        let pairs = CollisionPairs::self_collision(&geometry);
        for _ in 0..50 {
            let q = robot.random_q(&mut rng);
            let placement = Placement::of(&robot, &geometry, &q).unwrap();
            assert_same_closest(&geometry, &placement, &pairs, &format!("arm {arm}, q {q:?}"));
            overlapping +=
                usize::from(min_distance(&geometry, &placement, &pairs).unwrap().is_some_and(|p| p.distance <= 0.0));
        }
    }
    // Both separated and overlapping closest pairs occur often enough to mean something.
    assert!((200..1800).contains(&overlapping), "{overlapping} of 2000 overlapping");
}

#[test]
fn collides_fast_matches_collides_with_convex_meshes() {
    let mut rng = ChaCha8Rng::seed_from_u64(2026);
    let mut hits = 0;
    for arm in 0..40 {
        let (robot, geometry) = random_arm(&mut rng);
        let pairs = CollisionPairs::self_collision(&geometry);
        let spheres = Spheres::fit(&geometry, 4);
        let (mut sp, mut placement) = (spheres.placement(), Placement::new(&geometry));
        for _ in 0..100 {
            let q = robot.random_q(&mut rng);
            let margin = if rng.random_bool(0.3) { rng.random_range(0.0..0.05) } else { 0.0 };
            let exact = collides(&geometry, &Placement::of(&robot, &geometry, &q).unwrap(), &pairs, margin).unwrap();
            let fast = collides_fast(&robot, &geometry, &spheres, &q, &pairs, margin, &mut sp, &mut placement).unwrap();
            let placed = Placement::of(&robot, &geometry, &q).unwrap();
            assert_eq!(fast, exact, "arm {arm}, q {q:?}, margin {margin}");
            assert_eq!(exact, first_closer(&geometry, &placed, &pairs, margin), "arm {arm}, q {q:?}, margin {margin}");
            hits += usize::from(exact.is_some());
        }
    }
    assert!((400..3600).contains(&hits), "{hits} of 4000 colliding");
}
