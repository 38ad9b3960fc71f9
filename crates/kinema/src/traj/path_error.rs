//! Distance from points to a path: the tracking error of seed 000 §IV
//! (Fig. 5–6), where measured tool positions are compared with the desired
//! path by their distance perpendicular to it.
//!
//! - [`distances_to_path`]: each point's distance to a polyline, with the arc
//!   length of its nearest path point.
//! - [`tracking_error`]: seed 000's figure over several runs — per run the
//!   mean distance of its points to the desired path, then the mean and the
//!   sample standard deviation of those means over the runs ("0,17 ± 0,02 cm").

use nalgebra::Vector3;

use crate::{Error, InputError, Result};

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
    distances(points, "points", path)
}

/// [`distances_to_path`], with the points named `points_name` in errors.
fn distances(points: &[Vector3<f64>], points_name: &str, path: &[Vector3<f64>]) -> Result<Vec<PathDistance>> {
    if path.len() < 2 {
        return Err(Error::Input(InputError::TooFew {
            what: "path".into(),
            got: path.len(),
            min: 2,
            of: "point(s)".into(),
        }));
    }
    for (what, list) in [("path", path), (points_name, points)] {
        if let Some(i) = list.iter().position(|p| !p.iter().all(|v| v.is_finite())) {
            let value = list[i].iter().copied().find(|v| !v.is_finite()).unwrap_or(f64::NAN);
            return Err(Error::Input(InputError::NotFinite { what: format!("{what}: point {}", i + 1), value }));
        }
    }
    // Cumulative arc length at the start of each segment.
    let mut start = Vec::with_capacity(path.len());
    let mut s = 0.0;
    for w in path.windows(2) {
        start.push(s);
        s += (w[1] - w[0]).norm();
    }
    if s == 0.0 {
        return Err(Error::Input(InputError::OutOfRange {
            what: "path".into(),
            value: s,
            expected: "a path of non-zero length (all its points coincide)".into(),
        }));
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

/// Seed 000's tracking error (§IV-B, Fig. 6) of one or more measured runs of
/// a desired path.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TrackingError {
    /// Per run, the mean distance of its points to the desired path \[m\].
    pub run_means: Vec<f64>,
    /// Mean of `run_means` \[m\].
    pub mean: f64,
    /// Sample standard deviation (divisor n − 1) of `run_means` \[m\]; 0 for
    /// a single run.
    pub spread: f64,
}

/// Seed 000's tracking error: "the mean value of the distance between the
/// desired and the real path, in the direction perpendicular to the desired
/// path" (§IV-B). For each run, the mean over its points of the distance to
/// the nearest point of the polyline `desired` ([`distances_to_path`]; where
/// the nearest point is inside a segment this is the perpendicular distance,
/// at a vertex the distance to the vertex); then the mean and the sample
/// standard deviation of those per-run means, which the seed prints as
/// "0,17 ± 0,02 cm".
///
/// Errors: no run or an empty run, a desired path of fewer than two points
/// ([`InputError::TooFew`]); a path of zero length ([`InputError::OutOfRange`]);
/// non-finite coordinates ([`InputError::NotFinite`]).
///
/// # Examples
/// ```
/// use kinema::nalgebra::Vector3;
/// let desired = [Vector3::new(0.0, 0.0, 0.0), Vector3::new(0.1, 0.0, 0.0)]; // m
/// // Two runs, 1 mm and 3 mm beside the line.
/// let run = |d: f64| vec![Vector3::new(0.02, d, 0.0), Vector3::new(0.07, 0.0, d)];
/// let e = kinema::traj::tracking_error(&desired, &[run(0.001), run(0.003)])?;
/// assert!((e.run_means[0] - 0.001).abs() < 1e-12 && (e.run_means[1] - 0.003).abs() < 1e-12);
/// assert!((e.mean - 0.002).abs() < 1e-12);
/// assert!((e.spread - 0.002 / 2f64.sqrt()).abs() < 1e-12); // sample std of {1, 3} mm
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn tracking_error(desired: &[Vector3<f64>], runs: &[Vec<Vector3<f64>>]) -> Result<TrackingError> {
    if runs.is_empty() {
        return Err(Error::Input(InputError::TooFew {
            what: "runs".into(),
            got: 0,
            min: 1,
            of: "measured runs".into(),
        }));
    }
    if let Some(i) = runs.iter().position(|r| r.is_empty()) {
        return Err(Error::Input(InputError::TooFew {
            what: format!("runs: run {}", i + 1),
            got: 0,
            min: 1,
            of: "points".into(),
        }));
    }
    let mut run_means = Vec::with_capacity(runs.len());
    for (i, run) in runs.iter().enumerate() {
        let d = distances(run, &format!("runs: run {}", i + 1), desired)?;
        run_means.push(d.iter().map(|d| d.distance).sum::<f64>() / d.len() as f64);
    }
    let n = run_means.len() as f64;
    let mean = run_means.iter().sum::<f64>() / n;
    let spread = if run_means.len() > 1 {
        (run_means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
    } else {
        0.0
    };
    Ok(TrackingError { run_means, mean, spread })
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
        assert!(distances_to_path(&[o], &[o]).unwrap_err().to_string().contains("at least 2"));
        assert!(distances_to_path(&[o], &[o, o]).unwrap_err().to_string().contains("zero length"));
        let nan = Vector3::new(f64::NAN, 0.0, 0.0);
        assert!(distances_to_path(&[nan], &[o, Vector3::x()]).unwrap_err().to_string().contains("point 1"));
    }

    #[test]
    fn tracking_error_of_hand_computed_runs() {
        // An L-shaped path: (0,0,0) → (1,0,0) → (1,1,0).
        let path = [Vector3::new(0.0, 0.0, 0.0), Vector3::new(1.0, 0.0, 0.0), Vector3::new(1.0, 1.0, 0.0)];
        // Run 1: distances 0.1 (beside the first leg), 0.2 (beside the second
        // leg), 0.5 (beyond the start: to the vertex (0,0,0)) → mean 0.8/3.
        let r1 = vec![Vector3::new(0.5, 0.1, 0.0), Vector3::new(1.2, 0.5, 0.0), Vector3::new(-0.3, 0.4, 0.0)];
        // Run 2: 0.3 above the plane at two points → mean 0.3.
        let r2 = vec![Vector3::new(0.2, 0.0, 0.3), Vector3::new(1.0, 0.7, -0.3)];
        // Run 3: on the path → 0.
        let r3 = vec![Vector3::new(1.0, 0.5, 0.0)];
        let e = tracking_error(&path, &[r1.clone(), r2.clone(), r3]).unwrap();
        let m = [0.8 / 3.0, 0.3, 0.0];
        for (a, b) in e.run_means.iter().zip(m) {
            assert!((a - b).abs() < 1e-12, "{:?}", e.run_means);
        }
        let mean = (m[0] + m[1] + m[2]) / 3.0;
        let var = m.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / 2.0;
        assert!((e.mean - mean).abs() < 1e-12 && (e.spread - var.sqrt()).abs() < 1e-12);
        // One run: spread 0.
        let one = tracking_error(&path, &[r2]).unwrap();
        assert_eq!((one.mean, one.spread), (one.run_means[0], 0.0));
        assert!((one.mean - 0.3).abs() < 1e-12);
    }

    #[test]
    fn tracking_error_refuses_bad_input() {
        let path = [Vector3::zeros(), Vector3::x()];
        let e = tracking_error(&path, &[]).unwrap_err();
        assert!(matches!(&e, Error::Input(InputError::TooFew { what, got: 0, min: 1, .. }) if what == "runs"), "{e:?}");
        assert!(e.to_string().contains("0 measured runs; at least 1 needed"), "{e}");
        assert!(tracking_error(&path, &[vec![Vector3::x()], vec![]])
            .unwrap_err()
            .to_string()
            .contains("`runs: run 2` has 0 points"));
        let nan = Vector3::new(0.0, f64::NAN, 0.0);
        let e = tracking_error(&path, &[vec![Vector3::x()], vec![Vector3::x(), nan]]).unwrap_err().to_string();
        assert!(e.contains("run 2") && e.contains("point 2"), "{e}");
        assert!(tracking_error(&path[..1], &[vec![Vector3::x()]]).unwrap_err().to_string().contains("at least 2"));
    }
}
