//! Distance from points to a path: the tracking error of seed 000 §IV
//! (Fig. 5–6), where measured tool positions are compared with the desired
//! path by their distance perpendicular to it.

use nalgebra::Vector3;

use crate::{Error, Result};

/// Where a point is relative to a polyline path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathDistance {
    /// Distance from the point to the nearest point of the path \[m\].
    pub distance: f64,
    /// Arc length along the path of that nearest point \[m\].
    pub arc_length: f64,
    /// The nearest point of the path \[m\].
    pub nearest: Vector3<f64>,
}

/// The distance of each of `points` to the polyline through `path` (its
/// segments are straight; consecutive duplicates are allowed). Errors: a path
/// of fewer than two points or of zero length, non-finite coordinates.
///
/// # Examples
/// ```
/// use kinema::nalgebra::Vector3;
/// let path = [Vector3::new(0.0, 0.0, 0.0), Vector3::new(1.0, 0.0, 0.0), Vector3::new(1.0, 1.0, 0.0)];
/// let d = kinema::traj::distances_to_path(&[Vector3::new(0.5, 0.2, 0.0), Vector3::new(1.3, 0.5, 0.0)], &path)?;
/// assert!((d[0].distance - 0.2).abs() < 1e-12 && (d[0].arc_length - 0.5).abs() < 1e-12);
/// assert!((d[1].distance - 0.3).abs() < 1e-12 && (d[1].arc_length - 1.5).abs() < 1e-12);
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn distances_to_path(points: &[Vector3<f64>], path: &[Vector3<f64>]) -> Result<Vec<PathDistance>> {
    let bad = |what: &str, message: String| Error::InvalidArgument { what: what.into(), message };
    if path.len() < 2 {
        return Err(bad("path", format!("it has {} point(s); at least two are needed", path.len())));
    }
    if let Some(i) = path.iter().position(|p| !p.iter().all(|v| v.is_finite())) {
        return Err(bad("path", format!("point {} is not finite: {:?}", i + 1, path[i].as_slice())));
    }
    if let Some(i) = points.iter().position(|p| !p.iter().all(|v| v.is_finite())) {
        return Err(bad("points", format!("point {} is not finite: {:?}", i + 1, points[i].as_slice())));
    }
    // Cumulative arc length at the start of each segment.
    let mut start = Vec::with_capacity(path.len());
    let mut s = 0.0;
    for w in path.windows(2) {
        start.push(s);
        s += (w[1] - w[0]).norm();
    }
    if s == 0.0 {
        return Err(bad("path", "all its points coincide (zero length)".into()));
    }
    Ok(points
        .iter()
        .map(|p| {
            let mut best = PathDistance { distance: f64::INFINITY, arc_length: 0.0, nearest: path[0] };
            for (i, w) in path.windows(2).enumerate() {
                let d = w[1] - w[0];
                let len2 = d.norm_squared();
                let u = if len2 > 0.0 { ((p - w[0]).dot(&d) / len2).clamp(0.0, 1.0) } else { 0.0 };
                let c = w[0] + d * u;
                let dist = (p - c).norm();
                if dist < best.distance {
                    best = PathDistance { distance: dist, arc_length: start[i] + u * len2.sqrt(), nearest: c };
                }
            }
            best
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn distance_equals_a_dense_sampling_of_the_path() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        for _ in 0..300 {
            let path: Vec<Vector3<f64>> = (0..rng.random_range(2..6))
                .map(|_| {
                    Vector3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0))
                })
                .collect();
            let p = Vector3::new(rng.random_range(-2.0..2.0), rng.random_range(-2.0..2.0), rng.random_range(-2.0..2.0));
            let d = distances_to_path(&[p], &path).unwrap()[0];
            // Independent: sample each segment at 20 001 points.
            let mut best = f64::INFINITY;
            for w in path.windows(2) {
                for k in 0..=20_000 {
                    let c = w[0] + (w[1] - w[0]) * (k as f64 / 20_000.0);
                    best = best.min((p - c).norm());
                }
            }
            assert!(d.distance <= best + 1e-12 && best - d.distance < 2e-4, "{} vs {best}", d.distance);
            assert!(((p - d.nearest).norm() - d.distance).abs() < 1e-12);
            let total: f64 = path.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
            assert!((0.0..=total + 1e-12).contains(&d.arc_length));
        }
    }

    #[test]
    fn bad_paths_are_errors() {
        let o = Vector3::zeros();
        assert!(distances_to_path(&[o], &[o]).unwrap_err().to_string().contains("at least two"));
        assert!(distances_to_path(&[o], &[o, o]).unwrap_err().to_string().contains("zero length"));
        let nan = Vector3::new(f64::NAN, 0.0, 0.0);
        assert!(distances_to_path(&[nan], &[o, Vector3::x()]).unwrap_err().to_string().contains("point 1"));
    }
}
