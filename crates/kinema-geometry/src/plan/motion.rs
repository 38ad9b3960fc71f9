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

use nalgebra::{Point3, Vector3};

use kinema::{Pose, Robot};

use super::round::{segment_distance, RoundShape};
use crate::check::CollisionCheck;
use crate::error::Result;
use crate::placement::Placement;
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
}

/// A fixed shape as the sphere test asks it: a bounding box to cull far
/// spheres, then the exact distance to the sphere's centre.
#[derive(Debug, Clone)]
enum FixedShape {
    /// A box, measured by hand: the common obstacle, and parry's general
    /// point query costs several times more.
    Cuboid { shape: usize, lo: Point3<f64>, hi: Point3<f64>, box_from_world: Pose, half: Vector3<f64> },
    /// Any other shape, measured by parry.
    General { shape: usize, lo: Point3<f64>, hi: Point3<f64> },
}

impl FixedShape {
    fn new(check: &CollisionCheck, placement: &Placement, shape: usize) -> FixedShape {
        let aabb = placement.aabb(shape);
        let (lo, hi) = (aabb.mins, aabb.maxs);
        match check.geometry().shapes()[shape].shape() {
            Shape::Box { size } => {
                let world_from_box = placement.world_from_shape(check.geometry(), shape);
                FixedShape::Cuboid { shape, lo, hi, box_from_world: world_from_box.inverse(), half: size / 2.0 }
            }
            _ => FixedShape::General { shape, lo, hi },
        }
    }

    /// Whether a sphere at `centre` of radius `reach` comes within the shape.
    fn within(&self, centre: &Point3<f64>, reach: f64, placement: &Placement, check: &CollisionCheck) -> bool {
        let (lo, hi) = match self {
            FixedShape::Cuboid { lo, hi, .. } | FixedShape::General { lo, hi, .. } => (lo, hi),
        };
        let outside = (lo - centre).sup(&(centre - hi)).sup(&Vector3::zeros());
        if outside.norm_squared() > reach * reach {
            return false;
        }
        match self {
            FixedShape::Cuboid { box_from_world, half, .. } => box_distance(box_from_world, half, centre) <= reach,
            FixedShape::General { shape, .. } => {
                let at = placement.world_from_collider(*shape);
                check.geometry().shapes()[*shape].collider().distance_to_point(at, centre, true) <= reach
            }
        }
    }
}

/// The signed distance from `point` to a box of half extents `half` (negative inside).
fn box_distance(box_from_world: &Pose, half: &Vector3<f64>, point: &Point3<f64>) -> f64 {
    let local = box_from_world.rot * point.coords + box_from_world.pos;
    let excess = local.abs() - half;
    let outside = excess.sup(&Vector3::zeros()).norm();
    if outside > 0.0 {
        outside
    } else {
        excess.max()
    }
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
    spheres_at: SpherePlacement,
    /// The exact shapes: fixed ones placed once, moving ones per exact check.
    placement: Placement,
    q: Vec<f64>,
    q_end: Vec<f64>,
    growth: Vec<f64>,
    /// How far each shape moves over the whole segment being checked \[m\].
    sweeps: Vec<f64>,
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
        let mut fixed_shapes: Vec<FixedShape> = Vec::new();
        let mut fixed_index = |shape: usize| match fixed_shapes.iter().position(|f| f.shape() == shape) {
            Some(i) => i,
            None => {
                fixed_shapes.push(FixedShape::new(check, &placement, shape));
                fixed_shapes.len() - 1
            }
        };
        let mut round: Vec<RoundShape> = Vec::new();
        let mut round_of = |shape: usize| {
            RoundShape::of(&geometry.shapes()[shape]).map(|r| {
                round.push(r);
                round.len() - 1
            })
        };
        // Pairs of two fixed shapes never change: the start's exact check decides them.
        let tests = check
            .pairs()
            .iter()
            .filter(|&(a, b)| moving(a) || moving(b))
            .map(|(a, b)| match (fixed(a), fixed(b)) {
                (true, _) => PairTest::Fixed { moving: b, fixed: fixed_index(a) },
                (_, true) => PairTest::Fixed { moving: a, fixed: fixed_index(b) },
                _ if moving(a) && moving(b) => match (round_of(a), round_of(b)) {
                    (Some(ra), Some(rb)) => PairTest::Round { a: ra, b: rb, shapes: (a, b) },
                    _ => PairTest::Spheres(a, b),
                },
                _ => PairTest::Spheres(a, b),
            })
            .collect();
        Ok(MotionCheck {
            check,
            spheres_at: spheres.placement(),
            spheres,
            tests,
            fixed: fixed_shapes,
            round,
            placement,
            q: vec![0.0; robot.dof()],
            q_end: vec![0.0; robot.dof()],
            growth: vec![0.0; geometry.len()],
            sweeps: vec![0.0; geometry.len()],
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
        self.check.robot().check_q(q)?;
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
        let robot = self.check.robot();
        robot.check_q(from)?;
        robot.check_q(to)?;
        self.counts.segments += 1;
        self.sweeps = self.check.arms().sweeps(from, to);
        let longest = self.sweeps.iter().fold(0.0_f64, |m, &s| m.max(s));
        let intervals = interval_count(longest)?;
        for i in spread_order(intervals) {
            let (lo, hi) = (i as f64 / intervals as f64, (i + 1) as f64 / intervals as f64);
            if !self.interval_clear(from, to, lo, hi)? && !self.interval_free(from, to, lo, hi, 0)? {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// Whether the spheres at the middle of the part `lo`..`hi` of the
    /// segment, grown by how far each shape moves from there, clear it.
    fn interval_clear(&mut self, from: &[f64], to: &[f64], lo: f64, hi: f64) -> Result<bool> {
        for (g, s) in self.growth.iter_mut().zip(&self.sweeps) {
            *g = s * (hi - lo) / 2.0;
        }
        let mut q = std::mem::take(&mut self.q);
        lerp_into(from, to, (lo + hi) / 2.0, &mut q);
        let clear = self.spheres_clear(&q);
        self.q = q;
        clear
    }

    /// Decides a part of the segment the spheres did not clear: its two
    /// halves by the spheres again (each grows half as much), down to
    /// [`MAX_SPLITS`] halvings, then the continuous check on the real shapes.
    fn interval_free(&mut self, from: &[f64], to: &[f64], lo: f64, hi: f64, splits: usize) -> Result<bool> {
        if splits < MAX_SPLITS {
            let mid = (lo + hi) / 2.0;
            for (a, b) in [(lo, mid), (mid, hi)] {
                if !self.interval_clear(from, to, a, b)? && !self.interval_free(from, to, a, b, splits + 1)? {
                    return Ok(false);
                }
            }
            return Ok(true);
        }
        self.counts.exact_checks += 1;
        if self.shapes_clear(from, to, lo, hi)? {
            return Ok(true);
        }
        let (mut a, mut b) = (std::mem::take(&mut self.q), std::mem::take(&mut self.q_end));
        lerp_into(from, to, lo, &mut a);
        lerp_into(from, to, hi, &mut b);
        // The fixed shapes' poses in `placement` do not change with q.
        let contact = self.check.segment().first_contact(&a, &b, &mut self.placement);
        (self.q, self.q_end) = (a, b);
        Ok(contact?.is_none())
    }

    /// Whether the real shapes at the middle of `lo`..`hi`, apart by more
    /// than the margin plus how far each moves from there, clear it (the
    /// growth set by the last [`MotionCheck::interval_clear`] of this part).
    fn shapes_clear(&mut self, from: &[f64], to: &[f64], lo: f64, hi: f64) -> Result<bool> {
        let mut q = std::mem::take(&mut self.q);
        lerp_into(from, to, (lo + hi) / 2.0, &mut q);
        let placed = self.check.place(&q, &mut self.placement);
        self.q = q;
        placed?;
        let (geometry, margin) = (self.check.geometry(), self.check.margin());
        for (a, b) in self.check.pairs().iter() {
            let (ga, gb) = (self.growth[a], self.growth[b]);
            if ga == 0.0 && gb == 0.0 && geometry.shapes()[a].link() == 0 && geometry.shapes()[b].link() == 0 {
                continue; // two fixed shapes: decided at the start
            }
            let reach = ga + gb + margin;
            if aabb_gap(self.placement.aabb(a), self.placement.aabb(b)) > reach {
                continue;
            }
            if pair_gap(geometry, &self.placement, a, b)? <= reach {
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
                PairTest::Round { a, b, shapes } => {
                    let frames = self.spheres_at.frames();
                    let (ra, rb) = (&self.round[a], &self.round[b]);
                    let ([p1, q1], [p2, q2]) = (ra.placed(&frames[ra.link]), rb.placed(&frames[rb.link]));
                    let reach = ra.radius + rb.radius + self.growth[shapes.0] + self.growth[shapes.1] + margin;
                    segment_distance(&p1, &q1, &p2, &q2) <= reach
                }
                PairTest::Fixed { moving, fixed } => {
                    let extra = self.growth[moving] + margin;
                    let shape = &self.fixed[fixed];
                    self.spheres
                        .range_of(moving)
                        .any(|i| shape.within(&centres[i], radii[i] + extra, &self.placement, self.check))
                }
            };
            if near {
                return Ok(false);
            }
        }
        Ok(true)
    }
}

impl FixedShape {
    fn shape(&self) -> usize {
        match self {
            FixedShape::Cuboid { shape, .. } | FixedShape::General { shape, .. } => *shape,
        }
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
    use parry3d_f64::query::PointQuery;
    use parry3d_f64::shape::Cuboid;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::geometry::isometry;

    #[test]
    fn the_box_distance_is_parrys() {
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        for _ in 0..20_000 {
            let half = Vector3::from_fn(|_, _| rng.random_range(0.01..0.5));
            let world_from_box = Pose::translation(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), 0.3)
                * Pose::rot_z(rng.random_range(-3.0..3.0))
                * Pose::rot_x(rng.random_range(-3.0..3.0));
            let p = Point3::new(rng.random_range(-1.5..1.5), rng.random_range(-1.5..1.5), rng.random_range(-1.0..1.5));
            let reference = Cuboid::new(half).distance_to_point(&isometry(&world_from_box), &p, true);
            let mine = box_distance(&world_from_box.inverse(), &half, &p);
            // parry gives 0 inside a solid box; the hand-written one the (negative) depth.
            assert!((mine.max(0.0) - reference).abs() < 1e-12, "{mine} vs {reference}");
        }
    }

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
