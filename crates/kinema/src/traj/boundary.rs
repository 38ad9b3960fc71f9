//! Time-optimal one-coordinate motions between arbitrary boundary states
//! (position, velocity, acceleration), the building block of PTP motions
//! that are chained without stopping.
//!
//! A [`BoundaryLaw`] moves one coordinate from a [`BoundaryState`]
//! (p₀, v₀, a₀) to another (p_f, v_f, a_f) within |v| ≤ v_max, |a| ≤ a_max
//! and, when a jerk limit is given, |j| ≤ j_max:
//! - **third order** (jerk limit given): up to seven phases of constant jerk
//!   +j_max, 0 or −j_max — the structure of Ruckig (Berscheid & Kröger 2021);
//! - **second order** (no jerk limit): up to three phases of constant
//!   acceleration ±a_max or 0; the boundary accelerations must then be 0.
//!
//! [`BoundaryLaw::fastest`] is the time-optimal law. Its candidates are the
//! profiles whose acceleration rises, falls and rises again (or the mirror
//! image), each phase either a jerk ramp or a hold at a limit — +a_max,
//! −a_max or a cruise at ±v_max. Each family is reduced to one unknown
//! (the acceleration at the valley, or the length of a hold), whose roots
//! are isolated on a grid and refined by bisection; every candidate is then
//! rebuilt from the start state and re-checked (end state within 1e-9
//! relative, no limit exceeded by more than 1e-9 relative), and the fastest
//! survivor is returned.
//!
//! [`BoundaryLaw::with_duration`] moves between the same states in a given,
//! longer time (what synchronised PTP needs). Its families hold the velocity
//! at some v_c (a cruise with zero acceleration between two fastest
//! velocity changes) or hold the acceleration at some level below a_max;
//! where none of them has a root, two of their laws lasting that long, one
//! short of the target position and one past it, are blended (the limits
//! are convex and the motion is linear in the jerk). A duration can be
//! infeasible although a shorter one is feasible (a start
//! velocity towards a close target leaves no profile for some durations:
//! Ruckig's "blocked intervals"); [`BoundaryLaw::critical_durations`] lists
//! the durations where feasibility may change, and [`sync_duration`] picks
//! the smallest duration at which every coordinate has a law.
//!
//! States that no law can respect are refused with an error naming the
//! limit, rather than braked into the limits as Ruckig does: |v₀| or |v_f|
//! above v_max, |a₀| or |a_f| above a_max, or an acceleration that carries
//! the velocity past v_max whatever the jerk (v₀ + a₀|a₀|/(2 j_max) beyond
//! ±v_max, and the same backwards in time at the end).

use super::law::{MotionLimits, MIN_DURATION};
use crate::error::{Error, Result};

/// Position \[unit\], velocity \[unit/s\] and acceleration \[unit/s²\] of one coordinate.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BoundaryState {
    /// Position.
    pub p: f64,
    /// Velocity.
    pub v: f64,
    /// Acceleration.
    pub a: f64,
}

impl BoundaryState {
    /// A state at `p` with velocity `v` and acceleration `a`.
    pub fn new(p: f64, v: f64, a: f64) -> Self {
        BoundaryState { p, v, a }
    }

    /// At rest at `p`.
    pub fn rest(p: f64) -> Self {
        BoundaryState { p, v: 0.0, a: 0.0 }
    }
}

/// One phase: constant jerk `j` for `dt` seconds; `a` sets the acceleration
/// at the phase's start (second order) or `None` keeps it continuous.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Seg {
    dt: f64,
    j: f64,
    a: Option<f64>,
}

/// The most phases any candidate has (a blend of two seven-phase laws).
const MAX_SEGS: usize = 16;

#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Segs {
    s: [Seg; MAX_SEGS],
    n: usize,
}

impl Segs {
    fn push(&mut self, dt: f64, j: f64, a: Option<f64>) {
        if dt > 0.0 && self.n < MAX_SEGS {
            self.s[self.n] = Seg { dt, j, a };
            self.n += 1;
        }
    }
    fn extend(&mut self, other: &Segs) {
        for s in &other.s[..other.n] {
            self.push(s.dt, s.j, s.a);
        }
    }
    fn time(&self) -> f64 {
        self.s[..self.n].iter().map(|s| s.dt).sum()
    }
    /// The mirror image: every jerk and set acceleration negated.
    fn mirrored(&self) -> Segs {
        let mut out = *self;
        for s in &mut out.s[..out.n] {
            s.j = -s.j;
            s.a = s.a.map(|a| -a);
        }
        out
    }
    /// The same motion run backwards in time: phases reversed, jerk negated
    /// (only for continuous-acceleration, third-order phases).
    fn reversed(&self) -> Segs {
        let mut out = Segs::default();
        for s in self.s[..self.n].iter().rev() {
            out.push(s.dt, -s.j, None);
        }
        out
    }
}

/// Position, velocity and acceleration after `segs` from (0, v, a).
fn integrate(mut v: f64, mut a: f64, segs: &Segs) -> (f64, f64, f64) {
    let mut p = 0.0;
    for s in &segs.s[..segs.n] {
        if let Some(a0) = s.a {
            a = a0;
        }
        let u = s.dt;
        p += u * (v + u * (a / 2.0 + u * s.j / 6.0));
        v += u * (a + u * s.j / 2.0);
        a += u * s.j;
    }
    (p, v, a)
}

/// One phase of the built law: state at its start `t0` and constant jerk.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Piece {
    t0: f64,
    dt: f64,
    p: f64,
    v: f64,
    a: f64,
    j: f64,
}

impl Piece {
    #[inline]
    fn at(&self, u: f64) -> BoundaryState {
        BoundaryState {
            p: self.p + u * (self.v + u * (self.a / 2.0 + u * self.j / 6.0)),
            v: self.v + u * (self.a + u * self.j / 2.0),
            a: self.a + u * self.j,
        }
    }
}

/// A motion of one coordinate between two boundary states: phases of
/// constant jerk (third order) or constant acceleration (second order).
///
/// # Examples
/// ```
/// use kinema::traj::{BoundaryLaw, BoundaryState, MotionLimits};
/// // Arrive at 1 rad still moving at 0.5 rad/s, starting at rest.
/// let lim = MotionLimits::with_jerk(1.0, 2.0, 10.0);
/// let law = BoundaryLaw::fastest(BoundaryState::rest(0.0), BoundaryState::new(1.0, 0.5, 0.0), &lim)?;
/// let end = law.at(law.duration());
/// assert!((end.p - 1.0).abs() < 1e-9 && (end.v - 0.5).abs() < 1e-9);
/// // The same states in a longer, prescribed time (to synchronise joints).
/// let slow = BoundaryLaw::with_duration(law.from(), law.to(), &lim, 3.0)?;
/// assert!((slow.duration() - 3.0).abs() < 1e-12);
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundaryLaw {
    from: BoundaryState,
    to: BoundaryState,
    pieces: [Piece; MAX_SEGS],
    n: usize,
    duration: f64,
    jerk_limited: bool,
}

/// An [`Error::Infeasible`] about `what`.
fn infeasible(what: &str, reason: String) -> Error {
    Error::Infeasible { what: what.into(), reason }
}

/// The limits of one problem, validated.
#[derive(Debug, Clone, Copy)]
struct Lim {
    v: f64,
    a: f64,
    /// `None`: second order.
    j: Option<f64>,
}

/// The problem in a frame where it is mirrored and/or reversed in time.
#[derive(Debug, Clone, Copy)]
struct Prob {
    v0: f64,
    a0: f64,
    vf: f64,
    af: f64,
    dp: f64,
}

impl Prob {
    fn mirrored(&self) -> Prob {
        Prob { v0: -self.v0, a0: -self.a0, vf: -self.vf, af: -self.af, dp: -self.dp }
    }
    /// q(t) = p(T − t): start and end swap, velocities change sign.
    fn reversed(&self) -> Prob {
        Prob { v0: -self.vf, a0: self.af, vf: -self.v0, af: self.a0, dp: -self.dp }
    }
}

/// The transforms under which candidates are searched: identity, mirror,
/// reversal in time, both.
#[derive(Debug, Clone, Copy)]
struct Xf {
    mirror: bool,
    reverse: bool,
}

const XFS: [Xf; 4] = [
    Xf { mirror: false, reverse: false },
    Xf { mirror: true, reverse: false },
    Xf { mirror: false, reverse: true },
    Xf { mirror: true, reverse: true },
];

impl Xf {
    fn prob(self, p: &Prob) -> Prob {
        let p = if self.reverse { p.reversed() } else { *p };
        if self.mirror {
            p.mirrored()
        } else {
            p
        }
    }
    /// Segments found for the transformed problem, back in the original frame.
    fn back(self, s: &Segs) -> Segs {
        let s = if self.mirror { s.mirrored() } else { *s };
        if self.reverse {
            s.reversed()
        } else {
            s
        }
    }
}

/// All roots of `f` on \[lo, hi\]: sign changes on a grid of `n` intervals,
/// refined by bisection, plus near-tangent roots found where |f| has a local
/// minimum between grid points. `f` may return NaN where the family has no
/// profile.
fn roots(f: &dyn Fn(f64) -> f64, lo: f64, hi: f64, n: usize, out: &mut Vec<f64>) {
    if !(lo.is_finite() && hi.is_finite()) || hi < lo {
        return;
    }
    if hi == lo {
        if f(lo) == 0.0 {
            out.push(lo);
        }
        return;
    }
    let mut xs: Vec<f64> = (0..=n).map(|i| lo + (hi - lo) * i as f64 / n as f64).collect();
    xs[n] = hi; // exactly: roots on the bounds (a phase of length 0) are common
    let ys: Vec<f64> = xs.iter().map(|&x| f(x)).collect();
    let bisect = |mut a: f64, mut fa: f64, mut b: f64| -> f64 {
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            if m <= a || m >= b {
                break;
            }
            let fm = f(m);
            if fm.is_nan() {
                break;
            }
            if fm == 0.0 {
                return m;
            }
            if (fm < 0.0) == (fa < 0.0) {
                a = m;
                fa = fm;
            } else {
                b = m;
            }
        }
        0.5 * (a + b)
    };
    for i in 0..=n {
        if ys[i] == 0.0 {
            out.push(xs[i]);
        }
        if i == n {
            break;
        }
        let (ya, yb) = (ys[i], ys[i + 1]);
        if ya.is_finite() && yb.is_finite() && ya != 0.0 && yb != 0.0 && (ya < 0.0) != (yb < 0.0) {
            out.push(bisect(xs[i], ya, xs[i + 1]));
        }
    }
    // A pair of roots inside one grid interval (or a tangent root): a local
    // minimum of |f| without a sign change; look for the extremum.
    for i in 1..n {
        let (ya, ym, yb) = (ys[i - 1], ys[i], ys[i + 1]);
        if !(ya.is_finite() && ym.is_finite() && yb.is_finite()) || ym == 0.0 {
            continue;
        }
        let s = ym.signum();
        if ya.signum() != s || yb.signum() != s || !(ym.abs() <= ya.abs() && ym.abs() <= yb.abs()) {
            continue;
        }
        // Golden-section search for the minimum of s·f on [x_{i-1}, x_{i+1}].
        let (mut a, mut b) = (xs[i - 1], xs[i + 1]);
        let g = 0.618_033_988_749_895;
        let mut c = b - g * (b - a);
        let mut d = a + g * (b - a);
        let (mut fc, mut fd) = (s * f(c), s * f(d));
        for _ in 0..80 {
            if !(fc.is_finite() && fd.is_finite()) {
                break;
            }
            if fc < fd {
                b = d;
                d = c;
                fd = fc;
                c = b - g * (b - a);
                fc = s * f(c);
            } else {
                a = c;
                c = d;
                fc = fd;
                d = a + g * (b - a);
                fd = s * f(d);
            }
            if fc <= 0.0 || fd <= 0.0 {
                break;
            }
        }
        let (xm, fm) = if fc < fd { (c, fc) } else { (d, fd) };
        if !fm.is_finite() {
            continue;
        }
        if fm <= 0.0 {
            if fm == 0.0 {
                out.push(xm);
            } else {
                out.push(bisect(xs[i - 1], ya, xm));
                out.push(bisect(xm, s * fm, xs[i + 1]));
            }
        } else if fm <= 1e-13 * ym.abs().max(1e-300) {
            out.push(xm); // tangent: accepted if the rebuilt law checks out
        }
    }
}

/// Grid intervals for the one-unknown searches.
const GRID: usize = 64;

// ---------------------------------------------------------------------------
// Third order.

/// The velocity change (v0, a0) → (v1, a1) with jerk +j up to a peak
/// acceleration a_p (held at a_max if it would exceed it), then −j down to
/// a1. `root` picks a_p = +√K or −√K (both may be valid).
fn rise(v0: f64, a0: f64, v1: f64, a1: f64, l: &Lim, j: f64, root: bool) -> Option<Segs> {
    let k = j * (v1 - v0) + 0.5 * (a0 * a0 + a1 * a1);
    let hi = a0.max(a1);
    let tol = 1e-12 * l.a;
    if k < -tol * l.a {
        return None;
    }
    let r = k.max(0.0).sqrt();
    let mut ap = if root { r } else { -r };
    if ap < hi - tol {
        return None;
    }
    ap = ap.max(hi);
    let mut hold = 0.0;
    if ap > l.a {
        if !root {
            return None;
        }
        ap = l.a;
        hold = (v1 - v0 - (2.0 * ap * ap - a0 * a0 - a1 * a1) / (2.0 * j)) / ap;
        if hold < 0.0 {
            return None;
        }
    }
    let mut s = Segs::default();
    s.push((ap - a0) / j, j, None);
    s.push(hold, 0.0, None);
    s.push((ap - a1) / j, -j, None);
    Some(s)
}

/// As [`rise`] with the signs reversed: −j down to a valley, hold at −a_max, +j.
fn fall(v0: f64, a0: f64, v1: f64, a1: f64, l: &Lim, j: f64, root: bool) -> Option<Segs> {
    rise(-v0, -a0, -v1, -a1, l, j, root).map(|s| s.mirrored())
}

/// The fastest velocity change (v0, a0) → (v1, a1), ignoring position.
fn fastest_change(v0: f64, a0: f64, v1: f64, a1: f64, l: &Lim, j: f64) -> Option<Segs> {
    let mut best: Option<Segs> = None;
    for root in [true, false] {
        for s in [rise(v0, a0, v1, a1, l, j, root), fall(v0, a0, v1, a1, l, j, root)].into_iter().flatten() {
            if best.is_none_or(|b| s.time() < b.time()) {
                best = Some(s);
            }
        }
    }
    best
}

/// Residual of a candidate's position; NaN when there is none.
fn residual(p: &Prob, s: Option<Segs>) -> f64 {
    match s {
        Some(s) => integrate(p.v0, p.a0, &s).0 - p.dp,
        None => f64::NAN,
    }
}

/// Time-optimal candidates of one frame (acceleration rises, falls, rises).
fn fastest_third(p: &Prob, l: &Lim, j: f64, out: &mut Vec<Segs>) {
    let mut xs = Vec::new();
    // Cruise at +v_max between the fastest changes to and from it.
    for ra in [true, false] {
        for rb in [true, false] {
            let (Some(a), Some(b)) = (rise(p.v0, p.a0, l.v, 0.0, l, j, ra), fall(l.v, 0.0, p.vf, p.af, l, j, rb))
            else {
                continue;
            };
            let pa = integrate(p.v0, p.a0, &a).0;
            let pb = integrate(l.v, 0.0, &b).0;
            let cruise = (p.dp - pa - pb) / l.v;
            if cruise >= 0.0 {
                let mut s = a;
                s.push(cruise, 0.0, None);
                s.extend(&b);
                out.push(s);
            }
        }
    }
    // No cruise, valley acceleration x ∈ [−a_max, a_f], final ramp +j to a_f.
    let valley = |x: f64, root: bool| -> Option<Segs> {
        let vc = p.vf - (p.af * p.af - x * x) / (2.0 * j);
        let mut s = rise(p.v0, p.a0, vc, x, l, j, root)?;
        s.push((p.af - x) / j, j, None);
        Some(s)
    };
    for root in [true, false] {
        xs.clear();
        roots(&|x| residual(p, valley(x, root)), -l.a, p.af, GRID, &mut xs);
        out.extend(xs.iter().filter_map(|&x| valley(x, root)));
    }
    // No cruise, valley held at −a_max for x seconds.
    let v7 = p.vf - (p.af * p.af - l.a * l.a) / (2.0 * j);
    let held = |x: f64, root: bool| -> Option<Segs> {
        let mut s = rise(p.v0, p.a0, v7 + l.a * x, -l.a, l, j, root)?;
        s.push(x, 0.0, None);
        s.push((p.af + l.a) / j, j, None);
        Some(s)
    };
    let hmax = (l.v - v7) / l.a;
    if hmax > 0.0 {
        for root in [true, false] {
            xs.clear();
            roots(&|x| residual(p, held(x, root)), 0.0, hmax, GRID, &mut xs);
            out.extend(xs.iter().filter_map(|&x| held(x, root)));
        }
    }
}

/// Candidates lasting exactly `t` with one free hold: acceleration rises to a
/// peak a_p ≤ a_max held for some time, falls to a valley x, rises to a_f
/// (the valley held at −a_max for `hold` seconds when x = −a_max).
fn held_peak(p: &Prob, l: &Lim, j: f64, t: f64, x: f64, hold: f64, root: bool) -> Option<Segs> {
    let t7 = (p.af - x) / j;
    let vc = p.vf - (p.af * p.af - x * x) / (2.0 * j) + if hold > 0.0 { -x * hold } else { 0.0 };
    let tau = t - t7 - hold;
    if !(tau >= 0.0) {
        return None;
    }
    // a_p² − a_p(jτ + a0 + x) + (a0² + x²)/2 + j(vc − v0) = 0
    let b = j * tau + p.a0 + x;
    let c = 0.5 * (p.a0 * p.a0 + x * x) + j * (vc - p.v0);
    let disc = b * b - 4.0 * c;
    if disc < -1e-12 * b * b {
        return None;
    }
    let r = disc.max(0.0).sqrt();
    let ap = if root { 0.5 * (b + r) } else { 0.5 * (b - r) };
    let lo = p.a0.max(x);
    let tol = 1e-12 * l.a;
    if ap < lo - tol || ap > l.a + tol {
        return None;
    }
    let ap = ap.clamp(lo, l.a);
    let (t1, t3) = ((ap - p.a0) / j, (ap - x) / j);
    let th = tau - t1 - t3;
    if th < -1e-12 * t.max(1.0) {
        return None;
    }
    let mut s = Segs::default();
    s.push(t1, j, None);
    s.push(th.max(0.0), 0.0, None);
    s.push(t3, -j, None);
    s.push(hold, 0.0, None);
    s.push(t7, j, None);
    Some(s)
}

/// Candidates of one frame lasting exactly `t` (third order).
fn timed_third(p: &Prob, l: &Lim, j: f64, t: f64, out: &mut Vec<Segs>) {
    let mut xs = Vec::new();
    for root in [true, false] {
        xs.clear();
        roots(&|x| residual(p, held_peak(p, l, j, t, x, 0.0, root)), -l.a, p.af, GRID, &mut xs);
        out.extend(xs.iter().filter_map(|&x| held_peak(p, l, j, t, x, 0.0, root)));
        xs.clear();
        roots(&|h| residual(p, held_peak(p, l, j, t, -l.a, h, root)), 0.0, t, GRID, &mut xs);
        out.extend(xs.iter().filter_map(|&h| held_peak(p, l, j, t, -l.a, h, root)));
    }
}

/// Cruise at v_c (zero acceleration) between the fastest changes to and
/// from it, lasting exactly `t`; for any order (`j` = None: second order).
fn cruise_at(p: &Prob, l: &Lim, t: f64, vc: f64) -> Option<Segs> {
    let (a, b) = match l.j {
        Some(j) => (fastest_change(p.v0, p.a0, vc, 0.0, l, j)?, fastest_change(vc, 0.0, p.vf, p.af, l, j)?),
        None => {
            let ramp = |from: f64, to: f64| {
                let mut s = Segs::default();
                s.push((to - from).abs() / l.a, 0.0, Some(l.a.copysign(to - from)));
                s
            };
            (ramp(p.v0, vc), ramp(vc, p.vf))
        }
    };
    let cruise = t - a.time() - b.time();
    if !(cruise >= -1e-12 * t.max(1.0)) {
        return None;
    }
    let mut s = a;
    s.push(cruise.max(0.0), 0.0, Some(0.0).filter(|_| l.j.is_none()));
    s.extend(&b);
    Some(s)
}

/// Cruise candidates lasting exactly `t`: the cruise velocities v_c for which
/// the two fastest changes fit into `t` form intervals; on each, the roots of
/// the position residual.
fn timed_cruise(p: &Prob, l: &Lim, t: f64, out: &mut Vec<Segs>) {
    let slack = |vc: f64| -> f64 {
        let f = |a: Option<Segs>| a.map_or(f64::INFINITY, |s| s.time());
        match l.j {
            Some(j) => t - f(fastest_change(p.v0, p.a0, vc, 0.0, l, j)) - f(fastest_change(vc, 0.0, p.vf, p.af, l, j)),
            None => t - ((vc - p.v0).abs() + (p.vf - vc).abs()) / l.a,
        }
    };
    let n = 4 * GRID;
    let xs: Vec<f64> = (0..=n).map(|i| -l.v + 2.0 * l.v * i as f64 / n as f64).collect();
    let ss: Vec<f64> = xs.iter().map(|&x| slack(x)).collect();
    // The slack is largest near its best sample; feasible intervals are
    // runs of samples with slack ≥ 0, extended to slack = 0 by bisection.
    let edge = |mut inside: f64, mut outside: f64| -> f64 {
        for _ in 0..200 {
            let m = 0.5 * (inside + outside);
            if m == inside || m == outside {
                break;
            }
            if slack(m) >= 0.0 {
                inside = m;
            } else {
                outside = m;
            }
        }
        inside
    };
    let mut intervals = Vec::new();
    let mut i = 0;
    while i <= n {
        if ss[i] >= 0.0 {
            let start = i;
            while i < n && ss[i + 1] >= 0.0 {
                i += 1;
            }
            let lo = if start == 0 { xs[0] } else { edge(xs[start], xs[start - 1]) };
            let hi = if i == n { xs[n] } else { edge(xs[i], xs[i + 1]) };
            intervals.push((lo, hi));
        }
        i += 1;
    }
    if intervals.is_empty() {
        // A feasible set narrower than the grid: search around the best sample.
        let k = (0..=n).max_by(|&a, &b| ss[a].total_cmp(&ss[b])).unwrap_or(0);
        let (mut a, mut b) = (xs[k.saturating_sub(1)], xs[(k + 1).min(n)]);
        let g = 0.618_033_988_749_895;
        for _ in 0..100 {
            let c = b - g * (b - a);
            let d = a + g * (b - a);
            if slack(c) > slack(d) {
                b = d;
            } else {
                a = c;
            }
        }
        let m = 0.5 * (a + b);
        if slack(m) >= 0.0 {
            intervals.push((edge(m, xs[k.saturating_sub(1)]), edge(m, xs[(k + 1).min(n)])));
        }
    }
    let mut rs = Vec::new();
    for (lo, hi) in intervals {
        rs.clear();
        roots(&|vc| residual(p, cruise_at(p, l, t, vc)), lo, hi, GRID, &mut rs);
        out.extend(rs.iter().filter_map(|&vc| cruise_at(p, l, t, vc)));
    }
}

// ---------------------------------------------------------------------------
// Second order.

/// Time-optimal candidates of one frame: +a_max up to a peak velocity, an
/// optional cruise at v_max, −a_max down to v_f.
fn fastest_second(p: &Prob, l: &Lim, out: &mut Vec<Segs>) {
    let a = l.a;
    let build = |vp: f64, cruise: f64| {
        let mut s = Segs::default();
        s.push((vp - p.v0) / a, 0.0, Some(a));
        s.push(cruise, 0.0, Some(0.0));
        s.push((vp - p.vf) / a, 0.0, Some(-a));
        s
    };
    let (ta, tb) = ((l.v - p.v0) / a, (l.v - p.vf) / a);
    let cruise = (p.dp - 0.5 * (p.v0 + l.v) * ta - 0.5 * (l.v + p.vf) * tb) / l.v;
    if ta >= 0.0 && tb >= 0.0 && cruise >= 0.0 {
        out.push(build(l.v, cruise));
    }
    let k = a * p.dp + 0.5 * (p.v0 * p.v0 + p.vf * p.vf);
    if k >= 0.0 {
        for vp in [k.sqrt(), -k.sqrt()] {
            let vp = vp.min(l.v);
            if vp >= p.v0.max(p.vf) - 1e-12 * l.v {
                out.push(build(vp.max(p.v0.max(p.vf)), 0.0));
            }
        }
    }
}

/// Candidates lasting exactly `t` (second order): a cruise at v_c between
/// ramps at ±a_max, solved in closed form on each sign pattern.
fn timed_second(p: &Prob, l: &Lim, t: f64, out: &mut Vec<Segs>) {
    for sa in [1.0, -1.0] {
        for sb in [1.0, -1.0] {
            // t_A = α(v_c − v0), t_B = β(v_f − v_c); position quadratic in v_c.
            let (al, be) = (sa / l.a, sb / l.a);
            let qa = 0.5 * (be - al);
            let qb = t + al * p.v0 - be * p.vf;
            let qc = 0.5 * (be * p.vf * p.vf - al * p.v0 * p.v0) - p.dp;
            let mut cands = [f64::NAN; 2];
            if qa == 0.0 {
                cands[0] = -qc / qb;
            } else {
                let d = qb * qb - 4.0 * qa * qc;
                if d >= 0.0 {
                    // Numerically stable pair of roots.
                    let q = -0.5 * (qb + d.sqrt().copysign(qb));
                    cands = [q / qa, qc / q];
                }
            }
            for vc in cands {
                if vc.is_finite() && vc.abs() <= l.v * (1.0 + 1e-12) {
                    if let Some(s) = cruise_at(p, l, t, vc.clamp(-l.v, l.v)) {
                        out.push(s);
                    }
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------

fn lim_of(limits: &MotionLimits) -> Result<Lim> {
    for (name, v) in [("vmax", limits.vel), ("amax", limits.acc)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::OutOfRange { what: name.into(), value: v, expected: "a positive finite number".into() });
        }
    }
    if let Some(j) = limits.jerk {
        if !(j.is_finite() && j > 0.0) {
            return Err(Error::OutOfRange {
                what: "jmax".into(),
                value: j,
                expected: "a positive finite number".into(),
            });
        }
    }
    Ok(Lim { v: limits.vel, a: limits.acc, j: limits.jerk })
}

/// Refuses states that no law within `l` can start or end at.
fn check_states(from: &BoundaryState, to: &BoundaryState, l: &Lim) -> Result<()> {
    for (what, s) in [("start", from), ("target", to)] {
        for (name, x) in [("position", s.p), ("velocity", s.v), ("acceleration", s.a)] {
            if !x.is_finite() {
                return Err(Error::NotFinite { what: format!("{what} {name}"), value: x });
            }
        }
        let tol = 1e-12;
        if s.v.abs() > l.v * (1.0 + tol) {
            return Err(Error::OutOfRange {
                what: format!("{what} velocity"),
                value: s.v,
                expected: format!(
                    "a velocity within ±{} (vmax); no motion within the limits starts or ends beyond it",
                    l.v
                ),
            });
        }
        match l.j {
            None if s.a != 0.0 => {
                return Err(Error::MissingLimit {
                    limit: "jerk".into(),
                    option: "jmax".into(),
                    needed_by: format!(
                        "the {what} acceleration {} (without one the acceleration is a step and boundary \
                         accelerations must be 0)",
                        s.a
                    ),
                })
            }
            None => {}
            Some(j) => {
                if s.a.abs() > l.a * (1.0 + tol) {
                    return Err(Error::OutOfRange {
                        what: format!("{what} acceleration"),
                        value: s.a,
                        expected: format!("an acceleration within ±{} (amax)", l.a),
                    });
                }
                // The velocity the acceleration carries to, forwards from the
                // start or backwards from the target, before jerk can undo it.
                let reach =
                    if what == "start" { s.v + s.a * s.a.abs() / (2.0 * j) } else { s.v - s.a * s.a.abs() / (2.0 * j) };
                if reach.abs() > l.v * (1.0 + 1e-9) {
                    return Err(infeasible(
                        "vmax",
                        format!(
                            "the {what} state (velocity {}, acceleration {}) reaches a velocity of {reach} \
                             {} the acceleration can be brought to 0 with jmax {j}, beyond vmax {}",
                            s.v,
                            s.a,
                            if what == "start" { "before" } else { "when traced back to where" },
                            l.v
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

impl BoundaryLaw {
    fn build(from: BoundaryState, to: BoundaryState, segs: &Segs, jerk_limited: bool) -> BoundaryLaw {
        let mut law = BoundaryLaw { from, to, pieces: [Piece::default(); MAX_SEGS], n: 0, duration: 0.0, jerk_limited };
        let mut st = from;
        let mut t = 0.0;
        for s in &segs.s[..segs.n] {
            if let Some(a) = s.a {
                st.a = a;
            }
            let pc = Piece { t0: t, dt: s.dt, p: st.p, v: st.v, a: st.a, j: s.j };
            st = pc.at(s.dt);
            law.pieces[law.n] = pc;
            law.n += 1;
            t += s.dt;
        }
        law.duration = t;
        law
    }

    /// The state reached at the end of the last phase, before it is replaced
    /// by the exact target (what the re-check compares).
    fn end_state(&self) -> BoundaryState {
        if self.n == 0 {
            return self.from;
        }
        let last = &self.pieces[self.n - 1];
        last.at(last.dt)
    }

    /// Whether the law reaches its target and keeps within `l` (1e-9 relative).
    fn valid(&self, l: &Lim) -> bool {
        self.valid_but_position(l) && self.position_reached()
    }

    fn position_reached(&self) -> bool {
        let e = self.end_state();
        // The motion's own scale (a short motion far from 0 is held to its
        // size, not to its coordinates), plus the rounding of the coordinates.
        let (t, f, to) = (self.duration, &self.from, &self.to);
        let scale_p = (to.p - f.p).abs().max((f.v.abs() + to.v.abs()) * t).max((f.a.abs() + to.a.abs()) * t * t);
        let tol_p = 1e-9 * scale_p + 8.0 * f64::EPSILON * f.p.abs().max(to.p.abs());
        (e.p - self.to.p).abs() <= tol_p
    }

    /// Whether the law ends at the target's velocity and acceleration and keeps within `l`.
    fn valid_but_position(&self, l: &Lim) -> bool {
        let e = self.end_state();
        if !((e.v - self.to.v).abs() <= 1e-9 * l.v) {
            return false;
        }
        if self.jerk_limited && !((e.a - self.to.a).abs() <= 1e-9 * l.a) {
            return false;
        }
        let (v, a, j) = self.peaks();
        v <= l.v * (1.0 + 1e-9)
            && a <= l.a * (1.0 + 1e-9)
            && (!self.jerk_limited || j <= l.j.unwrap_or(0.0) * (1.0 + 1e-9))
    }

    fn from_candidates(from: BoundaryState, to: BoundaryState, l: &Lim, cands: &[Segs]) -> Vec<BoundaryLaw> {
        let mut laws: Vec<BoundaryLaw> = cands
            .iter()
            .filter(|s| s.s[..s.n].iter().all(|g| g.dt.is_finite() && g.dt >= 0.0))
            .map(|s| Self::build(from, to, s, l.j.is_some()))
            .filter(|law| law.valid(l))
            .collect();
        laws.sort_by(|a, b| a.duration.total_cmp(&b.duration));
        laws
    }

    fn problem(from: &BoundaryState, to: &BoundaryState) -> Prob {
        Prob { v0: from.v, a0: from.a, vf: to.v, af: to.a, dp: to.p - from.p }
    }

    /// Every locally time-optimal law (the candidates that survive the
    /// re-check), fastest first.
    fn candidates(from: BoundaryState, to: BoundaryState, l: &Lim) -> Vec<BoundaryLaw> {
        let p = Self::problem(&from, &to);
        let mut cands = Vec::new();
        for xf in &XFS[..if l.j.is_some() { 4 } else { 2 }] {
            let q = xf.prob(&p);
            let start = cands.len();
            match l.j {
                Some(j) => fastest_third(&q, l, j, &mut cands),
                None => fastest_second(&q, l, &mut cands),
            }
            for s in &mut cands[start..] {
                *s = xf.back(s);
            }
        }
        let mut laws = Self::from_candidates(from, to, l, &cands);
        if from == to {
            laws.insert(0, Self::build(from, to, &Segs::default(), l.j.is_some()));
        }
        laws
    }

    /// The time-optimal law from `from` to `to` within `limits` (a jerk
    /// limit makes it third order; without one it is second order and the
    /// boundary accelerations must be 0). A start equal to the target (also
    /// a moving one) gives a law of duration 0: it is already there.
    ///
    /// Rest to rest, the duration equals [`TimeLaw::from_limits`]'s trapezoid
    /// or S-curve over the same distance. Errors: a limit that is not a
    /// positive finite number; a non-finite state; a state no law can
    /// respect (see the module documentation); a duration below
    /// [`MIN_DURATION`]; no candidate passing the re-check (not expected: it
    /// would be a bug, reported rather than returned).
    ///
    /// [`TimeLaw::from_limits`]: super::TimeLaw::from_limits
    pub fn fastest(from: BoundaryState, to: BoundaryState, limits: &MotionLimits) -> Result<BoundaryLaw> {
        let l = lim_of(limits)?;
        check_states(&from, &to, &l)?;
        if from == to {
            return Ok(Self::build(from, to, &Segs::default(), l.j.is_some()));
        }
        let law = Self::candidates(from, to, &l).into_iter().next().ok_or_else(|| no_profile(&from, &to, None))?;
        check_min(law.duration)?;
        Ok(law)
    }

    /// The durations at which the set of feasible durations may change:
    /// the durations of every locally time-optimal law, fastest first. The
    /// first is [`BoundaryLaw::fastest`]'s; a duration between two listed
    /// ones is feasible either throughout or nowhere.
    pub fn critical_durations(from: BoundaryState, to: BoundaryState, limits: &MotionLimits) -> Result<Vec<f64>> {
        let l = lim_of(limits)?;
        check_states(&from, &to, &l)?;
        let mut d: Vec<f64> = Self::candidates(from, to, &l).iter().map(|c| c.duration).collect();
        d.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * b.abs().max(1e-300));
        Ok(d)
    }

    /// A law from `from` to `to` within `limits` lasting exactly `duration`
    /// \[s\] (at least the fastest law's). Errors: as [`BoundaryLaw::fastest`];
    /// a duration shorter than the fastest; a duration inside a blocked
    /// interval (no law lasts exactly that long: see the module documentation).
    pub fn with_duration(
        from: BoundaryState,
        to: BoundaryState,
        limits: &MotionLimits,
        duration: f64,
    ) -> Result<BoundaryLaw> {
        let l = lim_of(limits)?;
        check_states(&from, &to, &l)?;
        Self::timed(from, to, &l, duration, &Self::candidates(from, to, &l))
    }

    /// [`BoundaryLaw::with_duration`] with the limits checked and the locally
    /// optimal laws (`optimal`, fastest first) already known.
    fn timed(
        from: BoundaryState,
        to: BoundaryState,
        l: &Lim,
        duration: f64,
        optimal: &[BoundaryLaw],
    ) -> Result<BoundaryLaw> {
        let l = *l;
        if !(duration.is_finite() && duration >= 0.0) {
            return Err(Error::OutOfRange {
                what: "duration".into(),
                value: duration,
                expected: "a finite duration ≥ 0 [s]".into(),
            });
        }
        let still = from.v == 0.0 && from.a == 0.0 && to.v == 0.0 && to.a == 0.0 && from.p == to.p;
        if from == to && duration == 0.0 {
            return Ok(Self::build(from, to, &Segs::default(), l.j.is_some()));
        }
        if let Some(fast) = optimal.first() {
            if duration < fast.duration * (1.0 - 1e-12) {
                return Err(Error::OutOfRange {
                    what: "duration".into(),
                    value: duration,
                    expected: format!("at least {} s, the fastest motion between these states [s]", fast.duration),
                });
            }
        }
        check_min(duration)?;
        // A locally optimal law of this very duration (a limit of the families below).
        if let Some(c) = optimal.iter().find(|c| (c.duration - duration).abs() <= 1e-12 * duration) {
            return Ok(*c);
        }
        let p = Self::problem(&from, &to);
        let lasting = |cands: &[Segs]| {
            Self::from_candidates(from, to, &l, cands)
                .into_iter()
                .find(|c| (c.duration - duration).abs() <= 1e-12 * duration.max(1.0))
        };
        // The cheaper families first: a cruise (every rest-to-rest and most
        // other cases), then the held accelerations.
        let mut cands = Vec::new();
        if still {
            // At rest at the target: stay there.
            let mut s = Segs::default();
            s.push(duration, 0.0, None);
            cands.push(s);
        }
        timed_cruise(&p, &l, duration, &mut cands);
        if l.j.is_none() {
            timed_second(&p, &l, duration, &mut cands);
        }
        if let Some(law) = lasting(&cands) {
            return Ok(law);
        }
        if let Some(j) = l.j {
            cands.clear();
            for xf in XFS {
                let q = xf.prob(&p);
                let start = cands.len();
                timed_third(&q, &l, j, duration, &mut cands);
                for s in &mut cands[start..] {
                    *s = xf.back(s);
                }
            }
            if let Some(law) = lasting(&cands) {
                return Ok(law);
            }
        }
        if let Some(j) = l.j {
            if let Some(law) = Self::blend(from, to, &l, j, duration) {
                return Ok(law);
            }
        }
        Err(no_profile(&from, &to, Some(duration)))
    }

    /// No family has a root at `t`: two laws of the families that last `t`
    /// and end at the target's velocity and acceleration, one short of the
    /// target position and one past it, blended. The limits are convex
    /// (|v|, |a|, |j| bounded) and the motion is linear in the jerk, so
    /// λ·j₁(t) + (1 − λ)·j₂(t) keeps them and ends at λ·p₁ + (1 − λ)·p₂.
    fn blend(from: BoundaryState, to: BoundaryState, l: &Lim, j: f64, t: f64) -> Option<BoundaryLaw> {
        let p = Self::problem(&from, &to);
        let mut below: Option<(f64, Segs)> = None;
        let mut above: Option<(f64, Segs)> = None;
        let mut consider = |s: Option<Segs>| {
            let Some(s) = s else { return };
            if (s.time() - t).abs() > 1e-12 * t.max(1.0) || s.s[..s.n].iter().any(|g| !(g.dt >= 0.0)) {
                return;
            }
            let law = Self::build(from, to, &s, true);
            if !law.valid_but_position(l) {
                return;
            }
            let r = law.end_state().p - to.p;
            if r <= 0.0 && below.is_none_or(|(b, _)| r > b) {
                below = Some((r, s));
            }
            if r >= 0.0 && above.is_none_or(|(b, _)| r < b) {
                above = Some((r, s));
            }
        };
        let n = 4 * GRID;
        let grid = |lo: f64, hi: f64| (0..=n).map(move |i| lo + (hi - lo) * i as f64 / n as f64);
        for vc in grid(-l.v, l.v) {
            consider(cruise_at(&p, l, t, vc));
        }
        for xf in XFS {
            let q = xf.prob(&p);
            for root in [true, false] {
                for x in grid(-l.a, q.af) {
                    consider(held_peak(&q, l, j, t, x, 0.0, root).map(|s| xf.back(&s)));
                }
                for h in grid(0.0, t) {
                    consider(held_peak(&q, l, j, t, -l.a, h, root).map(|s| xf.back(&s)));
                }
            }
        }
        let ((r1, s1), (r2, s2)) = (below?, above?);
        let lambda = if r2 == r1 { 0.0 } else { r2 / (r2 - r1) }; // weight of s1
                                                                  // Merge the two phase grids.
        let mut cuts: Vec<f64> = Vec::with_capacity(s1.n + s2.n + 1);
        for s in [&s1, &s2] {
            let mut acc = 0.0;
            for g in &s.s[..s.n] {
                acc += g.dt;
                cuts.push(acc);
            }
        }
        cuts.sort_by(f64::total_cmp);
        cuts.dedup_by(|a, b| (*a - *b).abs() <= 1e-14 * t);
        let jerk_at = |s: &Segs, tm: f64| {
            let mut acc = 0.0;
            for g in &s.s[..s.n] {
                acc += g.dt;
                if tm < acc {
                    return g.j;
                }
            }
            s.s[s.n.saturating_sub(1)].j
        };
        let mut out = Segs::default();
        let mut prev = 0.0;
        for &c in &cuts {
            let mid = 0.5 * (prev + c);
            out.push(c - prev, lambda * jerk_at(&s1, mid) + (1.0 - lambda) * jerk_at(&s2, mid), None);
            prev = c;
        }
        let law = Self::build(from, to, &out, true);
        (law.valid(l) && (law.duration - t).abs() <= 1e-12 * t.max(1.0)).then_some(law)
    }

    /// The start state.
    pub fn from(&self) -> BoundaryState {
        self.from
    }

    /// The target state.
    pub fn to(&self) -> BoundaryState {
        self.to
    }

    /// Duration \[s\].
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// Whether the law is jerk-limited (third order).
    pub fn jerk_limited(&self) -> bool {
        self.jerk_limited
    }

    /// Durations of the phases \[s\], in order (zero-length phases left out).
    pub fn phase_times(&self) -> Vec<f64> {
        self.pieces[..self.n].iter().map(|p| p.dt).collect()
    }

    /// Jerk of each phase \[unit/s³\] (0 in every phase of a second-order law,
    /// whose acceleration steps between phases).
    pub fn phase_jerks(&self) -> Vec<f64> {
        self.pieces[..self.n].iter().map(|p| p.j).collect()
    }

    /// The state at time `t` \[s\]: the start state before 0; from the
    /// duration on, the target state (its position advanced by the target
    /// velocity and acceleration, so that a chained motion continues it).
    #[inline]
    pub fn at(&self, t: f64) -> BoundaryState {
        if !(t > 0.0) {
            return self.from;
        }
        if t >= self.duration || self.n == 0 {
            return self.to;
        }
        let i = self.pieces[..self.n].iter().rposition(|p| p.t0 <= t).unwrap_or(0);
        let u = (t - self.pieces[i].t0).clamp(0.0, self.pieces[i].dt);
        self.pieces[i].at(u)
    }

    /// Jerk at time `t` (0 outside the law).
    pub fn jerk_at(&self, t: f64) -> f64 {
        if !(t > 0.0) || t >= self.duration || self.n == 0 {
            return 0.0;
        }
        let i = self.pieces[..self.n].iter().rposition(|p| p.t0 <= t).unwrap_or(0);
        self.pieces[i].j
    }

    /// The largest |v|, |a| and |j| over the law, in closed form (velocity
    /// extrema inside a phase where the acceleration crosses 0). |j| is
    /// infinite for a second-order law with an acceleration step.
    pub fn peaks(&self) -> (f64, f64, f64) {
        let (mut v, mut a, mut j) =
            (self.from.v.abs().max(self.to.v.abs()), self.from.a.abs().max(self.to.a.abs()), 0.0f64);
        for pc in &self.pieces[..self.n] {
            let e = pc.at(pc.dt);
            v = v.max(pc.v.abs()).max(e.v.abs());
            a = a.max(pc.a.abs()).max(e.a.abs());
            j = j.max(pc.j.abs());
            if pc.j != 0.0 {
                let u = -pc.a / pc.j;
                if u > 0.0 && u < pc.dt {
                    v = v.max(pc.at(u).v.abs());
                }
            }
        }
        if !self.jerk_limited {
            let mut prev = self.from.a;
            for pc in &self.pieces[..self.n] {
                if pc.a != prev {
                    j = f64::INFINITY;
                }
                prev = pc.a;
            }
            if prev != self.to.a {
                j = f64::INFINITY;
            }
        }
        (v, a, j)
    }
}

fn check_min(duration: f64) -> Result<()> {
    if duration > 0.0 && duration < MIN_DURATION {
        return Err(infeasible(
            "duration",
            format!("the motion would last {duration:e} s, shorter than the {MIN_DURATION:e} s a motion may last"),
        ));
    }
    Ok(())
}

fn no_profile(from: &BoundaryState, to: &BoundaryState, duration: Option<f64>) -> Error {
    let when = duration.map_or(String::new(), |t| format!(" lasting exactly {t} s"));
    infeasible(
        "duration",
        format!(
            "no motion{when} from (p {}, v {}, a {}) to (p {}, v {}, a {}) within the limits \
             (a blocked duration: a longer one may be feasible)",
            from.p, from.v, from.a, to.p, to.v, to.a
        ),
    )
}

/// The smallest duration ≥ `at_least` \[s\] at which every coordinate has a
/// law, with the laws: each coordinate `i` from `from[i]` to `to[i]` within
/// `limits[i]`. Starts from the slowest coordinate's fastest duration and,
/// where that duration is blocked for another coordinate, moves on to the
/// next critical duration that every coordinate admits.
///
/// Errors: slices of different lengths; the errors of [`BoundaryLaw::fastest`]
/// for a coordinate (its index in `what`); no common duration found.
pub fn sync_duration(
    from: &[BoundaryState],
    to: &[BoundaryState],
    limits: &[MotionLimits],
    at_least: f64,
) -> Result<(f64, Vec<BoundaryLaw>)> {
    for (what, got) in [("to", to.len()), ("limits", limits.len())] {
        if got != from.len() {
            return Err(Error::WrongLength {
                what: what.into(),
                got,
                expected: from.len(),
                of: "one per start state".into(),
            });
        }
    }
    let mut critical = Vec::new();
    let mut t0 = at_least.max(0.0);
    let mut fastest = Vec::with_capacity(from.len());
    let mut optimal = Vec::with_capacity(from.len());
    let mut lims = Vec::with_capacity(from.len());
    for i in 0..from.len() {
        let l = lim_of(&limits[i])?;
        check_states(&from[i], &to[i], &l)?;
        let laws = BoundaryLaw::candidates(from[i], to[i], &l);
        let law = *laws.first().ok_or_else(|| no_profile(&from[i], &to[i], None))?;
        check_min(law.duration)?;
        t0 = t0.max(law.duration);
        fastest.push(law);
        critical.extend(laws.iter().map(|c| c.duration));
        optimal.push(laws);
        lims.push(l);
    }
    let mut tries: Vec<f64> = critical.into_iter().filter(|&t| t > t0).collect();
    tries.push(t0);
    tries.sort_by(f64::total_cmp);
    tries.dedup();
    let mut last_err = None;
    'outer: for &t in &tries {
        let mut laws = Vec::with_capacity(from.len());
        for i in 0..from.len() {
            if fastest[i].duration == t {
                laws.push(fastest[i]);
                continue;
            }
            match BoundaryLaw::timed(from[i], to[i], &lims[i], t, &optimal[i]) {
                Ok(l) => laws.push(l),
                Err(e) => {
                    last_err = Some(e);
                    continue 'outer;
                }
            }
        }
        return Ok((t, laws));
    }
    Err(last_err.unwrap_or_else(|| infeasible("duration", "no duration suits every coordinate".into())))
}
