//! Closed-form ROMMEL IK (seed 001 §3.2, derived from the modified-DH model).

use kinema::ik::rommel::RommelIk;
use kinema::ik::{IkSolver, Unreachable};
use kinema::nalgebra::Vector3;
use kinema::{Error, Pose, Robot, RpyConvention};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common;
use kinema::InputError;

fn wrap(a: f64) -> f64 {
    kinema::ik::wrap_angle(a)
}

fn robot() -> Robot {
    Robot::builtin("rommel").unwrap()
}

fn same(a: &[f64], b: &[f64], tol: f64) -> bool {
    common::same_angles(a, b, tol)
}

fn typed(robot: &Robot, q: &[f64]) -> ([f64; 3], [f64; 3]) {
    let f = robot.fk(q).unwrap().world_from_tool;
    let a = f.rot.column(2);
    ([f.pos.x, f.pos.y, f.pos.z], [a[0], a[1], a[2]])
}

#[test]
fn position_approach_round_trip_2000() {
    let robot = robot();
    let ik = RommelIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0x2011e1);
    for _ in 0..2500 {
        let q = robot.random_q(&mut rng);
        let (p, a) = typed(&robot, &q);
        let sols = ik.solve_position_approach(p, a).unwrap();
        assert!(sols.iter().any(|s| same(&s.q[..4], &q[..4], 1e-9)), "{q:?} not in {sols:#?}");
        for s in &sols {
            assert!(s.position_error < 1e-10 && s.orientation_error < 1e-10, "{s:?}");
            assert_eq!(s.q[4], 0.0);
            let z = robot.fk(&s.q).unwrap().world_from_tool.rot.column(2).into_owned();
            let a = Vector3::from(a);
            assert!(z.cross(&a).norm().atan2(z.dot(&a)) < 1e-10);
            assert!(s.q.iter().all(|v| v.is_finite()));
            assert_eq!(s.within_limits(), robot.fk(&s.q).unwrap().within_limits());
        }
    }
}

#[test]
fn pose_round_trip_2000() {
    let robot = robot();
    let ik = RommelIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    for _ in 0..2000 {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let sols = ik.solve(&target).unwrap();
        assert!(sols.iter().any(|s| same(&s.q, &q, 1e-9)), "{q:?} not in {sols:#?}");
        for s in &sols {
            assert!(s.position_error < 1e-10 && s.orientation_error < 1e-10, "{s:?}");
        }
    }
}

#[test]
fn approach_off_the_reachable_circle_is_unreachable_by_its_angle() {
    let robot = robot();
    let ik = RommelIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let mut checked = 0;
    for _ in 0..300 {
        let q = robot.random_q(&mut rng);
        let frames = robot.link_frames(&q).unwrap();
        let forearm = frames[4].rot.column(2).into_owned(); // joint-4 axis
        let (p, a) = typed(&robot, &q);
        // Tilt the approach towards the forearm by 0.1 rad.
        let a = Vector3::from(a);
        let tilted = (a * 0.1f64.cos() + forearm * 0.1f64.sin()).normalize();
        match ik.solve_position_approach(p, [tilted.x, tilted.y, tilted.z]) {
            Err(Error::Unreachable { reason: Unreachable::Orientation { angle, detail }, .. }) => {
                assert!(angle > 0.0 && angle <= 0.1 + 1e-12, "{angle}");
                assert!(detail.contains("perpendicular"));
                checked += 1;
            }
            // Another position branch may have a forearm perpendicular to the tilted approach.
            Ok(sols) => assert!(sols.iter().all(|s| s.position_error < 1e-10 && s.orientation_error < 1e-10)),
            Err(e) => panic!("{e}"),
        }
    }
    assert!(checked > 250);
    // The own-branch angle is exactly the tilt when the other branches are out of reach.
    let (p, _) = typed(&robot, &[0.0; 5]);
    match ik.solve_position_approach(p, [0.0, 0.1f64.sin(), -0.1f64.cos()]) {
        Err(Error::Unreachable { reason: Unreachable::Orientation { angle, .. }, .. }) => {
            assert!((angle - 0.1).abs() < 1e-12, "{angle}")
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn out_of_reach() {
    let robot = robot();
    let ik = RommelIk::new(&robot).unwrap();
    // 1 m above the shoulder: beyond l2 + l3 + l4 = 0.473 m.
    match ik.solve_position_approach([0.0, 1.27, 0.0], [1.0, 0.0, 0.0]) {
        Err(Error::Unreachable { reason: Unreachable::OutsideReach { by, boundary }, .. }) => {
            // Nearest branch: shoulder at radial 0.05 → distance √(1 + 0.05²).
            assert!((by - ((1.0f64 + 0.0025).sqrt() - 0.473)).abs() < 1e-12, "{by}");
            assert!(boundary.contains("outer"));
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(ik.solve(&Pose::translation(2.0, 0.0, 0.0)), Err(Error::Unreachable { .. })));
}

#[test]
fn singular_and_bad_input() {
    let robot = robot();
    let ik = RommelIk::new(&robot).unwrap();
    // Home is the stretched arm (elbow singularity): finite, exact, home among them.
    let home = robot.home().to_vec();
    let t = robot.fk(&home).unwrap().world_from_tool;
    let sols = ik.solve(&t).unwrap();
    assert!(sols.iter().any(|s| same(&s.q, &home, 1e-7)));
    assert!(sols.iter().all(|s| s.position_error < 1e-10 && s.orientation_error < 1e-10));
    // Wrist on the vertical axis (ρ = a1 − a2·s2 − d4·s23 = 0): the position does not
    // fix q1, the approach does (two ways); the original configuration is among them.
    for q1 in [0.7, -2.5, 3.0] {
        let q = [q1, 0.0, (0.05f64 / 0.258).asin(), 0.4, 0.2];
        let t = robot.fk(&q).unwrap().world_from_tool;
        assert!(t.pos.x.hypot(t.pos.z) < 1e-15);
        let sols = ik.solve(&t).unwrap();
        assert!(sols.iter().any(|s| same(&s.q, &q, 1e-9)), "{q:?} not in {sols:#?}");
        assert!(sols.iter().all(|s| s.position_error < 1e-10 && s.orientation_error < 1e-10));
        assert!(sols.iter().all(|s| s.branch.starts_with("axis/")));
    }
    // On the axis with an approach no q1 can reach: the smallest angle is reported.
    match ik.solve_position_approach([0.0, 0.7, 0.0], [0.0, 1.0, 0.0]) {
        Err(Error::Unreachable { reason: Unreachable::Orientation { angle, .. }, .. }) => assert!(angle > 0.1),
        other => panic!("{other:?}"),
    }
    // NaN, infinity, zero approach.
    assert!(matches!(
        ik.solve_position_approach([f64::NAN, 0.5, 0.0], [0.0, 0.0, 1.0]),
        Err(Error::Input(InputError::NotFinite { .. }))
    ));
    assert!(matches!(
        ik.solve_position_approach([0.1, 0.5, 0.0], [0.0, f64::INFINITY, 1.0]),
        Err(Error::Input(InputError::NotFinite { .. }))
    ));
    assert!(matches!(
        ik.solve_position_approach([0.1, 0.5, 0.0], [0.0, 0.0, 0.0]),
        Err(Error::Input(InputError::OutOfRange { .. }))
    ));
    let mut p = Pose::translation(0.1, 0.5, 0.0);
    p.pos.y = f64::NAN;
    assert!(matches!(ik.solve(&p), Err(Error::Input(InputError::NotFinite { .. }))));
    // Random finite input never panics or returns NaN.
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    for _ in 0..3000 {
        let p = [rng.random_range(-0.8..0.8), rng.random_range(-0.3..1.0), rng.random_range(-0.8..0.8)];
        let a = [rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0)];
        if let Ok(sols) = ik.solve_position_approach(p, a) {
            assert!(sols.iter().all(|s| s.q.iter().all(|v| v.is_finite()) && s.position_error < 1e-9));
        }
    }
}

#[test]
fn variant_lengths_base_and_tool() {
    let src = kinema::builtin_source("rommel").unwrap();
    let src = src.replacen("a = 0.215", "a = 0.25", 1).replacen("d = 0.258", "d = 0.20", 1);
    let robot = Robot::from_toml_str(&src, "variant.toml").unwrap();
    let robot = robot
        .with_base(Pose::from_xyz_rpy([0.1, 0.0, -0.2], [0.3, -0.2, 1.0], RpyConvention::Zyx))
        .unwrap()
        .with_tool(Pose::from_xyz_rpy([0.0, 0.0, 0.04], [0.0, 0.0, 0.5], RpyConvention::Zyx))
        .unwrap();
    let ik = RommelIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(33);
    for _ in 0..500 {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let sols = ik.solve(&target).unwrap();
        assert!(sols.iter().any(|s| same(&s.q, &q, 1e-9)), "{q:?}");
        assert!(sols.iter().all(|s| s.position_error < 1e-10 && s.orientation_error < 1e-10));
        let (p, a) = typed(&robot, &q);
        let sols = ik.solve_position_approach(p, a).unwrap();
        assert!(sols.iter().any(|s| same(&s.q[..4], &q[..4], 1e-9)));
    }
    let bad = robot.with_tool(Pose::translation(0.05, 0.0, 0.0)).unwrap();
    assert!(matches!(RommelIk::new(&bad), Err(Error::UnsupportedStructure { .. })));
    assert!(matches!(
        RommelIk::new(&Robot::builtin("scorbot-er-v-plus").unwrap()),
        Err(Error::UnsupportedStructure { .. })
    ));
}

#[test]
fn seed001_theta1_sign_and_theta5() {
    // Seed 001 §3.2: θ1 = tan⁻¹(z5/x5). With θ1 = q1 + π (Tabla 1) that would give
    // tan q1 = z/x; the model has tan q1 = −z/x (front branch q1 = atan2(z, −x)).
    let robot = robot();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut printed_wrong = 0;
    for _ in 0..1000 {
        let q = robot.random_q(&mut rng);
        let p = robot.fk(&q).unwrap().world_from_tool.pos;
        let frames = robot.link_frames(&q).unwrap();
        let rho = -p.x * q[0].cos() + p.z * q[0].sin(); // signed reach along u
        let derived = (p.z / rho).atan2(-p.x / rho);
        assert!(wrap(derived - q[0]).abs() < 1e-9);
        // The printed ratio z/x matches q1 (mod π) only where tan q1 = 0 or ∞.
        let printed = (p.z / p.x).atan();
        if wrap(2.0 * (printed - q[0])).abs() > 1e-6 {
            printed_wrong += 1;
        }
        // θ5 = −arccos(z4·n) cannot work: the approach n is always ⟂ z4 (joint-4 axis).
        let z4 = frames[4].rot.column(2);
        let n = robot.fk(&q).unwrap().world_from_tool.rot.column(2).into_owned();
        assert!(z4.dot(&n).abs() < 1e-12);
    }
    assert!(printed_wrong > 990);
}

#[test]
fn random_poses_never_panic_or_return_nan() {
    common::random_poses_never_panic_or_return_nan(&RommelIk::new(&robot()).unwrap());
}
