//! Closed-form Scorbot-ER V Plus IK (seed 000 §II-C) against forward kinematics.

use std::f64::consts::{FRAC_PI_2, PI};

use kinema::ik::scorbot::{ScorbotIk, R_H};
use kinema::ik::{IkSolver, Unreachable};
use kinema::math::{rot_to_rpy, rot_z, RpyConvention};
use kinema::nalgebra::Vector3;
use kinema::{Error, Pose, Robot};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common;
use kinema::InputError;

fn wrap(a: f64) -> f64 {
    kinema::ik::wrap_angle(a)
}

fn robot() -> Robot {
    Robot::builtin("scorbot-er-v-plus").unwrap()
}

/// Same configuration (angles compared modulo 2π).
fn same(a: &[f64], b: &[f64], tol: f64) -> bool {
    common::same_angles(a, b, tol)
}

/// (x, y, z, pitch, roll) of a configuration via FK and seed 000 eq. 13.
fn typed_target(robot: &Robot, q: &[f64]) -> ([f64; 3], f64, f64) {
    let p = robot.fk(q).unwrap().world_from_tool.pos;
    ([p.x, p.y, p.z], -(q[1] + q[2] + q[3]), q[4])
}

#[test]
fn rpy_of_r_rh_is_seed000_eq13() {
    // rot_to_rpy(R·R_h) = (θ5, −θ234, θ1) while |θ234| ≤ π/2.
    let robot = robot();
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    for _ in 0..500 {
        let mut q = robot.random_q(&mut rng);
        q[4] = rng.random_range(-3.0..3.0);
        let th234 = q[1] + q[2] + q[3];
        if th234.abs() > 1.5 {
            continue;
        }
        let r = robot.fk(&q).unwrap().world_from_tool.rot * R_H;
        let [roll, pitch, yaw] = rot_to_rpy(&r, RpyConvention::Zyx);
        assert!(wrap(roll - q[4]).abs() < 1e-9 && (pitch + th234).abs() < 1e-9 && wrap(yaw - q[0]).abs() < 1e-9);
    }
}

#[test]
fn typed_round_trip_2000() {
    let robot = robot();
    let ik = ScorbotIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0x5c0b0);
    for _ in 0..2500 {
        let q = robot.random_q(&mut rng);
        let (p, pitch, roll) = typed_target(&robot, &q);
        let sols = ik.solve_xyz_pitch_roll(p, pitch, roll).unwrap();
        assert!(!sols.is_empty());
        assert!(sols.iter().any(|s| same(&s.q, &q, 1e-9)), "q = {q:?} not among {sols:#?}");
        for s in &sols {
            assert!(s.position_error < 1e-10 && s.orientation_error < 1e-10, "{s:?}");
            assert!(s.q.iter().all(|v| v.is_finite()));
            // Each solution really has the asked pitch and roll (seed 000 eq. 13).
            assert!(wrap(-(s.q[1] + s.q[2] + s.q[3]) - pitch).abs() < 1e-12 && s.q[4] == roll);
            let p2 = robot.fk(&s.q).unwrap().world_from_tool.pos;
            assert!((p2 - Vector3::from(p)).norm() < 1e-10);
        }
        // Limits are flagged consistently with FK.
        for s in &sols {
            assert_eq!(s.within_limits(), robot.fk(&s.q).unwrap().within_limits());
        }
    }
}

#[test]
fn pose_round_trip_2000_and_yaw_error() {
    let robot = robot();
    let ik = ScorbotIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0xfee1);
    for i in 0..2000 {
        let q = robot.random_q(&mut rng);
        let mut target = robot.fk(&q).unwrap().world_from_tool;
        let sols = ik.solve(&target).unwrap();
        assert!(sols.iter().any(|s| same(&s.q, &q, 1e-9)), "q = {q:?}");
        assert!(sols[0].position_error < 1e-10 && sols[0].orientation_error < 1e-10);
        assert!(sols.iter().all(|s| s.position_error < 1e-10));
        assert!(ik.yaw_error(&target) < 1e-10);
        // A turn about the vertical is an uncontrollable yaw error: every solution
        // keeps the position, the best one shows exactly that error.
        let turn = if i % 2 == 0 { 0.3 } else { -1.1 };
        target.rot = rot_z(turn) * target.rot;
        let sols = ik.solve(&target).unwrap();
        let ye = ik.yaw_error(&target);
        assert!(sols.iter().all(|s| s.position_error < 1e-10));
        assert!((sols[0].orientation_error - ye).abs() < 1e-9, "{} vs {ye}", sols[0].orientation_error);
        let horizontal = target.pos.x.hypot(target.pos.y) > 1e-9;
        let approach_vertical = (robot.fk(&q).unwrap().world_from_tool.rot[(2, 2)].abs() - 1.0).abs() < 1e-12;
        if horizontal && !approach_vertical {
            let e = turn.abs().min(PI - turn.abs());
            assert!((ye - e).abs() < 1e-9, "yaw error {ye} for a turn of {turn}");
        }
    }
}

#[test]
fn four_branches_and_labels() {
    let robot = robot();
    let ik = ScorbotIk::new(&robot).unwrap();
    // A point close enough to the base for the back branch to reach it too, far
    // enough for the front wrist to lie in front of the shoulder.
    let sols = ik.solve_xyz_pitch_roll([0.2, 0.05, 0.45], 0.2, 0.3).unwrap();
    let labels: Vec<&str> = sols.iter().map(|s| s.branch.as_ref()).collect();
    assert_eq!(labels, ["front/elbow-up", "front/elbow-down", "back/elbow-up", "back/elbow-down"]);
    for s in &sols {
        // elbow-up: the elbow lies above the shoulder–wrist line (seen from the reach side).
        let (a1, a2, d1) = (0.016, 0.221, 0.349);
        let (q1, q2) = (s.q[0], s.q[1]);
        let elbow = Vector3::new(q1.cos() * (a1 + a2 * q2.cos()), q1.sin() * (a1 + a2 * q2.cos()), d1 + a2 * q2.sin());
        let shoulder = Vector3::new(q1.cos() * a1, q1.sin() * a1, d1);
        let th234 = s.q[1] + s.q[2] + s.q[3];
        let tip = robot.fk(&s.q).unwrap().world_from_tool.pos;
        let wrist = tip - 0.145 * Vector3::new(q1.cos() * th234.cos(), q1.sin() * th234.cos(), th234.sin());
        // Height of the elbow above the line, in the plane of the arm.
        let u = |v: Vector3<f64>| v.x * q1.cos() + v.y * q1.sin();
        let (du, dz) = (u(wrist) - u(shoulder), wrist.z - shoulder.z);
        let (eu, ez) = (u(elbow) - u(shoulder), elbow.z - shoulder.z);
        let cross = du * ez - dz * eu; // > 0: elbow to the left of shoulder→wrist
        let reach = if s.branch.starts_with("front") { du } else { -du };
        let above = cross * du.signum() > 0.0;
        assert!(reach > 0.0);
        assert_eq!(above, s.branch.ends_with("elbow-up"), "{}: cross {cross}", s.branch);
        // The rule in joint terms: elbow-up is θ3 ≤ 0 in front, θ3 ≥ 0 at the back.
        let front = s.branch.starts_with("front");
        assert_eq!(s.branch.ends_with("elbow-up"), if front { s.q[2] <= 0.0 } else { s.q[2] >= 0.0 });
    }
}

/// Seed 000 eq. 17 as printed: denominator 2·a2²·a3².
fn eq17_printed(k1: f64, k2: f64, a2: f64, a3: f64) -> f64 {
    ((k1 * k1 + k2 * k2 - a2 * a2 - a3 * a3) / (2.0 * a2 * a2 * a3 * a3)).clamp(-1.0, 1.0).acos()
}

/// Seed 000 eq. 17 corrected: denominator 2·a2·a3.
fn eq17_corrected(k1: f64, k2: f64, a2: f64, a3: f64) -> f64 {
    ((k1 * k1 + k2 * k2 - a2 * a2 - a3 * a3) / (2.0 * a2 * a3)).clamp(-1.0, 1.0).acos()
}

/// Seed 000 eq. 18 and 20 for the built-in lengths \[m\].
fn k12(p: [f64; 3], th1: f64, th234: f64) -> (f64, f64) {
    let (d1, a1, d5) = (0.349, 0.016, 0.145);
    (p[0] * th1.cos() + p[1] * th1.sin() - a1 - d5 * th234.cos(), p[2] - d1 - d5 * th234.sin())
}

fn eq20(k1: f64, k2: f64, th3: f64, a2: f64, a3: f64) -> f64 {
    let (a, b) = (a2 + a3 * th3.cos(), a3 * th3.sin());
    (a * k2 - b * k1).atan2(a * k1 + b * k2)
}

#[test]
fn seed000_eq17_denominator_is_2_a2_a3() {
    let robot = robot();
    let (a2, a3) = (0.221, 0.221);
    let q = [0.4, 0.9, 0.7, -0.5, 0.2];
    let (p, _, _) = typed_target(&robot, &q);
    let (k1, k2) = k12(p, q[0], q[1] + q[2] + q[3]);
    // Corrected: |θ3| comes back.
    assert!((eq17_corrected(k1, k2, a2, a3) - q[2].abs()).abs() < 1e-12);
    // Printed (2·a2²·a3²): a different angle (here 0 — the argument exceeds 1 and acos saturates).
    let printed = eq17_printed(k1, k2, a2, a3);
    assert!((printed - q[2].abs()).abs() > 0.1, "printed eq. 17 gave {printed}");
    // And the printed θ3 does not reproduce the position.
    let th3 = printed;
    let th2 = eq20(k1, k2, th3, a2, a3);
    let bad = [q[0], th2, th3, q[1] + q[2] + q[3] - th2 - th3, q[4]];
    let pb = robot.fk(&bad).unwrap().world_from_tool.pos;
    assert!((pb - Vector3::from(p)).norm() > 1e-3);
    // The same in millimetres (the paper's units): still wrong.
    let mm = 1000.0;
    let printed_mm = eq17_printed(k1 * mm, k2 * mm, a2 * mm, a3 * mm);
    assert!((printed_mm - q[2].abs()).abs() > 0.1);
    assert!((eq17_corrected(k1 * mm, k2 * mm, a2 * mm, a3 * mm) - q[2].abs()).abs() < 1e-12);

    // Over 500 random targets within the limits, with the lengths in m, cm or mm and either
    // sign of θ3: the corrected eq. 17 reaches every one (position within 1 µm); the printed
    // one only where the arm is almost stretched (the argument is clamped to acos(1) = 0, and
    // the tool then misses by ~a·θ3²/4, below 1 µm for abs(θ3) < 0.0043), which with lengths
    // in m is 2 targets of the 500, in cm and mm none.
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    let reaches = |eq17: fn(f64, f64, f64, f64) -> f64, q: &[f64], unit: f64| {
        let (p, _, _) = typed_target(&robot, q);
        let th234 = q[1] + q[2] + q[3];
        let (k1, k2) = k12(p, q[0], th234);
        let th3 = eq17(k1 * unit, k2 * unit, a2 * unit, a3 * unit);
        [th3, -th3].into_iter().any(|th3| {
            let th2 = eq20(k1, k2, th3, a2, a3);
            let fk = robot.fk(&[q[0], th2, th3, th234 - th2 - th3, q[4]]).unwrap().world_from_tool.pos;
            (fk - Vector3::from(p)).norm() < 1e-6
        })
    };
    let mut printed_reached = [0; 3];
    for _ in 0..500 {
        let q = robot.random_q(&mut rng);
        for (k, unit) in [1.0, 100.0, 1000.0].into_iter().enumerate() {
            if reaches(eq17_printed, &q, unit) {
                assert!(q[2].abs() < 0.0043, "printed eq. 17 reached q = {q:?} (unit {unit})");
                printed_reached[k] += 1;
            }
            assert!(reaches(eq17_corrected, &q, unit), "corrected eq. 17 missed q = {q:?} (unit {unit})");
        }
    }
    assert_eq!(printed_reached, [2, 0, 0], "targets the printed eq. 17 reached (m, cm, mm)");
}

#[test]
fn seed000_eq23_theta2_must_be_recomputed() {
    let robot = robot();
    let (a2, a3) = (0.221, 0.221);
    let q = [0.1, 0.8, -0.9, 0.3, 0.0];
    let (p, _, _) = typed_target(&robot, &q);
    let th234 = q[1] + q[2] + q[3];
    let (k1, k2) = k12(p, q[0], th234);
    let th3 = eq17_corrected(k1, k2, a2, a3);
    let th2 = eq20(k1, k2, th3, a2, a3);
    // Printed eq. 23: θ3' = −θ3, θ2' = −θ2 — misses the point.
    let printed = [q[0], -th2, -th3, th234 + th2 + th3, q[4]];
    let miss = (robot.fk(&printed).unwrap().world_from_tool.pos - Vector3::from(p)).norm();
    assert!(miss > 0.05, "printed eq. 23 misses by only {miss}");
    // Corrected: θ2 from eq. 20 with θ3' = −θ3 reaches the point, and is the original q.
    let th2b = eq20(k1, k2, -th3, a2, a3);
    let fixed = [q[0], th2b, -th3, wrap(th234 - th2b + th3), q[4]];
    assert!((robot.fk(&fixed).unwrap().world_from_tool.pos - Vector3::from(p)).norm() < 1e-12);
    assert!(same(&fixed, &q, 1e-12));
}

#[test]
fn seed000_eq17_positive_root_is_elbow_down_in_front() {
    // The paper calls eq. 17 (θ3 = +acos ≥ 0) "codo arriba" but also defines codo
    // arriba as θ3 < 0; geometrically θ3 > 0 with θ2 from eq. 20 is elbow down.
    let robot = robot();
    let ik = ScorbotIk::new(&robot).unwrap();
    let sols = ik.solve_xyz_pitch_roll([0.45, 0.0, 0.35], 0.0, 0.0).unwrap();
    let down = sols.iter().find(|s| s.branch == "front/elbow-down").unwrap();
    let up = sols.iter().find(|s| s.branch == "front/elbow-up").unwrap();
    assert!(down.q[2] > 0.0 && up.q[2] < 0.0);
    // Elbow height: a2·sin θ2 above the shoulder.
    assert!(up.q[1].sin() > down.q[1].sin());
}

#[test]
fn seed000_eq19_misprint() {
    // Printed: k1 = c2·B + s2·(−A), k2 = c2·B + s2·A; correct: k1 = A·c2 − B·s2, k2 = B·c2 + A·s2.
    let (a2, a3) = (0.221, 0.221);
    let (t2, t3): (f64, f64) = (0.7, -0.4);
    let (a, b) = (a2 + a3 * t3.cos(), a3 * t3.sin());
    let k1 = a3 * (t2 + t3).cos() + a2 * t2.cos();
    let k2 = a3 * (t2 + t3).sin() + a2 * t2.sin();
    assert!((k1 - (a * t2.cos() - b * t2.sin())).abs() < 1e-15 && (k2 - (b * t2.cos() + a * t2.sin())).abs() < 1e-15);
    assert!((k1 - (t2.cos() * b - t2.sin() * a)).abs() > 0.1);
}

#[test]
fn unreachable_targets() {
    let robot = robot();
    let ik = ScorbotIk::new(&robot).unwrap();
    // Far away: the wrist is 1 m + from the shoulder; both branches miss.
    match ik.solve_xyz_pitch_roll([1.5, 0.0, 0.349], 0.0, 0.0) {
        Err(Error::Unreachable { reason: Unreachable::OutsideReach { by, boundary }, .. }) => {
            // front: wrist at 1.5 − 0.145 − 0.016 from the shoulder axis → 1.339 − 0.442
            assert!((by - (1.5 - 0.145 - 0.016 - 0.442)).abs() < 1e-12, "{by}");
            assert!(boundary.contains("outer"));
        }
        other => panic!("{other:?}"),
    }
    let far = Pose::translation(0.0, 0.0, 2.0);
    assert!(matches!(ik.solve(&far), Err(Error::Unreachable { .. })));
    // The error message says by how much.
    let msg = ik.solve_xyz_pitch_roll([1.5, 0.0, 0.349], 0.0, 0.0).unwrap_err().to_string();
    assert!(msg.contains("m outside"), "{msg}");
}

#[test]
fn singular_targets_are_finite() {
    let robot = robot();
    let ik = ScorbotIk::new(&robot).unwrap();
    // qz: stretched horizontally (elbow singularity) — both elbows coincide. At the
    // boundary a rounding error ε in the reach moves θ3 by ~√(ε/a) ≈ 3e-8 rad
    // without moving the tool (the position is insensitive to θ3 there).
    let q = robot.pose("qz").unwrap().to_vec();
    let target = robot.fk(&q).unwrap().world_from_tool;
    let sols = ik.solve(&target).unwrap();
    assert!(sols.iter().any(|s| same(&s.q, &q, 1e-7)));
    assert!(sols.iter().all(|s| s.q.iter().all(|v| v.is_finite()) && s.position_error < 1e-10));
    // home: approach vertical (pitch π/2): roll absorbs yaw, exact for any yaw.
    let home = robot.home().to_vec();
    let mut t = robot.fk(&home).unwrap().world_from_tool;
    t.rot = rot_z(0.7) * t.rot;
    let sols = ik.solve(&t).unwrap();
    assert!(sols[0].orientation_error < 1e-10 && sols[0].position_error < 1e-10);
    assert_eq!(ik.yaw_error(&t), 0.0);
    // Tool point on the base axis: θ1 free; the Pose solve takes the target's yaw.
    let q = [0.6, 1.6, 0.9, -0.2, 0.3];
    let mut t = robot.fk(&q).unwrap().world_from_tool;
    t.pos.x = 0.0;
    t.pos.y = 0.0;
    let sols = ik.solve(&t).unwrap();
    assert!(sols[0].position_error < 1e-10 && sols[0].orientation_error < 1e-10, "{:?}", sols[0]);
    let typed = ik.solve_xyz_pitch_roll([0.0, 0.0, t.pos.z], -2.3, 0.0).unwrap();
    assert!(typed.iter().all(|s| s.position_error < 1e-10 && s.q.iter().all(|v| v.is_finite())));
    assert_eq!(typed[0].q[0], 0.0);
    // Exactly on the outer boundary: one (double) solution per branch.
    let sols = ik.solve_xyz_pitch_roll([0.016 + 0.442 + 0.145, 0.0, 0.349], 0.0, 0.0).unwrap();
    assert!(sols[0].q.iter().all(|v| v.abs() < 1e-7));
    // Random finite garbage never panics and never returns NaN.
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    for _ in 0..2000 {
        let p = [rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0)];
        let (b, g) = (rng.random_range(-10.0..10.0), rng.random_range(-10.0..10.0));
        if let Ok(s) = ik.solve_xyz_pitch_roll(p, b, g) {
            assert!(s.iter().all(|s| s.q.iter().all(|v| v.is_finite()) && s.position_error < 1e-9));
        }
    }
}

#[test]
fn nan_rejected() {
    let robot = robot();
    let ik = ScorbotIk::new(&robot).unwrap();
    assert!(matches!(
        ik.solve_xyz_pitch_roll([f64::NAN, 0.0, 0.3], 0.0, 0.0),
        Err(Error::Input(InputError::NotFinite { .. }))
    ));
    assert!(matches!(
        ik.solve_xyz_pitch_roll([0.3, 0.0, 0.3], f64::INFINITY, 0.0),
        Err(Error::Input(InputError::NotFinite { .. }))
    ));
    let mut t = Pose::translation(0.3, 0.0, 0.3);
    t.rot[(0, 0)] = f64::NAN;
    assert!(matches!(ik.solve(&t), Err(Error::Input(InputError::NotFinite { .. }))));
    assert_eq!(ik.yaw_error(&t), f64::INFINITY);
}

#[test]
fn variant_lengths_base_and_tool() {
    // Another robot file with other lengths, a moved base and a tool along the approach.
    let src = kinema::builtin_source("scorbot-er-v-plus").unwrap();
    let src = src.replacen("a = 221", "a = 250", 1).replacen("d = 145", "d = 120", 1);
    let robot = Robot::from_toml_str(&src, "variant.toml").unwrap();
    let robot = robot
        .with_base(Pose::from_xyz_rpy([0.1, -0.2, 0.05], [0.0, 0.0, 0.4], RpyConvention::Zyx))
        .unwrap()
        .with_tool(Pose::from_xyz_rpy([0.0, 0.0, 0.03], [0.0, 0.0, 0.2], RpyConvention::Zyx))
        .unwrap();
    let ik = ScorbotIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for _ in 0..500 {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let sols = ik.solve(&target).unwrap();
        assert!(sols.iter().any(|s| same(&s.q, &q, 1e-9)), "{q:?}");
        assert!(sols[0].position_error < 1e-10 && sols[0].orientation_error < 1e-10);
        let (p, pitch, roll) = typed_target(&robot, &q);
        let typed = ik.solve_xyz_pitch_roll(p, pitch, roll).unwrap();
        assert!(typed.iter().any(|s| same(&s.q, &q, 1e-9)));
    }
    // A tool offset sideways cannot be handled.
    let bad = robot.with_tool(Pose::translation(0.05, 0.0, 0.0)).unwrap();
    assert!(matches!(ScorbotIk::new(&bad), Err(Error::UnsupportedStructure { .. })));
    // Not a Scorbot at all.
    assert!(matches!(ScorbotIk::new(&Robot::builtin("puma560").unwrap()), Err(Error::UnsupportedStructure { .. })));
    let _ = FRAC_PI_2;
}

#[test]
fn random_poses_never_panic_or_return_nan() {
    common::random_poses_never_panic_or_return_nan(&ScorbotIk::new(&robot()).unwrap());
}

#[test]
fn kernels_match_the_evaluating_solvers() {
    let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
    let ik = ScorbotIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(78);
    for _ in 0..3000 {
        let q = robot.random_q(&mut rng);
        let t = robot.fk(&q).unwrap().world_from_tool;
        let p = [t.pos.x, t.pos.y, t.pos.z];
        let (pitch, roll) = (-(q[1] + q[2] + q[3]), q[4]);
        let c = ik.xyz_pitch_roll_candidates(p, pitch, roll).unwrap();
        let s = ik.solve_xyz_pitch_roll(p, pitch, roll).unwrap();
        common::kernel_matches_solve(&robot, &c, &s, p);
        assert!(c.qs().iter().any(|c| common::same_angles(c, &q, 1e-9)), "{q:?} not among {c:?}");
        let c = ik.pose_candidates(&t).unwrap();
        assert!(c.qs().iter().any(|c| common::same_angles(c, &q, 1e-9)), "{q:?} not among {c:?}");
        let mut s = ik.solve(&t).unwrap();
        // `solve` sorts by orientation error; compare as sets of (label, q).
        s.sort_by(|a, b| a.branch.cmp(&b.branch));
        let mut pairs: Vec<_> = c.iter().collect();
        pairs.sort_by(|a, b| a.1.cmp(b.1));
        for ((q, label), s) in pairs.iter().zip(&s) {
            assert_eq!((&q[..], *label), (&s.q[..], s.branch.as_ref()));
        }
    }
}
