//! Quantities with dimensions: units as written in programs, SI inside.

use std::f64::consts::PI;
use std::fmt;

/// The dimension of a value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dim {
    /// A plain number (counts, factors).
    None,
    /// m
    Length,
    /// rad
    Angle,
    /// s
    Time,
    /// A fraction written in % (stored as a fraction: 50% = 0.5).
    Percent,
    /// m/s
    LinVel,
    /// rad/s
    AngVel,
    /// m/s²
    LinAcc,
    /// rad/s²
    AngAcc,
}

impl Dim {
    /// How the dimension is named in messages, with its units.
    pub fn describe(self) -> &'static str {
        match self {
            Dim::None => "a plain number",
            Dim::Length => "a length (mm, cm, m)",
            Dim::Angle => "an angle (deg, rad)",
            Dim::Time => "a time (s, ms)",
            Dim::Percent => "a percentage (%)",
            Dim::LinVel => "a linear speed (mm/s, m/s)",
            Dim::AngVel => "an angular speed (deg/s, rad/s)",
            Dim::LinAcc => "a linear acceleration (mm/s^2, m/s^2)",
            Dim::AngAcc => "an angular acceleration (deg/s^2, rad/s^2)",
        }
    }
}

impl fmt::Display for Dim {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.describe())
    }
}

/// Scale to SI and dimension of a unit (lower case), or `None` if unknown.
pub fn unit(u: &str) -> Option<(f64, Dim)> {
    let deg = PI / 180.0;
    Some(match u {
        "mm" => (1e-3, Dim::Length),
        "cm" => (1e-2, Dim::Length),
        "m" => (1.0, Dim::Length),
        "deg" => (deg, Dim::Angle),
        "rad" => (1.0, Dim::Angle),
        "s" => (1.0, Dim::Time),
        "ms" => (1e-3, Dim::Time),
        "%" => (1e-2, Dim::Percent),
        "mm/s" => (1e-3, Dim::LinVel),
        "m/s" => (1.0, Dim::LinVel),
        "deg/s" => (deg, Dim::AngVel),
        "rad/s" => (1.0, Dim::AngVel),
        "mm/s^2" => (1e-3, Dim::LinAcc),
        "m/s^2" => (1.0, Dim::LinAcc),
        "deg/s^2" => (deg, Dim::AngAcc),
        "rad/s^2" => (1.0, Dim::AngAcc),
        _ => return None,
    })
}

/// A value in SI units with its dimension.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quantity {
    /// The value in SI units (m, rad, s; a fraction for %).
    pub value: f64,
    /// Its dimension.
    pub dim: Dim,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lexer::UNITS;

    #[test]
    fn every_unit_the_lexer_knows_has_a_scale() {
        for u in UNITS {
            assert!(unit(u).is_some(), "{u}");
        }
        assert_eq!(unit("deg").unwrap().0, PI / 180.0);
        assert_eq!(unit("mm/s^2").unwrap(), (1e-3, Dim::LinAcc));
    }
}
