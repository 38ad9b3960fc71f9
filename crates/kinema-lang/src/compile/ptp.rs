//! Joint motions (PTP, HOME): the target in joint space, limits from the
//! program and the robot, a time law per joint.

use kinema::traj::{self, Profile, Ptp, PtpOptions};

use crate::ast::{Expr, MotionOpts, Stmt, Target};
use crate::diag::Diagnostic;
use crate::units::Dim;

use super::eval::joint_dim;
use super::scara::Scara;
use super::text::{fmt_joints, keyword_of};
use super::trajectory_check::outside_limits;
use super::{Compiler, PosValue};

impl Compiler<'_> {
    /// HOME [t]: to the robot's home pose.
    pub(super) fn home(&mut self, s: &Stmt, e: Option<&Expr>) {
        let duration = match e {
            Some(e) => match self.value(e, Dim::Time, Some(1.0)) {
                Some(t) => Some(t),
                None => return,
            },
            None => None,
        };
        let home = self.robot.home().to_vec();
        if !matches!(self.scara, Scara::No) {
            // Seed 003 §III-D: cubic for the joints of the XY plane, linear for z and θ.
            let Some(t) = duration.or_else(|| self.missing_duration(s, "HOME")) else { return };
            self.scara_move(s, home, t, "HOME", "home".into());
        } else {
            self.ptp_to(s, home, duration, "home".into());
        }
    }

    /// The error for a motion that needs a duration on this robot and has none.
    fn missing_duration(&mut self, s: &Stmt, what: &str) -> Option<f64> {
        self.err(
            Diagnostic::error(s.span.clone(), format!("{what} needs a duration on this robot"))
                .with_hint(format!("write e.g. `{what} 5` (seconds), as seed 003 does")),
        );
        None
    }

    pub(super) fn ptp(&mut self, s: &Stmt, relative: bool, target: &Target, opts: &MotionOpts) {
        let duration = match &opts.duration {
            Some(d) => match self.value(d, Dim::Time, Some(1.0)) {
                Some(t) => Some(t),
                None => return,
            },
            None => None,
        };
        if opts.blend.is_some() {
            self.warn(
                Diagnostic::warning(s.span.clone(), "BLEND on a PTP is ignored: the motion stops at its target")
                    .with_hint("blending applies to LIN and CIRC"),
            );
        }
        let q_to = if relative {
            match target {
                Target::Joint(items, _) => {
                    let mut q = self.q.clone();
                    for (i, e) in items.iter().enumerate() {
                        let Some(d) = self.value(e, joint_dim(self.robot, i), None) else { return };
                        if let Some(qi) = q.get_mut(i) {
                            *qi += d;
                        }
                    }
                    q
                }
                _ => {
                    let Some(pose) = self.cart_target(target, true) else { return };
                    let Some(q) = self.ik(s, &pose) else { return };
                    q
                }
            }
        } else {
            match self.resolve(target) {
                Some(PosValue::Joint(q)) => q,
                Some(PosValue::Cart(pose)) => {
                    let Some(q) = self.ik(s, &pose) else { return };
                    q
                }
                None => return,
            }
        };
        let text = format!("joints [{}]", fmt_joints(&q_to));
        match &opts.avoid {
            Some(at) => self.ptp_around(s, at, q_to, text),
            None => self.ptp_to(s, q_to, duration, text),
        }
    }

    /// Whether `q_to` is a joint target the robot can take; else the error at `s`.
    pub(super) fn valid_joint_target(&mut self, s: &Stmt, q_to: &[f64]) -> bool {
        if let Err(e) = self.robot.check_q(q_to) {
            self.err(Diagnostic::error(s.span.clone(), e.to_string()));
            return false;
        }
        if let Some(m) = outside_limits(self.robot, q_to) {
            self.err(Diagnostic::error(s.span.clone(), format!("the target puts {m}")));
            return false;
        }
        true
    }

    pub(super) fn ptp_to(&mut self, s: &Stmt, q_to: Vec<f64>, duration: Option<f64>, text: String) {
        if !self.valid_joint_target(s, &q_to) {
            return;
        }
        let kw = keyword_of(&s.kind).to_string();
        let t0 = self.traj.times().last().copied().unwrap_or(0.0);
        let from = self.q.clone();
        let profile = self.profile;
        let j = match duration {
            // Exactly the stated time; the trajectory check reports any limit it breaks.
            Some(t) => {
                let Some(law) = self.law_for(s, profile, t) else { return };
                let laws = vec![law; from.len()];
                self.sample_laws(s, &from, &q_to, &laws)
            }
            None => {
                let o = match self.ptp_options(profile, &from, &q_to) {
                    Ok(o) => o,
                    Err(message) => {
                        self.err(Diagnostic::error(s.span.clone(), format!("{kw}: {message}")));
                        return;
                    }
                };
                let planned = Ptp::new(self.robot, &from, &q_to, &o);
                // Against the program's cap before sampling (a count that cannot be is
                // sample_unchecked's error, reported below).
                let count = planned.as_ref().ok().and_then(|p| traj::sample_count(p.duration(), self.opts.dt).ok());
                if count.is_some_and(|count| !self.room_for(s.span.clone(), count)) {
                    return;
                }
                match planned.and_then(|p| p.sample_unchecked(self.opts.dt)) {
                    Ok(j) => Some(j),
                    Err(e) => {
                        self.err(Diagnostic::error(s.span.clone(), format!("{kw}: {e}")).with_hint(if kw == "HOME" {
                            "give HOME a duration (`HOME 3s`) or set joint limits with JVEL and JACC".to_string()
                        } else {
                            format!(
                                "give the motion a duration (`{kw} … IN 2s`) or set joint limits with JVEL and JACC"
                            )
                        }));
                        return;
                    }
                }
            }
        };
        let Some(j) = j else { return };
        let end = t0 + j.times().last().copied().unwrap_or(0.0);
        if profile == Profile::Linear {
            self.velocity_steps.push((t0, end, from.iter().zip(&q_to).map(|(a, b)| a != b).collect()));
        }
        self.record(s, &kw, t0, end, profile.name(), text);
        self.append(&j, t0);
    }

    /// PTP limits per joint: JVEL/JACC for the joint's kind, capped by the
    /// robot's own limit, else the robot's; the ACC override scales the
    /// accelerations. An S-curve needs jerk limits: without the robot's, a
    /// joint's jerk is 10 × its acceleration per second (full acceleration
    /// reached in 0.1 s).
    pub(super) fn ptp_options(
        &self,
        profile: Profile,
        from: &[f64],
        to: &[f64],
    ) -> std::result::Result<PtpOptions, String> {
        let pick = |given: &[Option<f64>; 2], own: Option<f64>, prismatic: bool| -> Option<f64> {
            match (given[usize::from(prismatic)], own) {
                (Some(g), Some(o)) => Some(g.min(o)),
                (Some(g), None) => Some(g),
                (None, o) => o,
            }
        };
        let joints = self.robot.joints();
        let (mut vel, mut acc) = (Vec::with_capacity(joints.len()), Vec::with_capacity(joints.len()));
        for (i, j) in joints.iter().enumerate() {
            let prismatic = j.kind == kinema::JointType::Prismatic;
            let v = pick(&self.jvel, j.limits.vel, prismatic);
            let a = pick(&self.jacc, j.limits.acc, prismatic).map(|a| a * self.acc_override);
            let moves = to[i] != from[i];
            for (value, what) in [(v, "JVEL"), (a, "JACC")] {
                if value.is_none() && moves {
                    let unit = if prismatic { "mm/s" } else { "deg/s" };
                    let unit = if what == "JACC" { format!("{unit}^2") } else { unit.to_string() };
                    return Err(format!(
                        "joint {} ({}) moves but neither the robot model nor the program gives it {}; set one with `{what} <value> {unit}` or give the motion a duration",
                        i + 1,
                        j.name,
                        if what == "JVEL" { "a speed limit" } else { "an acceleration limit" }
                    ));
                }
            }
            // A joint that does not move needs no limit; any positive value does.
            vel.push(v.unwrap_or(1.0));
            acc.push(a.unwrap_or(1.0));
        }
        let jerk =
            joints.iter().zip(&acc).map(|(j, a)| j.limits.jerk.map_or(10.0 * a, |x| x * self.acc_override)).collect();
        Ok(PtpOptions { profile, vel: Some(vel), acc: Some(acc), jerk: Some(jerk), speed: self.speed, duration: None })
    }
}
