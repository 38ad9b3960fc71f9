//! Collision along a motion, not only at its samples: between two
//! configurations the joints move on the straight joint-space segment, and
//! conservative advancement (Schwarzer, Saha & Latombe 2005, "Adaptive
//! dynamic collision checking for single and multiple articulated robots in
//! complex environments", IEEE T-RO 21(3)) steps along it no farther than the
//! current distance allows, so a thin obstacle between two samples is never
//! stepped over.
//!
//! The bound: a revolute joint i turning by Δqᵢ moves a point p by at most
//! |Δqᵢ|·|p − Pᵢ| (Pᵢ a point on its axis), a prismatic one by |Δqᵢ|. For a
//! shape on link l, |p − Pᵢ| is bounded along the whole motion by the chain
//! of axis points Pᵢ → Pᵢ₊₁ → … → P_{l−1} (consecutive axis points sit on
//! one body, so their distances never change) plus the shape's reach from
//! P_{l−1}. Its lever arm Lᵢ is that sum, and no point of the shape moves
//! farther than Σ |Δqᵢ|·Lᵢ over the segment.

use nalgebra::Point3;

use kinema::{kin, JointType, Pose, Robot};

use crate::error::{Error, Result};
use crate::geometry::RobotGeometry;
use crate::pairs::CollisionPairs;
use crate::placement::{place, place_moving, Placement};
use crate::query::{aabb_gap, pair_gap};

/// A pair within this distance \[m\] of the margin counts as in contact:
/// the advancement's steps shrink with the distance, so it must stop short.
pub const CONTACT_TOLERANCE: f64 = 1e-6;

/// Steps of the advancement on one segment before it gives up (a pair
/// hovering just above the tolerance for the whole segment).
const MAX_STEPS: usize = 1_000_000;

/// How far each shape of a geometry can move per unit of each joint's motion,
/// from the robot's home configuration and a segment's slide travel.
#[derive(Debug, Clone)]
pub(crate) struct LeverArms {
    /// Per shape: its link (0 never moves) and the reach of its bounding
    /// sphere from the last joint's axis point, at home \[m\].
    shapes: Vec<(usize, f64)>,
    /// `chain[i]`: the distance from joint i's axis point to joint i+1's at home \[m\].
    chain: Vec<f64>,
    /// Which joints slide.
    slides: Vec<bool>,
    /// The configuration the distances above were measured in.
    home: Vec<f64>,
}

impl LeverArms {
    /// The lever arms of every shape of `geometry` on `robot`.
    pub(crate) fn new(robot: &Robot, geometry: &RobotGeometry) -> Result<LeverArms> {
        let (n, joints) = (robot.dof(), robot.joints());
        let mut frames = vec![Pose::IDENTITY; n + 2];
        kin::link_frames_into(robot, robot.home(), &mut frames)?;
        let axis_point = |i: usize| kin::joint_axis(&joints[i], i, &frames).1;
        let chain = (0..n.saturating_sub(1)).map(|i| (axis_point(i + 1) - axis_point(i)).norm()).collect();
        let placement = Placement::of(robot, geometry, robot.home())?;
        let shapes = geometry
            .shapes()
            .iter()
            .enumerate()
            .map(|(s, shape)| {
                let link = shape.link();
                if link == 0 {
                    return (0, 0.0);
                }
                let sphere = shape.collider().compute_local_bounding_sphere();
                let centre: Point3<f64> = placement.world_from_collider(s) * sphere.center;
                (link, (centre.coords - axis_point(link - 1)).norm() + sphere.radius)
            })
            .collect();
        let slides = joints.iter().map(|j| j.kind == JointType::Prismatic).collect();
        Ok(LeverArms { shapes, chain, slides, home: robot.home().to_vec() })
    }

    /// The farthest any point of each shape moves on the straight joint step
    /// `from` → `to` \[m, per shape\].
    ///
    /// A revolute joint i moves a point by at most |Δqᵢ| times its distance
    /// from the axis: the shape's reach from the last axis point plus the
    /// chain of axis points back to i. A slide moves every point by |Δqᵢ| and
    /// lengthens the chain around it by at most how far it is from home on
    /// the step, max(|fromᵢ − homeᵢ|, |toᵢ − homeᵢ|) (the joints stay between
    /// their ends on a straight step, in or out of their limits).
    pub(crate) fn sweeps(&self, from: &[f64], to: &[f64]) -> Vec<f64> {
        let travel = |i: usize| {
            if self.slides[i] {
                (from[i] - self.home[i]).abs().max((to[i] - self.home[i]).abs())
            } else {
                0.0
            }
        };
        self.shapes
            .iter()
            .map(|&(link, reach_at_home)| {
                if link == 0 {
                    return 0.0;
                }
                let mut reach = reach_at_home + travel(link - 1);
                let mut sweep = 0.0;
                for i in (0..link).rev() {
                    let lever = if self.slides[i] { 1.0 } else { reach };
                    sweep += lever * (to[i] - from[i]).abs();
                    if i > 0 {
                        reach += self.chain[i - 1] + travel(i - 1) + travel(i);
                    }
                }
                sweep
            })
            .collect()
    }
}

/// The first contact on a straight joint-space segment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SweptContact {
    /// Where on the segment, as a fraction in \[0, 1\] of it.
    pub fraction: f64,
    /// The pair, by shape index.
    pub pair: (usize, usize),
    /// The pair's distance there \[m\] (at most margin + [`CONTACT_TOLERANCE`]).
    pub distance: f64,
}

/// What one segment's check needs besides its ends.
pub(crate) struct Segment<'a> {
    pub robot: &'a Robot,
    pub geometry: &'a RobotGeometry,
    pub pairs: &'a CollisionPairs,
    pub arms: &'a LeverArms,
    pub margin: f64,
}

impl Segment<'_> {
    /// The first configuration on the segment `from` → `to` at which a pair
    /// comes within the margin (+ [`CONTACT_TOLERANCE`]); `None` when every
    /// pair stays farther along all of it.
    pub(crate) fn first_contact(
        &self,
        from: &[f64],
        to: &[f64],
        placement: &mut Placement,
    ) -> Result<Option<SweptContact>> {
        let dq: Vec<f64> = to.iter().zip(from).map(|(b, a)| b - a).collect();
        let sweeps = self.arms.sweeps(from, to);
        let mut q = from.to_vec();
        let mut near: Vec<(usize, usize)> = self.pairs.iter().collect();
        let mut fraction = 0.0;
        for _ in 0..MAX_STEPS {
            for (x, (a, d)) in q.iter_mut().zip(from.iter().zip(&dq)) {
                *x = a + fraction * d;
            }
            // Link 0's shapes do not move: placed at the first step only.
            if fraction == 0.0 {
                place(self.robot, self.geometry, &q, placement)?;
            } else {
                place_moving(self.robot, self.geometry, &q, placement)?;
            }
            let rest = 1.0 - fraction;
            let mut step = f64::INFINITY;
            let mut keep = Vec::with_capacity(near.len());
            for (a, b) in near {
                let sweep = sweeps[a] + sweeps[b];
                // A pair whose boxes stay apart for the rest of the segment is done with.
                if aabb_gap(placement.aabb(a), placement.aabb(b)) - self.margin > sweep * rest {
                    continue;
                }
                let distance = pair_gap(self.geometry, placement, a, b)?;
                let free = distance - self.margin;
                if free <= CONTACT_TOLERANCE {
                    return Ok(Some(SweptContact { fraction, pair: (a, b), distance }));
                }
                if free > sweep * rest {
                    continue;
                }
                step = step.min(free / sweep);
                keep.push((a, b));
            }
            near = keep;
            if near.is_empty() || fraction + step >= 1.0 {
                return Ok(None);
            }
            fraction += step;
        }
        Err(Error::Shape {
            name: self.robot.name().to_string(),
            message: format!(
                "the continuous check took over {MAX_STEPS} steps on one segment (a pair stays within a hair of \
                 the margin): sample the motion more finely"
            ),
        })
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::check::{CheckOptions, CollisionCheck};

    /// Seven points fixed to shape `s`'s link inside its bounding sphere: the
    /// centre and the sphere's six poles.
    fn marks(check: &CollisionCheck, placement: &Placement, s: usize) -> Vec<Point3<f64>> {
        let sphere = check.geometry().shapes()[s].collider().compute_local_bounding_sphere();
        let mut local = vec![sphere.center];
        for k in 0..3 {
            for sign in [-1.0, 1.0] {
                local.push(sphere.center + Vector3::ith(k, sign * sphere.radius));
            }
        }
        local.iter().map(|p| placement.world_from_collider(s) * p).collect()
    }

    /// A polar arm: a turn about z, a radial slide (so the slide lengthens the
    /// turn's lever arm, unlike a SCARA's vertical one) and a wrist.
    const POLAR: &str = r#"name = "polar"
source = "a test arm"
convention = "standard"
[units]
length = "m"
angle = "deg"
[[joint]]
name = "turn"
d = 0.3
a = 0
alpha = 90
min = -170
max = 170
[[joint]]
name = "reach"
type = "prismatic"
theta = 90
a = 0
alpha = -90
min = 0.2
max = 0.8
[[joint]]
name = "wrist"
d = 0.1
a = 0.05
alpha = 0
min = -180
max = 180
[poses]
home = [0, 0.5, 0]
[[shape]]
name = "ram"
link = 2
capsule = { radius = 0.04, length = 0.3 }
pose = [0, 0, -0.15, 0, 0, 0]
[[shape]]
name = "hand"
link = 3
box = [0.1, 0.05, 0.05]
pose = [0, 0, 0, 0, 0, 0]
"#;

    /// On every built-in robot (standard and modified DH, revolute and
    /// prismatic) and a polar arm, for seeded straight steps that leave the
    /// limits by half their span, no mark of any shape moves farther from the
    /// step's start than the bound of the step so far.
    #[test]
    fn no_point_of_a_shape_outruns_its_bound() {
        let mut rng = ChaCha8Rng::seed_from_u64(36);
        let dir = tempfile::tempdir().unwrap();
        let polar = dir.path().join("polar.toml");
        std::fs::write(&polar, POLAR).unwrap();
        let mut names: Vec<String> = kinema::builtin_names().map(String::from).collect();
        names.push(polar.to_str().unwrap().to_string());
        for name in &names {
            let check = CollisionCheck::load(name, &CheckOptions::default()).unwrap();
            let robot = check.robot();
            let arms = LeverArms::new(robot, check.geometry()).unwrap();
            let (mut start, mut there) = (check.placement(), check.placement());
            for _ in 0..200 {
                let wide = |rng: &mut ChaCha8Rng| -> Vec<f64> {
                    let joints = robot.joints().iter();
                    joints.map(|j| j.limits.min + (j.limits.max - j.limits.min) * rng.random_range(-0.5..1.5)).collect()
                };
                let (from, to) = (wide(&mut rng), wide(&mut rng));
                place(robot, check.geometry(), &from, &mut start).unwrap();
                for k in 1..=20 {
                    let q: Vec<f64> = from.iter().zip(&to).map(|(a, b)| a + (b - a) * k as f64 / 20.0).collect();
                    place(robot, check.geometry(), &q, &mut there).unwrap();
                    let bounds = arms.sweeps(&from, &q);
                    for (s, bound) in bounds.iter().enumerate() {
                        let moved = marks(&check, &start, s)
                            .iter()
                            .zip(marks(&check, &there, s))
                            .map(|(a, b)| (b - a).norm())
                            .fold(0.0, f64::max);
                        assert!(moved <= bound * (1.0 + 1e-12) + 1e-12, "{name} shape {s}: moved {moved} > {bound}");
                    }
                }
            }
        }
    }
}
