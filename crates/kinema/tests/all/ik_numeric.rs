//! Numeric inverse kinematics: round trips on every built-in robot, limits,
//! determinism, masks, the null-space objective and bad input.

use kinema::ik::{Damping, IkSolver, NumericIk, NumericOptions, Stop, Unreachable};
use kinema::math::pose_error;
use kinema::{Error, Pose, Robot};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common;
use kinema::InputError;

/// FK of random within-limit configurations → IK → the pose is reached within
/// tolerance, within limits, for (almost) every target.
#[test]
fn round_trip_every_robot() {
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    for name in kinema::builtin_names() {
        let robot = Robot::builtin(name).unwrap();
        let solver = NumericIk::new(&robot);
        let cases = 400;
        let mut failures = 0;
        for _ in 0..cases {
            let q = robot.random_q(&mut rng);
            let target = robot.fk(&q).unwrap().world_from_tool;
            let Ok(sols) = solver.solve(&target) else {
                failures += 1;
                continue;
            };
            let s = &sols[0];
            // Residual measured independently of the solver.
            let e = pose_error(&target, &robot.fk(&s.q).unwrap().world_from_tool);
            // The full pose, also for arms with fewer than six joints.
            assert!(e.position_norm() < 1e-6, "{name}: {}", e.position_norm());
            assert!(e.rotation_angle() < 1e-6, "{name}: {}", e.rotation_angle());
            assert!(s.within_limits(), "{name}: {:?}", s.q);
            let info = s.numeric.expect("numeric info");
            assert_eq!(info.stop, Stop::Converged);
            assert!((s.position_error - e.position_norm()).abs() < 1e-12);
        }
        // A 5-joint arm meets a full pose only at isolated configurations, which
        // seeded restarts miss when several joints sit near their limits (ROMMEL:
        // 3 of 400); its closed form solves those (tests/ik_rommel.rs).
        let allowed = if robot.dof() >= 6 { 1 } else { 4 };
        assert!(failures <= allowed, "{name}: {failures} of {cases} reachable targets not solved");
    }
}

#[test]
fn the_iiwa_reaches_thousands_of_poses() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let solver = NumericIk::new(&robot);
    let mut rng = ChaCha8Rng::seed_from_u64(1234);
    let n = 2000;
    let ok = (0..n)
        .filter(|_| {
            let target = robot.fk(&robot.random_q(&mut rng)).unwrap().world_from_tool;
            solver.solve(&target).is_ok_and(|s| s[0].within_limits() && s[0].position_error < 1e-6)
        })
        .count();
    assert!(ok as f64 / n as f64 >= 0.999, "{ok} of {n}");
}

#[test]
fn same_input_same_answer_and_seed_matters_only_for_restarts() {
    let robot = Robot::builtin("ur5").unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let a = NumericIk::with_options(&robot, NumericOptions { seed: 1, ..Default::default() }).unwrap();
    let b = NumericIk::with_options(&robot, NumericOptions { seed: 1, ..Default::default() }).unwrap();
    for _ in 0..200 {
        let target = robot.fk(&robot.random_q(&mut rng)).unwrap().world_from_tool;
        assert_eq!(a.solve(&target).unwrap(), b.solve(&target).unwrap());
    }
}

#[test]
fn starting_at_a_solution_takes_no_iteration() {
    let robot = Robot::builtin("panda").unwrap();
    let q = robot.pose("qr").unwrap().to_vec();
    let target = robot.fk(&q).unwrap().world_from_tool;
    let s = NumericIk::new(&robot).solve_from(&target, &q).unwrap();
    assert_eq!(s.numeric.unwrap().iterations, 0);
    assert_eq!(s.q, q);
}

#[test]
fn unreachable_target_is_an_error_not_a_wrong_success() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let solver = NumericIk::with_options(&robot, NumericOptions { max_restarts: 5, ..Default::default() }).unwrap();
    let target = Pose::translation(3.0, 0.0, 0.5);
    let e = solver.solve(&target).unwrap_err();
    let Error::Unreachable { reason: Unreachable::NoConvergence { position_error, restarts, .. }, .. } = &e else {
        panic!("{e:?}")
    };
    // The arm reaches at most ~1.3 m from its base; the best residual says how far off it stayed.
    assert!(*position_error > 1.0, "{e}");
    // The budget is 100 iterations for each of 6 starts; stalled starts leave
    // the rest of it to more restarts, and the error says what was spent.
    let Unreachable::NoConvergence { iterations, .. } = reason_of(&e) else { unreachable!() };
    assert!((600..700).contains(&iterations) && *restarts >= 5, "{e}");
    assert!(e.to_string().contains(&format!("{iterations} iterations over {restarts} restarts")), "{e}");
}

#[test]
fn bad_targets_and_options_are_rejected() {
    let robot = Robot::builtin("puma560").unwrap();
    let solver = NumericIk::new(&robot);
    let mut t = robot.fk(robot.home()).unwrap().world_from_tool;
    t.pos.x = f64::NAN;
    assert!(matches!(solver.solve(&t), Err(Error::Input(InputError::NotFinite { .. }))));
    let mut t = robot.fk(robot.home()).unwrap().world_from_tool;
    t.rot[(0, 0)] = 2.0;
    let e = solver.solve(&t).unwrap_err();
    assert!(matches!(&e, Error::Input(InputError::OutOfRange { what, .. }) if what == "target"), "{e:?}");
    assert!(e.to_string().contains("a rotation block"), "{e}");
    let good = robot.fk(robot.home()).unwrap().world_from_tool;
    assert!(matches!(solver.solve_from(&good, &[0.0; 3]), Err(Error::Input(InputError::JointCount { .. }))));
    let no_mask = NumericOptions { mask: Some([false; 6]), ..Default::default() };
    assert!(NumericIk::with_options(&robot, no_mask).is_err());
    let bad_tol = NumericOptions { tol_position: 0.0, ..Default::default() };
    assert!(NumericIk::with_options(&robot, bad_tol).is_err());
    let bad_rest = NumericOptions { rest: Some(vec![0.0; 2]), ..Default::default() };
    assert!(NumericIk::with_options(&robot, bad_rest).is_err());
}

#[test]
fn position_mask_ignores_orientation() {
    let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
    let position_only = NumericOptions { mask: Some([true, true, true, false, false, false]), ..Default::default() };
    let solver = NumericIk::with_options(&robot, position_only).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    for _ in 0..300 {
        let q = robot.random_q(&mut rng);
        let mut target = robot.fk(&q).unwrap().world_from_tool;
        // An orientation this arm cannot take at that position must not matter.
        target.rot = kinema::math::rot_x(0.7) * target.rot;
        let s = &solver.solve(&target).unwrap()[0];
        assert!(s.position_error < 1e-6);
    }
}

/// Without a mask, a 5-joint arm must meet the whole pose: a rotation it
/// cannot take is refused, with the closest configuration it found.
#[test]
fn five_joints_meet_the_full_pose_or_refuse() {
    let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
    let solver = NumericIk::with_options(&robot, NumericOptions { max_restarts: 5, ..Default::default() }).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(41);
    for _ in 0..40 {
        let q = robot.random_q(&mut rng);
        let mut target = robot.fk(&q).unwrap().world_from_tool;
        target.rot = kinema::math::rot_x(0.7) * target.rot;
        match solver.solve(&target) {
            Err(Error::Unreachable { reason: Unreachable::NoConvergence { .. }, closest: Some(c), .. }) => {
                let e = pose_error(&target, &robot.fk(&c.q).unwrap().world_from_tool);
                assert!((e.position_norm() - c.position_error).abs() < 1e-12);
                assert!(c.position_error > 1e-6 || c.orientation_error > 1e-6);
            }
            other => panic!("{other:?}"),
        }
    }
}

#[test]
fn null_space_rest_pose_pulls_a_redundant_arm() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let rest = vec![0.0, 0.4, 0.0, -1.2, 0.0, 0.8, 0.0];
    let plain = NumericIk::new(&robot);
    let pulled =
        NumericIk::with_options(&robot, NumericOptions { rest: Some(rest.clone()), ..Default::default() }).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    let dist = |q: &[f64]| q.iter().zip(&rest).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt();
    let (mut d_plain, mut d_pulled) = (0.0, 0.0);
    for _ in 0..200 {
        // Targets near the rest pose, started from a perturbed configuration.
        let q: Vec<f64> = rest.iter().map(|v| v + rng.random_range(-0.3..0.3)).collect();
        let target = robot.fk(&q).unwrap().world_from_tool;
        let start: Vec<f64> = q.iter().map(|v| v + rng.random_range(-0.2..0.2)).collect();
        let a = plain.solve_from(&target, &start).unwrap();
        let b = pulled.solve_from(&target, &start).unwrap();
        assert!(b.position_error < 1e-6 && b.orientation_error < 1e-6);
        d_plain += dist(&a.q);
        d_pulled += dist(&b.q);
    }
    assert!(d_pulled < d_plain, "rest pull did not bring solutions closer: {d_pulled} vs {d_plain}");
}

#[test]
fn every_damping_rule_solves_urdf_robots_too() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/iiwa14.urdf");
    let robot = Robot::from_file(path, None).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    for damping in [Damping::Chan, Damping::Sugihara, Damping::Wampler] {
        let solver = NumericIk::with_options(&robot, NumericOptions { damping, ..Default::default() }).unwrap();
        for _ in 0..100 {
            let target = robot.fk(&robot.random_q(&mut rng)).unwrap().world_from_tool;
            let s = &solver.solve(&target).unwrap()[0];
            assert!(s.position_error < 1e-6 && s.orientation_error < 1e-6 && s.within_limits(), "{damping:?}");
        }
    }
}

fn reason_of(e: &Error) -> Unreachable {
    match e {
        Error::Unreachable { reason, .. } => reason.clone(),
        other => panic!("{other:?}"),
    }
}

/// Reachable targets are found within the budget: FK of seeded
/// configurations within the limits of random general 6R arms and of
/// 7-joint arms with prismatic joints. With a fixed count of 100 restarts,
/// starts that stalled after ten iterations left most of the budget unspent
/// and 5 of the 6R targets and 4 of the others were refused.
#[test]
fn reachable_targets_are_found_within_the_budget() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    for (n, prismatic, allowed) in [(6, false, 0), (7, true, 2)] {
        let mut refused = Vec::new();
        for case in 0..1000 {
            let robot = loop {
                let r = common::arms::random_arm(&mut rng, n, None);
                if r.joints().iter().any(|j| j.kind == kinema::JointType::Prismatic) == prismatic {
                    break r;
                }
            };
            let q: Vec<f64> = robot
                .joints()
                .iter()
                .map(|j| rng.random_range(j.limits.min.max(-3.0)..j.limits.max.min(3.0)))
                .collect();
            let target = robot.fk(&q).unwrap().world_from_tool;
            if let Err(e) = NumericIk::new(&robot).solve(&target) {
                refused.push(format!("case {case}: {e}"));
            }
        }
        assert!(refused.len() <= allowed, "{n} joints: {} refused: {refused:?}", refused.len());
    }
}
