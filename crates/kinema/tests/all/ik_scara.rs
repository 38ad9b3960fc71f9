//! Closed-form SCARA-on-a-rail IK (seed 003 eq. 1) and its zone rule.

use kinema::ik::scara::ScaraIk;
use kinema::ik::{IkSolver, Unreachable};
use kinema::math::rot_x;
use kinema::{Error, Pose, Robot, RpyConvention};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common;
use kinema::InputError;

fn wrap(a: f64) -> f64 {
    kinema::ik::wrap_angle(a)
}

fn robot() -> Robot {
    Robot::builtin("scara5").unwrap()
}

/// [Px, Py, Pz, α] of a configuration, α = q2 + q3 + q5 (seed 003 eq. 1).
fn typed(robot: &Robot, q: &[f64]) -> [f64; 4] {
    let p = robot.fk(q).unwrap().world_from_tool.pos;
    [p.x, p.y, p.z, q[1] + q[2] + q[4]]
}

fn same(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.iter().zip(b).enumerate().all(|(i, (x, y))| if i == 4 { wrap(x - y).abs() < tol } else { (x - y).abs() < tol })
}

fn assert_reaches(robot: &Robot, s: &kinema::ik::Solution, t: [f64; 4]) {
    let fk = robot.fk(&s.q).unwrap().world_from_tool;
    let p = fk.pos;
    assert!((p.x - t[0]).hypot(p.y - t[1]).hypot(p.z - t[2]) < 1e-10, "{s:?} vs {t:?}");
    assert!(wrap(fk.rot[(1, 0)].atan2(fk.rot[(0, 0)]) - t[3]).abs() < 1e-10);
    assert!(s.position_error < 1e-10 && s.orientation_error < 1e-10);
}

#[test]
fn with_rail_round_trip_2000() {
    let robot = robot();
    let ik = ScaraIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0x5ca4a);
    for _ in 0..2500 {
        let q = robot.random_q(&mut rng);
        let t = typed(&robot, &q);
        let sols = ik.solve_with_rail(t, q[0]).unwrap();
        assert!(sols.iter().any(|s| same(&s.q, &q, 1e-9)), "{q:?} not in {sols:#?}");
        for s in &sols {
            assert_reaches(&robot, s, t);
            assert_eq!(s.within_limits(), robot.fk(&s.q).unwrap().within_limits());
            assert_eq!(s.branch == "elbow-right", s.q[2] >= 0.0);
        }
    }
}

#[test]
fn pose_round_trip_2000() {
    let robot = robot();
    let ik = ScaraIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    let [x0, x1, y0, y1] = ik.zone();
    let mut inside = 0;
    for _ in 0..2000 {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let sols = ik.solve(&target).unwrap_or_else(|e| panic!("{q:?} refused: {e}"));
        assert!(!sols.is_empty() && sols.len() <= 2);
        for s in &sols {
            assert!(s.position_error < 1e-10 && s.orientation_error < 1e-10 && s.within_limits(), "{s:?}");
        }
        // Inside the zone: both elbows at the zone rule's rail, as in seed 003.
        let (x, y) = (target.pos.x, target.pos.y);
        if (x0..=x1).contains(&x) && (y0..=y1).contains(&y) {
            inside += 1;
            let rail = y - (ik.comfortable_radius() - x.abs()).max(0.0);
            assert_eq!(sols.len(), 2);
            assert!(sols.iter().all(|s| (s.q[0] - rail).abs() < 1e-12), "{sols:?}");
        }
    }
    assert!(inside > 300, "{inside}");
}

/// Random within-limit configurations q, targets FK(q): `solve` and `solve_zone`
/// refuse none, and each solution reaches the target within limits.
#[test]
fn every_reachable_target_is_solved() {
    let robot = robot();
    let ik = ScaraIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0x5ca7);
    let (mut moved, mut one_elbow) = (0, 0);
    for _ in 0..4000 {
        let q = robot.random_q(&mut rng);
        let pose = robot.fk(&q).unwrap().world_from_tool;
        let sols = ik.solve(&pose).unwrap_or_else(|e| panic!("{q:?} refused: {e}"));
        for s in &sols {
            let fk = robot.fk(&s.q).unwrap();
            let e = kinema::math::pose_error(&pose, &fk.world_from_tool);
            assert!(e.position_norm() < 1e-9 && e.rotation_angle() < 1e-9, "{q:?}: {s:?}");
            assert!(s.within_limits() && fk.within_limits(), "{s:?}");
        }
        one_elbow += usize::from(sols.len() == 1);
        let t = typed(&robot, &q);
        let prev = if rng.random_bool(0.5) { Some(q.clone()) } else { None };
        let s = ik.solve_zone(t, prev.as_deref()).unwrap_or_else(|e| panic!("{t:?} refused: {e}"));
        assert_reaches(&robot, &s, t);
        assert!(s.within_limits(), "{s:?}");
        let (f, rail) = (robot.fk(&s.q).unwrap().world_from_tool.pos, s.q[0]);
        if (rail - (f.y - (ik.comfortable_radius() - f.x.abs()).max(0.0))).abs() > 1e-12 {
            moved += 1;
        }
    }
    eprintln!("4000 reachable targets: none refused; rail moved off the zone rule {moved} times, one elbow only {one_elbow} times");
    assert!(moved > 1000, "{moved}");
}

#[test]
fn zone_solutions_reach_and_respect_limits() {
    let robot = robot();
    let ik = ScaraIk::new(&robot).unwrap();
    let [x0, x1, y0, y1] = ik.zone();
    assert!(x0 < 0.0 && x1 > 0.5 && y1 - y0 > 0.5, "{:?}", ik.zone());
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for i in 0..3000 {
        let t = [
            rng.random_range(x0..=x1),
            rng.random_range(y0..=y1),
            rng.random_range(0.1..=0.3),
            rng.random_range(-3.0..3.0),
        ];
        let prev = if i % 2 == 0 { None } else { Some(vec![0.5, 0.0, -0.5, 0.1, 0.0]) };
        let s = ik.solve_zone(t, prev.as_deref()).unwrap();
        assert_reaches(&robot, &s, t);
        assert!(s.within_limits(), "{s:?}");
        assert_eq!(s.q[2] < 0.0, prev.is_some());
    }
    // The corners too.
    for (x, y) in [(x0, y0), (x0, y1), (x1, y0), (x1, y1)] {
        let s = ik.solve_zone([x, y, 0.2, 0.0], None).unwrap();
        assert!(s.within_limits() && s.position_error < 1e-10);
    }
}

#[test]
fn zone_paths_are_continuous() {
    let robot = robot();
    let ik = ScaraIk::new(&robot).unwrap();
    let [x0, x1, y0, y1] = ik.zone();
    let mut rng = ChaCha8Rng::seed_from_u64(0xc0ffee);
    let mut worst: f64 = 0.0;
    for path in 0..40 {
        let mut p = [rng.random_range(x0..=x1), rng.random_range(y0..=y1)];
        let alpha = rng.random_range(-3.0..3.0);
        let start_left = path % 2 == 1;
        let mut prev: Option<Vec<f64>> = None;
        let step = 2e-3;
        for _ in 0..400 {
            // Random walk with steps of 2 mm, reflected into the zone.
            let dir: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let mut next = [p[0] + step * dir.cos(), p[1] + step * dir.sin()];
            if !(x0..=x1).contains(&next[0]) {
                next[0] = p[0] - step * dir.cos();
            }
            if !(y0..=y1).contains(&next[1]) {
                next[1] = p[1] - step * dir.sin();
            }
            let moved = (next[0] - p[0]).hypot(next[1] - p[1]);
            p = next;
            let t = [p[0], p[1], 0.2, alpha];
            let seed = prev.clone().or_else(|| start_left.then(|| vec![0.0, 0.0, -1.0, 0.0, 0.0]));
            let s = ik.solve_zone(t, seed.as_deref()).unwrap();
            assert_reaches(&robot, &s, t);
            if let Some(q) = &prev {
                let dq = s.q.iter().zip(q).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
                worst = worst.max(dq / moved);
                assert!(dq <= 20.0 * moved, "jump {dq} for a step of {moved} at {t:?}: {:?} → {:?}", q, s.q);
                assert_eq!(s.q[2] < 0.0, q[2] < 0.0, "elbow side changed");
            }
            assert_eq!(s.q[2] < 0.0, start_left);
            prev = Some(s.q);
        }
    }
    assert!(worst > 0.0);
    eprintln!("largest |Δq|∞/|Δp| along the paths: {worst:.2} rad/m");
}

#[test]
fn outside_the_zone_is_unreachable_only_beyond_every_rail_position() {
    let robot = robot();
    let ik = ScaraIk::new(&robot).unwrap();
    let [x0, x1, y0, y1] = ik.zone();
    // L1 + L2 = 0.6 m from the shoulder anywhere on the rail [0, 1] m.
    for (t, by) in [
        ([0.7, 0.5 * (y0 + y1), 0.2, 0.0], 0.1),
        ([0.0, 1.7, 0.2, 0.0], 0.1),
        ([0.3, -0.7, 0.2, 0.0], 0.3f64.hypot(0.7) - 0.6),
    ] {
        match ik.solve_zone(t, None) {
            Err(Error::Unreachable { reason: Unreachable::OutsideReach { by: b, boundary }, .. }) => {
                assert!((b - by).abs() < 1e-9, "{b} vs {by}");
                assert!(boundary.contains("anywhere on the rail"), "{boundary}");
            }
            other => panic!("{other:?}"),
        }
    }
    // Outside the zone rectangle but reachable from another rail position: the
    // one nearest to the zone rule's, with every joint within limits.
    for t in [[x1 + 0.02, 0.5 * (y0 + y1), 0.2, 0.0], [0.3, y1 + 0.25, 0.2, 0.0], [x0 - 0.05, y0 - 0.05, 0.2, 0.0]] {
        let s = ik.solve_zone(t, None).unwrap();
        assert_reaches(&robot, &s, t);
        assert!(s.within_limits(), "{s:?}");
    }
    let s = ik.solve_zone([0.3, y1 + 0.25, 0.2, 0.0], None).unwrap();
    assert!((s.q[0] - 1.0).abs() < 1e-12, "the rail's end is nearest to the zone rule's 1.25 m: {s:?}");
    // Pz outside the stroke of joint 4 (z ∈ [0.1, 0.3] m).
    match ik.solve_zone([0.4, 0.6, 0.45, 0.0], None) {
        Err(Error::Unreachable { reason: Unreachable::OutsideReach { by, .. }, .. }) => {
            assert!((by - 0.15).abs() < 1e-9)
        }
        other => panic!("{other:?}"),
    }
    // solve_with_rail: beyond L1 + L2 = 0.6 m by 0.1 m.
    match ik.solve_with_rail([0.7, 0.5, 0.2, 0.0], 0.5) {
        Err(Error::Unreachable { reason: Unreachable::OutsideReach { by, .. }, .. }) => {
            assert!((by - 0.1).abs() < 1e-12)
        }
        other => panic!("{other:?}"),
    }
    // A tilted target: orientation error by the tilt angle.
    let t = Pose::new(rot_x(0.2), kinema::nalgebra::Vector3::new(0.4, 0.6, 0.2));
    match ik.solve(&t) {
        Err(Error::Unreachable { reason: Unreachable::Orientation { angle, .. }, .. }) => {
            assert!((angle - 0.2).abs() < 1e-12)
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn singular_and_bad_input() {
    let robot = robot();
    let ik = ScaraIk::new(&robot).unwrap();
    // qz: stretched arm (critical angle) — finite, exact position.
    let q = [0.0; 5];
    let t = typed(&robot, &q);
    let sols = ik.solve_with_rail(t, 0.0).unwrap();
    assert!(sols.iter().all(|s| s.position_error < 1e-10 && s.q.iter().all(|v| v.is_finite())));
    assert!(sols.iter().any(|s| same(&s.q, &q, 1e-7)));
    // NaN and infinity rejected.
    assert!(matches!(
        ik.solve_with_rail([f64::NAN, 0.0, 0.2, 0.0], 0.0),
        Err(Error::Input(InputError::NotFinite { .. }))
    ));
    assert!(matches!(
        ik.solve_with_rail([0.3, 0.0, 0.2, 0.0], f64::INFINITY),
        Err(Error::Input(InputError::NotFinite { .. }))
    ));
    assert!(matches!(ik.solve_zone([0.3, 0.5, 0.2, f64::NAN], None), Err(Error::Input(InputError::NotFinite { .. }))));
    assert!(matches!(
        ik.solve_zone([0.3, 0.5, 0.2, 0.0], Some(&[0.0; 3])),
        Err(Error::Input(InputError::WrongLength { .. }))
    ));
    let mut p = Pose::translation(0.3, 0.5, 0.2);
    p.pos.x = f64::NAN;
    assert!(matches!(ik.solve(&p), Err(Error::Input(InputError::NotFinite { .. }))));
    // Random finite input never panics or returns NaN.
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    for _ in 0..3000 {
        let t = [
            rng.random_range(-2.0..2.0),
            rng.random_range(-2.0..2.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-9.0..9.0),
        ];
        let results = [ik.solve_with_rail(t, rng.random_range(-1.0..2.0)), ik.solve_zone(t, None).map(|s| vec![s])];
        for sols in results.into_iter().flatten() {
            assert!(sols.iter().all(|s| s.q.iter().all(|v| v.is_finite()) && s.position_error < 1e-9));
        }
    }
}

#[test]
fn variant_lengths_base_and_tool() {
    let src = kinema::builtin_source("scara5").unwrap();
    let src = src.replacen("a = 0.35", "a = 0.40", 1).replacen("a = 0.25", "a = 0.30", 1);
    let robot = Robot::from_toml_str(&src, "variant.toml").unwrap();
    let base = Pose::from_xyz_rpy([0.2, -0.1, 0.05], [-std::f64::consts::FRAC_PI_2, 0.0, 0.0], RpyConvention::Zyx);
    let tool = Pose::from_xyz_rpy([0.03, 0.01, -0.05], [0.0, 0.0, 0.3], RpyConvention::Zyx);
    let robot = robot.with_base(base).unwrap().with_tool(tool).unwrap();
    let ik = ScaraIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    for _ in 0..500 {
        let q = robot.random_q(&mut rng);
        let fk = robot.fk(&q).unwrap().world_from_tool;
        let t = [fk.pos.x, fk.pos.y, fk.pos.z, fk.rot[(1, 0)].atan2(fk.rot[(0, 0)])];
        let sols = ik.solve_with_rail(t, q[0]).unwrap();
        assert!(sols.iter().any(|s| same(&s.q, &q, 1e-9)), "{q:?}");
        if let Ok(sols) = ik.solve(&fk) {
            assert!(sols.iter().all(|s| s.position_error < 1e-10 && s.orientation_error < 1e-10));
        }
    }
    // A rotated base breaks eq. 1; a tilted tool cannot be held.
    let r = robot.with_base(Pose::IDENTITY).unwrap();
    assert!(matches!(ScaraIk::new(&r), Err(Error::UnsupportedStructure { .. })));
    let r = robot.with_tool(Pose::rot_x(0.1)).unwrap();
    assert!(matches!(ScaraIk::new(&r), Err(Error::UnsupportedStructure { .. })));
    assert!(matches!(ScaraIk::new(&Robot::builtin("puma560").unwrap()), Err(Error::UnsupportedStructure { .. })));
}

#[test]
fn random_poses_never_panic_or_return_nan() {
    common::random_poses_never_panic_or_return_nan(&ScaraIk::new(&robot()).unwrap());
}

#[test]
fn rail_kernel_matches_solve_with_rail() {
    let robot = robot();
    let ik = ScaraIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    for _ in 0..3000 {
        let q = robot.random_q(&mut rng);
        let t = robot.fk(&q).unwrap().world_from_tool;
        let typed = [t.pos.x, t.pos.y, t.pos.z, t.rot[(1, 0)].atan2(t.rot[(0, 0)])];
        let c = ik.rail_candidates(typed, q[0]).unwrap();
        let s = ik.solve_with_rail(typed, q[0]).unwrap();
        common::kernel_matches_solve(&robot, &c, &s, [t.pos.x, t.pos.y, t.pos.z]);
        assert!(c.qs().iter().any(|c| common::same_angles(c, &q, 1e-9)), "{q:?} not among {c:?}");
    }
}
