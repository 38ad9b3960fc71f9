//! Capsules and spheres measured exactly: a capsule is the set of points
//! within its radius of a segment (a sphere of a point), so two of them are
//! apart by the segments' distance less both radii. Links close to each
//! other across a joint (the elbow's two neighbours) keep their fitted
//! spheres overlapping in most configurations; their capsules decide at
//! once.

use nalgebra::{Point3, Vector3};
use parry3d_f64::query::details::closest_points_segment_segment_with_locations_nD;
use parry3d_f64::shape::SegmentPointLocation;

use kinema::Pose;

use crate::geometry::LinkShape;
use crate::shape::Shape;

/// A capsule (or sphere) on a link: its segment's ends in the link frame.
#[derive(Debug, Clone)]
pub(crate) struct RoundShape {
    pub link: usize,
    ends: [Vector3<f64>; 2],
    pub radius: f64,
    /// Half the segment's length.
    pub half: f64,
}

impl RoundShape {
    /// The round shape `s` is, if it is a capsule or a sphere.
    pub(crate) fn of(s: &LinkShape) -> Option<RoundShape> {
        let (half, radius) = match s.shape() {
            Shape::Capsule { radius, length } => (length / 2.0, *radius),
            Shape::Sphere { radius } => (0.0, *radius),
            _ => return None,
        };
        let at = s.link_from_shape();
        let end = |z: f64| at.rot * Vector3::new(0.0, 0.0, z) + at.pos;
        Some(RoundShape { link: s.link(), ends: [end(-half), end(half)], radius, half })
    }

    /// The segment's ends in the world, with the link at `frame`.
    pub(crate) fn placed(&self, frame: &Pose) -> [Point3<f64>; 2] {
        self.ends.map(|e| Point3::from(crate::geometry::rotate(&frame.rot, &e) + frame.pos))
    }
}

/// The distance between segments p1–q1 and p2–q2 (parry's closest points
/// of two segments, the routine the exact queries use for round shapes).
pub(crate) fn segment_distance(p1: &Point3<f64>, q1: &Point3<f64>, p2: &Point3<f64>, q2: &Point3<f64>) -> f64 {
    let (la, lb) = closest_points_segment_segment_with_locations_nD((p1, q1), (p2, q2));
    (at(p1, q1, la) - at(p2, q2, lb)).norm()
}

fn at(p: &Point3<f64>, q: &Point3<f64>, location: SegmentPointLocation) -> Point3<f64> {
    match location {
        SegmentPointLocation::OnVertex(0) => *p,
        SegmentPointLocation::OnVertex(_) => *q,
        SegmentPointLocation::OnEdge([u, v]) => Point3::from(p.coords * u + q.coords * v),
    }
}

#[cfg(test)]
mod tests {
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;

    #[test]
    fn segment_distances_are_the_minimum_over_both_segments() {
        let mut rng = ChaCha8Rng::seed_from_u64(8);
        let point = |rng: &mut ChaCha8Rng| {
            Point3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0))
        };
        let mut cases = 0;
        while cases < 5_000 {
            let (p1, mut q1, p2, q2) = (point(&mut rng), point(&mut rng), point(&mut rng), point(&mut rng));
            // Parallel and degenerate segments too.
            match cases % 5 {
                0 => q1 = p1 + (q2 - p2) * 0.7,
                1 => q1 = p1,
                _ => {}
            }
            let exact = segment_distance(&p1, &q1, &p2, &q2);
            let brute = convex_minimum(&|s, t| ((p1 + (q1 - p1) * s) - (p2 + (q2 - p2) * t)).norm());
            assert!((exact - brute).abs() < 1e-9, "case {cases}: {exact} vs {brute}");
            cases += 1;
        }
    }

    /// The minimum over the unit square of a convex function, by nested golden-section searches.
    fn convex_minimum(f: &dyn Fn(f64, f64) -> f64) -> f64 {
        let golden = |g: &dyn Fn(f64) -> f64| {
            let (mut lo, mut hi) = (0.0, 1.0);
            let k = (5f64.sqrt() - 1.0) / 2.0;
            for _ in 0..80 {
                let (a, b) = (hi - k * (hi - lo), lo + k * (hi - lo));
                if g(a) < g(b) {
                    hi = b;
                } else {
                    lo = a;
                }
            }
            g((lo + hi) / 2.0)
        };
        golden(&|s| golden(&|t| f(s, t)))
    }
}
