//! Seed 004 §VIII-E: two LBR iiwa 14 R820 working together. Robot 1 holds a
//! part and turns it about the tool axis; robot 2, facing it 1.2 m away,
//! draws a circle of 5 cm radius 12 cm in front of the part. Both run on one
//! clock; the example prints the closest approach of the two tools and the
//! range of each robot's translational manipulability (seed 004 Fig. 30, 33).
//!
//! ```text
//! cargo run -p kinema --example 04_two_robot_cell
//! ```

use std::f64::consts::{FRAC_PI_2, PI};

use kinema::ik::iiwa::IiwaIk;
use kinema::math::{rot_y, rot_z};
use kinema::nalgebra::Vector3;
use kinema::traj::{
    check, to_joints, Blend, CartesianLimits, CartesianMotion, Cell, CheckOptions, JointMethod, Orientation, Profile,
    Segment, SelfMotion,
};
use kinema::{Pose, Robot};

/// A configuration for `pose` well inside the joint limits: over q3 = 0, ±0.4,
/// ±0.8, … (the iiwa's redundancy) and every branch, the one whose joints use
/// the smallest fraction of their ranges.
fn start_config(robot: &Robot, pose: &Pose) -> kinema::Result<Vec<f64>> {
    let ik = IiwaIk::new(robot)?;
    let usage = |q: &[f64]| {
        q.iter()
            .zip(robot.joints())
            .map(|(v, j)| v.abs() / j.limits.max.abs().min(j.limits.min.abs()))
            .fold(0.0, f64::max)
    };
    let mut best: Option<Vec<f64>> = None;
    for k in -8..=8 {
        let Ok(sols) = ik.solve_q3(pose, 0.4 * k as f64) else { continue };
        for s in sols.into_iter().filter(|s| s.within_limits()) {
            if best.as_ref().is_none_or(|b| usage(&s.q) < usage(b)) {
                best = Some(s.q);
            }
        }
    }
    best.ok_or_else(|| kinema::Error::Infeasible {
        what: "pose".into(),
        reason: "no q3 in ±3.2 rad gives a solution within the joint limits".into(),
    })
}

fn main() -> kinema::Result<()> {
    let iiwa = Robot::builtin("lbr-iiwa-14-r820")?;
    let r1 = iiwa.with_base(Pose::IDENTITY)?;
    let r2 = iiwa.with_base(Pose::new(rot_z(PI), Vector3::new(1.2, 0.0, 0.0)))?;
    let limits = CartesianLimits::new(0.2, 0.5);

    // Robot 1: the part at (0.55, 0, 0.6), tool pointing along +x (towards robot 2),
    // turned by 90° about its own axis.
    let hold = Pose::new(rot_y(FRAC_PI_2), Vector3::new(0.55, 0.0, 0.6));
    let turned = Pose::new(hold.rot * rot_z(FRAC_PI_2), hold.pos);
    let q1 = start_config(&r1, &hold)?;
    let m1 = CartesianMotion::new(
        vec![Segment::lin(&hold, &turned, Orientation::Slerp)?],
        Profile::SCurve,
        &CartesianLimits { jerk: Some(2.0), rot_jerk: Some(4.0), ..limits },
        Blend::None,
    )?;
    // q3 tracked (least joint motion): held, the turn ends in a wrist flip; seed 004's
    // rule avoids it but turns the joints faster than their acceleration limits allow.
    let t1 = to_joints(&r1, &m1, &q1, 0.01, JointMethod::Ik(SelfMotion::Track))?;

    // Robot 2: a full circle about the part's axis, 12 cm in front of it, its
    // tool pointing back at the part (along −x).
    let centre = Pose::new(rot_y(FRAC_PI_2), Vector3::new(0.67, 0.0, 0.6));
    let start = centre.transform_point(&Vector3::new(0.05, 0.0, 0.0));
    let facing = rot_y(-FRAC_PI_2);
    let circle = Segment::circ_about(&centre, &start, 2.0 * PI, &facing)?;
    let q2 = start_config(&r2, &circle.start())?;
    let m2 = CartesianMotion::new(vec![circle], Profile::Trapezoid, &limits, Blend::None)?;
    let t2 = to_joints(&r2, &m2, &q2, 0.01, JointMethod::default())?;

    for (name, robot, traj) in [("robot 1", &r1, &t1), ("robot 2", &r2, &t2)] {
        let report = check(robot, traj, &CheckOptions::default())?;
        println!(
            "{name}: {:.2} s, {} samples, {} violation(s)",
            traj.times().last().unwrap(),
            traj.len(),
            report.violations.len()
        );
    }
    let mut cell = Cell::new();
    cell.add("robot 1", r1, t1)?.add("robot 2", r2, t2)?;
    let report = cell.run(0.01)?;
    let (t, d) = report.closest(0, 1).expect("two robots");
    println!("closest approach of the tools: {d:.4} m at t = {t:.2} s");
    for (m, values) in report.manipulability.iter().enumerate() {
        let (lo, hi) = values.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), v| (lo.min(*v), hi.max(*v)));
        println!("robot {}: translational manipulability {lo:.4} … {hi:.4}", m + 1);
    }
    Ok(())
}
