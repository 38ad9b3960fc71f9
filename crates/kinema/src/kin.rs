//! Forward kinematics and Jacobians, as free functions over a [`Robot`]
//! (the model and its compiled chain) and caller-owned output.
//!
//! The functions here ([`fk`], [`jacobian_into`], [`link_frames_into`], …)
//! do not allocate and do not depend on any earlier call; they run the
//! compiled chain, and `tests/all/reference.rs` checks them against the plain
//! [`crate::reference`] functions. Convenience methods that
//! allocate ([`Robot::fk`], [`Robot::jacobian`], [`Robot::link_frames`]) sit
//! on top, and [`Data`] holds their reusable scratch.
//!
//! Jacobian rows are ordered \[vx vy vz ωx ωy ωz\]: linear velocity of the tool
//! point, then angular velocity.

use nalgebra::{Matrix3, Matrix6xX, Vector3};
use rayon::prelude::*;

use std::mem::MaybeUninit;

use crate::chain::{as_uninit, Layout};
use crate::data::Data;
use crate::error::{Error, InputError, Result};
use crate::math::{Pose, RpyConvention};
use crate::model::{DhConvention, Joint, JointSet, LinkGeometry};
use crate::robot::Robot;

/// The frame a Jacobian (or a velocity) is expressed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Frame {
    /// The robot's base frame (world frame if a base transform is set, as the
    /// base transform is part of the chain).
    #[default]
    Base,
    /// The tool frame: velocities of the tool point expressed in tool axes.
    Tool,
}

/// The result of forward kinematics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fk {
    /// The tool pose in the world frame: the robot's base transform
    /// (`world_from_base`), the chain, then the tool transform.
    pub world_from_tool: Pose,
    /// Joints whose value is outside their position limits. FK is computed
    /// anyway; this says which values a real robot could not take.
    pub out_of_limits: JointSet,
}

impl Fk {
    /// Whether every joint value is within its limits.
    pub fn within_limits(&self) -> bool {
        self.out_of_limits.is_empty()
    }
}

/// Forward kinematics: the tool pose in the base frame.
///
/// Errors if `q` has the wrong length or a non-finite value. Values outside
/// the joint limits are flagged in [`Fk::out_of_limits`], not rejected.
/// Does not allocate.
///
/// # Examples
/// ```
/// use kinema::{kin, Robot};
/// let robot = Robot::builtin("puma560")?;
/// let fk = kin::fk(&robot, robot.home())?;
/// assert_eq!(fk.world_from_tool, robot.fk(robot.home())?.world_from_tool);
/// # Ok::<(), kinema::Error>(())
/// ```
#[inline]
pub fn fk(robot: &Robot, q: &[f64]) -> Result<Fk> {
    if q.len() != robot.dof() {
        return Err(robot.bad_q(q));
    }
    // The walk checks q on the way (finiteness, limits) in its vector registers.
    let (pose, scanned) = robot.chain.fk(q);
    if !scanned.finite {
        return Err(robot.bad_q(q));
    }
    Ok(Fk { world_from_tool: pose, out_of_limits: JointSet(scanned.outside) })
}

/// Forward kinematics as the row-major 4 × 4 homogeneous matrix of
/// `world_from_tool` (row r, column c at `out[4·r + c]`; the layout of a
/// C or NumPy 4 × 4 array), written into `out`, which must have 16 values.
/// Returns the joints outside their limits. The same numbers as
/// [`fk`], without building a [`Pose`] first. Does not allocate;
/// on an error `out` is left as it was.
///
/// # Examples
/// ```
/// let robot = kinema::Robot::builtin("lbr-iiwa-14-r820")?;
/// let mut t = [0.0; 16];
/// let outside = kinema::kin::fk_matrix_into(&robot, robot.home(), &mut t)?;
/// assert!(outside.is_empty());
/// assert!((t[11] - 1.306).abs() < 1e-12); // z of the tool at home
/// assert_eq!(t[12..], [0.0, 0.0, 0.0, 1.0]);
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn fk_matrix_into(robot: &Robot, q: &[f64], out: &mut [f64]) -> Result<JointSet> {
    // SAFETY: `fk_matrix_into_uninit` writes only computed values into `out`.
    fk_matrix_into_uninit(robot, q, unsafe { as_uninit(out) })
}

/// As [`fk_matrix_into`], into memory that need not be
/// initialised, such as a freshly allocated NumPy array: on `Ok` all 16
/// values have been written, on an error none.
pub fn fk_matrix_into_uninit(robot: &Robot, q: &[f64], out: &mut [MaybeUninit<f64>]) -> Result<JointSet> {
    if q.len() != robot.dof() {
        return Err(robot.bad_q(q));
    }
    let len = out.len();
    let Ok(out) = <&mut [MaybeUninit<f64>; 16]>::try_from(out) else {
        return Err(Error::Input(InputError::WrongLength {
            what: "out".into(),
            got: len,
            expected: 16,
            of: "a 4 × 4 matrix".into(),
        }));
    };
    let scanned = robot.chain.fk_rows(q, out);
    if !scanned.finite {
        return Err(robot.bad_q(q));
    }
    Ok(JointSet(scanned.outside))
}

/// Forward kinematics of many configurations at once, in parallel over all
/// cores. `qs` holds the configurations one after another (row-major,
/// `N × dof` values). Every configuration is checked before any work is done.
///
/// # Examples
/// ```
/// let robot = kinema::Robot::builtin("puma560")?;
/// let qs = [robot.home(), robot.pose("qr")?].concat();
/// let all = robot.fk_batch(&qs)?;
/// assert_eq!(all.len(), 2);
/// assert_eq!(all[1].world_from_tool, robot.fk(robot.pose("qr")?)?.world_from_tool);
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn fk_batch(robot: &Robot, qs: &[f64]) -> Result<Vec<Fk>> {
    let n = robot.dof();
    if qs.len() % n != 0 {
        // The nearest whole number of configurations, as the count expected.
        return Err(Error::Input(InputError::WrongLength {
            what: "qs".into(),
            got: qs.len(),
            expected: (qs.len() / n).max(1) * n,
            of: format!("a whole number of {n}-joint configurations"),
        }));
    }
    for (index, q) in qs.chunks_exact(n).enumerate() {
        robot.check_q(q).map_err(|e| Error::InBatch { index, source: Box::new(e) })?;
    }
    Ok(qs
        .par_chunks_exact(n)
        .with_min_len(1024)
        .map(|q| {
            let (pose, scanned) = robot.chain.fk(q);
            Fk { world_from_tool: pose, out_of_limits: JointSet(scanned.outside) }
        })
        .collect())
}

/// All frames along the chain: `out[0]` is the base frame, `out[i]` the
/// frame of link i (DH frame i for DH tables, the URDF child link frame for
/// URDF) and `out[dof + 1]` the tool frame, all in the base frame.
/// `out` must have `dof + 2` entries. Does not allocate.
pub fn link_frames_into(robot: &Robot, q: &[f64], out: &mut [Pose]) -> Result<Fk> {
    let out_of_limits = robot.scan_q(q)?;
    let n = robot.dof();
    if out.len() != n + 2 {
        return Err(Error::Input(InputError::WrongLength {
            what: "out".into(),
            got: out.len(),
            expected: n + 2,
            of: format!("frames: the base, {n} links and the tool"),
        }));
    }
    out[0] = *robot.base();
    robot.chain.link_frames(q, out);
    Ok(Fk { world_from_tool: out[n + 1], out_of_limits })
}

/// Geometric Jacobian of the tool point, rows \[vx vy vz ωx ωy ωz\],
/// expressed in `frame`, written into `out` (must be 6 × dof).
/// Returns the forward kinematics computed on the way. Does not allocate;
/// on an error `out` is left as it was.
pub fn jacobian_into(robot: &Robot, q: &[f64], frame: Frame, out: &mut Matrix6xX<f64>) -> Result<Fk> {
    let n = robot.dof();
    if q.len() == n && out.ncols() != n {
        return Err(Error::Input(InputError::WrongLength {
            what: "out".into(),
            got: out.ncols(),
            expected: n,
            of: format!("Jacobian columns, one per joint of `{}`", robot.name()),
        }));
    }
    // Column-major 6 × n storage: column i is data[6i..6i+6].
    let mut pose = Pose::IDENTITY;
    // SAFETY: `jacobian_in` writes only computed values into the matrix.
    let data = unsafe { as_uninit(out.as_mut_slice()) };
    let out_of_limits = jacobian_in(robot, q, frame, Layout::ColumnMajor, data, Some(&mut pose))?;
    Ok(Fk { world_from_tool: pose, out_of_limits })
}

/// As [`jacobian_into`], written row-major into a slice of
/// 6 · dof values: row r (vx, vy, vz, ωx, ωy, ωz) is
/// `out[r·dof..(r + 1)·dof]`, the layout of a C or NumPy 6 × dof array.
/// Returns the joints outside their limits (like [`fk_matrix_into`],
/// no pose). Does not allocate; on an error `out` is left as it was.
///
/// # Examples
/// ```
/// use kinema::{kin, Frame, Robot};
/// let robot = Robot::builtin("ur5")?;
/// let mut rows = [0.0; 36];
/// kin::jacobian_rows_into(&robot, robot.home(), Frame::Base, &mut rows)?;
/// let j = robot.jacobian(robot.home(), Frame::Base)?;
/// assert_eq!(rows[5 * 6], j[(5, 0)]); // ωz of joint 1
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn jacobian_rows_into(robot: &Robot, q: &[f64], frame: Frame, out: &mut [f64]) -> Result<JointSet> {
    // SAFETY: `jacobian_rows_into_uninit` writes only computed values into `out`.
    jacobian_rows_into_uninit(robot, q, frame, unsafe { as_uninit(out) })
}

/// As [`jacobian_rows_into`], into memory that need not be
/// initialised, such as a freshly allocated NumPy array: on `Ok` every one
/// of the 6 · dof values has been written, on an error none.
pub fn jacobian_rows_into_uninit(
    robot: &Robot,
    q: &[f64],
    frame: Frame,
    out: &mut [MaybeUninit<f64>],
) -> Result<JointSet> {
    let n = robot.dof();
    if q.len() == n && out.len() != 6 * n {
        return Err(Error::Input(InputError::WrongLength {
            what: "out".into(),
            got: out.len(),
            expected: 6 * n,
            of: format!("a 6 × {n} Jacobian of `{}`", robot.name()),
        }));
    }
    jacobian_in(robot, q, frame, Layout::RowMajor, out, None)
}

/// The Jacobian into `data` (of the right length) in `layout`, and the
/// pose into `pose` when given. (Always inlined: with the dispatch on
/// the joint count inside, LLVM otherwise kept it a function of its own,
/// a call and some 35 instructions more per Jacobian.)
#[inline(always)]
fn jacobian_in(
    robot: &Robot,
    q: &[f64],
    frame: Frame,
    layout: Layout,
    data: &mut [MaybeUninit<f64>],
    pose: Option<&mut Pose>,
) -> Result<JointSet> {
    if q.len() != robot.dof() {
        return Err(robot.bad_q(q));
    }
    // The walk checks q on the way and writes nothing when a value is not finite.
    let scanned = robot.chain.jacobian(q, frame == Frame::Tool, layout, data, pose);
    if !scanned.finite {
        return Err(robot.bad_q(q));
    }
    Ok(JointSet(scanned.outside))
}

/// Analytic Jacobian: rows \[ẋ ẏ ż ṙ₁ ṙ₂ ṙ₃\] where (r₁, r₂, r₃) is the
/// tool's roll-pitch-yaw triple in `conv` (for [`RpyConvention::Zyx`]:
/// roll, pitch, yaw rates). Errors at the representation singularity
/// (middle angle ±π/2).
pub fn analytic_jacobian(robot: &Robot, q: &[f64], conv: RpyConvention) -> Result<Matrix6xX<f64>> {
    let mut j = Matrix6xX::zeros(robot.dof());
    let fk = jacobian_into(robot, q, Frame::Base, &mut j)?;
    let rpy = fk.world_from_tool.rpy(conv);
    let e = rpy_rate_matrix(rpy, conv);
    let cos_mid = rpy[1].cos();
    if cos_mid.abs() < 1e-9 {
        return Err(Error::RpySingularity { pitch: rpy[1] });
    }
    let einv = e.try_inverse().ok_or(Error::RpySingularity { pitch: rpy[1] })?;
    let w = j.fixed_rows::<3>(3).into_owned();
    j.fixed_rows_mut::<3>(3).copy_from(&(einv * w));
    Ok(j)
}

/// The matrix E with ω = E · (ṙ₁, ṙ₂, ṙ₃) for a roll-pitch-yaw triple in `conv`.
pub fn rpy_rate_matrix(rpy: [f64; 3], conv: RpyConvention) -> Matrix3<f64> {
    let [a, b, c] = rpy;
    match conv {
        // R = Rz(yaw)·Ry(pitch)·Rx(roll), triple = (roll, pitch, yaw):
        // ω = ṙoll·Rz·Ry·x̂ + ṗitch·Rz·ŷ + ẏaw·ẑ.
        RpyConvention::Zyx => {
            let (sp, cp) = b.sin_cos();
            let (sy, cy) = c.sin_cos();
            Matrix3::new(cy * cp, -sy, 0.0, sy * cp, cy, 0.0, -sp, 0.0, 1.0)
        }
        // R = Rx(a)·Ry(b)·Rz(c): ω = ȧ·x̂ + ḃ·Rx·ŷ + ċ·Rx·Ry·ẑ.
        RpyConvention::Xyz => {
            let (sa, ca) = a.sin_cos();
            let (sb, cb) = b.sin_cos();
            Matrix3::new(1.0, 0.0, sb, 0.0, ca, -sa * cb, 0.0, sa, ca * cb)
        }
    }
}

/// Convenience forms on [`Robot`]: each calls the free function of the same
/// name in this module, allocating where the result is a vector or matrix.
impl Robot {
    /// Forward kinematics; see [`fk`].
    ///
    /// # Examples
    /// ```
    /// let robot = kinema::Robot::builtin("lbr-iiwa-14-r820")?;
    /// let fk = robot.fk(robot.home())?;
    /// // Stretched upright: 0.36 + 0.42 + 0.40 + 0.126 m above the base.
    /// assert!((fk.world_from_tool.pos.z - 1.306).abs() < 1e-12);
    /// assert!(fk.within_limits());
    /// # Ok::<(), kinema::Error>(())
    /// ```
    #[inline]
    pub fn fk(&self, q: &[f64]) -> Result<Fk> {
        fk(self, q)
    }

    /// Forward kinematics of many configurations in parallel; see [`fk_batch`].
    pub fn fk_batch(&self, qs: &[f64]) -> Result<Vec<Fk>> {
        fk_batch(self, qs)
    }

    /// All frames along the chain (see [`link_frames_into`]), allocated.
    pub fn link_frames(&self, q: &[f64]) -> Result<Vec<Pose>> {
        let mut out = vec![Pose::IDENTITY; self.dof() + 2];
        link_frames_into(self, q, &mut out)?;
        Ok(out)
    }

    /// Geometric Jacobian (see [`jacobian_into`]), allocated.
    ///
    /// # Examples
    /// ```
    /// use kinema::{Robot, Frame};
    /// let robot = Robot::builtin("ur5")?;
    /// let j = robot.jacobian(robot.home(), Frame::Base)?;
    /// assert_eq!((j.nrows(), j.ncols()), (6, 6));
    /// // The first joint turns about the base z axis.
    /// assert!((j[(5, 0)] - 1.0).abs() < 1e-12);
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn jacobian(&self, q: &[f64], frame: Frame) -> Result<Matrix6xX<f64>> {
        let mut j = Matrix6xX::zeros(self.dof());
        jacobian_into(self, q, frame, &mut j)?;
        Ok(j)
    }

    /// Analytic Jacobian; see [`analytic_jacobian`].
    pub fn analytic_jacobian(&self, q: &[f64], conv: RpyConvention) -> Result<Matrix6xX<f64>> {
        analytic_jacobian(self, q, conv)
    }
}

impl Data {
    /// Geometric Jacobian into the scratch (see [`jacobian_into`]).
    pub fn jacobian(&mut self, robot: &Robot, q: &[f64], frame: Frame) -> Result<&Matrix6xX<f64>> {
        self.fit(robot);
        jacobian_into(robot, q, frame, &mut self.jacobian)?;
        Ok(&self.jacobian)
    }

    /// All link frames into the scratch (see [`link_frames_into`]).
    pub fn link_frames(&mut self, robot: &Robot, q: &[f64]) -> Result<&[Pose]> {
        self.fit(robot);
        link_frames_into(robot, q, &mut self.frames)?;
        Ok(&self.frames)
    }
}

/// Joint `i`'s axis (`joint` is `robot.joints()[i]`) in the frame of the
/// link frames `frames` (as [`link_frames_into`] gives them): its unit
/// direction and a point on it. The point is fixed on the link before the
/// joint and, for a revolute joint, on the link after it too. A standard DH joint
/// turns about z of the previous frame (link i is Rz(θ)·… after frame i−1); a
/// modified DH joint about z of its own frame (…·Rz(θ)); a general joint
/// about `axis` of its own frame, which the joint's own motion leaves unchanged.
pub fn joint_axis(j: &Joint, i: usize, frames: &[Pose]) -> (Vector3<f64>, Vector3<f64>) {
    match j.geometry {
        LinkGeometry::Dh { convention: DhConvention::Standard, .. } => {
            (frames[i].rot.column(2).into_owned(), frames[i].pos)
        }
        LinkGeometry::Dh { convention: DhConvention::Modified, .. } => {
            (frames[i + 1].rot.column(2).into_owned(), frames[i + 1].pos)
        }
        LinkGeometry::General { axis, .. } => (frames[i + 1].rot * axis, frames[i + 1].pos),
    }
}
