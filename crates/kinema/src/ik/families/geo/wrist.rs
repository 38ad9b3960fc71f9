//! The orientation solve of a spherical wrist: three joint axes through one
//! point, the last three joints of the spherical-wrist arms (`pieper`,
//! [`SphericalWristIk`](super::SphericalWristIk)). One function for both,
//! so the wrist's branches and singular conventions are the same whichever
//! solver asks. The SRS arms solve their wrist inside their own kernel
//! (`srs_kernel.rs`), with the same branches and conventions.
//!
//! With axes h_a, h_b, h_c (unit, at q = 0) and the rotation the wrist must
//! make, M = rot(h_a, q_a)·rot(h_b, q_b)·rot(h_c, q_c):
//!
//! * rot(h_b, q_b)·h_c = rot(h_a, −q_a)·M·h_c, subproblem 2 in (q_a, q_b)
//!   (two branches). When h_a ∥ h_c and h_b ⊥ h_c (an orthogonal wrist: the
//!   PUMA's, the iiwa's), rot(h_b, q_b)·h_c = cos q_b·h_c + sin q_b·(h_b × h_c),
//!   so q_b = ±atan2(|M·h_c off h_a|, h_cᵀ·M·h_c) and q_a by subproblem 1
//!   instead: subproblem 2 loses half the digits of q_b near q_b = 0, this
//!   form none.
//! * q_c by subproblem 1 on a vector u ⊥ h_c: rot(h_c, q_c)·u =
//!   rot(h_b, −q_b)·rot(h_a, −q_a)·M·u.
//!
//! **Singularity** (M·h_c ∥ h_a within 1e-12: axes a and c aligned): only a
//! combination of q_a and q_c is determined. Branch 1 takes q_a at its zero
//! angle, branch 2 half a turn from it; q_b by subproblem 1, q_c the rest.

use std::f64::consts::PI;

use nalgebra::Vector3;

use super::kin::parallel;
use super::subproblems::{rotate, sp1_angle, sp2};
use super::GEOM_TOL;

type V3 = Vector3<f64>;

/// Below this |h_a × M·h_c| the wrist is treated as singular.
const WRIST_SING_TOL: f64 = 1e-12;

/// A spherical wrist's axes, prepared once per robot.
#[derive(Debug, Clone)]
pub(crate) struct SphericalWrist {
    /// The axes h_a, h_b, h_c at q = 0 (unit).
    h: [V3; 3],
    /// A unit vector ⊥ h_c, for q_c.
    u: V3,
    /// h_b × h_c when h_a ∥ h_c and h_b ⊥ h_c (an orthogonal wrist), for the
    /// form of q_a, q_b that keeps its accuracy near the singularity.
    aligned: Option<V3>,
    /// The angle q_a takes on the first branch at the singularity \[rad\].
    singular_a: f64,
}

/// The wrist's solutions for one rotation: up to two (q_a, q_b, q_c).
#[derive(Debug, Clone, Copy)]
pub(crate) struct WristRoots {
    /// The angles \[rad\]; the first `n` are solutions.
    pub(crate) q: [[f64; 3]; 2],
    /// How many solutions.
    pub(crate) n: usize,
    /// Axes a and c were aligned (the branches differ by half a turn of q_a).
    pub(crate) singular: bool,
}

impl SphericalWrist {
    /// The wrist of unit axes `h` (through one point, h_b not parallel to
    /// h_c); at the singularity the first branch takes q_a = `singular_a`
    /// \[rad\], the second `singular_a` + π.
    pub(crate) fn new(h: [V3; 3], singular_a: f64) -> Self {
        let aligned =
            (parallel(&h[0], &h[2], GEOM_TOL) && h[1].dot(&h[2]).abs() <= GEOM_TOL).then(|| h[1].cross(&h[2]));
        SphericalWrist { h, u: perpendicular(&h[2]), aligned, singular_a }
    }

    /// The vector u ⊥ h_c whose image M·u [`SphericalWrist::solve`] takes.
    pub(crate) fn u(&self) -> V3 {
        self.u
    }

    /// The (up to 2) joint angles that make the rotation M, given M·h_c
    /// (`mh`) and M·u (`mu`, u = [`SphericalWrist::u`]); the subproblem's
    /// miss (a chord between unit vectors) when the wrist cannot turn h_c to
    /// M·h_c.
    pub(crate) fn solve(&self, mh: &V3, mu: &V3) -> Result<WristRoots, f64> {
        let [ha, hb, hc] = &self.h;
        let mut roots = WristRoots { q: [[0.0; 3]; 2], n: 2, singular: false };
        let v_perp = mh - ha * ha.dot(mh);
        let singular = v_perp.norm() <= WRIST_SING_TOL;
        match self.aligned {
            Some(a) if !singular => {
                let tb = v_perp.norm().atan2(mh.dot(hc));
                for (k, sign) in [1.0, -1.0].into_iter().enumerate() {
                    roots.q[k] = [sp1_angle(ha, &(a * sign), mh), sign * tb, 0.0];
                }
            }
            _ if singular => {
                roots.singular = true;
                for k in 0..2 {
                    let qa = self.singular_a + PI * k as f64;
                    roots.q[k] = [qa, sp1_angle(hb, hc, &rotate(ha, -qa, mh)), 0.0];
                }
            }
            _ => {
                let (aa, ab) = sp2(ha, mh, hb, hc);
                if !aa.exact {
                    return Err(aa.miss);
                }
                roots.n = aa.as_slice().len();
                for (k, (ta, tb)) in aa.as_slice().iter().zip(ab.as_slice()).enumerate() {
                    roots.q[k] = [-ta, *tb, 0.0];
                }
            }
        }
        for q in &mut roots.q[..roots.n] {
            let back = rotate(hb, -q[1], &rotate(ha, -q[0], mu));
            q[2] = sp1_angle(hc, &self.u, &back);
        }
        Ok(roots)
    }
}

/// A unit vector ⊥ the unit vector `k`.
pub(crate) fn perpendicular(k: &V3) -> V3 {
    let seed = if k.x.abs() < 0.9 { V3::x() } else { V3::y() };
    (seed - k * k.dot(&seed)).normalize()
}
