//! Capability maps (reachability): which tool poses an arm reaches, voxel by
//! voxel. The space around the robot is cut into cubes of a given edge; at
//! each cube's centre the tool is asked to take each of a fixed set of
//! orientations, and the map keeps how many of them some configuration
//! within the joint limits reaches (and, when the request carries an
//! admissibility test such as a scene's collision check, passes it). The
//! fraction per voxel is Zacharias, Borst and Hirzinger's *capability map*
//! ("Capturing robot workspace structure: representing robot capabilities",
//! IROS 2007), computed here with the IK request layer: the analytic family
//! where one fits, the numeric solver otherwise.

pub mod place;

use std::sync::atomic::{AtomicBool, Ordering};

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::error::{Error, InputError, Result};
use crate::ik::{registry, solve_target_with, IkRequest, IkTarget};
use crate::math::Pose;
use crate::model::JointType;
use crate::robot::Robot;

/// The centres of the voxels, edge `resolution` \[m\], that can hold a tool
/// point of `robot`: every multiple of `resolution` along x, y and z whose
/// cube meets the ball of [`reach_bound`] around the base. In z, y, x
/// order, so the same robot and resolution give the same list on every
/// machine (and a shard of it is a contiguous block).
pub fn voxel_centres(robot: &Robot, resolution: f64) -> Result<Vec<[f64; 3]>> {
    if !(resolution.is_finite() && resolution > 0.0) {
        return Err(Error::Input(InputError::OutOfRange {
            what: "resolution".into(),
            value: resolution,
            expected: "a positive voxel edge in metres".into(),
        }));
    }
    let centre = robot.base().pos;
    let radius = reach_bound(robot)? + resolution * 3f64.sqrt() / 2.0;
    // Counted in floating point first: a tiny edge must be refused, not overflow an integer.
    let cells = (radius / resolution).ceil() + 1.0;
    if !((2.0 * cells + 1.0).powi(3) <= MAX_GRID_CELLS) {
        return Err(Error::Input(InputError::OutOfRange {
            what: "resolution".into(),
            value: resolution,
            expected: format!(
                "a voxel edge giving at most {MAX_GRID_CELLS:e} cells around a reach of {radius:.3} m (e.g. {:.3} m or more)",
                2.0 * radius / MAX_GRID_CELLS.cbrt()
            ),
        }));
    }
    let cells = cells as i64;
    let index = |c: f64| (c / resolution).round() as i64;
    let (ix, iy, iz) = (index(centre.x), index(centre.y), index(centre.z));
    let mut centres = Vec::new();
    for k in iz - cells..=iz + cells {
        for j in iy - cells..=iy + cells {
            for i in ix - cells..=ix + cells {
                let p = Vector3::new(i as f64, j as f64, k as f64) * resolution;
                if (p - centre).norm() <= radius {
                    centres.push([p.x, p.y, p.z]);
                }
            }
        }
    }
    Ok(centres)
}

/// The most grid cells [`voxel_centres`] scans: about half are kept, 24 bytes
/// each, so a map holds at most a few hundred MB (a 2-cm grid around a 2-m arm
/// is 8·10⁶ cells).
const MAX_GRID_CELLS: f64 = 2e7;

/// A distance from the base origin no tool point of `robot` exceeds \[m\]:
/// the sum of the distances between successive frames along the chain at
/// `home` (a revolute joint keeps each of them; a prismatic joint adds its
/// largest travel from home).
pub fn reach_bound(robot: &Robot) -> Result<f64> {
    let frames = robot.link_frames(robot.home())?;
    let mut bound = 0.0;
    for pair in frames.windows(2) {
        bound += (pair[1].pos - pair[0].pos).norm();
    }
    for (joint, home) in robot.joints().iter().zip(robot.home()) {
        if joint.kind == JointType::Prismatic {
            let travel = (joint.limits.max - home).abs().max((joint.limits.min - home).abs());
            bound += if travel.is_finite() { travel } else { return Err(unbounded_slide(&joint.name)) };
        }
    }
    Ok(bound)
}

fn unbounded_slide(name: &str) -> Error {
    Error::Input(InputError::DoesNotFit {
        what: "robot".into(),
        reason: format!("prismatic joint `{name}` has no finite limits, so the reach has no bound"),
    })
}

/// `count` tool orientations spread uniformly over the rotations (seeded
/// random unit quaternions, Shoemake's construction), the same for a given
/// seed on every machine.
pub fn orientation_samples(count: usize, seed: u64) -> Vec<Matrix3<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..count)
        .map(|_| {
            let (u1, u2, u3): (f64, f64, f64) = (rng.random(), rng.random(), rng.random());
            let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
            let tau = std::f64::consts::TAU;
            let q = nalgebra::Quaternion::new(
                b * (tau * u3).cos(),
                a * (tau * u2).sin(),
                a * (tau * u2).cos(),
                b * (tau * u3).sin(),
            );
            *UnitQuaternion::from_quaternion(q).to_rotation_matrix().matrix()
        })
        .collect()
}

/// Whether some configuration within the joint limits reaches `target`
/// and passes the request's admissibility test: the request layer's answer
/// to a request for one solution (`request.all` is ignored), so an arm with
/// a self-motion searches it for one within the limits — a request for all
/// lists the closed form's solutions at one value of its parameter only. A
/// closed form's refusal is final ([`IkRequest::skip_closest`]): the numeric
/// look behind a refusal would cost most of a map's time on the voxels out of
/// reach. So the map is as complete as the robot's family (the closed forms
/// list every branch; a family that searches, such as `geo-general`, may
/// miss a pose the numeric solver would find).
pub fn reaches(
    robot: &Robot,
    family: Option<&dyn crate::ik::family::Family>,
    target: &Pose,
    request: &IkRequest,
) -> bool {
    let one = IkRequest { all: false, skip_closest: true, ..request.clone() };
    solve_target_with(robot, family, &IkTarget::Pose(*target), &one)
        .is_ok_and(|answer| answer.solutions.iter().any(|s| s.within_limits()))
}

/// For each voxel centre of `centres`, how many of `orientations` the tool
/// reaches there ([`reaches`]), computed on all cores. `done` is called once
/// per voxel (for a progress bar); `cancelled` is read between voxels, and
/// once it returns true the map stops with [`Error::Cancelled`].
pub fn capability_map(
    robot: &Robot,
    centres: &[[f64; 3]],
    orientations: &[Matrix3<f64>],
    request: &IkRequest,
    done: &(dyn Fn() + Sync),
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<u32>> {
    let family = registry::fit(robot);
    let stop = AtomicBool::new(false);
    let counts: Vec<Option<u32>> = centres
        .par_iter()
        .map(|c| {
            if stop.load(Ordering::Relaxed) || cancelled() {
                stop.store(true, Ordering::Relaxed);
                return None;
            }
            let position = Vector3::from(*c);
            let reached = orientations
                .iter()
                .filter(|rot| reaches(robot, family.as_deref(), &Pose::new(**rot, position), request))
                .count();
            done();
            Some(reached as u32)
        })
        .collect();
    counts.into_iter().collect::<Option<Vec<u32>>>().ok_or(Error::Cancelled)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_configuration_reaches_beyond_the_bound() {
        let mut rng = ChaCha8Rng::seed_from_u64(39);
        for name in crate::builtin_names() {
            let robot = Robot::builtin(name).unwrap();
            let bound = reach_bound(&robot).unwrap();
            let base = robot.base().pos;
            let mut farthest: f64 = 0.0;
            for _ in 0..20_000 {
                let q = robot.random_q(&mut rng);
                farthest = farthest.max((robot.fk(&q).unwrap().world_from_tool.pos - base).norm());
            }
            // Tight enough to matter: the arms stretch to most of it.
            assert!(farthest <= bound && farthest > 0.6 * bound, "{name}: {farthest} of {bound}");
        }
    }

    #[test]
    fn the_grid_is_deterministic_and_covers_the_ball() {
        let robot = Robot::builtin("puma560").unwrap();
        let centres = voxel_centres(&robot, 0.1).unwrap();
        assert_eq!(centres, voxel_centres(&robot, 0.1).unwrap());
        let bound = reach_bound(&robot).unwrap();
        let base = robot.base().pos;
        // Every voxel meeting the ball is listed: the voxel of any point within it.
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for _ in 0..2000 {
            let q = robot.random_q(&mut rng);
            let p = robot.fk(&q).unwrap().world_from_tool.pos;
            assert!((p - base).norm() <= bound);
            let cell = p.map(|v| (v / 0.1).round() * 0.1);
            assert!(centres.iter().any(|c| (Vector3::from(*c) - cell).norm() < 1e-9), "{p:?}");
        }
        for bad in [0.0, -0.1, f64::NAN, 1e-4, 1e-19, 2e-19, 1e-300, f64::MIN_POSITIVE] {
            assert!(voxel_centres(&robot, bad).unwrap_err().to_string().contains("resolution"), "{bad}");
        }
    }

    #[test]
    fn orientations_are_rotations_spread_over_the_sphere() {
        let rots = orientation_samples(256, 3);
        assert_eq!(rots, orientation_samples(256, 3));
        let mut mean_z = Vector3::zeros();
        for r in &rots {
            assert!((r.transpose() * r - Matrix3::identity()).norm() < 1e-12 && (r.determinant() - 1.0).abs() < 1e-12);
            mean_z += r.column(2);
        }
        // The approach axes of uniform rotations average to ~0 (|mean| ~ 1/√n).
        assert!((mean_z / 256.0).norm() < 0.2, "{mean_z:?}");
    }
}
