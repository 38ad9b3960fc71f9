//! The analytic spherical-wrist solver (`ik::pieper`): seeded FK → IK round
//! trips on the PUMA 560 and on synthetic arms of the other supported
//! arrangements, detection of unsupported robots, singular and unreachable
//! targets.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use kinema::ik::pieper::{ArmKind, PieperIk};
use kinema::ik::{IkSolver, NumericIk, NumericOptions, Solution, Unreachable};
use kinema::math::RpyConvention;
use kinema::InputError;
use kinema::{Error, Pose, Robot};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const TOL_POS: f64 = 1e-10;
const TOL_ROT: f64 = 1e-10;

fn puma() -> Robot {
    Robot::builtin("puma560").unwrap()
}

/// Angle difference wrapped to (−π, π].
fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(TAU);
    if d > PI {
        d - TAU
    } else {
        d
    }
}

fn same_config(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| angle_diff(*x, *y).abs() < tol)
}

fn assert_accurate(sols: &[Solution], what: &str) {
    for s in sols {
        assert!(s.q.iter().all(|v| v.is_finite()), "{what}: non-finite q in {s:?}");
        assert!(
            s.position_error < TOL_POS && s.orientation_error < TOL_ROT,
            "{what}: branch {} residual {:.3e} m, {:.3e} rad (q = {:?})",
            s.branch,
            s.position_error,
            s.orientation_error,
            s.q
        );
    }
}

/// FK → solve → every solution reproduces the target, `q` is among them and
/// the solutions are pairwise distinct; their number is checked against
/// `expect` when given. Returns the solutions.
fn round_trip(ik: &PieperIk, robot: &Robot, q: &[f64], expect: Option<usize>) -> Vec<Solution> {
    let target = robot.fk(q).unwrap().world_from_tool;
    let sols = ik.solve(&target).unwrap_or_else(|e| panic!("{}: q = {q:?}: {e}", robot.name()));
    assert_accurate(&sols, &format!("{} q = {q:?}", robot.name()));
    assert!(
        sols.iter().any(|s| same_config(&s.q, q, 1e-9)),
        "{}: q = {q:?} not among the solutions {:#?}",
        robot.name(),
        sols.iter().map(|s| (&s.branch, &s.q)).collect::<Vec<_>>()
    );
    if let Some(n) = expect {
        assert_eq!(sols.len(), n, "{}: q = {q:?}", robot.name());
    }
    assert!(sols.len() % 2 == 0 && sols.len() <= 8, "{}: {} solutions", robot.name(), sols.len());
    for (i, a) in sols.iter().enumerate() {
        for b in &sols[i + 1..] {
            assert!(
                !same_config(&a.q, &b.q, 1e-6),
                "{}: q = {q:?}: {} and {} coincide",
                robot.name(),
                a.branch,
                b.branch
            );
        }
    }
    sols
}

#[test]
fn puma560_round_trips() {
    let robot = puma();
    let ik = PieperIk::new(&robot).unwrap();
    assert_eq!(ik.arm_kind(), ArmKind::ShoulderPlane);
    assert_eq!(ik.name(), "pieper");
    let mut rng = ChaCha8Rng::seed_from_u64(560);
    let mut worst = (0.0f64, 0.0f64);
    for _ in 0..5000 {
        let q = robot.random_q(&mut rng);
        let sols = round_trip(&ik, &robot, &q, Some(8));
        for s in &sols {
            worst = (worst.0.max(s.position_error), worst.1.max(s.orientation_error));
        }
        // Every branch label appears exactly once.
        let mut labels: Vec<&str> = sols.iter().map(|s| s.branch.as_ref()).collect();
        labels.sort();
        labels.dedup();
        assert_eq!(labels.len(), 8);
    }
    assert!(worst.0 < TOL_POS && worst.1 < TOL_ROT, "worst residual {worst:?}");
}

#[test]
fn puma560_complete_against_numeric() {
    complete_against_numeric(&puma());
}

#[test]
fn puma560_branch_labels() {
    let robot = puma();
    let ik = PieperIk::new(&robot).unwrap();
    // `qn` is Corke's nominal right-arm, elbow-up configuration with q5 > 0,
    // which his `ikine_a` names `ruf` (the wrist flipped).
    let qn = robot.pose("qn").unwrap().to_vec();
    let sols = ik.solve(&robot.fk(&qn).unwrap().world_from_tool).unwrap();
    let own = sols.iter().find(|s| same_config(&s.q, &qn, 1e-9)).unwrap();
    assert_eq!(own.branch, "shoulder-right/elbow-up/wrist-flip");
    let labels: Vec<&str> = sols.iter().map(|s| s.branch.as_ref()).collect();
    for sh in ["right", "left"] {
        for el in ["up", "down"] {
            for wr in ["noflip", "flip"] {
                let l = format!("shoulder-{sh}/elbow-{el}/wrist-{wr}");
                assert!(labels.contains(&l.as_str()), "{l} missing from {labels:?}");
            }
        }
    }
    // Flip branches: q4 shifted by π, q5 negated, q6 shifted by π.
    for s in sols.iter().filter(|s| s.branch.ends_with("noflip")) {
        let arm = s.branch.trim_end_matches("/wrist-noflip");
        let f = sols.iter().find(|t| t.branch == format!("{arm}/wrist-flip")).unwrap();
        assert!(same_config(&s.q[..3], &f.q[..3], 1e-12));
        assert!(angle_diff(f.q[3], s.q[3] + PI).abs() < 1e-9);
        assert!((f.q[4] + s.q[4]).abs() < 1e-9);
        assert!(angle_diff(f.q[5], s.q[5] + PI).abs() < 1e-9);
    }
}

#[test]
fn puma560_with_base_and_tool() {
    let base = Pose::from_xyz_rpy([0.3, -0.2, 0.5], [0.1, -0.3, 1.2], RpyConvention::Zyx);
    let tool = Pose::from_xyz_rpy([0.02, 0.01, 0.15], [0.4, 0.2, -0.7], RpyConvention::Zyx);
    let robot = puma().with_base(base).unwrap().with_tool(tool).unwrap();
    let ik = PieperIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for _ in 0..500 {
        let q = robot.random_q(&mut rng);
        round_trip(&ik, &robot, &q, Some(8));
    }
}

#[test]
fn solutions_respect_limits_and_flags() {
    let robot = puma();
    let ik = PieperIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for _ in 0..200 {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let sols = ik.solve(&target).unwrap();
        for s in &sols {
            assert_eq!(s.within_limits(), robot.fk(&s.q).unwrap().within_limits());
        }
        let within = ik.solve_within_limits(&target).unwrap();
        assert!(within.iter().any(|s| same_config(&s.q, &q, 1e-9)));
    }
}

#[test]
fn detection_accepts_and_rejects() {
    assert!(PieperIk::new(&puma()).is_ok());
    let msg = |name: &str| match PieperIk::new(&Robot::builtin(name).unwrap()) {
        Err(Error::UnsupportedStructure { reason, .. }) => reason,
        other => panic!("{name}: expected UnsupportedStructure, got {other:?}"),
    };
    let ur5 = msg("ur5");
    assert!(ur5.contains("ur5") && ur5.contains("axes 4, 5, 6 do not intersect") && ur5.contains("0.0946"), "{ur5}");
    let iiwa = msg("lbr-iiwa-14-r820");
    assert!(iiwa.contains("exactly 6 revolute joints") && iiwa.contains("7"), "{iiwa}");
    let scorbot = msg("scorbot-er-v-plus");
    assert!(scorbot.contains("exactly 6 revolute joints") && scorbot.contains("5"), "{scorbot}");
    // A general (URDF-like) description is rejected: the solver reads the DH table.
    let general = Robot::from_file(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/ur5-general.toml"), None).unwrap();
    let m = match PieperIk::new(&general) {
        Err(Error::UnsupportedStructure { reason, .. }) => reason,
        other => panic!("expected UnsupportedStructure, got {other:?}"),
    };
    assert!(m.contains("general transform") && m.contains("DH table"), "{m}");
    // Every built-in robot is either accepted or rejected with a message, never a panic.
    for name in kinema::builtin_names() {
        let robot = Robot::builtin(name).unwrap();
        match PieperIk::new(&robot) {
            Ok(_) => {}
            Err(Error::UnsupportedStructure { robot: r, .. }) => assert_eq!(r, robot.name()),
            Err(e) => panic!("{name}: {e}"),
        }
    }
}

/// A standard-DH robot description with the given rows (d, a, alpha, offset
/// in m and degrees) and limits of ±170° (joint 3: ±160°).
fn synthetic(name: &str, convention: &str, rows: [(f64, f64, f64, f64); 6], extra: &str) -> Robot {
    let mut t = format!(
        "name = \"{name}\"\nsource = \"synthetic, tests/ik_pieper.rs\"\nconvention = \"{convention}\"\n{extra}\n[units]\nlength = \"m\"\nangle = \"deg\"\n"
    );
    for (i, (d, a, alpha, offset)) in rows.iter().enumerate() {
        let lim = if i == 2 { 160 } else { 170 };
        t += &format!(
            "[[joint]]\nname = \"j{}\"\nd = {d}\na = {a}\nalpha = {alpha}\noffset = {offset}\nmin = -{lim}\nmax = {lim}\n",
            i + 1
        );
    }
    t += "[poses]\nhome = [0, 0, 0, 0, 0, 0]\n";
    Robot::from_toml_str(&t, &format!("{name}.toml")).unwrap()
}

const BASE_TOOL: &str =
    "[base]\nxyz = [0.1, -0.2, 0.05]\nrpy = [0, 0, 30]\n[tool]\nxyz = [0.01, 0.02, 0.1]\nrpy = [10, -20, 5]\n";

/// Round trips on a synthetic arm; for arms with a1 ≠ 0 or a skewed shoulder
/// not every pose has all 8 solutions, but at least `min_eight` of `n` must.
fn synthetic_round_trips(robot: &Robot, kind: ArmKind, n: usize, min_eight: usize) {
    let ik = PieperIk::new(robot).unwrap_or_else(|e| panic!("{}: {e}", robot.name()));
    assert_eq!(ik.arm_kind(), kind, "{}", robot.name());
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    let mut eight = 0;
    for _ in 0..n {
        let q = robot.random_q(&mut rng);
        eight += usize::from(round_trip(&ik, robot, &q, None).len() == 8);
    }
    assert!(eight >= min_eight, "{}: only {eight} of {n} poses have 8 solutions", robot.name());
}

/// The numeric solver without restarts or limits, converging to 1e-12.
fn exact_numeric(robot: &Robot) -> NumericIk {
    let opts = NumericOptions {
        max_restarts: 0,
        enforce_limits: false,
        tol_position: 1e-12,
        tol_orientation: 1e-12,
        ..Default::default()
    };
    NumericIk::with_options(robot, opts).unwrap()
}

/// Runs `numeric` from `starts` random configurations and asserts that
/// every solution it converges to is among `sols`; returns how many it found.
fn numeric_solutions_are_listed(
    numeric: &NumericIk,
    target: &Pose,
    sols: &[Solution],
    starts: usize,
    rng: &mut ChaCha8Rng,
    what: &str,
) -> usize {
    let mut found = 0;
    for _ in 0..starts {
        let q0: Vec<f64> = (0..6).map(|_| rng.random_range(-PI..PI)).collect();
        let Ok(s) = numeric.solve_from(target, &q0) else { continue };
        if s.position_error < 1e-10 && s.orientation_error < 1e-10 {
            found += 1;
            assert!(
                sols.iter().any(|a| same_config(&a.q, &s.q, 1e-6)),
                "{what}: numeric solution {:?} missing from {:?}",
                s.q,
                sols.iter().map(|s| &s.q).collect::<Vec<_>>()
            );
        }
    }
    found
}

/// Completeness: every solution the numeric solver finds from random starts
/// (limits not enforced) is one of the analytic ones.
fn complete_against_numeric(robot: &Robot) {
    let ik = PieperIk::new(robot).unwrap();
    let numeric = exact_numeric(robot);
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut found = 0;
    for _ in 0..8 {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let sols = ik.solve(&target).unwrap();
        found += numeric_solutions_are_listed(&numeric, &target, &sols, 15, &mut rng, robot.name());
    }
    assert!(found > 20, "{}: only {found} numeric solutions", robot.name());
}

/// KUKA-KR-like: a1 ≠ 0, α1 = −90°, α2 = 0, no lateral offset, offsets on q2, q3 and q6, base and tool.
fn kr_like() -> Robot {
    synthetic(
        "kr-like",
        "standard",
        [
            (0.4, 0.025, -90.0, 0.0),
            (0.0, 0.455, 0.0, -90.0),
            (0.0, 0.035, 90.0, 180.0),
            (0.42, 0.0, -90.0, 0.0),
            (0.0, 0.0, 90.0, 0.0),
            (0.08, 0.0, 0.0, 15.0),
        ],
        BASE_TOOL,
    )
}

/// a1 = 0, α1 = 90°, α2 = 90°: axes 1 and 2 intersect, axes 2 and 3 perpendicular.
fn intersecting() -> Robot {
    synthetic(
        "intersecting",
        "standard",
        [
            (0.35, 0.0, 90.0, 0.0),
            (0.1, 0.3, 90.0, 20.0),
            (0.05, 0.02, -90.0, 0.0),
            (0.3, 0.0, 90.0, 0.0),
            (0.0, 0.0, -90.0, -30.0),
            (0.07, 0.0, 0.0, 0.0),
        ],
        BASE_TOOL,
    )
}

/// α1 = 0, a1 ≠ 0: axes 1 and 2 parallel; α2 = 90°.
fn parallel() -> Robot {
    synthetic(
        "parallel",
        "standard",
        [
            (0.3, 0.3, 0.0, 0.0),
            (0.05, 0.1, 90.0, 0.0),
            (0.02, 0.05, 90.0, 0.0),
            (0.25, 0.0, -90.0, 0.0),
            (0.0, 0.0, 90.0, 0.0),
            (0.06, 0.0, 0.0, 0.0),
        ],
        BASE_TOOL,
    )
}

#[test]
fn industrial_arm_with_shoulder_offset() {
    let robot = kr_like();
    synthetic_round_trips(&robot, ArmKind::ShoulderPlane, 1000, 850);
    complete_against_numeric(&robot);
}

#[test]
fn alpha2_of_180_and_negative_twists() {
    let robot = synthetic(
        "flipped",
        "standard",
        [
            (0.3, 0.05, 90.0, 10.0),
            (0.07, 0.35, 180.0, 0.0),
            (-0.04, 0.03, 90.0, 0.0),
            (0.3, 0.0, 90.0, -20.0),
            (0.0, 0.0, 90.0, 0.0),
            (0.1, 0.01, 30.0, 0.0),
        ],
        BASE_TOOL,
    );
    synthetic_round_trips(&robot, ArmKind::ShoulderPlane, 1000, 750);
}

#[test]
fn intersecting_shoulder_arm() {
    let robot = intersecting();
    synthetic_round_trips(&robot, ArmKind::IntersectingShoulder, 1000, 700);
    complete_against_numeric(&robot);
}

#[test]
fn parallel_shoulder_arm() {
    let robot = parallel();
    synthetic_round_trips(&robot, ArmKind::ParallelShoulder, 1000, 500);
    complete_against_numeric(&robot);
}

/// a1 ≠ 0 with α1 = α2 = 90°: the quartic case.
fn general_90_90() -> Robot {
    synthetic(
        "general-90-90",
        "standard",
        [
            (0.35, 0.1, 90.0, 0.0),
            (0.1, 0.3, 90.0, 20.0),
            (0.05, 0.02, -90.0, 0.0),
            (0.3, 0.0, 90.0, 0.0),
            (0.0, 0.0, -90.0, 0.0),
            (0.07, 0.0, 0.0, 0.0),
        ],
        BASE_TOOL,
    )
}

#[test]
fn general_pieper_arms() {
    let robot = general_90_90();
    synthetic_round_trips(&robot, ArmKind::General, 300, 100);
    complete_against_numeric(&robot);
    // Skewed twists: α1 = 60°, α2 = −45°.
    let robot = synthetic(
        "general-skewed",
        "standard",
        [
            (0.3, 0.15, 60.0, 0.0),
            (0.05, 0.35, -45.0, 0.0),
            (0.02, 0.05, 90.0, 0.0),
            (0.3, 0.0, -90.0, 0.0),
            (0.0, 0.0, 90.0, 0.0),
            (0.08, 0.0, 0.0, 0.0),
        ],
        "",
    );
    synthetic_round_trips(&robot, ArmKind::General, 300, 80);
    complete_against_numeric(&robot);
}

/// A seeded general spherical-wrist arm (a1 ≠ 0, skewed α1 and α2): the
/// random shoulder of [`ArmKind::General`], an orthogonal wrist. Returns it
/// with its d6.
fn random_general_arm(rng: &mut ChaCha8Rng, k: usize) -> (Robot, f64) {
    let mut skew = || {
        let a: f64 = rng.random_range(20.0..70.0);
        let a = if rng.random_bool(0.5) { 180.0 - a } else { a };
        if rng.random_bool(0.5) {
            -a
        } else {
            a
        }
    };
    let (alpha1, alpha2, alpha3) = (skew(), skew(), skew());
    let wrist = if rng.random_bool(0.5) { 90.0 } else { -90.0 };
    let mut len = |lo: f64, hi: f64| rng.random_range(lo..hi);
    let rows = [
        (len(0.1, 0.4), len(0.05, 0.3), alpha1, 0.0),
        (len(-0.1, 0.1), len(0.2, 0.5), alpha2, 0.0),
        (len(-0.1, 0.1), len(0.0, 0.1), alpha3, 0.0),
        (len(0.2, 0.5), 0.0, wrist, 0.0),
        (0.0, 0.0, -wrist, 0.0),
        (len(0.05, 0.15), 0.0, 0.0, 0.0),
    ];
    (synthetic(&format!("general-random-{k}"), "standard", rows, ""), rows[5].0)
}

/// The wrist centre (flange origin d6 back along its z axis; no tool).
fn wrist_centre(robot: &Robot, q: &[f64], d6: f64) -> kinema::nalgebra::Vector3<f64> {
    let t = robot.fk(q).unwrap().world_from_tool;
    let m = t.to_rows();
    kinema::nalgebra::Vector3::new(m[0][3] - d6 * m[0][2], m[1][3] - d6 * m[1][2], m[2][3] - d6 * m[2][2])
}

/// det ∂(wrist centre)/∂(q1, q2, q3) by central differences.
fn arm_jacobian_det(robot: &Robot, q: &[f64], d6: f64) -> f64 {
    let h = 1e-6;
    let cols: Vec<_> = (0..3)
        .map(|i| {
            let (mut a, mut b) = (q.to_vec(), q.to_vec());
            a[i] += h;
            b[i] -= h;
            (wrist_centre(robot, &a, d6) - wrist_centre(robot, &b, d6)) / (2.0 * h)
        })
        .collect();
    kinema::nalgebra::Matrix3::from_columns(&cols).determinant()
}

/// Issue 34 item 7: on seeded random general spherical-wrist arms every
/// solution a numeric multi-start finds (40 random starts, limits not
/// enforced) is among pieper's, and pieper lists 4 or 8 — at random targets
/// and at targets 1 mrad in θ3 from the fold of the arm's workspace, where
/// two roots of the θ3 quartic nearly meet (the case that lost two roots).
#[test]
fn general_arms_list_every_solution_a_multi_start_finds() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x347);
    let (mut targets, mut near_fold, mut numeric_found) = (0, 0, 0);
    for k in 0..8 {
        let (robot, d6) = random_general_arm(&mut rng, k);
        let ik = PieperIk::new(&robot).unwrap();
        assert_eq!(ik.arm_kind(), ArmKind::General, "{}", robot.name());
        let numeric = exact_numeric(&robot);
        let mut qs: Vec<(Vec<f64>, bool)> = (0..20).map(|_| (robot.random_q(&mut rng), false)).collect();
        // θ3 on the fold (det of the arm's Jacobian changes sign), then 1 mrad off it.
        for _ in 0..40 {
            let mut q = robot.random_q(&mut rng);
            let det_at = |q: &mut Vec<f64>, t3: f64| {
                q[2] = t3;
                arm_jacobian_det(&robot, q, d6)
            };
            let (mut lo, mut hi) = (-PI, -PI + 0.05);
            let mut flo = det_at(&mut q, lo);
            while hi <= PI && (flo > 0.0) == (det_at(&mut q, hi) > 0.0) {
                (lo, flo, hi) = (hi, det_at(&mut q, hi), hi + 0.05);
            }
            if hi > PI {
                continue;
            }
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if (det_at(&mut q, mid) > 0.0) == (flo > 0.0) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            q[2] = lo + if rng.random_bool(0.5) { 1e-3 } else { -1e-3 };
            qs.push((q, true));
            if qs.iter().filter(|(_, f)| *f).count() == 8 {
                break;
            }
        }
        for (q, fold) in qs {
            let target = robot.fk(&q).unwrap().world_from_tool;
            let sols = ik.solve(&target).unwrap_or_else(|e| panic!("{}: q = {q:?}: {e}", robot.name()));
            assert_accurate(&sols, &format!("{} q = {q:?}", robot.name()));
            assert!(sols.iter().any(|s| same_config(&s.q, &q, 1e-8)), "{}: q = {q:?} not found", robot.name());
            assert!(sols.len() == 4 || sols.len() == 8, "{}: q = {q:?}: {} solutions", robot.name(), sols.len());
            let what = format!("{}: q = {q:?} (near the fold: {fold})", robot.name());
            numeric_found += numeric_solutions_are_listed(&numeric, &target, &sols, 40, &mut rng, &what);
            targets += 1;
            near_fold += usize::from(fold);
        }
    }
    eprintln!("{targets} targets ({near_fold} near the fold), {numeric_found} numeric solutions, all listed");
    assert!(targets >= 200 && near_fold >= 40 && numeric_found > 2000, "{targets} {near_fold} {numeric_found}");
}

#[test]
fn modified_dh_puma() {
    // The PUMA 560 as a modified (Craig) table: row i holds αi−1, ai−1, di.
    let robot = synthetic(
        "puma-modified",
        "modified",
        [
            (0.0, 0.1, 30.0, 0.0),
            (0.0, 0.0, -90.0, 0.0),
            (0.15, 0.4318, 0.0, 0.0),
            (0.4318, 0.0203, -90.0, 0.0),
            (0.0, 0.0, 90.0, 0.0),
            (0.0, 0.0, -90.0, 0.0),
        ],
        BASE_TOOL,
    );
    synthetic_round_trips(&robot, ArmKind::ShoulderPlane, 1000, 1000);
}

#[test]
fn unsupported_arrangements_are_rejected() {
    let rows_ok = [
        (0.35, 0.0, 90.0, 0.0),
        (0.0, 0.4, 0.0, 0.0),
        (0.1, 0.02, -90.0, 0.0),
        (0.4, 0.0, 90.0, 0.0),
        (0.0, 0.0, -90.0, 0.0),
        (0.0, 0.0, 0.0, 0.0),
    ];
    let err = |rows| match PieperIk::new(&synthetic("x", "standard", rows, "")) {
        Err(Error::UnsupportedStructure { reason, .. }) => reason,
        other => panic!("expected UnsupportedStructure, got {other:?}"),
    };
    // Axes 1 and 2 coincide (α1 = 0, a1 = 0).
    let mut rows = rows_ok;
    rows[0].2 = 0.0;
    let m = err(rows);
    assert!(m.contains("degenerate shoulder"), "{m}");
    // Axes 1, 2, 3 parallel.
    let mut rows = rows_ok;
    rows[0].1 = 0.2;
    rows[0].2 = 0.0;
    let m = err(rows);
    assert!(m.contains("degenerate shoulder"), "{m}");
    // Non-orthogonal wrist.
    let mut rows = rows_ok;
    rows[3].2 = 60.0;
    let m = err(rows);
    assert!(m.contains("not orthogonal"), "{m}");
    // Parallel wrist axes.
    let mut rows = rows_ok;
    rows[4].2 = 0.0;
    let m = err(rows);
    assert!(m.contains("parallel"), "{m}");
    // a5 ≠ 0: the wrist axes do not meet.
    let mut rows = rows_ok;
    rows[4].1 = 0.05;
    let m = err(rows);
    assert!(m.contains("do not intersect") && m.contains("0.0500"), "{m}");
}

#[test]
fn wrist_singularity_gives_finite_answers() {
    let robot = puma();
    let ik = PieperIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for _ in 0..200 {
        let mut q = robot.random_q(&mut rng);
        q[4] = 0.0;
        let target = robot.fk(&q).unwrap().world_from_tool;
        let sols = ik.solve(&target).unwrap();
        assert_eq!(sols.len(), 8);
        assert_accurate(&sols, "q5 = 0");
        // Convention: q4 = 0 on the singular noflip branches, q6 takes the rest.
        for s in sols.iter().filter(|s| s.branch.ends_with("noflip") && s.q[4].sin().abs() < 1e-9) {
            assert!(s.q[3] == 0.0, "{s:?}");
        }
        // The original configuration is reproduced up to the q4/q6 trade-off.
        let own = sols.iter().find(|s| same_config(&s.q[..3], &q[..3], 1e-9) && s.branch.ends_with("noflip")).unwrap();
        assert!(angle_diff(own.q[3] + own.q[5], q[3] + q[5]).abs() < 1e-9);
    }
}

#[test]
fn shoulder_singularity() {
    // PUMA: the wrist centre cannot come closer than d3 = 0.15005 m to axis 1.
    let robot = puma();
    let ik = PieperIk::new(&robot).unwrap();
    let target = Pose::translation(0.0, 0.0, 1.2);
    match ik.solve(&target) {
        Err(e @ Error::Unreachable { reason: Unreachable::InsideExcluded { .. }, .. }) => {
            let Error::Unreachable { solver, reason: Unreachable::InsideExcluded { by, region }, .. } = &e else {
                unreachable!()
            };
            assert_eq!(solver, "pieper");
            assert!((by - 0.15005).abs() < 1e-12 && region.contains("cylinder of radius 0.150"), "{by} {region}");
            assert!(e.to_string().contains("m inside the cylinder"), "{e}");
        }
        other => panic!("expected InsideExcluded, got {other:?}"),
    }
    // PUMA: wrist centre exactly on that cylinder (both shoulder branches merge): finite, accurate.
    let q = [0.3, 0.2, -1.0, 0.4, 0.5, 0.6];
    let fk = robot.fk(&q).unwrap().world_from_tool;
    let ik_frames = robot.link_frames(&q).unwrap();
    let wc = ik_frames[4].pos;
    let rho = wc.x.hypot(wc.y);
    let scale = 0.15005 / rho;
    let target =
        Pose::new(fk.rot, fk.pos + kinema::nalgebra::Vector3::new(wc.x * (scale - 1.0), wc.y * (scale - 1.0), 0.0));
    let sols = ik.solve(&target).unwrap();
    assert_eq!(sols.len(), 8);
    assert!(sols.iter().all(|s| s.position_error < 1e-9 && s.orientation_error < 1e-10), "{sols:#?}");
    // A PUMA without the lateral offset (d3 = 0): wrist centre on axis 1, q1 is free (q1 = 0 by convention).
    let robot = synthetic(
        "puma-no-offset",
        "standard",
        [
            (0.6718, 0.0, 90.0, 0.0),
            (0.0, 0.4318, 0.0, 0.0),
            (0.0, 0.0203, -90.0, 0.0),
            (0.4318, 0.0, 90.0, 0.0),
            (0.0, 0.0, -90.0, 0.0),
            (0.0, 0.0, 0.0, 0.0),
        ],
        "",
    );
    let ik = PieperIk::new(&robot).unwrap();
    let q = [0.2, FRAC_PI_2, (-0.4318f64).atan2(0.0203) + PI, 0.3, 0.5, 0.1];
    let target = robot.fk(&q).unwrap().world_from_tool;
    let wc = robot.link_frames(&q).unwrap()[4].pos;
    assert!(wc.x.hypot(wc.y) < 1e-12, "{wc:?}");
    let sols = ik.solve(&target).unwrap();
    assert_accurate(&sols, "wrist centre on axis 1");
    assert!(sols.iter().any(|s| s.q[0] == 0.0));
}

#[test]
fn stretched_elbow() {
    let robot = puma();
    let ik = PieperIk::new(&robot).unwrap();
    // θ3 = atan2(−d4, a3): upper arm and forearm in line (qr-like), at the outer reach.
    let q = [0.3, 0.4, (-0.4318f64).atan2(0.0203), 0.5, 0.6, 0.7];
    let sols = ik.solve(&robot.fk(&q).unwrap().world_from_tool).unwrap();
    assert_eq!(sols.len(), 8);
    assert!(sols.iter().all(|s| s.position_error < 1e-9 && s.orientation_error < 1e-9), "{sols:#?}");
    assert!(sols.iter().any(|s| same_config(&s.q, &q, 1e-6)));
    // Slightly beyond: unreachable by the excess.
    let fk = robot.fk(&q).unwrap().world_from_tool;
    let shoulder = robot.link_frames(&q).unwrap()[1].pos;
    let dir = (fk.pos - shoulder).normalize();
    let target = Pose::new(fk.rot, fk.pos + dir * 1e-3);
    match ik.solve(&target) {
        Err(Error::Unreachable { reason: Unreachable::OutsideReach { by, boundary }, .. }) => {
            assert!(by > 0.0 && by < 2e-3 && boundary.contains("outer reach"), "{by} {boundary}")
        }
        other => panic!("expected OutsideReach, got {other:?}"),
    }
}

#[test]
fn unreachable_and_invalid_targets() {
    let robot = puma();
    let ik = PieperIk::new(&robot).unwrap();
    let err = ik.solve(&Pose::translation(5.0, 0.0, 0.5)).unwrap_err();
    match &err {
        Error::Unreachable { solver, reason: Unreachable::OutsideReach { by, .. }, .. } => {
            assert_eq!(solver, "pieper");
            assert!(*by > 3.5 && *by < 5.0, "{by}");
        }
        other => panic!("expected OutsideReach, got {other:?}"),
    }
    assert!(err.to_string().contains("outside"), "{err}");
    // The synthetic arms: 5 m away is outside a named boundary.
    for (robot, what) in [
        (kr_like(), "outer reach"),
        (intersecting(), "outer sphere"),
        (parallel(), "slab"),
        (general_90_90(), "general Pieper"),
    ] {
        let ik = PieperIk::new(&robot).unwrap();
        match ik.solve(&Pose::translation(5.0, 0.0, 5.0)) {
            Err(Error::Unreachable { reason: Unreachable::OutsideReach { by, boundary }, .. }) => {
                assert!(by > 1.0 && boundary.contains(what), "{}: {by} {boundary}", robot.name())
            }
            // The general arm's search measures no distance: no figure.
            Err(Error::Unreachable { reason: Unreachable::NotReached { detail }, .. }) => {
                assert!(detail.contains(what), "{}: {detail}", robot.name())
            }
            other => panic!("{}: expected OutsideReach, got {other:?}", robot.name()),
        }
    }
    let mut nan = Pose::translation(0.5, 0.1, 0.5);
    nan.pos.y = f64::NAN;
    assert!(matches!(ik.solve(&nan), Err(Error::Input(InputError::NotFinite { .. }))));
    let mut bad = Pose::translation(0.5, 0.1, 0.5);
    bad.rot[(0, 0)] = 2.0;
    assert!(matches!(ik.solve(&bad), Err(Error::Input(InputError::OutOfRange { .. }))));
    // Huge but finite targets: an error, never a panic or NaN (past 1e100 m, without a figure).
    for s in [1e10, 1e200, f64::MAX] {
        match ik.solve(&Pose::translation(s, -s, s)) {
            Err(Error::Unreachable { reason: Unreachable::OutsideReach { by, .. }, .. }) => assert!(by > 1e9, "{by}"),
            Err(Error::Unreachable { reason: Unreachable::NotReached { .. }, .. }) if s > 1e100 => {}
            other => panic!("expected OutsideReach, got {other:?}"),
        }
    }
}

#[test]
fn random_poses_never_panic_or_nan() {
    for (robot, n) in
        [(puma(), 2000), (kr_like(), 500), (intersecting(), 500), (parallel(), 500), (general_90_90(), 500)]
    {
        let ik = PieperIk::new(&robot).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(99);
        let (mut ok, mut unreachable) = (0, 0);
        for _ in 0..n {
            let xyz = [rng.random_range(-1.2..1.2), rng.random_range(-1.2..1.2), rng.random_range(-0.6..1.8)];
            let rpy = [rng.random_range(-PI..PI), rng.random_range(-1.5..1.5), rng.random_range(-PI..PI)];
            let target = Pose::from_xyz_rpy(xyz, rpy, RpyConvention::Zyx);
            match ik.solve(&target) {
                Ok(sols) => {
                    ok += 1;
                    assert!(!sols.is_empty() && sols.len() <= 8);
                    assert_accurate(&sols, &format!("{}: random pose", robot.name()));
                }
                Err(Error::Unreachable {
                    reason: Unreachable::OutsideReach { by, .. } | Unreachable::InsideExcluded { by, .. },
                    ..
                }) => {
                    unreachable += 1;
                    assert!(by.is_finite() && by >= 0.0);
                }
                Err(Error::Unreachable { reason: Unreachable::NotReached { .. }, .. }) => unreachable += 1,
                Err(e) => panic!("{e}"),
            }
        }
        assert!(ok > n / 20 && unreachable > n / 20, "{}: {ok} {unreachable}", robot.name());
    }
}
