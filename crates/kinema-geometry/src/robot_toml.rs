//! Link shapes of a kinema TOML robot description (`[[shape]]` tables, next
//! to the `[[joint]]`s the core reads from the same file), and loading a
//! robot with its geometry by name or path.
//!
//! ```toml
//! [[shape]]
//! name = "upper_arm"
//! link = 2                                      # 0 = base, i = the body moved by joint i
//! capsule = { radius = 0.06, length = 0.425 }
//! pose = [-0.2125, 0, 0, 0, 90, 0]              # in link 2's frame; the file's [units]
//! ```
//!
//! The core skips these tables (the kinematic model carries no shapes);
//! this module reads them with the file's `[units]`, so one file describes
//! the chain and its body.

use std::path::Path;

use serde::Deserialize;
use toml::Spanned;

use kinema::{Robot, RpyConvention};

use crate::error::{Error, Result};
use crate::geometry::{LinkShape, RobotGeometry};
use crate::toml_shape::{ShapeSpec, Src};
use crate::urdf::{load_urdf, ros_package_path, UrdfOptions};

/// The parts of a robot file this module reads; the core checks the rest.
#[derive(Deserialize)]
struct ShapesOfRobot {
    units: UnitsSpec,
    #[serde(default)]
    shape: Vec<Spanned<ShapeSpec>>,
}

#[derive(Deserialize)]
struct UnitsSpec {
    length: String,
    angle: String,
}

/// The `[[shape]]` tables of a TOML robot description as the geometry of
/// `robot` (the robot read from the same `text`). `file` names it in errors;
/// mesh paths are taken from `dir`. A file without shapes gives an empty
/// geometry.
///
/// # Examples
/// ```
/// use kinema::Robot;
/// let text = kinema::builtin_source("ur5").unwrap();
/// let robot = Robot::from_toml_str(text, "ur5.toml")?;
/// let geometry = kinema_geometry::toml_geometry(&robot, text, "ur5.toml", std::path::Path::new("."))?;
/// assert!(geometry.len() >= robot.dof());
/// # Ok::<(), kinema_geometry::Error>(())
/// ```
pub fn toml_geometry(robot: &Robot, text: &str, file: &str, dir: &Path) -> Result<RobotGeometry> {
    let mut src = Src { file, text, length_unit: 1.0, angle_unit: 1.0, rpy: RpyConvention::Zyx };
    let parsed: ShapesOfRobot = src.parse()?;
    src.length_unit = if parsed.units.length == "mm" { 1e-3 } else { 1.0 };
    src.angle_unit = if parsed.units.angle == "deg" { std::f64::consts::PI / 180.0 } else { 1.0 };
    let mut shapes: Vec<LinkShape> = Vec::with_capacity(parsed.shape.len());
    for (i, s) in parsed.shape.iter().enumerate() {
        let field = format!("shape[{i}]");
        let spec = s.get_ref();
        let name = spec.name.get_ref();
        let Some(link) = &spec.link else {
            let message = format!("shape `{name}` names no `link` (0 = base, i = the body moved by joint i)");
            return Err(src.err(s.span(), &field, message));
        };
        if *link.get_ref() > robot.dof() {
            let message =
                format!("link {} is not a link of this robot; expected 0 (base) to {}", link.get_ref(), robot.dof());
            return Err(src.err(link.span(), &format!("{field}.link"), message));
        }
        if shapes.iter().any(|o| o.name() == name) {
            return Err(src.err(
                spec.name.span(),
                &format!("{field}.name"),
                format!("a second shape named `{name}`; names must be unique"),
            ));
        }
        let (pose, shape) = src.shape(s, &field, dir)?;
        let shape = LinkShape::new(name.clone(), *link.get_ref(), pose, shape).map_err(|e| match e {
            Error::Shape { message, .. } => src.err(s.span(), &field, format!("shape `{name}`: {message}")),
            other => other,
        })?;
        shapes.push(shape);
    }
    RobotGeometry::new(robot, shapes)
}

/// A robot and its collision geometry from a built-in name (see
/// [`kinema::builtin_names`]), a `.toml` description (its `[[shape]]`s) or a
/// `.urdf` (its `<collision>` elements; `options` says where meshes are).
///
/// # Examples
/// ```
/// let (robot, geometry) = kinema_geometry::load_robot_geometry("panda", &Default::default())?;
/// assert_eq!(geometry.dof(), robot.dof());
/// assert!(!geometry.is_empty());
/// # Ok::<(), kinema_geometry::Error>(())
/// ```
pub fn load_robot_geometry(spec: &str, options: &UrdfOptions) -> Result<(Robot, RobotGeometry)> {
    if let Some(text) = kinema::builtin_source(spec) {
        let file = format!("robots/{spec}.toml");
        let robot = Robot::from_toml_str(text, &file)?;
        let geometry = toml_geometry(&robot, text, &file, Path::new("."))?;
        return Ok((robot, geometry));
    }
    if is_urdf(spec) {
        let options = UrdfOptions { skip_visual: true, ..options.clone() };
        let u = load_urdf(spec, &options)?;
        return Ok((u.robot, u.collision));
    }
    let robot = Robot::load(spec, options.tip.as_deref())?;
    let path = Path::new(spec);
    let text = kinema::read_bounded_text(path, "a robot description", kinema::MAX_DESCRIPTION_BYTES)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let geometry = toml_geometry(&robot, &text, spec, dir)?;
    Ok((robot, geometry))
}

/// The link shapes of robot `spec` for a check that can go without them
/// (a cell's link distances): [`load_robot_geometry`]'s, with the
/// directories of `ROS_PACKAGE_PATH` after `options`' own; or, when a mesh is
/// missing or unreadable, no shapes and that error, for the caller to show as
/// a warning. Any other error is returned.
pub fn load_shapes_or_none(spec: &str, options: &UrdfOptions) -> Result<(RobotGeometry, Option<Error>)> {
    let mut options = options.clone();
    options.package_paths.extend(ros_package_path());
    match load_robot_geometry(spec, &options) {
        Ok((_, geometry)) => Ok((geometry, None)),
        Err(e @ (Error::MeshNotFound { .. } | Error::Mesh { .. })) => {
            let robot = Robot::load(spec, options.tip.as_deref())?;
            Ok((RobotGeometry::new(&robot, Vec::new())?, Some(e)))
        }
        Err(e) => Err(e),
    }
}

/// Whether `spec` names a URDF file (by its extension, as [`Robot::load`] decides).
pub(crate) fn is_urdf(spec: &str) -> bool {
    let lower = spec.to_ascii_lowercase();
    lower.ends_with(".urdf") || lower.ends_with(".xml")
}
