//! A multi-robot cell (seed 004 §VIII-E): several robots placed in one
//! world frame by their base transforms, each running its own joint
//! trajectory on a common clock, with their tool poses, the distances
//! between their tools and their manipulability over time.
//!
//! A member whose trajectory ends before the others holds its last
//! configuration until the end of the common clock. Distances are those of
//! the tool points at the common clock's samples (not between them).

use nalgebra::Matrix6xX;

use super::JointTrajectory;
use crate::analysis::{yoshikawa, Axes};
use crate::error::{Error, InputError, Result};
use crate::kin::Frame;
use crate::math::Pose;
use crate::robot::Robot;

/// One robot of a cell with its trajectory.
#[derive(Debug, Clone)]
pub struct CellMember {
    /// A name for reports.
    pub name: String,
    /// The robot, its base transform placing it in the world frame.
    pub robot: Robot,
    /// Its joint trajectory (times from the common clock's zero).
    pub traj: JointTrajectory,
}

/// Several robots on a common clock.
#[derive(Debug, Clone, Default)]
pub struct Cell {
    members: Vec<CellMember>,
}

/// What [`Cell::run`] computed, sample by sample on the common clock.
#[derive(Debug, Clone, PartialEq)]
pub struct CellReport {
    /// Common sample times \[s\].
    pub times: Vec<f64>,
    /// Per member, its joint values at each time.
    pub q: Vec<Vec<Vec<f64>>>,
    /// Per member, its tool pose in the world frame at each time.
    pub tools: Vec<Vec<Pose>>,
    /// Per member, its translational manipulability (Yoshikawa on the
    /// linear-velocity rows, as seed 004 Fig. 30/33) at each time.
    pub manipulability: Vec<Vec<f64>>,
    /// For every pair (i, j), i < j: the distance between their tool points \[m\] at each time.
    pub distances: Vec<((usize, usize), Vec<f64>)>,
    /// Per member, the time its own trajectory ends \[s\]: from then on it
    /// holds its last configuration.
    pub ends: Vec<f64>,
}

/// The closest approach of two members' tool points (see [`CellReport::approaches`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Approach {
    /// The members (i, j), i < j, in the order they were added.
    pub pair: (usize, usize),
    /// The first sample time at which the distance is smallest \[s\].
    pub time: f64,
    /// That distance \[m\].
    pub distance: f64,
}

impl CellReport {
    /// (time, distance) of the closest approach of members `i` and `j`.
    pub fn closest(&self, i: usize, j: usize) -> Option<(f64, f64)> {
        let key = (i.min(j), i.max(j));
        let (_, d) = self.distances.iter().find(|(k, _)| *k == key)?;
        d.iter().zip(&self.times).map(|(d, t)| (*t, *d)).min_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// The closest approach of every pair, in the order of [`CellReport::distances`].
    pub fn approaches(&self) -> Vec<Approach> {
        self.distances
            .iter()
            .filter_map(|((i, j), _)| {
                let (time, distance) = self.closest(*i, *j)?;
                Some(Approach { pair: (*i, *j), time, distance })
            })
            .collect()
    }

    /// The spans of time during which members `i` and `j` are closer than
    /// `min` \[m\]: (first, last) sample time of each run of samples below it.
    pub fn closer_than(&self, i: usize, j: usize, min: f64) -> Vec<(f64, f64)> {
        let key = (i.min(j), i.max(j));
        let Some((_, d)) = self.distances.iter().find(|(k, _)| *k == key) else { return Vec::new() };
        let mut spans: Vec<(f64, f64)> = Vec::new();
        let mut open = false;
        for (d, &t) in d.iter().zip(&self.times) {
            if *d < min {
                match spans.last_mut() {
                    Some(span) if open => span.1 = t,
                    _ => spans.push((t, t)),
                }
                open = true;
            } else {
                open = false;
            }
        }
        spans
    }
}

/// `robot` placed in a cell: its own world frame (the frame of its forward
/// kinematics, its description's `[base]` included) put at `world_from_robot`
/// in the cell's world, so its base becomes `world_from_robot · base`.
///
/// # Examples
///
/// ```
/// # fn main() -> kinema::Result<()> {
/// use kinema::{Pose, Robot};
/// use kinema::traj::cell::placed;
/// let robot = Robot::builtin("ur5")?;
/// let at = Pose::from_xyz_rpy([1.0, 0.0, 0.0], [0.0, 0.0, 0.0], kinema::RpyConvention::Zyx);
/// let moved = placed(&robot, &at)?;
/// let (a, b) = (robot.fk(robot.home())?.world_from_tool.pos, moved.fk(robot.home())?.world_from_tool.pos);
/// assert!((b.x - a.x - 1.0).abs() < 1e-12 && (b.y - a.y).abs() < 1e-12);
/// # Ok(()) }
/// ```
pub fn placed(robot: &Robot, world_from_robot: &Pose) -> Result<Robot> {
    robot.with_base(*world_from_robot * *robot.base())
}

impl Cell {
    /// An empty cell.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a robot with its trajectory. Errors if the trajectory's joint
    /// count does not match the robot or it has no sample.
    pub fn add(&mut self, name: impl Into<String>, robot: Robot, traj: JointTrajectory) -> Result<&mut Self> {
        let name = name.into();
        if traj.dof() != robot.dof() {
            return Err(Error::Input(InputError::JointCount {
                robot: format!("{name} ({})", robot.name()),
                expected: robot.dof(),
                got: traj.dof(),
            }));
        }
        if traj.is_empty() {
            return Err(Error::Input(InputError::TooFew {
                what: name,
                got: 0,
                min: 1,
                of: "trajectory samples".into(),
            }));
        }
        self.members.push(CellMember { name, robot, traj });
        Ok(self)
    }

    /// The members, in the order they were added.
    pub fn members(&self) -> &[CellMember] {
        &self.members
    }

    /// Runs every member on a common clock sampled every `dt` \[s\] from 0 to
    /// the end of the longest trajectory. A member's joint values between its
    /// samples are interpolated linearly; before its first sample and after
    /// its last it holds them.
    pub fn run(&self, dt: f64) -> Result<CellReport> {
        if self.members.is_empty() {
            return Err(Error::Input(InputError::TooFew { what: "cell".into(), got: 0, min: 1, of: "robots".into() }));
        }
        let end = self.members.iter().map(|m| *m.traj.times().last().expect("non-empty")).fold(0.0, f64::max);
        let times = super::sample_times(end, dt)?;
        let n = self.members.len();
        let mut report = CellReport {
            q: vec![Vec::with_capacity(times.len()); n],
            tools: vec![Vec::with_capacity(times.len()); n],
            manipulability: vec![Vec::with_capacity(times.len()); n],
            distances: (0..n).flat_map(|i| (i + 1..n).map(move |j| ((i, j), Vec::new()))).collect(),
            ends: self.members.iter().map(|m| *m.traj.times().last().expect("non-empty")).collect(),
            times,
        };
        for (m, member) in self.members.iter().enumerate() {
            let mut jac = Matrix6xX::zeros(member.robot.dof());
            let mut q = vec![0.0; member.robot.dof()];
            for &t in &report.times {
                interpolate(&member.traj, t, &mut q);
                let fk = crate::kin::jacobian_into(&member.robot, &q, Frame::Base, &mut jac)?;
                report.tools[m].push(fk.world_from_tool);
                report.manipulability[m].push(yoshikawa(&jac, Axes::Translation)?);
                report.q[m].push(q.clone());
            }
        }
        for ((i, j), d) in &mut report.distances {
            *d = report.tools[*i].iter().zip(&report.tools[*j]).map(|(a, b)| (a.pos - b.pos).norm()).collect();
        }
        Ok(report)
    }
}

/// q of `traj` at `t` by linear interpolation, held outside its time span.
fn interpolate(traj: &JointTrajectory, t: f64, out: &mut [f64]) {
    let ts = traj.times();
    let k = ts.partition_point(|&x| x <= t);
    if k == 0 {
        out.copy_from_slice(traj.q(0));
    } else if k == ts.len() {
        out.copy_from_slice(traj.q(ts.len() - 1));
    } else {
        let (t0, t1) = (ts[k - 1], ts[k]);
        let u = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
        for ((o, a), b) in out.iter_mut().zip(traj.q(k - 1)).zip(traj.q(k)) {
            *o = a + u * (b - a);
        }
    }
}
