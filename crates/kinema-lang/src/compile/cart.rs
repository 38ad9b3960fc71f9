//! Cartesian motions (LIN, CIRC): segments gathered into blended chains,
//! timed together and converted to joint samples.

use kinema::math::Pose;
use kinema::traj::{self, Blend, CartesianLimits, CartesianMotion, JointMethod, Orientation, Profile, Segment};

use crate::ast::{MotionOpts, Stmt, StmtKind, Target};
use crate::diag::Diagnostic;
use crate::lexer::Span;
use crate::units::Dim;

use super::eval::eval;
use super::text::{describe_pose, fmt_xyz};
use super::{Compiler, PlannedMotion};

/// Cartesian segments waiting for the end of a blended chain.
pub(super) struct Chain {
    segments: Vec<Segment>,
    /// (statement, line, keyword, target text) of each segment.
    owners: Vec<(Span, usize, &'static str, String)>,
    blend: Option<f64>,
    blend_is_time: bool,
    duration: Option<f64>,
    /// Some motions of the chain have IN, others not.
    partial_in: bool,
    /// Blends given both as lengths and as times.
    mixed_blend: bool,
}

/// Failed conversions remembered (the most recent ones).
const FAILED_CONVERSIONS_KEPT: usize = 16;

impl Compiler<'_> {
    /// LIN target: a straight line, added to the pending chain.
    pub(super) fn lin(&mut self, s: &Stmt, relative: bool, target: &Target, opts: &MotionOpts) {
        let Some(to) = self.cart_target(target, relative) else { return };
        if self.skip_if_unreachable(s, &to) {
            return;
        }
        let from = self.chain_end();
        match Segment::lin(&from, &to, Orientation::Slerp) {
            Ok(seg) => self.push_segment(s, seg, opts, describe_pose(&to)),
            Err(e) => self.err(Diagnostic::error(s.span.clone(), format!("LIN: {e}"))),
        }
    }

    /// CIRC aux, target: an arc through `aux`, added to the pending chain.
    pub(super) fn circ(&mut self, s: &Stmt, aux: &Target, target: &Target, opts: &MotionOpts) {
        let (Some(a), Some(to)) = (self.cart_target(aux, false), self.cart_target(target, false)) else {
            return;
        };
        if self.skip_if_unreachable(s, &to) {
            return;
        }
        let from = self.chain_end();
        match Segment::circ_through(&from, &a.pos, &to) {
            Ok(seg) => {
                self.push_segment(s, seg, opts, format!("through ({}) to {}", fmt_xyz(&a.pos), describe_pose(&to)))
            }
            Err(e) => {
                self.err(Diagnostic::error(s.span.clone(), format!("CIRC: {e}")).with_hint(
                    "the start, the auxiliary point and the end must be three distinct points not on one line",
                ))
            }
        }
    }

    /// Where the robot is at the end of the pending chain (or now).
    pub(super) fn chain_end(&self) -> Pose {
        match &self.chain {
            Some(c) => c.segments.last().map(Segment::end).unwrap_or_else(|| self.current_pose()),
            None => self.current_pose(),
        }
    }

    fn push_segment(&mut self, s: &Stmt, seg: Segment, opts: &MotionOpts, target: String) {
        let blend = match &opts.blend {
            Some(b) => match eval(b, &self.counters) {
                Ok(q) => Some((q.value, q.dim == Dim::Time)),
                Err(d) => {
                    self.err(d);
                    return;
                }
            },
            None => None,
        };
        let duration = match &opts.duration {
            Some(d) => match self.value(d, Dim::Time, Some(1.0)) {
                Some(t) => Some(t),
                None => return,
            },
            None => None,
        };
        let kw: &'static str = if matches!(s.kind, StmtKind::Circ { .. }) { "CIRC" } else { "LIN" };
        let line = self.line(&s.span);
        let chain = self.chain.get_or_insert_with(|| Chain {
            segments: Vec::new(),
            owners: Vec::new(),
            blend: None,
            blend_is_time: false,
            duration: None,
            partial_in: false,
            mixed_blend: false,
        });
        chain.segments.push(seg);
        chain.owners.push((s.span.clone(), line, kw, target));
        // IN on a chain: the durations add up when every motion of it has one.
        chain.duration = match (chain.segments.len(), chain.duration, duration) {
            (1, _, d) => d,
            (_, Some(total), Some(d)) => Some(total + d),
            (_, None, None) => None,
            _ => {
                chain.partial_in = true;
                None
            }
        };
        match blend {
            Some((b, is_time)) => {
                // One blend per chain: the smallest asked for.
                match chain.blend {
                    None => {
                        chain.blend = Some(b);
                        chain.blend_is_time = is_time;
                    }
                    Some(c) if chain.blend_is_time == is_time => chain.blend = Some(c.min(b)),
                    Some(_) => chain.mixed_blend = true,
                }
            }
            None => self.flush_chain(),
        }
    }

    /// Plans, samples and appends the pending Cartesian chain.
    pub(super) fn flush_chain(&mut self) {
        let Some(chain) = self.chain.take() else { return };
        let first = chain.owners[0].0.clone();
        if chain.mixed_blend {
            self.warn(
                Diagnostic::warning(
                    first.clone(),
                    "this blended chain mixes BLEND lengths and times: only the kind given first is used",
                )
                .with_hint("give every BLEND of a chain in mm/m or every one in s"),
            );
        }
        if chain.partial_in {
            self.warn(
                Diagnostic::warning(
                    first.clone(),
                    "IN is ignored on this blended chain: give it on every motion of the chain or on none",
                )
                .with_hint("the chain is timed as one motion; its duration is the sum of the motions' IN"),
            );
        }
        let blend = match chain.blend {
            Some(b) if chain.segments.len() > 1 => {
                if chain.blend_is_time {
                    Blend::Time(b)
                } else {
                    Blend::Distance(b)
                }
            }
            _ => Blend::None,
        };
        let (k, ka) = (self.speed, self.acc_override);
        let limits = CartesianLimits {
            vel: self.cart.vel * k,
            acc: self.cart.acc * k * k * ka,
            jerk: self.cart.jerk.map(|j| j * k * k * k * ka),
            rot_vel: self.cart.rot_vel * k,
            rot_acc: self.cart.rot_acc * k * k * ka,
            rot_jerk: self.cart.rot_jerk.map(|j| j * k * k * k * ka),
        };
        let profile = if self.profile.rest_to_rest() { self.profile } else { Profile::Trapezoid };
        let stop = &self.opts.stop;
        let planned =
            CartesianMotion::new_until(chain.segments.clone(), profile, &limits, blend, &|| stop.reason().is_some());
        let mut motion = match planned {
            Ok(m) => m,
            Err(kinema::Error::Cancelled) => {
                if let Some(why) = self.opts.stop.reason() {
                    self.err(Diagnostic::error(first, format!("stopped here: {why}")));
                }
                self.stopped = true;
                return;
            }
            Err(e) => {
                self.err(Diagnostic::error(first, format!("cannot time this motion: {e}")));
                return;
            }
        };
        if let Some(d) = chain.duration {
            match motion.stretched_to(d) {
                Ok(m) => motion = m,
                Err(e) => {
                    self.err(
                        Diagnostic::error(first, format!("{e}"))
                            .with_hint("IN asks for an exact duration; it cannot be shorter than the motion allows at this SPEED/VEL/ACC"),
                    );
                    return;
                }
            }
        }
        if let Blend::Distance(_) | Blend::Time(_) = blend {
            for (i, b) in motion.blend_times().iter().enumerate() {
                if *b <= 0.0 {
                    let (span, line, ..) = &chain.owners[i];
                    self.warn(
                        Diagnostic::warning(
                            span.clone(),
                            format!("the blend after line {line} was reduced to nothing: the corner is too sharp for the limits with this profile"),
                        )
                        .with_hint("PROFILE scurve can blend sharper corners; or lower the speed"),
                    );
                }
            }
        }
        let Some(times) = self.sample_times(first.clone(), motion.duration()) else { return };
        let failed_before = self
            .failed_conversions
            .iter()
            .find(|(m, policy, tool, q, _)| {
                *tool == self.tool_generation
                    && q.as_slice() == self.q.as_slice()
                    && *m == motion
                    && *policy == self.self_motion
            })
            .map(|(.., e)| e.clone());
        let converted = match failed_before {
            Some(e) => Err(e),
            None => traj::to_joints_at(
                &self.robot_tool,
                &motion,
                &self.q,
                &times,
                JointMethod::Ik(self.self_motion.clone()),
            )
            .map_err(|e| {
                let e = e.to_string();
                if self.failed_conversions.len() == FAILED_CONVERSIONS_KEPT {
                    self.failed_conversions.remove(0);
                }
                self.failed_conversions.push((
                    motion.clone(),
                    self.self_motion.clone(),
                    self.tool_generation,
                    self.q.clone(),
                    e.clone(),
                ));
                e
            }),
        };
        let joints = match converted {
            Ok(j) => j,
            Err(e) => {
                // Which segment: the time in the error, else the first.
                let owner = chain.owners.first().expect("non-empty").clone();
                self.err(
                    Diagnostic::error(owner.0, format!("{} cannot be followed: {e}", owner.2))
                        .with_hint("move the target, change the start configuration, or use PTP"),
                );
                return;
            }
        };
        let t0 = self.traj.times().last().copied().unwrap_or(0.0);
        let starts = motion.segment_starts().to_vec();
        for (i, (span, line, kw, target)) in chain.owners.iter().enumerate() {
            let end = if i + 1 < chain.owners.len() { starts[i + 1] } else { motion.duration() };
            self.plan_motions.push(PlannedMotion {
                line: *line,
                kind: kw.to_string(),
                start: t0 + starts[i],
                end: t0 + end.max(starts[i]),
                profile: profile.name().to_string(),
                target: target.clone(),
            });
            self.motion_spans.push(span.clone());
        }
        self.append(&joints, t0);
    }
}
