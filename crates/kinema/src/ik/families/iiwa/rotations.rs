//! The rotations the arm-angle form is written in: Z-Y-Z angles of the
//! shoulder and wrist (either branch, and the singular case) and the turn
//! about the shoulder–wrist axis by the arm angle ψ.

use nalgebra::{Matrix3, Vector3};


use super::SINGULAR_SIN;
use crate::ik::wrap_angle;
use crate::math::FastMath;

/// ZYZ Euler angles (a, b, c) of m = Rz(a)·Ry(b)·Rz(c) with sign(b) = `sign`.
/// When |sin b| < [`SINGULAR_SIN`], a = `hint` and c takes the rest. c is
/// always computed from a and the whole matrix, so the triple reproduces m
/// even when a is ill-conditioned.
pub(super) fn zyz(m: &Matrix3<f64>, sign: f64, hint: f64) -> (f64, f64, f64) {
    let sb = m[(0, 2)].fast_hypot(m[(1, 2)]);
    let b = (sign * sb).fast_atan2(m[(2, 2)]);
    let a = if sb < SINGULAR_SIN { hint } else { (sign * m[(1, 2)]).fast_atan2(sign * m[(0, 2)]) };
    // Rz(c) = Ry(−b)·Rz(−a)·m; its row 1 is row 1 of Rz(−a)·m.
    let (sa, ca) = a.fast_sin_cos();
    let c = (ca * m[(1, 0)] - sa * m[(0, 0)]).fast_atan2(ca * m[(1, 1)] - sa * m[(0, 1)]);
    (wrap_angle(a), b, wrap_angle(c))
}

/// Rotation by `psi` about the unit axis `u` (Rodrigues).
pub(super) fn axis_rotation(u: &Vector3<f64>, psi: f64) -> Matrix3<f64> {
    let k = Matrix3::new(0.0, -u.z, u.y, u.z, 0.0, -u.x, -u.y, u.x, 0.0);
    let (s, c) = psi.fast_sin_cos();
    Matrix3::identity() + k * s + k * k * (1.0 - c)
}
