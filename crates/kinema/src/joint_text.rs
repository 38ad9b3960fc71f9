//! Joint values as text, the way every door reads them: a named pose or
//! comma-separated numbers.

use crate::error::{Error, InputError, Result};
use crate::model::JointType;
use crate::robot::Robot;

impl Robot {
    /// Joint values as text (a command line's `--q`, a cell's `start`): a
    /// named pose (`home`, `qr`, …) or comma-separated numbers in rad and m —
    /// or, with `degrees`, degrees for revolute joints (prismatic values stay
    /// in m). Checked for length and finiteness.
    ///
    /// # Examples
    /// ```
    /// let robot = kinema::Robot::builtin("ur5")?;
    /// assert_eq!(robot.parse_q("home", false)?, robot.home());
    /// assert_eq!(robot.parse_q("0, 90, 0, 0, 0, 0", true)?[1], std::f64::consts::FRAC_PI_2);
    /// assert!(robot.parse_q("0, 1, x", false).is_err());
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn parse_q(&self, text: &str, degrees: bool) -> Result<Vec<f64>> {
        let t = text.trim();
        let lower = t.to_ascii_lowercase();
        if t.chars().next().is_some_and(|c| c.is_ascii_alphabetic()) && lower != "nan" && !lower.starts_with("inf") {
            return Ok(self.pose(t)?.to_vec());
        }
        let mut q = Vec::with_capacity(self.dof());
        let mut start = 0; // byte offset of the current item in `t`
        for (i, raw) in t.split(',').enumerate() {
            let item = raw.trim();
            let at = start + (raw.len() - raw.trim_start().len());
            start += raw.len() + 1;
            let v: f64 = item.parse().map_err(|_| {
                Error::Input(InputError::Syntax {
                    what: "joint values".into(),
                    text: t.into(),
                    column: t[..at].chars().count() + 1,
                    expected: format!(
                        "value {} `{item}` is not a number; give {} comma-separated numbers or a named pose ({})",
                        i + 1,
                        self.dof(),
                        self.poses().iter().map(|p| p.name.as_str()).collect::<Vec<_>>().join(", ")
                    ),
                })
            })?;
            let revolute = self.joints().get(i).is_some_and(|j| j.kind == JointType::Revolute);
            q.push(if degrees && revolute { v.to_radians() } else { v });
        }
        self.check_q(&q)?;
        Ok(q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_q_reads_poses_numbers_and_degrees() {
        let robot = Robot::builtin("scara5").unwrap();
        assert_eq!(robot.parse_q("home", false).unwrap(), robot.home());
        // Degrees only for revolute joints.
        let q = robot.parse_q(" 0.5, 90, -90, 0.1, 180 ", true).unwrap();
        assert_eq!((q[0], q[3]), (0.5, 0.1));
        assert!((q[1] - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!((q[4] - std::f64::consts::PI).abs() < 1e-15);
    }

    #[test]
    fn parse_q_rejects_bad_text() {
        let robot = Robot::builtin("scara5").unwrap();
        let e = robot.parse_q("1,2,x", false).unwrap_err();
        let Error::Input(InputError::Syntax { what, column, expected, .. }) = &e else { panic!("{e:?}") };
        assert_eq!((what.as_str(), *column), ("joint values", 5));
        assert!(expected.contains("value 3") && expected.contains("`x`"), "{expected}");
        assert!(expected.contains("home") && expected.contains("qz"), "{expected}");
        for text in ["", ",", "1,,2,3,4", "1;2;3;4;5", "0.5, 90deg, 0, 0, 0", "1 2 3 4 5"] {
            assert!(matches!(robot.parse_q(text, false), Err(Error::Input(InputError::Syntax { .. }))), "{text:?}");
        }
        let e = robot.parse_q("0.5, 90deg, 0, 0, 0", false).unwrap_err();
        assert!(matches!(e, Error::Input(InputError::Syntax { column: 6, .. })), "{e:?}");
        let e = robot.parse_q("0.5, 0, 0, nan, 0", false).unwrap_err();
        assert!(matches!(e, Error::Input(InputError::BadJointValue { joint: 4, .. })), "{e:?}");
        let e = robot.parse_q("inf, 0, 0, 0, 0", true).unwrap_err();
        assert!(matches!(e, Error::Input(InputError::BadJointValue { joint: 1, .. })), "{e:?}");
        let e = robot.parse_q("nan", false).unwrap_err();
        assert!(
            matches!(
                e,
                Error::Input(InputError::JointCount { got: 1, .. }) | Error::Input(InputError::BadJointValue { .. })
            ),
            "{e:?}"
        );
        assert!(matches!(robot.parse_q("qx", false), Err(Error::Input(InputError::UnknownPose { .. }))));
        for len in [1, 4, 6, 9] {
            let e = robot.parse_q(&vec!["0.1"; len].join(","), false).unwrap_err();
            assert!(matches!(e, Error::Input(InputError::JointCount { expected: 5, got, .. }) if got == len), "{e:?}");
        }
    }
}
