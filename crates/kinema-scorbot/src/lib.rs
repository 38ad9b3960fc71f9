//! kinema on a real Scorbot-ER V Plus (seed 000 §III-B, §IV-B).
//!
//! * [`encoder`]: joint angles ↔ motor encoder counts (eq. 24, Tabla II–III),
//!   and the tool-position uncertainty the tables' ± columns imply.
//! * [`follow`]: seed 000's path following — resampling to ≤ 1 cm, IK,
//!   counts, and sending as a vector with `MOVES` or point by point.
//! * [`acl`]: a client for the controller's ACL language over a serial port or
//!   TCP, with timeouts, typed errors and a fault latch that blocks motion.
//! * [`metrics`]: tracking error of measured runs (seed 000 §IV-B) and the
//!   ISO 9283 path/pose accuracy and repeatability.
//! * [`calib`]: estimating the encoder constants (and link lengths) from
//!   measured tool positions by Levenberg–Marquardt, with uncertainties.
//! * [`sim`]: a simulator of the controller (ACL over TCP or a pseudo-terminal), with fault injection.
//! * [`experiment`]: seed 000's accuracy experiment (Fig. 5–6) on the simulator:
//!   a path planned with several sets of constants, followed, recorded and scored.
//!
//! # Example
//! ```
//! use kinema_scorbot::encoder::Constants;
//! let robot = kinema::Robot::builtin("scorbot-er-v-plus")?;
//! let c = Constants::named("calibrated")?;
//! let counts = c.counts_rounded(robot.home())?;
//! assert_eq!(counts.len(), 5);
//! # Ok::<(), kinema_scorbot::Error>(())
//! ```
#![warn(missing_docs)]

pub mod acl;
pub mod calib;
mod csvio;
pub mod encoder;
mod error;
pub mod experiment;
pub mod follow;
pub mod metrics;
pub mod sim;

pub use error::{Error, Result};
