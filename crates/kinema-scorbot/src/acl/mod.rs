//! A client for Controller-A's ACL language over any byte transport.
//!
//! The wire protocol (echo, reply lines, `>` prompt, `***` errors, paging)
//! is described in this crate's README. [`Client`] sends one command at a
//! time and reads its whole reply before returning:
//!
//! * every read has a timeout: the echo must arrive within
//!   [`Client::reply_timeout`]; the rest of the reply within the same timeout,
//!   or within [`Client::motion_timeout`] for the commands that answer when a
//!   motion ends (`HOME`, `MOVED`, `MOVES`, `OPEN`, `CLOSE`);
//! * a reply is bounded: at most [`MAX_REPLY_BYTES`] and [`MAX_PAGES`] pages,
//!   and all of it within the timeouts above plus [`PAGING_BUDGET`] — a
//!   controller that floods or pages forever is an error, not a hang;
//!   errors quote at most a short excerpt of what was received;
//! * a reply with a `***` line is [`Error::Controller`], one that does not
//!   parse is [`Error::Protocol`], both carrying the raw text;
//! * after any failure the client is *faulted*: motion commands return
//!   [`Error::Faulted`] until the caller calls [`Client::clear_fault`]
//!   (typically after [`Client::abort`] and a look at the arm). Commands that
//!   do not move the arm still work, so the caller can inspect the controller.
//!
//! # Examples
//! ```no_run
//! use kinema_scorbot::acl::Client;
//! let mut arm = Client::open_serial("/dev/ttyUSB0")?; // 9600 8N1, no flow control
//! arm.home()?;
//! arm.defp("P1")?;
//! arm.set_joint_position("P1", [0, -3437, 2867, 738, -738])?;
//! arm.move_d("P1", None)?;
//! let here = arm.listpv("P1")?;
//! println!("{:?}", here.counts);
//! # Ok::<(), kinema_scorbot::Error>(())
//! ```

mod commands;
pub(super) mod exchange;
mod link;
#[cfg(test)]
mod tests;

use std::io;
use std::net::{TcpStream, ToSocketAddrs};
use std::time::Duration;

use crate::error::{Error, Result};

pub use self::link::Link;

/// A Cartesian coordinate of an ACL position (`SETPVC`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CartesianAxis {
    /// X \[0.1 mm\].
    X,
    /// Y \[0.1 mm\].
    Y,
    /// Z \[0.1 mm\].
    Z,
    /// Pitch \[0.1°\].
    P,
    /// Roll \[0.1°\].
    R,
}

/// The controller's answer to one command.
#[derive(Debug, Clone, PartialEq)]
pub struct Reply {
    /// The command as sent (without the carriage return).
    pub command: String,
    /// The reply lines between the echo and the prompt, without line ends.
    pub lines: Vec<String>,
    /// Everything received for the command, as text.
    pub raw: String,
}

/// A position as `LISTPV` prints it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PositionReadout {
    /// Encoder counts of motors 1–5.
    pub counts: [i64; 5],
    /// X, Y, Z \[0.1 mm\], P, R \[0.1°\] by the controller's own kinematics,
    /// when it printed them.
    pub cartesian: Option<[i64; 5]>,
}

/// Default for [`Client::reply_timeout`].
pub const DEFAULT_REPLY_TIMEOUT: Duration = Duration::from_secs(3);
/// Default for [`Client::motion_timeout`].
pub const DEFAULT_MOTION_TIMEOUT: Duration = Duration::from_secs(120);

/// Most pages of one listing the client asks for.
pub const MAX_PAGES: usize = 1_000;
/// Most bytes one reply (or stale input before a command) may have.
pub const MAX_REPLY_BYTES: usize = 256 * 1024;
/// How much longer than a plain reply a paged listing may take in all.
pub const PAGING_BUDGET: Duration = Duration::from_secs(60);

/// Commands after which the controller answers only when a motion has ended.
const WAITING: [&str; 5] = ["HOME", "MOVED", "MOVES", "OPEN", "CLOSE"];
/// Commands that move the arm (blocked while the client is faulted).
const MOTION: [&str; 6] = ["HOME", "MOVE", "MOVED", "MOVES", "OPEN", "CLOSE"];

/// An ACL client over one [`Link`]. See the module documentation.
pub struct Client {
    link: Box<dyn Link>,
    /// Longest wait for the echo of a command and for a non-motion reply.
    pub reply_timeout: Duration,
    /// Longest wait for the end of a motion command's reply.
    pub motion_timeout: Duration,
    pending: Vec<u8>,
    fault: Option<String>,
}

impl std::fmt::Debug for Client {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Client")
            .field("reply_timeout", &self.reply_timeout)
            .field("motion_timeout", &self.motion_timeout)
            .field("fault", &self.fault)
            .finish_non_exhaustive()
    }
}

impl Client {
    /// A client over `link`, with the default timeouts.
    pub fn new(link: Box<dyn Link>) -> Client {
        Client {
            link,
            reply_timeout: DEFAULT_REPLY_TIMEOUT,
            motion_timeout: DEFAULT_MOTION_TIMEOUT,
            pending: Vec::new(),
            fault: None,
        }
    }

    /// Opens a serial device at the controller's settings: 9600 baud, 8 data
    /// bits, no parity, 1 stop bit, no flow control.
    pub fn open_serial(path: &str) -> Result<Client> {
        let port = serialport::new(path, 9600)
            .data_bits(serialport::DataBits::Eight)
            .parity(serialport::Parity::None)
            .stop_bits(serialport::StopBits::One)
            .flow_control(serialport::FlowControl::None)
            .timeout(DEFAULT_REPLY_TIMEOUT)
            .open()
            .map_err(|e| Error::io(format!("cannot open serial port {path}"), e.into()))?;
        Ok(Client::new(Box::new(port)))
    }

    /// Connects over TCP (a serial-to-network bridge or the simulator),
    /// giving up after `timeout`.
    pub fn connect_tcp(addr: &str, timeout: Duration) -> Result<Client> {
        let addrs: Vec<_> =
            addr.to_socket_addrs().map_err(|e| Error::io(format!("cannot resolve {addr}"), e))?.collect();
        let mut last = None;
        for a in addrs {
            match TcpStream::connect_timeout(&a, timeout) {
                Ok(s) => {
                    s.set_nodelay(true).ok();
                    return Ok(Client::new(Box::new(s)));
                }
                Err(e) => last = Some(e),
            }
        }
        // No address at all is a failure of the lookup, so it gets the OS's kind for that.
        let e = last.unwrap_or_else(|| io::Error::new(io::ErrorKind::NotFound, "the name resolves to no address"));
        Err(Error::io(format!("cannot connect to {addr}"), e))
    }

    /// The failure that blocks motion commands, if any.
    pub fn fault(&self) -> Option<&str> {
        self.fault.as_deref()
    }

    /// Allows motion commands again after a failure.
    pub fn clear_fault(&mut self) {
        self.fault = None;
    }

    /// Sends one command line and returns its reply (see the module
    /// documentation for timeouts and errors). `line` must be one line of
    /// printable ASCII.
    pub fn command(&mut self, line: &str) -> Result<Reply> {
        let line = line.trim();
        if line.is_empty() || !line.bytes().all(|b| (0x20..0x7f).contains(&b)) {
            return Err(Error::Malformed {
                what: "command".into(),
                text: line.into(),
                expected: "a command must be one non-empty line of printable ASCII".into(),
            });
        }
        let keyword = line.split_whitespace().next().unwrap_or("").to_ascii_uppercase();
        if MOTION.contains(&keyword.as_str()) {
            if let Some(cause) = &self.fault {
                return Err(Error::Faulted { cause: cause.clone() });
            }
        }
        let waiting = WAITING.contains(&keyword.as_str());
        let result = self.exchange(line, waiting, false);
        if let Err(e) = &result {
            self.fault = Some(e.to_string());
        }
        result
    }
}
