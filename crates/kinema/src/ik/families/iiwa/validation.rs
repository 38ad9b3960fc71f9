//! The validation of seed 004 §V-C: random configurations within the limits,
//! forward kinematics, and the solution at the same q3 nearest to them.

use super::*;

/// One case of [`IiwaIk::validation_cases`].
#[derive(Debug, Clone, PartialEq)]
pub struct ValidationCase {
    /// The random configuration \[rad\].
    pub q: Vec<f64>,
    /// max_i |q_i − q_inv,i| to the nearest solution with the same q3 \[rad\]
    /// (infinite if the target was reported unreachable).
    pub error: f64,
    /// The accuracy the target itself allows \[rad\]: u/σ_min, with u = 2⁻⁵³
    /// the unit roundoff and σ_min the smallest singular value of the
    /// Jacobian without the column of q3 (the 6×6 map that the fixed-q3
    /// solution inverts; m and rad). Rounding the target (each entry by up
    /// to u relative) moves the exact fixed-q3 solution by about this much
    /// in the worst direction, so no double-precision algorithm can promise
    /// a smaller error; it grows without bound near the singularities
    /// (q4 → 0, q6 → 0, the two shoulder solutions meeting).
    pub limit: f64,
}

/// Result of [`IiwaIk::validate`] (seed 004 §V-C).
#[derive(Debug, Clone, PartialEq)]
pub struct ValidationReport {
    /// Number of random configurations tried.
    pub cases: usize,
    /// Largest joint error max_i |q_i − q_inv,i| over all cases \[rad\].
    pub max_error: f64,
    /// Mean of the per-case largest joint error \[rad\].
    pub mean_error: f64,
    /// Fraction of cases whose error is below [`RECOVERED_TOLERANCE`].
    pub recovered_fraction: f64,
    /// The configuration with the largest error.
    pub worst_q: Vec<f64>,
    /// Largest error relative to what the target allows, max error / limit
    /// over the cases (see [`ValidationCase::limit`]): about 1–3 for an
    /// algorithm that loses nothing to its own rounding.
    pub max_error_over_limit: f64,
    /// Largest joint error over the well-conditioned cases, those whose
    /// [`ValidationCase::limit`] is at most [`WELL_CONDITIONED_LIMIT`] \[rad\]
    /// (0 if there are none).
    pub max_error_well_conditioned: f64,
    /// Number of cases counted in `max_error_well_conditioned`.
    pub well_conditioned_cases: usize,
}

impl IiwaIk {
    /// The validation of seed 004 §V-C: `n` random configurations within the
    /// limits (seeded with `seed`) → FK → [`IiwaIk::solve_q3`] with the same
    /// q3 → the solution nearest to the original. The error of a case is
    /// max_i |Δq_i| (differences wrapped to (−π, π]); the paper sums |Δq_i|
    /// instead, which is at most 7 times larger. A case whose target is
    /// reported unreachable counts with an infinite error.
    pub fn validate(&self, n: usize, seed: u64) -> ValidationReport {
        let cases = self.validation_cases(n, seed);
        let (mut max_error, mut sum, mut ok) = (0.0f64, 0.0, 0usize);
        let mut worst_q = Vec::new();
        let (mut max_conditioned, mut conditioned, mut max_ratio) = (0.0f64, 0usize, 0.0f64);
        for c in cases {
            if c.error <= RECOVERED_TOLERANCE {
                ok += 1;
            }
            if c.limit <= WELL_CONDITIONED_LIMIT {
                conditioned += 1;
                max_conditioned = max_conditioned.max(c.error);
            }
            max_ratio = max_ratio.max(c.error / c.limit);
            sum += c.error;
            if c.error > max_error || worst_q.is_empty() {
                max_error = max_error.max(c.error);
                worst_q = c.q;
            }
        }
        ValidationReport {
            cases: n,
            max_error,
            mean_error: if n > 0 { sum / n as f64 } else { 0.0 },
            recovered_fraction: if n > 0 { ok as f64 / n as f64 } else { 0.0 },
            worst_q,
            max_error_over_limit: max_ratio,
            max_error_well_conditioned: max_conditioned,
            well_conditioned_cases: conditioned,
        }
    }

    /// [`ValidationCase::limit`] of `q`: u/σ_min of the Jacobian without
    /// the column of q3 (infinite at a singular configuration).
    pub(super) fn rounding_limit(&self, q: &[f64]) -> f64 {
        let Ok(j) = self.robot.jacobian(q, Frame::Base) else { return f64::INFINITY };
        let j6 = nalgebra::Matrix6::from_fn(|r, c| j[(r, if c < 2 { c } else { c + 1 })]);
        let sigma_min = j6.singular_values().min();
        if sigma_min > 0.0 {
            0.5 * f64::EPSILON / sigma_min
        } else {
            f64::INFINITY
        }
    }

    /// The cases of [`IiwaIk::validate`] one by one, in order (for a plot of
    /// the error per case, seed 004 Fig. 6).
    pub fn validation_cases(&self, n: usize, seed: u64) -> Vec<ValidationCase> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut q = vec![0.0; 7];
        (0..n)
            .map(|_| {
                self.robot.random_q_into(&mut rng, &mut q);
                let error = self.robot.fk(&q).ok().and_then(|fk| self.arm_target(&fk.world_from_tool).ok()).map_or(
                    f64::INFINITY,
                    |t| match self.solve_q3_raw(&t, q[2], 0.0) {
                        Ok(sols) => sols
                            .qs()
                            .iter()
                            .map(|s| s.iter().zip(&q).map(|(a, b)| wrap_angle(a - b).abs()).fold(0.0, f64::max))
                            .fold(f64::INFINITY, f64::min),
                        Err(_) => f64::INFINITY,
                    },
                );
                ValidationCase { q: q.clone(), error, limit: self.rounding_limit(&q) }
            })
            .collect()
    }
}
