//! A work cell as an answer: each robot's placement, check and
//! manipulability, and each pair's closest approach.

use kinema::traj::{CellReport, CheckReport};
use kinema::{Pose, RpyConvention};
use kinema_geometry::BodyApproach;
use serde::Serialize;

use crate::traj::{CheckAnswer, TimedValue};

/// Where a robot's base sits in the cell.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Placement {
    /// Translation \[m\].
    pub xyz: [f64; 3],
    /// Roll, pitch, yaw \[rad\] (zyx).
    pub rpy: [f64; 3],
}

/// The smallest and largest manipulability along a robot's motion.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ManipRange {
    /// The smallest value and when.
    pub min: TimedValue,
    /// The largest value and when.
    pub max: TimedValue,
}

/// One robot of a cell.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CellRobot {
    /// Its name in the cell.
    pub name: String,
    /// The robot as the cell file names it.
    pub robot: String,
    /// Its number of joints.
    pub dof: usize,
    /// The trajectory CSV it follows, if it follows one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub trajectory: Option<String>,
    /// The program it runs, if it runs one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub program: Option<String>,
    /// Its base placement.
    pub base: Placement,
    /// When its own motion ends \[s\].
    pub end: f64,
    /// Its trajectory check.
    pub check: CheckAnswer,
    /// Its translational manipulability's extremes.
    pub manipulability: ManipRange,
}

/// A time span \[s\].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Span {
    /// Start \[s\].
    pub from: f64,
    /// End \[s\].
    pub to: f64,
}

/// The closest approach of two tool points.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ClosestApproach {
    /// When \[s\].
    pub t: f64,
    /// How close \[m\].
    pub distance: f64,
}

/// Two robots of a cell: how close their tools come.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CellPair {
    /// The two robots' names.
    pub robots: [String; 2],
    /// Their closest approach.
    pub closest: ClosestApproach,
    /// With a minimum distance: whether they keep it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ok: Option<bool>,
    /// With a minimum distance: when they come closer.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub closer_than_minimum: Option<Vec<Span>>,
}

/// How close the bodies (link shapes) of two robots, or of a robot and the
/// scene's obstacles, come over the run, between samples too.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CellBodies {
    /// The two robots' names; the second is `scene` for the obstacles.
    pub robots: [String; 2],
    /// The closest approach of their shapes (0: in contact).
    pub closest: ClosestApproach,
    /// The closest shapes: `robot/link`, or the obstacle's name.
    pub links: [String; 2],
    /// Whether they stay apart (distance above 0).
    pub ok: bool,
}

/// The answer of `kinema cell --json` (and of Python's `CellReport.to_dict`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CellAnswer {
    /// The cell file (none for a cell built in Python).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// The common duration \[s\].
    pub duration: f64,
    /// The common sample period \[s\].
    pub dt: f64,
    /// The number of common samples.
    pub samples: usize,
    /// The minimum tool distance asked for \[m\], if any.
    pub min_distance: Option<f64>,
    /// Whether every robot's check passes and every pair keeps the minimum distance.
    pub ok: bool,
    /// The robots.
    pub robots: Vec<CellRobot>,
    /// The pairs.
    pub pairs: Vec<CellPair>,
    /// How close the robots' link shapes come to each other and to the
    /// scene's obstacles (when the robots have shapes).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub bodies: Vec<CellBodies>,
}

/// What a door knows of one robot of a cell besides the core's report.
#[derive(Debug, Clone)]
pub struct CellMember<'a> {
    /// Its name in the cell.
    pub name: &'a str,
    /// The robot as the cell names it (a built-in name or a file).
    pub robot: &'a str,
    /// Its number of joints.
    pub dof: usize,
    /// The trajectory CSV it follows, if it follows one from a file.
    pub trajectory: Option<String>,
    /// The program file it runs, if it runs one.
    pub program: Option<String>,
    /// Where its base sits in the cell's world.
    pub base: &'a Pose,
    /// Its trajectory check.
    pub check: &'a CheckReport,
}

impl CellAnswer {
    /// The answer for the core's `report` of a cell whose robots are
    /// `members` (in the report's order), run every `dt` seconds with an
    /// optional minimum tool distance \[m\]; `file`: the cell file, if any.
    pub fn new(
        file: Option<String>,
        dt: f64,
        min_distance: Option<f64>,
        members: &[CellMember<'_>],
        report: &CellReport,
    ) -> CellAnswer {
        let robots: Vec<CellRobot> = members
            .iter()
            .enumerate()
            .map(|(m, member)| {
                let manip = &report.manipulability[m];
                let at = |k: usize| TimedValue { t: report.times[k], value: manip[k] };
                let kmin = (0..manip.len()).min_by(|x, y| manip[*x].total_cmp(&manip[*y])).unwrap_or(0);
                let kmax = (0..manip.len()).max_by(|x, y| manip[*x].total_cmp(&manip[*y])).unwrap_or(0);
                let b = member.base;
                CellRobot {
                    name: member.name.to_string(),
                    robot: member.robot.to_string(),
                    dof: member.dof,
                    trajectory: member.trajectory.clone(),
                    program: member.program.clone(),
                    // `+ 0.0`: no negative zeros in the angles.
                    base: Placement {
                        xyz: [b.pos.x, b.pos.y, b.pos.z],
                        rpy: b.rpy(RpyConvention::Zyx).map(|v| v + 0.0),
                    },
                    end: report.ends[m],
                    check: CheckAnswer::new(member.check),
                    manipulability: ManipRange { min: at(kmin), max: at(kmax) },
                }
            })
            .collect();
        let pairs: Vec<CellPair> = report
            .approaches()
            .iter()
            .map(|ap| {
                let (i, j) = ap.pair;
                let spans = min_distance.map(|min| report.closer_than(i, j, min));
                CellPair {
                    robots: [members[i].name.to_string(), members[j].name.to_string()],
                    closest: ClosestApproach { t: ap.time, distance: ap.distance },
                    ok: spans.as_ref().map(Vec::is_empty),
                    closer_than_minimum: spans.map(|s| s.iter().map(|&(from, to)| Span { from, to }).collect()),
                }
            })
            .collect();
        CellAnswer {
            file,
            duration: report.times.last().copied().unwrap_or(0.0),
            dt,
            samples: report.times.len(),
            min_distance,
            ok: members.iter().all(|m| m.check.violations.is_empty()) && pairs.iter().all(|p| p.ok.unwrap_or(true)),
            robots,
            pairs,
            bodies: Vec::new(),
        }
    }

    /// The answer with the closest approaches of the robots' bodies (robots
    /// by index into `names`, the cell's robots in order); `ok` turns false
    /// when two bodies touch.
    pub fn with_bodies(mut self, names: &[&str], approaches: &[BodyApproach]) -> CellAnswer {
        self.bodies = approaches
            .iter()
            .map(|ap| {
                let (i, j) = ap.robots;
                CellBodies {
                    robots: [names[i].to_string(), j.map_or("scene", |j| names[j]).to_string()],
                    closest: ClosestApproach { t: ap.time, distance: ap.distance },
                    links: [ap.closest.0.clone(), ap.closest.1.clone()],
                    ok: ap.distance > 0.0,
                }
            })
            .collect();
        self.ok &= self.bodies.iter().all(|b| b.ok);
        self
    }
}
