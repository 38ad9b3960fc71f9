use super::*;
use crate::math::rot_x;

#[test]
fn zyz_reproduces_the_matrix() {
    for (a, b, c) in [(0.3, 0.7, -1.2), (2.9, -0.4, 3.0), (0.0, 0.0, 0.5), (1.0, 1e-14, 2.0), (0.5, PI, 0.2)] {
        let m = rot_z(a) * rot_y(b) * rot_z(c);
        let (x, y, z) = zyz(&m, if b < 0.0 { -1.0 } else { 1.0 }, 0.0);
        let back = rot_z(x) * rot_y(y) * rot_z(z);
        // Singular convention (a = hint): the error is O(sin b) ≤ 1e-12.
        let tol = if b.sin().abs() < SINGULAR_SIN { 1e-12 } else { 1e-14 };
        assert!((back - m).norm() < tol, "{a} {b} {c} -> {x} {y} {z}");
    }
}

#[test]
fn twist_identity() {
    // Rx(−90°)·Rz(θ)·Rx(90°) = Ry(θ), the identity all formulas rest on.
    let th = 0.77;
    assert!((rot_x(-FRAC_PI_2) * rot_z(th) * rot_x(FRAC_PI_2) - rot_y(th)).norm() < 1e-15);
}
