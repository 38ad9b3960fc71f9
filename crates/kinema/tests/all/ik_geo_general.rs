//! `geo-general` (`ik::geo::GeneralIk`): the 2-D search for any 6R arm, on
//! seeded random arms with no special structure (random axes and random DH
//! tables): every solution meets the pose, the configuration a target came
//! from is found, the solutions are at least as many as a numeric
//! multi-start finds, the registry gives the family only arms no other
//! family fits, and `general` TOML and URDF descriptions are solved.

use std::f64::consts::PI;
use std::time::Instant;

use kinema::ik::geo::GeneralIk;
use kinema::ik::registry::{fit, FAMILIES};
use kinema::ik::{IkSolver, NumericIk, NumericOptions, Solution};
use kinema::nalgebra::{Rotation3, Unit, Vector3};
use kinema::{Pose, Robot};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common;
use common::same_angles;

type V3 = Vector3<f64>;

fn random_unit(rng: &mut ChaCha8Rng) -> V3 {
    loop {
        let v = V3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
        if v.norm() > 0.2 && v.norm() < 1.0 {
            return v.normalize();
        }
    }
}

fn random_pose(rng: &mut ChaCha8Rng) -> Pose {
    let axis = Unit::new_normalize(random_unit(rng));
    Pose::new(*Rotation3::from_axis_angle(&axis, rng.random_range(-PI..PI)).matrix(), random_unit(rng) * 0.3)
}

/// A 6R arm of `general` joints with random axes through random points.
fn random_axes_arm(rng: &mut ChaCha8Rng, k: usize) -> Robot {
    let mut h = [V3::zeros(); 6];
    let mut p = [V3::zeros(); 6];
    for i in 0..6 {
        h[i] = random_unit(rng);
        p[i] = if i == 0 { V3::zeros() } else { p[i - 1] + random_unit(rng) * rng.random_range(0.05..0.4) };
    }
    let (base, tool) = (random_pose(rng), random_pose(rng));
    common::robot_from_axes(&format!("axes-{k}"), &h, &p, base, tool)
}

/// The TOML of a 6R arm with a random standard DH table (lengths in m,
/// twists in degrees, limits ±180°).
fn random_dh_toml(rng: &mut ChaCha8Rng, k: usize) -> String {
    let mut toml = format!(
        "name = \"dh-{k}\"\nsource = \"random DH table, tests/ik_geo_general.rs\"\nconvention = \"standard\"\n\
         [units]\nlength = \"m\"\nangle = \"deg\"\n"
    );
    for i in 0..6 {
        let (d, a, alpha) = (rng.random_range(-0.3..0.3), rng.random_range(0.02..0.4), rng.random_range(10.0..170.0));
        let alpha = if rng.random_bool(0.5) { alpha } else { -alpha };
        toml += &format!("[[joint]]\nname = \"j{i}\"\nd = {d}\na = {a}\nalpha = {alpha}\nmin = -180\nmax = 180\n");
    }
    toml + "[poses]\nhome = [0, 0, 0, 0, 0, 0]\n"
}

/// `count` random general arms, half from axes, half from DH tables.
fn arms(seed: u64, count: usize) -> Vec<Robot> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..count)
        .map(|k| {
            if k % 2 == 0 {
                random_axes_arm(&mut rng, k)
            } else {
                Robot::from_toml_str(&random_dh_toml(&mut rng, k), "random.toml").unwrap()
            }
        })
        .collect()
}

/// Distinct configurations (modulo 2π, to `tol`) among `qs`.
fn distinct(qs: &[Vec<f64>], tol: f64) -> Vec<Vec<f64>> {
    let mut out: Vec<Vec<f64>> = Vec::new();
    for q in qs {
        if !out.iter().any(|o| same_angles(o, q, tol)) {
            out.push(q.clone());
        }
    }
    out
}

struct Sweep {
    targets: usize,
    original_found: usize,
    solutions: usize,
    nanos: u128,
    misses: Vec<String>,
}

/// FK → IK round trips: every solution within 1e-9 m / 1e-9 rad, distinct
/// modulo 2π, and whether the original configuration is among them.
fn round_trips(robots: &[Robot], per_arm: usize, seed: u64) -> Sweep {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut s = Sweep { targets: 0, original_found: 0, solutions: 0, nanos: 0, misses: Vec::new() };
    for robot in robots {
        let ik = GeneralIk::new(robot).unwrap();
        for _ in 0..per_arm {
            let q = robot.random_q(&mut rng);
            let target = robot.fk(&q).unwrap().world_from_tool;
            let t0 = Instant::now();
            let sols = ik.solve(&target).unwrap_or_default();
            s.nanos += t0.elapsed().as_nanos();
            s.targets += 1;
            s.solutions += sols.len();
            for sol in &sols {
                assert!(
                    sol.position_error < 1e-9 && sol.orientation_error < 1e-9,
                    "{}: q = {q:?}: {sol:?}",
                    robot.name()
                );
                let fk = robot.fk(&sol.q).unwrap().world_from_tool;
                assert!((fk.pos - target.pos).norm() < 1e-9 && (fk.rot - target.rot).norm() < 1e-9);
            }
            let qs: Vec<Vec<f64>> = sols.iter().map(|x| x.q.clone()).collect();
            assert_eq!(distinct(&qs, 1e-6).len(), qs.len(), "{}: duplicates {qs:?}", robot.name());
            if sols.iter().any(|x| same_angles(&x.q, &q, 1e-6)) {
                s.original_found += 1;
            } else {
                let jac = robot.jacobian(&q, kinema::Frame::Base).unwrap();
                let sv = jac.svd(false, false).singular_values;
                s.misses.push(format!(
                    "{}: q = {q:.4?}, {} solutions, smallest singular value {:.2e}",
                    robot.name(),
                    sols.len(),
                    sv.min()
                ));
            }
        }
    }
    s
}

#[test]
fn solutions_meet_the_pose_and_include_the_original() {
    let robots = arms(0x6e6e, 20);
    let s = round_trips(&robots, 100, 1);
    let rate = s.original_found as f64 / s.targets as f64;
    eprintln!(
        "geo-general: original found in {} of {} targets ({:.2} %), {:.2} solutions per target, {:.3} ms per solve",
        s.original_found,
        s.targets,
        100.0 * rate,
        s.solutions as f64 / s.targets as f64,
        s.nanos as f64 / s.targets as f64 * 1e-6
    );
    for m in &s.misses {
        eprintln!("  missed: {m}");
    }
    assert!(rate >= 0.99, "original found in only {:.2} %", 100.0 * rate);
}

/// Distinct converged solutions of a numeric multi-start (`starts` random
/// starting configurations, each run once without restarts).
fn numeric_solutions(robot: &Robot, target: &Pose, starts: usize, rng: &mut ChaCha8Rng) -> Vec<Vec<f64>> {
    let opts = NumericOptions {
        max_restarts: 0,
        enforce_limits: false,
        tol_position: 1e-10,
        tol_orientation: 1e-10,
        ..Default::default()
    };
    let numeric = NumericIk::with_options(robot, opts).unwrap();
    let mut found = Vec::new();
    for _ in 0..starts {
        let q0 = robot.random_q(rng);
        if let Ok(s) = numeric.solve_from(target, &q0) {
            if s.position_error <= 1e-9 && s.orientation_error <= 1e-9 {
                found.push(s.q.iter().map(|v| kinema::ik::wrap_angle(*v)).collect());
            }
        }
    }
    distinct(&found, 1e-5)
}

fn compare_with_numeric(arms_seed: u64, arm_count: usize, per_arm: usize, starts: usize) -> (usize, usize) {
    let robots = arms(arms_seed, arm_count);
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let (mut targets, mut at_least) = (0, 0);
    for robot in &robots {
        let ik = GeneralIk::new(robot).unwrap();
        for _ in 0..per_arm {
            let q = robot.random_q(&mut rng);
            let target = robot.fk(&q).unwrap().world_from_tool;
            let sols: Vec<Solution> = ik.solve(&target).unwrap_or_default();
            let numeric = numeric_solutions(robot, &target, starts, &mut rng);
            targets += 1;
            let missing: Vec<&Vec<f64>> =
                numeric.iter().filter(|n| !sols.iter().any(|s| same_angles(&s.q, n, 1e-5))).collect();
            if sols.len() >= numeric.len() {
                at_least += 1;
            } else {
                eprintln!(
                    "  {}: {} geometric < {} numeric; numeric not found: {missing:.4?}; found {:.4?}",
                    robot.name(),
                    sols.len(),
                    numeric.len(),
                    sols.iter().map(|s| s.q.clone()).collect::<Vec<_>>()
                );
            }
        }
    }
    (at_least, targets)
}

/// Issue 34 item 7: on every target, at least as many solutions as a
/// 100-start numeric search finds (an odd count, one missed, failed 1 of 200
/// here before the finer search around the solutions found).
#[test]
fn at_least_as_many_solutions_as_a_numeric_multi_start() {
    let (at_least, targets) = compare_with_numeric(0x6e6e, 20, 10, 100);
    eprintln!(
        "geo-general: ≥ the numeric multi-start's distinct solutions in {at_least} of {targets} targets ({:.2} %)",
        100.0 * at_least as f64 / targets as f64
    );
    assert_eq!(at_least, targets);
}

#[test]
#[ignore = "heavy sweep: cargo test -p kinema --release --test all -- --ignored --nocapture ik_geo_general::"]
fn heavy_sweep() {
    let s = round_trips(&arms(0xbeef, 100), 200, 3);
    eprintln!(
        "heavy: original found in {} of {} ({:.3} %), {:.3} ms per solve",
        s.original_found,
        s.targets,
        100.0 * s.original_found as f64 / s.targets as f64,
        s.nanos as f64 / s.targets as f64 * 1e-6
    );
    for m in s.misses.iter().take(30) {
        eprintln!("  missed: {m}");
    }
    let (at_least, targets) = compare_with_numeric(0xbeef, 50, 20, 300);
    eprintln!("heavy: ≥ numeric in {at_least} of {targets}");
}

#[test]
fn the_registry_gives_geo_general_only_to_arms_no_other_family_fits() {
    let general = FAMILIES.iter().position(|e| e.name == "geo-general").unwrap();
    for name in ["ur5", "puma560"] {
        let robot = Robot::builtin(name).unwrap();
        assert!(GeneralIk::new(&robot).is_ok(), "{name}: the general solver takes any 6R arm");
        let first = FAMILIES.iter().position(|e| (e.fit)(&robot).is_ok()).unwrap();
        assert!(first < general, "{name}: {}", FAMILIES[first].name);
        assert_ne!(fit(&robot).unwrap().name(), "geo-general");
    }
    // Seven joints and the Scorbot's five: no.
    assert!(GeneralIk::new(&Robot::builtin("panda").unwrap()).is_err());
    assert!(GeneralIk::new(&Robot::builtin("scorbot-er-v-plus").unwrap()).is_err());
    for robot in arms(0x6e6e, 6) {
        assert_eq!(fit(&robot).unwrap().name(), "geo-general", "{}", robot.name());
        assert_eq!(kinema::ik::analytic_solver(&robot).map(|s| s.name()), Some("geo-general"));
    }
}

/// The URDF of a general 6R arm: joint origins with rotations, and axes not
/// along the frame axes.
fn general_urdf() -> String {
    let joints = [
        ("0 0 0.1", "0 0 0", "0 0 1"),
        ("0.05 0.02 0.3", "0.4 0.1 0", "0.2 1 0.1"),
        ("0.35 -0.04 0.03", "0 0.3 0.2", "0.1 0.9 -0.3"),
        ("0.06 0.01 0.3", "-0.5 0 0.1", "1 0.1 0.2"),
        ("0.02 0.05 0.04", "0.3 -0.2 0", "0 0.8 0.5"),
        ("0.03 -0.02 0.08", "0 0 0.7", "0.6 0 1"),
    ];
    let mut s = String::from("<?xml version=\"1.0\"?>\n<robot name=\"general6r\">\n  <link name=\"l0\"/>\n");
    for (i, (xyz, rpy, axis)) in joints.iter().enumerate() {
        s += &format!(
            "  <link name=\"l{}\"/>\n  <joint name=\"j{}\" type=\"revolute\">\n    <parent link=\"l{i}\"/>\n    \
             <child link=\"l{}\"/>\n    <origin xyz=\"{xyz}\" rpy=\"{rpy}\"/>\n    <axis xyz=\"{axis}\"/>\n    \
             <limit lower=\"-3.14159\" upper=\"3.14159\" effort=\"1\" velocity=\"1\"/>\n  </joint>\n",
            i + 1,
            i + 1,
            i + 1
        );
    }
    s + "</robot>\n"
}

#[test]
fn general_urdf_and_toml_descriptions_are_solved() {
    let dir = std::env::temp_dir().join(format!("kinema-geo-general-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let urdf = dir.join("general6r.urdf");
    std::fs::write(&urdf, general_urdf()).unwrap();
    let from_urdf = Robot::from_file(&urdf, None).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let from_toml = Robot::from_toml_str(&random_dh_toml(&mut rng, 99), "dh.toml").unwrap();
    for robot in [from_urdf, from_toml] {
        let ik = fit(&robot).unwrap();
        assert_eq!(ik.name(), "geo-general", "{}", robot.name());
        // Every solution is checked inside; originals may be missed near singular targets.
        let s = round_trips(std::slice::from_ref(&robot), 30, 12);
        eprintln!("{}: original found in {} of 30; {:?}", robot.name(), s.original_found, s.misses);
        assert!(s.original_found >= 27, "{}: {} of 30; {:?}", robot.name(), s.original_found, s.misses);
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn unreachable_and_malformed_targets() {
    let robot = &arms(0x6e6e, 1)[0];
    let ik = GeneralIk::new(robot).unwrap();
    let far = Pose::translation(30.0, 0.0, 0.0);
    assert!(matches!(ik.solve(&far), Err(kinema::Error::Unreachable { .. })));
    let nan = Pose::translation(f64::NAN, 0.0, 0.0);
    assert!(matches!(ik.solve(&nan), Err(kinema::Error::Input(kinema::InputError::NotFinite { .. }))));
    common::random_poses_never_panic_or_return_nan(&ik);
}
