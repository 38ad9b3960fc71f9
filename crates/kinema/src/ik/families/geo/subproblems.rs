//! The Paden–Kahan subproblems: small geometric equations in one or two
//! rotation angles with closed-form solutions, from which the geometric IK
//! families are assembled.
//!
//! `rot(k, θ)` is the rotation by θ about the unit axis `k` (right hand).
//! Every subproblem returns all its solutions when it has some, or else the
//! least-squares one, with [`Angles::exact`] false and [`Angles::miss`] the
//! residual of that least-squares answer in the subproblem's own equation.
//! Data within a relative [`EXACT_TOL`] of solvable (a target on a reach
//! boundary, rounding in the caller's arithmetic) counts as solvable, and its
//! double root is returned twice so branch counts stay fixed.
//!
//! Axes must be unit vectors; a subproblem whose unknown does not change the
//! quantity it constrains (e.g. `p` on the axis) returns θ = 0, exact when
//! the equation holds for every θ.

use std::f64::consts::PI;

use nalgebra::{Matrix3, Vector3};

use crate::ik::wrap_angle;
use crate::math::FastMath;

type V3 = Vector3<f64>;

/// Relative tolerance below which a subproblem's data counts as solvable.
pub const EXACT_TOL: f64 = 1e-12;

/// Up to two angles solving a subproblem (or one least-squares angle).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Angles {
    theta: [f64; 2],
    len: usize,
    /// Whether the angles solve the equation (within [`EXACT_TOL`]).
    pub exact: bool,
    /// Residual of the returned angles in the subproblem's equation (0 when
    /// exact up to rounding) \[the equation's unit: m or rad\].
    pub miss: f64,
}

impl Angles {
    /// The angles \[rad\], each in (−π, π].
    pub fn as_slice(&self) -> &[f64] {
        &self.theta[..self.len]
    }

    /// The first angle \[rad\].
    pub fn first(&self) -> f64 {
        self.theta[0]
    }

    fn one(theta: f64, exact: bool, miss: f64) -> Self {
        Angles { theta: [theta, theta], len: 1, exact, miss }
    }
}

/// `rot(k, θ)` by Rodrigues' formula (`k` a unit vector).
pub fn rot(k: &V3, theta: f64) -> Matrix3<f64> {
    let (s, c) = theta.fast_sin_cos();
    let kx = k.cross_matrix();
    Matrix3::identity() + kx * s + kx * kx * (1.0 - c)
}

/// `rot(k, θ)·p` without forming the matrix.
pub fn rotate(k: &V3, theta: f64, p: &V3) -> V3 {
    rotate_sc(k, theta.fast_sin_cos(), p)
}

/// [`rotate`] given (sin θ, cos θ), for an angle that turns several vectors.
pub fn rotate_sc(k: &V3, (s, c): (f64, f64), p: &V3) -> V3 {
    p * c + k.cross(p) * s + k * (k.dot(p) * (1.0 - c))
}

/// Solutions θ of a·cos θ + b·sin θ = c; `scale` sets the tolerance
/// (|c| may exceed √(a² + b²) by [`EXACT_TOL`]·`scale` and still count).
fn trig(a: f64, b: f64, c: f64, scale: f64) -> Angles {
    let tol = EXACT_TOL * scale;
    let r = a.fast_hypot(b);
    if !(r.is_finite() && c.is_finite() && tol.is_finite()) {
        return Angles::one(0.0, false, f64::INFINITY);
    }
    if r <= tol {
        // θ does not enter: every θ solves it or none does.
        return Angles::one(0.0, c.abs() <= tol, c.abs());
    }
    let phi = b.fast_atan2(a);
    let excess = c.abs() - r;
    if excess > 0.0 {
        let theta = wrap_angle(if c >= 0.0 { phi } else { phi + PI });
        if excess <= tol {
            return Angles { theta: [theta, theta], len: 2, exact: true, miss: excess };
        }
        return Angles::one(theta, false, excess);
    }
    // A gap within rounding of the double root is the double root: the
    // equation is flat there, so √(rounding) would become an error in θ.
    if r - c.abs() <= 4.0 * f64::EPSILON * scale.max(r) {
        let theta = wrap_angle(if c >= 0.0 { phi } else { phi + PI });
        return Angles { theta: [theta, theta], len: 2, exact: true, miss: 0.0 };
    }
    // The half-width of the solution pair as atan2(√(r² − c²), c): accurate
    // also near the double root, where acos(c/r) loses half the digits.
    let delta = ((r - c.abs()) * (r + c.abs())).sqrt().fast_atan2(c);
    Angles { theta: [wrap_angle(phi + delta), wrap_angle(phi - delta)], len: 2, exact: true, miss: 0.0 }
}

/// Subproblem 1: θ with `rot(k, θ)·p = q`. Solvable when p and q have the
/// same component along k and the same distance from it; otherwise the θ
/// that aligns their projections on the plane ⊥ k (least squares). With p or
/// q on the axis, θ = 0.
///
/// # Examples
/// ```
/// use kinema::ik::geo::subproblems::{rotate, sp1};
/// use kinema::nalgebra::Vector3;
/// let (k, p) = (Vector3::new(0.0, 0.0, 1.0), Vector3::new(1.0, 2.0, 3.0));
/// let q = rotate(&k, 0.7, &p);
/// let a = sp1(&k, &p, &q);
/// assert!(a.exact && (a.first() - 0.7).abs() < 1e-12);
/// ```
pub fn sp1(k: &V3, p: &V3, q: &V3) -> Angles {
    let theta = sp1_angle(k, p, q);
    let miss = (rotate(k, theta, p) - q).norm();
    Angles::one(theta, miss <= EXACT_TOL * (1.0 + p.norm() + q.norm()), miss)
}

/// [`sp1`]'s angle alone, without the residual: for a caller that knows
/// the equation is solvable (or takes the least-squares angle anyway).
pub fn sp1_angle(k: &V3, p: &V3, q: &V3) -> f64 {
    let pp = p - k * k.dot(p);
    let qp = q - k * k.dot(q);
    k.dot(&pp.cross(&qp)).fast_atan2(pp.dot(&qp))
}

/// Subproblem 2: (θ1, θ2) with `rot(k1, θ1)·p1 = rot(k2, θ2)·p2`, for
/// non-parallel `k1`, `k2`. Both sides are the point c on the circle of p1
/// about k1 and on the circle of p2 about k2: up to two such points, each
/// giving one pair by [`sp1`]. Without an intersection (or with |p1| ≠ |p2|)
/// the pair for the point nearest to both circles.
///
/// Returns (θ1 values, θ2 values), paired by index.
///
/// # Examples
/// ```
/// use kinema::ik::geo::subproblems::{rotate, sp2};
/// use kinema::nalgebra::Vector3;
/// let (k1, k2) = (Vector3::z(), Vector3::x());
/// let p2 = Vector3::new(0.3, -0.5, 0.8);
/// let c = rotate(&k2, 1.1, &p2);
/// let p1 = rotate(&k1, -0.4, &c);
/// let (t1, t2) = sp2(&k1, &p1, &k2, &p2);
/// assert!(t1.exact && t2.exact);
/// assert!(t1.as_slice().iter().zip(t2.as_slice()).any(|(a, b)| (a - 0.4).abs() < 1e-12 && (b - 1.1).abs() < 1e-12));
/// ```
pub fn sp2(k1: &V3, p1: &V3, k2: &V3, p2: &V3) -> (Angles, Angles) {
    let s = k1.dot(k2);
    let n = k1.cross(k2);
    let det = n.norm_squared();
    let (a1, a2) = (k1.dot(p1), k2.dot(p2));
    // c = α·k1 + β·k2 + γ·n with c·k1 = a1, c·k2 = a2 and |c|² = |p|².
    let alpha = (a1 - s * a2) / det;
    let beta = (a2 - s * a1) / det;
    let base = k1 * alpha + k2 * beta;
    let rho2 = 0.5 * (p1.norm_squared() + p2.norm_squared());
    let g2 = (rho2 - base.norm_squared()) / det;
    let scale = rho2 + base.norm_squared();
    let cands: [V3; 2];
    let len;
    if g2 >= 0.0 || -g2 * det <= EXACT_TOL * scale {
        let g = g2.max(0.0).sqrt();
        cands = [base + n * g, base - n * g];
        len = 2;
    } else {
        cands = [base, base];
        len = 1;
    }
    let mut t1 = [0.0; 2];
    let mut t2 = [0.0; 2];
    let mut miss = 0.0f64;
    for i in 0..len {
        t1[i] = sp1(k1, p1, &cands[i]).first();
        t2[i] = sp1(k2, p2, &cands[i]).first();
        let m = (rotate(k1, t1[i], p1) - rotate(k2, t2[i], p2)).norm();
        // Not f64::max, which would drop a NaN.
        if !(m <= miss) {
            miss = m;
        }
    }
    let same_radius = (p1.norm_squared() - p2.norm_squared()).abs() <= EXACT_TOL * scale;
    let exact = len == 2 && same_radius && miss.is_finite();
    (Angles { theta: t1, len, exact, miss }, Angles { theta: t2, len, exact, miss })
}

/// Subproblem 3: θ with |`rot(k, θ)·p1` − `p2`| = `d` (`d` ≥ 0, \[m\]): up to
/// two; otherwise the θ whose distance is nearest to `d`.
///
/// # Examples
/// ```
/// use kinema::ik::geo::subproblems::{rotate, sp3};
/// use kinema::nalgebra::Vector3;
/// let (k, p1, p2) = (Vector3::y(), Vector3::new(1.0, 0.2, 0.0), Vector3::new(0.0, -0.3, 2.0));
/// let d = (rotate(&k, -2.0, &p1) - p2).norm();
/// let a = sp3(&k, &p1, &p2, d);
/// assert!(a.exact && a.as_slice().iter().any(|t| (t + 2.0).abs() < 1e-12));
/// ```
pub fn sp3(k: &V3, p1: &V3, p2: &V3, d: f64) -> Angles {
    // |rot·p1 − p2|² = |p1|² + |p2|² − 2·p2·rot·p1, with
    // p2·rot·p1 = (k·p1)(k·p2) + cos θ·(p2·p1⊥) + sin θ·(p2·(k × p1⊥)).
    let pp = p1 - k * k.dot(p1);
    let a = p2.dot(&pp);
    let b = p2.dot(&k.cross(&pp));
    let c = 0.5 * (p1.norm_squared() + p2.norm_squared() - d * d) - k.dot(p1) * k.dot(p2);
    let scale = p1.norm_squared() + p2.norm_squared() + d * d;
    let mut out = trig(a, b, c, scale);
    if !out.exact {
        out.miss = ((rotate(k, out.first(), p1) - p2).norm() - d).abs();
    }
    out
}

/// Subproblem 4: θ with `h`ᵀ·`rot(k, θ)`·`p` = `d` (the height of the
/// rotated point along h): up to two; otherwise the θ nearest to it.
///
/// # Examples
/// ```
/// use kinema::ik::geo::subproblems::{rotate, sp4};
/// use kinema::nalgebra::Vector3;
/// let (h, k, p) = (Vector3::new(0.0, 0.6, 0.8), Vector3::x(), Vector3::new(0.5, 1.0, -0.4));
/// let d = h.dot(&rotate(&k, 2.5, &p));
/// let a = sp4(&h, &k, &p, d);
/// assert!(a.exact && a.as_slice().iter().any(|t| (t - 2.5).abs() < 1e-12));
/// ```
pub fn sp4(h: &V3, k: &V3, p: &V3, d: f64) -> Angles {
    let pp = p - k * k.dot(p);
    let a = h.dot(&pp);
    let b = h.dot(&k.cross(&pp));
    let c = d - h.dot(k) * k.dot(p);
    trig(a, b, c, p.norm() + d.abs())
}

/// Up to four solutions (θ1, θ2, θ3) of [`sp5`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Triples {
    theta: [[f64; 3]; 4],
    len: usize,
}

impl Triples {
    /// The solutions \[rad\], each angle in (−π, π].
    pub fn as_slice(&self) -> &[[f64; 3]] {
        &self.theta[..self.len]
    }
}

/// Subproblem 5: (θ1, θ2, θ3) with
/// `p0 + rot(k1, θ1)·p1 = rot(k2, θ2)·(p2 + rot(k3, θ3)·p3)` — the position
/// of a point carried by three revolute joints with skew axes. Up to four
/// solutions; none when there is no exact one (no least-squares answer).
///
/// Derivation: rot(k2, θ2) keeps both the component along k2 and the norm,
/// so with v = p0 + rot(k1, θ1)·p1 and w = p2 + rot(k3, θ3)·p3,
/// k2·v = k2·w and |v|² = |w|². Each side is affine in
/// x1 = (cos θ1, sin θ1) and x3 = (cos θ3, sin θ3): two linear equations
/// A·x1 + B·x3 = d. The better-conditioned of A, B is inverted, leaving a
/// conic in the other unit vector (|x3|² = 1 with x3 = B⁻¹(d − A·x1)); its
/// intersections with the unit circle are the roots of a quartic in the
/// tangent of the half angle ([`circle_conic`]). Then θ2 by subproblem 1
/// (w onto v). Degenerate data (A and B both singular: p1 on k1 and p3 on
/// k3, say) gives no solution.
///
/// # Examples
/// ```
/// use kinema::ik::geo::subproblems::{rotate, sp5};
/// use kinema::nalgebra::Vector3;
/// let (k1, k2, k3) = (Vector3::z(), Vector3::x(), Vector3::new(0.0, 0.6, 0.8));
/// let (p1, p2, p3) = (Vector3::new(0.5, 0.1, 0.2), Vector3::new(0.1, 0.4, 0.0), Vector3::new(0.3, 0.0, 0.2));
/// let (t1, t2, t3) = (0.4, -1.2, 2.1);
/// let p0 = rotate(&k2, t2, &(p2 + rotate(&k3, t3, &p3))) - rotate(&k1, t1, &p1);
/// let s = sp5(&p0, &k1, &p1, &k2, &p2, &k3, &p3);
/// assert!(s.as_slice().iter().any(|t| (t[0] - t1).abs() < 1e-9 && (t[1] - t2).abs() < 1e-9 && (t[2] - t3).abs() < 1e-9));
/// ```
pub fn sp5(p0: &V3, k1: &V3, p1: &V3, k2: &V3, p2: &V3, k3: &V3, p3: &V3) -> Triples {
    let mut out = Triples { theta: [[0.0; 3]; 4], len: 0 };
    // R(k, θ)·p = k(k·p) + cos θ·p⊥ + sin θ·(k × p).
    let (p1a, p1c, p1s) = (k1 * k1.dot(p1), p1 - k1 * k1.dot(p1), k1.cross(p1));
    let (p3a, p3c, p3s) = (k3 * k3.dot(p3), p3 - k3 * k3.dot(p3), k3.cross(p3));
    let a = nalgebra::Matrix2::new(k2.dot(&p1c), k2.dot(&p1s), 2.0 * p0.dot(&p1c), 2.0 * p0.dot(&p1s));
    let b = nalgebra::Matrix2::new(-k2.dot(&p3c), -k2.dot(&p3s), -2.0 * p2.dot(&p3c), -2.0 * p2.dot(&p3s));
    let d = nalgebra::Vector2::new(
        k2.dot(&(p2 + p3a)) - k2.dot(&(p0 + p1a)),
        p2.norm_squared() + p3.norm_squared() + 2.0 * p2.dot(&p3a)
            - p0.norm_squared()
            - p1.norm_squared()
            - 2.0 * p0.dot(&p1a),
    );
    let (da, db) = (a.determinant(), b.determinant());
    let scale = (a.norm() + b.norm()).powi(2);
    if !(da.abs().max(db.abs()) > 1e-12 * scale) {
        return out;
    }
    // Invert the better-conditioned side: `x_other = inv·(d − m·x_free)`.
    let (inv, m, free_is_1) =
        if db.abs() >= da.abs() { (b.try_inverse(), a, true) } else { (a.try_inverse(), b, false) };
    let Some(inv) = inv else { return out };
    let (u, w) = (inv * d, inv * m);
    // |u − W·x|² = 1: xᵀ(WᵀW)x − 2(Wᵀu)·x + |u|² − 1 = 0.
    let s = w.transpose() * w;
    let g = w.transpose() * u * -2.0;
    let mut angles = [0.0; 4];
    let n = circle_conic(&s, &g, u.norm_squared() - 1.0, &mut angles);
    for &t in &angles[..n] {
        let (sn, cs) = t.fast_sin_cos();
        let x = nalgebra::Vector2::new(cs, sn);
        let y = u - w * x;
        let other = y.y.fast_atan2(y.x);
        let (t1, t3) = if free_is_1 { (t, other) } else { (other, t) };
        let v = p0 + rotate(k1, t1, p1);
        let wv = p2 + rotate(k3, t3, p3);
        let t2 = sp1(k2, &wv, &v).first();
        out.theta[out.len] = [wrap_angle(t1), t2, wrap_angle(t3)];
        out.len += 1;
    }
    out
}

/// The angles θ \[rad\] with x = (cos θ, sin θ) on the conic
/// xᵀ·S·x + g·x + h = 0 (`S` symmetric): up to four, written to `out`;
/// returns how many. With t = tan((θ − φ)/2) the equation times (1 + t²)² is
/// a quartic in t whose leading coefficient is the conic's value at θ = φ + π;
/// φ is the quarter turn that makes it largest, so no root hides at t = ∞.
pub fn circle_conic(s: &nalgebra::Matrix2<f64>, g: &nalgebra::Vector2<f64>, h: f64, out: &mut [f64; 4]) -> usize {
    let f =
        |c: f64, sn: f64| s[(0, 0)] * c * c + 2.0 * s[(0, 1)] * c * sn + s[(1, 1)] * sn * sn + g.x * c + g.y * sn + h;
    // f at θ = φ + π for φ = 0, π/2, π, −π/2.
    let at = [f(-1.0, 0.0), f(0.0, -1.0), f(1.0, 0.0), f(0.0, 1.0)];
    let k = (0..4).max_by(|&i, &j| at[i].abs().total_cmp(&at[j].abs())).unwrap_or(0);
    let phi = k as f64 * std::f64::consts::FRAC_PI_2;
    // Rotate the conic by φ: x = R(φ)·x'.
    let (sp, cp) = phi.sin_cos();
    let r = nalgebra::Matrix2::new(cp, -sp, sp, cp);
    let s2 = r.transpose() * s * r;
    let g2 = r.transpose() * g;
    let (s11, s12, s22) = (s2[(0, 0)], s2[(0, 1)], s2[(1, 1)]);
    let c = [
        s11 + g2.x + h,
        4.0 * s12 + 2.0 * g2.y,
        -2.0 * s11 + 4.0 * s22 + 2.0 * h,
        -4.0 * s12 + 2.0 * g2.y,
        s11 - g2.x + h,
    ];
    let mut t = [0.0; 4];
    let n = poly_real_roots(&c, &mut t);
    for i in 0..n {
        out[i] = wrap_angle(phi + 2.0 * t[i].atan());
    }
    n
}

/// The real roots of the polynomial Σ cᵢ·tⁱ (degree ≤ 4, `c[4]` ≠ 0 unless
/// lower), in increasing order, written to `out`; returns how many. Roots
/// of the derivative (recursively) split the real line into monotone pieces
/// bounded by Fujiwara's bound; each piece with a sign change holds one root,
/// found by Newton's method safeguarded by bisection. A double root shows as
/// a critical point where the polynomial vanishes to rounding.
pub fn poly_real_roots(c: &[f64], out: &mut [f64; 4]) -> usize {
    let mut deg = c.len().min(5) - 1;
    let big = c.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if !(big.is_finite() && big > 0.0) {
        return 0;
    }
    while deg > 0 && c[deg].abs() <= 1e-13 * big {
        deg -= 1;
    }
    match deg {
        0 => 0,
        1 => {
            out[0] = -c[0] / c[1];
            1
        }
        2 => {
            let (a, b, cc) = (c[2], c[1], c[0]);
            let disc = b * b - 4.0 * a * cc;
            if disc < 0.0 {
                return 0;
            }
            let q = -0.5 * (b + b.signum() * disc.sqrt());
            let (x1, x2) = if q == 0.0 { (0.0, 0.0) } else { (q / a, cc / q) };
            out[0] = x1.min(x2);
            out[1] = x1.max(x2);
            2
        }
        _ => {
            let p = |x: f64| c[..=deg].iter().rev().fold(0.0, |acc, v| acc * x + v);
            let mut dc = [0.0; 4];
            for i in 1..=deg {
                dc[i - 1] = c[i] * i as f64;
            }
            let mut crit = [0.0; 4];
            let nc = poly_real_roots(&dc[..deg], &mut crit);
            // Fujiwara's bound on |root|: tighter than Cauchy's, so fewer bisections.
            let mut bound = 0.0f64;
            for i in 1..=deg {
                let a = (c[deg - i] / c[deg]).abs() * if i == deg { 0.5 } else { 1.0 };
                bound = bound.max(match i {
                    1 => a,
                    2 => a.sqrt(),
                    // max(a^½, a^¼) ≥ a^⅓, without a cube root.
                    3 => a.sqrt().max(a.sqrt().sqrt()),
                    _ => a.sqrt().sqrt(),
                });
            }
            let bound = 2.0 * bound * (1.0 + 1e-12) + f64::MIN_POSITIVE;
            let mut edges = [0.0; 6];
            edges[0] = -bound;
            let mut ne = 1;
            for &x in &crit[..nc] {
                if x > -bound && x < bound {
                    edges[ne] = x;
                    ne += 1;
                }
            }
            edges[ne] = bound;
            ne += 1;
            let mut n = 0;
            let flat = 1e-14 * big;
            for w in 0..ne - 1 {
                let (lo, hi) = (edges[w], edges[w + 1]);
                let (flo, fhi) = (p(lo), p(hi));
                if w > 0 && flo.abs() <= flat {
                    // A root at a critical point (a double root, or one exactly there).
                    if n == 0 || (out[n - 1] - lo).abs() > 1e-12 * (1.0 + lo.abs()) {
                        out[n] = lo;
                        n += 1;
                    }
                    continue;
                }
                if (flo > 0.0) != (fhi > 0.0) && fhi.abs() > flat && n < 4 {
                    out[n] = newton_bisect(&p, &dc[..deg], lo, hi, flo, fhi);
                    n += 1;
                }
            }
            n
        }
    }
}

/// A root of `p` in [lo, hi] (p(lo) = `flo`, p(hi) = `fhi` of the other
/// sign): Newton steps with derivative coefficients `dc` from the
/// false-position point, bisection when a step leaves the bracket.
fn newton_bisect(p: &dyn Fn(f64) -> f64, dc: &[f64], mut lo: f64, mut hi: f64, flo: f64, fhi: f64) -> f64 {
    let dp = |x: f64| dc.iter().rev().fold(0.0, |acc, v| acc * x + v);
    let secant = lo - flo * (hi - lo) / (fhi - flo);
    let mut x = if secant > lo && secant < hi { secant } else { 0.5 * (lo + hi) };
    for _ in 0..100 {
        let fx = p(x);
        if fx == 0.0 {
            return x;
        }
        if (fx > 0.0) == (flo > 0.0) {
            lo = x;
        } else {
            hi = x;
        }
        let d = dp(x);
        let step = if d != 0.0 { x - fx / d } else { f64::NAN };
        let next = if step > lo && step < hi { step } else { 0.5 * (lo + hi) };
        // After a Newton step this small the next one is below rounding.
        if (next - x).abs() <= 1e-13 * (1.0 + x.abs()) || hi - lo <= 4.0 * f64::EPSILON * (1.0 + x.abs()) {
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

    fn unit(rng: &mut ChaCha8Rng) -> V3 {
        loop {
            let v = V3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
            let n = v.norm();
            if n > 0.1 && n < 1.0 {
                return v / n;
            }
        }
    }

    fn point(rng: &mut ChaCha8Rng) -> V3 {
        unit(rng) * rng.random_range(0.05..2.0)
    }

    fn angle(rng: &mut ChaCha8Rng) -> f64 {
        rng.random_range(-PI..PI)
    }

    fn has(a: &Angles, theta: f64) -> bool {
        a.as_slice().iter().any(|t| wrap_angle(t - theta).abs() < 1e-9)
    }

    #[test]
    fn rot_matches_rotate_and_is_a_rotation() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        for _ in 0..1000 {
            let (k, p, t) = (unit(&mut rng), point(&mut rng), angle(&mut rng));
            let r = rot(&k, t);
            assert!((r * p - rotate(&k, t, &p)).norm() < 1e-14);
            assert!((r.transpose() * r - Matrix3::identity()).norm() < 1e-14);
            assert!((r * k - k).norm() < 1e-14);
        }
    }

    #[test]
    fn sp1_round_trips_and_reports_misses() {
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        for _ in 0..10_000 {
            let (k, p, t) = (unit(&mut rng), point(&mut rng), angle(&mut rng));
            let a = sp1(&k, &p, &rotate(&k, t, &p));
            assert!(a.exact && a.miss < 1e-13, "{a:?}");
            assert!(has(&a, t), "{t}: {a:?}");
        }
        // Different heights along k: not solvable, the projections still align.
        let k = V3::z();
        let a = sp1(&k, &V3::new(1.0, 0.0, 0.0), &V3::new(0.0, 2.0, 0.5));
        assert!(!a.exact && (a.first() - PI / 2.0).abs() < 1e-12);
        assert!((a.miss - (1.0f64 + 0.25).sqrt()).abs() < 1e-12, "{a:?}");
        // A point on the axis: θ = 0, exact.
        let a = sp1(&k, &V3::new(0.0, 0.0, 1.0), &V3::new(0.0, 0.0, 1.0));
        assert!(a.exact && a.first() == 0.0);
    }

    #[test]
    fn sp2_round_trips_and_reports_misses() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for _ in 0..10_000 {
            let (k1, k2, p2) = (unit(&mut rng), unit(&mut rng), point(&mut rng));
            if k1.cross(&k2).norm() < 0.05 {
                continue;
            }
            let (t1, t2) = (angle(&mut rng), angle(&mut rng));
            let c = rotate(&k2, t2, &p2);
            let p1 = rotate(&k1, -t1, &c);
            let (a1, a2) = sp2(&k1, &p1, &k2, &p2);
            assert!(a1.exact && a2.exact && a1.as_slice().len() == 2, "{a1:?}");
            for (x, y) in a1.as_slice().iter().zip(a2.as_slice()) {
                assert!((rotate(&k1, *x, &p1) - rotate(&k2, *y, &p2)).norm() < 1e-12);
            }
            let found = a1
                .as_slice()
                .iter()
                .zip(a2.as_slice())
                .any(|(x, y)| wrap_angle(x - t1).abs() < 1e-8 && wrap_angle(y - t2).abs() < 1e-8);
            assert!(found, "{t1} {t2}: {a1:?} {a2:?}");
        }
        // The circles miss each other: one least-squares pair, flagged.
        let (k1, k2) = (V3::z(), V3::x());
        let (a1, a2) = sp2(&k1, &V3::new(0.0, 0.0, 1.0), &k2, &V3::new(1.0, 0.0, 0.0));
        assert!(!a1.exact && !a2.exact && a1.as_slice().len() == 1 && a1.miss > 0.1, "{a1:?}");
    }

    #[test]
    fn sp3_round_trips_and_reports_misses() {
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        for _ in 0..10_000 {
            let (k, p1, p2, t) = (unit(&mut rng), point(&mut rng), point(&mut rng), angle(&mut rng));
            let d = (rotate(&k, t, &p1) - p2).norm();
            let a = sp3(&k, &p1, &p2, d);
            assert!(a.exact && a.as_slice().len() == 2, "{a:?}");
            for x in a.as_slice() {
                assert!(((rotate(&k, *x, &p1) - p2).norm() - d).abs() < 1e-9);
            }
            // Near the double root the angle itself is ill-conditioned (∝ √ε).
            let pp = p1 - k * k.dot(&p1);
            let tangent = k.cross(&rotate(&k, t, &pp)).dot(&(rotate(&k, t, &p1) - p2)).abs();
            if tangent > 1e-3 {
                assert!(has(&a, t), "{t}: {a:?}");
            }
        }
        // Too far: the nearest distance, flagged with the gap.
        let k = V3::z();
        let a = sp3(&k, &V3::new(1.0, 0.0, 0.0), &V3::new(0.0, 0.0, 0.0), 3.0);
        assert!(!a.exact && (a.miss - 2.0).abs() < 1e-12, "{a:?}");
        let a = sp3(&k, &V3::new(1.0, 0.0, 0.0), &V3::new(3.0, 0.0, 0.0), 5.0);
        assert!(!a.exact && (a.first().abs() - PI).abs() < 1e-12 && (a.miss - 1.0).abs() < 1e-12, "{a:?}");
        // Exactly on the boundary: the double root, twice.
        let a = sp3(&k, &V3::new(1.0, 0.0, 0.0), &V3::new(3.0, 0.0, 0.0), 4.0);
        assert!(a.exact && a.as_slice().len() == 2 && a.as_slice().iter().all(|t| (t.abs() - PI).abs() < 1e-7));
    }

    #[test]
    fn sp4_round_trips_and_reports_misses() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for _ in 0..10_000 {
            let (h, k, p, t) = (unit(&mut rng), unit(&mut rng), point(&mut rng), angle(&mut rng));
            let d = h.dot(&rotate(&k, t, &p));
            let a = sp4(&h, &k, &p, d);
            assert!(a.exact && a.as_slice().len() == 2, "{a:?}");
            for x in a.as_slice() {
                assert!((h.dot(&rotate(&k, *x, &p)) - d).abs() < 1e-12);
            }
            let pp = p - k * k.dot(&p);
            if h.dot(&k.cross(&rotate(&k, t, &pp))).abs() > 1e-3 {
                assert!(has(&a, t), "{t}: {a:?}");
            }
        }
        // Out of range: the height nearest to d.
        let a = sp4(&V3::z(), &V3::x(), &V3::new(0.0, 1.0, 0.0), 1.5);
        assert!(!a.exact && (a.first() - PI / 2.0).abs() < 1e-12 && (a.miss - 0.5).abs() < 1e-12, "{a:?}");
        // h ∥ k: the height does not depend on θ.
        let a = sp4(&V3::x(), &V3::x(), &V3::new(0.3, 1.0, 0.0), 0.3);
        assert!(a.exact && a.first() == 0.0);
        let a = sp4(&V3::x(), &V3::x(), &V3::new(0.3, 1.0, 0.0), 0.4);
        assert!(!a.exact);
    }

    #[test]
    fn poly_real_roots_finds_simple_double_and_spread_roots() {
        let mut r = [0.0; 4];
        // (t − 1)(t + 2)(t − 3)(t + 0.5) = t⁴ − 1.5t³ − 6t² + 3.5t + 3
        let n = poly_real_roots(&[3.0, 3.5, -6.0, -1.5, 1.0], &mut r);
        assert_eq!(n, 4, "{r:?}");
        for (x, y) in r.iter().zip([-2.0, -0.5, 1.0, 3.0]) {
            assert!((x - y).abs() < 1e-12, "{r:?}");
        }
        // t⁴ + 1: none. (t − 1)²(t² + 1) = t⁴ − 2t³ + 2t² − 2t + 1: the double root.
        assert_eq!(poly_real_roots(&[1.0, 0.0, 0.0, 0.0, 1.0], &mut r), 0);
        let n = poly_real_roots(&[1.0, -2.0, 2.0, -2.0, 1.0], &mut r);
        assert!(n >= 1 && r[..n].iter().all(|x| (x - 1.0).abs() < 1e-6), "{r:?}");
        // Degree drops: 2t − 1.
        assert!(poly_real_roots(&[-1.0, 2.0, 0.0, 0.0, 0.0], &mut r) == 1 && (r[0] - 0.5).abs() < 1e-15);
    }

    #[test]
    fn sp5_round_trips() {
        let mut rng = ChaCha8Rng::seed_from_u64(6);
        let mut found = 0;
        let total = 10_000;
        for _ in 0..total {
            let (k1, k2, k3) = (unit(&mut rng), unit(&mut rng), unit(&mut rng));
            let (p1, p2, p3) = (point(&mut rng), point(&mut rng), point(&mut rng));
            let (t1, t2, t3) = (angle(&mut rng), angle(&mut rng), angle(&mut rng));
            let p0 = rotate(&k2, t2, &(p2 + rotate(&k3, t3, &p3))) - rotate(&k1, t1, &p1);
            let s = sp5(&p0, &k1, &p1, &k2, &p2, &k3, &p3);
            for t in s.as_slice() {
                let l = p0 + rotate(&k1, t[0], &p1);
                let r = rotate(&k2, t[1], &(p2 + rotate(&k3, t[2], &p3)));
                assert!((l - r).norm() < 1e-6 * (1.0 + l.norm()), "{t:?}: {}", (l - r).norm());
            }
            if s.as_slice().iter().any(|t| (0..3).all(|i| wrap_angle(t[i] - [t1, t2, t3][i]).abs() < 1e-6)) {
                found += 1;
            }
        }
        // Misses are near-tangent data, where the angles are ill-conditioned.
        assert!(found as f64 >= 0.998 * total as f64, "{found} of {total}");
    }

    #[test]
    fn non_finite_data_is_never_exact_and_never_panics() {
        let k = V3::z();
        let nan = V3::new(f64::NAN, 0.0, 0.0);
        assert!(!sp1(&k, &nan, &V3::x()).exact);
        assert!(!sp3(&k, &nan, &V3::x(), 1.0).exact);
        assert!(!sp4(&V3::x(), &k, &nan, 1.0).exact);
        assert!(!sp2(&k, &nan, &V3::x(), &V3::y()).0.exact);
    }
}
