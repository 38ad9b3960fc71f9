//! [`Data`]: the mutable scratch of one robot's computations, beside the
//! shared immutable [`Robot`] (Pinocchio's Model/Data split). The Jacobian,
//! link-frame and dynamics calls that reuse memory all take one `Data`.

use nalgebra::{Matrix6xX, Vector3};

use crate::math::Pose;
use crate::robot::Robot;

/// Reusable scratch for one robot, so repeated calls allocate nothing: the
/// Jacobian and link frames of [`Data::jacobian`] and [`Data::link_frames`],
/// and the motion subspaces and link wrenches of
/// [`rnea_into`](crate::dynamics::rnea_into) and
/// [`mass_matrix_into`](crate::dynamics::mass_matrix_into). Sized for one robot
/// by [`Data::new`]; handed a robot with another number of joints, a call
/// resizes it once (the only time these calls allocate). One per thread.
///
/// # Examples
/// ```
/// use kinema::{Data, Frame, Robot};
/// let robot = Robot::builtin("panda")?;
/// let mut data = Data::new(&robot);
/// for q in [robot.home(), robot.pose("qr")?] {
///     let j = data.jacobian(&robot, q, Frame::Base)?;
///     assert_eq!(j.ncols(), 7);
/// }
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct Data {
    pub(crate) jacobian: Matrix6xX<f64>,
    /// Base, one frame per joint, tool: `dof + 2` poses.
    pub(crate) frames: Vec<Pose>,
    pub(crate) subspace: Vec<Spatial>,
    pub(crate) wrench: Vec<Spatial>,
}

impl Data {
    /// Scratch sized for `robot`.
    pub fn new(robot: &Robot) -> Self {
        let n = robot.dof();
        Data {
            jacobian: Matrix6xX::zeros(n),
            frames: vec![Pose::IDENTITY; n + 2],
            subspace: vec![Spatial::ZERO; n],
            wrench: vec![Spatial::ZERO; n],
        }
    }

    /// Resize for `robot` when it has another number of joints.
    pub(crate) fn fit(&mut self, robot: &Robot) {
        if self.jacobian.ncols() != robot.dof() {
            *self = Data::new(robot);
        }
    }
}

/// A spatial motion or force vector as its angular and linear parts (see the
/// module docs of [`crate::dynamics`] for the ordering and the frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Spatial {
    pub(crate) ang: Vector3<f64>,
    pub(crate) lin: Vector3<f64>,
}

impl Spatial {
    pub(crate) const ZERO: Spatial = Spatial { ang: Vector3::new(0.0, 0.0, 0.0), lin: Vector3::new(0.0, 0.0, 0.0) };

    pub(crate) fn dot(&self, other: &Spatial) -> f64 {
        self.ang.dot(&other.ang) + self.lin.dot(&other.lin)
    }
}
