//! Analytic inverse kinematics of the LBR iiwa (seed 004 §V): seeded FK→IK
//! round trips, singular and unreachable targets, self-motion, arm angle,
//! feasible ψ intervals, q3 selection along a path and the §V-C validation.

use std::f64::consts::PI;

use kinema::ik::iiwa::{IiwaIk, ELBOW, SHOULDER, WRIST};
use kinema::ik::{wrap_angle, IkSolver, Unreachable};
use kinema::nalgebra::Vector3;
use kinema::{Error, Pose, Robot};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common;
use kinema::InputError;

const ROBOT: &str = "lbr-iiwa-14-r820";

fn setup() -> (Robot, IiwaIk) {
    let robot = Robot::builtin(ROBOT).unwrap();
    let ik = IiwaIk::new(&robot).unwrap();
    (robot, ik)
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| wrap_angle(x - y).abs()).fold(0.0, f64::max)
}

/// Whether q is within `eps` of a singularity of the solvers (sin of q2, q4 or q6 near 0).
fn near_singular(q: &[f64], eps: f64) -> bool {
    [q[1], q[3], q[5]].iter().any(|v| v.sin().abs() < eps)
}

fn assert_finite(q: &[f64]) {
    assert!(q.iter().all(|v| v.is_finite()), "{q:?}");
}

#[test]
fn round_trip_for_fixed_q3() {
    let (robot, ik) = setup();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut worst: f64 = 0.0;
    for _ in 0..3000 {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let sols = ik.solve_q3(&target, q[2]).unwrap();
        assert!(sols.len() <= 8 && !sols.is_empty());
        for s in &sols {
            assert!(s.position_error < 1e-10 && s.orientation_error < 1e-10, "{q:?}: {s:?}");
            assert_eq!(s.q[2], q[2]);
            assert_finite(&s.q);
            assert_eq!(s.within_limits(), robot.fk(&s.q).unwrap().within_limits());
        }
        let best = sols.iter().min_by(|a, b| max_diff(&a.q, &q).total_cmp(&max_diff(&b.q, &q))).unwrap();
        let e = max_diff(&best.q, &q);
        worst = worst.max(e);
        assert!(e < 1e-9, "{q:?} not recovered: {e:e}");
        if !near_singular(&q, 1e-6) {
            assert_eq!(sols.len(), 8, "{q:?}");
            let c = ik.config_of(&q);
            let label = kinema::ik::iiwa::config_label(c);
            assert!(
                best.branch == format!("{label}/front") || best.branch == format!("{label}/back"),
                "{}",
                best.branch
            );
            assert!(best.within_limits());
        }
    }
    eprintln!("fixed-q3 round trip, 3000 cases: worst max|Δq| = {worst:.3e} rad");
}

#[test]
fn base_and_tool_are_handled() {
    let robot = Robot::builtin(ROBOT)
        .unwrap()
        .with_base(Pose::translation(0.2, -0.1, 0.5) * Pose::rot_x(0.4) * Pose::rot_z(1.0))
        .unwrap()
        .with_tool(Pose::translation(0.0, 0.05, 0.1) * Pose::rot_y(0.3))
        .unwrap();
    let ik = IiwaIk::new(&robot).unwrap().with_q3(0.4);
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    for _ in 0..500 {
        let mut q = robot.random_q(&mut rng);
        q[2] = 0.4;
        let target = robot.fk(&q).unwrap().world_from_tool;
        let sols = ik.solve(&target).unwrap();
        assert!(sols.iter().all(|s| s.position_error < 1e-10 && s.orientation_error < 1e-10));
        assert!(sols.iter().any(|s| max_diff(&s.q, &q) < 1e-9));
    }
}

#[test]
fn default_q3_is_zero() {
    let (robot, ik) = setup();
    assert_eq!(ik.q3(), 0.0);
    let q = [0.3, 0.5, 0.0, -1.2, 0.4, 0.8, 0.1];
    let sols = ik.solve(&robot.fk(&q).unwrap().world_from_tool).unwrap();
    assert_eq!(sols.len(), 8);
    assert!(sols.iter().all(|s| s.q[2] == 0.0));
    assert!(sols.iter().any(|s| max_diff(&s.q, &q) < 1e-12));
    // All eight labels differ here.
    let mut labels: Vec<&str> = sols.iter().map(|s| s.branch.as_ref()).collect();
    labels.sort();
    labels.dedup();
    assert_eq!(labels.len(), 8);
}

#[test]
fn other_robots_are_rejected_with_a_reason() {
    for name in ["ur5", "panda", "puma560"] {
        let robot = Robot::builtin(name).unwrap();
        match IiwaIk::new(&robot) {
            Err(Error::UnsupportedStructure { reason, .. }) => assert!(!reason.is_empty()),
            other => panic!("{name}: {other:?}"),
        }
    }
}

#[test]
fn singular_configurations_give_finite_answers() {
    let (robot, ik) = setup();
    let mut qs: Vec<Vec<f64>> = Vec::new();
    // Cuadro III of seed 004 and the named poses (the model holds radians).
    for n in ["sing-q4", "sing-q2-q3", "sing-coupled", "home", "fig9"] {
        qs.push(robot.pose(n).unwrap().to_vec());
    }
    // Wrist on the axis of joint 1 (shoulder singularity) and q6 = 0.
    qs.push(vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    qs.push(vec![0.4, 0.0, 0.0, 0.0, 0.3, 0.0, -0.2]);
    qs.push(vec![0.2, 0.3, 0.0, -0.6, 0.0, 0.3, 0.0]);
    for q in &qs {
        let target = robot.fk(q).unwrap().world_from_tool;
        for q3 in [q[2], 0.0, 0.5] {
            match ik.solve_q3(&target, q3) {
                Ok(sols) => {
                    for s in &sols {
                        assert_finite(&s.q);
                        assert!(s.position_error < 1e-10 && s.orientation_error < 1e-10, "{q:?} q3={q3}: {s:?}");
                    }
                    if q3 == q[2] {
                        assert!(!sols.is_empty());
                    }
                }
                Err(Error::Unreachable {
                    reason: Unreachable::OutsideReach { by, .. } | Unreachable::InsideExcluded { by, .. },
                    ..
                }) => {
                    assert!(q3 != q[2] && by.is_finite() && by > 0.0)
                }
                Err(e) => panic!("{q:?} q3={q3}: {e}"),
            }
        }
        for config in 0..8 {
            for psi in [0.0, 1.0, -2.5, PI] {
                let s = ik.solve_psi(&target, psi, config).unwrap();
                assert_finite(&s.q);
                assert!(s.position_error < 1e-10 && s.orientation_error < 1e-10, "{q:?}: {s:?}");
            }
        }
        assert!(ik.psi_of(q).is_finite());
        let motion = ik.self_motion(q, 16).unwrap();
        assert!(motion.iter().all(|m| m.q.iter().all(|v| v.is_finite()) && m.elbow.iter().all(|v| v.is_finite())));
        ik.feasible_psi_intervals(&target, ik.config_of(q)).unwrap();
        ik.select(q, &target, Some(&Vector3::new(0.0, 0.0, 1.0))).unwrap();
    }
}

#[test]
fn unreachable_and_invalid_targets() {
    let (robot, ik) = setup();
    let far = Pose::translation(2.0, 0.0, 0.36);
    for err in [ik.solve_q3(&far, 0.0).unwrap_err(), ik.solve_psi(&far, 0.0, 0).unwrap_err()] {
        match err {
            Error::Unreachable { reason: Unreachable::OutsideReach { by, boundary }, .. } => {
                // The wrist point is at (2, 0, −0.126) m from the shoulder; reach is 0.82 m.
                assert!((by - (2.0f64.hypot(0.126) - 0.82)).abs() < 1e-9, "{by} {boundary}");
            }
            e => panic!("{e:?}"),
        }
    }
    // Too close to the shoulder: inside the inner sphere of radius 0.02 m.
    let near = Pose::translation(0.0, 0.0, 0.36 + 0.126 + 0.005);
    assert!(matches!(
        ik.solve_q3(&near, 0.0),
        Err(Error::Unreachable { reason: Unreachable::OutsideReach { .. }, .. })
    ));
    // Reachable, but not with this q3: wrist on the joint-1 axis needs sin q3 · sin q4 = 0.
    let q = [0.0, 0.3, 0.0, 1.0, 0.0, 0.0, 0.0];
    let mut target = robot.fk(&q).unwrap().world_from_tool;
    let w = target.pos - target.rot.column(2) * 0.126;
    target.pos -= Vector3::new(w.x, w.y, 0.0);
    match ik.solve_q3(&target, 1.0) {
        Err(Error::Unreachable { reason: Unreachable::InsideExcluded { by, region }, .. }) => {
            assert!(by > 0.0 && region.contains("cylinder"), "{by} {region}")
        }
        other => panic!("{other:?}"),
    }
    assert!(ik.solve_q3(&target, 0.0).is_ok());
    let mut nan = robot.fk(robot.home()).unwrap().world_from_tool;
    nan.pos.x = f64::NAN;
    assert!(matches!(ik.solve_q3(&nan, 0.0), Err(Error::Input(InputError::NotFinite { .. }))));
    assert!(matches!(ik.solve(&nan), Err(Error::Input(InputError::NotFinite { .. }))));
    assert!(ik.solve_psi(&nan, 0.0, 0).is_err());
    assert!(ik.feasible_psi_intervals(&nan, 0).is_err());
    assert!(ik.select(robot.home(), &nan, None).is_err());
    let good = robot.fk(robot.pose("fig9").unwrap()).unwrap().world_from_tool;
    assert!(ik.solve_q3(&good, f64::INFINITY).is_err());
    assert!(ik.solve_psi(&good, f64::NAN, 0).is_err());
    assert!(ik.solve_psi(&good, 0.0, 8).is_err());
    assert!(ik.self_motion(&[0.0; 6], 10).is_err());
    assert!(ik.self_motion(robot.home(), 0).is_err());
    assert!(ik.psi_of(&[0.1, f64::NAN, 0.0, 1.0, 0.0, 0.0, 0.0]).is_nan());
    assert!(ik.psi_of(&[0.1, 0.2]).is_nan());
    assert_eq!(ik.config_of(&[0.1, -0.2]), SHOULDER);
}

#[test]
fn arm_angle_round_trip() {
    let (robot, ik) = setup();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let (mut n, mut worst) = (0, 0.0f64);
    while n < 3000 {
        let q = robot.random_q(&mut rng);
        if near_singular(&q, 1e-6) {
            continue;
        }
        n += 1;
        let target = robot.fk(&q).unwrap().world_from_tool;
        let config = ik.config_of(&q);
        let psi = ik.psi_of(&q);
        let s = ik.solve_psi(&target, psi, config).unwrap();
        assert!(s.position_error < 1e-10 && s.orientation_error < 1e-10);
        let e = max_diff(&s.q, &q);
        worst = worst.max(e);
        assert!(e < 1e-8, "{q:?}: ψ = {psi}, {:?} (Δ = {e:e})", s.q);
        assert_eq!(ik.config_of(&s.q), config);
        assert!((wrap_angle(ik.psi_of(&s.q) - psi)).abs() < 1e-8);
    }
    eprintln!("ψ round trip, 3000 cases: worst max|Δq| = {worst:.3e} rad");
    // Bits as documented.
    let q = [0.1, -0.5, 0.2, 1.0, 0.3, -0.7, 0.0];
    assert_eq!(ik.config_of(&q), SHOULDER | WRIST);
    assert_eq!(ik.config_of(&[0.1, 0.5, 0.2, -1.0, 0.3, 0.7, 0.0]), ELBOW);
}

#[test]
fn self_motion_keeps_the_pose_and_moves_the_elbow_on_a_circle() {
    let (robot, ik) = setup();
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    for _ in 0..100 {
        let q = robot.random_q(&mut rng);
        if near_singular(&q, 1e-3) {
            continue;
        }
        let fk = robot.fk(&q).unwrap().world_from_tool;
        let samples = ik.self_motion(&q, 36).unwrap();
        assert_eq!(samples.len(), 36);
        assert!(max_diff(&samples[0].q, &q) < 1e-9);
        let frames = robot.link_frames(&q).unwrap();
        let shoulder = frames[1].pos;
        let wrist = frames[5].pos;
        assert!((samples[0].elbow - frames[3].pos).norm() < 1e-12);
        let u = (wrist - shoulder).normalize();
        let centre = shoulder + u * (samples[0].elbow - shoulder).dot(&u);
        let radius = (samples[0].elbow - centre).norm();
        assert!(radius > 1e-4);
        for s in &samples {
            let p = robot.fk(&s.q).unwrap().world_from_tool;
            let e = kinema::math::pose_error(&fk, &p);
            assert!(e.position_norm() < 1e-10 && e.rotation_angle() < 1e-10, "{s:?}");
            assert_eq!(ik.config_of(&s.q), ik.config_of(&q));
            assert_eq!(s.q[2], s.q3);
            // The elbow from the model's own frames agrees.
            assert!((robot.link_frames(&s.q).unwrap()[3].pos - s.elbow).norm() < 1e-12);
            assert!(((s.elbow - centre).norm() - radius).abs() < 1e-10);
            assert!((s.elbow - centre).dot(&u).abs() < 1e-10);
        }
        // Consecutive samples are 10° apart on the circle.
        let a = (samples[1].elbow - centre).angle(&(samples[0].elbow - centre));
        assert!((a - PI / 18.0).abs() < 1e-8, "{a}");
    }
}

#[test]
fn feasible_psi_intervals_are_correct() {
    let (robot, ik) = setup();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let feasible = |t: &Pose, psi: f64, c: u8| ik.solve_psi(t, psi, c).unwrap().within_limits();
    let mut seen = 0;
    for _ in 0..12 {
        let q = robot.random_q(&mut rng);
        if near_singular(&q, 1e-3) {
            continue;
        }
        let target = robot.fk(&q).unwrap().world_from_tool;
        let config = ik.config_of(&q);
        let iv = ik.feasible_psi_intervals(&target, config).unwrap();
        // q itself is within limits, so its ψ lies in one interval.
        let psi = ik.psi_of(&q);
        assert!(iv.iter().any(|&(a, b)| a - 1e-9 <= psi && psi <= b + 1e-9), "{psi} {iv:?}");
        for &(a, b) in &iv {
            assert!(-PI <= a && a <= b && b <= PI);
            assert!(feasible(&target, 0.5 * (a + b), config));
            assert!(feasible(&target, a, config) && feasible(&target, b, config), "{a} {b}");
            if a > -PI {
                assert!(!feasible(&target, a - 1e-7, config), "just below {a}");
            }
            if b < PI {
                assert!(!feasible(&target, b + 1e-7, config), "just above {b}");
            }
        }
        for w in iv.windows(2) {
            assert!(w[0].1 < w[1].0);
        }
        // A coarse independent scan agrees with the intervals.
        for k in 0..360 {
            let p = -PI + 2.0 * PI * (k as f64 + 0.5) / 360.0;
            let inside = iv.iter().any(|&(a, b)| a <= p && p <= b);
            assert_eq!(inside, feasible(&target, p, config), "ψ = {p}, {iv:?}");
        }
        seen += 1;
    }
    assert!(seen >= 8);
}

#[test]
fn selection_is_continuous_along_a_line() {
    let (robot, ik) = setup();
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let (mut paths, mut tries) = (0, 0);
    while paths < 5 {
        let q0 = robot.random_q(&mut rng);
        // Away from limits and singularities so a 10 cm line stays feasible.
        if q0.iter().zip(robot.joints()).any(|(v, j)| (v.abs() - j.limits.max).abs() < 0.3) || near_singular(&q0, 0.2) {
            continue;
        }
        tries += 1;
        let start = robot.fk(&q0).unwrap().world_from_tool;
        let dir = Vector3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0))
            .normalize();
        let length = 0.1;
        let mut q = q0.clone();
        let mut ok = true;
        for k in 1..=200 {
            let mut target = start;
            target.pos += dir * (length * k as f64 / 200.0);
            match ik.select(&q, &target, Some(&dir)) {
                Ok(s) => {
                    assert!(s.position_error < 1e-10 && s.orientation_error < 1e-10);
                    assert!(s.within_limits());
                    let step = max_diff(&s.q, &q);
                    assert!(step < 0.1, "step {k}: {step} from {q:?} to {:?}", s.q);
                    q = s.q;
                }
                Err(_) => {
                    ok = false;
                    break;
                }
            }
        }
        if ok {
            paths += 1;
        }
    }
    eprintln!("selection: {paths} complete paths of 200 poses out of {tries} tried");
    assert!(tries <= 10, "{tries} paths tried for 5 complete ones");
}

#[test]
fn selection_prefers_elbow_up_and_manipulability() {
    let (robot, ik) = setup();
    let q = robot.pose("fig9").unwrap().to_vec();
    let target = robot.fk(&q).unwrap().world_from_tool;
    let dir = Vector3::new(1.0, 0.0, 0.0);
    let s = ik.select(&q, &target, Some(&dir)).unwrap();
    assert!(s.position_error < 1e-10 && max_diff(&s.q, &q) <= 0.05 + 1e-12);
    // The chosen q3 is the best of the window along dir (or equal).
    let j = robot.jacobian(&s.q, kinema::Frame::Base).unwrap();
    let best = kinema::analysis::manipulability_along(&j, kinema::analysis::Axes::Translation, &dir).unwrap();
    for q3 in [q[2] - 0.05, q[2], q[2] + 0.05] {
        let Ok(near) = ik.solve_q3(&target, q3) else { continue };
        let n =
            near.iter().filter(|c| c.within_limits()).min_by(|a, b| max_diff(&a.q, &q).total_cmp(&max_diff(&b.q, &q)));
        if let Some(n) = n {
            let j = robot.jacobian(&n.q, kinema::Frame::Base).unwrap();
            let m = kinema::analysis::manipulability_along(&j, kinema::analysis::Axes::Translation, &dir).unwrap();
            assert!(m <= best + 1e-12, "{q3}: {m} > {best}");
        }
    }
    // Without a direction: the nearest, i.e. q itself.
    let s = ik.select(&q, &target, None).unwrap();
    assert!(max_diff(&s.q, &q) < 1e-9);
}

#[test]
fn validation_1e4() {
    let (_, ik) = setup();
    let r = ik.validate(10_000, 7);
    eprintln!("validate(10⁴): {r:?}");
    assert_eq!(r.cases, 10_000);
    assert_eq!(r.recovered_fraction, 1.0);
    assert!(r.max_error < 1e-10, "{r:?}");
    assert!(r.mean_error < 1e-13, "{r:?}");
    // Seed 004 §V-C's 1e-12 holds wherever the target's rounding allows it …
    assert!(r.well_conditioned_cases > 9_000, "{r:?}");
    assert!(r.max_error_well_conditioned <= 1e-12, "{r:?}");
    // … and everywhere the error stays within a few roundings of the target.
    assert!(r.max_error_over_limit < 5.0, "{r:?}");
}

/// The round-trip error is set by the conditioning of the problem, not by the
/// formulas: error · σ_min / u stays small, where σ_min is the smallest
/// singular value of the Jacobian without the column of q3 (the arm that
/// `solve_q3` inverts) and u the unit roundoff (the rounding of the target).
/// σ_min is computed here from the Jacobian directly, independently of
/// `ValidationCase::limit`, which must agree with it.
#[test]
fn validation_error_is_at_the_conditioning_floor() {
    let (robot, ik) = setup();
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let mut worst: f64 = 0.0;
    for _ in 0..2000 {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let e = ik.solve_q3(&target, q[2]).unwrap().iter().map(|s| max_diff(&s.q, &q)).fold(f64::INFINITY, f64::min);
        let j = robot.jacobian(&q, kinema::Frame::Base).unwrap();
        let j6 = kinema::nalgebra::DMatrix::from_fn(6, 6, |r, c| j[(r, if c < 2 { c } else { c + 1 })]);
        let ratio = e * j6.singular_values().min() / (0.5 * f64::EPSILON);
        worst = worst.max(ratio);
    }
    eprintln!("worst error·σ_min/u over 2000 cases: {worst:.2}");
    assert!(worst < 5.0, "{worst}");
    for c in ik.validation_cases(300, 8) {
        let j = robot.jacobian(&c.q, kinema::Frame::Base).unwrap();
        let j6 = kinema::nalgebra::DMatrix::from_fn(6, 6, |r, col| j[(r, if col < 2 { col } else { col + 1 })]);
        let want = 0.5 * f64::EPSILON / j6.singular_values().min();
        assert!((c.limit - want).abs() <= 1e-9 * want, "{} vs {want}", c.limit);
    }
}

/// A case the limit calls ill-conditioned really is: moving the target by
/// one rounding step along the worst direction (the left singular vector of
/// σ_min) moves the exact fixed-q3 solution by ≈ u/σ_min — checked by solving
/// the perturbed target with the closed form and comparing both solutions —
/// so a round-trip error of that size is the target's, not the solver's.
#[test]
fn ill_conditioned_cases_are_limited_by_the_target() {
    let (robot, ik) = setup();
    // Wrist nearly stretched (q6 = 2e-5 rad): σ_min ≈ 4e-6.
    let q = [0.4, 0.7, -0.3, -1.1, 0.9, 2e-5, 0.2];
    let target = robot.fk(&q).unwrap().world_from_tool;
    let j = robot.jacobian(&q, kinema::Frame::Base).unwrap();
    let j6 = kinema::nalgebra::Matrix6::from_fn(|r, c| j[(r, if c < 2 { c } else { c + 1 })]);
    let svd = j6.svd(true, true);
    let k = svd.singular_values.imin();
    let (sigma, u) = (svd.singular_values[k], svd.u.unwrap().column(k).into_owned());
    // A twist of size 1e-13 (a few hundred roundings, well above the noise)
    // along the worst direction, applied to the target.
    let h = 1e-13;
    let moved = kinema::Pose::new(
        kinema::math::axis_angle_to_rot(&(kinema::nalgebra::Vector3::new(u[3], u[4], u[5]) * h)) * target.rot,
        target.pos + kinema::nalgebra::Vector3::new(u[0], u[1], u[2]) * h,
    );
    let near = |t: &kinema::Pose| {
        ik.solve_q3(t, q[2])
            .unwrap()
            .into_iter()
            .min_by(|a, b| max_diff(&a.q, &q).total_cmp(&max_diff(&b.q, &q)))
            .unwrap()
    };
    let (a, b) = (near(&target), near(&moved));
    let shift = max_diff(&a.q, &b.q);
    eprintln!("σ_min {sigma:.3e}: a move of {h:e} along the worst direction moves the solution by {shift:.3e} rad");
    // First order: the solution moves by h/σ (in the 2-norm; the max-norm is at least 1/√6 of it).
    assert!(shift > h / sigma / 6f64.sqrt() * 0.5 && shift < h / sigma * 1.5, "shift {shift:e}, h/σ {:e}", h / sigma);
    assert!(shift > 1e-9, "{shift:e}");
}

#[test]
#[ignore = "10⁵ cases; run with --release -- --ignored"]
fn validation_1e5() {
    let (_, ik) = setup();
    let r = ik.validate(100_000, 11);
    eprintln!("validate(10⁵): {r:?}");
    assert_eq!(r.recovered_fraction, 1.0);
    assert!(r.max_error < 1e-8, "{r:?}");
    assert!(r.mean_error < 1e-13, "{r:?}");
    assert!(r.max_error_well_conditioned <= 1e-12, "{r:?}");
    assert!(r.max_error_over_limit < 5.0, "{r:?}");
}

#[test]
fn solve_q3_kernel_matches_solve_q3() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let ik = IiwaIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(79);
    for _ in 0..3000 {
        let q = robot.random_q(&mut rng);
        let t = robot.fk(&q).unwrap().world_from_tool;
        let c = ik.solve_q3_candidates(&t, q[2]).unwrap();
        let s = ik.solve_q3(&t, q[2]).unwrap();
        common::kernel_matches_solve(&robot, &c, &s, [t.pos.x, t.pos.y, t.pos.z]);
        assert!(c.qs().iter().any(|c| common::same_angles(c, &q, 1e-9)), "{q:?} not among {c:?}");
    }
}

/// A returned solution reaches `target` (FK-checked) and is within limits.
fn assert_reaches_within_limits(robot: &Robot, s: &kinema::ik::Solution, target: &Pose) {
    let fk = robot.fk(&s.q).unwrap();
    let e = kinema::math::pose_error(target, &fk.world_from_tool);
    assert!(e.position_norm() < 1e-9 && e.rotation_angle() < 1e-9, "{s:?}");
    assert!(s.position_error < 1e-9 && s.orientation_error < 1e-9, "{s:?}");
    assert!(s.within_limits() && fk.within_limits(), "{s:?}");
    assert_finite(&s.q);
}

/// A configuration near `q` (each joint moved by up to 0.2 rad, kept within limits).
fn nearby(robot: &Robot, q: &[f64], rng: &mut ChaCha8Rng) -> Vec<f64> {
    q.iter()
        .zip(robot.joints())
        .map(|(v, j)| (v + rng.random_range(-0.2..0.2)).clamp(j.limits.min, j.limits.max))
        .collect()
}

#[test]
fn searching_solves_every_reachable_target() {
    let (robot, ik) = setup();
    let mut rng = ChaCha8Rng::seed_from_u64(0x1aa5);
    let mut searched = 0;
    for _ in 0..3000 {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let sols = ik.solve_searching(&target, 0.0).unwrap_or_else(|e| panic!("{q:?} refused: {e}"));
        assert!(!sols.is_empty());
        for s in &sols {
            assert_reaches_within_limits(&robot, s, &target);
        }
        // The closed form at q3 = 0 keeps its `/front`/`/back` labels; the ψ search has none.
        if !sols[0].branch.ends_with("/front") && !sols[0].branch.ends_with("/back") {
            searched += 1;
            assert!(ik.solve_within_limits(&target).is_err());
        } else {
            assert!(sols.iter().all(|s| s.q[2] == 0.0));
        }
    }
    eprintln!("solve_searching: {searched} of 3000 targets needed the ψ search, none refused");
    assert!(searched > 30, "{searched}");
}

#[test]
fn searching_refuses_only_what_no_q3_reaches() {
    let (robot, ik) = setup();
    // Outside the annulus: the reach error of the closed form.
    let far = Pose::translation(2.0, 0.0, 0.36);
    assert!(matches!(
        ik.solve_searching(&far, 0.0),
        Err(Error::Unreachable { reason: Unreachable::OutsideReach { .. }, .. })
    ));
    let r = ik.solve_searching(&far, f64::NAN);
    assert!(matches!(r, Err(Error::Input(InputError::NotFinite { .. }))), "{r:?}");
    // The flange pointing into the base column: no ψ keeps q2 and q6 within ±120°.
    let q = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    let straight = robot.fk(&q).unwrap().world_from_tool;
    let down = Pose::new(Pose::rot_x(PI).rot, straight.pos - Vector3::new(0.0, 0.0, 0.6));
    match ik.solve_searching(&down, 0.0) {
        Err(Error::Unreachable { reason: Unreachable::JointLimits { rejected }, .. }) => {
            assert_eq!(rejected.len(), 8, "{rejected:?}")
        }
        other => panic!("{other:?}"),
    }
    let mut rng = ChaCha8Rng::seed_from_u64(0x1aa7);
    for _ in 0..200 {
        let p = Vector3::new(rng.random_range(-1.2..1.2), rng.random_range(-1.2..1.2), rng.random_range(-0.6..1.6));
        let t = Pose::new(Pose::rot_x(rng.random_range(-PI..PI)).rot * Pose::rot_y(rng.random_range(-PI..PI)).rot, p);
        if let Ok(sols) = ik.solve_searching(&t, 0.0) {
            sols.iter().for_each(|s| assert_reaches_within_limits(&robot, s, &t));
        }
    }
}

#[test]
fn selection_falls_back_to_the_search() {
    let (robot, ik) = setup();
    let mut rng = ChaCha8Rng::seed_from_u64(0x1aa6);
    let mut fell_back = 0;
    for _ in 0..3000 {
        let q = robot.random_q(&mut rng);
        let q0 = nearby(&robot, &q, &mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let s = ik.select(&q0, &target, None).unwrap_or_else(|e| panic!("{q:?} from {q0:?} refused: {e}"));
        assert_reaches_within_limits(&robot, &s, &target);
        if (s.q[2] - q0[2]).abs() > 0.05 + 1e-12 {
            fell_back += 1;
        }
    }
    eprintln!("select: {fell_back} of 3000 targets needed the ψ search, none refused");
    assert!(fell_back > 20, "{fell_back}");
}
