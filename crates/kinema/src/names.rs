//! Option values by name: one spelling of each option type, which the command
//! line, Python, the server and programs all parse with `FromStr` and print
//! with `Display`, so no door keeps its own list.

use std::fmt;
use std::str::FromStr;

use crate::error::{Error, InputError, Result};
use crate::ik::family::SelfMotionParameter;
use crate::ik::SolverChoice;
use crate::kin::Frame;
use crate::math::RpyConvention;
use crate::traj::{Blend, Profile};

/// An option type whose values are a fixed list of names.
pub trait Named: Copy + 'static {
    /// What the option is called in an error (`solver`, `rpy convention`).
    const WHAT: &'static str;
    /// Every value, in the order the names are listed.
    const ALL: &'static [Self];
    /// The value's name.
    fn name(self) -> &'static str;

    /// Every value's name, in order (for help texts and choice lists).
    fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|v| v.name()).collect()
    }

    /// The value named `text` (ASCII case ignored), or an error listing the names.
    fn from_name(text: &str) -> Result<Self> {
        let text = text.trim();
        Self::ALL.iter().copied().find(|v| v.name().eq_ignore_ascii_case(text)).ok_or_else(|| {
            Error::Input(InputError::UnknownName {
                what: Self::WHAT.into(),
                name: text.into(),
                known: Self::names().join(", "),
            })
        })
    }
}

/// `Display` and `FromStr` through [`Named`].
macro_rules! display_and_parse_by_name {
    ($($t:ty),*) => {$(
        impl fmt::Display for $t {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.name())
            }
        }
        impl FromStr for $t {
            type Err = Error;
            fn from_str(s: &str) -> Result<Self> {
                <$t as Named>::from_name(s)
            }
        }
    )*};
}

impl Named for RpyConvention {
    const WHAT: &'static str = "rpy convention";
    const ALL: &'static [Self] = &[RpyConvention::Zyx, RpyConvention::Xyz];
    fn name(self) -> &'static str {
        match self {
            RpyConvention::Zyx => "zyx",
            RpyConvention::Xyz => "xyz",
        }
    }
}

impl Named for SolverChoice {
    const WHAT: &'static str = "solver";
    const ALL: &'static [Self] = &[SolverChoice::Auto, SolverChoice::Analytic, SolverChoice::Numeric];
    fn name(self) -> &'static str {
        match self {
            SolverChoice::Auto => "auto",
            SolverChoice::Analytic => "analytic",
            SolverChoice::Numeric => "numeric",
        }
    }
}

impl Named for Frame {
    const WHAT: &'static str = "frame";
    const ALL: &'static [Self] = &[Frame::Base, Frame::Tool];
    fn name(self) -> &'static str {
        match self {
            Frame::Base => "base",
            Frame::Tool => "tool",
        }
    }
}

impl Named for Profile {
    const WHAT: &'static str = "profile";
    const ALL: &'static [Self] = &Profile::ALL;
    fn name(self) -> &'static str {
        Profile::name(self)
    }
}

impl Named for SelfMotionParameter {
    const WHAT: &'static str = "self-motion parameter";
    const ALL: &'static [Self] = &[SelfMotionParameter::Q3, SelfMotionParameter::ArmAngle];
    fn name(self) -> &'static str {
        match self {
            SelfMotionParameter::Q3 => "q3",
            SelfMotionParameter::ArmAngle => "psi",
        }
    }
}

display_and_parse_by_name!(RpyConvention, SolverChoice, Frame, Profile, SelfMotionParameter);

/// The forms a blend is written in.
const BLEND_FORMS: &str = "decel, none, a time in seconds (0.2) or a distance in metres (0.05m)";

impl fmt::Display for Blend {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Blend::None => f.write_str("none"),
            Blend::Deceleration => f.write_str("decel"),
            Blend::Time(s) => write!(f, "{s}"),
            Blend::Distance(m) => write!(f, "{m}m"),
        }
    }
}

impl FromStr for Blend {
    type Err = Error;
    /// `decel` (or `deceleration`), `none`, seconds (`0.2`) or metres (`0.05m`);
    /// a time or distance must be finite and not negative.
    fn from_str(s: &str) -> Result<Self> {
        let text = s.trim();
        let unknown = || {
            Error::Input(InputError::UnknownName { what: "blend".into(), name: text.into(), known: BLEND_FORMS.into() })
        };
        let amount = |number: &str| match number.trim().parse::<f64>() {
            Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
            _ => Err(unknown()),
        };
        match text.to_ascii_lowercase().as_str() {
            "decel" | "deceleration" => Ok(Blend::Deceleration),
            "none" => Ok(Blend::None),
            lower => match lower.strip_suffix('m') {
                Some(metres) => amount(metres).map(Blend::Distance),
                None => amount(lower.strip_suffix('s').unwrap_or(lower)).map(Blend::Time),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trips<T: Named + fmt::Display + FromStr<Err = Error> + PartialEq + fmt::Debug>() {
        for &v in T::ALL {
            assert_eq!(v.to_string().parse::<T>().unwrap(), v);
            assert_eq!(v.to_string().to_ascii_uppercase().parse::<T>().unwrap(), v);
        }
        let e = "nonsense".parse::<T>().unwrap_err().to_string();
        assert!(e.contains(T::WHAT) && e.contains("nonsense") && T::names().iter().all(|n| e.contains(n)), "{e}");
    }

    #[test]
    fn every_name_reads_back_and_a_wrong_one_lists_the_names() {
        round_trips::<RpyConvention>();
        round_trips::<SolverChoice>();
        round_trips::<Frame>();
        round_trips::<Profile>();
        round_trips::<SelfMotionParameter>();
    }

    #[test]
    fn blends_read_back_and_bad_ones_name_the_forms() {
        for b in [Blend::None, Blend::Deceleration, Blend::Time(0.25), Blend::Distance(0.05), Blend::Time(0.0)] {
            assert_eq!(b.to_string().parse::<Blend>().unwrap(), b);
        }
        assert_eq!("0.2s".parse::<Blend>().unwrap(), Blend::Time(0.2));
        assert_eq!(" Deceleration ".parse::<Blend>().unwrap(), Blend::Deceleration);
        for bad in ["", "m", "-1", "0.1x", "nanm", "inf", "fast"] {
            let e = bad.parse::<Blend>().unwrap_err().to_string();
            assert!(e.contains("blend") && e.contains("0.05m"), "{bad}: {e}");
        }
    }
}
