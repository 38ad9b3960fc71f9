//! # kinema-lang — the kinema robot programming language
//!
//! Seed 003 (§IV, Fig. 8) gave its SCARA a small language — `HOME`, `PAUSE`,
//! `MOVEZ`, `MOVETITA`, `MOVEXY`, `LOOP … END`, `//` comments — compiled to
//! joint signals. This crate keeps those statements exactly as printed (for
//! SCARA robots) and grows them into a small industrial-style motion language
//! for any robot: named positions (`POS`), `PTP`/`LIN`/`CIRC` to named or
//! literal targets, absolute or `REL`, speed and acceleration settings,
//! blending, `WAIT`, `HOME`, `LOOP` and `FOR`, tool and base frames, units
//! written in the program. The grammar is in `docs/language.md`.
//!
//! * [`parse`] — source text to a syntax tree ([`ast`]) and diagnostics;
//!   never panics, reports every syntax error in one run.
//! * [`compile`](fn@compile) — checks names, units, argument counts and what the robot
//!   can do, then runs the program on the robot model (IK for every
//!   target, a time law per motion, samples every `dt`) and checks the
//!   joint signals against the limits. The result is a [`Plan`]: the
//!   motions with their source lines and times, and the trajectory.
//! * [`Diagnostic`] — what is wrong, where (`file:line:col`), and a hint,
//!   rendered with the source line underlined.
//!
//! ## Example
//!
//! ```
//! let robot = kinema::Robot::builtin("scara5")?;
//! let program = "
//! // seed 003, Fig. 8
//! HOME 2;
//! LOOP 2
//!   MOVEZ -50, 1;
//!   MOVEXY 100, -50, 2;
//!   MOVEZ +50, 1;
//! END
//! ";
//! let plan = kinema_lang::compile(program, &robot, &kinema_lang::Options::default())
//!     .map_err(|d| kinema_lang::render_all(&d, "pick.prg", program))
//!     .unwrap();
//! assert!((plan.duration() - 10.0).abs() < 1e-9); // 2 + 2 × (1 + 2 + 1)
//! assert_eq!(plan.motions.len(), 7);
//! # Ok::<(), kinema::Error>(())
//! ```
#![warn(missing_docs)]

pub mod ast;
pub mod compile;
pub mod diag;
pub mod lexer;
pub mod parser;
pub mod planner;
pub mod stop;
pub mod units;

pub use compile::{compile, Options, Plan, PlannedMotion};
pub use diag::{render_all, Diagnostic, Severity};
pub use parser::parse;
pub use planner::PathPlanner;
pub use stop::{Stop, StopReason};

/// Every diagnostic of `src` for `robot` (parse, check, execution and limit
/// checks), without keeping the plan. Empty when the program is fine.
pub fn check(src: &str, robot: &kinema::Robot, opts: &Options) -> Vec<Diagnostic> {
    match compile(src, robot, opts) {
        Ok(plan) => plan.warnings,
        Err(d) => d,
    }
}
