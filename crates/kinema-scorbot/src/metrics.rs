//! How well a measured arm follows a desired path: seed 000's tracking error
//! (§IV-B, Fig. 5–6) and the ISO 9283 path and pose characteristics.
//!
//! # What is computed
//!
//! From a desired (commanded) polyline and n ≥ 1 measured runs of it, each a
//! polyline of measured tool positions \[m\], [`track`] returns a
//! [`TrackingReport`]:
//!
//! * **Seed 000's error** ([`kinema::traj::tracking_error`]): per run the mean
//!   distance of its measured points to the desired path, then mean ± sample
//!   standard deviation over the runs.
//! * **Path accuracy AT_p and path repeatability RT_p** (ISO 9283 §8.2–8.3).
//!   At m evaluation points P_j of the desired path, the plane through P_j
//!   normal to the path is intersected with every run; the n crossings c_ij
//!   have the barycentre b_j. Then
//!   `AT_p = max_j |b_j − P_j|` and `RT_p = max_j (l̄_j + 3·S_lj)`, with
//!   l_ij = |c_ij − b_j| and S_lj their sample standard deviation (n − 1).
//! * **Pose accuracy AP_p and pose repeatability RP_l** (ISO 9283 §7.2.1,
//!   §7.2.2) for the pose where the arm comes to rest: the last desired point
//!   is the commanded pose, the last point of each run an attained one;
//!   `AP_p = |x̄ − x_c|`, `RP_l = l̄ + 3·S_l` with l_i the distance of run i's
//!   last point to the barycentre x̄ of the last points.
//!
//! Repeatabilities need at least two runs; with one they are `None`.
//!
//! # Decisions (ISO 9283 leaves them to the user)
//!
//! * **Evaluation points** ([`Evaluation`]): by default the desired path is
//!   resampled uniformly in arc length at m = 100 points, both ends included
//!   ([`Evaluation::Resampled`]), so the figures do not depend on how densely
//!   the path was given; [`Evaluation::DesiredPoints`] uses the desired points
//!   themselves.
//! * **Normal plane at a vertex**: inside a segment the plane is normal to the
//!   segment; at a vertex of the polyline (including an evaluation point that
//!   falls on a corner) it is normal to the bisector of the incoming and
//!   outgoing directions (the mean of the two unit vectors); at the ends, to
//!   the first or last segment — unless the path is closed (its last point is
//!   its first), where the ends are one vertex. Zero-length segments are skipped.
//! * **Which crossing**: a run may cross the plane several times (a square's
//!   opposite side crosses a plane normal to the side it is on); the crossing
//!   nearest to P_j is taken. It is accepted if it is within
//!   [`TrackOptions::max_crossing_distance`] of P_j — by default 5 times the
//!   distance from P_j to the nearest point of the run. Otherwise (the run
//!   does not cross the plane near P_j, e.g. it stops short of the path's
//!   end), the run's **nearest point to P_j** is used instead, and the report
//!   counts these fallbacks in [`TrackingReport::fallback_points`].
//! * A segment of a run lying in the plane contributes its point nearest P_j.
//!
//! # Examples
//! ```
//! use kinema::nalgebra::Vector3;
//! use kinema_scorbot::metrics::{track, TrackOptions};
//! let desired: Vec<Vector3<f64>> = (0..=10).map(|k| Vector3::new(0.3 + 0.01 * k as f64, 0.0, 0.3)).collect();
//! // Two runs 1 mm and 3 mm above the line.
//! let run = |dz: f64| desired.iter().map(|p| p + Vector3::new(0.0, 0.0, dz)).collect::<Vec<_>>();
//! let r = track(&desired, &[run(0.001), run(0.003)], &TrackOptions::default())?;
//! assert!((r.mean_error - 0.002).abs() < 1e-12);
//! assert!((r.at_p - 0.002).abs() < 1e-12); // barycentre 2 mm above the line
//! assert!((r.rt_p.unwrap() - 0.001).abs() < 1e-12); // l = 1 mm for both, S_l = 0
//! assert!((r.ap_p - 0.002).abs() < 1e-12);
//! # Ok::<(), kinema_scorbot::Error>(())
//! ```

use std::path::Path;

use kinema::nalgebra::Vector3;
use serde::Serialize;

use crate::csvio;
use crate::error::{Error, Result};

/// Where along the desired path the path characteristics are evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Evaluation {
    /// m ≥ 2 points spaced uniformly in arc length, both ends included.
    Resampled(usize),
    /// The points of the desired path as given.
    DesiredPoints,
}

/// Options of [`track`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackOptions {
    /// The evaluation points; default [`Evaluation::Resampled`]`(100)`.
    pub evaluation: Evaluation,
    /// The farthest a run's crossing of a normal plane may be from the
    /// evaluation point \[m\] to be used; beyond it the run's nearest point is
    /// used. `None` (default): 5 × the distance from the evaluation point to
    /// the run's nearest point.
    pub max_crossing_distance: Option<f64>,
}

impl Default for TrackOptions {
    fn default() -> Self {
        TrackOptions { evaluation: Evaluation::Resampled(100), max_crossing_distance: None }
    }
}

/// Tracking figures of measured runs against a desired path (see the module
/// documentation). All lengths in metres. Serialised with the ISO figures
/// under their names: `AT_p`, `RT_p`, `AP_p`, `RP_p` (`null` with one run).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrackingReport {
    /// Seed 000's error: mean over the runs of each run's mean distance to
    /// the desired path \[m\].
    pub mean_error: f64,
    /// Sample standard deviation of the runs' mean distances \[m\] (0 for one run).
    pub mean_error_spread: f64,
    /// Each run's mean distance to the desired path \[m\].
    pub run_mean_errors: Vec<f64>,
    /// ISO 9283 path accuracy AT_p \[m\].
    #[serde(rename = "AT_p")]
    pub at_p: f64,
    /// ISO 9283 path repeatability RT_p \[m\]; `None` with one run.
    #[serde(rename = "RT_p")]
    pub rt_p: Option<f64>,
    /// ISO 9283 pose accuracy AP_p of the final pose \[m\].
    #[serde(rename = "AP_p")]
    pub ap_p: f64,
    /// ISO 9283 pose repeatability RP_l of the final pose \[m\]; `None` with one run.
    #[serde(rename = "RP_p")]
    pub rp_p: Option<f64>,
    /// Number of evaluation points m along the desired path.
    pub points: usize,
    /// Number of runs n.
    pub runs: usize,
    /// How many (evaluation point, run) pairs used the run's nearest point
    /// because the run did not cross the normal plane near the evaluation point.
    pub fallback_points: usize,
}

/// Tracking error and ISO 9283 path and pose characteristics of `runs` (each
/// a polyline of measured tool positions \[m\]) against the polyline
/// `desired` \[m\]. See the module documentation for the definitions and the
/// choices made.
///
/// Errors: a desired path of fewer than two points, no run, a run of fewer
/// than two points ([`Error::TooFew`]); a desired path of zero length
/// ([`Error::Infeasible`]); a non-finite coordinate, named by run and point
/// ([`Error::NotFinite`]); fewer than two evaluation points, a non-positive
/// or non-finite `max_crossing_distance` ([`Error::OutOfRange`]).
///
/// # Examples
/// ```
/// use kinema::nalgebra::Vector3;
/// use kinema_scorbot::metrics::{track, Evaluation, TrackOptions};
/// // A 10 cm square in the xz plane; one run 1 mm outside it all around.
/// let sq = |h: f64| {
///     let c = [(-h, -h), (h, -h), (h, h), (-h, h), (-h, -h)];
///     c.iter().map(|&(x, z)| Vector3::new(0.35 + x, 0.0, 0.3 + z)).collect::<Vec<_>>()
/// };
/// let opts = TrackOptions { evaluation: Evaluation::DesiredPoints, ..TrackOptions::default() };
/// let r = track(&sq(0.05), &[sq(0.051)], &opts)?;
/// // At the corners the crossing is the run's corner, √2 mm away.
/// assert!((r.at_p - 0.001 * 2f64.sqrt()).abs() < 1e-12);
/// assert!(r.rt_p.is_none() && r.runs == 1 && r.points == 5);
/// # Ok::<(), kinema_scorbot::Error>(())
/// ```
pub fn track(desired: &[Vector3<f64>], runs: &[Vec<Vector3<f64>>], options: &TrackOptions) -> Result<TrackingReport> {
    check_polyline("desired path", desired)?;
    if runs.is_empty() {
        return Err(Error::too_few("runs", 0, 1, "measured runs"));
    }
    for (i, run) in runs.iter().enumerate() {
        if run.len() < 2 {
            return Err(Error::too_few(format!("run {}", i + 1), run.len(), 2, "points"));
        }
        check_finite(&format!("run {}", i + 1), run)?;
    }
    if let Some(d) = options.max_crossing_distance {
        if !(d.is_finite() && d > 0.0) {
            return Err(Error::out_of_range("max_crossing_distance", d, "a positive, finite distance [m]"));
        }
    }
    let tracking = kinema::traj::tracking_error(desired, runs)?;
    let evals = evaluation_points(desired, options.evaluation)?;

    let mut at_p: f64 = 0.0;
    let mut rt_p: f64 = 0.0;
    let mut fallback_points = 0;
    let mut crossings = Vec::with_capacity(runs.len());
    for e in &evals {
        crossings.clear();
        for run in runs {
            let (nearest_point, nearest_dist) = nearest_on_polyline(run, &e.point);
            let limit = options.max_crossing_distance.unwrap_or(5.0 * nearest_dist + 1e-12);
            match plane_crossing(run, &e.point, &e.normal) {
                Some(c) if (c - e.point).norm() <= limit => crossings.push(c),
                _ => {
                    fallback_points += 1;
                    crossings.push(nearest_point);
                }
            }
        }
        let (accuracy, repeatability) = scatter(&crossings, &e.point);
        at_p = at_p.max(accuracy);
        rt_p = rt_p.max(repeatability.unwrap_or(0.0));
    }
    let last: Vec<Vector3<f64>> = runs.iter().map(|r| r[r.len() - 1]).collect();
    let (ap_p, rp_p) = scatter(&last, &desired[desired.len() - 1]);
    let multi = runs.len() > 1;
    Ok(TrackingReport {
        mean_error: tracking.mean,
        mean_error_spread: tracking.spread,
        run_mean_errors: tracking.run_means,
        at_p,
        rt_p: multi.then_some(rt_p),
        ap_p,
        rp_p,
        points: evals.len(),
        runs: runs.len(),
        fallback_points,
    })
}

/// ISO 9283 accuracy and repeatability of attained points around a commanded
/// one: (|barycentre − commanded|, l̄ + 3·S_l), the latter `None` for one point.
fn scatter(attained: &[Vector3<f64>], commanded: &Vector3<f64>) -> (f64, Option<f64>) {
    let n = attained.len() as f64;
    let bary = attained.iter().fold(Vector3::zeros(), |a, p| a + p) / n;
    let accuracy = (bary - commanded).norm();
    if attained.len() < 2 {
        return (accuracy, None);
    }
    let l: Vec<f64> = attained.iter().map(|p| (p - bary).norm()).collect();
    let mean = l.iter().sum::<f64>() / n;
    let s = (l.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    (accuracy, Some(mean + 3.0 * s))
}

fn check_polyline(what: &str, path: &[Vector3<f64>]) -> Result<()> {
    if path.len() < 2 {
        return Err(Error::too_few(what, path.len(), 2, "points"));
    }
    check_finite(what, path)?;
    if path.windows(2).all(|w| w[0] == w[1]) {
        return Err(Error::Infeasible { what: what.into(), reason: "all its points coincide (zero length)".into() });
    }
    Ok(())
}

/// The first non-finite coordinate of `path`, named by point and axis.
fn check_finite(what: &str, path: &[Vector3<f64>]) -> Result<()> {
    for (k, p) in path.iter().enumerate() {
        if let Some(a) = (0..3).find(|&a| !p[a].is_finite()) {
            return Err(Error::not_finite(format!("{what}, point {}, {}", k + 1, ["x", "y", "z"][a]), p[a]));
        }
    }
    Ok(())
}

/// An evaluation point with the unit normal of its plane (the path's tangent).
#[derive(Debug, Clone, Copy)]
struct EvalPoint {
    point: Vector3<f64>,
    normal: Vector3<f64>,
}

/// The tangent at vertex `k`: the bisector of the nearest non-degenerate
/// incoming and outgoing segments (either alone at the ends of an open path;
/// the ends of a closed path are one vertex).
fn vertex_tangent(dirs: &[Option<Vector3<f64>>], k: usize, closed: bool) -> Vector3<f64> {
    let mut incoming = dirs[..k].iter().rev().find_map(|d| *d);
    let mut outgoing = dirs[k..].iter().find_map(|d| *d);
    if closed {
        // The ends of a closed path are one vertex: wrap around.
        incoming = incoming.or_else(|| dirs.iter().rev().find_map(|d| *d));
        outgoing = outgoing.or_else(|| dirs.iter().find_map(|d| *d));
    }
    match (incoming, outgoing) {
        (Some(a), Some(b)) => {
            let s = a + b;
            // A path that turns back on itself: no bisector; use the incoming direction.
            if s.norm() < 1e-9 {
                a
            } else {
                s.normalize()
            }
        }
        (Some(a), None) => a,
        (None, Some(b)) => b,
        (None, None) => unreachable!("check_polyline refuses zero-length paths"),
    }
}

fn evaluation_points(desired: &[Vector3<f64>], evaluation: Evaluation) -> Result<Vec<EvalPoint>> {
    let dirs: Vec<Option<Vector3<f64>>> = desired
        .windows(2)
        .map(|w| {
            let d = w[1] - w[0];
            let n = d.norm();
            (n > 0.0).then(|| d / n)
        })
        .collect();
    let total: f64 = desired.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    let closed = (desired[0] - desired[desired.len() - 1]).norm() <= 1e-12 * total;
    match evaluation {
        Evaluation::DesiredPoints => Ok(desired
            .iter()
            .enumerate()
            .map(|(k, p)| EvalPoint { point: *p, normal: vertex_tangent(&dirs, k, closed) })
            .collect()),
        Evaluation::Resampled(m) => {
            if m < 2 {
                return Err(Error::out_of_range("evaluation points", m as f64, "at least two (both ends of the path)"));
            }
            if m > 10_000_000 {
                return Err(Error::out_of_range("evaluation points", m as f64, "at most 10⁷"));
            }
            // Arc length at each vertex.
            let mut cum = Vec::with_capacity(desired.len());
            cum.push(0.0);
            for w in desired.windows(2) {
                cum.push(cum[cum.len() - 1] + (w[1] - w[0]).norm());
            }
            let total = cum[cum.len() - 1];
            let tol = 1e-12 * total;
            let mut out = Vec::with_capacity(m);
            let mut seg = 0;
            for j in 0..m {
                let s = if j + 1 == m { total } else { total * j as f64 / (m - 1) as f64 };
                // Advance to the segment containing s (non-degenerate, cum[seg] ≤ s ≤ cum[seg+1]).
                while seg + 1 < dirs.len() && (dirs[seg].is_none() || s > cum[seg + 1] + tol) {
                    seg += 1;
                }
                let e = if (s - cum[seg]).abs() <= tol {
                    EvalPoint { point: desired[seg], normal: vertex_tangent(&dirs, seg, closed) }
                } else if (s - cum[seg + 1]).abs() <= tol {
                    EvalPoint { point: desired[seg + 1], normal: vertex_tangent(&dirs, seg + 1, closed) }
                } else {
                    let d = dirs[seg].expect("the loop stops on non-degenerate segments inside the path");
                    EvalPoint { point: desired[seg] + d * (s - cum[seg]), normal: d }
                };
                out.push(e);
            }
            Ok(out)
        }
    }
}

/// The point of polyline `run` nearest to `p`, and its distance.
fn nearest_on_polyline(run: &[Vector3<f64>], p: &Vector3<f64>) -> (Vector3<f64>, f64) {
    let mut best = (run[0], (run[0] - p).norm());
    for w in run.windows(2) {
        let c = nearest_on_segment(&w[0], &w[1], p);
        let d = (c - p).norm();
        if d < best.1 {
            best = (c, d);
        }
    }
    best
}

fn nearest_on_segment(a: &Vector3<f64>, b: &Vector3<f64>, p: &Vector3<f64>) -> Vector3<f64> {
    let d = b - a;
    let len2 = d.norm_squared();
    let u = if len2 > 0.0 { ((p - a).dot(&d) / len2).clamp(0.0, 1.0) } else { 0.0 };
    a + d * u
}

/// The crossing of polyline `run` with the plane through `p` with unit normal
/// `n` that is nearest to `p`, if the run reaches the plane.
fn plane_crossing(run: &[Vector3<f64>], p: &Vector3<f64>, n: &Vector3<f64>) -> Option<Vector3<f64>> {
    let mut best: Option<(Vector3<f64>, f64)> = None;
    for w in run.windows(2) {
        // Signed distances to the plane; a point within rounding of the plane
        // is on it (a run's end often lies exactly in the plane at the path's end).
        let snap = |v: Vector3<f64>| {
            let s = n.dot(&v);
            if s.abs() <= 1e-12 * v.norm() {
                0.0
            } else {
                s
            }
        };
        let (sa, sb) = (snap(w[0] - p), snap(w[1] - p));
        let c = if sa == 0.0 && sb == 0.0 {
            // The segment lies in the plane.
            nearest_on_segment(&w[0], &w[1], p)
        } else if (sa <= 0.0 && sb >= 0.0) || (sa >= 0.0 && sb <= 0.0) {
            w[0] + (w[1] - w[0]) * (sa / (sa - sb))
        } else {
            continue;
        };
        let d = (c - p).norm();
        if best.is_none_or(|(_, bd)| d < bd) {
            best = Some((c, d));
        }
    }
    best.map(|(c, _)| c)
}

/// Reads a points file: CSV with a header row that names columns `x`, `y`,
/// `z` (in any order, case-insensitive; other columns are ignored), one point
/// per row, in metres. Blank lines and lines starting with `#` are skipped.
///
/// Errors: the file cannot be read ([`Error::Io`]); a column is missing, a
/// row is short, a value is not a number or not finite ([`Error::Csv`],
/// naming the file, the line and the offending text); fewer than two points
/// ([`Error::InFile`]).
///
/// # Examples
/// ```
/// let path = std::env::temp_dir().join("kinema-scorbot-doc-points.csv");
/// std::fs::write(&path, "t,z,x,y\n0,0.3,0.35,0\n1,0.3,0.36,0.001\n")?;
/// let pts = kinema_scorbot::metrics::read_points_csv(&path)?;
/// assert_eq!(pts.len(), 2);
/// assert_eq!((pts[1].x, pts[1].y, pts[1].z), (0.36, 0.001, 0.3));
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_points_csv(path: &Path) -> Result<Vec<Vector3<f64>>> {
    points(csvio::read_columns(path, &["x", "y", "z"], &[])?, &path.display().to_string())
}

/// Parses the text of a points file (see [`read_points_csv`]); `origin`
/// names it in errors.
pub fn parse_points_csv(text: &str, origin: &str) -> Result<Vec<Vector3<f64>>> {
    points(csvio::parse_columns(text, origin, &["x", "y", "z"], &[])?, origin)
}

fn points(rows: Vec<csvio::Row>, origin: &str) -> Result<Vec<Vector3<f64>>> {
    if rows.len() < 2 {
        return Err(Error::InFile {
            path: origin.into(),
            source: Box::new(Error::too_few("path", rows.len(), 2, "points")),
        });
    }
    Ok(rows.iter().map(|r| Vector3::new(r.req[0], r.req[1], r.req[2])).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn line(n: usize) -> Vec<Vector3<f64>> {
        (0..n).map(|k| Vector3::new(0.1 * k as f64, 0.0, 0.0)).collect()
    }

    fn shifted(path: &[Vector3<f64>], d: Vector3<f64>) -> Vec<Vector3<f64>> {
        path.iter().map(|p| p + d).collect()
    }

    /// A square of half side `h` around (0.35, 0, 0.3) in the xz plane,
    /// `step` between points (1 cm in seed 000 §IV-B), closed, starting and
    /// ending at the middle of its bottom side.
    fn square(h: f64, step: f64) -> Vec<Vector3<f64>> {
        let corners = [(0.0, -h), (h, -h), (h, h), (-h, h), (-h, -h), (0.0, -h)];
        let mut out = Vec::new();
        for w in corners.windows(2) {
            let len = (w[1].0 - w[0].0).abs() + (w[1].1 - w[0].1).abs();
            let n = (len / step).round().max(1.0) as usize;
            for k in 0..n {
                let t = k as f64 / n as f64;
                let (x, z) = (w[0].0 + t * (w[1].0 - w[0].0), w[0].1 + t * (w[1].1 - w[0].1));
                out.push(Vector3::new(0.35 + x, 0.0, 0.3 + z));
            }
        }
        out.push(out[0]);
        out
    }

    #[test]
    fn straight_line_with_runs_offset_by_known_amounts() {
        let desired = line(11); // 0 … 1 m along x
        let mm = 1e-3;
        let runs: Vec<_> = [1.0, 3.0, 2.0].iter().map(|d| shifted(&desired, Vector3::new(0.0, d * mm, 0.0))).collect();
        let r = track(&desired, &runs, &TrackOptions::default()).unwrap();
        // Crossings at P + (0, δ_i, 0): barycentre 2 mm off, l = (1, 1, 0) mm,
        // l̄ = 2/3 mm, S_l = √((1/9 + 1/9 + 4/9)/2) = √(1/3) mm.
        let rt = (2.0 / 3.0 + 3.0 * (1.0f64 / 3.0).sqrt()) * mm;
        assert!((r.at_p - 2.0 * mm).abs() < 1e-12, "{r:?}");
        assert!((r.rt_p.unwrap() - rt).abs() < 1e-12, "{r:?}");
        assert!((r.ap_p - 2.0 * mm).abs() < 1e-12 && (r.rp_p.unwrap() - rt).abs() < 1e-12);
        assert!((r.mean_error - 2.0 * mm).abs() < 1e-12 && (r.mean_error_spread - mm).abs() < 1e-12);
        assert_eq!((r.points, r.runs, r.fallback_points), (100, 3, 0));
        for (a, b) in r.run_mean_errors.iter().zip([1.0, 3.0, 2.0]) {
            assert!((a - b * mm).abs() < 1e-12);
        }
        // A lag along the line changes neither AT_p nor RT_p inside the path,
        // but the final pose: each run stops 5 mm short.
        let lagged: Vec<_> = runs.iter().map(|r| shifted(r, Vector3::new(-5.0 * mm, 0.0, 0.0))).collect();
        let l = track(&desired, &lagged, &TrackOptions::default()).unwrap();
        assert!((l.ap_p - (25.0f64 + 4.0).sqrt() * mm).abs() < 1e-12, "{l:?}");
        // The plane at the path's end (x = 1 m) is not crossed by the lagged runs:
        // their nearest point (their end) is used.
        assert_eq!(l.fallback_points, 3);
        assert!((l.at_p - (25.0f64 + 4.0).sqrt() * mm).abs() < 1e-12);
    }

    #[test]
    fn a_square_like_seed_000_fig_6() {
        let desired = square(0.05, 0.01);
        assert_eq!(desired.len(), 41);
        let e = 0.001;
        let outer = square(0.05 + e, 0.01);
        let inner = square(0.05 - e, 0.01);
        let opts = TrackOptions { evaluation: Evaluation::DesiredPoints, ..TrackOptions::default() };
        let one = track(&desired, std::slice::from_ref(&outer), &opts).unwrap();
        // Corners: the bisector plane meets the outer run at its corner, √2·e away.
        assert!((one.at_p - e * 2f64.sqrt()).abs() < 1e-12, "{one:?}");
        assert!(one.rt_p.is_none() && one.rp_p.is_none());
        // Final pose: mid-side, e away.
        assert!((one.ap_p - e).abs() < 1e-12);
        // Mean distance: 37 run points are e from the square, the 4 corners √2·e.
        assert!((one.mean_error - (37.0 + 4.0 * 2f64.sqrt()) * e / 41.0).abs() < 1e-12);
        // Resampled at 100 points (spacing 0.4/99 m) no point is a corner: AT_p = e.
        let r = track(&desired, std::slice::from_ref(&outer), &TrackOptions::default()).unwrap();
        assert!((r.at_p - e).abs() < 1e-12, "{r:?}");
        // 81 points (spacing 5 mm) hit the corners again.
        let opts81 = TrackOptions { evaluation: Evaluation::Resampled(81), ..TrackOptions::default() };
        let r = track(&desired, std::slice::from_ref(&outer), &opts81).unwrap();
        assert!((r.at_p - e * 2f64.sqrt()).abs() < 1e-12, "{r:?}");
        // Outer and inner run: barycentre on the path, each crossing e (√2·e at
        // corners) from it, S_l = 0.
        let r = track(&desired, &[outer, inner.clone()], &opts81).unwrap();
        assert!(r.at_p < 1e-12, "{r:?}");
        assert!((r.rt_p.unwrap() - e * 2f64.sqrt()).abs() < 1e-12);
        assert!(r.ap_p < 1e-12 && (r.rp_p.unwrap() - e).abs() < 1e-12);
        assert_eq!(r.fallback_points, 0);
        // The run's points need not match the desired ones: a run sampled every
        // 3 mm inside the square by e gives the same figures as one sampled
        // every cm. Near a corner (within e of it), the plane normal to one side
        // misses the inner run's side, and the nearest point is used: the
        // corner of the inner run, √(e² + (e − δ)²) from a point δ before the corner.
        let dense = track(&desired, &[square(0.05 - e, 0.003)], &TrackOptions::default()).unwrap();
        let coarse = track(&desired, &[inner], &TrackOptions::default()).unwrap();
        assert!((dense.at_p - coarse.at_p).abs() < 1e-12 && dense.fallback_points == coarse.fallback_points);
        // The resampled point nearest a corner: s = 37·0.4/99 m, δ before the
        // corner at s = 0.15 m (and likewise after the corner at 0.25 m).
        let delta = 0.15 - 37.0 * 0.4 / 99.0;
        assert!(delta < e && (coarse.at_p - (e * e + (e - delta).powi(2)).sqrt()).abs() < 1e-12, "{coarse:?}");
    }

    #[test]
    fn constant_offset_normal_to_a_planar_path_gives_its_length() {
        let mut rng = ChaCha8Rng::seed_from_u64(9283);
        for case in 0..200 {
            // A random planar path (random walk in the xy plane), rotated and moved.
            let n = rng.random_range(2..12);
            let mut p = Vector3::zeros();
            let mut path = vec![p];
            for _ in 1..n {
                let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
                p += Vector3::new(a.cos(), a.sin(), 0.0) * rng.random_range(0.01..0.1);
                path.push(p);
            }
            let rot = kinema::nalgebra::Rotation3::from_euler_angles(
                rng.random_range(-3.0..3.0),
                rng.random_range(-3.0..3.0),
                rng.random_range(-3.0..3.0),
            );
            let t = Vector3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
            let path: Vec<_> = path.iter().map(|q| rot * q + t).collect();
            let dist = rng.random_range(1e-4..1e-2);
            let d = rot * Vector3::new(0.0, 0.0, dist);
            let runs = vec![shifted(&path, d); rng.random_range(1..4)];
            for evaluation in [Evaluation::DesiredPoints, Evaluation::Resampled(rng.random_range(2..60))] {
                let r = track(&path, &runs, &TrackOptions { evaluation, max_crossing_distance: None }).unwrap();
                assert!((r.at_p - dist).abs() < 1e-9, "case {case}: {r:?} vs {dist}");
                assert!((r.ap_p - dist).abs() < 1e-9);
                assert!((r.mean_error - dist).abs() < 1e-9 && r.mean_error_spread < 1e-9);
                if runs.len() > 1 {
                    assert!(r.rt_p.unwrap() < 1e-9 && r.rp_p.unwrap() < 1e-9);
                }
            }
        }
    }

    #[test]
    fn bad_input_is_refused_with_reasons() {
        let d = line(3);
        let o = TrackOptions::default();
        let err = |r: Result<TrackingReport>| r.unwrap_err();
        let e = err(track(&d[..1], std::slice::from_ref(&d), &o));
        assert!(matches!(&e, Error::TooFew { what, got: 1, min: 2, .. } if what == "desired path"), "{e:?}");
        assert!(e.to_string().contains("at least 2"), "{e}");
        let e = err(track(&[d[0], d[0]], std::slice::from_ref(&d), &o));
        assert!(matches!(&e, Error::Infeasible { .. }) && e.to_string().contains("zero length"), "{e:?}");
        let e = err(track(&d, &[], &o));
        assert!(matches!(&e, Error::TooFew { what, got: 0, min: 1, .. } if what == "runs"), "{e:?}");
        let e = err(track(&d, &[d.clone(), vec![d[0]]], &o));
        assert!(matches!(&e, Error::TooFew { what, got: 1, min: 2, .. } if what == "run 2"), "{e:?}");
        let mut bad = d.clone();
        bad[2].y = f64::NAN;
        let e = err(track(&d, &[bad.clone()], &o));
        assert!(
            matches!(&e, Error::NotFinite { what, value } if what == "run 1, point 3, y" && value.is_nan()),
            "{e:?}"
        );
        let e = err(track(&bad, std::slice::from_ref(&d), &o));
        assert!(matches!(&e, Error::NotFinite { what, .. } if what == "desired path, point 3, y"), "{e:?}");
        let e = TrackOptions { evaluation: Evaluation::Resampled(1), ..o };
        let e = err(track(&d, std::slice::from_ref(&d), &e));
        assert!(
            matches!(&e, Error::OutOfRange { what, value, .. } if what == "evaluation points" && *value == 1.0),
            "{e:?}"
        );
        let e = TrackOptions { max_crossing_distance: Some(f64::NAN), ..o };
        let e = err(track(&d, std::slice::from_ref(&d), &e));
        assert!(matches!(&e, Error::OutOfRange { what, .. } if what == "max_crossing_distance"), "{e:?}");
        // A run standing still is fine (its points are its crossings' fallback).
        let still = vec![Vector3::new(0.1, 0.002, 0.0); 3];
        let r = track(&d, &[still], &o).unwrap();
        assert!(r.at_p.is_finite() && r.fallback_points > 0);
    }

    #[test]
    fn csv_points_and_their_errors() {
        let p = parse_points_csv("# measured\nZ, \"x\" ,y,t\n0.3,0.35,0,0\n\n0.31, 0.36 ,-0.001,1\n", "a.csv").unwrap();
        assert_eq!(p, vec![Vector3::new(0.35, 0.0, 0.3), Vector3::new(0.36, -0.001, 0.31)]);
        let e = |t: &str| parse_points_csv(t, "m.csv").unwrap_err().to_string();
        let s = e("x,y\n1,2\n3,4\n");
        assert!(s.starts_with("m.csv:1") && s.contains("no column `z`"), "{s}");
        let s = e("x,y,z\n1,2,3\n1,abc,3\n");
        assert!(s.starts_with("m.csv:3") && s.contains("column `y`: `abc`"), "{s}");
        let s = e("x,y,z\n1,2,3\n1,NaN,3\n");
        assert!(s.starts_with("m.csv:3") && s.contains("`NaN` is not a finite number"), "{s}");
        let s = e("x,y,z\n1,2,3\n1,2\n");
        assert!(s.starts_with("m.csv:3") && s.contains("`z`"), "{s}");
        let few = parse_points_csv("x,y,z\n1,2,3\n", "m.csv").unwrap_err();
        assert!(
            matches!(&few, Error::InFile { path, source } if path == "m.csv"
                && matches!(**source, Error::TooFew { got: 1, min: 2, .. })),
            "{few:?}"
        );
        assert!(e("").starts_with("m.csv"));
        let s = read_points_csv(Path::new("/nonexistent/k.csv")).unwrap_err().to_string();
        assert!(s.contains("/nonexistent/k.csv"), "{s}");
        let dir = std::env::temp_dir().join(format!("kinema-metrics-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("p.csv");
        std::fs::write(&f, "x,y,z\n0,0,0\n1,inf,0\n").unwrap();
        let s = read_points_csv(&f).unwrap_err().to_string();
        assert!(s.contains("p.csv:3") && s.contains("`inf`"), "{s}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
