//! A planning problem set in the style of MotionBenchMaker (Chamzas et al.
//! 2022, "MotionBenchMaker: A Tool to Generate and Benchmark Motion Planning
//! Datasets", RA-L 7(2)): table, shelf, bookshelf, cage and boxes scenes with
//! seeded random placement, for the Panda and the iiwa. Each problem's start
//! and goal are collision-free and the straight segment between them is not,
//! so every problem needs a search; a long search (20 000 iterations) has
//! joined them once, so none sits in a pocket no path leaves. The goal reaches a pose in the scene's
//! task region (over an object on the table, into a shelf cell, into the
//! cage) through the IK contract with the scene as its admissibility test.
//!
//! The set is kept as data in `benchmarks/plan/` (one scene file per
//! problem, `problems.csv`); `KINEMA_WRITE_PLAN_PROBLEMS=1` rewrites it, and
//! the test below checks that the committed files are what this generator
//! makes. `plan_problem_set` (ignored, run by `.ci/run`) plans every problem
//! and prints the success rate and planning times.

use std::f64::consts::{FRAC_PI_2, PI};
use std::path::{Path, PathBuf};
use std::time::Duration;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use kinema::ik::{solve_target, IkRequest, IkTarget};
use kinema::{Pose, Robot};
use kinema_geometry::plan::{plan, Goal, PlanOptions};
use kinema_geometry::{load_robot_geometry, CollisionCheck, CollisionPairs, Scene};

use crate::common::densely_clear;

const ROBOTS: [&str; 2] = ["panda", "lbr-iiwa-14-r820"];
const FAMILIES: [&str; 5] = ["table", "shelf", "bookshelf", "cage", "boxes"];
const PER_FAMILY: u64 = 10;

/// One problem: a scene, a start and a goal configuration.
struct Problem {
    name: String,
    robot: &'static str,
    scene: String,
    start: Vec<f64>,
    goal: Vec<f64>,
}

fn set_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../benchmarks/plan")
}

/// Obstacle tables of a scene, written as the scene format reads them.
#[derive(Default)]
struct SceneText(String);

impl SceneText {
    fn cuboid(&mut self, name: &str, size: [f64; 3], at: [f64; 3], yaw: f64) {
        self.0 += &format!(
            "[[obstacle]]\nname = \"{name}\"\nbox = [{}]\npose = [{}, 0, 0, {}]\n\n",
            join(&size, 4),
            join(&at, 4),
            round(yaw, 4)
        );
    }

    fn post(&mut self, name: &str, radius: f64, length: f64, at: [f64; 3]) {
        self.0 += &format!(
            "[[obstacle]]\nname = \"{name}\"\ncylinder = {{ radius = {}, length = {} }}\npose = [{}, 0, 0, 0]\n\n",
            round(radius, 4),
            round(length, 4),
            join(&at, 4)
        );
    }
}

fn round(x: f64, decimals: i32) -> f64 {
    let k = 10f64.powi(decimals);
    let r = (x * k).round() / k;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

fn join(v: &[f64], decimals: i32) -> String {
    v.iter().map(|x| round(*x, decimals).to_string()).collect::<Vec<_>>().join(", ")
}

/// A point of a frame turned by `yaw` about z and moved to `origin`.
fn placed(origin: [f64; 3], yaw: f64, local: [f64; 3]) -> [f64; 3] {
    let (s, c) = yaw.sin_cos();
    [origin[0] + c * local[0] - s * local[1], origin[1] + s * local[0] + c * local[1], origin[2] + local[2]]
}

/// A family's scene and the tool poses its task asks for.
fn scene_and_targets(family: &str, rng: &mut ChaCha8Rng) -> (SceneText, Vec<Pose>) {
    let mut s = SceneText::default();
    let mut targets = Vec::new();
    let down = |yaw: f64| Pose::rot_z(yaw) * Pose::rot_x(PI);
    let forward = |yaw: f64| Pose::rot_z(yaw) * Pose::rot_y(FRAC_PI_2);
    match family {
        "table" => {
            let (x, top) = (rng.random_range(0.5..0.65), rng.random_range(0.05..0.3));
            s.cuboid("table", [0.6, 1.2, 0.04], [x, 0.0, top - 0.02], 0.0);
            for k in 0..rng.random_range(3..6) {
                let (ox, oy, h) =
                    (x + rng.random_range(-0.2..0.2), rng.random_range(-0.45..0.45), rng.random_range(0.08..0.2));
                s.cuboid(&format!("object{k}"), [0.06, 0.06, h], [ox, oy, top + h / 2.0], rng.random_range(-PI..PI));
                let above = top + h + rng.random_range(0.05..0.12);
                targets.push(Pose::translation(ox, oy, above) * down(rng.random_range(-PI..PI)));
            }
        }
        "shelf" | "bookshelf" => {
            let tall = family == "bookshelf";
            let yaw = if tall {
                rng.random_range(0.9..1.3) * if rng.random_bool(0.5) { 1.0 } else { -1.0 }
            } else {
                rng.random_range(-0.4..0.4)
            };
            let origin = [0.0, 0.0, 0.0];
            let depth = rng.random_range(0.6..0.72);
            let (boards, gap, bottom) = if tall { (5, 0.28, 0.0) } else { (3, 0.32, rng.random_range(0.1..0.3)) };
            let width = 0.8;
            let height = gap * (boards - 1) as f64;
            let back = placed(origin, yaw, [depth + 0.3, 0.0, bottom + height / 2.0]);
            s.cuboid("back", [0.02, width, height + 0.02], back, yaw);
            for side in [-1.0, 1.0] {
                let at = placed(origin, yaw, [depth + 0.15, side * width / 2.0, bottom + height / 2.0]);
                s.cuboid(
                    &format!("side{}", if side < 0.0 { "_right" } else { "_left" }),
                    [0.3, 0.02, height + 0.02],
                    at,
                    yaw,
                );
            }
            for b in 0..boards {
                let z = bottom + gap * b as f64;
                s.cuboid(&format!("board{b}"), [0.3, width, 0.02], placed(origin, yaw, [depth + 0.15, 0.0, z]), yaw);
                if b + 1 < boards {
                    let y = rng.random_range(-0.25..0.25);
                    let z_mid = z + rng.random_range(0.1..0.16);
                    let into = placed(origin, yaw, [depth + rng.random_range(0.04..0.12), y, z_mid]);
                    targets.push(Pose::translation(into[0], into[1], into[2]) * forward(yaw));
                    if tall {
                        let book =
                            placed(origin, yaw, [depth + 0.18, y + 0.16 * if y < 0.0 { 1.0 } else { -1.0 }, z + 0.1]);
                        s.cuboid(&format!("book{b}"), [0.2, 0.04, 0.18], book, yaw);
                    }
                }
            }
        }
        "cage" => {
            let (x, y, top) = (rng.random_range(0.45..0.6), rng.random_range(-0.2..0.2), rng.random_range(0.45..0.6));
            let half = 0.18;
            s.cuboid("floor", [2.0 * half + 0.04, 2.0 * half + 0.04, 0.02], [x, y, 0.01], 0.0);
            for (k, (dx, dy)) in [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)].iter().enumerate() {
                s.post(&format!("post{k}"), 0.015, top, [x + dx * half, y + dy * half, top / 2.0]);
            }
            s.cuboid("bar_front", [0.03, 2.0 * half, 0.03], [x - half, y, top], 0.0);
            s.cuboid("bar_back", [0.03, 2.0 * half, 0.03], [x + half, y, top], 0.0);
            s.cuboid("bar_middle", [0.03, 2.0 * half, 0.03], [x, y, top], 0.0);
            for _ in 0..4 {
                let p = [
                    x + rng.random_range(-0.1..0.1),
                    y + rng.random_range(-0.1..0.1),
                    rng.random_range(0.15..top - 0.12),
                ];
                targets.push(Pose::translation(p[0], p[1], p[2]) * down(rng.random_range(-PI..PI)));
            }
        }
        "boxes" => {
            for k in 0..rng.random_range(6..10) {
                let (r, a) = (rng.random_range(0.4..0.8), rng.random_range(-PI..PI));
                let size = [rng.random_range(0.08..0.25), rng.random_range(0.08..0.25), rng.random_range(0.08..0.25)];
                s.cuboid(
                    &format!("box{k}"),
                    size,
                    [r * a.cos(), r * a.sin(), rng.random_range(0.05..0.9)],
                    rng.random_range(-PI..PI),
                );
            }
            for _ in 0..6 {
                let (r, a, z) = (rng.random_range(0.35..0.7), rng.random_range(-PI..PI), rng.random_range(0.1..0.9));
                targets.push(Pose::translation(r * a.cos(), r * a.sin(), z) * down(rng.random_range(-PI..PI)));
            }
        }
        other => panic!("no family {other}"),
    }
    (s, targets)
}

fn check_of(robot: &str, scene: &str) -> CollisionCheck {
    let scene = Scene::from_toml(scene, "problem.toml", Path::new(".")).unwrap();
    let (robot, geometry) = load_robot_geometry(robot, &Default::default()).unwrap();
    let pairs = CollisionPairs::self_collision(&geometry);
    CollisionCheck::with_scene(robot, geometry, pairs, Some(&scene), 0.0).unwrap()
}

fn rounded_q(q: &[f64]) -> Vec<f64> {
    q.iter().map(|x| round(*x, 6)).collect()
}

fn within_limits(robot: &Robot, q: &[f64]) -> bool {
    robot.check_within_limits(q, "q").is_ok()
}

/// A free configuration: random within the limits, tool in front of the base.
fn free_start(check: &CollisionCheck, rng: &mut ChaCha8Rng) -> Option<Vec<f64>> {
    let robot = check.robot();
    for _ in 0..2000 {
        let q: Vec<f64> =
            robot.joints().iter().map(|j| rng.random_range(j.limits.min * 0.95..j.limits.max * 0.95)).collect();
        let q = rounded_q(&q);
        if within_limits(robot, &q) && check.first_collision(&q).unwrap().is_none() {
            return Some(q);
        }
    }
    None
}

/// A collision-free IK solution for one of `targets`.
fn free_goal(check: &CollisionCheck, targets: &[Pose], rng: &mut ChaCha8Rng) -> Option<Vec<f64>> {
    let robot = check.robot();
    let request = IkRequest { all: true, admissible: Some(check), ..Default::default() };
    let mut order: Vec<usize> = (0..targets.len()).collect();
    for i in (1..order.len()).rev() {
        order.swap(i, rng.random_range(0..=i));
    }
    for t in order {
        let Ok(answer) = solve_target(robot, &IkTarget::Pose(targets[t]), &request) else { continue };
        let pick = rng.random_range(0..answer.solutions.len());
        let q = rounded_q(&answer.solutions[pick].q);
        if within_limits(robot, &q) && check.first_collision(&q).unwrap().is_none() {
            return Some(q);
        }
    }
    None
}

/// Whether a long search joins `start` and `goal`: a random free start can
/// sit in a pocket of the cage no path leaves, which no planner should be
/// scored on. The budget is in iterations, so the answer does not depend on
/// the machine.
fn solvable(check: &CollisionCheck, start: &[f64], goal: &[f64], tag: u64) -> bool {
    let options = PlanOptions {
        seed: tag ^ 0x5eed,
        time_limit: Duration::from_secs(600),
        max_iterations: 20_000,
        shortcut_rounds: 0,
        ..Default::default()
    };
    plan(check, start, &Goal::Joints(goal.to_vec()), &options).is_ok()
}

fn generate(robot: &'static str, family: &str, index: u64) -> Problem {
    let tag = ROBOTS.iter().position(|r| *r == robot).unwrap() as u64 * 1000
        + FAMILIES.iter().position(|f| *f == family).unwrap() as u64 * 100
        + index;
    let mut rng = ChaCha8Rng::seed_from_u64(tag);
    for _ in 0..50 {
        let (scene, targets) = scene_and_targets(family, &mut rng);
        let check = check_of(robot, &scene.0);
        let Some(goal) = free_goal(&check, &targets, &mut rng) else { continue };
        // Start at another task pose or anywhere free, until the straight segment collides.
        for _ in 0..20 {
            let start =
                if rng.random_bool(0.5) { free_goal(&check, &targets, &mut rng) } else { free_start(&check, &mut rng) };
            let Some(start) = start.filter(|s| *s != goal) else { continue };
            let blocked = check.first_contact_between(&start, &goal, &mut check.placement()).unwrap().is_some();
            if blocked && solvable(&check, &start, &goal, tag) {
                let short = if robot == "panda" { "panda" } else { "iiwa" };
                return Problem { name: format!("{family}-{short}-{index:02}"), robot, scene: scene.0, start, goal };
            }
        }
    }
    panic!("{robot} {family} {index}: no problem in 50 scenes");
}

fn generate_all() -> Vec<Problem> {
    let mut out = Vec::new();
    for robot in ROBOTS {
        for family in FAMILIES {
            for index in 0..PER_FAMILY {
                out.push(generate(robot, family, index));
            }
        }
    }
    out
}

fn problems_csv(problems: &[Problem]) -> String {
    let mut text = String::from("name,robot,start,goal\n");
    for p in problems {
        text += &format!(
            "{},{},{},{}\n",
            p.name,
            p.robot,
            join(&p.start, 6).replace(", ", " "),
            join(&p.goal, 6).replace(", ", " ")
        );
    }
    text
}

const SCENE_HEADER: &str =
    "# Generated by crates/kinema-geometry/tests/all/plan_problems.rs (KINEMA_WRITE_PLAN_PROBLEMS=1).\n\n";

#[test]
#[ignore = "regenerates the set (a minute); sensitive to any change in IK, collision rounding or the planner"]
fn the_committed_problem_set_is_what_the_generator_makes() {
    let problems = generate_all();
    assert_eq!(problems.len(), ROBOTS.len() * FAMILIES.len() * PER_FAMILY as usize);
    let dir = set_dir();
    if std::env::var_os("KINEMA_WRITE_PLAN_PROBLEMS").is_some() {
        std::fs::create_dir_all(dir.join("scenes")).unwrap();
        for p in &problems {
            std::fs::write(dir.join("scenes").join(format!("{}.toml", p.name)), format!("{SCENE_HEADER}{}", p.scene))
                .unwrap();
        }
        std::fs::write(dir.join("problems.csv"), problems_csv(&problems)).unwrap();
    }
    let committed = std::fs::read_to_string(dir.join("problems.csv")).expect("benchmarks/plan/problems.csv");
    assert_eq!(committed, problems_csv(&problems), "regenerate with KINEMA_WRITE_PLAN_PROBLEMS=1");
    for p in &problems {
        let scene = std::fs::read_to_string(dir.join("scenes").join(format!("{}.toml", p.name))).unwrap();
        assert_eq!(scene, format!("{SCENE_HEADER}{}", p.scene), "{}", p.name);
    }
}

/// The committed problems, read back.
fn load_set() -> Vec<Problem> {
    let dir = set_dir();
    let text = std::fs::read_to_string(dir.join("problems.csv")).unwrap();
    let numbers = |s: &str| s.split(' ').map(|v| v.parse::<f64>().unwrap()).collect::<Vec<f64>>();
    text.lines()
        .skip(1)
        .map(|line| {
            let f: Vec<&str> = line.split(',').collect();
            let robot = ROBOTS.into_iter().find(|r| *r == f[1]).unwrap();
            let scene = std::fs::read_to_string(dir.join("scenes").join(format!("{}.toml", f[0]))).unwrap();
            Problem { name: f[0].to_string(), robot, scene, start: numbers(f[2]), goal: numbers(f[3]) }
        })
        .collect()
}

#[test]
fn every_committed_problem_has_free_ends_and_a_blocked_straight_segment() {
    let problems = load_set();
    assert_eq!(problems.len(), ROBOTS.len() * FAMILIES.len() * PER_FAMILY as usize);
    for p in &problems {
        let check = check_of(p.robot, &p.scene);
        for q in [&p.start, &p.goal] {
            assert!(within_limits(check.robot(), q), "{}", p.name);
            assert_eq!(check.first_collision(q).unwrap(), None, "{}", p.name);
        }
        assert!(
            check.first_contact_between(&p.start, &p.goal, &mut check.placement()).unwrap().is_some(),
            "{}",
            p.name
        );
    }
}

/// Plans every problem of the set on one thread with a 1 s budget, checks
/// every path densely (samples 1 mrad apart along each segment, exact
/// shapes), and prints the success rate and the planning times.
#[test]
#[ignore = "a benchmark: ~1 min; run by .ci/run"]
fn plan_problem_set() {
    let problems = load_set();
    let mut times = Vec::new();
    let mut failed = Vec::new();
    let (mut spheres, mut exact, mut total) = (0, 0, 0.0);
    for (k, p) in problems.iter().enumerate() {
        let check = check_of(p.robot, &p.scene);
        let options = PlanOptions { seed: k as u64, time_limit: Duration::from_secs(1), ..Default::default() };
        match plan(&check, &p.start, &Goal::Joints(p.goal.clone()), &options) {
            Ok(found) => {
                times.push((found.elapsed.as_secs_f64(), p.name.clone()));
                (spheres, exact, total) = (
                    spheres + found.counts.sphere_checks,
                    exact + found.counts.exact_checks,
                    total + found.elapsed.as_secs_f64(),
                );
                for w in found.path.windows(2) {
                    assert!(densely_clear(&check, &w[0], &w[1], 1e-3), "{}: a planned segment collides", p.name);
                }
            }
            Err(e) => failed.push(format!("{}: {e}", p.name)),
        }
    }
    times.sort_by(|a, b| a.0.total_cmp(&b.0));
    let at = |f: f64| times[((times.len() - 1) as f64 * f).round() as usize].0 * 1e3;
    println!(
        "plan problem set: {} of {} solved within 1 s; planning time median {:.2} ms, p90 {:.2} ms, max {:.2} ms ({})",
        times.len(),
        problems.len(),
        at(0.5),
        at(0.9),
        at(1.0),
        times.last().unwrap().1
    );
    println!("  solved problems: {total:.2} s in all, {spheres} sphere checks, {exact} exact interval checks");
    for family in FAMILIES {
        let mut t: Vec<f64> = times.iter().filter(|(_, n)| n.starts_with(family)).map(|(t, _)| t * 1e3).collect();
        t.sort_by(f64::total_cmp);
        if !t.is_empty() {
            println!("  {family:9}: {} solved, median {:.2} ms", t.len(), t[t.len() / 2]);
        }
    }
    for f in &failed {
        println!("  unsolved {f}");
    }
    // A guard against regressions, below the target of 99 % (benchmarks/README.md).
    assert!(times.len() * 100 >= problems.len() * 90, "{} of {} solved", times.len(), problems.len());
}
