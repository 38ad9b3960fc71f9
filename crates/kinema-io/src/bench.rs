//! `kinema bench --json`: timings of forward kinematics, the Jacobian and
//! the numeric IK on one machine. Nanoseconds and microseconds per call.

use serde::Serialize;

/// The numeric IK solver timed on reachable targets.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IkBench {
    /// Number of targets.
    pub targets: usize,
    /// Fraction solved within limits and 1e-6 m / 1e-6 rad.
    pub success_rate: f64,
    /// Mean time per solve \[µs\].
    pub mean_us: f64,
    /// Median time per solve \[µs\].
    pub median_us: f64,
    /// 99th percentile \[µs\].
    pub p99_us: f64,
    /// Mean iterations of the solved targets.
    pub mean_iterations: f64,
    /// Restarts over all targets.
    pub restarts: usize,
}

/// The answer of `kinema bench --json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BenchAnswer {
    /// The robot's name.
    pub robot: String,
    /// Its number of joints.
    pub dof: usize,
    /// Number of random configurations.
    pub configurations: usize,
    /// Their seed.
    pub seed: u64,
    /// FK median \[ns\].
    pub fk_ns: f64,
    /// FK 10th percentile \[ns\].
    pub fk_ns_p10: f64,
    /// FK 90th percentile \[ns\].
    pub fk_ns_p90: f64,
    /// Jacobian median \[ns\].
    pub jacobian_ns: f64,
    /// Jacobian 10th percentile \[ns\].
    pub jacobian_ns_p10: f64,
    /// Jacobian 90th percentile \[ns\].
    pub jacobian_ns_p90: f64,
    /// Batched FK on all threads \[ns per configuration\].
    pub fk_batch_ns_per_config: f64,
    /// Threads of the batch.
    pub threads: usize,
    /// The numeric IK, when asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ik: Option<IkBench>,
}
