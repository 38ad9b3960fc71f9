//! The registry of closed-form families ([`FAMILIES`]): the order they are
//! tried in, the typed targets each owns, and the lookups the request layer
//! makes through it (which family fits a robot, which owns a target kind).
//!
//! Adding a family: a module in `families/` implementing
//! [`ClosedForm`](super::ClosedForm) and [`Family`], and one line in [`FAMILIES`].

use super::families::{geo, iiwa, pieper, rommel, scara, scorbot};
use super::family::Family;
use super::target::TypedKind;
use crate::error::Result;
use crate::robot::Robot;

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
/// robots first, then the geometric solvers that read any description — the
/// closed forms, the 1-D searches, the SRS arm, and last the 2-D search that
/// takes any other 6R arm. [`geo::GeoIk`] tries its variants in this order.
pub const FAMILIES: &[Entry] = &[
    Entry { name: "iiwa", typed: &[], fit: |r| boxed(iiwa::IiwaIk::new(r)) },
    Entry { name: "pieper", typed: &[], fit: |r| boxed(pieper::PieperIk::new(r)) },
    Entry { name: "scorbot", typed: &[TypedKind::PitchRoll], fit: |r| boxed(scorbot::ScorbotIk::new(r)) },
    Entry { name: "scara", typed: &[TypedKind::Alpha], fit: |r| boxed(scara::ScaraIk::new(r)) },
    Entry { name: "rommel", typed: &[TypedKind::Approach], fit: |r| boxed(rommel::RommelIk::new(r)) },
    Entry { name: "geo-spherical-wrist", typed: &[], fit: |r| boxed(geo::SphericalWristIk::new(r)) },
    Entry { name: "geo-three-parallel", typed: &[], fit: |r| boxed(geo::ThreeParallelIk::new(r)) },
    Entry { name: "geo-three-parallel-search", typed: &[], fit: |r| boxed(geo::ThreeParallelSearchIk::new(r)) },
    Entry { name: "geo-two-intersecting-search", typed: &[], fit: |r| boxed(geo::TwoIntersectingSearchIk::new(r)) },
    Entry { name: "geo-srs", typed: &[], fit: |r| boxed(geo::SrsIk::new(r)) },
    Entry { name: "geo-general", typed: &[], fit: |r| boxed(geo::GeneralIk::new(r)) },
];

/// Whether the entry of [`FAMILIES`] named `family` lists typed targets of `kind`.
pub fn lists(family: &str, kind: TypedKind) -> bool {
    FAMILIES.iter().any(|e| e.name == family && e.typed.contains(&kind))
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
