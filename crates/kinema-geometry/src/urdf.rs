//! Link geometry from a URDF: `<collision>` and `<visual>` of every link,
//! placed on the kinema link the link rides on (see [`kinema::UrdfLink`]:
//! fixed links fold into their parent's body, as the mass properties do).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use nalgebra::Vector3;

use kinema::{Pose, Robot, RpyConvention, UrdfLink};

use crate::error::{Error, Result};
use crate::geometry::{LinkShape, RobotGeometry};
use crate::mesh::load_mesh;
use crate::shape::{Mesh, Shape};

/// How to read a URDF's geometry.
#[derive(Debug, Clone, Default)]
pub struct UrdfOptions {
    /// The chain's tip link (as for [`kinema::Robot::from_file`]); `None`
    /// for the only leaf reached through moving joints.
    pub tip: Option<String>,
    /// Directories to find `package://NAME/…` meshes in, in order: each
    /// directory is tried as one that holds the package `NAME/` and as the
    /// package itself (a directory named `NAME`). A door fills it from its
    /// option and `ROS_PACKAGE_PATH` ([`ros_package_path`]).
    pub package_paths: Vec<PathBuf>,
    /// Skip `<visual>` elements (and so their meshes): for collision checks only.
    pub skip_visual: bool,
}

/// A robot with its link geometry, from one URDF.
#[derive(Debug, Clone)]
pub struct UrdfRobot {
    /// The kinematic chain (the same robot [`kinema::Robot::from_file`] reads).
    pub robot: Robot,
    /// The `<collision>` shapes, named `LINK_i` (i counting the link's
    /// `<collision>` elements from 0), meshes as triangle meshes.
    pub collision: RobotGeometry,
    /// The `<visual>` shapes, named the same way (empty with
    /// [`UrdfOptions::skip_visual`]).
    pub visual: RobotGeometry,
    /// Every `<link>` of the URDF and the kinema link it rides on (fixed
    /// links folded into their parent), in document order: the names an
    /// SRDF may use ([`crate::Srdf::apply`]).
    pub links: Vec<UrdfLink>,
}

/// The directories of the `ROS_PACKAGE_PATH` environment variable (empty if unset).
pub fn ros_package_path() -> Vec<PathBuf> {
    std::env::var_os("ROS_PACKAGE_PATH").map(|v| std::env::split_paths(&v).collect()).unwrap_or_default()
}

/// Reads a URDF file (at most [`kinema::MAX_DESCRIPTION_BYTES`]) with its
/// link geometry; relative mesh paths are taken from the file's directory.
pub fn load_urdf(path: impl AsRef<Path>, options: &UrdfOptions) -> Result<UrdfRobot> {
    let path = path.as_ref();
    let shown = path.display().to_string();
    let text = kinema::read_bounded_text(path, "a robot description", kinema::MAX_DESCRIPTION_BYTES)?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    urdf_from_str(&text, &shown, &dir, options)
}

/// As [`load_urdf`], from the text of a URDF; `file` names it in messages and
/// relative mesh paths are taken from `dir`.
pub fn urdf_from_str(text: &str, file: &str, dir: &Path, options: &UrdfOptions) -> Result<UrdfRobot> {
    let (robot, links) = Robot::from_urdf_str_with_links(text, file, options.tip.as_deref())?;
    let u = urdf_rs::read_from_string(text).map_err(|e| {
        Error::Kinema(kinema::Error::Model(kinema::ModelError::Urdf {
            file: file.to_string(),
            message: format!("its <collision> or <visual> elements cannot be read: {e}"),
        }))
    })?;
    let on: HashMap<&str, &UrdfLink> = links.iter().map(|l| (l.name.as_str(), l)).collect();
    let mut reader = Reader { file, dir, options, meshes: HashMap::new() };
    let mut collision = Vec::new();
    let mut visual = Vec::new();
    for link in &u.links {
        let Some(at) = on.get(link.name.as_str()) else { continue };
        for (i, c) in link.collision.iter().enumerate() {
            collision.push(reader.shape(&link.name, i, at, &c.origin, &c.geometry)?);
        }
        if !options.skip_visual {
            for (i, v) in link.visual.iter().enumerate() {
                visual.push(reader.shape(&link.name, i, at, &v.origin, &v.geometry)?);
            }
        }
    }
    Ok(UrdfRobot {
        collision: RobotGeometry::new(&robot, collision)?,
        visual: RobotGeometry::new(&robot, visual)?,
        robot,
        links,
    })
}

/// Reads shapes of one URDF, each mesh file once.
struct Reader<'a> {
    file: &'a str,
    dir: &'a Path,
    options: &'a UrdfOptions,
    meshes: HashMap<(PathBuf, [u64; 3]), Arc<Mesh>>,
}

impl Reader<'_> {
    fn shape(
        &mut self,
        link: &str,
        index: usize,
        at: &UrdfLink,
        origin: &urdf_rs::Pose,
        geometry: &urdf_rs::Geometry,
    ) -> Result<LinkShape> {
        let shape = match geometry {
            urdf_rs::Geometry::Box { size } => Shape::Box { size: Vector3::from(**size) },
            urdf_rs::Geometry::Cylinder { radius, length } => Shape::Cylinder { radius: *radius, length: *length },
            urdf_rs::Geometry::Capsule { radius, length } => Shape::Capsule { radius: *radius, length: *length },
            urdf_rs::Geometry::Sphere { radius } => Shape::Sphere { radius: *radius },
            urdf_rs::Geometry::Mesh { filename, scale } => {
                let path = self.resolve(link, filename)?;
                let scale = scale.map_or([1.0; 3], |s| *s);
                let key = (path.clone(), scale.map(f64::to_bits));
                let mesh = match self.meshes.get(&key) {
                    Some(m) => m.clone(),
                    None => {
                        let m = Arc::new(load_mesh(&path, scale)?);
                        self.meshes.insert(key, m.clone());
                        m
                    }
                };
                Shape::TriangleMesh(mesh)
            }
        };
        let link_from_shape = at.link_from_urdf * Pose::from_xyz_rpy(*origin.xyz, *origin.rpy, RpyConvention::Zyx);
        Ok(LinkShape::new(format!("{link}_{index}"), at.link, link_from_shape, shape)?.with_link_name(link))
    }

    /// The file a URDF mesh name points to: `package://NAME/rest` through the
    /// package search path, `file://` and absolute paths as they are, other
    /// names relative to the URDF's directory.
    fn resolve(&self, link: &str, uri: &str) -> Result<PathBuf> {
        let mut searched = Vec::new();
        if let Some(rest) = uri.strip_prefix("package://") {
            let (package, inside) = rest.split_once('/').unwrap_or((rest, ""));
            for dir in &self.options.package_paths {
                searched.push(dir.join(package).join(inside));
                if dir.file_name().is_some_and(|n| n == package) {
                    searched.push(dir.join(inside));
                }
            }
        } else {
            let path = Path::new(uri.strip_prefix("file://").unwrap_or(uri));
            searched.push(if path.is_absolute() { path.to_path_buf() } else { self.dir.join(path) });
        }
        match searched.iter().find(|p| p.is_file()) {
            Some(found) => Ok(found.clone()),
            None => Err(Error::MeshNotFound {
                urdf: self.file.to_string(),
                link: link.to_string(),
                uri: uri.to_string(),
                searched,
            }),
        }
    }
}
