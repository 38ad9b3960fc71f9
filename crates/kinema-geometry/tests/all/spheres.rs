//! The conservative fast path: the fitted spheres contain every sampled
//! point of every kind of shape, and over thousands of seeded random arms,
//! obstacles and configurations the spheres never say "free" where the exact
//! shapes collide, and `collides_fast` answers as `collides` does.

use std::sync::Arc;

use kinema::nalgebra::{Point3, Vector3};
use kinema::Robot;
use kinema_geometry::{
    collides, collides_fast, spheres_free, CollisionPairs, LinkShape, Mesh, Placement, RobotGeometry, Shape, Spheres,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common::random_pose;

fn random_mesh(rng: &mut impl Rng) -> Arc<Mesh> {
    let stretch = Vector3::new(rng.random_range(0.02..0.3), rng.random_range(0.02..0.1), rng.random_range(0.01..0.1));
    let n = rng.random_range(6..20);
    let vertices: Vec<Point3<f64>> =
        (0..n).map(|_| Point3::from(Vector3::from_fn(|i, _| rng.random_range(-1.0..1.0) * stretch[i]))).collect();
    let triangles = (0..n as u32 - 2).map(|i| [i, i + 1, i + 2]).collect();
    Arc::new(Mesh::new(vertices, triangles, "random").unwrap())
}

fn random_shape(rng: &mut impl Rng) -> Shape {
    let kind = rng.random_range(0..6);
    let mut len = || rng.random_range(0.01..0.4);
    match kind {
        0 => Shape::Sphere { radius: len() / 2.0 },
        1 => Shape::Box { size: Vector3::new(len(), len(), len()) },
        2 => Shape::Cylinder { radius: len() / 4.0, length: len() },
        3 => Shape::Capsule { radius: len() / 4.0, length: len() },
        4 => Shape::ConvexMesh(random_mesh(&mut *rng)),
        _ => Shape::TriangleMesh(random_mesh(&mut *rng)),
    }
}

/// Points of `shape` (its frame): on its surface and inside.
fn sample_points(shape: &Shape, rng: &mut impl Rng, n: usize) -> Vec<Point3<f64>> {
    fn unit(rng: &mut impl Rng) -> Vector3<f64> {
        let v = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0f64));
        v.try_normalize(1e-9).unwrap_or(Vector3::x())
    }
    let mut out = Vec::new();
    for k in 0..n {
        let surface = k % 2 == 0;
        let (u, d) = (rng.random_range(0.0..=1.0f64), unit(rng));
        let depth = if surface { 1.0 } else { rng.random_range(0.0..=1.0f64) };
        let p = match shape {
            Shape::Sphere { radius } => d * *radius * depth,
            Shape::Box { size } => {
                let mut p = Vector3::from_fn(|i, _| rng.random_range(-0.5..=0.5) * size[i]);
                if surface {
                    let axis = rng.random_range(0..3);
                    p[axis] = size[axis] / 2.0 * if rng.random_bool(0.5) { 1.0 } else { -1.0 };
                }
                p
            }
            Shape::Cylinder { radius, length } => {
                let rim = Vector3::new(d.x, d.y, 0.0).try_normalize(1e-9).unwrap_or(Vector3::x());
                let z = if surface { length / 2.0 * d.z.signum() } else { (u - 0.5) * length };
                rim * *radius * depth + Vector3::new(0.0, 0.0, z)
            }
            Shape::Capsule { radius, length } => Vector3::new(0.0, 0.0, (u - 0.5) * length) + d * *radius * depth,
            Shape::ConvexMesh(m) | Shape::TriangleMesh(m) => {
                // A point of a triangle (the surface), or a convex combination of all
                // vertices (inside the hull).
                let weights: Vec<f64> = if surface {
                    let t = m.triangles[rng.random_range(0..m.triangles.len())];
                    let (a, b) = (rng.random_range(0.0..1.0f64), rng.random_range(0.0..1.0f64));
                    let (a, b) = if a + b > 1.0 { (1.0 - a, 1.0 - b) } else { (a, b) };
                    let mut w = vec![0.0; m.vertices.len()];
                    w[t[0] as usize] += 1.0 - a - b;
                    w[t[1] as usize] += a;
                    w[t[2] as usize] += b;
                    w
                } else {
                    let w: Vec<f64> = (0..m.vertices.len()).map(|_| rng.random_range(0.0..1.0f64).powi(8)).collect();
                    let s: f64 = w.iter().sum();
                    w.iter().map(|x| x / s).collect()
                };
                m.vertices.iter().zip(&weights).fold(Vector3::zeros(), |s, (v, w)| s + v.coords * *w)
            }
        };
        out.push(Point3::from(p));
    }
    out
}

#[test]
fn spheres_contain_every_sampled_point_of_every_shape() {
    let robot = Robot::builtin("ur5").unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(37);
    for case in 0..2000 {
        let shape = random_shape(&mut rng);
        let pose = random_pose(&mut rng, 0.5);
        let s = LinkShape::new("s", 3, pose, shape.clone()).unwrap();
        let geometry = RobotGeometry::new(&robot, vec![s]).unwrap();
        for max in [1, 3] {
            let spheres = Spheres::fit(&geometry, max);
            assert!(spheres.len() <= max && !spheres.is_empty());
            for p in sample_points(&shape, &mut rng, 60) {
                let at = pose.transform_point(&p.coords);
                let inside = spheres.of_shape(0).any(|(link, c, r)| link == 3 && (at - c).norm() <= r);
                assert!(inside, "case {case}: {} point {p} outside its {max} spheres", shape.kind());
            }
        }
    }
}

/// A random arm: a few random shapes on every link of a built-in robot, and
/// obstacles (shapes on the base, which does not move) around it.
fn random_scene(rng: &mut impl Rng) -> (Robot, RobotGeometry) {
    let name = ["ur5", "panda", "lbr-iiwa-14-r820", "puma560"][rng.random_range(0..4)];
    let robot = Robot::builtin(name).unwrap();
    let mut shapes = Vec::new();
    for link in 0..=robot.dof() {
        let count = if link == 0 { rng.random_range(2..6) } else { rng.random_range(1..3) };
        let reach = if link == 0 { 0.9 } else { 0.15 };
        for k in 0..count {
            let shape = random_shape(rng);
            shapes.push(LinkShape::new(format!("l{link}_{k}"), link, random_pose(rng, reach), shape).unwrap());
        }
    }
    let geometry = RobotGeometry::new(&robot, shapes).unwrap();
    (robot, geometry)
}

#[test]
fn spheres_never_say_free_where_the_shapes_collide() {
    let mut rng = ChaCha8Rng::seed_from_u64(2026);
    let (mut free, mut hits, mut maybe_free) = (0, 0, 0);
    for scene in 0..60 {
        let (robot, geometry) = random_scene(&mut rng);
        let pairs = CollisionPairs::self_collision(&geometry);
        let spheres = Spheres::fit(&geometry, 3);
        let mut sp = spheres.placement();
        let mut placement = Placement::new(&geometry);
        for _ in 0..100 {
            let q = robot.random_q(&mut rng);
            let margin = if rng.random_bool(0.3) { rng.random_range(0.0..0.05) } else { 0.0 };
            let exact = collides(&geometry, &Placement::of(&robot, &geometry, &q).unwrap(), &pairs, margin).unwrap();
            let says_free = spheres_free(&robot, &spheres, &q, &pairs, margin, &mut sp).unwrap();
            assert!(!(says_free && exact.is_some()), "scene {scene}, q {q:?}: spheres free, but {exact:?} collides");
            let fast = collides_fast(&robot, &geometry, &spheres, &q, &pairs, margin, &mut sp, &mut placement).unwrap();
            assert_eq!(fast, exact, "scene {scene}, q {q:?}: the fast path answers differently");
            match (says_free, exact.is_some()) {
                (true, _) => free += 1,
                (false, true) => hits += 1,
                (false, false) => maybe_free += 1,
            }
        }
    }
    // Both answers occur often enough for the property to mean something.
    assert!(free > 200 && hits > 500, "free {free}, colliding {hits}, maybe but free {maybe_free}");
}
