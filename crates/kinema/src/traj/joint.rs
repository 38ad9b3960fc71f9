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
    /// solver started from the previous sample without restarts. Six-joint
    /// arms first try Newton tracking from the constant-velocity prediction
    /// of the sample (converged to 1e-12, within limits, a correction below
    /// 0.1): the same branch as the nearest closed-form solution (tested
    /// sample by sample) at a quarter of the cost; the closed form takes over
    /// wherever it does not converge cleanly (near singularities). Velocities
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
        Error::Unreachable { solver, reason, closest } => {
            Error::Unreachable { solver: format!("{solver}, at t = {t:.4} s of the path"), reason, closest }
        }
        e => Error::InvalidArgument { what: format!("path sample at t = {t:.4} s"), message: e.to_string() },
    }
}

/// Largest change of q3's rate \[rad/s²\] the iiwa's q3 rule asks for along a
/// path when the model gives joint 3 no acceleration limit: the rule
/// searches q3 around the constant-rate prediction within ±a·dt² per
/// decision, so q3 turns smoothly instead of reversing at full speed (seed
/// 004's rule alone maximises manipulability greedily and chatters).
pub const Q3_ACCELERATION: f64 = 5.0;

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
            closest: None,
        },
    )
}

/// Whether `q` reaches `target` within [`TRACK_TOL`].
fn reaches(robot: &Robot, q: &[f64], target: &Pose) -> Result<bool> {
    let e = pose_error(target, &robot.fk(q)?.pose);
    Ok(e.position_norm() <= TRACK_TOL && e.rotation_angle() <= TRACK_TOL)
}

/// Position \[m\] and orientation \[rad\] error at which Newton tracking has
/// converged: rounding level for arms of about a metre.
const NEWTON_TOL: f64 = 1e-12;
/// Newton steps tried per sample before falling back to the closed form.
const NEWTON_STEPS: usize = 3;
/// Largest correction \[rad or m, any joint\] Newton tracking may make to its
/// prediction: well above what a smooth path needs at any sensible sample
/// period, well below the distance between two inverse-kinematics branches
/// away from singularities. Larger corrections go to the closed form.
const NEWTON_MAX_CORRECTION: f64 = 0.1;

/// Newton tracking for six-joint arms: refines `q` (on entry the prediction
/// of the next sample, on exit the solution) onto `target` by Newton steps
/// on the pose error with the base-frame Jacobian, q ← q + J⁻¹·e. True when
/// it converged to [`NEWTON_TOL`] within [`NEWTON_STEPS`], each step at most
/// half the previous (quadratic convergence, not wandering near a
/// singularity) and the total correction within [`NEWTON_MAX_CORRECTION`]; the
/// caller still checks the joint limits.
fn newton_track(robot: &Robot, target: &Pose, q: &mut [f64], jac: &mut Matrix6xX<f64>) -> Result<bool> {
    let mut q0 = [0.0; 6];
    q0.copy_from_slice(q);
    let mut last_step = f64::INFINITY;
    for _ in 0..=NEWTON_STEPS {
        let fk = robot.jacobian_into(q, Frame::Base, jac)?;
        let e = pose_error(target, &fk.pose);
        if e.position_norm() <= NEWTON_TOL && e.rotation_angle() <= NEWTON_TOL {
            return Ok(true);
        }
        let j = Matrix6::from_column_slice(jac.as_slice());
        let rhs =
            Vector6::new(e.translation.x, e.translation.y, e.translation.z, e.rotation.x, e.rotation.y, e.rotation.z);
        let Some(dq) = j.lu().solve(&rhs) else { return Ok(false) };
        let step = dq.amax();
        if !(step <= 0.5 * last_step) {
            return Ok(false);
        }
        last_step = step;
        for (i, qi) in q.iter_mut().enumerate() {
            *qi += dq[i];
            if !((*qi - q0[i]).abs() <= NEWTON_MAX_CORRECTION) {
                return Ok(false);
            }
        }
    }
    Ok(false)
}

/// The constant-joint-velocity prediction of sample `k` from the samples
/// before it in `qs` (row-major, `n` joints) at the (possibly non-uniform)
/// `times`: 2·q_{k−1} − q_{k−2} for uniform steps, q_{k−1} for k = 1.
fn predict(qs: &[f64], times: &[f64], k: usize, n: usize, q: &mut [f64]) {
    let prev = &qs[(k - 1) * n..k * n];
    if k < 2 {
        q.copy_from_slice(prev);
        return;
    }
    let r = (times[k] - times[k - 1]) / (times[k - 1] - times[k - 2]);
    let before = &qs[(k - 2) * n..(k - 1) * n];
    for i in 0..n {
        q[i] = prev[i] + r * (prev[i] - before[i]);
    }
}

/// Shifts revolute joints of `q` by whole turns towards `prev` where the
/// shifted value is still within the joint's limits (a closed form returns
/// one representative of each angle; a joint with more than a turn of range
/// continues through ±π instead of jumping).
fn unwind(robot: &Robot, q: &mut [f64], prev: &[f64]) {
    use std::f64::consts::{PI, TAU};
    for ((j, qi), p) in robot.joints().iter().zip(q.iter_mut()).zip(prev) {
        if j.kind != crate::JointType::Revolute {
            continue;
        }
        let (lo, hi) = (j.limits.min, j.limits.max);
        while *qi - p > PI && *qi - TAU >= lo {
            *qi -= TAU;
        }
        while p - *qi > PI && *qi + TAU <= hi {
            *qi += TAU;
        }
    }
}

fn by_ik(robot: &Robot, motion: &CartesianMotion, q_start: &[f64], times: &[f64]) -> Result<JointTrajectory> {
    let n = robot.dof();
    let qs = if let Ok(ik) = IiwaIk::new(robot) {
        iiwa_path(robot, &ik, motion, q_start, times)?
    } else {
        generic_path(robot, motion, q_start, times, n == 6)?
    };
    JointTrajectory::from_positions(n, times.to_vec(), qs)
}

/// Any arm but the iiwa along a path, row-major joint values. With
/// `tracking` (six joints), each sample is first Newton-tracked from the
/// constant-velocity prediction 2·q_{k−1} − q_{k−2}; where that does not
/// converge cleanly or leaves the limits, and always without `tracking`, the
/// analytic solution nearest the previous sample (within limits, reaching
/// the pose) is taken, or the numeric solver's answer from the previous
/// sample for arms without a closed form and for redundant arms.
fn generic_path(
    robot: &Robot,
    motion: &CartesianMotion,
    q_start: &[f64],
    times: &[f64],
    tracking: bool,
) -> Result<Vec<f64>> {
    let n = robot.dof();
    // A redundant arm's closed form fixes its self-motion (the SRS solver's
    // q3 = 0), which would jump along the path; the numeric solver follows it.
    let analytic = if n <= 6 { ik::analytic_solver(robot) } else { None };
    let numeric = NumericIk::with_options(robot, NumericOptions { max_restarts: 0, ..NumericOptions::default() })?;
    let mut set = ik::CandidateSet::new();
    let mut order = Vec::with_capacity(16);
    let mut cands: Vec<f64> = Vec::with_capacity(16 * n);
    let mut jac = Matrix6xX::zeros(n);
    let mut q = vec![0.0; n];
    // One configuration after another (row-major).
    let mut qs: Vec<f64> = Vec::with_capacity(times.len() * n);
    qs.extend_from_slice(q_start);
    for (k, &t) in times.iter().enumerate().skip(1) {
        let target = motion.at(t).pose;
        let prev = &qs[(k - 1) * n..k * n];
        if tracking {
            predict(&qs, times, k, n, &mut q);
            if newton_track(robot, &target, &mut q, &mut jac)? && robot.limit_flags(&q).is_empty() {
                qs.extend_from_slice(&q);
                continue;
            }
        }
        if let Some(solver) = &analytic {
            // Every solution, each taken by whole turns towards the previous
            // sample where its limits allow; the nearest within limits that
            // reaches the pose.
            solver.candidates_into(&target, &mut set).map_err(|e| at_time(t, e))?;
            cands.clear();
            order.clear();
            for i in 0..set.len() {
                let at = cands.len();
                cands.extend_from_slice(set.q(i));
                unwind(robot, &mut cands[at..], prev);
                if robot.limit_flags(&cands[at..]).is_empty() {
                    order.push((ik::joint_distance(robot, &cands[at..], prev), at));
                }
            }
            order.sort_by(|a, b| a.0.total_cmp(&b.0));
            let mut found = None;
            for &(_, at) in &order {
                if reaches(robot, &cands[at..at + n], &target)? {
                    found = Some(at);
                    break;
                }
            }
            let at = found.ok_or_else(|| unreachable_orientation(t, solver.name()))?;
            q.copy_from_slice(&cands[at..at + n]);
        } else {
            q = numeric.solve_from(&target, prev).map_err(|e| at_time(t, e))?.q;
        }
        qs.extend_from_slice(&q);
    }
    Ok(qs)
}

/// The iiwa along a path: seed 004's q3 rule (q_k = f(q_{k−1}, T_k)) every
/// [`Q3_DECISION_PERIOD`], with q3's drift limited by its velocity limit and
/// every joint's step by its own and its rate's change by
/// [`Q3_ACCELERATION`]; in between, q3 interpolated (cubic Hermite) and the
/// closed-form solution nearest to the previous sample. (Newton tracking of
/// the other six joints with q3 held was tried: 9.9 ms instead of 8.6 ms for
/// the 10 s LIN at 1 kHz — the 7-joint Jacobian and a 6×6 LU cost more than
/// the closed form on the two branches that can continue the path.)
fn iiwa_path(robot: &Robot, ik: &IiwaIk, motion: &CartesianMotion, q_start: &[f64], times: &[f64]) -> Result<Vec<f64>> {
    let vmax = |i: usize| robot.joints()[i].limits.vel.unwrap_or(f64::INFINITY);
    let amax3 = robot.joints()[2].limits.acc.unwrap_or(Q3_ACCELERATION);
    // q3's rate at the last decision: the next q3 is searched around the
    // constant-rate prediction, within what Q3_ACCELERATION allows.
    // The decision and whether it came from the smooth (rate-continuing) search.
    let decide = |prev: &[f64], rate: f64, t: f64, dt: f64| -> Result<(Vec<f64>, bool)> {
        let st = motion.at(t);
        let dir = (st.vel.norm() > 1e-12).then_some(st.vel);
        // 80 % of each joint's velocity limit: the samples between decisions
        // do not move exactly linearly and must stay within the limit too.
        let steps: Vec<f64> = (0..7).map(|i| 0.8 * vmax(i) * dt).collect();
        let within = |q: &[f64]| q.iter().zip(prev).zip(&steps).all(|((a, b), m)| (a - b).abs() <= *m);
        // First around q3's constant-rate prediction, its rate changing by at
        // most amax3·dt: three grid points and the parabola through them.
        let window = (0.5 * vmax(2) * dt).min(amax3 * dt * dt).min(ik::iiwa::SELECT_WINDOW);
        let points = if window < ik::iiwa::SELECT_WINDOW { 3 } else { 21 };
        let smooth = ik.select_continuing(prev, prev[2] + rate * dt, &st.pose, dir.as_ref(), window, points, &steps);
        if let Ok(sol) = &smooth {
            if within(&sol.q) {
                return Ok((sol.q.clone(), true));
            }
        }
        // That would make another joint jump (a singularity ahead): search the
        // whole window q3's velocity limit allows around the present q3.
        let window = (0.5 * vmax(2) * dt).min(ik::iiwa::SELECT_WINDOW);
        let points = if window < ik::iiwa::SELECT_WINDOW { 5 } else { 21 };
        match ik.select_continuing(prev, prev[2], &st.pose, dir.as_ref(), window, points, &steps) {
            Ok(sol) => Ok((sol.q, false)),
            Err(e) => match smooth {
                Ok(sol) => Ok((sol.q, false)),
                Err(_) => Err(at_time(t, e)),
            },
        }
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
    let mut rate = 0.0;
    // Whether `q` can follow `prev` within the joints' velocity limits over `dt`.
    let fits = |q: &[f64], prev: &[f64], dt: f64| {
        q.iter().zip(prev).enumerate().all(|(i, (a, b))| (a - b).abs() <= vmax(i) * dt)
    };
    // The segment from the anchor sample `a` to the next decision sample.
    let mut a = 0usize;
    let mut next = 1usize;
    while next < decisions.len() {
        let b = decisions[next];
        let (q_b, smooth) = decide(&qs[7 * a..7 * a + 7], rate, times[b], times[b] - times[a])?;
        let (q3a, q3b) = (qs[7 * a + 2], q_b[2]);
        let mut reanchored = false;
        for k in a + 1..b {
            let t = times[k];
            let u = (t - times[a]) / (times[b] - times[a]);
            let target = motion.at(t).pose;
            let prev = &qs[7 * (k - 1)..7 * k];
            // After a smooth decision, a cubic Hermite from (q3a, rate) to (q3b,
            // secant): q3's rate is continuous at the decisions (each segment
            // ends at its secant slope, the next starts with it), so q̈3 stays
            // near Q3_ACCELERATION instead of being impulses at the decisions.
            // After an escape from a singularity (a wide-window decision), a
            // straight line, which cannot overshoot towards it.
            let linear = q3a + (q3b - q3a) * u;
            let hermite = if smooth {
                let h = u * u * (2.0 - u);
                q3a + (q3b - q3a) * h + (times[b] - times[a]) * rate * u * (1.0 - u) * (1.0 - u)
            } else {
                linear
            };
            let dt_k = t - times[k - 1];
            let mut found: Option<[f64; 7]> = None;
            for q3 in [hermite, linear] {
                // Only the branches that can continue the path through `prev`.
                let picked = ik.solve_q3_near(&target, q3, prev).ok().and_then(|c| {
                    c.write_into(&mut set);
                    set.nearest_within_limits(robot, prev)
                });
                if let Some(i) = picked {
                    if fits(set.q(i), prev, dt_k) && reaches(robot, set.q(i), &target)? {
                        found = Some(set.q(i).try_into().expect("7 joints"));
                        break;
                    }
                }
                if hermite == linear {
                    break;
                }
            }
            match found {
                Some(q) => qs.extend_from_slice(&q),
                // The planned q3 does not work here: decide at this sample and
                // plan the rest of the segment again from it.
                None => {
                    let (q, _) = decide(prev, rate, t, dt_k)?;
                    rate = (q[2] - prev[2]) / dt_k;
                    qs.extend_from_slice(&q);
                    a = k;
                    reanchored = true;
                    break;
                }
            }
        }
        if reanchored {
            continue;
        }
        let prev = &qs[7 * (b - 1)..7 * b];
        let dt_b = times[b] - times[b - 1];
        if fits(&q_b, prev, dt_b) {
            rate = (q_b[2] - q3a) / (times[b] - times[a]);
            qs.extend_from_slice(&q_b);
        } else {
            // The samples before it drifted from the plan: decide from the last one.
            let (q, _) = decide(prev, rate, times[b], dt_b)?;
            rate = (q[2] - prev[2]) / dt_b;
            qs.extend_from_slice(&q);
        }
        a = b;
        next += 1;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rpy_to_rot;
    use crate::traj::{check, Blend, CartesianLimits, CheckOptions, Orientation, Profile, Segment};
    use crate::RpyConvention;
    use nalgebra::Vector3;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn lin(a: &Pose, b: &Pose) -> CartesianMotion {
        let limits =
            CartesianLimits { vel: 0.3, acc: 0.8, jerk: Some(4.0), rot_vel: 0.8, rot_acc: 2.0, rot_jerk: Some(8.0) };
        let seg = Segment::lin(a, b, Orientation::Slerp).unwrap();
        CartesianMotion::new(vec![seg], Profile::SCurve, &limits, Blend::None).unwrap()
    }

    /// Newton tracking is another algorithm for the same quantity as the
    /// closed form's nearest branch: over random PUMA lines both give the
    /// same joint path, sample by sample.
    #[test]
    fn newton_tracking_equals_the_nearest_closed_form_branch() {
        let robot = Robot::builtin("puma560").unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(41);
        let (mut compared, mut samples) = (0, 0);
        while compared < 150 {
            let q_a: Vec<f64> =
                robot.joints().iter().map(|j| rng.random_range(0.8 * j.limits.min..0.8 * j.limits.max)).collect();
            let a = robot.fk(&q_a).unwrap().pose;
            let shift =
                Vector3::new(rng.random_range(-0.2..0.2), rng.random_range(-0.2..0.2), rng.random_range(-0.2..0.2));
            let turn = rpy_to_rot(
                [rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5)],
                RpyConvention::Zyx,
            );
            let b = Pose::new(a.rot * turn, a.pos + shift);
            let m = lin(&a, &b);
            let dt = if compared % 2 == 0 { 0.01 } else { 0.001 };
            let times = sample_times(m.duration(), dt).unwrap();
            let Ok(closed) = generic_path(&robot, &m, &q_a, &times, false) else { continue };
            // The closed-form path is only a reference where it has no jump (a
            // branch change near a singularity has no "same branch" answer).
            let traj = JointTrajectory::from_positions(6, times.clone(), closed.clone()).unwrap();
            if !check(&robot, &traj, &CheckOptions::default()).unwrap().violations.is_empty() {
                continue;
            }
            let tracked = generic_path(&robot, &m, &q_a, &times, true).unwrap();
            let worst = closed.iter().zip(&tracked).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
            assert!(worst < 1e-8, "path {compared}: tracked and closed-form paths differ by {worst:.3e} rad");
            compared += 1;
            samples += times.len();
        }
        assert!(samples > 50_000, "{samples}");
    }

    /// Wrist 3 of the PUMA turns ±266°: a path that takes it through ±180°
    /// continues smoothly with both methods instead of jumping by a turn.
    #[test]
    fn a_joint_with_more_than_a_turn_passes_through_pi() {
        let robot = Robot::builtin("puma560").unwrap();
        let q_a = [0.3, 0.6, -2.5, 0.2, 0.8, 2.9];
        let a = robot.fk(&q_a).unwrap().pose;
        let b = Pose::new(a.rot * rpy_to_rot([0.0, 0.0, 0.8], RpyConvention::Zyx), a.pos);
        let m = lin(&a, &b);
        let times = sample_times(m.duration(), 0.01).unwrap();
        for tracking in [false, true] {
            let qs = generic_path(&robot, &m, &q_a, &times, tracking).unwrap();
            let last = qs[qs.len() - 1];
            assert!(last > std::f64::consts::PI, "tracking {tracking}: q6 ends at {last}");
            let traj = JointTrajectory::from_positions(6, times.clone(), qs).unwrap();
            let report = check(&robot, &traj, &CheckOptions::default()).unwrap();
            assert!(report.violations.is_empty(), "tracking {tracking}: {}", report.violations[0]);
        }
    }
}
