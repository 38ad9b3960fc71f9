//! The IK contract, door by door, IKFast-style: for every built-in robot,
//! and the URDF iiwa, PUMA 560 and UR5, every way of asking (solver choice, one or all, q0, task mask, position
//! only) and seeded targets of several kinds, count
//!
//! * **wrong**: a returned solution whose FK misses what the request
//!   constrains (measured here, independently of the library): must be 0;
//! * **refused**: a reachable target (FK of a within-limit configuration)
//!   answered with an error;
//! * **missing**: `all` did not list the configuration the target came from.
//!
//! `cargo test -p kinema --test all -- --nocapture ik_contract::` prints the table
//! that README.md quotes.

use std::collections::BTreeMap;

use kinema::ik::family::SelfMotionParameter;
use kinema::ik::{solve_target, IkRequest, IkTarget, SolverChoice};
use kinema::math::{axis_angle_to_rot, rot_to_axis_angle};
use kinema::nalgebra::Vector3;
use kinema::{Error, Pose, Robot};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Tolerance of the default request \[m, rad\].
const TOL: f64 = 1e-6;

#[derive(Default, Clone, Copy)]
struct Count {
    asked: usize,
    solved: usize,
    wrong: usize,
    refused: usize,
    missing: usize,
}

/// How the target is made from a random configuration q.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Kind {
    /// FK(q): reachable.
    Reachable,
    /// FK(q) moved by up to 1 cm and turned by up to 0.05 rad.
    Perturbed,
    /// FK(q) turned by 0.5 rad about a random axis.
    Rotated,
    /// FK(q) with the wrist joint (q5) at 1e-7 rad: near the wrist singularity.
    NearSingular,
    /// 10 m away: never reachable.
    Unreachable,
}

const KINDS: [Kind; 5] = [Kind::Reachable, Kind::Perturbed, Kind::Rotated, Kind::NearSingular, Kind::Unreachable];

fn random_axis(rng: &mut ChaCha8Rng) -> Vector3<f64> {
    loop {
        let v = Vector3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
        if v.norm() > 0.1 && v.norm() <= 1.0 {
            return v.normalize();
        }
    }
}

fn make_target(robot: &Robot, kind: Kind, rng: &mut ChaCha8Rng) -> (Vec<f64>, Pose) {
    let mut q = robot.random_q(rng);
    if kind == Kind::NearSingular && q.len() >= 5 {
        q[4] = 1e-7;
    }
    let mut pose = robot.fk(&q).unwrap().world_from_tool;
    match kind {
        Kind::Perturbed => {
            pose.pos += random_axis(rng) * rng.random_range(0.0..0.01);
            pose.rot = axis_angle_to_rot(&(random_axis(rng) * rng.random_range(0.0..0.05))) * pose.rot;
        }
        Kind::Rotated => pose.rot = axis_angle_to_rot(&(random_axis(rng) * 0.5)) * pose.rot,
        Kind::Unreachable => pose.pos += Vector3::new(10.0, 0.0, 0.0),
        Kind::Reachable | Kind::NearSingular => {}
    }
    (q, pose)
}

/// The masked residual of `q` against `target`, computed here.
fn misses(robot: &Robot, q: &[f64], target: &Pose, mask: [bool; 6]) -> bool {
    let reached = robot.fk(q).unwrap().world_from_tool;
    let dp = target.pos - reached.pos;
    let dw = rot_to_axis_angle(&(target.rot * reached.rot.transpose()));
    let norm = |v: Vector3<f64>, m: &[bool]| (0..3).filter(|&k| m[k]).map(|k| v[k] * v[k]).sum::<f64>().sqrt();
    norm(dp, &mask[..3]) > TOL * 1.000_001 || norm(dw, &mask[3..]) > TOL * 1.000_001
}

fn same_configuration(robot: &Robot, a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).zip(robot.joints()).all(|((x, y), j)| {
        let d = x - y;
        let d = if j.kind == kinema::JointType::Revolute { kinema::ik::wrap_angle(d) } else { d };
        d.abs() < 1e-6
    })
}

/// One door: a name and the request it makes.
struct Door {
    name: &'static str,
    solver: SolverChoice,
    all: bool,
    with_q0: bool,
    mask: bool,
    position: bool,
    /// A self-motion parameter held at the source configuration's value
    /// (`--q3`, `--psi`), with every solution there listed.
    fixed: Option<SelfMotionParameter>,
}

const DOORS: [Door; 9] = [
    Door {
        name: "pose auto",
        solver: SolverChoice::Auto,
        all: false,
        with_q0: false,
        mask: false,
        position: false,
        fixed: None,
    },
    Door {
        name: "pose auto --all",
        solver: SolverChoice::Auto,
        all: true,
        with_q0: false,
        mask: false,
        position: false,
        fixed: None,
    },
    Door {
        name: "pose auto --q0",
        solver: SolverChoice::Auto,
        all: false,
        with_q0: true,
        mask: false,
        position: false,
        fixed: None,
    },
    Door {
        name: "pose analytic --all",
        solver: SolverChoice::Analytic,
        all: true,
        with_q0: false,
        mask: false,
        position: false,
        fixed: None,
    },
    Door {
        name: "pose numeric",
        solver: SolverChoice::Numeric,
        all: false,
        with_q0: false,
        mask: false,
        position: false,
        fixed: None,
    },
    Door {
        name: "pose --mask",
        solver: SolverChoice::Auto,
        all: false,
        with_q0: false,
        mask: true,
        position: false,
        fixed: None,
    },
    Door {
        name: "position",
        solver: SolverChoice::Auto,
        all: false,
        with_q0: false,
        mask: false,
        position: true,
        fixed: None,
    },
    Door {
        name: "pose --q3 --all",
        solver: SolverChoice::Auto,
        all: true,
        with_q0: false,
        mask: false,
        position: false,
        fixed: Some(SelfMotionParameter::Q3),
    },
    Door {
        name: "pose --psi --all",
        solver: SolverChoice::Auto,
        all: true,
        with_q0: false,
        mask: false,
        position: false,
        fixed: Some(SelfMotionParameter::ArmAngle),
    },
];

#[test]
fn no_door_returns_a_wrong_solution() {
    let cases = 60;
    let mut table: BTreeMap<(String, &str, String), Count> = BTreeMap::new();
    // The built-in robots, and URDF descriptions that the analytic solvers read from their axes.
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data");
    let urdfs = ["iiwa14.urdf", "puma560.urdf", "ur5.urdf"];
    let robots = kinema::builtin_names()
        .map(|n| (n.to_string(), Robot::builtin(n).unwrap()))
        .chain(urdfs.iter().map(|f| (f.to_string(), Robot::from_file(format!("{data}/{f}"), None).unwrap())));
    for (name, robot) in robots {
        let name = name.as_str();
        let has_analytic = kinema::ik::analytic_solver(&robot).is_some();
        let family = kinema::ik::registry::fit(&robot);
        let redundancy = family.as_deref().and_then(|f| f.redundancy());
        let mut rng = ChaCha8Rng::seed_from_u64(0x1c0 ^ name.len() as u64);
        for door in &DOORS {
            if door.solver == SolverChoice::Analytic && !has_analytic {
                continue;
            }
            if door.fixed.is_some_and(|p| !redundancy.is_some_and(|r| r.parameters().contains(&p))) {
                continue;
            }
            for kind in KINDS {
                let c = table.entry((name.to_string(), door.name, format!("{kind:?}"))).or_default();
                for _ in 0..cases {
                    let (q, pose) = make_target(&robot, kind, &mut rng);
                    let mask = if door.mask {
                        // A random mask with at least one component, position always kept.
                        let mut m = [true; 6];
                        let free = rng.random_range(3..6);
                        m[free] = false;
                        m
                    } else if door.position {
                        [true, true, true, false, false, false]
                    } else {
                        [true; 6]
                    };
                    let target = if door.position {
                        IkTarget::Position([pose.pos.x, pose.pos.y, pose.pos.z])
                    } else {
                        IkTarget::Pose(pose)
                    };
                    let q0 = if door.with_q0 { Some(q.as_slice()) } else { None };
                    let held = |p: SelfMotionParameter| {
                        door.fixed.filter(|&f| f == p).map(|f| redundancy.expect("checked above").parameter_of(&q, f))
                    };
                    let request = IkRequest {
                        solver: door.solver,
                        all: door.all,
                        q0,
                        mask: door.mask.then_some(mask),
                        q3: held(SelfMotionParameter::Q3),
                        psi: held(SelfMotionParameter::ArmAngle),
                        ..Default::default()
                    };
                    c.asked += 1;
                    let reachable = matches!(kind, Kind::Reachable | Kind::NearSingular);
                    let answer = solve_target(&robot, &target, &request);
                    let answer = match answer {
                        Ok(a) => a,
                        Err(Error::Unreachable { .. }) => {
                            c.refused += usize::from(reachable);
                            continue;
                        }
                        Err(e) => panic!("{name} {}: {e}", door.name),
                    };
                    let solutions = if door.all {
                        answer.solutions
                    } else {
                        match kinema::ik::pick_one(&robot, answer.solver, answer.solutions, q0) {
                            Ok(s) => vec![s],
                            Err(Error::Unreachable { .. }) => {
                                c.refused += usize::from(reachable);
                                continue;
                            }
                            Err(e) => panic!("{name} {}: {e}", door.name),
                        }
                    };
                    c.solved += 1;
                    assert!(!solutions.is_empty());
                    c.wrong += solutions.iter().filter(|s| misses(&robot, &s.q, &pose, mask)).count();
                    if door.all && reachable && !solutions.iter().any(|s| same_configuration(&robot, &s.q, &q)) {
                        c.missing += 1;
                    }
                }
            }
        }
    }
    println!(
        "{:<20} {:<20} {:<13} {:>6} {:>6} {:>6} {:>8} {:>8}",
        "robot", "door", "target", "asked", "solved", "wrong", "refused", "missing"
    );
    let mut wrong = 0;
    for ((robot, door, kind), c) in &table {
        println!(
            "{robot:<20} {door:<20} {kind:<13} {:>6} {:>6} {:>6} {:>8} {:>8}",
            c.asked, c.solved, c.wrong, c.refused, c.missing
        );
        wrong += c.wrong;
    }
    println!("\nSummed over robots and target kinds (refused: of the reachable and near-singular targets):");
    println!("{:<20} {:>6} {:>6} {:>6} {:>8} {:>8}", "door", "asked", "solved", "wrong", "refused", "missing");
    let mut by_door: BTreeMap<&str, (Count, usize)> = BTreeMap::new();
    for ((_, door, kind), c) in &table {
        let (sum, reachable) = by_door.entry(door).or_default();
        (sum.asked, sum.solved, sum.wrong) = (sum.asked + c.asked, sum.solved + c.solved, sum.wrong + c.wrong);
        (sum.refused, sum.missing) = (sum.refused + c.refused, sum.missing + c.missing);
        if kind == "Reachable" || kind == "NearSingular" {
            *reachable += c.asked;
        }
    }
    for (door, (c, reachable)) in &by_door {
        let refused = format!("{}/{reachable}", c.refused);
        println!("{door:<20} {:>6} {:>6} {:>6} {refused:>8} {:>8}", c.asked, c.solved, c.wrong, c.missing);
    }
    assert_eq!(wrong, 0, "solutions returned that miss the request");
    // Reachable targets asked with the solver left to choose are never refused.
    for ((robot, door, kind), c) in &table {
        if kind == "Reachable" && !door.contains("numeric") && !door.contains("analytic") {
            assert_eq!(c.refused, 0, "{robot} {door}: reachable targets refused");
        }
    }
}

// Issue 34, items 5, 6 and 8: joints with more than a turn of range, joints on
// a limit, and what an unreachable target's message quotes.

mod edges {
    use super::*;
    use kinema::ik::{analytic_solver, pick_one, Solution};
    use kinema::model::{Joint, Limits};
    use kinema::{JointType, LinkGeometry};
    use std::f64::consts::TAU;

    fn data(name: &str) -> String {
        format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR"))
    }

    /// `robot` with the limits `f` gives each joint (everything else kept).
    fn with_limits(robot: &Robot, f: impl Fn(usize, &Joint) -> Limits) -> Robot {
        let joints: Vec<Joint> =
            robot.joints().iter().enumerate().map(|(i, j)| Joint { limits: f(i, j), ..j.clone() }).collect();
        robot.to_builder().joints(joints).build().map(Robot::new).unwrap()
    }

    fn deg(lo: f64, hi: f64, j: &Joint) -> Limits {
        Limits { min: lo.to_radians(), max: hi.to_radians(), ..j.limits }
    }

    /// `robot` with DH length `a` of joint `i` set (to move it into the search families).
    fn with_a(robot: &Robot, i: usize, value: f64) -> Robot {
        let mut joints = robot.joints().to_vec();
        if let LinkGeometry::Dh { a, .. } = &mut joints[i].geometry {
            *a = value;
        }
        robot.to_builder().joints(joints).build().map(Robot::new).unwrap()
    }

    /// The KUKA KR 16-like URDF (A1 ±185°, A4 and A6 ±350°, A2 up to 35°).
    fn kr16() -> Robot {
        Robot::load(&data("kr16-like.urdf"), Some("tool0")).unwrap()
    }

    /// Robots of every family whose joints have more than a turn of range
    /// (name, robot): KUKA-like ±350° wrists, Kinova-like ±360° and
    /// continuous joints. The built-in UR5 (±360°), Scorbot (q5 ±570°) and
    /// SCARA (q5 ±360°) have them already.
    fn wide() -> Vec<(String, Robot)> {
        let puma = Robot::builtin("puma560").unwrap();
        let iiwa = Robot::builtin("lbr-iiwa-14-r820").unwrap();
        let wrists = |i: usize, j: &Joint| if i == 3 || i == 5 { deg(-350.0, 350.0, j) } else { j.limits };
        let kinova = |_: usize, j: &Joint| deg(-360.0, 360.0, j);
        let continuous = |i: usize, j: &Joint| {
            if i == 5 {
                Limits { min: f64::NEG_INFINITY, max: f64::INFINITY, ..j.limits }
            } else {
                j.limits
            }
        };
        let iiwa_wide = |i: usize, j: &Joint| if i == 0 || i == 6 { deg(-350.0, 350.0, j) } else { j.limits };
        let iiwa_urdf = Robot::load(&data("iiwa14.urdf"), None).unwrap();
        vec![
            ("puma560 ±350° wrists (pieper)".into(), with_limits(&puma, wrists)),
            ("puma560 ±360° (pieper)".into(), with_limits(&puma, kinova)),
            ("puma560 continuous q6 (pieper)".into(), with_limits(&puma, continuous)),
            ("kr16-like URDF (geo spherical)".into(), kr16()),
            ("ur5 ±360° (geo three-parallel)".into(), Robot::builtin("ur5").unwrap()),
            ("ur5 continuous q6 (geo three-parallel)".into(), with_limits(&Robot::builtin("ur5").unwrap(), continuous)),
            ("ur5 offset wrist ±360° (search)".into(), with_a(&Robot::builtin("ur5").unwrap(), 4, 0.02)),
            ("puma560 offset wrist ±350° (search)".into(), with_a(&with_limits(&puma, wrists), 3, 0.03)),
            ("iiwa q1, q7 ±350° (iiwa)".into(), with_limits(&iiwa, iiwa_wide)),
            ("iiwa URDF q1, q7 ±350° (geo-srs)".into(), with_limits(&iiwa_urdf, iiwa_wide)),
            ("scorbot q5 ±570°".into(), Robot::builtin("scorbot-er-v-plus").unwrap()),
            (
                "rommel ±350° q1".into(),
                with_limits(
                    &Robot::builtin("rommel").unwrap(),
                    |i, j| {
                        if i == 0 {
                            deg(-350.0, 350.0, j)
                        } else {
                            j.limits
                        }
                    },
                ),
            ),
        ]
    }

    fn max_diff(a: &[f64], b: &[f64]) -> f64 {
        a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
    }

    /// How far from q0 the pick may be: 0 up to rounding, but a family with a
    /// self-motion picks its parameter on a grid near q0's (seed 004 §V-E),
    /// so its pick is only near.
    fn near_enough(robot: &Robot) -> f64 {
        let redundant = kinema::ik::registry::fit(robot).is_some_and(|f| f.redundancy().is_some());
        if redundant {
            0.5
        } else {
            1e-6
        }
    }

    fn is_continuous(j: &Joint) -> bool {
        j.kind == JointType::Revolute && !(j.limits.min.is_finite() && j.limits.max.is_finite())
    }

    /// Item 5: with `q0` = the configuration a target came from, the pick is
    /// that configuration (the within-limit solution nearest q0, at distance
    /// 0), not another branch or a copy 2π away, and `all` lists it; a
    /// continuous joint keeps q0's turn. Counted over seeded targets where the
    /// answer holds q modulo 2π at all (a redundant family may answer with
    /// other solutions).
    #[test]
    fn q0_picks_the_nearest_copy_on_joints_with_more_than_a_turn() {
        let cases = 300;
        let mut report = Vec::new();
        let mut failures = 0;
        for (k, (name, robot)) in wide().into_iter().enumerate() {
            let mut rng = ChaCha8Rng::seed_from_u64(3400 + k as u64);
            let (mut eligible, mut missed, mut far, mut unlisted, mut outside) = (0, 0, 0, 0, 0);
            for _ in 0..cases {
                let mut q = robot.random_q(&mut rng);
                for (v, j) in q.iter_mut().zip(robot.joints()) {
                    if is_continuous(j) {
                        *v += TAU * rng.random_range(-2i32..=2) as f64;
                    }
                }
                let target = IkTarget::Pose(robot.fk(&q).unwrap().world_from_tool);
                let all = IkRequest { q0: Some(&q), all: true, ..Default::default() };
                let Ok(answer) = solve_target(&robot, &target, &all) else { continue };
                if !answer.solutions.iter().any(|s| same_configuration(&robot, &s.q, &q)) {
                    continue;
                }
                eligible += 1;
                let near = near_enough(&robot);
                unlisted += usize::from(!answer.solutions.iter().any(|s| max_diff(&s.q, &q) < 1e-6));
                let one = IkRequest { q0: Some(&q), ..Default::default() };
                let picked =
                    solve_target(&robot, &target, &one).and_then(|a| pick_one(&robot, a.solver, a.solutions, Some(&q)));
                match picked {
                    Ok(s) => {
                        let d = max_diff(&s.q, &q);
                        missed += usize::from(d > near);
                        far += usize::from(d > 1.0);
                        outside += usize::from(!robot.limit_flags(&s.q).is_empty());
                    }
                    Err(_) => missed += 1,
                }
            }
            report.push(format!(
                "{name}: {eligible} targets, q0 not picked {missed} ({:.1} %, > 1 rad away {far}), not listed by all {unlisted}, outside limits {outside}",
                100.0 * missed as f64 / eligible.max(1) as f64
            ));
            assert!(eligible > cases / 4 || name.contains("iiwa"), "{name}: only {eligible} targets recover q");
            failures += missed + unlisted + outside;
        }
        println!("{}", report.join("\n"));
        assert_eq!(failures, 0, "\n{}", report.join("\n"));
    }

    /// Item 5, `all`: every within-limit copy is listed (or counted as
    /// folded): on the KR 16-like arm, each solution's copies in A1, A4 and A6.
    #[test]
    fn all_lists_every_copy_within_limits() {
        let robot = kr16();
        let mut rng = ChaCha8Rng::seed_from_u64(3410);
        for _ in 0..200 {
            let q = robot.random_q(&mut rng);
            let target = IkTarget::Pose(robot.fk(&q).unwrap().world_from_tool);
            let answer = solve_target(&robot, &target, &IkRequest { all: true, ..Default::default() }).unwrap();
            assert_eq!(answer.folded, 0);
            for s in answer.solutions.iter().filter(|s| s.within_limits()) {
                for i in [0, 3, 5] {
                    let lim = robot.joints()[i].limits;
                    for k in [-1.0, 1.0] {
                        let mut c = s.q.clone();
                        c[i] += k * TAU;
                        if lim.contains(c[i]) {
                            assert!(
                                answer.solutions.iter().any(|o| max_diff(&o.q, &c) < 1e-9),
                                "copy of {:?} with q{} {k:+}·2π missing",
                                s.q,
                                i + 1
                            );
                        }
                    }
                }
            }
        }
    }

    /// Robots for the limit and message tests: the built-ins, the URDFs,
    /// the wide ones above and a general Pieper arm.
    fn zoo() -> Vec<(String, Robot)> {
        let mut robots: Vec<(String, Robot)> =
            kinema::builtin_names().map(|n| (n.to_string(), Robot::builtin(n).unwrap())).collect();
        for f in ["iiwa14.urdf", "puma560.urdf", "ur5.urdf"] {
            robots.push((f.to_string(), Robot::load(&data(f), None).unwrap()));
        }
        robots.push(("ur5-general.toml".into(), Robot::load(&data("ur5-general.toml"), None).unwrap()));
        robots.extend(wide());
        let general = "name = \"general-90-90\"\nsource = \"synthetic\"\nconvention = \"standard\"\n[units]\nlength = \"m\"\nangle = \"deg\"\n";
        let rows = [
            (0.35, 0.1, 90.0, 0.0),
            (0.1, 0.3, 90.0, 20.0),
            (0.05, 0.02, -90.0, 0.0),
            (0.3, 0.0, 90.0, 0.0),
            (0.0, 0.0, -90.0, 0.0),
            (0.07, 0.0, 0.0, 0.0),
        ];
        let mut t = general.to_string();
        for (i, (d, a, alpha, offset)) in rows.iter().enumerate() {
            t += &format!("[[joint]]\nname = \"j{}\"\nd = {d}\na = {a}\nalpha = {alpha}\noffset = {offset}\nmin = -170\nmax = 170\n", i + 1);
        }
        t += "[poses]\nhome = [0, 0, 0, 0, 0, 0]\n";
        robots.push(("general Pieper arm".into(), Robot::from_toml_str(&t, "general.toml").unwrap()));
        // A random 6R arm: the general 2-D search.
        let dh = "name = \"dh\"\nsource = \"synthetic\"\nconvention = \"standard\"\n[units]\nlength = \"m\"\nangle = \"deg\"\n\
                  [[joint]]\nname = \"j1\"\nd = 0.2\na = 0.1\nalpha = 60\nmin = -350\nmax = 350\n\
                  [[joint]]\nname = \"j2\"\nd = -0.1\na = 0.3\nalpha = 30\nmin = -180\nmax = 180\n\
                  [[joint]]\nname = \"j3\"\nd = 0.05\na = 0.25\nalpha = -70\nmin = -180\nmax = 180\n\
                  [[joint]]\nname = \"j4\"\nd = 0.1\na = 0.08\nalpha = 110\nmin = -180\nmax = 180\n\
                  [[joint]]\nname = \"j5\"\nd = -0.05\na = 0.12\nalpha = -40\nmin = -180\nmax = 180\n\
                  [[joint]]\nname = \"j6\"\nd = 0.08\na = 0.05\nalpha = 20\nmin = -350\nmax = 350\n\
                  [poses]\nhome = [0, 0, 0, 0, 0, 0]\n";
        robots.push(("random 6R (geo-general)".into(), Robot::from_toml_str(dh, "dh.toml").unwrap()));
        robots
    }

    /// Item 6: a target whose configuration has a joint exactly on its limit
    /// is solved, and the answer is strictly within limits: by every family
    /// (q0 = the configuration, so the pick should be it), and by the
    /// numeric solver.
    #[test]
    fn a_joint_exactly_on_its_limit_is_accepted() {
        let cases = 200;
        let mut report = Vec::new();
        let mut failures = 0;
        for (k, (name, robot)) in zoo().into_iter().enumerate() {
            let family = analytic_solver(&robot).map(|s| s.name()).unwrap_or("numeric");
            let near = near_enough(&robot);
            let mut rng = ChaCha8Rng::seed_from_u64(3420 + k as u64);
            let (mut asked, mut refused, mut missed, mut outside, mut numeric_bad) = (0, 0, 0, 0, 0);
            for case in 0..cases {
                let mut q = robot.random_q(&mut rng);
                let i = rng.random_range(0..robot.dof());
                let lim = robot.joints()[i].limits;
                q[i] = if rng.random_bool(0.5) { lim.min } else { lim.max };
                if !q[i].is_finite() {
                    continue;
                }
                asked += 1;
                let target = IkTarget::Pose(robot.fk(&q).unwrap().world_from_tool);
                let one = IkRequest { q0: Some(&q), ..Default::default() };
                let check = |s: &Solution| {
                    !robot.limit_flags(&s.q).is_empty()
                        || misses(&robot, &s.q, &robot.fk(&q).unwrap().world_from_tool, [true; 6])
                };
                // Where `all` holds q (modulo 2π: not at a singularity, not another
                // point of a self-motion), the pick near q must be q itself.
                let all = IkRequest { q0: Some(&q), all: true, ..Default::default() };
                let recoverable = solve_target(&robot, &target, &all)
                    .is_ok_and(|a| a.solutions.iter().any(|s| same_configuration(&robot, &s.q, &q)));
                let picked =
                    solve_target(&robot, &target, &one).and_then(|a| pick_one(&robot, a.solver, a.solutions, Some(&q)));
                match picked {
                    Ok(s) => {
                        outside += usize::from(check(&s));
                        missed += usize::from(recoverable && max_diff(&s.q, &q) > near);
                    }
                    Err(_) => refused += 1,
                }
                if case % 10 == 0 {
                    // The numeric solver from a start 0.1 rad away.
                    let start: Vec<f64> = q
                        .iter()
                        .zip(robot.joints())
                        .map(|(v, j)| (v + 0.1).clamp(j.limits.min, j.limits.max))
                        .collect();
                    let numeric = IkRequest { solver: SolverChoice::Numeric, q0: Some(&start), ..Default::default() };
                    let solved = solve_target(&robot, &target, &numeric)
                        .and_then(|a| pick_one(&robot, a.solver, a.solutions, None));
                    if let Ok(s) = solved {
                        numeric_bad += usize::from(check(&s));
                    }
                }
            }
            report.push(format!(
                "{name} ({family}): {asked} targets, refused {refused} ({:.1} %), q not picked {missed}, outside limits {outside}, numeric outside {numeric_bad}",
                100.0 * refused as f64 / asked.max(1) as f64
            ));
            failures += refused + missed + outside + numeric_bad;
        }
        println!("{}", report.join("\n"));
        assert_eq!(failures, 0, "\n{}", report.join("\n"));
    }

    /// The figures "X m outside/inside" in a message.
    fn figures(message: &str) -> Vec<String> {
        let words: Vec<&str> = message.split_whitespace().collect();
        (2..words.len())
            .filter(|&w| words[w - 1] == "m" && (words[w].starts_with("outside") || words[w].starts_with("inside")))
            .map(|w| words[w - 2].to_string())
            .collect()
    }

    /// Item 8: every figure an unreachable message quotes is a distance: the
    /// targets are within-limit poses moved by d (up to 1000 m, and absurdly
    /// far), so the tool (and wrist centre) is at most d from where the arm
    /// reaches: no figure may be larger, infinite, or not a number, and no
    /// message may talk of a `by` the reader does not see.
    #[test]
    fn unreachable_messages_quote_only_distances() {
        let mut report = Vec::new();
        let mut failures = 0;
        for (k, (name, robot)) in zoo().into_iter().enumerate() {
            let Some(solver) = analytic_solver(&robot) else { continue };
            let mut rng = ChaCha8Rng::seed_from_u64(3430 + k as u64);
            let (mut refused, mut bad) = (0, Vec::new());
            let cases = if solver.name().contains("search") || solver.name() == "geo-general" { 60 } else { 300 };
            for case in 0..cases {
                let q = robot.random_q(&mut rng);
                let mut pose = robot.fk(&q).unwrap().world_from_tool;
                let d = match case % 20 {
                    0 => 1e120,
                    1 => 1e200,
                    2 => 10.0,
                    _ => 10f64.powf(rng.random_range(-2.0..3.0)),
                };
                pose.pos += random_axis(&mut rng) * d;
                let Err(e) = solver.solve(&pose) else { continue };
                refused += 1;
                let m = e.to_string();
                let wrong = figures(&m).iter().any(|f| {
                    !f.parse::<f64>().is_ok_and(|x| x.is_finite() && x >= 0.0 && x <= d * (1.0 + 1e-9) + 1e-9)
                }) || m.contains("`by`")
                    || m.contains(" by)")
                    || m.ends_with(" by");
                if wrong {
                    bad.push(format!("d = {d:.3e}: {m}"));
                }
            }
            report.push(format!(
                "{name} ({}): {refused} refused, {} with a figure that is not a distance{}",
                solver.name(),
                bad.len(),
                bad.first().map_or(String::new(), |m| format!(", e.g. {m}"))
            ));
            failures += bad.len();
        }
        println!("{}", report.join("\n"));
        assert_eq!(failures, 0, "\n{}", report.join("\n"));
    }
}
