//! One IK request as the command line, the viewer and the Python bindings make
//! it: which solver, an optional previous configuration, the iiwa's q3 or ψ,
//! and the rule that picks one solution from many.

use super::{analytic_solver, IiwaIk, IkSolver, NumericIk, NumericOptions, Solution, Solutions, Unreachable};
use crate::error::{Error, Result};
use crate::math::Pose;
use crate::model::Robot;

/// Which solver a request asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SolverChoice {
    /// The robot's analytic solver if it has one, else the numeric one.
    #[default]
    Auto,
    /// The analytic solver; an error if the robot has none.
    Analytic,
    /// The numeric solver.
    Numeric,
}

/// A full-pose IK request (see [`solve_request`]).
#[derive(Debug, Clone, Default)]
pub struct IkRequest<'a> {
    /// Which solver.
    pub solver: SolverChoice,
    /// A previous configuration \[rad, m\]: the numeric solver starts there;
    /// for an iiwa-type arm without `all`, seed 004 §V-E's selection near it.
    pub q0: Option<&'a [f64]>,
    /// Whether every solution is wanted (else one will be picked).
    pub all: bool,
    /// iiwa: the closed form at this q3 \[rad\] (up to 8 solutions).
    pub q3: Option<f64>,
    /// iiwa: the arm angle ψ \[rad\] (one solution per global configuration).
    pub psi: Option<f64>,
    /// Options of the numeric solver (seed, tolerances, task mask, …). With a
    /// task mask the numeric solver is used (analytic solvers need full poses).
    pub numeric: NumericOptions,
}

/// Runs `request` on `target` and returns the solver's name and every
/// solution it gave. Errors: q3/ψ for a robot that is not iiwa-type, or
/// together with a task mask; [`SolverChoice::Analytic`] for a robot without
/// an analytic solver; the solver's own errors ([`Error::Unreachable`], …).
///
/// # Examples
/// ```
/// use kinema::ik::{solve_request, pick_one, IkRequest};
/// let robot = kinema::Robot::builtin("puma560")?;
/// let q = [0.1, -0.5, 0.4, 0.3, 0.6, -0.2];
/// let target = robot.fk(&q)?.pose;
/// let (name, all) = solve_request(&robot, &target, &IkRequest { all: true, ..Default::default() })?;
/// assert_eq!((name, all.len()), ("pieper", 8));
/// let one = pick_one(&robot, name, all, Some(&q))?;
/// assert!(one.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9));
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn solve_request(robot: &Robot, target: &Pose, request: &IkRequest) -> Result<(&'static str, Vec<Solution>)> {
    let masked = request.numeric.mask.is_some();
    if (request.q3.is_some() || request.psi.is_some()) && masked {
        return Err(Error::InvalidArgument {
            what: "target".into(),
            message: "q3 and ψ need a full target pose, not a task mask".into(),
        });
    }
    if let Some(q3) = request.q3 {
        return Ok(("iiwa", IiwaIk::new(robot)?.solve_q3(target, q3)?));
    }
    if let Some(psi) = request.psi {
        let s = IiwaIk::new(robot)?;
        let all: Vec<Solution> = (0u8..8).filter_map(|c| s.solve_psi(target, psi, c).ok()).collect();
        if all.is_empty() {
            // The reason the first global configuration gives.
            return Ok(("iiwa", vec![s.solve_psi(target, psi, 0)?]));
        }
        return Ok(("iiwa", all));
    }
    let numeric_only = masked || request.solver == SolverChoice::Numeric;
    // iiwa with a previous configuration: seed 004 §V-E's q_k = f(q_{k−1}, T_k)
    // (q3 searched near the previous one), else the closed form at q3 = q0[2].
    if let (Some(q0), false, false) = (request.q0, request.all, numeric_only) {
        if let Ok(s) = IiwaIk::new(robot) {
            robot.check_q(q0)?;
            return Ok(("iiwa", s.select(q0, target, None).map(|x| vec![x]).or_else(|_| s.solve_q3(target, q0[2]))?));
        }
    }
    let analytic = if numeric_only { None } else { analytic_solver(robot) };
    match (request.solver, analytic) {
        (SolverChoice::Analytic, None) => Err(Error::InvalidArgument {
            what: "solver".into(),
            message: format!(
                "robot `{}` has no analytic solver for this target (analytic solvers: iiwa-type 7R, 6R with a \
                 spherical wrist, Scorbot, SCARA on a rail, ROMMEL; position-only targets are numeric); use the \
                 numeric solver",
                robot.name()
            ),
        }),
        (_, Some(s)) => Ok((s.name(), s.solve(target)?)),
        (_, None) => {
            let solver = NumericIk::with_options(robot, request.numeric.clone())?;
            let solutions = match request.q0 {
                Some(q0) => vec![solver.solve_from(target, q0)?],
                None => solver.solve(target)?,
            };
            Ok(("numeric", solutions))
        }
    }
}

/// The one solution to report from `solutions` of solver `solver`: within
/// the joint limits, the nearest to `q0` when given, else the first.
/// [`Error::Unreachable`] with [`Unreachable::JointLimits`] (naming each
/// branch and its offending joints) when none is within limits.
pub fn pick_one(robot: &Robot, solver: &str, solutions: Vec<Solution>, q0: Option<&[f64]>) -> Result<Solution> {
    if !solutions.iter().any(Solution::within_limits) {
        let rejected = solutions
            .iter()
            .map(|s| {
                let j: Vec<String> = s.out_of_limits.indices().map(|i| format!("q{}", i + 1)).collect();
                format!("{} ({})", s.branch, j.join(", "))
            })
            .collect();
        return Err(Error::Unreachable { solver: solver.to_string(), reason: Unreachable::JointLimits { rejected } });
    }
    let within = solutions.within_limits();
    let pick = match q0 {
        Some(q0) => within.nearest(robot, q0).cloned(),
        None => within.into_iter().next(),
    };
    // `within` is not empty, so there is a pick.
    pick.ok_or_else(|| Error::InvalidArgument { what: "solutions".into(), message: "none to pick from".into() })
}
