//! Trajectories as answers: what a planned motion is (its summary), a
//! trajectory check's report and a time law.

use kinema::traj::{BoundaryPtp, CheckReport, Expr, Profile, Ptp, TimeLaw, Violation};
use kinema::Robot;
use serde::Serialize;

/// A point of a Cartesian path the robot cannot take, left out.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SkippedPoint {
    /// Its index among the waypoints given.
    pub index: usize,
    /// Its position \[m\].
    pub position: [f64; 3],
    /// Why the inverse kinematics refused it.
    pub reason: String,
}

impl SkippedPoint {
    /// The answer for the core's skipped waypoint.
    pub fn new(p: &kinema::traj::waypoints::SkippedPoint) -> SkippedPoint {
        SkippedPoint { index: p.index, position: [p.pose.pos.x, p.pose.pos.y, p.pose.pos.z], reason: p.reason.clone() }
    }
}

/// One joint's expression of an expression trajectory.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointExpression {
    /// The joint, counting from 1.
    pub joint: usize,
    /// The expression as written.
    pub expr: String,
}

/// What a planned trajectory is, without its samples: the answer of
/// `kinema traj … --json` (which adds the sample rows when they go to
/// standard output) and, with the samples, of `POST /api/traj`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrajSummary {
    /// The robot's name.
    pub robot: String,
    /// `ptp`, `cartesian` (LIN, CIRC, a path) or `expression`.
    pub motion: &'static str,
    /// The time law's name.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub profile: Option<String>,
    /// The planned duration \[s\].
    pub duration: f64,
    /// The number of samples.
    pub samples: usize,
    /// PTP: the phase times of the time law \[s\]; `null` for a PTP between
    /// moving states without a common law.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub phase_times: Option<Option<Vec<f64>>>,
    /// PTP between moving states: each joint's phase times \[s\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub joint_phase_times: Option<Vec<Vec<f64>>>,
    /// Cartesian: when each segment starts \[s\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub segment_starts: Option<Vec<f64>>,
    /// Cartesian: how long each pair of segments overlaps \[s\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub blend_times: Option<Vec<f64>>,
    /// Cartesian: the waypoints left out.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub skipped: Option<Vec<SkippedPoint>>,
    /// Expression trajectories: each joint's expression.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub expressions: Option<Vec<JointExpression>>,
    /// A planned motion around obstacles: its path and how it was found.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plan: Option<PlanAnswer>,
}

/// How a collision-free motion was found ([`kinema_geometry::plan::Plan`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlanAnswer {
    /// The path's via points, start first \[rad, m\].
    pub via_points: Vec<Vec<f64>>,
    /// Via points of the search's path before shortening.
    pub found_via_points: usize,
    /// Goal configurations aimed at (a pose goal's IK solutions).
    pub goals: usize,
    /// Search iterations (0: the straight segment was free).
    pub iterations: usize,
    /// Configurations in both search trees.
    pub nodes: usize,
    /// The path's length \[joint-space norm\].
    pub length: f64,
    /// Planning time \[s\].
    pub planning_time: f64,
    /// Segments checked for collision.
    pub segments_checked: u64,
    /// Configurations the spheres were placed at.
    pub sphere_checks: u64,
    /// Intervals the spheres could not clear, decided on the exact shapes.
    pub exact_checks: u64,
}

impl PlanAnswer {
    /// The answer for `plan`.
    pub fn new(plan: &kinema_geometry::plan::Plan) -> PlanAnswer {
        PlanAnswer {
            via_points: plan.path.clone(),
            found_via_points: plan.found_via_points,
            goals: plan.goals,
            iterations: plan.iterations,
            nodes: plan.nodes,
            length: plan.length(),
            planning_time: plan.elapsed.as_secs_f64(),
            segments_checked: plan.counts.segments,
            sphere_checks: plan.counts.sphere_checks,
            exact_checks: plan.counts.exact_checks,
        }
    }
}

impl TrajSummary {
    /// A summary of `motion` on `robot` with nothing but its law's name,
    /// duration and sample count; the motion's own fields are set by the caller.
    pub fn new(
        robot: &Robot,
        motion: &'static str,
        profile: Option<&str>,
        duration: f64,
        samples: usize,
    ) -> TrajSummary {
        TrajSummary {
            robot: robot.name().to_string(),
            motion,
            profile: profile.map(str::to_string),
            duration,
            samples,
            phase_times: None,
            joint_phase_times: None,
            segment_starts: None,
            blend_times: None,
            skipped: None,
            expressions: None,
            plan: None,
        }
    }

    /// The summary of a point-to-point motion: its shared law's name and phase times.
    pub fn ptp(robot: &Robot, plan: &Ptp, samples: usize) -> TrajSummary {
        let law = plan.law();
        TrajSummary {
            phase_times: Some(Some(law.phase_times().to_vec())),
            ..TrajSummary::new(robot, "ptp", Some(law.profile().name()), plan.duration(), samples)
        }
    }

    /// The summary of a point-to-point motion between moving states planned
    /// with `profile`: each joint's phase times, and the common law's when
    /// the motion has one (`null` otherwise).
    pub fn boundary_ptp(robot: &Robot, plan: &BoundaryPtp, profile: Profile, samples: usize) -> TrajSummary {
        TrajSummary {
            phase_times: Some(plan.rest().map(|p| p.law().phase_times().to_vec())),
            joint_phase_times: Some(plan.laws().iter().map(|l| l.phase_times()).collect()),
            ..TrajSummary::new(robot, "ptp", Some(profile.name()), plan.duration(), samples)
        }
    }

    /// The summary of joint curves given by expressions of t (`exprs`: the
    /// joint, counting from 0, and its expression) over `duration` \[s\].
    pub fn expression(robot: &Robot, exprs: &[(usize, Expr)], duration: f64, samples: usize) -> TrajSummary {
        TrajSummary {
            expressions: Some(
                exprs.iter().map(|(j, e)| JointExpression { joint: j + 1, expr: e.text().to_string() }).collect(),
            ),
            ..TrajSummary::new(robot, "expression", None, duration, samples)
        }
    }

    /// The summary of a Cartesian motion under `profile`: its segment starts and blend times.
    pub fn cartesian(
        robot: &Robot,
        motion: &kinema::traj::CartesianMotion,
        profile: Profile,
        samples: usize,
        skipped: &[kinema::traj::waypoints::SkippedPoint],
    ) -> TrajSummary {
        TrajSummary {
            segment_starts: Some(motion.segment_starts().to_vec()),
            blend_times: Some(motion.blend_times()),
            skipped: Some(skipped.iter().map(SkippedPoint::new).collect()),
            ..TrajSummary::new(robot, "cartesian", Some(profile.name()), motion.duration(), samples)
        }
    }
}

/// A value at a time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TimedValue {
    /// The time \[s\].
    pub t: f64,
    /// The value.
    pub value: f64,
}

/// One finding of a trajectory check.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ViolationAnswer {
    /// What kind (`position`, `velocity`, …).
    pub kind: &'static str,
    /// When \[s\].
    pub t: f64,
    /// At which sample.
    pub sample: usize,
    /// Which joint, counting from 1 (none for a whole-robot finding).
    pub joint: Option<usize>,
    /// The value found.
    pub value: f64,
    /// The limit it breaks.
    pub limit: f64,
    /// The finding in words.
    pub message: String,
    /// What else there is to say (for a collision: the pair).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub detail: Option<String>,
}

impl ViolationAnswer {
    fn new(v: &Violation) -> ViolationAnswer {
        ViolationAnswer {
            kind: v.kind.name(),
            t: v.time,
            sample: v.sample,
            joint: v.joint.map(|j| j + 1),
            value: v.value,
            limit: v.limit,
            message: v.to_string(),
            detail: v.detail.clone(),
        }
    }
}

/// A trajectory check's report (`kinema traj check --json`, and per robot in
/// `kinema cell --json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CheckAnswer {
    /// The number of samples.
    pub samples: usize,
    /// Whether nothing breaks a limit.
    pub ok: bool,
    /// Largest |q̇| per joint.
    pub peak_velocity: Vec<f64>,
    /// Largest |q̈| per joint.
    pub peak_acceleration: Vec<f64>,
    /// Largest |q⃛| per joint.
    pub peak_jerk: Vec<f64>,
    /// The smallest manipulability and when, when asked for.
    pub min_manipulability: Option<TimedValue>,
    /// What breaks a limit.
    pub violations: Vec<ViolationAnswer>,
    /// What deserves a look but breaks no limit.
    pub warnings: Vec<ViolationAnswer>,
}

impl CheckAnswer {
    /// The answer for the core's report.
    pub fn new(report: &CheckReport) -> CheckAnswer {
        CheckAnswer {
            samples: report.samples,
            ok: report.violations.is_empty(),
            peak_velocity: report.peak_vel.clone(),
            peak_acceleration: report.peak_acc.clone(),
            peak_jerk: report.peak_jerk.clone(),
            min_manipulability: report.min_manipulability.map(|(t, value)| TimedValue { t, value }),
            violations: report.violations.iter().map(ViolationAnswer::new).collect(),
            warnings: report.warnings.iter().map(ViolationAnswer::new).collect(),
        }
    }
}

/// A time law sampled: the columns `t, p, v, a, j` and a row per sample.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LawSamples {
    /// `["t", "p", "v", "a", "j"]`.
    pub columns: [&'static str; 5],
    /// t \[s\], position, velocity, acceleration and jerk per sample.
    pub rows: Vec<[f64; 5]>,
}

/// A one-dimensional time law over a distance (`kinema traj law --json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LawAnswer {
    /// The law's name.
    pub profile: &'static str,
    /// The distance covered (1 for a law of given duration).
    pub distance: f64,
    /// Its duration \[s\].
    pub duration: f64,
    /// Its phase times \[s\].
    pub phase_times: Vec<f64>,
    /// The largest velocity; `null` if unbounded.
    pub peak_velocity: Option<f64>,
    /// The largest acceleration; `null` if unbounded.
    pub peak_acceleration: Option<f64>,
    /// The largest jerk; `null` if unbounded.
    pub peak_jerk: Option<f64>,
    /// Trapezoid: the acceleration phase \[s\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t_acc: Option<f64>,
    /// Trapezoid: the cruise phase \[s\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t_cruise: Option<f64>,
    /// Trapezoid: the deceleration phase \[s\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t_dec: Option<f64>,
    /// S-curve: the first jerk phase \[s\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t_jerk: Option<f64>,
    /// The law sampled, when a sample period was given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub samples: Option<LawSamples>,
}

impl LawAnswer {
    /// The answer for `law` covering `distance` (its peaks and samples scaled
    /// by it); `dt`: also the law sampled every `dt` seconds.
    pub fn new(law: &TimeLaw, distance: f64, dt: Option<f64>) -> kinema::Result<LawAnswer> {
        let peaks = law.peaks();
        let finite = |v: f64| Some(v * distance).filter(|_| v.is_finite());
        let phases = law.phase_times();
        let (mut t_acc, mut t_cruise, mut t_dec, mut t_jerk) = (None, None, None, None);
        match law.profile() {
            Profile::Trapezoid => {
                t_acc = Some(phases.first().copied().unwrap_or(0.0));
                t_cruise = Some(if phases.len() == 3 { phases[1] } else { 0.0 });
                t_dec = Some(phases.last().copied().unwrap_or(0.0));
            }
            // Phases: jerk, constant acceleration, jerk, cruise, … (zero-length ones omitted).
            Profile::SCurve => t_jerk = Some(phases.first().copied().unwrap_or(0.0)),
            _ => {}
        }
        let samples = match dt {
            Some(dt) => {
                let rows = kinema::traj::sample_times(law.duration(), dt)?
                    .iter()
                    .map(|&t| {
                        let s = law.at(t);
                        [t, s.s * distance, s.sd * distance, s.sdd * distance, s.sddd * distance]
                    })
                    .collect();
                Some(LawSamples { columns: ["t", "p", "v", "a", "j"], rows })
            }
            None => None,
        };
        Ok(LawAnswer {
            profile: law.profile().name(),
            distance,
            duration: law.duration(),
            phase_times: phases.to_vec(),
            peak_velocity: finite(peaks.sd),
            peak_acceleration: finite(peaks.sdd),
            peak_jerk: finite(peaks.sddd),
            t_acc,
            t_cruise,
            t_dec,
            t_jerk,
            samples,
        })
    }
}
