//! A joint-space path of straight segments, timed: one [`Ptp`] per segment,
//! stopping at every via point (at rest, but for the linear profile's
//! velocity jump). The robot stays on the segments exactly (each PTP moves
//! all joints along its straight line), so a path certified collision-free
//! segment by segment stays so once timed.

use super::{sample_count, sample_times, JointTrajectory, Ptp, PtpOptions};
use crate::error::{Error, InputError, Result};
use crate::robot::Robot;

/// Whether `options` and `dt` can time a path of `robot` starting at
/// `start`: the checks of [`ptp_through`] that do not depend on the rest of
/// the path, for a caller to ask before it spends time finding one.
pub fn check_timing(robot: &Robot, start: &[f64], options: &PtpOptions, dt: f64) -> Result<()> {
    ptp_through(robot, &[start.to_vec()], options, dt).map(|_| ())
}

/// Times `path` (at least one configuration of `robot`) with a PTP per
/// segment under `options`, stopping at each via point, sampled every `dt`
/// \[s\] and at each segment's end. Repeated via points are skipped.
///
/// Errors: an empty path; a configuration of the wrong length, not finite
/// or outside the joint limits; the PTP's limit errors; more samples than a
/// trajectory may hold.
///
/// # Examples
/// ```
/// use kinema::traj::{via::ptp_through, PtpOptions};
/// let robot = kinema::Robot::builtin("puma560")?;
/// let path = [vec![0.0; 6], vec![0.5, 0.2, 0.0, 0.0, 0.0, 0.0], vec![0.5, 0.2, -0.4, 0.0, 0.3, 0.0]];
/// let traj = ptp_through(&robot, &path, &PtpOptions::for_robot(&robot), 0.01)?;
/// let last = traj.len() - 1;
/// assert_eq!(traj.q(last), path[2].as_slice());
/// assert!(traj.qd(last).iter().all(|v| v.abs() < 1e-9));
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn ptp_through(robot: &Robot, path: &[Vec<f64>], options: &PtpOptions, dt: f64) -> Result<JointTrajectory> {
    let Some(first) = path.first() else {
        return Err(Error::Input(InputError::TooFew {
            what: "path".into(),
            got: 0,
            min: 1,
            of: "configurations".into(),
        }));
    };
    let (mut segments, mut ends) = (Vec::with_capacity(path.len()), Vec::with_capacity(path.len()));
    let mut from = first;
    for to in &path[1..] {
        if to != from {
            segments.push(Ptp::new(robot, from, to, options)?);
            ends.push(to.as_slice());
            from = to;
        }
    }
    if segments.is_empty() {
        segments.push(Ptp::new(robot, first, first, options)?);
        ends.push(first.as_slice());
    }
    let mut samples = 1usize;
    for ptp in &segments {
        samples = samples.saturating_add(sample_count(ptp.duration(), dt)? - 1);
    }
    let n = robot.dof();
    let mut traj = JointTrajectory::reserved(n, samples)?;
    let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut start = 0.0;
    for (k, (ptp, end)) in segments.iter().zip(ends).enumerate() {
        let times = sample_times(ptp.duration(), dt)?;
        // Each segment's first sample is the previous one's last.
        let skip = usize::from(k > 0);
        for &t in &times[skip..] {
            ptp.state_into(t, &mut q, &mut qd, &mut qdd);
            if t == ptp.duration() {
                // The via point itself, not from + 1·(to − from) rounded.
                q.copy_from_slice(end);
            }
            traj.push(start + t, &q, &qd, &qdd)?;
        }
        start += ptp.duration();
    }
    Ok(traj)
}

#[cfg(test)]
mod tests {
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::traj::{check, CheckOptions};

    #[test]
    fn timed_paths_pass_through_every_via_point_at_rest_within_the_limits() {
        let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let options = PtpOptions::for_robot(&robot);
        for _ in 0..40 {
            let count = rng.random_range(2..6);
            let path: Vec<Vec<f64>> = (0..count)
                .map(|_| robot.joints().iter().map(|j| rng.random_range(j.limits.min..j.limits.max) * 0.9).collect())
                .collect();
            let traj = ptp_through(&robot, &path, &options, 0.01).unwrap();
            check(&robot, &traj, &CheckOptions::default()).unwrap().into_result().unwrap();
            for via in &path {
                let k = (0..traj.len()).find(|&k| traj.q(k) == via.as_slice()).expect("a via point is a sample");
                assert!(traj.qd(k).iter().all(|v| v.abs() < 1e-9), "at rest at a via point");
            }
            // Between via points the robot stays on the straight segment.
            for k in 0..traj.len() {
                let q = traj.q(k);
                let on_some = path.windows(2).any(|w| on_segment(&w[0], &w[1], q));
                assert!(on_some, "sample {k} off the path");
            }
        }
    }

    fn on_segment(a: &[f64], b: &[f64], q: &[f64]) -> bool {
        let d: Vec<f64> = b.iter().zip(a).map(|(b, a)| b - a).collect();
        let len2: f64 = d.iter().map(|x| x * x).sum();
        let s =
            if len2 == 0.0 { 0.0 } else { q.iter().zip(a).zip(&d).map(|((q, a), d)| (q - a) * d).sum::<f64>() / len2 };
        (-1e-12..=1.0 + 1e-12).contains(&s) && q.iter().zip(a).zip(&d).all(|((q, a), d)| (q - (a + s * d)).abs() < 1e-9)
    }

    #[test]
    fn an_empty_path_is_refused_by_name() {
        let robot = Robot::builtin("puma560").unwrap();
        let err = ptp_through(&robot, &[], &PtpOptions::for_robot(&robot), 0.01).unwrap_err();
        assert!(err.to_string().contains("path"), "{err}");
    }
}
