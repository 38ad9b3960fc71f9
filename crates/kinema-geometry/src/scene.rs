//! Scenes: obstacles fixed in the world and robots on their bases, from one
//! TOML file — the format `kinema cell` files grow into (a cell file is a
//! scene plus motions, so a scene reader accepts a cell file).
//!
//! ```toml
//! rpy = "zyx"                          # optional: R = Rz(yaw)·Ry(pitch)·Rx(roll), the default
//!
//! [[obstacle]]
//! name = "bench"
//! box = [1.2, 0.6, 0.05]               # full edge lengths, m
//! pose = [0.6, 0.0, 0.4, 0, 0, 0]      # x y z, roll pitch yaw (rad), or "400mm", "90deg"
//!
//! [[robot]]                            # the keys of a `kinema cell` robot
//! name = "left"
//! robot = "lbr-iiwa-14-r820"
//! base = { xyz = [0, 0, 0], rpy = [0, 0, "180deg"] }
//! ```
//!
//! Obstacles take the shape keys of a robot file's `[[shape]]` (sphere,
//! box, cylinder, capsule, mesh; see `toml_shape.rs`). Plain numbers are SI.
//! Unknown keys are errors naming the key and the keys expected.

use std::path::Path;

use serde::Deserialize;
use toml::Spanned;

use kinema::quantity::{Dim, Quantity};
use kinema::{Pose, Robot, RpyConvention};

use crate::error::{Error, Result};
use crate::geometry::{LinkShape, RobotGeometry};
use crate::pairs::CollisionPairs;
use crate::shape::Shape;
use crate::toml_shape::{ShapeSpec, Src};

/// The largest scene file read \[bytes\] (meshes are read separately).
pub const MAX_SCENE_BYTES: u64 = 16 << 20;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    /// Keys of a `kinema cell` file (its clock and tool distance), read by
    /// `kinema cell`; accepted here so that a cell file is a scene.
    #[serde(rename = "dt")]
    _dt: Option<toml::Value>,
    #[serde(rename = "min_distance")]
    _min_distance: Option<toml::Value>,
    rpy: Option<RpyConvention>,
    #[serde(default)]
    obstacle: Vec<Spanned<ShapeSpec>>,
    #[serde(default)]
    robot: Vec<Spanned<RobotSpec>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RobotSpec {
    name: Spanned<String>,
    robot: String,
    tip: Option<String>,
    base: Option<BaseSpec>,
    /// A cell member's motion, read by `kinema cell`.
    #[serde(rename = "trajectory")]
    _trajectory: Option<toml::Value>,
    #[serde(rename = "program")]
    _program: Option<toml::Value>,
    /// Where it stands in a check of another robot (a program's start in a cell).
    start: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BaseSpec {
    xyz: Option<[Spanned<Quantity>; 3]>,
    rpy: Option<[Spanned<Quantity>; 3]>,
}

/// An obstacle: a named shape fixed in the world.
#[derive(Debug, Clone)]
pub struct Obstacle {
    /// Its name (unique within the scene).
    pub name: String,
    /// The body it is part of, by which pairs are reported: its own name, or
    /// `robot/link` for a shape of a scene robot standing as an obstacle.
    pub body: String,
    /// The shape's frame in the world.
    pub world_from_shape: Pose,
    /// The shape, in its own frame.
    pub shape: Shape,
}

/// A robot standing in the scene (as a `kinema cell` member).
#[derive(Debug, Clone)]
pub struct SceneRobot {
    /// Its name in the scene.
    pub name: String,
    /// A built-in name or a description path (relative to the scene file's folder, resolved).
    pub robot: String,
    /// A URDF's tip link.
    pub tip: Option<String>,
    /// Its base frame in the world.
    pub world_from_base: Pose,
    /// Where it stands when another robot is checked among the scene's
    /// (joint values in rad and m, or a named pose; `None`: home). In a
    /// `kinema cell` file, a program's start.
    pub start: Option<String>,
}

/// Obstacles and robots of one scene file.
#[derive(Debug, Clone, Default)]
pub struct Scene {
    /// The obstacles, in file order.
    pub obstacles: Vec<Obstacle>,
    /// The robots, in file order.
    pub robots: Vec<SceneRobot>,
}

impl Scene {
    /// Reads a scene file (at most [`MAX_SCENE_BYTES`]); mesh and robot
    /// paths in it are relative to its folder.
    pub fn load(path: impl AsRef<Path>) -> Result<Scene> {
        let path = path.as_ref();
        let shown = path.display().to_string();
        let text = kinema::read_bounded_text(path, "a scene", MAX_SCENE_BYTES)?;
        Scene::from_toml(&text, &shown, path.parent().unwrap_or(Path::new(".")))
    }

    /// Parses a scene from `text`; `file` names it in errors, `dir` is where
    /// relative paths start.
    ///
    /// # Examples
    /// ```
    /// let text = "[[obstacle]]\nname = \"bench\"\nbox = [1.2, 0.6, 0.05]\npose = [0.6, 0, \"400mm\", 0, 0, 0]\n";
    /// let scene = kinema_geometry::Scene::from_toml(text, "lab.toml", std::path::Path::new("."))?;
    /// assert_eq!(scene.obstacles[0].name, "bench");
    /// assert!((scene.obstacles[0].world_from_shape.pos.z - 0.4).abs() < 1e-15);
    /// assert!(kinema_geometry::Scene::from_toml("[[obstacle]]\nname = \"x\"\nbox = [1, 1, 1]\ncolour = 3\n", "bad.toml", std::path::Path::new(".")).is_err());
    /// # Ok::<(), kinema_geometry::Error>(())
    /// ```
    pub fn from_toml(text: &str, file: &str, dir: &Path) -> Result<Scene> {
        let mut src = Src { file, text, length_unit: 1.0, angle_unit: 1.0, rpy: RpyConvention::Zyx };
        let parsed: SceneFile = src.parse()?;
        src.rpy = parsed.rpy.unwrap_or(RpyConvention::Zyx);
        let mut scene = Scene::default();
        for (i, o) in parsed.obstacle.iter().enumerate() {
            let field = format!("obstacle[{i}]");
            let spec = o.get_ref();
            let name = spec.name.get_ref();
            if let Some(link) = &spec.link {
                let message = "obstacles are fixed in the world; `link` belongs to a robot file's [[shape]]";
                return Err(src.err(link.span(), &format!("{field}.link"), message));
            }
            if scene.obstacles.iter().any(|x| &x.name == name) {
                let message = format!("a second obstacle named `{name}`; names must be unique");
                return Err(src.err(spec.name.span(), &format!("{field}.name"), message));
            }
            let (world_from_shape, shape) = src.shape(o, &field, dir)?;
            // Checks the dimensions now, with the file's line, not at the first query.
            LinkShape::new(name.clone(), 0, world_from_shape, shape.clone()).map_err(|e| match e {
                Error::Shape { message, .. } => src.err(o.span(), &field, format!("obstacle `{name}`: {message}")),
                other => other,
            })?;
            scene.obstacles.push(Obstacle { name: name.clone(), body: name.clone(), world_from_shape, shape });
        }
        for (i, r) in parsed.robot.iter().enumerate() {
            let field = format!("robot[{i}]");
            let spec = r.get_ref();
            let mut v = [0.0; 6];
            if let Some(base) = &spec.base {
                for (k, q) in base.xyz.iter().flatten().enumerate() {
                    v[k] = src.value(q, Dim::Length, &format!("{field}.base.xyz"))?;
                }
                for (k, q) in base.rpy.iter().flatten().enumerate() {
                    v[3 + k] = src.value(q, Dim::Angle, &format!("{field}.base.rpy"))?;
                }
            }
            let robot = if kinema::builtin_source(&spec.robot).is_some() {
                spec.robot.clone()
            } else {
                dir.join(&spec.robot).to_string_lossy().into_owned()
            };
            scene.robots.push(SceneRobot {
                name: spec.name.get_ref().clone(),
                robot,
                tip: spec.tip.clone(),
                world_from_base: Pose::from_xyz_rpy([v[0], v[1], v[2]], [v[3], v[4], v[5]], src.rpy),
                start: spec.start.clone(),
            });
        }
        Ok(scene)
    }

    /// `robot`'s `geometry` with the obstacles added (on its base link, at
    /// their world poses: `robot` stands where its own base transform puts
    /// it), and the pairs to check: `robot_pairs` (its self-collision pairs)
    /// and every shape of a moving link against every obstacle. Shapes of the
    /// base link (0) are not checked against obstacles: a base stands on
    /// something. Obstacles keep their body names as link names, so pairs are
    /// reported by link or obstacle name. The scene's robots are not used
    /// here; [`Scene::standing`] turns them into obstacles.
    pub fn with_robot(
        &self,
        robot: &Robot,
        geometry: &RobotGeometry,
        robot_pairs: &CollisionPairs,
    ) -> Result<(RobotGeometry, CollisionPairs)> {
        if robot_pairs.shape_count() != geometry.len() {
            return Err(Error::Mismatch {
                what: "the robot's pair list".into(),
                got: robot_pairs.shape_count(),
                expected: geometry.len(),
            });
        }
        let world_from_base = robot.link_frames(robot.home())?[0];
        let mut shapes = geometry.shapes().to_vec();
        for o in &self.obstacles {
            if geometry.find(&o.name).is_some() {
                return Err(Error::Shape {
                    name: o.name.clone(),
                    message: format!(
                        "an obstacle has the name of a shape of robot `{}`; rename the obstacle",
                        robot.name()
                    ),
                });
            }
            let base_from_shape = world_from_base.inverse() * o.world_from_shape;
            shapes.push(
                LinkShape::new(o.name.clone(), 0, base_from_shape, o.shape.clone())?.with_link_name(o.body.clone()),
            );
        }
        let combined = RobotGeometry::new(robot, shapes)?;
        let moving = (0..geometry.len()).filter(|&s| geometry.shapes()[s].link() > 0);
        let against = moving.flat_map(|s| (geometry.len()..combined.len()).map(move |o| (s, o)));
        let pairs = CollisionPairs::from_pairs(&combined, robot_pairs.iter().chain(against.collect::<Vec<_>>()))?;
        Ok((combined, pairs))
    }
}
