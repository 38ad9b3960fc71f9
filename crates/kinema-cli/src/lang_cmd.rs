//! `kinema check | run | compile PROGRAM`: the robot programming language.

use crate::stdout::{out, outln};
use std::path::PathBuf;
use std::time::Duration;

use anyhow::Result;
use clap::Args;
use kinema::RpyConvention;
use kinema_lang::{render_all, Options, Plan, Stop};
use serde_json::json;

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
    /// loop pass reached); no limit by default. Ctrl-C stops it at any time.
    #[arg(long, value_name = "SECONDS")]
    pub(crate) time_limit: Option<f64>,
    /// Skip motions to targets out of reach, with a warning each (seed 003 Fig. 9: the
    /// generated trajectory leaves out a point outside the workspace), instead of failing.
    #[arg(long)]
    pub(crate) skip_unreachable: bool,
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

/// Reads, compiles, prints the diagnostics; the plan, or exit code 1.
pub(crate) fn build(a: &ProgramArgs) -> Result<(Plan, String)> {
    let robot = a.robot.load()?;
    let src = crate::input::read_text_limited(&a.program, crate::input::MAX_TEXT_BYTES, "program")?;
    let start = match &a.start {
        Some(text) => Some(crate::input::parse_q(&robot, text, false)?),
        None => None,
    };
    let mut stop = match a.time_limit {
        Some(s) if s.is_finite() && s >= 0.0 => Stop::after(Duration::from_secs_f64(s)),
        Some(s) => anyhow::bail!("--time-limit must be a number of seconds ≥ 0, not {s}"),
        None => Stop::never(),
    };
    // The first Ctrl-C asks the program to stop (it reports where); a second one
    // ends the process at once.
    let _cancellable = crate::interrupt::cancellable();
    stop = stop.with_flag(crate::interrupt::flag());
    let opts = Options { dt: a.dt, start, stop, skip_unreachable: a.skip_unreachable, ..Options::default() };
    let name = a.program.display().to_string();
    match kinema_lang::compile(&src, &robot, &opts) {
        Ok(plan) => {
            if !plan.warnings.is_empty() {
                eprint!("{}", render_all(&plan.warnings, &name, &src));
            }
            check_interrupted()?;
            Ok((plan, name))
        }
        Err(diags) => {
            eprint!("{}", render_all(&diags, &name, &src));
            check_interrupted()?;
            Err(Exit(1).into())
        }
    }
}

pub fn check(a: ProgramArgs) -> Result<()> {
    let (plan, name) = build(&a)?;
    outln!("{name}: ok on `{}` — {} motion(s), {:.4} s", plan.robot.name(), plan.motions.len(), plan.duration())?;
    Ok(())
}

fn summary(plan: &Plan) -> Result<serde_json::Value> {
    let q = plan.final_q().to_vec();
    let pose = plan.robot.fk(&q)?.world_from_tool;
    Ok(json!({
        "duration": plan.duration(),
        "motions": plan.motions.len(),
        "samples": plan.trajectory.len(),
        "final_q": q,
        "final_pose": {
            "xyz": [pose.pos.x, pose.pos.y, pose.pos.z],
            "rpy": pose.rpy(RpyConvention::Zyx),
            "T": pose.to_matrix().row_iter().map(|r| r.iter().copied().collect::<Vec<f64>>()).collect::<Vec<_>>(),
        },
    }))
}

pub fn run(a: RunArgs) -> Result<()> {
    if a.json && crate::output::is_stdout(&a.out) {
        anyhow::bail!("--json with --out -: the JSON summary and the CSV would both go to standard output; write the CSV to a file");
    }
    let (plan, _) = build(&a.program)?;
    let robot = &plan.robot;
    let conv = RpyConvention::Zyx;
    let rows = traj_cmd::table(robot, &plan.trajectory, conv)?;
    // Ctrl-C while the table was computed: still nothing written.
    check_interrupted()?;
    write_atomically(&a.out, |w| {
        let mut w = csv::Writer::from_writer(w);
        w.write_record(traj_cmd::header(robot.dof(), conv))?;
        for row in &rows {
            w.write_record(row.iter().map(|v| format!("{v:.12}")))?;
        }
        w.flush()?;
        Ok(())
    })?;
    eprintln!("wrote {} samples ({:.4} s) to {}", rows.len(), plan.duration(), a.out.display());
    if a.json {
        print_json(&summary(&plan)?)?;
    }
    Ok(())
}

pub fn compile(a: CompileArgs) -> Result<()> {
    let (plan, name) = build(&a.program)?;
    if a.json {
        let motions: Vec<_> = plan
            .motions
            .iter()
            .map(|m| json!({"line": m.line, "kind": m.kind, "start": m.start, "end": m.end, "profile": m.profile, "target": m.target}))
            .collect();
        let mut s = summary(&plan)?;
        s["plan"] = json!(motions);
        return print_json(&s);
    }
    if a.listing {
        outln!("# {name}")?;
        out!("{}", plan.listing())?;
    } else {
        outln!("{name}: {} motion(s), {:.4} s (use --listing for the plan)", plan.motions.len(), plan.duration())?;
    }
    Ok(())
}
