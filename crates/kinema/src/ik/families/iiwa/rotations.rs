//! The rotations the closed form is written in: Z-Y-Z angles of the
//! shoulder and wrist (both branches, and the singular case), elementary
//! rotations from a sine and cosine, and the turn about the shoulder–wrist
//! axis by the arm angle ψ.

use nalgebra::{Matrix3, Vector3};

use std::f64::consts::PI;

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

/// The atan2 arguments (y, x) of both ZYZ triples of `m` (see [`zyz`]):
/// b (sin b ≥ 0), a and c, and whether |sin b| < [`SINGULAR_SIN`] (then a =
/// `hint`, and its arguments are (0, 1), not used). [`zyz_pair_of`] makes the
/// two triples from the three angles; the kernel of [`IiwaIk::solve_q3`]
/// batches the atan2s of several matrices in between.
#[inline]
pub(super) fn zyz_args(m: &Matrix3<f64>, hint: f64) -> ([(f64, f64); 3], bool) {
    let sb = m[(0, 2)].fast_hypot(m[(1, 2)]);
    let singular = sb < SINGULAR_SIN;
    let (a, sa, ca) = if singular {
        let (sa, ca) = hint.fast_sin_cos();
        ((0.0, 1.0), sa, ca)
    } else {
        ((m[(1, 2)], m[(0, 2)]), m[(1, 2)] / sb, m[(0, 2)] / sb)
    };
    // Rz(c) = Ry(−b)·Rz(−a)·m; its row 1 is row 1 of Rz(−a)·m.
    let c = (ca * m[(1, 0)] - sa * m[(0, 0)], ca * m[(1, 1)] - sa * m[(0, 1)]);
    ([(sb, m[(2, 2)]), a, c], singular)
}

/// Both ZYZ triples from the angles of [`zyz_args`]' arguments, sin b ≥ 0
/// first: the same as [`zyz`] with sign +1 and −1, the second derived from
/// the first as (a + π, −b, c + π) instead of being solved again (when
/// `singular`: a = `hint` and (hint, −b, c)).
#[inline]
pub(super) fn zyz_pair_of([b, a, c]: [f64; 3], singular: bool, hint: f64) -> [(f64, f64, f64); 2] {
    let (a, c) = (wrap_angle(if singular { hint } else { a }), wrap_angle(c));
    if singular {
        [(a, b, c), (a, -b, c)]
    } else {
        [(a, b, c), (wrap_angle(a + PI), -b, wrap_angle(c + PI))]
    }
}

/// Rotation about z with sine `s` and cosine `c`.
#[inline]
pub(super) fn rz(s: f64, c: f64) -> Matrix3<f64> {
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// Rotation about y with sine `s` and cosine `c`.
#[inline]
pub(super) fn ry(s: f64, c: f64) -> Matrix3<f64> {
    Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
}

/// Rotation by `psi` about the unit axis `u` (Rodrigues).
pub(super) fn axis_rotation(u: &Vector3<f64>, psi: f64) -> Matrix3<f64> {
    let k = Matrix3::new(0.0, -u.z, u.y, u.z, 0.0, -u.x, -u.y, u.x, 0.0);
    let (s, c) = psi.fast_sin_cos();
    Matrix3::identity() + k * s + k * k * (1.0 - c)
}
