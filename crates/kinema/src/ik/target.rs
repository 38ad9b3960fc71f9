//! What the tool must reach: a full pose, a position, or a family's typed
//! target ([`TypedTarget`]). A kind of typed target ([`TypedKind`]) is data
//! the family that owns it declares next to its solver (the Scorbot's
//! pitch and roll, ROMMEL's approach, the SCARA's tool angle); the request
//! layer and the doors read it through the registry and name no family.

use crate::error::{Error, InputError, Result};
use crate::math::Pose;

/// What the tool must reach (see [`solve_target`](super::solve_target)). Positions are tool points
/// in the world frame (the frame of [`Robot::fk`](crate::Robot::fk)) \[m\]; angles \[rad\].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum IkTarget {
    /// A full tool pose `world_from_tool`: the robot's analytic solver or the
    /// numeric one ([`solve_request`](super::solve_request)).
    Pose(Pose),
    /// The tool point alone, the orientation free: the numeric solver with
    /// the position-only task mask \[x, y, z\]. The solutions' residuals are
    /// measured against this position with the orientation of the robot's
    /// `home` pose as a placeholder, so their `orientation_error` means
    /// nothing (see [`IkTarget::orientation_free`]).
    Position([f64; 3]),
    /// The tool point and the orientation components one family's arm
    /// controls, solved by the family that owns its kind.
    Typed(TypedTarget),
}

impl IkTarget {
    /// Whether the orientation is not part of the target ([`IkTarget::Position`]):
    /// then a solution's `orientation_error` is measured against a placeholder
    /// (the `home` orientation) and says nothing about success. The typed
    /// targets measure it against the orientation they fix, so it is ~0.
    pub fn orientation_free(&self) -> bool {
        matches!(self, IkTarget::Position(_))
    }

    /// The typed target, if this is one.
    pub fn typed(&self) -> Option<&TypedTarget> {
        match self {
            IkTarget::Typed(t) => Some(t),
            _ => None,
        }
    }

    /// The tool point of a position or typed target; `None` for a pose.
    pub fn position(&self) -> Option<[f64; 3]> {
        match self {
            IkTarget::Pose(_) => None,
            IkTarget::Position(position) => Some(*position),
            IkTarget::Typed(t) => Some(t.position),
        }
    }
}

/// What one orientation component of a typed target is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// An angle \[rad\]: one value.
    Angle,
    /// A direction in the world frame: three values, any non-zero length.
    Direction,
}

impl Quantity {
    /// How many values the component takes.
    pub fn value_count(self) -> usize {
        match self {
            Quantity::Angle => 1,
            Quantity::Direction => 3,
        }
    }

    /// What its values are, in words.
    fn describe(self) -> &'static str {
        match self {
            Quantity::Angle => "an angle",
            Quantity::Direction => "a direction x, y, z",
        }
    }
}

/// One named component of a typed target beside its tool point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Component {
    /// Its name, as every door reads it (`pitch`, `approach`, …).
    pub name: &'static str,
    /// What it is.
    pub quantity: Quantity,
}

/// The most values the components of one typed target take together.
pub const MAX_TYPED_VALUES: usize = 4;

/// A kind of typed target: the tool point plus named components, declared
/// by the family that owns it and listed in its registry entry.
#[derive(Debug, PartialEq, Eq)]
pub struct TypedKind {
    /// Its name (`pitch-roll`, `approach`, `tool-angle`).
    pub name: &'static str,
    /// Its components, in the order their values are stored.
    pub components: &'static [Component],
    /// Whose target it is and what it fixes, for messages ("Scorbot: position, pitch and roll").
    pub summary: &'static str,
}

impl TypedKind {
    /// The range of values component `name` takes in [`TypedTarget::values`].
    fn span(&self, name: &str) -> Option<std::ops::Range<usize>> {
        let mut start = 0;
        for c in self.components {
            let end = start + c.quantity.value_count();
            if c.name == name {
                return Some(start..end);
            }
            start = end;
        }
        None
    }

    /// Its name and summary, for messages: "`pitch-roll` target (Scorbot: position, pitch and roll)".
    pub fn described(&self) -> String {
        format!("`{}` target ({})", self.name, self.summary)
    }

    /// How many values its components take.
    pub fn value_count(&self) -> usize {
        self.components.iter().map(|c| c.quantity.value_count()).sum()
    }

    /// A kind whose components take more than [`MAX_TYPED_VALUES`] values
    /// cannot be stored: said, not a panic.
    fn check_size(&self) -> Result<()> {
        if self.value_count() > MAX_TYPED_VALUES {
            return Err(invalid(
                "target",
                format!(
                    "a {} takes {} values; a typed target holds at most {MAX_TYPED_VALUES}",
                    self.described(),
                    self.value_count()
                ),
            ));
        }
        Ok(())
    }

    /// The target of this kind at `position` with its components' values,
    /// given by name in any order; every component once, nothing else.
    pub fn target(&'static self, position: [f64; 3], given: &[(&str, &[f64])]) -> Result<TypedTarget> {
        self.check_size()?;
        if let Some((name, _)) = given.iter().enumerate().find_map(|(i, g)| given[..i].iter().find(|h| h.0 == g.0)) {
            return Err(invalid(name, format!("given twice for a {}", self.described())));
        }
        let mut values = [0.0; MAX_TYPED_VALUES];
        for c in self.components {
            let Some((_, v)) = given.iter().find(|(name, _)| *name == c.name) else {
                return Err(invalid(c.name, format!("missing: a {} needs it", self.described())));
            };
            if v.len() != c.quantity.value_count() {
                return Err(Error::Input(InputError::WrongLength {
                    what: c.name.into(),
                    expected: c.quantity.value_count(),
                    got: v.len(),
                    of: format!("{} of a {}", c.quantity.describe(), self.described()),
                }));
            }
            let span = self.span(c.name).expect("a component of this kind");
            values[span].copy_from_slice(v);
        }
        if let Some((name, _)) = given.iter().find(|(name, _)| self.span(name).is_none()) {
            return Err(invalid(name, format!("not a component of a {}", self.described())));
        }
        TypedTarget::new(self, position, &values[..self.value_count()])
    }
}

/// A typed target: the tool point \[m\] and the values of its kind's
/// components, angles \[rad\] and directions (world frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TypedTarget {
    /// Its kind.
    pub kind: &'static TypedKind,
    /// The tool point \[m\].
    pub position: [f64; 3],
    values: [f64; MAX_TYPED_VALUES],
}

impl TypedTarget {
    /// The target of `kind` at `position` with `values` in the order of its
    /// components; all finite, a direction not zero.
    pub fn new(kind: &'static TypedKind, position: [f64; 3], values: &[f64]) -> Result<TypedTarget> {
        kind.check_size()?;
        if values.len() != kind.value_count() {
            return Err(Error::Input(InputError::WrongLength {
                what: format!("{} target values", kind.name),
                expected: kind.value_count(),
                got: values.len(),
                of: format!("the components of a {}, in order", kind.described()),
            }));
        }
        if let Some(&value) = position.iter().find(|v| !v.is_finite()) {
            return Err(Error::Input(InputError::NotFinite { what: "position".into(), value }));
        }
        let mut stored = [0.0; MAX_TYPED_VALUES];
        stored[..values.len()].copy_from_slice(values);
        let target = TypedTarget { kind, position, values: stored };
        for c in kind.components {
            let v = target.component(c.name);
            if let Some(&value) = v.iter().find(|v| !v.is_finite()) {
                return Err(Error::Input(InputError::NotFinite { what: c.name.into(), value }));
            }
            if c.quantity == Quantity::Direction && v.iter().all(|&x| x == 0.0) {
                return Err(invalid(c.name, "a direction cannot be the zero vector".into()));
            }
        }
        Ok(target)
    }

    /// The values of all components, in their kind's order.
    pub fn values(&self) -> &[f64] {
        &self.values[..self.kind.value_count()]
    }

    /// The values of component `name`.
    ///
    /// # Panics
    /// If its kind has no such component: a family reads only its own kinds.
    pub fn component(&self, name: &str) -> &[f64] {
        let span = self.kind.span(name).unwrap_or_else(|| panic!("a {} target has no `{name}`", self.kind.name));
        &self.values[span]
    }

    /// The angle of component `name` \[rad\] (see [`TypedTarget::component`]).
    pub fn angle(&self, name: &str) -> f64 {
        self.component(name)[0]
    }

    /// The direction of component `name` (see [`TypedTarget::component`]).
    pub fn direction(&self, name: &str) -> [f64; 3] {
        let v = self.component(name);
        [v[0], v[1], v[2]]
    }
}

fn invalid(what: &str, reason: String) -> Error {
    Error::Input(InputError::DoesNotFit { what: what.into(), reason })
}

#[cfg(test)]
mod tests {
    use super::*;

    static KIND: TypedKind = TypedKind {
        name: "test",
        components: &[
            Component { name: "heading", quantity: Quantity::Angle },
            Component { name: "axis", quantity: Quantity::Direction },
        ],
        summary: "test: position, heading and axis",
    };

    #[test]
    fn components_are_stored_in_order_and_read_by_name() {
        let given: [(&str, &[f64]); 2] = [("axis", &[0.0, 2.0, 0.0]), ("heading", &[0.5])];
        let t = KIND.target([1.0, 2.0, 3.0], &given).unwrap();
        assert_eq!(t.values(), &[0.5, 0.0, 2.0, 0.0]);
        assert_eq!(t.angle("heading"), 0.5);
        assert_eq!(t.direction("axis"), [0.0, 2.0, 0.0]);
    }

    #[test]
    fn bad_components_are_named() {
        let message = |given: &[(&str, &[f64])]| KIND.target([0.0; 3], given).unwrap_err().to_string();
        assert!(message(&[("heading", &[0.5])]).contains("axis"));
        assert!(message(&[("heading", &[0.5]), ("axis", &[1.0, 0.0])]).contains("axis"));
        assert!(message(&[("heading", &[0.5]), ("axis", &[0.0; 3])]).contains("zero vector"));
        assert!(message(&[("heading", &[f64::NAN]), ("axis", &[1.0, 0.0, 0.0])]).contains("heading"));
        let extra: [(&str, &[f64]); 3] = [("heading", &[0.5]), ("axis", &[1.0, 0.0, 0.0]), ("roll", &[0.0])];
        assert!(message(&extra).contains("invalid `roll`: not a component"), "{}", message(&extra));
        let twice: [(&str, &[f64]); 3] = [("heading", &[0.5]), ("axis", &[1.0, 0.0, 0.0]), ("heading", &[0.1])];
        assert!(message(&twice).contains("invalid `heading`: given twice"), "{}", message(&twice));
    }

    #[test]
    fn a_kind_too_large_to_store_is_refused() {
        static WIDE: TypedKind = TypedKind {
            name: "wide",
            components: &[
                Component { name: "a", quantity: Quantity::Direction },
                Component { name: "b", quantity: Quantity::Direction },
            ],
            summary: "two directions",
        };
        let given: [(&str, &[f64]); 2] = [("a", &[1.0, 0.0, 0.0]), ("b", &[0.0, 1.0, 0.0])];
        assert!(WIDE.target([0.0; 3], &given).unwrap_err().to_string().contains("at most 4"));
        assert!(TypedTarget::new(&WIDE, [0.0; 3], &[0.0; 6]).is_err());
    }
}
