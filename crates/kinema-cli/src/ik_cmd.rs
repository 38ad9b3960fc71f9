//! `kinema ik`: inverse kinematics from the command line.

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use kinema::ik::{IkSolver, NumericIk, NumericOptions, Solution, Solutions};
use kinema::nalgebra::{Matrix4, Vector3};
use kinema::{Error, Pose, Robot, RpyConvention};
use serde_json::{json, Value};

use crate::{print_json, Exit, RobotArg, RpyArg};

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SolverArg {
    /// The robot's analytic solver when it has one, else numeric.
    Auto,
    /// The robot's analytic solver (an error if it has none).
    Analytic,
    /// Damped least squares with seeded restarts (any robot).
    Numeric,
}

#[derive(Args)]
pub struct IkArgs {
    #[command(flatten)]
    robot: RobotArg,
    /// Target as a 4×4 homogeneous matrix, 16 numbers row-major (m).
    #[arg(long = "T", allow_hyphen_values = true, conflicts_with_all = ["pose", "position"])]
    t: Option<String>,
    /// Target as x,y,z,roll,pitch,yaw (m, rad; degrees with --deg).
    #[arg(long, allow_hyphen_values = true, conflicts_with = "position")]
    pose: Option<String>,
    /// Target position x,y,z (m) only; orientation free.
    #[arg(long, allow_hyphen_values = true)]
    position: Option<String>,
    /// Roll-pitch-yaw convention of --pose.
    #[arg(long, value_enum, default_value = "zyx")]
    rpy: RpyArg,
    /// Which solver.
    #[arg(long, value_enum, default_value = "auto")]
    solver: SolverArg,
    /// Print every solution found (default: one, nearest to --q0 when given).
    #[arg(long)]
    all: bool,
    /// Previous / initial configuration (comma-separated or a named pose).
    #[arg(long, allow_hyphen_values = true)]
    q0: Option<String>,
    /// Angles in --pose, --q0 and the printed solutions are in degrees.
    #[arg(long)]
    deg: bool,
    /// Seed of the numeric solver's restarts.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

fn numbers(text: &str, what: &str, count: usize) -> Result<Vec<f64>> {
    let v: Vec<f64> = text
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .map(|s| s.parse::<f64>().with_context(|| format!("{what}: `{s}` is not a number")))
        .collect::<Result<_>>()?;
    if v.len() != count {
        bail!("{what} needs {count} numbers, got {}", v.len());
    }
    if let Some(x) = v.iter().find(|x| !x.is_finite()) {
        bail!("{what} contains {x}; all values must be finite");
    }
    Ok(v)
}

/// The target pose and which task components it constrains.
fn target(a: &IkArgs, robot: &Robot) -> Result<(Pose, Option<[bool; 6]>)> {
    let ang = |v: f64| if a.deg { v.to_radians() } else { v };
    if let Some(t) = &a.t {
        let v = numbers(t, "--T", 16)?;
        let m = Matrix4::from_row_slice(&v);
        let pose = Pose::from_matrix(&m)
            .context("--T is not a rigid transform: the last row must be 0 0 0 1 and the 3×3 block a rotation")?;
        return Ok((pose, None));
    }
    if let Some(p) = &a.pose {
        let v = numbers(p, "--pose", 6)?;
        let conv: RpyConvention = a.rpy.into();
        return Ok((Pose::from_xyz_rpy([v[0], v[1], v[2]], [ang(v[3]), ang(v[4]), ang(v[5])], conv), None));
    }
    if let Some(p) = &a.position {
        let v = numbers(p, "--position", 3)?;
        let fk = robot.fk(robot.home())?;
        // Orientation is free: keep home's rotation as a placeholder, masked out.
        return Ok((
            Pose::new(fk.pose.rot, Vector3::new(v[0], v[1], v[2])),
            Some([true, true, true, false, false, false]),
        ));
    }
    bail!("give a target: --T \"16 numbers\", --pose x,y,z,roll,pitch,yaw or --position x,y,z")
}

fn solution_json(robot: &Robot, s: &Solution, deg: bool) -> Value {
    let q: Vec<f64> =
        s.q.iter()
            .zip(robot.joints())
            .map(|(v, j)| if deg && j.kind == kinema::JointType::Revolute { v.to_degrees() } else { *v })
            .collect();
    let mut v = json!({
        "q": q,
        "branch": s.branch,
        "within_limits": s.within_limits(),
        "position_error": s.position_error,
        "orientation_error": s.orientation_error,
    });
    if let Some(n) = s.numeric {
        v["iterations"] = json!(n.iterations);
        v["restarts"] = json!(n.restarts);
        v["stop"] = json!(n.stop.to_string());
    }
    v
}

pub fn ik(a: IkArgs) -> Result<()> {
    let robot = a.robot.load()?;
    let (pose, mask) = target(&a, &robot)?;
    let q0 = a.q0.as_deref().map(|t| robot.parse_q(t, a.deg)).transpose()?;
    if a.solver == SolverArg::Analytic {
        bail!("robot `{}` has no analytic solver yet; use --solver numeric", robot.name());
    }
    let opts = NumericOptions { seed: a.seed, mask, ..Default::default() };
    let solver = NumericIk::with_options(&robot, opts)?;
    let result = match &q0 {
        Some(q0) => solver.solve_from(&pose, q0).map(|s| vec![s]),
        None => solver.solve(&pose),
    };
    let solutions = match result {
        Ok(s) => s,
        Err(Error::Unreachable { solver, reason }) => {
            if a.json {
                print_json(&json!({"error": "unreachable", "solver": solver, "reason": reason.to_string()}))?;
            } else {
                eprintln!("error: unreachable target ({solver} solver): {reason}");
            }
            return Err(Exit(2).into());
        }
        Err(e) => return Err(e.into()),
    };
    let chosen: Vec<&Solution> = if a.all {
        solutions.iter().collect()
    } else {
        let pick = match &q0 {
            Some(q0) => solutions.nearest(&robot, q0),
            None => solutions.iter().find(|s| s.within_limits()).or(solutions.first()),
        };
        pick.into_iter().collect()
    };
    if a.json {
        let list: Vec<Value> = chosen.iter().map(|s| solution_json(&robot, s, a.deg)).collect();
        return print_json(&json!({"robot": robot.name(), "solver": solver.name(), "solutions": list}));
    }
    println!("robot {}  solver {}  {} solution(s)", robot.name(), solver.name(), chosen.len());
    for s in chosen {
        let unit = if a.deg { "deg/m" } else { "rad/m" };
        let q: Vec<String> =
            s.q.iter()
                .zip(robot.joints())
                .map(|(v, j)| {
                    format!("{:.6}", if a.deg && j.kind == kinema::JointType::Revolute { v.to_degrees() } else { *v })
                })
                .collect();
        println!("  [{}] ({unit})  branch {}", q.join(", "), s.branch);
        println!(
            "    residual {:.3e} m, {:.3e} rad; {}{}",
            s.position_error,
            s.orientation_error,
            if s.within_limits() { "within limits" } else { "OUTSIDE joint limits" },
            s.numeric.map_or(String::new(), |n| format!(
                "; {} iterations, {} restarts, {}",
                n.iterations, n.restarts, n.stop
            ))
        );
    }
    Ok(())
}
