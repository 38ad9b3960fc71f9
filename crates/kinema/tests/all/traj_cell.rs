//! The multi-robot cell (seed 004 §VIII-E).

use kinema::math::rot_z;
use kinema::nalgebra::Vector3;
use kinema::traj::{Cell, JointTrajectory, Profile, Ptp, PtpOptions};
use kinema::{Pose, Robot};

fn iiwa() -> Robot {
    Robot::builtin("lbr-iiwa-14-r820").unwrap()
}

fn ptp(robot: &Robot, to: &[f64]) -> JointTrajectory {
    let opts = PtpOptions { profile: Profile::Quintic, acc: Some(vec![2.0]), ..PtpOptions::default() };
    Ptp::new(robot, robot.home(), to, &opts).unwrap().sample(robot, 0.01).unwrap()
}

#[test]
fn common_clock_poses_distances_and_manipulability() {
    let r1 = iiwa();
    let base2 = Pose::new(rot_z(std::f64::consts::PI), Vector3::new(1.2, 0.0, 0.0));
    let r2 = iiwa().with_base(base2).unwrap();
    let t1 = ptp(&r1, &[0.3, 0.8, 0.0, -1.0, 0.2, 0.6, 0.0]);
    let t2 = ptp(&r2, &[-0.2, 0.4, 0.1, -0.5, 0.0, 0.3, 0.5]);
    let (d1, d2) = (*t1.times().last().unwrap(), *t2.times().last().unwrap());
    assert!(d1 != d2);
    let mut cell = Cell::new();
    cell.add("a", r1.clone(), t1.clone()).unwrap().add("b", r2.clone(), t2.clone()).unwrap();
    let report = cell.run(0.005).unwrap();
    assert!((report.times.last().unwrap() - d1.max(d2)).abs() < 1e-12);
    let base_free = iiwa();
    for (k, &t) in report.times.iter().enumerate() {
        // Independent: FK of each robot's interpolated q, robot 2 through its base by hand.
        let p1 = r1.fk(&report.q[0][k]).unwrap().world_from_tool.pos;
        let p2 = base2.transform_point(&base_free.fk(&report.q[1][k]).unwrap().world_from_tool.pos);
        assert!((report.tools[0][k].pos - p1).norm() < 1e-12 && (report.tools[1][k].pos - p2).norm() < 1e-12);
        assert!((report.distances[0].1[k] - (p1 - p2).norm()).abs() < 1e-12);
        for (m, robot) in [&r1, &r2].into_iter().enumerate() {
            let j = robot.jacobian(&report.q[m][k], kinema::Frame::Base).unwrap();
            let want = kinema::analysis::yoshikawa(&j, kinema::analysis::Axes::Translation).unwrap();
            assert!((report.manipulability[m][k] - want).abs() < 1e-12);
        }
        // Each robot holds its last configuration after its own end.
        for (m, (traj, end)) in [(&t1, d1), (&t2, d2)].into_iter().enumerate() {
            if t >= end {
                assert_eq!(report.q[m][k], traj.q(traj.len() - 1));
            }
        }
    }
    // On a member's own sample times (every 0.01 s) the values are its samples.
    for k in (0..report.times.len()).step_by(2) {
        let t = report.times[k];
        if t < d1 - 1e-9 {
            let j = (t / 0.01).round() as usize;
            let diff: f64 = report.q[0][k].iter().zip(t1.q(j)).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            assert!(diff < 1e-12, "t = {t}: {diff}");
        }
    }
    let (t_min, d_min) = report.closest(0, 1).unwrap();
    assert!(report.distances[0].1.iter().all(|d| *d >= d_min) && report.times.contains(&t_min));
}

#[test]
fn cell_errors() {
    let mut cell = Cell::new();
    assert!(cell.run(0.01).is_err());
    let scara = Robot::builtin("scara5").unwrap();
    let e = cell.add("x", scara, JointTrajectory::new(7)).unwrap_err().to_string();
    assert!(e.contains("5 joints") && e.contains('7'), "{e}");
    let e = cell.add("y", iiwa(), JointTrajectory::new(7)).unwrap_err().to_string();
    assert!(e.contains("`y` has 0 trajectory samples"), "{e}");
    cell.add("z", iiwa(), ptp(&iiwa(), &[0.1; 7])).unwrap();
    assert!(cell.run(0.0).is_err());
    assert!(cell.run(0.01).unwrap().distances.is_empty());
}

#[test]
fn approaches_spans_below_a_distance_and_placement() {
    let r1 = iiwa();
    let r2 = kinema::traj::cell::placed(&iiwa(), &Pose::new(rot_z(std::f64::consts::PI), Vector3::new(1.2, 0.0, 0.0)))
        .unwrap();
    let t1 = ptp(&r1, &[0.3, 0.8, 0.0, -1.0, 0.2, 0.6, 0.0]);
    let t2 = ptp(&r2, &[-0.2, 0.4, 0.1, -0.5, 0.0, 0.3, 0.5]);
    let mut cell = Cell::new();
    cell.add("a", r1, t1.clone()).unwrap().add("b", r2, t2.clone()).unwrap();
    let report = cell.run(0.01).unwrap();
    assert_eq!(report.ends, vec![*t1.times().last().unwrap(), *t2.times().last().unwrap()]);
    let [a] = report.approaches()[..] else { panic!("one pair") };
    assert_eq!(a.pair, (0, 1));
    assert_eq!(Some((a.time, a.distance)), report.closest(1, 0));
    let d = &report.distances[0].1;
    // A threshold between the smallest and largest distance: the spans hold
    // exactly the samples below it, by brute force.
    let (lo, hi) = d.iter().fold((f64::INFINITY, 0.0f64), |(l, h), v| (l.min(*v), h.max(*v)));
    let min = 0.5 * (lo + hi);
    let spans = report.closer_than(0, 1, min);
    assert!(!spans.is_empty());
    for (k, &t) in report.times.iter().enumerate() {
        let inside = spans.iter().any(|(s, e)| *s <= t && t <= *e);
        assert_eq!(inside, d[k] < min, "t = {t}");
    }
    assert!(report.closer_than(0, 1, lo).is_empty());
    // A robot whose description has a base keeps it under the placement.
    let scara = Robot::builtin("scara5").unwrap();
    let at = Pose::new(rot_z(0.3), Vector3::new(0.5, -0.2, 0.1));
    let moved = kinema::traj::cell::placed(&scara, &at).unwrap();
    let q = scara.home().to_vec();
    let want = at.transform_point(&scara.fk(&q).unwrap().world_from_tool.pos);
    assert!((moved.fk(&q).unwrap().world_from_tool.pos - want).norm() < 1e-12);
}
