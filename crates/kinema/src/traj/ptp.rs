//! Joint-space point-to-point motions: [`Ptp`], all joints on one shared
//! law (seed 004 eq. 38), and [`BoundaryPtp`], each joint on its own
//! time-optimal law between given boundary velocities and accelerations.

use super::boundary::{sync_duration, BoundaryLaw, BoundaryState};
use super::law::{MotionLimits, Profile, TimeLaw};
use super::{check, sample_times, CheckOptions, JointTrajectory};
use crate::error::{Error, InputError, Result};
use crate::robot::Robot;

/// Joint `i` moves but the robot model gives no `limit` for it, and neither does `option`.
fn missing_limit(robot: &Robot, i: usize, limit: &str, option: &str) -> Error {
    robot.for_joint(
        i,
        Error::Input(InputError::MissingLimit {
            limit: limit.into(),
            option: option.into(),
            needed_by: "its motion in the robot model".into(),
        }),
    )
}

/// A joint whose model has a jerk limit cannot follow a step in
/// acceleration (the Panda's controller rejects one), so the laws that start
/// and stop with one — the trapezoid and the cubic — are refused when such a
/// joint moves. (A `jmax` option is for the laws that use it, as documented;
/// the linear law is exempt: it ignores acceleration too.)
fn refuse_acceleration_steps(robot: &Robot, profile: Profile, delta: &[f64]) -> Result<()> {
    if !matches!(profile, Profile::Trapezoid | Profile::Cubic) {
        return Ok(());
    }
    let jerk = |i: usize| robot.joints()[i].limits.jerk;
    let Some(i) = (0..delta.len()).find(|&i| delta[i] != 0.0 && jerk(i).is_some()) else { return Ok(()) };
    Err(robot.for_joint(
        i,
        Error::Input(InputError::DoesNotFit {
            what: "profile".into(),
            reason: format!(
                "the joint has a jerk limit of {}, which the {} profile's steps in acceleration break; \
                 use the scurve or quintic profile",
                jerk(i).unwrap_or(f64::NAN),
                profile.name()
            ),
        }),
    ))
}

/// Options of a point-to-point motion.
#[derive(Debug, Clone, PartialEq)]
pub struct PtpOptions {
    /// The family of the shared time law.
    pub profile: Profile,
    /// Velocity limits \[rad/s or m/s\]: one value for every joint or one per
    /// joint; `None` uses the robot's.
    pub vel: Option<Vec<f64>>,
    /// Acceleration limits, as `vel`.
    pub acc: Option<Vec<f64>>,
    /// Jerk limits (S-curve and, optionally, quintic), as `vel`.
    pub jerk: Option<Vec<f64>>,
    /// Velocity override in (0, 1]: the velocity limits are scaled by it, the
    /// acceleration limits by its square and the jerk limits by its cube (a
    /// slower run of the same motion, like an industrial controller's % override).
    pub speed: f64,
    /// A duration \[s\] to stretch the motion to (at least the fastest one).
    pub duration: Option<f64>,
}

impl Default for PtpOptions {
    /// The trapezoid and the robot's limits. For a robot whose model has jerk
    /// limits use [`PtpOptions::for_robot`]: the trapezoid is refused there.
    fn default() -> Self {
        PtpOptions { profile: Profile::Trapezoid, vel: None, acc: None, jerk: None, speed: 1.0, duration: None }
    }
}

impl PtpOptions {
    /// The defaults for `robot`: its limits and [`default_profile`]`(robot)`,
    /// what `kinema traj ptp` and Python's `Robot.ptp` use when no profile is
    /// named.
    ///
    /// # Examples
    /// ```
    /// use kinema::traj::{Profile, Ptp, PtpOptions};
    /// let panda = kinema::Robot::builtin("panda")?;
    /// let opts = PtpOptions::for_robot(&panda);
    /// assert_eq!(opts.profile, Profile::SCurve); // Franka publishes jerk limits
    /// let ptp = Ptp::new(&panda, panda.home(), &[0.5, -0.3, 0.2, -2.0, 0.1, 1.8, 0.6], &opts)?;
    /// assert!(ptp.duration() > 0.0);
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn for_robot(robot: &Robot) -> PtpOptions {
        PtpOptions { profile: default_profile(robot), ..PtpOptions::default() }
    }
}

/// The time law a point-to-point motion of `robot` gets when none is named:
/// the trapezoid (seed 004 eq. 32–37) unless the model has jerk limits,
/// whose controller (the Panda's) rejects the trapezoid's steps in
/// acceleration — then the S-curve, which respects them, or the quintic
/// (continuous acceleration, no jerk limit needed) when only some joints have one.
pub fn default_profile(robot: &Robot) -> Profile {
    let with_jerk = robot.joints().iter().filter(|j| j.limits.jerk.is_some()).count();
    match with_jerk {
        0 => Profile::Trapezoid,
        n if n == robot.dof() => Profile::SCurve,
        _ => Profile::Quintic,
    }
}

/// Per-joint limits from an option (1 or n values) or the robot.
pub(crate) fn joint_limits(
    robot: &Robot,
    given: Option<&[f64]>,
    what: &str,
    from_robot: impl Fn(usize) -> Option<f64>,
) -> Result<Vec<Option<f64>>> {
    let n = robot.dof();
    match given {
        Some(v) if v.len() == 1 => Ok(vec![Some(v[0]); n]),
        Some(v) if v.len() == n => Ok(v.iter().map(|&x| Some(x)).collect()),
        Some(v) => Err(Error::Input(InputError::WrongLength {
            what: what.into(),
            got: v.len(),
            expected: n,
            of: format!("one per joint of `{}`, or 1 for every joint", robot.name()),
        })),
        None => Ok((0..n).map(from_robot).collect()),
    }
}

/// A synchronised point-to-point motion in joint space (seed 004 §VIII-B,
/// eq. 38: q(t) = q_ini + s(t)·(q_obj − q_ini)).
///
/// All joints share one normalised law s(t). Joint i moves Δ_i·s(t), so it
/// respects its limits when ṡ ≤ v_i/|Δ_i|, s̈ ≤ a_i/|Δ_i| and s⃛ ≤ j_i/|Δ_i|;
/// the shared law is the fastest one with ṡ ≤ min_i v_i/|Δ_i| and so on —
/// computed per joint, each limit decided by the joint it binds. (Seed 004
/// used only the slowest actuator and the largest displacement, which can be
/// slower or, with unequal limits, violate a faster joint's acceleration.)
#[derive(Debug, Clone, PartialEq)]
pub struct Ptp {
    law: TimeLaw,
    from: Vec<f64>,
    delta: Vec<f64>,
}

impl Ptp {
    /// Plans the motion from `from` to `to` (joint values of `robot`).
    ///
    /// Errors: wrong joint counts or non-finite values; a target outside the
    /// joint position limits; a moving joint without a velocity/acceleration
    /// (or, for the S-curve, jerk) limit in the robot or the options; a
    /// non-positive limit or a `speed` outside (0, 1].
    pub fn new(robot: &Robot, from: &[f64], to: &[f64], opts: &PtpOptions) -> Result<Ptp> {
        robot.check_within_limits(from, "from")?;
        robot.check_within_limits(to, "to")?;
        if !(opts.speed > 0.0 && opts.speed <= 1.0) {
            return Err(Error::Input(InputError::OutOfRange {
                what: "speed".into(),
                value: opts.speed,
                expected: "an override in (0, 1]".into(),
            }));
        }
        let js = robot.joints();
        let vel = joint_limits(robot, opts.vel.as_deref(), "vmax", |i| js[i].limits.vel)?;
        let acc = joint_limits(robot, opts.acc.as_deref(), "amax", |i| js[i].limits.acc)?;
        let jerk = joint_limits(robot, opts.jerk.as_deref(), "jmax", |i| js[i].limits.jerk)?;
        let delta: Vec<f64> = to.iter().zip(from).map(|(b, a)| b - a).collect();
        refuse_acceleration_steps(robot, opts.profile, &delta)?;
        let need_acc = opts.profile != Profile::Linear;
        let need_jerk = opts.profile == Profile::SCurve;
        let k = opts.speed;
        let mut shared = MotionLimits { vel: f64::INFINITY, acc: f64::INFINITY, jerk: None };
        for (i, d) in delta.iter().enumerate() {
            let d = d.abs();
            if d == 0.0 {
                continue;
            }
            let missing = |limit: &str, option: &str| missing_limit(robot, i, limit, option);
            let v = vel[i].ok_or_else(|| missing("velocity", "vmax"))?;
            shared.vel = shared.vel.min(v * k / d);
            if need_acc {
                let a = acc[i].ok_or_else(|| missing("acceleration", "amax"))?;
                shared.acc = shared.acc.min(a * k * k / d);
            }
            match jerk[i] {
                Some(j) => shared.jerk = Some(shared.jerk.unwrap_or(f64::INFINITY).min(j * k * k * k / d)),
                None if need_jerk => return Err(missing("jerk", "jmax")),
                None => {}
            }
        }
        if !need_acc {
            shared.acc = 1.0;
        }
        let moving = delta.iter().any(|d| *d != 0.0);
        let mut law = if moving {
            TimeLaw::from_limits(opts.profile, 1.0, &shared)?
        } else {
            TimeLaw::from_limits(opts.profile, 0.0, &MotionLimits::with_jerk(1.0, 1.0, 1.0))?
        };
        if let Some(t) = opts.duration {
            law = law.stretched_to(t)?;
        }
        Ok(Ptp { law, from: from.to_vec(), delta })
    }

    /// The shared time law.
    pub fn law(&self) -> &TimeLaw {
        &self.law
    }

    /// Duration \[s\].
    pub fn duration(&self) -> f64 {
        self.law.duration()
    }

    /// q, q̇, q̈ at time `t` \[s\], written into the three slices (each `dof` long).
    pub fn state_into(&self, t: f64, q: &mut [f64], qd: &mut [f64], qdd: &mut [f64]) {
        let s = self.law.at(t);
        for i in 0..self.delta.len() {
            q[i] = self.from[i] + s.s * self.delta[i];
            qd[i] = s.sd * self.delta[i];
            qdd[i] = s.sdd * self.delta[i];
        }
    }

    /// Samples every `dt` \[s\] from 0, plus the end time, and checks the
    /// result ([`check`] with [`CheckOptions::default`]); a violation is an
    /// [`Error::Trajectory`] and nothing is returned.
    pub fn sample(&self, robot: &Robot, dt: f64) -> Result<JointTrajectory> {
        let traj = self.sample_unchecked(dt)?;
        let mut opts = CheckOptions::default();
        if self.law.profile() == Profile::Linear {
            // The linear law starts and stops with a velocity step (seed 003's z
            // and θ): its acceleration is unbounded by design, so only
            // positions and velocities are checked.
            (opts.acc, opts.jerk) = (Some(vec![f64::INFINITY]), Some(vec![f64::INFINITY]));
        }
        check(robot, &traj, &opts)?.into_result()?;
        Ok(traj)
    }

    /// As [`Ptp::sample`] without the check.
    pub fn sample_unchecked(&self, dt: f64) -> Result<JointTrajectory> {
        let times = sample_times(self.duration(), dt)?;
        let n = self.delta.len();
        let mut traj = JointTrajectory::reserved(n, times.len())?;
        let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for t in times {
            self.state_into(t, &mut q, &mut qd, &mut qdd);
            traj.push(t, &q, &qd, &qdd)?;
        }
        Ok(traj)
    }
}

/// Joint velocities \[rad/s or m/s\] and accelerations \[rad/s² or m/s²\] at
/// the start and the end of a point-to-point motion ([`BoundaryPtp`]): one
/// value per joint; `None` means 0 for every joint.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct JointBoundary {
    /// Start velocities.
    pub v0: Option<Vec<f64>>,
    /// Start accelerations (need a jerk-limited profile).
    pub a0: Option<Vec<f64>>,
    /// End velocities.
    pub v1: Option<Vec<f64>>,
    /// End accelerations (need a jerk-limited profile).
    pub a1: Option<Vec<f64>>,
}

impl JointBoundary {
    /// Whether every boundary velocity and acceleration is 0 (rest to rest).
    pub fn is_rest(&self) -> bool {
        [&self.v0, &self.a0, &self.v1, &self.a1].iter().all(|v| v.as_ref().is_none_or(|v| v.iter().all(|&x| x == 0.0)))
    }

    /// The four vectors, `dof` long each (zeros where not given). Errors
    /// name the field: a length other than `dof`, a value that is not finite.
    fn vectors(&self, dof: usize) -> Result<[Vec<f64>; 4]> {
        let one = |what: &str, v: &Option<Vec<f64>>| -> Result<Vec<f64>> {
            let Some(v) = v else { return Ok(vec![0.0; dof]) };
            if v.len() != dof {
                return Err(Error::Input(InputError::WrongLength {
                    what: what.into(),
                    got: v.len(),
                    expected: dof,
                    of: "one per joint".into(),
                }));
            }
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                return Err(Error::Input(InputError::NotFinite { what: format!("{what}[{}]", i + 1), value: v[i] }));
            }
            Ok(v.clone())
        };
        Ok([one("v0", &self.v0)?, one("a0", &self.a0)?, one("v1", &self.v1)?, one("a1", &self.a1)?])
    }
}

/// A synchronised point-to-point motion between joint states with
/// velocities and accelerations: motions chained without stopping.
///
/// Rest to rest (every boundary value 0) it is exactly [`Ptp`]: one shared
/// law, a straight line in joint space. Otherwise each joint follows its
/// own [`BoundaryLaw`] and all of them end together at the smallest
/// duration T that every joint admits ([`sync_duration`]: at least the
/// slowest joint's fastest duration, moved past any joint's blocked
/// interval). The path in joint space is then in general not a straight
/// line. Profiles: the S-curve (jerk-limited, any boundary accelerations)
/// and the trapezoid (boundary accelerations 0); other profiles are
/// refused with boundary velocities.
///
/// # Examples
/// ```
/// use kinema::traj::{BoundaryPtp, JointBoundary, Profile, PtpOptions};
/// let robot = kinema::Robot::builtin("lbr-iiwa-14-r820")?;
/// let to = [-0.1090, 1.2417, 0.4463, 1.9156, -0.9695, -1.8728, 0.4876];
/// let opts = PtpOptions { profile: Profile::SCurve, acc: Some(vec![2.0]), jerk: Some(vec![10.0]), ..PtpOptions::default() };
/// // Pass through `to` at 0.2 rad/s on joint 1 instead of stopping there.
/// let boundary = JointBoundary { v1: Some(vec![0.2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]), ..JointBoundary::default() };
/// let ptp = BoundaryPtp::new(&robot, robot.home(), &to, &opts, &boundary)?;
/// let traj = ptp.sample(&robot, 0.01)?; // checked: limits hold, no jumps
/// assert!((traj.qd(traj.len() - 1)[0] - 0.2).abs() < 1e-9);
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct BoundaryPtp {
    plan: BoundaryPlan,
}

#[derive(Debug, Clone, PartialEq)]
enum BoundaryPlan {
    Rest(Box<Ptp>),
    Joints { duration: f64, laws: Vec<BoundaryLaw> },
}

impl BoundaryPtp {
    /// Plans the motion from `from` to `to` with the boundary velocities and
    /// accelerations of `boundary`, within the limits of `opts` (as [`Ptp::new`];
    /// `opts.duration` is a least duration).
    ///
    /// Errors: those of [`Ptp::new`]; a boundary vector that is not one
    /// finite value per joint; boundary velocities with a profile other than
    /// the trapezoid or S-curve; boundary accelerations without a jerk-limited
    /// profile; a target state beyond a limit (see [`BoundaryLaw::fastest`]; a
    /// start beyond one is braked first).
    pub fn new(robot: &Robot, from: &[f64], to: &[f64], opts: &PtpOptions, boundary: &JointBoundary) -> Result<Self> {
        let [v0, a0, v1, a1] = boundary.vectors(robot.dof())?;
        if boundary.is_rest() {
            return Ok(BoundaryPtp { plan: BoundaryPlan::Rest(Box::new(Ptp::new(robot, from, to, opts)?)) });
        }
        // The checks of Ptp::new on positions, speed and limits.
        let probe = PtpOptions { duration: None, ..opts.clone() };
        Ptp::new(robot, from, to, &PtpOptions { profile: Profile::Linear, ..probe.clone() })?;
        let jerk_limited = match opts.profile {
            Profile::SCurve => true,
            Profile::Trapezoid => false,
            p => {
                return Err(Error::Input(InputError::DoesNotFit {
                    what: "profile".into(),
                    reason: format!(
                        "the {} profile only moves rest to rest; boundary velocities and accelerations \
                         need the trapezoid or scurve profile",
                        p.name()
                    ),
                }))
            }
        };
        if !jerk_limited {
            if let Some(i) = a0.iter().chain(&a1).position(|&a| a != 0.0) {
                let (what, j) = if i < a0.len() { ("a0", i) } else { ("a1", i - a0.len()) };
                return Err(robot.for_joint(
                    j,
                    Error::Input(InputError::DoesNotFit {
                        what: what.into(),
                        reason: "a boundary acceleration needs the jerk-limited scurve profile \
                                 (the trapezoid's acceleration steps)"
                            .into(),
                    }),
                ));
            }
        }
        // A joint moves if it changes position or has a boundary velocity.
        let moving: Vec<f64> = (0..robot.dof())
            .map(|i| if to[i] != from[i] || v0[i] != 0.0 || v1[i] != 0.0 { 1.0 } else { 0.0 })
            .collect();
        refuse_acceleration_steps(robot, opts.profile, &moving)?;
        let js = robot.joints();
        let vel = joint_limits(robot, opts.vel.as_deref(), "vmax", |i| js[i].limits.vel)?;
        let acc = joint_limits(robot, opts.acc.as_deref(), "amax", |i| js[i].limits.acc)?;
        let jerk = joint_limits(robot, opts.jerk.as_deref(), "jmax", |i| js[i].limits.jerk)?;
        let k = opts.speed;
        let n = robot.dof();
        let (mut starts, mut ends, mut limits) = (Vec::with_capacity(n), Vec::with_capacity(n), Vec::with_capacity(n));
        for i in 0..n {
            let start = BoundaryState::new(from[i], v0[i], a0[i]);
            let end = BoundaryState::new(to[i], v1[i], a1[i]);
            let missing = |limit: &str, option: &str| missing_limit(robot, i, limit, option);
            let lim = if start == end && start.v == 0.0 && start.a == 0.0 {
                MotionLimits::with_jerk(1.0, 1.0, 1.0) // at rest throughout
            } else {
                let v = vel[i].ok_or_else(|| missing("velocity", "vmax"))? * k;
                let a = acc[i].ok_or_else(|| missing("acceleration", "amax"))? * k * k;
                if jerk_limited {
                    MotionLimits::with_jerk(v, a, jerk[i].ok_or_else(|| missing("jerk", "jmax"))? * k * k * k)
                } else {
                    MotionLimits::new(v, a)
                }
            };
            // Name the joint in a refused state.
            BoundaryLaw::fastest(start, end, &lim).map_err(|e| match e {
                Error::Input(InputError::OutOfRange { .. })
                | Error::Input(InputError::NotFinite { .. })
                | Error::Input(InputError::MissingLimit { .. })
                | Error::Infeasible { .. } => robot.for_joint(i, e),
                e => e,
            })?;
            starts.push(start);
            ends.push(end);
            limits.push(lim);
        }
        let (duration, laws) = sync_duration(&starts, &ends, &limits, opts.duration.unwrap_or(0.0))?;
        Ok(BoundaryPtp { plan: BoundaryPlan::Joints { duration, laws } })
    }

    /// The straight-line motion with one shared law, when every boundary
    /// value is 0.
    pub fn rest(&self) -> Option<&Ptp> {
        match &self.plan {
            BoundaryPlan::Rest(p) => Some(p),
            BoundaryPlan::Joints { .. } => None,
        }
    }

    /// Each joint's law (empty for a rest-to-rest motion: see [`BoundaryPtp::rest`]).
    pub fn laws(&self) -> &[BoundaryLaw] {
        match &self.plan {
            BoundaryPlan::Rest(_) => &[],
            BoundaryPlan::Joints { laws, .. } => laws,
        }
    }

    /// Duration \[s\].
    pub fn duration(&self) -> f64 {
        match &self.plan {
            BoundaryPlan::Rest(p) => p.duration(),
            BoundaryPlan::Joints { duration, .. } => *duration,
        }
    }

    /// q, q̇, q̈ at time `t` \[s\], written into the three slices (each `dof` long).
    pub fn state_into(&self, t: f64, q: &mut [f64], qd: &mut [f64], qdd: &mut [f64]) {
        match &self.plan {
            BoundaryPlan::Rest(p) => p.state_into(t, q, qd, qdd),
            BoundaryPlan::Joints { laws, .. } => {
                for (i, law) in laws.iter().enumerate() {
                    let s = law.at(t);
                    (q[i], qd[i], qdd[i]) = (s.p, s.v, s.a);
                }
            }
        }
    }

    /// Samples every `dt` \[s\] from 0, plus the end time, and checks the
    /// result as [`Ptp::sample`] does (limits, jumps; jerk where the robot or
    /// the options give a limit); a violation is an [`Error::Trajectory`].
    pub fn sample(&self, robot: &Robot, dt: f64) -> Result<JointTrajectory> {
        if let BoundaryPlan::Rest(p) = &self.plan {
            return p.sample(robot, dt);
        }
        let traj = self.sample_unchecked(dt)?;
        check(robot, &traj, &CheckOptions::default())?.into_result()?;
        Ok(traj)
    }

    /// As [`BoundaryPtp::sample`] without the check.
    pub fn sample_unchecked(&self, dt: f64) -> Result<JointTrajectory> {
        let times = sample_times(self.duration(), dt)?;
        let n = match &self.plan {
            BoundaryPlan::Rest(p) => p.delta.len(),
            BoundaryPlan::Joints { laws, .. } => laws.len(),
        };
        let mut traj = JointTrajectory::reserved(n, times.len())?;
        let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for t in times {
            self.state_into(t, &mut q, &mut qd, &mut qdd);
            traj.push(t, &q, &qd, &qdd)?;
        }
        Ok(traj)
    }
}
