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
//! `cargo test -p kinema --test ik_contract -- --nocapture` prints the table
//! that README.md quotes.

use std::collections::BTreeMap;

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
    fixed: Option<&'static str>,
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
        fixed: Some("q3"),
    },
    Door {
        name: "pose --psi --all",
        solver: SolverChoice::Auto,
        all: true,
        with_q0: false,
        mask: false,
        position: false,
        fixed: Some("psi"),
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
        let family = kinema::ik::family::fit(&robot);
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
                    let held = |p: &str| {
                        door.fixed.filter(|&f| f == p).map(|f| redundancy.expect("checked above").parameter_of(&q, f))
                    };
                    let request = IkRequest {
                        solver: door.solver,
                        all: door.all,
                        q0,
                        mask: door.mask.then_some(mask),
                        q3: held("q3"),
                        psi: held("psi"),
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
