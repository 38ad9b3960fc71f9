//! How a redundant arm's self-motion is chosen while it follows a Cartesian
//! path: held, fixed, tracked with minimal joint motion, or steered by an
//! objective (seed 004 §V-E's manipulability along the motion, or distance
//! from the joint limits). The family's redundancy parameter comes through
//! [`Redundancy`]; nothing here names a robot family.

use std::fmt;

use super::cart::CartesianMotion;
use crate::analysis::{manipulability_along, Axes};
use crate::error::{Error, InputError, Result};
use crate::ik::family::{parameter_names, Choice, Redundancy, SelfMotionParameter};
use crate::ik::{self, CandidateSet};
use crate::kin::Frame;
use crate::robot::Robot;

/// The policy for a redundant arm's self-motion along a Cartesian path.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum SelfMotion {
    /// [`SelfMotion::Hold`] for an arm whose solver family has a
    /// self-motion parameter, unless that path cannot be followed or fails
    /// the trajectory check and [`SelfMotion::Manipulability`]'s passes;
    /// [`SelfMotion::Track`] for other redundant arms; nothing for arms
    /// without a self-motion.
    #[default]
    Auto,
    /// The family's first parameter (q3 for the iiwa and other SRS arms) stays
    /// at its value in the start configuration, as industrial controllers hold
    /// the redundancy angle during LIN and CIRC motions.
    Hold,
    /// One of the family's parameters ([`Redundancy::parameters`]) held at
    /// a value, which the start configuration must have; `None` holds the
    /// start's value.
    Fixed {
        /// The parameter.
        parameter: SelfMotionParameter,
        /// Its value \[rad\].
        value: Option<f64>,
    },
    /// The least joint motion per sample: the numeric solver from the
    /// previous sample (damped least squares), the self-motion drifting only
    /// as the steps need.
    Track,
    /// Seed 004 §V-E: the first parameter searched near its previous value
    /// for the largest translational manipulability along the direction of
    /// motion, elbow-up configurations first.
    Manipulability,
    /// The first parameter searched near its previous value for the
    /// configuration furthest from the joint limits.
    AvoidLimits,
}

impl fmt::Display for SelfMotion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SelfMotion::Auto => write!(f, "auto"),
            SelfMotion::Hold => write!(f, "hold"),
            SelfMotion::Fixed { parameter, value: Some(value) } => write!(f, "{parameter} = {value}"),
            SelfMotion::Fixed { parameter, value: None } => write!(f, "{parameter} held"),
            SelfMotion::Track => write!(f, "track"),
            SelfMotion::Manipulability => write!(f, "manipulability"),
            SelfMotion::AvoidLimits => write!(f, "avoid-limits"),
        }
    }
}

impl SelfMotion {
    /// The policy as the CLI's `--q3`/`--psi`, Python's `q3=`/`psi=` and the
    /// language's `REDUNDANCY` write it: for `q3`, a mode (`auto`, `hold`,
    /// `track`, `manipulability`, `avoid-limits`) or a value; for `psi`,
    /// `hold` or a value. A value is in radians times `scale` (π/180 for
    /// degrees).
    ///
    /// # Examples
    /// ```
    /// use kinema::ik::family::SelfMotionParameter::{ArmAngle, Q3};
    /// use kinema::traj::SelfMotion;
    /// assert_eq!(SelfMotion::parse(Q3, "track", 1.0)?, SelfMotion::Track);
    /// assert_eq!(SelfMotion::parse(ArmAngle, "0.5", 1.0)?, SelfMotion::Fixed { parameter: ArmAngle, value: Some(0.5) });
    /// assert!(SelfMotion::parse("psi".parse()?, "track", 1.0).is_err());
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn parse(parameter: SelfMotionParameter, text: &str, scale: f64) -> Result<SelfMotion> {
        let text = text.trim();
        let mode = text.to_ascii_lowercase().replace('_', "-");
        let first = parameter == SelfMotionParameter::Q3;
        match mode.as_str() {
            "auto" if first => return Ok(SelfMotion::Auto),
            "hold" if first => return Ok(SelfMotion::Hold),
            "hold" => return Ok(SelfMotion::Fixed { parameter, value: None }),
            "track" if first => return Ok(SelfMotion::Track),
            "manipulability" if first => return Ok(SelfMotion::Manipulability),
            "avoid-limits" | "avoidlimits" if first => return Ok(SelfMotion::AvoidLimits),
            _ => {}
        }
        match text.parse::<f64>() {
            Ok(v) if (v * scale).is_finite() => Ok(SelfMotion::Fixed { parameter, value: Some(v * scale) }),
            _ => Err(Error::Input(InputError::UnknownName {
                what: parameter.to_string(),
                name: text.into(),
                known: if first {
                    "auto, hold, track, manipulability, avoid-limits, or a finite angle".into()
                } else {
                    "hold, or a finite angle".into()
                },
            })),
        }
    }
}

/// Largest change of the parameter's rate \[rad/s²\] the objective-driven
/// policies ask for (less where the model's limit on its joint is lower):
/// the search looks around the constant-rate prediction within ±a·dt² per
/// decision, so the parameter turns smoothly instead of reversing at full
/// speed (seed 004's rule alone maximises manipulability greedily and
/// chatters).
pub const PARAMETER_ACCELERATION: f64 = 5.0;

/// Period \[s\] at which the objective-driven policies decide the parameter
/// along a path; between decisions it is interpolated and each sample is one
/// closed-form solve.
pub const DECISION_PERIOD: f64 = 0.02;

/// Half-width \[rad\] of the widest window searched around the parameter
/// at a decision.
const WINDOW: f64 = 0.05;

/// How a path's joint values are found for one robot and policy.
pub(crate) enum Plan<'a> {
    /// Each sample from the closed-form candidates at a held value.
    Held { family: &'a dyn Redundancy, parameter: SelfMotionParameter, value: f64 },
    /// Decisions by an objective, interpolated between.
    Steered { family: &'a dyn Redundancy, objective: Objective },
    /// The numeric solver from the previous sample.
    Numeric,
    /// The arm has no self-motion: the generic path.
    None,
}

/// What a steered policy maximises.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Objective {
    Manipulability,
    LimitMargin,
}

/// The plan for `policy` on `robot`, whose fitted family's redundancy is
/// `family`, starting at `q_start`.
pub(crate) fn plan<'a>(
    robot: &Robot,
    family: Option<&'a dyn Redundancy>,
    policy: &SelfMotion,
    q_start: &[f64],
) -> Result<Plan<'a>> {
    let redundant = robot.dof() > 6;
    let refuse = |reason: String| Err(Error::Input(InputError::DoesNotFit { what: "self-motion".into(), reason }));
    if !redundant {
        return match policy {
            SelfMotion::Auto => Ok(Plan::None),
            p => refuse(format!(
                "robot `{}` has {} joints and no self-motion; the `{p}` policy is for redundant arms",
                robot.name(),
                robot.dof()
            )),
        };
    }
    let Some(family) = family else {
        return match policy {
            SelfMotion::Auto | SelfMotion::Track => Ok(Plan::Numeric),
            p => refuse(format!(
                "robot `{}` has no closed-form self-motion parameter for the `{p}` policy; use `track`",
                robot.name()
            )),
        };
    };
    let first = family.parameters()[0];
    Ok(match policy {
        SelfMotion::Auto | SelfMotion::Hold => {
            Plan::Held { family, parameter: first, value: family.parameter_of(q_start, first) }
        }
        SelfMotion::Fixed { parameter, value } => {
            let Some(&name) = family.parameters().iter().find(|p| *p == parameter) else {
                return Err(Error::Input(InputError::UnknownName {
                    what: "self-motion".into(),
                    name: parameter.to_string(),
                    known: parameter_names(family.parameters()),
                }));
            };
            let at_start = family.parameter_of(q_start, name);
            let Some(value) = *value else {
                return Ok(Plan::Held { family, parameter: name, value: at_start });
            };
            if !(value.is_finite() && (at_start - value).abs() <= START_TOLERANCE) {
                return refuse(format!(
                    "the start configuration has {name} = {at_start:.6}, not the {value} the path holds; start \
                     from a configuration with {name} = {value} (`kinema ik … --{name} {value}`) or hold the \
                     start's value"
                ));
            }
            Plan::Held { family, parameter: name, value }
        }
        SelfMotion::Track => Plan::Numeric,
        SelfMotion::Manipulability => Plan::Steered { family, objective: Objective::Manipulability },
        SelfMotion::AvoidLimits => Plan::Steered { family, objective: Objective::LimitMargin },
    })
}

/// How far \[rad\] the start configuration's parameter may be from a fixed value.
const START_TOLERANCE: f64 = 1e-6;

/// A steered path, row-major joint values: the parameter decided every
/// [`DECISION_PERIOD`] by the objective, with its drift limited by its
/// joint's velocity limit, every joint's step by its own, and its rate's
/// change by [`PARAMETER_ACCELERATION`]; in between, the parameter
/// interpolated (cubic Hermite) and the closed-form candidate nearest the
/// previous sample.
pub(crate) fn steered_path(
    robot: &Robot,
    family: &dyn Redundancy,
    objective: Objective,
    motion: &CartesianMotion,
    q_start: &[f64],
    times: &[f64],
) -> Result<Vec<f64>> {
    let n = robot.dof();
    let j = family.joint();
    let parameter = family.parameters()[0];
    let vmax = |i: usize| robot.joints()[i].limits.vel.unwrap_or(f64::INFINITY);
    // The smoothness target, or the joint's own acceleration limit where that is lower.
    let amax = robot.joints()[j].limits.acc.map_or(PARAMETER_ACCELERATION, |a| a.min(PARAMETER_ACCELERATION));
    // One decision: around the parameter's constant-rate prediction first
    // (smooth), else the whole window its velocity limit allows (escaping a
    // joint jump ahead). Returns the configuration and whether it was smooth.
    let decide = |prev: &[f64], rate: f64, t: f64, dt: f64| -> Result<(Vec<f64>, bool)> {
        let st = motion.at(t);
        let dir = (st.vel.norm() > 1e-12).then_some(st.vel);
        let along = |q: &[f64]| -> Result<f64> {
            match (objective, dir) {
                (Objective::Manipulability, Some(v)) => {
                    manipulability_along(&robot.jacobian(q, Frame::Base)?, Axes::Translation, &v)
                }
                (Objective::Manipulability, None) => Ok(0.0),
                (Objective::LimitMargin, _) => Ok(ik::limit_margin(robot, q)),
            }
        };
        // 80 % of each joint's velocity limit: the samples between decisions
        // do not move exactly linearly and must stay within the limit too.
        let steps: Vec<f64> = (0..n).map(|i| 0.8 * vmax(i) * dt).collect();
        let within = |q: &[f64]| q.iter().zip(prev).zip(&steps).all(|((a, b), m)| (a - b).abs() <= *m);
        let choice = |center: f64, window: f64, points: usize| Choice {
            prev,
            center,
            window,
            points,
            max_steps: &steps,
            score: Some(&along),
            family_preference: objective == Objective::Manipulability,
        };
        let window = (0.5 * vmax(j) * dt).min(amax * dt * dt).min(WINDOW);
        let points = if window < WINDOW { 3 } else { 21 };
        let smooth = family.choose(&st.pose, &choice(prev[j] + rate * dt, window, points));
        if let Ok(sol) = &smooth {
            if within(&sol.q) {
                return Ok((sol.q.clone(), true));
            }
        }
        let window = (0.5 * vmax(j) * dt).min(WINDOW);
        let points = if window < WINDOW { 5 } else { 21 };
        match family.choose(&st.pose, &choice(prev[j], window, points)) {
            Ok(sol) => Ok((sol.q, false)),
            Err(e) => match smooth {
                Ok(sol) => Ok((sol.q, false)),
                Err(_) => Err(super::to_joints::at_time(t, e)),
            },
        }
    };
    // Decision samples: every sample at coarse periods, else about every DECISION_PERIOD.
    let mut decisions = vec![0usize];
    for k in 1..times.len() {
        if times[k] - times[*decisions.last().expect("non-empty")] >= DECISION_PERIOD - 1e-12 || k + 1 == times.len() {
            decisions.push(k);
        }
    }
    let mut qs: Vec<f64> = Vec::with_capacity(times.len() * n);
    qs.extend_from_slice(q_start);
    let mut set = CandidateSet::new();
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
        let (q_b, smooth) = decide(&qs[n * a..n * a + n], rate, times[b], times[b] - times[a])?;
        let (pa, pb) = (qs[n * a + j], q_b[j]);
        let mut reanchored = false;
        for k in a + 1..b {
            let t = times[k];
            let u = (t - times[a]) / (times[b] - times[a]);
            let target = motion.at(t).pose;
            let prev = &qs[n * (k - 1)..n * k];
            // After a smooth decision, a cubic Hermite from (pa, rate) to (pb,
            // secant): the rate is continuous at the decisions, so the
            // parameter's acceleration stays near PARAMETER_ACCELERATION
            // instead of impulses. After an escape (a wide-window decision), a
            // straight line, which cannot overshoot towards the singularity.
            let linear = pa + (pb - pa) * u;
            let hermite = if smooth {
                let h = u * u * (2.0 - u);
                pa + (pb - pa) * h + (times[b] - times[a]) * rate * u * (1.0 - u) * (1.0 - u)
            } else {
                linear
            };
            let dt_k = t - times[k - 1];
            let mut found: Option<Vec<f64>> = None;
            for value in [hermite, linear] {
                let picked = family
                    .continue_at(&target, parameter, value, prev, &mut set)
                    .ok()
                    .and_then(|_| set.nearest_within_limits(robot, prev));
                if let Some(i) = picked {
                    if fits(set.q(i), prev, dt_k) && super::to_joints::reaches(robot, set.q(i), &target)? {
                        found = Some(set.q(i).to_vec());
                        break;
                    }
                }
                if hermite == linear {
                    break;
                }
            }
            match found {
                Some(q) => qs.extend_from_slice(&q),
                // The planned value does not work here: decide at this sample
                // and plan the rest of the segment again from it.
                None => {
                    let (q, _) = decide(prev, rate, t, dt_k)?;
                    rate = (q[j] - prev[j]) / dt_k;
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
        let prev = &qs[n * (b - 1)..n * b];
        let dt_b = times[b] - times[b - 1];
        if fits(&q_b, prev, dt_b) {
            rate = (q_b[j] - pa) / (times[b] - times[a]);
            qs.extend_from_slice(&q_b);
        } else {
            // The samples before it drifted from the plan: decide from the last one.
            let (q, _) = decide(prev, rate, times[b], dt_b)?;
            rate = (q[j] - prev[j]) / dt_b;
            qs.extend_from_slice(&q);
        }
        a = b;
        next += 1;
    }
    Ok(qs)
}
