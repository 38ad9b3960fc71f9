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
use super::{geo, iiwa, pieper, rommel, scara, scorbot, IkSolver, Solution};
use crate::error::Result;
use crate::math::Pose;
use crate::model::Robot;

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
        Err(crate::Error::InvalidArgument {
            what: "target".into(),
            message: format!("the {} solver takes no {:?} target", self.name(), target.typed_kind()),
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
    /// [`Redundancy::value_of`] reads (e.g. `["q3", "psi"]`).
    fn parameters(&self) -> &'static [&'static str];

    /// Every closed-form solution with `parameter` at `value`.
    fn solve_at(&self, target: &Pose, parameter: &str, value: f64) -> Result<Vec<Solution>>;

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
}

/// One family in the registry.
pub struct Entry {
    /// The family's name, as its solver reports it.
    pub name: &'static str,
    /// The typed targets it owns.
    pub typed: &'static [TypedKind],
    /// Fits the family to a robot, or says why its structure does not fit.
    pub fit: fn(&Robot) -> Result<Box<dyn Family>>,
}

fn boxed<F: Family + 'static>(r: Result<F>) -> Result<Box<dyn Family>> {
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
    FAMILIES.iter().find_map(|e| (e.fit)(robot).ok())
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
