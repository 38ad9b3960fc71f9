//! Inverse-kinematics benchmarks: kinema's numeric solver and, side by side,
//! the `k` crate's `JacobianIkSolver` on the same chain and the same targets.
//!
//! ```text
//! cargo bench -p kinema --bench ik
//! ```
//!
//! Targets are FK of seeded random within-limit configurations of the
//! `lbr-iiwa-14-r820`; tolerance 1e-6 m / 1e-6 rad. Before timing, each
//! solver's success rate on the targets is printed (a timed solver that
//! fails is not a fast solver). kinema starts from `home` and restarts from
//! seeded random configurations; k starts from `home` once (it has no restarts).

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use k::InverseKinematicsSolver;
use kinema::ik::{IkSolver, NumericIk};
use kinema::{Pose, Robot};

mod common;
use common::*;

const N_TARGETS: usize = 1000;

fn fk_targets(robot: &Robot) -> Vec<Pose> {
    let qs = configs(robot, 0x1c, N_TARGETS);
    qs.chunks_exact(robot.dof()).map(|q| robot.fk(q).expect("valid q").world_from_tool).collect()
}

fn k_target(p: &Pose) -> Iso {
    k_iso(p)
}

fn ik(c: &mut Criterion) {
    let robot = Robot::builtin("lbr-iiwa-14-r820").expect("built-in");
    let targets = fk_targets(&robot);
    let solver = NumericIk::new(&robot);
    let ok = targets
        .iter()
        .filter(|t| solver.solve(t).is_ok_and(|s| s[0].within_limits() && s[0].position_error <= 1e-6))
        .count();
    eprintln!("kinema numeric ik: {ok} of {N_TARGETS} targets solved within limits");

    let chain = k_chain(&robot);
    cross_check(&robot, &chain);
    let k_solver = k::JacobianIkSolver::new(1e-6, 1e-6, 0.5, 100);
    let home = robot.home().to_vec();
    let (mut k_ok, mut k_ok_limits) = (0, 0);
    for t in &targets {
        chain.set_joint_positions_unchecked(&home);
        if k_solver.solve(&chain, &k_target(t)).is_ok() {
            k_ok += 1;
            // The k chain carries no joint limits: check its answer against the robot's.
            if robot.limit_flags(&chain.joint_positions()).is_empty() {
                k_ok_limits += 1;
            }
        }
    }
    eprintln!(
        "k JacobianIkSolver: {k_ok} of {N_TARGETS} targets reached, {k_ok_limits} of them within the joint limits"
    );

    let mut g = c.benchmark_group("ik/lbr-iiwa-14-r820");
    let mut i = 0;
    g.bench_function("kinema-numeric", |b| {
        b.iter(|| {
            i = (i + 1) % N_TARGETS;
            black_box(solver.solve(black_box(&targets[i])).ok())
        })
    });
    let mut i = 0;
    g.bench_function("k-jacobian", |b| {
        b.iter(|| {
            i = (i + 1) % N_TARGETS;
            chain.set_joint_positions_unchecked(&home);
            black_box(k_solver.solve(&chain, black_box(&k_target(&targets[i]))).ok())
        })
    });
    g.finish();

    // Analytic solvers: all solutions of one target per call.
    let mut g = c.benchmark_group("ik-analytic");
    for name in ["lbr-iiwa-14-r820", "puma560", "scorbot-er-v-plus", "scara5", "rommel"] {
        let robot = Robot::builtin(name).expect("built-in");
        let solver = kinema::ik::analytic_solver(&robot).expect("analytic solver");
        // Targets the solver can reach (the SCARA's zone rule covers part of the workspace).
        let reachable: Vec<Pose> = fk_targets(&robot).into_iter().filter(|t| solver.solve(t).is_ok()).collect();
        assert!(!reachable.is_empty(), "{name}: no reachable target");
        let mut i = 0;
        g.bench_function(name, |b| {
            b.iter(|| {
                i = (i + 1) % reachable.len();
                black_box(solver.solve(black_box(&reachable[i])).ok())
            })
        });
    }
    // The geometric solvers (ik::geo), all solutions per call: the UR5 (its only
    // analytic solver) and the PUMA 560 beside `pieper` above.
    for name in ["ur5", "puma560"] {
        let robot = Robot::builtin(name).expect("built-in");
        let solver = kinema::ik::geo::GeoIk::new(&robot).expect("geometric solver");
        let targets = fk_targets(&robot);
        let mut i = 0;
        g.bench_function(format!("{name}/{}", solver.name()), |b| {
            b.iter(|| {
                i = (i + 1) % targets.len();
                black_box(solver.solve(black_box(&targets[i])).ok())
            })
        });
    }
    // The iiwa's closed form for a given q3 (seed 004 eq. 3–11), 8 solutions.
    let robot = Robot::builtin("lbr-iiwa-14-r820").expect("built-in");
    let iiwa = kinema::ik::iiwa::IiwaIk::new(&robot).expect("iiwa");
    let qs = configs(&robot, 0x3a, N_TARGETS);
    let cases: Vec<(Pose, f64)> =
        qs.chunks_exact(7).map(|q| (robot.fk(q).expect("valid").world_from_tool, q[2])).collect();
    let mut i = 0;
    g.bench_function("lbr-iiwa-14-r820/solve_q3", |b| {
        b.iter(|| {
            i = (i + 1) % cases.len();
            black_box(iiwa.solve_q3(black_box(&cases[i].0), cases[i].1).ok())
        })
    });
    let mut i = 0;
    g.bench_function("lbr-iiwa-14-r820/solve_q3_candidates", |b| {
        b.iter(|| {
            i = (i + 1) % cases.len();
            black_box(iiwa.solve_q3_candidates(black_box(&cases[i].0), cases[i].1).ok())
        })
    });
    // The same structure read from a URDF (ik::geo::SrsIk), all solutions at q's q3.
    let urdf = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/iiwa14.urdf");
    let robot = Robot::from_file(urdf, None).expect("iiwa14.urdf");
    let srs = kinema::ik::geo::SrsIk::new(&robot).expect("SRS arm");
    let qs = configs(&robot, 0x3b, N_TARGETS);
    let cases: Vec<(Pose, f64)> =
        qs.chunks_exact(7).map(|q| (robot.fk(q).expect("valid").world_from_tool, q[2])).collect();
    let mut i = 0;
    g.bench_function("iiwa14.urdf/geo-srs/solve_q3", |b| {
        b.iter(|| {
            i = (i + 1) % cases.len();
            black_box(srs.solve_q3(black_box(&cases[i].0), cases[i].1).ok())
        })
    });
    g.bench_function("iiwa14.urdf/geo-srs/solve_q3_candidates", |b| {
        b.iter(|| {
            i = (i + 1) % cases.len();
            black_box(srs.solve_q3_candidates(black_box(&cases[i].0), cases[i].1).ok())
        })
    });
    // The Scorbot's natural target (x, y, z, pitch, roll), seed 000 eq. 13–23.
    let robot = Robot::builtin("scorbot-er-v-plus").expect("built-in");
    let scorbot = kinema::ik::scorbot::ScorbotIk::new(&robot).expect("scorbot");
    let typed: Vec<([f64; 3], f64, f64)> = configs(&robot, 0x5c, N_TARGETS)
        .chunks_exact(5)
        .map(|q| {
            let p = robot.fk(q).expect("valid").world_from_tool.pos;
            // β = −θ234 and γ = θ5 with θ4 = q4 − π/2 (seed 000 Tabla I offsets).
            ([p.x, p.y, p.z], -(q[1] + q[2] + q[3]), q[4])
        })
        .collect();
    for (name, kernel) in
        [("scorbot-er-v-plus/xyz_pitch_roll", false), ("scorbot-er-v-plus/xyz_pitch_roll_candidates", true)]
    {
        let mut i = 0;
        g.bench_function(name, |b| {
            b.iter(|| {
                i = (i + 1) % typed.len();
                let (p, pitch, roll) = black_box(typed[i]);
                if kernel {
                    black_box(scorbot.xyz_pitch_roll_candidates(p, pitch, roll).ok().map(|c| c.len()))
                } else {
                    black_box(scorbot.solve_xyz_pitch_roll(p, pitch, roll).ok().map(|s| s.len()))
                }
            })
        });
    }
    // The SCARA's closed form for a given rail position q1, seed 003 eq. 1.
    let robot = Robot::builtin("scara5").expect("built-in");
    let scara = kinema::ik::scara::ScaraIk::new(&robot).expect("scara");
    let rail: Vec<([f64; 4], f64)> = configs(&robot, 0x5d, N_TARGETS)
        .chunks_exact(5)
        .map(|q| {
            let t = robot.fk(q).expect("valid").world_from_tool;
            ([t.pos.x, t.pos.y, t.pos.z, t.rot[(1, 0)].atan2(t.rot[(0, 0)])], q[0])
        })
        .collect();
    for (name, kernel) in [("scara5/with_rail", false), ("scara5/rail_candidates", true)] {
        let mut i = 0;
        g.bench_function(name, |b| {
            b.iter(|| {
                i = (i + 1) % rail.len();
                let (t, q1) = black_box(rail[i]);
                if kernel {
                    black_box(scara.rail_candidates(t, q1).ok().map(|c| c.len()))
                } else {
                    black_box(scara.solve_with_rail(t, q1).ok().map(|s| s.len()))
                }
            })
        });
    }
    g.finish();
}

/// `ik::solve_batch` on 4000 reachable targets with one rayon thread and
/// with two: the throughput ratio on this 2-core machine is the batch's
/// parallel speed-up (ids `ik-batch/<robot>/threads-<k>`).
fn batch(c: &mut Criterion) {
    use kinema::ik::{solve_batch, IkRequest, IkTarget};
    let mut g = c.benchmark_group("ik-batch");
    for name in ["ur5", "lbr-iiwa-14-r820"] {
        let robot = Robot::builtin(name).expect("built-in");
        let qs = configs(&robot, 0xba7c, 4000);
        let targets: Vec<IkTarget> = qs
            .chunks_exact(robot.dof())
            .map(|q| IkTarget::Pose(robot.fk(q).expect("valid q").world_from_tool))
            .collect();
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a thread pool");
            g.bench_function(format!("{name}/threads-{threads}"), |b| {
                b.iter(|| {
                    pool.install(|| {
                        let r = solve_batch(&robot, black_box(&targets), &IkRequest::default(), &|| {}, &|| false);
                        black_box(r.map(|v| v.len()))
                    })
                })
            });
        }
    }
    g.finish();
}

fn config() -> Criterion {
    Criterion::default().sample_size(20).measurement_time(Duration::from_secs(4)).warm_up_time(Duration::from_secs(1))
}

criterion_group! {
    name = benches;
    config = config();
    targets = ik, batch
}
criterion_main!(benches);
