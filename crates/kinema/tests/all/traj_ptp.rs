//! Point-to-point joint motions (seed 004 §VIII-B, eq. 38) and the
//! trajectory checks.

use kinema::traj::{
    check, CheckOptions, JointTrajectory, MotionLimits, Profile, Ptp, PtpOptions, TimeLaw, ViolationKind,
};
use kinema::{Error, Robot};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common;

/// Seed 004 §VIII-B: q_obj of the PTP example.
const SEED_Q_OBJ: [f64; 7] = [-0.1090, 1.2417, 0.4463, 1.9156, -0.9695, -1.8728, 0.4876];

fn iiwa() -> Robot {
    Robot::builtin("lbr-iiwa-14-r820").unwrap()
}

/// The iiwa with Cuadro I's velocity limits but without the (estimated)
/// acceleration limits of its built-in file.
fn iiwa_without_acc() -> Robot {
    let text = kinema::builtin_source("lbr-iiwa-14-r820").unwrap();
    let text: String = text.lines().filter(|l| !l.starts_with("acc =")).map(|l| format!("{l}\n")).collect();
    Robot::from_toml_str(&text, "iiwa-no-acc.toml").unwrap()
}

fn opts(profile: Profile) -> PtpOptions {
    PtpOptions { profile, acc: Some(vec![2.0]), jerk: Some(vec![15.0]), ..PtpOptions::default() }
}

#[test]
fn seed_ptp_example_respects_cuadro_i_and_one_limit_binds() {
    let robot = iiwa();
    for profile in Profile::ALL {
        let o = opts(profile);
        let ptp = Ptp::new(&robot, robot.home(), &SEED_Q_OBJ, &o).unwrap();
        let traj = ptp.sample(&robot, 0.001).unwrap();
        // The linear law starts with a velocity step: no acceleration limit applies to it.
        let acc = Some(vec![if profile == Profile::Linear { f64::INFINITY } else { 2.0 }]);
        let report = check(&robot, &traj, &CheckOptions { acc, ..CheckOptions::default() }).unwrap();
        assert!(report.violations.is_empty(), "{profile}: {:?}", report.violations.first());
        // Starts at q_ini, ends exactly at q_obj, all joints together.
        assert_eq!(traj.q(0), robot.home());
        let last = traj.q(traj.len() - 1);
        assert!(last.iter().zip(&SEED_Q_OBJ).all(|(a, b)| (a - b).abs() < 1e-12), "{profile}: {last:?}");
        // Synchronised and as fast as allowed: the binding joint reaches its
        // velocity or acceleration limit (sampled at 1 kHz, so within 1e-3).
        let vel_use = (0..7).map(|i| report.peak_vel[i] / robot.joints()[i].limits.vel.unwrap()).fold(0.0f64, f64::max);
        let acc_use = report.peak_acc.iter().map(|a| a / 2.0).fold(0.0f64, f64::max);
        if profile == Profile::Linear {
            assert!((vel_use - 1.0).abs() < 1e-9, "{profile}: {vel_use}");
        } else {
            assert!(
                vel_use.max(acc_use) > 0.999 && vel_use.max(acc_use) <= 1.0 + 1e-9,
                "{profile}: {vel_use} {acc_use}"
            );
        }
    }
}

#[test]
fn random_ptps_stay_within_limits_and_beat_the_seeds_slowest_joint_rule() {
    let mut rng = ChaCha8Rng::seed_from_u64(404);
    for name in ["lbr-iiwa-14-r820", "puma560", "scara5", "ur5"] {
        let robot = Robot::builtin(name).unwrap();
        let n = robot.dof();
        for case in 0..150 {
            let from = robot.random_q(&mut rng);
            let to = robot.random_q(&mut rng);
            let vel: Vec<f64> = (0..n).map(|_| rng.random_range(0.2..3.0)).collect();
            let acc: Vec<f64> = (0..n).map(|_| rng.random_range(0.5..10.0)).collect();
            let jerk: Vec<f64> = (0..n).map(|_| rng.random_range(2.0..100.0)).collect();
            let profile = Profile::ALL[case % 5];
            let o = PtpOptions {
                profile,
                vel: Some(vel.clone()),
                acc: Some(acc.clone()),
                jerk: Some(jerk.clone()),
                ..PtpOptions::default()
            };
            let ptp = Ptp::new(&robot, &from, &to, &o).unwrap();
            let traj = ptp.sample_unchecked(ptp.duration() / 300.0).unwrap();
            // The derivative checks hold without false alarms on exact samples:
            // jerk for the laws that limit it, acceleration for all but the linear law.
            let limited_jerk = matches!(profile, Profile::SCurve | Profile::Quintic);
            let c = CheckOptions {
                vel: Some(vel.clone()),
                acc: Some(acc.clone()),
                jerk: limited_jerk.then(|| jerk.clone()),
                ..CheckOptions::default()
            };
            let report = check(&robot, &traj, &c).unwrap();
            let bad: Vec<_> = report
                .violations
                .iter()
                .filter(|v| {
                    !(profile == Profile::Linear
                        && matches!(v.kind, ViolationKind::Acceleration | ViolationKind::Inconsistent))
                })
                .collect();
            assert!(bad.is_empty(), "{name} {profile}: {}", bad[0]);
            // Jerk, by finite differences of the analytic acceleration (S-curve only).
            if profile == Profile::SCurve {
                let law = ptp.law();
                for k in 0..2000 {
                    let t = law.duration() * k as f64 / 2000.0;
                    let s = law.at(t);
                    for i in 0..n {
                        let dq = (to[i] - from[i]).abs();
                        assert!(s.sddd.abs() * dq <= jerk[i] * (1.0 + 1e-9), "{name}: joint {i} jerk at {t}");
                    }
                }
            }
            // The seed's rule: the slowest actuator and the largest displacement.
            if profile == Profile::Trapezoid {
                let dmax = from.iter().zip(&to).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
                let vmin = vel.iter().copied().fold(f64::INFINITY, f64::min);
                let amin = acc.iter().copied().fold(f64::INFINITY, f64::min);
                let seed = TimeLaw::from_limits(Profile::Trapezoid, dmax, &MotionLimits::new(vmin, amin)).unwrap();
                assert!(
                    ptp.duration() <= seed.duration() * (1.0 + 1e-12),
                    "{name}: {} > {}",
                    ptp.duration(),
                    seed.duration()
                );
            }
        }
    }
}

#[test]
fn speed_override_and_stretching_slow_the_same_path_down() {
    let robot = iiwa();
    let full = Ptp::new(&robot, robot.home(), &SEED_Q_OBJ, &opts(Profile::SCurve)).unwrap();
    let half =
        Ptp::new(&robot, robot.home(), &SEED_Q_OBJ, &PtpOptions { speed: 0.5, ..opts(Profile::SCurve) }).unwrap();
    assert!((half.duration() - 2.0 * full.duration()).abs() < 1e-9 * full.duration());
    let long =
        Ptp::new(&robot, robot.home(), &SEED_Q_OBJ, &PtpOptions { duration: Some(20.0), ..opts(Profile::SCurve) })
            .unwrap();
    assert!((long.duration() - 20.0).abs() < 1e-12);
    let err = Ptp::new(&robot, robot.home(), &SEED_Q_OBJ, &PtpOptions { duration: Some(0.1), ..opts(Profile::SCurve) })
        .unwrap_err();
    assert!(err.to_string().contains("stretched"), "{err}");
}

#[test]
fn bad_input_gives_errors_that_name_the_problem() {
    let robot = iiwa_without_acc();
    let msg = |r: kinema::Result<Ptp>| r.unwrap_err().to_string();
    // A model with velocity limits (Cuadro I) but no acceleration limits.
    let m = msg(Ptp::new(&robot, robot.home(), &SEED_Q_OBJ, &PtpOptions::default()));
    assert!(m.contains("acceleration") && m.contains("amax") && m.contains("joint 1"), "{m}");
    let m = msg(Ptp::new(&robot, robot.home(), &SEED_Q_OBJ[..6], &opts(Profile::Cubic)));
    assert!(m.contains("7 joints") && m.contains('6'), "{m}");
    let mut nan = SEED_Q_OBJ;
    nan[3] = f64::NAN;
    assert!(msg(Ptp::new(&robot, robot.home(), &nan, &opts(Profile::Cubic))).contains("finite"));
    let mut far = SEED_Q_OBJ;
    far[1] = 3.0;
    let m = msg(Ptp::new(&robot, robot.home(), &far, &opts(Profile::Cubic)));
    assert!(m.starts_with("joint 2 (`") && m.contains("expected a value within the joint's limits"), "{m}");
    let m = msg(Ptp::new(
        &robot,
        robot.home(),
        &SEED_Q_OBJ,
        &PtpOptions { acc: Some(vec![1.0, 2.0]), ..opts(Profile::Cubic) },
    ));
    assert!(m.contains("7 expected") && m.contains("or 1 for every joint"), "{m}");
    let m =
        msg(Ptp::new(&robot, robot.home(), &SEED_Q_OBJ, &PtpOptions { acc: Some(vec![-1.0]), ..opts(Profile::Cubic) }));
    assert!(m.contains("amax"), "{m}");
    let m = msg(Ptp::new(&robot, robot.home(), &SEED_Q_OBJ, &PtpOptions { jerk: None, ..opts(Profile::SCurve) }));
    assert!(m.contains("jerk") && m.contains("jmax"), "{m}");
    let m = msg(Ptp::new(&robot, robot.home(), &SEED_Q_OBJ, &PtpOptions { speed: 0.0, ..opts(Profile::Cubic) }));
    assert!(m.contains("speed"), "{m}");
    let ptp = Ptp::new(&robot, robot.home(), &SEED_Q_OBJ, &opts(Profile::Cubic)).unwrap();
    for dt in [0.0, -1.0, f64::NAN, 1e-12] {
        assert!(ptp.sample(&robot, dt).is_err(), "dt = {dt}");
    }
    // No motion: a single sample at t = 0.
    let still = Ptp::new(&robot, robot.home(), robot.home(), &PtpOptions::default()).unwrap();
    assert_eq!(still.duration(), 0.0);
    assert_eq!(still.sample(&robot, 0.01).unwrap().len(), 1);
}

/// A trajectory of `robot` from a function of t (q, qd, qdd).
fn traj_of(robot: &Robot, times: &[f64], f: impl Fn(f64) -> (Vec<f64>, Vec<f64>, Vec<f64>)) -> JointTrajectory {
    let mut t = JointTrajectory::new(robot.dof());
    for &x in times {
        let (q, qd, qdd) = f(x);
        t.push(x, &q, &qd, &qdd).unwrap();
    }
    t
}

#[test]
fn check_reports_each_violation_with_its_time_and_joint() {
    // Velocity limits only: the branch flip below is then one jump, not also
    // the accelerations its second difference implies.
    let robot = iiwa_without_acc();
    let times: Vec<f64> = (0..=100).map(|k| k as f64 * 0.01).collect();
    let slow = |t: f64| (vec![0.1 * t; 7], vec![0.1; 7], vec![0.0; 7]);
    let ok = traj_of(&robot, &times, slow);
    assert!(check(&robot, &ok, &CheckOptions::default()).unwrap().violations.is_empty());

    // A branch flip: joint 4 jumps by 2 rad at t = 0.50 s.
    let flip = traj_of(&robot, &times, |t| {
        let (mut q, qd, qdd) = slow(t);
        if t >= 0.5 - 1e-12 {
            q[3] -= 2.0;
        }
        (q, qd, qdd)
    });
    let r = check(&robot, &flip, &CheckOptions::default()).unwrap();
    assert_eq!(r.violations.len(), 1, "{:?}", r.violations);
    let v = &r.violations[0];
    assert_eq!((v.kind, v.joint, v.sample), (ViolationKind::Jump, Some(3), 50));
    assert!((v.time - 0.5).abs() < 1e-12 && v.to_string().contains("joint 4 jumps"), "{v}");

    // Velocity above Cuadro I's 75°/s for A4 at t ≥ 0.8 s; acceleration above a given limit.
    let fast = traj_of(&robot, &times, |t| {
        let (q, mut qd, mut qdd) = slow(t);
        if t >= 0.8 - 1e-12 {
            qd[3] = 2.0;
        }
        qdd[6] = if (t - 0.3).abs() < 1e-9 { 5.0 } else { 0.0 };
        (q, qd, qdd)
    });
    let r = check(&robot, &fast, &CheckOptions { acc: Some(vec![4.0]), ..CheckOptions::default() }).unwrap();
    let of = |kind| r.violations.iter().filter(|v| v.kind == kind).map(|v| (v.joint, v.sample)).collect::<Vec<_>>();
    assert_eq!(of(ViolationKind::Acceleration), [(Some(6), 30)]);
    assert_eq!(of(ViolationKind::Velocity), (80..=100).map(|k| (Some(3), k)).collect::<Vec<_>>());
    // q itself moves at 0.1 rad/s: the 2 rad/s column contradicts it.
    assert_eq!(of(ViolationKind::Inconsistent), (80..=100).map(|k| (Some(3), k)).collect::<Vec<_>>());
    assert_eq!(r.violations.len(), 1 + 21 + 21);

    // Position outside the ±120° of A2; NaN; time going backwards.
    let mut bad = JointTrajectory::new(7);
    bad.push(0.0, &[0.0, 2.2, 0.0, 0.0, 0.0, 0.0, 0.0], &[0.0; 7], &[0.0; 7]).unwrap();
    bad.push(0.1, &[f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], &[0.0; 7], &[0.0; 7]).unwrap();
    bad.push(0.05, &[0.0; 7], &[0.0; 7], &[0.0; 7]).unwrap();
    let r = check(&robot, &bad, &CheckOptions::default()).unwrap();
    let kinds: Vec<_> = r.violations.iter().map(|v| (v.kind, v.sample)).collect();
    assert_eq!(kinds, [(ViolationKind::Position, 0), (ViolationKind::Malformed, 1), (ViolationKind::Malformed, 2)]);
    match r.into_result().unwrap_err() {
        Error::Trajectory { count, first, .. } => {
            assert_eq!(count, 3);
            assert!(first.contains("t = 0.0000 s") && first.contains("joint 2"), "{first}");
        }
        e => panic!("{e}"),
    }
    // Wrong joint count.
    assert!(check(&robot, &JointTrajectory::new(6), &CheckOptions::default()).is_err());
}

#[test]
fn check_finds_the_singularity_a_ptp_passes_through() {
    // Joint 4 goes from −0.5 to 0.5 rad: q4 = 0 (stretched elbow, Cuadro III) at mid-time.
    let robot = iiwa();
    let from = [0.2, 0.5, 0.1, -0.5, 0.3, 0.8, 0.0];
    let to = [0.2, 0.5, 0.1, 0.5, 0.3, 0.8, 0.0];
    let ptp = Ptp::new(&robot, &from, &to, &opts(Profile::Quintic)).unwrap();
    let traj = ptp.sample_unchecked(0.001).unwrap();
    let r = check(&robot, &traj, &CheckOptions { min_manipulability: Some(1e-3), ..CheckOptions::default() }).unwrap();
    let (t_min, m_min) = r.min_manipulability.unwrap();
    assert!((t_min - ptp.duration() / 2.0).abs() < 2e-3, "{t_min} vs {}", ptp.duration() / 2.0);
    assert!(m_min < 1e-4, "{m_min}"); // the nearest 1 ms sample, ~linear in the distance to q4 = 0
    assert!(r.violations.iter().all(|v| v.kind == ViolationKind::NearSingular));
    assert!(r.violations.iter().any(|v| (v.time - t_min).abs() < 1e-12));
    // The sampled PTP is refused when asked to stay away from singularities… and
    // emitted by default (seed 004 accepted passing one at bounded speed).
    assert!(ptp.sample(&robot, 0.001).is_ok());
}

/// `--vmax 1e100 --amax 1e100` used to give one sample at the target: the
/// start was lost and the check passed.
#[test]
fn limits_too_large_to_sample_are_refused_not_collapsed_to_the_target() {
    let robot = Robot::builtin("puma560").unwrap();
    let (from, to) = (robot.pose("qz").unwrap().to_vec(), robot.pose("qr").unwrap().to_vec());
    let opts = PtpOptions { vel: Some(vec![1e100]), acc: Some(vec![1e100]), ..PtpOptions::default() };
    let e = Ptp::new(&robot, &from, &to, &opts).unwrap_err().to_string();
    assert!(e.contains("shorter than"), "{e}");
    // Large but plannable limits keep both ends (unchecked: they are far above the robot's own).
    let opts = PtpOptions { vel: Some(vec![1e6]), acc: Some(vec![1e6]), ..PtpOptions::default() };
    let traj = Ptp::new(&robot, &from, &to, &opts).unwrap().sample_unchecked(0.01).unwrap();
    assert!(traj.len() >= 2);
    assert_eq!(traj.q(0), &from[..]);
    assert_eq!(traj.q(traj.len() - 1), &to[..]);
}

/// `traj check` trusted the q̇/q̈ columns: a 7.4 mrad one-sample glitch in q
/// passed. What q itself implies is now checked against the columns and the
/// limits.
#[test]
fn a_glitch_in_q_is_found_although_the_derivative_columns_look_fine() {
    let robot = iiwa();
    let ptp = Ptp::new(&robot, robot.home(), &SEED_Q_OBJ, &opts(Profile::SCurve)).unwrap();
    let clean = ptp.sample(&robot, 0.01).unwrap();
    let glitch = |k0: usize| {
        let mut t = JointTrajectory::new(7);
        for k in 0..clean.len() {
            let mut q = clean.q(k).to_vec();
            if k == k0 {
                q[1] += 0.0074;
            }
            t.push(clean.times()[k], &q, clean.qd(k), clean.qdd(k)).unwrap();
        }
        t
    };
    let c = CheckOptions { acc: Some(vec![2.0]), ..CheckOptions::default() };
    assert!(check(&robot, &clean, &c).unwrap().violations.is_empty());
    for k0 in [1, clean.len() / 3, clean.len() - 2] {
        let r = check(&robot, &glitch(k0), &c).unwrap();
        assert!(!r.violations.is_empty(), "glitch at sample {k0} passed");
        assert!(r.violations.iter().all(|v| v.joint == Some(1) && v.sample.abs_diff(k0) <= 1), "{:?}", r.violations);
        assert!(r.violations.iter().any(|v| v.kind == ViolationKind::Inconsistent));
    }
}

/// The Panda's model has jerk limits; a trapezoid PTP (acceleration steps)
/// passed the check. The planner now refuses it, and a trapezoid trajectory
/// from elsewhere (a CSV) sampled at 1 ms is refused by the check; the
/// S-curve planned for those limits passes.
#[test]
fn jerk_limits_of_the_model_are_checked() {
    let robot = Robot::builtin("panda").unwrap();
    let to = [0.5, -0.3, 0.2, -2.0, 0.1, 1.8, 0.6];
    let from = robot.home().to_vec();
    let e = Ptp::new(&robot, &from, &to, &PtpOptions::default()).unwrap_err().to_string();
    assert!(e.contains("jerk limit") && e.contains("scurve"), "{e}");
    // The same motion on a trapezoid law, built by hand: joint 1 accelerates at
    // 10 rad/s², a step of 10 000 rad/s³ over 1 ms against its 7 500.
    let law = TimeLaw::from_limits(Profile::Trapezoid, 1.0, &MotionLimits::new(2.0, 20.0)).unwrap();
    let mut trapezoid = JointTrajectory::new(7);
    for t in kinema::traj::sample_times(law.duration(), 0.001).unwrap() {
        let s = law.at(t);
        let at = |k: usize| -> Vec<f64> {
            (0..7)
                .map(|i| [from[i] + s.s * (to[i] - from[i]), s.sd * (to[i] - from[i]), s.sdd * (to[i] - from[i])][k])
                .collect()
        };
        trapezoid.push(t, &at(0), &at(1), &at(2)).unwrap();
    }
    let r = check(&robot, &trapezoid, &CheckOptions::default()).unwrap();
    assert!(r.violations.iter().any(|v| v.kind == ViolationKind::Jerk), "{:?}", r.violations.first());
    let scurve = PtpOptions { profile: Profile::SCurve, ..PtpOptions::default() };
    let smooth = Ptp::new(&robot, &from, &to, &scurve).unwrap().sample(&robot, 0.001).unwrap();
    let r = check(&robot, &smooth, &CheckOptions::default()).unwrap();
    assert!(r.violations.is_empty(), "{:?}", r.violations.first());
    let peak = r.peak_jerk.iter().zip(robot.joints()).map(|(j, jt)| j / jt.limits.jerk.unwrap()).fold(0.0, f64::max);
    assert!(peak > 0.5 && peak <= 1.0 + 1e-9, "{peak}");
}

/// Singular passages are reported as warnings with a stated threshold, one
/// per passage, at its most singular sample.
#[test]
fn singular_passages_are_warnings_one_per_passage() {
    let robot = iiwa();
    let from = [0.2, 0.5, 0.1, -0.5, 0.3, 0.8, 0.0];
    let to = [0.2, 0.5, 0.1, 0.5, 0.3, 0.8, 0.0];
    let ptp = Ptp::new(&robot, &from, &to, &opts(Profile::Quintic)).unwrap();
    let traj = ptp.sample(&robot, 0.001).unwrap();
    let c = CheckOptions { singular_warning: Some(kinema::traj::SINGULAR_WARNING), ..CheckOptions::default() };
    let r = check(&robot, &traj, &c).unwrap();
    assert!(r.violations.is_empty());
    assert_eq!(r.warnings.len(), 1, "{:?}", r.warnings);
    let w = &r.warnings[0];
    assert_eq!(w.kind, ViolationKind::Singular);
    assert!((w.time - ptp.duration() / 2.0).abs() < 2e-3, "{w}");
    assert!(w.to_string().contains("singular passage"), "{w}");
    // Away from it, nothing.
    let calm = Ptp::new(&robot, &from, &[0.3, 0.6, 0.1, -0.8, 0.3, 0.8, 0.0], &opts(Profile::Quintic)).unwrap();
    assert!(check(&robot, &calm.sample(&robot, 0.01).unwrap(), &c).unwrap().warnings.is_empty());
}

/// `robot` with its rate limits removed, so that only the limit-free checks apply.
fn without_rate_limits(robot: &Robot) -> Robot {
    let joints = robot
        .joints()
        .iter()
        .map(|j| {
            let mut j = j.clone();
            (j.limits.vel, j.limits.acc, j.limits.jerk) = (None, None, None);
            j
        })
        .collect();
    Robot::new(robot.to_builder().joints(joints).build().unwrap())
}

/// A switch of IK branch in mid-path is a branch jump, with no rate limit
/// to break: on every built-in with a closed form, seeded short paths
/// sampled every 10 ms follow one branch and then switch to another at one
/// sample. The path on one branch passes; the switched one is reported at
/// the switch, and only there.
#[test]
fn a_switch_of_ik_branch_is_a_branch_jump_without_limits() {
    let mut rng = ChaCha8Rng::seed_from_u64(0xB4A);
    let (mut switches, mut robots) = (0, 0);
    for robot in Robot::builtins().unwrap() {
        let Some(solver) = kinema::ik::analytic_solver(&robot) else { continue };
        let robot = without_rate_limits(&robot);
        robots += 1;
        for _ in 0..60 {
            let q0: Vec<f64> = robot
                .joints()
                .iter()
                .map(|j| {
                    let (lo, hi) = (j.limits.min.max(-3.0), j.limits.max.min(3.0));
                    lo + (hi - lo) * rng.random_range(0.15..0.85)
                })
                .collect();
            // 50 samples while the configuration moves 0.5 mrad per joint per sample.
            let dq: Vec<f64> = (0..q0.len()).map(|_| rng.random_range(-5e-4..5e-4)).collect();
            let path: Vec<Vec<f64>> =
                (0..50).map(|k| q0.iter().zip(&dq).map(|(q, d)| q + d * k as f64).collect()).collect();
            let times: Vec<f64> = (0..50).map(|k| k as f64 * 0.01).collect();
            let flat: Vec<f64> = path.iter().flatten().copied().collect();
            let smooth = JointTrajectory::from_positions(robot.dof(), times.clone(), flat).unwrap();
            let report = check(&robot, &smooth, &CheckOptions::default()).unwrap();
            assert!(report.violations.is_empty(), "{}: {}", robot.name(), report.violations[0]);
            // From sample 25 on, the branch of sample 25's pose farthest from the path.
            let pose = robot.fk(&path[25]).unwrap().world_from_tool;
            let Ok(solutions) = solver.solve(&pose) else { continue };
            let far = solutions
                .iter()
                .filter(|s| s.position_error < 1e-9 && s.orientation_error < 1e-9)
                .map(|s| s.q.clone())
                .max_by(|a, b| distance(a, &path[25]).total_cmp(&distance(b, &path[25])));
            let Some(other) = far.filter(|q| distance(q, &path[25]) > 0.5) else { continue };
            let mut flat: Vec<f64> = path[..25].iter().flatten().copied().collect();
            for k in 25..50 {
                flat.extend(other.iter().zip(&dq).map(|(q, d)| q + d * (k - 25) as f64));
            }
            let switched = JointTrajectory::from_positions(robot.dof(), times, flat).unwrap();
            let report = check(&robot, &switched, &CheckOptions::default()).unwrap();
            let jumps: Vec<_> = report.violations.iter().filter(|v| v.kind == ViolationKind::BranchJump).collect();
            assert!(
                jumps.len() == 1 && jumps[0].sample == 25,
                "{}: {:?} from {:?} to {other:?}",
                robot.name(),
                report.violations,
                path[25]
            );
            assert!(jumps[0].to_string().contains("a branch jump"), "{}", jumps[0]);
            switches += 1;
        }
    }
    assert!(robots >= 5 && switches >= 150, "{switches} switches on {robots} robots");
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum()
}

/// Smooth motions are not branch jumps: on random arms of every joint kind,
/// seeded joint curves at up to 2 rad/s (0.5 m/s prismatic) sampled every
/// 10 ms pass with no rate limit, and so do the same curves sampled every
/// 50 ms.
#[test]
fn smooth_motions_on_random_arms_are_not_branch_jumps() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5A0);
    for case in 0..1500 {
        let n = rng.random_range(2..=7);
        let robot = common::arms::random_arm(&mut rng, n, None);
        let q0 = common::arms::random_q(&mut rng, n);
        let amp: Vec<f64> = (0..n).map(|_| rng.random_range(0.0..1.0)).collect();
        let freq: Vec<f64> = (0..n).map(|_| rng.random_range(0.2..2.0)).collect();
        let dt = if case % 2 == 0 { 0.01 } else { 0.05 };
        let times: Vec<f64> = (0..=(2.0 / dt) as usize).map(|k| k as f64 * dt).collect();
        let mut flat = Vec::with_capacity(times.len() * n);
        for &t in &times {
            for (i, joint) in robot.joints().iter().enumerate() {
                let scale = if joint.kind == kinema::JointType::Prismatic { 0.25 } else { 1.0 };
                flat.push(q0[i] + scale * amp[i] * (freq[i] * t).sin());
            }
        }
        let traj = JointTrajectory::from_positions(n, times, flat).unwrap();
        let opts = CheckOptions { vel: Some(vec![f64::INFINITY]), ..CheckOptions::default() };
        let report = check(&robot, &traj, &opts).unwrap();
        let jumps: Vec<_> = report.violations.iter().filter(|v| v.kind == ViolationKind::BranchJump).collect();
        assert!(jumps.is_empty(), "case {case}: {}", jumps[0]);
    }
}

/// Issue 34: every built-in robot plans a PTP with the defaults — its own
/// velocity and acceleration limits and [`PtpOptions::for_robot`]'s profile
/// (the Panda's S-curve, whose jerk limits refuse the trapezoid) — from
/// `home` to seeded random configurations within its limits and to each of
/// its named poses, and the sampled trajectory passes the checks.
#[test]
fn every_builtin_plans_a_default_ptp_from_home() {
    let mut rng = ChaCha8Rng::seed_from_u64(34);
    for name in kinema::builtin_names() {
        let robot = Robot::builtin(name).unwrap();
        let opts = PtpOptions::for_robot(&robot);
        let has_jerk = robot.joints().iter().any(|j| j.limits.jerk.is_some());
        assert_eq!(opts.profile == Profile::Trapezoid, !has_jerk, "{name}: {}", opts.profile);
        for (i, j) in robot.joints().iter().enumerate() {
            assert!(j.limits.vel.is_some_and(|v| v > 0.0), "{name}: joint {} has no velocity limit", i + 1);
            assert!(j.limits.acc.is_some_and(|a| a > 0.0), "{name}: joint {} has no acceleration limit", i + 1);
        }
        let targets: Vec<(String, Vec<f64>)> = (0..5)
            .map(|k| (format!("random {k}"), robot.random_q(&mut rng)))
            .chain(robot.poses().iter().filter(|p| p.name != "home").map(|p| (p.name.clone(), p.q.clone())))
            .collect();
        for (what, to) in targets {
            let ptp = Ptp::new(&robot, robot.home(), &to, &opts)
                .unwrap_or_else(|e| panic!("{name}: default PTP from home to {what} {to:?}: {e}"));
            let traj = ptp.sample(&robot, 0.01).unwrap_or_else(|e| panic!("{name}: home to {what}: {e}"));
            let moves = to.as_slice() != robot.home();
            assert!(
                ptp.duration() < 60.0 && (ptp.duration() > 0.0) == moves,
                "{name}: to {what}: {} s",
                ptp.duration()
            );
            let last = traj.q(traj.len() - 1);
            assert!(last.iter().zip(&to).all(|(a, b)| (a - b).abs() < 1e-12), "{name}: home to {what}");
        }
    }
}

/// Issue 35 item 5: a trajectory is measured before its memory is taken. A
/// 7-joint PTP sampled into 9 million samples (1.58 GB of t, q, q̇, q̈) is
/// refused at once naming the figure and dt; one just under 1 GiB is made.
#[test]
fn a_trajectory_larger_than_its_memory_limit_is_refused_before_allocating() {
    let robot = iiwa();
    let ptp = Ptp::new(&robot, robot.home(), &SEED_Q_OBJ, &opts(Profile::Trapezoid)).unwrap();
    let dt = ptp.duration() / 9.0e6;
    let start = std::time::Instant::now();
    let e = ptp.sample_unchecked(dt).unwrap_err().to_string();
    assert!(start.elapsed() < std::time::Duration::from_secs(1), "{:?}", start.elapsed());
    assert!(e.contains("1.58 GB") && e.contains("1.07 GB") && e.contains("dt"), "{e}");
    let per_sample = 8 * (1 + 3 * 7);
    let most = kinema::traj::MAX_TRAJECTORY_BYTES / per_sample;
    assert!(JointTrajectory::reserved(7, most).is_ok());
    assert!(JointTrajectory::reserved(7, most + 1).is_err());
    assert!(JointTrajectory::reserved(64, usize::MAX).is_err());
}
