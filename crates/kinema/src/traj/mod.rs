//! Trajectory generation (seed 004 §VIII): time laws, joint-space
//! point-to-point motions, sampled joint trajectories and the checks every
//! generated trajectory goes through before it is handed out.
//!
//! - [`law`]: normalised time laws s(t) — trapezoid, jerk-limited S-curve,
//!   cubic, quintic, linear — from limits or from a duration.
//! - [`Ptp`]: a synchronised joint-space motion (seed 004 eq. 38) in which
//!   all joints share one law and every joint respects its own limits.
//! - [`JointTrajectory`]: samples t, q, q̇, q̈; [`check`] finds position,
//!   velocity and acceleration limit violations, jumps between samples and
//!   near-singular samples, each with its time and joint.
//!
//! # Examples
//! ```
//! use kinema::traj::{Profile, Ptp, PtpOptions};
//! let robot = kinema::Robot::builtin("lbr-iiwa-14-r820")?;
//! let to = [-0.1090, 1.2417, 0.4463, 1.9156, -0.9695, -1.8728, 0.4876]; // seed 004 §VIII-B
//! let opts = PtpOptions { profile: Profile::SCurve, acc: Some(vec![2.0]), jerk: Some(vec![10.0]), ..PtpOptions::default() };
//! let ptp = Ptp::new(&robot, robot.home(), &to, &opts)?;
//! let traj = ptp.sample(&robot, 0.01)?; // checked: limits hold, no jumps
//! assert!((traj.times().last().unwrap() - ptp.duration()).abs() < 1e-12);
//! # Ok::<(), kinema::Error>(())
//! ```

pub mod boundary;
mod branch_jump;
pub mod cart;
pub mod cell;
mod check;
pub mod expr;
pub mod law;
pub mod self_motion;
pub mod to_joints;
pub mod track;
pub mod waypoints;

pub use boundary::{sync_duration, BoundaryLaw, BoundaryState};
pub use cart::{Blend, CartesianLimits, CartesianMotion, CartesianState, Orientation, Segment, Waypoint};
pub use cell::{Cell, CellMember, CellReport};
pub use check::{check, CheckOptions, CheckReport, Violation, ViolationKind, SINGULAR_WARNING};
pub use expr::{expression_trajectory, Expr};
pub use law::{LawState, MotionLimits, Profile, TimeLaw, MIN_DURATION};
pub use self_motion::SelfMotion;
pub use to_joints::{to_joints, to_joints_at, JointMethod};
pub use track::{distances_to_path, tracking_error, PathDistance, TrackingError};

use crate::error::{Error, Result};
use crate::robot::Robot;

/// Joint `i` moves but the robot model gives no `limit` for it, and neither does `option`.
fn missing_limit(robot: &Robot, i: usize, limit: &str, option: &str) -> Error {
    robot.for_joint(
        i,
        Error::MissingLimit {
            limit: limit.into(),
            option: option.into(),
            needed_by: "its motion in the robot model".into(),
        },
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
        Error::DoesNotFit {
            what: "profile".into(),
            reason: format!(
                "the joint has a jerk limit of {}, which the {} profile's steps in acceleration break; \
                 use the scurve or quintic profile",
                jerk(i).unwrap_or(f64::NAN),
                profile.name()
            ),
        },
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
        Some(v) => Err(Error::WrongLength {
            what: what.into(),
            got: v.len(),
            expected: n,
            of: format!("one per joint of `{}`, or 1 for every joint", robot.name()),
        }),
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
        robot.check_q(from)?;
        robot.check_q(to)?;
        for (what, q) in [("from", from), ("to", to)] {
            if let Some(i) = robot.limit_flags(q).indices().next() {
                let l = robot.joints()[i].limits;
                return Err(robot.for_joint(
                    i,
                    Error::OutOfRange {
                        what: what.into(),
                        value: q[i],
                        expected: format!("a value within the joint's limits [{}, {}]", l.min, l.max),
                    },
                ));
            }
        }
        if !(opts.speed > 0.0 && opts.speed <= 1.0) {
            return Err(Error::OutOfRange {
                what: "speed".into(),
                value: opts.speed,
                expected: "an override in (0, 1]".into(),
            });
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
                return Err(Error::WrongLength {
                    what: what.into(),
                    got: v.len(),
                    expected: dof,
                    of: "one per joint".into(),
                });
            }
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                return Err(Error::NotFinite { what: format!("{what}[{}]", i + 1), value: v[i] });
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
                return Err(Error::DoesNotFit {
                    what: "profile".into(),
                    reason: format!(
                        "the {} profile only moves rest to rest; boundary velocities and accelerations \
                         need the trapezoid or scurve profile",
                        p.name()
                    ),
                })
            }
        };
        if !jerk_limited {
            if let Some(i) = a0.iter().chain(&a1).position(|&a| a != 0.0) {
                let (what, j) = if i < a0.len() { ("a0", i) } else { ("a1", i - a0.len()) };
                return Err(robot.for_joint(
                    j,
                    Error::DoesNotFit {
                        what: what.into(),
                        reason: "a boundary acceleration needs the jerk-limited scurve profile \
                                 (the trapezoid's acceleration steps)"
                            .into(),
                    },
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
                Error::OutOfRange { .. }
                | Error::NotFinite { .. }
                | Error::MissingLimit { .. }
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

/// The most samples one trajectory may have: 10⁷, 2.8 hours at 1 kHz. A 7-joint
/// trajectory of that length holds 1.8 GB (t, q, q̇, q̈), its planned poses another
/// 1.3 GB; more is refused with an error rather than left to exhaust the memory.
pub const MAX_SAMPLES: usize = 10_000_000;

/// The most memory one sampled trajectory may take (t, q, q̇, q̈ as 8-byte
/// values): 1 GiB, 6.1 million samples of a 7-joint arm. Checked before the
/// memory is taken, so that a run within the caps stays within a few GB.
pub const MAX_TRAJECTORY_BYTES: usize = 1 << 30;

/// 0, dt, 2·dt, … and the end time `duration` itself: `dt` \[s\] must be positive
/// and give at most [`MAX_SAMPLES`] samples over `duration` \[s\].
pub fn sample_times(duration: f64, dt: f64) -> Result<Vec<f64>> {
    let samples = sample_count(duration, dt)?;
    let steps = (duration / dt).floor() as usize;
    let mut out: Vec<f64> = (0..=steps).map(|k| k as f64 * dt).collect();
    if samples > steps + 1 {
        out.push(duration);
    } else if let Some(last) = out.last_mut() {
        *last = duration;
    }
    debug_assert_eq!(out.len(), samples);
    Ok(out)
}

/// How many samples [`sample_times`] gives for `duration` and `dt`, without making them
/// (to check a budget first); the same errors.
pub fn sample_count(duration: f64, dt: f64) -> Result<usize> {
    if !(dt.is_finite() && dt > 0.0) {
        return Err(Error::OutOfRange { what: "dt".into(), value: dt, expected: "a positive time step [s]".into() });
    }
    if !(duration.is_finite() && duration >= 0.0) {
        return Err(Error::OutOfRange {
            what: "duration".into(),
            value: duration,
            expected: "a finite, non-negative time [s]".into(),
        });
    }
    let steps = (duration / dt).floor();
    // 0, dt, …, steps·dt, and the end unless steps·dt already is it (to rounding).
    let end_apart = duration - steps * dt > 1e-12 * duration.max(1.0);
    let samples = steps + 1.0 + f64::from(u8::from(end_apart));
    if samples > MAX_SAMPLES as f64 {
        let count = if samples.is_finite() { format!("{samples:.0}") } else { "more than 10^308".to_string() };
        return Err(Error::OutOfRange {
            what: "dt".into(),
            value: dt,
            expected: format!(
                "a larger time step: over {} s this one would give {count} samples (at most {MAX_SAMPLES})",
                crate::error::number_text(duration)
            ),
        });
    }
    Ok(samples as usize)
}

/// A sampled joint trajectory: times and, per sample, q, q̇ and q̈.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct JointTrajectory {
    dof: usize,
    t: Vec<f64>,
    q: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
}

impl JointTrajectory {
    /// An empty trajectory of `dof` joints.
    pub fn new(dof: usize) -> Self {
        Self::with_capacity(dof, 0)
    }

    /// The memory \[bytes\] `samples` samples of `dof` joints take: t, q, q̇
    /// and q̈ as 8-byte values (saturating).
    pub fn bytes_for(dof: usize, samples: usize) -> usize {
        samples.saturating_mul(1 + 3 * dof).saturating_mul(std::mem::size_of::<f64>())
    }

    /// An empty trajectory with room for `samples` samples, taken now: an
    /// error, not an abort, when that is more than [`MAX_TRAJECTORY_BYTES`]
    /// or more than the system gives.
    pub fn reserved(dof: usize, samples: usize) -> Result<Self> {
        let bytes = Self::bytes_for(dof, samples);
        let too_many = |why: String| Error::OutOfRange {
            what: "samples".into(),
            value: samples as f64,
            expected: format!(
                "fewer samples of {dof} joint(s): t, q, q̇ and q̈ of these would take {:.2} GB, {why}; \
                 a larger time step (dt) gives fewer",
                bytes as f64 / 1e9
            ),
        };
        if bytes > MAX_TRAJECTORY_BYTES {
            return Err(too_many(format!(
                "above the limit of {:.2} GB for one trajectory",
                MAX_TRAJECTORY_BYTES as f64 / 1e9
            )));
        }
        let mut traj = Self::new(dof);
        let per_joint = samples * dof;
        let taken = traj.t.try_reserve_exact(samples).and_then(|()| {
            traj.q.try_reserve_exact(per_joint)?;
            traj.qd.try_reserve_exact(per_joint)?;
            traj.qdd.try_reserve_exact(per_joint)
        });
        taken.map_err(|_| too_many("more memory than the system gives".into()))?;
        Ok(traj)
    }

    /// An empty trajectory with room for `samples` samples (no limit: see
    /// [`JointTrajectory::reserved`] for a request that may be large).
    pub fn with_capacity(dof: usize, samples: usize) -> Self {
        JointTrajectory {
            dof,
            t: Vec::with_capacity(samples),
            q: Vec::with_capacity(samples * dof),
            qd: Vec::with_capacity(samples * dof),
            qdd: Vec::with_capacity(samples * dof),
        }
    }

    /// A trajectory from sampled positions alone: `q` holds one configuration
    /// of `dof` values per time in `t` (row-major); velocities and
    /// accelerations are second-order finite differences
    /// ([`to_joints::derivatives`]). Errors: `q` not `dof` values per time.
    pub fn from_positions(dof: usize, t: Vec<f64>, q: Vec<f64>) -> Result<Self> {
        if q.len() != t.len() * dof {
            return Err(Error::WrongLength {
                what: "q".into(),
                got: q.len(),
                expected: t.len() * dof,
                of: format!("{dof} per sample time, {} times", t.len()),
            });
        }
        let mut qd = vec![0.0; q.len()];
        let mut qdd = vec![0.0; q.len()];
        if dof > 0 {
            for (k, (v, a)) in qd.chunks_exact_mut(dof).zip(qdd.chunks_exact_mut(dof)).enumerate() {
                to_joints::derivatives(&t, &q, dof, k, v, a);
            }
        }
        Ok(JointTrajectory { dof, t, q, qd, qdd })
    }

    /// A trajectory from samples read elsewhere (a file, an array): `q`, and
    /// `qd`/`qdd` when given, hold `dof` values per time in `t` (row-major);
    /// missing velocities or accelerations are estimated from the positions
    /// as in [`JointTrajectory::from_positions`] (what `kinema traj check`
    /// does with a file without `qd`/`qdd` columns). Nothing else is checked
    /// here: [`check`] reports non-finite values and times that do not increase.
    ///
    /// Errors: no samples; a slice that is not `dof` values per time.
    ///
    /// # Examples
    /// ```
    /// use kinema::traj::JointTrajectory;
    /// let t = vec![0.0, 0.1, 0.2];
    /// let q = vec![0.0, 1.0, 0.01, 1.0, 0.02, 1.0]; // 2 joints
    /// let traj = JointTrajectory::from_samples(2, t, q, None, None)?;
    /// assert!((traj.qd(1)[0] - 0.1).abs() < 1e-12 && traj.qd(1)[1] == 0.0);
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn from_samples(
        dof: usize,
        t: Vec<f64>,
        q: Vec<f64>,
        qd: Option<Vec<f64>>,
        qdd: Option<Vec<f64>>,
    ) -> Result<Self> {
        if t.is_empty() {
            return Err(Error::TooFew { what: "t".into(), got: 0, min: 1, of: "samples".into() });
        }
        for (what, v) in [("qd", &qd), ("qdd", &qdd)] {
            if let Some(v) = v {
                if v.len() != t.len() * dof {
                    return Err(Error::WrongLength {
                        what: what.into(),
                        got: v.len(),
                        expected: t.len() * dof,
                        of: format!("{dof} per sample time, {} times", t.len()),
                    });
                }
            }
        }
        let mut traj = Self::from_positions(dof, t, q)?;
        if let Some(v) = qd {
            traj.qd = v;
        }
        if let Some(a) = qdd {
            traj.qdd = a;
        }
        Ok(traj)
    }

    /// Appends a sample. Errors if a slice does not have `dof` values.
    pub fn push(&mut self, t: f64, q: &[f64], qd: &[f64], qdd: &[f64]) -> Result<()> {
        for (what, v) in [("q", q), ("qd", qd), ("qdd", qdd)] {
            if v.len() != self.dof {
                return Err(Error::WrongLength {
                    what: what.into(),
                    got: v.len(),
                    expected: self.dof,
                    of: "one per joint of the trajectory".into(),
                });
            }
        }
        self.t.push(t);
        self.q.extend_from_slice(q);
        self.qd.extend_from_slice(qd);
        self.qdd.extend_from_slice(qdd);
        Ok(())
    }

    /// Number of joints.
    pub fn dof(&self) -> usize {
        self.dof
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Whether there is no sample.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Sample times \[s\].
    pub fn times(&self) -> &[f64] {
        &self.t
    }

    /// Joint values of sample `k`.
    pub fn q(&self, k: usize) -> &[f64] {
        &self.q[k * self.dof..(k + 1) * self.dof]
    }

    /// Joint velocities of sample `k`.
    pub fn qd(&self, k: usize) -> &[f64] {
        &self.qd[k * self.dof..(k + 1) * self.dof]
    }

    /// Joint accelerations of sample `k`.
    pub fn qdd(&self, k: usize) -> &[f64] {
        &self.qdd[k * self.dof..(k + 1) * self.dof]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_times_step_by_dt_end_at_the_duration_and_refuse_what_cannot_be_held() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(61);
        for _ in 0..2000 {
            let duration = rng.random_range(0.0..20.0);
            let dt = 10f64.powf(rng.random_range(-3.0..0.5));
            let t = sample_times(duration, dt).unwrap();
            assert_eq!(sample_count(duration, dt).unwrap(), t.len());
            assert_eq!(t[0], 0.0);
            assert_eq!(*t.last().unwrap(), duration);
            assert!(t.len() <= MAX_SAMPLES);
            // Every step is dt but the last, which is (0, dt] (a few ulp over dt at most).
            for w in t[..t.len() - 1].windows(2) {
                assert!((w[1] - w[0] - dt).abs() <= 1e-12 * duration.max(1.0), "{duration} {dt} {w:?}");
            }
            if t.len() > 1 {
                let last = t[t.len() - 1] - t[t.len() - 2];
                assert!(last > 0.0 && last <= dt * (1.0 + 1e-9) + 1e-12 * duration.max(1.0), "{duration} {dt} {last}");
            }
        }
        // Right at the limit, and one sample over it.
        let dt = 1e-3;
        let most = (MAX_SAMPLES as f64 - 1.5) * dt;
        assert_eq!(sample_times(most, dt).unwrap().len(), MAX_SAMPLES);
        let e = sample_times(most + dt, dt).unwrap_err().to_string();
        assert!(e.contains("would give 10000001 samples (at most 10000000)"), "{e}");
        // A duration that is a whole number of steps has no extra end sample: exactly
        // MAX_SAMPLES of them fit.
        let whole = (MAX_SAMPLES - 1) as f64 * 0.5;
        assert_eq!(sample_times(whole, 0.5).unwrap().len(), MAX_SAMPLES);
        let e = sample_times(whole + 0.5, 0.5).unwrap_err().to_string();
        assert!(e.contains("would give 10000001 samples (at most 10000000)"), "{e}");
        let e = sample_count(1e300, 1e-300).unwrap_err().to_string();
        assert!(e.contains("would give more than 10^308 samples"), "{e}");
        for (duration, dt, what) in [
            (1.0, 0.0, "dt"),
            (1.0, -0.1, "dt"),
            (1.0, f64::NAN, "dt"),
            (1.0, f64::INFINITY, "dt"),
            (f64::NAN, 0.1, "duration"),
            (f64::INFINITY, 0.1, "duration"),
            (-1.0, 0.1, "duration"),
            (1e300, 1e-300, "dt"),
        ] {
            match sample_times(duration, dt) {
                Err(Error::OutOfRange { what: w, .. }) => assert_eq!(w, what, "{duration} {dt}"),
                other => panic!("{duration} s / {dt} s: {other:?}"),
            }
        }
    }

    #[test]
    fn violation_names_are_the_lower_case_kinds() {
        use ViolationKind::*;
        for kind in [Malformed, Position, Velocity, Acceleration, Jump, NearSingular, Jerk, Inconsistent, Singular] {
            assert_eq!(kind.name(), format!("{kind:?}").to_lowercase());
        }
    }

    #[test]
    fn from_samples_keeps_given_derivatives_and_estimates_the_others() {
        let t = vec![0.0, 0.1, 0.25, 0.3];
        let q: Vec<f64> = t.iter().flat_map(|&t: &f64| [t * t, (3.0 * t).sin()]).collect();
        let estimated = JointTrajectory::from_positions(2, t.clone(), q.clone()).unwrap();
        let qd: Vec<f64> = (0..8).map(|i| i as f64).collect();
        let traj = JointTrajectory::from_samples(2, t.clone(), q.clone(), Some(qd.clone()), None).unwrap();
        for k in 0..t.len() {
            assert_eq!(traj.q(k), estimated.q(k));
            assert_eq!(traj.qd(k), &qd[2 * k..2 * k + 2]);
            assert_eq!(traj.qdd(k), estimated.qdd(k));
        }
        assert_eq!(JointTrajectory::from_samples(2, t.clone(), q.clone(), None, None).unwrap(), estimated);
        assert!(JointTrajectory::from_samples(2, t.clone(), q.clone(), None, Some(vec![0.0; 3])).is_err());
        assert!(JointTrajectory::from_samples(2, t, q[..6].to_vec(), None, None).is_err());
        let e = JointTrajectory::from_samples(2, vec![], vec![], None, None).unwrap_err();
        assert!(matches!(&e, Error::TooFew { what, got: 0, .. } if what == "t"), "{e:?}");
    }
}
