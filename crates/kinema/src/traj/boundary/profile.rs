//! A profile — a sequence of segments of constant jerk — integrating it,
//! and building and re-checking the law it makes.

use super::problem::{Limits, Problem};
use super::{BoundaryLaw, BoundaryState};

/// The most segments a profile has: a blend of two seven-segment profiles
/// on the merged grid of their segment boundaries.
pub(super) const MAX_PROFILE_SEGMENTS: usize = 14;

/// The most phases any law has: a brake of up to four segments, then a profile.
pub(super) const MAX_SEGMENTS: usize = 4 + MAX_PROFILE_SEGMENTS;

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
    segments: [JerkSegment; MAX_PROFILE_SEGMENTS],
    len: usize,
}

impl Profile {
    /// Appends a segment; zero-length ones are left out.
    pub fn push(&mut self, dt: f64, jerk: f64, set_acc: Option<f64>) {
        if dt > 0.0 && self.len < MAX_PROFILE_SEGMENTS {
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
        out.mirror();
        out
    }

    /// Turns this profile into its mirror image.
    pub fn mirror(&mut self) {
        for s in &mut self.segments[..self.len] {
            s.jerk = -s.jerk;
            s.set_acc = s.set_acc.map(|a| -a);
        }
    }

    /// Turns this profile into the same motion run backwards in time:
    /// segments reversed, jerk negated (only for third-order profiles,
    /// whose acceleration is continuous).
    pub fn reverse(&mut self) {
        self.segments[..self.len].reverse();
        for s in &mut self.segments[..self.len] {
            s.jerk = -s.jerk;
            s.set_acc = None;
        }
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

impl Profile {
    /// The phases of this profile from `from`: the state at each segment's
    /// start, integrated segment by segment, each starting `offset` \[s\]
    /// later than it does within the profile.
    pub fn phases(&self, from: BoundaryState, offset: f64) -> impl Iterator<Item = Phase> + Clone + '_ {
        let (mut st, mut t) = (from, 0.0);
        self.segments().iter().map(move |s| {
            if let Some(a) = s.set_acc {
                st.a = a;
            }
            let phase = Phase { t0: t + offset, dt: s.dt, p: st.p, v: st.v, a: st.a, j: s.jerk };
            st = phase.at(s.dt);
            t += s.dt;
            phase
        })
    }
}

/// The largest |v|, |a| and |j| over the phases of a law from `from` to
/// `to`, in closed form (velocity extrema inside a phase where the
/// acceleration crosses 0). |j| is infinite for a second-order law with an
/// acceleration step.
pub(super) fn peaks_of(
    from: &BoundaryState,
    to: &BoundaryState,
    jerk_limited: bool,
    phases: impl Iterator<Item = Phase> + Clone,
) -> (f64, f64, f64) {
    let (mut v, mut a, mut j) = (from.v.abs().max(to.v.abs()), from.a.abs().max(to.a.abs()), 0.0f64);
    for pc in phases.clone() {
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
    if !jerk_limited {
        let mut prev = from.a;
        for pc in phases {
            if pc.a != prev {
                j = f64::INFINITY;
            }
            prev = pc.a;
        }
        if prev != to.a {
            j = f64::INFINITY;
        }
    }
    (v, a, j)
}

/// A profile from a start state towards a target, re-checked without
/// building its law: the same phases, end state and peaks the law would
/// have, so that only the chosen candidate is built.
pub(super) struct Trial<'a> {
    from: BoundaryState,
    to: BoundaryState,
    profile: &'a Profile,
    jerk_limited: bool,
    /// The state reached at the end of the last phase, before it is replaced
    /// by the exact target (what the re-check compares).
    end: BoundaryState,
    duration: f64,
}

impl<'a> Trial<'a> {
    pub fn new(from: BoundaryState, to: BoundaryState, profile: &'a Profile, jerk_limited: bool) -> Trial<'a> {
        let (mut end, mut duration) = (from, 0.0);
        for phase in profile.phases(from, 0.0) {
            end = phase.at(phase.dt);
            duration += phase.dt;
        }
        Trial { from, to, profile, jerk_limited, end, duration }
    }

    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// The end position minus the target's.
    pub fn residual(&self) -> f64 {
        self.end.p - self.to.p
    }

    /// Whether the law reaches its target and keeps within `l` (1e-9 relative).
    pub fn valid(&self, l: &Limits) -> bool {
        self.valid_but_position(l) && self.position_reached()
    }

    fn position_reached(&self) -> bool {
        // The motion's own scale (a short motion far from 0 is held to its
        // size, not to its coordinates), plus the rounding of the coordinates.
        let (t, f, to) = (self.duration, &self.from, &self.to);
        let scale_p = (to.p - f.p).abs().max((f.v.abs() + to.v.abs()) * t).max((f.a.abs() + to.a.abs()) * t * t);
        let tol_p = 1e-9 * scale_p + 8.0 * f64::EPSILON * f.p.abs().max(to.p.abs());
        (self.end.p - self.to.p).abs() <= tol_p
    }

    /// Whether the law ends at the target's velocity and acceleration and keeps within `l`.
    pub fn valid_but_position(&self, l: &Limits) -> bool {
        let e = self.end;
        if !((e.v - self.to.v).abs() <= 1e-9 * l.vel) {
            return false;
        }
        if self.jerk_limited && !((e.a - self.to.a).abs() <= 1e-9 * l.acc) {
            return false;
        }
        let (v, a, j) = peaks_of(&self.from, &self.to, self.jerk_limited, self.profile.phases(self.from, 0.0));
        v <= l.vel * (1.0 + 1e-9)
            && a <= l.acc * (1.0 + 1e-9)
            && (!self.jerk_limited || j <= l.jerk.unwrap_or(0.0) * (1.0 + 1e-9))
    }
}

/// A candidate that passed the re-check: its profile (from the start state
/// it was searched from) and its duration \[s\].
#[derive(Debug, Clone, Copy)]
pub(super) struct Candidate {
    pub duration: f64,
    pub profile: Profile,
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
        law.append(profile, from);
        law
    }

    /// Appends the phases of `profile` from `start`, after the phases already there.
    pub(super) fn append(&mut self, profile: &Profile, start: BoundaryState) {
        let offset = self.duration;
        let mut t = 0.0;
        for phase in profile.phases(start, offset) {
            t += phase.dt;
            self.phases[self.n] = phase;
            self.n += 1;
        }
        self.duration = offset + t;
    }

    /// The candidates that pass the re-check, fastest first.
    pub(super) fn from_candidates(
        from: BoundaryState,
        to: BoundaryState,
        l: &Limits,
        cands: &[Profile],
    ) -> Vec<Candidate> {
        // Sorted as (duration, index) pairs, then copied once in that order.
        let mut order: Vec<(f64, usize)> = Vec::with_capacity(cands.len());
        for (i, s) in cands.iter().enumerate().filter(|(_, s)| Self::lengths_usable(s)) {
            let trial = Trial::new(from, to, s, l.jerk.is_some());
            if trial.valid(l) {
                order.push((trial.duration, i));
            }
        }
        order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        order.iter().map(|&(duration, i)| Candidate { duration, profile: cands[i] }).collect()
    }

    /// The fastest of the candidates that pass the re-check and last `t`
    /// (1e-12 relative): the first such one in [`Self::from_candidates`]'s
    /// order, found without the others' peaks.
    pub(super) fn first_lasting(
        from: BoundaryState,
        to: BoundaryState,
        l: &Limits,
        cands: &[Profile],
        t: f64,
    ) -> Option<Profile> {
        let mut best: Option<Trial> = None;
        for s in cands.iter().filter(|s| Self::lengths_usable(s)) {
            let trial = Trial::new(from, to, s, l.jerk.is_some());
            let lasts = (trial.duration - t).abs() <= 1e-12 * t.max(1.0);
            if lasts && best.as_ref().is_none_or(|b| trial.duration < b.duration) && trial.valid(l) {
                best = Some(trial);
            }
        }
        best.map(|b| *b.profile)
    }

    /// Whether every segment length of `s` is finite and ≥ 0.
    fn lengths_usable(s: &Profile) -> bool {
        s.segments().iter().all(|g| g.dt.is_finite() && g.dt >= 0.0)
    }
}
