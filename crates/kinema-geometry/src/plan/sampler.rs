//! Random configurations within the joint limits.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use kinema::Robot;

/// Uniform sampling of the box of joint limits; a joint without finite
/// limits (a continuous one) is sampled over one turn around zero.
#[derive(Debug, Clone)]
pub(crate) struct Sampler {
    ranges: Vec<(f64, f64)>,
}

impl Sampler {
    pub(crate) fn new(robot: &Robot) -> Sampler {
        let ranges = robot
            .joints()
            .iter()
            .map(|j| {
                let (lo, hi) = (j.limits.min, j.limits.max);
                if lo.is_finite() && hi.is_finite() {
                    (lo, hi)
                } else {
                    (-std::f64::consts::PI, std::f64::consts::PI)
                }
            })
            .collect();
        Sampler { ranges }
    }

    pub(crate) fn sample_into(&self, rng: &mut ChaCha8Rng, out: &mut [f64]) {
        for (x, &(lo, hi)) in out.iter_mut().zip(&self.ranges) {
            *x = if hi > lo { rng.random_range(lo..=hi) } else { lo };
        }
    }

    /// The diagonal of the sampled box (OMPL's "maximum extent").
    pub(crate) fn extent(&self) -> f64 {
        self.ranges.iter().map(|(lo, hi)| (hi - lo) * (hi - lo)).sum::<f64>().sqrt()
    }
}
