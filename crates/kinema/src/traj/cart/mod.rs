//! Cartesian motions (seed 004 §VIII-C/D): straight lines (LIN), circular
//! arcs (CIRC) and chains of them blended through via points, each timed by
//! a [`TimeLaw`].
//!
//! A [`Segment`] is a geometric piece p(u), R(u), u ∈ \[0, 1\]. A
//! [`CartesianMotion`] runs segments one after another; with blending the
//! next one starts before the previous ends and the two are superposed
//! (seed 004 eq. 41: P(t) = P_ini + s(t)·(P_obj − P_ini) + s′(t − t_s)·(P_sig − P_obj)),
//! which rounds the corner and keeps the velocity continuous. Orientations
//! superpose the same way as world-frame increments, R(t) = Δ_n(t)⋯Δ_1(t)·R_0.
//!
//! Each segment's law is the fastest of its family with ṡ ≤ min(v/L, ω/θ),
//! s̈ ≤ min(a/L, α/θ) (and jerk likewise), L the path length and θ the
//! rotation angle — the larger of the translational and rotational
//! requirements, decided per limit — and with the limits holding for the
//! real vectors: on an arc the centripetal acceleration shares the
//! acceleration budget, and with RPY interpolation |ω| (not each angle's
//! rate) is what `rot_vel` bounds. Where two blended segments overlap, their
//! velocities and accelerations add; where the sum would exceed a limit the
//! blend is shortened (bisection on its length, down to a full stop at the
//! via point), so every limit holds and a blended motion is never slower
//! than stopping at every point. With the trapezoid, whose accelerations are
//! constant, a corner sharper than 60° cannot be blended at full
//! acceleration (|a₂ − a₁| = 2·a·sin(angle/2) > a): it becomes a stop; the
//! S-curve blends more corners.

use nalgebra::Vector3;

mod segment;

use self::segment::segment_law;
pub use self::segment::Segment;

use super::law::{Profile, TimeLaw};
use super::MAX_SAMPLES;
use crate::error::{Error, InputError, Result};
use crate::math::{rot_to_axis_angle, Pose, RpyConvention};

/// How a LIN segment interpolates orientation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Orientation {
    /// Spherical linear interpolation of the rotation (constant angular
    /// velocity axis; the default).
    #[default]
    Slerp,
    /// Linear interpolation of roll-pitch-yaw angles in the given convention
    /// (seed 004 eq. 40).
    Rpy(RpyConvention),
}

/// A point a LIN motion goes to: its pose, and the roll-pitch-yaw triple it
/// was written as, if it was written as one.
///
/// Seed 004 eq. 40 interpolates the triples as written. A triple read back
/// from the rotation matrix may be another triple of the same rotation (a
/// pitch past π/2 comes back mirrored, roll and yaw turned by π), and
/// interpolating towards that one turns the tool the long way round.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Waypoint {
    pose: Pose,
    rpy: Option<([f64; 3], RpyConvention)>,
}

impl Waypoint {
    /// A waypoint written as a position \[m\] and a roll-pitch-yaw triple \[rad\].
    pub fn from_xyz_rpy(xyz: [f64; 3], rpy: [f64; 3], conv: RpyConvention) -> Waypoint {
        Waypoint { pose: Pose::from_xyz_rpy(xyz, rpy, conv), rpy: Some((rpy, conv)) }
    }

    /// The pose.
    pub fn pose(&self) -> &Pose {
        &self.pose
    }

    /// The triple it was written as in `conv`, if it was.
    fn written_rpy(&self, conv: RpyConvention) -> Option<[f64; 3]> {
        self.rpy.filter(|(_, c)| *c == conv).map(|(t, _)| t)
    }
}

impl From<Pose> for Waypoint {
    fn from(pose: Pose) -> Waypoint {
        Waypoint { pose, rpy: None }
    }
}

/// Cartesian limits of a motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CartesianLimits {
    /// Tool-point speed \[m/s\].
    pub vel: f64,
    /// Tool-point acceleration \[m/s²\].
    pub acc: f64,
    /// Tool-point jerk \[m/s³\] (S-curve).
    pub jerk: Option<f64>,
    /// Angular speed |ω| of the tool \[rad/s\], whatever the interpolation.
    pub rot_vel: f64,
    /// Angular acceleration \[rad/s²\].
    pub rot_acc: f64,
    /// Angular jerk \[rad/s³\] (S-curve).
    pub rot_jerk: Option<f64>,
}

impl CartesianLimits {
    /// Translational limits, with rotational ones of the same numbers per radian.
    pub fn new(vel: f64, acc: f64) -> Self {
        CartesianLimits { vel, acc, jerk: None, rot_vel: vel, rot_acc: acc, rot_jerk: None }
    }
}

/// Position, velocity and acceleration of the tool along a motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CartesianState {
    /// Tool pose.
    pub pose: Pose,
    /// Linear velocity \[m/s\].
    pub vel: Vector3<f64>,
    /// Angular velocity (world frame) \[rad/s\].
    pub omega: Vector3<f64>,
    /// Linear acceleration \[m/s²\].
    pub acc: Vector3<f64>,
    /// Angular acceleration \[rad/s²\].
    pub alpha: Vector3<f64>,
}

/// Sampled maxima of a motion's limit ratio refined by golden section, the
/// largest first (each refinement costs 120 evaluations).
const MAX_REFINED_PEAKS: usize = 8;

/// How consecutive segments join.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Blend {
    /// Stop at every via point.
    None,
    /// Seed 004 (t_s = T1): the next segment starts when the previous one
    /// begins to decelerate (the default).
    #[default]
    Deceleration,
    /// The next segment starts this long \[s\] before the previous ends
    /// (clamped to half the duration of either).
    Time(f64),
    /// The next segment starts when the previous has this much path \[m\]
    /// left (clamped as for `Time`).
    Distance(f64),
}

/// A timed sequence of segments.
#[derive(Debug, Clone, PartialEq)]
pub struct CartesianMotion {
    segments: Vec<Segment>,
    laws: Vec<TimeLaw>,
    starts: Vec<f64>,
    duration: f64,
    finished: Finished,
}

/// The pose after the first k segments have all run to their end, for every
/// k, so that [`CartesianMotion::at`] composes only the segments running at
/// `t` and costs the same on a chain of two segments or of thousands.
#[derive(Debug, Clone, PartialEq)]
struct Finished {
    /// `by[k]`: when segments 0..=k have all ended \[s\] (non-decreasing).
    by: Vec<f64>,
    /// `poses[k]`: the pose once segments 0..k have ended (`poses[0]` is the start).
    poses: Vec<Pose>,
}

impl Finished {
    fn new(segments: &[Segment], laws: &[TimeLaw], starts: &[f64]) -> Finished {
        let mut by = Vec::with_capacity(segments.len());
        let mut poses = Vec::with_capacity(segments.len() + 1);
        let first = segments[0].start();
        let (mut p, mut r) = (first.pos, first.rot);
        poses.push(first);
        let mut latest = f64::NEG_INFINITY;
        for ((seg, law), start) in segments.iter().zip(laws).zip(starts) {
            latest = latest.max(start + law.duration());
            by.push(latest);
            // As `at_reference` adds a segment at its end: the same operations in
            // the same order, so that both give the same bits.
            p += seg.point(1.0, 0.0, 0.0).0 - seg.point(0.0, 0.0, 0.0).0;
            r = seg.increment(1.0, 0.0, 0.0).0 * r;
            poses.push(Pose::new(r, p));
        }
        Finished { by, poses }
    }
}

impl CartesianMotion {
    /// The motion of `segments` timed by `laws` from `starts`, lasting `duration`.
    fn assemble(segments: Vec<Segment>, laws: Vec<TimeLaw>, starts: Vec<f64>, duration: f64) -> CartesianMotion {
        let finished = Finished::new(&segments, &laws, &starts);
        CartesianMotion { segments, laws, starts, duration, finished }
    }

    /// Times `segments` (each must start where the previous ends, within
    /// 1e-9 m and 1e-9 rad) with laws of `profile` under `limits`, joined as
    /// `blend` says.
    ///
    /// Errors: no segment; segments that do not join; invalid limits.
    pub fn new(segments: Vec<Segment>, profile: Profile, limits: &CartesianLimits, blend: Blend) -> Result<Self> {
        Self::new_until(segments, profile, limits, blend, &|| false)
    }

    /// [`CartesianMotion::new`] that looks at `stop` between segments and
    /// returns [`Error::Cancelled`] once it says so: a chain of thousands of
    /// blended segments takes seconds to time.
    pub fn new_until(
        segments: Vec<Segment>,
        profile: Profile,
        limits: &CartesianLimits,
        blend: Blend,
        stop: &dyn Fn() -> bool,
    ) -> Result<Self> {
        if segments.is_empty() {
            return Err(Error::Input(InputError::TooFew {
                what: "segments".into(),
                got: 0,
                min: 1,
                of: "segments".into(),
            }));
        }
        for (i, w) in segments.windows(2).enumerate() {
            let (a, b) = (w[0].end(), w[1].start());
            let dp = (a.pos - b.pos).norm();
            let dr = rot_to_axis_angle(&(a.rot * b.rot.transpose())).norm();
            if dp > 1e-9 || dr > 1e-9 {
                return Err(Error::Input(InputError::DoesNotFit {
                    what: "segments".into(),
                    reason: format!(
                        "segment {} does not start where segment {} ends (off by {dp:.3e} m, {dr:.3e} rad)",
                        i + 2,
                        i + 1
                    ),
                }));
            }
        }
        let lin_jerk = match (profile, limits.jerk) {
            (Profile::SCurve, None) => {
                return Err(Error::Input(InputError::MissingLimit {
                    limit: "jerk".into(),
                    option: "jmax".into(),
                    needed_by: "the scurve profile".into(),
                }))
            }
            (_, j) => j,
        };
        let rot_jerk = limits.rot_jerk.or(lin_jerk);
        let named =
            [("vel", limits.vel), ("acc", limits.acc), ("rot_vel", limits.rot_vel), ("rot_acc", limits.rot_acc)];
        if let Some((what, value)) = named.into_iter().find(|(_, v)| !(v.is_finite() && *v > 0.0)) {
            return Err(Error::Input(InputError::OutOfRange {
                what: what.into(),
                value,
                expected: "a positive finite limit".into(),
            }));
        }
        let laws = segments
            .iter()
            .map(|seg| segment_law(seg, profile, limits, lin_jerk, rot_jerk))
            .collect::<Result<Vec<_>>>()?;
        let mut starts = vec![0.0];
        let mut overlaps = Vec::with_capacity(segments.len().saturating_sub(1));
        for i in 1..segments.len() {
            if stop() {
                return Err(Error::Cancelled);
            }
            let (prev, next) = (&laws[i - 1], &laws[i]);
            let requested = match blend {
                Blend::None => 0.0,
                Blend::Deceleration => decel_time(prev),
                Blend::Time(t) => t.max(0.0),
                Blend::Distance(d) => {
                    let (l, _) = segments[i - 1].lengths();
                    if l <= 0.0 || d <= 0.0 {
                        0.0
                    } else {
                        // Latest t with l·(1 − s(t)) ≥ d, by bisection on the monotone law.
                        let target = 1.0 - (d / l).min(1.0);
                        let (mut lo, mut hi) = (0.0, prev.duration());
                        for _ in 0..100 {
                            let mid = 0.5 * (lo + hi);
                            if prev.at(mid).s < target {
                                lo = mid;
                            } else {
                                hi = mid;
                            }
                        }
                        prev.duration() - lo
                    }
                }
            }
            .min(0.5 * prev.duration())
            .min(0.5 * next.duration());
            // The two segments alone, the second starting `o` before the first ends.
            let pair = |o: f64| {
                CartesianMotion::assemble(
                    vec![segments[i - 1], segments[i]],
                    vec![*prev, *next],
                    vec![0.0, prev.duration() - o],
                    prev.duration() + next.duration() - o,
                )
            };
            let fits = |o: f64| {
                let p = pair(o);
                o <= 0.0 || p.peak_ratio(limits, prev.duration() - o, prev.duration()) <= 1.0 + 1e-10
            };
            // Where the sum of the two would break a limit, blend less (down to a stop).
            let overlap = if fits(requested) {
                requested
            } else {
                let (mut lo, mut hi) = (0.0, requested);
                for _ in 0..40 {
                    let mid = 0.5 * (lo + hi);
                    if fits(mid) {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                lo
            };
            overlaps.push(overlap);
            starts.push(starts[i - 1] + prev.duration() - overlap);
        }
        let duration = starts.iter().zip(&laws).map(|(s, l)| s + l.duration()).fold(0.0, f64::max);
        Ok(CartesianMotion::assemble(segments, laws, starts, duration))
    }

    /// The largest ratio of a velocity to its limit, or of an acceleration to
    /// its limit (as a square root, the factor a uniform slow-down would
    /// need), over \[t0, t1\]: sampled at 501 points, then every sampled
    /// local maximum above 0.999 refined by golden-section search between its
    /// neighbours (exact to ~1e-12 where the peak lies between two samples).
    fn peak_ratio(&self, limits: &CartesianLimits, t0: f64, t1: f64) -> f64 {
        let ratio = |t: f64| {
            let st = self.at(t);
            (st.vel.norm() / limits.vel)
                .max((st.acc.norm() / limits.acc).sqrt())
                .max(st.omega.norm() / limits.rot_vel)
                .max((st.alpha.norm() / limits.rot_acc).sqrt())
        };
        const N: usize = 500;
        let h = (t1 - t0) / N as f64;
        let vals: Vec<f64> = (0..=N).map(|k| ratio(t0 + h * k as f64)).collect();
        let mut best = vals.iter().copied().fold(0.0, f64::max);
        // Sampled local maxima near the limit, the largest first. Rounding makes
        // a plateau at the limit ripple, so a maximum must stand out by more
        // than that, and only the few largest are refined.
        let noise = 1e-12;
        let mut peaks: Vec<usize> = (0..=N)
            .filter(|&k| {
                let (a, b) = (k.saturating_sub(1), (k + 1).min(N));
                vals[k] > 1.0 - 1e-3 && (k == 0 || vals[k] > vals[a] + noise) && vals[k] >= vals[b]
            })
            .collect();
        peaks.sort_by(|&x, &y| vals[y].total_cmp(&vals[x]));
        for &k in peaks.iter().take(MAX_REFINED_PEAKS) {
            let (a, b) = (k.saturating_sub(1), (k + 1).min(N));
            let (mut lo, mut hi) = (t0 + h * a as f64, t0 + h * b as f64);
            const G: f64 = 0.618_033_988_749_894_9;
            for _ in 0..60 {
                let (m1, m2) = (hi - G * (hi - lo), lo + G * (hi - lo));
                if ratio(m1) < ratio(m2) {
                    lo = m1;
                } else {
                    hi = m2;
                }
            }
            best = best.max(ratio(0.5 * (lo + hi)));
        }
        best
    }

    /// The same motion slowed down uniformly to last `duration` \[s\] (at least
    /// its own): every time scaled by k = T′/T, so velocities shrink by k,
    /// accelerations by k², jerks by k³, and every limit still holds.
    pub fn stretched_to(&self, duration: f64) -> Result<Self> {
        if !(duration.is_finite() && duration >= self.duration) {
            return Err(Error::Input(InputError::OutOfRange {
                what: "duration".into(),
                value: duration,
                expected: format!(
                    "at least the motion's own duration, {} s (a motion is only stretched)",
                    self.duration
                ),
            }));
        }
        if self.duration == 0.0 {
            return Ok(self.clone());
        }
        let k = duration / self.duration;
        Ok(CartesianMotion::assemble(
            self.segments.clone(),
            self.laws.iter().map(|l| l.stretched_to(l.duration() * k)).collect::<Result<_>>()?,
            self.starts.iter().map(|s| s * k).collect(),
            duration,
        ))
    }

    /// Duration \[s\].
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// How long each blend lasts \[s\] (segment i + 1 starts this long before
    /// segment i ends), after any reduction needed to respect the limits.
    pub fn blend_times(&self) -> Vec<f64> {
        (1..self.laws.len()).map(|i| self.starts[i - 1] + self.laws[i - 1].duration() - self.starts[i]).collect()
    }

    /// Start times \[s\] of the segments.
    pub fn segment_starts(&self) -> &[f64] {
        &self.starts
    }

    /// The segments' time laws.
    pub fn laws(&self) -> &[TimeLaw] {
        &self.laws
    }

    /// Pose, velocity and acceleration at time `t` \[s\] (clamped to the motion).
    pub fn at(&self, t: f64) -> CartesianState {
        // Segments 0..done have ended by t, segments from `started` on not
        // begun: only those between move (one, or two in a blend).
        let done = self.finished.by.partition_point(|&end| end <= t);
        let started = done + self.starts[done..].partition_point(|&start| start <= t);
        self.compose(&self.finished.poses[done], done..started, t)
    }

    /// [`CartesianMotion::at`] the plain way, every segment composed at `t`:
    /// the reference the fast path is tested against.
    #[doc(hidden)]
    pub fn at_reference(&self, t: f64) -> CartesianState {
        self.compose(&self.segments[0].start(), 0..self.segments.len(), t)
    }

    /// The state at `t` of segments `range` composed onto `from`, the pose
    /// the segments before them have reached.
    fn compose(&self, from: &Pose, range: std::ops::Range<usize>, t: f64) -> CartesianState {
        let (mut p, mut v, mut a) = (from.pos, Vector3::zeros(), Vector3::zeros());
        let (mut r, mut w, mut al) = (from.rot, Vector3::zeros(), Vector3::zeros());
        let running = self.segments[range.clone()].iter().zip(&self.laws[range.clone()]).zip(&self.starts[range]);
        for ((seg, law), start) in running {
            let s = law.at(t - start);
            let (pp, pv, pa) = seg.point(s.s, s.sd, s.sdd);
            p += pp - seg.point(0.0, 0.0, 0.0).0;
            v += pv;
            a += pa;
            let (d, dw, da) = seg.increment(s.s, s.sd, s.sdd);
            // Compose Δ·(R, ω, α): ω' = ω_Δ + Δ·ω, α' = α_Δ + Δ·α + ω_Δ × (Δ·ω).
            let (rw, ra) = (d * w, d * al);
            al = da + ra + dw.cross(&rw);
            w = dw + rw;
            r = d * r;
        }
        CartesianState { pose: Pose::new(r, p), vel: v, omega: w, acc: a, alpha: al }
    }

    /// Poses split so that consecutive ones are at most `max_step` \[m\]
    /// apart along the path and `max_angle` \[rad\] apart in orientation (seed
    /// 000 used 1 cm for its controller), from start to end: the times at
    /// which to sample.
    pub fn resample_times(&self, max_step: f64, max_angle: f64) -> Result<Vec<f64>> {
        for (what, value, unit) in [("max_step", max_step, "m"), ("max_angle", max_angle, "rad")] {
            if !(value > 0.0) {
                return Err(Error::Input(InputError::OutOfRange {
                    what: what.into(),
                    value,
                    expected: format!("a positive step [{unit}]"),
                }));
            }
        }
        let n = 20_000usize;
        let coarse: Vec<Pose> = (0..=n).map(|k| self.at(self.duration * k as f64 / n as f64).pose).collect();
        let far = |q: &Pose, last: &Pose| {
            (q.pos - last.pos).norm() > max_step
                || rot_to_axis_angle(&(q.rot * last.rot.transpose())).norm() > max_angle
        };
        // How many samples the limits ask for, from the coarse poses (each step of the result
        // spans max_step or max_angle, but for the last): a path that needs far more than can
        // be held is refused now, not after minutes of bisection.
        let (mut needed, mut by_angle) = (1.0, 0.0);
        for w in coarse.windows(2) {
            let angle = rot_to_axis_angle(&(w[1].rot * w[0].rot.transpose())).norm() / max_angle;
            let step = (w[1].pos - w[0].pos).norm() / max_step;
            needed += step.max(angle);
            if angle > step {
                by_angle += angle;
            }
        }
        // Named after the limit that asks for most of the samples.
        let (what, value) = if by_angle > 0.5 * needed { ("max_angle", max_angle) } else { ("max_step", max_step) };
        let too_many = |about: String| {
            Error::Input(InputError::OutOfRange {
                what: what.into(),
                value,
                expected: format!(
                    "larger steps: {} m / {} rad would split this path into {about} samples (at most {MAX_SAMPLES})",
                    crate::error::number_text(max_step),
                    crate::error::number_text(max_angle)
                ),
            })
        };
        if needed > 1.01 * MAX_SAMPLES as f64 {
            let about = if needed.is_finite() { format!("about {needed:.3e}") } else { "more than 10^308".into() };
            return Err(too_many(about));
        }
        let mut out = vec![0.0];
        let mut last = coarse[0];
        // A time whose pose is within reach of `last`: where the bisections start.
        let mut within = 0.0;
        for (k, pose) in coarse.iter().enumerate().skip(1) {
            let t = self.duration * k as f64 / n as f64;
            // One coarse step may span several max_steps (a long path, a small step):
            // as many samples as it needs, each the last time within reach of the one
            // before, found by bisection between `within` and t.
            while far(pose, &last) {
                let (mut lo, mut hi) = (within, t);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if far(&self.at(mid).pose, &last) {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                if lo <= *out.last().expect("non-empty") {
                    return Err(Error::Input(InputError::OutOfRange {
                        what: "max_step".into(),
                        value: max_step,
                        expected: "a step above the sampling resolution of this path [m]".into(),
                    }));
                }
                // Room for this sample and the end's.
                if out.len() + 2 > MAX_SAMPLES {
                    return Err(too_many(format!("more than {MAX_SAMPLES}")));
                }
                out.push(lo);
                last = self.at(lo).pose;
                within = lo;
            }
            within = t;
        }
        if self.duration > *out.last().expect("non-empty") {
            out.push(self.duration);
        }
        Ok(out)
    }
}

/// How long `law` decelerates at its end (its last phases with s̈ < 0).
fn decel_time(law: &TimeLaw) -> f64 {
    let t = law.duration();
    match law.profile() {
        Profile::Trapezoid => law.phase_times().last().copied().unwrap_or(0.0),
        Profile::SCurve => {
            let p = law.phase_times();
            // Phases after the cruise (or after the acceleration when there is none).
            let half = if p.len() == 7 || p.len() == 5 { p.len() / 2 + 1 } else { p.len() / 2 };
            p[half.min(p.len())..].iter().sum()
        }
        _ => t / 2.0,
    }
}
