//! A sampled joint trajectory.

use kinema::traj::JointTrajectory;
use serde::ser::{Serialize, SerializeSeq, SerializeStruct, Serializer};

/// A sampled trajectory's samples: the times `t`, and per sample the rows
/// `q`, `qd`, `qdd` (flattened into a [`crate::TrajSummary`] or a
/// [`crate::ProgramAnswer`], which say how many and how long). Serialised
/// straight from the trajectory, without copying its samples.
#[derive(Debug, Clone, Copy)]
pub struct TrajectoryAnswer<'a>(pub &'a JointTrajectory);

/// One column of rows (`q`, `qd` or `qdd`), written sample by sample.
struct Rows<'a>(&'a JointTrajectory, fn(&JointTrajectory, usize) -> &[f64]);

impl Serialize for Rows<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(self.0.len()))?;
        for k in 0..self.0.len() {
            seq.serialize_element((self.1)(self.0, k))?;
        }
        seq.end()
    }
}

impl Serialize for TrajectoryAnswer<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let traj = self.0;
        let mut st = s.serialize_struct("Trajectory", 4)?;
        st.serialize_field("t", traj.times())?;
        st.serialize_field("q", &Rows(traj, JointTrajectory::q))?;
        st.serialize_field("qd", &Rows(traj, JointTrajectory::qd))?;
        st.serialize_field("qdd", &Rows(traj, JointTrajectory::qdd))?;
        st.end()
    }
}
