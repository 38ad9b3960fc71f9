//! Built-in robots (embedded from `robots/*.toml`) and loading by name or path.

use std::path::Path;

use crate::error::{Error, InputError, ModelError, Result};
use crate::robot::Robot;

include!(concat!(env!("OUT_DIR"), "/builtin_robots.rs"));

/// The largest robot description file that [`Robot::from_file`] reads
/// \[bytes\]: 16 MiB, far above any real description (the largest URDF in the
/// tests is 20 KiB), so that `/dev/zero` or a FIFO given by mistake is refused
/// instead of filling the memory.
pub const MAX_DESCRIPTION_BYTES: u64 = 16 << 20;

/// Names of the built-in robots, sorted.
pub fn builtin_names() -> impl Iterator<Item = &'static str> {
    BUILTIN.iter().map(|(name, _)| *name)
}

/// The TOML text of a built-in robot.
pub fn builtin_source(name: &str) -> Option<&'static str> {
    BUILTIN.iter().find(|(n, _)| *n == name).map(|(_, text)| *text)
}

impl Robot {
    /// A built-in robot by name (see [`builtin_names`]).
    ///
    /// # Examples
    /// ```
    /// let robot = kinema::Robot::builtin("scorbot-er-v-plus")?;
    /// assert_eq!(robot.dof(), 5);
    /// assert!(kinema::Robot::builtin("r2d2").is_err());
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn builtin(name: &str) -> Result<Robot> {
        let text = builtin_source(name).ok_or_else(|| {
            Error::Model(ModelError::UnknownRobot {
                name: name.to_string(),
                known: builtin_names().collect::<Vec<_>>().join(", "),
            })
        })?;
        Robot::from_toml_str(text, &format!("robots/{name}.toml"))
    }

    /// Every built-in robot, in name order.
    pub fn builtins() -> Result<Vec<Robot>> {
        builtin_names().map(Robot::builtin).collect()
    }

    /// Parses a TOML robot description (`file` appears in error messages).
    pub fn from_toml_str(text: &str, file: &str) -> Result<Robot> {
        crate::desc::robot_from_toml(text, file)
    }

    /// Parses a URDF and takes the chain from the root link to `tip`
    /// (default: the only leaf link).
    pub fn from_urdf_str(text: &str, file: &str, tip: Option<&str>) -> Result<Robot> {
        crate::urdf::robot_from_urdf(text, file, tip)
    }

    /// As [`Robot::from_urdf_str`], and where each `<link>` of the URDF
    /// rides on the robot (see [`crate::UrdfLink`]), for link geometry.
    ///
    /// # Examples
    /// ```
    /// let urdf = r#"<robot name="r">
    ///   <link name="base"/> <link name="arm"/> <link name="flange"/>
    ///   <joint name="j1" type="continuous"><parent link="base"/><child link="arm"/></joint>
    ///   <joint name="f" type="fixed"><parent link="arm"/><child link="flange"/>
    ///     <origin xyz="0 0 0.5"/></joint>
    /// </robot>"#;
    /// let (robot, links) = kinema::Robot::from_urdf_str_with_links(urdf, "r.urdf", None)?;
    /// assert_eq!(robot.dof(), 1);
    /// assert_eq!(links[2].name, "flange");
    /// assert_eq!(links[2].link, 1); // fixed to the body of joint 1
    /// assert!((links[2].link_from_urdf.pos.z - 0.5).abs() < 1e-15);
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn from_urdf_str_with_links(
        text: &str,
        file: &str,
        tip: Option<&str>,
    ) -> Result<(Robot, Vec<crate::UrdfLink>)> {
        crate::urdf::robot_and_links_from_urdf(text, file, tip)
    }

    /// Reads a `.toml` or `.urdf` file of at most [`MAX_DESCRIPTION_BYTES`].
    pub fn from_file(path: impl AsRef<Path>, tip: Option<&str>) -> Result<Robot> {
        Robot::from_file_with_text(path, tip).map(|(robot, _)| robot)
    }

    /// [`Robot::from_file`], with the text it was read from: what a copy of
    /// the robot elsewhere is rebuilt from, whatever becomes of the file.
    pub fn from_file_with_text(path: impl AsRef<Path>, tip: Option<&str>) -> Result<(Robot, String)> {
        let path = path.as_ref();
        let shown = path.display().to_string();
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        let read = || crate::read::read_bounded_text(path, "a robot description", MAX_DESCRIPTION_BYTES);
        match ext.as_deref() {
            Some("toml") => {
                if tip.is_some() {
                    return Err(Error::Input(InputError::DoesNotFit {
                        what: "tip".into(),
                        reason: "a tip link only applies to URDF files".into(),
                    }));
                }
                let text = read()?;
                Ok((Robot::from_toml_str(&text, &shown)?, text))
            }
            Some("urdf") | Some("xml") => {
                let text = read()?;
                Ok((Robot::from_urdf_str(&text, &shown, tip)?, text))
            }
            _ => Err(Error::Input(InputError::DoesNotFit {
                what: "robot file".into(),
                reason: format!("`{shown}` must end in .toml (kinema description) or .urdf"),
            })),
        }
    }

    /// A built-in name, or a path to a `.toml`/`.urdf` file.
    pub fn load(spec: &str, tip: Option<&str>) -> Result<Robot> {
        if builtin_source(spec).is_some() {
            if tip.is_some() {
                return Err(Error::Input(InputError::DoesNotFit {
                    what: "tip".into(),
                    reason: "a tip link only applies to URDF files".into(),
                }));
            }
            return Robot::builtin(spec);
        }
        let lower = spec.to_ascii_lowercase();
        if lower.ends_with(".toml") || lower.ends_with(".urdf") || lower.ends_with(".xml") || Path::new(spec).exists() {
            return Robot::from_file(spec, tip);
        }
        Err(Error::Model(ModelError::UnknownRobot {
            name: spec.to_string(),
            known: builtin_names().collect::<Vec<_>>().join(", "),
        }))
    }
}
