//! Cartesian motions turned into joint trajectories: by inverse kinematics
//! at every sample with continuity, or by resolved-rate integration.

use nalgebra::{Matrix6, Matrix6xX, Vector6};

use super::cart::CartesianMotion;
use super::{sample_times, JointTrajectory};
use crate::error::{Error, Result};
use crate::ik::iiwa::IiwaIk;
use crate::ik::{self, NumericIk, NumericOptions};
use crate::kin::Frame;
use crate::math::{pose_error, Pose};
use crate::model::Robot;

/// How a Cartesian motion becomes joint values.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum JointMethod {
    /// Inverse kinematics at every sample: the robot's analytic solver when it
    /// has one (every solution, the one nearest the previous sample within
    /// limits and reaching the pose; for the iiwa the q3 selection rule of
    /// seed 004 §V-E, q_k = f(q_{k−1}, T_k), with the direction of motion,
    /// applied every [`Q3_DECISION_PERIOD`] with q3 interpolated between), else the numeric
    /// solver started from the previous sample without restarts. Velocities
    /// and accelerations are second-order finite differences of the samples.
    #[default]
    Ik,
    /// Resolved rate (what seed 004 used for its joint velocity plots):
    /// q̇ = J⁺(ẋ_d + k·e) with the damped pseudo-inverse J⁺ = Jᵀ(JJᵀ + λ²I)⁻¹,
    /// integrated with the sample period; e is the pose error and k =
    /// `gain`/dt.
    ResolvedRate {
        /// Damping λ.
        damping: f64,
        /// Error feedback per step, in (0, 1].
        gain: f64,
    },
}

/// Largest position \[m\] and orientation \[rad\] residual accepted from IK.
const TRACK_TOL: f64 = 1e-6;

/// Samples `motion` every `dt` \[s\] and converts it to joint values of
/// `robot`, starting from `q_start` (which must reach the motion's start pose
/// within 1e-6 m / 1e-6 rad). The result is not checked; see
/// [`super::check`].
///
/// Errors: `q_start` wrong or not at the start pose; a sample the IK cannot
/// reach (its time and the reason); for the 5-DOF arms, a path whose
/// orientation they cannot follow.
pub fn to_joints(
    robot: &Robot,
    motion: &CartesianMotion,
    q_start: &[f64],
    dt: f64,
    method: JointMethod,
) -> Result<JointTrajectory> {
    let times = sample_times(motion.duration(), dt)?;
    to_joints_at(robot, motion, q_start, &times, method)
}

/// As [`to_joints`], at the given increasing sample times (e.g. from
/// [`CartesianMotion::resample_times`], so consecutive poses are at most a
/// given distance apart, as seed 000 sent its controller).
pub fn to_joints_at(
    robot: &Robot,
    motion: &CartesianMotion,
    q_start: &[f64],
    times: &[f64],
    method: JointMethod,
) -> Result<JointTrajectory> {
    robot.check_q(q_start)?;
    if times.first() != Some(&0.0) || times.windows(2).any(|w| !(w[1] > w[0])) || times.iter().any(|t| !t.is_finite()) {
        return Err(Error::InvalidArgument {
            what: "times".into(),
            message: "sample times must start at 0 and increase strictly".into(),
        });
    }
    let start = motion.at(0.0).pose;
    let e = pose_error(&start, &robot.fk(q_start)?.pose);
    if e.position_norm() > TRACK_TOL || e.rotation_angle() > TRACK_TOL {
        return Err(Error::InvalidArgument {
            what: "q_start".into(),
            message: format!(
                "the start configuration does not reach the motion's start pose (off by {:.3e} m, {:.3e} rad)",
                e.position_norm(),
                e.rotation_angle()
            ),
        });
    }
    let times = times.to_vec();
    match method {
        JointMethod::Ik => by_ik(robot, motion, q_start, &times),
        JointMethod::ResolvedRate { damping, gain } => resolved_rate(robot, motion, q_start, &times, damping, gain),
    }
}

fn at_time(t: f64, e: Error) -> Error {
    match e {
        Error::Unreachable { solver, reason } => {
            Error::Unreachable { solver: format!("{solver}, at t = {t:.4} s of the path"), reason }
        }
        e => Error::InvalidArgument { what: format!("path sample at t = {t:.4} s"), message: e.to_string() },
    }
}

/// Period \[s\] at which the iiwa's q3 rule decides q3 along a path; between
/// decisions q3 is interpolated linearly and each sample is one closed-form
/// solve (the rule costs ~20 solves, a sample one).
pub const Q3_DECISION_PERIOD: f64 = 0.02;

fn unreachable_orientation(t: f64, solver: &str) -> Error {
    at_time(
        t,
        Error::Unreachable {
            solver: solver.into(),
            reason: ik::Unreachable::Orientation {
                angle: f64::NAN,
                detail: "no solution reaches this pose of the path exactly (the arm cannot take its orientation)"
                    .into(),
            },
        },
    )
}

/// Whether `q` reaches `target` within [`TRACK_TOL`].
fn reaches(robot: &Robot, q: &[f64], target: &Pose) -> Result<bool> {
    let e = pose_error(target, &robot.fk(q)?.pose);
    Ok(e.position_norm() <= TRACK_TOL && e.rotation_angle() <= TRACK_TOL)
}

fn by_ik(robot: &Robot, motion: &CartesianMotion, q_start: &[f64], times: &[f64]) -> Result<JointTrajectory> {
    let n = robot.dof();
    let qs = if let Ok(ik) = IiwaIk::new(robot) {
        iiwa_path(robot, &ik, motion, q_start, times)?
    } else {
        let analytic = ik::analytic_solver(robot);
        let numeric = NumericIk::with_options(robot, NumericOptions { max_restarts: 0, ..NumericOptions::default() })?;
        let mut set = ik::CandidateSet::new();
        let mut order = Vec::with_capacity(16);
        // One configuration after another (row-major).
        let mut qs: Vec<f64> = Vec::with_capacity(times.len() * n);
        qs.extend_from_slice(q_start);
        for &t in &times[1..] {
            let target = motion.at(t).pose;
            let prev = &qs[qs.len() - n..];
            if let Some(solver) = &analytic {
                // Every solution; the nearest within limits that reaches the pose.
                solver.candidates_into(&target, &mut set).map_err(|e| at_time(t, e))?;
                order.clear();
                order.extend(
                    (0..set.len())
                        .filter(|&i| robot.limit_flags(set.q(i)).is_empty())
                        .map(|i| (ik::joint_distance(robot, set.q(i), prev), i)),
                );
                order.sort_by(|a, b| a.0.total_cmp(&b.0));
                let mut found = None;
                for &(_, i) in &order {
                    if reaches(robot, set.q(i), &target)? {
                        found = Some(i);
                        break;
                    }
                }
                let i = found.ok_or_else(|| unreachable_orientation(t, solver.name()))?;
                qs.extend_from_slice(set.q(i));
            } else {
                let q = numeric.solve_from(&target, prev).map_err(|e| at_time(t, e))?.q;
                qs.extend_from_slice(&q);
            }
        }
        qs
    };
    JointTrajectory::from_positions(n, times.to_vec(), qs)
}

/// The iiwa along a path: seed 004's q3 rule (q_k = f(q_{k−1}, T_k)) every
/// [`Q3_DECISION_PERIOD`], with q3's drift limited by its velocity limit and
/// every joint's step by its own; in between, q3 interpolated and the
/// closed-form solution nearest to the previous sample.
fn iiwa_path(robot: &Robot, ik: &IiwaIk, motion: &CartesianMotion, q_start: &[f64], times: &[f64]) -> Result<Vec<f64>> {
    let vmax = |i: usize| robot.joints()[i].limits.vel.unwrap_or(f64::INFINITY);
    let decide = |prev: &[f64], t: f64, dt: f64| -> Result<Vec<f64>> {
        let st = motion.at(t);
        let dir = (st.vel.norm() > 1e-12).then_some(st.vel);
        let window = (0.5 * vmax(2) * dt).min(ik::iiwa::SELECT_WINDOW);
        // 80 % of each joint's velocity limit: the samples between decisions
        // do not move exactly linearly and must stay within the limit too.
        let steps: Vec<f64> = (0..7).map(|i| 0.8 * vmax(i) * dt).collect();
        // A small window needs few grid points to follow the manipulability gradient.
        let points = if window < ik::iiwa::SELECT_WINDOW { 5 } else { 21 };
        Ok(ik.select_continuing(prev, &st.pose, dir.as_ref(), window, points, &steps).map_err(|e| at_time(t, e))?.q)
    };
    // Decision samples: every sample at coarse periods, else about every Q3_DECISION_PERIOD.
    let mut decisions = vec![0usize];
    for k in 1..times.len() {
        if times[k] - times[*decisions.last().expect("non-empty")] >= Q3_DECISION_PERIOD - 1e-12 || k + 1 == times.len()
        {
            decisions.push(k);
        }
    }
    let mut qs: Vec<f64> = Vec::with_capacity(times.len() * 7);
    qs.extend_from_slice(q_start);
    let mut set = ik::CandidateSet::new();
    for w in decisions.windows(2) {
        let (a, b) = (w[0], w[1]);
        let q_b = decide(&qs[7 * a..7 * a + 7], times[b], times[b] - times[a])?;
        let (q3a, q3b) = (qs[7 * a + 2], q_b[2]);
        for k in a + 1..b {
            let t = times[k];
            let u = (t - times[a]) / (times[b] - times[a]);
            let target = motion.at(t).pose;
            let prev = &qs[7 * (k - 1)..7 * k];
            // Only the branches that can continue the path through `prev`.
            let picked = ik.solve_q3_near(&target, q3a + u * (q3b - q3a), prev).ok().and_then(|c| {
                c.write_into(&mut set);
                set.nearest_within_limits(robot, prev)
            });
            match picked {
                Some(i) if reaches(robot, set.q(i), &target)? => {
                    let q: [f64; 7] = set.q(i).try_into().expect("7 joints");
                    qs.extend_from_slice(&q);
                }
                // The interpolated q3 does not work here: decide at this sample.
                _ => {
                    let q = decide(prev, t, t - times[k - 1])?;
                    qs.extend_from_slice(&q);
                }
            }
        }
        qs.extend_from_slice(&q_b);
    }
    Ok(qs)
}

/// First and second derivatives at sample `k` of the positions `q` (`dof`
/// values per time in `t`, row-major) from the three nearest samples
/// (Lagrange interpolation on non-uniform times, second order; 0 for a single
/// sample, the difference quotient for two).
pub fn derivatives(t: &[f64], q: &[f64], dof: usize, k: usize, qd: &mut [f64], qdd: &mut [f64]) {
    let row = |k: usize| &q[k * dof..(k + 1) * dof];
    if t.len() < 3 {
        qd.fill(0.0);
        qdd.fill(0.0);
        if t.len() == 2 {
            for (i, v) in qd.iter_mut().enumerate() {
                *v = (row(1)[i] - row(0)[i]) / (t[1] - t[0]);
            }
        }
        return;
    }
    let c = k.clamp(1, t.len() - 2);
    let (x0, x1, x2) = (t[c - 1], t[c], t[c + 1]);
    let x = t[k];
    // Derivatives of the Lagrange basis polynomials at x.
    let d = [
        (2.0 * x - x1 - x2) / ((x0 - x1) * (x0 - x2)),
        (2.0 * x - x0 - x2) / ((x1 - x0) * (x1 - x2)),
        (2.0 * x - x0 - x1) / ((x2 - x0) * (x2 - x1)),
    ];
    let dd = [2.0 / ((x0 - x1) * (x0 - x2)), 2.0 / ((x1 - x0) * (x1 - x2)), 2.0 / ((x2 - x0) * (x2 - x1))];
    let (qa, qb, qc) = (row(c - 1), row(c), row(c + 1));
    for i in 0..qd.len() {
        let (a, b, e) = (qa[i], qb[i], qc[i]);
        qd[i] = d[0] * a + d[1] * b + d[2] * e;
        qdd[i] = dd[0] * a + dd[1] * b + dd[2] * e;
    }
}

fn resolved_rate(
    robot: &Robot,
    motion: &CartesianMotion,
    q_start: &[f64],
    times: &[f64],
    damping: f64,
    gain: f64,
) -> Result<JointTrajectory> {
    if !(damping >= 0.0 && damping.is_finite() && gain > 0.0 && gain <= 1.0) {
        return Err(Error::InvalidArgument {
            what: "resolved rate".into(),
            message: format!("damping {damping} must be ≥ 0 and gain {gain} in (0, 1]"),
        });
    }
    let n = robot.dof();
    let mut jac = Matrix6xX::zeros(n);
    let mut q = q_start.to_vec();
    let mut traj = JointTrajectory::with_capacity(n, times.len());
    let mut rates: Vec<f64> = Vec::with_capacity(times.len() * n);
    let mut qs: Vec<Vec<f64>> = Vec::with_capacity(times.len());
    for (k, &t) in times.iter().enumerate() {
        let st = motion.at(t);
        let fk = robot.jacobian_into(&q, Frame::Base, &mut jac)?;
        let step = if k + 1 < times.len() { times[k + 1] - t } else { times[k] - times[k.saturating_sub(1)] };
        let e = pose_error(&st.pose, &fk.pose);
        let fb = if step > 0.0 { gain / step } else { 0.0 };
        let twist = Vector6::from_iterator(
            (st.vel + e.translation * fb).iter().chain((st.omega + e.rotation * fb).iter()).copied(),
        );
        let jjt = &jac * jac.transpose() + Matrix6::identity() * (damping * damping);
        let y = jjt.lu().solve(&twist).ok_or_else(|| Error::InvalidArgument {
            what: "damping".into(),
            message: format!("J·Jᵀ is singular at t = {t:.4} s; use a positive damping"),
        })?;
        let qd: Vec<f64> = (jac.transpose() * y).iter().copied().collect();
        qs.push(q.clone());
        rates.extend_from_slice(&qd);
        for i in 0..n {
            q[i] += qd[i] * step;
        }
        if q.iter().any(|v| !v.is_finite()) {
            return Err(Error::InvalidArgument {
                what: "resolved rate".into(),
                message: format!("the integration diverged at t = {t:.4} s (near a singularity?)"),
            });
        }
    }
    let mut qdd = vec![0.0; n];
    let mut scratch = vec![0.0; n];
    for k in 0..times.len() {
        derivatives(times, &rates, n, k, &mut qdd, &mut scratch);
        traj.push(times[k], &qs[k], &rates[k * n..(k + 1) * n], &qdd)?;
    }
    Ok(traj)
}

/// The tool pose of every sample of `traj` (for comparing a joint trajectory with its path).
pub fn poses(robot: &Robot, traj: &JointTrajectory) -> Result<Vec<Pose>> {
    (0..traj.len()).map(|k| robot.fk(traj.q(k)).map(|f| f.pose)).collect()
}
