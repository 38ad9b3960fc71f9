//! From a syntax tree to a motion plan: a static check (names, units,
//! argument counts, what the robot can do), then execution of the program
//! on a model of the robot — inverse kinematics for every target, a time law
//! for every motion, samples every `dt` — and the trajectory check, whose
//! violations are reported at the line of the motion that caused them.

mod avoid;
mod cart;
mod check;
mod eval;
mod exec;
mod ptp;
mod samples;
mod scara;
mod settings;
mod target;
mod text;
mod trajectory_check;

use std::collections::{HashMap, HashSet};
use std::f64::consts::PI;
use std::sync::Arc;

use kinema::ik::Admissible;
use kinema::math::Pose;
use kinema::traj::{CartesianLimits, CartesianMotion, JointTrajectory, Profile, SelfMotion};
use kinema::Robot;

use crate::diag::{Diagnostic, LineIndex};
use crate::lexer::Span;
use crate::planner::PathPlanner;
use crate::stop::Stop;

use self::cart::Chain;
use self::check::Scope;
use self::scara::Scara;
use self::trajectory_check::outside_limits;

/// How a program is compiled.
#[derive(Debug, Clone)]
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
    /// A test every configuration of the finished trajectory must pass (a
    /// scene's collision check: samples and the steps between them), each
    /// refused stretch reported at the line of its motion.
    pub admissible: Option<Arc<dyn Admissible>>,
    /// The planner of `PTP … AVOID` (given with `admissible`, on the same
    /// shapes): a PTP whose straight motion collides follows its path.
    /// Without one, AVOID warns and the motion stays straight.
    pub planner: Option<Arc<dyn PathPlanner>>,
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
            admissible: None,
            planner: None,
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

/// A named position's value.
#[derive(Debug, Clone)]
enum PosValue {
    Joint(Vec<f64>),
    /// A pose in the world frame (the BASE in force when it was declared applied).
    Cart(Pose),
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
            scara: Scara::fit(robot),
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
}
