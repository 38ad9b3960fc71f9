//! `kinema ik`: inverse kinematics from the command line.

use crate::stdout::outln;
use anyhow::{bail, Context, Result};
use clap::Args;
use kinema::ik::{
    Admissible, Closest, IkAnswer, IkRequest, IkTarget, NumericOptions, Solution, SolverChoice, Tolerance,
};
use kinema::nalgebra::Matrix4;
use kinema::{Error, Pose, Robot, RpyConvention};
use kinema_io::{SelfMotionAnswer, UnreachableAnswer, ValidateAnswer};

use crate::{print_json, Exit, RobotArg};
use kinema::InputError;

pub(crate) mod batch;

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
    #[arg(long, default_value = "zyx", value_parser = crate::by_name::<RpyConvention>())]
    rpy: RpyConvention,
    /// Which solver.
    #[arg(long, default_value = "auto", value_parser = crate::by_name::<SolverChoice>())]
    solver: SolverChoice,
    /// Scorbot: pitch β of the tool (seed 000 eq. 13), with --position and --roll.
    #[arg(long, allow_hyphen_values = true, requires = "position")]
    pitch: Option<f64>,
    /// Scorbot: roll γ of the tool (seed 000 eq. 13), with --position and --pitch.
    #[arg(long, allow_hyphen_values = true, requires = "position")]
    roll: Option<f64>,
    /// ROMMEL: tool approach direction ax,ay,az, with --position.
    #[arg(long, allow_hyphen_values = true, requires = "position")]
    approach: Option<String>,
    /// SCARA: tool angle α = q2 + q3 + q5, with --position (the zone rule picks the rail).
    #[arg(long, allow_hyphen_values = true, requires = "position")]
    alpha: Option<f64>,
    /// iiwa-type (SRS) arms: solve with this fixed q3 (up to 8 closed-form solutions).
    #[arg(long, allow_hyphen_values = true, conflicts_with = "psi")]
    q3: Option<f64>,
    /// iiwa-type (SRS) arms, any description: solve at this arm angle ψ (one solution per configuration).
    #[arg(long, allow_hyphen_values = true)]
    psi: Option<f64>,
    /// Task mask for --T/--pose: which of x,y,z,ωx,ωy,ωz (world frame) must be met, six 0/1 values
    /// (e.g. 1,1,1,0,1,1 frees the rotation about the world z axis). Default: all six.
    #[arg(long, allow_hyphen_values = true, conflicts_with = "position")]
    mask: Option<String>,
    /// Position tolerance a solution must meet (m).
    #[arg(long, default_value_t = 1e-6)]
    tol_position: f64,
    /// Orientation tolerance a solution must meet (rad).
    #[arg(long, default_value_t = 1e-6)]
    tol_orientation: f64,
    /// Print every solution found (default: one, nearest to --q0 when given).
    #[arg(long, conflicts_with = "input")]
    all: bool,
    /// Batch: a CSV of targets, one per line: 16 numbers (a 4×4 matrix, row-major), 6 (x,y,z,roll,pitch,yaw
    /// as --pose) or 3 (a position); solved on all cores, one solution per line written to --output.
    #[arg(long, requires = "output", conflicts_with_all = ["t", "pose", "position", "pitch", "roll", "approach", "alpha", "q3", "psi"])]
    input: Option<std::path::PathBuf>,
    /// Batch: where to write the solutions (CSV; written in full or not at all).
    #[arg(long, requires = "input")]
    output: Option<std::path::PathBuf>,
    /// Batch: solve only shard i of n (`2/4`: the second of four contiguous blocks of the input's
    /// targets); the shards' outputs, concatenated in order, are the unsharded output byte for byte.
    #[arg(long, requires = "input")]
    shard: Option<kinema_io::Shard>,
    /// Previous / initial configuration (comma-separated or a named pose).
    #[arg(long, allow_hyphen_values = true)]
    q0: Option<String>,
    /// Angles in --pose, --q0 and the printed solutions are in degrees.
    #[arg(long)]
    deg: bool,
    /// Seed of the numeric solver's restarts.
    #[arg(long, default_value_t = 0, value_parser = crate::seed)]
    seed: u64,
    /// Print JSON.
    #[arg(long)]
    json: bool,
    /// Collision checks (with --scene or --srdf): a solution in collision is discarded, and an iiwa-type arm
    /// searches its self-motion for a free one.
    #[command(flatten)]
    body: crate::BodyArgs,
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

/// The target of --T, --pose or --position (position only; `solve` adds the
/// typed targets' pitch/roll, approach or α to it).
fn target(a: &IkArgs) -> Result<IkTarget> {
    let ang = |v: f64| if a.deg { v.to_radians() } else { v };
    if let Some(t) = &a.t {
        let v = numbers(t, "--T", 16)?;
        let m = Matrix4::from_row_slice(&v);
        let pose = Pose::from_matrix(&m)
            .context("--T is not a rigid transform: the last row must be 0 0 0 1 and the 3×3 block a rotation")?;
        return Ok(IkTarget::Pose(pose));
    }
    if let Some(p) = &a.pose {
        let v = numbers(p, "--pose", 6)?;
        let conv = a.rpy;
        return Ok(IkTarget::Pose(Pose::from_xyz_rpy([v[0], v[1], v[2]], [ang(v[3]), ang(v[4]), ang(v[5])], conv)));
    }
    if let Some(p) = &a.position {
        return Ok(IkTarget::Position(triple(p, "--position")?));
    }
    bail!("give a target: --T \"16 numbers\", --pose x,y,z,roll,pitch,yaw or --position x,y,z")
}

/// Prints an unreachable target (JSON on stdout with --json) and exits with code 2.
fn unreachable(a: &IkArgs, robot: &Robot, solver: &str, reason: &str, closest: Option<&Closest>) -> Result<()> {
    if a.json {
        print_json(&UnreachableAnswer::new(robot, solver, reason, closest, a.deg))?;
    } else {
        eprintln!("error: unreachable target ({solver} solver): {reason}");
        if let Some(c) = closest {
            let q: Vec<String> = kinema_io::shown_q(robot, &c.q, a.deg).iter().map(|v| format!("{v:.6}")).collect();
            eprintln!(
                "closest configuration found: [{}] (misses by {:.3e} m, {:.3e} rad)",
                q.join(", "),
                c.position_error,
                c.orientation_error
            );
        }
    }
    Err(Exit(2).into())
}

/// The six 0/1 flags of --mask.
fn mask(text: &str) -> Result<[bool; 6]> {
    let v = numbers(text, "--mask", 6)?;
    let mut m = [false; 6];
    for (flag, x) in m.iter_mut().zip(&v) {
        *flag = match *x {
            1.0 => true,
            0.0 => false,
            _ => bail!("--mask takes six 0/1 flags for x,y,z,ωx,ωy,ωz; got {x}"),
        };
    }
    Ok(m)
}

fn triple(text: &str, what: &str) -> Result<[f64; 3]> {
    let v = numbers(text, what, 3)?;
    Ok([v[0], v[1], v[2]])
}

type Solved = kinema::Result<IkAnswer>;

/// Runs the solver the arguments ask for (the core's `ik::solve_target`);
/// returns its answer and the target solved for.
fn solve(
    a: &IkArgs,
    robot: &Robot,
    target: IkTarget,
    q0: Option<&[f64]>,
    admissible: Option<&dyn Admissible>,
) -> Result<(Solved, IkTarget)> {
    let ang = |v: f64| if a.deg { v.to_radians() } else { v };
    // Flag grammar, not the core's rule: a typed flag beside --T/--pose would be ignored (clap's
    // `requires` does not fire when a conflicting target flag is given).
    let typed_target = a.pitch.is_some() || a.roll.is_some() || a.approach.is_some() || a.alpha.is_some();
    if typed_target && !matches!(target, IkTarget::Position(_)) {
        bail!(
            "--pitch/--roll, --approach and --alpha complete a --position target; they do not apply to --T or --pose"
        );
    }
    let target = match target {
        IkTarget::Position(position) => {
            // The components of a typed target, by name; the core says which target they make.
            let approach = a.approach.as_deref().map(|text| triple(text, "--approach")).transpose()?;
            let [pitch, roll, alpha] = [a.pitch, a.roll, a.alpha].map(|v| v.map(ang));
            let given = [
                ("pitch", pitch.as_ref().map(std::slice::from_ref)),
                ("roll", roll.as_ref().map(std::slice::from_ref)),
                ("alpha", alpha.as_ref().map(std::slice::from_ref)),
                ("approach", approach.as_ref().map(|d| &d[..])),
            ];
            kinema::ik::registry::typed_target(position, &given)?.map_or(target, IkTarget::Typed)
        }
        other => other,
    };
    let request = request(a, q0, admissible)?;
    match kinema::ik::solve_target(robot, &target, &request) {
        Ok(answer) => Ok((Ok(answer), target)),
        Err(e @ Error::Unreachable { .. }) => Ok((Err(e), target)),
        Err(e) => Err(e.into()),
    }
}

/// The request the flags make (solver, q0, all, q3/ψ, mask, tolerance, seed,
/// the collision check).
pub(crate) fn request<'a>(
    a: &IkArgs,
    q0: Option<&'a [f64]>,
    admissible: Option<&'a dyn Admissible>,
) -> Result<IkRequest<'a>> {
    let ang = |v: f64| if a.deg { v.to_radians() } else { v };
    Ok(IkRequest {
        solver: a.solver,
        q0,
        all: a.all,
        q3: a.q3.map(ang),
        psi: a.psi.map(ang),
        mask: a.mask.as_deref().map(mask).transpose()?,
        tolerance: Tolerance { position: a.tol_position, orientation: a.tol_orientation },
        numeric: NumericOptions { seed: a.seed, ..Default::default() },
        admissible,
        ..Default::default()
    })
}

/// Names the flag of a request field the core refused: its message names
/// the request's field (`tolerance.position`, `solver`, `mask` …), the
/// command line knows it as a flag (`--tol-position`, `--solver`, `--mask` …).
fn request_flag(e: anyhow::Error) -> anyhow::Error {
    let what = match e.downcast_ref::<Error>().map(Error::root) {
        Some(Error::Input(InputError::OutOfRange { what, .. }) | Error::Input(InputError::DoesNotFit { what, .. })) => {
            what.as_str()
        }
        _ => return e,
    };
    let flag = match what {
        "tolerance.position" => "--tol-position",
        "tolerance.orientation" => "--tol-orientation",
        "solver" => "--solver",
        "mask" => "--mask",
        "q3" => "--q3/--psi",
        "target" => "the target (--T, --pose or --position, with --pitch/--roll, --approach or --alpha)",
        _ => return e,
    };
    e.context(flag)
}

pub fn ik(a: IkArgs) -> Result<()> {
    // clap's `requires = "input"` on --output is not enforced when a target flag that conflicts with
    // --input is given, so the batch pair is checked here: a lone --output would be ignored.
    if a.output.is_some() && a.input.is_none() {
        return Err(crate::usage_error(
            "--output needs --input: it is where a batch's answers go (one per line of the --input CSV of \
             targets); the answer to a single target is printed (add --json and redirect it to keep it)",
        ));
    }
    let check = a.body.load_if_asked(&a.robot)?;
    let admissible = check.as_ref().map(|c| c as &dyn Admissible);
    let robot = match &check {
        Some(c) => c.robot().clone(),
        None => a.robot.load()?,
    };
    if let (Some(input), Some(output)) = (&a.input, &a.output) {
        return batch::run(&a, &robot, input, output, admissible);
    }
    let target = target(&a)?;
    let q0 = a.q0.as_deref().map(|t| robot.parse_q(t, a.deg)).transpose()?;
    let (result, target) = solve(&a, &robot, target, q0.as_deref(), admissible).map_err(request_flag)?;
    let orientation_free = target.orientation_free();
    let answer = match result {
        Ok(s) => s,
        Err(Error::Unreachable { solver, reason, closest }) => {
            return unreachable(&a, &robot, &solver, &reason.to_string(), closest.as_deref())
        }
        Err(e) => return Err(e.into()),
    };
    let chosen: Vec<Solution> = if a.all {
        answer.solutions.clone()
    } else {
        match kinema::ik::pick_one(&robot, answer.solver, answer.solutions.clone(), q0.as_deref()) {
            Ok(s) => vec![s],
            Err(Error::Unreachable { solver, reason, closest }) => {
                return unreachable(&a, &robot, &solver, &reason.to_string(), closest.as_deref())
            }
            Err(e) => return Err(e.into()),
        }
    };
    if a.json {
        let json = kinema_io::IkAnswer {
            q3: a.q3.map(|v| if a.deg { v.to_radians() } else { v }),
            psi: a.psi.map(|v| if a.deg { v.to_radians() } else { v }),
            ..kinema_io::IkAnswer::new(&robot, &answer, &chosen, &target, a.rpy)
        };
        return print_json(&if a.deg { json.in_degrees(&robot) } else { json });
    }
    let IkAnswer { solver: name, discarded, tolerance, folded, .. } = answer;
    outln!("robot {}  solver {}  {} solution(s)", robot.name(), name, chosen.len())?;
    let (missed, rejected): (Vec<_>, Vec<_>) = discarded.iter().partition(|d| d.rejection.is_none());
    if !missed.is_empty() {
        outln!("  ({} candidate(s) discarded: {}, {tolerance})", missed.len(), kinema_io::DISCARD_REASON)?;
    }
    if let Some(first) = rejected.first().and_then(|d| d.rejection.as_ref()) {
        outln!("  ({} solution(s) discarded, the first for {first})", rejected.len())?;
    }
    if folded > 0 && a.all {
        outln!("  ({folded} more copies within limits, joints turned by whole turns, not listed)")?;
    }
    for s in chosen {
        let unit = if a.deg { "deg/m" } else { "rad/m" };
        let q: Vec<String> =
            s.q.iter()
                .zip(robot.joints())
                .map(|(v, j)| {
                    format!("{:.6}", if a.deg && j.kind == kinema::JointType::Revolute { v.to_degrees() } else { *v })
                })
                .collect();
        outln!("  [{}] ({unit})  branch {}", q.join(", "), s.branch)?;
        let orientation =
            if orientation_free { "orientation free".to_string() } else { format!("{:.3e} rad", s.orientation_error) };
        outln!(
            "    residual {:.3e} m, {orientation}; {}{}",
            s.position_error,
            if s.within_limits() { "within limits" } else { "OUTSIDE joint limits" },
            s.numeric.map_or(String::new(), |n| format!(
                "; {} iterations, {} restarts, {}",
                n.iterations, n.restarts, n.stop
            ))
        )?;
    }
    Ok(())
}

#[derive(Args)]
pub struct ValidateArgs {
    #[command(flatten)]
    robot: RobotArg,
    /// Number of random configurations, 1 to 10 000 000.
    #[arg(long, default_value_t = 1000, value_parser = crate::count(1, crate::MAX_CONFIGURATIONS))]
    n: usize,
    /// Seed of the random configurations.
    #[arg(long, default_value_t = 1, value_parser = crate::seed)]
    seed: u64,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

/// `kinema ik-validate`: for the iiwa, IK with the original q3 (the paper's
/// experiment); for other robots, the robot's analytic solver on the full pose.
pub fn validate(a: ValidateArgs) -> Result<()> {
    let robot = a.robot.load()?;
    let v = if let Ok(s) = kinema::ik::iiwa::IiwaIk::new(&robot) {
        let r = s.validate(a.n, a.seed);
        ValidateAnswer {
            robot: robot.name().to_string(),
            solver: "iiwa (same q3)".into(),
            cases: r.cases,
            solved: None,
            max_error: r.max_error,
            mean_error: r.mean_error,
            recovered_fraction: r.recovered_fraction,
            max_position_residual: None,
            max_error_over_limit: Some(r.max_error_over_limit),
            max_error_well_conditioned: Some(r.max_error_well_conditioned),
            well_conditioned_cases: Some(r.well_conditioned_cases),
        }
    } else {
        let Some(solver) = kinema::ik::analytic_solver(&robot) else {
            bail!("robot `{}` has no analytic solver to validate", robot.name());
        };
        let r = kinema::ik::round_trip(&robot, solver.as_ref(), a.n, a.seed)?;
        ValidateAnswer {
            robot: robot.name().to_string(),
            solver: solver.name().to_string(),
            cases: r.cases,
            solved: Some(r.solved),
            max_error: r.max_error,
            mean_error: r.mean_error,
            recovered_fraction: r.recovered_fraction,
            max_position_residual: Some(r.max_position_residual),
            max_error_over_limit: None,
            max_error_well_conditioned: None,
            well_conditioned_cases: None,
        }
    };
    if a.json {
        return print_json(&v);
    }
    // The solver's name as JSON text, quoted, as this line has always shown it.
    outln!("robot {}  solver {:?}  {} cases (seed {})", robot.name(), v.solver, a.n, a.seed)?;
    outln!("max |Δq| {:.3e}, mean {:.3e}, recovered {:.2} %", v.max_error, v.mean_error, v.recovered_fraction * 100.0)?;
    if let (Some(ratio), Some(wc), Some(n)) =
        (v.max_error_over_limit, v.max_error_well_conditioned, v.well_conditioned_cases)
    {
        outln!(
            "max |Δq| over the {n} well-conditioned cases (target rounding moves the solution ≤ 1e-13) {wc:.3e}; \
             worst error / rounding limit {ratio:.2}"
        )?;
    }
    Ok(())
}

#[derive(Args)]
pub struct SelfMotionArgs {
    #[command(flatten)]
    robot: RobotArg,
    /// The configuration whose tool pose is kept (comma-separated or a named pose).
    #[arg(long, allow_hyphen_values = true)]
    q: String,
    /// Revolute values in degrees.
    #[arg(long)]
    deg: bool,
    /// Number of samples around the self-motion, 1 to 1 000 000.
    #[arg(long, default_value_t = 36, value_parser = crate::count(1, 1_000_000))]
    steps: usize,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

/// `kinema selfmotion`: the self-motion through `--q` of an arm with an arm
/// angle (seed 004 §V-D, Fig. 7), from any description of it.
pub fn selfmotion(a: SelfMotionArgs) -> Result<()> {
    let robot = a.robot.load()?;
    let family = kinema::ik::registry::fit(&robot);
    let Some(redundancy) = family.as_deref().and_then(|f| f.redundancy()) else {
        bail!(
            "robot `{}` has no self-motion with a closed form (an arm of the iiwa's structure has one)",
            robot.name()
        );
    };
    let q = robot.parse_q(&a.q, a.deg)?;
    let samples = kinema::ik::family::self_motion(&robot, redundancy, &q, a.steps)?;
    if a.json {
        return print_json(&SelfMotionAnswer::new(&robot, &samples));
    }
    outln!("robot {}: {} samples of the self-motion through q", robot.name(), samples.len())?;
    for m in &samples {
        outln!(
            "  ψ {:>8.4}  q3 {:>8.4}  elbow [{:.4}, {:.4}, {:.4}]  {}",
            m.psi,
            m.q3,
            m.elbow.x,
            m.elbow.y,
            m.elbow.z,
            if m.within_limits { "within limits" } else { "outside limits" }
        )?;
    }
    Ok(())
}
