//! One IK request as the command line, the viewer and the Python bindings make
//! it: what the tool must reach ([`IkTarget`]: a full pose, a position, or a
//! robot family's typed target), which solver, an optional previous
//! configuration, the iiwa's q3 or ψ, and the rule that picks one solution
//! from many.

use nalgebra::Vector3;

use super::admissible::{self, Admissible, SelfMotionSearch};
use super::contract::{self, IkAnswer, Tolerance};
use super::family::{Family, SelfMotionParameter};
use super::registry;
use super::target::IkTarget;
use super::{Closest, IkSolver, NumericIk, NumericOptions, Solution, Solutions, Unreachable};
use crate::error::{Error, InputError, Result};
use crate::math::Pose;
use crate::robot::Robot;

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

/// The task mask of a position-only target: x, y, z.
const POSITION_MASK: [bool; 6] = [true, true, true, false, false, false];

/// A full-pose IK request (see [`solve_request`]).
#[derive(Debug, Clone, Default)]
pub struct IkRequest<'a> {
    /// Which solver.
    pub solver: SolverChoice,
    /// A previous configuration \[rad, m\]: the numeric solver starts there;
    /// for an iiwa-type arm, seed 004 §V-E's selection near it, or with `all`
    /// every closed-form solution at its q3 (the 8 branches, among them the
    /// continuation of a path through `q0`).
    pub q0: Option<&'a [f64]>,
    /// Whether every solution is wanted (else one will be picked).
    pub all: bool,
    /// iiwa-type (SRS) arms: the closed form at this q3 \[rad\] (up to 8 solutions).
    pub q3: Option<f64>,
    /// iiwa-type (SRS) arms: the arm angle ψ \[rad\] (one solution per configuration).
    pub psi: Option<f64>,
    /// Which components \[x y z ωx ωy ωz\] (world frame) of a full pose a
    /// solution must meet; `None`: all six. With a mask the numeric solver is
    /// used (the closed forms solve full poses).
    pub mask: Option<[bool; 6]>,
    /// How close FK of a returned solution must come to the target.
    pub tolerance: Tolerance,
    /// Options of the numeric solver (seed, iterations, restarts, damping, …);
    /// its mask and tolerances are set from `mask` and `tolerance`.
    pub numeric: NumericOptions,
    /// A test every solution must pass besides meeting the target (a scene's
    /// collision check): rejected solutions are discarded, and a redundant
    /// arm's self-motion is searched before the target is refused (see
    /// [`Admissible`]).
    pub admissible: Option<&'a dyn Admissible>,
    /// Keep an analytic solver's refusal as it is: no bounded numeric search
    /// for the closest configuration (or for a solution the closed form
    /// missed) behind it. For callers that ask many targets whether they are
    /// reachable at all, such as [`capability_map`](crate::reach::capability_map).
    pub skip_closest: bool,
}

impl IkRequest<'_> {
    /// The numeric solver's options for this request.
    fn numeric_options(&self) -> NumericOptions {
        NumericOptions {
            mask: self.mask,
            tol_position: self.tolerance.position,
            tol_orientation: self.tolerance.orientation,
            ..self.numeric.clone()
        }
    }
}

/// Runs `request` on the full pose `target` and returns the solver's name and
/// every solution that meets it: [`solve_target`] for a pose, without the
/// discarded candidates. Errors: q3/ψ for a robot that is not iiwa-type, or
/// together with a task mask; [`SolverChoice::Analytic`] for a robot without
/// an analytic solver; the solver's own errors ([`Error::Unreachable`], …).
///
/// # Examples
/// ```
/// use kinema::ik::{solve_request, pick_one, IkRequest};
/// let robot = kinema::Robot::builtin("puma560")?;
/// let q = [0.1, -0.5, 0.4, 0.3, 0.6, -0.2];
/// let target = robot.fk(&q)?.world_from_tool;
/// let (name, all) = solve_request(&robot, &target, &IkRequest { all: true, ..Default::default() })?;
/// // The 8 branches, and the copies of joints 4 and 6 (±266°) turned by 2π that are within limits.
/// assert!(name == "pieper" && all.len() >= 8);
/// let one = pick_one(&robot, name, all, Some(&q))?;
/// assert!(one.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9));
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn solve_request(robot: &Robot, target: &Pose, request: &IkRequest) -> Result<(&'static str, Vec<Solution>)> {
    let answer = solve_target(robot, &IkTarget::Pose(*target), request)?;
    Ok((answer.solver, answer.solutions))
}

/// [`solve_request`] with the family already fitted to `robot`
/// ([`registry::fit`]), so that many requests fit it once.
fn solve_request_with(
    robot: &Robot,
    fitted: Option<&dyn Family>,
    target: &Pose,
    request: &IkRequest,
) -> Result<(&'static str, Vec<Solution>)> {
    if let Some(q0) = request.q0 {
        // The redundant families read q0's parameter.
        robot.check_q(q0)?;
    }
    let masked = request.mask.is_some();
    let fixed =
        request.q3.map(|v| (SelfMotionParameter::Q3, v)).or(request.psi.map(|v| (SelfMotionParameter::ArmAngle, v)));
    if fixed.is_some() && masked {
        return Err(Error::Input(InputError::DoesNotFit {
            what: "target".into(),
            reason: "q3 and ψ need a full target pose, not a task mask".into(),
        }));
    }
    let numeric_only = masked || request.solver == SolverChoice::Numeric;
    let family = if numeric_only && fixed.is_none() { None } else { fitted };
    if let Some((parameter, value)) = fixed {
        let f = family;
        let Some(r) = f.and_then(|f| f.redundancy()).filter(|r| r.parameters().contains(&parameter)) else {
            let has = f.map_or("no closed-form solver".to_string(), |f| {
                let params =
                    f.redundancy().map_or("none".to_string(), |r| super::family::parameter_names(r.parameters()));
                format!("the {} solver, whose self-motion parameters are: {params}", f.name())
            });
            let reason = if f.and_then(|f| f.redundancy()).is_some() {
                format!("{parameter} is not a self-motion parameter of robot `{}` (it has {has})", robot.name())
            } else {
                format!(
                    "q3 and ψ select the closed form of iiwa-type arms, which does not fit robot `{}` (it has {has})",
                    robot.name()
                )
            };
            return Err(Error::Input(InputError::DoesNotFit { what: parameter.to_string(), reason }));
        };
        return Ok((f.map_or("", |f| f.name()), r.solve_at(target, parameter, value)?));
    }
    // A redundant family: every closed-form solution at q0's parameter when
    // all are wanted; else the family's rule near q0 (the iiwa: seed 004
    // §V-E's q_k = f(q_{k−1}, T_k)); without q0 and one wanted, the default
    // value unless every solution there violates a limit, then the
    // self-motion is searched before the target is refused.
    if let Some(f) = family {
        if let Some(r) = f.redundancy() {
            let solutions = match (request.q0, request.all) {
                (Some(q0), true) => Some(r.solve_at(target, r.parameters()[0], r.value_of(q0))?),
                (Some(q0), false) => Some(r.solve_near(target, q0)?),
                (None, false) => Some(r.solve_searching(target, r.default_value())?),
                (None, true) => None,
            };
            if let Some(solutions) = solutions {
                return Ok((f.name(), solutions));
            }
        }
    }
    match (request.solver, family) {
        (SolverChoice::Analytic, None) if masked => Err(Error::Input(InputError::DoesNotFit {
            what: "solver".into(),
            reason: format!(
                "robot `{}` has no analytic solver for a task mask or a position-only target (the closed forms \
                 solve full poses); use the numeric solver",
                robot.name()
            ),
        })),
        (SolverChoice::Analytic, None) => Err(Error::Input(InputError::DoesNotFit {
            what: "solver".into(),
            reason: format!(
                "robot `{}` has no analytic solver for this target (analytic solvers: iiwa-type 7R, 6R with a \
                 spherical wrist or with three parallel axes, Scorbot, SCARA on a rail, ROMMEL; position-only \
                 targets are numeric); use the numeric solver",
                robot.name()
            ),
        })),
        (_, Some(f)) => Ok((f.name(), f.propose(target)?)),
        (_, None) => {
            let solver = NumericIk::with_options(robot, request.numeric_options())?;
            let solutions = match request.q0 {
                Some(q0) => vec![solver.solve_from(target, q0)?],
                None => solver.solve(target)?,
            };
            Ok(("numeric", solutions))
        }
    }
}

/// Solves `target` as `request` asks — the one dispatch of `kinema ik`, the
/// viewer, the language and Python for every kind of target — and returns
/// the solutions that meet the target ([`IkAnswer`]).
///
/// * A full pose ([`IkTarget::Pose`]): [`solve_request`]; with
///   `request.mask`, only the selected components are constrained.
/// * A position ([`IkTarget::Position`]): [`solve_request`] with the position-only task mask
///   (numeric solver; [`SolverChoice::Analytic`] is refused as for any masked
///   target).
/// * The typed targets: the family's solver ([`ScorbotIk`](crate::ik::scorbot::ScorbotIk), [`RommelIk`](crate::ik::rommel::RommelIk),
///   [`ScaraIk`](crate::ik::scara::ScaraIk)) whatever the robot; a robot of another family gives that
///   solver's own error ("the Scorbot solver needs 5 revolute joints …").
///   `request.all` and `request.numeric` do not apply; the SCARA keeps the
///   elbow side and q5 of `request.q0`.
///
/// **The contract.** Every candidate the solver proposes is measured by FK
/// ([`contract::residual`]); only those within `request.tolerance` on every
/// constrained component are returned, the others are listed in
/// [`IkAnswer::discarded`]. When none meets the target the result is
/// [`Error::Unreachable`] with the reason and, where one was found, the
/// closest configuration: an analytic refusal of a pose or position gets a
/// bounded numeric second look, whose solution is returned instead when the
/// solver choice is [`SolverChoice::Auto`]. So an arm with fewer than six
/// joints meets a full pose exactly or not at all, unless a mask frees what
/// it cannot control.
///
/// Errors ([`InputError::DoesNotFit`], [`InputError::TooFew`], [`InputError::OutOfRange`]) before any solving: both q3 and ψ;
/// `q0` not a configuration of `robot`; a typed target, q3 or ψ with
/// [`SolverChoice::Numeric`] (they select an analytic solver); q3 or ψ with a
/// target that is not a full pose; a mask with a target that is not a full
/// pose, or selecting nothing; a tolerance that is not positive; a
/// non-finite position.
///
/// # Examples
/// ```
/// use kinema::ik::{pick_one, solve_target, IkRequest, IkTarget, SolverChoice};
/// use kinema::Pose;
/// let robot = kinema::Robot::builtin("scorbot-er-v-plus")?;
/// let q = [0.3, 1.2, -1.0, -0.6, 0.4];
/// let reached = robot.fk(&q)?.world_from_tool;
/// let p = reached.pos;
/// // Seed 000 eq. 13: pitch β = −(θ2 + θ3 + θ4), roll γ = θ5.
/// let given: [(&str, Option<&[f64]>); 2] = [("pitch", Some(&[-(1.2 - 1.0 - 0.6)])), ("roll", Some(&[0.4]))];
/// let target = IkTarget::Typed(kinema::ik::registry::typed_target([p.x, p.y, p.z], &given)?.unwrap());
/// let answer = solve_target(&robot, &target, &IkRequest::default())?;
/// assert_eq!(answer.solver, "scorbot");
/// let one = pick_one(&robot, answer.solver, answer.solutions, Some(&q))?;
/// assert!(one.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9));
///
/// // A full pose the arm reaches: only the candidates that meet it.
/// let answer = solve_target(&robot, &IkTarget::Pose(reached), &IkRequest { all: true, ..Default::default() })?;
/// assert!(answer.solutions.iter().all(|s| s.position_error < 1e-9 && s.orientation_error < 1e-9));
/// // Turned about the vertical: five joints cannot follow, so it is unreachable…
/// let turned = Pose::new(kinema::math::rot_z(0.5) * reached.rot, reached.pos);
/// assert!(solve_target(&robot, &IkTarget::Pose(turned), &IkRequest::default()).is_err());
/// // …unless a task mask frees the rotation about the world z axis.
/// let free_yaw = IkRequest { mask: Some([true, true, true, true, true, false]), ..Default::default() };
/// assert!(solve_target(&robot, &IkTarget::Pose(turned), &free_yaw).is_ok());
///
/// // Position only: the numeric solver with a position mask.
/// let answer = solve_target(&robot, &IkTarget::Position([p.x, p.y, p.z]), &IkRequest::default())?;
/// assert_eq!(answer.solver, "numeric");
/// assert!(answer.solutions[0].position_error < 1e-6);
///
/// // A typed target selects an analytic solver.
/// let numeric = IkRequest { solver: SolverChoice::Numeric, ..Default::default() };
/// assert!(solve_target(&robot, &target, &numeric).is_err());
/// // A typed target of another family: that solver's own error.
/// let alpha = IkTarget::Typed(kinema::ik::scara::TOOL_ANGLE.target([p.x, p.y, p.z], &[("alpha", &[0.0])])?);
/// assert!(solve_target(&robot, &alpha, &IkRequest::default()).unwrap_err().to_string().contains("SCARA"));
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn solve_target(robot: &Robot, target: &IkTarget, request: &IkRequest) -> Result<IkAnswer> {
    solve_target_with(robot, registry::fit(robot).as_deref(), target, request)
}

/// [`solve_target`] with the family already fitted to `robot`
/// ([`registry::fit`], `None` when none fits): the same answer, without
/// fitting it again for every target (Python's `Robot` and
/// [`super::solve_batch`] fit it once).
pub fn solve_target_with(
    robot: &Robot,
    fitted: Option<&dyn Family>,
    target: &IkTarget,
    request: &IkRequest,
) -> Result<IkAnswer> {
    check_request(robot, target, request)?;
    let mask = match target {
        IkTarget::Position(_) => Some(POSITION_MASK),
        _ => request.mask,
    };
    let answer = match propose(robot, fitted, target, request) {
        // A fixed q3 or ψ is a constraint the numeric solver does not keep.
        Err(Error::Unreachable { solver, reason, closest: None })
            if solver != "numeric" && request.q3.is_none() && request.psi.is_none() && !request.skip_closest =>
        {
            closest_by_numeric(robot, target, mask, request, solver, reason)?
        }
        other => {
            let (name, candidates) = other?;
            measure(robot, fitted, target, mask, request, name, candidates)?
        }
    };
    let Some(test) = request.admissible else {
        return Ok(answer);
    };
    let solver = answer.solver;
    let family = fitted.filter(|f| f.name() == solver);
    let measure_at = |candidates| measure(robot, family, target, mask, request, solver, candidates);
    let search = match (target, family.and_then(|f| f.redundancy())) {
        (IkTarget::Pose(pose), Some(redundancy)) if request.q3.is_none() && request.psi.is_none() => {
            Some(SelfMotionSearch { robot, redundancy, target: *pose, measure: &measure_at })
        }
        _ => None,
    };
    admissible::admit(answer, test, search)
}

/// The contract on `candidates` ([`contract::sort_out`]), then every
/// solution's copies within the joint limits ([`contract::unfold_turns`]),
/// so that [`pick_one`] sees the one nearest `request.q0`.
fn measure(
    robot: &Robot,
    fitted: Option<&dyn Family>,
    target: &IkTarget,
    mask: Option<[bool; 6]>,
    request: &IkRequest,
    name: &'static str,
    candidates: Vec<Solution>,
) -> Result<IkAnswer> {
    let mut answer = contract::sort_out(robot, fitted, target, mask, request.tolerance, name, candidates)?;
    contract::unfold_turns(robot, fitted, target, mask, &mut answer, request.q0)?;
    Ok(answer)
}

/// The combinations [`solve_target`] refuses before solving.
pub(crate) fn check_request(robot: &Robot, target: &IkTarget, request: &IkRequest) -> Result<()> {
    let invalid = |what: &str, reason: &str| {
        Err(Error::Input(InputError::DoesNotFit { what: what.into(), reason: reason.into() }))
    };
    let iiwa = request.q3.is_some() || request.psi.is_some();
    if request.q3.is_some() && request.psi.is_some() {
        return invalid("q3", "give q3 or psi, not both");
    }
    if let Some(q0) = request.q0 {
        robot.check_q(q0)?;
    }
    if (target.typed().is_some() || iiwa) && request.solver == SolverChoice::Numeric {
        return invalid(
            "solver",
            "pitch/roll, approach and alpha targets, q3 and psi select an analytic solver; drop the numeric solver",
        );
    }
    if iiwa && !matches!(target, IkTarget::Pose(_)) {
        return invalid("target", "q3 and psi need a full target pose, not a position-only or typed target");
    }
    if request.mask.is_some() && !matches!(target, IkTarget::Pose(_)) {
        return invalid(
            "mask",
            "a task mask selects components of a full pose; a position or typed target already says what it fixes",
        );
    }
    if request.mask.is_some() && iiwa {
        return invalid(
            "mask",
            "a task mask frees components of the pose, q3 and psi solve the full pose in closed form; give one",
        );
    }
    if request.mask.is_some_and(|m| !m.iter().any(|&b| b)) {
        return Err(super::no_component());
    }
    let tolerance =
        [("tolerance.position", request.tolerance.position), ("tolerance.orientation", request.tolerance.orientation)];
    for (what, value) in tolerance {
        if !(value > 0.0) {
            return Err(Error::Input(InputError::OutOfRange {
                what: what.into(),
                value,
                expected: "a positive tolerance".into(),
            }));
        }
    }
    Ok(())
}

/// The candidates of the solver `request` selects for `target`, before the
/// contract's check.
fn propose(
    robot: &Robot,
    fitted: Option<&dyn Family>,
    target: &IkTarget,
    request: &IkRequest,
) -> Result<(&'static str, Vec<Solution>)> {
    match *target {
        IkTarget::Pose(ref pose) => solve_request_with(robot, fitted, pose, request),
        IkTarget::Position(p) => {
            if let Some(&value) = p.iter().find(|v| !v.is_finite()) {
                return Err(Error::Input(InputError::NotFinite { what: "position".into(), value }));
            }
            let mut masked = request.clone();
            masked.mask = Some(POSITION_MASK);
            solve_request_with(robot, fitted, &position_pose(robot, p)?, &masked)
        }
        IkTarget::Typed(ref typed) => {
            registry::with_owner(robot, fitted, typed.kind, |f| Ok((f.name(), f.solve_typed(typed, request.q0)?)))
        }
    }
}

/// A position target as a pose: home's rotation is a placeholder that the
/// position mask leaves out.
fn position_pose(robot: &Robot, p: [f64; 3]) -> Result<Pose> {
    Ok(Pose::new(robot.fk(robot.home())?.world_from_tool.rot, Vector3::from(p)))
}

/// Restarts of the numeric search behind an analytic solver's refusal.
const SECOND_OPINION_RESTARTS: usize = 8;

/// An analytic solver refused a pose or position target: the numeric solver
/// gets a bounded second look (from q0 or home, then seeded restarts). If it
/// meets the target and the request let the solver be chosen, its solution is
/// the answer; otherwise the refusal stands, with the closest configuration
/// the search found. Typed targets keep the refusal as it is.
fn closest_by_numeric(
    robot: &Robot,
    target: &IkTarget,
    mask: Option<[bool; 6]>,
    request: &IkRequest,
    solver: String,
    reason: Unreachable,
) -> Result<IkAnswer> {
    // A "closest" configuration whose miss is not finite (an absurdly far target) is no help.
    let refusal = |closest: Option<Box<Closest>>| {
        let closest = closest.filter(|c| c.position_error.is_finite() && c.orientation_error.is_finite());
        Err(Error::Unreachable { solver: solver.clone(), reason: reason.clone(), closest })
    };
    let pose = match target {
        IkTarget::Pose(pose) => *pose,
        IkTarget::Position(p) => position_pose(robot, *p)?,
        _ => return refusal(None),
    };
    let opts = NumericOptions {
        max_restarts: SECOND_OPINION_RESTARTS.min(request.numeric.max_restarts),
        mask,
        ..request.numeric_options()
    };
    let numeric = NumericIk::with_options(robot, opts)?;
    match numeric.solve_from(&pose, request.q0.unwrap_or(robot.home())) {
        Ok(s) if request.solver == SolverChoice::Auto => {
            measure(robot, None, target, mask, request, "numeric", vec![s])
        }
        Ok(s) => refusal(Some(Box::new(Closest::of(&s)))),
        Err(Error::Unreachable { closest, .. }) => refusal(closest),
        Err(e) => Err(e),
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
        return Err(Error::Unreachable {
            solver: solver.to_string(),
            reason: Unreachable::JointLimits { rejected },
            closest: None,
        });
    }
    let within = solutions.within_limits();
    let pick = match q0 {
        Some(q0) => within.nearest(robot, q0).cloned(),
        None => within.into_iter().next(),
    };
    // `within` is not empty, so there is a pick.
    pick.ok_or_else(|| {
        Error::Input(InputError::TooFew {
            what: "solutions".into(),
            got: 0,
            min: 1,
            of: "solutions within limits".into(),
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ik::target::TypedTarget;
    use crate::ik::{rommel::APPROACH, scara::TOOL_ANGLE, scorbot::PITCH_ROLL};
    use crate::ik::{scara::ScaraIk, scorbot::ScorbotIk, IiwaIk};
    use crate::ik::{scorbot::R_H, wrap_angle};
    use crate::math::{rot_x, rot_y};
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn all() -> IkRequest<'static> {
        IkRequest { all: true, ..Default::default() }
    }

    fn xyz(p: &Pose) -> [f64; 3] {
        [p.pos.x, p.pos.y, p.pos.z]
    }

    /// iiwa with q0 and `all`: the closed form at q0's q3, which contains q0
    /// itself; without `all`, one solution (§V-E's selection) near q0. q3
    /// on an arm of another shape says why.
    #[test]
    fn iiwa_with_q0_and_all_solves_at_q0s_q3() {
        let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
        let ik = IiwaIk::new(&robot).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(85);
        for _ in 0..200 {
            let q = robot.random_q(&mut rng);
            let pose = robot.fk(&q).unwrap().world_from_tool;
            let request = IkRequest { q0: Some(&q), all: true, ..Default::default() };
            let (name, sols) = solve_request(&robot, &pose, &request).unwrap();
            assert_eq!(name, "iiwa");
            assert_eq!(sols, ik.solve_q3(&pose, q[2]).unwrap());
            let d = |s: &Solution| s.q.iter().zip(&q).map(|(a, b)| wrap_angle(a - b).abs()).fold(0.0, f64::max);
            assert!(sols.iter().any(|s| d(s) < 1e-9));
            let one = IkRequest { q0: Some(&q), ..Default::default() };
            let (_, picked) = solve_request(&robot, &pose, &one).unwrap();
            assert_eq!(picked.len(), 1);
            // §V-E's rule (q3 near q0's, elbow up preferred): a nearby solution that reaches the pose.
            assert!(picked[0].position_error < 1e-9 && picked[0].orientation_error < 1e-9);
            assert!(d(&picked[0]) < 0.5, "{:?} vs {q:?}", picked[0].q);
        }
        let panda = Robot::builtin("panda").unwrap();
        let pose = panda.fk(panda.home()).unwrap().world_from_tool;
        let e = solve_request(&panda, &pose, &IkRequest { q3: Some(0.1), ..Default::default() }).unwrap_err();
        assert!(e.to_string().contains("q3 and ψ select the closed form of iiwa-type arms"), "{e}");
    }

    /// A full pose goes through `solve_request` unchanged.
    #[test]
    fn pose_targets_are_solve_request() {
        let robot = Robot::builtin("puma560").unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(80);
        for _ in 0..50 {
            let q = robot.random_q(&mut rng);
            let pose = robot.fk(&q).unwrap().world_from_tool;
            let request = IkRequest { q0: Some(&q), ..Default::default() };
            assert_eq!(
                solve_target(&robot, &IkTarget::Pose(pose), &request).unwrap().solutions,
                solve_request(&robot, &pose, &request).unwrap().1
            );
        }
    }

    /// Seed 000 eq. 13: every solution reaches the position with pitch
    /// β = −θ234 and roll γ = θ5, i.e. R·R_h = Rz(yaw)·Ry(β)·Rx(γ) for some yaw.
    #[test]
    fn scorbot_pitch_roll_targets_are_reached() {
        let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(81);
        let mut recovered = 0;
        for _ in 0..300 {
            let q = robot.random_q(&mut rng);
            let p = xyz(&robot.fk(&q).unwrap().world_from_tool);
            let (pitch, roll) = (-(q[1] + q[2] + q[3]), q[4]);
            let target = IkTarget::Typed(TypedTarget::new(&PITCH_ROLL, p, &[pitch, roll]).unwrap());
            let IkAnswer { solver: name, solutions: sols, .. } = solve_target(&robot, &target, &all()).unwrap();
            assert_eq!(name, "scorbot");
            // The solver's candidates, each kept (the residuals are the contract's own measure),
            // with their copies within limits (q5 has ±570°): the same modulo 2π.
            let proposed = ScorbotIk::new(&robot).unwrap().solve_xyz_pitch_roll(p, pitch, roll).unwrap();
            let same = |a: &Solution, b: &Solution| {
                a.branch == b.branch && a.q.iter().zip(&b.q).all(|(x, y)| wrap_angle(x - y).abs() < 1e-12)
            };
            assert!(proposed.iter().all(|p| sols.iter().any(|s| s.q == p.q && s.branch == p.branch)));
            assert!(sols.iter().all(|s| proposed.iter().any(|p| same(s, p))));
            for s in &sols {
                let fk = robot.fk(&s.q).unwrap().world_from_tool;
                assert!((fk.pos - Vector3::from(p)).norm() < 1e-9, "{s:?}");
                let yaw_only = fk.rot * R_H * rot_x(roll).transpose() * rot_y(pitch).transpose();
                assert!((yaw_only[(2, 2)] - 1.0).abs() < 1e-9, "{s:?}");
            }
            let want: Vec<f64> = q.iter().map(|v| wrap_angle(*v)).collect();
            recovered += sols.iter().any(|s| s.q[..4].iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-7)) as usize;
        }
        assert_eq!(recovered, 300);
    }

    #[test]
    fn rommel_approach_targets_are_reached() {
        let robot = Robot::builtin("rommel").unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(82);
        for _ in 0..300 {
            let q = robot.random_q(&mut rng);
            let fk = robot.fk(&q).unwrap().world_from_tool;
            let a = fk.rot.column(2) * 2.5; // any length
            let target = IkTarget::Typed(TypedTarget::new(&APPROACH, xyz(&fk), &[a.x, a.y, a.z]).unwrap());
            let IkAnswer { solver: name, solutions: sols, .. } = solve_target(&robot, &target, &all()).unwrap();
            assert_eq!(name, "rommel");
            assert!(!sols.is_empty());
            for s in &sols {
                let got = robot.fk(&s.q).unwrap().world_from_tool;
                assert!((got.pos - fk.pos).norm() < 1e-9);
                assert!((got.rot.column(2) - fk.rot.column(2)).norm() < 1e-9);
            }
        }
    }

    #[test]
    fn scara_alpha_targets_follow_the_zone_rule() {
        let robot = Robot::builtin("scara5").unwrap();
        let ik = ScaraIk::new(&robot).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(83);
        let mut reached = 0;
        for _ in 0..300 {
            let q = robot.random_q(&mut rng);
            let p = xyz(&robot.fk(&q).unwrap().world_from_tool);
            let alpha = q[1] + q[2] + q[4];
            let target = IkTarget::Typed(TypedTarget::new(&TOOL_ANGLE, p, &[alpha]).unwrap());
            let request = IkRequest { q0: Some(&q), ..Default::default() };
            let zone = ik.solve_zone([p[0], p[1], p[2], alpha], Some(&q));
            match solve_target(&robot, &target, &request) {
                Ok(IkAnswer { solver: name, solutions: sols, .. }) => {
                    assert_eq!(name, "scara");
                    // The zone rule's solution first, then its copies within limits (q5 has ±360°).
                    assert_eq!(sols[0], zone.unwrap());
                    assert!(sols
                        .iter()
                        .all(|s| s.q[..4] == sols[0].q[..4] && wrap_angle(s.q[4] - sols[0].q[4]).abs() < 1e-12));
                    let s = &sols[0];
                    let fk = robot.fk(&s.q).unwrap().world_from_tool;
                    assert!((fk.pos - Vector3::from(p)).norm() < 1e-9);
                    assert!(wrap_angle(s.q[1] + s.q[2] + s.q[4] - alpha).abs() < 1e-9);
                    assert!(s.orientation_error < 1e-9);
                    reached += 1;
                }
                Err(e) => assert_eq!(Err(e), zone),
            }
        }
        assert!(reached > 60, "{reached}");
    }

    #[test]
    fn position_targets_use_the_masked_numeric_solver() {
        for name in ["puma560", "panda", "scorbot-er-v-plus"] {
            let robot = Robot::builtin(name).unwrap();
            let mut rng = ChaCha8Rng::seed_from_u64(84);
            for _ in 0..15 {
                let q = robot.random_q(&mut rng);
                let p = xyz(&robot.fk(&q).unwrap().world_from_tool);
                let IkAnswer { solver, solutions: sols, .. } =
                    solve_target(&robot, &IkTarget::Position(p), &IkRequest::default()).unwrap();
                assert_eq!(solver, "numeric");
                for s in &sols {
                    assert!((robot.fk(&s.q).unwrap().world_from_tool.pos - Vector3::from(p)).norm() < 1e-6, "{name}");
                }
            }
        }
    }

    /// A fixed q3 the target cannot be reached with is refused with the
    /// closed form's reason; the numeric second look, which does not keep q3,
    /// must not answer instead. The same request in a batch is refused as a
    /// whole when it cannot apply (a mask with position targets).
    #[test]
    fn a_fixed_q3_is_kept_or_the_target_refused() {
        let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
        let ik = IiwaIk::new(&robot).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(86);
        let mut refused = 0;
        for _ in 0..400 {
            let pose = robot.fk(&robot.random_q(&mut rng)).unwrap().world_from_tool;
            let q3 = 2.0;
            let request = IkRequest { q3: Some(q3), ..Default::default() };
            match (ik.solve_q3(&pose, q3), solve_target(&robot, &IkTarget::Pose(pose), &request)) {
                (Err(_), Err(Error::Unreachable { solver, .. })) => {
                    assert_eq!(solver, "iiwa");
                    refused += 1;
                }
                (Err(e), other) => panic!("closed form: {e}; request: {other:?}"),
                (Ok(_), Ok(answer)) => assert!(answer.solutions.iter().all(|s| (s.q[2] - q3).abs() < 1e-12)),
                (Ok(_), Err(e)) => assert!(matches!(e, Error::Unreachable { .. }), "{e}"),
            }
        }
        assert!(refused > 0, "no target out of reach at q3 = 2: the test does not exercise the refusal");
        let targets = [IkTarget::Position([0.4, 0.1, 0.5])];
        let masked = IkRequest { mask: Some([true, true, true, false, false, false]), ..Default::default() };
        let e = crate::ik::solve_batch(&robot, &targets, &masked, &|| {}, &|| false).unwrap_err();
        assert!(e.to_string().contains("task mask"), "{e}");
    }

    #[test]
    fn wrong_combinations_are_refused() {
        let scorbot = Robot::builtin("scorbot-er-v-plus").unwrap();
        let iiwa = Robot::builtin("lbr-iiwa-14-r820").unwrap();
        let typed = IkTarget::Typed(TypedTarget::new(&PITCH_ROLL, [0.4, 0.1, 0.3], &[0.5, 0.0]).unwrap());
        let message = |r: &Robot, t: &IkTarget, q: &IkRequest| solve_target(r, t, q).unwrap_err().to_string();
        let numeric = IkRequest { solver: SolverChoice::Numeric, ..Default::default() };
        assert!(message(&scorbot, &typed, &numeric).contains("select an analytic solver"));
        let q3 = IkRequest { q3: Some(0.0), ..Default::default() };
        let pose = iiwa.fk(iiwa.home()).unwrap().world_from_tool;
        assert!(message(&iiwa, &IkTarget::Position(xyz(&pose)), &q3).contains("full target pose"));
        let both = IkRequest { q3: Some(0.0), psi: Some(0.0), ..Default::default() };
        assert!(message(&iiwa, &IkTarget::Pose(pose), &both).contains("not both"));
        let masked =
            IkRequest { q3: Some(0.0), mask: Some([true, true, true, true, true, false]), ..Default::default() };
        assert!(message(&iiwa, &IkTarget::Pose(pose), &masked).contains("invalid `mask`"));
        assert!(message(&iiwa, &typed, &IkRequest::default()).contains("Scorbot solver needs 5 revolute joints"));
        let approach = IkTarget::Typed(TypedTarget::new(&APPROACH, [0.4, 0.1, 0.3], &[0.0, 0.0, 1.0]).unwrap());
        assert!(message(&scorbot, &approach, &IkRequest::default()).contains("modified-DH"));
        let short = [0.0, 1.0];
        assert!(message(&scorbot, &typed, &IkRequest { q0: Some(&short), ..Default::default() }).contains("5 joints"));
        let nan = IkTarget::Position([f64::NAN, 0.0, 0.0]);
        assert!(message(&scorbot, &nan, &IkRequest::default()).contains("finite"));
        // The analytic solver on a position-only target: refused as for any task mask.
        let analytic = IkRequest { solver: SolverChoice::Analytic, ..Default::default() };
        assert!(message(&scorbot, &IkTarget::Position([0.4, 0.1, 0.3]), &analytic).contains("no analytic solver"));
        // Out of reach: the solver's reason.
        let far = IkTarget::Typed(TypedTarget::new(&PITCH_ROLL, [2.0, 0.0, 0.3], &[0.0, 0.0]).unwrap());
        assert!(matches!(
            solve_target(&scorbot, &far, &IkRequest::default()),
            Err(Error::Unreachable { ref solver, .. }) if solver == "scorbot"
        ));
    }
}
