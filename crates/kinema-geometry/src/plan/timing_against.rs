//! A path timed against another robot that moves along its own trajectory
//! (path–velocity decomposition): the path was planned with the other
//! robot held still; here its segments are timed as PTPs, at rest at each
//! via point, and the robot waits at a via point, a few sample periods at a
//! time, until the next segment can be run without the other robot coming
//! within the clearance. Every stretch is checked by [`closest_approaches`]
//! (the `kinema cell` check: continuous between samples), on the union of
//! both robots' sample times.

use kinema::traj::{JointTrajectory, Ptp, PtpOptions};
use kinema::Robot;

use crate::approach::{closest_approaches, Body};
use crate::error::{Error, Result};
use crate::geometry::RobotGeometry;

/// Sample periods waited between two tries of a departure: each try checks
/// a whole segment, so waits are made in steps a few samples long.
const WAIT_STEPS: usize = 5;

/// Where and when two robots meet whatever the waits: what
/// [`Error::Crossing`] reports.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("`{robot}` cannot keep clear of `{other}` {at}: `{a}` – `{b}` come within {clearance} m at t = {time:.4} s")]
pub struct Crossing {
    /// The robot whose path is timed.
    pub robot: String,
    /// The robot moving along its trajectory.
    pub other: String,
    /// Where on its path the timed robot is (`waiting at via point 1 of the path`).
    pub at: String,
    /// When \[s, on the other robot's time base\] they come closest.
    pub time: f64,
    /// The timed robot's link (`robot/link`).
    pub a: String,
    /// The other robot's link.
    pub b: String,
    /// The clearance asked for \[m\].
    pub clearance: f64,
}

/// A robot of a cell: its name, the robot placed on its base, its shapes.
#[derive(Debug, Clone, Copy)]
pub struct CellRobot<'a> {
    /// Its name, in reports (`name/link`).
    pub name: &'a str,
    /// The robot placed in the cell's world.
    pub robot: &'a Robot,
    /// Its link shapes.
    pub geometry: &'a RobotGeometry,
}

/// Times `path` of `mover` (via points joined by straight segments, each a
/// PTP under `options` sampled every `dt` \[s\]) on the time base of
/// `other`'s trajectory (joints linear between its samples, held after the
/// last), waiting at via points so the two stay more than `clearance`
/// \[m\] apart; the path's end is then held until `other` stops.
///
/// Errors: [`Error::Crossing`] when a wait cannot help (the other robot
/// comes to the waiting robot, or blocks a segment after it has stopped),
/// naming the two links; the PTP's errors.
///
/// # Examples
/// ```
/// use kinema::traj::{via::ptp_through, PtpOptions};
/// use kinema::{Pose, RpyConvention};
/// use kinema_geometry::plan::{time_against, CellRobot};
/// use kinema_geometry::{load_robot_geometry, UrdfOptions};
/// let (robot, geometry) = load_robot_geometry("puma560", &UrdfOptions::default())?;
/// // A second PUMA 1.5 m away makes the same motion; the first waits for it.
/// let base = Pose::from_xyz_rpy([1.5, 0.0, 0.0], [0.0, 0.0, std::f64::consts::PI], RpyConvention::Zyx);
/// let neighbour = kinema::traj::cell::placed(&robot, &base)?;
/// let path = vec![vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0], vec![0.5, 0.0, 0.0, 0.0, 0.0, 0.0]];
/// let options = PtpOptions::for_robot(&robot);
/// let its_motion = ptp_through(&neighbour, &path, &options, 0.01)?;
/// let me = CellRobot { name: "a", robot: &robot, geometry: &geometry };
/// let other = CellRobot { name: "b", robot: &neighbour, geometry: &geometry };
/// let timed = time_against(me, &path, &options, 0.01, other, &its_motion, 0.01)?;
/// assert_eq!(timed.q(timed.len() - 1), path[1].as_slice());
/// # Ok::<(), kinema_geometry::Error>(())
/// ```
pub fn time_against(
    mover: CellRobot<'_>,
    path: &[Vec<f64>],
    options: &PtpOptions,
    dt: f64,
    other: CellRobot<'_>,
    other_motion: &JointTrajectory,
    clearance: f64,
) -> Result<JointTrajectory> {
    let Some(first) = path.first() else {
        return Err(Error::Kinema(kinema::Error::Input(kinema::InputError::TooFew {
            what: "path".into(),
            got: 0,
            min: 1,
            of: "configurations".into(),
        })));
    };
    let timing = Timing::new(mover, other, other_motion, clearance)?;
    let n = mover.robot.dof();
    let zeros = vec![0.0; n];
    let mut out = JointTrajectory::new(n);
    out.push(0.0, first, &zeros, &zeros)?;
    let mut t = 0.0;
    let segments = path.windows(2).filter(|w| w[0] != w[1]).enumerate();
    for (i, w) in segments {
        let segment = sample_segment(mover.robot, &w[0], &w[1], options, dt)?;
        let mut depart = t;
        loop {
            let moving: Vec<(f64, &[f64])> =
                (0..segment.len()).map(|k| (depart + segment.times()[k], segment.q(k))).collect();
            let Some((time, a, b)) = timing.clear(&moving)? else { break };
            if depart >= timing.other_end {
                let at = format!("on segment {} after `{}` has stopped", i + 1, other.name);
                return Err(timing.crossing(at, time, a, b));
            }
            let wait = WAIT_STEPS as f64 * dt;
            if let Some((time, a, b)) = timing.clear(&[(depart, &w[0]), (depart + wait, &w[0])])? {
                return Err(timing.crossing(format!("waiting at via point {i} of the path"), time, a, b));
            }
            for k in 1..=WAIT_STEPS {
                out.push(depart + k as f64 * dt, &w[0], &zeros, &zeros)?;
            }
            depart += wait;
        }
        for k in 1..segment.len() {
            let q = if k + 1 == segment.len() { w[1].as_slice() } else { segment.q(k) };
            out.push(depart + segment.times()[k], q, segment.qd(k), segment.qdd(k))?;
        }
        t = depart + segment.times().last().copied().unwrap_or(0.0);
    }
    let last = path.last().expect("not empty");
    let end = timing.other_end.max(t);
    if let Some((time, a, b)) = timing.clear(&[(t, last), (end, last)])? {
        return Err(timing.crossing("holding the end of the path".into(), time, a, b));
    }
    Ok(out)
}

/// One PTP segment's samples.
fn sample_segment(robot: &Robot, from: &[f64], to: &[f64], options: &PtpOptions, dt: f64) -> Result<JointTrajectory> {
    Ok(Ptp::new(robot, from, to, options)?.sample_unchecked(dt)?)
}

/// The check of a stretch of the mover's motion against the other's.
struct Timing<'a> {
    bodies: [Body; 2],
    other: &'a JointTrajectory,
    other_end: f64,
    clearance: f64,
    names: (&'a str, &'a str),
}

impl<'a> Timing<'a> {
    fn new(mover: CellRobot<'a>, other: CellRobot<'a>, motion: &'a JointTrajectory, clearance: f64) -> Result<Self> {
        let body = |r: CellRobot<'_>| Body::new(r.name, r.robot.clone(), r.geometry.clone(), None);
        Ok(Timing {
            bodies: [body(mover)?, body(other)?],
            other: motion,
            other_end: motion.times().last().copied().unwrap_or(0.0),
            clearance,
            names: (mover.name, other.name),
        })
    }

    /// The first approach within the clearance (time, links) while the
    /// mover passes `moving` (time, joints; linear between) and the other
    /// follows its trajectory; `None` when clear.
    fn clear(&self, moving: &[(f64, &[f64])]) -> Result<Option<(f64, String, String)>> {
        let (t0, t1) = (moving[0].0, moving[moving.len() - 1].0);
        let mut times: Vec<f64> = moving.iter().map(|m| m.0).collect();
        times.extend(self.other.times().iter().copied().filter(|&t| t > t0 && t < t1));
        times.sort_by(f64::total_cmp);
        times.dedup();
        let mover: Vec<Vec<f64>> = times.iter().map(|&t| at_time(moving, t)).collect();
        let other_samples: Vec<(f64, &[f64])> =
            (0..self.other.len()).map(|k| (self.other.times()[k], self.other.q(k))).collect();
        let other: Vec<Vec<f64>> = times.iter().map(|&t| at_time(&other_samples, t)).collect();
        let found = closest_approaches(&self.bodies, &times, &[mover, other])?;
        Ok(found.into_iter().find(|f| f.distance <= self.clearance).map(|f| (f.time, f.closest.0, f.closest.1)))
    }

    fn crossing(&self, at: String, time: f64, a: String, b: String) -> Error {
        let (robot, other) = (self.names.0.to_string(), self.names.1.to_string());
        Error::Crossing(Box::new(Crossing { robot, other, at, time, a, b, clearance: self.clearance }))
    }
}

/// Joint values at `t` of samples (time, joints), linear between them and
/// held before the first and after the last.
fn at_time(samples: &[(f64, &[f64])], t: f64) -> Vec<f64> {
    let k = samples.partition_point(|s| s.0 <= t);
    if k == 0 {
        return samples[0].1.to_vec();
    }
    if k == samples.len() {
        return samples[k - 1].1.to_vec();
    }
    let ((ta, a), (tb, b)) = (samples[k - 1], samples[k]);
    let s = if tb > ta { (t - ta) / (tb - ta) } else { 1.0 };
    a.iter().zip(b).map(|(a, b)| a + s * (b - a)).collect()
}

#[cfg(test)]
mod tests {
    use kinema::traj::via::ptp_through;
    use kinema::{Pose, RpyConvention};

    use super::*;
    use crate::robot_toml::load_robot_geometry;
    use crate::urdf::UrdfOptions;

    #[test]
    fn samples_are_interpolated_and_held_at_the_ends() {
        let (a, b) = ([0.0, 2.0], [1.0, 4.0]);
        let samples = [(1.0, &a[..]), (3.0, &b[..])];
        assert_eq!(at_time(&samples, 0.0), a);
        assert_eq!(at_time(&samples, 2.0), [0.5, 3.0]);
        assert_eq!(at_time(&samples, 9.0), b);
    }

    #[test]
    fn a_far_robot_leaves_the_path_timed_as_without_it_and_one_in_the_way_is_named() {
        let (robot, geometry) = load_robot_geometry("puma560", &UrdfOptions::default()).unwrap();
        let far =
            kinema::traj::cell::placed(&robot, &Pose::from_xyz_rpy([5.0, 0.0, 0.0], [0.0; 3], RpyConvention::Zyx))
                .unwrap();
        let path = vec![vec![0.0; 6], vec![1.0, 0.3, -0.4, 0.0, 0.2, 0.0]];
        let options = PtpOptions::for_robot(&robot);
        let other_motion = ptp_through(&far, &path, &options, 0.01).unwrap();
        let me = CellRobot { name: "a", robot: &robot, geometry: &geometry };
        let other = CellRobot { name: "b", robot: &far, geometry: &geometry };
        let timed = time_against(me, &path, &options, 0.01, other, &other_motion, 0.01).unwrap();
        assert_eq!(timed, ptp_through(&robot, &path, &options, 0.01).unwrap());
        // The same robot on the same base is in the way from the start.
        let same = CellRobot { name: "b", robot: &robot, geometry: &geometry };
        let err = time_against(me, &path, &options, 0.01, same, &other_motion, 0.01).unwrap_err();
        assert!(matches!(&err, Error::Crossing(c) if c.robot == "a" && c.other == "b"), "{err}");
    }
}
