//! From a syntax tree to a motion plan: a static check (names, units,
//! argument counts, what the robot can do), then execution of the program
//! on a model of the robot — inverse kinematics for every target, a time law
//! for every motion, samples every `dt` — and the trajectory check, whose
//! violations are reported at the line of the motion that caused them.

use std::collections::{HashMap, HashSet};
use std::f64::consts::PI;
use std::rc::Rc;

use kinema::ik;
use kinema::ik::family::{self, Family, SelfMotionParameter, TypedKind};
use kinema::ik::IkTarget;
use kinema::math::{rpy_to_rot, Pose};
use kinema::nalgebra::Vector3;
use kinema::traj::{
    self, Blend, CartesianLimits, CartesianMotion, CheckOptions, JointMethod, JointTrajectory, Orientation, Profile,
    Ptp, PtpOptions, Segment, SelfMotion, TimeLaw,
};
use kinema::{Robot, RpyConvention};

use crate::ast::{BinOp, Expr, MotionKind, MotionOpts, Program, Stmt, StmtKind, Target};
use crate::diag::{Diagnostic, LineIndex};
use crate::lexer::Span;
use crate::stop::{Stop, StopReason};
use crate::units::{unit, Dim, Quantity};

/// How a program is compiled.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// Sample period \[s\] of the joint signals.
    pub dt: f64,
    /// Joint values at the start; the robot's `home` pose when `None`.
    pub start: Option<Vec<f64>>,
    /// Largest number of samples a program may produce (a guard against
    /// loops that would run for days).
    pub max_samples: usize,
    /// Largest number of steps executed: every statement run counts one, and
    /// so does every pass of a `LOOP`/`FOR`, empty or not. A loop that cannot
    /// finish under what is left is refused before its first pass.
    pub max_steps: usize,
    /// When to give up early (a deadline, Ctrl-C); never by default.
    pub stop: Stop,
    /// Skip motions to targets the robot cannot reach, with a warning each
    /// (seed 003 Fig. 9), instead of failing on them.
    pub skip_unreachable: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            dt: 0.01,
            start: None,
            max_samples: 5_000_000,
            max_steps: 1_000_000,
            stop: Stop::never(),
            skip_unreachable: false,
        }
    }
}

/// One motion of the plan (statements that take time: motions, waits, the
/// seed's instructions), in execution order.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannedMotion {
    /// Source line (from 1) of the statement.
    pub line: usize,
    /// The statement's keyword (`PTP`, `LIN`, `CIRC`, `WAIT`, `HOME`, `MOVEXY`, …).
    pub kind: String,
    /// Start time \[s\].
    pub start: f64,
    /// End time \[s\].
    pub end: f64,
    /// The time law (`trapezoid`, `scurve`, `cubic`, `linear`, `cubic+linear`, `hold`).
    pub profile: String,
    /// Where the robot goes, in words and SI units.
    pub target: String,
}

/// The solver of seed 003's relative instructions (MOVEXY, MOVEZ, MOVETITA):
/// the family that owns tool-angle targets (a point and the angle α about
/// z), fitted to the robot with the present TOOL.
enum Scara {
    /// No family takes tool-angle targets on this robot: the instructions are
    /// refused before the program runs.
    No,
    /// The fitted family.
    Solver(Rc<dyn Family>),
    /// The SCARA with a tool its IK cannot take (a tilted one): which TOOL, and why. HOME
    /// and PTP/LIN still work; MOVEXY/MOVEZ/MOVETITA are errors.
    ToolRefused(String),
}

/// A compiled program.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The motions in execution order.
    pub motions: Vec<PlannedMotion>,
    /// The joint signals: t, q, q̇, q̈ at every sample.
    pub trajectory: JointTrajectory,
    /// The robot as it ends the program (with the last TOOL).
    pub robot: Robot,
    /// Warnings (the program ran).
    pub warnings: Vec<Diagnostic>,
}

impl Plan {
    /// Total duration \[s\].
    pub fn duration(&self) -> f64 {
        self.trajectory.times().last().copied().unwrap_or(0.0)
    }

    /// The last joint values.
    pub fn final_q(&self) -> &[f64] {
        self.trajectory.q(self.trajectory.len() - 1)
    }

    /// The motion plan as text: a header, then one line per motion with its
    /// source line, keyword, start and end time, profile and target.
    pub fn listing(&self) -> String {
        let mut out = format!(
            "# `{}`: {} motion(s), {:.4} s\n{:>5}  {:<8}  {:>10}  {:>10}  {:<24}  target\n",
            self.robot.name(),
            self.motions.len(),
            self.duration(),
            "line",
            "motion",
            "start [s]",
            "end [s]",
            "profile"
        );
        for m in &self.motions {
            out.push_str(&format!(
                "{:>5}  {:<8}  {:>10.4}  {:>10.4}  {:<24}  {}\n",
                m.line, m.kind, m.start, m.end, m.profile, m.target
            ));
        }
        out
    }
}

/// Parses, checks and compiles `src` for `robot`. On any error nothing is
/// produced and every diagnostic found is returned (errors and warnings).
pub fn compile(src: &str, robot: &Robot, opts: &Options) -> Result<Plan, Vec<Diagnostic>> {
    let (program, mut diags) = crate::parser::parse(src);
    if diags.iter().any(Diagnostic::is_error) {
        return Err(diags);
    }
    let Some(mut c) = Compiler::new(src, robot, opts, &mut diags) else { return Err(diags) };
    c.static_block(&program.stmts, &mut Scope::default());
    if !c.errors.is_empty() {
        diags.append(&mut c.errors);
        return Err(diags);
    }
    c.run(&program);
    let Compiler { plan_motions, traj, robot_tool, warnings, errors, .. } = c;
    diags.extend(warnings.iter().cloned());
    diags.extend(errors);
    if diags.iter().any(Diagnostic::is_error) {
        return Err(diags);
    }
    Ok(Plan { motions: plan_motions, trajectory: traj, robot: robot_tool, warnings: diags })
}

/// Names visible during the static check.
#[derive(Debug, Clone, Default)]
struct Scope {
    /// POS names declared so far: joint (true) or Cartesian (false).
    positions: HashMap<String, bool>,
    /// FOR counters in scope.
    counters: Vec<String>,
    /// What each POS replaced (name, previous value), to undo a block's POS at its END
    /// without copying the scope for every block.
    undo: Vec<(String, Option<bool>)>,
}

impl Scope {
    fn declare(&mut self, key: &str, joint: bool) {
        let before = self.positions.insert(key.to_string(), joint);
        self.undo.push((key.to_string(), before));
    }

    /// Forgets the POS declared since `mark` (a length of `undo`).
    fn undo_to(&mut self, mark: usize) {
        while self.undo.len() > mark {
            let (key, before) = self.undo.pop().expect("longer than mark");
            match before {
                Some(j) => self.positions.insert(key, j),
                None => self.positions.remove(&key),
            };
        }
    }
}

/// A named position's value.
#[derive(Debug, Clone)]
enum PosValue {
    Joint(Vec<f64>),
    /// A pose in the world frame (the BASE in force when it was declared applied).
    Cart(Pose),
}

/// Cartesian segments waiting for the end of a blended chain.
struct Chain {
    segments: Vec<Segment>,
    /// (statement, line, keyword, target text) of each segment.
    owners: Vec<(Span, usize, &'static str, String)>,
    blend: Option<f64>,
    blend_is_time: bool,
    duration: Option<f64>,
    /// Some motions of the chain have IN, others not.
    partial_in: bool,
    /// Blends given both as lengths and as times.
    mixed_blend: bool,
}

struct Compiler<'a> {
    src: &'a str,
    lines: LineIndex,
    robot: &'a Robot,
    robot_tool: Robot,
    opts: &'a Options,
    scara: Scara,
    // State.
    q: Vec<f64>,
    traj: JointTrajectory,
    speed: f64,
    /// ACC p%: acceleration (and jerk) override.
    acc_override: f64,
    /// JVEL / JACC for revolute \[0\] and prismatic \[1\] joints.
    jvel: [Option<f64>; 2],
    jacc: [Option<f64>; 2],
    cart: CartesianLimits,
    profile: Profile,
    /// The self-motion policy of later LIN and CIRC motions (REDUNDANCY).
    self_motion: SelfMotion,
    base: Pose,
    positions: HashMap<String, PosValue>,
    counters: HashMap<String, f64>,
    chain: Option<Chain>,
    steps: usize,
    stopped: bool,
    // Output.
    plan_motions: Vec<PlannedMotion>,
    /// Statement span of each planned motion (for the trajectory check).
    motion_spans: Vec<Span>,
    /// (start, end, joints) of the motions in which those joints follow the
    /// linear law: its velocity steps at both ends are by design (seed 003's
    /// z and θ), so the check's acceleration findings there are not errors.
    velocity_steps: Vec<(f64, f64, Vec<bool>)>,
    warnings: Vec<Diagnostic>,
    errors: Vec<Diagnostic>,
    /// (span, message) of every warning and error so far: each is reported once.
    reported: HashSet<(Span, String, bool)>,
    /// Cartesian motions whose conversion to joints failed, with the inputs that
    /// decide it (tool generation, start joints) and the error: a failing LIN in a loop
    /// is computed once, not once per pass. Exact: the conversion is deterministic.
    failed_conversions: Vec<(CartesianMotion, SelfMotion, usize, Vec<f64>, String)>,
    /// Changes with every TOOL (the robot the conversion uses).
    tool_generation: usize,
}

/// Known positions named in the hint of an unknown one.
const KNOWN_LISTED: usize = 20;

/// Failed conversions remembered (the most recent ones).
const FAILED_CONVERSIONS_KEPT: usize = 16;

/// Defaults for Cartesian motions (an industrial controller's are similar):
/// 0.25 m/s, 1 m/s², 5 m/s³; 90°/s, 180°/s², 900°/s³.
fn default_cartesian() -> CartesianLimits {
    CartesianLimits { vel: 0.25, acc: 1.0, jerk: Some(5.0), rot_vel: PI / 2.0, rot_acc: PI, rot_jerk: Some(5.0 * PI) }
}

impl<'a> Compiler<'a> {
    fn new(src: &'a str, robot: &'a Robot, opts: &'a Options, diags: &mut Vec<Diagnostic>) -> Option<Self> {
        let q = match &opts.start {
            Some(q) => q.clone(),
            None => robot.home().to_vec(),
        };
        let whole = 0..src.len().min(1);
        if let Err(e) = robot.check_q(&q) {
            diags.push(Diagnostic::error(whole, format!("start configuration: {e}")));
            return None;
        }
        if let Some(m) = outside_limits(robot, &q) {
            diags.push(Diagnostic::error(whole, format!("start configuration: {m}")));
            return None;
        }
        if !(opts.dt > 0.0 && opts.dt.is_finite()) {
            diags.push(Diagnostic::error(whole, format!("the sample period must be positive, not {}", opts.dt)));
            return None;
        }
        let mut traj = JointTrajectory::new(robot.dof());
        let zeros = vec![0.0; robot.dof()];
        traj.push(0.0, &q, &zeros, &zeros).ok()?;
        Some(Compiler {
            src,
            lines: LineIndex::new(src),
            robot,
            robot_tool: robot.clone(),
            opts,
            scara: family::for_typed(robot, TypedKind::Alpha).map_or(Scara::No, |f| Scara::Solver(Rc::from(f))),
            q,
            traj,
            speed: 1.0,
            acc_override: 1.0,
            jvel: [None; 2],
            jacc: [None; 2],
            cart: default_cartesian(),
            profile: Profile::Trapezoid,
            self_motion: SelfMotion::Auto,
            base: Pose::IDENTITY,
            positions: HashMap::new(),
            counters: HashMap::new(),
            chain: None,
            steps: 0,
            stopped: false,
            plan_motions: Vec::new(),
            motion_spans: Vec::new(),
            velocity_steps: Vec::new(),
            warnings: Vec::new(),
            errors: Vec::new(),
            reported: HashSet::new(),
            failed_conversions: Vec::new(),
            tool_generation: 0,
        })
    }

    fn line(&self, span: &Span) -> usize {
        self.lines.line(span.start.min(self.src.len()))
    }

    /// Whether `d` is new (not yet reported at its place); remembers it.
    fn is_new(&mut self, d: &Diagnostic) -> bool {
        self.reported.insert((d.span.clone(), d.message.clone(), d.is_error()))
    }

    fn warn(&mut self, d: Diagnostic) {
        if self.is_new(&d) {
            self.warnings.push(d);
        }
    }

    fn err(&mut self, d: Diagnostic) {
        // The same problem inside a loop is reported once.
        if self.is_new(&d) {
            self.errors.push(d);
        }
        if self.errors.len() >= 50 {
            self.stopped = true;
        }
    }

    // ------------------------------------------------------------------
    // Static check: every statement once, loop bodies once.
    // ------------------------------------------------------------------

    fn static_block(&mut self, stmts: &[Stmt], scope: &mut Scope) {
        for s in stmts {
            self.static_stmt(s, scope);
        }
    }

    // Range checks read better inside their match arm than folded into its guard.
    #[allow(clippy::collapsible_match)]
    fn static_stmt(&mut self, s: &Stmt, scope: &mut Scope) {
        match &s.kind {
            StmtKind::Pos { name, value } => {
                if let Some(joint) = self.static_target(value, scope) {
                    if scope.counters.contains(&name.key) {
                        self.err(Diagnostic::error(
                            name.span.clone(),
                            format!("`{}` is a FOR counter here", name.text),
                        ));
                    }
                    scope.declare(&name.key, joint);
                }
            }
            StmtKind::Motion { kind, relative, target, opts } => {
                if *relative {
                    if let Target::Named(nm) = target {
                        self.err(
                            Diagnostic::error(nm.span.clone(), "REL needs an offset written out, not a named position")
                                .with_hint("write e.g. LIN REL CART(0mm, 0mm, -50mm)"),
                        );
                    }
                    if *kind == MotionKind::Lin && matches!(target, Target::Joint(..)) {
                        self.err(Diagnostic::error(target.span(), "LIN REL takes a Cartesian offset CART(...)"));
                    }
                }
                self.static_target(target, scope);
                self.static_opts(opts, scope);
                if *kind == MotionKind::Lin {
                    self.static_cartesian_capable(s);
                }
            }
            StmtKind::Circ { aux, target, opts } => {
                self.static_target(aux, scope);
                self.static_target(target, scope);
                self.static_opts(opts, scope);
                self.static_cartesian_capable(s);
            }
            StmtKind::Speed(e) => {
                if let Some(v) = self.static_expect(e, Dim::Percent, None, scope) {
                    if known_bad(v, |v| v > 0.0 && v <= 1.0) {
                        self.err(Diagnostic::error(
                            e.span(),
                            format!("SPEED must be in (0 %, 100 %], not {} %", v * 100.0),
                        ));
                    }
                }
            }
            StmtKind::Vel(e) | StmtKind::Acc(e) | StmtKind::JVel(e) | StmtKind::JAcc(e) => {
                let is_vel = matches!(s.kind, StmtKind::Vel(_) | StmtKind::JVel(_));
                let dims = if is_vel { [Dim::LinVel, Dim::AngVel] } else { [Dim::LinAcc, Dim::AngAcc] };
                let percent_ok = matches!(s.kind, StmtKind::Acc(_));
                match self.static_eval(e, scope) {
                    Some(q) if percent_ok && q.dim == Dim::Percent => {
                        if known_bad(q.value, |v| v > 0.0 && v <= 1.0) {
                            self.err(Diagnostic::error(
                                e.span(),
                                format!("ACC must be in (0 %, 100 %], not {} %", q.value * 100.0),
                            ));
                        }
                    }
                    Some(q) if dims.contains(&q.dim) => {
                        if known_bad(q.value, |v| v > 0.0) {
                            self.err(Diagnostic::error(e.span(), "must be positive"));
                        }
                    }
                    Some(q) => self.err(Diagnostic::error(
                        e.span(),
                        format!(
                            "expected {} or {}{}, found {}",
                            dims[0],
                            dims[1],
                            if percent_ok { " or a percentage (%)" } else { "" },
                            q.dim
                        ),
                    )),
                    None => {}
                }
            }
            StmtKind::Profile(name) => {
                if parse_profile(&name.key).is_none() {
                    self.err(
                        Diagnostic::error(name.span.clone(), format!("unknown profile `{}`", name.text))
                            .with_hint("profiles: trapezoid, scurve, quintic, cubic"),
                    );
                }
            }
            StmtKind::Redundancy { mode, value } => match value {
                None => {
                    if mode.key.parse::<f64>().is_ok()
                        || SelfMotion::parse(SelfMotionParameter::Q3, &mode.key, 1.0).is_err()
                    {
                        self.err(
                            Diagnostic::error(mode.span.clone(), format!("unknown self-motion policy `{}`", mode.text))
                                .with_hint("policies: hold, track, manipulability, avoid-limits, auto; or q3 = 30deg, psi = 0.5rad"),
                        );
                    }
                }
                Some(e) => {
                    if mode.key.parse::<SelfMotionParameter>().is_err() {
                        self.err(
                            Diagnostic::error(
                                mode.span.clone(),
                                format!("`{}` is not a self-motion parameter", mode.text),
                            )
                            .with_hint("a value is given for q3 or psi: REDUNDANCY q3 = 30deg"),
                        );
                    }
                    self.static_expect(e, Dim::Angle, None, scope);
                }
            },
            StmtKind::Tool(t) | StmtKind::Base(t) => {
                if !matches!(t, Target::Cart(..)) && !matches!(t, Target::Named(_)) {
                    self.err(Diagnostic::error(t.span(), "a frame is written CART(x, y, z, roll, pitch, yaw)"));
                }
                if let Some(true) = self.static_target(t, scope) {
                    self.err(Diagnostic::error(t.span(), "a frame must be a Cartesian position, not joint values"));
                }
            }
            StmtKind::Wait(e) => {
                if let Some(v) = self.static_expect(e, Dim::Time, Some(1.0), scope) {
                    if v < 0.0 {
                        self.err(Diagnostic::error(e.span(), "a wait cannot be negative"));
                    }
                }
            }
            StmtKind::Home(e) => {
                if let Some(e) = e {
                    self.static_time(e, scope);
                }
            }
            StmtKind::Loop { count, body } => {
                if let Some(v) = self.static_expect(count, Dim::None, None, scope) {
                    if self.check_count(v, count.span()) && !v.is_nan() {
                        self.check_passes(s, v, 0);
                    }
                }
                let mark = scope.undo.len();
                self.static_block(body, scope);
                scope.undo_to(mark);
            }
            StmtKind::For { var, from, to, body } => {
                let mut bounds = [None, None];
                for (k, e) in [from, to].into_iter().enumerate() {
                    if let Some(v) = self.static_expect(e, Dim::None, None, scope) {
                        if self.check_bound(v, e.span()) && !v.is_nan() {
                            bounds[k] = Some(v);
                        }
                    }
                }
                if let [Some(a), Some(b)] = bounds {
                    if self.check_passes(s, for_passes(a, b), 0) {
                        self.check_exact(s, a, b);
                    }
                }
                let mark = scope.undo.len();
                scope.counters.push(var.key.clone());
                self.static_block(body, scope);
                scope.counters.pop();
                scope.undo_to(mark);
            }
            StmtKind::MoveZ { dz, time } | StmtKind::MoveTita { dtheta: dz, time } => {
                self.static_scara(s);
                let (dim, scale) = if matches!(s.kind, StmtKind::MoveZ { .. }) {
                    (Dim::Length, 1e-3)
                } else {
                    (Dim::Angle, PI / 180.0)
                };
                self.static_expect(dz, dim, Some(scale), scope);
                self.static_time(time, scope);
            }
            StmtKind::MoveXy { dx, dy, time } => {
                self.static_scara(s);
                self.static_expect(dx, Dim::Length, Some(1e-3), scope);
                self.static_expect(dy, Dim::Length, Some(1e-3), scope);
                self.static_time(time, scope);
            }
        }
    }

    /// Whether a LOOP count is fine (or unknown); the error if not.
    fn check_count(&mut self, v: f64, span: Span) -> bool {
        if known_bad(v, |v| v >= 1.0 && v.fract() == 0.0) {
            self.err(
                Diagnostic::error(span, format!("a loop count must be a positive whole number, not {v}"))
                    .with_hint("LOOP 3 repeats its body three times"),
            );
            return false;
        }
        true
    }

    /// Whether a FOR bound is fine (or unknown): a whole number.
    fn check_bound(&mut self, v: f64, span: Span) -> bool {
        if known_bad(v, |v| v.fract() == 0.0) {
            self.err(Diagnostic::error(span, format!("FOR bounds are whole numbers, not {v}")));
            return false;
        }
        true
    }

    /// Whether FOR bounds (known, whole, and few passes apart) are small enough that
    /// counting up by one from the first is exact.
    fn check_exact(&mut self, s: &Stmt, a: f64, b: f64) -> bool {
        if a.abs() <= MAX_EXACT && b.abs() <= MAX_EXACT {
            return true;
        }
        self.err(Diagnostic::error(
            s.keyword.clone(),
            format!("FOR bounds must lie within ±{MAX_EXACT} (where whole numbers are exact), not {a} and {b}"),
        ));
        false
    }

    /// Refuses loop `s` when its `passes` alone exceed the steps left after `used`
    /// (each pass costs one step): it could never finish.
    fn check_passes(&mut self, s: &Stmt, passes: f64, used: usize) -> bool {
        let left = self.opts.max_steps.saturating_sub(used);
        if passes <= left as f64 {
            return true;
        }
        let kw = keyword_of(&s.kind);
        let left_text = if used == 0 { String::new() } else { format!(" ({left} left at this point)") };
        self.err(
            Diagnostic::error(
                s.keyword.clone(),
                format!(
                    "this {kw} makes {passes} passes, more than the step limit of {} allows{left_text}; it is not run",
                    self.opts.max_steps
                ),
            )
            .with_hint("every statement run and every pass of a loop, empty or not, counts one step"),
        );
        self.stopped = true;
        false
    }

    fn static_time(&mut self, e: &Expr, scope: &Scope) {
        if let Some(v) = self.static_expect(e, Dim::Time, Some(1.0), scope) {
            if known_bad(v, |v| v > 0.0) {
                self.err(Diagnostic::error(e.span(), format!("a duration must be positive, not {v} s")));
            }
        }
    }

    fn static_scara(&mut self, s: &Stmt) {
        if matches!(self.scara, Scara::No) {
            self.err(
                Diagnostic::error(
                    s.keyword.clone(),
                    format!(
                        "{} is an instruction of the SCARA on a rail (seed 003); `{}` is not one",
                        keyword_of(&s.kind),
                        self.robot.name()
                    ),
                )
                .with_hint("run it with --robot scara5, or use PTP/LIN with CART(...) targets"),
            );
        }
    }

    fn static_cartesian_capable(&mut self, s: &Stmt) {
        if self.robot.dof() < 6 && ik::analytic_solver(self.robot).is_none() {
            self.err(Diagnostic::error(
                s.keyword.clone(),
                format!(
                    "`{}` has {} joints and no closed-form solver: it cannot follow a Cartesian line in position and orientation",
                    self.robot.name(),
                    self.robot.dof()
                ),
            ));
        }
    }

    #[allow(clippy::collapsible_match)]
    fn static_opts(&mut self, o: &MotionOpts, scope: &Scope) {
        if let Some(d) = &o.duration {
            self.static_time(d, scope);
        }
        if let Some(b) = &o.blend {
            match self.static_eval(b, scope) {
                Some(q) if q.dim == Dim::Length || q.dim == Dim::Time => {
                    if known_bad(q.value, |v| v >= 0.0) {
                        self.err(Diagnostic::error(b.span(), "a blend cannot be negative"));
                    }
                }
                Some(q) => self.err(
                    Diagnostic::error(b.span(), format!("BLEND takes a length or a time, found {}", q.dim))
                        .with_hint("BLEND 20mm starts the next motion when 20 mm of this one are left; BLEND 0.2s, 0.2 s before its end"),
                ),
                None => {}
            }
        }
    }

    /// Checks a target; `Some(true)` for joint values, `Some(false)` for a pose.
    fn static_target(&mut self, t: &Target, scope: &Scope) -> Option<bool> {
        let n = self.robot.dof();
        match t {
            Target::Named(name) => {
                if let Some(j) = scope.positions.get(&name.key) {
                    return Some(*j);
                }
                if self.robot.pose(&name.key).is_ok() {
                    return Some(true);
                }
                // At most a few names (a program of thousands of positions and typos
                // would otherwise list them all at each typo).
                let total = scope.positions.len() + self.robot.poses().len();
                let mut known: Vec<String> = scope
                    .positions
                    .keys()
                    .cloned()
                    .chain(self.robot.poses().iter().map(|p| p.name.clone()))
                    .take(KNOWN_LISTED)
                    .collect();
                if total > KNOWN_LISTED {
                    known.push(format!("and {} more", total - KNOWN_LISTED));
                }
                let hint = if known.is_empty() {
                    "declare it first: POS name = CART(...) or JOINT(...)".to_string()
                } else {
                    format!("known positions: {}; declare new ones with POS name = ...", known.join(", "))
                };
                self.err(
                    Diagnostic::error(name.span.clone(), format!("unknown position `{}`", name.text)).with_hint(hint),
                );
                None
            }
            Target::Joint(items, span) => {
                if items.len() != n {
                    self.err(
                        Diagnostic::error(
                            span.clone(),
                            format!("JOINT has {} values; `{}` has {n} joints", items.len(), self.robot.name()),
                        )
                        .with_hint(format!("write {n} values, e.g. JOINT({})", joint_example(self.robot))),
                    );
                }
                for (i, e) in items.iter().enumerate() {
                    let dim = joint_dim(self.robot, i);
                    self.static_expect(e, dim, None, scope);
                }
                Some(true)
            }
            Target::Cart(items, span) => {
                if items.len() != 3 && items.len() != 6 {
                    self.err(
                        Diagnostic::error(
                            span.clone(),
                            format!("CART has {} values; it takes x, y, z or x, y, z, roll, pitch, yaw", items.len()),
                        )
                        .with_hint("e.g. CART(500mm, 0mm, 400mm, 0deg, 180deg, 0deg)"),
                    );
                }
                for (i, e) in items.iter().enumerate() {
                    let dim = if i < 3 { Dim::Length } else { Dim::Angle };
                    self.static_expect(e, dim, None, scope);
                }
                Some(false)
            }
        }
    }

    /// Evaluates with FOR counters unknown (NaN); reports unknown names and
    /// unit errors.
    fn static_eval(&mut self, e: &Expr, scope: &Scope) -> Option<Quantity> {
        let counters: HashMap<String, f64> = scope.counters.iter().map(|c| (c.clone(), f64::NAN)).collect();
        match eval(e, &counters) {
            Ok(q) => Some(q),
            Err(d) => {
                self.err(d);
                None
            }
        }
    }

    /// The value in SI of an expression of dimension `dim`; a plain number
    /// takes `default_scale` (the seed's mm, degrees and seconds) or, without
    /// one, is only accepted when it is 0.
    fn static_expect(&mut self, e: &Expr, dim: Dim, default_scale: Option<f64>, scope: &Scope) -> Option<f64> {
        let q = self.static_eval(e, scope)?;
        match coerce(q, dim, default_scale, e) {
            Ok(v) => Some(v),
            Err(d) => {
                self.err(d);
                None
            }
        }
    }

    // ------------------------------------------------------------------
    // Execution.
    // ------------------------------------------------------------------

    fn run(&mut self, program: &Program) {
        self.block(&program.stmts);
        self.flush_chain();
        if self.errors.is_empty() {
            self.check_trajectory();
        }
    }

    fn block(&mut self, stmts: &[Stmt]) {
        for s in stmts {
            if !self.step(s) {
                return;
            }
            self.stmt(s);
        }
    }

    /// Counts one step at `s` (a statement, or a pass of the loop `s`) and looks at the
    /// stop; false, with the one error that says why, when the run must end here.
    fn step(&mut self, s: &Stmt) -> bool {
        if self.stopped {
            return false;
        }
        self.steps += 1;
        if let Some(why) = self.opts.stop.reason() {
            self.stop_here(s, why);
            return false;
        }
        if self.steps > self.opts.max_steps {
            self.err(
                Diagnostic::error(
                    s.keyword.clone(),
                    format!(
                        "the program executes more than {} statements (the step limit; loop passes counted); it is cut here",
                        self.opts.max_steps
                    ),
                )
                .with_hint("every statement run and every pass of a loop, empty or not, counts one step"),
            );
            self.stopped = true;
            return false;
        }
        true
    }

    fn stop_here(&mut self, s: &Stmt, why: StopReason) {
        self.err(Diagnostic::error(s.keyword.clone(), format!("stopped here: {why}")));
        self.stopped = true;
    }

    fn value(&mut self, e: &Expr, dim: Dim, default_scale: Option<f64>) -> Option<f64> {
        match eval(e, &self.counters).and_then(|q| coerce(q, dim, default_scale, e)) {
            Ok(v) => Some(v),
            Err(d) => {
                self.err(d);
                None
            }
        }
    }

    fn stmt(&mut self, s: &Stmt) {
        // A statement that is not a blended Cartesian motion ends the chain.
        let continues_chain = matches!(s.kind, StmtKind::Motion { kind: MotionKind::Lin, .. } | StmtKind::Circ { .. })
            || matches!(
                s.kind,
                StmtKind::Pos { .. }
                    | StmtKind::Speed(_)
                    | StmtKind::Vel(_)
                    | StmtKind::Acc(_)
                    | StmtKind::JVel(_)
                    | StmtKind::JAcc(_)
            );
        if !continues_chain {
            self.flush_chain();
        }
        match &s.kind {
            StmtKind::Pos { name, value } => {
                if let Some(v) = self.resolve(value) {
                    self.positions.insert(name.key.clone(), v);
                }
            }
            StmtKind::Motion { kind: MotionKind::Ptp, relative, target, opts } => self.ptp(s, *relative, target, opts),
            StmtKind::Motion { kind: MotionKind::Lin, relative, target, opts } => {
                let Some(to) = self.cart_target(target, *relative) else { return };
                if self.skip_if_unreachable(s, &to) {
                    return;
                }
                let from = self.chain_end();
                match Segment::lin(&from, &to, Orientation::Slerp) {
                    Ok(seg) => self.push_segment(s, seg, opts, describe_pose(&to)),
                    Err(e) => self.err(Diagnostic::error(s.span.clone(), format!("LIN: {e}"))),
                }
            }
            StmtKind::Circ { aux, target, opts } => {
                let (Some(a), Some(to)) = (self.cart_target(aux, false), self.cart_target(target, false)) else {
                    return;
                };
                if self.skip_if_unreachable(s, &to) {
                    return;
                }
                let from = self.chain_end();
                match Segment::circ_through(&from, &a.pos, &to) {
                    Ok(seg) => self.push_segment(
                        s,
                        seg,
                        opts,
                        format!("through ({}) to {}", fmt_xyz(&a.pos), describe_pose(&to)),
                    ),
                    Err(e) => self.err(Diagnostic::error(s.span.clone(), format!("CIRC: {e}")).with_hint(
                        "the start, the auxiliary point and the end must be three distinct points not on one line",
                    )),
                }
            }
            StmtKind::Speed(e) => {
                if let Some(v) = self.value(e, Dim::Percent, None) {
                    if known_bad(v, |v| v > 0.0 && v <= 1.0) {
                        self.err(Diagnostic::error(
                            e.span(),
                            format!("SPEED must be in (0 %, 100 %], not {} %", v * 100.0),
                        ));
                    } else {
                        self.speed = v;
                    }
                }
            }
            StmtKind::Vel(e) | StmtKind::Acc(e) | StmtKind::JVel(e) | StmtKind::JAcc(e) => {
                if let Ok(q) = eval(e, &self.counters) {
                    if known_bad(q.value, |v| v > 0.0 && (q.dim != Dim::Percent || v <= 1.0)) {
                        self.err(Diagnostic::error(
                            e.span(),
                            format!("out of range: {} (must be positive, at most 100 %)", q.value),
                        ));
                        return;
                    }
                    match (&s.kind, q.dim) {
                        (StmtKind::Vel(_), Dim::LinVel) => self.cart.vel = q.value,
                        (StmtKind::Vel(_), Dim::AngVel) => self.cart.rot_vel = q.value,
                        (StmtKind::Acc(_), Dim::LinAcc) => self.cart.acc = q.value,
                        (StmtKind::Acc(_), Dim::AngAcc) => self.cart.rot_acc = q.value,
                        (StmtKind::Acc(_), Dim::Percent) if q.value > 0.0 && q.value <= 1.0 => {
                            self.acc_override = q.value
                        }
                        (StmtKind::JVel(_), Dim::AngVel) => self.jvel[0] = Some(q.value),
                        (StmtKind::JVel(_), Dim::LinVel) => self.jvel[1] = Some(q.value),
                        (StmtKind::JAcc(_), Dim::AngAcc) => self.jacc[0] = Some(q.value),
                        (StmtKind::JAcc(_), Dim::LinAcc) => self.jacc[1] = Some(q.value),
                        _ => {}
                    }
                }
            }
            StmtKind::Profile(name) => {
                if let Some(p) = parse_profile(&name.key) {
                    self.profile = p;
                }
            }
            StmtKind::Redundancy { mode, value } => {
                let policy = match value {
                    None => SelfMotion::parse(SelfMotionParameter::Q3, &mode.key, 1.0).ok(),
                    Some(e) => {
                        let value = self.value(e, Dim::Angle, None);
                        mode.key
                            .parse()
                            .ok()
                            .zip(value)
                            .map(|(parameter, v)| SelfMotion::Fixed { parameter, value: Some(v) })
                    }
                };
                if let Some(policy) = policy {
                    self.self_motion = policy;
                }
            }
            StmtKind::Tool(t) => {
                if let Some(PosValue::Cart(p)) = self.resolve_frame(t) {
                    match self.robot.with_tool(p) {
                        Ok(r) => {
                            // The SCARA's relative moves need its solver with the new tool. A
                            // tool it cannot take (a tilted one) is fine for PTP/LIN and HOME;
                            // MOVEXY/MOVEZ/MOVETITA after it are errors (they did nothing).
                            if !matches!(self.scara, Scara::No) {
                                match family::for_typed(&r, TypedKind::Alpha) {
                                    Ok(f) => self.scara = Scara::Solver(Rc::from(f)),
                                    Err(e) => {
                                        let why = match e {
                                            kinema::Error::SolverDoesNotFit { reason, .. } => reason,
                                            e => e.to_string(),
                                        };
                                        let line = self.line(&t.span());
                                        self.warn(Diagnostic::warning(
                                            t.span(),
                                            format!("the SCARA's closed-form IK cannot take this tool: {why}; MOVEXY, MOVEZ and MOVETITA cannot follow it"),
                                        ));
                                        self.scara = Scara::ToolRefused(format!("the TOOL at line {line}: {why}"));
                                    }
                                }
                            }
                            self.robot_tool = r;
                            self.tool_generation += 1;
                        }
                        Err(e) => self.err(Diagnostic::error(t.span(), format!("TOOL: {e}"))),
                    }
                }
            }
            StmtKind::Base(t) => {
                if let Some(PosValue::Cart(p)) = self.resolve_frame(t) {
                    self.base = p;
                }
            }
            StmtKind::Wait(e) => {
                if let Some(t) = self.value(e, Dim::Time, Some(1.0)) {
                    if t < 0.0 {
                        self.err(Diagnostic::error(e.span(), format!("a wait cannot be negative ({t} s)")));
                    } else {
                        self.hold(s, t, "WAIT");
                    }
                }
            }
            StmtKind::Home(e) => {
                let duration = match e {
                    Some(e) => match self.value(e, Dim::Time, Some(1.0)) {
                        Some(t) => Some(t),
                        None => return,
                    },
                    None => None,
                };
                let home = self.robot.home().to_vec();
                if !matches!(self.scara, Scara::No) {
                    // Seed 003 §III-D: cubic for the joints of the XY plane, linear for z and θ.
                    let Some(t) = duration.or_else(|| self.missing_duration(s, "HOME")) else { return };
                    self.scara_move(s, home, t, "HOME", "home".into());
                } else {
                    self.ptp_to(s, home, duration, "home".into());
                }
            }
            StmtKind::Loop { count, body } => {
                let Some(n) = self.value(count, Dim::None, None) else { return };
                let counted = self.check_count(n, count.span()) && !n.is_nan();
                if !(counted && self.check_passes(s, n, self.steps)) {
                    return;
                }
                // Each pass is a step, so an empty body ends at the step limit too.
                for _ in 0..(n as u64) {
                    if !self.step(s) {
                        return;
                    }
                    self.block(body);
                }
            }
            StmtKind::For { var, from, to, body } => {
                let (Some(a), Some(b)) = (self.value(from, Dim::None, None), self.value(to, Dim::None, None)) else {
                    return;
                };
                let whole = self.check_bound(a, from.span()) && self.check_bound(b, to.span());
                if !(whole && self.check_passes(s, for_passes(a, b), self.steps) && self.check_exact(s, a, b)) {
                    return;
                }
                let saved = self.counters.get(&var.key).copied();
                // Both bounds are whole and within ±2⁵³, so i takes every value exactly.
                let mut i = a;
                while i <= b && self.step(s) {
                    self.counters.insert(var.key.clone(), i);
                    self.block(body);
                    i += 1.0;
                }
                match saved {
                    Some(v) => self.counters.insert(var.key.clone(), v),
                    None => self.counters.remove(&var.key),
                };
            }
            StmtKind::MoveZ { dz, time } => {
                let (Some(dz), Some(t)) =
                    (self.value(dz, Dim::Length, Some(1e-3)), self.value(time, Dim::Time, Some(1.0)))
                else {
                    return;
                };
                self.scara_relative(s, [0.0, 0.0, dz, 0.0], t, "MOVEZ");
            }
            StmtKind::MoveTita { dtheta, time } => {
                let (Some(da), Some(t)) =
                    (self.value(dtheta, Dim::Angle, Some(PI / 180.0)), self.value(time, Dim::Time, Some(1.0)))
                else {
                    return;
                };
                self.scara_relative(s, [0.0, 0.0, 0.0, da], t, "MOVETITA");
            }
            StmtKind::MoveXy { dx, dy, time } => {
                let (Some(dx), Some(dy), Some(t)) = (
                    self.value(dx, Dim::Length, Some(1e-3)),
                    self.value(dy, Dim::Length, Some(1e-3)),
                    self.value(time, Dim::Time, Some(1.0)),
                ) else {
                    return;
                };
                self.scara_relative(s, [dx, dy, 0.0, 0.0], t, "MOVEXY");
            }
        }
    }

    fn missing_duration(&mut self, s: &Stmt, what: &str) -> Option<f64> {
        self.err(
            Diagnostic::error(s.span.clone(), format!("{what} needs a duration on this robot"))
                .with_hint(format!("write e.g. `{what} 5` (seconds), as seed 003 does")),
        );
        None
    }

    /// The value of a target: joint values or a world pose (with the BASE applied).
    fn resolve(&mut self, t: &Target) -> Option<PosValue> {
        match t {
            Target::Named(name) => {
                if let Some(v) = self.positions.get(&name.key) {
                    return Some(v.clone());
                }
                match self.robot.pose(&name.key) {
                    Ok(q) => Some(PosValue::Joint(q.to_vec())),
                    Err(_) => {
                        self.err(Diagnostic::error(name.span.clone(), format!("unknown position `{}`", name.text)));
                        None
                    }
                }
            }
            Target::Joint(items, _) => {
                let mut q = Vec::with_capacity(items.len());
                for (i, e) in items.iter().enumerate() {
                    q.push(self.value(e, joint_dim(self.robot, i), None)?);
                }
                Some(PosValue::Joint(q))
            }
            Target::Cart(items, _) => {
                let p = self.cart_values(items)?;
                Some(PosValue::Cart(self.base.mul(&p)))
            }
        }
    }

    /// The values of CART(...) in SI: x, y, z and roll, pitch, yaw (0 where not written).
    fn cart_numbers(&mut self, items: &[Expr]) -> Option<[f64; 6]> {
        let mut v = [0.0; 6];
        for (i, e) in items.iter().enumerate().take(6) {
            v[i] = self.value(e, if i < 3 { Dim::Length } else { Dim::Angle }, None)?;
        }
        Some(v)
    }

    fn cart_values(&mut self, items: &[Expr]) -> Option<Pose> {
        let v = self.cart_numbers(items)?;
        if items.len() == 3 {
            // Position only: keep the orientation the robot will have (in the base frame).
            let current = self.base.inverse().mul(&self.chain_end());
            return Some(Pose::new(current.rot, Vector3::new(v[0], v[1], v[2])));
        }
        Some(Pose::from_xyz_rpy([v[0], v[1], v[2]], [v[3], v[4], v[5]], RpyConvention::Zyx))
    }

    /// A frame for TOOL/BASE: written in the robot's own frame, not the current BASE.
    fn resolve_frame(&mut self, t: &Target) -> Option<PosValue> {
        match t {
            Target::Cart(items, _) => {
                let v = self.cart_numbers(items)?;
                Some(PosValue::Cart(Pose::from_xyz_rpy([v[0], v[1], v[2]], [v[3], v[4], v[5]], RpyConvention::Zyx)))
            }
            other => self.resolve(other),
        }
    }

    fn current_pose(&self) -> Pose {
        self.robot_tool.fk(&self.q).map(|f| f.world_from_tool).unwrap_or_else(|_| Pose::IDENTITY)
    }

    /// The pose a Cartesian motion goes to (joint targets by FK).
    fn cart_target(&mut self, t: &Target, relative: bool) -> Option<Pose> {
        if relative {
            let Target::Cart(items, _) = t else { return None };
            let v = self.cart_numbers(items)?;
            let from = self.chain_end();
            // An offset in the BASE frame: translation added, rotation applied on the left.
            let rb = self.base.rot;
            let dpos = rb * Vector3::new(v[0], v[1], v[2]);
            let drot = rb * rpy_to_rot([v[3], v[4], v[5]], RpyConvention::Zyx) * rb.transpose();
            return Some(Pose::new(drot * from.rot, from.pos + dpos));
        }
        match self.resolve(t)? {
            PosValue::Cart(p) => Some(p),
            PosValue::Joint(q) => match self.robot_tool.fk(&q) {
                Ok(f) => Some(f.world_from_tool),
                Err(e) => {
                    self.err(Diagnostic::error(t.span(), e.to_string()));
                    None
                }
            },
        }
    }

    /// Where the robot is at the end of the pending chain (or now).
    fn chain_end(&self) -> Pose {
        match &self.chain {
            Some(c) => c.segments.last().map(Segment::end).unwrap_or_else(|| self.current_pose()),
            None => self.current_pose(),
        }
    }

    fn push_segment(&mut self, s: &Stmt, seg: Segment, opts: &MotionOpts, target: String) {
        let blend = match &opts.blend {
            Some(b) => match eval(b, &self.counters) {
                Ok(q) => Some((q.value, q.dim == Dim::Time)),
                Err(d) => {
                    self.err(d);
                    return;
                }
            },
            None => None,
        };
        let duration = match &opts.duration {
            Some(d) => match self.value(d, Dim::Time, Some(1.0)) {
                Some(t) => Some(t),
                None => return,
            },
            None => None,
        };
        let kw: &'static str = if matches!(s.kind, StmtKind::Circ { .. }) { "CIRC" } else { "LIN" };
        let line = self.line(&s.span);
        let chain = self.chain.get_or_insert_with(|| Chain {
            segments: Vec::new(),
            owners: Vec::new(),
            blend: None,
            blend_is_time: false,
            duration: None,
            partial_in: false,
            mixed_blend: false,
        });
        chain.segments.push(seg);
        chain.owners.push((s.span.clone(), line, kw, target));
        // IN on a chain: the durations add up when every motion of it has one.
        chain.duration = match (chain.segments.len(), chain.duration, duration) {
            (1, _, d) => d,
            (_, Some(total), Some(d)) => Some(total + d),
            (_, None, None) => None,
            _ => {
                chain.partial_in = true;
                None
            }
        };
        match blend {
            Some((b, is_time)) => {
                // One blend per chain: the smallest asked for.
                match chain.blend {
                    None => {
                        chain.blend = Some(b);
                        chain.blend_is_time = is_time;
                    }
                    Some(c) if chain.blend_is_time == is_time => chain.blend = Some(c.min(b)),
                    Some(_) => chain.mixed_blend = true,
                }
            }
            None => self.flush_chain(),
        }
    }

    /// Plans, samples and appends the pending Cartesian chain.
    fn flush_chain(&mut self) {
        let Some(chain) = self.chain.take() else { return };
        let first = chain.owners[0].0.clone();
        if chain.mixed_blend {
            self.warn(
                Diagnostic::warning(
                    first.clone(),
                    "this blended chain mixes BLEND lengths and times: only the kind given first is used",
                )
                .with_hint("give every BLEND of a chain in mm/m or every one in s"),
            );
        }
        if chain.partial_in {
            self.warn(
                Diagnostic::warning(
                    first.clone(),
                    "IN is ignored on this blended chain: give it on every motion of the chain or on none",
                )
                .with_hint("the chain is timed as one motion; its duration is the sum of the motions' IN"),
            );
        }
        let blend = match chain.blend {
            Some(b) if chain.segments.len() > 1 => {
                if chain.blend_is_time {
                    Blend::Time(b)
                } else {
                    Blend::Distance(b)
                }
            }
            _ => Blend::None,
        };
        let (k, ka) = (self.speed, self.acc_override);
        let limits = CartesianLimits {
            vel: self.cart.vel * k,
            acc: self.cart.acc * k * k * ka,
            jerk: self.cart.jerk.map(|j| j * k * k * k * ka),
            rot_vel: self.cart.rot_vel * k,
            rot_acc: self.cart.rot_acc * k * k * ka,
            rot_jerk: self.cart.rot_jerk.map(|j| j * k * k * k * ka),
        };
        let profile = if self.profile.rest_to_rest() { self.profile } else { Profile::Trapezoid };
        let stop = &self.opts.stop;
        let planned =
            CartesianMotion::new_until(chain.segments.clone(), profile, &limits, blend, &|| stop.reason().is_some());
        let mut motion = match planned {
            Ok(m) => m,
            Err(kinema::Error::Cancelled) => {
                if let Some(why) = self.opts.stop.reason() {
                    self.err(Diagnostic::error(first, format!("stopped here: {why}")));
                }
                self.stopped = true;
                return;
            }
            Err(e) => {
                self.err(Diagnostic::error(first, format!("cannot time this motion: {e}")));
                return;
            }
        };
        if let Some(d) = chain.duration {
            match motion.stretched_to(d) {
                Ok(m) => motion = m,
                Err(e) => {
                    self.err(
                        Diagnostic::error(first, format!("{e}"))
                            .with_hint("IN asks for an exact duration; it cannot be shorter than the motion allows at this SPEED/VEL/ACC"),
                    );
                    return;
                }
            }
        }
        if let Blend::Distance(_) | Blend::Time(_) = blend {
            for (i, b) in motion.blend_times().iter().enumerate() {
                if *b <= 0.0 {
                    let (span, line, ..) = &chain.owners[i];
                    self.warn(
                        Diagnostic::warning(
                            span.clone(),
                            format!("the blend after line {line} was reduced to nothing: the corner is too sharp for the limits with this profile"),
                        )
                        .with_hint("PROFILE scurve can blend sharper corners; or lower the speed"),
                    );
                }
            }
        }
        let Some(times) = self.sample_times(first.clone(), motion.duration()) else { return };
        let failed_before = self
            .failed_conversions
            .iter()
            .find(|(m, policy, tool, q, _)| {
                *tool == self.tool_generation
                    && q.as_slice() == self.q.as_slice()
                    && *m == motion
                    && *policy == self.self_motion
            })
            .map(|(.., e)| e.clone());
        let converted = match failed_before {
            Some(e) => Err(e),
            None => traj::to_joints_at(
                &self.robot_tool,
                &motion,
                &self.q,
                &times,
                JointMethod::Ik(self.self_motion.clone()),
            )
            .map_err(|e| {
                let e = e.to_string();
                if self.failed_conversions.len() == FAILED_CONVERSIONS_KEPT {
                    self.failed_conversions.remove(0);
                }
                self.failed_conversions.push((
                    motion.clone(),
                    self.self_motion.clone(),
                    self.tool_generation,
                    self.q.clone(),
                    e.clone(),
                ));
                e
            }),
        };
        let joints = match converted {
            Ok(j) => j,
            Err(e) => {
                // Which segment: the time in the error, else the first.
                let owner = chain.owners.first().expect("non-empty").clone();
                self.err(
                    Diagnostic::error(owner.0, format!("{} cannot be followed: {e}", owner.2))
                        .with_hint("move the target, change the start configuration, or use PTP"),
                );
                return;
            }
        };
        let t0 = self.traj.times().last().copied().unwrap_or(0.0);
        let starts = motion.segment_starts().to_vec();
        for (i, (span, line, kw, target)) in chain.owners.iter().enumerate() {
            let end = if i + 1 < chain.owners.len() { starts[i + 1] } else { motion.duration() };
            self.plan_motions.push(PlannedMotion {
                line: *line,
                kind: kw.to_string(),
                start: t0 + starts[i],
                end: t0 + end.max(starts[i]),
                profile: profile.name().to_string(),
                target: target.clone(),
            });
            self.motion_spans.push(span.clone());
        }
        self.append(&joints, t0);
    }

    /// Whether `samples` more samples fit under the program's cap; if not, the error at
    /// `span` and the program stops there.
    fn room_for(&mut self, span: crate::lexer::Span, samples: usize) -> bool {
        // The trajectory holds the start already, and a statement's first sample is the
        // present one: `samples` adds samples − 1.
        let total = self.traj.len().saturating_add(samples.saturating_sub(1));
        let bytes = JointTrajectory::bytes_for(self.robot.dof(), total);
        if total <= self.opts.max_samples && bytes <= traj::MAX_TRAJECTORY_BYTES {
            return true;
        }
        let message = if total > self.opts.max_samples {
            format!("the program produces more than {} samples", self.opts.max_samples)
        } else {
            format!(
                "the program's {total} samples of {} joints would take {:.2} GB, above the limit of {:.2} GB",
                self.robot.dof(),
                bytes as f64 / 1e9,
                traj::MAX_TRAJECTORY_BYTES as f64 / 1e9
            )
        };
        self.err(Diagnostic::error(span, format!("{message}; it is cut here (raise dt or shorten the program)")));
        self.stopped = true;
        false
    }

    fn append(&mut self, j: &JointTrajectory, t0: f64) {
        let span = self.motion_spans.last().cloned().unwrap_or(0..0);
        if !self.room_for(span, j.len()) {
            return;
        }
        for k in 1..j.len() {
            // Cannot fail: same joint count, finite values, increasing times.
            let _ = self.traj.push(t0 + j.times()[k], j.q(k), j.qd(k), j.qdd(k));
        }
        if !j.is_empty() {
            self.q = j.q(j.len() - 1).to_vec();
        }
    }

    fn hold(&mut self, s: &Stmt, t: f64, kind: &str) {
        let t0 = self.traj.times().last().copied().unwrap_or(0.0);
        if t > 0.0 {
            let Some(times) = self.sample_times(s.span.clone(), t) else { return };
            self.record(s, kind, t0, t0 + t, "hold", "stand still".into());
            if !self.room_for(s.span.clone(), times.len()) {
                return;
            }
            // Straight into the trajectory: a copy made first would double
            // the memory of a long WAIT at the sample limit.
            let (q, z) = (self.q.clone(), vec![0.0; self.robot.dof()]);
            for &tt in &times[1..] {
                // Cannot fail: same joint count, finite values, increasing times.
                let _ = self.traj.push(t0 + tt, &q, &z, &z);
            }
        }
    }

    fn record(&mut self, s: &Stmt, kind: &str, start: f64, end: f64, profile: &str, target: String) {
        let line = self.line(&s.span);
        self.plan_motions.push(PlannedMotion { line, kind: kind.into(), start, end, profile: profile.into(), target });
        self.motion_spans.push(s.span.clone());
    }

    fn ptp(&mut self, s: &Stmt, relative: bool, target: &Target, opts: &MotionOpts) {
        let duration = match &opts.duration {
            Some(d) => match self.value(d, Dim::Time, Some(1.0)) {
                Some(t) => Some(t),
                None => return,
            },
            None => None,
        };
        if opts.blend.is_some() {
            self.warn(
                Diagnostic::warning(s.span.clone(), "BLEND on a PTP is ignored: the motion stops at its target")
                    .with_hint("blending applies to LIN and CIRC"),
            );
        }
        let q_to = if relative {
            match target {
                Target::Joint(items, _) => {
                    let mut q = self.q.clone();
                    for (i, e) in items.iter().enumerate() {
                        let Some(d) = self.value(e, joint_dim(self.robot, i), None) else { return };
                        if let Some(qi) = q.get_mut(i) {
                            *qi += d;
                        }
                    }
                    q
                }
                _ => {
                    let Some(pose) = self.cart_target(target, true) else { return };
                    let Some(q) = self.ik(s, &pose) else { return };
                    q
                }
            }
        } else {
            match self.resolve(target) {
                Some(PosValue::Joint(q)) => q,
                Some(PosValue::Cart(pose)) => {
                    let Some(q) = self.ik(s, &pose) else { return };
                    q
                }
                None => return,
            }
        };
        let text = format!("joints [{}]", fmt_joints(&q_to));
        self.ptp_to(s, q_to, duration, text);
    }

    /// The configuration reaching `pose` nearest to the current one, within
    /// limits: the request every door makes (`ik::solve_target`, then
    /// `ik::pick_one`), so a program gets exactly what `kinema ik --q0` gives.
    fn ik(&mut self, s: &Stmt, pose: &Pose) -> Option<Vec<f64>> {
        let robot = &self.robot_tool;
        let request = ik::IkRequest { q0: Some(&self.q), ..Default::default() };
        let result = ik::solve_target(robot, &ik::IkTarget::Pose(*pose), &request)
            .and_then(|answer| ik::pick_one(robot, answer.solver, answer.solutions, Some(&self.q)));
        match result {
            Ok(sol) => Some(sol.q),
            Err(e @ kinema::Error::Unreachable { .. }) if self.opts.skip_unreachable => {
                self.skipped(s, &e);
                None
            }
            Err(e) => {
                self.err(Diagnostic::error(s.span.clone(), format!("target unreachable: {e}")).with_hint(
                    "check the position against the robot's reach and the orientation against what the arm can take",
                ));
                None
            }
        }
    }

    /// With [`Options::skip_unreachable`]: a warning that statement `s` was
    /// skipped, its target being out of reach.
    fn skipped(&mut self, s: &Stmt, why: &kinema::Error) {
        self.warn(Diagnostic::warning(s.span.clone(), format!("skipped: {why}")).with_hint(
            "the robot stays where it is and the program goes on (skip-unreachable); without it this is an error",
        ));
    }

    /// With [`Options::skip_unreachable`], whether the Cartesian motion of
    /// `s` ends at a pose out of reach (then skipped with a warning).
    fn skip_if_unreachable(&mut self, s: &Stmt, to: &Pose) -> bool {
        if !self.opts.skip_unreachable {
            return false;
        }
        match traj::waypoints::reach(&self.robot_tool, to) {
            Err(e @ kinema::Error::Unreachable { .. }) => {
                self.skipped(s, &e);
                true
            }
            _ => false,
        }
    }

    fn ptp_to(&mut self, s: &Stmt, q_to: Vec<f64>, duration: Option<f64>, text: String) {
        if let Err(e) = self.robot.check_q(&q_to) {
            self.err(Diagnostic::error(s.span.clone(), e.to_string()));
            return;
        }
        if let Some(m) = outside_limits(self.robot, &q_to) {
            self.err(Diagnostic::error(s.span.clone(), format!("the target puts {m}")));
            return;
        }
        let kw = keyword_of(&s.kind).to_string();
        let t0 = self.traj.times().last().copied().unwrap_or(0.0);
        let from = self.q.clone();
        let profile = self.profile;
        let j = match duration {
            // Exactly the stated time; the trajectory check reports any limit it breaks.
            Some(t) => {
                let Some(law) = self.law_for(s, profile, t) else { return };
                let laws = vec![law; from.len()];
                self.sample_laws(s, &from, &q_to, &laws)
            }
            None => {
                let o = match self.ptp_options(profile, &from, &q_to) {
                    Ok(o) => o,
                    Err(message) => {
                        self.err(Diagnostic::error(s.span.clone(), format!("{kw}: {message}")));
                        return;
                    }
                };
                let planned = Ptp::new(self.robot, &from, &q_to, &o);
                // Against the program's cap before sampling (a count that cannot be is
                // sample_unchecked's error, reported below).
                let count = planned.as_ref().ok().and_then(|p| traj::sample_count(p.duration(), self.opts.dt).ok());
                if count.is_some_and(|count| !self.room_for(s.span.clone(), count)) {
                    return;
                }
                match planned.and_then(|p| p.sample_unchecked(self.opts.dt)) {
                    Ok(j) => Some(j),
                    Err(e) => {
                        self.err(Diagnostic::error(s.span.clone(), format!("{kw}: {e}")).with_hint(if kw == "HOME" {
                            "give HOME a duration (`HOME 3s`) or set joint limits with JVEL and JACC".to_string()
                        } else {
                            format!(
                                "give the motion a duration (`{kw} … IN 2s`) or set joint limits with JVEL and JACC"
                            )
                        }));
                        return;
                    }
                }
            }
        };
        let Some(j) = j else { return };
        let end = t0 + j.times().last().copied().unwrap_or(0.0);
        if profile == Profile::Linear {
            self.velocity_steps.push((t0, end, from.iter().zip(&q_to).map(|(a, b)| a != b).collect()));
        }
        self.record(s, &kw, t0, end, profile.name(), text);
        self.append(&j, t0);
    }

    /// PTP limits per joint: JVEL/JACC for the joint's kind, capped by the
    /// robot's own limit, else the robot's; the ACC override scales the
    /// accelerations. An S-curve needs jerk limits: without the robot's, a
    /// joint's jerk is 10 × its acceleration per second (full acceleration
    /// reached in 0.1 s).
    fn ptp_options(&self, profile: Profile, from: &[f64], to: &[f64]) -> std::result::Result<PtpOptions, String> {
        let pick = |given: &[Option<f64>; 2], own: Option<f64>, prismatic: bool| -> Option<f64> {
            match (given[usize::from(prismatic)], own) {
                (Some(g), Some(o)) => Some(g.min(o)),
                (Some(g), None) => Some(g),
                (None, o) => o,
            }
        };
        let joints = self.robot.joints();
        let (mut vel, mut acc) = (Vec::with_capacity(joints.len()), Vec::with_capacity(joints.len()));
        for (i, j) in joints.iter().enumerate() {
            let prismatic = j.kind == kinema::JointType::Prismatic;
            let v = pick(&self.jvel, j.limits.vel, prismatic);
            let a = pick(&self.jacc, j.limits.acc, prismatic).map(|a| a * self.acc_override);
            let moves = to[i] != from[i];
            for (value, what) in [(v, "JVEL"), (a, "JACC")] {
                if value.is_none() && moves {
                    let unit = if prismatic { "mm/s" } else { "deg/s" };
                    let unit = if what == "JACC" { format!("{unit}^2") } else { unit.to_string() };
                    return Err(format!(
                        "joint {} ({}) moves but neither the robot model nor the program gives it {}; set one with `{what} <value> {unit}` or give the motion a duration",
                        i + 1,
                        j.name,
                        if what == "JVEL" { "a speed limit" } else { "an acceleration limit" }
                    ));
                }
            }
            // A joint that does not move needs no limit; any positive value does.
            vel.push(v.unwrap_or(1.0));
            acc.push(a.unwrap_or(1.0));
        }
        let jerk =
            joints.iter().zip(&acc).map(|(j, a)| j.limits.jerk.map_or(10.0 * a, |x| x * self.acc_override)).collect();
        Ok(PtpOptions { profile, vel: Some(vel), acc: Some(acc), jerk: Some(jerk), speed: self.speed, duration: None })
    }

    fn law_for(&mut self, s: &Stmt, profile: Profile, t: f64) -> Option<TimeLaw> {
        match TimeLaw::from_duration(profile, t) {
            Ok(l) => Some(l),
            Err(e) => {
                self.err(Diagnostic::error(s.span.clone(), e.to_string()));
                None
            }
        }
    }

    /// The sample times of the statement at `span`, lasting `duration` \[s\]; an error there
    /// when they are too many to hold (a `WAIT` of years, say), never a silent skip, and
    /// checked against the program's cap before any sample of the motion is computed.
    fn sample_times(&mut self, span: crate::lexer::Span, duration: f64) -> Option<Vec<f64>> {
        match traj::sample_times(duration, self.opts.dt) {
            Ok(times) => self.room_for(span, times.len()).then_some(times),
            Err(e) => {
                self.err(Diagnostic::error(span, e.to_string()).with_hint("shorten it or raise dt".to_string()));
                None
            }
        }
    }

    /// Joint i goes from `from[i]` to `to[i]` with `laws[i]` (all of one duration).
    fn sample_laws(&mut self, s: &Stmt, from: &[f64], to: &[f64], laws: &[TimeLaw]) -> Option<JointTrajectory> {
        let duration = laws[0].duration();
        let times = self.sample_times(s.span.clone(), duration)?;
        let n = from.len();
        let mut j = match JointTrajectory::reserved(n, times.len()) {
            Ok(j) => j,
            Err(e) => {
                self.err(Diagnostic::error(s.span.clone(), e.to_string()));
                return None;
            }
        };
        let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for &t in &times {
            for i in 0..n {
                let st = laws[i].at(t);
                let d = to[i] - from[i];
                q[i] = from[i] + st.s * d;
                qd[i] = st.sd * d;
                qdd[i] = st.sdd * d;
            }
            j.push(t, &q, &qd, &qdd).ok()?;
        }
        Some(j)
    }

    /// Seed 003's relative moves: `delta` = [dx, dy, dz, dα] of the tool.
    fn scara_relative(&mut self, s: &Stmt, delta: [f64; 4], t: f64, kw: &str) {
        let ik = match &self.scara {
            Scara::Solver(ik) => Rc::clone(ik),
            // Other robots are refused before running.
            Scara::No => return,
            Scara::ToolRefused(why) => {
                let why = why.clone();
                self.err(
                    Diagnostic::error(
                        s.span.clone(),
                        format!("{kw} needs the SCARA's closed-form IK, which cannot take {why}"),
                    )
                    .with_hint("a SCARA tool may be offset and turned about z, not tilted; or move with PTP"),
                );
                return;
            }
        };
        let pose = self.current_pose();
        let alpha = pose.rot[(1, 0)].atan2(pose.rot[(0, 0)]);
        let target = [pose.pos.x + delta[0], pose.pos.y + delta[1], pose.pos.z + delta[2], alpha + delta[3]];
        let q_to = if delta[0] == 0.0 && delta[1] == 0.0 {
            // Z and θ alone: only joint 4 (z) or 5 (θ) moves, as the seed's linear law does.
            let mut q = self.q.clone();
            if delta[2] != 0.0 {
                let dzdq = self.dz_dq4();
                q[3] += delta[2] / dzdq;
            }
            q[4] += delta[3];
            q
        } else {
            let typed = IkTarget::PositionAlpha { position: [target[0], target[1], target[2]], alpha: target[3] };
            // The request every door makes, so the point is held to the contract and picked alike.
            let request = ik::IkRequest { q0: Some(&self.q), ..Default::default() };
            let robot = &self.robot_tool;
            let solved = ik::solve_target_with(robot, Some(&*ik), &typed, &request)
                .and_then(|answer| ik::pick_one(robot, answer.solver, answer.solutions, Some(&self.q)));
            match solved {
                Ok(sol) => {
                    let mut q = sol.q;
                    // Keep θ continuous: the nearest equivalent of q5 to the present one.
                    while q[4] - self.q[4] > PI {
                        q[4] -= 2.0 * PI;
                    }
                    while self.q[4] - q[4] > PI {
                        q[4] += 2.0 * PI;
                    }
                    q
                }
                Err(e @ kinema::Error::Unreachable { .. }) if self.opts.skip_unreachable => {
                    self.skipped(s, &e);
                    return;
                }
                Err(e) => {
                    self.err(
                        Diagnostic::error(s.span.clone(), format!("{kw} to ({:.4}, {:.4}) m is unreachable: {e}", target[0], target[1]))
                            .with_hint("seed 003 skips points outside the workspace: run with skip-unreachable (`kinema run --skip-unreachable`) to do the same"),
                    );
                    return;
                }
            }
        };
        let text = format!(
            "tool ({}) m, θ {} rad",
            fmt_xyz(&Vector3::new(target[0], target[1], target[2])),
            fmt_angle(target[3])
        );
        self.scara_move(s, q_to, t, kw, text);
    }

    /// ∂z/∂q4 of the tool (the vertical axis is linear in q4).
    fn dz_dq4(&self) -> f64 {
        let mut q = self.q.clone();
        let z0 = self.current_pose().pos.z;
        q[3] += 0.01;
        let z1 = self.robot_tool.fk(&q).map(|f| f.world_from_tool.pos.z).unwrap_or(z0 - 0.01);
        (z1 - z0) / 0.01
    }

    /// Seed 003 §III-D: joints 1–3 (rail, shoulder, elbow: the XY plane) and the
    /// wrist's compensation of them follow a cubic; z and θ alone follow a
    /// linear law. Lasts exactly `t`.
    fn scara_move(&mut self, s: &Stmt, q_to: Vec<f64>, t: f64, kw: &str, text: String) {
        if let Some(m) = outside_limits(self.robot, &q_to) {
            self.err(Diagnostic::error(s.span.clone(), format!("{kw} puts {m}")));
            return;
        }
        let (Some(cubic), Some(linear)) = (self.law_for(s, Profile::Cubic, t), self.law_for(s, Profile::Linear, t))
        else {
            return;
        };
        let xy_moves = (0..3).any(|i| q_to[i] != self.q[i]);
        let laws: Vec<TimeLaw> = (0..5).map(|i| if i < 3 || (i == 4 && xy_moves) { cubic } else { linear }).collect();
        let from = self.q.clone();
        let Some(j) = self.sample_laws(s, &from, &q_to, &laws) else { return };
        let t0 = self.traj.times().last().copied().unwrap_or(0.0);
        let profile = match (xy_moves, kw) {
            (true, "HOME") => "cubic + linear (z)",
            (true, _) => "cubic",
            (false, _) => "linear",
        };
        let linear: Vec<bool> = (0..5).map(|i| laws[i].profile() == Profile::Linear && q_to[i] != from[i]).collect();
        self.velocity_steps.push((t0, t0 + t, linear));
        self.record(s, kw, t0, t0 + t, profile, text);
        self.append(&j, t0);
    }

    /// The trajectory check; each violation at the line of its motion.
    fn check_trajectory(&mut self) {
        let report = match traj::check(self.robot, &self.traj, &CheckOptions::default()) {
            Ok(r) => r,
            Err(e) => {
                self.err(Diagnostic::error(0..0, format!("trajectory check: {e}")));
                return;
            }
        };
        let mut seen = HashSet::new();
        let last = self.plan_motions.len().saturating_sub(1);
        // Within a sample of a linear motion's ends, an acceleration finding of
        // its joints is the law's velocity step (as `Ptp::sample` exempts it).
        let margin = self.opts.dt + 1e-9;
        let steps = std::mem::take(&mut self.velocity_steps);
        let stepped = |v: &traj::Violation| {
            matches!(
                v.kind,
                traj::ViolationKind::Acceleration | traj::ViolationKind::Jerk | traj::ViolationKind::Inconsistent
            ) && v.joint.is_some_and(|j| {
                // Motions follow one another: their steps are in time order, so
                // only those around v.time are looked at.
                let from = steps.partition_point(|(_, b, _)| *b + margin < v.time);
                steps[from..].iter().take_while(|(a, ..)| *a - margin <= v.time).any(|(_, _, js)| js[j])
            })
        };
        for v in report.violations.into_iter().filter(|v| !stepped(v)) {
            // The first motion with start < t ≤ end (starts and ends never decrease).
            let k = self.plan_motions.partition_point(|m| m.end + 1e-12 < v.time);
            let k = if self.plan_motions.get(k).is_some_and(|m| v.time > m.start - 1e-12) { k } else { last };
            // A jump is the velocity excess seen between two samples: one report per joint and motion.
            let kind = if v.kind == traj::ViolationKind::Jump { traj::ViolationKind::Velocity } else { v.kind };
            if !seen.insert((k, v.joint, kind as u8)) {
                continue;
            }
            let span = self.motion_spans.get(k).cloned().unwrap_or(0..0);
            let joint = v.joint.map(|j| format!(" ({})", self.robot.joints()[j].name)).unwrap_or_default();
            let (what, hint) = if kind == traj::ViolationKind::BranchJump {
                ("the joints jump", "the inverse kinematics changed branch between two samples: start the motion from a configuration on its branch, or add a via point")
            } else {
                ("limit violated", "slow the motion down (SPEED, VEL, ACC or a longer IN/time) or move the target")
            };
            self.err(Diagnostic::error(span, format!("{what}{joint}: {v}")).with_hint(hint));
        }
    }
}

/// "joint i (name) at v, outside its limits [min, max]" for the first joint of
/// `q` outside its limits.
fn outside_limits(robot: &Robot, q: &[f64]) -> Option<String> {
    let i = robot.limit_flags(q).indices().next()?;
    let j = &robot.joints()[i];
    Some(format!(
        "joint {} ({}) at {:.6}, outside its limits [{:.6}, {:.6}]",
        i + 1,
        j.name,
        q[i],
        j.limits.min,
        j.limits.max
    ))
}

/// Largest FOR bound: beyond 2⁵³ adding 1 to an `f64` may leave it unchanged.
const MAX_EXACT: f64 = 9_007_199_254_740_992.0;

/// How many passes `FOR i = a TO b` makes (0 when b < a).
fn for_passes(a: f64, b: f64) -> f64 {
    if b < a {
        0.0
    } else {
        b - a + 1.0
    }
}

/// A value known at check time (FOR counters are NaN there) that fails `ok`.
fn known_bad(v: f64, ok: impl Fn(f64) -> bool) -> bool {
    !v.is_nan() && !ok(v)
}

/// The statement keyword, for messages.
fn keyword_of(k: &StmtKind) -> &'static str {
    match k {
        StmtKind::Pos { .. } => "POS",
        StmtKind::Motion { kind: MotionKind::Ptp, .. } => "PTP",
        StmtKind::Motion { kind: MotionKind::Lin, .. } => "LIN",
        StmtKind::Circ { .. } => "CIRC",
        StmtKind::Speed(_) => "SPEED",
        StmtKind::Vel(_) => "VEL",
        StmtKind::Acc(_) => "ACC",
        StmtKind::JVel(_) => "JVEL",
        StmtKind::JAcc(_) => "JACC",
        StmtKind::Profile(_) => "PROFILE",
        StmtKind::Redundancy { .. } => "REDUNDANCY",
        StmtKind::Tool(_) => "TOOL",
        StmtKind::Base(_) => "BASE",
        StmtKind::Wait(_) => "WAIT",
        StmtKind::Home(_) => "HOME",
        StmtKind::Loop { .. } => "LOOP",
        StmtKind::For { .. } => "FOR",
        StmtKind::MoveZ { .. } => "MOVEZ",
        StmtKind::MoveTita { .. } => "MOVETITA",
        StmtKind::MoveXy { .. } => "MOVEXY",
    }
}

fn parse_profile(key: &str) -> Option<Profile> {
    match key {
        "trapezoid" | "trapezoidal" => Some(Profile::Trapezoid),
        "scurve" | "s-curve" => Some(Profile::SCurve),
        "quintic" => Some(Profile::Quintic),
        "cubic" => Some(Profile::Cubic),
        _ => None,
    }
}

fn joint_dim(robot: &Robot, i: usize) -> Dim {
    match robot.joints().get(i).map(|j| j.kind) {
        Some(kinema::JointType::Prismatic) => Dim::Length,
        _ => Dim::Angle,
    }
}

fn joint_example(robot: &Robot) -> String {
    robot
        .joints()
        .iter()
        .map(|j| if j.kind == kinema::JointType::Prismatic { "0mm" } else { "0deg" })
        .collect::<Vec<_>>()
        .join(", ")
}

/// A value to 4 decimals, the same on every machine: no `-0.0000`.
fn fmt4(v: f64) -> String {
    if v.abs() < 5e-5 {
        "0.0000".into()
    } else {
        format!("{v:.4}")
    }
}

/// An angle to 4 decimals in (−π, π], −π shown as π (rounding decides between them).
fn fmt_angle(a: f64) -> String {
    let a = ik::wrap_angle(a);
    fmt4(if a < -PI + 5e-5 { a + 2.0 * PI } else { a })
}

fn fmt_xyz(p: &Vector3<f64>) -> String {
    format!("{}, {}, {}", fmt4(p.x), fmt4(p.y), fmt4(p.z))
}

fn fmt_joints(q: &[f64]) -> String {
    q.iter().map(|v| fmt4(*v)).collect::<Vec<_>>().join(", ")
}

fn describe_pose(p: &Pose) -> String {
    let r = p.rpy(RpyConvention::Zyx);
    format!("xyz ({}) m, rpy ({}, {}, {}) rad", fmt_xyz(&p.pos), fmt_angle(r[0]), fmt_angle(r[1]), fmt_angle(r[2]))
}

/// Evaluates an expression to SI with its dimension.
pub(crate) fn eval(e: &Expr, counters: &HashMap<String, f64>) -> Result<Quantity, Diagnostic> {
    match e {
        Expr::Num { value, unit: None, .. } => Ok(Quantity { value: *value, dim: Dim::None }),
        Expr::Num { value, unit: Some(u), span } => match unit(u) {
            Some((scale, dim)) => Ok(Quantity { value: value * scale, dim }),
            None => Err(Diagnostic::error(span.clone(), format!("unknown unit `{u}`"))),
        },
        Expr::Var(name) => match counters.get(&name.key) {
            Some(v) => Ok(Quantity { value: *v, dim: Dim::None }),
            None => Err(Diagnostic::error(name.span.clone(), format!("unknown name `{}` in an expression", name.text))
                .with_hint("only FOR counters can be used in expressions; numbers need their unit, e.g. 50mm")),
        },
        Expr::Neg(inner, _) => {
            let q = eval(inner, counters)?;
            Ok(Quantity { value: -q.value, dim: q.dim })
        }
        Expr::Bin { op, lhs, rhs, span } => {
            let (a, b) = (eval(lhs, counters)?, eval(rhs, counters)?);
            let mismatch =
                |what: &str| Diagnostic::error(span.clone(), format!("cannot {what} {} and {}", a.dim, b.dim));
            match op {
                BinOp::Add | BinOp::Sub => {
                    if a.dim != b.dim {
                        return Err(mismatch(if *op == BinOp::Add { "add" } else { "subtract" })
                            .with_hint("both sides need the same kind of unit, e.g. 50mm + 2cm"));
                    }
                    let value = if *op == BinOp::Add { a.value + b.value } else { a.value - b.value };
                    Ok(Quantity { value, dim: a.dim })
                }
                BinOp::Mul => match (a.dim, b.dim) {
                    (Dim::None, d) | (d, Dim::None) => Ok(Quantity { value: a.value * b.value, dim: d }),
                    _ => Err(mismatch("multiply").with_hint("one side of * must be a plain number")),
                },
                BinOp::Div => {
                    if b.value == 0.0 {
                        return Err(Diagnostic::error(span.clone(), "division by zero"));
                    }
                    match (a.dim, b.dim) {
                        (d, Dim::None) => Ok(Quantity { value: a.value / b.value, dim: d }),
                        (x, y) if x == y => Ok(Quantity { value: a.value / b.value, dim: Dim::None }),
                        _ => Err(mismatch("divide")),
                    }
                }
            }
        }
    }
}

/// A quantity as a value of dimension `dim` (see [`Compiler::static_expect`]).
fn coerce(q: Quantity, dim: Dim, default_scale: Option<f64>, e: &Expr) -> Result<f64, Diagnostic> {
    if q.dim == dim {
        return Ok(q.value);
    }
    if q.dim == Dim::None {
        if let Some(scale) = default_scale {
            return Ok(q.value * scale);
        }
        if dim == Dim::None || q.value == 0.0 {
            return Ok(q.value);
        }
        let example = match dim {
            Dim::Length => "50mm or 0.05m",
            Dim::Angle => "30deg or 0.5rad",
            Dim::Time => "2s",
            Dim::Percent => "50%",
            Dim::LinVel => "250mm/s",
            Dim::AngVel => "90deg/s",
            Dim::LinAcc => "1m/s^2",
            Dim::AngAcc => "180deg/s^2",
            Dim::None => "",
        };
        return Err(Diagnostic::error(e.span(), format!("missing unit: expected {dim}"))
            .with_hint(format!("write e.g. {example}")));
    }
    Err(Diagnostic::error(e.span(), format!("expected {dim}, found {}", q.dim)))
}
