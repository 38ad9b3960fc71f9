//! Trajectory benchmarks: planning a synchronised 7-DOF point-to-point motion
//! (issue 4 target: S-curve plan ≤ 5 µs), evaluating it, and sampling a LIN
//! with IK at every sample (10 000 samples; target ≤ 10 ms).
//!
//! ```text
//! cargo bench -p kinema --bench traj
//! ```
//!
//! Start and goal are seeded random within-limit configurations of the
//! `lbr-iiwa-14-r820`, with per-joint velocity (the robot's, seed 004
//! Cuadro I), acceleration (2 rad/s²) and jerk (15 rad/s³) limits.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use kinema::nalgebra::Vector3;
use kinema::traj::{
    check, to_joints, Blend, CartesianLimits, CartesianMotion, CheckOptions, JointMethod, Orientation, Profile, Ptp,
    PtpOptions, Segment,
};
use kinema::{Pose, Robot};
use rand::SeedableRng;

const N: usize = 256;

fn traj(c: &mut Criterion) {
    let robot = Robot::builtin("lbr-iiwa-14-r820").expect("built-in");
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0x7a);
    let pairs: Vec<(Vec<f64>, Vec<f64>)> =
        (0..N).map(|_| (robot.random_q(&mut rng), robot.random_q(&mut rng))).collect();
    let mut g = c.benchmark_group("traj/lbr-iiwa-14-r820");
    for profile in [Profile::SCurve, Profile::Trapezoid, Profile::Quintic] {
        let opts = PtpOptions { profile, acc: Some(vec![2.0]), jerk: Some(vec![15.0]), ..PtpOptions::default() };
        let mut i = 0;
        g.bench_function(format!("ptp-plan/{profile}"), |b| {
            b.iter(|| {
                i = (i + 1) % N;
                let (from, to) = &pairs[i];
                black_box(Ptp::new(&robot, black_box(from), black_box(to), &opts).map(|p| p.duration()).ok())
            })
        });
    }
    let opts =
        PtpOptions { profile: Profile::SCurve, acc: Some(vec![2.0]), jerk: Some(vec![15.0]), ..PtpOptions::default() };
    let plan = Ptp::new(&robot, &pairs[0].0, &pairs[0].1, &opts).expect("plan");
    let (mut q, mut qd, mut qdd) = ([0.0; 7], [0.0; 7], [0.0; 7]);
    let mut t = 0.0;
    g.bench_function("ptp-state/scurve", |b| {
        b.iter(|| {
            t = (t + 0.001) % plan.duration();
            plan.state_into(black_box(t), &mut q, &mut qd, &mut qdd);
            black_box(q[0] + qd[0] + qdd[0])
        })
    });
    g.finish();

    // A 10 s LIN sampled at 1 kHz with IK at every sample (issue 4 target ≤ 10 ms):
    // the iiwa (q3 rule, 21 closed-form solves per sample) and the PUMA 560 (Pieper, nearest of 8).
    let mut g = c.benchmark_group("traj-lin-10s-1khz");
    g.sample_size(10);
    for name in ["lbr-iiwa-14-r820", "puma560"] {
        let robot = Robot::builtin(name).expect("built-in");
        let q0: Vec<f64> = match name {
            "puma560" => vec![0.2, -0.6, 0.4, 0.3, 0.7, -0.2],
            _ => vec![0.3, 0.6, -0.2, -1.2, 0.4, 0.9, 0.1],
        };
        let a = robot.fk(&q0).expect("valid").world_from_tool;
        let b = Pose::new(a.rot * kinema::math::rot_x(0.2), a.pos + Vector3::new(0.05, 0.15, 0.1));
        let seg = Segment::lin(&a, &b, Orientation::Slerp).expect("segment");
        let lim = CartesianLimits::new(1.0, 1.0);
        let motion = CartesianMotion::new(vec![seg], Profile::Quintic, &lim, Blend::None)
            .and_then(|m| m.stretched_to(10.0))
            .expect("motion");
        let dt = motion.duration() / 10_000.0;
        let traj = to_joints(&robot, &motion, &q0, dt, JointMethod::default()).expect("reachable");
        let report = check(&robot, &traj, &CheckOptions::default()).expect("checked");
        eprintln!(
            "{name}: LIN of {:.2} s, {} samples, {} violation(s)",
            motion.duration(),
            traj.len(),
            report.violations.len()
        );
        g.bench_function(name, |bch| {
            bch.iter(|| black_box(to_joints(&robot, &motion, &q0, dt, JointMethod::default()).map(|t| t.len()).ok()))
        });
    }
    g.finish();
}

fn config() -> Criterion {
    Criterion::default().sample_size(30).measurement_time(Duration::from_secs(3)).warm_up_time(Duration::from_secs(1))
}

criterion_group! {
    name = benches;
    config = config();
    targets = traj
}
criterion_main!(benches);
