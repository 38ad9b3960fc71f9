//! A work cell as an answer: each robot's placement, check and
//! manipulability, and each pair's closest approach.

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

/// The answer of `kinema cell --json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CellAnswer {
    /// The cell file.
    pub file: String,
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
}
