//! Planning time of the boundary-state laws (issue 25): one coordinate's
//! time-optimal law between random (p, v, a) states, the same with a
//! prescribed longer duration, seven jerk-limited coordinates synchronised
//! (`sync_duration`, fast and reference search), and a synchronised 7-DOF
//! PTP through a via velocity on the `lbr-iiwa-14-r820`.
//!
//! ```text
//! cargo bench -p kinema --bench boundary
//! KINEMA_SYNC7_CSV=cases.csv cargo bench -p kinema --bench boundary -- sync-7dof
//! ```
//!
//! With `KINEMA_SYNC7_CSV` the 7-coordinate problems are read from the file
//! `benchmarks/ruckig_cases.py --timing` wrote (the very problems Ruckig was
//! timed on, see `benchmarks/run_ruckig.sh`).
//!
//! Seeded inputs, drawn as in `tests/all/traj_boundary.rs`: limits v ∈ [0.1, 10],
//! a ∈ [0.1, 100], j ∈ [1, 1000] (log-uniform), states within them.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use kinema::traj::boundary::reference;
use kinema::traj::{
    sync_duration, BoundaryLaw, BoundaryPtp, BoundaryState, JointBoundary, MotionLimits, Profile, PtpOptions,
};
use kinema::Robot;
use rand::{Rng, SeedableRng};

const N: usize = 256;

fn log_uniform(rng: &mut impl Rng, lo: f64, hi: f64) -> f64 {
    rng.random_range(lo.ln()..hi.ln()).exp()
}

fn state(rng: &mut impl Rng, l: &MotionLimits, p: f64) -> BoundaryState {
    let v = rng.random_range(-l.vel..l.vel);
    let room = l.jerk.map_or(0.0, |j| (2.0 * j * (l.vel - v.abs())).sqrt().min(l.acc));
    let a = if room > 0.0 { rng.random_range(-room..room) } else { 0.0 };
    BoundaryState::new(p, v, a)
}

fn boundary(c: &mut Criterion) {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0x25);
    let mut g = c.benchmark_group("boundary");
    for jerk in [true, false] {
        let cases: Vec<(BoundaryState, BoundaryState, MotionLimits)> = (0..N)
            .map(|_| {
                let (v, a) = (log_uniform(&mut rng, 0.1, 10.0), log_uniform(&mut rng, 0.1, 100.0));
                let l = if jerk {
                    MotionLimits::with_jerk(v, a, log_uniform(&mut rng, 1.0, 1000.0))
                } else {
                    MotionLimits::new(v, a)
                };
                let p = rng.random_range(-5.0..5.0);
                (state(&mut rng, &l, 0.0), state(&mut rng, &l, p), l)
            })
            .collect();
        let name = if jerk { "third-order" } else { "second-order" };
        let mut i = 0;
        g.bench_function(format!("fastest/{name}"), |b| {
            b.iter(|| {
                i = (i + 1) % N;
                let (f, t, l) = &cases[i];
                black_box(BoundaryLaw::fastest(*f, *t, l).map(|x| x.duration()).ok())
            })
        });
        let slow: Vec<f64> =
            cases.iter().map(|(f, t, l)| BoundaryLaw::fastest(*f, *t, l).map_or(1.0, |x| x.duration()) * 1.3).collect();
        g.bench_function(format!("with-duration/{name}"), |b| {
            b.iter(|| {
                i = (i + 1) % N;
                let (f, t, l) = &cases[i];
                black_box(BoundaryLaw::with_duration(*f, *t, l, slow[i]).map(|x| x.duration()).ok())
            })
        });
    }
    let sync7 = sync7_cases(&mut rng);
    let mut i = 0;
    g.bench_function("sync-7dof-third/fast", |b| {
        b.iter(|| {
            i = (i + 1) % sync7.len();
            let (f, t, l) = &sync7[i];
            black_box(sync_duration(f, t, l, 0.0).map(|x| x.0).ok())
        })
    });
    g.bench_function("sync-7dof-third/reference", |b| {
        b.iter(|| {
            i = (i + 1) % sync7.len();
            let (f, t, l) = &sync7[i];
            black_box(reference::sync_duration(f, t, l, 0.0).map(|x| x.0).ok())
        })
    });
    let robot = Robot::builtin("lbr-iiwa-14-r820").expect("built-in");
    let pairs: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> = (0..N)
        .map(|_| {
            let (a, b) = (robot.random_q(&mut rng), robot.random_q(&mut rng));
            let w = (0..7).map(|i| if b[i] > a[i] { 0.2 } else { -0.2 }).collect();
            (a, b, w)
        })
        .collect();
    let opts =
        PtpOptions { profile: Profile::SCurve, acc: Some(vec![2.0]), jerk: Some(vec![15.0]), ..PtpOptions::default() };
    let mut i = 0;
    g.bench_function("ptp-plan-7dof-via-velocity/scurve", |b| {
        b.iter(|| {
            i = (i + 1) % N;
            let (from, to, w) = &pairs[i];
            let jb = JointBoundary { v1: Some(w.clone()), ..JointBoundary::default() };
            black_box(BoundaryPtp::new(&robot, from, to, &opts, &jb).map(|p| p.duration()).ok())
        })
    });
    g.finish();
}

type Joints = (Vec<BoundaryState>, Vec<BoundaryState>, Vec<MotionLimits>);

/// Seven jerk-limited coordinates per problem: from `KINEMA_SYNC7_CSV`
/// (rows of `ruckig_cases.py`: kind, case, dof, then p0 v0 a0 pf vf af vmax
/// amax jmax per joint) or drawn here.
fn sync7_cases(rng: &mut impl Rng) -> Vec<Joints> {
    if let Ok(path) = std::env::var("KINEMA_SYNC7_CSV") {
        let text = std::fs::read_to_string(&path).expect("KINEMA_SYNC7_CSV");
        return text.lines().map(parse_joints).collect();
    }
    (0..N)
        .map(|_| {
            let mut c: Joints = Default::default();
            for _ in 0..7 {
                let l = MotionLimits::with_jerk(
                    log_uniform(rng, 0.1, 10.0),
                    log_uniform(rng, 0.1, 100.0),
                    log_uniform(rng, 1.0, 1000.0),
                );
                let p = rng.random_range(-5.0..5.0);
                c.0.push(state(rng, &l, 0.0));
                c.1.push(state(rng, &l, p));
                c.2.push(l);
            }
            c
        })
        .collect()
}

fn parse_joints(line: &str) -> Joints {
    let f: Vec<&str> = line.split(',').collect();
    let dof: usize = f[2].parse().expect("dof");
    let x: Vec<f64> = f[3..3 + 9 * dof].iter().map(|s| s.parse().expect("number")).collect();
    let mut c: Joints = Default::default();
    for j in x.chunks(9) {
        c.0.push(BoundaryState::new(j[0], j[1], j[2]));
        c.1.push(BoundaryState::new(j[3], j[4], j[5]));
        c.2.push(MotionLimits::with_jerk(j[6], j[7], j[8]));
    }
    c
}

criterion_group! {
    name = benches;
    config = Criterion::default().measurement_time(Duration::from_secs(4));
    targets = boundary
}
criterion_main!(benches);
