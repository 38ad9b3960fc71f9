//! Dynamics per call on the PUMA 560 (its `[joint.inertial]` tables): RNEA,
//! the mass matrix (CRBA) and forward dynamics, at 256 seeded random states;
//! the allocating reference functions and the buffered `rnea_into` and
//! `mass_matrix_into`.
//!
//! ```text
//! cargo bench -p kinema --bench dynamics
//! ```
//!
//! The reference path allocates per call (link frames, the motion subspaces);
//! benchmarks/run_core_peers.sh times the same calls beside Pinocchio's C++.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use kinema::dynamics::{forward_dynamics, mass_matrix, mass_matrix_into, rnea, rnea_into};
use kinema::nalgebra::{DMatrix, Vector3};
use kinema::Data;
use kinema::Robot;
use rand::{Rng, SeedableRng};

const N: usize = 256;

fn dynamics(c: &mut Criterion) {
    let robot = Robot::builtin("puma560").expect("built-in");
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(26);
    let g = Vector3::new(0.0, 0.0, -9.81);
    let states: Vec<[Vec<f64>; 3]> = (0..N)
        .map(|_| {
            let q = robot.random_q(&mut rng);
            let qd = (0..6).map(|_| rng.random_range(-2.0..2.0)).collect();
            let qdd = (0..6).map(|_| rng.random_range(-3.0..3.0)).collect();
            [q, qd, qdd]
        })
        .collect();
    let mut k = 0;
    let mut next = || {
        k = (k + 1) % N;
        &states[k]
    };
    c.bench_function("puma560 rnea", |b| {
        b.iter(|| {
            let [q, qd, qdd] = next();
            black_box(rnea(&robot, q, qd, qdd, &g).unwrap())
        })
    });
    let mut buf = Data::new(&robot);
    let mut tau = [0.0; 6];
    c.bench_function("puma560 rnea_into", |b| {
        b.iter(|| {
            let [q, qd, qdd] = next();
            rnea_into(&robot, &mut buf, q, qd, qdd, &g, &mut tau).unwrap();
            black_box(&tau);
        })
    });
    c.bench_function("puma560 mass_matrix (crba)", |b| b.iter(|| black_box(mass_matrix(&robot, &next()[0]).unwrap())));
    let mut m = DMatrix::zeros(6, 6);
    c.bench_function("puma560 mass_matrix_into (crba)", |b| {
        b.iter(|| {
            mass_matrix_into(&robot, &mut buf, &next()[0], &mut m).unwrap();
            black_box(&m);
        })
    });
    c.bench_function("puma560 forward_dynamics (aba)", |b| {
        b.iter(|| {
            let [q, qd, tau] = next();
            black_box(forward_dynamics(&robot, q, qd, tau, &g).unwrap())
        })
    });
}

criterion_group!(benches, dynamics);
criterion_main!(benches);
