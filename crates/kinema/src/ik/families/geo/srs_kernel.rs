//! The closed form of every SRS arm (spherical shoulder, elbow, spherical
//! wrist) with joint 3 fixed or at an arm angle, shared by [`SrsIk`](super::SrsIk) (axes read
//! from any description) and [`IiwaIk`](crate::ik::iiwa::IiwaIk) (the
//! iiwa's DH table): one set of formulas, specialised to each robot once.
//!
//! **Frames.** Everything is computed in the arm's canonical frame C: ẑ =
//! h₁, ŷ along the part of h₂ normal to h₁, x̂ = ŷ × ẑ, origin at the
//! shoulder point s. So rot(h₁, q) = Rz(q) and h₂ = (0, s₁₂, c₁₂) with
//! c₁₂ = h₁·h₂. On the iiwa's DH frame 0, C is frame 0 itself (h₁ = z,
//! h₂ = y), and every formula below reduces to seed 004 eq. 3–11.
//!
//! **Elbow.** With joints 1–3 at zero, the wrist centre relative to s is
//! x₀(q₄) = k₀ + cos q₄·k₁ + sin q₄·k₂, where a = w − p₄ (p₄ on axis 4),
//! k₀ = p₄ − s + h₄(h₄·a), k₁ = a − h₄(h₄·a), k₂ = h₄ × k₁ (k₁ ⊥ k₂,
//! |k₁| = |k₂|). Hence |x₀|² = K + 2R·cos(q₄ − φ) with K = |k₀|² + |k₁|²,
//! R = |k₁|·|k₀⊥h₄| and φ = atan2(k₀·k₂, k₀·k₁). Joints 1–3 do not change
//! the distance, so r = |W − s| fixes cos θ = (r² − K)/(2R), θ = q₄ − φ.
//! With r_out,in² = K ± 2R = |k₀·h₄|² + (|k₀⊥h₄| ± |k₁|)², 1 ∓ cos θ =
//! (r_out,in² − r²)/(±2R) factor into (r_out − r)(r_out + r) and
//! (r − r_in)(r + r_in): full precision at the stretched and folded arm.
//! Two elbows, sin θ = ±√((1 − cos θ)(1 + cos θ)).
//!
//! **Shoulder.** x = R₃·x₀(q₄) is known once q₃ and q₄ are; rot(h₁, q₁)·
//! rot(h₂, q₂)·x = d = W − s. The vector v = rot(h₂, q₂)·x = Rz(−q₁)·d has
//! v_z = d_z (Rz keeps z) and h₂·v = h₂·x, i.e. s₁₂·v_y + c₁₂·v_z =
//! s₁₂·x_y + c₁₂·x_z, so v_y = x_y + c₁₂(x_z − d_z)/s₁₂ =: p, and
//! v_x = u = ±√(ρ² − p²) with ρ = |d_xy| (two shoulders; none when ρ < |p|).
//! Then q₁ is the angle from (u, p) to (d_x, d_y) about z, one atan2 of
//! their cross and dot products, and q₂ the angle from x to v about h₂,
//! measured in the basis (s₁₂ẑ − c₁₂ŷ, x̂) of the plane normal to h₂, which
//! rot(h₂, q₂) turns by q₂. On the iiwa this is seed 004 eq. 8–9 with the
//! sign choice made by the atan2 instead of by an FK test.
//!
//! **Wrist.** M = R₀₄ᵀ·R_G = rot(h₅, q₅)·rot(h₆, q₆)·rot(h₇, q₇). The
//! same two-axis solve in the wrist's frame (ẑ = h₅, ŷ along h₆ ⊥ h₅) with
//! x = h₇ and d = M·h₇ gives q₅ and q₆. For q₇ take u₂ ⊥ h₇ along h₆'s part
//! normal to h₇ and u = u₂ × h₇: then rot(h₇, q₇)·u = cos q₇·u + sin q₇·u₂,
//! and with g = rot(h₅, q₅)·rot(h₆, q₆)·u₂, sin q₇ = g·M·u and cos q₇ =
//! g·M·u₂. On the iiwa (h₅ = h₇ = z, h₆ = y) these are the ZYZ angles
//! atan2(m₁₂, m₀₂), atan2(√(m₀₂² + m₁₂²), m₂₂) and row 1 of Rz(−q₅)·M,
//! accurate near q₆ = 0. When h₇ ∥ h₅ and h₆ ⊥ h₇ the second wrist is
//! (q₅ + π, −q₆, q₇ + π) without further atan2s, since rot(h₅, π)·rot(h₆,
//! −q₆)·rot(h₅, −π) = rot(h₆, q₆).
//!
//! **Arm angle** ([`SrsKernel::solve_psi`], ψ as `SrsIk`'s documentation
//! defines it): for each elbow the shoulder rotation R = R₁R₂R₃ =
//! Rot(d̂, ψ)·R° is known, and axes 1, 2, 3 solve it as the wrist solves M
//! (the same [`Spherical`] solve, with x = h₃ and d = R·h₃).
//!
//! **Singular cases** (never NaN): a first axis of a pair along the vector
//! it must turn (d on axis 1: the shoulder; M·h₇ on axis 5: the wrist), by
//! less than 1e-12, leaves its angle free: it takes the caller's hint and
//! the second angle follows.
//!
//! All angles of a call are independent once the sines and cosines are
//! known, so their atan2s go in batches of eight (`atan2_x8`).

use std::f64::consts::PI;

use nalgebra::{Matrix3, Vector3};

use super::wrist::perpendicular;
use super::GEOM_TOL;
use crate::ik::wrap_angle;
use crate::math::{atan2_x8, rot_z, FastMath};

type V3 = Vector3<f64>;

/// Below this distance from the first axis of a pair (in that pair's own
/// length unit: m for the shoulder, 1 for the wrist's unit vectors) its
/// angle is free and takes the hint.
pub(crate) const SINGULAR: f64 = 1e-12;
/// Below this |h₅ × h₇| and |h₆·h₇| the wrist's second branch is derived from its first.
const ALIGNED_TOL: f64 = 1e-12;
/// Relative tolerance for targets just outside a reach boundary (clamped onto it).
const REACH_TOL: f64 = 1e-12;

/// A fixed vector turning about a fixed unit axis h:
/// rot(h, q)·v = `par` + cos q·`perp` + sin q·`cross`.
#[derive(Debug, Clone, Copy)]
struct Turn {
    par: V3,
    perp: V3,
    cross: V3,
}

impl Turn {
    fn new(h: &V3, v: &V3) -> Self {
        let par = h * h.dot(v);
        let perp = v - par;
        Turn { par, perp, cross: h.cross(&perp) }
    }

    #[inline]
    fn at(&self, (s, c): (f64, f64)) -> V3 {
        self.par + self.perp * c + self.cross * s
    }
}

/// Rotations about a fixed unit axis from a sine and cosine (Rodrigues).
#[derive(Debug, Clone, Copy)]
struct Axis {
    k: Matrix3<f64>,
    k2: Matrix3<f64>,
}

impl Axis {
    fn new(h: &V3) -> Self {
        let k = h.cross_matrix();
        Axis { k, k2: k * k }
    }

    #[inline]
    fn rot(&self, (s, c): (f64, f64)) -> Matrix3<f64> {
        Matrix3::identity() + self.k * s + self.k2 * (1.0 - c)
    }
}

/// Two unit axes through one point, seen in the frame where the first is
/// ẑ and the second (0, `s`, `c`), `s` > 0: the solve of rot(a, q_a)·
/// rot(b, q_b)·x = d (see the module documentation).
#[derive(Debug, Clone, Copy)]
struct Pair {
    c: f64,
    s: f64,
    /// c / s.
    cot: f64,
}

/// One root of a [`Pair`]: each angle's atan2 arguments (y, x) with its sine
/// and cosine (the second's left at (0, 1) by [`Spherical::aligned_roots`],
/// which needs none); `fixed` when the first angle was free and took the hint.
#[derive(Debug, Clone, Copy)]
struct PairRoot {
    a: (f64, f64),
    sa: (f64, f64),
    fixed: bool,
    b: (f64, f64),
    sb: (f64, f64),
}

impl Pair {
    /// The pair's frame (rows: its x̂, ŷ, ẑ in the outer frame) and the pair.
    fn new(a: &V3, b: &V3) -> (Matrix3<f64>, Pair) {
        let y = (b - a * a.dot(b)).normalize();
        let x = y.cross(a);
        let frame = Matrix3::from_rows(&[x.transpose(), y.transpose(), a.transpose()]);
        let (c, s) = (a.dot(b), b.dot(&y));
        (frame, Pair { c, s, cot: c / s })
    }

    /// p = v_y and ρ = |d_xy|: the two shoulders exist when ρ ≥ |p|.
    #[inline(always)]
    fn offsets(&self, x: &V3, d: &V3) -> (f64, f64) {
        (x.y + self.cot * (x.z - d.z), d.x.fast_hypot(d.y))
    }

    /// The root with v_x = `u` (u² + p² = ρ², ρ = `rho`); the first angle
    /// is `hint` \[rad\] when free. (u, p) and (d_x, d_y) both have
    /// length ρ, so the first angle's cross and dot products have length ρ².
    #[inline(always)]
    fn root(&self, x: &V3, d: &V3, (p, rho): (f64, f64), u: f64, hint: f64) -> PairRoot {
        let (a, sa, fixed, u) = if rho < SINGULAR {
            let (s, c) = hint.fast_sin_cos();
            ((0.0, 1.0), (s, c), true, c * d.x + s * d.y)
        } else {
            let (y, x) = (d.y * u - d.x * p, d.x * u + d.y * p);
            let inv = 1.0 / (rho * rho);
            ((y, x), (y * inv, x * inv), false, u)
        };
        let (xa, xb) = (self.s * x.z - self.c * x.y, x.x);
        let (va, vb) = (self.s * d.z - self.c * p, u);
        let (y, xx) = (xa * vb - xb * va, xa * va + xb * vb);
        let h = y.fast_hypot(xx);
        let (b, sb) = if h > 0.0 {
            let inv = 1.0 / h;
            ((y, xx), (y * inv, xx * inv))
        } else {
            ((0.0, 1.0), (0.0, 1.0))
        };
        PairRoot { a, sa, fixed, b, sb }
    }
}

/// Why no solution exists for a q₃ (each with its miss).
#[derive(Debug, Clone, Copy)]
pub(crate) enum Miss {
    /// The wrist centre is farther from the shoulder than the arm reaches, by \[m\].
    Outer(f64),
    /// The wrist centre is nearer the shoulder than the arm folds, by \[m\].
    Inner(f64),
    /// The wrist centre lies in the region about axis 1 this q₃ cannot
    /// enter, by \[m\] (the smallest over the elbows).
    Arm(f64),
    /// The wrist cannot turn axis 7 to the direction asked for; the chord
    /// between unit vectors by which it misses.
    Wrist(f64),
}

/// What the caller asks of a fixed-q₃ solve besides the target.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Options {
    /// q₁ \[rad\] when the wrist centre is on axis 1.
    pub(crate) q1_hint: f64,
    /// At the wrist singularity the second wrist branch takes q₅ + π (and
    /// q₇ + π) rather than repeating q₅ with −q₆.
    pub(crate) flip_singular_wrist: bool,
    /// Keep only the branches that can continue a path through this configuration.
    pub(crate) near: Option<[f64; 7]>,
}

/// Up to 8 joint vectors with their (elbow, shoulder, wrist) root indices.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Solutions {
    pub(crate) q: [[f64; 7]; 8],
    pub(crate) branch: [(usize, usize, usize); 8],
    pub(crate) len: usize,
}

impl Solutions {
    /// No solutions yet.
    pub(crate) fn empty() -> Self {
        Solutions { q: [[0.0; 7]; 8], branch: [(0, 0, 0); 8], len: 0 }
    }

    fn push(&mut self, q: [f64; 7], branch: (usize, usize, usize)) {
        self.q[self.len] = q;
        self.branch[self.len] = branch;
        self.len += 1;
    }

    /// The joint vectors and their (elbow, shoulder, wrist) indices.
    pub(crate) fn iter(&self) -> impl Iterator<Item = (&[f64; 7], (usize, usize, usize))> {
        self.q[..self.len].iter().zip(self.branch[..self.len].iter().copied())
    }
}

/// The target as the kernel takes it, in the canonical frame: the wrist
/// centre relative to the shoulder and R_G applied to the wrist's h₇, u, u₂.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Goal {
    pub(crate) d: V3,
    g: [V3; 3],
}

/// Three unit axes a, b, c through one point (the spherical wrist, or the
/// shoulder in the arm-angle form): rot(a, q_a)·rot(b, q_b)·rot(c, q_c) = M
/// from the images of c, u and u₂ under M (see the module documentation).
#[derive(Debug, Clone)]
struct Spherical {
    /// C → the frame of the pair (a, b) (ẑ = a), or `None` when they coincide.
    frame: Option<Matrix3<f64>>,
    pair: Pair,
    /// c in the pair's frame.
    hc: V3,
    /// u₂ turning about b (pair's frame).
    u2: Turn,
    /// c, u, u₂ in C: the vectors whose images M takes.
    vectors: [V3; 3],
    /// c ∥ a and b ⊥ c: the second root follows from the first.
    aligned: bool,
}

/// A [`Spherical`] solve's roots: each pair root with the atan2 arguments
/// of its q_c; the second is not used when the solve is aligned.
#[derive(Debug, Clone, Copy)]
struct Roots {
    pair: [PairRoot; 2],
    c: [(f64, f64); 2],
}

impl Spherical {
    /// The solve for axes `ha`, `hb`, `hc` given in C.
    fn new(ha: &V3, hb: &V3, hc: &V3) -> Self {
        let (frame, pair) = Pair::new(ha, hb);
        let u2 = (hb - hc * hc.dot(hb)).normalize();
        let u = u2.cross(hc);
        Spherical {
            pair,
            hc: frame * hc,
            u2: Turn::new(&(frame * hb), &(frame * u2)),
            vectors: [*hc, u, u2],
            aligned: ha.cross(hc).norm() <= ALIGNED_TOL && hb.dot(hc).abs() <= ALIGNED_TOL,
            frame: unless_identity(frame),
        }
    }

    /// The roots for the images `m` (in C) of c, u, u₂; q_a takes 0 where
    /// it is free (π on the second root when `flip`). The miss (a chord
    /// between unit vectors) when b cannot turn c onto M·c.
    #[inline(always)]
    fn roots(&self, m: &[V3; 3], flip: bool) -> Result<Roots, f64> {
        let [mh, mu, mu2] = m.map(|v| apply(&self.frame, &v));
        if self.aligned {
            return Ok(self.aligned_roots(&mh, &mu, &mu2));
        }
        let (p, rho) = self.pair.offsets(&self.hc, &mh);
        let gap = rho - p.abs();
        if gap < -REACH_TOL * (1.0 + rho) {
            return Err(-gap);
        }
        // p = 0 for an orthogonal wrist: u = ρ without a square root.
        let u_abs = if p == 0.0 { rho } else { (gap.max(0.0) * (rho + p.abs())).sqrt() };
        let first = self.pair.root(&self.hc, &mh, (p, rho), u_abs, 0.0);
        let mut out = Roots { pair: [first; 2], c: [(0.0, 1.0); 2] };
        for k in 0..if self.aligned { 1 } else { 2 } {
            if k == 1 {
                let hint = if flip { PI } else { 0.0 };
                out.pair[1] = self.pair.root(&self.hc, &mh, (p, rho), -u_abs, hint);
            }
            let root = &out.pair[k];
            let g = self.u2.at(root.sb);
            let (sa, ca) = root.sa;
            let g = V3::new(ca * g.x - sa * g.y, sa * g.x + ca * g.y, g.z);
            out.c[k] = (g.dot(&mu), g.dot(&mu2));
        }
        Ok(out)
    }

    /// [`Spherical::roots`] for c = σ·a, b ⊥ c (the frame's ẑ and ŷ), where
    /// the general formulas reduce to Z-Y-Z angles: p = 0, u = ρ, u₂ = b
    /// (so rot(b, q_b)·u₂ = u₂ and g = Rz(q_a)·ŷ), q_b from (σρ, σ·(M·c)_z).
    #[inline(always)]
    fn aligned_roots(&self, mh: &V3, mu: &V3, mu2: &V3) -> Roots {
        let rho = mh.x.fast_hypot(mh.y);
        let sigma = self.hc.z.signum();
        let (a, sa, fixed, u) = if rho < SINGULAR {
            ((0.0, 1.0), (0.0, 1.0), true, mh.x)
        } else {
            let inv = 1.0 / rho;
            ((mh.y, mh.x), (mh.y * inv, mh.x * inv), false, rho)
        };
        let (s, c) = sa;
        let root = PairRoot { a, sa, fixed, b: (sigma * u, sigma * mh.z), sb: (0.0, 1.0) };
        let qc = (c * mu.y - s * mu.x, c * mu2.y - s * mu2.x);
        Roots { pair: [root; 2], c: [qc; 2] }
    }

    /// Both roots' (q_a, q_b, q_c) from the atan2 of each root's arguments
    /// (`second` is not read when aligned).
    #[inline]
    fn angles(&self, fixed: [bool; 2], first: [f64; 3], second: [f64; 3], flip: bool) -> [[f64; 3]; 2] {
        let free = |fixed: bool, angle: f64, hint: f64| if fixed { hint } else { angle };
        let [qa, qb, qc] = first;
        let first = [free(fixed[0], qa, 0.0), qb, qc];
        if !self.aligned {
            let second = [free(fixed[1], second[0], if flip { PI } else { 0.0 }), second[1], second[2]];
            return [first, second];
        }
        let [qa, qb, qc] = first;
        if fixed[0] && !flip {
            return [[qa, qb, qc], [qa, -qb, qc]];
        }
        [[wrap_angle(qa), qb, wrap_angle(qc)], [wrap_angle(qa + PI), -qb, wrap_angle(qc + PI)]]
    }

    /// Both roots' angles by scalar atan2s (the arm-angle form).
    fn solve(&self, m: &[V3; 3], flip: bool) -> Result<[[f64; 3]; 2], f64> {
        let r = self.roots(m, flip)?;
        let at = |k: usize| [r.pair[k].a, r.pair[k].b, r.c[k]].map(|(y, x)| y.fast_atan2(x));
        let second = if self.aligned { [0.0; 3] } else { at(1) };
        Ok(self.angles([r.pair[0].fixed, r.pair[1].fixed], at(0), second, flip))
    }
}

/// The SRS arm's constants, prepared once per robot (see the module documentation).
#[derive(Debug, Clone)]
pub(crate) struct SrsKernel {
    /// Description frame → C, or `None` when they coincide.
    frame: Option<Matrix3<f64>>,
    shoulder: Pair,
    /// k₀, k₁, k₂ turning about h₃ (C).
    upper: [Turn; 3],
    /// h₂ in C.
    h2v: V3,
    h2: Axis,
    h3: Axis,
    h4: Axis,
    /// K, 2R, r_out, r_in and (sin φ, cos φ) of the elbow.
    reach: (f64, f64, f64, f64, (f64, f64)),
    /// Axes 5, 6, 7.
    wrist: Spherical,
    /// Axes 1, 2, 3, for the arm-angle form.
    joints123: Spherical,
}

/// The unit vector along `v`, or h₁ = ẑ when `v` is (numerically) zero.
fn unit_or_z(v: &V3) -> V3 {
    let n = v.norm();
    if n > 1e-300 {
        v / n
    } else {
        V3::z()
    }
}

/// The right-handed orthonormal frame \[x̂, ŷ, x̂ × ŷ\] with x̂ the unit
/// vector `x` and ŷ along the part of `y` normal to it (any unit vector ⊥ x̂
/// when `y` ∥ x̂).
fn frame(x: &V3, y: &V3) -> Matrix3<f64> {
    let y = y - x * x.dot(y);
    let y = if y.norm() > GEOM_TOL { y.normalize() } else { perpendicular(x) };
    Matrix3::from_columns(&[*x, y, x.cross(&y)])
}

/// The matrix, or `None` when it is the identity (to skip its products).
fn unless_identity(m: Matrix3<f64>) -> Option<Matrix3<f64>> {
    (m != Matrix3::identity()).then_some(m)
}

fn apply(m: &Option<Matrix3<f64>>, v: &V3) -> V3 {
    match m {
        Some(m) => m * v,
        None => *v,
    }
}

impl SrsKernel {
    /// The kernel of the arm with unit axes `h` (at q = 0), shoulder point
    /// `s`, a point `p4` on axis 4 and wrist centre `w`, all in one frame
    /// (the description frame). The caller has checked the structure: axes
    /// 1, 2, 3 through s, 5, 6, 7 through w, h₁ ∦ h₂, h₅ ∦ h₆, h₆ ∦ h₇,
    /// axis 4 through neither point.
    pub(crate) fn new(h: &[V3; 7], s: &V3, p4: &V3, w: &V3) -> Self {
        let (to_c, shoulder) = Pair::new(&h[0], &h[1]);
        let c = |v: &V3| to_c * v;
        let (h3, h4) = (c(&h[2]), c(&h[3]));
        let a = c(&(w - p4));
        let k1 = a - h4 * h4.dot(&a);
        let k0 = c(&(p4 - s)) + h4 * h4.dot(&a);
        let k2 = h4.cross(&k1);
        let k0_along = h4.dot(&k0);
        let k0_across = (k0 - h4 * k0_along).norm();
        let big_r = k1.norm() * k0_across;
        let phi = (k0.dot(&k2) / big_r, k0.dot(&k1) / big_r);
        let reach = (
            k0.norm_squared() + k1.norm_squared(),
            2.0 * big_r,
            k0_along.fast_hypot(k0_across + k1.norm()),
            k0_along.fast_hypot(k0_across - k1.norm()),
            phi,
        );
        let wrist = Spherical::new(&c(&h[4]), &c(&h[5]), &c(&h[6]));
        let joints123 = Spherical::new(&V3::z(), &c(&h[1]), &h3);
        SrsKernel {
            frame: unless_identity(to_c),
            shoulder,
            upper: [Turn::new(&h3, &k0), Turn::new(&h3, &k1), Turn::new(&h3, &k2)],
            h2v: c(&h[1]),
            h2: Axis::new(&c(&h[1])),
            h3: Axis::new(&h3),
            h4: Axis::new(&h4),
            reach,
            wrist,
            joints123,
        }
    }

    /// The goal for a wrist centre at `d` from the shoulder point and a
    /// motion whose rotation is `r` (R_G = R₁…R₇), both in the description frame.
    pub(crate) fn goal(&self, d: &V3, r: &Matrix3<f64>) -> Goal {
        let in_c = |v: &V3| apply(&self.frame, v);
        let [a, b, c] = self.wrist.vectors;
        match &self.frame {
            None => Goal { d: *d, g: [r * a, r * b, r * c] },
            Some(f) => {
                let rc = f * r * f.transpose();
                Goal { d: in_c(d), g: [rc * a, rc * b, rc * c] }
            }
        }
    }

    /// The largest and smallest distance \[m\] of the wrist centre from the shoulder point.
    pub(crate) fn reach(&self) -> (f64, f64) {
        (self.reach.2, self.reach.3)
    }

    /// (sin, cos) of the elbow's θ = q₄ − φ (|sin θ|), or the reach miss.
    pub(crate) fn elbow(&self, r: f64) -> Result<(f64, f64), Miss> {
        let (_, two_r, outer, inner, _) = self.reach;
        if r > outer + REACH_TOL * (1.0 + outer) {
            return Err(Miss::Outer(r - outer));
        }
        if r < inner - REACH_TOL * (1.0 + outer) {
            return Err(Miss::Inner(inner - r));
        }
        let one_minus = ((outer - r) * (outer + r) / two_r).max(0.0);
        let one_plus = ((r - inner) * (r + inner) / two_r).max(0.0);
        Ok(((one_minus * one_plus).sqrt(), 0.5 * (one_plus - one_minus)))
    }

    /// sin(q₄ − φ) of a joint vector: the side of its elbow.
    fn elbow_side(&self, q4: f64) -> f64 {
        let (s, c) = q4.fast_sin_cos();
        let (sp, cp) = self.reach.4;
        s * cp - c * sp
    }

    /// All solutions with joint 3 at `q3` \[rad\] (see the module documentation).
    /// Each is handed to `push` with its (elbow, shoulder, wrist) root indices.
    pub(crate) fn solve_q3(
        &self,
        goal: &Goal,
        q3: f64,
        opt: &Options,
        mut push: impl FnMut([f64; 7], (usize, usize, usize)),
    ) -> Result<(), Miss> {
        let d = &goal.d;
        let (st, ct) = self.elbow(d.norm())?;
        let sc3 = q3.fast_sin_cos();
        let [k0, k1, k2] = self.upper.map(|t| t.at(sc3));
        let r3 = self.h3.rot(sc3);
        // The near configuration's shoulder offset v_x for this target, and its elbow side.
        let (u_near, side_near) = match &opt.near {
            Some(q) => {
                let (s1, c1) = q[0].fast_sin_cos();
                let side = self.elbow_side(q[3]);
                (Some(c1 * d.x + s1 * d.y), if side.abs() > 0.05 { side.signum() } else { 0.0 })
            }
            None => (None, 0.0),
        };
        // Lanes: slot·5 + (q₁, q₂, q₅, q₆, q₇) for slot = 2·elbow + shoulder,
        // 20 + elbow for q₄, 24 + slot·4 + (q₅, q₆, q₇) for a second wrist
        // that is not derived from the first.
        let (mut ys, mut xs) = ([0.0; 40], [1.0; 40]);
        // Per slot: whether q₁ and each wrist's q₅ took their hints.
        let mut found: [Option<(bool, [bool; 2])>; 4] = [None; 4];
        let mut arm_miss = f64::INFINITY;
        let mut wrist_miss = f64::INFINITY;
        let (sp, cp) = self.reach.4;
        for (e, sign) in [1.0, -1.0].into_iter().enumerate() {
            if sign * side_near < 0.0 {
                continue;
            }
            let st = sign * st;
            let sc4 = (sp * ct + cp * st, cp * ct - sp * st);
            (ys[20 + e], xs[20 + e]) = sc4;
            let x = k0 + k1 * sc4.1 + k2 * sc4.0;
            let (p, rho) = self.shoulder.offsets(&x, d);
            let gap = rho - p.abs();
            if gap < -REACH_TOL * (1.0 + rho) {
                arm_miss = arm_miss.min(-gap);
                continue;
            }
            let u_abs = (gap.max(0.0) * (rho + p.abs())).sqrt();
            let r34 = r3 * self.h4.rot(sc4);
            for (sh, u) in [u_abs, -u_abs].into_iter().enumerate() {
                if u_near.is_some_and(|un| u * un < 0.0 && un.abs() > 0.5 * u_abs) {
                    continue;
                }
                let slot = 2 * e + sh;
                let arm = self.shoulder.root(&x, d, (p, rho), u, opt.q1_hint);
                (ys[5 * slot], xs[5 * slot]) = arm.a;
                (ys[5 * slot + 1], xs[5 * slot + 1]) = arm.b;
                let (s1, c1) = arm.sa;
                let r2 = self.h2.rot(arm.sb);
                let r12 = Matrix3::from_rows(&[
                    r2.row(0) * c1 - r2.row(1) * s1,
                    r2.row(0) * s1 + r2.row(1) * c1,
                    r2.row(2).into_owned(),
                ]);
                let r04t = (r12 * r34).transpose();
                match self.wrist_roots(&r04t, goal, opt, &mut ys, &mut xs, slot) {
                    Ok(w) => found[slot] = Some((arm.fixed, [w.pair[0].fixed, w.pair[1].fixed])),
                    Err(m) => wrist_miss = wrist_miss.min(m),
                }
            }
        }
        let batches = if self.wrist.aligned { 3 } else { 5 };
        let mut angles = [0.0; 40];
        for k in 0..batches {
            let lanes = 8 * k..8 * k + 8;
            let y = ys[lanes.clone()].try_into().unwrap_or([0.0; 8]);
            let x = xs[lanes].try_into().unwrap_or([1.0; 8]);
            angles[8 * k..8 * k + 8].copy_from_slice(&atan2_x8(y, x));
        }
        let mut any = false;
        for (slot, root) in found.iter().enumerate() {
            let Some((arm_fixed, wrist)) = *root else { continue };
            any = true;
            let a = &angles[5 * slot..5 * slot + 5];
            let q1 = if arm_fixed { opt.q1_hint } else { a[0] };
            let head = [q1, a[1], q3, angles[20 + slot / 2]];
            for (wi, [q5, q6, q7]) in self.wrist_angles(wrist, &angles, slot, opt).into_iter().enumerate() {
                push([head[0], head[1], head[2], head[3], q5, q6, q7], (slot / 2, slot % 2, wi));
            }
        }
        if any {
            return Ok(());
        }
        Err(if wrist_miss.is_finite() { Miss::Wrist(wrist_miss) } else { Miss::Arm(arm_miss) })
    }

    /// x₀(q₄) (see the module documentation) from sin and cos q₄.
    fn upper_wrist(&self, (s4, c4): (f64, f64)) -> V3 {
        let [k0, k1, k2] = self.upper.map(|t| t.par + t.perp);
        k0 + k1 * c4 + k2 * s4
    }

    /// The upper arm's frame with joints 1–3 at zero: x̂₀ and the part of h₂
    /// normal to it (the normal of the arm's plane on the iiwa).
    fn arm_frame(&self, x0: &V3) -> Matrix3<f64> {
        frame(&unit_or_z(x0), &self.h2v)
    }

    /// The arm angle's reference frame for the wrist centre at `d`: d̂ and
    /// the normal h₁ × d of the plane through axis 1 and the wrist centre
    /// (h₂ when the wrist centre is on axis 1, where that plane is undefined).
    fn reference_frame(&self, d: &V3) -> Matrix3<f64> {
        let normal = V3::new(-d.y, d.x, 0.0);
        let normal = if normal.norm() < SINGULAR { self.h2v } else { normal };
        frame(&unit_or_z(d), &normal)
    }

    /// The solutions at the arm angle `psi` \[rad\] (`SrsIk`'s module
    /// documentation derives it), all 8 or only the (elbow, shoulder, wrist)
    /// root `only`: the shoulder rotation Rot(d̂, ψ)·R° split by the
    /// spherical solve of axes 1, 2, 3, then the wrist. `flip` as
    /// [`Options::flip_singular_wrist`].
    pub(crate) fn solve_psi(
        &self,
        goal: &Goal,
        psi: f64,
        flip: bool,
        only: Option<[usize; 3]>,
        out: &mut Solutions,
    ) -> Result<(), Miss> {
        out.len = 0;
        let d = &goal.d;
        let (st, ct) = self.elbow(d.norm())?;
        let reference = self.reference_frame(d);
        let (sp, cp) = psi.fast_sin_cos();
        let (y, z) = (reference.column(1), reference.column(2));
        let turned = Matrix3::from_columns(&[reference.column(0).into_owned(), y * cp + z * sp, z * cp - y * sp]);
        let wanted = |k: usize, i: usize| only.is_none_or(|o| o[k] == i);
        let (sphi, cphi) = self.reach.4;
        let (mut arm_miss, mut wrist_miss) = (f64::INFINITY, f64::INFINITY);
        for (e, sign) in [1.0, -1.0].into_iter().enumerate() {
            if !wanted(0, e) {
                continue;
            }
            let st = sign * st;
            let sc4 = (sphi * ct + cphi * st, cphi * ct - sphi * st);
            let shoulder = turned * self.arm_frame(&self.upper_wrist(sc4)).transpose();
            let arms = match self.joints123.solve(&self.joints123.vectors.map(|v| shoulder * v), false) {
                Ok(arms) => arms,
                Err(miss) => {
                    arm_miss = arm_miss.min(miss);
                    continue;
                }
            };
            let (r4, q4) = (self.h4.rot(sc4), sc4.0.fast_atan2(sc4.1));
            for (sh, [q1, q2, q3]) in arms.into_iter().enumerate() {
                if !wanted(1, sh) {
                    continue;
                }
                let r04t =
                    (rot_z(q1) * self.h2.rot(q2.fast_sin_cos()) * self.h3.rot(q3.fast_sin_cos()) * r4).transpose();
                match self.wrist.solve(&goal.g.map(|g| r04t * g), flip) {
                    Ok(wrists) => {
                        for (wi, [q5, q6, q7]) in wrists.into_iter().enumerate().filter(|(wi, _)| wanted(2, *wi)) {
                            out.push([q1, q2, q3, q4, q5, q6, q7], (e, sh, wi));
                        }
                    }
                    Err(miss) => wrist_miss = wrist_miss.min(miss),
                }
            }
        }
        if out.len > 0 {
            return Ok(());
        }
        Err(if wrist_miss.is_finite() { Miss::Wrist(wrist_miss) } else { Miss::Arm(arm_miss) })
    }

    /// The arm angle ψ \[rad\] in (−π, π] of joint values `q` (7 finite
    /// values), the inverse of [`SrsKernel::solve_psi`]; it depends on
    /// q₁…q₄ only.
    pub(crate) fn psi_of(&self, q: &[f64]) -> f64 {
        let shoulder = rot_z(q[0]) * self.h2.rot(q[1].fast_sin_cos()) * self.h3.rot(q[2].fast_sin_cos());
        let x0 = self.upper_wrist(q[3].fast_sin_cos());
        let reference = self.reference_frame(&(shoulder * x0));
        let carried = shoulder * self.arm_frame(&x0).column(1);
        let (d, normal) = (reference.column(0), reference.column(1));
        wrap_angle(d.dot(&normal.cross(&carried)).atan2(normal.dot(&carried)))
    }

    /// The wrist's roots for R₀₄ᵀ (`r04t`), their atan2 arguments written
    /// into the lanes of `slot`; the miss when it has none.
    #[inline(always)]
    fn wrist_roots(
        &self,
        r04t: &Matrix3<f64>,
        goal: &Goal,
        opt: &Options,
        ys: &mut [f64; 40],
        xs: &mut [f64; 40],
        slot: usize,
    ) -> Result<Roots, f64> {
        let roots = self.wrist.roots(&goal.g.map(|g| r04t * g), opt.flip_singular_wrist)?;
        for (k, l) in [5 * slot + 2, 24 + 4 * slot].into_iter().enumerate() {
            (ys[l], xs[l]) = roots.pair[k].a;
            (ys[l + 1], xs[l + 1]) = roots.pair[k].b;
            (ys[l + 2], xs[l + 2]) = roots.c[k];
        }
        Ok(roots)
    }

    /// Both wrists' (q₅, q₆, q₇) of `slot` from the batched angles.
    fn wrist_angles(&self, fixed: [bool; 2], angles: &[f64; 40], slot: usize, opt: &Options) -> [[f64; 3]; 2] {
        let at = |l: usize| [angles[l], angles[l + 1], angles[l + 2]];
        self.wrist.angles(fixed, at(5 * slot + 2), at(24 + 4 * slot), opt.flip_singular_wrist)
    }
}
