//! The geometric solvers (`ik::geo`): the product-of-exponentials kinematics
//! against `Robot::fk` on every kind of description, seeded FK → IK round
//! trips on the UR5 and the PUMA 560 (built-in DH, URDF, TOML `general`) and
//! on random arms of each family, agreement with `pieper` on the PUMA, and
//! unreachable and malformed targets.

use std::f64::consts::PI;

use kinema::ik::geo::{
    GeoIk, Kinematics, ShoulderKind, SphericalWristIk, ThreeParallelIk, ThreeParallelSearchIk, TwoIntersectingSearchIk,
};
use kinema::ik::pieper::PieperIk;
use kinema::ik::{analytic_solver, IkSolver, NumericIk, NumericOptions, Solution};
use kinema::nalgebra::{Rotation3, Unit, Vector3};
use kinema::{DhConvention, Error, GeometryKind, Joint, JointType, Limits, LinkGeometry, Model, Pose, Robot};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common;
use common::same_angles;
use kinema::InputError;

type V3 = Vector3<f64>;

const TOL: f64 = 1e-9;
const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data");

fn data(file: &str) -> Robot {
    Robot::from_file(format!("{DATA}/{file}"), None).unwrap()
}

fn random_unit(rng: &mut ChaCha8Rng) -> V3 {
    loop {
        let v = V3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
        if v.norm() > 0.2 && v.norm() < 1.0 {
            return v.normalize();
        }
    }
}

fn random_point(rng: &mut ChaCha8Rng, r: f64) -> V3 {
    random_unit(rng) * rng.random_range(0.0..r)
}

fn random_pose(rng: &mut ChaCha8Rng) -> Pose {
    let axis = Unit::new_normalize(random_unit(rng));
    Pose::new(*Rotation3::from_axis_angle(&axis, rng.random_range(-PI..PI)).matrix(), random_point(rng, 0.5))
}

/// A unit vector at least `min` (in |sin|) away from each of `others`.
fn unit_away(rng: &mut ChaCha8Rng, others: &[V3], min: f64) -> V3 {
    loop {
        let v = random_unit(rng);
        if others.iter().all(|o| v.cross(o).norm() > min) {
            return v;
        }
    }
}

/// A 6R robot of `general` joints with axes (h, p) at q = 0 and a random base and tool.
fn robot_from_axes(name: &str, h: &[V3; 6], p: &[V3; 6], rng: &mut ChaCha8Rng) -> Robot {
    let (base, tool) = (random_pose(rng), random_pose(rng));
    common::robot_from_axes(name, h, p, base, tool)
}

/// A random arm with a spherical wrist; `parallel23` picks the shoulder.
fn random_spherical(rng: &mut ChaCha8Rng, parallel23: bool) -> Robot {
    random_spherical_with(rng, parallel23, false)
}

/// As `random_spherical`; with `offset4` axis 4 passes the point where axes 5
/// and 6 meet at a distance of 0.05–0.2 m.
fn random_spherical_with(rng: &mut ChaCha8Rng, parallel23: bool, offset4: bool) -> Robot {
    let mut h = [V3::zeros(); 6];
    let mut p = [V3::zeros(); 6];
    if parallel23 {
        h[1] = random_unit(rng);
        h[2] = if rng.random_bool(0.5) { h[1] } else { -h[1] };
        h[0] = unit_away(rng, &h[1..2], 0.3);
        p[0] = random_point(rng, 0.3);
        p[1] = random_point(rng, 0.3);
        p[2] = p[1] + unit_away(rng, &h[1..2], 0.3) * rng.random_range(0.2..0.6);
    } else {
        let c = random_point(rng, 0.3);
        h[0] = random_unit(rng);
        h[1] = unit_away(rng, &h[..1], 0.3);
        h[2] = unit_away(rng, &h[..2], 0.3);
        p[0] = c + h[0] * rng.random_range(-0.3..0.3);
        p[1] = c + h[1] * rng.random_range(-0.3..0.3);
        p[2] = c + unit_away(rng, &h[2..3], 0.3) * rng.random_range(0.2..0.6);
    }
    let w = p[2] + unit_away(rng, &h[2..3], 0.3) * rng.random_range(0.2..0.6);
    h[3] = random_unit(rng);
    h[4] = unit_away(rng, &h[3..4], 0.3);
    h[5] = unit_away(rng, &h[4..5], 0.3);
    for i in 3..6 {
        p[i] = w + h[i] * rng.random_range(-0.2..0.2);
    }
    if offset4 {
        p[3] += unit_away(rng, &h[3..4], 0.3).cross(&h[3]).normalize() * rng.random_range(0.05..0.2);
    }
    robot_from_axes("random-spherical", &h, &p, rng)
}

/// A random arm with axes 2 ∥ 3 ∥ 4 and axes 5, 6 meeting.
fn random_three_parallel(rng: &mut ChaCha8Rng) -> Robot {
    random_three_parallel_with(rng, false)
}

/// As `random_three_parallel`; with `skew56` axis 6 passes axis 5 at a
/// distance of 0.05–0.2 m.
fn random_three_parallel_with(rng: &mut ChaCha8Rng, skew56: bool) -> Robot {
    let mut h = [V3::zeros(); 6];
    let mut p = [V3::zeros(); 6];
    h[1] = random_unit(rng);
    for i in [2, 3] {
        h[i] = if rng.random_bool(0.5) { h[1] } else { -h[1] };
    }
    h[0] = unit_away(rng, &h[1..2], 0.3);
    h[4] = unit_away(rng, &h[1..2], 0.3);
    h[5] = unit_away(rng, &h[4..5], 0.3);
    p[0] = random_point(rng, 0.3);
    p[1] = random_point(rng, 0.3);
    p[2] = p[1] + unit_away(rng, &h[1..2], 0.3) * rng.random_range(0.2..0.6);
    p[3] = p[2] + unit_away(rng, &h[1..2], 0.3) * rng.random_range(0.2..0.6);
    let x = p[3] + random_point(rng, 0.3);
    p[4] = x + h[4] * rng.random_range(-0.2..0.2);
    p[5] = x + h[5] * rng.random_range(-0.2..0.2);
    if skew56 {
        p[5] += h[4].cross(&h[5]).normalize() * rng.random_range(0.05..0.2);
    }
    robot_from_axes("random-three-parallel", &h, &p, rng)
}

/// A random revolute chain mixing standard DH, modified DH and general
/// joints (any signs, offsets), with a random base and tool.
fn random_chain(rng: &mut ChaCha8Rng) -> Robot {
    let n = rng.random_range(1..=8);
    let joints: Vec<Joint> = (0..n)
        .map(|i| {
            let geometry = match rng.random_range(0..3) {
                0 | 1 => LinkGeometry::Dh {
                    convention: if rng.random_bool(0.5) { DhConvention::Standard } else { DhConvention::Modified },
                    d: rng.random_range(-0.5..0.5),
                    a: rng.random_range(-0.5..0.5),
                    alpha: rng.random_range(-PI..PI),
                    theta: 0.0,
                },
                _ => LinkGeometry::General { origin: random_pose(rng), axis: random_unit(rng) },
            };
            Joint {
                name: format!("j{}", i + 1),
                kind: JointType::Revolute,
                geometry,
                offset: rng.random_range(-1.0..1.0),
                limits: Limits::position(-PI, PI),
            }
        })
        .collect();
    // A table mixing conventions is a `general` robot; the joints say which convention each row follows.
    Model::builder("random", GeometryKind::General)
        .joints(joints)
        .base(random_pose(rng))
        .tool(random_pose(rng))
        .pose("home", vec![0.0; n])
        .build()
        .map(Robot::new)
        .unwrap()
}

fn assert_poe_matches_fk(robot: &Robot, rng: &mut ChaCha8Rng, n: usize) {
    let kin = Kinematics::new(robot).unwrap_or_else(|e| panic!("{}: {e}", robot.name()));
    for _ in 0..n {
        let q: Vec<f64> = (0..robot.dof()).map(|_| rng.random_range(-2.0 * PI..2.0 * PI)).collect();
        let (a, b) = (kin.fk(&q), robot.fk(&q).unwrap().world_from_tool);
        let err = (a.pos - b.pos).norm().max((a.rot - b.rot).norm());
        assert!(err < 1e-12, "{}: q = {q:?}: {err:.3e}", robot.name());
    }
}

#[test]
fn product_of_exponentials_equals_fk_on_every_description() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x9e0);
    let mut n = 0;
    for name in kinema::builtin_names() {
        let robot = Robot::builtin(name).unwrap();
        if robot.joint_types().contains('P') {
            let e = Kinematics::new(&robot).unwrap_err().to_string();
            assert!(e.contains("prismatic"), "{name}: {e}");
            continue;
        }
        assert_poe_matches_fk(&robot, &mut rng, 1000);
        n += 1;
    }
    assert!(n >= 4);
    for file in ["iiwa14.urdf", "ur5-general.toml", "iiwa-modified.toml", "puma560.urdf", "ur5.urdf"] {
        assert_poe_matches_fk(&data(file), &mut rng, 1000);
    }
    for _ in 0..500 {
        let robot = random_chain(&mut rng);
        assert_poe_matches_fk(&robot, &mut rng, 10);
    }
}

/// What a round trip over many configurations found.
#[derive(Debug, Default)]
struct Tally {
    cases: usize,
    /// Cases whose configuration was not among the solutions.
    missed: usize,
    /// Cases with fewer than 8 solutions.
    fewer: usize,
    worst_pos: f64,
    worst_rot: f64,
}

fn check_solutions(robot: &Robot, sols: &[Solution], what: &str) {
    // Up to 8 for the closed forms; a general 6R arm (the searches) has up to 16.
    assert!(!sols.is_empty() && sols.len() <= 16, "{what}: {} solutions", sols.len());
    for s in sols {
        assert!(s.q.iter().all(|v| v.is_finite()), "{what}: {s:?}");
        assert!(s.position_error < TOL && s.orientation_error < TOL, "{what}: {} {s:?}", robot.name());
        assert_eq!(s.out_of_limits, robot.limit_flags(&s.q), "{what}");
        for (v, j) in s.q.iter().zip(robot.joints()) {
            // Wrapped to (−π, π] unless a turn brought it within the limits.
            assert!((*v > -PI && *v <= PI) || j.limits.contains(*v), "{what}: {v}");
        }
    }
}

/// No two solutions of a search are the same configuration (one zero found twice).
fn assert_distinct(sols: &[Solution], what: &str) {
    for (i, a) in sols.iter().enumerate() {
        for b in &sols[i + 1..] {
            assert!(!same_angles(&a.q, &b.q, 1e-7), "{what}: {} and {} coincide: {:?}", a.branch, b.branch, a.q);
        }
    }
}

fn round_trips(robot: &Robot, ik: &dyn IkSolver, n: usize, seed: u64) -> Tally {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut t = Tally::default();
    for _ in 0..n {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let what = format!("{} q = {q:?}", robot.name());
        let sols = ik.solve(&target).unwrap_or_else(|e| panic!("{what}: {e}"));
        check_solutions(robot, &sols, &what);
        if ik.name().ends_with("-search") {
            assert_distinct(&sols, &what);
        }
        t.cases += 1;
        if !sols.iter().any(|s| same_angles(&s.q, &q, 1e-9)) {
            t.missed += 1;
        }
        if sols.len() < 8 {
            t.fewer += 1;
        }
        for s in &sols {
            t.worst_pos = t.worst_pos.max(s.position_error);
            t.worst_rot = t.worst_rot.max(s.orientation_error);
        }
    }
    t
}

/// Round trips; `always_eight`: every generic target has 8 solutions (the
/// PUMA), else fewer are allowed (the UR5's other wrist branch often puts its
/// planar arm out of reach; `complete_against_numeric` checks those).
fn assert_round_trips(robot: &Robot, expect_name: &str, n: usize, seed: u64, always_eight: bool) {
    let ik = GeoIk::new(robot).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(ik.name(), expect_name, "{}", robot.name());
    let t = round_trips(robot, &ik, n, seed);
    eprintln!("{}: {t:?}", robot.name());
    // Random configurations are singular with probability zero; allow a rare near-singular one.
    assert!(t.missed * 500 <= n, "{}: {t:?}", robot.name());
    if always_eight {
        assert!(t.fewer * 500 <= n, "{}: {t:?}", robot.name());
    }
}

/// For seeded targets, the numeric solver started from many random
/// configurations finds nothing the geometric solver missed: every converged
/// answer is one of its solutions (modulo 2π). Returns how many targets had
/// fewer than 8 solutions.
fn complete_against_numeric(robot: &Robot, targets: usize, starts: usize) -> usize {
    let ik = GeoIk::new(robot).unwrap();
    let opts = NumericOptions { max_restarts: 0, enforce_limits: false, ..Default::default() };
    let numeric = NumericIk::with_options(robot, opts).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0xc0);
    let mut fewer = 0;
    for _ in 0..targets {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let sols = ik.solve(&target).unwrap();
        if sols.len() < 8 {
            fewer += 1;
        }
        for _ in 0..starts {
            let q0 = robot.random_q(&mut rng);
            let Ok(s) = numeric.solve_from(&target, &q0) else { continue };
            if s.position_error > 1e-10 || s.orientation_error > 1e-10 {
                continue;
            }
            assert!(
                sols.iter().any(|g| same_angles(&g.q, &s.q, 1e-5)),
                "{}: q = {q:?}: the numeric solution {:?} is not among the {} geometric ones",
                robot.name(),
                s.q,
                sols.len()
            );
        }
    }
    fewer
}

#[test]
fn geometric_solutions_are_complete_against_numeric() {
    let fewer = complete_against_numeric(&Robot::builtin("ur5").unwrap(), 40, 150);
    eprintln!("ur5: {fewer} of 40 targets have fewer than 8 solutions");
    assert!(fewer > 0, "the sample should include targets with fewer than 8 solutions");
    assert_eq!(complete_against_numeric(&Robot::builtin("puma560").unwrap(), 10, 100), 0);
    complete_against_numeric(&data("ur5.urdf"), 10, 100);
}

#[test]
fn ur5_round_trips_on_three_descriptions() {
    assert_round_trips(&Robot::builtin("ur5").unwrap(), "geo-three-parallel", 3000, 5, false);
    assert_round_trips(&data("ur5.urdf"), "geo-three-parallel", 3000, 6, false);
    assert_round_trips(&data("ur5-general.toml"), "geo-three-parallel", 2000, 7, false);
}

#[test]
fn puma560_round_trips_on_two_descriptions() {
    let puma = Robot::builtin("puma560").unwrap();
    assert_round_trips(&puma, "geo-spherical-wrist", 3000, 560, true);
    assert_round_trips(&data("puma560.urdf"), "geo-spherical-wrist", 3000, 561, true);
    let ik = SphericalWristIk::new(&puma).unwrap();
    assert_eq!(ik.shoulder_kind(), ShoulderKind::Parallel23);
}

#[test]
fn random_arms_of_each_family_round_trip() {
    let mut rng = ChaCha8Rng::seed_from_u64(0xa5);
    for k in 0..60 {
        let (robot, name) = match k % 3 {
            0 => (random_spherical(&mut rng, true), "geo-spherical-wrist"),
            1 => (random_spherical(&mut rng, false), "geo-spherical-wrist"),
            _ => (random_three_parallel(&mut rng), "geo-three-parallel"),
        };
        let ik = GeoIk::new(&robot).unwrap_or_else(|e| panic!("arm {k}: {e}"));
        assert_eq!(ik.name(), name, "arm {k}");
        if let GeoIk::SphericalWrist(s) = &ik {
            assert_eq!(matches!(s.shoulder_kind(), ShoulderKind::Parallel23), k % 3 == 0, "arm {k}");
        }
        let t = round_trips(&robot, &ik, 100, k);
        // Random arms have fewer than 8 real solutions for some targets; the
        // configuration itself must still be found.
        assert!(t.missed <= 1, "arm {k}: {t:?}");
    }
}

#[test]
fn puma560_agrees_with_pieper() {
    let robot = Robot::builtin("puma560").unwrap();
    let (geo, pieper) = (GeoIk::new(&robot).unwrap(), PieperIk::new(&robot).unwrap());
    let mut rng = ChaCha8Rng::seed_from_u64(0x9199);
    for _ in 0..2000 {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let (a, b) = (geo.solve(&target).unwrap(), pieper.solve(&target).unwrap());
        assert_eq!(a.len(), b.len(), "q = {q:?}");
        for s in &a {
            let twin = b.iter().find(|t| same_angles(&t.q, &s.q, 1e-8));
            let twin = twin.unwrap_or_else(|| panic!("q = {q:?}: {} {:?} not found by pieper", s.branch, s.q));
            // The same value, not only the same angle: both move by ±2π into the limits the same way.
            assert!(s.q.iter().zip(&twin.q).all(|(x, y)| (x - y).abs() < 1e-8), "{s:?} {twin:?}");
            assert_eq!(s.out_of_limits, twin.out_of_limits);
        }
    }
}

#[test]
fn analytic_solver_keeps_existing_solvers_and_adds_geo() {
    let pick = |r: &Robot| analytic_solver(r).map(|s| s.name());
    assert_eq!(pick(&Robot::builtin("puma560").unwrap()), Some("pieper"));
    assert_eq!(pick(&Robot::builtin("lbr-iiwa-14-r820").unwrap()), Some("iiwa"));
    assert_eq!(pick(&Robot::builtin("ur5").unwrap()), Some("geo-three-parallel"));
    assert_eq!(pick(&data("ur5.urdf")), Some("geo-three-parallel"));
    assert_eq!(pick(&data("ur5-general.toml")), Some("geo-three-parallel"));
    assert_eq!(pick(&data("puma560.urdf")), Some("geo-spherical-wrist"));
    assert!(GeoIk::new(&Robot::builtin("panda").unwrap()).is_err());
    assert!(GeoIk::new(&data("iiwa14.urdf")).is_err());
}

#[test]
fn unreachable_and_malformed_targets() {
    for robot in [Robot::builtin("ur5").unwrap(), Robot::builtin("puma560").unwrap(), data("puma560.urdf")] {
        let ik = GeoIk::new(&robot).unwrap();
        for far in [3.0, 10.0, 1e6, 1e200] {
            let t = Pose::translation(far, 0.2, 0.1);
            match ik.solve(&t) {
                Err(Error::Unreachable { solver, reason, .. }) => {
                    assert_eq!(solver, ik.name());
                    assert!(!reason.to_string().is_empty());
                }
                other => panic!("{}: {far}: {other:?}", robot.name()),
            }
        }
        let mut nan = Pose::translation(0.3, 0.2, 0.1);
        nan.pos.x = f64::NAN;
        assert!(matches!(ik.solve(&nan), Err(Error::Input(InputError::NotFinite { .. }))));
        let mut skew = Pose::translation(0.3, 0.2, 0.1);
        skew.rot[(0, 1)] = 0.5;
        assert!(matches!(ik.solve(&skew), Err(Error::Input(InputError::OutOfRange { .. }))));
        common::random_poses_never_panic_or_return_nan(&ik);
    }
}

#[test]
fn singular_configurations_give_finite_solutions() {
    // Wrist singularities (q5 = 0) and stretched or folded arms (q3 = 0, π),
    // plus the UR5's shoulder singularity candidates: every returned solution
    // reaches the target, with no NaN.
    for robot in [Robot::builtin("ur5").unwrap(), Robot::builtin("puma560").unwrap(), data("ur5.urdf")] {
        let ik = GeoIk::new(&robot).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(77);
        for k in 0..300 {
            let mut q = robot.random_q(&mut rng);
            match k % 3 {
                0 => q[4] = 0.0,
                1 => q[2] = 0.0,
                _ => q[4] = PI,
            }
            let target = robot.fk(&q).unwrap().world_from_tool;
            let what = format!("{} q = {q:?}", robot.name());
            match ik.solve(&target) {
                Ok(sols) => {
                    for s in &sols {
                        assert!(s.q.iter().all(|v| v.is_finite()), "{what}: {s:?}");
                        assert!(s.position_error < 1e-8 && s.orientation_error < 1e-8, "{what}: {s:?}");
                    }
                }
                Err(e) => panic!("{what}: {e}"),
            }
        }
        // All zeros: the PUMA's and the UR5's wrists are singular there.
        let q0 = [0.0; 6];
        let sols = ik.solve(&robot.fk(&q0).unwrap().world_from_tool).unwrap();
        assert!(sols.iter().all(|s| s.position_error < 1e-8 && s.orientation_error < 1e-8), "{sols:?}");
    }
}

#[test]
fn families_refuse_other_structures() {
    let ur5 = Robot::builtin("ur5").unwrap();
    let e = SphericalWristIk::new(&ur5).unwrap_err().to_string();
    assert!(e.contains("spherical wrist"), "{e}");
    let puma = Robot::builtin("puma560").unwrap();
    let e = ThreeParallelIk::new(&puma).unwrap_err().to_string();
    assert!(e.contains("not parallel"), "{e}");
    let e = GeoIk::new(&Robot::builtin("panda").unwrap()).unwrap_err().to_string();
    assert!(e.contains("6 revolute joints"), "{e}");
}

/// A 6R standard-DH robot from rows (d \[m\], a \[m\], α \[deg\], offset \[deg\]).
fn dh_robot(name: &str, rows: &[(f64, f64, f64, f64); 6], tool: Pose) -> Robot {
    let joints: Vec<Joint> = rows
        .iter()
        .enumerate()
        .map(|(i, &(d, a, alpha, offset))| Joint {
            name: format!("a{}", i + 1),
            kind: JointType::Revolute,
            geometry: LinkGeometry::Dh {
                convention: DhConvention::Standard,
                d,
                a,
                alpha: alpha.to_radians(),
                theta: 0.0,
            },
            offset: offset.to_radians(),
            limits: Limits::position(-PI, PI),
        })
        .collect();
    Model::builder(name, GeometryKind::Standard)
        .joints(joints)
        .tool(tool)
        .pose("home", vec![0.0; 6])
        .build()
        .map(Robot::new)
        .unwrap()
}

#[test]
fn industrial_spherical_wrist_arms_round_trip_and_match_pieper() {
    // ABB IRB 140 (ABB product specification dimensions, standard DH) and KUKA KR 210
    // (the DH table of Udacity's KR210 pick-and-place project): shoulder offsets a1,
    // an elbow offset a3 and offsets on q2.
    let irb140 = dh_robot(
        "irb140",
        &[
            (0.352, 0.070, -90.0, 0.0),
            (0.0, 0.360, 0.0, -90.0),
            (0.0, 0.0, 90.0, 0.0),
            (0.380, 0.0, -90.0, 0.0),
            (0.0, 0.0, 90.0, 0.0),
            (0.065, 0.0, 0.0, 0.0),
        ],
        Pose::IDENTITY,
    );
    let kr210 = dh_robot(
        "kr210",
        &[
            (0.75, 0.35, -90.0, 0.0),
            (0.0, 1.25, 0.0, -90.0),
            (0.0, -0.054, -90.0, 0.0),
            (1.50, 0.0, 90.0, 0.0),
            (0.0, 0.0, -90.0, 0.0),
            (0.303, 0.0, 0.0, 0.0),
        ],
        Pose::translation(0.0, 0.0, 0.11),
    );
    for (k, robot) in [irb140, kr210].into_iter().enumerate() {
        // With a shoulder offset a1 the backward shoulder branch is often out of reach: the
        // count is checked against pieper below instead.
        assert_round_trips(&robot, "geo-spherical-wrist", 2000, 140 + k as u64, false);
        let (geo, pieper) = (GeoIk::new(&robot).unwrap(), PieperIk::new(&robot).unwrap());
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        for _ in 0..500 {
            let target = robot.fk(&robot.random_q(&mut rng)).unwrap().world_from_tool;
            let (a, b) = (geo.solve(&target).unwrap(), pieper.solve(&target).unwrap());
            assert_eq!(a.len(), b.len());
            assert!(a.iter().all(|s| b.iter().any(|t| same_angles(&s.q, &t.q, 1e-8))), "{}", robot.name());
        }
    }
}

#[test]
fn candidates_into_equals_solve() {
    use kinema::ik::CandidateSet;
    let mut set = CandidateSet::new();
    for robot in [Robot::builtin("ur5").unwrap(), data("puma560.urdf")] {
        let ik = GeoIk::new(&robot).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(31);
        for _ in 0..200 {
            let target = robot.fk(&robot.random_q(&mut rng)).unwrap().world_from_tool;
            let sols = ik.solve(&target).unwrap();
            ik.candidates_into(&target, &mut set).unwrap();
            assert_eq!(set.len(), sols.len());
            for (i, s) in sols.iter().enumerate() {
                assert_eq!(set.q(i), &s.q[..]);
                assert_eq!(set.branch(i), s.branch);
            }
        }
        // Every branch label appears at most once.
        let target = robot.fk(&robot.random_q(&mut rng)).unwrap().world_from_tool;
        let mut labels: Vec<String> = ik.solve(&target).unwrap().iter().map(|s| s.branch.to_string()).collect();
        let n = labels.len();
        labels.sort();
        labels.dedup();
        assert_eq!(labels.len(), n);
    }
}

#[test]
fn joint_values_move_into_the_limits_by_a_turn() {
    // The UR5's limits are ±2π: a solution is the wrapped angle, so within (−π, π].
    // With limits [0, 2π) on every joint, the same solutions come back shifted by 2π.
    let ur5 = Robot::builtin("ur5").unwrap();
    let mut joints = ur5.joints().to_vec();
    for j in &mut joints {
        j.limits = Limits::position(0.0, 2.0 * PI - 1e-9);
    }
    let shifted = Model::builder("ur5-shifted", GeometryKind::Standard)
        .joints(joints)
        .base(*ur5.base())
        .tool(*ur5.tool())
        .pose("home", vec![1.0; 6])
        .build()
        .map(Robot::new)
        .unwrap();
    let (a, b) = (GeoIk::new(&ur5).unwrap(), GeoIk::new(&shifted).unwrap());
    let target = ur5.fk(&[0.3, -1.1, 1.4, -0.6, 0.9, 2.0]).unwrap().world_from_tool;
    let (sa, sb) = (a.solve(&target).unwrap(), b.solve(&target).unwrap());
    assert_eq!(sa.len(), sb.len());
    for (x, y) in sa.iter().zip(&sb) {
        assert!(x.within_limits() && y.within_limits(), "{y:?}");
        assert!(y.q.iter().all(|v| (0.0..2.0 * PI).contains(v)));
        assert!(same_angles(&x.q, &y.q, 1e-12));
    }
}

#[test]
fn search_solves_three_parallel_arms_with_an_offset_wrist() {
    // The UR5 with a 2 cm offset a5 between axes 5 and 6: not the closed form's family.
    let ur5 = Robot::builtin("ur5").unwrap();
    let mut joints = ur5.joints().to_vec();
    if let LinkGeometry::Dh { a, .. } = &mut joints[4].geometry {
        *a = 0.02;
    }
    let offset = Model::builder("ur5-offset-wrist", GeometryKind::Standard)
        .joints(joints)
        .base(*ur5.base())
        .tool(*ur5.tool())
        .poses(ur5.poses().to_vec())
        .build()
        .map(Robot::new)
        .unwrap();
    assert!(ThreeParallelIk::new(&offset).is_err());
    assert!(ThreeParallelSearchIk::new(&ur5).is_err());
    assert_eq!(analytic_solver(&offset).map(|s| s.name()), Some("geo-three-parallel-search"));
    let ik = GeoIk::new(&offset).unwrap();
    let t = round_trips(&offset, &ik, 2000, 12);
    eprintln!("{}: {t:?}", offset.name());
    assert!(t.missed * 200 <= t.cases, "{t:?}");
    complete_against_numeric(&offset, 10, 60);

    let mut rng = ChaCha8Rng::seed_from_u64(0x5ea);
    for k in 0..20 {
        let robot = random_three_parallel_with(&mut rng, true);
        let ik = GeoIk::new(&robot).unwrap_or_else(|e| panic!("arm {k}: {e}"));
        assert_eq!(ik.name(), "geo-three-parallel-search");
        let t = round_trips(&robot, &ik, 300, k);
        assert!(t.missed <= 1, "arm {k}: {t:?}");
    }
    let e = ik.solve(&Pose::translation(10.0, 0.0, 0.0)).unwrap_err();
    assert!(matches!(e, Error::Unreachable { .. }), "{e}");
    common::random_poses_never_panic_or_return_nan(&ik);
}

#[test]
fn search_solves_offset_wrists_whose_last_two_axes_meet() {
    // The PUMA 560 with its wrist's axis 4 moved 3 cm off the wrist centre (a4 = 0.03).
    let puma = Robot::builtin("puma560").unwrap();
    let mut joints = puma.joints().to_vec();
    if let LinkGeometry::Dh { a, .. } = &mut joints[3].geometry {
        *a = 0.03;
    }
    let offset = Model::builder("puma560-offset-wrist", GeometryKind::Standard)
        .joints(joints)
        .base(*puma.base())
        .tool(*puma.tool())
        .poses(puma.poses().to_vec())
        .build()
        .map(Robot::new)
        .unwrap();
    assert!(SphericalWristIk::new(&offset).is_err() && TwoIntersectingSearchIk::new(&puma).is_err());
    assert_eq!(analytic_solver(&offset).map(|s| s.name()), Some("geo-two-intersecting-search"));
    let ik = GeoIk::new(&offset).unwrap();
    let t = round_trips(&offset, &ik, 2000, 13);
    eprintln!("{}: {t:?}", offset.name());
    assert!(t.missed * 200 <= t.cases, "{t:?}");
    complete_against_numeric(&offset, 10, 60);

    let mut rng = ChaCha8Rng::seed_from_u64(0x21);
    for k in 0..20 {
        let robot = random_spherical_with(&mut rng, k % 2 == 0, true);
        let ik = GeoIk::new(&robot).unwrap_or_else(|e| panic!("arm {k}: {e}"));
        assert_eq!(ik.name(), "geo-two-intersecting-search");
        let t = round_trips(&robot, &ik, 200, k);
        assert!(t.missed <= 1, "arm {k}: {t:?}");
    }
    let e = ik.solve(&Pose::translation(10.0, 0.0, 0.0)).unwrap_err();
    assert!(matches!(e, Error::Unreachable { .. }), "{e}");
    common::random_poses_never_panic_or_return_nan(&ik);
}

/// The geometric families are entries of the one registry: on seeded random
/// arms of each structure `registry::fit` picks the family `GeoIk::new`
/// picks, and the two give the same solutions, branch for branch.
#[test]
fn the_registry_fits_random_arms_as_geo_ik_does() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x4e6);
    for k in 0..24 {
        let (robot, name) = match k % 4 {
            0 => (random_spherical(&mut rng, k % 8 == 0), "geo-spherical-wrist"),
            1 => (random_three_parallel(&mut rng), "geo-three-parallel"),
            2 => (random_three_parallel_with(&mut rng, true), "geo-three-parallel-search"),
            _ => (random_spherical_with(&mut rng, k % 8 == 3, true), "geo-two-intersecting-search"),
        };
        let geo = GeoIk::new(&robot).unwrap_or_else(|e| panic!("arm {k}: {e}"));
        let fitted = kinema::ik::registry::fit(&robot).unwrap_or_else(|| panic!("arm {k}: no family fits"));
        assert_eq!((geo.name(), fitted.name()), (name, name), "arm {k}");
        for _ in 0..10 {
            let target = robot.fk(&robot.random_q(&mut rng)).unwrap().world_from_tool;
            match (geo.solve(&target), fitted.solve(&target)) {
                (Ok(a), Ok(b)) => {
                    assert_eq!(a.len(), b.len(), "arm {k}");
                    for (s, t) in a.iter().zip(&b) {
                        assert_eq!((&s.branch, &s.q), (&t.branch, &t.q), "arm {k}");
                    }
                }
                (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "arm {k}"),
                (a, b) => panic!("arm {k}: {a:?} against {b:?}"),
            }
        }
    }
}
