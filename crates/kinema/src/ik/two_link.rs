//! The planar two-link arm (shoulder and elbow in one plane), the closed
//! form several families reduce to: the elbow angle for a reach, and how far
//! outside the annulus a reach is.

use crate::math::FastMath;

/// A point outside the annulus \[|l1 − l2|, l1 + l2\] a planar two-link arm reaches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct AnnulusMiss {
    /// How far outside \[m\].
    pub by: f64,
    /// Radius of the boundary missed \[m\].
    pub radius: f64,
    /// Whether it is the outer boundary (else the inner one).
    pub outer: bool,
}

/// The elbow angle θ ∈ \[0, π\] of a planar two-link arm, with its sine and cosine.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ElbowAngle {
    pub angle: f64,
    pub sin: f64,
    pub cos: f64,
}

/// |Elbow angle| of a planar two-link arm with link lengths `l1`, `l2` whose
/// tip lies at distance `r` from the shoulder, by the half-angle form of the
/// law of cosines, tan²(θ/2) = ((l1+l2)² − r²)/(r² − (l1−l2)²), which stays
/// accurate near the stretched and folded arm where acos loses half the digits.
/// sin θ and cos θ come from the same half-angle tangent, without a further
/// sine/cosine evaluation. A point outside the annulus by more than `tol` is
/// an [`AnnulusMiss`].
pub(crate) fn two_link_elbow(r: f64, l1: f64, l2: f64, tol: f64) -> std::result::Result<ElbowAngle, AnnulusMiss> {
    let t = two_link_elbow_terms(r, l1, l2, tol)?;
    Ok(ElbowAngle { angle: 2.0 * t.half_y.fast_atan2(t.half_x), sin: t.sin, cos: t.cos })
}

/// [`two_link_elbow`] without its one `atan2`: the angle is
/// 2·atan2(`half_y`, `half_x`), left to the caller (a kernel that gathers
/// several angles into one [`crate::math::atan2_lanes`] call).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ElbowTerms {
    pub half_y: f64,
    pub half_x: f64,
    pub sin: f64,
    pub cos: f64,
}

/// The terms of [`two_link_elbow`] (same arguments, same misses).
#[inline]
pub(crate) fn two_link_elbow_terms(r: f64, l1: f64, l2: f64, tol: f64) -> std::result::Result<ElbowTerms, AnnulusMiss> {
    let (outer, inner) = (l1 + l2, (l1 - l2).abs());
    if r > outer + tol {
        return Err(AnnulusMiss { by: r - outer, radius: outer, outer: true });
    }
    if r < inner - tol {
        return Err(AnnulusMiss { by: inner - r, radius: inner, outer: false });
    }
    let num = ((outer - r) * (outer + r)).max(0.0);
    let den = ((r - inner) * (r + inner)).max(0.0);
    let sum = num + den;
    if sum == 0.0 {
        return Ok(ElbowTerms { half_y: 0.0, half_x: 1.0, sin: 0.0, cos: 1.0 });
    }
    // With t = tan(θ/2) = √(num/den): cos θ = (1 − t²)/(1 + t²), sin θ = 2t/(1 + t²).
    Ok(ElbowTerms {
        half_y: num.sqrt(),
        half_x: den.sqrt(),
        sin: 2.0 * (num * den).sqrt() / sum,
        cos: (den - num) / sum,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn two_link_elbow_sine_and_cosine_match_the_angle_and_the_law_of_cosines() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        for k in 0..20_000 {
            let (l1, l2): (f64, f64) = (rng.random_range(0.05..1.0), rng.random_range(0.05..1.0));
            let (inner, outer) = ((l1 - l2).abs(), l1 + l2);
            // Every fifth case on a boundary, where the half-angle form matters most.
            let r = match k % 5 {
                0 => outer,
                1 => inner,
                _ => rng.random_range(inner..outer),
            };
            let e = two_link_elbow(r, l1, l2, 1e-12).unwrap();
            let (s, c) = e.angle.sin_cos();
            assert!((e.sin - s).abs() < 1e-14 && (e.cos - c).abs() < 1e-14, "{l1} {l2} {r}: {e:?}");
            assert!(e.sin >= 0.0 && (0.0..=std::f64::consts::PI).contains(&e.angle));
            // The elbow puts the tip at distance r: r² = l1² + l2² + 2·l1·l2·cos θ.
            let r2 = l1 * l1 + l2 * l2 + 2.0 * l1 * l2 * e.cos;
            assert!((r2.max(0.0).sqrt() - r).abs() < 1e-7 * outer, "{l1} {l2} {r}: {r2}");
        }
        let miss = two_link_elbow(2.1, 1.0, 1.0, 1e-12).unwrap_err();
        assert!(miss.outer && (miss.by - 0.1).abs() < 1e-12);
        let miss = two_link_elbow(0.1, 1.0, 0.5, 1e-12).unwrap_err();
        assert!(!miss.outer && (miss.by - 0.4).abs() < 1e-12);
    }
}
