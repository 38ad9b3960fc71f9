//! What a closed-form family offers beyond full poses: typed targets of its
//! own ([`Family`]) and a redundancy parameter for an arm with a
//! self-motion (the iiwa's q3 and arm angle ψ, [`Redundancy`]), with the
//! searches a request makes over it. The request layer asks families
//! through these traits and never names one; which family owns which typed
//! target is written once, in the [`registry`].

use super::registry;
use super::target::{TypedKind, TypedTarget};
use super::{CandidateSet, IkSolver, Solution};
use crate::error::{InputError, Result};
use crate::math::Pose;
use crate::robot::Robot;
use nalgebra::Vector3;

/// A redundancy parameter a family may expose ([`Redundancy::parameters`]):
/// the quantity a request fixes to pick one configuration of an arm's
/// self-motion. Parsed and printed by name (`q3`, `psi`) through
/// [`Named`](crate::Named), so every door reads it the same way.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SelfMotionParameter {
    /// The angle of the joint the family names in [`Redundancy::joint`]
    /// (joint 3 of the iiwa and the other SRS arms, seed 004 §V-B), `q3`.
    Q3,
    /// The arm angle ψ of the elbow about the shoulder–wrist line (seed 004
    /// §V-D), `psi`.
    ArmAngle,
}

/// A closed-form solver family fitted to one robot.
pub trait Family: IkSolver {
    /// Whether this family solves typed targets of `kind`: what its entry
    /// in [`FAMILIES`](registry::FAMILIES) lists (the one place it is
    /// written). A family registered elsewhere ([`registry::fit_in`]) may
    /// override it.
    fn owns(&self, kind: &TypedKind) -> bool {
        registry::lists(self.name(), kind)
    }

    /// Every solution of a typed target this family owns (see
    /// [`Entry::typed`](registry::Entry::typed)); `q0` is the previous configuration, for families
    /// that keep a branch or a side from it.
    fn solve_typed(&self, target: &TypedTarget, q0: Option<&[f64]>) -> Result<Vec<Solution>> {
        let _ = q0;
        Err(crate::Error::Input(crate::InputError::DoesNotFit {
            what: "target".into(),
            reason: format!("the {} solver takes no {}", self.name(), target.kind.described()),
        }))
    }

    /// The orientation error \[rad\] of `reached` against a typed target of
    /// this family, on the components that target fixes.
    fn typed_orientation_error(&self, target: &TypedTarget, reached: &Pose) -> f64 {
        let _ = (target, reached);
        f64::INFINITY
    }

    /// The family's redundancy, if its arm has a self-motion.
    fn redundancy(&self) -> Option<&dyn Redundancy> {
        None
    }

    /// For a family owning tool-angle targets (a point and the tool's angle
    /// about the vertical): their kind, and which joints move the tool in
    /// the plane, along the vertical and about it.
    fn tool_angle_joints(&self) -> Option<ToolAngleJoints> {
        None
    }
}

/// The joints of an arm that takes tool-angle targets, by what each moves:
/// seed 003's relative instructions move the vertical or the roll joint
/// alone (MOVEZ, MOVETITA) and time the planar joints differently from them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ToolAngleJoints {
    /// The joints that place the tool in the horizontal plane (0-based).
    pub planar: &'static [usize],
    /// The joint that moves the tool along the vertical alone.
    pub vertical: usize,
    /// The joint that turns the tool about the vertical alone.
    pub roll: usize,
    /// The kind of the family's tool-angle targets: one angle component.
    pub kind: &'static TypedKind,
}

impl ToolAngleJoints {
    /// The tool-angle target at `position` \[m\] with the tool's angle about
    /// the vertical \[rad\].
    pub fn target(&self, position: [f64; 3], angle: f64) -> Result<TypedTarget> {
        TypedTarget::new(self.kind, position, &[angle])
    }
}

/// The redundancy parameters of a family whose arm has a self-motion (a
/// 7-joint arm reaching a 6-component pose): the closed form at a given
/// value, and the searches a request without one uses.
pub trait Redundancy {
    /// The parameters a request may fix, the first being the one
    /// [`Redundancy::value_of`] reads (e.g. `[Q3, ArmAngle]`).
    fn parameters(&self) -> &'static [SelfMotionParameter];

    /// Every closed-form solution with `parameter` at `value`.
    fn solve_at(&self, target: &Pose, parameter: SelfMotionParameter, value: f64) -> Result<Vec<Solution>>;

    /// The first parameter's value at configuration `q`.
    fn value_of(&self, q: &[f64]) -> f64;

    /// One solution continuing `q0` (the family's rule along a path), the
    /// self-motion searched before the target is refused.
    fn solve_near(&self, target: &Pose, q0: &[f64]) -> Result<Vec<Solution>>;

    /// Solutions within the joint limits: at `prefer` when there are any,
    /// else searched along the self-motion.
    fn solve_searching(&self, target: &Pose, prefer: f64) -> Result<Vec<Solution>>;

    /// The value a request without one starts from.
    fn default_value(&self) -> f64 {
        0.0
    }

    /// The joint whose value the first parameter is (joint 3, index 2, for
    /// the iiwa and the other SRS arms).
    fn joint(&self) -> usize;

    /// The value of `parameter` (one of [`Redundancy::parameters`]) at
    /// configuration `q`; NaN for a parameter the family does not have.
    fn parameter_of(&self, q: &[f64], parameter: SelfMotionParameter) -> f64 {
        if parameter == self.parameters()[0] {
            self.value_of(q)
        } else {
            f64::NAN
        }
    }

    /// The closed-form candidates with `parameter` at `value` that can
    /// continue a path through `prev`, into `out` (cleared first). The
    /// default is every solution of [`Redundancy::solve_at`]; a family may
    /// leave out the branches a path cannot switch to.
    fn continue_at(
        &self,
        target: &Pose,
        parameter: SelfMotionParameter,
        value: f64,
        prev: &[f64],
        out: &mut CandidateSet,
    ) -> Result<()> {
        let _ = prev;
        solutions_into(self, target, parameter, value, out)
    }

    /// The next configuration of a path: the first parameter searched on a
    /// grid around `choice.center`, for each value the candidate within
    /// limits nearest `choice.prev`; candidates within `choice.max_steps`
    /// preferred, then the best `choice.score` (the nearest without one).
    /// A family may put its own preference first (the iiwa's elbow up, seed
    /// 004 §V-E) when `choice.family_preference` is set.
    fn choose(&self, target: &Pose, choice: &Choice) -> Result<Solution>;
}

/// Every solution of [`Redundancy::solve_at`] into `out` (cleared first).
pub fn solutions_into<R: Redundancy + ?Sized>(
    family: &R,
    target: &Pose,
    parameter: SelfMotionParameter,
    value: f64,
    out: &mut CandidateSet,
) -> Result<()> {
    out.clear();
    for s in family.solve_at(target, parameter, value)? {
        out.push(&s.q, s.branch);
    }
    Ok(())
}

/// The names of `parameters`, comma-separated (for messages).
pub fn parameter_names(parameters: &[SelfMotionParameter]) -> String {
    parameters.iter().map(|p| p.to_string()).collect::<Vec<_>>().join(", ")
}

/// An objective over configurations (higher is better).
pub type Score<'a> = dyn Fn(&[f64]) -> Result<f64> + 'a;

/// What [`Redundancy::choose`] searches and how it ranks.
pub struct Choice<'a> {
    /// The previous configuration of the path.
    pub prev: &'a [f64],
    /// The centre of the first parameter's grid \[rad\].
    pub center: f64,
    /// The grid's half-width \[rad\] (0 keeps the centre).
    pub window: f64,
    /// Number of grid points (odd).
    pub points: usize,
    /// Per joint, the step from `prev` \[rad or m\] within which a candidate is preferred.
    pub max_steps: &'a [f64],
    /// The objective to maximise (higher is better); `None` takes the nearest.
    pub score: Option<&'a Score<'a>>,
    /// Whether the family's own preference comes before the score.
    pub family_preference: bool,
}

impl Choice<'_> {
    /// The grid values of the first parameter within `lo..=hi`.
    pub fn grid(&self, lo: f64, hi: f64) -> impl Iterator<Item = (i64, f64)> + '_ {
        let steps = if self.window > 0.0 { (self.points / 2) as i64 } else { 0 };
        let step = if steps > 0 { self.window / steps as f64 } else { 0.0 };
        (-steps..=steps).map(move |k| (k, self.center + k as f64 * step)).filter(move |(_, v)| *v >= lo && *v <= hi)
    }

    /// Checks the grid and the step limits against `dof` joints.
    pub fn check(&self, dof: usize) -> Result<()> {
        use crate::Error;
        if !self.center.is_finite() {
            return Err(Error::Input(InputError::NotFinite { what: "center".into(), value: self.center }));
        }
        if !(self.window >= 0.0 && self.window.is_finite()) {
            return Err(Error::Input(InputError::OutOfRange {
                what: "window".into(),
                value: self.window,
                expected: "a finite half-width ≥ 0".into(),
            }));
        }
        if self.points % 2 == 0 {
            return Err(Error::Input(InputError::OutOfRange {
                what: "points".into(),
                value: self.points as f64,
                expected: "an odd number of grid points".into(),
            }));
        }
        for (what, got) in [("max_steps", self.max_steps.len()), ("prev", self.prev.len())] {
            if got != dof {
                return Err(Error::Input(InputError::WrongLength {
                    what: what.into(),
                    got,
                    expected: dof,
                    of: "one per joint".into(),
                }));
            }
        }
        Ok(())
    }
}

/// [`Redundancy::choose`] for a family with no preference of its own: the
/// grid over its first parameter with [`Redundancy::continue_at`].
pub fn choose_on_grid(robot: &Robot, family: &dyn Redundancy, target: &Pose, choice: &Choice) -> Result<Solution> {
    choice.check(robot.dof())?;
    let lim = robot.joints()[family.joint()].limits;
    let parameter = family.parameters()[0];
    let mut set = CandidateSet::new();
    let mut found: Vec<(Vec<f64>, String)> = Vec::new();
    let mut last_err = None;
    for (_, value) in choice.grid(lim.min, lim.max) {
        match family.continue_at(target, parameter, value, choice.prev, &mut set) {
            Ok(()) => {
                if let Some(i) = set.nearest_within_limits(robot, choice.prev) {
                    found.push((set.q(i).to_vec(), set.branch(i).to_owned()));
                }
            }
            Err(e) => last_err = Some(e),
        }
    }
    if found.is_empty() {
        return Err(last_err.unwrap_or_else(|| crate::Error::Unreachable {
            solver: "self-motion".into(),
            reason: super::Unreachable::JointLimits {
                rejected: vec![format!(
                    "every {parameter} within {:.4} rad of {:.4} leaves a joint limit",
                    choice.window, choice.center
                )],
            },
            closest: None,
        }));
    }
    let small = |q: &[f64]| q.iter().zip(choice.prev).zip(choice.max_steps).all(|((a, b), m)| (a - b).abs() <= *m);
    if found.iter().any(|(q, _)| small(q)) {
        found.retain(|(q, _)| small(q));
    }
    let mut best = (f64::NEG_INFINITY, f64::INFINITY, 0usize);
    for (i, (q, _)) in found.iter().enumerate() {
        let score = match choice.score {
            Some(f) => f(q)?,
            None => 0.0,
        };
        let dist = super::joint_distance(robot, q, choice.prev);
        if score > best.0 || (score == best.0 && dist < best.1) {
            best = (score, dist, i);
        }
    }
    let (q, branch) = found.swap_remove(best.2);
    Solution::evaluate(robot, q, target, branch)
}

/// One sample of the self-motion (seed 004 §V-D, Fig. 7).
#[derive(Debug, Clone, PartialEq)]
pub struct SelfMotionSample {
    /// Arm angle ψ \[rad\] of the sample.
    pub psi: f64,
    /// q3 of the sample \[rad\] (the paper's self-motion parameter).
    pub q3: f64,
    /// Joint values \[rad\]; on the same branch as the input.
    pub q: Vec<f64>,
    /// Elbow position (origin of link frame 3 — DH frame 3 for a DH table — on the axis of joint 4) in the
    /// robot's base (world) coordinates \[m\].
    pub elbow: Vector3<f64>,
    /// Whether every joint is within its limits.
    pub within_limits: bool,
}

/// The self-motion through `q` (seed 004 §V-D, Fig. 7) of an arm whose
/// family has an arm angle ψ: `steps` samples of ψ, equally spaced over a
/// full turn from ψ of `q`, each the closed-form solution on `q`'s branch
/// (the label of the solution at ψ of `q` that is `q`; labels are constant
/// along ψ), with the elbow — the origin of link frame 3, on the elbow's
/// axis — in world coordinates. The same for a DH table, TOML `general`
/// joints or a URDF. Errors: no arm angle, `steps` = 0, a `q` the closed
/// form does not reproduce.
pub fn self_motion(robot: &Robot, family: &dyn Redundancy, q: &[f64], steps: usize) -> Result<Vec<SelfMotionSample>> {
    let infeasible = |what: &str, reason: String| crate::Error::Infeasible { what: what.into(), reason };
    if steps == 0 {
        return Err(super::iiwa::no_steps());
    }
    if !family.parameters().contains(&SelfMotionParameter::ArmAngle) {
        return Err(crate::Error::Input(crate::InputError::DoesNotFit {
            what: "robot".into(),
            reason: format!(
                "robot `{}` has no arm angle ψ to turn (its self-motion parameters: {})",
                robot.name(),
                parameter_names(family.parameters())
            ),
        }));
    }
    if robot.dof() < 4 {
        return Err(crate::Error::Input(crate::InputError::DoesNotFit {
            what: "robot".into(),
            reason: format!("robot `{}` has no elbow frame", robot.name()),
        }));
    }
    let target = robot.fk(q)?.world_from_tool;
    let psi0 = family.parameter_of(q, SelfMotionParameter::ArmAngle);
    let start = family.solve_at(&target, SelfMotionParameter::ArmAngle, psi0)?;
    let branch = start
        .iter()
        .map(|s| (super::joint_distance(robot, &s.q, q), s))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .filter(|(d, _)| *d < 1e-6)
        .map(|(_, s)| s.branch.clone())
        .ok_or_else(|| infeasible("q", format!("the closed form at ψ = {psi0:.6} rad does not reproduce q")))?;
    (0..steps)
        .map(|k| {
            let psi = super::wrap_angle(psi0 + std::f64::consts::TAU * k as f64 / steps as f64);
            let s = family
                .solve_at(&target, SelfMotionParameter::ArmAngle, psi)?
                .into_iter()
                .find(|s| s.branch == branch)
                .ok_or_else(|| infeasible("psi", format!("branch {branch} has no solution at ψ = {psi:.6} rad")))?;
            let elbow = robot.link_frames(&s.q)?[3].pos;
            Ok(SelfMotionSample { psi, q3: s.q[2], within_limits: s.within_limits(), elbow, q: s.q })
        })
        .collect()
}
