//! Real roots of a polynomial of low degree on an interval, for the closed
//! forms of the step-1 families: the roots of the derivative split the
//! interval into pieces where the polynomial is monotone, each piece holds
//! at most one root, found by Newton's method kept inside its bracket.

/// The highest degree [`real_roots`] takes.
pub(super) const MAX_DEGREE: usize = 6;

/// The real roots of c\[0\] + c\[1\]·x + … + c\[n\]·xⁿ (n ≤ [`MAX_DEGREE`]) in
/// \[`lo`, `hi`\], ascending, appended to `out`. A double root (a tangent)
/// is reported once, where the polynomial's value is within its rounding
/// error of 0 at a root of the derivative. A polynomial that is 0
/// everywhere has no roots reported.
pub(super) fn real_roots(c: &[f64], lo: f64, hi: f64, out: &mut Vec<f64>) {
    let mut roots = [0.0; MAX_DEGREE];
    let n = roots_into(c, lo, hi, &mut roots);
    out.extend_from_slice(&roots[..n]);
}

/// [`real_roots`] into a fixed buffer, returning how many it found.
fn roots_into(c: &[f64], lo: f64, hi: f64, roots: &mut [f64; MAX_DEGREE]) -> usize {
    let Some(deg) = c.iter().rposition(|&x| x != 0.0) else {
        return 0;
    };
    assert!(deg <= MAX_DEGREE, "degree at most MAX_DEGREE");
    if !(lo.is_finite() && hi.is_finite()) || hi < lo || deg == 0 {
        return 0;
    }
    let c = &c[..=deg];
    // Pieces between the roots of the derivative are monotone.
    let mut derivative = [0.0; MAX_DEGREE];
    for (i, d) in derivative.iter_mut().enumerate().take(deg) {
        *d = (i + 1) as f64 * c[i + 1];
    }
    let mut critical = [0.0; MAX_DEGREE];
    let nc = roots_into(&derivative[..deg], lo, hi, &mut critical);
    let mut n = 0;
    let mut push = |x: f64, roots: &mut [f64; MAX_DEGREE]| {
        if n < MAX_DEGREE && (n == 0 || x > roots[n - 1]) {
            roots[n] = x;
            n += 1;
        }
    };
    let (mut a, mut fa) = (lo, value(c, lo));
    if fa == 0.0 {
        push(lo, roots);
    }
    for (i, &b) in critical[..nc].iter().chain([hi].iter()).enumerate() {
        let mut fb = value(c, b);
        if fb != 0.0 && i < nc && fb.abs() <= rounding(c, b) {
            fb = 0.0; // a tangent: 0 within rounding at a root of the derivative
        }
        if fb == 0.0 {
            push(b, roots);
        } else if fa != 0.0 && (fa < 0.0) != (fb < 0.0) {
            push(bracketed_root(c, a, fa, b), roots);
        }
        (a, fa) = (b, fb);
    }
    n
}

/// The polynomial's value at `x` (Horner).
fn value(c: &[f64], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |p, &ci| p * x + ci)
}

/// The value and the derivative at `x`.
fn value_and_slope(c: &[f64], x: f64) -> (f64, f64) {
    let (mut p, mut d) = (0.0, 0.0);
    for &ci in c.iter().rev() {
        d = d * x + p;
        p = p * x + ci;
    }
    (p, d)
}

/// A bound on the rounding error of [`value`] at `x`.
fn rounding(c: &[f64], x: f64) -> f64 {
    let size = c.iter().rev().fold(0.0, |s, &ci| s * x.abs() + ci.abs());
    4.0 * c.len() as f64 * f64::EPSILON * size
}

/// The root of a polynomial monotone on \[a, b\] whose value changes sign
/// there (`fa` at `a`): Newton steps, bisection where a step would leave
/// the bracket, until the bracket or the step reaches the resolution of f64.
fn bracketed_root(c: &[f64], mut a: f64, fa: f64, mut b: f64) -> f64 {
    let rising = fa < 0.0;
    let mut x = 0.5 * (a + b);
    for _ in 0..100 {
        let (p, d) = value_and_slope(c, x);
        if p == 0.0 {
            return x;
        }
        if (p < 0.0) == rising {
            a = x;
        } else {
            b = x;
        }
        let newton = x - p / d;
        let next = if newton > a && newton < b { newton } else { 0.5 * (a + b) };
        if next == x || !(b - a > 2.0 * f64::EPSILON * a.abs().max(b.abs())) {
            return next;
        }
        x = next;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The coefficients of ∏ (x − rᵢ), times `scale`.
    fn from_roots(rs: &[f64], scale: f64) -> Vec<f64> {
        let mut c = vec![scale];
        for &r in rs {
            let mut next = vec![0.0; c.len() + 1];
            for (i, &ci) in c.iter().enumerate() {
                next[i + 1] += ci;
                next[i] -= r * ci;
            }
            c = next;
        }
        c
    }

    #[test]
    fn finds_the_roots_of_random_products_of_linear_factors() {
        let mut rng = ChaCha8Rng::seed_from_u64(3601);
        for case in 0..20_000 {
            let deg = rng.random_range(1..=MAX_DEGREE);
            let mut rs: Vec<f64> = (0..deg).map(|_| rng.random_range(-3.0..3.0)).collect();
            rs.sort_by(f64::total_cmp);
            let scale = if rng.random_bool(0.5) { 1.0 } else { -0.01 };
            let c = from_roots(&rs, scale);
            let mut found = Vec::new();
            real_roots(&c, -4.0, 4.0, &mut found);
            // Roots closer than the polynomial's resolution may merge.
            for &r in &rs {
                let near = found.iter().any(|&f| (f - r).abs() < 1e-6);
                let crowded = rs.iter().filter(|&&o| (o - r).abs() < 1e-2).count() > 1;
                assert!(near || crowded, "case {case}: root {r} of {rs:?} not in {found:?}");
            }
            for &f in &found {
                let size = c.iter().rev().fold(0.0, |s, &ci| s * f64::abs(f) + f64::abs(ci));
                assert!(value(&c, f).abs() <= 1e-9 * size, "case {case}: {f} is not a root of {rs:?}");
            }
            assert!(found.windows(2).all(|w| w[0] < w[1]), "case {case}: {found:?} not ascending");
        }
    }

    #[test]
    fn reports_a_double_root_once_and_roots_on_the_bounds() {
        let mut found = Vec::new();
        real_roots(&from_roots(&[0.5, 0.5, -1.0], 1.0), -2.0, 2.0, &mut found);
        assert_eq!(found.len(), 2, "{found:?}");
        assert!((found[0] + 1.0).abs() < 1e-12 && (found[1] - 0.5).abs() < 1e-7, "{found:?}");
        found.clear();
        real_roots(&from_roots(&[-1.0, 2.0], 1.0), -1.0, 2.0, &mut found);
        assert_eq!(found, vec![-1.0, 2.0]);
        found.clear();
        real_roots(&[1.0, 0.0, 1.0], -5.0, 5.0, &mut found);
        real_roots(&[0.0, 0.0], -5.0, 5.0, &mut found);
        assert!(found.is_empty(), "{found:?}");
    }
}
