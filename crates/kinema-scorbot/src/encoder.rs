//! Joint angles ↔ encoder counts of the Scorbot-ER V Plus (seed 000 eq. 24,
//! Tabla II, Tabla III).
//!
//! # The model
//!
//! The controller drives five motors. Motor 1 turns the base, motor 2 the
//! shoulder; motor 3 sets the elbow as an *absolute* angle (the arm is
//! mechanically "uncoupled": moving the shoulder does not change the forearm's
//! angle to the base), and motors 4 and 5 form a differential wrist: pitch moves
//! them in opposite senses, roll in the same sense. With the kinematic model's
//! joint angles θ1…θ5 in degrees (the joint values of `robots/scorbot-er-v-plus.toml`),
//! eq. 24 defines the motor angles
//!
//! ```text
//! u1 = θ1
//! u2 = θ2
//! u3 = −θ2 − θ3
//! u4 = −θ2 − θ3 − θ4 + θ5
//! u5 =  θ2 + θ3 + θ4 + θ5
//! ```
//!
//! and the counts are ce_i = cg_i · u_i − h_i, with cg_i the counts per degree
//! (Tabla II) and h_i the home offset (Tabla III).
//!
//! # How the home offsets enter (our decision; the seed does not print it)
//!
//! Eq. 24 has no offsets, yet the seed says the controller's home (where every
//! count is zero) differs from the model's home θ = 0 by the counts of Tabla III.
//! We take Tabla III as **the model's motor angles at the controller's home,
//! expressed in counts**: at ce = 0, cg_i·u_i = h_i, hence ce_i = cg_i·u_i − h_i.
//! With the factory values this puts the controller's home at θ ≈ (0°, 120.3°,
//! −95.0°, −88.8°, 0°): tool at x = 169.1 mm, z = 504.4 mm, pitch θ2+θ3+θ4 = −63.5°,
//! which is where the ACL controller reports its home (X 169.0 mm, Z 504.6 mm,
//! P −63.3°) — the opposite sign puts the shoulder at −120°, 85° beyond its
//! limit. The wrist offsets (1773, −1773) are consistent with this reading too:
//! they are a pure pitch (u4 = −u5), no roll.
//!
//! The inverse map solves the linear system exactly:
//! u_i = (ce_i + h_i)/cg_i, θ1 = u1, θ2 = u2, θ3 = −u2 − u3, θ5 = (u4 + u5)/2,
//! θ4 = (u5 − u4)/2 + u3.
//!
//! # Uncertainty
//!
//! Tabla II and III give ± columns for the calibrated and measured sets (the
//! factory sets have none). For commanded counts, an error δcg_i or δh_i moves
//! the arm by δu_i = −u_i·δcg_i/cg_i or δh_i/cg_i, hence δθ = A⁻¹·e_i·δu_i and
//! δp = J_v·δθ (first order). [`Constants::tool_uncertainty`] sums these
//! contributions in quadrature, treating the ten constants as independent.

use std::path::Path;

use kinema::nalgebra::Vector3;
use kinema::{Frame, Robot};
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// Number of motors (and joints) of the Scorbot-ER V Plus.
pub const MOTORS: usize = 5;

/// The largest |count| accepted either way (2³¹ − 1). A Scorbot joint
/// travels a few 10⁴ counts, so anything beyond is a typing or unit error.
pub const MAX_COUNTS: f64 = 2_147_483_647.0;

fn check_count_range(what: &str, counts: &[f64; MOTORS]) -> Result<()> {
    match counts.iter().position(|c| c.abs() > MAX_COUNTS) {
        Some(i) => {
            let of = if what == "counts" { String::new() } else { format!(" for the {what}") };
            Err(Error::out_of_range(
                &format!("motor {} counts{of}", i + 1),
                counts[i],
                format!("a count within ±{MAX_COUNTS}"),
            ))
        }
        None => Ok(()),
    }
}

/// Which counts-per-degree column of seed 000 Tabla II.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CountsPerDegree {
    /// The values stored in the controller ("Fábrica").
    Factory,
    /// The seed's calibration ("Calibración"), with uncertainties.
    Calibrated,
}

/// Which home-offset column of seed 000 Tabla III.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HomeOffsets {
    /// The values stored in the controller ("Fábrica").
    Factory,
    /// The seed's measurement ("Medido"), with uncertainties.
    Measured,
}

/// Tabla II, "Fábrica" \[counts/deg\].
pub const FACTORY_COUNTS_PER_DEGREE: [f64; MOTORS] = [141.88, 113.51, 113.51, 27.9, 27.9];
/// Tabla II, "Calibración" \[counts/deg\].
pub const CALIBRATED_COUNTS_PER_DEGREE: [f64; MOTORS] = [141.0, 111.0, 111.0, 29.0, 29.0];
/// Tabla II, "Calibración", ± column \[counts/deg\].
pub const CALIBRATED_COUNTS_PER_DEGREE_SIGMA: [f64; MOTORS] = [3.0, 3.0, 3.0, 0.5, 0.5];
/// Tabla III, "Fábrica" \[counts\].
pub const FACTORY_HOME_OFFSETS: [f64; MOTORS] = [0.0, 13653.0, -2867.0, 1773.0, -1773.0];
/// Tabla III, "Medido" \[counts\].
pub const MEASURED_HOME_OFFSETS: [f64; MOTORS] = [0.0, 13515.0, -2630.0, 1794.0, -2011.0];
/// Tabla III, "Medido", ± column \[counts\].
pub const MEASURED_HOME_OFFSETS_SIGMA: [f64; MOTORS] = [282.0, 222.0, 222.0, 58.0, 58.0];

/// The constants of the encoder model: counts per degree and home offsets for
/// each motor, with their standard uncertainties (0 where unknown).
///
/// A constants file is TOML with these keys (the `_sigma` keys are optional):
///
/// ```toml
/// name = "lab arm, 2026-11 calibration"
/// counts_per_degree = [141.0, 111.0, 111.0, 29.0, 29.0]
/// counts_per_degree_sigma = [3.0, 3.0, 3.0, 0.5, 0.5]
/// home_offsets = [0, 13515, -2630, 1794, -2011]
/// home_offsets_sigma = [282, 222, 222, 58, 58]
/// ```
///
/// # Examples
/// ```
/// use kinema_scorbot::encoder::{Constants, CountsPerDegree, HomeOffsets};
/// let c = Constants::preset(CountsPerDegree::Factory, HomeOffsets::Factory);
/// let q = [0.1, 1.2, -0.9, -0.5, 0.3]; // rad
/// let counts = c.counts(&q)?;
/// let back = c.angles(&counts)?;
/// assert!(q.iter().zip(&back).all(|(a, b)| (a - b).abs() < 1e-12));
/// // The controller's home (all counts zero) is the model's θ2 ≈ 120.3°.
/// let home = c.angles(&[0.0; 5])?;
/// assert!((home[1].to_degrees() - 13653.0 / 113.51).abs() < 1e-9);
/// # Ok::<(), kinema_scorbot::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Constants {
    /// A name for reports.
    #[serde(default)]
    pub name: String,
    /// cg_i \[counts/deg\], one per motor.
    pub counts_per_degree: [f64; MOTORS],
    /// Standard uncertainty of cg_i \[counts/deg\].
    #[serde(default)]
    pub counts_per_degree_sigma: [f64; MOTORS],
    /// h_i \[counts\]: the model's motor angles at the controller's home, in counts.
    pub home_offsets: [f64; MOTORS],
    /// Standard uncertainty of h_i \[counts\].
    #[serde(default)]
    pub home_offsets_sigma: [f64; MOTORS],
}

/// First-order uncertainty of the tool position caused by the uncertainty of
/// the constants, at one configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct ToolUncertainty {
    /// Standard deviation along base x, y, z \[m\].
    pub sigma: [f64; 3],
    /// √(σx² + σy² + σz²) \[m\].
    pub radius: f64,
    /// Contribution of each constant: its name (`cg1`…`cg5`, `h1`…`h5`) and the
    /// displacement of the tool caused by one standard uncertainty \[m\].
    pub contributions: Vec<(String, [f64; 3])>,
}

impl Constants {
    /// A combination of the seed's tables.
    pub fn preset(cpd: CountsPerDegree, home: HomeOffsets) -> Constants {
        let (c, cs, cn) = match cpd {
            CountsPerDegree::Factory => (FACTORY_COUNTS_PER_DEGREE, [0.0; MOTORS], "factory"),
            CountsPerDegree::Calibrated => {
                (CALIBRATED_COUNTS_PER_DEGREE, CALIBRATED_COUNTS_PER_DEGREE_SIGMA, "calibrated")
            }
        };
        let (h, hs, hn) = match home {
            HomeOffsets::Factory => (FACTORY_HOME_OFFSETS, [0.0; MOTORS], "factory"),
            HomeOffsets::Measured => (MEASURED_HOME_OFFSETS, MEASURED_HOME_OFFSETS_SIGMA, "measured"),
        };
        Constants {
            name: format!("seed 000: {cn} counts per degree (Tabla II), {hn} home offsets (Tabla III)"),
            counts_per_degree: c,
            counts_per_degree_sigma: cs,
            home_offsets: h,
            home_offsets_sigma: hs,
        }
    }

    /// A preset by name: `factory` (both factory columns), `calibrated`
    /// (calibrated counts per degree and measured offsets, the seed's model),
    /// or `CPD/HOME` with CPD `factory|calibrated` and HOME `factory|measured`.
    pub fn named(name: &str) -> Result<Constants> {
        let (c, h) = match name {
            "factory" => (CountsPerDegree::Factory, HomeOffsets::Factory),
            "calibrated" => (CountsPerDegree::Calibrated, HomeOffsets::Measured),
            other => {
                let parse = || -> Option<(CountsPerDegree, HomeOffsets)> {
                    let (a, b) = other.split_once('/')?;
                    let c = match a {
                        "factory" => CountsPerDegree::Factory,
                        "calibrated" => CountsPerDegree::Calibrated,
                        _ => return None,
                    };
                    let h = match b {
                        "factory" => HomeOffsets::Factory,
                        "measured" => HomeOffsets::Measured,
                        _ => return None,
                    };
                    Some((c, h))
                };
                parse().ok_or_else(|| Error::UnknownName {
                    what: "constants".into(),
                    name: other.into(),
                    known: "the presets factory, calibrated, or CPD/HOME with CPD factory|calibrated and \
                                HOME factory|measured (or a .toml file)"
                        .into(),
                })?
            }
        };
        Ok(Constants::preset(c, h))
    }

    /// Parses a constants file's text (see the type's documentation); `origin`
    /// names it in errors.
    pub fn from_toml(text: &str, origin: &str) -> Result<Constants> {
        let c: Constants = toml::from_str(text).map_err(|e| toml_error(text, origin, &e))?;
        c.validate().map_err(|e| Error::InFile { path: origin.into(), source: Box::new(e) })?;
        Ok(c)
    }

    /// The constants as a constants file (see the type's documentation);
    /// [`Constants::from_toml`] reads it back exactly.
    pub fn to_toml(&self) -> String {
        // Serialising plain numbers and a string cannot fail.
        toml::to_string(self).unwrap_or_default()
    }

    /// Reads a constants file (see [`Constants::from_toml`]).
    pub fn from_file(path: &Path) -> Result<Constants> {
        let text =
            std::fs::read_to_string(path).map_err(|e| Error::io(format!("cannot read `{}`", path.display()), e))?;
        Constants::from_toml(&text, &path.display().to_string())
    }

    /// A preset name (see [`Constants::named`]) or, if it ends in `.toml`, a file.
    pub fn load(spec: &str) -> Result<Constants> {
        if spec.ends_with(".toml") {
            Constants::from_file(Path::new(spec))
        } else {
            Constants::named(spec)
        }
    }

    /// Checks that every constant is finite, every cg nonzero and every
    /// uncertainty ≥ 0.
    pub fn validate(&self) -> Result<()> {
        for i in 0..MOTORS {
            let cg = self.counts_per_degree[i];
            if !cg.is_finite() {
                return Err(Error::not_finite(format!("counts_per_degree[{}]", i + 1), cg));
            }
            if cg.abs() < 1e-9 {
                return Err(Error::out_of_range(
                    &format!("counts_per_degree[{}]", i + 1),
                    cg,
                    "a nonzero number of counts per degree",
                ));
            }
            if !self.home_offsets[i].is_finite() {
                return Err(Error::not_finite(format!("home_offsets[{}]", i + 1), self.home_offsets[i]));
            }
            for (what, s) in [
                ("counts_per_degree_sigma", self.counts_per_degree_sigma[i]),
                ("home_offsets_sigma", self.home_offsets_sigma[i]),
            ] {
                if !(s.is_finite() && s >= 0.0) {
                    return Err(Error::out_of_range(&format!("{what}[{}]", i + 1), s, "a finite number ≥ 0"));
                }
            }
        }
        Ok(())
    }

    /// Motor counts for joint angles `q` \[rad\] (eq. 24 with offsets), not
    /// rounded. Errors: not five values, or a value not finite.
    pub fn counts(&self, q: &[f64]) -> Result<[f64; MOTORS]> {
        let q = check_five("joint angles", q)?;
        let u = motor_angles(&q.map(f64::to_degrees));
        Ok(std::array::from_fn(|i| self.counts_per_degree[i] * u[i] - self.home_offsets[i]))
    }

    /// Motor counts rounded to the nearest integer, as the controller takes them.
    pub fn counts_rounded(&self, q: &[f64]) -> Result<[i64; MOTORS]> {
        let c = self.counts(q)?;
        check_count_range("joint angles", &c)?;
        Ok(c.map(|v| v.round() as i64))
    }

    /// Joint angles \[rad\] for motor counts (the inverse of
    /// [`Constants::counts`]). Errors: not five values, a value not finite
    /// or beyond [`MAX_COUNTS`].
    pub fn angles(&self, counts: &[f64]) -> Result<[f64; MOTORS]> {
        let c = check_five("counts", counts)?;
        check_count_range("counts", &c)?;
        let u: [f64; MOTORS] = std::array::from_fn(|i| (c[i] + self.home_offsets[i]) / self.counts_per_degree[i]);
        Ok(joint_angles(&u).map(f64::to_radians))
    }

    /// The tool-position uncertainty at `q` \[rad\] of `robot` (the Scorbot
    /// model) caused by the constants' uncertainties, for an arm commanded with
    /// the counts these constants give for `q` (see the module documentation).
    ///
    /// The ten constants are treated as independent (true of the seed's
    /// tables). Constants written by a calibration are correlated (its h4 and
    /// h5 derive from one estimated pitch offset); for those the full
    /// covariance of `calib::Calibration` is the better guide.
    ///
    /// # Examples
    /// ```
    /// use kinema_scorbot::encoder::Constants;
    /// let robot = kinema::Robot::builtin("scorbot-er-v-plus")?;
    /// let c = Constants::named("calibrated")?;
    /// let u = c.tool_uncertainty(&robot, robot.home())?;
    /// assert!(u.radius > 0.005 && u.radius < 0.05); // several mm to a few cm
    /// let f = Constants::named("factory")?; // no ± columns: no uncertainty
    /// assert_eq!(f.tool_uncertainty(&robot, robot.home())?.radius, 0.0);
    /// # Ok::<(), kinema_scorbot::Error>(())
    /// ```
    pub fn tool_uncertainty(&self, robot: &Robot, q: &[f64]) -> Result<ToolUncertainty> {
        if robot.dof() != MOTORS {
            return Err(Error::DoesNotFit {
                what: "robot".into(),
                reason: format!(
                    "`{}` has {} joints; the encoder model is for the 5-joint Scorbot",
                    robot.name(),
                    robot.dof()
                ),
            });
        }
        let counts = self.counts(q)?;
        let jac = robot.jacobian(q, Frame::Base)?;
        let jv = jac.fixed_rows::<3>(0);
        let u: [f64; MOTORS] = std::array::from_fn(|i| (counts[i] + self.home_offsets[i]) / self.counts_per_degree[i]);
        let mut var = Vector3::zeros();
        let mut contributions = Vec::with_capacity(2 * MOTORS);
        for i in 0..MOTORS {
            let cg = self.counts_per_degree[i];
            // δu_i [deg] for one standard uncertainty of cg_i and of h_i.
            for (name, du) in [
                (format!("cg{}", i + 1), -u[i] / cg * self.counts_per_degree_sigma[i]),
                (format!("h{}", i + 1), self.home_offsets_sigma[i] / cg),
            ] {
                let mut e = [0.0; MOTORS];
                e[i] = du;
                let dtheta = joint_angles(&e).map(f64::to_radians);
                let dp = jv * kinema::nalgebra::DVector::from_column_slice(&dtheta);
                var += dp.component_mul(&dp);
                contributions.push((name, [dp[0], dp[1], dp[2]]));
            }
        }
        let sigma = [var.x.sqrt(), var.y.sqrt(), var.z.sqrt()];
        Ok(ToolUncertainty { sigma, radius: var.sum().sqrt(), contributions })
    }
}

/// Eq. 24 without constants: motor angles u from joint angles θ (same unit).
pub fn motor_angles(t: &[f64; MOTORS]) -> [f64; MOTORS] {
    let t23 = t[1] + t[2];
    let t234 = t23 + t[3];
    [t[0], t[1], -t23, -t234 + t[4], t234 + t[4]]
}

/// The inverse of [`motor_angles`]: joint angles θ from motor angles u.
pub fn joint_angles(u: &[f64; MOTORS]) -> [f64; MOTORS] {
    let t234 = 0.5 * (u[4] - u[3]);
    [u[0], u[1], -u[1] - u[2], t234 + u[2], 0.5 * (u[3] + u[4])]
}

/// An [`Error::Toml`] for a parse error of `text`, with the 1-based line
/// and column of where it went wrong (1, 1 when the parser does not say).
fn toml_error(text: &str, origin: &str, e: &toml::de::Error) -> Error {
    let at = e.span().map_or(0, |s| s.start).min(text.len());
    let before = text.get(..at).unwrap_or("");
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().unwrap_or("").chars().count() + 1;
    Error::Toml { path: origin.into(), line, column, message: e.message().trim_end().to_string() }
}

fn check_five(what: &str, v: &[f64]) -> Result<[f64; MOTORS]> {
    if v.len() != MOTORS {
        return Err(Error::WrongLength {
            what: what.into(),
            got: v.len(),
            expected: MOTORS,
            of: "one per motor of the Scorbot".into(),
        });
    }
    if let Some(i) = v.iter().position(|x| !x.is_finite()) {
        return Err(Error::not_finite(format!("{what}[{}]", i + 1), v[i]));
    }
    Ok(std::array::from_fn(|i| v[i]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn eq24_and_its_inverse_round_trip_over_random_angles_and_constants() {
        let mut rng = ChaCha8Rng::seed_from_u64(24);
        for _ in 0..5000 {
            let c = Constants {
                name: String::new(),
                counts_per_degree: std::array::from_fn(|_| {
                    rng.random_range(10.0..200.0) * [-1.0, 1.0][rng.random_range(0..2)]
                }),
                counts_per_degree_sigma: [0.0; MOTORS],
                home_offsets: std::array::from_fn(|_| rng.random_range(-20000.0..20000.0)),
                home_offsets_sigma: [0.0; MOTORS],
            };
            let q: [f64; MOTORS] = std::array::from_fn(|_| rng.random_range(-3.0..3.0));
            let counts = c.counts(&q).unwrap();
            // Independent check: eq. 24 written out term by term, in degrees.
            let d = q.map(f64::to_degrees);
            let cg = c.counts_per_degree;
            let h = c.home_offsets;
            let eq24 = [
                cg[0] * d[0] - h[0],
                cg[1] * d[1] - h[1],
                cg[2] * (-d[1] - d[2]) - h[2],
                cg[3] * (-d[1] - d[2] - d[3] + d[4]) - h[3],
                cg[4] * (d[1] + d[2] + d[3] + d[4]) - h[4],
            ];
            for i in 0..MOTORS {
                assert!((counts[i] - eq24[i]).abs() < 1e-9 * (1.0 + eq24[i].abs()));
            }
            let back = c.angles(&counts).unwrap();
            for i in 0..MOTORS {
                assert!((back[i] - q[i]).abs() < 1e-11, "{q:?} -> {back:?}");
            }
            // And counts -> angles -> counts.
            let ce: [f64; MOTORS] = std::array::from_fn(|_| rng.random_range(-30000.0..30000.0));
            let again = c.counts(&c.angles(&ce).unwrap()).unwrap();
            for i in 0..MOTORS {
                assert!((again[i] - ce[i]).abs() < 1e-7);
            }
        }
    }

    #[test]
    fn the_controllers_home_is_where_acl_reports_it() {
        // ACL's LISTPV at the controller's home: X 169.0 mm, Z 504.6 mm, pitch −63.3°.
        let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
        let c = Constants::named("factory").unwrap();
        let q = c.angles(&[0.0; 5]).unwrap();
        let p = robot.fk(&q).unwrap().world_from_tool.pos;
        assert!((p.x - 0.169).abs() < 0.001 && p.y.abs() < 1e-9 && (p.z - 0.5046).abs() < 0.001, "{p:?}");
        assert!(((q[1] + q[2] + q[3]).to_degrees() + 63.3).abs() < 0.5);
        assert!(robot.check_q(&q).is_ok());
    }

    #[test]
    fn uncertainty_matches_a_finite_difference_of_the_constants() {
        let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
        let c = Constants::named("calibrated").unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for _ in 0..200 {
            let q = robot.random_q(&mut rng);
            let u = c.tool_uncertainty(&robot, &q).unwrap();
            let counts = c.counts(&q).unwrap();
            let p0 = robot.fk(&q).unwrap().world_from_tool.pos;
            let mut var = [0.0; 3];
            for (k, (name, dp)) in u.contributions.iter().enumerate() {
                // Perturb the constant by ε·σ and difference the FK of the angles
                // the same counts then produce.
                let i = k / 2;
                let eps = 1e-4;
                let mut c2 = c.clone();
                if name.starts_with("cg") {
                    c2.counts_per_degree[i] += eps * c.counts_per_degree_sigma[i];
                } else {
                    c2.home_offsets[i] += eps * c.home_offsets_sigma[i];
                }
                let p1 = robot.fk(&c2.angles(&counts).unwrap()).unwrap().world_from_tool.pos;
                for a in 0..3 {
                    let fd = (p1[a] - p0[a]) / eps;
                    assert!((fd - dp[a]).abs() < 1e-6 + 1e-3 * dp[a].abs(), "{name}: {fd} vs {}", dp[a]);
                    var[a] += fd * fd;
                }
            }
            for (v, s) in var.iter().zip(&u.sigma) {
                assert!((v.sqrt() - s).abs() < 1e-6 + 1e-3 * s);
            }
        }
    }

    #[test]
    fn bad_inputs_and_files_are_refused_with_reasons() {
        let c = Constants::named("factory").unwrap();
        let e = c.counts(&[0.0; 4]).unwrap_err();
        assert!(matches!(&e, Error::WrongLength { what, got: 4, expected: 5, .. } if what == "joint angles"), "{e:?}");
        assert!(e.to_string().contains("4 values"), "{e}");
        let e = c.angles(&[0.0, f64::NAN, 0.0, 0.0, 0.0]).unwrap_err();
        assert!(matches!(&e, Error::NotFinite { what, value } if what == "counts[2]" && value.is_nan()), "{e:?}");
        // `scorbot angles --counts 1e308,…` used to be accepted.
        let e = c.angles(&[1e308, 0.0, 0.0, 0.0, 0.0]).unwrap_err();
        assert!(
            matches!(&e, Error::OutOfRange { what, value, .. } if what == "motor 1 counts" && *value == 1e308),
            "{e:?}"
        );
        assert!(c.angles(&[MAX_COUNTS, -MAX_COUNTS, 0.0, 0.0, 0.0]).is_ok());
        let e = c.counts_rounded(&[1e12, 0.0, 0.0, 0.0, 0.0]).unwrap_err();
        assert!(matches!(&e, Error::OutOfRange { what, .. } if what == "motor 1 counts for the joint angles"), "{e:?}");
        let e = Constants::named("fabrica").unwrap_err();
        assert!(
            matches!(&e, Error::UnknownName { what, name, .. } if what == "constants" && name == "fabrica"),
            "{e:?}"
        );
        let e =
            Constants::from_toml("counts_per_degree = [1,2,3,4,0]\nhome_offsets=[0,0,0,0,0]", "x.toml").unwrap_err();
        assert!(
            matches!(&e, Error::InFile { path, source } if path == "x.toml"
                && matches!(&**source, Error::OutOfRange { what, value, .. } if what == "counts_per_degree[5]" && *value == 0.0)),
            "{e:?}"
        );
        let e = Constants::from_toml("counts_per_degree = [1,2,3]\nhome_offsets=[0,0,0,0,0]", "x.toml").unwrap_err();
        assert!(matches!(&e, Error::Toml { path, line: 1, column: 21.., .. } if path == "x.toml"), "{e:?}");
        assert!(e.to_string().starts_with("x.toml:1:"), "{e}");
        let e = Constants::from_toml("counts_per_degre = [1,2,3,4,5]\nhome_offsets=[0,0,0,0,0]", "x.toml").unwrap_err();
        assert!(e.to_string().contains("counts_per_degre"), "{e}");
        let e = Constants::from_toml("# c\n\ncounts_per_degree = [1,2,3,4,5]\nhome_offsets = [0,0,x]", "x.toml")
            .unwrap_err();
        assert!(matches!(&e, Error::Toml { line: 4, column: 21, .. }), "{e:?}");
        let e = Constants::from_file(Path::new("/nonexistent/c.toml")).unwrap_err();
        let io =
            std::error::Error::source(&e).and_then(|s| s.source()).and_then(|s| s.downcast_ref::<std::io::Error>());
        assert_eq!(io.map(|e| e.kind()), Some(std::io::ErrorKind::NotFound), "{e:?}");
        let ok = Constants::from_toml(&c.to_toml(), "y").unwrap();
        assert_eq!(ok, c);
    }
}
