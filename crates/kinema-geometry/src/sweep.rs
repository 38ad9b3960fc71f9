//! Collision along a motion, not only at its samples: between two
//! configurations the joints move on the straight joint-space segment, and
//! conservative advancement (Schwarzer, Saha & Latombe 2005, "Exact
//! collision checking of robot paths") steps along it no farther than the
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
use crate::placement::{place, Placement};
use crate::query::{aabb_gap, pair_gap};

/// A pair within this distance \[m\] of the margin counts as in contact:
/// the advancement's steps shrink with the distance, so it must stop short.
pub const CONTACT_TOLERANCE: f64 = 1e-6;

/// Steps of the advancement on one segment before it gives up (a pair
/// hovering just above the tolerance for the whole segment).
const MAX_STEPS: usize = 1_000_000;

/// How far each shape of a geometry can move per unit of each joint's motion.
#[derive(Debug, Clone)]
pub(crate) struct LeverArms {
    /// `arms[s][i]`: joint i's lever on shape s \[m/rad, or 1 for a slide\];
    /// 0 where joint i does not move it.
    arms: Vec<Vec<f64>>,
}

impl LeverArms {
    /// The lever arms of every shape of `geometry` on `robot`.
    pub(crate) fn new(robot: &Robot, geometry: &RobotGeometry) -> Result<LeverArms> {
        let (n, joints) = (robot.dof(), robot.joints());
        if geometry.is_empty() {
            // Nothing moves: no slide needs a bound.
            return Ok(LeverArms { arms: Vec::new() });
        }
        let mut frames = vec![Pose::IDENTITY; n + 2];
        kin::link_frames_into(robot, robot.home(), &mut frames)?;
        let axis_point = |i: usize| kin::joint_axis(&joints[i], i, &frames).1;
        // How far a slide can carry its own axis point relative to the bodies around it.
        let travel = |i: usize| -> Result<f64> {
            if joints[i].kind == JointType::Revolute {
                return Ok(0.0);
            }
            let l = joints[i].limits;
            let span = l.max - l.min;
            if !span.is_finite() {
                return Err(Error::Shape {
                    name: joints[i].name.clone(),
                    message: "a slide without finite limits has no bound on how far it carries the links".into(),
                });
            }
            Ok(span)
        };
        // chain[i]: the distance from joint i's axis point to joint i+1's, on the body between them.
        let mut chain = Vec::with_capacity(n.saturating_sub(1));
        for i in 0..n.saturating_sub(1) {
            chain.push((axis_point(i + 1) - axis_point(i)).norm() + travel(i)? + travel(i + 1)?);
        }
        let placement = Placement::of(robot, geometry, robot.home())?;
        let mut arms = Vec::with_capacity(geometry.len());
        for (s, shape) in geometry.shapes().iter().enumerate() {
            let mut arm = vec![0.0; n];
            let link = shape.link();
            if link > 0 {
                let sphere = shape.collider().compute_local_bounding_sphere();
                let centre: Point3<f64> = placement.world_from_collider(s) * sphere.center;
                let last = link - 1;
                let mut reach = (centre.coords - axis_point(last)).norm() + sphere.radius + travel(last)?;
                for i in (0..link).rev() {
                    arm[i] = if joints[i].kind == JointType::Prismatic { 1.0 } else { reach };
                    if i > 0 {
                        reach += chain[i - 1];
                    }
                }
            }
            arms.push(arm);
        }
        Ok(LeverArms { arms })
    }

    /// The farthest any point of shape `s` moves on a straight joint step `dq`.
    pub(crate) fn sweep(&self, s: usize, dq: &[f64]) -> f64 {
        self.arms[s].iter().zip(dq).map(|(l, d)| l * d.abs()).sum()
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
        let sweeps: Vec<f64> = (0..self.geometry.len()).map(|s| self.arms.sweep(s, &dq)).collect();
        let mut q = from.to_vec();
        let mut near: Vec<(usize, usize)> = self.pairs.iter().collect();
        let mut fraction = 0.0;
        for _ in 0..MAX_STEPS {
            for (x, (a, d)) in q.iter_mut().zip(from.iter().zip(&dq)) {
                *x = a + fraction * d;
            }
            place(self.robot, self.geometry, &q, placement)?;
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
