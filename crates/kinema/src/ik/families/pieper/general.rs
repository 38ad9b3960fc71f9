//! θ3 of Pieper's general shoulder (a1 ≠ 0, α1 ≠ 0 mod 180°) in closed form.
//!
//! The wrist centre in frame 1 before the rotation θ2 is g(θ3), whose
//! components are of degree 1 in (cos θ3, sin θ3). With p the wrist centre
//! in the DH base frame, R = |p − d1·z|² − a1² and z its height above d1,
//! eliminating θ1 and θ2 leaves
//!
//! F(θ3) = ((R − |g|²) / (2·a1))² + ((z − cα1·g_z) / sα1)² − (g_x² + g_y²) = 0,
//!
//! a trigonometric polynomial of degree 2. Its coefficients are fixed sums
//! of products of g's, so [`GeneralShoulder`] keeps those products and a
//! solve only combines them with R and z; as a conic in (cos θ3, sin θ3)
//! the equation is a quartic in a tangent half-angle ([`circle_conic`]).

use nalgebra::{Matrix2, Vector2};

use super::Link;
use crate::ik::geo::subproblems::circle_conic;
use crate::ik::wrap_angle;
use crate::math::FastMath;

/// c + a·cos θ + b·sin θ, as [c, a, b].
type Trig1 = [f64; 3];

/// c + a1·cos θ + b1·sin θ + a2·cos 2θ + b2·sin 2θ, as [c, a1, b1, a2, b2].
pub(super) type Trig2 = [f64; 5];

/// The product of two polynomials of degree 1 (cos²θ = (1 + cos 2θ)/2,
/// sin²θ = (1 − cos 2θ)/2, 2·sin θ·cos θ = sin 2θ).
fn times(x: Trig1, y: Trig1) -> Trig2 {
    let [x0, xa, xb] = x;
    let [y0, ya, yb] = y;
    [
        x0 * y0 + 0.5 * (xa * ya + xb * yb),
        x0 * ya + xa * y0,
        x0 * yb + xb * y0,
        0.5 * (xa * ya - xb * yb),
        0.5 * (xa * yb + xb * ya),
    ]
}

/// Σ wᵢ·termᵢ, a degree-1 term entering the constant and first harmonics only.
fn combine(terms: &[(f64, &[f64])]) -> Trig2 {
    let mut out = [0.0; 5];
    for (w, t) in terms {
        for (o, v) in out.iter_mut().zip(t.iter()) {
            *o += w * v;
        }
    }
    out
}

/// The products of g(θ3) that F is made of, from the links.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct GeneralShoulder {
    /// |g|², of degree 1 (the squares of the θ3-dependent parts sum to a constant).
    norm2: Trig1,
    /// (|g|²)².
    norm2_sq: Trig2,
    /// g_z.
    gz: Trig1,
    /// g_z².
    gz_sq: Trig2,
    /// g_x² + g_y².
    horizontal_sq: Trig2,
    a1: f64,
    ca1: f64,
    sa1: f64,
}

impl GeneralShoulder {
    pub(super) fn new(links: &[Link; 6]) -> Self {
        let [l1, l2, l3, l4, ..] = *links;
        // g = (f1 + a2, cα2·f2 − sα2·f3, sα2·f2 + cα2·f3 + d2) with
        // f1 = a3·c3 + d4·sα3·s3, f2 = a3·s3 − d4·sα3·c3, f3 = d3 + d4·cα3.
        let (k, f3) = (l4.d * l3.sa, l3.d + l4.d * l3.ca);
        let gx = [l2.a, l3.a, k];
        let gy = [-l2.sa * f3, -l2.ca * k, l2.ca * l3.a];
        let gz = [l2.ca * f3 + l2.d, -l2.sa * k, l2.sa * l3.a];
        let (gx_sq, gy_sq, gz_sq) = (times(gx, gx), times(gy, gy), times(gz, gz));
        let horizontal_sq = combine(&[(1.0, &gx_sq), (1.0, &gy_sq)]);
        let full = combine(&[(1.0, &horizontal_sq), (1.0, &gz_sq)]);
        let norm2 = [full[0], full[1], full[2]];
        GeneralShoulder {
            norm2,
            norm2_sq: times(norm2, norm2),
            gz,
            gz_sq,
            horizontal_sq,
            a1: l1.a,
            ca1: l1.ca,
            sa1: l1.sa,
        }
    }

    /// F's coefficients for the wrist centre at squared distance `r2` from
    /// the point d1 up axis 1 and height `z` above it.
    pub(super) fn condition(&self, r2: f64, z: f64) -> Trig2 {
        let r = r2 - self.a1 * self.a1;
        let (u, v) = (0.25 / (self.a1 * self.a1), 1.0 / (self.sa1 * self.sa1));
        let constant = [r * r * u + z * z * v, 0.0, 0.0];
        combine(&[
            (1.0, &constant),
            (-2.0 * r * u, &self.norm2),
            (u, &self.norm2_sq),
            (-2.0 * z * self.ca1 * v, &self.gz),
            (self.ca1 * self.ca1 * v, &self.gz_sq),
            (-1.0, &self.horizontal_sq),
        ])
    }
}

/// The value and the derivative of `c` at θ.
fn value_and_slope(c: &Trig2, theta: f64) -> (f64, f64) {
    let [c0, a1, b1, a2, b2] = *c;
    let ((s1, c1), (s2, c2)) = (theta.fast_sin_cos(), (2.0 * theta).fast_sin_cos());
    (c0 + a1 * c1 + b1 * s1 + a2 * c2 + b2 * s2, -a1 * s1 + b1 * c1 - 2.0 * a2 * s2 + 2.0 * b2 * c2)
}

/// The real roots θ \[rad\] in (−π, π], increasing, of the polynomial `c`,
/// written to `out`; returns how many. One Newton step on `c` refines each
/// (kept only when it lowers |F|, which it does not across a double root).
pub(super) fn roots(c: &Trig2, out: &mut [f64; 4]) -> usize {
    let [c0, a1, b1, a2, b2] = *c;
    // a2·cos 2θ + b2·sin 2θ = a2·(cos² − sin²) + 2·b2·cos·sin.
    let n = circle_conic(&Matrix2::new(a2, b2, b2, -a2), &Vector2::new(a1, b1), c0, out);
    for t in &mut out[..n] {
        let (f, slope) = value_and_slope(c, *t);
        let next = *t - f / slope;
        if next.is_finite() && (next - *t).abs() < 1e-6 && value_and_slope(c, next).0.abs() < f.abs() {
            *t = wrap_angle(next);
        }
    }
    out[..n].sort_by(f64::total_cmp);
    n
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;

    fn random_link(rng: &mut ChaCha8Rng) -> Link {
        let alpha: f64 = rng.random_range(-PI..PI);
        Link {
            d: rng.random_range(-0.5..0.5),
            a: rng.random_range(-0.5..0.5),
            ca: alpha.cos(),
            sa: alpha.sin(),
            offset: 0.0,
        }
    }

    /// F straight from its definition, g(θ3) by the link transforms: the
    /// plain reference the precomputed coefficients are tested against.
    fn f_direct(links: &[Link; 6], r2: f64, z: f64, t3: f64) -> f64 {
        let [l1, l2, l3, l4, ..] = *links;
        let (s3, c3) = t3.sin_cos();
        let (f1, f2, f3) = (l3.a * c3 + l4.d * l3.sa * s3, l3.a * s3 - l4.d * l3.sa * c3, l3.d + l4.d * l3.ca);
        let g = [f1 + l2.a, l2.ca * f2 - l2.sa * f3, l2.sa * f2 + l2.ca * f3 + l2.d];
        let norm2 = g.iter().map(|v| v * v).sum::<f64>();
        let p = (r2 - norm2 - l1.a * l1.a) / (2.0 * l1.a);
        let q = (z - l1.ca * g[2]) / l1.sa;
        p * p + q * q - (g[0] * g[0] + g[1] * g[1])
    }

    #[test]
    fn the_coefficients_give_f_as_its_definition_does() {
        let mut rng = ChaCha8Rng::seed_from_u64(0x9e7);
        for _ in 0..2000 {
            let links: [Link; 6] = std::array::from_fn(|_| random_link(&mut rng));
            if links[0].a.abs() < 0.05 || links[0].sa.abs() < 0.2 {
                continue;
            }
            let shoulder = GeneralShoulder::new(&links);
            let (r2, z) = (rng.random_range(0.0..1.5), rng.random_range(-1.0..1.0));
            let c = shoulder.condition(r2, z);
            for _ in 0..5 {
                let t = rng.random_range(-PI..PI);
                let (want, got) = (f_direct(&links, r2, z, t), value_and_slope(&c, t).0);
                let scale = 1.0 + c.iter().map(|v| v.abs()).sum::<f64>();
                assert!((want - got).abs() <= 1e-12 * scale, "{want} vs {got} (scale {scale})");
            }
        }
    }

    /// Against a scan of 20 000 points: every sign change of F lies within a
    /// step of a returned root, and every returned root makes F vanish to
    /// rounding. Half of the polynomials are built with a double root.
    #[test]
    fn roots_are_every_sign_change_of_a_dense_scan() {
        let mut rng = ChaCha8Rng::seed_from_u64(0x2007);
        const N: usize = 20_000;
        let step = 2.0 * PI / N as f64;
        for case in 0..500 {
            let mut c: Trig2 = std::array::from_fn(|_| rng.random_range(-1.0..1.0));
            if case % 2 == 1 {
                // Shift so that a local minimum touches zero: a double root.
                let t0 = rng.random_range(-PI..PI);
                let (mut lo, mut best) = (t0, f64::INFINITY);
                for i in 0..N {
                    let t = -PI + i as f64 * step;
                    let v = value_and_slope(&c, t).0;
                    if v < best {
                        (lo, best) = (t, v);
                    }
                }
                c[0] -= value_and_slope(&c, lo).0;
            }
            let mut out = [0.0; 4];
            let n = roots(&c, &mut out);
            let scale = c.iter().map(|v| v.abs()).sum::<f64>();
            for &t in &out[..n] {
                assert!(value_and_slope(&c, t).0.abs() <= 1e-9 * scale, "case {case}: F({t}) ≠ 0");
            }
            for i in 0..N {
                let (a, b) = (-PI + i as f64 * step, -PI + (i + 1) as f64 * step);
                let (fa, fb) = (value_and_slope(&c, a).0, value_and_slope(&c, b).0);
                if (fa > 0.0) != (fb > 0.0) && fa.abs().min(fb.abs()) > 1e-9 * scale {
                    assert!(
                        out[..n].iter().any(|r| wrap_angle(r - a).abs() <= 2.0 * step),
                        "case {case}: sign change at {a} missed; roots {:?}",
                        &out[..n]
                    );
                }
            }
        }
    }
}
