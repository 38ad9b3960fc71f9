//! Self-collision per configuration: forward kinematics and placement alone
//! (`place`), exact `collides` and `min_distance` (forward kinematics and
//! placement included) and the sphere fast path
//! (`spheres_free`, and `collides_fast` with its exact fallback).
//!
//! ```text
//! cargo bench -p kinema-geometry --bench collision
//! KINEMA_COAL_CSV=coal.csv cargo bench -p kinema-geometry --bench collision
//! ```
//!
//! With `KINEMA_COAL_CSV` (written by `benchmarks/coal_peers.py`, see
//! `benchmarks/run_coal_peers.sh`): example-robot-data's Panda, its collision
//! meshes and the pairs its SRDF leaves, at the first 1000 configurations
//! of the file, the ones coal is timed on. Without it: the built-in Panda
//! with a capsule per link, at seeded random configurations.

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion};
use kinema::nalgebra::{UnitQuaternion, Vector3};
use kinema::{Pose, Robot};
use kinema_geometry::{
    collides, collides_fast, load_urdf, min_distance, min_distance_reference, pair_distance, place, spheres_free,
    CollisionPairs, LinkShape, Placement, RobotGeometry, Shape, Spheres, Srdf, UrdfOptions,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const CONFIGURATIONS: usize = 1000;

type Case = (Robot, RobotGeometry, CollisionPairs, Vec<Vec<f64>>);

/// The Panda of `KINEMA_COAL_CSV`, or the built-in with capsules.
fn case() -> Case {
    match std::env::var("KINEMA_COAL_CSV") {
        Ok(path) => from_coal_csv(&path),
        Err(_) => capsule_panda(),
    }
}

fn from_coal_csv(path: &str) -> Case {
    let text = std::fs::read_to_string(path).expect("KINEMA_COAL_CSV");
    let mut lines = text.lines().skip_while(|l| !l.starts_with("#robot,panda,"));
    let header: Vec<&str> = lines.next().expect("a Panda in KINEMA_COAL_CSV").split(',').collect();
    let options =
        UrdfOptions { tip: Some(header[5].into()), package_paths: vec![PathBuf::from(header[4])], skip_visual: true };
    let urdf = load_urdf(header[2], &options).unwrap();
    let mut pairs = CollisionPairs::all(&urdf.collision);
    Srdf::load(header[3]).unwrap().apply(&urdf.collision, &urdf.links, &mut pairs).unwrap();
    let n = urdf.robot.dof();
    let qs = lines
        .take_while(|l| l.starts_with("panda,"))
        .take(CONFIGURATIONS)
        .map(|l| l.split(',').skip(1).take(n).map(|c| c.parse().unwrap()).collect())
        .collect();
    (urdf.robot, urdf.collision, pairs, qs)
}

/// Link i's capsule from frame i−1's origin to frame i's, in link i's frame.
fn capsule_panda() -> Case {
    let robot = Robot::builtin("panda").unwrap();
    let frames = robot.link_frames(robot.home()).unwrap();
    let mut shapes = Vec::new();
    for i in 1..=robot.dof() {
        let p = frames[i].inverse().transform_point(&frames[i - 1].pos);
        let rot = UnitQuaternion::rotation_between(&Vector3::z(), &p).unwrap_or_else(UnitQuaternion::identity);
        let pose = Pose::new(rot.to_rotation_matrix().into_inner(), p / 2.0);
        let shape = Shape::Capsule { radius: 0.05, length: p.norm() };
        shapes.push(LinkShape::new(format!("link{i}"), i, pose, shape).unwrap());
    }
    let geometry = RobotGeometry::new(&robot, shapes).unwrap();
    let pairs = CollisionPairs::self_collision(&geometry);
    let mut rng = ChaCha8Rng::seed_from_u64(37);
    let qs = (0..CONFIGURATIONS).map(|_| robot.random_q(&mut rng)).collect();
    (robot, geometry, pairs, qs)
}

/// Each configuration with the pair `min_distance` finds closest there.
fn closest_pairs(
    robot: &Robot,
    geometry: &RobotGeometry,
    pairs: &CollisionPairs,
    qs: &[Vec<f64>],
) -> Vec<(Vec<f64>, (usize, usize))> {
    let mut placement = Placement::new(geometry);
    qs.iter()
        .filter_map(|q| {
            place(robot, geometry, q, &mut placement).unwrap();
            let p = min_distance(geometry, &placement, pairs).unwrap()?;
            Some((q.clone(), (p.a, p.b)))
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let (robot, geometry, pairs, qs) = case();
    let spheres = Spheres::fit(&geometry, 4);
    let mut placement = Placement::new(&geometry);
    let mut sp = spheres.placement();
    let free = qs.iter().filter(|q| spheres_free(&robot, &spheres, q, &pairs, 0.0, &mut sp).unwrap()).count();
    println!("spheres prove {free} of {} configurations free", qs.len());
    let closest = closest_pairs(&robot, &geometry, &pairs, &qs[..qs.len().min(100)]);
    let mut g = c.benchmark_group("panda-self");
    let mut i = 0;
    let mut next = || {
        i = (i + 1) % qs.len();
        &qs[i]
    };
    // Forward kinematics and placement alone: what `collides` and `min_distance` spend before any pair.
    g.bench_function("place", |b| b.iter(|| black_box(place(&robot, &geometry, next(), &mut placement).unwrap())));
    g.bench_function("collides", |b| {
        b.iter(|| {
            let q = next();
            place(&robot, &geometry, q, &mut placement).unwrap();
            black_box(collides(&geometry, &placement, &pairs, 0.0).unwrap())
        })
    });
    // Mesh–mesh distances take milliseconds: ten samples keep this one to seconds.
    g.sample_size(10);
    g.bench_function("min_distance", |b| {
        b.iter(|| {
            let q = next();
            place(&robot, &geometry, q, &mut placement).unwrap();
            black_box(min_distance(&geometry, &placement, &pairs).unwrap())
        })
    });
    // The plain all-pairs scan `min_distance` is tested against: every pair's distance in full.
    g.bench_function("min_distance_reference", |b| {
        b.iter(|| {
            let q = next();
            place(&robot, &geometry, q, &mut placement).unwrap();
            black_box(min_distance_reference(&geometry, &placement, &pairs).unwrap())
        })
    });
    // One exact pair alone: the closest pair's distance and witness points.
    g.bench_function("closest_pair", |b| {
        let mut k = 0;
        b.iter(|| {
            k = (k + 1) % closest.len();
            let (q, (sa, sb)) = &closest[k];
            place(&robot, &geometry, q, &mut placement).unwrap();
            black_box(pair_distance(&geometry, &placement, *sa, *sb).unwrap())
        })
    });
    g.sample_size(100);
    g.bench_function("spheres_free", |b| {
        b.iter(|| black_box(spheres_free(&robot, &spheres, next(), &pairs, 0.0, &mut sp).unwrap()))
    });
    g.bench_function("collides_fast", |b| {
        b.iter(|| {
            let q = next();
            black_box(collides_fast(&robot, &geometry, &spheres, q, &pairs, 0.0, &mut sp, &mut placement).unwrap())
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
