//! The check every generated trajectory goes through, and `kinema traj
//! check` runs on a CSV: limits on q, q̇, q̈ and q⃛, jumps (with or without
//! limits: `branch_jump.rs`), derivative
//! columns that q itself contradicts, and singular passages.
//!
//! The derivative checks need no model of how the samples were made: over a
//! step h, the secant (q_k − q_{k−1})/h is the mean of q̇ over the step, so
//! with |q̈| ≤ A each end's q̇ lies within A·h/2 of it; the second divided
//! difference of q is a weighted mean of q̈ (a non-negative kernel of unit
//! mass), so it is within A too; and the secant of q̈ is the mean of q⃛,
//! within the jerk limit when q̈ is continuous, as a jerk limit requires.

use super::{joint_limits, JointTrajectory};
use crate::analysis::{rows, yoshikawa, Axes};
use crate::error::{Error, InputError, Result};
pub use crate::error::{Violation, ViolationKind};
use crate::ik::{Admissible, Rejection};
use crate::kin::Frame;
use crate::robot::Robot;

/// The inverse condition number σ_min/σ_max of the Jacobian below which
/// `kinema traj check` reports a singular passage (a warning, not a
/// violation): there a tool speed of 1 m/s or rad/s needs joint speeds about
/// 1 000 times larger in some direction than in another.
pub const SINGULAR_WARNING: f64 = 1e-3;

/// Extra room on the derivative-consistency bound A·h/2, for derivatives
/// estimated by finite differences rather than given exactly.
const CONSISTENCY_SLACK: f64 = 0.05;

/// Options of [`check`].
#[derive(Debug, Clone)]
pub struct CheckOptions<'a> {
    /// Relative slack on every limit (rounding), default 1e-9.
    pub tolerance: f64,
    /// Velocity limits to use instead of the robot's (1 or dof values).
    pub vel: Option<Vec<f64>>,
    /// Acceleration limits to use instead of the robot's (1 or dof values).
    pub acc: Option<Vec<f64>>,
    /// Jerk limits to use instead of the robot's (1 or dof values).
    pub jerk: Option<Vec<f64>>,
    /// Report samples whose Yoshikawa manipulability is below this value.
    pub min_manipulability: Option<f64>,
    /// The Jacobian rows that manipulability uses: all six by default (zero
    /// at every singularity of a 6+-joint arm), or the translation rows as in
    /// seed 004 Fig. 30/33 (for 5-joint arms, whose full measure is always 0).
    pub manipulability_axes: Axes,
    /// Report singular passages (the Jacobian's inverse condition number
    /// below this value) as warnings; off by default, as it costs a
    /// singular value decomposition per sample. `kinema traj check` uses
    /// [`SINGULAR_WARNING`].
    pub singular_warning: Option<f64>,
    /// How finely the joint values and their derivatives are known (half the
    /// last printed digit of a CSV: 5e-13 for kinema's 12 decimals; 0 for
    /// values computed in memory): the derivative checks allow for it.
    pub value_resolution: f64,
    /// The same for the times (5e-10 for kinema's 9 decimals).
    pub time_resolution: f64,
    /// A test every configuration of the motion must pass (a scene's
    /// collision check), at the samples and on the straight joint-space
    /// steps between them.
    pub admissible: Option<&'a dyn Admissible>,
}

impl Default for CheckOptions<'_> {
    fn default() -> Self {
        CheckOptions {
            tolerance: 1e-9,
            vel: None,
            acc: None,
            jerk: None,
            min_manipulability: None,
            manipulability_axes: Axes::All,
            singular_warning: None,
            value_resolution: 0.0,
            time_resolution: 0.0,
            admissible: None,
        }
    }
}

/// What [`check`] measured and found.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckReport {
    /// Number of samples.
    pub samples: usize,
    /// Largest |q̇| per joint.
    pub peak_vel: Vec<f64>,
    /// Largest |q̈| per joint.
    pub peak_acc: Vec<f64>,
    /// Largest |q⃛| per joint (the secant of q̈ over each step).
    pub peak_jerk: Vec<f64>,
    /// (time, value) of the smallest manipulability, when asked for.
    pub min_manipulability: Option<(f64, f64)>,
    /// Everything that is wrong, in sample order (then joint, then kind:
    /// malformed, position, velocity, jump, branch jump, acceleration,
    /// inconsistent, jerk, near-singular), one per sample, joint and kind.
    pub violations: Vec<Violation>,
    /// What deserves a look but breaks no limit (singular passages: one per
    /// passage, at its most singular sample).
    pub warnings: Vec<Violation>,
}

impl CheckReport {
    /// The report if nothing is wrong, else an [`Error::Trajectory`].
    pub fn into_result(self) -> Result<CheckReport> {
        if self.violations.is_empty() {
            return Ok(self);
        }
        Err(Error::Trajectory {
            count: self.violations.len(),
            first: self.violations[0].to_string(),
            violations: self.violations,
        })
    }
}

/// Checks a joint trajectory of `robot` (seed 004 checked its curves by eye;
/// this does it for every sample): position limits; velocity, acceleration
/// and jerk limits (the robot's, or those of `opts`) on the given q̇, q̈ and
/// on what q itself implies (see the module documentation); jumps between
/// consecutive samples larger than the velocity limit allows over their time
/// step; branch jumps, limits or not: steps in which the joints move far
/// while the tool barely moves (see `branch_jump.rs`; not repeated where a
/// joint already jumps past its velocity limit); non-finite values or
/// non-increasing times; with
/// `opts.min_manipulability`, closeness to singularities (Yoshikawa's
/// measure on `opts.manipulability_axes`); with `opts.singular_warning`,
/// singular passages as warnings. A joint without a limit is not checked
/// for it.
///
/// Errors only for a trajectory of the wrong joint count or bad options;
/// violations are listed in the report.
pub fn check(robot: &Robot, traj: &JointTrajectory, opts: &CheckOptions) -> Result<CheckReport> {
    let n = robot.dof();
    if traj.dof() != n {
        return Err(Error::Input(InputError::JointCount {
            robot: robot.name().to_string(),
            expected: n,
            got: traj.dof(),
        }));
    }
    let js = robot.joints();
    let vel = joint_limits(robot, opts.vel.as_deref(), "vmax", |i| js[i].limits.vel)?;
    let acc = joint_limits(robot, opts.acc.as_deref(), "amax", |i| js[i].limits.acc)?;
    let jerk = joint_limits(robot, opts.jerk.as_deref(), "jmax", |i| js[i].limits.jerk)?;
    let slack = 1.0 + opts.tolerance;
    let mut report = CheckReport {
        samples: traj.len(),
        peak_vel: vec![0.0; n],
        peak_acc: vec![0.0; n],
        peak_jerk: vec![0.0; n],
        min_manipulability: None,
        violations: Vec::new(),
        warnings: Vec::new(),
    };
    let mut jac = nalgebra::Matrix6xX::zeros(n);
    for k in 0..traj.len() {
        let t = traj.times()[k];
        let (q, qd, qdd) = (traj.q(k), traj.qd(k), traj.qdd(k));
        let v = |kind, joint, value, limit| Violation { kind, sample: k, time: t, joint, value, limit, detail: None };
        let prev_t = if k > 0 { traj.times()[k - 1] } else { f64::NEG_INFINITY };
        if !finite(traj, k) || t <= prev_t {
            let bad = q.iter().chain(qd).chain(qdd).copied().find(|x| !x.is_finite()).unwrap_or(t);
            report.violations.push(v(ViolationKind::Malformed, None, bad, prev_t));
            continue;
        }
        for i in 0..n {
            let l = js[i].limits;
            let pos_tol = opts.tolerance * (1.0 + l.max.abs().max(l.min.abs()).min(1e6));
            if q[i] < l.min - pos_tol || q[i] > l.max + pos_tol {
                let bound = if q[i] < l.min { l.min } else { l.max };
                report.violations.push(v(ViolationKind::Position, Some(i), q[i], bound));
            }
            report.peak_vel[i] = report.peak_vel[i].max(qd[i].abs());
            report.peak_acc[i] = report.peak_acc[i].max(qdd[i].abs());
            if let Some(vl) = vel[i] {
                if qd[i].abs() > vl * slack {
                    report.violations.push(v(ViolationKind::Velocity, Some(i), qd[i], vl));
                }
                if k > 0 && prev_t.is_finite() {
                    let step = q[i] - traj.q(k - 1)[i];
                    let allowed = vl * (t - prev_t) * slack + 1e-12;
                    if step.abs() > allowed {
                        report.violations.push(v(ViolationKind::Jump, Some(i), step, allowed));
                    }
                }
            }
            if let Some(al) = acc[i] {
                if qdd[i].abs() > al * slack {
                    report.violations.push(v(ViolationKind::Acceleration, Some(i), qdd[i], al));
                }
            }
        }
        if let Some(th) = opts.min_manipulability {
            crate::kin::jacobian_into(robot, q, Frame::Base, &mut jac)?;
            let m = yoshikawa(&jac, opts.manipulability_axes)?;
            if report.min_manipulability.is_none_or(|(_, best)| m < best) {
                report.min_manipulability = Some((t, m));
            }
            if m < th {
                report.violations.push(v(ViolationKind::NearSingular, None, m, th));
            }
        }
    }
    let jumped: std::collections::HashSet<usize> =
        report.violations.iter().filter(|v| v.kind == ViolationKind::Jump).map(|v| v.sample).collect();
    report.violations.extend(super::branch_jump::branch_jumps(robot, traj, |k| jumped.contains(&k))?);
    let resolution = Resolution { value: opts.value_resolution, time: opts.time_resolution };
    check_steps(traj, &acc, &jerk, opts.tolerance, resolution, &mut report);
    if let Some(th) = opts.singular_warning {
        report.warnings = singular_passages(robot, traj, th, opts.manipulability_axes)?;
    }
    if let Some(test) = opts.admissible {
        report.violations.extend(rejections_along(traj, test)?);
    }
    // In sample order, then joint, then kind; one violation per (sample, joint,
    // kind): the given derivative's before what q implies.
    report.violations.sort_by_key(|v| (v.sample, v.joint, v.kind.rank()));
    let mut seen = std::collections::HashSet::new();
    report.violations.retain(|v| seen.insert((v.sample, v.joint, v.kind)));
    Ok(report)
}

/// `Ok` when `test` admits every configuration of `traj`, at its samples
/// and on the straight joint-space steps between them; else an
/// [`Error::Trajectory`] listing where each refused stretch begins (what
/// [`check`] reports with [`CheckOptions::admissible`], without the other
/// checks).
pub fn collision_free(traj: &JointTrajectory, test: &dyn Admissible) -> Result<()> {
    let report = CheckReport {
        samples: traj.len(),
        peak_vel: Vec::new(),
        peak_acc: Vec::new(),
        peak_jerk: Vec::new(),
        min_manipulability: None,
        violations: rejections_along(traj, test)?,
        warnings: Vec::new(),
    };
    report.into_result().map(|_| ())
}

/// One [`ViolationKind::Collision`] per stretch of the motion that `test`
/// refuses, where the stretch begins: at a sample that starts the motion
/// (or follows a malformed one), or on the straight step from the previous
/// sample.
fn rejections_along(traj: &JointTrajectory, test: &dyn Admissible) -> Result<Vec<Violation>> {
    let t = traj.times();
    let mut out = Vec::new();
    // At sample k (fraction 0 of no step), or at `fraction` of the step k−1 → k:
    // reported at sample k−1 when the step's own start is where it begins.
    let collision = |k: usize, fraction: f64, r: Rejection| Violation {
        kind: ViolationKind::Collision,
        sample: if fraction == 0.0 && k > 0 { k - 1 } else { k },
        time: if k > 0 { t[k - 1] + fraction * (t[k] - t[k - 1]) } else { t[k] },
        joint: None,
        value: fraction,
        limit: 0.0,
        detail: Some(r.detail),
    };
    // Whether the previous sample is refused (its stretch already reported).
    let mut inside = false;
    for k in 0..traj.len() {
        if !finite(traj, k) {
            inside = false;
            continue;
        }
        let starts = k == 0 || !finite(traj, k - 1) || t[k] <= t[k - 1];
        if starts || inside {
            let refused = test.rejects(traj.q(k))?;
            if let (Some(r), false) = (&refused, inside) {
                out.push(Violation { sample: k, time: t[k], ..collision(k, 0.0, r.clone()) });
            }
            inside = refused.is_some();
            continue;
        }
        if let Some((fraction, r)) = test.first_rejection_between(traj.q(k - 1), traj.q(k))? {
            out.push(collision(k, fraction, r));
            inside = test.rejects(traj.q(k))?.is_some();
        }
    }
    Ok(out)
}

/// Whether sample `k` holds only finite values.
fn finite(traj: &JointTrajectory, k: usize) -> bool {
    traj.times()[k].is_finite() && traj.q(k).iter().chain(traj.qd(k)).chain(traj.qdd(k)).all(|x| x.is_finite())
}

/// How finely values and times are known, with machine rounding on top.
#[derive(Clone, Copy)]
struct Resolution {
    value: f64,
    time: f64,
}

impl Resolution {
    /// The uncertainty of a difference quotient (b − a)/h of values of size
    /// about `scale` and result `quotient`.
    fn quotient(&self, scale: f64, quotient: f64, h: f64) -> f64 {
        (2.0 * (self.value + 2.0 * f64::EPSILON * scale) + quotient.abs() * 2.0 * self.time) / h
    }
}

/// The checks over steps between samples: q̇ against q's secant, q's second
/// divided difference against the acceleration limit, q̈'s secant against
/// the jerk limit, each allowing for the resolution of the data.
fn check_steps(
    traj: &JointTrajectory,
    acc: &[Option<f64>],
    jerk: &[Option<f64>],
    tol: f64,
    res: Resolution,
    report: &mut CheckReport,
) {
    let t = traj.times();
    let mut push = |kind, k: usize, i: usize, value: f64, limit: f64| {
        report.violations.push(Violation { kind, sample: k, time: t[k], joint: Some(i), value, limit, detail: None });
    };
    for k in 1..traj.len() {
        if !(finite(traj, k - 1) && finite(traj, k) && t[k] > t[k - 1]) {
            continue;
        }
        let h = t[k] - t[k - 1];
        let next = (k + 1 < traj.len() && finite(traj, k + 1) && t[k + 1] > t[k]).then(|| t[k + 1] - t[k]);
        for i in 0..traj.dof() {
            let (q0, q1) = (traj.q(k - 1)[i], traj.q(k)[i]);
            let secant = (q1 - q0) / h;
            let secant_err = res.quotient(q0.abs().max(q1.abs()), secant, h);
            if let Some(a) = acc[i] {
                let allowed = 0.5 * a * h * (1.0 + CONSISTENCY_SLACK) + secant_err + res.value;
                for kk in [k - 1, k] {
                    let qd = traj.qd(kk)[i];
                    if (qd - secant).abs() > allowed + tol * qd.abs() {
                        push(ViolationKind::Inconsistent, kk, i, qd, secant);
                    }
                }
                if let Some(h2) = next {
                    let q2 = traj.q(k + 1)[i];
                    let secant2 = (q2 - q1) / h2;
                    let second = 2.0 * (secant2 - secant) / (h + h2);
                    let err2 = res.quotient(q1.abs().max(q2.abs()), secant2, h2);
                    let rounding = 2.0 * (secant_err + err2 + second.abs() * res.time) / (h + h2);
                    if second.abs() > a * (1.0 + tol) + rounding {
                        push(ViolationKind::Acceleration, k, i, second, a);
                    }
                }
            }
            let (a0, a1) = (traj.qdd(k - 1)[i], traj.qdd(k)[i]);
            let jerk_here = (a1 - a0) / h;
            report.peak_jerk[i] = report.peak_jerk[i].max(jerk_here.abs());
            if let Some(j) = jerk[i] {
                if jerk_here.abs() > j * (1.0 + tol) + res.quotient(a0.abs().max(a1.abs()), jerk_here, h) {
                    push(ViolationKind::Jerk, k, i, jerk_here, j);
                }
            }
        }
    }
}

/// One warning per passage where the Jacobian's inverse condition number is
/// below `threshold`, at the passage's most singular sample.
fn singular_passages(robot: &Robot, traj: &JointTrajectory, threshold: f64, axes: Axes) -> Result<Vec<Violation>> {
    if !(threshold > 0.0 && threshold < 1.0) {
        return Err(Error::Input(InputError::OutOfRange {
            what: "singular_warning".into(),
            value: threshold,
            expected: "a number in (0, 1): it is a ratio of singular values".into(),
        }));
    }
    let mut jac = nalgebra::Matrix6xX::zeros(robot.dof());
    let mut out: Vec<Violation> = Vec::new();
    let mut inside = false;
    for k in 0..traj.len() {
        if !finite(traj, k) {
            inside = false;
            continue;
        }
        crate::kin::jacobian_into(robot, traj.q(k), Frame::Base, &mut jac)?;
        // min(rows, joints) singular values: all of them are zero-able.
        let sv = rows(&jac, axes)?.singular_values();
        let (lo, hi) = sv.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &s| (lo.min(s), hi.max(s)));
        let ratio = if hi > 0.0 { lo / hi } else { 0.0 };
        if ratio < threshold {
            let w = Violation {
                kind: ViolationKind::Singular,
                sample: k,
                time: traj.times()[k],
                joint: None,
                value: ratio,
                limit: threshold,
                detail: None,
            };
            match out.last_mut() {
                Some(last) if inside => {
                    if ratio < last.value {
                        *last = w;
                    }
                }
                _ => out.push(w),
            }
            inside = true;
        } else {
            inside = false;
        }
    }
    Ok(out)
}
