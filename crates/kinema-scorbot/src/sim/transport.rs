//! The simulated controller behind a TCP listener or a pseudo-terminal.

use std::io::{self, Read, Write};
use std::net::{Shutdown, TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::{Controller, SimConfig};
use crate::error::{Error, Result};

/// Longest wait of one read, so `stop` is seen and motions end on time.
const POLL: Duration = Duration::from_millis(20);
/// Shortest wait of one read (no busy spinning).
const MIN_WAIT: Duration = Duration::from_millis(1);
/// How long a write to a TCP client may block before the client is dropped.
const WRITE_TIMEOUT: Duration = Duration::from_secs(2);

fn io_error(doing: &str, e: io::Error) -> Error {
    Error::io(format!("simulator: {doing}"), e)
}

fn is_timeout(e: &io::Error) -> bool {
    matches!(e.kind(), io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut | io::ErrorKind::Interrupted)
}

/// How long the next read may wait.
fn read_wait(ctl: &Controller, now: Duration) -> Duration {
    ctl.next_deadline().map_or(POLL, |d| d.saturating_sub(now)).clamp(MIN_WAIT, POLL)
}

/// Serves the simulated controller on `listener` until `stop` is set (it is
/// checked at least every 20 ms). One connection is served at a time; further
/// clients wait in the listener's backlog. The controller's state persists
/// across connections, like a real controller whose cable is replugged;
/// motions go on while no client is connected.
///
/// Errors: an invalid `config` (see [`Controller::new`]), a failing listener,
/// or a record file that cannot be written.
///
/// # Examples
/// ```
/// use std::io::{Read, Write};
/// use std::sync::{atomic::AtomicBool, Arc};
/// use kinema_scorbot::sim::{serve_tcp, SimConfig};
/// let listener = std::net::TcpListener::bind("127.0.0.1:0")?;
/// let addr = listener.local_addr()?;
/// let stop = Arc::new(AtomicBool::new(false));
/// let server = {
///     let stop = stop.clone();
///     std::thread::spawn(move || serve_tcp(listener, SimConfig::default(), stop))
/// };
/// let mut s = std::net::TcpStream::connect(addr)?;
/// s.write_all(b"CON\r")?;
/// let mut reply = Vec::new();
/// let mut buf = [0u8; 64];
/// while !reply.ends_with(b">") {
///     let n = s.read(&mut buf)?;
///     reply.extend_from_slice(&buf[..n]);
/// }
/// assert_eq!(reply, b"CON\r\nDone.\r\n>");
/// stop.store(true, std::sync::atomic::Ordering::Relaxed);
/// server.join().unwrap()?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn serve_tcp(listener: TcpListener, config: SimConfig, stop: Arc<AtomicBool>) -> Result<()> {
    let mut ctl = Controller::new(config)?;
    listener.set_nonblocking(true).map_err(|e| io_error("making the listener non-blocking", e))?;
    let epoch = Instant::now();
    while !stop.load(Ordering::Relaxed) {
        match listener.accept() {
            Ok((stream, _)) => serve_connection(&mut ctl, stream, epoch, &stop)?,
            Err(e) if is_timeout(&e) => {
                let now = epoch.elapsed();
                ctl.advance(now);
                // Nobody is listening: what the controller prints is lost.
                ctl.take_output(now);
                if let Some(e) = ctl.take_record_error() {
                    return Err(e);
                }
                std::thread::sleep(read_wait(&ctl, now));
            }
            Err(e) => return Err(io_error("accepting a connection", e)),
        }
    }
    Ok(())
}

/// Serves one TCP client until it leaves, a disconnect fault, or `stop`.
fn serve_connection(ctl: &mut Controller, mut stream: TcpStream, epoch: Instant, stop: &AtomicBool) -> Result<()> {
    let setup = stream
        .set_nonblocking(false)
        .and_then(|_| stream.set_nodelay(true))
        .and_then(|_| stream.set_write_timeout(Some(WRITE_TIMEOUT)));
    if setup.is_err() {
        // The client is already gone.
        ctl.connection_lost(epoch.elapsed());
        return Ok(());
    }
    let mut buf = [0u8; 1024];
    loop {
        if stop.load(Ordering::Relaxed) {
            let _ = stream.shutdown(Shutdown::Both);
            ctl.connection_lost(epoch.elapsed());
            return Ok(());
        }
        let now = epoch.elapsed();
        let mut gone = stream.set_read_timeout(Some(read_wait(ctl, now))).is_err();
        if !gone {
            match stream.read(&mut buf) {
                Ok(0) => gone = true,
                Ok(n) => ctl.feed(epoch.elapsed(), &buf[..n]),
                Err(e) if is_timeout(&e) => {}
                Err(_) => gone = true,
            }
        }
        let now = epoch.elapsed();
        ctl.advance(now);
        let out = ctl.take_output(now);
        if !gone && !out.is_empty() && stream.write_all(&out).and_then(|_| stream.flush()).is_err() {
            gone = true;
        }
        if let Some(e) = ctl.take_record_error() {
            let _ = stream.shutdown(Shutdown::Both);
            return Err(e);
        }
        if gone || ctl.wants_disconnect() {
            let _ = stream.shutdown(Shutdown::Both);
            ctl.connection_lost(epoch.elapsed());
            return Ok(());
        }
    }
}

/// The simulated controller behind a pseudo-terminal pair: a client opens
/// [`PtySim::path`] like the controller's serial port.
///
/// The slave side stays open inside `PtySim` (in raw mode: no echo by the
/// line discipline, no CR/LF translation), so clients may close and reopen the
/// path without the simulator seeing an end of file. Output the simulator
/// writes while no client has the path open waits in the terminal's buffer
/// for the next client, as on a real serial line's receiver; a client should
/// discard stale input after opening.
///
/// # Examples
/// ```no_run
/// use std::sync::{atomic::AtomicBool, Arc};
/// use kinema_scorbot::sim::{PtySim, SimConfig};
/// let sim = PtySim::open(SimConfig::default())?;
/// println!("controller on {}", sim.path());
/// let stop = Arc::new(AtomicBool::new(false));
/// sim.run(stop)?; // until `stop` is set
/// # Ok::<(), kinema_scorbot::Error>(())
/// ```
#[cfg(unix)]
pub struct PtySim {
    controller: Controller,
    master: serialport::TTYPort,
    /// Held open so the master never reads EIO between clients.
    _slave: serialport::TTYPort,
    path: String,
}

#[cfg(unix)]
impl std::fmt::Debug for PtySim {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PtySim").field("path", &self.path).finish_non_exhaustive()
    }
}

#[cfg(unix)]
impl PtySim {
    /// Opens a pseudo-terminal pair for a new controller.
    ///
    /// Errors: an invalid `config` (see [`Controller::new`]); no
    /// pseudo-terminal available ([`Error::Io`]).
    pub fn open(config: SimConfig) -> Result<PtySim> {
        let controller = Controller::new(config)?;
        let (master, slave) = serialport::TTYPort::pair()
            .map_err(|e| Error::io("simulator: cannot open a pseudo-terminal pair", e.into()))?;
        let path = serialport::SerialPort::name(&slave).ok_or_else(|| {
            Error::io("simulator", io::Error::new(io::ErrorKind::NotFound, "the pseudo-terminal has no path"))
        })?;
        Ok(PtySim { controller, master, _slave: slave, path })
    }

    /// The device path a client opens (e.g. `/dev/pts/3`), at any baud rate
    /// (`serialport::new(path, 9600)`).
    pub fn path(&self) -> String {
        self.path.clone()
    }

    /// Serves the controller until `stop` is set (checked at least every
    /// 20 ms) or a [`super::FaultKind::Disconnect`] fault closes the
    /// pseudo-terminal (then `Ok(())`; the path disappears).
    ///
    /// Errors: the pseudo-terminal fails, or the record file cannot be
    /// written.
    pub fn run(mut self, stop: Arc<AtomicBool>) -> Result<()> {
        use serialport::SerialPort;
        let epoch = Instant::now();
        let ctl = &mut self.controller;
        let mut buf = [0u8; 1024];
        while !stop.load(Ordering::Relaxed) {
            let now = epoch.elapsed();
            self.master
                .set_timeout(read_wait(ctl, now))
                .map_err(|e| Error::io("simulator: setting the pty timeout", e.into()))?;
            match self.master.read(&mut buf) {
                Ok(0) => std::thread::sleep(MIN_WAIT),
                Ok(n) => ctl.feed(epoch.elapsed(), &buf[..n]),
                Err(e) if is_timeout(&e) => {}
                Err(e) => return Err(io_error("reading the pseudo-terminal", e)),
            }
            let now = epoch.elapsed();
            ctl.advance(now);
            let out = ctl.take_output(now);
            if !out.is_empty() {
                match self.master.write_all(&out) {
                    Ok(()) => {}
                    // Nobody reads and the terminal's buffer is full: the bytes are lost.
                    Err(e) if is_timeout(&e) => {}
                    Err(e) => return Err(io_error("writing the pseudo-terminal", e)),
                }
            }
            if let Some(e) = ctl.take_record_error() {
                return Err(e);
            }
            if ctl.wants_disconnect() {
                return Ok(());
            }
        }
        Ok(())
    }
}
