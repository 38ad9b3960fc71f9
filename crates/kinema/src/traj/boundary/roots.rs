//! Roots of a function of one unknown on an interval: sign changes on a
//! grid, refined by bisection (reference) or the Illinois variant of
//! regula falsi (fast), plus pairs of roots hidden between two grid points
//! (found at a minimum of |f|); and the edge of a region where f ≥ 0.

/// Grid intervals for the one-unknown searches.
pub(super) const GRID: usize = 64;

/// Grid intervals of the fast search: the pair search at dips stands in
/// for the finer grid.
const FAST_GRID: usize = 32;

/// How a bracketed root is refined and when a hidden pair is looked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Search {
    /// Regula falsi (Illinois), and a pair search only where a parabola
    /// through three grid values dips towards 0.
    Fast,
    /// Plain bisection, and a pair search at every local minimum of |f|.
    Reference,
}

impl Search {
    /// Grid intervals for the one-unknown searches.
    pub fn intervals(self) -> usize {
        match self {
            Search::Fast => FAST_GRID,
            Search::Reference => GRID,
        }
    }
}

/// All roots of `f` on \[lo, hi\]: sign changes on a grid of `n` intervals,
/// refined by bisection, plus near-tangent roots found where |f| has a local
/// minimum between grid points. `f` may return NaN where the family has no
/// profile.
pub(super) fn find(search: Search, f: &impl Fn(f64) -> f64, lo: f64, hi: f64, n: usize, out: &mut Vec<f64>) {
    if !(lo.is_finite() && hi.is_finite()) || hi < lo {
        return;
    }
    if hi == lo {
        if f(lo) == 0.0 {
            out.push(lo);
        }
        return;
    }
    assert!(n <= GRID, "at most GRID intervals");
    let (mut xs, mut ys) = ([0.0; GRID + 1], [0.0; GRID + 1]);
    for (i, (x, y)) in xs.iter_mut().zip(&mut ys).take(n + 1).enumerate() {
        // The last exactly: roots on the bounds (a phase of length 0) are common.
        *x = if i == n { hi } else { lo + (hi - lo) * i as f64 / n as f64 };
        *y = f(*x);
    }
    for i in 0..=n {
        if ys[i] == 0.0 {
            out.push(xs[i]);
        }
        if i == n {
            break;
        }
        let (ya, yb) = (ys[i], ys[i + 1]);
        if ya.is_finite() && yb.is_finite() && ya != 0.0 && yb != 0.0 && (ya < 0.0) != (yb < 0.0) {
            out.push(match search {
                Search::Fast => illinois(f, xs[i], ya, xs[i + 1], yb),
                Search::Reference => bisect(f, xs[i], ya, xs[i + 1]),
            });
        }
    }
    for i in 1..n {
        let ys = [ys[i - 1], ys[i], ys[i + 1]];
        if search == Search::Reference || dips(ys) {
            pair_near_minimum(f, [xs[i - 1], xs[i], xs[i + 1]], ys, out);
        }
    }
}

/// A root of `f` between `a` (where f = `fa`) and `b`, where f has the other sign.
fn bisect(f: &impl Fn(f64) -> f64, mut a: f64, mut fa: f64, mut b: f64) -> f64 {
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
}

/// A root of `f` between `a` and `b` (where f = `fa`, `fb` of opposite
/// signs) by regula falsi, the retained end's value halved when the same
/// end is kept twice (Illinois) so that both ends converge. Falls back to
/// bisection where `f` is NaN.
pub(super) fn illinois(f: &impl Fn(f64) -> f64, mut a: f64, mut fa: f64, mut b: f64, mut fb: f64) -> f64 {
    let mut side = 0;
    for _ in 0..100 {
        if !(b - a > 4.0 * f64::EPSILON * a.abs().max(b.abs())) {
            break;
        }
        let mut x = b - fb * (b - a) / (fb - fa);
        if !(x > a && x < b) {
            x = 0.5 * (a + b);
        }
        let fx = f(x);
        if fx.is_nan() {
            return bisect(f, a, fa, b);
        }
        if fx == 0.0 {
            return x;
        }
        if (fx < 0.0) == (fa < 0.0) {
            (a, fa) = (x, fx);
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            (b, fb) = (x, fx);
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    if fa.abs() < fb.abs() {
        a
    } else {
        b
    }
}

/// Whether the parabola through three grid values of one sign (the middle
/// one smallest in size) comes within a quarter of the middle value of 0:
/// only then can a pair of roots hide between them.
fn dips([ya, ym, yb]: [f64; 3]) -> bool {
    let s = ym.signum();
    let (ya, ym, yb) = (s * ya, s * ym, s * yb);
    let curv = 0.5 * (ya + yb) - ym;
    let slope = 0.5 * (yb - ya);
    !(curv > 0.0) || ym - slope * slope / (4.0 * curv) <= 0.25 * ym
}

/// A pair of roots inside one grid interval (or a tangent root) shows as a
/// local minimum of |f| without a sign change: look for the extremum.
fn pair_near_minimum(f: &impl Fn(f64) -> f64, xs: [f64; 3], ys: [f64; 3], out: &mut Vec<f64>) {
    let [ya, ym, yb] = ys;
    if !(ya.is_finite() && ym.is_finite() && yb.is_finite()) || ym == 0.0 {
        return;
    }
    let s = ym.signum();
    if ya.signum() != s || yb.signum() != s || !(ym.abs() <= ya.abs() && ym.abs() <= yb.abs()) {
        return;
    }
    // Golden-section search for the minimum of s·f on [x_{i-1}, x_{i+1}].
    let (mut a, mut b) = (xs[0], xs[2]);
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
        return;
    }
    if fm <= 0.0 {
        if fm == 0.0 {
            out.push(xm);
        } else {
            out.push(bisect(f, xs[0], ya, xm));
            out.push(bisect(f, xm, s * fm, xs[2]));
        }
    } else if fm <= 1e-13 * ym.abs().max(1e-300) {
        out.push(xm); // tangent: accepted if the rebuilt law checks out
    }
}

/// The last point from `inside` towards `outside` where `f` ≥ 0, to the
/// resolution of f64, given f(`inside`) ≥ 0 and f(`outside`) < 0 or NaN.
/// Regula falsi (Illinois) while the values allow it, bisection where they
/// are not finite or a step has not halved the bracket: the edges of a
/// feasible interval this way take a handful of evaluations, not fifty.
pub(super) fn last_inside(f: &impl Fn(f64) -> f64, mut inside: f64, mut outside: f64) -> f64 {
    let (mut fi, mut fo) = (f(inside), f(outside));
    let (mut side, mut stalled) = (0, 0);
    let mut width = (outside - inside).abs();
    for _ in 0..200 {
        let mid = 0.5 * (inside + outside);
        if mid == inside || mid == outside {
            break;
        }
        let secant = inside - fi * (outside - inside) / (fo - fi);
        let between = (secant - inside) * (secant - outside) < 0.0;
        let x = if between && stalled < 2 { secant } else { mid };
        let fx = f(x);
        if fx >= 0.0 {
            (inside, fi) = (x, fx);
            if side == -1 {
                fo *= 0.5;
            }
            side = -1;
        } else {
            (outside, fo) = (x, fx);
            if side == 1 {
                fi *= 0.5;
            }
            side = 1;
        }
        let w = (outside - inside).abs();
        if w <= 0.5 * width {
            (width, stalled) = (w, 0);
        } else {
            stalled += 1;
        }
    }
    inside
}
