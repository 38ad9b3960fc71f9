//! The Coriolis matrix C(q, q̇) whose product with q̇ is [`super::coriolis`]
//! and for which Ṁ − 2C is skew-symmetric.
//!
//! C is not unique (any C + N with N·q̇ = 0 gives the same torques); this is
//! the factorisation of Echeandia and Wensing, "Numerical methods to
//! compute the Coriolis matrix and Christoffel symbols for rigid-body
//! systems" (J. Comput. Nonlinear Dyn., 2021), the one Pinocchio's
//! `computeCoriolisMatrix` returns, so the two agree entry by entry. Per body, B(I, v) = ½(v×*·I − I·v× + (I·v)×̄) with (f×̄)·m = m ×* f
//! satisfies B·v = v ×* I·v and B + Bᵀ = İ; summed over the links beyond
//! joint k into Bᶜ_k (like the composite inertia Iᶜ_k of CRBA),
//! C_ij = S_iᵀ·(Iᶜ_k·Ṡ_j + Bᶜ_k·S_j) with k the later of i and j.

use nalgebra::{DMatrix, Matrix6, Vector6};

use super::{check_rates, cross_motion, kinematics, skew, split};
use crate::error::Result;
use crate::robot::Robot;

/// The matrix of v ×ₘ (Featherstone eq. 2.31): \[\[ω̃, 0\], \[ṽ₀, ω̃\]\].
fn motion_cross_matrix(v: &Vector6<f64>) -> Matrix6<f64> {
    let (w, v0) = split(v);
    let mut out = Matrix6::zeros();
    out.fixed_view_mut::<3, 3>(0, 0).copy_from(&skew(&w));
    out.fixed_view_mut::<3, 3>(3, 3).copy_from(&skew(&w));
    out.fixed_view_mut::<3, 3>(3, 0).copy_from(&skew(&v0));
    out
}

/// The matrix of m ↦ m ×* f (Featherstone eq. 2.32 read as linear in m):
/// \[\[−ñ, −f̃\], \[−f̃, 0\]\] for f = \[n; f\]. It is skew-symmetric.
fn force_bar_matrix(f: &Vector6<f64>) -> Matrix6<f64> {
    let (n, f0) = split(f);
    let mut out = Matrix6::zeros();
    out.fixed_view_mut::<3, 3>(0, 0).copy_from(&-skew(&n));
    out.fixed_view_mut::<3, 3>(0, 3).copy_from(&-skew(&f0));
    out.fixed_view_mut::<3, 3>(3, 0).copy_from(&-skew(&f0));
    out
}

/// C(q, q̇) (dof × dof; N·m·s/rad, N·s/m or mixed): C·q̇ = [`super::coriolis`]`(q, q̇)` and
/// Ṁ − 2C is skew-symmetric; see the module documentation for which C.
pub(super) fn coriolis_matrix(robot: &Robot, q: &[f64], qd: &[f64]) -> Result<DMatrix<f64>> {
    check_rates(robot, "qd", qd)?;
    let k = kinematics(robot, q)?;
    let n = robot.dof();
    // Outward: link velocities, Ṡ_j = v_j ×ₘ S_j (S_j moves with link j) and
    // each body's B(I, v).
    let mut v = Vector6::zeros();
    let mut sdot = Vec::with_capacity(n);
    let mut b = Vec::with_capacity(n);
    for ((s, inertia), &rate) in k.s.iter().zip(&k.inertia).zip(qd) {
        v += s * rate;
        sdot.push(cross_motion(&v, s));
        let vx = motion_cross_matrix(&v);
        b.push(0.5 * (-vx.transpose() * inertia - inertia * vx + force_bar_matrix(&(inertia * v))));
    }
    // Inward: composites of links k..n, in one frame a plain sum.
    let mut c = DMatrix::zeros(n, n);
    let (mut ic, mut bc) = (Matrix6::zeros(), Matrix6::zeros());
    for kk in (0..n).rev() {
        ic += k.inertia[kk];
        bc += b[kk];
        // The entries whose later index is kk: column kk down to the
        // diagonal, and row kk left of it.
        let f = ic * sdot[kk] + bc * k.s[kk];
        for i in 0..=kk {
            c[(i, kk)] = k.s[i].dot(&f);
        }
        let g = ic.transpose() * k.s[kk];
        let h = bc.transpose() * k.s[kk];
        for j in 0..kk {
            c[(kk, j)] = g.dot(&sdot[j]) + h.dot(&k.s[j]);
        }
    }
    Ok(c)
}
