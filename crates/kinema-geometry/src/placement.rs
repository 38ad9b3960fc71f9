//! World poses of every shape for one joint vector (Pinocchio's
//! `GeometryData`), in caller-owned buffers that are reused call after call.

use nalgebra::{Isometry3, Point3};
use parry3d_f64::bounding_volume::Aabb;

use kinema::{kin, Fk, Pose, Robot};

use crate::error::{Error, Result};
use crate::geometry::{isometry, RobotGeometry};

/// Where the shapes of one [`RobotGeometry`] are for one joint vector:
/// fill it with [`place`] (or make one with [`Placement::of`]).
#[derive(Debug, Clone)]
pub struct Placement {
    frames: Vec<Pose>,
    links: Vec<Isometry3<f64>>,
    world_from_collider: Vec<Isometry3<f64>>,
    aabbs: Vec<Aabb>,
}

impl Placement {
    /// Empty buffers sized for `geometry` (every shape at the origin until placed).
    pub fn new(geometry: &RobotGeometry) -> Placement {
        let n = geometry.len();
        let origin = Aabb::new(Point3::origin(), Point3::origin());
        Placement {
            frames: vec![Pose::IDENTITY; geometry.dof() + 2],
            links: vec![Isometry3::identity(); geometry.dof() + 1],
            world_from_collider: vec![Isometry3::identity(); n],
            aabbs: vec![origin; n],
        }
    }

    /// The placement of `geometry` on `robot` at `q` (allocates; see [`place`]).
    pub fn of(robot: &Robot, geometry: &RobotGeometry, q: &[f64]) -> Result<Placement> {
        let mut out = Placement::new(geometry);
        place(robot, geometry, q, &mut out)?;
        Ok(out)
    }

    /// The number of shapes it holds poses for.
    pub fn len(&self) -> usize {
        self.world_from_collider.len()
    }

    /// Whether it holds no shape.
    pub fn is_empty(&self) -> bool {
        self.world_from_collider.is_empty()
    }

    /// The frames of the last [`place`]: base, links 1…dof, tool (as
    /// [`kinema::kin::link_frames_into`] gives them; world frame).
    pub fn frames(&self) -> &[Pose] {
        &self.frames
    }

    /// The world pose of shape `index`'s own frame (the frame its
    /// dimensions are given in).
    pub fn world_from_shape(&self, geometry: &RobotGeometry, index: usize) -> Pose {
        let s = &geometry.shapes()[index];
        self.frames[s.link()] * *s.link_from_shape()
    }

    pub(crate) fn world_from_collider(&self, index: usize) -> &Isometry3<f64> {
        &self.world_from_collider[index]
    }

    /// The world-axis-aligned box around shape `index` (for broad phases).
    pub fn aabb(&self, index: usize) -> &Aabb {
        &self.aabbs[index]
    }
}

/// Places every shape of `geometry` for `robot` at joint values `q`
/// \[rad or m\]: forward kinematics of all links, then each shape's world pose
/// and bounding box into `out`. Returns the forward kinematics computed on the
/// way. Does not allocate; errors (and leaves `out` meaningless) if `q` is
/// not a joint vector of `robot` or `out` or `geometry` was made for another
/// robot.
///
/// # Examples
/// ```
/// use kinema::{Pose, Robot};
/// use kinema_geometry::{place, LinkShape, Placement, RobotGeometry, Shape};
/// let robot = Robot::builtin("ur5")?;
/// let flange = LinkShape::new("flange", 6, Pose::translation(0.0, 0.0, 0.01), Shape::Sphere { radius: 0.04 })?;
/// let geometry = RobotGeometry::new(&robot, vec![flange])?;
/// let mut placement = Placement::new(&geometry);
/// let fk = place(&robot, &geometry, robot.home(), &mut placement)?;
/// let at = placement.world_from_shape(&geometry, 0);
/// let expected = robot.link_frames(robot.home())?[6] * Pose::translation(0.0, 0.0, 0.01);
/// assert!((at.pos - expected.pos).norm() < 1e-12);
/// assert!(fk.within_limits());
/// # Ok::<(), kinema_geometry::Error>(())
/// ```
pub fn place(robot: &Robot, geometry: &RobotGeometry, q: &[f64], out: &mut Placement) -> Result<Fk> {
    check_fits(robot, geometry, out)?;
    let fk = kin::link_frames_into(robot, q, &mut out.frames)?;
    place_on_frames(geometry, out, true);
    Ok(fk)
}

/// [`place`] for a placement `out` that [`place`] filled for the same
/// `robot` and `geometry` before: the shapes on link 0 (the base, and a
/// scene's obstacles), which no joint moves, keep their poses and boxes.
pub(crate) fn place_moving(robot: &Robot, geometry: &RobotGeometry, q: &[f64], out: &mut Placement) -> Result<Fk> {
    check_fits(robot, geometry, out)?;
    let fk = kin::link_frames_into(robot, q, &mut out.frames)?;
    place_on_frames(geometry, out, false);
    Ok(fk)
}

/// [`place`] for link `frames` already computed (as [`place`]'s, same length)
/// by the caller: copies them and places the shapes, without forward kinematics.
pub(crate) fn place_at_frames(
    robot: &Robot,
    geometry: &RobotGeometry,
    frames: &[Pose],
    out: &mut Placement,
) -> Result<()> {
    check_fits(robot, geometry, out)?;
    if frames.len() != out.frames.len() {
        return Err(Error::Mismatch { what: "the link frames".into(), got: frames.len(), expected: out.frames.len() });
    }
    out.frames.copy_from_slice(frames);
    place_on_frames(geometry, out, true);
    Ok(())
}

/// Each shape's world pose and bounding box from the link frames in `out`
/// (those on link 0 too when `base_too`).
fn place_on_frames(geometry: &RobotGeometry, out: &mut Placement, base_too: bool) {
    for (link, frame) in out.links.iter_mut().zip(&out.frames).skip(usize::from(!base_too)) {
        *link = isometry(frame);
    }
    for (i, s) in geometry.shapes().iter().enumerate() {
        if !base_too && s.link() == 0 {
            continue;
        }
        let pose = out.links[s.link()] * s.link_from_collider();
        out.aabbs[i] = s.collider().compute_aabb(&pose);
        out.world_from_collider[i] = pose;
    }
}

/// Errors unless `geometry` was made for `robot` and `out` for `geometry`.
fn check_fits(robot: &Robot, geometry: &RobotGeometry, out: &Placement) -> Result<()> {
    if geometry.dof() != robot.dof() || geometry.robot() != robot.name() {
        return Err(Error::Shape {
            name: geometry.robot().to_string(),
            message: format!(
                "this geometry was made for robot `{}` ({} joints), not for `{}` ({} joints)",
                geometry.robot(),
                geometry.dof(),
                robot.name(),
                robot.dof()
            ),
        });
    }
    if out.len() != geometry.len() || out.frames.len() != robot.dof() + 2 {
        return Err(Error::Mismatch { what: "the placement".into(), got: out.len(), expected: geometry.len() });
    }
    Ok(())
}
