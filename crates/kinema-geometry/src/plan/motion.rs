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

use nalgebra::Point3;

use kinema::Robot;

use crate::check::CollisionCheck;
use crate::error::Result;
use crate::placement::Placement;
use crate::shape::Shape;
use crate::spheres::{place_spheres, SpherePlacement, Spheres};

/// Spheres fitted per shape: a capsule of length 4× its width gets four.
const SPHERES_PER_SHAPE: usize = 4;

/// How one checked pair is tested on the fast path.
#[derive(Debug, Clone, Copy)]
enum PairTest {
    /// Sphere against sphere (two moving shapes, or a mesh obstacle).
    Spheres(usize, usize),
    /// The spheres of a moving shape against a fixed shape's exact distance.
    Fixed { moving: usize, fixed: usize },
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

/// The planner's collision test on one [`CollisionCheck`] (see the
/// [module documentation](self)), with its reusable buffers.
#[derive(Debug, Clone)]
pub struct MotionCheck<'c> {
    check: &'c CollisionCheck,
    spheres: Spheres,
    tests: Vec<PairTest>,
    spheres_at: SpherePlacement,
    /// The exact shapes: fixed ones placed once, moving ones per exact check.
    placement: Placement,
    q: Vec<f64>,
    q_end: Vec<f64>,
    growth: Vec<f64>,
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
        // Pairs of two fixed shapes never change: the start's exact check decides them.
        let tests = check
            .pairs()
            .iter()
            .filter(|&(a, b)| moving(a) || moving(b))
            .map(|(a, b)| match (fixed(a), fixed(b)) {
                (true, _) => PairTest::Fixed { moving: b, fixed: a },
                (_, true) => PairTest::Fixed { moving: a, fixed: b },
                _ => PairTest::Spheres(a, b),
            })
            .collect();
        let robot = check.robot();
        let mut placement = check.placement();
        check.place(robot.home(), &mut placement)?;
        Ok(MotionCheck {
            check,
            spheres_at: spheres.placement(),
            spheres,
            tests,
            placement,
            q: vec![0.0; robot.dof()],
            q_end: vec![0.0; robot.dof()],
            growth: vec![0.0; geometry.len()],
            counts: MotionCounts::default(),
        })
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
        self.growth.fill(0.0);
        if self.spheres_clear(q)? {
            return Ok(true);
        }
        self.counts.exact_checks += 1;
        Ok(self.check.first_collision(q)?.is_none())
    }

    /// Whether the straight joint-space segment `from` → `to`, ends
    /// included, keeps every checked pair farther apart than the margin.
    /// Exact: no contact between samples is missed.
    pub fn segment_free(&mut self, from: &[f64], to: &[f64]) -> Result<bool> {
        self.counts.segments += 1;
        let sweeps = self.check.arms().sweeps(from, to);
        let longest = sweeps.iter().fold(0.0_f64, |m, &s| m.max(s));
        let intervals = interval_count(longest, self.check.margin());
        for (g, s) in self.growth.iter_mut().zip(&sweeps) {
            *g = s / (2 * intervals) as f64;
        }
        for i in spread_order(intervals) {
            let (lo, hi) = (i as f64 / intervals as f64, (i + 1) as f64 / intervals as f64);
            let mid = (lo + hi) / 2.0;
            let mut q = std::mem::take(&mut self.q);
            lerp_into(from, to, mid, &mut q);
            let clear = self.spheres_clear(&q);
            self.q = q;
            if clear? {
                continue;
            }
            self.counts.exact_checks += 1;
            let (mut a, mut b) = (std::mem::take(&mut self.q), std::mem::take(&mut self.q_end));
            lerp_into(from, to, lo, &mut a);
            lerp_into(from, to, hi, &mut b);
            // The fixed shapes' poses in `placement` do not change with q.
            let contact = self.check.segment().first_contact(&a, &b, &mut self.placement);
            (self.q, self.q_end) = (a, b);
            if contact?.is_some() {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// Whether the spheres at `q`, each grown by its shape's `growth`,
    /// prove every pair apart by more than the margin.
    fn spheres_clear(&mut self, q: &[f64]) -> Result<bool> {
        self.counts.sphere_checks += 1;
        place_spheres(self.check.robot(), &self.spheres, q, &mut self.spheres_at)?;
        let margin = self.check.margin();
        let (centres, radii) = (self.spheres_at.centres(), self.spheres.radii());
        let shapes = self.check.geometry().shapes();
        for test in &self.tests {
            let near = match *test {
                PairTest::Spheres(a, b) => {
                    let extra = self.growth[a] + self.growth[b] + margin;
                    self.spheres.range_of(a).any(|i| {
                        self.spheres.range_of(b).any(|j| {
                            let reach = radii[i] + radii[j] + extra;
                            (centres[i] - centres[j]).norm_squared() <= reach * reach
                        })
                    })
                }
                PairTest::Fixed { moving, fixed } => {
                    let at = self.placement.world_from_collider(fixed);
                    let collider = shapes[fixed].collider();
                    let extra = self.growth[moving] + margin;
                    self.spheres.range_of(moving).any(|i| {
                        let centre: &Point3<f64> = &centres[i];
                        collider.distance_to_point(at, centre, true) <= radii[i] + extra
                    })
                }
            };
            if near {
                return Ok(false);
            }
        }
        Ok(true)
    }
}

/// How many intervals a segment whose shapes move at most `longest` \[m\]
/// is cut into: each sphere grows by at most a quarter of the margin, or
/// 5 mm without one, so that growth rarely sends an interval to the exact check.
fn interval_count(longest: f64, margin: f64) -> usize {
    let growth = if margin > 0.0 { (margin / 4.0).min(0.005) } else { 0.005 };
    ((longest / (2.0 * growth)).ceil() as usize).max(1)
}

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
