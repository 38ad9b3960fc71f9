//! The answers of `kinema scorbot … --json`. They describe this one arm's
//! encoders and controller, which no other door speaks of, so they live
//! beside the command rather than in `kinema-io`. Radians, metres, counts.

use kinema_scorbot::metrics::TrackingReport;
use serde::Serialize;

/// `kinema scorbot counts --json`: encoder counts of a configuration.
#[derive(Serialize)]
pub(super) struct CountsAnswer {
    pub constants: String,
    pub q: Vec<f64>,
    pub counts: [i64; 5],
    pub counts_exact: [f64; 5],
    pub tool_position: [f64; 3],
    /// The tool point's 1σ per axis from the constants' uncertainties \[m\].
    pub tool_sigma: [f64; 3],
    pub tool_sigma_radius: f64,
    pub out_of_limits: Vec<String>,
}

/// `kinema scorbot angles --json`: the configuration of encoder counts.
#[derive(Serialize)]
pub(super) struct AnglesAnswer {
    pub constants: String,
    pub counts: Vec<f64>,
    /// Joint values in `unit`.
    pub q: Vec<f64>,
    /// `rad` or `deg`.
    pub unit: &'static str,
    pub tool_position: [f64; 3],
    pub out_of_limits: Vec<String>,
}

/// `kinema scorbot follow --dry-run`: the counts a path would be sent as.
#[derive(Serialize)]
pub(super) struct FollowPlanAnswer {
    pub points: usize,
    pub counts: Vec<[i64; 5]>,
    pub branches: Vec<String>,
}

/// `kinema scorbot where --json`: where the controller says the arm is.
#[derive(Serialize)]
pub(super) struct WhereAnswer {
    pub counts: [i64; 5],
    pub q: [f64; 5],
    pub tool_position: [f64; 3],
    /// The controller's own X, Y, Z, pitch, roll (tenths of mm and degrees).
    pub controller_cartesian: Option<[i64; 5]>,
}

/// One joint model of the path experiment and how it tracked.
#[derive(Serialize)]
pub(super) struct ExperimentModel<'a> {
    pub label: &'a str,
    pub branch: &'a str,
    pub samples: Vec<usize>,
    pub report: &'a TrackingReport,
}

/// `kinema scorbot experiment --json` (seed 000 Fig. 6 on the simulator).
#[derive(Serialize)]
pub(super) struct ExperimentAnswer<'a> {
    pub path: String,
    pub desired_points: usize,
    pub true_constants: String,
    pub controller_constants: String,
    pub noise: f64,
    pub seed: u64,
    pub models: Vec<ExperimentModel<'a>>,
}
