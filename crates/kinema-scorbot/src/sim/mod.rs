//! A simulator of the Scorbot-ER V Plus controller (Controller-A) speaking the
//! ACL subset of this crate's README, to test a host-side client end to end.
//!
//! * [`Controller`]: the controller as a pure state machine with explicit time.
//!   Bytes go in with [`Controller::feed`], time moves on with
//!   [`Controller::advance`], and bytes come out with
//!   [`Controller::take_output`]. Motions complete in simulated time; nothing
//!   here sleeps, reads a clock or touches a socket.
//! * [`serve_tcp`]: the controller behind a TCP listener, one connection at a
//!   time; its state survives reconnections like a real controller whose cable
//!   is replugged.
//! * [`PtySim`]: the controller behind a pseudo-terminal, so a client opens it
//!   like a serial port (`serialport::new(path, 9600)`).
//! * [`SimConfig`]: the controller's stored encoder constants, the physical
//!   arm's constants, a time scale, injected [`Fault`]s, and an optional record
//!   of the physical tool position (an emulation of the seed's external
//!   camera).
//!
//! # Behaviour beyond the README (our choices)
//!
//! * Nothing is sent on connection; a client may send a bare `\r` to get a
//!   prompt (an empty line is echoed as `\r\n` followed by `>`).
//! * Lines end at `\r`; `\n` bytes are ignored. A line longer than
//!   [`MAX_LINE`] bytes is answered with `*** LINE TOO LONG`.
//! * While a command that answers at the end of a motion (`HOME`, `MOVED`,
//!   `MOVES`, `OPEN`, `CLOSE`) waits, lines typed ahead are kept (up to
//!   [`MAX_TYPE_AHEAD`]) and run after its prompt; only `A` runs at once. The
//!   waiting command then ends with `*** MOTION ABORTED` and its prompt, and
//!   the `A` follows with its own echo, `Done.` and prompt.
//! * Every motion command goes through one motion queue: `MOVE` answers at
//!   once, the others when their own motion ends. `A` and `COFF` stop the arm
//!   and empty the queue; `CLRBUF` empties the queue and lets the running
//!   motion end. An aborted `HOME` leaves the arm not homed.
//! * `OPEN` and `CLOSE` need control on but not homing.
//! * While `LISTP` waits at `Type <cr> to continue`, the next line (whatever
//!   it holds) continues the listing; it is not echoed.
//! * `LISTP` prints one name per line (`P1`, `V[3]`, …), scalar positions in
//!   name order, then vector elements.
//! * `SETPV` on a Cartesian position solves it first and then sets the axis
//!   (the position becomes a joint position); `SETPVC` on a joint position
//!   starts from its coordinates by forward kinematics.
//! * A [`FaultKind::Delay`] holds back the output of the commands after the
//!   delayed one too: output never overtakes earlier output.
//! * The gripper starts open.
//! * A joint angle counts as within its limit up to [`LIMIT_TOLERANCE`] beyond
//!   it, so positions solved by inverse kinematics on a limit survive the
//!   rounding to whole counts.
//!
//! # Examples
//! ```
//! use std::time::Duration;
//! use kinema_scorbot::sim::{Controller, SimConfig};
//! let mut c = Controller::new(SimConfig { time_scale: 0.01, ..SimConfig::default() })?;
//! let t = Duration::ZERO;
//! c.feed(t, b"home\r");
//! assert_eq!(c.take_output(t), b"home\r\nHOMING...\r\n");
//! // Homing takes 5 s nominal, 50 ms at this time scale.
//! let t = Duration::from_millis(50);
//! c.advance(t);
//! assert_eq!(c.take_output(t), b"Done.\r\n>");
//! assert!(c.is_homed());
//! # Ok::<(), kinema_scorbot::Error>(())
//! ```

mod controller;
#[cfg(test)]
mod tests;
mod transport;

use std::fmt;
use std::path::PathBuf;
use std::str::FromStr;
use std::time::Duration;

use crate::encoder::{Constants, CountsPerDegree, HomeOffsets};
use crate::error::Error;

pub use controller::{Controller, LIMIT_TOLERANCE, MAX_LINE, MAX_SAMPLES, MAX_SAMPLES_PER_MOTION, MAX_TYPE_AHEAD};
pub use transport::serve_tcp;
#[cfg(unix)]
pub use transport::PtySim;

/// The ACL keywords the simulator understands (uppercase).
pub const COMMANDS: [&str; 18] = [
    "HOME", "CON", "COFF", "SPEED", "DEFP", "DIMP", "HERE", "SETPV", "SETPVC", "LISTPV", "LISTP", "MOVE", "MOVED",
    "MOVES", "OPEN", "CLOSE", "A", "CLRBUF",
];

/// The commands that move the arm or the gripper.
pub const MOTION_COMMANDS: [&str; 6] = ["HOME", "MOVE", "MOVED", "MOVES", "OPEN", "CLOSE"];

/// Configuration of the simulated controller and arm.
#[derive(Debug, Clone, PartialEq)]
pub struct SimConfig {
    /// The encoder constants stored in the controller: they convert counts to
    /// joint angles for the limit check, `LISTPV` and `SETPVC`, and set the
    /// motors' speeds. Default: `Constants::named("factory")`.
    pub constants: Constants,
    /// The constants of the physical arm: the recorded tool positions are the
    /// forward kinematics of the angles these give for the counts. Default:
    /// `Constants::named("calibrated")` (seed 000's calibration).
    pub true_constants: Constants,
    /// Factor applied to every duration of simulated motion (1.0: real
    /// time; 0.01: a 5 s homing takes 50 ms). Must be finite and > 0.
    pub time_scale: f64,
    /// Faults to inject (see [`Fault`]).
    pub faults: Vec<Fault>,
    /// If set, a CSV file (`x,y,z` header, metres) of the physical tool
    /// position every 10 ms of nominal motion time during every arm motion
    /// (`HOME`, `MOVE`, `MOVED`, `MOVES`; each motion's samples run from its
    /// start to its end or stop, both included). The file is created with its
    /// header when the controller starts (atomically: temporary file +
    /// rename); each motion's rows are appended in one write when it ends. A
    /// long motion is sampled more coarsely (at most
    /// [`MAX_SAMPLES_PER_MOTION`] rows), and recording stops after
    /// [`MAX_SAMPLES`] rows.
    pub record: Option<PathBuf>,
    /// Standard deviation of the Gaussian measurement noise added to each
    /// recorded coordinate \[m\]. Default 0.
    pub noise: f64,
    /// Seed of the noise (and of the garbage bytes of [`FaultKind::Garble`]).
    pub seed: u64,
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig {
            constants: Constants::preset(CountsPerDegree::Factory, HomeOffsets::Factory),
            true_constants: Constants::preset(CountsPerDegree::Calibrated, HomeOffsets::Measured),
            time_scale: 1.0,
            faults: Vec::new(),
            record: None,
            noise: 0.0,
            seed: 0,
        }
    }
}

/// What an injected fault does to the command it hits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FaultKind {
    /// No echo, no reply, no prompt; the command has no effect.
    Drop,
    /// The command takes effect and is echoed, but each reply line is replaced
    /// by garbage (non-ASCII bytes and letters, never `***`, `Done.` or `>`);
    /// the prompt (and a listing's `Type <cr> to continue`) still follows.
    Garble,
    /// The command takes effect at once, but everything it prints (the echo
    /// included) is sent this much later (wall-clock time, not scaled).
    Delay(Duration),
    /// For a motion command: the connection is closed halfway through its
    /// motion and the arm stops there. For another command (or a refused
    /// motion command): the connection is closed when the command arrives,
    /// and the command has no effect.
    Disconnect,
}

/// A fault injected at the `nth` occurrence of a command keyword.
///
/// The text form (`FromStr`, `Display`) is `KIND@COMMAND[#N]` with KIND one of
/// `drop`, `garble`, `delay=SECONDS`, `disconnect`; N defaults to 1.
///
/// # Examples
/// ```
/// use std::time::Duration;
/// use kinema_scorbot::sim::{Fault, FaultKind};
/// let f: Fault = "delay=3.5@home#2".parse()?;
/// assert_eq!(f, Fault { kind: FaultKind::Delay(Duration::from_millis(3500)), command: "HOME".into(), nth: 2 });
/// assert_eq!(f.to_string(), "delay=3.5@HOME#2");
/// assert_eq!("drop@MOVED".parse::<Fault>()?.to_string(), "drop@MOVED");
/// assert!("explode@HOME".parse::<Fault>().is_err());
/// # Ok::<(), kinema_scorbot::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Fault {
    /// What happens.
    pub kind: FaultKind,
    /// The command keyword it hits, uppercase (`MOVED`, `LISTPV`, …).
    pub command: String,
    /// Which occurrence of the keyword it hits, 1-based (counted over every
    /// line with that keyword the controller reads, refused ones included).
    pub nth: usize,
}

const FAULT_FORMS: &str = "drop@CMD, garble@CMD, delay=SECONDS@CMD or disconnect@CMD, each optionally followed by \
                           #N for the N-th occurrence (e.g. drop@MOVED, garble@LISTPV#2, delay=3.5@HOME, \
                           disconnect@MOVES)";

impl FromStr for Fault {
    type Err = Error;

    fn from_str(s: &str) -> Result<Fault, Error> {
        let bad = |why: String| Error::Malformed {
            what: "fault".into(),
            text: s.into(),
            expected: format!("{why}; the accepted forms are {FAULT_FORMS}"),
        };
        let text = s.trim();
        let (kind_text, rest) = text.split_once('@').ok_or_else(|| bad("no `@` before the command".into()))?;
        let (command, nth) = match rest.split_once('#') {
            Some((c, n)) => {
                let nth = n
                    .trim()
                    .parse::<usize>()
                    .ok()
                    .filter(|&n| n >= 1)
                    .ok_or_else(|| bad(format!("`#{n}` is not an occurrence number ≥ 1")))?;
                (c, nth)
            }
            None => (rest, 1),
        };
        let command = command.trim().to_ascii_uppercase();
        if command.is_empty() || !COMMANDS.contains(&command.as_str()) {
            return Err(bad(format!("`{command}` is not a command of the simulator ({})", COMMANDS.join(", "))));
        }
        let kind_text = kind_text.trim().to_ascii_lowercase();
        let kind = match kind_text.as_str() {
            "drop" => FaultKind::Drop,
            "garble" => FaultKind::Garble,
            "disconnect" => FaultKind::Disconnect,
            k => match k.strip_prefix("delay=") {
                Some(secs) => {
                    let v: f64 =
                        secs.trim().parse().map_err(|_| bad(format!("`{secs}` is not a number of seconds")))?;
                    if !(v.is_finite() && (0.0..=86_400.0).contains(&v)) {
                        return Err(bad(format!("a delay of {v} s; it must be between 0 and 86400 s")));
                    }
                    FaultKind::Delay(Duration::from_secs_f64(v))
                }
                None => return Err(bad(format!("unknown fault kind `{k}`"))),
            },
        };
        Ok(Fault { kind, command, nth })
    }
}

impl fmt::Display for Fault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.kind {
            FaultKind::Drop => write!(f, "drop")?,
            FaultKind::Garble => write!(f, "garble")?,
            FaultKind::Delay(d) => write!(f, "delay={}", d.as_secs_f64())?,
            FaultKind::Disconnect => write!(f, "disconnect")?,
        }
        write!(f, "@{}", self.command)?;
        if self.nth != 1 {
            write!(f, "#{}", self.nth)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod fault_tests {
    use super::*;

    #[test]
    fn faults_parse_and_print_back() {
        for (text, kind, cmd, nth) in [
            ("drop@MOVED", FaultKind::Drop, "MOVED", 1),
            ("garble@LISTPV#2", FaultKind::Garble, "LISTPV", 2),
            ("delay=3.5@HOME", FaultKind::Delay(Duration::from_millis(3500)), "HOME", 1),
            ("disconnect@MOVES", FaultKind::Disconnect, "MOVES", 1),
            ("delay=0.25@A#10", FaultKind::Delay(Duration::from_millis(250)), "A", 10),
        ] {
            let f: Fault = text.parse().unwrap();
            assert_eq!(f, Fault { kind, command: cmd.into(), nth });
            assert_eq!(f.to_string(), text);
            assert_eq!(f.to_string().parse::<Fault>().unwrap(), f);
        }
        assert_eq!(" Garble@listpv # 3 ".parse::<Fault>().unwrap().to_string(), "garble@LISTPV#3");
    }

    #[test]
    fn bad_faults_name_the_accepted_forms() {
        for (text, part) in [
            ("drop", "no `@`"),
            ("drop@", "not a command"),
            ("drop@JUMP", "`JUMP` is not a command"),
            ("boom@HOME", "unknown fault kind `boom`"),
            ("delay=x@HOME", "not a number of seconds"),
            ("delay=-1@HOME", "between 0 and 86400"),
            ("delay=nan@HOME", "between 0 and 86400"),
            ("drop@HOME#0", "occurrence number"),
            ("drop@HOME#x", "occurrence number"),
        ] {
            let e = text.parse::<Fault>().unwrap_err().to_string();
            assert!(e.contains(part), "{text}: {e}");
            assert!(e.contains("delay=SECONDS@CMD"), "{e}");
        }
    }
}
