//! A pose as every door writes it.

use kinema::{Named, Pose, RpyConvention};
use serde::Serialize;

/// A pose: the 4×4 matrix, the position, roll-pitch-yaw in a named
/// convention and the unit quaternion (w, x, y, z). Metres and radians.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PoseAnswer {
    /// The homogeneous matrix, row by row.
    #[serde(rename = "T")]
    pub matrix: [[f64; 4]; 4],
    /// Translation \[m\].
    pub position: [f64; 3],
    /// Roll, pitch, yaw \[rad\] in `rpy_convention`.
    pub rpy: [f64; 3],
    /// `zyx` (R = Rz·Ry·Rx, the default) or `xyz` (R = Rx·Ry·Rz).
    pub rpy_convention: &'static str,
    /// The rotation as a unit quaternion, scalar first.
    pub quaternion_wxyz: [f64; 4],
}

impl PoseAnswer {
    /// `pose` with its roll-pitch-yaw angles in `convention`.
    pub fn new(pose: &Pose, convention: RpyConvention) -> PoseAnswer {
        let q = pose.quaternion();
        PoseAnswer {
            matrix: pose.to_rows(),
            position: [pose.pos.x, pose.pos.y, pose.pos.z],
            rpy: pose.rpy(convention),
            rpy_convention: convention.name(),
            quaternion_wxyz: [q.w, q.i, q.j, q.k],
        }
    }
}
