//! Cartesian motions turned into joint trajectories: by inverse kinematics
//! at every sample with continuity, or by resolved-rate integration.

use nalgebra::{Matrix6, Matrix6xX, Vector6};

use super::cart::CartesianMotion;
use super::self_motion::{self, Plan, SelfMotion};
use super::{sample_times, JointTrajectory};
use crate::error::{Error, InputError, Result};
use crate::ik::{self, CandidateSet, NumericIk, NumericOptions};
use crate::kin::Frame;
use crate::math::{pose_error, Pose};
use crate::robot::Robot;

/// How a Cartesian motion becomes joint values.
#[derive(Debug, Clone, PartialEq)]
pub enum JointMethod {
    /// Inverse kinematics at every sample, the self-motion of a redundant
    /// arm chosen by the [`SelfMotion`] policy: the robot's closed form when
    /// it has one (every solution, the one nearest the previous sample within
    /// limits and reaching the pose), else the numeric solver started from
    /// the previous sample without restarts. Six-joint arms first refine the
    /// constant-velocity prediction of the sample by Newton steps
    /// (converged to 1e-12, within limits, a correction below 0.1): the same
    /// branch as the nearest closed-form solution (tested sample by sample)
    /// at a quarter of the cost; the closed form takes over wherever it does
    /// not converge cleanly (near singularities). Velocities and
    /// accelerations are second-order finite differences of the samples.
    Ik(SelfMotion),
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

impl JointMethod {
    /// Resolved rate with the gains every door uses: damping λ = 0.01 and
    /// half the pose error fed back per step.
    pub const RESOLVED_RATE: JointMethod = JointMethod::ResolvedRate { damping: 0.01, gain: 0.5 };

    /// The method named `ik` (with `self_motion`) or `rate` (with
    /// [`JointMethod::RESOLVED_RATE`]'s gains), as every door writes it.
    pub fn named(name: &str, self_motion: SelfMotion) -> crate::Result<JointMethod> {
        match name.trim().to_ascii_lowercase().as_str() {
            "ik" => Ok(JointMethod::Ik(self_motion)),
            "rate" => Ok(JointMethod::RESOLVED_RATE),
            _ => Err(crate::Error::Input(crate::InputError::UnknownName {
                what: "method".into(),
                name: name.trim().into(),
                known: "ik, rate".into(),
            })),
        }
    }
}

impl Default for JointMethod {
    /// IK at every sample with the robot's default self-motion policy.
    fn default() -> Self {
        JointMethod::Ik(SelfMotion::Auto)
    }
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
    check_times(times)?;
    let start = motion.at(0.0).pose;
    let e = pose_error(&start, &robot.fk(q_start)?.world_from_tool);
    if e.position_norm() > TRACK_TOL || e.rotation_angle() > TRACK_TOL {
        return Err(Error::Input(InputError::DoesNotFit {
            what: "q_start".into(),
            reason: format!(
                "the start configuration does not reach the motion's start pose (off by {:.3e} m, {:.3e} rad)",
                e.position_norm(),
                e.rotation_angle()
            ),
        }));
    }
    let times = times.to_vec();
    match method {
        JointMethod::Ik(policy) => by_ik(robot, motion, q_start, &times, &policy),
        JointMethod::ResolvedRate { damping, gain } => resolved_rate(robot, motion, q_start, &times, damping, gain),
    }
}

/// `e` located at the path sample of time `t`.
pub(super) fn at_time(t: f64, e: Error) -> Error {
    Error::OnPath { t, source: Box::new(e) }
}

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

/// Every candidate of a sample leaves a joint limit: which joints, per candidate.
fn outside_limits(robot: &Robot, t: f64, solver: &str, set: &CandidateSet) -> Error {
    let rejected = (0..set.len())
        .map(|i| {
            let joints: Vec<String> = robot.limit_flags(set.q(i)).indices().map(|j| format!("q{}", j + 1)).collect();
            format!("{} ({})", set.branch(i), joints.join(", "))
        })
        .collect();
    at_time(
        t,
        Error::Unreachable { solver: solver.into(), reason: ik::Unreachable::JointLimits { rejected }, closest: None },
    )
}

/// Whether `q` reaches `target` within [`TRACK_TOL`].
pub(super) fn reaches(robot: &Robot, q: &[f64], target: &Pose) -> Result<bool> {
    let e = pose_error(target, &robot.fk(q)?.world_from_tool);
    Ok(e.position_norm() <= TRACK_TOL && e.rotation_angle() <= TRACK_TOL)
}

/// Position \[m\] and orientation \[rad\] error at which Newton refinement has
/// converged: rounding level for arms of about a metre.
const NEWTON_TOL: f64 = 1e-12;
/// Newton steps tried per sample before falling back to the closed form.
const NEWTON_STEPS: usize = 3;
/// Largest correction \[rad or m, any joint\] Newton refinement may make to its
/// prediction: well above what a smooth path needs at any sensible sample
/// period, well below the distance between two inverse-kinematics branches
/// away from singularities. Larger corrections go to the closed form.
const NEWTON_MAX_CORRECTION: f64 = 0.1;

/// Newton refinement for six-joint arms: refines `q` (on entry the prediction
/// of the next sample, on exit the solution) onto `target` by Newton steps
/// on the pose error with the base-frame Jacobian, q ← q + J⁻¹·e. True when
/// it converged to [`NEWTON_TOL`] within [`NEWTON_STEPS`], each step at most
/// half the previous (quadratic convergence, not wandering near a
/// singularity) and the total correction within [`NEWTON_MAX_CORRECTION`]; the
/// caller still checks the joint limits.
fn newton_refine(robot: &Robot, target: &Pose, q: &mut [f64], jac: &mut Matrix6xX<f64>) -> Result<bool> {
    let mut q0 = [0.0; 6];
    q0.copy_from_slice(q);
    let mut last_step = f64::INFINITY;
    for _ in 0..=NEWTON_STEPS {
        let fk = crate::kin::jacobian_into(robot, q, Frame::Base, jac)?;
        let e = pose_error(target, &fk.world_from_tool);
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

fn by_ik(
    robot: &Robot,
    motion: &CartesianMotion,
    q_start: &[f64],
    times: &[f64],
    policy: &SelfMotion,
) -> Result<JointTrajectory> {
    let family = ik::registry::fit(robot);
    let redundancy = family.as_deref().and_then(|f| f.redundancy());
    let plan = self_motion::plan(robot, redundancy, policy, q_start)?;
    let held = follow(robot, &plan, motion, q_start, times);
    // The default holds the self-motion where that path passes the check,
    // else takes seed 004's rule when its path does.
    if let (SelfMotion::Auto, Some(family)) = (policy, redundancy) {
        if !passes(robot, &held) {
            let steered = Plan::Steered { family, objective: self_motion::Objective::Manipulability };
            let rule = follow(robot, &steered, motion, q_start, times);
            if passes(robot, &rule) {
                return rule;
            }
        }
    }
    held
}

/// Whether a converted path exists and passes [`super::check`] with the default options.
fn passes(robot: &Robot, traj: &Result<JointTrajectory>) -> bool {
    traj.as_ref()
        .is_ok_and(|t| super::check(robot, t, &super::CheckOptions::default()).is_ok_and(|r| r.violations.is_empty()))
}

/// The joint path of `plan` along `motion`.
fn follow(
    robot: &Robot,
    plan: &Plan,
    motion: &CartesianMotion,
    q_start: &[f64],
    times: &[f64],
) -> Result<JointTrajectory> {
    let n = robot.dof();
    let qs = match *plan {
        Plan::None => match ik::analytic_solver(robot) {
            Some(solver) => {
                let closed = |target: &Pose, _: &[f64], set: &mut CandidateSet| solver.candidates_into(target, set);
                generic_path(robot, motion, q_start, times, n == 6, Some((&closed, solver.name())))?
            }
            None => generic_path(robot, motion, q_start, times, n == 6, None)?,
        },
        Plan::Numeric => generic_path(robot, motion, q_start, times, false, None)?,
        Plan::Held { family, parameter, value } => {
            let held = |target: &Pose, prev: &[f64], set: &mut CandidateSet| {
                family.continue_at(target, parameter, value, prev, set)
            };
            let name = format!("{parameter} held at {value:.6}");
            generic_path(robot, motion, q_start, times, false, Some((&held, &name)))?
        }
        Plan::Steered { family, objective } => {
            self_motion::steered_path(robot, family, objective, motion, q_start, times)?
        }
    };
    JointTrajectory::from_positions(n, times.to_vec(), qs)
}

/// The closed-form candidates of a sample (target, previous sample, out)
/// and a name for errors.
type ClosedCandidates<'a> = (&'a dyn Fn(&Pose, &[f64], &mut CandidateSet) -> Result<()>, &'a str);

/// A path sample by sample, row-major joint values. With `newton_first` (six
/// joints), each sample is first Newton-refined from the constant-velocity
/// prediction 2·q_{k−1} − q_{k−2}; where that does not converge cleanly or
/// leaves the limits, and always without `newton_first`, the `closed` candidate
/// nearest the previous sample (within limits, reaching the pose) is taken,
/// or without `closed` the numeric solver's answer from the previous sample.
fn generic_path(
    robot: &Robot,
    motion: &CartesianMotion,
    q_start: &[f64],
    times: &[f64],
    newton_first: bool,
    closed: Option<ClosedCandidates>,
) -> Result<Vec<f64>> {
    let n = robot.dof();
    let numeric = NumericIk::with_options(robot, NumericOptions { max_restarts: 0, ..NumericOptions::default() })?;
    let mut set = CandidateSet::new();
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
        if newton_first {
            predict(&qs, times, k, n, &mut q);
            if newton_refine(robot, &target, &mut q, &mut jac)? && ik::settle_on_limits(robot, &mut q).is_empty() {
                qs.extend_from_slice(&q);
                continue;
            }
        }
        if let Some((candidates, name)) = closed {
            // Every solution, each taken by whole turns towards the previous
            // sample where its limits allow; the nearest within limits that
            // reaches the pose.
            candidates(&target, prev, &mut set).map_err(|e| at_time(t, e))?;
            cands.clear();
            order.clear();
            for i in 0..set.len() {
                let at = cands.len();
                cands.extend_from_slice(set.q(i));
                // (A value past a limit by rounding is moved onto it.)
                if ik::nearest_turns(robot, &mut cands[at..], prev).is_empty() {
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
            let at = match found {
                Some(at) => at,
                None if order.is_empty() && !set.is_empty() => return Err(outside_limits(robot, t, name, &set)),
                None => return Err(unreachable_orientation(t, name)),
            };
            q.copy_from_slice(&cands[at..at + n]);
        } else {
            q = numeric.solve_from(&target, prev).map_err(|e| at_time(t, e))?.q;
        }
        qs.extend_from_slice(&q);
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

/// Sample times start at 0, are finite and increase strictly.
fn check_times(times: &[f64]) -> Result<()> {
    let Some(&first) = times.first() else {
        return Err(Error::Input(InputError::TooFew {
            what: "times".into(),
            got: 0,
            min: 1,
            of: "sample times".into(),
        }));
    };
    if first != 0.0 {
        return Err(Error::Input(InputError::OutOfRange {
            what: "times[0]".into(),
            value: first,
            expected: "0 (sample times start at 0 and increase strictly)".into(),
        }));
    }
    if let Some(k) = times.iter().position(|t| !t.is_finite()) {
        return Err(Error::Input(InputError::NotFinite { what: format!("times[{k}]"), value: times[k] }));
    }
    if let Some(k) = times.windows(2).position(|w| !(w[1] > w[0])) {
        return Err(Error::Input(InputError::OutOfRange {
            what: format!("times[{}]", k + 1),
            value: times[k + 1],
            expected: format!("more than times[{k}] = {} (sample times increase strictly)", times[k]),
        }));
    }
    Ok(())
}

fn resolved_rate(
    robot: &Robot,
    motion: &CartesianMotion,
    q_start: &[f64],
    times: &[f64],
    damping: f64,
    gain: f64,
) -> Result<JointTrajectory> {
    if !(damping >= 0.0 && damping.is_finite()) {
        return Err(Error::Input(InputError::OutOfRange {
            what: "damping".into(),
            value: damping,
            expected: "a finite number ≥ 0".into(),
        }));
    }
    if !(gain > 0.0 && gain <= 1.0) {
        return Err(Error::Input(InputError::OutOfRange {
            what: "gain".into(),
            value: gain,
            expected: "a number in (0, 1]".into(),
        }));
    }
    let n = robot.dof();
    let mut jac = Matrix6xX::zeros(n);
    let mut q = q_start.to_vec();
    let mut traj = JointTrajectory::reserved(n, times.len())?;
    let mut rates: Vec<f64> = Vec::with_capacity(times.len() * n);
    let mut qs: Vec<Vec<f64>> = Vec::with_capacity(times.len());
    for (k, &t) in times.iter().enumerate() {
        let st = motion.at(t);
        let fk = crate::kin::jacobian_into(robot, &q, Frame::Base, &mut jac)?;
        let step = if k + 1 < times.len() { times[k + 1] - t } else { times[k] - times[k.saturating_sub(1)] };
        let e = pose_error(&st.pose, &fk.world_from_tool);
        let fb = if step > 0.0 { gain / step } else { 0.0 };
        let twist = Vector6::from_iterator(
            (st.vel + e.translation * fb).iter().chain((st.omega + e.rotation * fb).iter()).copied(),
        );
        let jjt = &jac * jac.transpose() + Matrix6::identity() * (damping * damping);
        let y = jjt.lu().solve(&twist).ok_or_else(|| Error::Infeasible {
            what: "damping".into(),
            reason: format!("J·Jᵀ is singular at t = {t:.4} s; use a positive damping"),
        })?;
        let qd: Vec<f64> = (jac.transpose() * y).iter().copied().collect();
        qs.push(q.clone());
        rates.extend_from_slice(&qd);
        for i in 0..n {
            q[i] += qd[i] * step;
        }
        if q.iter().any(|v| !v.is_finite()) {
            return Err(Error::Infeasible {
                what: "resolved rate".into(),
                reason: format!("the integration diverged at t = {t:.4} s (near a singularity?)"),
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
    (0..traj.len()).map(|k| robot.fk(traj.q(k)).map(|f| f.world_from_tool)).collect()
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

    /// [`generic_path`] with the robot's closed form.
    fn closed_form_path(
        robot: &Robot,
        m: &CartesianMotion,
        q: &[f64],
        times: &[f64],
        newton_first: bool,
    ) -> Result<Vec<f64>> {
        let solver = ik::analytic_solver(robot).unwrap();
        let closed = |target: &Pose, _: &[f64], set: &mut CandidateSet| solver.candidates_into(target, set);
        generic_path(robot, m, q, times, newton_first, Some((&closed, solver.name())))
    }

    fn lin(a: &Pose, b: &Pose) -> CartesianMotion {
        let limits =
            CartesianLimits { vel: 0.3, acc: 0.8, jerk: Some(4.0), rot_vel: 0.8, rot_acc: 2.0, rot_jerk: Some(8.0) };
        let seg = Segment::lin(a, b, Orientation::Slerp).unwrap();
        CartesianMotion::new(vec![seg], Profile::SCurve, &limits, Blend::None).unwrap()
    }

    /// Newton refinement is another algorithm for the same quantity as the
    /// closed form's nearest branch: over random PUMA lines both give the
    /// same joint path, sample by sample.
    #[test]
    fn newton_refinement_equals_the_nearest_closed_form_branch() {
        let robot = Robot::builtin("puma560").unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(41);
        let (mut compared, mut samples) = (0, 0);
        while compared < 150 {
            let q_a: Vec<f64> =
                robot.joints().iter().map(|j| rng.random_range(0.8 * j.limits.min..0.8 * j.limits.max)).collect();
            let a = robot.fk(&q_a).unwrap().world_from_tool;
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
            let Ok(closed) = closed_form_path(&robot, &m, &q_a, &times, false) else { continue };
            // The closed-form path is only a reference where it has no jump (a
            // branch change near a singularity has no "same branch" answer).
            let traj = JointTrajectory::from_positions(6, times.clone(), closed.clone()).unwrap();
            if !check(&robot, &traj, &CheckOptions::default()).unwrap().violations.is_empty() {
                continue;
            }
            let tracked = closed_form_path(&robot, &m, &q_a, &times, true).unwrap();
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
        let a = robot.fk(&q_a).unwrap().world_from_tool;
        let b = Pose::new(a.rot * rpy_to_rot([0.0, 0.0, 0.8], RpyConvention::Zyx), a.pos);
        let m = lin(&a, &b);
        let times = sample_times(m.duration(), 0.01).unwrap();
        for newton_first in [false, true] {
            let qs = closed_form_path(&robot, &m, &q_a, &times, newton_first).unwrap();
            let last = qs[qs.len() - 1];
            assert!(last > std::f64::consts::PI, "newton_first {newton_first}: q6 ends at {last}");
            let traj = JointTrajectory::from_positions(6, times.clone(), qs).unwrap();
            let report = check(&robot, &traj, &CheckOptions::default()).unwrap();
            assert!(report.violations.is_empty(), "newton_first {newton_first}: {}", report.violations[0]);
        }
    }
}
