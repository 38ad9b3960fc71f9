//! The simulated controller as a state machine with explicit time (see the
//! parent module for the behaviour and the choices beyond the README).

use std::collections::{BTreeMap, HashMap, VecDeque};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Duration;

use kinema::ik::scorbot::ScorbotIk;
use kinema::Robot;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{FaultKind, SimConfig, COMMANDS, MOTION_COMMANDS};
use crate::encoder::{Constants, MOTORS};
use crate::error::{Error, Result};

/// Longest command line the controller takes \[bytes\]; a longer one is
/// answered with `*** LINE TOO LONG`.
pub const MAX_LINE: usize = 256;

/// Most lines kept while a motion command waits (further lines are lost, as
/// in a full type-ahead buffer).
pub const MAX_TYPE_AHEAD: usize = 64;

/// How far beyond a joint limit a target may lie and still be accepted
/// \[rad\] (0.057°, about one count of the wrist motors).
pub const LIMIT_TOLERANCE: f64 = 1e-3;

/// Lines of a listing before `Type <cr> to continue`.
const PAGE: usize = 20;
/// The line that pauses a listing.
const PAGER: &str = "Type <cr> to continue";
/// Most queued motions.
const MAX_QUEUE: usize = 1000;
/// Most stored positions (scalars plus vector elements).
const MAX_POSITIONS: usize = 10_000;
/// Longest vector.
const MAX_VECTOR: usize = 1000;
/// Longest name of a position or vector \[characters\].
const MAX_NAME: usize = 16;
/// Largest |counts| or |coordinate| accepted in `SETPV`/`SETPVC`.
const MAX_VALUE: i64 = 1_000_000_000;
/// Longest motion time argument \[0.01 s\] (one hour).
const MAX_TIME_ARG: i64 = 360_000;
/// Maximum motor speeds at `SPEED 100` \[deg/s\] **\[assumed\]**.
const MOTOR_SPEED: [f64; MOTORS] = [90.0, 90.0, 90.0, 180.0, 180.0];
/// Nominal duration of `HOME` \[s\] **\[assumed\]**.
const HOME_SECONDS: f64 = 5.0;
/// Nominal duration of `OPEN`/`CLOSE` \[s\] **\[assumed\]**.
const GRIPPER_SECONDS: f64 = 0.5;
/// Sampling period of the recorded tool position \[s of nominal time\].
const SAMPLE_PERIOD: f64 = 0.01;

/// Most samples recorded for one motion; a longer motion is sampled more
/// coarsely so a slow move cannot stall the controller or flood the disk.
pub const MAX_SAMPLES_PER_MOTION: usize = 20_000;

/// Most samples recorded in a session (about 60 MB of CSV); later motions are
/// not recorded and [`Controller::take_record_error`] reports it once.
pub const MAX_SAMPLES: usize = 1_000_000;
/// Largest accepted time scale.
const MAX_TIME_SCALE: f64 = 1e6;

/// What a stored position holds.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Coords {
    /// Defined (`DEFP`, `DIMP`) but never given coordinates.
    None,
    /// Encoder counts of motors 1–5.
    Joint([i64; MOTORS]),
    /// X, Y, Z \[0.1 mm\], P, R \[0.1°\].
    Cartesian([i64; MOTORS]),
}

/// A position reference: `P1` or `V[3]` (names uppercase).
#[derive(Debug, Clone, PartialEq)]
enum PosRef {
    Point(String),
    Element(String, usize),
}

impl PosRef {
    fn label(&self) -> String {
        match self {
            PosRef::Point(n) => n.clone(),
            PosRef::Element(v, i) => format!("{v}[{i}]"),
        }
    }
}

/// How the faults hitting one command change its output.
#[derive(Debug, Clone, Copy, Default)]
struct Ctx {
    delay: Duration,
    garble: bool,
    disconnect: bool,
}

/// A received line.
#[derive(Debug, Clone)]
struct Line {
    bytes: Vec<u8>,
    too_long: bool,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum MotionKind {
    Arm,
    Home,
    Gripper { open: bool },
}

/// A queued motion.
#[derive(Debug, Clone)]
struct Item {
    kind: MotionKind,
    /// Arm targets in order (counts).
    targets: Vec<[i64; MOTORS]>,
    /// Total time given with the command \[s, nominal\].
    time: Option<f64>,
    /// The waiting command's output context, if a command waits for it.
    waiter: Option<Ctx>,
    /// Close the connection halfway through.
    disconnect: bool,
}

/// The running motion: a piecewise-linear path of counts in time.
#[derive(Debug, Clone)]
struct Active {
    kind: MotionKind,
    start: Duration,
    /// (offset from `start` \[s, simulated\], counts).
    knots: Vec<(f64, [f64; MOTORS])>,
    waiter: Option<Ctx>,
    /// Offset \[s, simulated\] at which the connection is closed.
    disconnect_at: Option<f64>,
}

impl Active {
    fn end(&self) -> f64 {
        self.knots.last().map_or(0.0, |k| k.0)
    }

    fn at(&self, offset: f64) -> [f64; MOTORS] {
        let first = self.knots.first().map_or([0.0; MOTORS], |k| k.1);
        if offset <= 0.0 {
            return first;
        }
        for w in self.knots.windows(2) {
            let ((t0, a), (t1, b)) = (w[0], w[1]);
            if offset <= t1 {
                let s = if t1 > t0 { ((offset - t0) / (t1 - t0)).clamp(0.0, 1.0) } else { 1.0 };
                return std::array::from_fn(|i| a[i] + s * (b[i] - a[i]));
            }
        }
        self.knots.last().map_or(first, |k| k.1)
    }
}

/// What the command interpreter is doing.
#[derive(Debug, Clone)]
enum Mode {
    /// The prompt has been printed.
    Idle,
    /// A command waits for the end of its motion.
    Waiting,
    /// A listing waits for `\r`.
    Paging { rest: VecDeque<String>, ctx: Ctx },
}

/// The result of running one command.
enum Outcome {
    /// Reply lines, then the prompt.
    Lines(Vec<String>),
    /// An error line (`***`), then the prompt.
    Refused(String),
    /// These lines now; the rest when the queued motion ends.
    Wait(Vec<String>),
    /// A listing, paged.
    Listing(Vec<String>),
}

type Reply = std::result::Result<Outcome, String>;

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
    /// [`FaultKind::Disconnect`]). Input is ignored until
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

    // ----- line discipline --------------------------------------------------

    fn on_line(&mut self, t: Duration, line: Line) {
        if matches!(self.mode, Mode::Waiting) && is_abort(&line) {
            self.execute(t, line);
        } else if is_abort(&line) && matches!(self.mode, Mode::Paging { .. }) {
            // An abort ends a paused listing (with its prompt), then runs.
            if let Mode::Paging { ctx, .. } = std::mem::replace(&mut self.mode, Mode::Idle) {
                self.emit_prompt(t, ctx);
            }
            self.execute(t, line);
        } else if self.type_ahead.len() < MAX_TYPE_AHEAD {
            self.type_ahead.push_back(line);
        }
        self.pump(t);
        // A motion of zero duration ends at once.
        self.advance(t);
    }

    /// Runs the lines typed ahead while the interpreter is not waiting.
    fn pump(&mut self, t: Duration) {
        if self.pumping {
            return;
        }
        self.pumping = true;
        while !self.disconnect && !matches!(self.mode, Mode::Waiting) {
            let Some(line) = self.type_ahead.pop_front() else { break };
            if matches!(self.mode, Mode::Paging { .. }) {
                self.next_page(t);
            } else {
                self.execute(t, line);
            }
        }
        self.pumping = false;
    }

    fn execute(&mut self, t: Duration, line: Line) {
        let ctx0 = Ctx::default();
        if line.too_long {
            self.emit_echo(t, ctx0, &line.bytes);
            self.emit_line(t, ctx0, "*** LINE TOO LONG");
            self.emit_prompt(t, ctx0);
            return;
        }
        let text = String::from_utf8_lossy(&line.bytes).into_owned();
        let tokens: Vec<&str> = text.split_ascii_whitespace().collect();
        let keyword = tokens.first().map(|k| k.to_ascii_uppercase()).unwrap_or_default();
        let known = COMMANDS.iter().copied().find(|c| *c == keyword);
        let mut ctx = Ctx::default();
        let mut dropped = false;
        if let Some(k) = known {
            let n = self.seen.entry(k).or_insert(0);
            *n += 1;
            let n = *n;
            for f in self.faults.iter().filter(|f| f.command == k && f.nth == n) {
                match f.kind {
                    FaultKind::Drop => dropped = true,
                    FaultKind::Garble => ctx.garble = true,
                    FaultKind::Delay(d) => ctx.delay += d,
                    FaultKind::Disconnect => ctx.disconnect = true,
                }
            }
        }
        if dropped {
            return;
        }
        let motion = known.is_some_and(|k| MOTION_COMMANDS.contains(&k));
        if ctx.disconnect && !motion {
            self.request_disconnect(t);
            return;
        }
        if keyword == "A" && tokens.len() == 1 {
            // The interrupted command answers first, then the abort.
            self.halt(t, true);
        }
        let mark = self.out.len();
        self.emit_echo(t, ctx, &line.bytes);
        let args = &tokens[tokens.len().min(1)..];
        match self.run(t, &keyword, args, ctx) {
            Ok(Outcome::Lines(lines)) => {
                for l in &lines {
                    self.emit_line(t, ctx, l);
                }
                self.emit_prompt(t, ctx);
            }
            Ok(Outcome::Refused(e)) | Err(e) => {
                if ctx.disconnect {
                    // A refused motion command under a disconnect fault: the
                    // cable goes at once.
                    self.out.truncate(mark);
                    self.request_disconnect(t);
                    return;
                }
                self.emit_line(t, ctx, &e);
                self.emit_prompt(t, ctx);
            }
            Ok(Outcome::Wait(lines)) => {
                for l in &lines {
                    self.emit_line(t, ctx, l);
                }
                self.mode = Mode::Waiting;
            }
            Ok(Outcome::Listing(lines)) => {
                self.mode = Mode::Paging { rest: lines.into(), ctx };
                self.next_page(t);
            }
        }
    }

    fn next_page(&mut self, t: Duration) {
        let Mode::Paging { rest, ctx } = &mut self.mode else { return };
        let ctx = *ctx;
        let n = rest.len().min(PAGE);
        let page: Vec<String> = rest.drain(..n).collect();
        let more = !rest.is_empty();
        for l in &page {
            self.emit_line(t, ctx, l);
        }
        if more {
            self.emit_raw(t, ctx, format!("{PAGER}\r\n").into_bytes());
        } else {
            self.mode = Mode::Idle;
            self.emit_prompt(t, ctx);
        }
    }

    // ----- output -----------------------------------------------------------

    fn emit_raw(&mut self, t: Duration, ctx: Ctx, bytes: Vec<u8>) {
        let release = (t + ctx.delay).max(self.last_release);
        self.last_release = release;
        match self.out.back_mut() {
            Some((r, b)) if *r == release => b.extend_from_slice(&bytes),
            _ => self.out.push_back((release, bytes)),
        }
    }

    fn emit_echo(&mut self, t: Duration, ctx: Ctx, line: &[u8]) {
        let mut b = line.to_vec();
        b.extend_from_slice(b"\r\n");
        self.emit_raw(t, ctx, b);
    }

    fn emit_line(&mut self, t: Duration, ctx: Ctx, line: &str) {
        let mut b = if ctx.garble { self.garbage() } else { line.as_bytes().to_vec() };
        b.extend_from_slice(b"\r\n");
        self.emit_raw(t, ctx, b);
    }

    fn emit_prompt(&mut self, t: Duration, ctx: Ctx) {
        self.emit_raw(t, ctx, b">".to_vec());
    }

    /// Letters and non-ASCII bytes: never `*`, `.`, `>`, `\r` or `\n`.
    fn garbage(&mut self) -> Vec<u8> {
        let n = self.garble_rng.random_range(6..=24);
        (0..n)
            .map(|_| {
                if self.garble_rng.random_bool(0.5) {
                    let c = self.garble_rng.random_range(0..52u8);
                    if c < 26 {
                        b'A' + c
                    } else {
                        b'a' + (c - 26)
                    }
                } else {
                    self.garble_rng.random_range(0x80..=0xffu8)
                }
            })
            .collect()
    }

    fn request_disconnect(&mut self, t: Duration) {
        self.disconnect = true;
        self.out.retain(|(r, _)| *r <= t);
        self.type_ahead.clear();
    }

    // ----- commands ---------------------------------------------------------

    fn run(&mut self, t: Duration, keyword: &str, args: &[&str], ctx: Ctx) -> Reply {
        let done = || Ok(Outcome::Lines(vec!["Done.".into()]));
        match keyword {
            "" => Ok(Outcome::Lines(Vec::new())),
            "HOME" => {
                no_args(keyword, args)?;
                self.may_move(false)?;
                self.enqueue(t, MotionKind::Home, Vec::new(), None, true, ctx)?;
                Ok(Outcome::Wait(vec!["HOMING...".into()]))
            }
            "CON" => {
                no_args(keyword, args)?;
                self.control = true;
                done()
            }
            "COFF" => {
                no_args(keyword, args)?;
                self.halt(t, true);
                self.control = false;
                done()
            }
            "SPEED" => {
                let [n] = args else { return Err(bad("SPEED takes one integer 1..100")) };
                match n.parse::<u32>() {
                    Ok(n) if (1..=100).contains(&n) => {
                        self.speed = n;
                        done()
                    }
                    _ => Err(bad(&format!("speed `{n}`; it must be an integer 1..100"))),
                }
            }
            "DEFP" => {
                let [p] = args else { return Err(bad("DEFP takes one position name")) };
                let name = parse_name(p)?;
                if self.vectors.contains_key(&name) {
                    return Err(bad(&format!("{name} is a vector")));
                }
                if !self.points.contains_key(&name) {
                    self.room_for(1)?;
                    self.points.insert(name, Coords::None);
                }
                done()
            }
            "DIMP" => {
                if args.is_empty() {
                    return Err(bad("DIMP takes a vector and its length, as V[n]"));
                }
                let spec = args.concat();
                let (name, n) = match parse_ref(&spec)? {
                    PosRef::Element(v, n) if n <= MAX_VECTOR => (v, n),
                    PosRef::Element(_, n) => return Err(bad(&format!("length {n}; at most {MAX_VECTOR}"))),
                    PosRef::Point(_) => return Err(bad("DIMP takes a vector and its length, as V[n]")),
                };
                if self.points.contains_key(&name) {
                    return Err(bad(&format!("{name} is a position, not a vector")));
                }
                let old = self.vectors.get(&name).map_or(0, Vec::len);
                self.room_for(n.saturating_sub(old))?;
                let v = self.vectors.entry(name).or_default();
                v.resize(n, Coords::None);
                done()
            }
            "HERE" => {
                let [p] = args else { return Err(bad("HERE takes one position")) };
                let r = parse_ref(p)?;
                let c = self.counts_at(t);
                self.store(&r, Coords::Joint(c), true)?;
                done()
            }
            "SETPV" => {
                let [p, axis, value] = args else { return Err(bad("SETPV takes a position, an axis 1..5 and counts")) };
                let r = parse_ref(p)?;
                let axis = match axis.parse::<usize>() {
                    Ok(a) if (1..=MOTORS).contains(&a) => a,
                    _ => return Err(bad(&format!("axis `{axis}`; it must be 1..5"))),
                };
                let value = parse_value(value)?;
                let mut c = match self.lookup(&r)? {
                    Coords::None => [0; MOTORS],
                    Coords::Joint(c) => c,
                    Coords::Cartesian(x) => self.solve_cartesian(x, self.counts_at(t))?,
                };
                c[axis - 1] = value;
                self.store(&r, Coords::Joint(c), false)?;
                done()
            }
            "SETPVC" => {
                let [p, coord, value] = args else {
                    return Err(bad("SETPVC takes a position, X|Y|Z|P|R and a value"));
                };
                let r = parse_ref(p)?;
                let k = match coord.to_ascii_uppercase().as_str() {
                    "X" => 0,
                    "Y" => 1,
                    "Z" => 2,
                    "P" => 3,
                    "R" => 4,
                    _ => return Err(bad(&format!("coordinate `{coord}`; it must be X, Y, Z, P or R"))),
                };
                let value = parse_value(value)?;
                let mut x = match self.lookup(&r)? {
                    Coords::None => return Err(no_coordinates(&r)),
                    Coords::Joint(c) => self.cartesian_of(c)?,
                    Coords::Cartesian(x) => x,
                };
                x[k] = value;
                self.store(&r, Coords::Cartesian(x), false)?;
                done()
            }
            "LISTPV" => {
                let [p] = args else { return Err(bad("LISTPV takes one position")) };
                let r = parse_ref(p)?;
                let (c, x) = match self.lookup(&r)? {
                    Coords::None => return Err(no_coordinates(&r)),
                    Coords::Joint(c) => (c, self.cartesian_of(c)?),
                    Coords::Cartesian(x) => (self.solve_cartesian(x, self.counts_at(t))?, x),
                };
                Ok(Outcome::Lines(vec![
                    format!("Position {}", r.label()),
                    format!(" 1:{} 2:{} 3:{} 4:{} 5:{}", c[0], c[1], c[2], c[3], c[4]),
                    format!(" X:{} Y:{} Z:{} P:{} R:{}", x[0], x[1], x[2], x[3], x[4]),
                ]))
            }
            "LISTP" => {
                no_args(keyword, args)?;
                let mut lines: Vec<String> = self.points.keys().cloned().collect();
                for (v, elems) in &self.vectors {
                    lines.extend((1..=elems.len()).map(|i| format!("{v}[{i}]")));
                }
                Ok(Outcome::Listing(lines))
            }
            "MOVE" | "MOVED" => {
                let (p, time) = match args {
                    [p] => (p, None),
                    [p, tm] => (p, Some(parse_time(tm)?)),
                    _ => return Err(bad(&format!("{keyword} takes a position and an optional time (0.01 s)"))),
                };
                self.may_move(true)?;
                let r = parse_ref(p)?;
                let target = self.resolve(&r, self.planned_end())?;
                let waits = keyword == "MOVED";
                self.enqueue(t, MotionKind::Arm, vec![target], time, waits, ctx)?;
                if waits {
                    Ok(Outcome::Wait(Vec::new()))
                } else {
                    done()
                }
            }
            "MOVES" => {
                let (v, a, b, time) = match args {
                    [v, a, b] => (v, a, b, None),
                    [v, a, b, tm] => (v, a, b, Some(parse_time(tm)?)),
                    _ => return Err(bad("MOVES takes a vector, a first and a last index, and an optional time")),
                };
                let name = parse_name(v)?;
                let len = match self.vectors.get(&name) {
                    Some(e) => e.len(),
                    None => return Err(format!("*** VECTOR {name} NOT DEFINED")),
                };
                let index = |s: &str| match s.parse::<usize>() {
                    Ok(i) if (1..=len).contains(&i) => Ok(i),
                    _ => Err(bad(&format!("index `{s}`; {name} has positions 1..{len}"))),
                };
                let (a, b) = (index(a)?, index(b)?);
                self.may_move(true)?;
                let order: Vec<usize> = if a <= b { (a..=b).collect() } else { (b..=a).rev().collect() };
                let mut near = self.planned_end();
                let mut targets = Vec::with_capacity(order.len());
                for i in order {
                    let c = self.resolve(&PosRef::Element(name.clone(), i), near)?;
                    targets.push(c);
                    near = c;
                }
                self.enqueue(t, MotionKind::Arm, targets, time, true, ctx)?;
                Ok(Outcome::Wait(Vec::new()))
            }
            "OPEN" | "CLOSE" => {
                no_args(keyword, args)?;
                self.may_move(false)?;
                let kind = MotionKind::Gripper { open: keyword == "OPEN" };
                self.enqueue(t, kind, Vec::new(), None, true, ctx)?;
                Ok(Outcome::Wait(Vec::new()))
            }
            "A" => {
                no_args(keyword, args)?;
                done()
            }
            "CLRBUF" => {
                no_args(keyword, args)?;
                let waiters: Vec<Ctx> = self.queue.drain(..).filter_map(|i| i.waiter).collect();
                self.abort_waiters(t, waiters);
                done()
            }
            _ => Ok(Outcome::Refused("*** UNKNOWN COMMAND".into())),
        }
    }

    /// Checks control (and homing, for the arm).
    fn may_move(&self, arm: bool) -> std::result::Result<(), String> {
        if !self.control {
            return Err("*** CONTROL DISABLED".into());
        }
        if arm && !self.homed {
            return Err("*** HOME NOT DONE".into());
        }
        Ok(())
    }

    /// Queues a motion (starting it now if the arm is idle). With `waits`,
    /// the command answers when it ends; a disconnect fault rides with it.
    fn enqueue(
        &mut self,
        t: Duration,
        kind: MotionKind,
        targets: Vec<[i64; MOTORS]>,
        time: Option<f64>,
        waits: bool,
        ctx: Ctx,
    ) -> std::result::Result<(), String> {
        if self.queue.len() >= MAX_QUEUE {
            return Err("*** BUFFER FULL".into());
        }
        let waiter = waits.then_some(ctx);
        self.queue.push_back(Item { kind, targets, time, waiter, disconnect: ctx.disconnect });
        if self.active.is_none() {
            if let Some(next) = self.queue.pop_front() {
                self.start(next, t);
            }
        }
        Ok(())
    }

    // ----- positions --------------------------------------------------------

    fn room_for(&self, extra: usize) -> std::result::Result<(), String> {
        let used = self.points.len() + self.vectors.values().map(Vec::len).sum::<usize>();
        if used + extra > MAX_POSITIONS {
            return Err(format!("*** BAD ARGUMENT: no room; at most {MAX_POSITIONS} positions"));
        }
        Ok(())
    }

    fn lookup(&self, r: &PosRef) -> std::result::Result<Coords, String> {
        let found = match r {
            PosRef::Point(n) => self.points.get(n).copied(),
            PosRef::Element(v, i) => self.vectors.get(v).and_then(|e| e.get(i - 1)).copied(),
        };
        found.ok_or_else(|| format!("*** POSITION {} NOT DEFINED", r.label()))
    }

    /// Stores coordinates into a defined position (or, with `define`, into a
    /// scalar position created if needed).
    fn store(&mut self, r: &PosRef, c: Coords, define: bool) -> std::result::Result<(), String> {
        match r {
            PosRef::Point(n) => {
                if self.vectors.contains_key(n) {
                    return Err(bad(&format!("{n} is a vector")));
                }
                if !self.points.contains_key(n) {
                    if !define {
                        return Err(format!("*** POSITION {n} NOT DEFINED"));
                    }
                    self.room_for(1)?;
                }
                self.points.insert(n.clone(), c);
                Ok(())
            }
            PosRef::Element(v, i) => match self.vectors.get_mut(v).and_then(|e| e.get_mut(i - 1)) {
                Some(slot) => {
                    *slot = c;
                    Ok(())
                }
                None => Err(format!("*** POSITION {} NOT DEFINED", r.label())),
            },
        }
    }

    /// The counts a position stands for, checked against the joint limits;
    /// Cartesian positions are solved nearest to `near`.
    fn resolve(&self, r: &PosRef, near: [i64; MOTORS]) -> std::result::Result<[i64; MOTORS], String> {
        let c = match self.lookup(r)? {
            Coords::None => return Err(no_coordinates(r)),
            Coords::Joint(c) => c,
            Coords::Cartesian(x) => self.solve_cartesian(x, near)?,
        };
        self.check_limits(&c)?;
        Ok(c)
    }

    fn check_limits(&self, c: &[i64; MOTORS]) -> std::result::Result<(), String> {
        let q = self.constants.angles(&c.map(|v| v as f64)).map_err(|e| format!("*** BAD ARGUMENT: {e}"))?;
        for (i, (j, v)) in self.robot.joints().iter().zip(q).enumerate() {
            let l = j.limits;
            if !(v >= l.min - LIMIT_TOLERANCE && v <= l.max + LIMIT_TOLERANCE) {
                return Err(format!(
                    "*** OUT OF RANGE: axis {} (joint angle {:.1} deg, limits {:.1} to {:.1} deg)",
                    i + 1,
                    v.to_degrees(),
                    l.min.to_degrees(),
                    l.max.to_degrees()
                ));
            }
        }
        Ok(())
    }

    /// X, Y, Z \[0.1 mm\], P = θ2+θ3+θ4, R = θ5 \[0.1°\] of counts, by the
    /// controller's constants.
    fn cartesian_of(&self, c: [i64; MOTORS]) -> std::result::Result<[i64; MOTORS], String> {
        let q = self.constants.angles(&c.map(|v| v as f64)).map_err(|e| format!("*** BAD ARGUMENT: {e}"))?;
        let p = self.robot.fk(&q).map_err(|e| format!("*** BAD ARGUMENT: {e}"))?.world_from_tool.pos;
        let tenths = |v: f64| (v * 10.0).round().clamp(-9e15, 9e15) as i64;
        Ok([
            tenths(p.x * 1000.0),
            tenths(p.y * 1000.0),
            tenths(p.z * 1000.0),
            tenths((q[1] + q[2] + q[3]).to_degrees()),
            tenths(q[4].to_degrees()),
        ])
    }

    /// Counts for Cartesian coordinates: the within-limits IK solution
    /// nearest (in joint space) to the configuration of `near`.
    fn solve_cartesian(&self, x: [i64; MOTORS], near: [i64; MOTORS]) -> std::result::Result<[i64; MOTORS], String> {
        const UNREACHABLE: &str = "*** POSITION NOT REACHABLE";
        let p = [x[0] as f64 * 1e-4, x[1] as f64 * 1e-4, x[2] as f64 * 1e-4];
        // The seed's pitch β = −(θ2+θ3+θ4) = −P.
        let pitch = -(x[3] as f64 / 10.0).to_radians();
        let roll = (x[4] as f64 / 10.0).to_radians();
        let q_near = self.constants.angles(&near.map(|v| v as f64)).map_err(|_| UNREACHABLE.to_string())?;
        let sols = self.ik.solve_xyz_pitch_roll(p, pitch, roll).map_err(|_| UNREACHABLE.to_string())?;
        let mut best: Option<(f64, [i64; MOTORS])> = None;
        for s in sols.iter().filter(|s| s.within_limits() && s.position_error < 1e-6) {
            let Ok(c) = self.constants.counts_rounded(&s.q) else { continue };
            if self.check_limits(&c).is_err() {
                continue;
            }
            let d: f64 = s.q.iter().zip(&q_near).map(|(a, b)| (a - b) * (a - b)).sum();
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, c));
            }
        }
        best.map(|b| b.1).ok_or_else(|| UNREACHABLE.to_string())
    }

    // ----- motion -----------------------------------------------------------

    fn counts_at(&self, t: Duration) -> [i64; MOTORS] {
        match &self.active {
            Some(a) => round_counts(&a.at(secs(t.saturating_sub(a.start)))),
            None => self.counts,
        }
    }

    /// Where the arm will be when every queued motion has ended.
    fn planned_end(&self) -> [i64; MOTORS] {
        for item in self.queue.iter().rev() {
            match item.kind {
                MotionKind::Arm => {
                    if let Some(c) = item.targets.last() {
                        return *c;
                    }
                }
                MotionKind::Home => return [0; MOTORS],
                MotionKind::Gripper { .. } => {}
            }
        }
        match &self.active {
            Some(a) => round_counts(&a.at(a.end())),
            None => self.counts,
        }
    }

    /// Nominal duration of a move between counts \[s\] at the current speed.
    fn move_seconds(&self, a: &[f64; MOTORS], b: &[f64; MOTORS]) -> f64 {
        (0..MOTORS)
            .map(|i| {
                let du = (b[i] - a[i]).abs() / self.constants.counts_per_degree[i].abs();
                du / (MOTOR_SPEED[i] * f64::from(self.speed) / 100.0)
            })
            .fold(0.0, f64::max)
    }

    fn start(&mut self, item: Item, t: Duration) {
        let from = self.counts.map(|v| v as f64);
        let scale = self.time_scale;
        let knots = match item.kind {
            MotionKind::Home => vec![(0.0, from), (HOME_SECONDS * scale, [0.0; MOTORS])],
            MotionKind::Gripper { .. } => vec![(0.0, from), (GRIPPER_SECONDS * scale, from)],
            MotionKind::Arm => {
                let mut points = vec![from];
                points.extend(item.targets.iter().map(|c| c.map(|v| v as f64)));
                let mut seg: Vec<f64> = points.windows(2).map(|w| self.move_seconds(&w[0], &w[1])).collect();
                if let Some(total) = item.time {
                    let sum: f64 = seg.iter().sum();
                    let n = seg.len().max(1) as f64;
                    for s in &mut seg {
                        *s = if sum > 0.0 { total * *s / sum } else { total / n };
                    }
                }
                let mut knots = vec![(0.0, from)];
                let mut acc = 0.0;
                for (s, p) in seg.iter().zip(&points[1..]) {
                    acc += s * scale;
                    knots.push((acc, *p));
                }
                knots
            }
        };
        let mut a = Active { kind: item.kind, start: t, knots, waiter: item.waiter, disconnect_at: None };
        if item.disconnect {
            a.disconnect_at = Some(a.end() / 2.0);
        }
        self.active = Some(a);
    }

    /// The running motion reaches its end at `t`.
    fn finish(&mut self, t: Duration) {
        let Some(a) = self.active.take() else { return };
        let end = a.end();
        self.counts = round_counts(&a.at(end));
        match a.kind {
            MotionKind::Home => self.homed = true,
            MotionKind::Gripper { open } => self.gripper_open = open,
            MotionKind::Arm => {}
        }
        self.sample(&a, end);
        if let Some(w) = a.waiter {
            self.emit_line(t, w, "Done.");
            self.emit_prompt(t, w);
            self.mode = Mode::Idle;
            self.pump(t);
        }
    }

    /// Stops the arm where it is at `t` and empties the queue; waiting
    /// commands end with `*** MOTION ABORTED` if `notify`.
    fn halt(&mut self, t: Duration, notify: bool) {
        let mut waiters = Vec::new();
        if let Some(a) = self.active.take() {
            let off = secs(t.saturating_sub(a.start)).min(a.end());
            self.counts = round_counts(&a.at(off));
            if a.kind == MotionKind::Home {
                self.homed = false;
            }
            self.sample(&a, off);
            waiters.extend(a.waiter);
        }
        waiters.extend(self.queue.drain(..).filter_map(|i| i.waiter));
        if notify {
            self.abort_waiters(t, waiters);
        } else if !waiters.is_empty() {
            self.mode = Mode::Idle;
        }
    }

    fn abort_waiters(&mut self, t: Duration, waiters: Vec<Ctx>) {
        if waiters.is_empty() {
            return;
        }
        for w in waiters {
            self.emit_line(t, w, "*** MOTION ABORTED");
            self.emit_prompt(t, w);
        }
        self.mode = Mode::Idle;
    }

    // ----- recording --------------------------------------------------------

    /// Records the physical tool position along `a` up to `until` \[s,
    /// simulated offset\], every 10 ms of nominal time (coarser if the motion
    /// would give more than [`MAX_SAMPLES_PER_MOTION`]), and appends the new
    /// rows to the file.
    fn sample(&mut self, a: &Active, until: f64) {
        if self.record.is_none() || matches!(a.kind, MotionKind::Gripper { .. }) {
            return;
        }
        if self.samples.len() >= MAX_SAMPLES {
            if !self.record_full {
                self.record_full = true;
                let path = self.record.as_ref().map(|p| p.display().to_string()).unwrap_or_default();
                self.record_error = Some(Error::RecordFull { path, max: MAX_SAMPLES });
            }
            return;
        }
        let nominal = until / self.time_scale;
        let period = SAMPLE_PERIOD.max(nominal / MAX_SAMPLES_PER_MOTION as f64);
        let n = (nominal / period - 1e-9).ceil().max(0.0) as usize;
        let from = self.samples.len();
        for k in 0..=n {
            let tau = (k as f64 * period).min(nominal);
            let counts = a.at(tau * self.time_scale);
            let Ok(q) = self.true_constants.angles(&counts) else { continue };
            let Ok(fk) = self.robot.fk(&q) else { continue };
            let p = fk.world_from_tool.pos;
            let mut s = [p.x, p.y, p.z];
            if self.noise > 0.0 {
                for v in &mut s {
                    *v += self.noise * gaussian(&mut self.noise_rng);
                }
            }
            self.samples.push(s);
        }
        self.append_record(from);
    }

    /// Creates the record file with its header (atomically).
    fn write_record(&mut self) {
        let Some(path) = &self.record else { return };
        if let Err(e) = write_atomically(path, b"x,y,z\n") {
            if self.record_error.is_none() {
                self.record_error = Some(Error::Record { path: path.display().to_string(), source: e.into() });
            }
        }
    }

    /// Appends the samples from index `from` on to the record file, in one write.
    fn append_record(&mut self, from: usize) {
        let Some(path) = &self.record else { return };
        let mut text = String::with_capacity(64 * (self.samples.len() - from));
        for s in &self.samples[from..] {
            let _ = writeln!(text, "{},{},{}", s[0], s[1], s[2]);
        }
        let result = std::fs::OpenOptions::new()
            .append(true)
            .open(path)
            .and_then(|mut f| std::io::Write::write_all(&mut f, text.as_bytes()));
        if let Err(e) = result {
            if self.record_error.is_none() {
                self.record_error = Some(Error::Record { path: path.display().to_string(), source: e.into() });
            }
        }
    }
}

/// Writes a temporary file next to `path` (an unpredictable name, created
/// exclusively, removed on any failure) and renames it over `path`.
fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let mut tmp = tempfile::Builder::new().prefix(".kinema-record-").suffix(".tmp").tempfile_in(dir)?;
    std::io::Write::write_all(&mut tmp, bytes)?;
    tmp.as_file().sync_all()?;
    tmp.persist(path).map(|_| ()).map_err(|e| e.error)
}

/// A standard normal deviate (Box–Muller).
fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>(); // (0, 1]
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

fn secs(d: Duration) -> f64 {
    d.as_secs_f64()
}

fn dur(s: f64) -> Duration {
    Duration::try_from_secs_f64(s.max(0.0)).unwrap_or(Duration::MAX)
}

fn round_counts(c: &[f64; MOTORS]) -> [i64; MOTORS] {
    c.map(|v| v.round() as i64)
}

fn is_abort(line: &Line) -> bool {
    !line.too_long && {
        let text = String::from_utf8_lossy(&line.bytes);
        let mut t = text.split_ascii_whitespace();
        t.next().is_some_and(|k| k.eq_ignore_ascii_case("A")) && t.next().is_none()
    }
}

fn bad(what: &str) -> String {
    format!("*** BAD ARGUMENT: {what}")
}

fn no_coordinates(r: &PosRef) -> String {
    format!("*** POSITION {} HAS NO COORDINATES", r.label())
}

fn no_args(keyword: &str, args: &[&str]) -> std::result::Result<(), String> {
    if args.is_empty() {
        Ok(())
    } else {
        Err(bad(&format!("{keyword} takes no arguments")))
    }
}

/// A position or vector name: a letter, then letters, digits or `_`.
fn parse_name(s: &str) -> std::result::Result<String, String> {
    let ok = !s.is_empty()
        && s.len() <= MAX_NAME
        && s.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_')
        && s.as_bytes()[0].is_ascii_alphabetic();
    if ok {
        Ok(s.to_ascii_uppercase())
    } else {
        Err(bad(&format!("name `{s}`; names are a letter then letters, digits or _ (at most {MAX_NAME})")))
    }
}

/// `NAME` or `NAME[i]` with i ≥ 1.
fn parse_ref(s: &str) -> std::result::Result<PosRef, String> {
    match s.split_once('[') {
        None => Ok(PosRef::Point(parse_name(s)?)),
        Some((v, rest)) => {
            let name = parse_name(v)?;
            match rest.strip_suffix(']').map(str::parse::<usize>) {
                Some(Ok(i)) if i >= 1 => Ok(PosRef::Element(name, i)),
                _ => Err(bad(&format!("`{s}`; an element is written V[n] with n >= 1"))),
            }
        }
    }
}

fn parse_value(s: &str) -> std::result::Result<i64, String> {
    match s.parse::<i64>() {
        Ok(v) if (-MAX_VALUE..=MAX_VALUE).contains(&v) => Ok(v),
        _ => Err(bad(&format!("value `{s}`; an integer of at most {MAX_VALUE} in magnitude"))),
    }
}

/// A time argument \[0.01 s\] → nominal seconds.
fn parse_time(s: &str) -> std::result::Result<f64, String> {
    match s.parse::<i64>() {
        Ok(v) if (1..=MAX_TIME_ARG).contains(&v) => Ok(v as f64 / 100.0),
        _ => Err(bad(&format!("time `{s}`; an integer 1..{MAX_TIME_ARG} (hundredths of a second)"))),
    }
}
