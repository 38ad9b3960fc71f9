//! # kinema-geometry — the bodies of kinema's robots, and collision and distance between them
//!
//! Link geometry sits beside the kinematic model, as Pinocchio's
//! `GeometryModel` does beside its `Model`; the robot itself does not grow
//! shape fields.
//!
//! * [`Shape`] — sphere, box, cylinder, capsule, convex mesh, triangle mesh,
//!   in the shape's own frame (round shapes along z, boxes by full edge lengths).
//! * [`LinkShape`] — a named shape fixed to one link of a robot (0 = base,
//!   i = the body moved by joint i; the numbering of
//!   [`kinema::kin::link_frames_into`]), at a pose in that link's frame.
//! * [`RobotGeometry`] — the shapes of one robot, immutable and shareable.
//!   From a URDF with [`load_urdf`] (`<collision>` and `<visual>`; `package://`
//!   and relative mesh paths; STL, OBJ and COLLADA meshes via [`load_mesh`]),
//!   or built in code; for kinema's TOML robots from their `[[shape]]`
//!   tables with [`toml_geometry`] (every built-in robot has them;
//!   [`load_robot_geometry`] loads a robot and its shapes by name or path).
//! * [`Placement`] — the world pose and bounding box of every shape for one
//!   joint vector, filled by [`place`] into reusable buffers.
//! * [`CollisionPairs`] — which pairs are checked ([`CollisionPairs::self_collision`]:
//!   shapes on links that are not neighbours on the chain).
//! * [`Spheres`] — the conservative fast path: each shape inside a few
//!   spheres on its link; [`spheres_free`] (forward kinematics included)
//!   says "free" only when the exact shapes are free, [`collides_fast`]
//!   asks the exact shapes only where it cannot.
//! * [`Srdf`] — an SRDF's `<disable_collisions>`: read, applied to a pair
//!   list, written; [`generate_srdf`] finds them as MoveIt's setup assistant does.
//! * Queries on parry3d-f64: [`collides`] (the first pair within a safety
//!   margin), [`contacts`], [`min_distance`] and [`pair_distance`] (signed
//!   distance with witness points, as a [`Proximity`]).
//!
//! * [`CollisionCheck`] — a robot, its shapes, a scene's obstacles, the
//!   pairs (less an SRDF's) and a margin, loaded by [`CollisionCheck::load`]
//!   the same way for every door; it is IK's admissibility test
//!   ([`kinema::ik::Admissible`]): `kinema ik --scene` discards solutions in
//!   collision and searches a redundant arm's self-motion for a free one.
//! * [`Scene`] — obstacles fixed in the world and robots on their bases, from
//!   one TOML file (a `kinema cell` file is a scene plus motions);
//!   [`Scene::with_robot`] adds the obstacles to a robot's geometry and pairs.
//!   The broad phase is each placed shape's axis-aligned box: only pairs whose
//!   boxes are within the margin (or, for distances, within the best distance
//!   so far) reach the exact query.
//!
//! Units are SI: metres and radians.
//!
//! ## Example
//!
//! ```
//! use kinema::{Pose, Robot};
//! use kinema_geometry::{collides, min_distance, CollisionPairs, LinkShape, Placement, RobotGeometry, Shape};
//!
//! let robot = Robot::builtin("ur5")?;
//! // A capsule for the upper arm (link 2) and a ball at the wrist (link 6).
//! let arm = Shape::Capsule { radius: 0.06, length: 0.425 };
//! let upper_arm = LinkShape::new("upper_arm", 2, Pose::translation(-0.2125, 0.0, 0.0) * Pose::rot_y(std::f64::consts::FRAC_PI_2), arm)?;
//! let wrist = LinkShape::new("wrist", 6, Pose::IDENTITY, Shape::Sphere { radius: 0.05 })?;
//! let geometry = RobotGeometry::new(&robot, vec![upper_arm, wrist])?;
//! let pairs = CollisionPairs::self_collision(&geometry);
//!
//! let mut placement = Placement::new(&geometry);
//! kinema_geometry::place(&robot, &geometry, robot.home(), &mut placement)?;
//! assert_eq!(collides(&geometry, &placement, &pairs, 0.0)?, None);
//! let closest = min_distance(&geometry, &placement, &pairs)?.expect("one pair");
//! assert!(closest.distance > 0.0);
//! assert!(((closest.point_b - closest.point_a).norm() - closest.distance).abs() < 1e-9);
//! # Ok::<(), kinema_geometry::Error>(())
//! ```
#![warn(missing_docs)]
// `!(x > 0.0)` is used on purpose: unlike `x <= 0.0` it is also true for NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod approach;
mod check;
mod convex;
mod error;
mod geometry;
mod mesh;
mod pairs;
mod placement;
pub mod plan;
mod query;
mod robot_toml;
mod scene;
mod scene_robots;
mod segment_box;
mod shape;
mod spheres;
mod srdf;
mod sweep;
mod toml_shape;
mod urdf;

pub use approach::{closest_approaches, Body, BodyApproach, APPROACH_TOLERANCE};
pub use check::{CheckOptions, CollisionCheck};
pub use error::{Error, Result};
pub use geometry::{LinkShape, RobotGeometry};
pub use mesh::{load_mesh, MAX_MESH_BYTES};
pub use pairs::CollisionPairs;
pub use placement::{place, Placement};
pub use query::{collides, contacts, min_distance, min_distance_reference, pair_distance, Proximity};
pub use robot_toml::{load_robot_geometry, load_shapes_or_none, toml_geometry};
pub use scene::{Obstacle, Scene, SceneRobot, MAX_SCENE_BYTES};
pub use shape::{Mesh, Shape};
pub use spheres::{collides_fast, spheres_free, SpherePlacement, Spheres};
pub use srdf::{generate_srdf, DisabledPair, Srdf};
pub use sweep::{SweptContact, CONTACT_TOLERANCE};
pub use urdf::{load_urdf, ros_package_path, urdf_from_str, UrdfOptions, UrdfRobot};

pub use parry3d_f64;
