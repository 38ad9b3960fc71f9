//! kinema and `k` per call on the robots of run_core_peers.sh, with Criterion, cycling through the
//! states `pinocchio_bench states` wrote (the ones Pinocchio's C++ is timed on).
//!
//! ```text
//! CORE_PEERS_LIST=robots.tsv cargo bench --bench core_peers
//! ```
//!
//! `robots.tsv`: one robot a line, `name<TAB>urdf<TAB>tip<TAB>states.csv`. Benchmark ids
//! `<name>/<operation>-<peer>`; run_core_peers.sh reads each one's median from Criterion's
//! `estimates.json`.
//!
//! * fk: kinema `Robot::fk` (checks q, tool pose, limit flags); k `set_joint_positions_unchecked`
//!   + `SerialChain::end_transform`.
//! * jacobian: kinema `kin::jacobian_into(q, Frame::Base, ..)` into a kept 6 × n matrix (it
//!   computes the pose on the way); k `set_joint_positions_unchecked` + `k::jacobian` (allocates).
//! * rnea, crba: kinema `dynamics::rnea_into` and `mass_matrix_into` over kept buffers (both
//!   triangles), and `-plain`: the allocating reference `rnea` and `mass_matrix`. k has no dynamics.

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use kinema::dynamics::{mass_matrix, mass_matrix_into, rnea, rnea_into};
use kinema::nalgebra::{DMatrix, Matrix6xX, Vector3};
use kinema::Data;
use kinema::Frame;
use kinema_core_peers::{load, read_states, State};

/// Calls `f` on the states in turn, so that no branch predictor learns one input.
fn cycle<'a>(states: &'a [State]) -> impl FnMut() -> &'a State {
    let mut k = 0;
    move || {
        k = (k + 1) % states.len();
        &states[k]
    }
}

fn core_peers(c: &mut Criterion) {
    let list = std::env::var("CORE_PEERS_LIST").expect("CORE_PEERS_LIST=robots.tsv (see run_core_peers.sh)");
    let list = std::fs::read_to_string(&list).expect("CORE_PEERS_LIST is readable");
    let g = Vector3::new(0.0, 0.0, -9.81);
    for line in list.lines().filter(|l| !l.trim().is_empty()) {
        let [name, urdf, tip, states]: [&str; 4] =
            line.split('\t').collect::<Vec<_>>().try_into().expect("4 tab-separated fields");
        let peers = load(Path::new(urdf), tip).expect("robot loads");
        let (robot, chain) = (&peers.robot, &peers.k);
        let n = robot.dof();
        let states = read_states(Path::new(states), n).expect("states");
        let mut group = c.benchmark_group(name);

        let mut next = cycle(&states);
        group.bench_function("fk-kinema", |b| b.iter(|| black_box(robot.fk(&next().q).unwrap())));
        group.bench_function("fk-k", |b| {
            b.iter(|| {
                chain.set_joint_positions_unchecked(&next().q);
                black_box(chain.end_transform())
            })
        });
        let mut jac = Matrix6xX::zeros(n);
        group.bench_function("jacobian-kinema", |b| {
            b.iter(|| {
                kinema::kin::jacobian_into(robot, &next().q, Frame::Base, &mut jac).unwrap();
                black_box(&jac);
            })
        });
        group.bench_function("jacobian-k", |b| {
            b.iter(|| {
                chain.set_joint_positions_unchecked(&next().q);
                black_box(k::jacobian(chain))
            })
        });
        let mut buf = Data::new(robot);
        let mut tau = vec![0.0; n];
        group.bench_function("rnea-kinema", |b| {
            b.iter(|| {
                let s = next();
                rnea_into(robot, &mut buf, &s.q, &s.qd, &s.qdd, &g, &mut tau).unwrap();
                black_box(&tau);
            })
        });
        group.bench_function("rnea-kinema-plain", |b| {
            b.iter(|| {
                let s = next();
                black_box(rnea(robot, &s.q, &s.qd, &s.qdd, &g).unwrap())
            })
        });
        let mut m = DMatrix::zeros(n, n);
        group.bench_function("crba-kinema", |b| {
            b.iter(|| {
                mass_matrix_into(robot, &mut buf, &next().q, &mut m).unwrap();
                black_box(&m);
            })
        });
        group.bench_function("crba-kinema-plain", |b| b.iter(|| black_box(mass_matrix(robot, &next().q).unwrap())));
        group.finish();
    }
}

/// Short runs: each pass of run_core_peers.sh times every call once; the passes give the spread.
fn config() -> Criterion {
    Criterion::default()
        .sample_size(20)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_millis(800))
        .without_plots()
}

criterion_group! { name = benches; config = config(); targets = core_peers }
criterion_main!(benches);
