//! A cell played by the page (`kinema serve --cell`): several robots on a
//! common clock, sent once with every sample's link poses computed here, so
//! the page only places shapes.

use kinema::Robot;
use kinema_geometry::RobotGeometry;
use serde::Serialize;

use crate::api::MAX_SAMPLES;
use crate::error::{Error, Result};
use crate::shapes::GeometryAnswer;

/// One robot of a cell: its name in the cell, the robot placed on its base
/// in the cell's world, its link shapes and its joint values at every time
/// of the common clock.
#[derive(Debug, Clone)]
pub struct CellMotion {
    /// The member's name in the cell.
    pub name: String,
    /// The robot, its base transform placing it in the world frame.
    pub robot: Robot,
    /// Its link shapes (empty: the page draws rods between its frames).
    pub geometry: RobotGeometry,
    /// Its joint values at each time of the clock \[rad or m\].
    pub q: Vec<Vec<f64>>,
}

/// The answer of `GET /api/cell`: the clock and each member's motion.
#[derive(Debug, Serialize)]
pub struct CellAnswer {
    /// The common sample times \[s\] (empty when the server has no cell).
    pub times: Vec<f64>,
    /// The members.
    pub members: Vec<CellMemberAnswer>,
}

/// One member as the page draws it.
#[derive(Debug, Serialize)]
pub struct CellMemberAnswer {
    /// Its name in the cell.
    pub name: String,
    /// Its shapes in its link frames (as `GET /api/robots/{name}/geometry`).
    pub geometry: GeometryAnswer,
    /// Its joint values at each time.
    pub q: Vec<Vec<f64>>,
    /// At each time, its frames (base, links, tool) in the world frame, each
    /// as 12 numbers: the rotation's rows, then the position \[m\].
    pub frames: Vec<Vec<[f64; 12]>>,
}

impl CellAnswer {
    /// The answer for `members` sampled at `times`; refused (422) above
    /// [`MAX_SAMPLES`] robot samples.
    pub fn new(times: &[f64], members: &[CellMotion]) -> Result<CellAnswer> {
        let samples = times.len().saturating_mul(members.len());
        if samples > MAX_SAMPLES {
            return Err(Error::Unprocessable {
                message: format!(
                    "the cell has {samples} robot samples; the viewer plays at most {MAX_SAMPLES}: give a larger dt"
                ),
            });
        }
        let members = members.iter().map(|m| member(times, m)).collect::<Result<Vec<_>>>()?;
        Ok(CellAnswer { times: times.to_vec(), members })
    }
}

fn member(times: &[f64], m: &CellMotion) -> Result<CellMemberAnswer> {
    if m.q.len() != times.len() {
        return Err(Error::Unprocessable {
            message: format!("cell robot `{}` has {} samples for {} times", m.name, m.q.len(), times.len()),
        });
    }
    let mut frames = Vec::with_capacity(m.q.len());
    for q in &m.q {
        let poses = m.robot.link_frames(q)?;
        let flat = |p: &kinema::Pose| {
            let (r, t) = (&p.rot, &p.pos);
            [
                r[(0, 0)],
                r[(0, 1)],
                r[(0, 2)],
                r[(1, 0)],
                r[(1, 1)],
                r[(1, 2)],
                r[(2, 0)],
                r[(2, 1)],
                r[(2, 2)],
                t[0],
                t[1],
                t[2],
            ]
        };
        frames.push(poses.iter().map(flat).collect());
    }
    let geometry = GeometryAnswer::new(m.robot.name(), m.robot.dof(), None, Some(&m.geometry));
    Ok(CellMemberAnswer { name: m.name.clone(), geometry, q: m.q.clone(), frames })
}
