//! The geometric solver for SRS arms (`ik::geo::SrsIk`, the iiwa's
//! structure read from the axes): seeded FK → IK round trips at the
//! configuration's own q3 on the URDF iiwa, the built-in DH iiwa and the
//! modified-DH one, agreement with the DH-only `IiwaIk`, random SRS arms,
//! the within-limits search over q3, singular and unreachable targets.

use std::f64::consts::PI;

use kinema::ik::geo::SrsIk;
use kinema::ik::iiwa::IiwaIk;
use kinema::ik::{analytic_solver, solve_request, IkRequest, IkSolver, Solution, Unreachable};
use kinema::nalgebra::{Rotation3, Unit, Vector3};
use kinema::{Error, Pose, Robot};
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

fn dh_iiwa() -> Robot {
    Robot::builtin("lbr-iiwa-14-r820").unwrap()
}

fn random_unit(rng: &mut ChaCha8Rng) -> V3 {
    loop {
        let v = V3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
        if v.norm() > 0.2 && v.norm() < 1.0 {
            return v.normalize();
        }
    }
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

fn random_pose(rng: &mut ChaCha8Rng) -> Pose {
    let axis = Unit::new_normalize(random_unit(rng));
    let p = random_unit(rng) * rng.random_range(0.0..0.5);
    Pose::new(*Rotation3::from_axis_angle(&axis, rng.random_range(-PI..PI)).matrix(), p)
}

/// A random 7R SRS arm of `general` joints: axes 1–3 through a shoulder
/// point, axes 5–7 through a wrist centre, an elbow axis passing both at
/// random link lengths, a random mounting (base) and tool.
fn random_srs(rng: &mut ChaCha8Rng) -> Robot {
    let mut h = [V3::zeros(); 7];
    let mut p = [V3::zeros(); 7];
    let s = random_unit(rng) * rng.random_range(0.0..0.3);
    h[0] = random_unit(rng);
    h[1] = unit_away(rng, &h[..1], 0.3);
    h[2] = unit_away(rng, &h[1..2], 0.3);
    let elbow = s + random_unit(rng) * rng.random_range(0.2..0.6);
    h[3] = unit_away(rng, &[(elbow - s).normalize()], 0.3);
    let w = elbow + unit_away(rng, &h[3..4], 0.3) * rng.random_range(0.2..0.6);
    h[4] = random_unit(rng);
    h[5] = unit_away(rng, &h[4..5], 0.3);
    h[6] = unit_away(rng, &h[5..6], 0.3);
    for i in 0..7 {
        let centre = match i {
            0..=2 => s,
            3 => elbow,
            _ => w,
        };
        p[i] = centre + h[i] * rng.random_range(-0.2..0.2);
    }
    robot_from_axes(&h, &p, rng)
}

/// A 7R robot of `general` joints with axes (h, p) at q = 0 and a random base and tool.
fn robot_from_axes(h: &[V3; 7], p: &[V3; 7], rng: &mut ChaCha8Rng) -> Robot {
    let (base, tool) = (random_pose(rng), random_pose(rng));
    common::robot_from_axes("random-srs", h, p, base, tool)
}

fn reaches(s: &Solution) -> bool {
    s.position_error < TOL && s.orientation_error < TOL && s.q.iter().all(|v| v.is_finite())
}

/// `cases` round trips at the configuration's own q3: every solution reaches
/// the target, and the configuration is among them except near a
/// singularity (|sin q2|, |sin q4| or |sin q6| below 1e-4), which is counted.
/// Returns (cases, singular misses).
fn round_trips(robot: &Robot, cases: usize, seed: u64) -> (usize, usize) {
    let ik = SrsIk::new(robot).unwrap_or_else(|e| panic!("{e}"));
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut singular_misses = 0;
    for _ in 0..cases {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let sols = ik.solve_q3(&target, q[2]).unwrap_or_else(|e| panic!("{} {q:?}: {e}", robot.name()));
        assert!(!sols.is_empty() && sols.len() <= 8);
        assert!(sols.iter().all(reaches), "{} {q:?}: {sols:?}", robot.name());
        if !sols.iter().any(|s| same_angles(&s.q, &q, 1e-7)) {
            let near = [1, 3, 5].iter().any(|&i| q[i].sin().abs() < 1e-4);
            assert!(near, "{} {q:?} not recovered: {sols:?}", robot.name());
            singular_misses += 1;
        }
    }
    (cases, singular_misses)
}

#[test]
fn the_structure_is_read_from_the_axes_of_any_description() {
    for robot in [data("iiwa14.urdf"), dh_iiwa(), data("iiwa-modified.toml")] {
        let ik = SrsIk::new(&robot).unwrap_or_else(|e| panic!("{}: {e}", robot.name()));
        let (s, w) = ik.centres();
        // Stretched at q = 0: shoulder–elbow 0.42 m plus elbow–wrist 0.4 m.
        assert!(((w - s).norm() - 0.82).abs() < 1e-9, "{}: {s} {w}", robot.name());
    }
    let pick = |r: &Robot| analytic_solver(r).map(|s| s.name());
    assert_eq!(pick(&dh_iiwa()), Some("iiwa"));
    assert_eq!(pick(&data("iiwa14.urdf")), Some("geo-srs"));
    assert_eq!(pick(&data("iiwa-modified.toml")), Some("geo-srs"));
    for name in ["panda", "ur5", "puma560"] {
        let e = SrsIk::new(&Robot::builtin(name).unwrap()).unwrap_err().to_string();
        assert!(e.contains("7 revolute joints") || e.contains("no spherical"), "{name}: {e}");
    }
    let e = SrsIk::new(&Robot::builtin("panda").unwrap()).unwrap_err().to_string();
    assert!(e.contains("no spherical"), "{e}");
}

#[test]
fn urdf_iiwa_round_trips_at_its_q3() {
    let (cases, singular) = round_trips(&data("iiwa14.urdf"), 2500, 0x5125);
    eprintln!("iiwa14.urdf: {cases} round trips, {singular} near-singular not recovered");
    assert!(singular <= 5, "{singular}");
}

#[test]
fn dh_iiwas_round_trip_through_the_geometric_solver() {
    for (robot, seed) in [(dh_iiwa(), 0x5126), (data("iiwa-modified.toml"), 0x5127)] {
        let (cases, singular) = round_trips(&robot, 2000, seed);
        eprintln!("{}: {cases} round trips, {singular} near-singular not recovered", robot.name());
        assert!(singular <= 5, "{singular}");
    }
}

/// On the DH iiwa the geometric solver and `IiwaIk` give one solution set
/// (modulo 2π, to 1e-8) at every q3; `IiwaIk` keeps coinciding solutions
/// once, so only the distinct ones are compared.
#[test]
fn same_solution_set_as_the_dh_iiwa_solver() {
    let robot = dh_iiwa();
    let (geo, dh) = (SrsIk::new(&robot).unwrap(), IiwaIk::new(&robot).unwrap());
    let mut rng = ChaCha8Rng::seed_from_u64(0x5128);
    let mut differ = 0;
    for _ in 0..2000 {
        let q = robot.random_q(&mut rng);
        let q3 = if rng.random_bool(0.5) { q[2] } else { rng.random_range(-2.9..2.9) };
        let target = robot.fk(&q).unwrap().world_from_tool;
        match (geo.solve_q3(&target, q3), dh.solve_q3(&target, q3)) {
            (Ok(a), Ok(b)) => {
                let covered =
                    |x: &[Solution], y: &[Solution]| x.iter().all(|s| y.iter().any(|t| same_angles(&s.q, &t.q, 1e-8)));
                if !(covered(&a, &b) && covered(&b, &a)) {
                    differ += 1;
                    assert!([1, 3, 5].iter().any(|&i| q[i].sin().abs() < 1e-4), "{q:?} at {q3}: {a:?} vs {b:?}");
                }
            }
            (Err(Error::Unreachable { .. }), Err(Error::Unreachable { .. })) => {}
            (a, b) => panic!("{q:?} at {q3}: {a:?} vs {b:?}"),
        }
    }
    assert!(differ <= 5, "{differ}");
}

#[test]
fn random_srs_arms_round_trip() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5129);
    let mut singular = 0;
    for k in 0..20 {
        let robot = random_srs(&mut rng);
        assert_eq!(analytic_solver(&robot).map(|s| s.name()), Some("geo-srs"), "arm {k}");
        singular += round_trips(&robot, 150, 0x5200 + k).1;
    }
    assert!(singular <= 5, "{singular}");
}

#[test]
fn kernel_matches_solve() {
    let robot = data("iiwa14.urdf");
    let ik = SrsIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0x512a);
    for _ in 0..200 {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let c = ik.solve_q3_candidates(&target, q[2]).unwrap();
        let sols = ik.solve_q3(&target, q[2]).unwrap();
        common::kernel_matches_solve(&robot, &c, &sols, target.pos.into());
        assert_eq!(ik.solve(&target).ok(), ik.solve_q3(&target, 0.0).ok());
    }
}

/// FK of a within-limit configuration is never refused by the search, and
/// every solution it returns is within limits and reaches the target.
#[test]
fn searching_never_refuses_a_reachable_target() {
    for (robot, seed) in [(data("iiwa14.urdf"), 0x512b), (dh_iiwa(), 0x512c)] {
        let ik = SrsIk::new(&robot).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut searched = 0;
        for _ in 0..2000 {
            let q = robot.random_q(&mut rng);
            let target = robot.fk(&q).unwrap().world_from_tool;
            let sols = ik.solve_searching(&target, 0.0).unwrap_or_else(|e| panic!("{q:?} refused: {e}"));
            assert!(!sols.is_empty());
            assert!(sols.iter().all(|s| s.within_limits() && reaches(s)), "{q:?}: {sols:?}");
            searched += usize::from(sols.iter().any(|s| s.q[2] != 0.0));
        }
        eprintln!("{}: {searched} of 2000 targets needed the q3 search, none refused", robot.name());
        assert!(searched > 20, "{searched}");
    }
}

#[test]
fn singular_configurations_give_finite_solutions() {
    let robot = data("iiwa14.urdf");
    let ik = SrsIk::new(&robot).unwrap();
    let cases: [[f64; 7]; 6] = [
        [0.3, 0.5, -0.7, -1.2, 0.4, 0.0, 0.1], // wrist: axes 5 and 7 aligned
        [0.3, 0.5, -0.7, 0.0, 0.4, 0.8, 0.1],  // stretched elbow
        [0.3, 0.0, -0.7, 0.0, 0.4, 0.8, 0.1],  // wrist centre on axis 1
        [0.0; 7],                              // all of them
        [0.3, 0.5, 0.2, -1.2, 0.4, 1e-9, 0.1], // next to the wrist singularity
        [0.3, 1e-9, 0.2, 0.0, 0.4, 0.8, 0.1],  // next to the shoulder singularity
    ];
    for q in cases {
        let target = robot.fk(&q).unwrap().world_from_tool;
        let sols = ik.solve_q3(&target, q[2]).unwrap_or_else(|e| panic!("{q:?}: {e}"));
        assert_eq!(sols.len(), 8, "{q:?}");
        assert!(sols.iter().all(reaches), "{q:?}: {sols:?}");
        let sols = ik.solve_searching(&target, q[2]).unwrap();
        assert!(sols.iter().all(|s| s.within_limits() && reaches(s)), "{q:?}: {sols:?}");
        let psi = ik.psi_of(&q);
        assert!(psi.is_finite(), "{q:?}");
        for at in [psi, psi + 1.0, -2.5] {
            let sols = ik.solve_psi(&target, at).unwrap_or_else(|e| panic!("{q:?} at ψ {at}: {e}"));
            assert_eq!(sols.len(), 8, "{q:?}");
            assert!(sols.iter().all(reaches), "{q:?} at ψ {at}: {sols:?}");
            assert!(sols.iter().all(|s| ik.psi_of(&s.q).is_finite()), "{q:?} at ψ {at}: {sols:?}");
        }
        if q[1].sin().abs() > 1e-6 {
            // Off the shoulder singularity, ψ of every solution is the ψ asked for.
            let sols = ik.solve_psi(&target, psi + 1.0).unwrap();
            assert!(sols.iter().all(|s| angle_gap(ik.psi_of(&s.q), psi + 1.0) < TOL), "{q:?}: {sols:?}");
        }
    }
}

#[test]
fn unreachable_and_malformed_targets() {
    let robot = data("iiwa14.urdf");
    let ik = SrsIk::new(&robot).unwrap();
    let far = Pose::translation(2.0, 0.0, 0.36);
    for r in [ik.solve_q3(&far, 0.3), ik.solve_searching(&far, 0.0)] {
        assert!(matches!(r, Err(Error::Unreachable { reason: Unreachable::OutsideReach { .. }, .. })), "{r:?}");
    }
    assert!(matches!(
        ik.solve_q3(&robot.fk(&[0.0; 7]).unwrap().world_from_tool, f64::NAN),
        Err(Error::Input(InputError::NotFinite { .. }))
    ));
    assert!(matches!(ik.solve_searching(&far, f64::INFINITY), Err(Error::Input(InputError::NotFinite { .. }))));
    let mut bad = far;
    bad.pos.x = f64::NAN;
    assert!(matches!(ik.solve_q3(&bad, 0.0), Err(Error::Input(InputError::NotFinite { .. }))));
    let huge = Pose::translation(1e300, -1e300, 1e308);
    assert!(matches!(ik.solve_q3(&huge, 0.0), Err(Error::Unreachable { .. })));
    // The flange pointing into the base column: no q3 keeps q2 and q6 within limits.
    let straight = robot.fk(&[0.0; 7]).unwrap().world_from_tool;
    let down = Pose::new(Pose::rot_x(PI).rot, straight.pos - Vector3::new(0.0, 0.0, 0.6));
    match ik.solve_searching(&down, 0.0) {
        Err(Error::Unreachable { reason: Unreachable::JointLimits { rejected }, .. }) => assert!(!rejected.is_empty()),
        other => panic!("{other:?}"),
    }
    common::random_poses_never_panic_or_return_nan(&ik);
    assert!(matches!(
        ik.solve_psi(&far, 0.3),
        Err(Error::Unreachable { reason: Unreachable::OutsideReach { .. }, .. })
    ));
    assert!(matches!(ik.solve_psi(&straight, f64::NAN), Err(Error::Input(InputError::NotFinite { .. }))));
    assert!(matches!(ik.solve_psi(&bad, 0.0), Err(Error::Input(InputError::NotFinite { .. }))));
    assert!(matches!(ik.solve_psi(&huge, 0.0), Err(Error::Unreachable { .. })));
    assert!(ik.psi_of(&[0.1, f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0]).is_nan() && ik.psi_of(&[0.1; 6]).is_nan());
}

/// Random finite poses at random arm angles, on the URDF iiwa and on
/// random SRS arms: never a panic or a NaN; every solution reaches the
/// target; anything else is `Unreachable`.
#[test]
fn random_poses_at_random_arm_angles_never_panic_or_return_nan() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5133);
    let mut robots = vec![data("iiwa14.urdf")];
    robots.extend((0..5).map(|_| random_srs(&mut rng)));
    let mut solved = 0;
    for robot in &robots {
        let ik = SrsIk::new(robot).unwrap();
        for _ in 0..1000 {
            let target = random_pose(&mut rng);
            match ik.solve_psi(&target, rng.random_range(-4.0..4.0)) {
                Ok(sols) => {
                    solved += 1;
                    assert!(sols.iter().all(|s| s.q.iter().all(|v| v.is_finite()) && s.position_error < TOL));
                }
                Err(Error::Unreachable { .. }) => {}
                Err(e) => panic!("{e}"),
            }
        }
    }
    assert!(solved > 500, "{solved}");
}

/// The request layer: q3 or ψ on a URDF iiwa is this solver's closed form;
/// with q0, all solutions at q0's q3; one solution is searched within limits.
#[test]
fn requests_on_a_urdf_iiwa_use_the_geometric_closed_form() {
    let robot = data("iiwa14.urdf");
    let ik = SrsIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0x512d);
    for _ in 0..100 {
        let q = robot.random_q(&mut rng);
        let pose = robot.fk(&q).unwrap().world_from_tool;
        let (name, sols) = solve_request(&robot, &pose, &IkRequest { q3: Some(q[2]), ..Default::default() }).unwrap();
        assert_eq!((name, &sols), ("geo-srs", &ik.solve_q3(&pose, q[2]).unwrap()));
        let psi = ik.psi_of(&q);
        let (name, sols) = solve_request(&robot, &pose, &IkRequest { psi: Some(psi), ..Default::default() }).unwrap();
        assert_eq!((name, &sols), ("geo-srs", &ik.solve_psi(&pose, psi).unwrap()));
        assert!(sols.iter().any(|s| same_angles(&s.q, &q, 1e-7)));
        let all = IkRequest { q0: Some(&q), all: true, ..Default::default() };
        let (_, sols) = solve_request(&robot, &pose, &all).unwrap();
        assert!(sols.iter().any(|s| same_angles(&s.q, &q, 1e-7)));
        let one = IkRequest { q0: Some(&q), ..Default::default() };
        let (_, sols) = solve_request(&robot, &pose, &one).unwrap();
        let picked = kinema::ik::pick_one(&robot, name, sols, Some(&q)).unwrap();
        assert!(same_angles(&picked.q, &q, 1e-7), "{:?} vs {q:?}", picked.q);
        let (_, sols) = solve_request(&robot, &pose, &IkRequest::default()).unwrap();
        assert!(!sols.is_empty() && sols.iter().all(|s| s.within_limits() && reaches(s)));
    }
}

/// The largest |ψ₁ − ψ₂| modulo 2π.
fn angle_gap(a: f64, b: f64) -> f64 {
    kinema::ik::wrap_angle(a - b).abs()
}

/// The DH iiwa rewritten as `general` joints from its axes at q = 0: the
/// same motion, read without a DH table; the axes listed in `reversed`
/// point the other way (those joints turn with the opposite sign).
fn general_copy_of_dh_iiwa(reversed: &[usize]) -> Robot {
    let dh = dh_iiwa();
    let kin = kinema::ik::geo::Kinematics::new(&dh).unwrap();
    let (mut h, p): (Vec<V3>, Vec<V3>) = (kin.h.clone(), kin.p.clone());
    for &i in reversed {
        h[i] = -h[i];
    }
    let tool = Pose::translation(-p[6].x, -p[6].y, -p[6].z) * kin.tool;
    common::robot_from_axes("iiwa-general", &h, &p, Pose::default(), tool)
}

/// What the ψ round trips measured.
#[derive(Debug, Default)]
struct PsiStats {
    cases: usize,
    /// Random ψ the shoulder cannot take (none on the iiwa).
    refused: usize,
    /// Sources not among the solutions at their own ψ, next to a singularity.
    singular_misses: usize,
    max_psi_error: f64,
    max_recovery_error: f64,
}

/// `cases` configurations q of `robot`: at a random ψ every solution
/// reaches the target and has that ψ; at ψ(q), q is among the solutions
/// (except next to a singularity: |sin q2|, |sin q4| or |sin q6| below 1e-4,
/// counted).
fn psi_round_trips(robot: &Robot, cases: usize, seed: u64) -> PsiStats {
    let ik = SrsIk::new(robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut st = PsiStats { cases, ..Default::default() };
    for _ in 0..cases {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let psi = rng.random_range(-PI..PI);
        match ik.solve_psi(&target, psi) {
            Ok(sols) => {
                assert!(!sols.is_empty() && sols.len() <= 8);
                for s in &sols {
                    assert!(reaches(s), "{} {q:?} at ψ {psi}: {s:?}", robot.name());
                    st.max_psi_error = st.max_psi_error.max(angle_gap(ik.psi_of(&s.q), psi));
                }
            }
            Err(Error::Unreachable { reason: Unreachable::Orientation { .. }, .. }) => st.refused += 1,
            Err(e) => panic!("{} {q:?} at ψ {psi}: {e}", robot.name()),
        }
        let own = ik.psi_of(&q);
        let sols = ik.solve_psi(&target, own).unwrap_or_else(|e| panic!("{} {q:?} at its ψ {own}: {e}", robot.name()));
        assert!(sols.iter().all(reaches), "{} {q:?}: {sols:?}", robot.name());
        let nearest = sols
            .iter()
            .map(|s| s.q.iter().zip(&q).fold(0.0f64, |m, (a, b)| m.max(angle_gap(*a, *b))))
            .fold(f64::INFINITY, f64::min);
        if nearest < 1e-7 {
            st.max_recovery_error = st.max_recovery_error.max(nearest);
        } else {
            let near = [1, 3, 5].iter().any(|&i| q[i].sin().abs() < 1e-4);
            assert!(near, "{} {q:?} not recovered at its ψ {own}: {sols:?}", robot.name());
            st.singular_misses += 1;
        }
    }
    st
}

#[test]
fn urdf_iiwa_round_trips_through_the_arm_angle() {
    let st = psi_round_trips(&data("iiwa14.urdf"), 3000, 0x5130);
    eprintln!("iiwa14.urdf ψ round trips: {st:?}");
    assert_eq!(st.refused, 0, "every ψ is reachable on the iiwa");
    assert!(st.max_psi_error < TOL && st.max_recovery_error < 1e-8, "{st:?}");
    assert!(st.singular_misses <= 5, "{st:?}");
}

#[test]
fn random_srs_arms_round_trip_through_the_arm_angle() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5131);
    let mut total = PsiStats::default();
    for k in 0..20 {
        let robot = random_srs(&mut rng);
        let st = psi_round_trips(&robot, 200, 0x5300 + k);
        total.cases += st.cases;
        total.refused += st.refused;
        total.singular_misses += st.singular_misses;
        total.max_psi_error = total.max_psi_error.max(st.max_psi_error);
        total.max_recovery_error = total.max_recovery_error.max(st.max_recovery_error);
    }
    eprintln!("random SRS arms, ψ round trips: {total:?}");
    assert!(total.max_psi_error < TOL && total.max_recovery_error < 1e-8, "{total:?}");
    assert!(total.singular_misses <= 5, "{total:?}");
    // Most random ψ are reachable even with skewed shoulder axes.
    assert!(total.refused < total.cases / 2, "{total:?}");
}

/// On the DH iiwa, its `general` copy and the URDF (same axes, a base and a
/// tool), ψ read from the geometry is `IiwaIk`'s ψ, and at a given ψ the
/// solutions are `IiwaIk`'s eight configurations.
#[test]
fn the_arm_angle_is_the_dh_iiwa_solvers() {
    let standard = dh_iiwa();
    let base = Pose::new(Pose::rot_z(PI / 6.0).rot, Vector3::new(0.1, -0.2, 0.05));
    let mounted = standard.clone().with_base(base).unwrap().with_tool(Pose::translation(0.0, 0.0, 0.045)).unwrap();
    let pairs = [
        (standard.clone(), standard.clone()),
        (general_copy_of_dh_iiwa(&[]), standard),
        (data("iiwa14.urdf"), mounted),
    ];
    for (k, (robot, reference)) in pairs.into_iter().enumerate() {
        let (geo, dh) = (SrsIk::new(&robot).unwrap(), IiwaIk::new(&reference).unwrap());
        let mut rng = ChaCha8Rng::seed_from_u64(0x5132 + k as u64);
        let (mut max_psi, mut max_q, mut differ) = (0.0f64, 0.0f64, 0);
        for _ in 0..2000 {
            let q = robot.random_q(&mut rng);
            let target = robot.fk(&q).unwrap().world_from_tool;
            assert!(((target.pos - reference.fk(&q).unwrap().world_from_tool.pos).norm()) < 1e-12);
            max_psi = max_psi.max(angle_gap(geo.psi_of(&q), dh.psi_of(&q)));
            let psi = if rng.random_bool(0.5) { dh.psi_of(&q) } else { rng.random_range(-PI..PI) };
            let ours = geo.solve_psi(&target, psi).unwrap();
            let theirs: Vec<Solution> = (0u8..8).map(|c| dh.solve_psi(&target, psi, c).unwrap()).collect();
            let gap = |s: &Solution, set: &[Solution]| {
                set.iter()
                    .map(|t| s.q.iter().zip(&t.q).fold(0.0f64, |m, (a, b)| m.max(angle_gap(*a, *b))))
                    .fold(f64::INFINITY, f64::min)
            };
            let worst =
                ours.iter().map(|s| gap(s, &theirs)).chain(theirs.iter().map(|t| gap(t, &ours))).fold(0.0, f64::max);
            if worst < 1e-8 {
                max_q = max_q.max(worst);
            } else {
                differ += 1;
                assert!([1, 3, 5].iter().any(|&i| q[i].sin().abs() < 1e-4), "{q:?} at ψ {psi}: {ours:?} vs {theirs:?}");
            }
        }
        eprintln!(
            "{}: 2000 cases, max |Δψ| {max_psi:.2e}, max |Δq| {max_q:.2e}, {differ} near-singular differ",
            robot.name()
        );
        assert!(max_psi < TOL, "{}: {max_psi}", robot.name());
        assert!(differ <= 5, "{differ}");
    }
}

/// Describing axis 1 or axis 2 reversed moves ψ's zero by π; reversing both,
/// or any other axis, changes nothing.
#[test]
fn reversing_axis_1_or_2_moves_the_zero_of_the_arm_angle_by_pi() {
    let dh = IiwaIk::new(&dh_iiwa()).unwrap();
    let cases: [(&[usize], f64); 5] = [(&[0], PI), (&[1], PI), (&[0, 1], 0.0), (&[2, 3], 0.0), (&[1, 6], PI)];
    for (reversed, shift) in cases {
        let robot = general_copy_of_dh_iiwa(reversed);
        let geo = SrsIk::new(&robot).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(0x5134);
        let mut max_gap = 0.0f64;
        for _ in 0..1000 {
            let q = dh_iiwa().random_q(&mut rng);
            let mut flipped = q.clone();
            for &i in reversed {
                flipped[i] = -q[i];
            }
            let (a, b) = (robot.fk(&flipped).unwrap().world_from_tool, dh_iiwa().fk(&q).unwrap().world_from_tool);
            assert!((a.pos - b.pos).norm() < 1e-12 && (a.rot - b.rot).norm() < 1e-12);
            max_gap = max_gap.max(angle_gap(geo.psi_of(&flipped), dh.psi_of(&q) + shift));
        }
        assert!(max_gap < TOL, "{reversed:?}: {max_gap}");
    }
}

/// Sweeping ψ over a turn in small steps, each branch label follows one
/// continuous branch: its next solution is nearer its own previous one than
/// any other label's (joints move fast only next to a singularity, where
/// the largest step is measured).
#[test]
fn branch_labels_follow_their_branch_along_the_arm_angle() {
    let robot = data("iiwa14.urdf");
    let ik = SrsIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0x5139);
    let steps = 720;
    let gap = |a: &Solution, b: &Solution| a.q.iter().zip(&b.q).fold(0.0f64, |m, (x, y)| m.max(angle_gap(*x, *y)));
    let (mut swaps, mut largest) = (0, 0.0f64);
    for _ in 0..50 {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let at = |k: usize| ik.solve_psi(&target, -PI + 2.0 * PI * k as f64 / steps as f64).unwrap();
        let mut prev = at(0);
        for k in 1..=steps {
            let next = at(k);
            assert_eq!(prev.len(), next.len());
            for (i, b) in next.iter().enumerate() {
                assert_eq!(prev[i].branch, b.branch);
                let own = gap(&prev[i], b);
                largest = largest.max(own);
                let other = prev
                    .iter()
                    .enumerate()
                    .filter(|(j, _)| *j != i)
                    .map(|(_, a)| gap(a, b))
                    .fold(f64::INFINITY, f64::min);
                swaps += usize::from(other < own);
            }
            prev = next;
        }
    }
    eprintln!("{swaps} label swaps in 50 × {steps} ψ steps × 8 branches; largest step of one label {largest:.3} rad");
    assert_eq!(swaps, 0);
}

/// `family::self_motion` (any family with ψ) gives the DH iiwa's own
/// self-motion (`IiwaIk::self_motion`, seed 004 Fig. 7), and on the URDF
/// iiwa keeps the tool pose while the elbow turns about the shoulder–wrist line.
#[test]
fn the_generic_self_motion_is_the_iiwas_and_works_from_urdf() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5e1f);
    let dh = dh_iiwa();
    let iiwa = IiwaIk::new(&dh).unwrap();
    let dh_family = kinema::ik::registry::fit(&dh).unwrap();
    let urdf = data("iiwa14.urdf");
    let urdf_family = kinema::ik::registry::fit(&urdf).unwrap();
    let mut worst = (0.0f64, 0.0f64);
    for _ in 0..200 {
        let q = dh.random_q(&mut rng);
        let ours = kinema::ik::family::self_motion(&dh, dh_family.redundancy().unwrap(), &q, 24).unwrap();
        let theirs = iiwa.self_motion(&q, 24).unwrap();
        for (a, b) in ours.iter().zip(&theirs) {
            worst.0 = worst.0.max((a.psi - b.psi).abs()).max((a.elbow - b.elbow).norm());
            worst.1 = worst.1.max(a.q.iter().zip(&b.q).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max));
            assert_eq!(a.within_limits, b.within_limits);
        }
        let q = urdf.random_q(&mut rng);
        let pose = urdf.fk(&q).unwrap().world_from_tool;
        let samples = kinema::ik::family::self_motion(&urdf, urdf_family.redundancy().unwrap(), &q, 24).unwrap();
        assert!(samples[0].q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-8));
        // Equal steps of ψ put the elbows equally spaced on one circle: its
        // centre is their centroid.
        let centre = samples.iter().map(|m| m.elbow).sum::<Vector3<f64>>() / samples.len() as f64;
        let radius = (samples[0].elbow - centre).norm();
        for m in &samples {
            let reached = urdf.fk(&m.q).unwrap().world_from_tool;
            assert!((reached.pos - pose.pos).norm() < 1e-9 && (reached.rot - pose.rot).norm() < 1e-9);
            assert!(((m.elbow - centre).norm() - radius).abs() < 1e-9);
        }
    }
    assert!(worst.0 < 1e-9 && worst.1 < 1e-8, "generic vs IiwaIk self-motion: {worst:?}");
    let family = urdf_family.redundancy().unwrap();
    assert!(kinema::ik::family::self_motion(&urdf, family, urdf.home(), 0).is_err());
}

/// The one SRS kernel behind `geo-srs` and `iiwa`, on thousands of random
/// SRS arms (axes at random angles, so mostly not perpendicular) at random
/// q: every candidate reaches the target to 1e-9 and q is among them
/// (away from singular q). On the DH iiwa, generic q give 8 distinct
/// candidates that all reach the target: at most 8 solutions exist for a
/// fixed q3, so that is the complete set the former iiwa kernel returned,
/// and its labels keep seed 004's meaning (the bits of each solution, a
/// distinct `/front` or `/back` per shoulder).
#[test]
fn one_kernel_round_trips_random_srs_arms_and_keeps_the_iiwa_set() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5a11);
    let (mut cases, mut missed) = (0, 0);
    for _ in 0..2000 {
        let robot = random_srs(&mut rng);
        let ik = SrsIk::new(&robot).unwrap();
        for _ in 0..2 {
            let q = robot.random_q(&mut rng);
            let target = robot.fk(&q).unwrap().world_from_tool;
            let c = ik.solve_q3_candidates(&target, q[2]).unwrap_or_else(|e| panic!("{q:?}: {e}"));
            for (s, _) in c.iter() {
                let fk = robot.fk(s).unwrap().world_from_tool;
                let (dp, dr) = ((fk.pos - target.pos).norm(), (fk.rot - target.rot).norm());
                assert!(dp < TOL && dr < TOL, "{q:?} -> {s:?}: {dp:e} m, {dr:e}");
            }
            cases += 1;
            if !c.qs().iter().any(|s| same_angles(s, &q, 1e-7)) {
                assert!([1, 3, 5].iter().any(|&i| q[i].sin().abs() < 1e-3), "{q:?} not recovered");
                missed += 1;
            }
        }
    }
    assert!(missed * 100 <= cases, "{missed} of {cases} singular misses");
    let robot = dh_iiwa();
    let ik = IiwaIk::new(&robot).unwrap();
    for _ in 0..3000 {
        let q = robot.random_q(&mut rng);
        if [1, 3, 5].iter().any(|&i| q[i].sin().abs() < 1e-3) {
            continue;
        }
        let target = robot.fk(&q).unwrap().world_from_tool;
        let c = ik.solve_q3_candidates(&target, q[2]).unwrap();
        assert_eq!(c.len(), 8, "{q:?}");
        let mut labels: Vec<&str> = c.iter().map(|(_, b)| b).collect();
        labels.sort_unstable();
        labels.dedup();
        assert_eq!(labels.len(), 8, "{labels:?}");
        for (i, (s, branch)) in c.iter().enumerate() {
            let fk = robot.fk(s).unwrap().world_from_tool;
            assert!((fk.pos - target.pos).norm() < TOL && (fk.rot - target.rot).norm() < TOL, "{q:?} -> {s:?}");
            assert!(branch.starts_with(kinema::ik::iiwa::config_label(ik.config_of(s))), "{branch} for {s:?}");
            assert!(c.qs()[..i].iter().all(|o| !same_angles(o, s, 1e-6)), "{q:?}: repeated {s:?}");
        }
        assert!(c.qs().iter().any(|s| same_angles(s, &q, 1e-9)), "{q:?}");
    }
}
