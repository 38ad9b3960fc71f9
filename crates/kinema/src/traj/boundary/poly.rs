//! Real roots of a polynomial of low degree on an interval, for the closed
//! forms of the step-1 families: the roots of the derivative split the
//! interval into pieces where the polynomial is monotone, and each piece
//! whose ends differ in sign holds one root — in closed form for degree
//! ≤ 2, above that by Newton's method kept inside its bracket.

/// The highest degree [`real_roots`] takes.
pub(super) const MAX_DEGREE: usize = 6;

/// Up to [`MAX_DEGREE`] roots, ascending, kept on the stack: the searches
/// call [`real_roots`] a few hundred times per synchronised motion.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Roots {
    xs: [f64; MAX_DEGREE],
    n: usize,
}

impl Roots {
    /// Appends `x` if it is above the last root (a root on the end of one
    /// piece is also the start of the next).
    fn push(&mut self, x: f64) {
        if self.n < MAX_DEGREE && (self.n == 0 || x > self.xs[self.n - 1]) {
            self.xs[self.n] = x;
            self.n += 1;
        }
    }

    pub fn as_slice(&self) -> &[f64] {
        &self.xs[..self.n]
    }
}

/// The real roots of c\[0\] + c\[1\]·x + … + c\[n\]·xⁿ (n ≤ [`MAX_DEGREE`]) in
/// \[`lo`, `hi`\], ascending. A double root (a tangent) is reported once,
/// where the polynomial's value is within its rounding error of 0 at a root
/// of the derivative. A polynomial that is 0 everywhere has no roots reported.
pub(super) fn real_roots(c: &[f64], lo: f64, hi: f64) -> Roots {
    let mut roots = Roots::default();
    let Some(deg) = c.iter().rposition(|&x| x != 0.0) else {
        return roots;
    };
    assert!(deg <= MAX_DEGREE, "degree at most MAX_DEGREE");
    if !(lo.is_finite() && hi.is_finite()) || hi < lo || deg == 0 {
        return roots;
    }
    let c = &c[..=deg];
    if deg >= 3 && clearly_without_roots(c, lo, hi) {
        return roots; // most of the valley families' quartics, without their pieces
    }
    let critical = critical_points(c, lo, hi);
    let critical = critical.as_slice();
    let (mut a, mut fa) = (lo, value(c, lo));
    if fa == 0.0 {
        roots.push(lo);
    }
    for (i, &b) in critical.iter().chain([hi].iter()).enumerate() {
        let mut fb = value(c, b);
        if fb != 0.0 && i < critical.len() && fb.abs() <= rounding(c, b) {
            fb = 0.0; // a tangent: 0 within rounding at a root of the derivative
        }
        if fb == 0.0 {
            roots.push(b);
        } else if fa != 0.0 && (fa < 0.0) != (fb < 0.0) {
            roots.push(root_in_piece(c, a, fa, b, fb));
        }
        (a, fa) = (b, fb);
    }
    roots
}

/// Whether `c` is clearly far from 0 throughout \[`lo`, `hi`\]: in its
/// Taylor expansion about the middle, the value there outweighs the other
/// terms at the half-width, with room (1e-12 of the coefficients' size) for
/// rounding, so no root and no tangent within rounding can be missed.
fn clearly_without_roots(c: &[f64], lo: f64, hi: f64) -> bool {
    with_known_len(c, |c| clearly_without_roots_of(c, lo, hi))
}

#[inline(always)]
fn clearly_without_roots_of(c: &[f64], lo: f64, hi: f64) -> bool {
    let (m, r) = (0.5 * (lo + hi), 0.5 * (hi - lo));
    let n = c.len() - 1;
    let mut b = [0.0; MAX_DEGREE + 1];
    b[..=n].copy_from_slice(c);
    for i in 0..n {
        for k in (i..n).rev() {
            b[k] += m * b[k + 1];
        }
    }
    let tail = b[1..=n].iter().rev().fold(0.0, |s, &bk| (s + bk.abs()) * r);
    let reach = lo.abs().max(hi.abs());
    let size = c.iter().rev().fold(0.0, |s, &ck| s * reach + ck.abs());
    b[0].abs() > tail + 1e-12 * size
}

/// The roots of the derivative of `c` (degree ≥ 1) in \[`lo`, `hi`\]: the
/// ends of the pieces where `c` is monotone.
fn critical_points(c: &[f64], lo: f64, hi: f64) -> Roots {
    let deg = c.len() - 1;
    let mut critical = Roots::default();
    match deg {
        1 => {}
        2 => {
            let x = -c[1] / (2.0 * c[2]);
            if x >= lo && x <= hi {
                critical.push(x);
            }
        }
        _ => {
            let mut derivative = [0.0; MAX_DEGREE];
            for (i, d) in derivative.iter_mut().enumerate().take(deg) {
                *d = (i + 1) as f64 * c[i + 1];
            }
            critical = real_roots(&derivative[..deg], lo, hi);
        }
    }
    critical
}

/// The root of `c` on a piece \[a, b\] where it is monotone and changes sign
/// (`fa`, `fb` its values at the ends): in closed form for degree ≤ 2 (kept
/// if rounding leaves it inside the piece), else by [`bracketed_root`].
fn root_in_piece(c: &[f64], a: f64, fa: f64, b: f64, fb: f64) -> f64 {
    let inside = |x: f64| x >= a && x <= b;
    match c.len() - 1 {
        1 => Some(-c[0] / c[1]).filter(|&x| inside(x)),
        2 => quadratic_roots(c).into_iter().flatten().find(|&x| inside(x)),
        _ => None,
    }
    .unwrap_or_else(|| bracketed_root(c, a, fa, b, fb))
}

/// The two real roots of c\[0\] + c\[1\]·x + c\[2\]·x², computed without
/// cancellation (the larger in size from q = −(c₁ + sign(c₁)·√disc)/2, the
/// other as c₀/q); `None` where the discriminant is negative or q is 0.
fn quadratic_roots(c: &[f64]) -> [Option<f64>; 2] {
    let disc = c[1] * c[1] - 4.0 * c[2] * c[0];
    if !(disc >= 0.0) {
        return [None, None];
    }
    let q = -0.5 * (c[1] + disc.sqrt().copysign(c[1]));
    if q == 0.0 {
        return [None, None];
    }
    [Some(q / c[2]), Some(c[0] / q)]
}

/// `f(c)` with the length of `c` known to the compiler for the lengths the
/// families use (degree 2 to 4), so that the loops over the coefficients
/// are unrolled and kept in registers; the same arithmetic either way.
#[inline(always)]
fn with_known_len<R>(c: &[f64], f: impl Fn(&[f64]) -> R) -> R {
    match c.len() {
        5 => f(&c[..5]),
        4 => f(&c[..4]),
        3 => f(&c[..3]),
        _ => f(c),
    }
}

/// The polynomial's value at `x` (Horner).
fn value(c: &[f64], x: f64) -> f64 {
    with_known_len(c, |c| c.iter().rev().fold(0.0, |p, &ci| p * x + ci))
}

/// The value and the derivative at `x`.
#[inline(always)]
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
    let size = with_known_len(c, |c| c.iter().rev().fold(0.0, |s, &ci| s * x.abs() + ci.abs()));
    4.0 * c.len() as f64 * f64::EPSILON * size
}

/// The root of a polynomial monotone on \[a, b\] whose value changes sign
/// there (`fa` at `a`, `fb` at `b`): Newton steps from the secant's root,
/// bisection where a step would leave the bracket, until a step or the
/// bracket reaches the resolution of f64.
fn bracketed_root(c: &[f64], a: f64, fa: f64, b: f64, fb: f64) -> f64 {
    with_known_len(c, |c| bracketed_root_of(c, a, fa, b, fb))
}

#[inline(always)]
fn bracketed_root_of(c: &[f64], mut a: f64, fa: f64, mut b: f64, fb: f64) -> f64 {
    let rising = fa < 0.0;
    let mut x = a - fa * (b - a) / (fb - fa);
    if !(x > a && x < b) {
        x = 0.5 * (a + b);
    }
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
        let resolution = 2.0 * f64::EPSILON * a.abs().max(b.abs());
        if !((next - x).abs() > resolution && b - a > resolution) {
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

    /// The root finder the closed forms replaced, kept as the reference:
    /// the same pieces, each root by Newton's method from the piece's middle
    /// (bisection where a step would leave the bracket) at every degree.
    fn reference_roots(c: &[f64], lo: f64, hi: f64) -> Vec<f64> {
        let Some(deg) = c.iter().rposition(|&x| x != 0.0) else {
            return Vec::new();
        };
        if !(lo.is_finite() && hi.is_finite()) || hi < lo || deg == 0 {
            return Vec::new();
        }
        let c = &c[..=deg];
        let derivative: Vec<f64> = (0..deg).map(|i| (i + 1) as f64 * c[i + 1]).collect();
        let critical = reference_roots(&derivative, lo, hi);
        let mut roots: Vec<f64> = Vec::new();
        let push = |x: f64, roots: &mut Vec<f64>| {
            if roots.last().is_none_or(|&l| x > l) {
                roots.push(x);
            }
        };
        let (mut a, mut fa) = (lo, value(c, lo));
        if fa == 0.0 {
            push(lo, &mut roots);
        }
        for (i, &b) in critical.iter().chain([hi].iter()).enumerate() {
            let mut fb = value(c, b);
            if fb != 0.0 && i < critical.len() && fb.abs() <= rounding(c, b) {
                fb = 0.0;
            }
            if fb == 0.0 {
                push(b, &mut roots);
            } else if fa != 0.0 && (fa < 0.0) != (fb < 0.0) {
                push(reference_bracketed(c, a, fa, b), &mut roots);
            }
            (a, fa) = (b, fb);
        }
        roots
    }

    fn reference_bracketed(c: &[f64], mut a: f64, fa: f64, mut b: f64) -> f64 {
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

    fn found(c: &[f64], lo: f64, hi: f64) -> Vec<f64> {
        real_roots(c, lo, hi).as_slice().to_vec()
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
            let found = found(&c, -4.0, 4.0);
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

    /// Thousands of random polynomials of each degree, built from known
    /// roots (some doubled, some on an end of the interval, some outside
    /// it): every root the reference finds is found (within 1e-7 of the
    /// polynomial's scale), nothing else is, and every known simple root
    /// inside the interval is among them.
    #[test]
    fn finds_every_root_the_reference_finds() {
        let mut rng = ChaCha8Rng::seed_from_u64(3604);
        for deg in 1..=MAX_DEGREE {
            for case in 0..4000 {
                let mut rs: Vec<f64> = (0..deg).map(|_| rng.random_range(-3.0..3.0)).collect();
                if deg >= 2 && rng.random_bool(0.3) {
                    rs[1] = rs[0]; // a double root
                }
                let (mut lo, mut hi) = (rng.random_range(-4.0..0.0), rng.random_range(0.0..4.0));
                match rng.random_range(0..4) {
                    0 => lo = rs[deg - 1],
                    1 => hi = rs[deg - 1],
                    _ => {}
                }
                let (lo, hi) = (lo.min(hi), lo.max(hi));
                let scale = if rng.random_bool(0.5) { 1.0 } else { -0.01 };
                let c = from_roots(&rs, scale);
                let (fast, reference) = (found(&c, lo, hi), reference_roots(&c, lo, hi));
                let close = |x: f64, ys: &[f64]| ys.iter().any(|&y| (x - y).abs() <= 1e-7);
                let what = format!("degree {deg} case {case}: roots {rs:?} on [{lo}, {hi}]");
                assert!(reference.iter().all(|&r| close(r, &fast)), "{what}: {fast:?} misses some of {reference:?}");
                assert!(fast.iter().all(|&f| close(f, &reference)), "{what}: {fast:?} has more than {reference:?}");
                for &r in &rs {
                    // A root on an end may move just outside it in the rounded coefficients.
                    let simple = rs.iter().filter(|&&o| (o - r).abs() < 1e-2).count() == 1;
                    if simple && r > lo + 1e-6 && r < hi - 1e-6 {
                        assert!(close(r, &fast), "{what}: {r} not in {fast:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn reports_a_double_root_once_and_roots_on_the_bounds() {
        let found_in = |c: &[f64], lo, hi| found(c, lo, hi);
        let double = found_in(&from_roots(&[0.5, 0.5, -1.0], 1.0), -2.0, 2.0);
        assert_eq!(double.len(), 2, "{double:?}");
        assert!((double[0] + 1.0).abs() < 1e-12 && (double[1] - 0.5).abs() < 1e-7, "{double:?}");
        assert_eq!(found_in(&from_roots(&[-1.0, 2.0], 1.0), -1.0, 2.0), vec![-1.0, 2.0]);
        assert!(found_in(&from_roots(&[1.0, 1.0], 1.0), -5.0, 5.0) == vec![1.0]);
        assert!(found_in(&[1.0, 0.0, 1.0], -5.0, 5.0).is_empty());
        assert!(found_in(&[0.0, 0.0], -5.0, 5.0).is_empty());
    }
}
