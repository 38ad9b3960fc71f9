//! `kinema check | run | compile PROGRAM`: the robot programming language.

use crate::stdout::{out, outln};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use anyhow::Result;
use clap::Args;
use kinema::RpyConvention;
use kinema_io::ProgramAnswer;
use kinema_lang::{render_all, Options, Plan, Stop};

use crate::{print_json, traj_cmd, write_atomically, Exit, RobotArg};

#[derive(Args)]
pub struct ProgramArgs {
    /// The program file (any name or extension).
    pub(crate) program: PathBuf,
    #[command(flatten)]
    pub(crate) robot: RobotArg,
    /// Sample period of the joint signals [s].
    #[arg(long, default_value_t = 0.01)]
    pub(crate) dt: f64,
    /// Joint values at the start (rad and m, comma-separated, or a named pose); default `home`.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) start: Option<String>,
    /// Stop the program after this many seconds, wall clock (an error at the statement or
    /// loop pass reached); `inf` for no limit. Ctrl-C stops it at any time.
    #[arg(long, value_name = "SECONDS", default_value_t = DEFAULT_TIME_LIMIT)]
    pub(crate) time_limit: f64,
    /// Skip motions to targets out of reach, with a warning each (seed 003 Fig. 9: the
    /// generated trajectory leaves out a point outside the workspace), instead of failing.
    #[arg(long)]
    pub(crate) skip_unreachable: bool,
    #[command(flatten)]
    pub(crate) body: crate::BodyArgs,
}

/// How long a program may compute by default \[s, wall clock\]: a bound on
/// every run, as the server's 10 s, that a long program lifts with `--time-limit`.
pub(crate) const DEFAULT_TIME_LIMIT: f64 = 120.0;

/// The stop of a program run: after `limit` seconds (`inf`: never) or on Ctrl-C.
pub(crate) fn program_stop(limit: f64) -> Result<Stop> {
    let stop = match limit {
        s if s == f64::INFINITY => Stop::never(),
        s if s.is_finite() && s >= 0.0 => Stop::after(Duration::from_secs_f64(s)),
        s => anyhow::bail!("--time-limit must be a number of seconds ≥ 0 (or `inf` for none), not {s}"),
    };
    Ok(stop.with_flag(crate::interrupt::flag()))
}

/// After a run stopped by its time budget: which option changes it.
pub(crate) fn note_time_limit(diags: &[kinema_lang::Diagnostic]) {
    if diags.iter().any(|d| d.message.contains("the time budget of")) {
        eprintln!("note: --time-limit sets the budget (default {DEFAULT_TIME_LIMIT} s; `inf` for none)");
    }
}

/// Whether Ctrl-C was pressed (the error to return then: nothing is written).
fn check_interrupted() -> Result<()> {
    if crate::interrupt::interrupted() {
        eprintln!("cancelled (Ctrl-C); nothing was written");
        return Err(Exit(crate::interrupt::EXIT_INTERRUPTED).into());
    }
    Ok(())
}

#[derive(Args)]
pub struct RunArgs {
    #[command(flatten)]
    program: ProgramArgs,
    /// Where to write the joint signals (CSV: t, q, q̇, q̈, tool pose, manipulability).
    #[arg(long)]
    out: PathBuf,
    /// Also print a JSON summary: duration, motions, final joints and tool pose.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
pub struct CompileArgs {
    #[command(flatten)]
    program: ProgramArgs,
    /// Print the motion plan: one line per motion with its source line, times, profile and target.
    #[arg(long)]
    listing: bool,
    /// Print the plan as JSON.
    #[arg(long)]
    json: bool,
}

/// A compiled program with the file name and text its diagnostics quote.
pub(crate) struct Compiled {
    pub(crate) plan: Plan,
    pub(crate) name: String,
    pub(crate) source: String,
}

impl Compiled {
    /// The answer of `run --json` and `compile --json` (the server's
    /// `/api/run` gives the same, with the samples).
    fn answer(&self) -> Result<ProgramAnswer> {
        Ok(ProgramAnswer::new(&self.plan, &self.name, &self.source)?)
    }
}

/// Reads, compiles, prints the diagnostics; the plan, or exit code 1.
pub(crate) fn build(a: &ProgramArgs) -> Result<Compiled> {
    let (robot, body) = a.body.robot_and_check(&a.robot)?;
    let src = crate::input::read_text_limited(&a.program, crate::input::MAX_TEXT_BYTES, "program")?;
    let start = match &a.start {
        Some(text) => Some(robot.parse_q(text, false)?),
        None => None,
    };
    // The first Ctrl-C asks the program to stop (it reports where); a second one
    // ends the process at once.
    let _cancellable = crate::interrupt::cancellable();
    let stop = program_stop(a.time_limit)?;
    let body = body.map(Arc::new);
    let admissible = body.clone().map(|c| c as Arc<dyn kinema::ik::Admissible>);
    let planner = body.map(|check| kinema_io::ScenePlanner::shared(check, Some(crate::interrupt::flag())));
    let opts = Options {
        dt: a.dt,
        start,
        stop,
        skip_unreachable: a.skip_unreachable,
        admissible,
        planner,
        ..Options::default()
    };
    let name = a.program.display().to_string();
    match kinema_lang::compile(&src, &robot, &opts) {
        Ok(plan) => {
            if !plan.warnings.is_empty() {
                eprint!("{}", render_all(&plan.warnings, &name, &src));
            }
            check_interrupted()?;
            Ok(Compiled { plan, name, source: src })
        }
        Err(diags) => {
            eprint!("{}", render_all(&diags, &name, &src));
            check_interrupted()?;
            note_time_limit(&diags);
            Err(Exit(1).into())
        }
    }
}

pub fn check(a: ProgramArgs) -> Result<()> {
    let Compiled { plan, name, .. } = build(&a)?;
    outln!("{name}: ok on `{}` — {} motion(s), {:.4} s", plan.robot.name(), plan.motions.len(), plan.duration())?;
    Ok(())
}

pub fn run(a: RunArgs) -> Result<()> {
    if a.json && crate::output::is_stdout(&a.out) {
        anyhow::bail!("--json with --out -: the JSON summary and the CSV would both go to standard output; write the CSV to a file");
    }
    let built = build(&a.program)?;
    let plan = &built.plan;
    let robot = &plan.robot;
    let conv = RpyConvention::Zyx;
    // Ctrl-C while the plan was made: still nothing written.
    check_interrupted()?;
    write_atomically(&a.out, |w| {
        traj_cmd::write_csv(w, &a.out.display().to_string(), robot, &plan.trajectory, conv, 12)
    })?;
    eprintln!("wrote {} samples ({:.4} s) to {}", plan.trajectory.len(), plan.duration(), a.out.display());
    if a.json {
        print_json(&built.answer()?)?;
    }
    Ok(())
}

pub fn compile(a: CompileArgs) -> Result<()> {
    let built = build(&a.program)?;
    if a.json {
        return print_json(&built.answer()?);
    }
    let Compiled { plan, name, .. } = built;
    if a.listing {
        outln!("# {name}")?;
        out!("{}", plan.listing())?;
    } else {
        outln!("{name}: {} motion(s), {:.4} s (use --listing for the plan)", plan.motions.len(), plan.duration())?;
    }
    Ok(())
}
