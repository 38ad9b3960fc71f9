//! Where the self-motion keeps every joint within its limits: the feasible
//! intervals of the arm angle ψ, and the search over ψ and the
//! configuration bits when no q3 or ψ is given.

use super::*;
use crate::error::InputError;

impl IiwaIk {
    /// The intervals of ψ in \[−π, π\] where the solution with configuration
    /// bits `config` keeps every joint within its limits, sorted. An interval
    /// through ψ = ±π is returned as two pieces, one ending at π and one
    /// starting at −π.
    ///
    /// Computed by sampling ψ at [`PSI_SAMPLES`] equally spaced points and
    /// refining each change of feasibility by bisection to [`PSI_TOLERANCE`];
    /// a feasible or infeasible stretch shorter than the sample spacing
    /// (≈ 3 mrad) can be missed. An empty list means no ψ is feasible.
    pub fn feasible_psi_intervals(&self, target: &Pose, config: u8) -> Result<Vec<(f64, f64)>> {
        check_config(config)?;
        let t = self.arm_target(target)?;
        self.elbow(t.w.norm())?;
        let feasible = |psi: f64| -> bool {
            self.solve_psi_raw(&t, psi, config).map(|q| self.robot.limit_flags(&q).is_empty()).unwrap_or(false)
        };
        // Bisection between a and b (feasibility differs); returns the point on the feasible side.
        let refine = |mut a: f64, mut b: f64| -> f64 {
            let fa = feasible(a);
            while (b - a).abs() > PSI_TOLERANCE {
                let m = 0.5 * (a + b);
                if feasible(m) == fa {
                    a = m;
                } else {
                    b = m;
                }
            }
            if fa {
                a
            } else {
                b
            }
        };
        let n = PSI_SAMPLES;
        let psi_at = |k: usize| -PI + TAU * k as f64 / n as f64;
        let mut out = Vec::new();
        let mut start: Option<f64> = if feasible(-PI) { Some(-PI) } else { None };
        let mut prev = start.is_some();
        for k in 1..=n {
            let psi = if k == n { PI } else { psi_at(k) };
            let f = feasible(psi);
            if f != prev {
                let edge = refine(psi_at(k - 1), psi);
                if f {
                    start = Some(edge);
                } else if let Some(s) = start.take() {
                    out.push((s, edge));
                }
                prev = f;
            }
        }
        if let Some(s) = start {
            out.push((s, PI));
        }
        Ok(out)
    }

    /// The solutions within the joint limits for `target` (`world_from_tool`),
    /// searching the self-motion when q3 = `prefer_q3` \[rad\] has none.
    ///
    /// First the closed form at `prefer_q3` ([`IiwaIk::solve_q3`]): if any of
    /// its solutions is within limits, those are returned (labels as there).
    /// Otherwise the arm angle ψ of each of the 8 configurations is searched
    /// ([`IiwaIk::solve_psi`]): [`SEARCH_SAMPLES`] equally spaced samples of the
    /// smallest distance to a joint limit (negative outside), then golden-section
    /// refinement around its [`SEARCH_PEAKS`] highest local maxima. For each
    /// configuration that reaches a non-negative margin, the solution of largest
    /// margin is returned (label `shoulder±/elbow±/wrist±`), so a found solution
    /// keeps as far from the limits as the search saw. Deterministic and bounded:
    /// at most 8 × ([`SEARCH_SAMPLES`] + [`SEARCH_PEAKS`] × ([`SEARCH_STEPS`] + 2)) solves.
    ///
    /// Errors: those of [`IiwaIk::solve_q3`] for a non-finite target or q3 and a
    /// wrist point outside the shoulder–wrist annulus; [`Unreachable::JointLimits`]
    /// (the best margin of each configuration and the joints it violates) when
    /// the search finds no solution within limits. A feasible stretch of ψ
    /// narrower than the refinement brackets can be missed.
    ///
    /// # Examples
    /// ```
    /// use kinema::ik::iiwa::IiwaIk;
    /// let robot = kinema::Robot::builtin("lbr-iiwa-14-r820")?;
    /// let ik = IiwaIk::new(&robot)?;
    /// let q = [0.3, 0.5, -0.7, -1.2, 0.4, 0.8, 0.1];
    /// let sols = ik.solve_searching(&robot.fk(&q)?.world_from_tool, 0.0)?;
    /// assert!(!sols.is_empty());
    /// assert!(sols.iter().all(|s| s.within_limits() && s.position_error < 1e-10 && s.orientation_error < 1e-10));
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn solve_searching(&self, target: &Pose, prefer_q3: f64) -> Result<Vec<Solution>> {
        match self.solve_q3(target, prefer_q3) {
            Ok(sols) if sols.iter().any(Solution::within_limits) => {
                return Ok(sols.into_iter().filter(Solution::within_limits).collect())
            }
            Err(e @ (Error::Input(InputError::OutOfRange { .. }) | Error::Input(InputError::NotFinite { .. }))) => {
                return Err(e)
            }
            _ => {}
        }
        let t = self.arm_target(target)?;
        self.elbow(t.w.norm())?;
        let found = self.search_psi(&t)?;
        found
            .iter()
            .map(|f| Solution::evaluate(&self.robot, f.best.1.to_vec(), target, config_label(f.config)))
            .collect()
    }

    /// The solution within limits nearest to `q_prev` ([`joint_distance`])
    /// among those the ψ search of [`IiwaIk::solve_searching`] sees: every
    /// feasible sample and refined peak of the 8 configurations.
    pub(super) fn nearest_searched(&self, q_prev: &[f64], target: &Pose) -> Result<Solution> {
        let t = self.arm_target(target)?;
        self.elbow(t.w.norm())?;
        let found = self.search_psi(&t)?;
        let dist = |q: &[f64; 7]| joint_distance(&self.robot, q, q_prev);
        let best = found
            .iter()
            .flat_map(|f| f.feasible.iter())
            .min_by(|a, b| dist(a).total_cmp(&dist(b)))
            .copied()
            .unwrap_or(found[0].best.1);
        Solution::evaluate(&self.robot, best.to_vec(), target, config_label(bits(&best)))
    }

    /// The smallest distance of `q` to a joint limit ([`crate::ik::limit_margin`]).
    pub(super) fn limit_margin(&self, q: &[f64; 7]) -> f64 {
        crate::ik::limit_margin(&self.robot, q)
    }

    /// The ψ search of every configuration: those with a solution within
    /// limits, or [`Unreachable::JointLimits`] with each one's best attempt.
    pub(super) fn search_psi(&self, t: &ArmTarget) -> Result<Vec<PsiFound>> {
        let all: Vec<PsiFound> = (0u8..8).map(|c| self.search_config(t, c)).collect();
        if all.iter().any(|f| f.best.0 >= 0.0) {
            return Ok(all.into_iter().filter(|f| f.best.0 >= 0.0).collect());
        }
        let rejected = all
            .iter()
            .map(|f| {
                let joints: Vec<String> =
                    self.robot.limit_flags(&f.best.1).indices().map(|i| format!("q{}", i + 1)).collect();
                format!("{} over ψ: best {:.4} rad outside ({})", config_label(f.config), -f.best.0, joints.join(", "))
            })
            .collect();
        Err(Error::Unreachable { solver: "iiwa".into(), reason: Unreachable::JointLimits { rejected }, closest: None })
    }

    /// Coarse scan of the limit margin over ψ for one configuration, then
    /// golden-section refinement of its highest local maxima.
    pub(super) fn search_config(&self, t: &ArmTarget, config: u8) -> PsiFound {
        let n = SEARCH_SAMPLES;
        let h = TAU / n as f64;
        let psi_at = |k: usize| -PI + h * k as f64;
        let eval = |psi: f64| match self.solve_psi_raw(t, psi, config) {
            Ok(q) => (self.limit_margin(&q), q),
            Err(_) => (f64::NEG_INFINITY, [0.0; 7]),
        };
        let samples: Vec<(f64, [f64; 7])> = (0..n).map(|k| eval(psi_at(k))).collect();
        let m = |k: usize| samples[k % n].0;
        let mut peaks: Vec<usize> = (0..n).filter(|&k| m(k) >= m(k + n - 1) && m(k) >= m(k + 1)).collect();
        peaks.sort_by(|&a, &b| m(b).total_cmp(&m(a)));
        peaks.truncate(SEARCH_PEAKS);
        let refined =
            peaks.iter().map(|&k| eval(golden_max(|psi| eval(psi).0, psi_at(k) - h, psi_at(k) + h, SEARCH_STEPS)));
        let feasible_at = |x: &(f64, [f64; 7])| (x.0 >= 0.0).then_some(x.1);
        let all: Vec<(f64, [f64; 7])> = samples.iter().copied().chain(refined).collect();
        let best = all.iter().copied().max_by(|a, b| a.0.total_cmp(&b.0)).unwrap_or((f64::NEG_INFINITY, [0.0; 7]));
        PsiFound { config, best, feasible: all.iter().filter_map(feasible_at).collect() }
    }
}
