//! The registry of closed-form families ([`FAMILIES`]): the order they are
//! tried in, the typed targets each owns, and the lookups the request layer
//! and the doors make through it (which family fits a robot, which owns a
//! target kind, which kind a door's named components make).
//!
//! Adding a family: a module in `families/` implementing
//! [`ClosedForm`](super::ClosedForm) and [`Family`] (with the [`TypedKind`]s
//! it owns, if any), and one line in [`FAMILIES`].

use super::families::{geo, iiwa, pieper, rommel, scara, scorbot};
use super::family::{Family, ToolAngleJoints};
use super::target::{TypedKind, TypedTarget};
use crate::error::{Error, InputError, Result};
use crate::robot::Robot;

/// One family in the registry.
#[derive(Clone, Copy)]
pub struct Entry {
    /// The family's name, as its solver reports it.
    pub name: &'static str,
    /// The kinds of typed target it owns (declared in its module).
    pub typed: &'static [&'static TypedKind],
    /// Fits the family to a robot, or says why its structure does not fit.
    pub fit: fn(&Robot) -> Result<Box<dyn Family>>,
}

/// A fitted family boxed for [`Entry::fit`].
pub fn boxed<F: Family + 'static>(r: Result<F>) -> Result<Box<dyn Family>> {
    r.map(|f| Box::new(f) as Box<dyn Family>)
}

/// The families, in the order they are tried: the DH readers of the seeds'
/// robots first, then the geometric solvers that read any description — the
/// closed forms, the 1-D searches, the SRS arm, and last the 2-D search that
/// takes any other 6R arm. [`geo::GeoIk`] tries its variants in this order.
pub const FAMILIES: &[Entry] = &[
    Entry { name: "iiwa", typed: &[], fit: |r| boxed(iiwa::IiwaIk::new(r)) },
    Entry { name: "pieper", typed: &[], fit: |r| boxed(pieper::PieperIk::new(r)) },
    Entry { name: "scorbot", typed: &[&scorbot::PITCH_ROLL], fit: |r| boxed(scorbot::ScorbotIk::new(r)) },
    Entry { name: "scara", typed: &[&scara::TOOL_ANGLE], fit: |r| boxed(scara::ScaraIk::new(r)) },
    Entry { name: "rommel", typed: &[&rommel::APPROACH], fit: |r| boxed(rommel::RommelIk::new(r)) },
    Entry { name: "geo-spherical-wrist", typed: &[], fit: |r| boxed(geo::SphericalWristIk::new(r)) },
    Entry { name: "geo-three-parallel", typed: &[], fit: |r| boxed(geo::ThreeParallelIk::new(r)) },
    Entry { name: "geo-three-parallel-search", typed: &[], fit: |r| boxed(geo::ThreeParallelSearchIk::new(r)) },
    Entry { name: "geo-two-intersecting-search", typed: &[], fit: |r| boxed(geo::TwoIntersectingSearchIk::new(r)) },
    Entry { name: "geo-srs", typed: &[], fit: |r| boxed(geo::SrsIk::new(r)) },
    Entry { name: "geo-general", typed: &[], fit: |r| boxed(geo::GeneralIk::new(r)) },
];

/// Whether the entry of [`FAMILIES`] named `family` lists typed targets of `kind`.
pub fn lists(family: &str, kind: &TypedKind) -> bool {
    FAMILIES.iter().any(|e| e.name == family && e.typed.contains(&kind))
}

/// Every kind of typed target the families of `families` own, in registry order.
pub fn typed_kinds(families: &[Entry]) -> Vec<&'static TypedKind> {
    let mut kinds: Vec<&'static TypedKind> = Vec::new();
    for &kind in families.iter().flat_map(|e| e.typed) {
        if !kinds.contains(&kind) {
            kinds.push(kind);
        }
    }
    kinds
}

/// The typed target a door's named components make at `position`: the one
/// kind of [`FAMILIES`] that has them all; `None` when none is given (a
/// position target). Every door (CLI flags, Python keywords, JSON fields)
/// reads typed targets through this, passing the components it offers with
/// `None` for those not given.
pub fn typed_target(position: [f64; 3], offered: &[(&str, Option<&[f64]>)]) -> Result<Option<TypedTarget>> {
    let given: Vec<(&str, &[f64])> = offered.iter().filter_map(|&(name, v)| Some((name, v?))).collect();
    typed_target_in(FAMILIES, position, &given)
}

/// [`typed_target`] over another registry (e.g. [`FAMILIES`] and families of a caller's own).
pub fn typed_target_in(
    families: &[Entry],
    position: [f64; 3],
    given: &[(&str, &[f64])],
) -> Result<Option<TypedTarget>> {
    let Some(&(first, _)) = given.first() else { return Ok(None) };
    let kinds = typed_kinds(families);
    let has = |kind: &TypedKind, name: &str| kind.components.iter().any(|c| c.name == name);
    let listing = || kinds.iter().map(|k| k.described()).collect::<Vec<_>>().join("; ");
    let Some(kind) = kinds.iter().find(|k| has(k, first)) else {
        return Err(Error::Input(InputError::DoesNotFit {
            what: first.into(),
            reason: format!("no typed target has this component; they are: {}", listing()),
        }));
    };
    if let Some(&(other, _)) = given.iter().find(|(name, _)| !has(kind, name)) {
        return Err(Error::Input(InputError::DoesNotFit {
            what: other.into(),
            reason: format!(
                "`{first}` and `{other}` belong to different typed targets; give the components of one: {}",
                listing()
            ),
        }));
    }
    kind.target(position, given).map(Some)
}

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
    kind: &TypedKind,
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
pub fn for_typed(robot: &Robot, kind: &TypedKind) -> Result<Box<dyn Family>> {
    let mut first_error = None;
    for entry in FAMILIES.iter().filter(|e| e.typed.contains(&kind)) {
        match (entry.fit)(robot) {
            Ok(f) => return Ok(f),
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    Err(first_error.unwrap_or_else(|| {
        Error::Input(InputError::DoesNotFit {
            what: "target".into(),
            reason: format!("no registered family owns the {}", kind.described()),
        })
    }))
}

/// The family fitted to `robot` that takes tool-angle targets (a point and
/// the tool's angle about the vertical), with what its joints move; `None`
/// when no family owning a typed kind fits and says it takes them.
pub fn for_tool_angle(robot: &Robot) -> Option<(Box<dyn Family>, ToolAngleJoints)> {
    typed_kinds(FAMILIES).into_iter().find_map(|kind| {
        let family = for_typed(robot, kind).ok()?;
        let joints = family.tool_angle_joints().filter(|j| j.kind == kind)?;
        Some((family, joints))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_typed_kind_has_an_owner_and_names_are_unique() {
        let mut names: Vec<&str> = FAMILIES.iter().map(|e| e.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), FAMILIES.len());
        // A component names one kind, so a door's components say which target they make.
        let kinds = typed_kinds(FAMILIES);
        assert_eq!(kinds.len(), 3);
        let mut components: Vec<&str> = kinds.iter().flat_map(|k| k.components.iter().map(|c| c.name)).collect();
        let count = components.len();
        components.sort_unstable();
        components.dedup();
        assert_eq!(components.len(), count);
    }

    #[test]
    fn named_components_make_the_target_of_their_kind() {
        let p = [0.4, 0.1, 0.3];
        assert_eq!(typed_target(p, &[]).unwrap(), None);
        assert_eq!(typed_target(p, &[("pitch", None)]).unwrap(), None);
        let given: [(&str, Option<&[f64]>); 3] = [("roll", Some(&[0.2])), ("alpha", None), ("pitch", Some(&[0.1]))];
        let t = typed_target(p, &given).unwrap().unwrap();
        assert_eq!((t.kind.name, t.position, t.values()), ("pitch-roll", p, &[0.1, 0.2][..]));
        let t = typed_target(p, &[("approach", Some(&[0.0, 0.0, -2.0]))]).unwrap().unwrap();
        assert_eq!(t.direction("approach"), [0.0, 0.0, -2.0]);
        let message = |given: &[(&str, Option<&[f64]>)]| typed_target(p, given).unwrap_err().to_string();
        assert!(message(&[("pitch", Some(&[0.1]))]).contains("`roll`"));
        assert!(message(&[("alpha", Some(&[0.1])), ("pitch", Some(&[0.1]))])
            .contains("`alpha` and `pitch` belong to different typed targets"));
        assert!(message(&[("yaw", Some(&[0.1]))]).contains("no typed target has this component"));
    }

    #[test]
    fn a_family_owns_the_kinds_its_entry_lists() {
        for name in crate::builtin_names() {
            let robot = Robot::builtin(name).unwrap();
            let Some(entry) = FAMILIES.iter().find(|e| (e.fit)(&robot).is_ok()) else { continue };
            let f = (entry.fit)(&robot).unwrap();
            for kind in typed_kinds(FAMILIES) {
                assert_eq!(f.owns(kind), entry.typed.contains(&kind), "{name} {}", kind.name);
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
