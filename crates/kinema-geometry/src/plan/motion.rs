//! Whether the robot may stand at a configuration, and move on the straight
//! joint-space segment between two: the planner's collision questions,
//! asked millions of times, so the spheres answer first.
//!
//! A segment is cut into k equal intervals, each checked at its middle
//! configuration. A shape moves at most `sweep/(2k)` from there within its
//! interval (the lever-arm bound of [`sweep`](crate::sweep)), so spheres
//! grown by that much and still more than the margin apart prove the whole
//! interval free. An interval whose grown spheres come close is decided
//! exactly by conservative advancement on the real shapes. Either way no
//! contact between samples is missed, and the answer is the exact one.
//!
//! Intervals are visited in bit-reversed order (middle, quarters, eighths, …),
//! so a collision anywhere on a segment is found after a few checks.
//!
//! Fixed shapes (the scene's obstacles, link 0) are not cut into spheres:
//! a robot sphere is compared with the obstacle itself (its distance to the
//! sphere's centre), which is as cheap for boxes and cylinders and far less
//! pessimistic. Triangle-mesh obstacles keep their spheres: a soup of
//! triangles has no inside to measure from.

use std::time::Instant;

use nalgebra::Point3;

use kinema::Robot;

use super::fixed::FixedShape;
use super::round::{segment_distance, RoundShape};
use crate::check::CollisionCheck;
use crate::error::Result;
use crate::placement::{place_moving, Placement};
use crate::query::{aabb_gap, pair_gap};
use crate::shape::Shape;
use crate::spheres::{place_spheres, SpherePlacement, Spheres};

/// How far \[m\] a shape may move from the middle of an interval the
/// spheres check: coarse, because an interval they cannot clear is halved
/// (the growth with it) before the exact check.
const GROWTH: f64 = 0.02;

/// Halvings of an interval the spheres did not clear before the exact check.
const MAX_SPLITS: usize = 3;

/// Spheres fitted per shape: a capsule of length 4× its width gets four.
const SPHERES_PER_SHAPE: usize = 4;

/// How one checked pair is tested on the fast path.
#[derive(Debug, Clone, Copy)]
enum PairTest {
    /// Sphere against sphere (two moving shapes, or a mesh obstacle).
    Spheres(usize, usize),
    /// Two moving capsules or spheres, exactly (indices into [`MotionCheck::round`]).
    Round { a: usize, b: usize, shapes: (usize, usize) },
    /// The spheres of a moving shape against a fixed shape's exact
    /// distance (`fixed` indexes [`MotionCheck::fixed`]).
    Fixed { moving: usize, fixed: usize },
    /// A moving capsule or sphere against a fixed box, exactly (`round`
    /// indexes [`MotionCheck::round`], `moving` is its shape).
    RoundBox { round: usize, moving: usize, fixed: usize },
}

/// What a test at an interval's middle configuration says of the interval.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Outcome {
    /// Every pair apart by more than the margin plus the growth: free.
    Clear,
    /// A pair within the margin at the middle itself: not free.
    Colliding,
    /// Neither: a finer test decides.
    Near,
}

/// Counts of the work done, for benchmarks and tests.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MotionCounts {
    /// Configurations the spheres were placed at.
    pub sphere_checks: u64,
    /// Intervals (or configurations) the spheres could not clear, decided exactly.
    pub exact_checks: u64,
    /// Segments checked.
    pub segments: u64,
}

/// The planner's collision test on one [`CollisionCheck`], with its
/// reusable buffers: exact answers for a configuration and for a straight
/// joint-space segment, the spheres (grown by how far each link can move
/// within an interval of the segment) deciding most of them and the real
/// shapes the rest (see [`plan`](super) for the steps).
#[derive(Debug, Clone)]
pub struct MotionCheck<'c> {
    check: &'c CollisionCheck,
    spheres: Spheres,
    tests: Vec<PairTest>,
    fixed: Vec<FixedShape>,
    round: Vec<RoundShape>,
    /// The round shapes' core segments at the configuration last tested.
    round_at: Vec<[Point3<f64>; 2]>,
    spheres_at: SpherePlacement,
    /// The exact shapes: fixed ones placed once, moving ones per exact check.
    placement: Placement,
    q: Vec<f64>,
    q_end: Vec<f64>,
    growth: Vec<f64>,
    /// How far each shape moves over the whole segment being checked \[m\].
    sweeps: Vec<f64>,
    /// Intervals of the segment being checked that its first pass left open.
    undecided: Vec<usize>,
    /// When a segment check gives up and answers "blocked" (see [`MotionCheck::set_deadline`]).
    deadline: Option<Instant>,
    counts: MotionCounts,
}

impl<'c> MotionCheck<'c> {
    /// The test for `check`'s robot, shapes, pairs and margin.
    pub fn new(check: &'c CollisionCheck) -> Result<MotionCheck<'c>> {
        let geometry = check.geometry();
        let spheres = Spheres::fit(geometry, SPHERES_PER_SHAPE);
        let fixed = |s: usize| {
            let shape = &geometry.shapes()[s];
            shape.link() == 0 && !matches!(shape.shape(), Shape::TriangleMesh(_))
        };
        let moving = |s: usize| geometry.shapes()[s].link() != 0;
        let robot = check.robot();
        let mut placement = check.placement();
        check.place(robot.home(), &mut placement)?;
        // Every shape's fast-test form: fixed ones placed once, round ones as capsules.
        let mut fixed_shapes: Vec<FixedShape> = Vec::new();
        let mut round: Vec<RoundShape> = Vec::new();
        let (mut fixed_of, mut round_of) = (vec![None; geometry.len()], vec![None; geometry.len()]);
        for s in 0..geometry.len() {
            if let Some(r) = RoundShape::of(&geometry.shapes()[s]) {
                round.push(r);
                round_of[s] = Some(round.len() - 1);
            }
            if fixed(s) {
                fixed_shapes.push(FixedShape::new(check, &placement, s));
                fixed_of[s] = Some(fixed_shapes.len() - 1);
            }
        }
        let fixed_test = |moving: usize, fixed: usize| match round_of[moving] {
            Some(round) if fixed_shapes[fixed].is_box() => PairTest::RoundBox { round, moving, fixed },
            _ => PairTest::Fixed { moving, fixed },
        };
        // Pairs of two fixed shapes never change: the start's exact check decides them.
        let tests = check
            .pairs()
            .iter()
            .filter(|&(a, b)| moving(a) || moving(b))
            .map(|(a, b)| match (round_of[a], round_of[b], fixed_of[a], fixed_of[b]) {
                (Some(ra), Some(rb), ..) => PairTest::Round { a: ra, b: rb, shapes: (a, b) },
                (.., Some(f), _) => fixed_test(b, f),
                (.., Some(f)) => fixed_test(a, f),
                _ => PairTest::Spheres(a, b),
            })
            .collect();
        Ok(MotionCheck {
            check,
            spheres_at: spheres.placement(),
            spheres,
            tests,
            fixed: fixed_shapes,
            round_at: vec![[Point3::origin(); 2]; round.len()],
            round,
            placement,
            q: vec![0.0; robot.dof()],
            q_end: vec![0.0; robot.dof()],
            growth: vec![0.0; geometry.len()],
            sweeps: vec![0.0; geometry.len()],
            undecided: Vec::new(),
            deadline: None,
            counts: MotionCounts::default(),
        })
    }

    /// From `deadline` on, a segment check answers "not free" at its next
    /// interval instead of finishing: a planner's time budget stays kept
    /// when one check is slow (shapes made of many triangles). `None`:
    /// every check runs to its exact answer.
    pub fn set_deadline(&mut self, deadline: Option<Instant>) {
        self.deadline = deadline;
    }

    fn past_deadline(&self) -> bool {
        self.deadline.is_some_and(|d| Instant::now() >= d)
    }

    /// The robot.
    pub fn robot(&self) -> &Robot {
        self.check.robot()
    }

    /// The work done so far.
    pub fn counts(&self) -> MotionCounts {
        self.counts
    }

    /// Whether the robot at `q` keeps every checked pair farther apart than
    /// the margin. Exact (the spheres only shortcut a clear answer).
    pub fn config_free(&mut self, q: &[f64]) -> Result<bool> {
        self.check.robot().check_q(q)?;
        self.growth.fill(0.0);
        match self.fast_test(q)? {
            Outcome::Clear => Ok(true),
            Outcome::Colliding => Ok(false),
            Outcome::Near => {
                self.counts.exact_checks += 1;
                Ok(self.check.first_collision(q)?.is_none())
            }
        }
    }

    /// Whether the straight joint-space segment `from` → `to`, ends
    /// included, keeps every checked pair farther apart than the margin.
    /// Exact: no contact between samples is missed.
    ///
    /// A first pass asks the fast test at every interval's middle: a
    /// collision there ends the check at once (most segments a search
    /// tries collide), a clear answer settles the interval. The intervals
    /// left are then decided one by one: halved, then measured on the real shapes.
    pub fn segment_free(&mut self, from: &[f64], to: &[f64]) -> Result<bool> {
        let robot = self.check.robot();
        robot.check_q(from)?;
        robot.check_q(to)?;
        self.counts.segments += 1;
        self.sweeps = self.check.arms().sweeps(from, to);
        let longest = self.sweeps.iter().fold(0.0_f64, |m, &s| m.max(s));
        let intervals = interval_count(longest)?;
        let part = |i: usize| (i as f64 / intervals as f64, (i + 1) as f64 / intervals as f64);
        let mut undecided = std::mem::take(&mut self.undecided);
        undecided.clear();
        for (n, i) in spread_order(intervals).enumerate() {
            if n % DEADLINE_EVERY == DEADLINE_EVERY - 1 && self.past_deadline() {
                self.undecided = undecided;
                return Ok(false);
            }
            let (lo, hi) = part(i);
            match self.interval_outcome(from, to, lo, hi)? {
                Outcome::Clear => {}
                Outcome::Colliding => {
                    self.undecided = undecided;
                    return Ok(false);
                }
                Outcome::Near => undecided.push(i),
            }
        }
        let mut free = true;
        for &i in &undecided {
            let (lo, hi) = part(i);
            if !self.interval_free(from, to, lo, hi, 0)? {
                free = false;
                break;
            }
        }
        self.undecided = undecided;
        Ok(free)
    }

    /// Sets each shape's growth to how far it moves from the middle of the
    /// part `lo`..`hi` of the segment.
    fn grow_for(&mut self, lo: f64, hi: f64) {
        for (g, s) in self.growth.iter_mut().zip(&self.sweeps) {
            *g = s * (hi - lo) / 2.0;
        }
    }

    /// The fast test at the middle of the part `lo`..`hi` of the segment,
    /// the shapes grown by how far each moves from there.
    fn interval_outcome(&mut self, from: &[f64], to: &[f64], lo: f64, hi: f64) -> Result<Outcome> {
        self.grow_for(lo, hi);
        let mut q = std::mem::take(&mut self.q);
        lerp_into(from, to, (lo + hi) / 2.0, &mut q);
        let outcome = self.fast_test(&q);
        self.q = q;
        outcome
    }

    /// Decides a part of the segment the fast test left open: its two
    /// halves by the fast test again (each grows half as much), down to
    /// [`MAX_SPLITS`] halvings, then the real shapes at its middle and, if
    /// still undecided, the continuous check.
    fn interval_free(&mut self, from: &[f64], to: &[f64], lo: f64, hi: f64, splits: usize) -> Result<bool> {
        if splits < MAX_SPLITS {
            let mid = (lo + hi) / 2.0;
            for (a, b) in [(lo, mid), (mid, hi)] {
                match self.interval_outcome(from, to, a, b)? {
                    Outcome::Clear => {}
                    Outcome::Colliding => return Ok(false),
                    Outcome::Near => {
                        if !self.interval_free(from, to, a, b, splits + 1)? {
                            return Ok(false);
                        }
                    }
                }
            }
            return Ok(true);
        }
        if self.past_deadline() {
            return Ok(false);
        }
        self.counts.exact_checks += 1;
        self.grow_for(lo, hi);
        match self.shapes_at_middle(from, to, lo, hi)? {
            Outcome::Clear => return Ok(true),
            Outcome::Colliding => return Ok(false),
            Outcome::Near => {}
        }
        let (mut a, mut b) = (std::mem::take(&mut self.q), std::mem::take(&mut self.q_end));
        lerp_into(from, to, lo, &mut a);
        lerp_into(from, to, hi, &mut b);
        // The fixed shapes' poses in `placement` do not change with q.
        let contact = self.check.segment().first_contact(&a, &b, &mut self.placement);
        (self.q, self.q_end) = (a, b);
        Ok(contact?.is_none())
    }

    /// The real shapes at the middle of `lo`..`hi`: apart by more than the
    /// margin plus how far each moves from there (the growth set for this
    /// part), or a pair already within the margin there, or neither.
    fn shapes_at_middle(&mut self, from: &[f64], to: &[f64], lo: f64, hi: f64) -> Result<Outcome> {
        let mut q = std::mem::take(&mut self.q);
        lerp_into(from, to, (lo + hi) / 2.0, &mut q);
        // Placed in full in `new`: the fixed shapes stay.
        let placed = place_moving(self.check.robot(), self.check.geometry(), &q, &mut self.placement);
        self.q = q;
        placed?;
        let (geometry, margin) = (self.check.geometry(), self.check.margin());
        let mut middle = Outcome::Clear;
        for (a, b) in self.check.pairs().iter() {
            let (ga, gb) = (self.growth[a], self.growth[b]);
            if ga == 0.0 && gb == 0.0 && geometry.shapes()[a].link() == 0 && geometry.shapes()[b].link() == 0 {
                continue; // two fixed shapes: decided at the start
            }
            let reach = ga + gb + margin;
            if aabb_gap(self.placement.aabb(a), self.placement.aabb(b)) > reach {
                continue;
            }
            let gap = pair_gap(geometry, &self.placement, a, b)?;
            if gap <= margin {
                return Ok(Outcome::Colliding);
            }
            if gap <= reach {
                middle = Outcome::Near;
            }
        }
        Ok(middle)
    }

    /// The fast test at `q`, each shape grown by its `growth`: clear when
    /// every pair is proved apart by more than the margin; colliding when a
    /// pair tested exactly (capsules, a capsule and a box) is within the
    /// margin at `q` itself; else near.
    fn fast_test(&mut self, q: &[f64]) -> Result<Outcome> {
        self.counts.sphere_checks += 1;
        place_spheres(self.check.robot(), &self.spheres, q, &mut self.spheres_at)?;
        let margin = self.check.margin();
        let (centres, radii, frames) = (self.spheres_at.centres(), self.spheres.radii(), self.spheres_at.frames());
        for (at, r) in self.round_at.iter_mut().zip(&self.round) {
            *at = r.placed(&frames[r.link]);
        }
        let mut outcome = Outcome::Clear;
        for test in &self.tests {
            let pair = match *test {
                PairTest::Spheres(a, b) => {
                    let extra = self.growth[a] + self.growth[b] + margin;
                    let near = self.spheres.range_of(a).any(|i| {
                        self.spheres.range_of(b).any(|j| {
                            let reach = radii[i] + radii[j] + extra;
                            (centres[i] - centres[j]).norm_squared() <= reach * reach
                        })
                    });
                    if near {
                        Outcome::Near
                    } else {
                        Outcome::Clear
                    }
                }
                PairTest::Round { a, b, shapes } => {
                    let (ra, rb) = (&self.round[a], &self.round[b]);
                    let ([p1, q1], [p2, q2]) = (&self.round_at[a], &self.round_at[b]);
                    let touch = ra.radius + rb.radius + margin;
                    let reach = touch + self.growth[shapes.0] + self.growth[shapes.1];
                    // The spheres around both capsules first: most pairs are far apart.
                    let (centre_gap, bound) =
                        (nalgebra::center(p1, q1) - nalgebra::center(p2, q2), reach + ra.half + rb.half);
                    if centre_gap.norm_squared() > bound * bound {
                        Outcome::Clear
                    } else {
                        exact_outcome(segment_distance(p1, q1, p2, q2), touch, reach)
                    }
                }
                PairTest::RoundBox { round, moving, fixed } => {
                    let r = &self.round[round];
                    let [p, q] = &self.round_at[round];
                    let touch = r.radius + margin;
                    let reach = touch + self.growth[moving];
                    match self.fixed[fixed].segment_gap_squared(p, q, reach) {
                        Some(squared) => exact_outcome(squared.sqrt(), touch, reach),
                        None => Outcome::Clear,
                    }
                }
                PairTest::Fixed { moving, fixed } => {
                    let extra = self.growth[moving] + margin;
                    let shape = &self.fixed[fixed];
                    let near = self
                        .spheres
                        .range_of(moving)
                        .any(|i| shape.within(&centres[i], radii[i] + extra, &self.placement, self.check));
                    if near {
                        Outcome::Near
                    } else {
                        Outcome::Clear
                    }
                }
            };
            match pair {
                Outcome::Colliding => return Ok(Outcome::Colliding),
                Outcome::Near => outcome = Outcome::Near,
                Outcome::Clear => {}
            }
        }
        Ok(outcome)
    }
}

/// An exactly measured pair at `distance` (between core shapes): colliding
/// within `touch`, near within `reach`, else clear.
fn exact_outcome(distance: f64, touch: f64, reach: f64) -> Outcome {
    if distance <= touch {
        Outcome::Colliding
    } else if distance <= reach {
        Outcome::Near
    } else {
        Outcome::Clear
    }
}

/// How many intervals a segment whose shapes move at most `longest` \[m\]
/// is cut into: each sphere grows by at most [`GROWTH`]. An error past
/// [`MAX_INTERVALS`], so one check stays bounded.
fn interval_count(longest: f64) -> Result<usize> {
    let count = (longest / (2.0 * GROWTH)).ceil();
    if !(count <= MAX_INTERVALS as f64) {
        return Err(crate::Error::Kinema(kinema::Error::Input(kinema::InputError::OutOfRange {
            what: "the segment's sweep [m]".into(),
            value: longest,
            expected: format!(
                "at most {} m of motion of any shape along one segment",
                2.0 * GROWTH * MAX_INTERVALS as f64
            ),
        })));
    }
    Ok((count as usize).max(1))
}

/// Intervals of a first pass between two looks at the clock.
const DEADLINE_EVERY: usize = 16;

/// The most intervals one segment is cut into.
const MAX_INTERVALS: usize = 1 << 16;

/// 0..n in bit-reversed order (for n = 8: 0 4 2 6 1 5 3 7): every prefix is
/// spread over the whole range.
pub(crate) fn spread_order(n: usize) -> impl Iterator<Item = usize> {
    let bits = usize::BITS - n.saturating_sub(1).leading_zeros();
    (0..1usize << bits)
        .map(move |i| if bits == 0 { 0 } else { i.reverse_bits() >> (usize::BITS - bits) })
        .filter(move |&i| i < n)
}

/// `out` = `from` + s·(`to` − `from`).
pub(crate) fn lerp_into(from: &[f64], to: &[f64], s: f64, out: &mut [f64]) {
    for ((o, a), b) in out.iter_mut().zip(from).zip(to) {
        *o = a + s * (b - a);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spread_order_visits_each_interval_once() {
        for n in 1..300 {
            let mut seen: Vec<usize> = spread_order(n).collect();
            assert_eq!(seen.len(), n);
            seen.sort_unstable();
            assert!(seen.iter().enumerate().all(|(i, &v)| i == v), "n = {n}");
        }
        assert_eq!(spread_order(8).collect::<Vec<_>>(), [0, 4, 2, 6, 1, 5, 3, 7]);
    }
}
