//! Small closed-form pieces of the arm's solution: 3×3 products on plain
//! row arrays, the link rotations, and the position equations of the first
//! three joints.

use nalgebra::Vector3;

use super::{Link, AXIS_TOL};
use crate::math::FastMath;

/// A 3×3 matrix as rows (plain arrays: a few multiplications per solve, fast
/// also in debug builds).
pub(super) type M3 = [[f64; 3]; 3];

/// a·b.
pub(super) fn mul(a: &M3, b: &M3) -> M3 {
    let mut c = [[0.0; 3]; 3];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    c
}

/// aᵀ·b.
pub(super) fn tmul(a: &M3, b: &M3) -> M3 {
    let mut c = [[0.0; 3]; 3];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = a[0][i] * b[0][j] + a[1][i] * b[1][j] + a[2][i] * b[2][j];
        }
    }
    c
}

/// Rz(θ)·Rx(α) of a link.
pub(super) fn rzrx(theta: f64, l: Link) -> M3 {
    let (s, c) = theta.fast_sin_cos();
    [[c, -s * l.ca, s * l.sa], [s, c * l.ca, -c * l.sa], [0.0, l.sa, l.ca]]
}

/// g(θ3) = Tz(d2)·Tx(a2)·Rx(α2)·A3·(0, 0, d4): the wrist centre in frame 1
/// before the rotation θ2 about its z axis.
pub(super) fn arm_g(links: &[Link; 6], t3: f64) -> Vector3<f64> {
    let [_, l2, l3, l4, ..] = *links;
    let (s3, c3) = t3.fast_sin_cos();
    let f1 = l3.a * c3 + l4.d * l3.sa * s3;
    let f2 = l3.a * s3 - l4.d * l3.sa * c3;
    let f3 = l3.d + l4.d * l3.ca;
    Vector3::new(f1 + l2.a, l2.ca * f2 - l2.sa * f3, l2.sa * f2 + l2.ca * f3 + l2.d)
}

/// θ1 from (px, py) = Rz(θ1)·(w1, w2), (w1, w2) the horizontal part of
/// Tx(a1)·Rx(α1)·Rz(θ2)·g. On axis 1 (θ1 free): q1 = 0.
pub(super) fn theta1(l1: Link, g: &Vector3<f64>, t2: f64, p: &Vector3<f64>) -> f64 {
    let (s2, c2) = t2.fast_sin_cos();
    let u = Vector3::new(c2 * g.x - s2 * g.y, s2 * g.x + c2 * g.y, g.z);
    let w1 = u.x + l1.a;
    let w2 = l1.ca * u.y - l1.sa * u.z;
    if w1.fast_hypot(w2) <= AXIS_TOL || p.x.fast_hypot(p.y) <= AXIS_TOL {
        l1.offset
    } else {
        p.y.fast_atan2(p.x) - w2.fast_atan2(w1)
    }
}

/// For the intersecting shoulder: |p − o1|² = K + A·c3 + B·s3; returns (K, (A, B)).
pub(super) fn intersecting_coeffs(links: &[Link; 6]) -> (f64, (f64, f64)) {
    let [_, l2, l3, l4, ..] = *links;
    let f3 = l3.d + l4.d * l3.ca;
    let k = l3.a * l3.a + (l4.d * l3.sa).powi(2) + f3 * f3 + l2.a * l2.a + l2.d * l2.d + 2.0 * l2.d * l2.ca * f3;
    let a = 2.0 * l2.a * l3.a - 2.0 * l2.d * l2.sa * l4.d * l3.sa;
    let b = 2.0 * l2.a * l4.d * l3.sa + 2.0 * l2.d * l2.sa * l3.a;
    (k, (a, b))
}
