//! Numbers with units in description files (a scene, a cell, a robot's
//! `[[shape]]`s): a plain number in the file's unit, or a string with its
//! unit (`"100mm"`, `"90deg"`, `"20ms"`). One reader, so every file takes
//! the same units and says the same thing about a wrong one.

use serde::de::{self, Deserializer, Visitor};
use serde::Deserialize;

/// What a value measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dim {
    /// m, cm, mm.
    Length,
    /// rad, deg.
    Angle,
    /// s, ms.
    Time,
}

impl Dim {
    /// The units a string may carry, with their size in SI, and how to say what is expected.
    fn units(self) -> (&'static [(&'static str, f64)], &'static str) {
        match self {
            Dim::Length => (&[("m", 1.0), ("cm", 1e-2), ("mm", 1e-3)], "a length (m, cm, mm)"),
            Dim::Angle => (&[("rad", 1.0), ("deg", std::f64::consts::PI / 180.0)], "an angle (rad, deg)"),
            Dim::Time => (&[("s", 1.0), ("ms", 1e-3)], "a time (s, ms)"),
        }
    }
}

/// A value of a file: a plain number, or a string with a unit.
#[derive(Debug, Clone, PartialEq)]
pub enum Quantity {
    /// A number in the file's unit for its dimension.
    Number(f64),
    /// A number glued to its unit, e.g. `"100mm"`.
    Text(String),
}

impl Quantity {
    /// The value in SI units, `plain` being the size in SI of the file's
    /// unit for plain numbers (1 for SI files; a string without a unit is a
    /// plain number); an error message naming the text and the units
    /// expected when it is not `dim` or not finite.
    ///
    /// # Examples
    /// ```
    /// use kinema::quantity::{Dim, Quantity};
    /// assert_eq!(Quantity::Text("250mm".into()).si(Dim::Length, 1.0), Ok(0.25));
    /// assert_eq!(Quantity::Number(250.0).si(Dim::Length, 1e-3), Ok(0.25));
    /// assert!(Quantity::Text("5furlong".into()).si(Dim::Length, 1.0).unwrap_err().contains("unknown unit"));
    /// ```
    pub fn si(&self, dim: Dim, plain: f64) -> Result<f64, String> {
        match self {
            Quantity::Number(v) => finite(v * plain, &v.to_string()),
            Quantity::Text(t) => read(t, dim, plain),
        }
    }
}

/// A number with an optional unit of `dim` (`"0.1"`, `"100mm"`, `"1e-3m"`),
/// in SI; a bare number is taken as SI (a command line's lengths and times).
pub fn parse_with_unit(text: &str, dim: Dim) -> Result<f64, String> {
    read(text, dim, 1.0)
}

/// `text` in SI: its unit's size times its number, `plain` when it has no unit.
fn read(text: &str, dim: Dim, plain: f64) -> Result<f64, String> {
    let t = text.trim();
    // `1e-3m`: an exponent is part of the number.
    let split = t.find(|c: char| c.is_ascii_alphabetic() && c != 'e' && c != 'E').unwrap_or(t.len());
    let (num, unit) = t.split_at(split);
    let (units, what) = dim.units();
    let v: f64 = num.trim().parse().map_err(|_| format!("`{t}` is not {what}"))?;
    let scale = match unit.trim() {
        "" => plain,
        u => match units.iter().find(|(name, _)| *name == u) {
            Some((_, s)) => *s,
            None => return Err(format!("`{t}`: unknown unit `{u}`; expected {what}")),
        },
    };
    finite(v * scale, t)
}

fn finite(v: f64, shown: &str) -> Result<f64, String> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("`{shown}` is not a finite number"))
    }
}

impl<'de> Deserialize<'de> for Quantity {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = Quantity;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number or a string with a unit such as \"100mm\" or \"90deg\"")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Quantity, E> {
                Ok(Quantity::Number(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Quantity, E> {
                Ok(Quantity::Number(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Quantity, E> {
                Ok(Quantity::Number(v as f64))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Quantity, E> {
                Ok(Quantity::Text(v.to_string()))
            }
        }
        d.deserialize_any(V)
    }
}
