//! Numeric inverse kinematics for any chain: damped least squares
//! (Levenberg–Marquardt) with joint limits enforced inside the iteration,
//! deterministic random restarts, a task mask and an optional null-space
//! pull towards a rest configuration.
//!
//! Each iteration solves, in task space (a 6×6 system whatever the number of
//! joints),
//!
//! ```text
//! Δq = Jᵀ (J Jᵀ + λ I)⁻¹ e        (= (JᵀJ + λ I)⁻¹ Jᵀ e)
//! ```
//!
//! with e = \[p* − p; θ·u\] the masked pose error (θ·u the axis-angle vector
//! of R*·Rᵀ) and λ from the chosen [`Damping`], scaled by an adaptive factor
//! that grows when a step does not reduce the error and shrinks when it does.
//! The new configuration is projected onto the joint limits. A start that
//! stalls or runs out of iterations is followed by a restart from a random
//! configuration drawn from a generator seeded with [`NumericOptions::seed`],
//! so the same input gives the same answer, always.

use nalgebra::{Matrix6, Matrix6xX, Vector6};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::{check_target, no_component, Closest, IkSolver, NumericInfo, Solution, Stop, Unreachable};
use crate::error::{Error, InputError, Result};
use crate::kin::Frame;
use crate::math::{rot_to_axis_angle, Pose};
use crate::model::JointType;
use crate::robot::Robot;

/// A start whose error energy has not halved within this many iterations is
/// abandoned for a restart (LM converges much faster than that near a solution).
const STALL_WINDOW: usize = 10;

/// How the damping λ is chosen (E = ½ eᵀe, the current error energy).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Damping {
    /// Chan & Lawrence (1988): λ = E.
    Chan,
    /// Sugihara (2011): λ = E + w̄ with a small constant w̄ = 1e-3 (keeps the
    /// system regular near singularities). The default.
    #[default]
    Sugihara,
    /// Wampler (1986): a constant λ = 1e-3.
    Wampler,
}

/// Options of the numeric solver.
#[derive(Debug, Clone, PartialEq)]
pub struct NumericOptions {
    /// Position tolerance \[m\].
    pub tol_position: f64,
    /// Orientation tolerance \[rad\].
    pub tol_orientation: f64,
    /// Iterations per start.
    pub max_iterations: usize,
    /// Restarts after the first start, as a budget: a solve may spend
    /// `max_iterations × (max_restarts + 1)` iterations in all, and restarts
    /// (past this count if starts stall early) until a start converges or
    /// the budget is spent.
    pub max_restarts: usize,
    /// Seed of the restarts' random configurations.
    pub seed: u64,
    /// Damping rule.
    pub damping: Damping,
    /// Which task components \[vx vy vz ωx ωy ωz\] (base frame) must match.
    /// `None`: all six, whatever the number of joints (an arm with fewer than
    /// six meets a full pose only where the pose lies on its reachable set).
    pub mask: Option<[bool; 6]>,
    /// Project every iterate onto the joint limits (default true).
    pub enforce_limits: bool,
    /// Secondary objective for redundant arms: pull towards this configuration
    /// in the null space of the task.
    pub rest: Option<Vec<f64>>,
    /// Gain of the null-space pull (per iteration, dimensionless).
    pub rest_gain: f64,
}

impl Default for NumericOptions {
    fn default() -> Self {
        NumericOptions {
            tol_position: 1e-6,
            tol_orientation: 1e-6,
            max_iterations: 100,
            max_restarts: 100,
            seed: 0,
            damping: Damping::default(),
            mask: None,
            enforce_limits: true,
            rest: None,
            rest_gain: 0.1,
        }
    }
}

/// The numeric solver for one robot.
///
/// # Examples
/// ```
/// use kinema::ik::{IkSolver, NumericIk};
/// let robot = kinema::Robot::builtin("lbr-iiwa-14-r820")?;
/// let target = robot.fk(&[0.3, 0.5, -0.2, -1.2, 0.4, 0.8, 0.1])?.world_from_tool;
/// let sols = NumericIk::new(&robot).solve(&target)?;
/// assert!(sols[0].position_error < 1e-6 && sols[0].within_limits());
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct NumericIk {
    robot: Robot,
    opts: NumericOptions,
}

impl NumericIk {
    /// A solver with default options.
    pub fn new(robot: &Robot) -> Self {
        NumericIk { robot: robot.clone(), opts: NumericOptions::default() }
    }

    /// A solver with the given options (checked).
    pub fn with_options(robot: &Robot, opts: NumericOptions) -> Result<Self> {
        for (what, value) in [("tol_position", opts.tol_position), ("tol_orientation", opts.tol_orientation)] {
            if !(value > 0.0) {
                return Err(Error::Input(InputError::OutOfRange {
                    what: what.into(),
                    value,
                    expected: "a positive tolerance".into(),
                }));
            }
        }
        if opts.max_iterations == 0 {
            return Err(Error::Input(InputError::OutOfRange {
                what: "max_iterations".into(),
                value: 0.0,
                expected: "at least 1 iteration".into(),
            }));
        }
        if let Some(rest) = &opts.rest {
            robot.check_q(rest)?;
        }
        if !(opts.rest_gain >= 0.0 && opts.rest_gain.is_finite()) {
            return Err(Error::Input(InputError::OutOfRange {
                what: "rest_gain".into(),
                value: opts.rest_gain,
                expected: "a finite gain ≥ 0".into(),
            }));
        }
        if opts.mask.is_some_and(|m| !m.iter().any(|&b| b)) {
            return Err(no_component());
        }
        Ok(NumericIk { robot: robot.clone(), opts })
    }

    /// The options in use.
    pub fn options(&self) -> &NumericOptions {
        &self.opts
    }

    fn mask(&self) -> [bool; 6] {
        self.opts.mask.unwrap_or([true; 6])
    }

    /// Solves starting from `q0` (then from seeded random restarts).
    pub fn solve_from(&self, target: &Pose, q0: &[f64]) -> Result<Solution> {
        check_target(target)?;
        self.robot.check_q(q0)?;
        let r = &self.robot;
        let n = r.dof();
        let mask = self.mask();
        let mut ws = Work { j: Matrix6xX::zeros(n), q: q0.to_vec(), trial: vec![0.0; n] };
        let mut rng = ChaCha8Rng::seed_from_u64(self.opts.seed);
        let mut best = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
        let mut best_q = ws.q.clone();
        let budget = self.iteration_budget();
        let mut spent = 0;
        let mut restart = 0;
        while spent < budget {
            if restart > 0 {
                r.random_q_into(&mut rng, &mut ws.q);
            } else if self.opts.enforce_limits {
                clamp(r, &mut ws.q);
            }
            let (stop, iterations, ep, eo) = self.run(target, &mask, &mut ws)?;
            let energy = ep * ep + eo * eo;
            if energy < best.0 {
                best = (energy, ep, eo);
                best_q.copy_from_slice(&ws.q);
            }
            if stop == Stop::Converged {
                let mut s = Solution::evaluate(r, ws.q.clone(), target, "numeric")?;
                s.numeric = Some(NumericInfo { iterations, restarts: restart, stop });
                return Ok(s);
            }
            // A stalled start costs at least one iteration of the budget.
            spent += iterations.max(1);
            restart += 1;
        }
        Err(Error::Unreachable {
            solver: "numeric".into(),
            reason: Unreachable::NoConvergence {
                position_error: best.1,
                orientation_error: best.2,
                restarts: restart.saturating_sub(1),
                iterations: spent,
            },
            closest: Some(Box::new(Closest { q: best_q, position_error: best.1, orientation_error: best.2 })),
        })
    }

    /// The iterations one solve may spend in all: a full run of
    /// `max_iterations` for the first start and for each of `max_restarts`.
    /// Starts that stall early leave the rest to more restarts.
    fn iteration_budget(&self) -> usize {
        self.opts.max_iterations.saturating_mul(self.opts.max_restarts.saturating_add(1))
    }

    /// One start: iterates from `ws.q`, leaves the result in `ws.q`.
    /// Returns (stop reason, iterations, masked position error, masked orientation error).
    fn run(&self, target: &Pose, mask: &[bool; 6], ws: &mut Work) -> Result<(Stop, usize, f64, f64)> {
        let r = &self.robot;
        let o = &self.opts;
        let fk = crate::kin::jacobian_into(r, &ws.q, Frame::Base, &mut ws.j)?;
        let mut e = task_error(target, &fk.world_from_tool, mask);
        let mut energy = 0.5 * e.norm_squared();
        mask_rows(&mut ws.j, mask);
        let mut mu = 1.0;
        // Energy a few iterations back, to notice a start that no longer makes progress.
        let mut checkpoint = energy;
        for it in 0..o.max_iterations {
            let (ep, eo) = split_norms(&e);
            if ep < o.tol_position && eo < o.tol_orientation {
                return Ok((Stop::Converged, it, ep, eo));
            }
            if it > 0 && it % STALL_WINDOW == 0 {
                if energy > 0.5 * checkpoint {
                    return Ok((Stop::Stalled, it, ep, eo));
                }
                checkpoint = energy;
            }
            let lambda = mu
                * match o.damping {
                    Damping::Chan => energy,
                    Damping::Sugihara => energy + 1e-3,
                    Damping::Wampler => 1e-3,
                };
            let mut a = gram(&ws.j);
            for k in 0..6 {
                a[(k, k)] += lambda.max(1e-12);
            }
            let Some(chol) = a.cholesky() else {
                return Ok((Stop::Stalled, it, ep, eo));
            };
            let y = chol.solve(&e);
            // Δq = Jᵀ y, plus the null-space pull towards the rest pose.
            for (i, t) in ws.trial.iter_mut().enumerate() {
                *t = ws.j.column(i).dot(&y);
            }
            if let Some(rest) = &o.rest {
                // (I − J⁺J) k (rest − q), with the damped J⁺ = Jᵀ A⁻¹.
                let z: Vec<f64> = rest.iter().zip(&ws.q).map(|(a, b)| o.rest_gain * (a - b)).collect();
                let jz: Vector6<f64> = (0..z.len()).fold(Vector6::zeros(), |acc, i| acc + ws.j.column(i) * z[i]);
                let w = chol.solve(&jz);
                for (i, t) in ws.trial.iter_mut().enumerate() {
                    *t += z[i] - ws.j.column(i).dot(&w);
                }
            }
            let step = ws.trial.iter().map(|d| d * d).sum::<f64>().sqrt();
            for (t, q) in ws.trial.iter_mut().zip(&ws.q) {
                *t += q;
            }
            if o.enforce_limits {
                clamp(r, &mut ws.trial);
            }
            let fk_trial = r.fk(&ws.trial)?;
            let e_trial = task_error(target, &fk_trial.world_from_tool, mask);
            let energy_trial = 0.5 * e_trial.norm_squared();
            if energy_trial < energy {
                std::mem::swap(&mut ws.q, &mut ws.trial);
                crate::kin::jacobian_into(r, &ws.q, Frame::Base, &mut ws.j)?;
                mask_rows(&mut ws.j, mask);
                e = e_trial;
                energy = energy_trial;
                mu = (mu * 0.5).max(1e-3);
            } else {
                // Rejected: q and J stay as they are; damp harder.
                mu *= 10.0;
                if mu > 1e10 || step < 1e-15 {
                    return Ok((Stop::Stalled, it + 1, ep, eo));
                }
            }
        }
        let (ep, eo) = split_norms(&e);
        let stop = if ep < o.tol_position && eo < o.tol_orientation { Stop::Converged } else { Stop::MaxIterations };
        Ok((stop, o.max_iterations, ep, eo))
    }
}

impl IkSolver for NumericIk {
    fn name(&self) -> &'static str {
        "numeric"
    }

    /// One solution, started from the robot's `home` configuration and then
    /// from seeded random restarts.
    fn solve(&self, target: &Pose) -> Result<Vec<Solution>> {
        Ok(vec![self.solve_from(target, self.robot.home())?])
    }
}

/// Scratch buffers of one solve.
struct Work {
    j: Matrix6xX<f64>,
    q: Vec<f64>,
    trial: Vec<f64>,
}

/// The masked pose error \[p* − p; θ·u\] in the base frame.
fn task_error(target: &Pose, actual: &Pose, mask: &[bool; 6]) -> Vector6<f64> {
    let dp = target.pos - actual.pos;
    let dw = rot_to_axis_angle(&(target.rot * actual.rot.transpose()));
    let mut e = Vector6::new(dp.x, dp.y, dp.z, dw.x, dw.y, dw.z);
    for k in 0..6 {
        if !mask[k] {
            e[k] = 0.0;
        }
    }
    e
}

/// J·Jᵀ (6×6), accumulated column by column without allocating.
fn gram(j: &Matrix6xX<f64>) -> Matrix6<f64> {
    let mut a = Matrix6::zeros();
    for col in j.column_iter() {
        for r in 0..6 {
            for c in r..6 {
                a[(r, c)] += col[r] * col[c];
            }
        }
    }
    for r in 0..6 {
        for c in 0..r {
            a[(r, c)] = a[(c, r)];
        }
    }
    a
}

fn split_norms(e: &Vector6<f64>) -> (f64, f64) {
    (e.fixed_rows::<3>(0).norm(), e.fixed_rows::<3>(3).norm())
}

fn mask_rows(j: &mut Matrix6xX<f64>, mask: &[bool; 6]) {
    for (k, &m) in mask.iter().enumerate() {
        if !m {
            j.row_mut(k).fill(0.0);
        }
    }
}

/// Projects `q` onto the joint limits (unbounded revolute joints are wrapped
/// into (−π, π] instead, which keeps the numbers small).
fn clamp(robot: &Robot, q: &mut [f64]) {
    for (v, j) in q.iter_mut().zip(robot.joints()) {
        let l = &j.limits;
        if l.min.is_finite() || l.max.is_finite() {
            *v = v.clamp(l.min, l.max);
        } else if j.kind == JointType::Revolute {
            *v = super::wrap_angle(*v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn deterministic_for_the_same_seed() {
        let robot = Robot::builtin("panda").unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let solver = NumericIk::new(&robot);
        for _ in 0..50 {
            let target = robot.fk(&robot.random_q(&mut rng)).unwrap().world_from_tool;
            let a = solver.solve(&target).unwrap();
            let b = solver.solve(&target).unwrap();
            assert_eq!(a, b);
        }
    }

    #[test]
    fn damping_variants_all_converge() {
        let robot = Robot::builtin("ur5").unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for damping in [Damping::Chan, Damping::Sugihara, Damping::Wampler] {
            let solver = NumericIk::with_options(&robot, NumericOptions { damping, ..Default::default() }).unwrap();
            for _ in 0..100 {
                let target = robot.fk(&robot.random_q(&mut rng)).unwrap().world_from_tool;
                let s = &solver.solve(&target).unwrap()[0];
                assert!(s.position_error < 1e-6 && s.orientation_error < 1e-6, "{damping:?}: {s:?}");
                assert!(s.within_limits());
            }
        }
    }
}
