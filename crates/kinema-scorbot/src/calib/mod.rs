//! Calibration of the encoder constants (and, optionally, the link lengths)
//! from externally measured tool positions — the future work of seed 000 §V.
//!
//! # Problem
//!
//! Each [`Sample`] pairs the counts ce₁…ce₅ commanded to (or read from) the
//! controller with the tool position p measured by an external system (seed
//! 000 used Whycon, ±1 mm) in the frame of [`kinema::Robot::fk`] — the robot's
//! base frame for the built-in model. With the encoder model of
//! [`crate::encoder`] (u_i = (ce_i + h_i)/cg_i in degrees, θ = eq. 24⁻¹(u)),
//! the model predicts p̂(ce; x) = FK(θ(ce; x)); [`calibrate`] finds the
//! parameters x minimising Σ |p − p̂|² by Levenberg–Marquardt, starting from
//! [`CalibrationOptions::initial`] (e.g. the factory constants).
//!
//! # Identifiability (what the positions can and cannot tell)
//!
//! The tool lies on the roll axis (d5 along z₅; [`calibrate`] refuses a tool
//! offset off that axis), so the position does not depend on θ5, and it
//! depends on the wrist only through the pitch θ2 + θ3 + θ4 = (u5 − u4)/2.
//! Writing the wrist motors as
//!
//! ```text
//! u4 = ce4/cg4 + r − c,   u5 = ce5/cg5 + r + c,
//! c = (h5/cg5 − h4/cg4)/2   (θ2+θ3+θ4 at the controller's home, deg)
//! r = (h4/cg4 + h5/cg5)/2   (θ5 at the controller's home, deg)
//! ```
//!
//! the pitch is (ce5/cg5 − ce4/cg4)/2 + c: it contains cg4, cg5 and c, never r.
//! Hence:
//!
//! * **h4 and h5 are not identifiable separately**, only through c. We
//!   estimate c (parameter `pitch_home`) and keep the roll part r at its
//!   initial value; the returned h4 = cg4·(r − c) and h5 = cg5·(r + c), and their
//!   uncertainties are conditional on r being right (the roll offset needs a
//!   measured orientation, which positions do not give).
//! * **cg4 and cg5 are separable only if the data move motors 4 and 5
//!   independently**, i.e. the roll varies: if ce4 = α·ce5 + β over all
//!   samples (pure pitch motions, or pitch and roll in a fixed proportion),
//!   the pitch is ce5·(1/cg5 − α/cg4)/2 + const, so only that one combination
//!   of cg4 and cg5 (and one offset) is determined. [`calibrate`] refuses such data.
//! * cg_i and h_i of motors 1–3 are separable only if motor i's counts vary.
//! * With identifiable data, the remaining nine parameters
//!   (cg1…cg5, h1, h2, h3, c) are determined: motor 1 by the azimuth of the
//!   tool, motors 2, 3 and the pitch by the arcs of radius a2, a3 and d5 they
//!   sweep in the arm's vertical plane.
//!
//! ## With link lengths ([`CalibrationOptions::estimate_links`])
//!
//! In the arm's vertical plane (radial distance ρ, height z) the model reads
//!
//! ```text
//! ρ = a1 + a2·cos u2 + a3·cos u3 + d5·cos w,   z = d1 + a2·sin u2 − a3·sin u3 + d5·sin w,
//! x = ρ·cos u1,  y = ρ·sin u1,   w = θ2+θ3+θ4 (the pitch angle above)
//! ```
//!
//! * **a1 vs h1**: a1 moves the tool radially, h1 turns it about the base
//!   axis — orthogonal directions; separable whenever ρ ≠ 0.
//! * **d1 vs h2**: d1 shifts every sample vertically by the same amount; h2
//!   turns the upper arm, moving the tool along the arc a2·(−sin u2, cos u2),
//!   which is vertical only near u2 = 0. Separable when the shoulder sweeps a
//!   wide arc; strongly correlated if the samples keep the upper arm near
//!   horizontal.
//! * **a2 vs cg2, a3 vs cg3, d5 vs cg4/cg5/c**: a length is the radius of an
//!   arc, cg its angular scale and h its phase; all three are separable when
//!   the arc spans a good fraction of a radian. Each arc is centred on the
//!   previous joint, so the constants (a1, d1) are not confounded with them.
//! * d5 and a tool translation along z₅ add up: only d5 is estimated; the
//!   tool transform stays as given.
//!
//! So with samples spread over the joint ranges all 14 parameters are
//! identifiable. Measured in the tests (150 random within-limits
//! configurations, 1 mm noise per axis, truth = seed 000's calibrated/measured
//! columns, start = factory): condition number of the scaled Jacobian ≈ 4 for
//! the 9 encoder parameters and ≈ 11 with the 5 link lengths; over 12
//! calibrations the errors divided by the reported sigmas have rms 0.86 and
//! never exceed 2.4. Identifiability is checked numerically in any case: the
//! Jacobian's columns are scaled to unit norm and its condition number
//! (largest / smallest singular value) is reported in
//! [`Calibration::condition_number`]; above
//! [`CalibrationOptions::max_condition`] the calibration is refused, naming
//! the parameters that make up the undetermined combination (the right
//! singular vector of the smallest singular value).
//!
//! # Method
//!
//! Levenberg–Marquardt on the column-scaled Jacobian (Marquardt's scaling:
//! the damping λ acts on every parameter in units of its effect on the
//! positions). The Jacobian is **analytic** for the encoder parameters — the
//! chain rule through the robot's geometric Jacobian J_v (translation rows):
//! ∂p/∂cg_i = J_v·∂θ/∂u_i·∂u_i/∂cg_i with ∂u_i/∂cg_i = −u_i/cg_i
//! (motors 1–3), −ce_i/cg_i² (motors 4, 5), ∂u_i/∂h_i = 1/cg_i,
//! ∂u4/∂c = −1, ∂u5/∂c = +1 — and a **difference** for the link lengths:
//! at fixed joint angles the tool position is affine in every DH length, so
//! p(L + 1 m) − p(L) is the derivative exactly (up to rounding).
//!
//! Uncertainties: the covariance σ²·(JᵀJ)⁻¹ at the solution, with σ² =
//! Σ|p − p̂|² / (3N − P) estimated from the residuals (N samples, P
//! parameters) — i.e. assuming independent, equal-variance errors per axis
//! and a correct model.
//!
//! # Examples
//! ```
//! use kinema::nalgebra::Vector3;
//! use kinema_scorbot::calib::{calibrate, tool_position, CalibrationOptions, Sample};
//! use kinema_scorbot::encoder::Constants;
//! let robot = kinema::Robot::builtin("scorbot-er-v-plus")?;
//! let truth = Constants::named("calibrated")?; // the arm really behaves like this
//! // 40 configurations varying every joint (roll too), noise-free measurements.
//! let samples = (0..40)
//!     .map(|k| {
//!         let t = k as f64;
//!         let q = [0.8 * (0.7 * t).sin(), 0.8 + 0.5 * (1.3 * t).cos(), -0.9 + 0.6 * (0.9 * t).sin(),
//!                  -0.4 + 0.7 * (1.7 * t).cos(), 2.0 * (0.4 * t).sin()];
//!         let counts = truth.counts(&q)?;
//!         Ok(Sample { counts, position: tool_position(&robot, &truth, &counts)? })
//!     })
//!     .collect::<kinema_scorbot::Result<Vec<_>>>()?;
//! let cal = calibrate(&robot, &samples, &CalibrationOptions::default())?; // from the factory values
//! assert!((cal.constants.counts_per_degree[1] - 111.0).abs() < 1e-6);
//! assert!(cal.rms_residual < 1e-9);
//! # Ok::<(), kinema_scorbot::Error>(())
//! ```

mod model;
mod samples;
#[cfg(test)]
mod tests;

use kinema::nalgebra::{DMatrix, DVector, Vector3};
use kinema::Robot;
use serde::Serialize;

use crate::encoder::{Constants, MOTORS};
use crate::error::{Error, Result};

use self::model::Model;
pub use self::samples::{parse_samples_csv, read_samples_csv};

/// One measurement: the counts of the five motors and the tool position the
/// external system measured there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Encoder counts ce₁…ce₅ \[counts\].
    pub counts: [f64; MOTORS],
    /// Measured tool position in the frame of [`Robot::fk`] \[m\].
    pub position: Vector3<f64>,
}

/// Options of [`calibrate`].
#[derive(Debug, Clone, PartialEq)]
pub struct CalibrationOptions {
    /// The starting point, and the source of the roll offset r = (h4/cg4 +
    /// h5/cg5)/2 that positions cannot determine (kept as given).
    pub initial: Constants,
    /// Also estimate the link lengths d1, a1, a2, a3, d5 \[m\] of the model.
    pub estimate_links: bool,
    /// Most Levenberg–Marquardt iterations (Jacobian evaluations); default 100.
    pub max_iterations: usize,
    /// Convergence: stop when a step changes the parameters by less than this
    /// fraction of their effect on the positions (scaled step norm / scaled
    /// parameter norm); default 1e-10.
    pub tolerance: f64,
    /// Refuse when the condition number of the column-scaled Jacobian exceeds
    /// this (the data do not determine some combination of parameters);
    /// default 1e8.
    pub max_condition: f64,
}

impl Default for CalibrationOptions {
    /// From the factory constants, encoder parameters only.
    fn default() -> Self {
        CalibrationOptions {
            initial: Constants::preset(crate::encoder::CountsPerDegree::Factory, crate::encoder::HomeOffsets::Factory),
            estimate_links: false,
            max_iterations: 100,
            tolerance: 1e-10,
            max_condition: 1e8,
        }
    }
}

/// One estimated parameter.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Parameter {
    /// `cg1`…`cg5`, `h1`…`h3`, `pitch_home` (c of the module documentation),
    /// and with links `d1`, `a1`, `a2`, `a3`, `d5`.
    pub name: String,
    /// Its unit: `counts/deg`, `counts`, `deg` or `m`.
    pub unit: String,
    /// The estimate.
    pub value: f64,
    /// Its standard uncertainty (same unit).
    pub sigma: f64,
    /// The starting value (same unit).
    pub initial: f64,
}

/// The result of [`calibrate`].
#[derive(Debug, Clone, Serialize)]
pub struct Calibration {
    /// The estimated constants, with their uncertainties in the `_sigma`
    /// fields. h4 and h5 (and their sigmas) are derived from cg4, cg5,
    /// `pitch_home` and the initial roll offset (see the module documentation).
    pub constants: Constants,
    /// The robot model, with the estimated link lengths if they were
    /// estimated (otherwise the input model).
    #[serde(skip)]
    pub robot: Robot,
    /// Every estimated parameter with its uncertainty, in the order of
    /// [`Calibration::covariance`].
    pub parameters: Vec<Parameter>,
    /// Covariance of the parameters (σ²·(JᵀJ)⁻¹), in their units.
    pub covariance: Vec<Vec<f64>>,
    /// The roll offset r = (h4/cg4 + h5/cg5)/2 kept from the initial constants \[deg\].
    pub roll_home: f64,
    /// √(Σ|p − p̂|² / N): rms distance between measured and predicted positions \[m\].
    pub rms_residual: f64,
    /// Largest distance between a measured and its predicted position \[m\].
    pub max_residual: f64,
    /// Estimated standard deviation of the measurement per axis, σ =
    /// √(Σ|p − p̂|² / (3N − P)) \[m\].
    pub sigma: f64,
    /// Number of samples N.
    pub samples: usize,
    /// Levenberg–Marquardt iterations used.
    pub iterations: usize,
    /// Condition number of the column-scaled Jacobian at the solution (1 for
    /// independent parameters; large when parameters are nearly confounded).
    pub condition_number: f64,
}

/// The tool position \[m\] the model `robot` reaches when the arm behaves
/// as `constants` say and is commanded `counts`: FK(`constants.angles(counts)`).
pub fn tool_position(robot: &Robot, constants: &Constants, counts: &[f64; MOTORS]) -> Result<Vector3<f64>> {
    Ok(robot.fk(&constants.angles(counts)?)?.world_from_tool.pos)
}

/// Names and units of the encoder parameters, in the order of the parameter vector.
const ENCODER: [(&str, &str); 9] = [
    ("cg1", "counts/deg"),
    ("cg2", "counts/deg"),
    ("cg3", "counts/deg"),
    ("cg4", "counts/deg"),
    ("cg5", "counts/deg"),
    ("h1", "counts"),
    ("h2", "counts"),
    ("h3", "counts"),
    ("pitch_home", "deg"),
];
/// The link lengths and where they sit in the DH table: (name, joint index, is `d`).
const LINKS: [(&str, usize, bool); 5] =
    [("d1", 0, true), ("a1", 0, false), ("a2", 1, false), ("a3", 2, false), ("d5", 4, true)];

/// Counts spread below which a motor is taken as not moving (the controller's
/// counts are integers: differences of a count or two are rounding).
const MIN_COUNT_SPREAD: f64 = 2.0;

/// Estimates the encoder constants (and, with `options.estimate_links`, the
/// link lengths d1, a1, a2, a3, d5) of `robot` (the Scorbot model) from
/// `samples`, by Levenberg–Marquardt from `options.initial`. See the module
/// documentation for the parameterisation, what is identifiable and how the
/// uncertainties are computed.
///
/// Errors:
/// * [`Error::NeedsScorbot`]: a robot without the Scorbot structure (five
///   revolute standard-DH joints, tool on the roll axis).
/// * [`Error::NotFinite`]: a sample with a non-finite value.
/// * [`Error::OutOfRange`], [`Error::NotFinite`]: invalid initial constants
///   or options.
/// * [`Error::Calibration`]: fewer samples than needed (3N must exceed the
///   number of parameters); a motor whose counts do not vary (its cg_i and
///   h_i cannot be separated); ce4 an affine function of ce5 (no independent
///   roll: cg4 and cg5 cannot be separated); a condition number above
///   `options.max_condition` (naming the parameters involved); no convergence
///   within `options.max_iterations`.
///
/// # Examples
/// See the [module documentation](self).
pub fn calibrate(robot: &Robot, samples: &[Sample], options: &CalibrationOptions) -> Result<Calibration> {
    let model = Model::new(robot, options)?;
    let p = model.names.len();
    check_options(options)?;
    check_samples(samples, p, &options.initial)?;
    let measured: Vec<f64> = samples.iter().flat_map(|s| s.position.iter().copied()).collect();
    let measured = DVector::from_vec(measured);

    let mut x = model.initial.clone();
    let residual = |x: &DVector<f64>| -> Result<DVector<f64>> { Ok(&measured - model.predict(x, samples)?) };
    let mut r = residual(&x)?;
    let mut cost = r.norm_squared();
    // The data must determine the parameters at the start already.
    let (_, scales, svd) = model.scaled_jacobian(&x, samples)?;
    identifiable(&svd, &scales, &model.names, options.max_condition)?;

    let mut lambda = 1e-3;
    let mut iterations = 0;
    let mut converged = false;
    'outer: while iterations < options.max_iterations {
        iterations += 1;
        let (js, scales, _) = model.scaled_jacobian(&x, samples)?;
        let a = js.tr_mul(&js);
        let g = js.tr_mul(&r);
        let xs = x.component_mul(&scales).norm();
        loop {
            let mut m = a.clone();
            for i in 0..p {
                m[(i, i)] += lambda;
            }
            let step = m.cholesky().map(|c| c.solve(&g));
            if let Some(ds) = step {
                let dx = ds.component_div(&scales);
                let xn = &x + &dx;
                // A step that makes a cg vanish or the model fail is just a bad step.
                let trial = residual(&xn).ok().map(|rn| (rn.norm_squared(), rn));
                if let Some((cost_n, rn)) = trial.filter(|(c, _)| c.is_finite() && *c < cost) {
                    x = xn;
                    r = rn;
                    cost = cost_n;
                    lambda = (lambda / 10.0).max(1e-15);
                    if ds.norm() <= options.tolerance * (xs + options.tolerance) {
                        converged = true;
                        break 'outer;
                    }
                    break;
                }
            }
            lambda *= 10.0;
            if lambda > 1e16 {
                // No step decreases the cost any more: at the minimum to rounding.
                converged = true;
                break 'outer;
            }
        }
    }
    if !converged {
        return Err(Error::Calibration {
            parameters: Vec::new(),
            message: format!(
                "no convergence in {iterations} iterations (rms residual now {:.3} mm); allow more iterations or start closer",
                (cost / samples.len() as f64).sqrt() * 1e3
            ),
        });
    }

    // Uncertainties at the solution.
    let (_, scales, svd) = model.scaled_jacobian(&x, samples)?;
    let condition_number = identifiable(&svd, &scales, &model.names, options.max_condition)?;
    let dof = (3 * samples.len() - p) as f64;
    let sigma2 = cost / dof;
    let v_t = svd.v_t.as_ref().expect("computed with V");
    let mut cov = DMatrix::zeros(p, p);
    for (k, sv) in svd.singular_values.iter().enumerate() {
        let v = v_t.row(k).transpose();
        cov += &v * v.transpose() / (sv * sv);
    }
    for i in 0..p {
        for j in 0..p {
            cov[(i, j)] *= sigma2 / (scales[i] * scales[j]);
        }
    }
    let sig = |i: usize| cov[(i, i)].max(0.0).sqrt();

    let mut constants = model.constants(&x)?;
    constants.name = format!(
        "calibrated from {} samples (kinema-scorbot calib, rms residual {:.3} mm)",
        samples.len(),
        (cost / samples.len() as f64).sqrt() * 1e3
    );
    for i in 0..MOTORS {
        constants.counts_per_degree_sigma[i] = sig(i);
    }
    for i in 0..3 {
        constants.home_offsets_sigma[i] = sig(5 + i);
    }
    // h4 = cg4·(r − c), h5 = cg5·(r + c): first-order propagation from (cg, c)
    // with their covariance; r is taken as exact.
    let c = x[8];
    for (i, sign) in [(3usize, -1.0), (4usize, 1.0)] {
        let g = [model.roll_home + sign * c, sign * x[i]]; // ∂h/∂cg, ∂h/∂c
        let var = g[0] * g[0] * cov[(i, i)] + 2.0 * g[0] * g[1] * cov[(i, 8)] + g[1] * g[1] * cov[(8, 8)];
        constants.home_offsets_sigma[i] = var.max(0.0).sqrt();
    }
    let robot_out = model.robot(&x)?;
    let predicted = model.predict(&x, samples)?;
    let max_residual = (0..samples.len())
        .map(|k| (measured.fixed_rows::<3>(3 * k) - predicted.fixed_rows::<3>(3 * k)).norm())
        .fold(0.0, f64::max);
    let parameters = (0..p)
        .map(|i| Parameter {
            name: model.names[i].0.to_string(),
            unit: model.names[i].1.to_string(),
            value: x[i],
            sigma: sig(i),
            initial: model.initial[i],
        })
        .collect();
    Ok(Calibration {
        constants,
        robot: robot_out,
        parameters,
        covariance: (0..p).map(|i| (0..p).map(|j| cov[(i, j)]).collect()).collect(),
        roll_home: model.roll_home,
        rms_residual: (cost / samples.len() as f64).sqrt(),
        max_residual,
        sigma: sigma2.sqrt(),
        samples: samples.len(),
        iterations,
        condition_number,
    })
}

fn check_options(o: &CalibrationOptions) -> Result<()> {
    if o.max_iterations == 0 {
        return Err(Error::out_of_range("max_iterations", 0.0, "at least one iteration"));
    }
    if !(o.tolerance.is_finite() && o.tolerance > 0.0) {
        return Err(Error::out_of_range("tolerance", o.tolerance, "a positive, finite number"));
    }
    if o.max_condition.is_nan() || o.max_condition <= 1.0 {
        return Err(Error::out_of_range("max_condition", o.max_condition, "a number greater than 1"));
    }
    Ok(())
}

fn check_samples(samples: &[Sample], p: usize, initial: &Constants) -> Result<()> {
    for (k, s) in samples.iter().enumerate() {
        if let Some(i) = s.counts.iter().position(|v| !v.is_finite()) {
            return Err(Error::not_finite(format!("sample {}, count {}", k + 1, i + 1), s.counts[i]));
        }
        if let Some((i, v)) = s.position.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(Error::not_finite(format!("sample {}, position {}", k + 1, ["x", "y", "z"][i]), *v));
        }
    }
    let need = p / 3 + 1;
    if samples.len() < need {
        return Err(Error::Calibration {
            parameters: Vec::new(),
            message: format!(
                "{} sample(s) give {} equations for {p} parameters; at least {need} samples are needed (and many more for useful uncertainties)",
                samples.len(),
                3 * samples.len()
            ),
        });
    }
    let spread = |i: usize| {
        let (lo, hi) = samples
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), s| (a.min(s.counts[i]), b.max(s.counts[i])));
        hi - lo
    };
    for i in 0..MOTORS {
        if spread(i) < MIN_COUNT_SPREAD {
            return Err(Error::Calibration {
                parameters: vec![format!("cg{}", i + 1)],
                message: format!(
                    "motor {}'s counts do not vary over the samples (spread {} counts), so cg{} cannot be told apart from its offset; move motor {} between samples",
                    i + 1,
                    spread(i),
                    i + 1,
                    i + 1
                ),
            });
        }
    }
    // cg4 and cg5 need the roll to vary: ce4 must not be an affine function of ce5.
    let n = samples.len() as f64;
    let (m4, m5) = samples.iter().fold((0.0, 0.0), |(a, b), s| (a + s.counts[3] / n, b + s.counts[4] / n));
    let (s45, s55) = samples
        .iter()
        .fold((0.0, 0.0), |(a, b), s| (a + (s.counts[3] - m4) * (s.counts[4] - m5), b + (s.counts[4] - m5).powi(2)));
    let slope = s45 / s55;
    let rms = (samples.iter().map(|s| (s.counts[3] - m4 - slope * (s.counts[4] - m5)).powi(2)).sum::<f64>() / n).sqrt();
    if rms < MIN_COUNT_SPREAD {
        let roll = rms / initial.counts_per_degree[3].abs();
        return Err(Error::Calibration {
            parameters: vec!["cg4".into(), "cg5".into()],
            message: format!(
                "motors 4 and 5 never move independently (ce4 = {slope:.4}·ce5 + const within {rms:.2} counts rms, ≈{roll:.3}°): \
                 the samples vary the wrist's pitch and roll only in a fixed proportion (e.g. pitch alone), and the position depends on the \
                 wrist only through its pitch, so cg4 and cg5 cannot be told apart — vary the roll independently of the pitch"
            ),
        });
    }
    Ok(())
}

/// Checks the condition number of the column-scaled Jacobian and returns it.
fn identifiable(
    svd: &kinema::nalgebra::SVD<f64, kinema::nalgebra::Dyn, kinema::nalgebra::Dyn>,
    scales: &DVector<f64>,
    names: &[(&str, &str)],
    max_condition: f64,
) -> Result<f64> {
    if let Some(i) = scales.iter().position(|s| !(*s > 0.0 && s.is_finite())) {
        return Err(Error::Calibration {
            parameters: vec![names[i].0.into()],
            message: format!("the positions do not depend on {} at all for these samples", names[i].0),
        });
    }
    let sv = &svd.singular_values;
    let (mut kmin, mut kmax) = (0, 0);
    for k in 0..sv.len() {
        if sv[k] < sv[kmin] {
            kmin = k;
        }
        if sv[k] > sv[kmax] {
            kmax = k;
        }
    }
    let cond = if sv[kmin] > 0.0 { sv[kmax] / sv[kmin] } else { f64::INFINITY };
    if cond.is_nan() || cond > max_condition {
        let v = svd.v_t.as_ref().expect("computed with V").row(kmin).transpose();
        let mut involved: Vec<(usize, f64)> =
            v.iter().enumerate().filter(|(_, c)| c.abs() > 0.1).map(|(i, c)| (i, *c)).collect();
        involved.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
        let combo: Vec<String> = involved.iter().map(|(i, c)| format!("{c:+.2}·{}", names[*i].0)).collect();
        return Err(Error::Calibration {
            parameters: involved.iter().map(|(i, _)| names[*i].0.to_string()).collect(),
            message: format!(
                "the samples do not determine {} (condition number {cond:.2e} > {max_condition:.1e}; the scaled combination {} is free); \
                 spread the samples over the joint ranges",
                involved.iter().map(|(i, _)| names[*i].0).collect::<Vec<_>>().join(", "),
                combo.join(" ")
            ),
        });
    }
    Ok(cond)
}
