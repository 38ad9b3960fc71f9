//! A multi-robot cell (seed 004 §VIII-E): several robots placed in one
//! world frame by their base transforms, each running its own joint
//! trajectory on a common clock, with their tool poses, the distances
//! between their tools and their manipulability over time.

use nalgebra::Matrix6xX;

use super::JointTrajectory;
use crate::analysis::{yoshikawa, Axes};
use crate::error::{Error, Result};
use crate::kin::Frame;
use crate::math::Pose;
use crate::model::Robot;

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
}

impl CellReport {
    /// (time, distance) of the closest approach of members `i` and `j`.
    pub fn closest(&self, i: usize, j: usize) -> Option<(f64, f64)> {
        let key = (i.min(j), i.max(j));
        let (_, d) = self.distances.iter().find(|(k, _)| *k == key)?;
        d.iter().zip(&self.times).map(|(d, t)| (*t, *d)).min_by(|a, b| a.1.total_cmp(&b.1))
    }
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
            return Err(Error::JointCount {
                robot: format!("{name} ({})", robot.name()),
                expected: robot.dof(),
                got: traj.dof(),
            });
        }
        if traj.is_empty() {
            return Err(Error::InvalidArgument { what: name, message: "the trajectory has no sample".into() });
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
            return Err(Error::InvalidArgument { what: "cell".into(), message: "the cell has no robot".into() });
        }
        let end = self.members.iter().map(|m| *m.traj.times().last().expect("non-empty")).fold(0.0, f64::max);
        let times = super::sample_times(end, dt)?;
        let n = self.members.len();
        let mut report = CellReport {
            q: vec![Vec::with_capacity(times.len()); n],
            tools: vec![Vec::with_capacity(times.len()); n],
            manipulability: vec![Vec::with_capacity(times.len()); n],
            distances: (0..n).flat_map(|i| (i + 1..n).map(move |j| ((i, j), Vec::new()))).collect(),
            times,
        };
        for (m, member) in self.members.iter().enumerate() {
            let mut jac = Matrix6xX::zeros(member.robot.dof());
            let mut q = vec![0.0; member.robot.dof()];
            for &t in &report.times {
                interpolate(&member.traj, t, &mut q);
                let fk = member.robot.jacobian_into(&q, Frame::Base, &mut jac)?;
                report.tools[m].push(fk.pose);
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
