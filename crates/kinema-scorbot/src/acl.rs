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

use std::io::{self, Read, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::time::{Duration, Instant};

use crate::error::{Error, Result};

/// A byte transport to the controller with a settable read timeout: a TCP
/// stream, a serial port, or anything else that reads and writes bytes.
pub trait Link: Read + Write + Send {
    /// Sets how long one `read` may block before failing with
    /// `TimedOut`/`WouldBlock`.
    fn set_timeout(&mut self, timeout: Duration) -> io::Result<()>;

    /// Reads what has already arrived without waiting: `WouldBlock` when
    /// nothing has. The default waits at most a millisecond.
    fn read_now(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        self.set_timeout(Duration::from_millis(1))?;
        self.read(buf)
    }
}

impl Link for TcpStream {
    fn set_timeout(&mut self, timeout: Duration) -> io::Result<()> {
        self.set_read_timeout(Some(timeout.max(Duration::from_millis(1))))
    }

    fn read_now(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        self.set_nonblocking(true)?;
        let r = self.read(buf);
        self.set_nonblocking(false)?;
        r
    }
}

impl Link for Box<dyn serialport::SerialPort> {
    fn set_timeout(&mut self, timeout: Duration) -> io::Result<()> {
        serialport::SerialPort::set_timeout(self.as_mut(), timeout).map_err(io::Error::from)
    }

    fn read_now(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let waiting = self.bytes_to_read().map_err(io::Error::from)?;
        if waiting == 0 {
            return Err(io::Error::new(io::ErrorKind::WouldBlock, "nothing received"));
        }
        let n = buf.len().min(waiting as usize);
        self.read(&mut buf[..n])
    }
}

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

    fn exchange(&mut self, line: &str, waiting: bool, skip_to_echo: bool) -> Result<Reply> {
        self.discard_stale(line)?;
        let mut out = Vec::with_capacity(line.len() + 1);
        out.extend_from_slice(line.as_bytes());
        out.push(b'\r');
        self.link
            .write_all(&out)
            .and_then(|_| self.link.flush())
            .map_err(|e| io_error(e, &format!("sending `{line}`")))?;

        let mut raw: Vec<u8> = Vec::new();
        let mut lines: Vec<String> = Vec::new();
        let mut echoed = false;
        let mut pages = 0usize;
        let wait = if waiting { self.motion_timeout } else { self.reply_timeout };
        let budget = self.reply_timeout + wait + PAGING_BUDGET;
        let hard_deadline = Instant::now() + budget;
        let mut deadline = Instant::now() + self.reply_timeout;
        loop {
            if raw.len() + self.pending.len() > MAX_REPLY_BYTES {
                raw.append(&mut self.pending);
                return Err(Error::Protocol {
                    command: line.into(),
                    message: format!("the reply is longer than {MAX_REPLY_BYTES} bytes"),
                    raw: String::from_utf8_lossy(&raw).into_owned(),
                });
            }
            // Consume complete lines.
            while let Some(nl) = self.pending.iter().position(|&b| b == b'\n') {
                let chunk: Vec<u8> = self.pending.drain(..=nl).collect();
                raw.extend_from_slice(&chunk);
                let text = String::from_utf8_lossy(&chunk).trim_matches(['\r', '\n']).to_string();
                if !echoed {
                    // The prompt of an earlier command may precede the echo.
                    let echo = text.trim_start_matches('>').trim();
                    if !echo.eq_ignore_ascii_case(line) && skip_to_echo {
                        // What a command interrupted by this one printed.
                        continue;
                    }
                    if !echo.eq_ignore_ascii_case(line) {
                        return Err(Error::Protocol {
                            command: line.into(),
                            message: format!("expected the echo `{line}`, got `{echo}`"),
                            raw: String::from_utf8_lossy(&raw).into_owned(),
                        });
                    }
                    echoed = true;
                    deadline = Instant::now() + wait;
                    continue;
                }
                if text.contains("Type <cr>") {
                    // A paged listing: ask for the next page.
                    deadline = self.next_page(&mut pages, line, &raw)?;
                    continue;
                }
                lines.push(text);
            }
            // The prompt ends the reply.
            if echoed
                && self.pending.iter().all(|b| b.is_ascii_whitespace() || *b == b'>')
                && self.pending.contains(&b'>')
            {
                raw.append(&mut self.pending);
                break;
            }
            let now = Instant::now();
            if now >= deadline.min(hard_deadline) {
                raw.extend_from_slice(&self.pending);
                self.pending.clear();
                let timeout = if now >= hard_deadline {
                    budget
                } else if echoed && waiting {
                    self.motion_timeout
                } else {
                    self.reply_timeout
                };
                return Err(Error::Timeout {
                    command: line.into(),
                    timeout,
                    received: String::from_utf8_lossy(&raw).into_owned(),
                });
            }
            let got = self.read_some(deadline.min(hard_deadline) - now, line)?;
            if !got && echoed && String::from_utf8_lossy(&self.pending).contains("Type <cr>") {
                // A page prompt printed without a line end, and nothing after it.
                deadline = self.next_page(&mut pages, line, &raw)?;
                raw.append(&mut self.pending);
            }
        }
        let raw = String::from_utf8_lossy(&raw).into_owned();
        if let Some(bad) = lines.iter().find(|l| l.contains("***")) {
            let message = bad.trim().chars().take(crate::error::EXCERPT_CHARS).collect();
            return Err(Error::Controller { command: line.into(), message, raw });
        }
        Ok(Reply { command: line.into(), lines, raw })
    }

    /// Asks a paged listing for its next page (a carriage return), at most
    /// [`MAX_PAGES`] times per command; returns the new reply deadline.
    fn next_page(&mut self, pages: &mut usize, line: &str, raw: &[u8]) -> Result<Instant> {
        *pages += 1;
        if *pages > MAX_PAGES {
            return Err(Error::Protocol {
                command: line.into(),
                message: format!("more than {MAX_PAGES} pages"),
                raw: String::from_utf8_lossy(raw).into_owned(),
            });
        }
        self.link.write_all(b"\r").map_err(|e| io_error(e, &format!("paging `{line}`")))?;
        Ok(Instant::now() + self.reply_timeout)
    }

    /// Reads what is available within `wait` into `pending`; whether
    /// anything arrived.
    fn read_some(&mut self, wait: Duration, line: &str) -> Result<bool> {
        self.link
            .set_timeout(wait.min(Duration::from_millis(200)))
            .map_err(|e| io_error(e, "setting the read timeout"))?;
        let mut buf = [0u8; 512];
        match self.link.read(&mut buf) {
            Ok(0) => Err(Error::Disconnected { during: format!("waiting for the reply to `{line}`") }),
            Ok(n) => {
                self.pending.extend_from_slice(&buf[..n]);
                Ok(true)
            }
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock | io::ErrorKind::Interrupted
                ) =>
            {
                Ok(false)
            }
            Err(e) => Err(io_error(e, &format!("waiting for the reply to `{line}`"))),
        }
    }

    /// Drops bytes left over from an earlier command (a late reply after a
    /// timeout) so they cannot be taken for this command's reply.
    fn discard_stale(&mut self, line: &str) -> Result<()> {
        self.pending.clear();
        let mut buf = [0u8; 512];
        let (mut dropped, deadline) = (0usize, Instant::now() + self.reply_timeout);
        loop {
            if dropped > MAX_REPLY_BYTES || Instant::now() >= deadline {
                return Err(Error::Protocol {
                    command: line.into(),
                    message: format!(
                        "before it was sent, the controller kept sending unasked ({dropped} bytes in {:?}); is it flooding the line?",
                        self.reply_timeout
                    ),
                    raw: String::from_utf8_lossy(&buf).into_owned(),
                });
            }
            match self.link.read_now(&mut buf) {
                Ok(0) => return Err(Error::Disconnected { during: "checking for stale input".into() }),
                Ok(n) => dropped += n,
                Err(e)
                    if matches!(
                        e.kind(),
                        io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock | io::ErrorKind::Interrupted
                    ) =>
                {
                    return Ok(())
                }
                Err(e) => return Err(io_error(e, "checking for stale input")),
            }
        }
    }

    /// Runs a command that answers `Done.` (required after a motion command;
    /// after the others, a reply without any line is accepted too, as some
    /// controller firmware prints nothing). Any other text is a protocol error.
    fn done(&mut self, line: &str) -> Result<()> {
        let reply = self.command(line)?;
        let keyword = line.split_whitespace().next().unwrap_or("").to_ascii_uppercase();
        let motion = MOTION.contains(&keyword.as_str());
        let said_done = reply.lines.iter().any(|l| l.trim() == "Done.");
        // HOME announces itself before it ends.
        let other =
            reply.lines.iter().map(|l| l.trim()).any(|l| !l.is_empty() && l != "Done." && !l.starts_with("HOMING"));
        if (said_done || !motion) && !other {
            Ok(())
        } else {
            let message = if other { "expected only `Done.`" } else { "expected `Done.`" };
            let err = Error::Protocol { command: line.into(), message: message.into(), raw: reply.raw };
            self.fault = Some(err.to_string());
            Err(err)
        }
    }

    /// `HOME`: homes every axis; returns when homing has ended.
    pub fn home(&mut self) -> Result<()> {
        self.done("HOME")
    }

    /// `CON`: servo control on.
    pub fn con(&mut self) -> Result<()> {
        self.done("CON")
    }

    /// `COFF`: servo control off.
    pub fn coff(&mut self) -> Result<()> {
        self.done("COFF")
    }

    /// `SPEED n`, n = 1…100 \[% of the maximum speed\].
    pub fn speed(&mut self, percent: u32) -> Result<()> {
        if !(1..=100).contains(&percent) {
            return Err(Error::out_of_range("speed", percent.into(), "1…100 (% of the maximum speed)"));
        }
        self.done(&format!("SPEED {percent}"))
    }

    /// `DEFP p`: defines a position.
    pub fn defp(&mut self, position: &str) -> Result<()> {
        check_name(position, false)?;
        self.done(&format!("DEFP {position}"))
    }

    /// `DIMP v[n]`: defines a vector of `len` positions `v[1]`…`v[len]`.
    pub fn dimp(&mut self, vector: &str, len: usize) -> Result<()> {
        check_name(vector, false)?;
        if len == 0 {
            return Err(Error::too_few("vector length", 0, 1, "positions"));
        }
        self.done(&format!("DIMP {vector}[{len}]"))
    }

    /// `HERE p`: records the arm's current counts into `position`.
    pub fn here(&mut self, position: &str) -> Result<()> {
        check_name(position, true)?;
        self.done(&format!("HERE {position}"))
    }

    /// `SETPV p axis counts`: one axis (1–5) of a joint position.
    pub fn setpv(&mut self, position: &str, axis: usize, counts: i64) -> Result<()> {
        check_name(position, true)?;
        if !(1..=5).contains(&axis) {
            return Err(Error::out_of_range("axis", axis as f64, "1…5 (the Scorbot's axes)"));
        }
        self.done(&format!("SETPV {position} {axis} {counts}"))
    }

    /// All five axes of a joint position (five `SETPV`s).
    pub fn set_joint_position(&mut self, position: &str, counts: [i64; 5]) -> Result<()> {
        for (i, c) in counts.iter().enumerate() {
            self.setpv(position, i + 1, *c)?;
        }
        Ok(())
    }

    /// `SETPVC p axis value`: one Cartesian coordinate \[0.1 mm or 0.1°\].
    pub fn setpvc(&mut self, position: &str, axis: CartesianAxis, value: i64) -> Result<()> {
        check_name(position, true)?;
        self.done(&format!("SETPVC {position} {axis:?} {value}"))
    }

    /// `LISTPV p`: the position's counts and, when printed, its Cartesian
    /// coordinates.
    pub fn listpv(&mut self, position: &str) -> Result<PositionReadout> {
        check_name(position, true)?;
        let line = format!("LISTPV {position}");
        let reply = self.command(&line)?;
        parse_listpv(&reply).inspect_err(|e| self.fault = Some(e.to_string()))
    }

    /// `LISTP`: the names of the defined positions (every page).
    pub fn list_positions(&mut self) -> Result<Vec<String>> {
        let reply = self.command("LISTP")?;
        Ok(reply.lines.into_iter().map(|l| l.trim().to_string()).filter(|l| !l.is_empty()).collect())
    }

    /// `MOVE p [t]`: starts a joint-interpolated move and returns at once.
    /// `time` in hundredths of a second.
    pub fn move_to(&mut self, position: &str, time: Option<u32>) -> Result<()> {
        check_name(position, true)?;
        self.done(&with_time(format!("MOVE {position}"), time))
    }

    /// `MOVED p [t]`: moves and returns when the motion has ended.
    pub fn move_d(&mut self, position: &str, time: Option<u32>) -> Result<()> {
        check_name(position, true)?;
        self.done(&with_time(format!("MOVED {position}"), time))
    }

    /// `MOVES v first last [t]`: a smooth move through `v[first]`…`v[last]`;
    /// returns when it has ended.
    pub fn moves(&mut self, vector: &str, first: usize, last: usize, time: Option<u32>) -> Result<()> {
        check_name(vector, false)?;
        if first == 0 || last < first {
            return Err(Error::DoesNotFit {
                what: "vector range".into(),
                reason: format!("{first}…{last}; need 1 ≤ first ≤ last"),
            });
        }
        self.done(&with_time(format!("MOVES {vector} {first} {last}"), time))
    }

    /// `OPEN`: opens the gripper.
    pub fn open(&mut self) -> Result<()> {
        self.done("OPEN")
    }

    /// `CLOSE`: closes the gripper.
    pub fn close(&mut self) -> Result<()> {
        self.done("CLOSE")
    }

    /// `A`: aborts any motion. Allowed while faulted; reads until its own
    /// echo and prompt, discarding what a pending motion command printed.
    /// Does not clear the fault.
    pub fn abort(&mut self) -> Result<()> {
        let fault = self.fault.clone();
        let r = self.exchange("A", false, true).and_then(|reply| {
            // Controller-A answers an abort with `Done.`; anything else is not an abort.
            match reply.lines.iter().map(|l| l.trim()).filter(|l| !l.is_empty()).collect::<Vec<_>>()[..] {
                [] | ["Done."] => Ok(()),
                _ => Err(Error::Protocol { command: "A".into(), message: "expected `Done.`".into(), raw: reply.raw }),
            }
        });
        // An abort never clears (nor, by itself, sets) the fault state… unless it fails.
        self.fault = match &r {
            Ok(_) => fault,
            Err(e) => Some(e.to_string()),
        };
        r
    }

    /// `CLRBUF`: clears queued motions.
    pub fn clrbuf(&mut self) -> Result<()> {
        self.done("CLRBUF")
    }
}

fn with_time(mut line: String, time: Option<u32>) -> String {
    if let Some(t) = time {
        line.push_str(&format!(" {t}"));
    }
    line
}

/// Position names: letters, digits and `_`; with `indexed`, also `v[n]`.
fn check_name(name: &str, indexed: bool) -> Result<()> {
    let (base, index) = match name.split_once('[') {
        Some((b, rest)) if indexed => (b, Some(rest)),
        _ => (name, None),
    };
    let ok_base = !base.is_empty()
        && base.len() <= 16
        && base.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && base.chars().next().is_some_and(|c| c.is_ascii_alphabetic());
    let ok_index = index.is_none_or(|r| r.strip_suffix(']').is_some_and(|n| n.parse::<u32>().is_ok_and(|n| n >= 1)));
    if ok_base && ok_index {
        Ok(())
    } else {
        Err(Error::Malformed {
            what: "position name".into(),
            text: name.into(),
            expected: format!(
                "names are a letter then letters, digits or _ (at most 16){}",
                if indexed { ", optionally indexed as NAME[n] with n ≥ 1" } else { "" }
            ),
        })
    }
}

/// Parses `LISTPV`'s lines: `k:value` pairs, 1–5 for counts and X Y Z P R.
fn parse_listpv(reply: &Reply) -> Result<PositionReadout> {
    let mut counts = [None; 5];
    let mut cart = [None; 5];
    let bad = |message: String| Error::Protocol { command: reply.command.clone(), message, raw: reply.raw.clone() };
    for line in &reply.lines {
        // Pairs `k:value`, with any spacing after the colon (`1:100`, `1: 100`,
        // `1:   100` when a controller right-aligns its columns).
        let mut tokens = line.split_whitespace();
        while let Some(tok) = tokens.next() {
            let Some((k, v)) = tok.split_once(':') else { continue };
            let slot = match k.to_ascii_uppercase().as_str() {
                "1" => &mut counts[0],
                "2" => &mut counts[1],
                "3" => &mut counts[2],
                "4" => &mut counts[3],
                "5" => &mut counts[4],
                "X" => &mut cart[0],
                "Y" => &mut cart[1],
                "Z" => &mut cart[2],
                "P" => &mut cart[3],
                "R" => &mut cart[4],
                _ => continue,
            };
            let v = if v.is_empty() { tokens.next().unwrap_or("") } else { v };
            *slot = Some(v.parse::<i64>().map_err(|_| bad(format!("`{k}:{v}` is not an integer coordinate")))?);
        }
    }
    let Some(counts) = collect(counts) else {
        return Err(bad("expected the counts of axes 1–5 as `1:c1 … 5:c5`".into()));
    };
    Ok(PositionReadout { counts, cartesian: collect(cart) })
}

fn collect(v: [Option<i64>; 5]) -> Option<[i64; 5]> {
    let mut out = [0; 5];
    for i in 0..5 {
        out[i] = v[i]?;
    }
    Some(out)
}

fn io_error(e: io::Error, doing: &str) -> Error {
    match e.kind() {
        io::ErrorKind::BrokenPipe
        | io::ErrorKind::ConnectionReset
        | io::ErrorKind::ConnectionAborted
        | io::ErrorKind::UnexpectedEof => Error::Disconnected { during: doing.into() },
        // A pseudo-terminal whose other side closed reads EIO.
        _ if e.raw_os_error() == Some(5) => Error::Disconnected { during: doing.into() },
        _ => Error::io(format!("controller link: {doing}"), e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::VecDeque;
    use std::sync::{Arc, Mutex};

    /// A scripted link: each write of a command line pops the next canned
    /// answer into the read queue.
    struct Script {
        answers: VecDeque<Vec<u8>>,
        inbox: VecDeque<u8>,
        sent: Arc<Mutex<Vec<String>>>,
        closed: bool,
    }

    impl Read for Script {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            if self.inbox.is_empty() {
                if self.closed {
                    return Ok(0);
                }
                return Err(io::Error::new(io::ErrorKind::TimedOut, "nothing"));
            }
            let n = buf.len().min(self.inbox.len()).min(7); // arrive in small pieces
            for b in buf.iter_mut().take(n) {
                *b = self.inbox.pop_front().unwrap();
            }
            Ok(n)
        }
    }

    impl Write for Script {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            self.sent.lock().unwrap().push(String::from_utf8_lossy(buf).into_owned());
            if let Some(a) = self.answers.pop_front() {
                self.inbox.extend(a);
            }
            Ok(buf.len())
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    impl Link for Script {
        fn set_timeout(&mut self, _: Duration) -> io::Result<()> {
            Ok(())
        }
    }

    fn client(answers: &[&str]) -> (Client, Arc<Mutex<Vec<String>>>) {
        let sent = Arc::new(Mutex::new(Vec::new()));
        let s = Script {
            answers: answers.iter().map(|a| a.as_bytes().to_vec()).collect(),
            inbox: VecDeque::new(),
            sent: sent.clone(),
            closed: false,
        };
        let mut c = Client::new(Box::new(s));
        c.reply_timeout = Duration::from_millis(50);
        c.motion_timeout = Duration::from_millis(50);
        (c, sent)
    }

    #[test]
    fn parses_echo_lines_and_prompt_in_pieces() {
        let (mut c, sent) = client(&[
            "LISTPV P1\r\nPosition P1\r\n 1:0  2:-3437  3: 2867 4:738 5:-738\r\n X:1691 Y:0 Z:5044 P:-636 R:0\r\n>",
        ]);
        let r = c.listpv("P1").unwrap();
        assert_eq!(r.counts, [0, -3437, 2867, 738, -738]);
        assert_eq!(r.cartesian, Some([1691, 0, 5044, -636, 0]));
        // Right-aligned columns.
        let (mut c, _) = client(&["LISTPV P1\r\nPosition P1\r\n 1:     0  2: -3437  3:   2867 4:738 5:  -738\r\n>"]);
        let r = c.listpv("P1").unwrap();
        assert_eq!(r.counts, [0, -3437, 2867, 738, -738]);
        assert_eq!(r.cartesian, None);
        assert_eq!(sent.lock().unwrap()[0], "LISTPV P1\r");
    }

    #[test]
    fn controller_errors_fault_the_client_until_cleared() {
        let (mut c, sent) = client(&[
            "MOVED P9\r\n*** POSITION P9 NOT DEFINED\r\n>",
            "LISTPV P1\r\nPosition P1\r\n 1:1 2:2 3:3 4:4 5:5\r\n>",
            "MOVED P1\r\nDone.\r\n>",
        ]);
        let e = c.move_d("P9", None).unwrap_err();
        assert!(matches!(&e, Error::Controller { message, .. } if message.contains("NOT DEFINED")), "{e}");
        // Motion is blocked, and nothing is sent for it.
        assert!(matches!(c.move_d("P1", None), Err(Error::Faulted { .. })));
        assert_eq!(sent.lock().unwrap().len(), 1);
        // Inspection still works.
        assert_eq!(c.listpv("P1").unwrap().counts, [1, 2, 3, 4, 5]);
        c.clear_fault();
        c.move_d("P1", None).unwrap();
    }

    #[test]
    fn timeouts_wrong_echoes_and_missing_done_are_typed_errors() {
        let (mut c, _) = client(&["HOM"]);
        let e = c.home().unwrap_err();
        assert!(matches!(&e, Error::Timeout { received, .. } if received == "HOM"), "{e}");
        let (mut c, _) = client(&["XQ#@!\r\nDone.\r\n>"]);
        assert!(matches!(c.con(), Err(Error::Protocol { .. })));
        let (mut c, _) = client(&["CON\r\nqz%&\r\n>"]);
        let e = c.con().unwrap_err();
        assert!(matches!(&e, Error::Protocol { raw, .. } if raw.contains("qz%&")), "{e}");
        let (mut c, _) = client(&["LISTPV A\r\nPosition A\r\n 1:0 2:x\r\n>"]);
        assert!(c.listpv("A").unwrap_err().to_string().contains("`2:x`"));
        // A motion command must say `Done.`; a setting may say nothing.
        let (mut c, _) = client(&["MOVED P\r\n>"]);
        assert!(matches!(c.move_d("P", None), Err(Error::Protocol { .. })));
        let (mut c, _) = client(&["SPEED 20\r\n>", "HOME\r\nHOMING...\r\nDone.\r\n>"]);
        c.speed(20).unwrap();
        c.home().unwrap();
    }

    #[test]
    fn endless_paging_is_cut_off() {
        let page = "X\r\nType <cr> to continue\r\n";
        let mut answers = vec![format!("LISTP\r\n{page}")];
        answers.extend(std::iter::repeat_n(page.to_string(), MAX_PAGES + 1));
        let refs: Vec<&str> = answers.iter().map(String::as_str).collect();
        let (mut c, _) = client(&refs);
        let e = c.list_positions().unwrap_err();
        assert!(e.to_string().contains("pages"), "{e}");
    }

    #[test]
    fn paged_listings_are_continued() {
        let (mut c, sent) = client(&["LISTP\r\nA\r\nB\r\nType <cr> to continue\r\n", "C\r\n>"]);
        assert_eq!(c.list_positions().unwrap(), ["A", "B", "C"]);
        assert_eq!(sent.lock().unwrap()[1], "\r");
        // Without a line end after the page prompt.
        let (mut c, _) = client(&["LISTP\r\nA\r\nType <cr> to continue", "\r\nC\r\n>"]);
        assert_eq!(c.list_positions().unwrap(), ["A", "C"]);
    }

    #[test]
    fn a_closed_link_is_a_disconnection() {
        let sent = Arc::new(Mutex::new(Vec::new()));
        let s = Script { answers: VecDeque::new(), inbox: VecDeque::new(), sent, closed: true };
        let mut c = Client::new(Box::new(s));
        assert!(matches!(c.home(), Err(Error::Disconnected { .. })));
        assert!(matches!(c.home(), Err(Error::Faulted { .. })));
    }

    #[test]
    fn bad_arguments_are_refused_before_sending() {
        let (mut c, sent) = client(&[]);
        assert!(c.speed(0).is_err());
        assert!(c.defp("1abc").is_err());
        assert!(c.defp("P[1]").is_err());
        assert!(c.setpv("P", 6, 0).is_err());
        assert!(c.moves("V", 3, 2, None).is_err());
        assert!(c.command("MOVE A\rMOVE B").is_err());
        assert!(sent.lock().unwrap().is_empty());
        assert!(c.fault().is_none());
    }

    /// A controller that never stops talking: after `echo` (if any), the
    /// same line over and over, as fast as it is read.
    struct Flood {
        echo: Vec<u8>,
        line: &'static [u8],
        at: usize,
        started: bool,
        /// Floods before the command is sent, too.
        before: bool,
    }

    impl Read for Flood {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            if !self.started && !self.before {
                return Err(io::Error::new(io::ErrorKind::TimedOut, "nothing yet"));
            }
            if self.started && !self.echo.is_empty() {
                let n = buf.len().min(self.echo.len());
                buf[..n].copy_from_slice(&self.echo[..n]);
                self.echo.drain(..n);
                return Ok(n);
            }
            self.fill(buf)
        }
    }

    impl Flood {
        fn fill(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            for b in buf.iter_mut() {
                *b = self.line[self.at % self.line.len()];
                self.at += 1;
            }
            Ok(buf.len())
        }
    }

    impl Write for Flood {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            self.started = true;
            Ok(buf.len())
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    impl Link for Flood {
        fn set_timeout(&mut self, _: Duration) -> io::Result<()> {
            Ok(())
        }
    }

    fn flooded(echo: &str, line: &'static [u8], before: bool) -> Client {
        let link = Flood { echo: echo.as_bytes().to_vec(), line, at: 0, started: false, before };
        let mut c = Client::new(Box::new(link));
        c.reply_timeout = Duration::from_millis(200);
        c.motion_timeout = Duration::from_millis(200);
        c
    }

    #[test]
    fn a_flooding_controller_is_cut_off_quickly_with_a_short_message() {
        // After the echo: lines, a line without end, endless page prompts.
        for line in [&b"POSITION 1\r\n"[..], b"xxxxxxxxxxxxxxxx", b"Type <cr> to continue\r\n"] {
            let mut c = flooded("LISTP\r\n", line, false);
            let started = Instant::now();
            let e = c.list_positions().unwrap_err();
            assert!(started.elapsed() < Duration::from_secs(5), "{:?}", started.elapsed());
            let msg = e.to_string();
            assert!(msg.len() < 2 * crate::error::EXCERPT_CHARS + 300, "{} bytes: {}", msg.len(), &msg[..300]);
            assert!(matches!(e, Error::Protocol { .. } | Error::Timeout { .. }), "{msg}");
        }
        // Before the command is even sent.
        let mut c = flooded("", b"noise\r\n", true);
        let started = Instant::now();
        let e = c.con().unwrap_err();
        assert!(started.elapsed() < Duration::from_secs(5));
        assert!(e.to_string().contains("kept sending unasked"), "{e}");
    }

    #[test]
    fn an_abort_must_be_answered_with_done() {
        let (mut c, _) = client(&["A\r\nDone.\r\n>"]);
        c.abort().unwrap();
        let (mut c, _) = client(&["A\r\n#$%&garble\r\n>"]);
        let e = c.abort().unwrap_err();
        assert!(matches!(&e, Error::Protocol { .. }), "{e}");
        assert!(c.fault().is_some());
    }
}
