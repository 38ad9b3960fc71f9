//! Spatial math: rigid transforms, orientation representations, pose errors.
//!
//! Everything is SI: metres and radians.
//!
//! Two roll-pitch-yaw conventions appear in the seed papers and both are
//! supported, always named explicitly through [`RpyConvention`]:
//!
//! * [`RpyConvention::Zyx`] — seed 000 eq. (6)–(7): R = Rz(yaw)·Ry(pitch)·Rx(roll).
//!   This is also URDF's `rpy` and the default everywhere in kinema.
//! * [`RpyConvention::Xyz`] — Corke's "arm" convention used by seed 004:
//!   R = Rx(a)·Ry(b)·Rz(c) for the triple (a, b, c).

mod pose;
mod rotation;
#[cfg(test)]
mod tests;
mod trig;

pub use self::pose::{pose_error, Pose, PoseError};
pub use self::rotation::{
    axis_angle_to_rot, rot_to_axis_angle, rot_to_rpy, rot_to_rpy_near, rot_x, rot_y, rot_z, rpy_to_rot, RpyConvention,
};
#[cfg(target_arch = "x86_64")]
pub(crate) use self::trig::Fused;
pub use self::trig::{atan2, atan2_lanes, atan2_x8, hypot, sin_cos};
pub(crate) use self::trig::{
    sin_cos_kernel, FastMath, Madd, Plain, COS_POLY, PIO2_1, PIO2_2, PIO2_3, RINT_SHIFT, SIN_COS_RANGE, SIN_POLY,
};
