//! Rigid transforms and the error between two of them.

use nalgebra::{Matrix3, Matrix4, Rotation3, UnitQuaternion, Vector3};

use super::rotation::{rot_to_axis_angle, rot_to_rpy, rot_x, rot_y, rot_z, rpy_to_rot, RpyConvention};

/// A rigid transform (rotation + translation), `child` expressed in `parent`.
///
/// Names of values of this type read like `world_from_tool`: the pose of the
/// tool frame expressed in the base frame, which maps tool coordinates to base
/// coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Rotation matrix (orthonormal, det +1).
    pub rot: Matrix3<f64>,
    /// Translation \[m\].
    pub pos: Vector3<f64>,
}

impl Default for Pose {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Pose {
    /// The identity transform.
    pub const IDENTITY: Pose =
        Pose { rot: Matrix3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0), pos: Vector3::new(0.0, 0.0, 0.0) };

    /// Builds a pose from a rotation matrix and a translation \[m\].
    pub fn new(rot: Matrix3<f64>, pos: Vector3<f64>) -> Self {
        Pose { rot, pos }
    }

    /// Pure translation \[m\].
    pub fn translation(x: f64, y: f64, z: f64) -> Self {
        Pose { rot: Matrix3::identity(), pos: Vector3::new(x, y, z) }
    }

    /// Pure rotation about x by `angle` \[rad\].
    pub fn rot_x(angle: f64) -> Self {
        Pose { rot: rot_x(angle), pos: Vector3::zeros() }
    }

    /// Pure rotation about y by `angle` \[rad\].
    pub fn rot_y(angle: f64) -> Self {
        Pose { rot: rot_y(angle), pos: Vector3::zeros() }
    }

    /// Pure rotation about z by `angle` \[rad\].
    pub fn rot_z(angle: f64) -> Self {
        Pose { rot: rot_z(angle), pos: Vector3::zeros() }
    }

    /// Translation `xyz` \[m\] and orientation `rpy` \[rad\] in the given convention.
    pub fn from_xyz_rpy(xyz: [f64; 3], rpy: [f64; 3], conv: RpyConvention) -> Self {
        Pose { rot: rpy_to_rot(rpy, conv), pos: Vector3::from(xyz) }
    }

    /// Composition `self · other`.
    #[inline]
    pub fn mul(&self, other: &Pose) -> Pose {
        Pose { rot: self.rot * other.rot, pos: self.pos + self.rot * other.pos }
    }

    /// The inverse transform.
    pub fn inverse(&self) -> Pose {
        let rt = self.rot.transpose();
        Pose { rot: rt, pos: -(rt * self.pos) }
    }

    /// Maps a point given in the child frame into the parent frame.
    pub fn transform_point(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.rot * p + self.pos
    }

    /// The 4×4 homogeneous matrix.
    pub fn to_matrix(&self) -> Matrix4<f64> {
        let mut m = Matrix4::identity();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.rot);
        m.fixed_view_mut::<3, 1>(0, 3).copy_from(&self.pos);
        m
    }

    /// The 4×4 homogeneous matrix as four rows (handy for JSON output).
    pub fn to_rows(&self) -> [[f64; 4]; 4] {
        let m = self.to_matrix();
        let mut rows = [[0.0; 4]; 4];
        for (r, row) in rows.iter_mut().enumerate() {
            for (c, v) in row.iter_mut().enumerate() {
                *v = m[(r, c)];
            }
        }
        rows
    }

    /// Builds a pose from a 4×4 homogeneous matrix. The rotation block is
    /// re-orthonormalised (nearest rotation) so small rounding in a file does
    /// not propagate. Returns `None` if the matrix is not finite, its last row
    /// is not `[0 0 0 1]`, or its rotation block is far from a rotation.
    pub fn from_matrix(m: &Matrix4<f64>) -> Option<Pose> {
        if m.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let last = [m[(3, 0)], m[(3, 1)], m[(3, 2)], m[(3, 3)]];
        if last.iter().zip([0.0, 0.0, 0.0, 1.0]).any(|(a, b)| (a - b).abs() > 1e-9) {
            return None;
        }
        let r: Matrix3<f64> = m.fixed_view::<3, 3>(0, 0).into();
        if (r.transpose() * r - Matrix3::identity()).norm() > 1e-6 || r.determinant() < 0.0 {
            return None;
        }
        Some(Pose { rot: nearest_rotation(r), pos: m.fixed_view::<3, 1>(0, 3).into() })
    }

    /// Orientation as a unit quaternion.
    pub fn quaternion(&self) -> UnitQuaternion<f64> {
        UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(self.rot))
    }

    /// Orientation as roll-pitch-yaw \[rad\] in the given convention.
    pub fn rpy(&self, conv: RpyConvention) -> [f64; 3] {
        rot_to_rpy(&self.rot, conv)
    }

    /// Orientation as an axis-angle vector (unit axis × angle in \[0, π\]) \[rad\].
    pub fn axis_angle(&self) -> Vector3<f64> {
        rot_to_axis_angle(&self.rot)
    }

    /// Whether every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.rot.iter().chain(self.pos.iter()).all(|v| v.is_finite())
    }
}

impl std::ops::Mul for Pose {
    type Output = Pose;
    fn mul(self, rhs: Pose) -> Pose {
        Pose::mul(&self, &rhs)
    }
}

/// The rotation nearest to `r` (its polar factor), for a matrix already
/// within about 1e-6 of a rotation (‖rᵀr − I‖ < 1e-6, which
/// [`Pose::from_matrix`] checks first). Newton–Schulz iteration
/// X ← X·(3I − XᵀX)/2 squares the error each step, so three steps reach
/// rounding level from that distance without the eigen-solver a general
/// projection needs.
pub(super) fn nearest_rotation(r: Matrix3<f64>) -> Matrix3<f64> {
    let mut x = r;
    for _ in 0..3 {
        x = x * (Matrix3::identity() * 3.0 - x.transpose() * x) * 0.5;
    }
    x
}

/// The difference between two poses, as seen in the base frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseError {
    /// `target.pos − actual.pos` \[m\].
    pub translation: Vector3<f64>,
    /// Axis-angle vector of `target.rot · actual.rotᵀ` \[rad\]: the rotation that
    /// takes `actual` onto `target`, in base coordinates.
    pub rotation: Vector3<f64>,
}

impl PoseError {
    /// Distance between the two positions \[m\].
    pub fn position_norm(&self) -> f64 {
        self.translation.norm()
    }
    /// Angle of the rotation between the two orientations \[rad\].
    pub fn rotation_angle(&self) -> f64 {
        self.rotation.norm()
    }
}

/// The error that takes `actual` to `target` (both in the same frame).
pub fn pose_error(target: &Pose, actual: &Pose) -> PoseError {
    PoseError {
        translation: target.pos - actual.pos,
        rotation: rot_to_axis_angle(&(target.rot * actual.rot.transpose())),
    }
}
