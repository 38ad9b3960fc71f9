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

use std::f64::consts::PI;
use std::path::Path;

use kinema::nalgebra::{DMatrix, DVector, Vector3};
use kinema::{Frame, LinkGeometry, Robot};
use serde::Serialize;

use crate::csvio;
use crate::encoder::{joint_angles, Constants, MOTORS};
use crate::error::{Error, Result};

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

/// Reads samples: CSV with a header naming columns `c1,c2,c3,c4,c5` (counts)
/// and `x,y,z` (measured tool position, metres), in any order; other columns
/// are ignored; blank lines and `#` lines are skipped. Errors name the file,
/// the line and the offending text.
///
/// # Examples
/// ```
/// let path = std::env::temp_dir().join("kinema-scorbot-doc-samples.csv");
/// std::fs::write(&path, "x,y,z,c1,c2,c3,c4,c5\n0.3,0.01,0.4,100,-2000,500,40,-60\n")?;
/// let s = kinema_scorbot::calib::read_samples_csv(&path)?;
/// assert_eq!(s[0].counts, [100.0, -2000.0, 500.0, 40.0, -60.0]);
/// assert_eq!(s[0].position.z, 0.4);
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_samples_csv(path: &Path) -> Result<Vec<Sample>> {
    Ok(csvio::read_columns(path, &SAMPLE_COLUMNS, &[])?.iter().map(sample).collect())
}

/// Parses the text of a samples file (see [`read_samples_csv`]); `origin`
/// names it in errors.
pub fn parse_samples_csv(text: &str, origin: &str) -> Result<Vec<Sample>> {
    Ok(csvio::parse_columns(text, origin, &SAMPLE_COLUMNS, &[])?.iter().map(sample).collect())
}

const SAMPLE_COLUMNS: [&str; 8] = ["c1", "c2", "c3", "c4", "c5", "x", "y", "z"];

fn sample(r: &csvio::Row) -> Sample {
    let v = &r.req;
    Sample { counts: [v[0], v[1], v[2], v[3], v[4]], position: Vector3::new(v[5], v[6], v[7]) }
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

/// The parameterised model: x = (cg1…cg5, h1, h2, h3, c \[, d1, a1, a2, a3, d5\]).
struct Model<'a> {
    robot: &'a Robot,
    names: Vec<(&'static str, &'static str)>,
    initial: DVector<f64>,
    /// r of the module documentation \[deg\], fixed.
    roll_home: f64,
    estimate_links: bool,
}

impl<'a> Model<'a> {
    fn new(robot: &'a Robot, options: &CalibrationOptions) -> Result<Self> {
        kinema::ik::scorbot::ScorbotIk::new(robot)
            .map_err(|e| Error::NeedsScorbot { needed_by: "the calibration model".into(), source: e })?;
        let c0 = &options.initial;
        c0.validate()?;
        let (cg, h) = (c0.counts_per_degree, c0.home_offsets);
        let mut names: Vec<(&str, &str)> = ENCODER.to_vec();
        let mut x = vec![cg[0], cg[1], cg[2], cg[3], cg[4], h[0], h[1], h[2], 0.5 * (h[4] / cg[4] - h[3] / cg[3])];
        if options.estimate_links {
            for (name, joint, is_d) in LINKS {
                names.push((name, "m"));
                x.push(dh_length(robot, joint, is_d));
            }
        }
        Ok(Model {
            robot,
            names,
            initial: DVector::from_vec(x),
            roll_home: 0.5 * (h[3] / cg[3] + h[4] / cg[4]),
            estimate_links: options.estimate_links,
        })
    }

    fn constants(&self, x: &DVector<f64>) -> Result<Constants> {
        let cg = [x[0], x[1], x[2], x[3], x[4]];
        let c = x[8];
        let h = [x[5], x[6], x[7], cg[3] * (self.roll_home - c), cg[4] * (self.roll_home + c)];
        let out = Constants {
            name: String::new(),
            counts_per_degree: cg,
            counts_per_degree_sigma: [0.0; MOTORS],
            home_offsets: h,
            home_offsets_sigma: [0.0; MOTORS],
        };
        out.validate()?;
        Ok(out)
    }

    fn robot(&self, x: &DVector<f64>) -> Result<Robot> {
        if !self.estimate_links {
            return Ok(self.robot.clone());
        }
        let links: Vec<f64> = (0..LINKS.len()).map(|k| x[ENCODER.len() + k]).collect();
        with_links(self.robot, &links)
    }

    /// Predicted positions, stacked (3N).
    fn predict(&self, x: &DVector<f64>, samples: &[Sample]) -> Result<DVector<f64>> {
        let constants = self.constants(x)?;
        let robot = self.robot(x)?;
        let mut out = DVector::zeros(3 * samples.len());
        for (k, s) in samples.iter().enumerate() {
            out.fixed_rows_mut::<3>(3 * k).copy_from(&tool_position(&robot, &constants, &s.counts)?);
        }
        Ok(out)
    }

    /// The Jacobian of the predicted positions with its columns scaled to
    /// unit norm, the scales (column norms), and the SVD of the scaled one.
    #[allow(clippy::type_complexity)]
    fn scaled_jacobian(
        &self,
        x: &DVector<f64>,
        samples: &[Sample],
    ) -> Result<(DMatrix<f64>, DVector<f64>, kinema::nalgebra::SVD<f64, kinema::nalgebra::Dyn, kinema::nalgebra::Dyn>)>
    {
        let p = self.names.len();
        let constants = self.constants(x)?;
        let robot = self.robot(x)?;
        // Models with one link length longer by 1 m (see the module docs).
        let longer: Vec<Robot> = if self.estimate_links {
            (0..LINKS.len())
                .map(|k| {
                    let mut links: Vec<f64> = (0..LINKS.len()).map(|j| x[ENCODER.len() + j]).collect();
                    links[k] += 1.0;
                    with_links(self.robot, &links)
                })
                .collect::<Result<_>>()?
        } else {
            Vec::new()
        };
        let cg = constants.counts_per_degree;
        let h = constants.home_offsets;
        let deg = PI / 180.0;
        // ∂θ/∂u_i [rad/deg], from the linear inverse of eq. 24.
        let dtheta: [[f64; MOTORS]; MOTORS] = std::array::from_fn(|i| {
            let mut e = [0.0; MOTORS];
            e[i] = deg;
            joint_angles(&e)
        });
        let mut j = DMatrix::zeros(3 * samples.len(), p);
        for (k, s) in samples.iter().enumerate() {
            let q = constants.angles(&s.counts)?;
            let jac = robot.jacobian(&q, Frame::Base)?;
            // g[i] = ∂p/∂u_i [m/deg]
            let g: [Vector3<f64>; MOTORS] = std::array::from_fn(|i| {
                let mut v = Vector3::zeros();
                for (jj, d) in dtheta[i].iter().enumerate() {
                    v += jac.fixed_view::<3, 1>(0, jj) * *d;
                }
                v
            });
            let ce = s.counts;
            let mut set = |col: usize, v: Vector3<f64>| j.fixed_view_mut::<3, 1>(3 * k, col).copy_from(&v);
            for i in 0..3 {
                let u = (ce[i] + h[i]) / cg[i];
                set(i, g[i] * (-u / cg[i]));
                set(5 + i, g[i] / cg[i]);
            }
            set(3, g[3] * (-ce[3] / (cg[3] * cg[3])));
            set(4, g[4] * (-ce[4] / (cg[4] * cg[4])));
            set(8, g[4] - g[3]);
            if self.estimate_links {
                let p0 = robot.fk(&q)?.world_from_tool.pos;
                for (l, r) in longer.iter().enumerate() {
                    set(ENCODER.len() + l, r.fk(&q)?.world_from_tool.pos - p0);
                }
            }
        }
        let scales = DVector::from_iterator(p, j.column_iter().map(|c| c.norm()));
        let mut js = j;
        for (c, s) in scales.iter().enumerate() {
            if *s > 0.0 {
                js.column_mut(c).scale_mut(1.0 / s);
            }
        }
        let svd = js.clone().svd(false, true);
        Ok((js, scales, svd))
    }
}

fn dh_length(robot: &Robot, joint: usize, is_d: bool) -> f64 {
    match robot.joints()[joint].geometry {
        LinkGeometry::Dh { d, a, .. } => {
            if is_d {
                d
            } else {
                a
            }
        }
        // Model::new has checked the standard-DH structure.
        LinkGeometry::General { .. } => unreachable!("checked by ScorbotIk::new"),
    }
}

/// A copy of `robot` with the link lengths d1, a1, a2, a3, d5 \[m\] replaced.
fn with_links(robot: &Robot, links: &[f64]) -> Result<Robot> {
    let mut joints = robot.joints().to_vec();
    for ((_, joint, is_d), value) in LINKS.iter().zip(links) {
        if let LinkGeometry::Dh { d, a, .. } = &mut joints[*joint].geometry {
            if *is_d {
                *d = *value;
            } else {
                *a = *value;
            }
        }
    }
    Ok(Robot::new(robot.model().to_builder().joints(joints).build()?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::encoder::{CountsPerDegree, HomeOffsets};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn scorbot() -> Robot {
        Robot::builtin("scorbot-er-v-plus").unwrap()
    }

    fn truth() -> Constants {
        Constants::preset(CountsPerDegree::Calibrated, HomeOffsets::Measured)
    }

    /// Standard normal deviate (Box–Muller).
    fn gauss(rng: &mut ChaCha8Rng) -> f64 {
        let u1: f64 = rng.random_range(f64::MIN_POSITIVE..1.0);
        let u2: f64 = rng.random_range(0.0..1.0);
        (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
    }

    /// `n` random within-limits configurations of the true arm (`physical`,
    /// the model with the true links), commanded with integer counts,
    /// measured with `noise` \[m\] per axis.
    fn simulate(physical: &Robot, truth: &Constants, n: usize, noise: f64, seed: u64) -> Vec<Sample> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        (0..n)
            .map(|_| {
                let q = physical.random_q(&mut rng);
                let counts = truth.counts_rounded(&q).unwrap().map(|c| c as f64);
                let p = tool_position(physical, truth, &counts).unwrap();
                let e = Vector3::new(gauss(&mut rng), gauss(&mut rng), gauss(&mut rng)) * noise;
                Sample { counts, position: p + e }
            })
            .collect()
    }

    /// The true value of each parameter of a calibration.
    fn true_values(cal: &Calibration, truth: &Constants, links: &[f64]) -> Vec<f64> {
        let (cg, h) = (truth.counts_per_degree, truth.home_offsets);
        cal.parameters
            .iter()
            .map(|p| match p.name.as_str() {
                "cg1" => cg[0],
                "cg2" => cg[1],
                "cg3" => cg[2],
                "cg4" => cg[3],
                "cg5" => cg[4],
                "h1" => h[0],
                "h2" => h[1],
                "h3" => h[2],
                "pitch_home" => 0.5 * (h[4] / cg[4] - h[3] / cg[3]),
                other => links[LINKS.iter().position(|l| l.0 == other).unwrap()],
            })
            .collect()
    }

    fn nominal_links(robot: &Robot) -> Vec<f64> {
        LINKS.iter().map(|(_, j, d)| dh_length(robot, *j, *d)).collect()
    }

    #[test]
    fn jacobian_matches_central_differences() {
        let robot = scorbot();
        for estimate_links in [false, true] {
            let options = CalibrationOptions { estimate_links, ..CalibrationOptions::default() };
            let model = Model::new(&robot, &options).unwrap();
            let samples = simulate(&robot, &truth(), 20, 0.0, 3);
            let x = model.initial.clone();
            let (js, scales, _) = model.scaled_jacobian(&x, &samples).unwrap();
            for c in 0..x.len() {
                // A step of ~1e-6 of each parameter's natural scale, so that
                // every step turns a joint by about 1e-6 rad: rounding in FK
                // then costs ~1e-10 of the derivative and truncation ~1e-12.
                // (A home offset near 0 counts once got a step of 1e-6 counts,
                // 1e-10 rad, where rounding alone was ~1e-6 of the derivative.)
                let scale = match model.names[c].1 {
                    "counts" => 1e4,
                    "deg" => 60.0,
                    _ => 1.0,
                };
                let h = 1e-6 * x[c].abs().max(scale);
                let (mut xp, mut xm) = (x.clone(), x.clone());
                xp[c] += h;
                xm[c] -= h;
                let fd = (model.predict(&xp, &samples).unwrap() - model.predict(&xm, &samples).unwrap()) / (2.0 * h);
                let an = js.column(c) * scales[c];
                assert!((&fd - &an).norm() <= 1e-7 * an.norm(), "{}: {} vs {}", model.names[c].0, fd, an);
            }
        }
    }

    #[test]
    fn noise_free_data_recover_the_truth() {
        let robot = scorbot();
        let t = truth();
        let samples = simulate(&robot, &t, 60, 0.0, 11);
        let cal = calibrate(&robot, &samples, &CalibrationOptions::default()).unwrap();
        let want = true_values(&cal, &t, &[]);
        for (p, w) in cal.parameters.iter().zip(&want) {
            assert!((p.value - w).abs() <= 1e-6 * w.abs().max(1.0), "{}: {} vs {w}", p.name, p.value);
        }
        assert!(cal.rms_residual < 1e-9 && cal.max_residual < 1e-9, "{}", cal.rms_residual);
        // The roll part is kept, so h4 and h5 are those of the factory roll (0), not the truth's.
        assert!(cal.roll_home.abs() < 1e-12);
        let c = &cal.constants;
        assert!(
            (c.home_offsets[4] / c.counts_per_degree[4]
                - c.home_offsets[3] / c.counts_per_degree[3]
                - (t.home_offsets[4] / 29.0 - t.home_offsets[3] / 29.0))
                .abs()
                < 1e-6
        );
        // Links too.
        let mut physical_links = nominal_links(&robot);
        for (l, d) in physical_links.iter_mut().zip([0.002, -0.0015, 0.001, -0.002, 0.003]) {
            *l += d;
        }
        let physical = with_links(&robot, &physical_links).unwrap();
        let samples = simulate(&physical, &t, 80, 0.0, 12);
        let options = CalibrationOptions { estimate_links: true, ..CalibrationOptions::default() };
        let cal = calibrate(&robot, &samples, &options).unwrap();
        let want = true_values(&cal, &t, &physical_links);
        for (p, w) in cal.parameters.iter().zip(&want) {
            assert!((p.value - w).abs() <= 1e-6 * w.abs().max(1e-3), "{}: {} vs {w}", p.name, p.value);
        }
        assert_eq!(nominal_links(&cal.robot).len(), 5);
        for (a, b) in nominal_links(&cal.robot).iter().zip(&physical_links) {
            assert!((a - b).abs() < 1e-9);
        }
    }

    #[test]
    fn one_millimetre_noise_estimates_are_within_their_sigmas() {
        // The acceptance test: truth = Tabla II "Calibración" and Tabla III
        // "Medido", start from the factory columns, 150 random configurations,
        // 1 mm of Gaussian noise per axis.
        let robot = scorbot();
        let t = truth();
        let mut physical_links = nominal_links(&robot);
        for (l, d) in physical_links.iter_mut().zip([0.002, -0.0015, 0.001, -0.002, 0.003]) {
            *l += d;
        }
        let physical = with_links(&robot, &physical_links).unwrap();
        let mut z2 = Vec::new();
        for (estimate_links, arm) in [(false, &robot), (true, &physical)] {
            for seed in 0..6 {
                let samples = simulate(arm, &t, 150, 0.001, 100 + seed);
                let options = CalibrationOptions { estimate_links, ..CalibrationOptions::default() };
                let cal = calibrate(&robot, &samples, &options).unwrap();
                let want = true_values(&cal, &t, &physical_links);
                for (p, w) in cal.parameters.iter().zip(&want) {
                    let z = (p.value - w) / p.sigma;
                    let bound = if seed == 0 { 3.0 } else { 4.0 };
                    assert!(
                        z.abs() < bound,
                        "seed {seed}, links {estimate_links}: {} = {} ± {} vs {w} (z = {z})",
                        p.name,
                        p.value,
                        p.sigma
                    );
                    z2.push(z * z);
                }
                // rms residual ≈ 1 mm·√(3·(1 − P/3N)) (three axes of 1 mm noise).
                let p = cal.parameters.len() as f64;
                let expect = 0.001 * (3.0 * (1.0 - p / 450.0)).sqrt();
                assert!((cal.rms_residual / expect - 1.0).abs() < 0.15, "{} vs {expect}", cal.rms_residual);
                assert!((cal.sigma - 0.001).abs() < 0.00015, "{}", cal.sigma);
                assert!(cal.condition_number > 1.0 && cal.condition_number < 1e5, "{}", cal.condition_number);
                if seed == 0 {
                    eprintln!(
                        "links {estimate_links}: condition number {:.1}, {} iterations",
                        cal.condition_number, cal.iterations
                    );
                }
                // The reported constants carry the sigmas.
                assert_eq!(cal.constants.counts_per_degree_sigma[1], cal.parameters[1].sigma);
                assert!(cal.constants.home_offsets_sigma.iter().all(|s| *s > 0.0));
            }
        }
        let rms = (z2.iter().sum::<f64>() / z2.len() as f64).sqrt();
        eprintln!(
            "normalised errors: rms {rms:.3} over {} estimates, max |z| {:.2}",
            z2.len(),
            z2.iter().fold(0.0f64, |a, b| a.max(*b)).sqrt()
        );
        assert!((0.5..1.5).contains(&rms), "rms of normalised errors {rms}");
    }

    #[test]
    fn data_that_cannot_determine_the_parameters_are_refused() {
        let robot = scorbot();
        let t = truth();
        let opts = CalibrationOptions::default();
        let err = |s: &[Sample], o: &CalibrationOptions| calibrate(&robot, s, o).unwrap_err();
        // Too few samples.
        let few = simulate(&robot, &t, 3, 0.0, 1);
        let e = err(&few, &opts);
        assert!(e.to_string().contains("at least 4 samples"), "{e}");
        // Motor 1 never moves.
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        let mut fixed_base = simulate(&robot, &t, 50, 0.0, 2);
        for s in &mut fixed_base {
            s.counts[0] = 1234.0;
        }
        let e = err(&fixed_base, &opts);
        assert!(matches!(&e, Error::Calibration { parameters, .. } if parameters == &["cg1"]), "{e}");
        // Pure pitch motions: the roll never varies.
        let pitch_only: Vec<Sample> = (0..50)
            .map(|_| {
                let mut q = robot.random_q(&mut rng);
                q[4] = 0.3;
                let counts = t.counts_rounded(&q).unwrap().map(|c| c as f64);
                Sample { counts, position: tool_position(&robot, &t, &counts).unwrap() }
            })
            .collect();
        let e = err(&pitch_only, &opts);
        assert!(e.to_string().contains("cg4 and cg5 cannot be told apart"), "{e}");
        assert!(matches!(&e, Error::Calibration { parameters, .. } if parameters == &["cg4", "cg5"]));
        // The shoulder moving only a hair: the SVD check names what is undetermined.
        let mut narrow = Vec::new();
        for _ in 0..50 {
            let mut q = robot.random_q(&mut rng);
            q[1] = 1.0 + rng.random_range(-1e-9..1e-9);
            let counts = t.counts(&q).unwrap();
            let counts = [counts[0], 5000.0 + rng.random_range(0.0..2.5), counts[2], counts[3], counts[4]];
            narrow.push(Sample { counts, position: tool_position(&robot, &t, &counts).unwrap() });
        }
        // It is determined in principle (noise-free data), but barely: the
        // condition number is large …
        let cal = calibrate(&robot, &narrow, &opts).unwrap();
        assert!(cal.condition_number > 1e4, "{}", cal.condition_number);
        // … and a stricter limit refuses it, naming cg2 and h2 as the free combination.
        let strict = CalibrationOptions { max_condition: 1e4, ..opts.clone() };
        let e = err(&narrow, &strict);
        assert!(
            matches!(&e, Error::Calibration { parameters, .. } if parameters[..2] == ["h2", "cg2"] || parameters[..2] == ["cg2", "h2"]),
            "{e:?}"
        );
        assert!(e.to_string().contains("condition number"), "{e}");
        // Bad samples and options.
        let mut nan = few.clone();
        nan.extend(simulate(&robot, &t, 10, 0.0, 4));
        nan[5].position.y = f64::NAN;
        let e = err(&nan, &opts);
        assert!(matches!(&e, Error::NotFinite { what, .. } if what == "sample 6, position y"), "{e:?}");
        let good = simulate(&robot, &t, 20, 0.0, 5);
        let bad_opts = CalibrationOptions { max_iterations: 0, ..opts.clone() };
        let e = err(&good, &bad_opts);
        assert!(
            matches!(&e, Error::OutOfRange { what, value, .. } if what == "max_iterations" && *value == 0.0),
            "{e:?}"
        );
        let mut bad_initial = opts.clone();
        bad_initial.initial.counts_per_degree[2] = 0.0;
        let e = err(&good, &bad_initial);
        assert!(matches!(&e, Error::OutOfRange { what, .. } if what == "counts_per_degree[3]"), "{e:?}");
        let five = Robot::builtin("scara5");
        if let Ok(other) = five {
            let e = calibrate(&other, &good, &opts).unwrap_err();
            assert!(matches!(&e, Error::NeedsScorbot { .. }), "{e:?}");
            assert!(e.to_string().contains("Scorbot structure"), "{e}");
        }
        let one_iteration = CalibrationOptions { max_iterations: 1, ..opts.clone() };
        let e = err(&simulate(&robot, &t, 30, 0.001, 6), &one_iteration);
        assert!(e.to_string().contains("no convergence in 1 iterations"), "{e}");
    }

    #[test]
    fn samples_files() {
        let s = parse_samples_csv("# c\nc5,c4,c3,c2,c1,z,y,x,t\n5,4,3,2,1,0.3,0.2,0.1,0\n", "s.csv").unwrap();
        assert_eq!(s, vec![Sample { counts: [1.0, 2.0, 3.0, 4.0, 5.0], position: Vector3::new(0.1, 0.2, 0.3) }]);
        let e = parse_samples_csv("c1,c2,c3,c4,x,y,z\n1,2,3,4,0,0,0\n", "s.csv").unwrap_err().to_string();
        assert!(e.starts_with("s.csv:1") && e.contains("`c5`"), "{e}");
        let e = parse_samples_csv("c1,c2,c3,c4,c5,x,y,z\n1,2,3,4,5,0,zero,0\n", "s.csv").unwrap_err().to_string();
        assert!(e.starts_with("s.csv:2") && e.contains("`zero`"), "{e}");
        let e = read_samples_csv(Path::new("/nonexistent/s.csv")).unwrap_err();
        let io =
            std::error::Error::source(&e).and_then(|s| s.source()).and_then(|s| s.downcast_ref::<std::io::Error>());
        assert_eq!(io.map(|e| e.kind()), Some(std::io::ErrorKind::NotFound), "{e:?}");
    }
}
