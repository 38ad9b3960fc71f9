//! Zeros of one-dimensional residuals over a full turn of one joint, for the
//! search-based families (IK-Geo's 1-D search): each family fixes one joint,
//! solves the rest in closed form per branch, and leaves one scalar residual
//! per branch that vanishes at the solutions.
//!
//! The residual of each branch is sampled on [`GRID`] + 1 points over
//! [−π, π]; sign changes are refined by bisection to rounding level. A branch
//! may exist on part of the turn only (where the closed-form step has a
//! root): where it ends (found by bisection on whether it exists) it turns
//! steeply into the branch it merges with, so the last two cells are scanned
//! again on 25 points denser towards the end. Two zeros within about one
//! sampling step (a near-singular target) show as a small |e| between
//! larger ones: the extremum there is found by golden-section search and the
//! zeros on both sides by bisection; an extremum that only touches zero
//! (within 1e-14) is reported as a zero too, for the caller to check.
//! Missed: a branch that exists only between two grid points, and more than
//! two zeros within one step.

/// Grid points over one turn.
pub const GRID: usize = 720;

/// Labels by shoulder·8 + elbow·4 + root (roots past the fourth share the last).
pub(super) const LABELS: [&str; 16] = [
    "shoulder-1/elbow-1/root-1",
    "shoulder-1/elbow-1/root-2",
    "shoulder-1/elbow-1/root-3",
    "shoulder-1/elbow-1/root-4",
    "shoulder-1/elbow-2/root-1",
    "shoulder-1/elbow-2/root-2",
    "shoulder-1/elbow-2/root-3",
    "shoulder-1/elbow-2/root-4",
    "shoulder-2/elbow-1/root-1",
    "shoulder-2/elbow-1/root-2",
    "shoulder-2/elbow-1/root-3",
    "shoulder-2/elbow-1/root-4",
    "shoulder-2/elbow-2/root-1",
    "shoulder-2/elbow-2/root-2",
    "shoulder-2/elbow-2/root-3",
    "shoulder-2/elbow-2/root-4",
];

/// What the search saw, for an explanation when it finds nothing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Seen {
    /// Whether some branch existed somewhere on the turn.
    pub any_defined: bool,
    /// Smallest |e| on the grid.
    pub best: f64,
    /// Smallest miss reported where a branch did not exist.
    pub min_miss: f64,
}

type Residual<'a> = &'a dyn Fn(f64, usize) -> Result<f64, f64>;

fn at(i: usize) -> f64 {
    -std::f64::consts::PI + i as f64 * (std::f64::consts::TAU / GRID as f64)
}

/// Calls `zero(x, branch)` for every zero found of `residual(x, branch)`
/// (`Ok(e)`, or `Err(miss)` where the branch does not exist), branches
/// `0..branches`; each zero once.
pub(super) fn find_zeros(branches: usize, residual: Residual, zero: &mut dyn FnMut(f64, usize)) -> Seen {
    let mut seen = Seen { any_defined: false, best: f64::INFINITY, min_miss: f64::INFINITY };
    let mut samples = [f64::NAN; GRID + 1];
    for b in 0..branches {
        let e = |x: f64| residual(x, b);
        let mut found = Found { x: [0.0; 32], len: 0 };
        let mut emit = |x: f64| {
            if found.insert(x) {
                zero(x, b);
            }
        };
        for (i, v) in samples.iter_mut().enumerate() {
            *v = match e(at(i)) {
                Ok(v) => v,
                Err(miss) => {
                    seen.min_miss = seen.min_miss.min(miss);
                    f64::NAN
                }
            };
        }
        for i in 0..GRID {
            let (s0, s1) = (samples[i], samples[i + 1]);
            match (s0.is_nan(), s1.is_nan()) {
                (false, false) => {
                    seen.any_defined = true;
                    seen.best = seen.best.min(s0.abs());
                    if s0 == 0.0 || (s0 > 0.0) != (s1 > 0.0) && s1 != 0.0 {
                        emit(bisect(&e, at(i), at(i + 1), s0));
                    }
                }
                // The branch ends inside this cell. Near its end it turns steeply into the
                // branch it merges with, so two zeros may share the cell: scan it (and the
                // cell before) finely, denser towards the end.
                (false, true) => {
                    seen.any_defined = true;
                    let end = branch_end(&e, at(i), at(i + 1));
                    let lo = if i > 0 && !samples[i - 1].is_nan() { at(i - 1) } else { at(i) };
                    scan_fine(&e, lo, end, true, &mut emit);
                }
                (true, false) => {
                    seen.any_defined = true;
                    let start = branch_end(&e, at(i + 1), at(i));
                    let hi = if i + 2 <= GRID && !samples[i + 2].is_nan() { at(i + 2) } else { at(i + 1) };
                    scan_fine(&e, start, hi, false, &mut emit);
                }
                (true, true) => {}
            }
        }
        for i in 1..GRID {
            close_pair(&e, [at(i - 1), at(i), at(i + 1)], [samples[i - 1], samples[i], samples[i + 1]], &mut emit);
        }
    }
    seen
}

/// Zeros already reported for one branch.
struct Found {
    x: [f64; 32],
    len: usize,
}

impl Found {
    /// Records `x` unless a zero within 1e-9 was already found; returns whether it is new.
    fn insert(&mut self, x: f64) -> bool {
        if self.x[..self.len].iter().any(|y| (x - y).abs() < 1e-9) {
            return false;
        }
        if self.len < self.x.len() {
            self.x[self.len] = x;
            self.len += 1;
        }
        true
    }
}

/// Sign changes and close pairs of e on [lo, hi] sampled at 25 points,
/// denser towards `hi` (`dense_at_hi`) or `lo`.
fn scan_fine(e: &dyn Fn(f64) -> Result<f64, f64>, lo: f64, hi: f64, dense_at_hi: bool, emit: &mut dyn FnMut(f64)) {
    const K: usize = 24;
    let mut xs = [0.0; K + 1];
    let mut es = [f64::NAN; K + 1];
    for k in 0..=K {
        let t = k as f64 / K as f64;
        xs[k] = if dense_at_hi { hi - (hi - lo) * (1.0 - t) * (1.0 - t) } else { lo + (hi - lo) * t * t };
        es[k] = e(xs[k]).unwrap_or(f64::NAN);
    }
    for k in 0..K {
        let (e0, e1) = (es[k], es[k + 1]);
        if e0.is_nan() || e1.is_nan() {
            continue;
        }
        if e0 == 0.0 || (e0 > 0.0) != (e1 > 0.0) && e1 != 0.0 {
            emit(bisect(e, xs[k], xs[k + 1], e0));
        }
    }
    for k in 1..K {
        close_pair(e, [xs[k - 1], xs[k], xs[k + 1]], [es[k - 1], es[k], es[k + 1]], emit);
    }
}

/// Two zeros within a sampling step show as a small |e| between larger ones
/// of the same sign: find the extremum between them and, if it crosses (or
/// touches) zero, the zeros on both sides of it.
fn close_pair(e: &dyn Fn(f64) -> Result<f64, f64>, x: [f64; 3], v: [f64; 3], emit: &mut dyn FnMut(f64)) {
    let [a, m, c] = v;
    let same_sign = a * m > 0.0 && m * c > 0.0;
    if !(same_sign && m.abs() < a.abs() && m.abs() <= c.abs()) {
        return;
    }
    let sign = m.signum();
    let xe = extremum(e, sign, x[0], x[2]);
    let Ok(ex) = e(xe) else { return };
    if ex * sign > 0.0 && ex.abs() > 1e-14 {
        return;
    }
    if ex * sign > 0.0 || ex == 0.0 {
        emit(xe);
        return;
    }
    emit(bisect(e, x[0], xe, a));
    emit(bisect(e, xe, x[2], ex));
}

/// The last x from `inside` (branch exists) towards `outside` (it does not)
/// where the branch still exists, by bisection.
fn branch_end(e: &dyn Fn(f64) -> Result<f64, f64>, mut inside: f64, mut outside: f64) -> f64 {
    for _ in 0..60 {
        let mid = 0.5 * (inside + outside);
        if mid == inside || mid == outside {
            break;
        }
        if e(mid).is_ok() {
            inside = mid;
        } else {
            outside = mid;
        }
    }
    inside
}

/// Where `sign`·e is smallest in [lo, hi], by golden-section search (where
/// the branch does not exist counts as +∞).
fn extremum(e: &dyn Fn(f64) -> Result<f64, f64>, sign: f64, mut lo: f64, mut hi: f64) -> f64 {
    let f = |x: f64| e(x).map_or(f64::INFINITY, |v| sign * v);
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    let (mut x1, mut x2) = (hi - ratio * (hi - lo), lo + ratio * (hi - lo));
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..80 {
        if f1 <= f2 {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - ratio * (hi - lo);
            f1 = f(x1);
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + ratio * (hi - lo);
            f2 = f(x2);
        }
    }
    if f1 <= f2 {
        x1
    } else {
        x2
    }
}

/// A zero of e in [lo, hi] (e(lo) = `elo`, the other sign at hi), by bisection.
fn bisect(e: &dyn Fn(f64) -> Result<f64, f64>, mut lo: f64, mut hi: f64, mut elo: f64) -> f64 {
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if elo == 0.0 || mid <= lo || mid >= hi {
            break;
        }
        let Ok(em) = e(mid) else { break };
        if (em > 0.0) == (elo > 0.0) && em != 0.0 {
            lo = mid;
            elo = em;
        } else {
            hi = mid;
        }
    }
    if elo == 0.0 {
        lo
    } else {
        0.5 * (lo + hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_simple_close_and_touching_zeros_and_zeros_at_branch_ends() {
        let found = |r: Residual| {
            let mut z = Vec::new();
            find_zeros(2, r, &mut |x, b| z.push((b, x)));
            z
        };
        // Simple zeros: sin(3x) − 0.2 has 6 on one turn.
        let z = found(&|x: f64, b| if b == 0 { Ok((3.0 * x).sin() - 0.2) } else { Err(1.0) });
        assert_eq!(z.len(), 6, "{z:?}");
        assert!(z.iter().all(|(_, x)| ((3.0 * x).sin() - 0.2).abs() < 1e-14));
        // Two zeros 1e-3 apart, well inside one grid cell.
        let z = found(&|x: f64, b| if b == 1 { Ok((x - 0.3) * (x - 0.301) * (1.0 + 0.1 * x)) } else { Err(1.0) });
        assert_eq!(z.len(), 2, "{z:?}");
        assert!(z.iter().any(|(_, x)| (x - 0.3).abs() < 1e-12) && z.iter().any(|(_, x)| (x - 0.301).abs() < 1e-12));
        // A zero that only touches: reported once, near the touching point.
        let z = found(&|x: f64, b| if b == 0 { Ok((x - 0.3).powi(2)) } else { Err(1.0) });
        assert!(z.len() == 1 && (z[0].1 - 0.3).abs() < 1e-6, "{z:?}");
        // A branch that exists only for x > 0.5 and crosses zero at 0.5 + 1e-6.
        let z = found(&|x: f64, b| if b == 0 && x > 0.5 { Ok(x - 0.5 - 1e-6) } else { Err(0.1) });
        assert_eq!(z.len(), 1, "{z:?}");
        assert!((z[0].1 - 0.5 - 1e-6).abs() < 1e-14);
        // Nowhere defined: nothing found, the miss reported.
        let mut z = Vec::new();
        let seen = find_zeros(2, &|_, _| Err(0.25), &mut |x, b| z.push((b, x)));
        assert!(z.is_empty() && !seen.any_defined && seen.min_miss == 0.25);
    }
}
