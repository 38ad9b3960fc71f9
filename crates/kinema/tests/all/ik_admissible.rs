//! IK with an admissibility test (what a scene's collision check is to the
//! core), on seeded targets: a rejected configuration is never returned, a
//! non-redundant arm's answer is the plain answer less the rejected
//! solutions, and a redundant arm searches its self-motion for an admitted
//! one before refusing.

use kinema::ik::{solve_target, Admissible, Assessment, IkRequest, IkTarget, Rejection, Unreachable};
use kinema::math::rot_to_axis_angle;
use kinema::{Error, Robot};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Admits configurations whose joint `joint` is at least `min`; the
/// clearance is how far above it is.
struct AtLeast {
    joint: usize,
    min: f64,
}

impl AtLeast {
    fn rejection(&self) -> Rejection {
        Rejection { kind: "collision", detail: format!("q{} below {}", self.joint + 1, self.min) }
    }
}

impl Admissible for AtLeast {
    fn rejects(&self, q: &[f64]) -> kinema::Result<Option<Rejection>> {
        Ok((q[self.joint] < self.min).then(|| self.rejection()))
    }

    fn assess(&self, q: &[f64]) -> kinema::Result<Assessment> {
        Ok(match self.rejects(q)? {
            Some(rejection) => Assessment::Rejected(rejection),
            None => Assessment::Clear(q[self.joint] - self.min),
        })
    }

    fn first_rejection_between(&self, from: &[f64], to: &[f64]) -> kinema::Result<Option<(f64, Rejection)>> {
        // The joint moves linearly: below `min` from the start, or from where it crosses it.
        let (a, b) = (from[self.joint], to[self.joint]);
        let s = if a < self.min {
            0.0
        } else if b < self.min {
            (a - self.min) / (a - b)
        } else {
            return Ok(None);
        };
        Ok(Some((s, self.rejection())))
    }
}

/// A configuration within the limits, drawn uniformly.
fn within_limits(robot: &Robot, rng: &mut ChaCha8Rng) -> Vec<f64> {
    robot.joints().iter().map(|j| rng.random_range(j.limits.min.max(-3.0)..j.limits.max.min(3.0))).collect()
}

/// Whether FK of `q` meets `target` within 1e-6 (measured here).
fn meets(robot: &Robot, q: &[f64], target: &kinema::Pose) -> bool {
    let reached = robot.fk(q).unwrap().world_from_tool;
    let dp = (reached.pos - target.pos).norm();
    let dw = rot_to_axis_angle(&(target.rot * reached.rot.transpose())).norm();
    dp < 1e-6 && dw < 1e-6
}

#[test]
fn a_redundant_arm_searches_its_self_motion_for_an_admitted_solution() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    // q3 = 0 (the default) is never admitted: every answer comes from the search.
    let test = AtLeast { joint: 2, min: 0.5 };
    let mut rng = ChaCha8Rng::seed_from_u64(37);
    let (mut solved, mut cases) = (0, 0);
    while cases < 300 {
        let mut q = within_limits(&robot, &mut rng);
        q[2] = rng.random_range(0.8..2.5);
        if robot.fk(&q).unwrap().out_of_limits.indices().next().is_some() {
            continue;
        }
        cases += 1;
        let target = robot.fk(&q).unwrap().world_from_tool;
        let request = IkRequest { admissible: Some(&test), ..Default::default() };
        match solve_target(&robot, &IkTarget::Pose(target), &request) {
            Ok(answer) => {
                solved += 1;
                assert!(!answer.discarded.is_empty() || q[2] >= 0.5);
                for s in &answer.solutions {
                    assert!(s.q[2] >= 0.5, "case {cases}: q3 = {} returned", s.q[2]);
                    assert!(meets(&robot, &s.q, &target), "case {cases}: {:?} misses the target", s.q);
                    assert!(s.within_limits());
                }
                assert!(answer.discarded.iter().all(|d| d.rejection.as_ref().is_none_or(|r| r.kind == "collision")));
            }
            Err(e) => panic!("case {cases}: q = {q:?} reaches the target admitted, but: {e}"),
        }
    }
    assert_eq!(solved, 300);
}

#[test]
fn a_non_redundant_arm_returns_the_plain_answer_less_the_rejected() {
    let robot = Robot::builtin("puma560").unwrap();
    let test = AtLeast { joint: 0, min: 0.0 };
    let mut rng = ChaCha8Rng::seed_from_u64(38);
    let (mut kept, mut refused) = (0, 0);
    for case in 0..500 {
        let q = within_limits(&robot, &mut rng);
        let target = IkTarget::Pose(robot.fk(&q).unwrap().world_from_tool);
        let all = IkRequest { all: true, ..Default::default() };
        let plain = solve_target(&robot, &target, &all).unwrap();
        let admitted: Vec<&Vec<f64>> = plain.solutions.iter().map(|s| &s.q).filter(|q| q[0] >= 0.0).collect();
        let checked = solve_target(&robot, &target, &IkRequest { admissible: Some(&test), ..all });
        match checked {
            Ok(answer) => {
                kept += 1;
                let got: Vec<&Vec<f64>> = answer.solutions.iter().map(|s| &s.q).collect();
                assert_eq!(got, admitted, "case {case}");
                let rejected = answer.discarded.iter().filter(|d| d.rejection.is_some()).count();
                assert_eq!(rejected, plain.solutions.len() - admitted.len(), "case {case}");
            }
            Err(Error::Unreachable { reason: Unreachable::Rejected { candidates, searched, .. }, .. }) => {
                refused += 1;
                assert!(admitted.is_empty(), "case {case}: refused, but {admitted:?} are admitted");
                assert_eq!(candidates, plain.solutions.len());
                assert_eq!(searched, None);
            }
            Err(e) => panic!("case {case}: {e}"),
        }
    }
    // Half the shoulder's range is rejected: most targets keep a solution, some do not.
    assert!(kept > 300 && refused > 0, "kept {kept}, refused {refused}");
}

#[test]
fn a_fixed_q3_is_not_searched() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let test = AtLeast { joint: 2, min: 0.5 };
    let q = [0.3, 0.6, 1.0, -1.2, 0.4, 0.8, 0.1];
    let target = IkTarget::Pose(robot.fk(&q).unwrap().world_from_tool);
    let fixed = IkRequest { q3: Some(0.0), admissible: Some(&test), ..Default::default() };
    let e = solve_target(&robot, &target, &fixed).unwrap_err();
    let Error::Unreachable { reason: Unreachable::Rejected { searched: None, candidates, .. }, .. } = &e else {
        panic!("{e}")
    };
    assert!(*candidates > 0);
    assert!(e.to_string().contains("collision: q3 below 0.5"), "{e}");
    // Left free, the search finds q3 ≥ 0.5.
    let free = IkRequest { admissible: Some(&test), ..Default::default() };
    let answer = solve_target(&robot, &target, &free).unwrap();
    assert!(answer.solutions.iter().all(|s| s.q[2] >= 0.5));
}

/// `traj::check` with an admissibility test: one violation per refused
/// stretch, where it begins — between samples at the exact crossing time —
/// and `collision_free` refuses the same motion.
#[test]
fn a_checked_motion_reports_where_each_refused_stretch_begins() {
    use kinema::traj::{check, collision_free, CheckOptions, JointTrajectory, ViolationKind};
    let robot = Robot::builtin("ur5").unwrap();
    let test = AtLeast { joint: 0, min: 0.0 };
    // q1 over time: 1, 0.5, −0.5 (crossing at t = 1.5), −1, 0.5 (out), −0.2 (back in at t = 4 + 5/7).
    let q1 = [1.0, 0.5, -0.5, -1.0, 0.5, -0.2];
    let t: Vec<f64> = (0..q1.len()).map(|k| k as f64).collect();
    let q: Vec<f64> = q1.iter().flat_map(|&x| [x, -1.0, 1.0, 0.0, 0.0, 0.0]).collect();
    let traj = JointTrajectory::from_positions(6, t, q).unwrap();
    let opts = CheckOptions { admissible: Some(&test), ..CheckOptions::default() };
    let report = check(&robot, &traj, &opts).unwrap();
    let hits: Vec<_> = report.violations.iter().filter(|v| v.kind == ViolationKind::Collision).collect();
    assert_eq!(hits.len(), 2, "{hits:?}");
    assert_eq!(hits[0].sample, 2);
    assert!((hits[0].time - 1.5).abs() < 1e-12, "{}", hits[0].time);
    assert_eq!(hits[1].sample, 5);
    assert!((hits[1].time - (4.0 + 5.0 / 7.0)).abs() < 1e-12, "{}", hits[1].time);
    assert_eq!(hits[0].detail.as_deref(), Some("q1 below 0"));
    assert!(hits[0].to_string().contains("collision: q1 below 0 (between samples 1 and 2)"), "{}", hits[0]);
    let refused = collision_free(&traj, &test).unwrap_err();
    assert!(matches!(refused, Error::Trajectory { count: 2, .. }), "{refused}");
    // A step that begins refused right at its first sample (q1 exactly at the
    // bound, then below) is reported at that sample and its time.
    let edge =
        JointTrajectory::from_positions(6, vec![0.0, 1.0, 2.0], [[0.5; 6], [0.0; 6], [-0.5; 6]].concat()).unwrap();
    let report = check(&robot, &edge, &opts).unwrap();
    let hit = report.violations.iter().find(|v| v.kind == ViolationKind::Collision).unwrap();
    assert_eq!((hit.sample, hit.time), (1, 1.0), "{hit:?}");
    // A motion that starts refused is reported at its first sample.
    let start = JointTrajectory::from_positions(6, vec![0.0, 1.0], [[-0.1; 6], [0.3; 6]].concat()).unwrap();
    let first = collision_free(&start, &test).unwrap_err().to_string();
    assert!(first.contains("sample 0"), "{first}");
}
