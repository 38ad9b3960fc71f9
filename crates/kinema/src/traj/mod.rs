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
pub mod path_error;
mod ptp;
pub mod self_motion;
pub mod to_joints;
pub mod via;
pub mod waypoints;

pub use boundary::{sync_duration, BoundaryLaw, BoundaryState};
pub use cart::{Blend, CartesianLimits, CartesianMotion, CartesianState, Orientation, Segment, Waypoint};
pub use cell::{Cell, CellMember, CellReport};
pub use check::{check, collision_free, CheckOptions, CheckReport, Violation, ViolationKind, SINGULAR_WARNING};
pub use expr::{expression_trajectory, Expr};
pub use law::{LawState, MotionLimits, Profile, TimeLaw, MIN_DURATION};
pub use path_error::{distances_to_path, tracking_error, PathDistance, TrackingError};
pub(crate) use ptp::joint_limits;
pub use ptp::{default_profile, BoundaryPtp, JointBoundary, Ptp, PtpOptions};
pub use self_motion::SelfMotion;
pub use to_joints::{to_joints, to_joints_at, JointMethod};

use crate::error::{Error, InputError, Result};

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
        return Err(Error::Input(InputError::OutOfRange {
            what: "dt".into(),
            value: dt,
            expected: "a positive time step [s]".into(),
        }));
    }
    if !(duration.is_finite() && duration >= 0.0) {
        return Err(Error::Input(InputError::OutOfRange {
            what: "duration".into(),
            value: duration,
            expected: "a finite, non-negative time [s]".into(),
        }));
    }
    let steps = (duration / dt).floor();
    // 0, dt, …, steps·dt, and the end unless steps·dt already is it (to rounding).
    let end_apart = duration - steps * dt > 1e-12 * duration.max(1.0);
    let samples = steps + 1.0 + f64::from(u8::from(end_apart));
    if samples > MAX_SAMPLES as f64 {
        let count = if samples.is_finite() { format!("{samples:.0}") } else { "more than 10^308".to_string() };
        return Err(Error::Input(InputError::OutOfRange {
            what: "dt".into(),
            value: dt,
            expected: format!(
                "a larger time step: over {} s this one would give {count} samples (at most {MAX_SAMPLES})",
                crate::error::number_text(duration)
            ),
        }));
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
        let too_many = |why: String| {
            Error::Input(InputError::OutOfRange {
                what: "samples".into(),
                value: samples as f64,
                expected: format!(
                    "fewer samples of {dof} joint(s): t, q, q̇ and q̈ of these would take {:.2} GB, {why}; \
                 a larger time step (dt) gives fewer",
                    bytes as f64 / 1e9
                ),
            })
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
            return Err(Error::Input(InputError::WrongLength {
                what: "q".into(),
                got: q.len(),
                expected: t.len() * dof,
                of: format!("{dof} per sample time, {} times", t.len()),
            }));
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
            return Err(Error::Input(InputError::TooFew { what: "t".into(), got: 0, min: 1, of: "samples".into() }));
        }
        for (what, v) in [("qd", &qd), ("qdd", &qdd)] {
            if let Some(v) = v {
                if v.len() != t.len() * dof {
                    return Err(Error::Input(InputError::WrongLength {
                        what: what.into(),
                        got: v.len(),
                        expected: t.len() * dof,
                        of: format!("{dof} per sample time, {} times", t.len()),
                    }));
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
                return Err(Error::Input(InputError::WrongLength {
                    what: what.into(),
                    got: v.len(),
                    expected: self.dof,
                    of: "one per joint of the trajectory".into(),
                }));
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
                Err(Error::Input(InputError::OutOfRange { what: w, .. })) => assert_eq!(w, what, "{duration} {dt}"),
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
        assert!(matches!(&e, Error::Input(InputError::TooFew { what, got: 0, .. }) if what == "t"), "{e:?}");
    }
}
