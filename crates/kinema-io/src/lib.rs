//! The answers kinema gives, as one set of [`serde::Serialize`] types: what
//! `kinema … --json` prints, what the HTTP API (`kinema-serve`) returns and
//! what Python's `to_dict` calls give, field for field, so the three doors
//! cannot drift apart.
//!
//! [`trajectory_csv`] is the one reader and writer of a joint trajectory CSV,
//! so that what one command writes another reads.
//!
//! Each answer's constructor calls the core and reads its values out, so a
//! door converts and prints and decides nothing.
//!
//! ```
//! use kinema::{Robot, RpyConvention};
//! use kinema_io::FkAnswer;
//!
//! let robot = Robot::builtin("puma560")?;
//! let answer = FkAnswer::new(&robot, robot.home(), RpyConvention::Zyx)?;
//! assert_eq!(answer.pose.position, answer.frames.last().unwrap().position);
//! # Ok::<(), kinema::Error>(())
//! ```

#![warn(missing_docs)]

mod avoid;
mod bench;
mod cell;
mod collide;
mod error;
mod ik;
mod kinematics;
mod pose;
mod program;
mod robot;
mod shard;
mod solution;
mod traj;
mod trajectory;
pub mod trajectory_csv;

pub use avoid::{ScenePlanner, AVOID_TIME_LIMIT};
pub use bench::{BenchAnswer, IkBench};
pub use cell::{CellAnswer, CellBodies, CellMember, CellPair, CellRobot, ClosestApproach, ManipRange, Placement, Span};
pub use collide::{CollideAnswer, CollidePair, DistanceAnswer};
pub use error::ErrorAnswer;
pub use ik::{
    shown_q, ClosestAnswer, DiscardedAnswer, DiscardedCandidate, IkAnswer, SelfMotionAnswer, SelfMotionPoint,
    ToleranceAnswer, UnreachableAnswer, ValidateAnswer, DISCARD_REASON, MISSED,
};
pub use program::{MotionAnswer, ProgramAnswer};
pub use shard::Shard;
pub use traj::{
    CheckAnswer, JointExpression, LawAnswer, LawSamples, PlanAnswer, SkippedPoint, TimedValue, TrajSummary,
    ViolationAnswer,
};

pub use kinematics::{
    Coefficient, DependentJoint, Ellipsoid, FkAnswer, FrameAnswer, JacobianAnswer, JointAxis, JointRef, ManipAnswer,
};
pub use pose::PoseAnswer;
pub use robot::{JointGeometry, JointInfo, RobotIk, RobotInfo, RobotSummary};
pub use solution::SolutionAnswer;
pub use trajectory::TrajectoryAnswer;
