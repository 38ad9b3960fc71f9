//! # kinema — kinematics, inverse kinematics, trajectories and dynamics of serial robot arms
//!
//! The core library of the kinema toolkit:
//!
//! * [`Model`] — the plain description of a serial chain of revolute and
//!   prismatic joints, and [`Robot`], a model compiled for computing; described by a standard-DH table, a modified-DH table or per-joint fixed
//!   transforms and axes (URDF). Load one with [`Robot::builtin`],
//!   [`Robot::from_file`] (`.toml` or `.urdf`) or build it in code
//!   ([`description::Description`], validated as a file is, every problem named at once).
//! * Forward kinematics ([`Robot::fk`], [`Robot::link_frames`],
//!   [`Robot::fk_batch`]) and Jacobians ([`Robot::jacobian`],
//!   [`Robot::analytic_jacobian`]) in [`kin`]; the hot paths do not allocate.
//! * [`reference`](mod@reference) — the same FK, frames and Jacobians written plainly and
//!   generic over the scalar (dual numbers work): the definition the fast
//!   path is tested against, and the place to start reading.
//! * Spatial math in [`math`]: [`Pose`], roll-pitch-yaw in two named
//!   conventions ([`RpyConvention`]), quaternions, axis-angle, pose errors.
//! * Manipulability and singularity analysis in [`analysis`].
//! * Inverse kinematics in [`ik`]: every closed-form solution where the
//!   robot's structure admits one (solver families read from the joint axes,
//!   behind [`ik::IkSolver`]), a numeric solver for any chain, and one request
//!   layer ([`ik::solve_target`], [`ik::solve_batch`]) that lists a solution
//!   only if forward kinematics of it meets the target.
//! * Trajectories in [`traj`]: time laws, synchronised joint-space PTP
//!   ([`traj::Ptp`]), Cartesian LIN and CIRC with blending, several robots on
//!   one clock ([`traj::Cell`]), and [`traj::check`], which checks every
//!   sample against the limits before anything is written.
//! * Rigid-body dynamics in [`dynamics`]: inverse dynamics
//!   ([`dynamics::rnea`]), the mass matrix ([`dynamics::mass_matrix`]),
//!   forward dynamics ([`dynamics::forward_dynamics`]) and allocation-free
//!   variants.
//!
//! Units are SI everywhere: metres, radians, seconds. Jacobian rows are
//! \[vx vy vz ωx ωy ωz\]. `nalgebra` is re-exported.
//!
//! ## Example
//!
//! ```
//! use kinema::{Robot, Frame, analysis};
//!
//! let robot = Robot::builtin("lbr-iiwa-14-r820")?;
//! let q = [0.0, 0.5, 0.0, -1.2, 0.0, 0.6, 0.0];
//! let fk = robot.fk(&q)?;
//! assert!(fk.within_limits());
//! let j = robot.jacobian(&q, Frame::Base)?;
//! let report = analysis::report(&j)?;
//! assert_eq!(report.rank, 6);
//! // A tiny joint motion moves the tool by J·dq.
//! let dq = [1e-7; 7];
//! let moved = robot.fk(&[q[0] + dq[0], q[1] + dq[1], q[2] + dq[2], q[3] + dq[3], q[4] + dq[4], q[5] + dq[5], q[6] + dq[6]])?;
//! let predicted = fk.world_from_tool.pos + (j.fixed_rows::<3>(0) * kinema::nalgebra::DVector::from_row_slice(&dq));
//! assert!((moved.world_from_tool.pos - predicted).norm() < 1e-12);
//! # Ok::<(), kinema::Error>(())
//! ```
#![warn(missing_docs)]
// `!(x > 0.0)` is used on purpose throughout: unlike `x <= 0.0` it is also
// true for NaN, which is how inputs are rejected.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub use nalgebra;

pub mod analysis;
mod chain;
mod data;
mod desc;
pub mod description;
pub mod dynamics;
mod error;
pub mod ik;
mod joint_text;
pub mod kin;
mod lanes;
pub mod math;
pub mod model;
mod names;
pub mod quantity;
pub mod reach;
mod read;
pub mod reference;
mod registry;
mod robot;
pub mod traj;
mod urdf;

pub use data::Data;
pub use error::{Error, FileError, InputError, IoError, ModelError, Result};
pub use kin::{Fk, Frame};
pub use math::{Pose, PoseError, RpyConvention};
pub use model::{
    DhConvention, GeometryKind, Inertial, Joint, JointSet, JointType, Limits, LinkGeometry, Metadata, Model,
    ModelBuilder, NamedPose, MAX_MAGNITUDE,
};
pub use names::Named;
pub use read::{read_bounded, read_bounded_text};
pub use registry::{builtin_names, builtin_source, MAX_DESCRIPTION_BYTES};
pub use robot::Robot;
pub use urdf::UrdfLink;
