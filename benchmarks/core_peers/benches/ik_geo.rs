//! kinema's closed-form IK against IK-Geo's Rust crate per call, on the same arms and targets
//! (issue 34 item 10: every closed-form family within 1.5× of IK-Geo):
//!
//! ```text
//! cargo bench --manifest-path benchmarks/core_peers/Cargo.toml --features ik-geo --bench ik_geo
//! ```
//!
//! (ik-geo builds nlopt with CMake: `cmake` on PATH, e.g. `pip install cmake` in a venv.)
//! Benchmark ids `<arm>/<what>`, 256 targets from seeded configurations within the limits:
//! * `kinema-candidates`: the closed form's joint vectors (`IkSolver::candidates_into` into a
//!   kept buffer), what IK-Geo's call returns;
//! * `kinema-solve`: the same and each one's FK residual and limit flags (`IkSolver::solve`);
//! * `ik-geo`: `Robot::ik(R, t)` of the family the arm has (solutions and least-squares flags).
//!
//! `core-peers ik-geo-check` checks first that the two find the same solutions.

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use ik_geo::robot::IKSolver;
use kinema::ik::CandidateSet;
use kinema_core_peers::ikgeo::arms;
use rand::SeedableRng;

fn ik_geo(c: &mut Criterion) {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    for arm in arms(&repo).expect("arms load") {
        let solver = kinema::ik::analytic_solver(&arm.robot).expect("a closed form");
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(34);
        let targets: Vec<_> =
            (0..256).map(|_| arm.robot.fk(&arm.robot.random_q(&mut rng)).unwrap().world_from_tool).collect();
        let geo_targets: Vec<_> = targets.iter().map(|t| arm.geo_target(t)).collect();
        let mut group = c.benchmark_group(arm.name);
        let mut k = 0;
        let mut set = CandidateSet::new();
        group.bench_function("kinema-candidates", |b| {
            b.iter(|| {
                k = (k + 1) % targets.len();
                solver.candidates_into(&targets[k], &mut set).unwrap();
                black_box(&set);
            })
        });
        group.bench_function("kinema-solve", |b| {
            b.iter(|| {
                k = (k + 1) % targets.len();
                black_box(solver.solve(&targets[k]).unwrap())
            })
        });
        group.bench_function("ik-geo", |b| {
            b.iter(|| {
                k = (k + 1) % geo_targets.len();
                let (r, t) = geo_targets[k];
                black_box(arm.geo.ik(r, t))
            })
        });
        group.finish();
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2));
    targets = ik_geo
}
criterion_main!(benches);
