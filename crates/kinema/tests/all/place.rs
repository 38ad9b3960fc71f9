//! Base placement checked against a brute-force oracle that never moves the
//! robot: each task pose is carried into the frame of the robot's own base
//! as if the base stood at the candidate, and handed to IK.

use kinema::ik::{solve_target, IkRequest, IkTarget};
use kinema::math::Pose;
use kinema::reach::place::{base_candidates, place_scores, ranking, Region};
use kinema::Robot;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// How many of `task` the unmoved robot reaches once each pose is seen from
/// `base` instead of its own base.
fn oracle_score(robot: &Robot, base: &Pose, task: &[Pose]) -> u32 {
    let own = robot.base();
    let one = IkRequest { skip_closest: true, ..Default::default() };
    let reached = task.iter().filter(|t| {
        let seen = own.mul(&base.inverse()).mul(t);
        solve_target(robot, &IkTarget::Pose(seen), &one).is_ok_and(|a| a.solutions.iter().any(|s| s.within_limits()))
    });
    reached.count() as u32
}

/// A task the robot standing at `base` reaches in full (FK of random
/// configurations), plus a few poses far out of anyone's reach.
fn task_from(robot: &Robot, base: &Pose, rng: &mut ChaCha8Rng, poses: usize) -> Vec<Pose> {
    let moved = robot.with_base(*base).unwrap();
    let mut task: Vec<Pose> = (0..poses).map(|_| moved.fk(&robot.random_q(rng)).unwrap().world_from_tool).collect();
    task.push(Pose::translation(base.pos.x, base.pos.y, base.pos.z + 50.0));
    task
}

fn check_ranking(name: &str, tasks: usize) {
    let robot = Robot::builtin(name).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0x4004);
    let region = Region { x: (-0.5, 0.5), y: (-0.5, 0.5), z: None };
    let bases = base_candidates(&robot, &region, 0.5, 2).unwrap();
    assert_eq!(bases.len(), 18);
    for _ in 0..tasks {
        let best = rng.random_range(0..bases.len());
        let task = task_from(&robot, &bases[best], &mut rng, 5);
        let scores = place_scores(&robot, &bases, &task, &IkRequest::default(), &|| {}, &|| false).unwrap();
        let expected: Vec<u32> = bases.iter().map(|b| oracle_score(&robot, b, &task)).collect();
        assert_eq!(scores, expected, "{name}");
        // The base the task was drawn from reaches every reachable pose: the top score.
        assert_eq!(scores[best], task.len() as u32 - 1, "{name}");
        let order = ranking(&scores);
        assert_eq!(scores[order[0]], task.len() as u32 - 1, "{name}");
        for w in order.windows(2) {
            assert!(scores[w[0]] > scores[w[1]] || (scores[w[0]] == scores[w[1]] && w[0] < w[1]), "{name}");
        }
        assert!(scores.iter().any(|&s| s < scores[best]), "{name}: every base scores the same");
    }
}

#[test]
fn puma_placement_matches_the_oracle() {
    check_ranking("puma560", 3);
}

#[test]
fn iiwa_placement_matches_the_oracle() {
    check_ranking("lbr-iiwa-14-r820", 2);
}

#[test]
fn the_default_region_surrounds_the_task() {
    let robot = Robot::builtin("puma560").unwrap();
    let task = [Pose::translation(1.0, 2.0, 0.3), Pose::translation(3.0, 2.0, 0.3)];
    let region = Region::around_task(&robot, &task).unwrap();
    let r = kinema::reach::reach_bound(&robot).unwrap();
    assert_eq!(region.x, (2.0 - r, 2.0 + r));
    assert_eq!(region.y, (2.0 - r, 2.0 + r));
    assert!(Region::around_task(&robot, &[]).is_err());
    assert!(base_candidates(&robot, &region, 0.0, 1).is_err());
    assert!(base_candidates(&robot, &region, 0.1, 0).is_err());
}

#[test]
fn a_cancelled_placement_stops() {
    let robot = Robot::builtin("puma560").unwrap();
    let bases = base_candidates(&robot, &Region { x: (0.0, 1.0), y: (0.0, 1.0), z: None }, 0.5, 1).unwrap();
    let task = [Pose::translation(0.3, 0.0, 0.5)];
    let e = place_scores(&robot, &bases, &task, &IkRequest::default(), &|| {}, &|| true);
    assert!(matches!(e, Err(kinema::Error::Cancelled)));
}
