//! Fixed shapes (the scene's obstacles, link 0) as the fast test asks them:
//! a bounding box to cull far robot shapes, then an exact distance — to a
//! sphere's centre, or to a capsule's axis for a box. Boxes, the common
//! obstacle, are measured by hand: parry's general queries cost several
//! times more, and parry is the tests' reference for both.

use nalgebra::{Point3, Vector3};

use kinema::Pose;

use crate::check::CollisionCheck;
use crate::geometry::rotate;
use crate::placement::Placement;
use crate::segment_box::segment_box_distance_squared;
use crate::shape::Shape;

/// One fixed shape, placed once.
#[derive(Debug, Clone)]
pub(crate) enum FixedShape {
    /// A box: its world bounding box, the inverse of its pose, half its size.
    Cuboid { lo: Point3<f64>, hi: Point3<f64>, box_from_world: Pose, half: Vector3<f64> },
    /// Any other shape, measured by parry.
    General { shape: usize, lo: Point3<f64>, hi: Point3<f64> },
}

impl FixedShape {
    pub(crate) fn new(check: &CollisionCheck, placement: &Placement, shape: usize) -> FixedShape {
        let aabb = placement.aabb(shape);
        let (lo, hi) = (aabb.mins, aabb.maxs);
        match check.geometry().shapes()[shape].shape() {
            Shape::Box { size } => {
                let world_from_box = placement.world_from_shape(check.geometry(), shape);
                FixedShape::Cuboid { lo, hi, box_from_world: world_from_box.inverse(), half: size / 2.0 }
            }
            _ => FixedShape::General { shape, lo, hi },
        }
    }

    /// Whether the shape is a box (which [`FixedShape::segment_gap_squared`] measures).
    pub(crate) fn is_box(&self) -> bool {
        matches!(self, FixedShape::Cuboid { .. })
    }

    fn bounds(&self) -> (&Point3<f64>, &Point3<f64>) {
        match self {
            FixedShape::Cuboid { lo, hi, .. } | FixedShape::General { lo, hi, .. } => (lo, hi),
        }
    }

    /// Whether a sphere at `centre` of radius `reach` comes within the shape.
    pub(crate) fn within(
        &self,
        centre: &Point3<f64>,
        reach: f64,
        placement: &Placement,
        check: &CollisionCheck,
    ) -> bool {
        let (lo, hi) = self.bounds();
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

    /// For a box: the squared distance from the segment `p`–`q` to it, or
    /// `None` when its bounding box alone shows it farther than `reach`.
    /// Other shapes answer `Some(0)` (not measured here).
    pub(crate) fn segment_gap_squared(&self, p: &Point3<f64>, q: &Point3<f64>, reach: f64) -> Option<f64> {
        let FixedShape::Cuboid { lo, hi, box_from_world, half } = self else {
            return Some(0.0);
        };
        let (seg_lo, seg_hi) = (p.inf(q), p.sup(q));
        let apart = (lo - seg_hi).sup(&(seg_lo - hi)).sup(&Vector3::zeros());
        if apart.norm_squared() > reach * reach {
            return None;
        }
        let (a, b) = (to_box(box_from_world, p), to_box(box_from_world, q));
        Some(segment_box_distance_squared(&a, &b, half))
    }
}

/// `point` in a box's frame.
fn to_box(box_from_world: &Pose, point: &Point3<f64>) -> Vector3<f64> {
    rotate(&box_from_world.rot, &point.coords) + box_from_world.pos
}

/// The signed distance from `point` to a box of half extents `half` (negative inside).
pub(crate) fn box_distance(box_from_world: &Pose, half: &Vector3<f64>, point: &Point3<f64>) -> f64 {
    let excess = to_box(box_from_world, point).abs() - half;
    let outside = excess.sup(&Vector3::zeros()).norm();
    if outside > 0.0 {
        outside
    } else {
        excess.max()
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

    fn random_box(rng: &mut ChaCha8Rng) -> (Vector3<f64>, Pose) {
        let half = Vector3::from_fn(|_, _| rng.random_range(0.01..0.5));
        let world_from_box = Pose::translation(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), 0.3)
            * Pose::rot_z(rng.random_range(-3.0..3.0))
            * Pose::rot_x(rng.random_range(-3.0..3.0));
        (half, world_from_box)
    }

    fn random_point(rng: &mut ChaCha8Rng) -> Point3<f64> {
        Point3::new(rng.random_range(-1.5..1.5), rng.random_range(-1.5..1.5), rng.random_range(-1.0..1.5))
    }

    #[test]
    fn the_box_distance_is_parrys() {
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        for _ in 0..20_000 {
            let (half, world_from_box) = random_box(&mut rng);
            let p = random_point(&mut rng);
            let reference = Cuboid::new(half).distance_to_point(&isometry(&world_from_box), &p, true);
            let mine = box_distance(&world_from_box.inverse(), &half, &p);
            // parry gives 0 inside a solid box; the hand-written one the (negative) depth.
            assert!((mine.max(0.0) - reference).abs() < 1e-12, "{mine} vs {reference}");
        }
    }

    #[test]
    fn a_far_segment_is_culled_and_a_crossing_one_is_near() {
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        let (half, world_from_box) = random_box(&mut rng);
        let centre = Point3::from(world_from_box.pos);
        // A box around the box's circumscribed sphere: bounds the shape however it is turned.
        let corner = Vector3::repeat(half.norm());
        let shape = FixedShape::Cuboid {
            lo: centre - corner,
            hi: centre + corner,
            box_from_world: world_from_box.inverse(),
            half,
        };
        let through = [centre + Vector3::new(-3.0, 0.0, 0.0), centre + Vector3::new(3.0, 0.0, 0.0)];
        assert_eq!(shape.segment_gap_squared(&through[0], &through[1], 0.0), Some(0.0));
        let far = [centre + Vector3::new(3.0, 3.0, 0.0), centre + Vector3::new(3.0, 4.0, 0.0)];
        assert_eq!(shape.segment_gap_squared(&far[0], &far[1], 0.1), None);
        let beside = [centre + Vector3::new(-3.0, 1.0, 0.0), centre + Vector3::new(3.0, 1.0, 0.0)];
        let gap = shape.segment_gap_squared(&beside[0], &beside[1], 2.0).unwrap().sqrt();
        let reference =
            box_distance(&world_from_box.inverse(), &half, &Point3::new(centre.x, centre.y + 1.0, centre.z));
        assert!(gap <= reference + 1e-12 && gap > 0.0, "{gap} vs {reference}");
    }
}
