//! The fast path against the reference path, and the reference path against
//! derivatives of itself.
//!
//! `Robot::fk`, `Robot::link_frames`, `Robot::jacobian` (base and tool frame)
//! and `kin::jacobian_rows_into` must equal `kinema::reference` to rounding
//! on every built-in robot, on random arms of every joint kind, mix and
//! length from 1 to 12, on chains of every joint kind after every other, and
//! on the descriptions in `tests/data`. The reference Jacobian must equal
//! central differences of the reference FK, and the derivatives of the
//! reference FK evaluated with dual numbers (`num_dual::Dual64`, forward-mode
//! automatic differentiation through the same generic code). Each test prints
//! the largest difference it saw (`cargo test -p kinema --test reference --
//! --nocapture`).

use kinema::nalgebra::{IsometryMatrix3, Matrix3, Matrix6xX, Vector3};
use kinema::{reference, DhConvention, Frame, Joint, JointType, LinkGeometry, Pose, Robot};
use num_dual::Dual64;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common;
use common::arms::{every_joint_kind, random_arm, random_q, robot_of};

/// The mixes of random arms: uniform chains of standard or of modified DH
/// revolute joints with exact twists (the fast path's branch-free shapes),
/// and arms mixing every kind.
const MIXES: [Option<DhConvention>; 3] = [Some(DhConvention::Standard), Some(DhConvention::Modified), None];

/// A bound on every distance in the chain at `q` \[m\]: the base and tool
/// offsets, every link's lengths and every prismatic joint's travel. Position
/// errors grow with it; rotation errors do not, so it only loosens those.
fn reach(robot: &Robot, q: &[f64]) -> f64 {
    let link = |j: &Joint, v: f64| {
        let travel = if j.kind == JointType::Prismatic { (v + j.offset).abs() } else { 0.0 };
        travel
            + match j.geometry {
                LinkGeometry::Dh { d, a, .. } => d.abs() + a.abs(),
                LinkGeometry::General { origin, .. } => origin.pos.norm(),
            }
    };
    let links: f64 = robot.joints().iter().zip(q).map(|(j, &v)| link(j, v)).sum();
    robot.base().pos.norm() + robot.tool().pos.norm() + links
}

/// The largest difference between the fast path and the reference at `q`
/// that is still rounding: a few ulp per factor of the chain (two per joint,
/// base, tool), times the reach.
fn tolerance(robot: &Robot, q: &[f64]) -> f64 {
    1e-15 * (2 * robot.dof() + 2) as f64 * reach(robot, q).max(1.0)
}

/// Max-norm distance between a fast-path pose and a reference transform.
fn pose_diff(fast: &Pose, plain: &IsometryMatrix3<f64>) -> f64 {
    let dr = (fast.rot - plain.rotation.matrix()).abs().max();
    let dp = (fast.pos - plain.translation.vector).abs().max();
    dr.max(dp)
}

/// The largest differences seen, absolute and as a fraction of the tolerance.
#[derive(Default)]
struct Worst {
    cases: usize,
    diff: f64,
    of_tolerance: f64,
}

impl Worst {
    fn see(&mut self, diff: f64, tol: f64, what: &dyn Fn() -> String) {
        assert!(diff <= tol, "{} differs by {diff:e} (tolerance {tol:e})", what());
        self.diff = self.diff.max(diff);
        self.of_tolerance = self.of_tolerance.max(diff / tol);
    }

    fn report(&self, what: &str) {
        eprintln!(
            "{what}: {} configurations, largest difference {:.2e} ({:.0} % of its tolerance)",
            self.cases,
            self.diff,
            100.0 * self.of_tolerance
        );
    }
}

/// Every fast-path result at `q` against the reference: FK, every link frame,
/// the Jacobian in both frames, column-major and row-major.
fn check_fast_path(robot: &Robot, q: &[f64], worst: &mut Worst, label: &str) {
    let n = robot.dof();
    let tol = tolerance(robot, q);
    let what = |part: &str| format!("{label}: {part} at q = {q:?} of {robot:?}");
    let frames = reference::link_frames(robot, q).unwrap();
    worst.see(pose_diff(&robot.fk(q).unwrap().world_from_tool, &frames[n + 1]), tol, &|| what("FK"));
    for (i, (fast, plain)) in robot.link_frames(q).unwrap().iter().zip(&frames).enumerate() {
        worst.see(pose_diff(fast, plain), tol, &|| what(&format!("frame {i}")));
    }
    let mut rows = vec![f64::NAN; 6 * n];
    for frame in [Frame::Base, Frame::Tool] {
        let plain = reference::jacobian(robot, q, frame).unwrap();
        let fast = robot.jacobian(q, frame).unwrap();
        worst.see((&fast - &plain).abs().max(), tol, &|| what(&format!("{frame:?} Jacobian")));
        kinema::kin::jacobian_rows_into(robot, q, frame, &mut rows).unwrap();
        let row_major = Matrix6xX::from_row_slice(&rows);
        worst.see((&row_major - &plain).abs().max(), tol, &|| what(&format!("{frame:?} Jacobian rows")));
    }
    worst.cases += 1;
}

#[test]
fn every_builtin_robot_matches_the_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x2ef0);
    let mut worst = Worst::default();
    let names: Vec<&str> = kinema::builtin_names().collect();
    assert!(names.len() >= 7, "expected the built-in robots, found {names:?}");
    for name in names {
        let robot = Robot::builtin(name).unwrap();
        for pose in robot.poses() {
            check_fast_path(&robot, &pose.q, &mut worst, name);
        }
        for _ in 0..2000 {
            check_fast_path(&robot, &robot.random_q(&mut rng), &mut worst, name);
        }
    }
    worst.report("built-in robots");
}

#[test]
fn random_arms_of_every_mix_and_length_match_the_reference() {
    const ARMS: usize = 60;
    const CONFIGS: usize = 5;
    let mut rng = ChaCha8Rng::seed_from_u64(0x2ef1);
    let mut worst = Worst::default();
    for uniform in MIXES {
        for n in 1..=12 {
            for _ in 0..ARMS {
                let robot = random_arm(&mut rng, n, uniform);
                for _ in 0..CONFIGS {
                    let q = random_q(&mut rng, n);
                    check_fast_path(&robot, &q, &mut worst, &format!("{n} joints, {uniform:?}"));
                }
            }
        }
    }
    worst.report("random arms");
}

#[test]
fn every_joint_kind_after_every_other_matches_the_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x2ef2);
    let mut worst = Worst::default();
    let kinds = every_joint_kind();
    let base = Pose::rot_x(0.4) * Pose::translation(0.1, 0.0, 0.2);
    for (i, a) in kinds.iter().enumerate() {
        for (k, b) in kinds.iter().enumerate() {
            let robot = robot_of(vec![a.clone(), b.clone(), a.clone()], base, Pose::rot_z(0.2));
            for _ in 0..3 {
                let q = random_q(&mut rng, 3);
                check_fast_path(&robot, &q, &mut worst, &format!("kinds {i}, {k}, {i}"));
            }
        }
    }
    // All of them in one chain: several of the fast path's eight-joint blocks.
    let robot = robot_of(kinds.clone(), base, Pose::rot_z(0.2));
    for _ in 0..200 {
        check_fast_path(&robot, &random_q(&mut rng, kinds.len()), &mut worst, "all kinds");
    }
    worst.report("every kind after every kind");
}

/// The descriptions in `tests/data` that load: every URDF (a tree once per
/// leaf link, as its tip) and every TOML but the one made to fail.
fn data_robots() -> Vec<(String, Robot)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let mut robots = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let file = path.file_name().unwrap().to_string_lossy().to_string();
        match path.extension().and_then(|e| e.to_str()) {
            Some("urdf") => match Robot::from_file(&path, None) {
                Ok(robot) => robots.push((file, robot)),
                Err(_) => {
                    let text = std::fs::read_to_string(&path).unwrap();
                    let urdf = urdf_rs::read_from_string(&text).unwrap();
                    let tips: Vec<(String, Robot)> = urdf
                        .links
                        .iter()
                        .filter_map(|l| Robot::from_file(&path, Some(&l.name)).ok().map(|r| (l.name.clone(), r)))
                        .collect();
                    assert!(!tips.is_empty(), "{file}: loads with no tip");
                    robots.extend(tips.into_iter().map(|(tip, r)| (format!("{file} to {tip}"), r)));
                }
            },
            Some("toml") if file != "malformed.toml" => {
                robots.push((file.clone(), Robot::from_file(&path, None).unwrap()))
            }
            _ => {}
        }
    }
    robots
}

#[test]
fn the_test_descriptions_match_the_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x2ef3);
    let mut worst = Worst::default();
    let robots = data_robots();
    let urdfs = robots.iter().filter(|(f, _)| f.contains(".urdf")).count();
    assert!(urdfs >= 4, "expected the URDFs of tests/data (three arms, two tips of a tree), found {urdfs}");
    for (file, robot) in &robots {
        for _ in 0..1000 {
            check_fast_path(robot, &robot.random_q(&mut rng), &mut worst, file);
        }
    }
    worst.report("tests/data descriptions");
}

/// The rotation vector ω of a skew-symmetric \[ω\]× (its skew part, if rounding left some symmetric part).
fn vee(m: &Matrix3<f64>) -> Vector3<f64> {
    0.5 * Vector3::new(m[(2, 1)] - m[(1, 2)], m[(0, 2)] - m[(2, 0)], m[(1, 0)] - m[(0, 1)])
}

/// Built-in robots and random arms of every mix, with a configuration each.
fn sample_arms(rng: &mut ChaCha8Rng) -> Vec<(Robot, Vec<f64>)> {
    let mut arms = Vec::new();
    for name in kinema::builtin_names() {
        let robot = Robot::builtin(name).unwrap();
        for _ in 0..50 {
            let q = robot.random_q(rng);
            arms.push((robot.clone(), q));
        }
    }
    for uniform in MIXES {
        for _ in 0..300 {
            let n = rng.random_range(1..=12);
            arms.push((random_arm(rng, n, uniform), random_q(rng, n)));
        }
    }
    arms
}

#[test]
fn reference_jacobian_equals_central_differences_of_reference_fk() {
    const H: f64 = 1e-6;
    let mut rng = ChaCha8Rng::seed_from_u64(0x2ef4);
    let mut worst = Worst::default();
    for (robot, q) in sample_arms(&mut rng) {
        let j = reference::jacobian(&robot, &q, Frame::Base).unwrap();
        let at = |i: usize, h: f64| {
            let mut q = q.clone();
            q[i] += h;
            reference::world_from_tool(&robot, &q).unwrap()
        };
        // Central differences are good to ~h² times the third derivatives
        // plus rounding / h, so this is far looser than the other checks.
        let tol = 1e-8 * reach(&robot, &q).max(1.0).powi(2);
        for i in 0..robot.dof() {
            let (p, m) = (at(i, H), at(i, -H));
            let v = (p.translation.vector - m.translation.vector) / (2.0 * H);
            // R(q + h)·R(q − h)ᵀ ≈ I + [2h·ω]×.
            let w = vee(&(p.rotation.matrix() * m.rotation.matrix().transpose())) / (2.0 * H);
            let what = || format!("column {i} at q = {q:?} of {robot:?}");
            worst.see((j.fixed_view::<3, 1>(0, i) - v).abs().max(), tol, &what);
            worst.see((j.fixed_view::<3, 1>(3, i) - w).abs().max(), tol, &what);
        }
        worst.cases += 1;
    }
    worst.report("reference Jacobian − central differences");
}

/// The reference FK at `q` with joint `i` seeded: every value's derivative
/// part is its derivative by q_i.
fn fk_derivative(robot: &Robot, q: &[f64], i: usize) -> IsometryMatrix3<Dual64> {
    let qd: Vec<Dual64> = q.iter().enumerate().map(|(k, &v)| Dual64::new(v, if k == i { 1.0 } else { 0.0 })).collect();
    reference::world_from_tool(robot, &qd).unwrap()
}

#[test]
fn reference_jacobian_equals_reference_fk_differentiated_with_dual_numbers() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x2ef5);
    let mut worst = Worst::default();
    for (robot, q) in sample_arms(&mut rng) {
        let tol = tolerance(&robot, &q);
        let base = reference::jacobian(&robot, &q, Frame::Base).unwrap();
        let tool = reference::jacobian(&robot, &q, Frame::Tool).unwrap();
        for i in 0..robot.dof() {
            let t = fk_derivative(&robot, &q, i);
            let r = t.rotation.matrix().map(|x| x.re);
            let dr = t.rotation.matrix().map(|x| x.eps);
            let dp = t.translation.vector.map(|x| x.eps);
            // The same arithmetic also gives the value: exactly the f64 reference.
            let plain = reference::world_from_tool(&robot, &q).unwrap();
            assert_eq!(r, *plain.rotation.matrix());
            // Ṙ = [ω]×·R in the base frame, Ṙ = R·[ω_tool]× in the tool's axes.
            let columns = [
                (&base, dp, vee(&(dr * r.transpose())), Frame::Base),
                (&tool, r.transpose() * dp, vee(&(r.transpose() * dr)), Frame::Tool),
            ];
            for (j, v, w, frame) in columns {
                let what = || format!("{frame:?} column {i} at q = {q:?} of {robot:?}");
                worst.see((j.fixed_view::<3, 1>(0, i) - v).abs().max(), tol, &what);
                worst.see((j.fixed_view::<3, 1>(3, i) - w).abs().max(), tol, &what);
            }
        }
        worst.cases += 1;
    }
    worst.report("reference Jacobian − dual-number derivatives of reference FK");
}

/// Joint rates for `robot`, each in [−2, 2] rad/s or m/s.
fn random_rates(rng: &mut ChaCha8Rng, n: usize) -> Vec<f64> {
    (0..n).map(|_| rng.random_range(-2.0..=2.0)).collect()
}

#[test]
fn jacobian_dot_equals_the_jacobian_differentiated_with_dual_numbers() {
    // q + ε·q̇ through the reference Jacobian: its ε part is exactly dJ/dt.
    let mut rng = ChaCha8Rng::seed_from_u64(0x2ef6);
    let mut worst = Worst::default();
    for (robot, q) in sample_arms(&mut rng) {
        let qd = random_rates(&mut rng, robot.dof());
        let dual: Vec<Dual64> = q.iter().zip(&qd).map(|(&a, &b)| Dual64::new(a, b)).collect();
        let tol = tolerance(&robot, &q) * 4.0;
        for frame in [Frame::Base, Frame::Tool] {
            let jd = reference::jacobian_dot(&robot, &q, &qd, frame).unwrap();
            let want = reference::jacobian(&robot, &dual, frame).unwrap().map(|x| x.eps);
            let what = || format!("{frame:?} at q = {q:?}, q̇ = {qd:?} of {robot:?}");
            worst.see((jd - want).abs().max(), tol, &what);
        }
        worst.cases += 1;
    }
    worst.report("reference J̇ − dual-number derivative of the reference Jacobian");
}

#[test]
fn jacobian_dot_equals_central_differences_of_the_jacobian() {
    const H: f64 = 1e-6;
    let mut rng = ChaCha8Rng::seed_from_u64(0x2ef7);
    let mut worst = Worst::default();
    for (robot, q) in sample_arms(&mut rng) {
        let qd = random_rates(&mut rng, robot.dof());
        let at = |s: f64| -> Vec<f64> { q.iter().zip(&qd).map(|(a, b)| a + s * b).collect() };
        let tol = 1e-7 * reach(&robot, &q).max(1.0).powi(2);
        for frame in [Frame::Base, Frame::Tool] {
            let jd = reference::jacobian_dot(&robot, &q, &qd, frame).unwrap();
            let ahead = reference::jacobian(&robot, &at(H), frame).unwrap();
            let behind = reference::jacobian(&robot, &at(-H), frame).unwrap();
            let what = || format!("{frame:?} at q = {q:?}, q̇ = {qd:?} of {robot:?}");
            worst.see((jd - (ahead - behind) / (2.0 * H)).abs().max(), tol, &what);
        }
        worst.cases += 1;
    }
    worst.report("reference J̇ − central differences of the reference Jacobian");
    let robot = Robot::builtin("panda").unwrap();
    let e = reference::jacobian_dot(&robot, robot.home(), &[0.0; 6], Frame::Base).unwrap_err();
    assert!(matches!(e, kinema::Error::Input(kinema::InputError::JointCount { expected: 7, got: 6, .. })), "{e:?}");
}

#[test]
fn a_wrong_joint_count_is_an_error() {
    let robot = Robot::builtin("panda").unwrap();
    for q in [vec![0.0; 6], vec![0.0; 8], vec![]] {
        assert!(matches!(
            reference::world_from_tool(&robot, &q),
            Err(kinema::Error::Input(kinema::InputError::JointCount { .. }))
        ));
        assert!(matches!(
            reference::jacobian(&robot, &q, Frame::Tool),
            Err(kinema::Error::Input(kinema::InputError::JointCount { .. }))
        ));
    }
}
