//! `PTP … AVOID` against planners that answer by rule: a detour is timed
//! through its via point at rest and ends on the target; a straight answer
//! leaves the plan as without AVOID; no path is an error at the statement;
//! each statement gets its own, repeatable seed.

use std::sync::{Arc, Mutex};

use kinema::Robot;
use kinema_lang::{compile, Options, PathPlanner};

/// Answers with a detour through the midpoint raised by `lift` on joint 2
/// (`lift` 0: the straight segment; NaN: no path), noting each seed.
#[derive(Default)]
struct ByRule {
    lift: f64,
    seeds: Mutex<Vec<u64>>,
}

impl PathPlanner for ByRule {
    fn path(&self, from: &[f64], to: &[f64], seed: u64) -> Result<Vec<Vec<f64>>, String> {
        self.seeds.lock().unwrap().push(seed);
        if self.lift.is_nan() {
            return Err("the budget ran out".into());
        }
        if self.lift == 0.0 {
            return Ok(vec![from.to_vec(), to.to_vec()]);
        }
        let mut mid: Vec<f64> = from.iter().zip(to).map(|(a, b)| (a + b) / 2.0).collect();
        mid[1] += self.lift;
        Ok(vec![from.to_vec(), mid, to.to_vec()])
    }
}

fn with(planner: &Arc<ByRule>) -> Options {
    Options { planner: Some(planner.clone() as Arc<dyn PathPlanner>), ..Options::default() }
}

const PROGRAM: &str = "PTP JOINT(1rad, 0.5rad, 0, 0, 0, 0) AVOID\nPTP JOINT(0, 0, 0, 0, 0, 0) AVOID\n";

#[test]
fn a_detour_passes_its_via_point_at_rest_and_ends_on_the_target() {
    let robot = Robot::builtin("puma560").unwrap();
    let planner = Arc::new(ByRule { lift: 0.4, ..Default::default() });
    let plan = compile(PROGRAM, &robot, &with(&planner)).unwrap();
    let straight = compile(&PROGRAM.replace(" AVOID", ""), &robot, &Options::default()).unwrap();
    assert!(plan.duration() > straight.duration(), "the detour is longer");
    let traj = &plan.trajectory;
    let via = [0.5, 0.25 + 0.4, 0.0, 0.0, 0.0, 0.0];
    let k = (0..traj.len()).find(|&k| traj.q(k) == via).expect("the via point is a sample");
    assert!(traj.qd(k).iter().all(|v| *v == 0.0), "at rest there");
    assert_eq!(plan.final_q(), [0.0; 6]);
    assert!(plan.motions[0].target.contains("1 via point(s)"), "{}", plan.motions[0].target);
    let seeds = planner.seeds.lock().unwrap().clone();
    assert_ne!(seeds[0], seeds[1], "each statement its own seed");
    let again = Arc::new(ByRule { lift: 0.4, ..Default::default() });
    compile(PROGRAM, &robot, &with(&again)).unwrap();
    assert_eq!(*again.seeds.lock().unwrap(), seeds, "the same program, the same seeds");
}

#[test]
fn a_straight_answer_keeps_the_plan_of_a_plain_ptp() {
    let robot = Robot::builtin("puma560").unwrap();
    let planner = Arc::new(ByRule::default());
    let plan = compile(PROGRAM, &robot, &with(&planner)).unwrap();
    let plain = compile(&PROGRAM.replace(" AVOID", ""), &robot, &Options::default()).unwrap();
    assert_eq!(plan, plain);
}

#[test]
fn no_path_is_an_error_at_the_statement_with_the_reason() {
    let robot = Robot::builtin("puma560").unwrap();
    let planner = Arc::new(ByRule { lift: f64::NAN, ..Default::default() });
    let src = "WAIT 1\nPTP JOINT(1rad, 0.5rad, 0, 0, 0, 0) AVOID\n";
    let diags = compile(src, &robot, &with(&planner)).unwrap_err();
    let e = diags.iter().find(|d| d.is_error()).unwrap();
    assert_eq!(&src[e.span.clone()], "PTP JOINT(1rad, 0.5rad, 0, 0, 0, 0) AVOID");
    assert!(e.message.contains("no collision-free path") && e.message.contains("budget ran out"), "{}", e.message);
}

#[test]
fn avoid_is_refused_with_in_and_twice() {
    let robot = Robot::builtin("puma560").unwrap();
    let planner = Arc::new(ByRule::default());
    for (src, message) in [
        ("PTP JOINT(1rad, 0, 0, 0, 0, 0) AVOID IN 2s\n", "AVOID cannot be combined with IN"),
        ("PTP JOINT(1rad, 0, 0, 0, 0, 0) AVOID AVOID\n", "AVOID given twice"),
    ] {
        let diags = compile(src, &robot, &with(&planner)).unwrap_err();
        assert!(diags.iter().any(|d| d.message.contains(message)), "{src}: {diags:?}");
    }
}
