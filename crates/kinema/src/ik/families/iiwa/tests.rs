use super::*;
use crate::math::rot_x;

#[test]
fn twist_identity() {
    // Rx(−90°)·Rz(θ)·Rx(90°) = Ry(θ), the identity all formulas rest on.
    let th = 0.77;
    assert!((rot_x(-FRAC_PI_2) * rot_z(th) * rot_x(FRAC_PI_2) - rot_y(th)).norm() < 1e-15);
}
