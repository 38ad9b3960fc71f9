//! The simulated controller as a state machine with explicit time (see the
//! parent module for the behaviour and the choices beyond the README).

mod commands;
mod motion;
mod positions;
mod record;
mod terminal;

use std::collections::{BTreeMap, HashMap, VecDeque};
use std::path::PathBuf;
use std::time::Duration;

use kinema::ik::scorbot::ScorbotIk;
use kinema::Robot;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::encoder::{Constants, MOTORS};
use crate::error::{Error, Result};

use self::motion::{dur, round_counts, secs, Active, Item};
use self::positions::Coords;
use self::terminal::{Line, Mode};
use super::{SimConfig, COMMANDS};

/// Longest command line the controller takes \[bytes\]; a longer one is
/// answered with `*** LINE TOO LONG`.
pub const MAX_LINE: usize = 256;

/// Most lines kept while a motion command waits (further lines are lost, as
/// in a full type-ahead buffer).
pub const MAX_TYPE_AHEAD: usize = 64;

/// How far beyond a joint limit a target may lie and still be accepted
/// \[rad\] (0.057°, about one count of the wrist motors).
pub const LIMIT_TOLERANCE: f64 = 1e-3;

/// Most samples recorded for one motion; a longer motion is sampled more
/// coarsely so a slow move cannot stall the controller or flood the disk.
pub const MAX_SAMPLES_PER_MOTION: usize = 20_000;

/// Most samples recorded in a session (about 60 MB of CSV); later motions are
/// not recorded and [`Controller::take_record_error`] reports it once.
pub const MAX_SAMPLES: usize = 1_000_000;
/// Largest accepted time scale.
const MAX_TIME_SCALE: f64 = 1e6;

/// The simulated Controller-A: a state machine with explicit time.
///
/// Times are [`Duration`]s since an arbitrary epoch chosen by the caller and
/// must not go backwards (an earlier time is taken as the latest one seen).
/// Typical use by a transport: on every read call [`Controller::feed`] with
/// the bytes; on every timeout [`Controller::advance`]; after either, send
/// [`Controller::take_output`] and close the connection if
/// [`Controller::wants_disconnect`], then call [`Controller::connection_lost`].
/// [`Controller::next_deadline`] tells when something will happen next.
///
/// # Examples
/// ```
/// use std::time::Duration;
/// use kinema_scorbot::sim::{Controller, SimConfig};
/// let mut c = Controller::new(SimConfig::default())?;
/// let t = Duration::from_secs(1);
/// c.feed(t, b"speed 20\r");
/// assert_eq!(c.take_output(t), b"speed 20\r\nDone.\r\n>");
/// c.feed(t, b"move p1\r");
/// assert_eq!(c.take_output(t), b"move p1\r\n*** HOME NOT DONE\r\n>");
/// assert_eq!(c.speed(), 20);
/// # Ok::<(), kinema_scorbot::Error>(())
/// ```
#[derive(Debug)]
pub struct Controller {
    robot: Robot,
    ik: ScorbotIk,
    constants: Constants,
    true_constants: Constants,
    time_scale: f64,
    faults: Vec<super::Fault>,
    record: Option<PathBuf>,
    noise: f64,
    noise_rng: ChaCha8Rng,
    garble_rng: ChaCha8Rng,

    clock: Duration,
    counts: [i64; MOTORS],
    homed: bool,
    control: bool,
    speed: u32,
    gripper_open: bool,
    points: BTreeMap<String, Coords>,
    vectors: BTreeMap<String, Vec<Coords>>,
    queue: VecDeque<Item>,
    active: Option<Active>,

    mode: Mode,
    line: Vec<u8>,
    line_too_long: bool,
    type_ahead: VecDeque<Line>,
    pumping: bool,
    out: VecDeque<(Duration, Vec<u8>)>,
    last_release: Duration,
    seen: HashMap<&'static str, usize>,
    disconnect: bool,

    samples: Vec<[f64; 3]>,
    record_full: bool,
    record_error: Option<Error>,
}

impl Controller {
    /// A controller at its home position (all counts 0) but not homed,
    /// control on, speed 50, gripper open, no positions.
    ///
    /// Errors: invalid constants, a time scale not finite and in (0, 10⁶], a
    /// noise not finite and ≥ 0, a fault on an unknown command or with
    /// `nth` = 0, or a record file that cannot be written (it is created at
    /// once with its header).
    pub fn new(config: SimConfig) -> Result<Controller> {
        config.constants.validate()?;
        config.true_constants.validate()?;
        if !(config.time_scale.is_finite() && config.time_scale > 0.0 && config.time_scale <= MAX_TIME_SCALE) {
            return Err(Error::out_of_range(
                "time scale",
                config.time_scale,
                format!("a finite number > 0 and ≤ {MAX_TIME_SCALE}"),
            ));
        }
        if !(config.noise.is_finite() && config.noise >= 0.0) {
            return Err(Error::out_of_range("noise", config.noise, "a finite distance ≥ 0 [m]"));
        }
        for f in &config.faults {
            if !COMMANDS.contains(&f.command.as_str()) || f.nth == 0 {
                return Err(Error::Malformed {
                    what: "fault".into(),
                    text: f.to_string(),
                    expected: format!("the command must be one of {} (uppercase) and nth ≥ 1", COMMANDS.join(", ")),
                });
            }
        }
        let robot = Robot::builtin("scorbot-er-v-plus")?;
        let ik = ScorbotIk::new(&robot)?;
        let mut c = Controller {
            robot,
            ik,
            constants: config.constants,
            true_constants: config.true_constants,
            time_scale: config.time_scale,
            faults: config.faults,
            record: config.record,
            noise: config.noise,
            noise_rng: ChaCha8Rng::seed_from_u64(config.seed),
            garble_rng: ChaCha8Rng::seed_from_u64(config.seed ^ 0x9e37_79b9_7f4a_7c15),
            clock: Duration::ZERO,
            counts: [0; MOTORS],
            homed: false,
            control: true,
            speed: 50,
            gripper_open: true,
            points: BTreeMap::new(),
            vectors: BTreeMap::new(),
            queue: VecDeque::new(),
            active: None,
            mode: Mode::Idle,
            line: Vec::new(),
            line_too_long: false,
            type_ahead: VecDeque::new(),
            pumping: false,
            out: VecDeque::new(),
            last_release: Duration::ZERO,
            seen: HashMap::new(),
            disconnect: false,
            samples: Vec::new(),
            record_full: false,
            record_error: None,
        };
        c.write_record();
        match c.record_error.take() {
            Some(e) => Err(e),
            None => Ok(c),
        }
    }

    // ----- inspection -------------------------------------------------------

    /// The arm's counts at the latest time seen (interpolated during a motion,
    /// rounded to whole counts).
    pub fn counts(&self) -> [i64; MOTORS] {
        match &self.active {
            Some(a) => round_counts(&a.at(secs(self.clock.saturating_sub(a.start)))),
            None => self.counts,
        }
    }

    /// Whether `HOME` has completed (and no later `HOME` was aborted).
    pub fn is_homed(&self) -> bool {
        self.homed
    }

    /// Whether a motion is running or queued.
    pub fn is_moving(&self) -> bool {
        self.active.is_some() || !self.queue.is_empty()
    }

    /// Whether servo control is on (`CON`/`COFF`).
    pub fn control_on(&self) -> bool {
        self.control
    }

    /// The speed setting \[% of maximum\].
    pub fn speed(&self) -> u32 {
        self.speed
    }

    /// Whether the gripper is open.
    pub fn gripper_open(&self) -> bool {
        self.gripper_open
    }

    /// The latest time seen.
    pub fn now(&self) -> Duration {
        self.clock
    }

    /// Whether the controller wants the connection closed (a
    /// [`FaultKind::Disconnect`](super::FaultKind::Disconnect)). Input is ignored until
    /// [`Controller::connection_lost`].
    pub fn wants_disconnect(&self) -> bool {
        self.disconnect
    }

    /// The physical tool positions recorded so far \[m\] (with noise), if a
    /// record file is configured.
    pub fn recorded(&self) -> &[[f64; 3]] {
        &self.samples
    }

    /// The first failure to write the record file since the last call.
    pub fn take_record_error(&mut self) -> Option<Error> {
        self.record_error.take()
    }

    /// The next time at which output is released or a motion event happens,
    /// if any is pending.
    pub fn next_deadline(&self) -> Option<Duration> {
        let mut next: Option<Duration> = self.out.front().map(|o| o.0);
        let mut consider = |t: Duration| next = Some(next.map_or(t, |n| n.min(t)));
        if let Some(a) = &self.active {
            let off = match a.disconnect_at {
                Some(d) if d <= a.end() => d,
                _ => a.end(),
            };
            consider(a.start + dur(off));
        } else if !self.queue.is_empty() {
            consider(self.clock);
        }
        next
    }

    // ----- time and bytes ---------------------------------------------------

    /// Takes received bytes at time `now`: advances to `now`, then runs the
    /// complete lines (ended by `\r`).
    pub fn feed(&mut self, now: Duration, bytes: &[u8]) {
        self.advance(now);
        let t = self.clock;
        for &b in bytes {
            if self.disconnect {
                break;
            }
            match b {
                b'\r' => {
                    let line = Line { bytes: std::mem::take(&mut self.line), too_long: self.line_too_long };
                    self.line_too_long = false;
                    self.on_line(t, line);
                }
                b'\n' => {}
                _ if self.line.len() < MAX_LINE => self.line.push(b),
                _ => self.line_too_long = true,
            }
        }
    }

    /// Moves simulated time on to `now`: motions end (or stop halfway for a
    /// disconnect fault) at their own times, and the commands typed ahead
    /// run when a waiting command ends.
    pub fn advance(&mut self, now: Duration) {
        let now = now.max(self.clock);
        loop {
            let Some(a) = &self.active else {
                match self.queue.pop_front() {
                    Some(item) => {
                        self.start(item, self.clock);
                        continue;
                    }
                    None => break,
                }
            };
            let (off, halt) = match a.disconnect_at {
                Some(d) if d <= a.end() => (d, true),
                _ => (a.end(), false),
            };
            let at = a.start + dur(off);
            if at > now {
                break;
            }
            self.clock = self.clock.max(at);
            if halt {
                self.halt(at, false);
                self.request_disconnect(at);
            } else {
                self.finish(at);
            }
        }
        self.clock = now;
    }

    /// The output released up to `now` (delayed replies stay until their time).
    pub fn take_output(&mut self, now: Duration) -> Vec<u8> {
        let mut bytes = Vec::new();
        while let Some((t, _)) = self.out.front() {
            if *t > now {
                break;
            }
            if let Some((_, b)) = self.out.pop_front() {
                bytes.extend_from_slice(&b);
            }
        }
        bytes
    }

    /// The connection has closed at `now` (by the host or after
    /// [`Controller::wants_disconnect`]): unsent output, a partial line, lines
    /// typed ahead and a paused listing are dropped; a command waiting for a
    /// motion will not answer, but the motion goes on. The controller's state
    /// (positions, counts, homing) stays.
    pub fn connection_lost(&mut self, now: Duration) {
        self.advance(now);
        self.line.clear();
        self.line_too_long = false;
        self.type_ahead.clear();
        self.out.clear();
        self.mode = Mode::Idle;
        if let Some(a) = &mut self.active {
            a.waiter = None;
            a.disconnect_at = None;
        }
        for item in &mut self.queue {
            item.waiter = None;
            item.disconnect = false;
        }
        self.disconnect = false;
    }
}
