//! Closed-form solver families as plugins. A family recognises the robots
//! it can solve from their structure (each solver's `new` tests the joint
//! axes or the table, never names), solves full poses ([`IkSolver`]), and may
//! also solve typed targets of its own and expose a redundancy parameter
//! (the iiwa's q3 and arm angle ψ). Families register in [`FAMILIES`], in the
//! order they are tried; the request layer asks them through this trait and
//! never names one.
//!
//! Adding a family: a module implementing [`IkSolver`] and [`Family`], and
//! one line in [`FAMILIES`].

use super::request::IkTarget;
use super::{geo, iiwa, pieper, rommel, scara, scorbot, CandidateSet, IkSolver, Solution};
use crate::error::Result;
use crate::math::Pose;
use crate::robot::Robot;
use nalgebra::Vector3;

/// The kinds of typed target (a tool point plus the components a family's
/// arm controls), as [`IkTarget`] has them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TypedKind {
    /// [`IkTarget::PositionPitchRoll`].
    PitchRoll,
    /// [`IkTarget::PositionApproach`].
    Approach,
    /// [`IkTarget::PositionAlpha`].
    Alpha,
}

impl IkTarget {
    /// The typed kind of this target; `None` for a pose or a position.
    pub fn typed_kind(&self) -> Option<TypedKind> {
        match self {
            IkTarget::Pose(_) | IkTarget::Position(_) => None,
            IkTarget::PositionPitchRoll { .. } => Some(TypedKind::PitchRoll),
            IkTarget::PositionApproach { .. } => Some(TypedKind::Approach),
            IkTarget::PositionAlpha { .. } => Some(TypedKind::Alpha),
        }
    }

    /// The tool point of a position or typed target; `None` for a pose.
    pub fn position(&self) -> Option<[f64; 3]> {
        match *self {
            IkTarget::Pose(_) => None,
            IkTarget::Position(position)
            | IkTarget::PositionPitchRoll { position, .. }
            | IkTarget::PositionApproach { position, .. }
            | IkTarget::PositionAlpha { position, .. } => Some(position),
        }
    }
}

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
    /// Whether this family solves typed targets of `kind` (its entry in
    /// [`FAMILIES`] lists the same kinds).
    fn owns(&self, kind: TypedKind) -> bool {
        let _ = kind;
        false
    }

    /// Every solution of a typed target this family owns (see
    /// [`Entry::typed`]); `q0` is the previous configuration, for families
    /// that keep a branch or a side from it.
    fn solve_typed(&self, target: &IkTarget, q0: Option<&[f64]>) -> Result<Vec<Solution>> {
        let _ = q0;
        Err(crate::Error::DoesNotFit {
            what: "target".into(),
            reason: format!("the {} solver takes no {:?} target", self.name(), target.typed_kind()),
        })
    }

    /// The orientation error \[rad\] of `reached` against a typed target of
    /// this family, on the components that target fixes.
    fn typed_orientation_error(&self, target: &IkTarget, reached: &Pose) -> f64 {
        let _ = (target, reached);
        f64::INFINITY
    }

    /// The family's redundancy, if its arm has a self-motion.
    fn redundancy(&self) -> Option<&dyn Redundancy> {
        None
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
            return Err(Error::NotFinite { what: "center".into(), value: self.center });
        }
        if !(self.window >= 0.0 && self.window.is_finite()) {
            return Err(Error::OutOfRange {
                what: "window".into(),
                value: self.window,
                expected: "a finite half-width ≥ 0".into(),
            });
        }
        if self.points % 2 == 0 {
            return Err(Error::OutOfRange {
                what: "points".into(),
                value: self.points as f64,
                expected: "an odd number of grid points".into(),
            });
        }
        for (what, got) in [("max_steps", self.max_steps.len()), ("prev", self.prev.len())] {
            if got != dof {
                return Err(Error::WrongLength { what: what.into(), got, expected: dof, of: "one per joint".into() });
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
        return Err(crate::Error::DoesNotFit {
            what: "robot".into(),
            reason: format!(
                "robot `{}` has no arm angle ψ to turn (its self-motion parameters: {})",
                robot.name(),
                parameter_names(family.parameters())
            ),
        });
    }
    if robot.dof() < 4 {
        return Err(crate::Error::DoesNotFit {
            what: "robot".into(),
            reason: format!("robot `{}` has no elbow frame", robot.name()),
        });
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

/// One family in the registry.
#[derive(Clone, Copy)]
pub struct Entry {
    /// The family's name, as its solver reports it.
    pub name: &'static str,
    /// The typed targets it owns.
    pub typed: &'static [TypedKind],
    /// Fits the family to a robot, or says why its structure does not fit.
    pub fit: fn(&Robot) -> Result<Box<dyn Family>>,
}

/// A fitted family boxed for [`Entry::fit`].
pub fn boxed<F: Family + 'static>(r: Result<F>) -> Result<Box<dyn Family>> {
    r.map(|f| Box::new(f) as Box<dyn Family>)
}

/// The families, in the order they are tried: the DH readers of the seeds'
/// robots first, then the geometric solvers that read any description.
pub const FAMILIES: &[Entry] = &[
    Entry { name: "iiwa", typed: &[], fit: |r| boxed(iiwa::IiwaIk::new(r)) },
    Entry { name: "pieper", typed: &[], fit: |r| boxed(pieper::PieperIk::new(r)) },
    Entry { name: "scorbot", typed: &[TypedKind::PitchRoll], fit: |r| boxed(scorbot::ScorbotIk::new(r)) },
    Entry { name: "scara", typed: &[TypedKind::Alpha], fit: |r| boxed(scara::ScaraIk::new(r)) },
    Entry { name: "rommel", typed: &[TypedKind::Approach], fit: |r| boxed(rommel::RommelIk::new(r)) },
    Entry { name: "geo", typed: &[], fit: |r| boxed(geo::GeoIk::new(r)) },
    Entry { name: "geo-srs", typed: &[], fit: |r| boxed(geo::SrsIk::new(r)) },
    Entry { name: "geo-general", typed: &[], fit: |r| boxed(geo::GeneralIk::new(r)) },
];

/// The first family in [`FAMILIES`] that fits `robot`.
pub fn fit(robot: &Robot) -> Option<Box<dyn Family>> {
    fit_in(FAMILIES, robot)
}

/// The first family of `families` that fits `robot`: [`fit`] over another
/// registry, e.g. [`FAMILIES`] and families of a caller's own, for
/// [`solve_target_with`](super::solve_target_with).
pub fn fit_in(families: &[Entry], robot: &Robot) -> Option<Box<dyn Family>> {
    families.iter().find_map(|e| (e.fit)(robot).ok())
}

/// Runs `task` with the family that owns typed targets of `kind`: `fitted`
/// when it does, else the one [`for_typed`] fits (or its error).
pub(crate) fn with_owner<T>(
    robot: &Robot,
    fitted: Option<&dyn Family>,
    kind: TypedKind,
    task: impl FnOnce(&dyn Family) -> Result<T>,
) -> Result<T> {
    if let Some(f) = fitted.filter(|f| f.owns(kind)) {
        return task(f);
    }
    task(for_typed(robot, kind)?.as_ref())
}

/// The family that owns typed targets of `kind`, fitted to `robot`; the
/// owner's own error when the robot is not of its kind ("the Scorbot solver
/// needs 5 revolute joints …").
pub fn for_typed(robot: &Robot, kind: TypedKind) -> Result<Box<dyn Family>> {
    let mut first_error = None;
    for entry in FAMILIES.iter().filter(|e| e.typed.contains(&kind)) {
        match (entry.fit)(robot) {
            Ok(f) => return Ok(f),
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    Err(first_error.expect("every typed kind has a family in FAMILIES"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_typed_kind_has_an_owner_and_names_are_unique() {
        for kind in [TypedKind::PitchRoll, TypedKind::Approach, TypedKind::Alpha] {
            assert!(FAMILIES.iter().any(|e| e.typed.contains(&kind)), "{kind:?}");
        }
        let mut names: Vec<&str> = FAMILIES.iter().map(|e| e.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), FAMILIES.len());
    }

    #[test]
    fn a_family_owns_the_kinds_its_entry_lists() {
        for name in crate::builtin_names() {
            let robot = Robot::builtin(name).unwrap();
            let Some(entry) = FAMILIES.iter().find(|e| (e.fit)(&robot).is_ok()) else { continue };
            let f = (entry.fit)(&robot).unwrap();
            for kind in [TypedKind::PitchRoll, TypedKind::Approach, TypedKind::Alpha] {
                assert_eq!(f.owns(kind), entry.typed.contains(&kind), "{name} {kind:?}");
            }
        }
    }

    #[test]
    fn the_builtin_robots_get_the_family_their_solver_reports() {
        for name in crate::builtin_names() {
            let robot = Robot::builtin(name).unwrap();
            if let Some(f) = fit(&robot) {
                let entry = FAMILIES.iter().find(|e| (e.fit)(&robot).is_ok()).unwrap();
                assert!(f.name().starts_with(entry.name), "{name}: {} from entry {}", f.name(), entry.name);
            }
        }
    }
}
