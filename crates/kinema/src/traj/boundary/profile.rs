//! A profile — a sequence of segments of constant jerk — integrating it,
//! and building and re-checking the law it makes.

use super::problem::{Limits, Problem};
use super::{BoundaryLaw, BoundaryState};

/// The most segments any law has: a brake of up to four, then a blend of
/// two seven-segment laws.
pub(super) const MAX_SEGMENTS: usize = 20;

/// Constant jerk for `dt` seconds; `set_acc` sets the acceleration at the
/// segment's start (second order: it steps) or `None` keeps it continuous.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct JerkSegment {
    pub dt: f64,
    pub jerk: f64,
    pub set_acc: Option<f64>,
}

/// A candidate motion as segments, relative to its start state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct Profile {
    segments: [JerkSegment; MAX_SEGMENTS],
    len: usize,
}

impl Profile {
    /// Appends a segment; zero-length ones are left out.
    pub fn push(&mut self, dt: f64, jerk: f64, set_acc: Option<f64>) {
        if dt > 0.0 && self.len < MAX_SEGMENTS {
            self.segments[self.len] = JerkSegment { dt, jerk, set_acc };
            self.len += 1;
        }
    }

    /// The profile of `segments`, zero-length ones left out.
    pub fn from_segments<'a>(segments: impl IntoIterator<Item = &'a JerkSegment>) -> Profile {
        let mut s = Profile::default();
        for g in segments {
            s.push(g.dt, g.jerk, g.set_acc);
        }
        s
    }

    pub fn extend(&mut self, other: &Profile) {
        for s in other.segments() {
            self.push(s.dt, s.jerk, s.set_acc);
        }
    }

    pub fn segments(&self) -> &[JerkSegment] {
        &self.segments[..self.len]
    }

    pub fn duration(&self) -> f64 {
        self.segments().iter().map(|s| s.dt).sum()
    }

    /// The mirror image: every jerk and set acceleration negated.
    pub fn mirrored(&self) -> Profile {
        let mut out = *self;
        for s in &mut out.segments[..out.len] {
            s.jerk = -s.jerk;
            s.set_acc = s.set_acc.map(|a| -a);
        }
        out
    }

    /// The same motion run backwards in time: segments reversed, jerk
    /// negated (only for third-order profiles, whose acceleration is continuous).
    pub fn reversed(&self) -> Profile {
        let mut out = Profile::default();
        for s in self.segments().iter().rev() {
            out.push(s.dt, -s.jerk, None);
        }
        out
    }

    /// Position, velocity and acceleration at the end, from (0, v, a).
    pub fn integrate(&self, v: f64, a: f64) -> (f64, f64, f64) {
        let mut m = Integrator::new(v, a);
        for s in self.segments() {
            m.segment(s);
        }
        (m.p, m.v, m.a)
    }

    /// The jerk at time `t` into the profile (the last segment's after it).
    pub fn jerk_at(&self, t: f64) -> f64 {
        let mut end = 0.0;
        for s in self.segments() {
            end += s.dt;
            if t < end {
                return s.jerk;
            }
        }
        self.segments[self.len.saturating_sub(1)].jerk
    }
}

/// The state reached segment by segment, with the arithmetic of
/// [`Profile::integrate`]: the searches evaluate a candidate's end position
/// this way without building (and copying) a [`Profile`]. Segments a
/// profile would leave out (length ≤ 0) are skipped, so both give the same
/// numbers to the last bit.
#[derive(Debug, Clone, Copy)]
pub(super) struct Integrator {
    pub p: f64,
    pub v: f64,
    pub a: f64,
}

impl Integrator {
    /// At position 0 with velocity `v` and acceleration `a`.
    pub fn new(v: f64, a: f64) -> Integrator {
        Integrator { p: 0.0, v, a }
    }

    /// Advances over one segment.
    #[inline]
    pub fn segment(&mut self, s: &JerkSegment) {
        if !(s.dt > 0.0) {
            return;
        }
        if let Some(a0) = s.set_acc {
            self.a = a0;
        }
        let u = s.dt;
        self.p += u * (self.v + u * (self.a / 2.0 + u * s.jerk / 6.0));
        self.v += u * (self.a + u * s.jerk / 2.0);
        self.a += u * s.jerk;
    }
}

/// The end position of the profile of `segments` from `p`'s start state
/// minus the target's, without building the profile.
pub(super) fn residual_of<'a>(p: &Problem, segments: impl IntoIterator<Item = &'a JerkSegment>) -> f64 {
    let mut m = Integrator::new(p.v0, p.a0);
    for g in segments {
        m.segment(g);
    }
    m.p - p.dp
}

/// One segment of a built law: the state at its start `t0` and its jerk.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct Phase {
    pub t0: f64,
    pub dt: f64,
    pub p: f64,
    pub v: f64,
    pub a: f64,
    pub j: f64,
}

impl Phase {
    #[inline]
    pub fn at(&self, u: f64) -> BoundaryState {
        BoundaryState {
            p: self.p + u * (self.v + u * (self.a / 2.0 + u * self.j / 6.0)),
            v: self.v + u * (self.a + u * self.j / 2.0),
            a: self.a + u * self.j,
        }
    }
}

impl BoundaryLaw {
    pub(super) fn build(from: BoundaryState, to: BoundaryState, profile: &Profile, jerk_limited: bool) -> BoundaryLaw {
        let mut law = BoundaryLaw {
            from,
            to,
            phases: [Phase::default(); MAX_SEGMENTS],
            n: 0,
            duration: 0.0,
            braking: 0.0,
            jerk_limited,
        };
        let mut st = from;
        let mut t = 0.0;
        for s in profile.segments() {
            if let Some(a) = s.set_acc {
                st.a = a;
            }
            let phase = Phase { t0: t, dt: s.dt, p: st.p, v: st.v, a: st.a, j: s.jerk };
            st = phase.at(s.dt);
            law.phases[law.n] = phase;
            law.n += 1;
            t += s.dt;
        }
        law.duration = t;
        law
    }

    /// The state reached at the end of the last phase, before it is replaced
    /// by the exact target (what the re-check compares).
    pub(super) fn end_state(&self) -> BoundaryState {
        if self.n == 0 {
            return self.from;
        }
        let last = &self.phases[self.n - 1];
        last.at(last.dt)
    }

    /// Whether the law reaches its target and keeps within `l` (1e-9 relative).
    pub(super) fn valid(&self, l: &Limits) -> bool {
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
    pub(super) fn valid_but_position(&self, l: &Limits) -> bool {
        let e = self.end_state();
        if !((e.v - self.to.v).abs() <= 1e-9 * l.vel) {
            return false;
        }
        if self.jerk_limited && !((e.a - self.to.a).abs() <= 1e-9 * l.acc) {
            return false;
        }
        let (v, a, j) = self.peaks();
        v <= l.vel * (1.0 + 1e-9)
            && a <= l.acc * (1.0 + 1e-9)
            && (!self.jerk_limited || j <= l.jerk.unwrap_or(0.0) * (1.0 + 1e-9))
    }

    /// The candidates that build into valid laws, fastest first.
    pub(super) fn from_candidates(
        from: BoundaryState,
        to: BoundaryState,
        l: &Limits,
        cands: &[Profile],
    ) -> Vec<BoundaryLaw> {
        // Sorted as (duration, index) pairs, then copied once in that order:
        // a law is a kilobyte, and a sort would move each several times.
        let mut order: Vec<(f64, usize)> = Vec::with_capacity(cands.len());
        let mut valid = Vec::with_capacity(cands.len());
        for s in cands.iter().filter(|s| Self::lengths_usable(s)) {
            let law = Self::build(from, to, s, l.jerk.is_some());
            if law.valid(l) {
                order.push((law.duration, valid.len()));
                valid.push(law);
            }
        }
        order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        order.iter().map(|&(_, i)| valid[i]).collect()
    }

    /// The fastest of the candidates that build into valid laws lasting
    /// `t` (1e-12 relative): the first such law in [`Self::from_candidates`]'s
    /// order, found without building the others' peaks.
    pub(super) fn first_lasting(
        from: BoundaryState,
        to: BoundaryState,
        l: &Limits,
        cands: &[Profile],
        t: f64,
    ) -> Option<BoundaryLaw> {
        let mut best: Option<BoundaryLaw> = None;
        for s in cands.iter().filter(|s| Self::lengths_usable(s)) {
            let law = Self::build(from, to, s, l.jerk.is_some());
            let lasts = (law.duration - t).abs() <= 1e-12 * t.max(1.0);
            if lasts && best.is_none_or(|b| law.duration < b.duration) && law.valid(l) {
                best = Some(law);
            }
        }
        best
    }

    /// Whether every segment length of `s` is finite and ≥ 0.
    fn lengths_usable(s: &Profile) -> bool {
        s.segments().iter().all(|g| g.dt.is_finite() && g.dt >= 0.0)
    }
}
