//! How close the bodies of several robots on one clock come to each other
//! and to a scene's obstacles (`kinema cell`, seed 004 §VIII-E), not only
//! at the samples: between two samples every robot's joints move in a
//! straight line, and the closest approach is bounded there by branch and
//! bound — the smallest distance of two bodies cannot fall faster than the
//! sum of how far any point of each can move (the lever-arm bound of
//! `sweep.rs`), so a step whose lower bound is above the best distance found
//! needs no look, and the others are halved until it is.

use kinema::Robot;

use crate::error::{Error, Result};
use crate::geometry::RobotGeometry;
use crate::pairs::CollisionPairs;
use crate::placement::{place, Placement};
use crate::query::{aabb_gap, placed_gap};
use crate::scene::Scene;
use crate::sweep::LeverArms;

/// How far below the reported distance \[m\] the true closest approach
/// between samples may lie.
pub const APPROACH_TOLERANCE: f64 = 1e-4;

/// Halvings of one step at most (2⁻³⁰ of a sample period).
const MAX_DEPTH: u32 = 30;

/// One robot of a cell with its shapes, the scene's obstacles joined to it.
#[derive(Debug, Clone)]
pub struct Body {
    name: String,
    robot: Robot,
    geometry: RobotGeometry,
    /// Shapes `0..own` are the robot's; the rest are the scene's obstacles.
    own: usize,
    arms: LeverArms,
}

impl Body {
    /// Robot `name` (as placed in the cell's world) with its `geometry`, and
    /// `scene`'s obstacles when given.
    pub fn new(name: impl Into<String>, robot: Robot, geometry: RobotGeometry, scene: Option<&Scene>) -> Result<Body> {
        let own = geometry.len();
        let geometry = match scene {
            Some(scene) => scene.with_robot(&robot, &geometry, &CollisionPairs::none(&geometry))?.0,
            None => geometry,
        };
        let arms = LeverArms::new(&robot, &geometry)?;
        Ok(Body { name: name.into(), robot, geometry, own, arms })
    }

    /// The robot's own shapes on moving links.
    fn moving(&self) -> Vec<usize> {
        (0..self.own).filter(|&s| self.geometry.shapes()[s].link() > 0).collect()
    }

    /// Whether the body has obstacles of a scene joined to it.
    fn has_obstacles(&self) -> bool {
        self.geometry.len() > self.own
    }

    /// "robot/link" for one of its own shapes, the obstacle's name for one of the scene's.
    fn label(&self, shape: usize) -> String {
        let link = self.geometry.shapes()[shape].link_name();
        if shape < self.own {
            format!("{}/{link}", self.name)
        } else {
            link.to_string()
        }
    }

    /// The farthest any point of the robot's own shapes moves on the joint step `from` → `to`.
    fn sweep(&self, from: &[f64], to: &[f64]) -> f64 {
        self.arms.sweeps(from, to)[..self.own].iter().copied().fold(0.0, f64::max)
    }
}

/// The closest approach of two bodies (or of one body and the scene).
#[derive(Debug, Clone, PartialEq)]
pub struct BodyApproach {
    /// The two robots, by index in the list given; `b` is `None` for the scene.
    pub robots: (usize, Option<usize>),
    /// When \[s\].
    pub time: f64,
    /// How close \[m\] (0 when the shapes touch or overlap); the true minimum
    /// between samples is at most [`APPROACH_TOLERANCE`] below it.
    pub distance: f64,
    /// The closest shapes: `robot/link`, or the obstacle's name.
    pub closest: (String, String),
}

/// Every body's joint values at one instant.
type Instant<'a> = Vec<&'a [f64]>;

/// The closest approach of every two bodies, and of every body to the
/// scene's obstacles, over the samples `q[body][k]` at `times[k]` (linear in
/// the joints between samples).
pub fn closest_approaches(bodies: &[Body], times: &[f64], q: &[Vec<Vec<f64>>]) -> Result<Vec<BodyApproach>> {
    let wrong = |what: &str, got: usize, expected: usize, of: &str| {
        let (what, of) = (what.to_string(), of.to_string());
        Err(Error::Kinema(kinema::Error::Input(kinema::InputError::WrongLength { what, got, expected, of })))
    };
    if q.len() != bodies.len() {
        return wrong("q", q.len(), bodies.len(), "one sample list per body");
    }
    if let Some((b, qs)) = q.iter().enumerate().find(|(_, qs)| qs.len() != times.len()) {
        return wrong(&format!("q[{b}]"), qs.len(), times.len(), "one sample per time");
    }
    let mut placements: Vec<Placement> = bodies.iter().map(|b| Placement::new(&b.geometry)).collect();
    let mut out = Vec::new();
    let mut pairs: Vec<(usize, Option<usize>)> = Vec::new();
    for i in 0..bodies.len() {
        for j in i + 1..bodies.len() {
            pairs.push((i, Some(j)));
        }
    }
    pairs.extend((0..bodies.len()).filter(|&i| bodies[i].has_obstacles()).map(|i| (i, None)));
    for (i, j) in pairs {
        let search = Search { bodies, pair: (i, j), times, q };
        if let Some(found) = search.run(&mut placements)? {
            out.push(found);
        }
    }
    Ok(out)
}

/// The branch-and-bound search of one pair.
struct Search<'a> {
    bodies: &'a [Body],
    pair: (usize, Option<usize>),
    times: &'a [f64],
    q: &'a [Vec<Vec<f64>>],
}

/// The closest shapes of a pair at one instant: (distance, shape of a, shape of b).
type Closest = (f64, usize, usize);

impl Search<'_> {
    fn run(&self, placements: &mut [Placement]) -> Result<Option<BodyApproach>> {
        let n = self.times.len();
        let mut best: Option<(f64, Closest)> = None;
        let mut at = Vec::with_capacity(n);
        for k in 0..n {
            let c = self.closest_at(&self.sample(k), placements)?;
            if let Some(c) = c {
                if best.is_none_or(|(_, b)| c.0 < b.0) {
                    best = Some((self.times[k], c));
                }
            }
            at.push(c.map_or(f64::INFINITY, |c| c.0));
        }
        let Some(mut best) = best else { return Ok(None) };
        for k in 1..n {
            self.refine(k, (0.0, at[k - 1]), (1.0, at[k]), 0, &mut best, placements)?;
        }
        let (time, (distance, a, b)) = best;
        let (i, j) = self.pair;
        let other = j.map_or(&self.bodies[i], |j| &self.bodies[j]);
        Ok(Some(BodyApproach { robots: self.pair, time, distance, closest: (self.bodies[i].label(a), other.label(b)) }))
    }

    /// Halves the part (s0, s1) of step k−1 → k while its lower bound is below the best.
    fn refine(
        &self,
        k: usize,
        (s0, d0): (f64, f64),
        (s1, d1): (f64, f64),
        depth: u32,
        best: &mut (f64, Closest),
        placements: &mut [Placement],
    ) -> Result<()> {
        let reach = self.sweep(k) * (s1 - s0);
        let bound = if (d1 - d0).abs() <= reach { (d0 + d1 - reach) / 2.0 } else { d0.min(d1) };
        // A step that may hold a contact not yet found is always looked into.
        let may_touch = bound <= 0.0 && best.1 .0 > 0.0;
        if (bound >= best.1 .0 - APPROACH_TOLERANCE && !may_touch) || depth >= MAX_DEPTH {
            return Ok(());
        }
        let s = (s0 + s1) / 2.0;
        let instant = self.between(k, s);
        let qs: Instant = instant.iter().map(Vec::as_slice).collect();
        let d = match self.closest_at(&qs, placements)? {
            Some(c) => {
                if c.0 < best.1 .0 {
                    let (t0, t1) = (self.times[k - 1], self.times[k]);
                    *best = (t0 + s * (t1 - t0), c);
                }
                c.0
            }
            None => f64::INFINITY,
        };
        self.refine(k, (s0, d0), (s, d), depth + 1, best, placements)?;
        self.refine(k, (s, d), (s1, d1), depth + 1, best, placements)
    }

    /// The bodies' joint values at sample k.
    fn sample(&self, k: usize) -> Instant<'_> {
        self.q.iter().map(|qs| qs[k].as_slice()).collect()
    }

    /// The bodies' joint values at fraction `s` of step k−1 → k.
    fn between(&self, k: usize, s: f64) -> Vec<Vec<f64>> {
        self.q.iter().map(|qs| qs[k - 1].iter().zip(&qs[k]).map(|(a, b)| a + s * (b - a)).collect()).collect()
    }

    /// How fast the pair's distance can change over step k−1 → k \[m per whole step\].
    fn sweep(&self, k: usize) -> f64 {
        let moved = |b: usize| self.bodies[b].sweep(&self.q[b][k - 1], &self.q[b][k]);
        let (i, j) = self.pair;
        moved(i) + j.map_or(0.0, moved)
    }

    /// The closest shapes of the pair with every body at `qs` (`None` when a
    /// body has no shape to measure).
    fn closest_at(&self, qs: &[&[f64]], placements: &mut [Placement]) -> Result<Option<Closest>> {
        let (i, j) = self.pair;
        let a = &self.bodies[i];
        place(&a.robot, &a.geometry, qs[i], &mut placements[i])?;
        // Against the scene only the moving links count: a base stands on something.
        let (b, a_shapes, b_shapes) = match j {
            Some(j) => {
                let b = &self.bodies[j];
                place(&b.robot, &b.geometry, qs[j], &mut placements[j])?;
                (j, (0..a.own).collect::<Vec<_>>(), 0..b.own)
            }
            None => (i, a.moving(), a.own..a.geometry.len()),
        };
        let (pa, pb) = (&placements[i], &placements[b]);
        let body_b = &self.bodies[b];
        let mut best: Option<Closest> = None;
        for sa in a_shapes {
            for sb in b_shapes.clone() {
                let limit = best.map_or(f64::INFINITY, |c| c.0);
                if aabb_gap(pa.aabb(sa), pb.aabb(sb)) >= limit {
                    continue;
                }
                let (shape_a, shape_b) = (&a.geometry.shapes()[sa], &body_b.geometry.shapes()[sb]);
                let d = placed_gap(pa.world_from_collider(sa), shape_a, pb.world_from_collider(sb), shape_b).map_err(
                    |_| Error::UnsupportedPair {
                        a: a.label(sa),
                        b: body_b.label(sb),
                        kinds: format!("{} – {}", shape_a.shape().kind(), shape_b.shape().kind()),
                    },
                )?;
                if d < limit {
                    best = Some((d, sa, sb));
                }
            }
        }
        Ok(best)
    }
}
