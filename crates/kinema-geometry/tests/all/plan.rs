//! The planner: its segment test against dense exact checks, its paths
//! certified by the continuous check and `traj::check`, determinism per
//! seed, pose goals through IK, and errors that name what is wrong.

use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use kinema::traj::{CheckOptions as TrajCheck, PtpOptions};
use kinema_geometry::plan::{plan, Goal, MotionCheck, PlanOptions};
use kinema_geometry::{load_robot_geometry, CollisionCheck, CollisionPairs, Error, Scene};

use crate::common::densely_clear;

/// An iiwa on a bench with a post in front of it and a shelf board to its
/// left: straight joint motions across the front often hit the post.
const POST_SCENE: &str = r#"
[[obstacle]]
name = "bench"
box = [1.6, 1.6, 0.05]
pose = [0, 0, -0.03, 0, 0, 0]

[[obstacle]]
name = "post"
cylinder = { radius = 0.06, length = 1.2 }
pose = [0.55, 0, 0.6, 0, 0, 0]

[[obstacle]]
name = "board"
box = [0.5, 0.3, 0.02]
pose = [0, 0.6, 0.55, 0, 0, 0]
"#;

fn post_check() -> CollisionCheck {
    let scene = Scene::from_toml(POST_SCENE, "post.toml", Path::new(".")).unwrap();
    let (robot, geometry) = load_robot_geometry("lbr-iiwa-14-r820", &Default::default()).unwrap();
    let pairs = CollisionPairs::self_collision(&geometry);
    CollisionCheck::with_scene(robot, geometry, pairs, Some(&scene), 0.0).unwrap()
}

fn random_q(check: &CollisionCheck, rng: &mut ChaCha8Rng) -> Vec<f64> {
    check.robot().joints().iter().map(|j| rng.random_range(j.limits.min..j.limits.max)).collect()
}

fn free_q(check: &CollisionCheck, rng: &mut ChaCha8Rng) -> Vec<f64> {
    loop {
        let q = random_q(check, rng);
        if check.first_collision(&q).unwrap().is_none() {
            return q;
        }
    }
}

#[test]
fn the_segment_test_agrees_with_dense_exact_checks() {
    let check = post_check();
    let mut motion = MotionCheck::new(&check).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (mut free, mut blocked) = (0, 0);
    for _ in 0..300 {
        let q = random_q(&check, &mut rng);
        assert_eq!(motion.config_free(&q).unwrap(), check.first_collision(&q).unwrap().is_none(), "{q:?}");
    }
    for _ in 0..150 {
        let a = free_q(&check, &mut rng);
        // Short and long segments.
        let reach = if rng.random_bool(0.5) { 0.3 } else { 3.0 };
        let b: Vec<f64> = a
            .iter()
            .zip(check.robot().joints())
            .map(|(x, j)| (x + rng.random_range(-reach..reach)).clamp(j.limits.min, j.limits.max))
            .collect();
        let says_free = motion.segment_free(&a, &b).unwrap();
        let contact = check.first_contact_between(&a, &b, &mut check.placement()).unwrap();
        if says_free {
            free += 1;
            assert!(contact.is_none(), "free by the fast test, the continuous check finds {contact:?}");
            assert!(densely_clear(&check, &a, &b, 0.002), "free by the fast test, a dense sample collides");
        } else {
            blocked += 1;
            assert!(contact.is_some(), "blocked by the fast test, clear by the continuous check");
        }
    }
    assert!(free > 20 && blocked > 20, "free {free}, blocked {blocked}: the cases must cover both");
    let counts = motion.counts();
    assert!(counts.sphere_checks > 2 * counts.exact_checks, "the spheres decide most checks: {counts:?}");
}

/// Free start and goal whose straight segment collides.
fn blocked_problems(check: &CollisionCheck, count: usize, seed: u64) -> Vec<(Vec<f64>, Vec<f64>)> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Vec::new();
    while out.len() < count {
        let (a, b) = (free_q(check, &mut rng), free_q(check, &mut rng));
        if check.first_contact_between(&a, &b, &mut check.placement()).unwrap().is_some() {
            out.push((a, b));
        }
    }
    out
}

#[test]
fn planned_paths_are_collision_free_timed_within_limits_and_repeatable() {
    let check = post_check();
    let robot = check.robot();
    let options = PlanOptions { time_limit: Duration::from_secs(10), ..Default::default() };
    for (n, (from, to)) in blocked_problems(&check, 12, 5).into_iter().enumerate() {
        let found = plan(&check, &from, &Goal::Joints(to.clone()), &PlanOptions { seed: n as u64, ..options.clone() })
            .unwrap_or_else(|e| panic!("problem {n}: {e}"));
        assert_eq!(found.path[0], from);
        assert_eq!(found.path.last().unwrap(), &to);
        assert!(found.path.len() >= 3, "the straight segment collides, so the path turns");
        assert!(found.iterations > 0 && found.nodes > 2);
        for w in found.path.windows(2) {
            assert!(check.first_contact_between(&w[0], &w[1], &mut check.placement()).unwrap().is_none());
            assert!(densely_clear(&check, &w[0], &w[1], 0.005), "problem {n}");
        }
        let traj = found.trajectory(robot, &PtpOptions::for_robot(robot), 0.01).unwrap();
        let report = check_with_scene(&check, &traj);
        assert!(report.violations.is_empty(), "problem {n}: {:?}", report.violations);
        assert_eq!(traj.q(traj.len() - 1), to.as_slice());
        let again =
            plan(&check, &from, &Goal::Joints(to.clone()), &PlanOptions { seed: n as u64, ..options.clone() }).unwrap();
        assert_eq!(again.path, found.path, "problem {n}: the same seed gives the same path");
    }
}

fn check_with_scene(scene: &CollisionCheck, traj: &kinema::traj::JointTrajectory) -> kinema::traj::CheckReport {
    let opts = TrajCheck { admissible: Some(scene), ..Default::default() };
    kinema::traj::check(scene.robot(), traj, &opts).unwrap()
}

#[test]
fn a_free_straight_segment_is_the_plan() {
    let check = post_check();
    let from = [0.0, 0.3, 0.0, -1.2, 0.0, 0.8, 0.0];
    let to = [0.1, 0.35, 0.0, -1.1, 0.1, 0.7, 0.2];
    let found = plan(&check, &from, &Goal::Joints(to.to_vec()), &PlanOptions::default()).unwrap();
    assert_eq!(found.path, [from.to_vec(), to.to_vec()]);
    assert_eq!(found.iterations, 0);
}

#[test]
fn a_pose_goal_ends_at_a_free_configuration_reaching_the_pose() {
    let check = post_check();
    let robot = check.robot();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for (n, (from, to)) in blocked_problems(&check, 4, 9).into_iter().enumerate() {
        let pose = robot.fk(&to).unwrap().world_from_tool;
        let options = PlanOptions { seed: rng.random(), time_limit: Duration::from_secs(10), ..Default::default() };
        let found = plan(&check, &from, &Goal::Pose(pose), &options).unwrap_or_else(|e| panic!("problem {n}: {e}"));
        assert!(found.goals >= 8, "branches and self-motion samples: {}", found.goals);
        let end = robot.fk(found.path.last().unwrap()).unwrap().world_from_tool;
        assert!((end.pos - pose.pos).norm() < 1e-6, "problem {n}");
        assert!((end.rot - pose.rot).norm() < 1e-6, "problem {n}");
        robot.check_within_limits(found.path.last().unwrap(), "goal").unwrap();
        for w in found.path.windows(2) {
            assert!(check.first_contact_between(&w[0], &w[1], &mut check.placement()).unwrap().is_none());
        }
    }
}

#[test]
fn errors_name_the_colliding_pair_the_joint_and_the_budget() {
    let check = post_check();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let free = free_q(&check, &mut rng);
    // Folded onto itself.
    let into_bench = [0.0, 1.9, 0.0, 0.5, 0.0, 0.0, 0.0];
    let e = plan(&check, &into_bench, &Goal::Joints(free.clone()), &PlanOptions::default()).unwrap_err();
    assert!(matches!(e, Error::Blocked { which: "start", .. }), "{e}");
    assert!(e.to_string().contains("`link 1` – `link 3`"), "{e}");
    let e = plan(&check, &free, &Goal::Joints(into_bench.to_vec()), &PlanOptions::default()).unwrap_err();
    assert!(e.to_string().starts_with("the goal configuration collides"), "{e}");
    let mut beyond = free.clone();
    beyond[1] = 3.0;
    let e = plan(&check, &beyond, &Goal::Joints(free.clone()), &PlanOptions::default()).unwrap_err();
    assert!(e.to_string().contains("joint 2") && e.to_string().contains("limits"), "{e}");
    let (from, to) = blocked_problems(&check, 1, 2).remove(0);
    let starved = PlanOptions { max_iterations: 1, ..Default::default() };
    let e = plan(&check, &from, &Goal::Joints(to.clone()), &starved).unwrap_err();
    assert!(matches!(e, Error::NoPath { iterations: 1, .. }), "{e}");
    assert!(e.to_string().contains("before the limit of 1 iteration(s) ran out"), "{e}");
    let stop = AtomicBool::new(true);
    let e =
        plan(&check, &from, &Goal::Joints(to), &PlanOptions { cancel: Some(&stop), ..Default::default() }).unwrap_err();
    assert!(matches!(e, Error::Interrupted), "{e}");
}

#[test]
fn a_start_within_the_contact_tolerance_is_refused_by_name() {
    let check = post_check();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let (clear, hit) = loop {
        let (a, b) = (free_q(&check, &mut rng), random_q(&check, &mut rng));
        if check.first_collision(&b).unwrap().is_some() {
            break (a, b);
        }
    };
    // Bisect to the last clear configuration before the first contact.
    let (mut lo, mut hi) = (0.0, 1.0);
    let at = |s: f64| clear.iter().zip(&hit).map(|(a, b)| a + s * (b - a)).collect::<Vec<f64>>();
    for _ in 0..60 {
        let mid = (lo + hi) / 2.0;
        if check.first_collision(&at(mid)).unwrap().is_none() {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let touching = at(lo);
    assert!(check.first_collision(&touching).unwrap().is_none());
    let e = plan(&check, &touching, &Goal::Joints(clear), &PlanOptions::default()).unwrap_err();
    assert!(matches!(e, Error::Blocked { which: "start", .. }), "{e}");
}

#[test]
fn misused_motion_checks_and_steps_are_errors() {
    let check = post_check();
    let mut motion = MotionCheck::new(&check).unwrap();
    let q = [0.0; 7];
    let short = [0.0; 6];
    let mut nan = q;
    nan[3] = f64::NAN;
    let mut far = q;
    far[0] = 1e8;
    assert!(motion.config_free(&short).is_err());
    assert!(motion.config_free(&nan).is_err());
    assert!(motion.segment_free(&q, &short).is_err());
    assert!(motion.segment_free(&nan, &q).is_err());
    let e = motion.segment_free(&q, &far).unwrap_err();
    assert!(e.to_string().contains("sweep"), "{e}");
    let from = [0.0, 0.3, 0.0, -1.2, 0.0, 0.8, 0.0];
    let to = Goal::Joints(vec![0.1, 0.35, 0.0, -1.1, 0.1, 0.7, 0.2]);
    for step in [0.0, -1.0, 1e-9, f64::NAN, f64::INFINITY] {
        let e = plan(&check, &from, &to, &PlanOptions { step: Some(step), ..Default::default() }).unwrap_err();
        assert!(e.to_string().contains("step"), "{step}: {e}");
    }
}

#[test]
fn a_segment_check_past_its_deadline_answers_blocked() {
    let check = post_check();
    let mut motion = MotionCheck::new(&check).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    // A long free segment: many intervals, so the first pass looks at the clock.
    let (from, to) = (0..500)
        .map(|_| (free_q(&check, &mut rng), free_q(&check, &mut rng)))
        .find(|(a, b)| {
            let long = a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum::<f64>() > 4.0;
            long && motion.segment_free(a, b).unwrap()
        })
        .expect("a long free segment among 500");
    motion.set_deadline(Some(std::time::Instant::now()));
    assert!(!motion.segment_free(&from, &to).unwrap());
    motion.set_deadline(None);
    assert!(motion.segment_free(&from, &to).unwrap());
}
