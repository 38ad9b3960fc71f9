//! Path following as in seed 000 §IV-B: a Cartesian path (x, y, z, pitch,
//! roll) is resampled so consecutive points are at most 1 cm apart, solved with
//! the seed's inverse kinematics, converted to encoder counts with eq. 24, and
//! sent to the controller as a position vector and `MOVES` (or point by point
//! with `MOVED`).
//!
//! # Examples
//! ```
//! use kinema::nalgebra::Vector3;
//! use kinema_scorbot::encoder::Constants;
//! use kinema_scorbot::follow::{plan, PathPoint, PlanOptions};
//! let robot = kinema::Robot::builtin("scorbot-er-v-plus")?;
//! let c = Constants::named("calibrated")?;
//! let path = [
//!     PathPoint::new(Vector3::new(0.35, 0.0, 0.25), 0.0, 0.0),
//!     PathPoint::new(Vector3::new(0.35, 0.0, 0.35), 0.0, 0.0),
//! ];
//! let p = plan(&robot, &c, &path, &PlanOptions::default())?;
//! assert_eq!(p.points.len(), 11); // 10 cm in steps of 1 cm
//! assert!(p.branches.iter().all(|b| b == "front/elbow-up"));
//! # Ok::<(), kinema_scorbot::Error>(())
//! ```

use std::path::Path;

use kinema::ik::scorbot::ScorbotIk;
use kinema::nalgebra::Vector3;
use kinema::Robot;

use crate::acl::Client;
use crate::encoder::{Constants, MOTORS};
use crate::error::{Error, Result};

/// The seed's largest step between consecutive path points \[m\].
pub const SEED_MAX_STEP: f64 = 0.01;

/// One point of a Cartesian path for the Scorbot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathPoint {
    /// Tool position in the robot's world frame \[m\].
    pub position: Vector3<f64>,
    /// Pitch β \[rad\] (seed 000 eq. 13: β = −(θ2+θ3+θ4), positive points down).
    pub pitch: f64,
    /// Roll γ = θ5 \[rad\].
    pub roll: f64,
}

impl PathPoint {
    /// A point from its parts.
    pub fn new(position: Vector3<f64>, pitch: f64, roll: f64) -> PathPoint {
        PathPoint { position, pitch, roll }
    }
}

/// Options of [`plan`].
#[derive(Debug, Clone, PartialEq)]
pub struct PlanOptions {
    /// Largest distance between consecutive points after resampling \[m\].
    pub max_step: f64,
    /// Configuration to start nearest to \[rad\]; without it the first point
    /// prefers `front/elbow-up`, then `front/elbow-down`.
    pub q0: Option<Vec<f64>>,
}

impl Default for PlanOptions {
    fn default() -> Self {
        PlanOptions { max_step: SEED_MAX_STEP, q0: None }
    }
}

/// A path ready to send: the resampled points, their joint angles and counts.
#[derive(Debug, Clone, PartialEq)]
pub struct FollowPlan {
    /// The resampled path.
    pub points: Vec<PathPoint>,
    /// Joint angles of each point \[rad\].
    pub q: Vec<[f64; MOTORS]>,
    /// Encoder counts of each point (eq. 24 with the plan's constants).
    pub counts: Vec<[i64; MOTORS]>,
    /// IK branch chosen at each point.
    pub branches: Vec<String>,
}

/// Splits every segment of `path` into equal parts no longer than
/// `max_step` \[m\], interpolating pitch and roll linearly. Errors: an empty
/// path, a non-finite value, `max_step` not positive, or more than 10⁶ points.
pub fn resample(path: &[PathPoint], max_step: f64) -> Result<Vec<PathPoint>> {
    if path.is_empty() {
        return Err(Error::too_few("path", 0, 1, "points"));
    }
    if !(max_step.is_finite() && max_step > 0.0) {
        return Err(Error::out_of_range("max step", max_step, "a positive step [m]"));
    }
    for (i, p) in path.iter().enumerate() {
        let values =
            [("x", p.position.x), ("y", p.position.y), ("z", p.position.z), ("pitch", p.pitch), ("roll", p.roll)];
        if let Some((name, v)) = values.iter().find(|(_, v)| !v.is_finite()) {
            return Err(Error::not_finite(format!("point {} of the path, {name}", i + 1), *v));
        }
    }
    let mut out = vec![path[0]];
    for w in path.windows(2) {
        let (a, b) = (w[0], w[1]);
        let parts = ((b.position - a.position).norm() / max_step).ceil().max(1.0);
        if out.len() as f64 + parts > 1e6 {
            return Err(Error::Infeasible {
                what: "max step".into(),
                reason: format!("resampling at {max_step} m gives more than 10⁶ points"),
            });
        }
        let parts = parts as usize;
        for k in 1..=parts {
            let s = k as f64 / parts as f64;
            out.push(PathPoint {
                position: a.position + (b.position - a.position) * s,
                pitch: a.pitch + (b.pitch - a.pitch) * s,
                roll: a.roll + (b.roll - a.roll) * s,
            });
        }
    }
    Ok(out)
}

/// Resamples `path` and solves each point with the seed's closed-form IK
/// (`ScorbotIk`), keeping solutions within the robot's joint limits and
/// choosing at each point the one nearest the previous point's (so joints do
/// not jump between branches), then converts to counts with `constants`.
/// Errors name the first point that has no solution within limits and why.
pub fn plan(robot: &Robot, constants: &Constants, path: &[PathPoint], options: &PlanOptions) -> Result<FollowPlan> {
    let ik = ScorbotIk::new(robot)?;
    if let Some(q0) = &options.q0 {
        robot.check_q(q0)?;
    }
    let points = resample(path, options.max_step)?;
    let mut q = Vec::with_capacity(points.len());
    let mut branches = Vec::with_capacity(points.len());
    let mut counts = Vec::with_capacity(points.len());
    let mut prev: Option<[f64; MOTORS]> = options.q0.as_ref().map(|v| std::array::from_fn(|i| v[i]));
    for (k, p) in points.iter().enumerate() {
        // Errors here name the point, so the caller can find it in the path.
        let at = |e: Error| Error::AtPathPoint { point: k + 1, at: *p, source: Box::new(e) };
        let cands = ik
            .xyz_pitch_roll_candidates([p.position.x, p.position.y, p.position.z], p.pitch, p.roll)
            .map_err(|e| at(e.into()))?;
        let mut best: Option<([f64; MOTORS], String, f64)> = None;
        let mut outside = Vec::new();
        for (cq, label) in cands.iter() {
            let cq: [f64; MOTORS] = std::array::from_fn(|i| cq[i]);
            let flags = robot.limit_flags(&cq);
            if !flags.is_empty() {
                let joints: Vec<String> = flags.indices().map(|j| (j + 1).to_string()).collect();
                outside.push(format!("{label} (joint {})", joints.join(", ")));
                continue;
            }
            let cost = match prev {
                Some(pq) => cq.iter().zip(&pq).map(|(a, b)| (a - b).powi(2)).sum::<f64>(),
                None => match label {
                    "front/elbow-up" => 0.0,
                    "front/elbow-down" => 1.0,
                    _ => 2.0,
                },
            };
            if best.as_ref().is_none_or(|b| cost < b.2) {
                best = Some((cq, label.to_string(), cost));
            }
        }
        let Some((cq, label, _)) = best else {
            return Err(at(Error::OutsideLimits { outside }));
        };
        counts.push(constants.counts_rounded(&cq)?);
        q.push(cq);
        branches.push(label);
        prev = Some(cq);
    }
    Ok(FollowPlan { points, q, counts, branches })
}

/// Most positions sent as one vector; longer plans are split into several
/// vectors, each followed smoothly (the arm may pause between them).
pub const VECTOR_LIMIT: usize = 1000;

/// How [`execute`] sends a plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SendMode {
    /// `DIMP v[n]`, `SETPV` for every point, then one `MOVES v 1 n` (smooth);
    /// plans longer than [`VECTOR_LIMIT`] go as several vectors `v`, `v2`, ….
    Vector,
    /// `DEFP p`, then for every point `SETPV` and `MOVED p` (stops at each point).
    Points,
}

/// Sends `plan` to the controller under the position or vector name `name`.
/// `time` is the duration of the whole motion (`Vector`) or of each step
/// (`Points`) in hundredths of a second; without it the controller's speed
/// setting decides. `progress(done, total)` is called after each point is sent
/// and after each move. Stops at the first error (the client is then faulted).
pub fn execute(
    client: &mut Client,
    plan: &FollowPlan,
    name: &str,
    mode: SendMode,
    time: Option<u32>,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<()> {
    let n = plan.counts.len();
    if n == 0 {
        return Err(Error::too_few("plan", 0, 1, "points"));
    }
    match mode {
        SendMode::Vector => {
            // Vectors of at most VECTOR_LIMIT points: `name`, `name2`, `name3`, …
            // each sent and then moved through with one MOVES.
            let chunks = n.div_ceil(VECTOR_LIMIT);
            let mut done = 0;
            for (k, chunk) in plan.counts.chunks(VECTOR_LIMIT).enumerate() {
                let vname = if k == 0 { name.to_string() } else { format!("{name}{}", k + 1) };
                client.dimp(&vname, chunk.len())?;
                for (i, c) in chunk.iter().enumerate() {
                    client.set_joint_position(&format!("{vname}[{}]", i + 1), *c)?;
                    done += 1;
                    progress(done, n + chunks);
                }
                let share = time.map(|t| ((t as f64 * chunk.len() as f64 / n as f64).round() as u32).max(1));
                client.moves(&vname, 1, chunk.len(), share)?;
                done += 1;
                progress(done, n + chunks);
            }
        }
        SendMode::Points => {
            client.defp(name)?;
            for (k, c) in plan.counts.iter().enumerate() {
                client.set_joint_position(name, *c)?;
                client.move_d(name, time)?;
                progress(k + 1, n);
            }
        }
    }
    Ok(())
}

/// Reads a path CSV: a header naming columns `x`, `y`, `z` \[m\] and
/// optionally `pitch` and `roll` (radians, or degrees with `degrees`; 0 when
/// absent), in any order; other columns are ignored. Errors name the file,
/// line and text.
pub fn read_path_csv(path: &Path, degrees: bool) -> Result<Vec<PathPoint>> {
    let table = crate::csvio::read_columns(path, &["x", "y", "z"], &["pitch", "roll"])?;
    let scale = if degrees { 1f64.to_radians() } else { 1.0 };
    Ok(table
        .iter()
        .map(|r| {
            PathPoint::new(
                Vector3::new(r.req[0], r.req[1], r.req[2]),
                r.opt[0].unwrap_or(0.0) * scale,
                r.opt[1].unwrap_or(0.0) * scale,
            )
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn pt(x: f64, y: f64, z: f64) -> PathPoint {
        PathPoint::new(Vector3::new(x, y, z), 0.0, 0.0)
    }

    #[test]
    fn resampling_keeps_vertices_and_steps_under_the_limit() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for _ in 0..500 {
            let n = rng.random_range(1..8);
            let path: Vec<PathPoint> = (0..n)
                .map(|_| {
                    PathPoint::new(
                        Vector3::new(
                            rng.random_range(-0.5..0.5),
                            rng.random_range(-0.5..0.5),
                            rng.random_range(0.0..0.6),
                        ),
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-3.0..3.0),
                    )
                })
                .collect();
            let step = rng.random_range(0.003..0.05);
            let r = resample(&path, step).unwrap();
            assert!(r.windows(2).all(|w| (w[1].position - w[0].position).norm() <= step * (1.0 + 1e-12)));
            // Every original vertex is kept, in order.
            let mut j = 0;
            for p in &path {
                while j < r.len() && (r[j].position - p.position).norm() > 1e-12 {
                    j += 1;
                }
                assert!(j < r.len(), "vertex {p:?} lost");
            }
            // No more points than needed: one fewer step would exceed the limit.
            let expected: usize = 1 + path
                .windows(2)
                .map(|w| ((w[1].position - w[0].position).norm() / step).ceil().max(1.0) as usize)
                .sum::<usize>();
            assert_eq!(r.len(), expected);
        }
    }

    #[test]
    fn plans_reach_every_point_with_fk_and_never_jump() {
        let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
        let c = Constants::named("calibrated").unwrap();
        // The seed's Fig. 6 square in the xz plane.
        let square =
            [pt(0.40, 0.0, 0.20), pt(0.50, 0.0, 0.20), pt(0.50, 0.0, 0.30), pt(0.40, 0.0, 0.30), pt(0.40, 0.0, 0.20)];
        let p = plan(&robot, &c, &square, &PlanOptions::default()).unwrap();
        assert_eq!(p.points.len(), 41);
        for (k, q) in p.q.iter().enumerate() {
            let fk = robot.fk(q).unwrap();
            assert!((fk.world_from_tool.pos - p.points[k].position).norm() < 1e-9);
            assert!(fk.within_limits());
            // Counts agree with eq. 24 and map back to within half a count.
            let back = c.angles(&p.counts[k].map(|v| v as f64)).unwrap();
            assert!(back.iter().zip(q).all(|(a, b)| (a - b).abs() < 0.01f64.to_radians()));
        }
        for w in p.q.windows(2) {
            let jump = w[0].iter().zip(&w[1]).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            assert!(jump < 0.1, "joint jump of {jump} rad between neighbours");
        }
    }

    #[test]
    fn unreachable_points_are_named() {
        let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
        let c = Constants::named("factory").unwrap();
        let e = plan(&robot, &c, &[pt(0.3, 0.0, 0.3), pt(1.5, 0.0, 0.3)], &PlanOptions::default()).unwrap_err();
        let text = e.to_string();
        assert!(text.contains("point ") && text.contains("x 0.3"), "{text}");
        assert!(
            matches!(&e, Error::AtPathPoint { point: 1.., source, .. } if matches!(**source, Error::Kinematics(_) | Error::OutsideLimits { .. })),
            "{e:?}"
        );
        let e = plan(&robot, &c, &[pt(0.3, 0.0, f64::NAN)], &PlanOptions::default()).unwrap_err();
        assert!(
            matches!(&e, Error::NotFinite { what, value } if what == "point 1 of the path, z" && value.is_nan()),
            "{e:?}"
        );
        let e = plan(&robot, &c, &[], &PlanOptions::default()).unwrap_err();
        assert!(matches!(&e, Error::TooFew { got: 0, min: 1, .. }), "{e:?}");
        let opts = PlanOptions { max_step: 0.0, q0: None };
        let e = plan(&robot, &c, &[pt(0.3, 0.0, 0.3)], &opts).unwrap_err();
        assert!(matches!(&e, Error::OutOfRange { what, value, .. } if what == "max step" && *value == 0.0), "{e:?}");
        let opts = PlanOptions { max_step: 0.01, q0: Some(vec![0.0; 3]) };
        assert!(plan(&robot, &c, &[pt(0.3, 0.0, 0.3)], &opts).is_err());
    }
}
