//! Shapes fixed to a robot's links ([`LinkShape`]) and the list of them for
//! one robot ([`RobotGeometry`]), after Pinocchio's `GeometryObject` and
//! `GeometryModel`.

use nalgebra::{Isometry3, Translation3};
use parry3d_f64::shape::SharedShape;

use kinema::{Pose, Robot};

use crate::convex::MeshHull;
use crate::error::{Error, Result};
use crate::shape::Shape;

/// One shape fixed to one link of a robot.
///
/// Links are numbered as [`kinema::kin::link_frames_into`] numbers its
/// frames: 0 is the base (everything before the first joint), i the body
/// moved by joint i. The tool frame is not a link of its own: shapes on the
/// flange or the tool ride on link `dof`.
#[derive(Debug, Clone)]
pub struct LinkShape {
    name: String,
    link: usize,
    link_name: String,
    link_from_shape: Pose,
    shape: Shape,
    collider: SharedShape,
    /// A triangle mesh's convex hull (see `convex.rs`).
    hull: Option<MeshHull>,
    link_from_collider: Isometry3<f64>,
}

impl LinkShape {
    /// A shape named `name` on link `link`, its frame at `link_from_shape`
    /// in the link frame. Checks the shape's dimensions and builds its
    /// collision form (a mesh's hull or bounding-volume tree) once.
    pub fn new(name: impl Into<String>, link: usize, link_from_shape: Pose, shape: Shape) -> Result<LinkShape> {
        let name = name.into();
        if !link_from_shape.is_finite() {
            return Err(Error::Shape { name, message: "its pose in the link frame is not finite".into() });
        }
        let (collider, shape_from_collider) = shape.collider(&name)?;
        let link_from_collider = match shape_from_collider {
            Some(c) => isometry(&link_from_shape) * c,
            None => isometry(&link_from_shape),
        };
        Ok(LinkShape {
            link_name: format!("link {link}"),
            name,
            link,
            link_from_shape,
            hull: shape.surface_hull(),
            shape,
            collider,
            link_from_collider,
        })
    }

    /// The same shape with the name of the link it belongs to (the URDF
    /// link's name; by default `link i`), used when pairs are named by link.
    pub fn with_link_name(mut self, link_name: impl Into<String>) -> LinkShape {
        self.link_name = link_name.into();
        self
    }

    /// The shape's name (unique within its [`RobotGeometry`]).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The link it is fixed to (0 = base, i = the body moved by joint i).
    pub fn link(&self) -> usize {
        self.link
    }

    /// The name of the link it belongs to (see [`LinkShape::with_link_name`]).
    pub fn link_name(&self) -> &str {
        &self.link_name
    }

    /// The shape's frame in its link's frame.
    pub fn link_from_shape(&self) -> &Pose {
        &self.link_from_shape
    }

    /// The shape in its own frame.
    pub fn shape(&self) -> &Shape {
        &self.shape
    }

    pub(crate) fn collider(&self) -> &SharedShape {
        &self.collider
    }

    /// Whether the shape is a triangle mesh found convex when it was made
    /// (its surface is its convex hull's boundary): such a mesh is measured
    /// as the hull wherever the two give the same answer.
    pub fn is_convex_mesh(&self) -> bool {
        self.hull.as_ref().is_some_and(|h| h.exact)
    }

    /// A triangle mesh's convex hull: a bound of its distances, and the
    /// mesh's own distance to what it is apart from when marked exact.
    pub(crate) fn hull(&self) -> Option<&MeshHull> {
        self.hull.as_ref()
    }

    pub(crate) fn link_from_collider(&self) -> &Isometry3<f64> {
        &self.link_from_collider
    }
}

/// The shapes of one robot for one purpose (collision or visual): immutable
/// once built, cheap to share (`Send + Sync`; meshes are reference counted).
/// World poses for a joint vector go into a [`crate::Placement`].
#[derive(Debug, Clone)]
pub struct RobotGeometry {
    robot: String,
    dof: usize,
    shapes: Vec<LinkShape>,
}

impl RobotGeometry {
    /// The geometry of `robot` made of `shapes`. Errors if a shape rides on a
    /// link the robot does not have, or two shapes share a name.
    ///
    /// # Examples
    /// ```
    /// use kinema::{Pose, Robot};
    /// use kinema_geometry::{LinkShape, RobotGeometry, Shape};
    /// let robot = Robot::builtin("ur5")?;
    /// let ball = Shape::Sphere { radius: 0.05 };
    /// let shapes = vec![LinkShape::new("wrist", 6, Pose::IDENTITY, ball.clone())?];
    /// let geometry = RobotGeometry::new(&robot, shapes)?;
    /// assert_eq!(geometry.len(), 1);
    /// assert!(RobotGeometry::new(&robot, vec![LinkShape::new("x", 7, Pose::IDENTITY, ball)?]).is_err());
    /// # Ok::<(), kinema_geometry::Error>(())
    /// ```
    pub fn new(robot: &Robot, shapes: Vec<LinkShape>) -> Result<RobotGeometry> {
        let dof = robot.dof();
        for (i, s) in shapes.iter().enumerate() {
            if s.link > dof {
                return Err(Error::NoSuchLink { name: s.name.clone(), link: s.link, robot: robot.name().into(), dof });
            }
            if shapes[..i].iter().any(|o| o.name == s.name) {
                return Err(Error::Shape {
                    name: s.name.clone(),
                    message: "two shapes have this name; names must be unique within a robot's geometry".into(),
                });
            }
        }
        Ok(RobotGeometry { robot: robot.name().to_string(), dof, shapes })
    }

    /// The name of the robot it was made for.
    pub fn robot(&self) -> &str {
        &self.robot
    }

    /// The joint count of the robot it was made for.
    pub fn dof(&self) -> usize {
        self.dof
    }

    /// The shapes, in order (a shape's index is its position here).
    pub fn shapes(&self) -> &[LinkShape] {
        &self.shapes
    }

    /// The number of shapes.
    pub fn len(&self) -> usize {
        self.shapes.len()
    }

    /// Whether there are no shapes.
    pub fn is_empty(&self) -> bool {
        self.shapes.is_empty()
    }

    /// The index of the shape named `name`.
    pub fn find(&self, name: &str) -> Option<usize> {
        self.shapes.iter().position(|s| s.name == name)
    }
}

/// A kinema pose as parry's isometry (the rotation as a unit quaternion).
pub(crate) fn isometry(pose: &Pose) -> Isometry3<f64> {
    Isometry3::from_parts(Translation3::from(pose.pos), pose.quaternion())
}

/// `pose`'s rotation applied to `v`, written out: nalgebra's generic product
/// is not inlined at the workspace's test optimisation level, and the
/// planner's sphere and capsule placement call this in its innermost loop.
#[inline]
pub(crate) fn rotate(m: &nalgebra::Matrix3<f64>, v: &nalgebra::Vector3<f64>) -> nalgebra::Vector3<f64> {
    nalgebra::Vector3::new(
        m[(0, 0)] * v.x + m[(0, 1)] * v.y + m[(0, 2)] * v.z,
        m[(1, 0)] * v.x + m[(1, 1)] * v.y + m[(1, 2)] * v.z,
        m[(2, 0)] * v.x + m[(2, 1)] * v.y + m[(2, 2)] * v.z,
    )
}
