//! The reference path: forward kinematics, link frames and Jacobians written
//! plainly from the textbook formulas, generic over the scalar.
//!
//! This module is the definition of what kinema computes; start reading here.
//! [`Robot::fk`], [`Robot::link_frames`] and [`Robot::jacobian`] run a
//! compiled, vectorised form of the same chain (the private `chain` and
//! `lanes` modules, see docs/internals.md, "The hot loops"), and
//! `crates/kinema/tests/all/reference.rs` tests them against the functions here on
//! every built-in robot, on random arms of every joint kind and on URDFs.
//!
//! Each joint's link transform is the product of its description's factors
//! ([`link_transform`]); one loop over the joints multiplies them
//! ([`link_frames`], [`world_from_tool`]); each Jacobian column is the cross
//! product of the joint's axis with the lever to the tool point
//! ([`jacobian`]). The functions are generic over `T: RealField + Copy`, so
//! besides `f64` they run on dual numbers or other automatic-differentiation
//! scalars: nothing here branches on a value or has its own trigonometry.
//! They allocate and multiply whole transforms, so they are much slower than
//! the fast path; they are meant to be read, tested against and
//! differentiated, not run in hot loops.
//!
//! Transforms are [`IsometryMatrix3`]: a rotation matrix and a translation,
//! named like [`Pose`] (`world_from_tool`: tool coordinates to world
//! coordinates). Joint values are in rad (revolute) or m (prismatic).
//!
//! # Examples
//! ```
//! use kinema::{reference, Frame, Robot};
//! let robot = Robot::builtin("panda")?;
//! let q = robot.home();
//! let fast = robot.fk(q)?.world_from_tool;
//! let plain = reference::world_from_tool(&robot, q)?;
//! assert!((fast.pos - plain.translation.vector).norm() < 1e-12);
//! assert!((fast.rot - plain.rotation.matrix()).norm() < 1e-12);
//! let j = reference::jacobian(&robot, q, Frame::Base)?;
//! assert!((robot.jacobian(q, Frame::Base)? - j).norm() < 1e-12);
//! # Ok::<(), kinema::Error>(())
//! ```

use nalgebra::{IsometryMatrix3, Matrix3, Matrix6xX, RealField, Rotation3, Translation3, Vector3};

use crate::error::{Error, InputError, Result};
use crate::kin::Frame;
use crate::math::Pose;
use crate::model::{DhConvention, Joint, JointType, LinkGeometry};
use crate::robot::Robot;

/// A model constant (given in `f64`) in the scalar `T`.
fn constant<T: RealField + Copy>(x: f64) -> T {
    nalgebra::convert(x)
}

/// A [`Pose`] of the model (base, tool, a URDF origin) as a transform in `T`.
///
/// # Examples
/// ```
/// use kinema::{reference, Pose};
/// let p = Pose::rot_z(0.5) * Pose::translation(1.0, 2.0, 3.0);
/// let t = reference::transform::<f64>(&p);
/// assert_eq!(t.rotation.matrix(), &p.rot);
/// assert_eq!(t.translation.vector, p.pos);
/// ```
pub fn transform<T: RealField + Copy>(pose: &Pose) -> IsometryMatrix3<T> {
    let rotation = Rotation3::from_matrix_unchecked(pose.rot.map(constant));
    IsometryMatrix3::from_parts(Translation3::from(pose.pos.map(constant)), rotation)
}

/// Rotation about x by `angle` \[rad\].
fn rot_x<T: RealField + Copy>(angle: T) -> IsometryMatrix3<T> {
    let (s, c) = angle.sin_cos();
    let (o, l) = (T::zero(), T::one());
    rotation(Matrix3::new(l, o, o, o, c, -s, o, s, c))
}

/// Rotation about z by `angle` \[rad\].
fn rot_z<T: RealField + Copy>(angle: T) -> IsometryMatrix3<T> {
    let (s, c) = angle.sin_cos();
    let (o, l) = (T::zero(), T::one());
    rotation(Matrix3::new(c, -s, o, s, c, o, o, o, l))
}

/// Rotation about the unit vector `axis` by `angle` \[rad\], by Rodrigues'
/// formula R = I + sin θ·K + (1 − cos θ)·K² with K = \[axis\]×. (Written out
/// rather than nalgebra's `from_axis_angle`, which returns the identity for an
/// angle that compares equal to zero and so drops a dual number's derivative.)
fn rot_about<T: RealField + Copy>(axis: &Vector3<T>, angle: T) -> IsometryMatrix3<T> {
    let (s, c) = angle.sin_cos();
    let k = axis.cross_matrix();
    rotation(Matrix3::identity() + k * s + k * k * (T::one() - c))
}

/// Translation by (x, y, z) \[m\].
fn trans<T: RealField + Copy>(x: T, y: T, z: T) -> IsometryMatrix3<T> {
    IsometryMatrix3::translation(x, y, z)
}

/// A pure rotation given by its (orthonormal) matrix.
fn rotation<T: RealField + Copy>(m: Matrix3<T>) -> IsometryMatrix3<T> {
    IsometryMatrix3::from_parts(Translation3::identity(), Rotation3::from_matrix_unchecked(m))
}

/// A general joint's axis as a unit vector in `T`. The model holds it as a
/// unit vector to within 1e-9 (`Robot::new` checks); dividing by its norm
/// here makes the rounding of a description's numbers irrelevant, as in the
/// fast path, which turns the z axis onto it.
fn unit_axis<T: RealField + Copy>(axis: &Vector3<f64>) -> Vector3<T> {
    (axis / axis.norm()).map(constant)
}

/// The transform of one link, `previous_link_from_link`, at joint value `q`
/// \[rad or m\]: the textbook product of the joint's description.
///
/// The joint variable is θ = q + offset for a revolute joint, d = q + offset
/// for a prismatic one ([`Joint::offset`]):
///
/// * standard DH (Spong/Corke): Rz(θ)·Tz(d)·Tx(a)·Rx(α);
/// * modified DH (Craig): Rx(α)·Tx(a)·Rz(θ)·Tz(d), with the row's α and a
///   those of the previous link;
/// * general (URDF): `origin`, then a turn of θ about, or a slide of d
///   along, the unit `axis` of the joint frame.
///
/// A DH row's `theta` is read only for a prismatic joint and its `d` only for
/// a revolute one: the other is the joint variable.
///
/// # Examples
/// ```
/// use kinema::{reference, DhConvention, Joint, JointType, Limits, LinkGeometry};
/// let joint = Joint {
///     name: "j".into(),
///     kind: JointType::Revolute,
///     geometry: LinkGeometry::Dh { convention: DhConvention::Standard, d: 0.1, a: 0.5, alpha: 0.0, theta: 0.0 },
///     offset: 0.0,
///     limits: Limits::unbounded(),
/// };
/// // A quarter turn puts the end of the 0.5 m link on the y axis, 0.1 m up.
/// let t = reference::link_transform(&joint, std::f64::consts::FRAC_PI_2);
/// assert!((t.translation.vector - kinema::nalgebra::Vector3::new(0.0, 0.5, 0.1)).norm() < 1e-15);
/// ```
pub fn link_transform<T: RealField + Copy>(joint: &Joint, q: T) -> IsometryMatrix3<T> {
    let v = q + constant(joint.offset);
    let prismatic = joint.kind == JointType::Prismatic;
    match joint.geometry {
        LinkGeometry::Dh { convention, d, a, alpha, theta } => {
            let (theta, d) = if prismatic { (constant(theta), v) } else { (v, constant(d)) };
            let (o, a, alpha) = (T::zero(), constant(a), constant(alpha));
            match convention {
                DhConvention::Standard => rot_z(theta) * trans(o, o, d) * trans(a, o, o) * rot_x(alpha),
                DhConvention::Modified => rot_x(alpha) * trans(a, o, o) * rot_z(theta) * trans(o, o, d),
            }
        }
        LinkGeometry::General { origin, axis } => {
            let axis = unit_axis::<T>(&axis);
            let motion = if prismatic {
                let p = axis * v;
                trans(p.x, p.y, p.z)
            } else {
                rot_about(&axis, v)
            };
            transform(&origin) * motion
        }
    }
}

/// All frames along the chain, as [`Robot::link_frames`] gives them:
/// element 0 is the base frame (`world_from_base`, [`Model::base`](crate::Model::base)), element
/// i is `world_from_link_i` (DH frame i for DH tables, the URDF child link
/// frame for URDF), and element dof + 1 is `world_from_tool`
/// ([`Model::tool`](crate::Model::tool) after the last link). `q` holds one value per joint
/// \[rad or m\].
///
/// Errors if `q` does not have one value per joint. The values are not
/// checked (a NaN gives NaN frames).
///
/// # Examples
/// ```
/// use kinema::{reference, Robot};
/// let robot = Robot::builtin("ur5")?;
/// let frames = reference::link_frames(&robot, robot.home())?;
/// let fast = robot.link_frames(robot.home())?;
/// for (plain, fast) in frames.iter().zip(&fast) {
///     assert!((plain.translation.vector - fast.pos).norm() < 1e-12);
/// }
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn link_frames<T: RealField + Copy>(robot: &Robot, q: &[T]) -> Result<Vec<IsometryMatrix3<T>>> {
    if q.len() != robot.dof() {
        return Err(Error::Input(InputError::JointCount {
            robot: robot.name().to_string(),
            expected: robot.dof(),
            got: q.len(),
        }));
    }
    let mut frames = Vec::with_capacity(robot.dof() + 2);
    let mut world_from_link = transform::<T>(robot.base());
    frames.push(world_from_link);
    for (joint, &qi) in robot.joints().iter().zip(q) {
        world_from_link *= link_transform(joint, qi);
        frames.push(world_from_link);
    }
    frames.push(world_from_link * transform::<T>(robot.tool()));
    Ok(frames)
}

/// Forward kinematics: the tool pose in the world frame, base and tool
/// transforms included (what [`Robot::fk`] returns as [`crate::Fk::world_from_tool`]).
/// `q` holds one value per joint \[rad or m\].
///
/// Errors if `q` does not have one value per joint.
///
/// # Examples
/// ```
/// use kinema::{reference, Robot};
/// let robot = Robot::builtin("lbr-iiwa-14-r820")?;
/// // Stretched upright: 0.36 + 0.42 + 0.40 + 0.126 m above the base.
/// let t = reference::world_from_tool(&robot, robot.home())?;
/// assert!((t.translation.vector.z - 1.306).abs() < 1e-12);
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn world_from_tool<T: RealField + Copy>(robot: &Robot, q: &[T]) -> Result<IsometryMatrix3<T>> {
    let frames = link_frames(robot, q)?;
    Ok(frames[robot.dof() + 1])
}

/// Where a joint's axis lies in the world frame, from the frames of the
/// links before and after it (`world_from_link_{i−1}`, `world_from_link_i`):
/// a point on the axis and its unit direction, the way a positive q turns or
/// slides.
fn joint_axis<T: RealField + Copy>(
    joint: &Joint,
    before: &IsometryMatrix3<T>,
    after: &IsometryMatrix3<T>,
) -> (Vector3<T>, Vector3<T>) {
    match joint.geometry {
        // Standard DH: joint i moves about or along z_{i−1}, through o_{i−1}.
        LinkGeometry::Dh { convention: DhConvention::Standard, .. } => {
            (before.translation.vector, before.rotation * Vector3::z())
        }
        // Modified DH: joint i moves about or along z_i, through o_i.
        LinkGeometry::Dh { convention: DhConvention::Modified, .. } => {
            (after.translation.vector, after.rotation * Vector3::z())
        }
        // General: about or along `axis` of the joint frame, through its
        // origin. The link frame is the joint frame moved by the joint, and
        // that motion keeps both the axis direction and (for a turn) its
        // origin in place, so the link frame gives both.
        LinkGeometry::General { axis, .. } => (after.translation.vector, after.rotation * unit_axis::<T>(&axis)),
    }
}

/// The geometric Jacobian of the tool point, 6 × dof, rows \[vx vy vz ωx ωy ωz\]:
/// column i is the tool's linear and angular velocity for a unit rate of
/// joint i, expressed in `frame` ([`Frame::Base`]: the world frame, base
/// transform included; [`Frame::Tool`]: the tool's axes), as
/// [`Robot::jacobian`] gives it. `q` holds one value per joint \[rad or m\].
///
/// Why the columns are cross products: when only joint i moves, everything
/// beyond it moves rigidly. A revolute joint turns it about the axis line
/// (point o, unit direction z), so the tool point p moves with z × (p − o)
/// and the tool turns with z; a prismatic joint slides it along z and turns
/// nothing. The velocities the joints give the tool add up (each is a
/// rigid motion of the rest of the chain), so the columns are the partial
/// derivatives of the tool's position and orientation, which the tests check
/// against finite differences and dual numbers.
///
/// Errors if `q` does not have one value per joint.
///
/// # Examples
/// ```
/// use kinema::{reference, Frame, Robot};
/// let robot = Robot::builtin("ur5")?;
/// let j = reference::jacobian(&robot, robot.home(), Frame::Base)?;
/// // The first joint turns about the base z axis.
/// assert!((j[(5, 0)] - 1.0).abs() < 1e-12);
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn jacobian<T: RealField + Copy>(robot: &Robot, q: &[T], frame: Frame) -> Result<Matrix6xX<T>> {
    let frames = link_frames(robot, q)?;
    let n = robot.dof();
    let tool = frames[n + 1];
    let p = tool.translation.vector;
    let mut j = Matrix6xX::zeros(n);
    for (i, joint) in robot.joints().iter().enumerate() {
        let (o, z) = joint_axis(joint, &frames[i], &frames[i + 1]);
        let (v, w) = match joint.kind {
            JointType::Revolute => (z.cross(&(p - o)), z),
            JointType::Prismatic => (z, Vector3::zeros()),
        };
        j.fixed_view_mut::<3, 1>(0, i).copy_from(&v);
        j.fixed_view_mut::<3, 1>(3, i).copy_from(&w);
    }
    if frame == Frame::Tool {
        // The same velocities in the tool's axes: Rᵀ·v and Rᵀ·ω.
        let tool_from_world = tool.rotation.matrix().transpose();
        for i in 0..n {
            let v = tool_from_world * j.fixed_view::<3, 1>(0, i);
            let w = tool_from_world * j.fixed_view::<3, 1>(3, i);
            j.fixed_view_mut::<3, 1>(0, i).copy_from(&v);
            j.fixed_view_mut::<3, 1>(3, i).copy_from(&w);
        }
    }
    Ok(j)
}

/// The time derivative J̇(q, q̇) of [`jacobian`]: how the Jacobian's columns
/// change while the joints move at rates `qd` \[rad/s or m/s\], 6 × dof in
/// `frame`, rows \[v; ω\] as [`jacobian`]. With it a tool acceleration is
/// J·q̈ + J̇·q̇ (operational-space control, acceleration-level IK).
///
/// Why it is one more walk: a joint's axis moves only with the joints before
/// it, so its direction z turns with their angular velocity ω₍<i₎ (ż = ω₍<i₎ × z)
/// and its point o moves with their velocity at o; the tool point moves with
/// every joint (ṗ = J_v·q̇). A revolute column z × (p − o) then changes at
/// ż × (p − o) + z × (ṗ − ȯ), its angular part at ż; a prismatic column's
/// linear part at ż. In the tool's axes, d/dt(Rᵀ·x) = Rᵀ·(ẋ − ω × x), with ω
/// the tool's angular velocity.
///
/// Errors if `q` or `qd` does not have one value per joint.
///
/// # Examples
/// ```
/// use kinema::{reference, Frame, Robot};
/// let robot = Robot::builtin("ur5")?;
/// let (q, qd) = ([0.1, -0.7, 1.2, 0.3, -0.4, 2.0], [0.5, 0.2, -0.3, 0.1, 0.4, -0.2]);
/// let jd = reference::jacobian_dot(&robot, &q, &qd, Frame::Base)?;
/// // Close to the Jacobian's change over a short move along q̇.
/// let h = 1e-6;
/// let at = |s: f64| -> Vec<f64> { q.iter().zip(&qd).map(|(a, b)| a + s * b).collect() };
/// let (ahead, behind) = (reference::jacobian(&robot, &at(h), Frame::Base)?, reference::jacobian(&robot, &at(-h), Frame::Base)?);
/// assert!((jd - (ahead - behind) / (2.0 * h)).abs().max() < 1e-6);
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn jacobian_dot<T: RealField + Copy>(robot: &Robot, q: &[T], qd: &[T], frame: Frame) -> Result<Matrix6xX<T>> {
    if qd.len() != robot.dof() {
        return Err(Error::Input(InputError::JointCount {
            robot: robot.name().to_string(),
            expected: robot.dof(),
            got: qd.len(),
        }));
    }
    let frames = link_frames(robot, q)?;
    let n = robot.dof();
    let j = jacobian(robot, q, Frame::Base)?;
    let p = frames[n + 1].translation.vector;
    let column = |i: usize| (j.fixed_view::<3, 1>(0, i).into_owned(), j.fixed_view::<3, 1>(3, i).into_owned());
    // The tool point's velocity, from every joint.
    let p_dot = (0..n).fold(Vector3::zeros(), |acc, k| acc + column(k).0 * qd[k]);
    let mut jd = Matrix6xX::zeros(n);
    // The angular velocity of the links before joint i, and the velocity
    // they give the point of joint i's axis, accumulated joint by joint.
    let mut omega = Vector3::zeros();
    let mut moved_by: Vec<(Vector3<T>, Vector3<T>, JointType)> = Vec::with_capacity(n);
    for (i, joint) in robot.joints().iter().enumerate() {
        let (o, z) = joint_axis(joint, &frames[i], &frames[i + 1]);
        let o_dot = moved_by.iter().zip(qd).fold(Vector3::zeros(), |acc, ((ok, zk, kind), &r)| match kind {
            JointType::Revolute => acc + zk.cross(&(o - ok)) * r,
            JointType::Prismatic => acc + zk * r,
        });
        let z_dot = omega.cross(&z);
        let (v_dot, w_dot) = match joint.kind {
            JointType::Revolute => (z_dot.cross(&(p - o)) + z.cross(&(p_dot - o_dot)), z_dot),
            JointType::Prismatic => (z_dot, Vector3::zeros()),
        };
        jd.fixed_view_mut::<3, 1>(0, i).copy_from(&v_dot);
        jd.fixed_view_mut::<3, 1>(3, i).copy_from(&w_dot);
        omega += column(i).1 * qd[i];
        moved_by.push((o, z, joint.kind));
    }
    if frame == Frame::Tool {
        let tool_from_world = frames[n + 1].rotation.matrix().transpose();
        for i in 0..n {
            let (v, w) = column(i);
            let v_dot = tool_from_world * (jd.fixed_view::<3, 1>(0, i) - omega.cross(&v));
            let w_dot = tool_from_world * (jd.fixed_view::<3, 1>(3, i) - omega.cross(&w));
            jd.fixed_view_mut::<3, 1>(0, i).copy_from(&v_dot);
            jd.fixed_view_mut::<3, 1>(3, i).copy_from(&w_dot);
        }
    }
    Ok(jd)
}
