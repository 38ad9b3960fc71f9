//! The distance between a segment and a box in closed form: a capsule's
//! core against the common obstacle, asked by the planner's fast test and
//! by every exact query on such a pair (parry's GJK costs several times more,
//! and is the test's reference).

use nalgebra::Vector3;

/// The squared distance between the segment `a`–`b` and the box of half
/// extents `half`, both in the box's frame (0 when they meet).
///
/// Along the segment each coordinate's excess over the box is 0 or linear
/// in the parameter, changing form where the coordinate crosses a face
/// plane; between those (at most six) crossings the squared distance is a
/// quadratic, minimised in closed form. The whole is convex, so the least
/// piece minimum is the distance.
pub(crate) fn segment_box_distance_squared(a: &Vector3<f64>, b: &Vector3<f64>, half: &Vector3<f64>) -> f64 {
    let d = b - a;
    let mut cuts = [0.0; 8];
    let mut n = 0;
    cuts[n] = 0.0;
    n += 1;
    for i in 0..3 {
        if d[i] != 0.0 {
            for face in [-half[i], half[i]] {
                let t = (face - a[i]) / d[i];
                if t > 0.0 && t < 1.0 {
                    cuts[n] = t;
                    n += 1;
                }
            }
        }
    }
    cuts[n] = 1.0;
    n += 1;
    let cuts = &mut cuts[..n];
    cuts.sort_unstable_by(f64::total_cmp);
    let mut best = f64::INFINITY;
    for w in cuts.windows(2) {
        let (t0, t1) = (w[0], w[1]);
        let mid = 0.5 * (t0 + t1);
        // Squared distance on this piece: Σ (c + s·t)² over the axes outside the box.
        let (mut qa, mut qb, mut qc) = (0.0, 0.0, 0.0);
        for i in 0..3 {
            let x = a[i] + mid * d[i];
            let (c, s) = if x > half[i] {
                (a[i] - half[i], d[i])
            } else if x < -half[i] {
                (-half[i] - a[i], -d[i])
            } else {
                continue;
            };
            qa += s * s;
            qb += 2.0 * c * s;
            qc += c * c;
        }
        let t = if qa > 0.0 { (-qb / (2.0 * qa)).clamp(t0, t1) } else { t0 };
        best = best.min((qa * t * t + qb * t + qc).max(0.0));
    }
    best
}

#[cfg(test)]
mod tests {
    use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion};
    use parry3d_f64::shape::{Capsule, Cuboid};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;

    #[test]
    fn the_segment_box_distance_is_parrys() {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let point = |rng: &mut ChaCha8Rng| Vector3::from_fn(|_, _| rng.random_range(-1.5..1.5));
        for case in 0..20_000 {
            let half = Vector3::from_fn(|_, _| rng.random_range(0.01..0.5));
            let a = point(&mut rng);
            // Points, axis-parallel segments (zero components), short and long ones.
            let b = match case % 4 {
                0 => a,
                1 => a + Vector3::new(rng.random_range(-1.0..1.0), 0.0, 0.0),
                2 => a + Vector3::from_fn(|_, _| rng.random_range(-0.05..0.05)),
                _ => point(&mut rng),
            };
            let reference = parry3d_f64::query::distance(
                &Isometry3::identity(),
                &Cuboid::new(half),
                &Isometry3::from_parts(Translation3::identity(), UnitQuaternion::identity()),
                &Capsule::new(Point3::from(a), Point3::from(b), 0.0),
            )
            .unwrap();
            let mine = segment_box_distance_squared(&a, &b, &half).sqrt();
            assert!((mine - reference).abs() < 1e-9, "case {case}: {mine} vs {reference}");
        }
    }
}
