//! Manipulability and singularity analysis of a Jacobian.
//!
//! All functions take a geometric Jacobian with rows \[vx vy vz ωx ωy ωz\]
//! (see [`crate::Robot::jacobian`]) and never panic: a non-finite Jacobian
//! gives an error.

use nalgebra::{DMatrix, DVector, Matrix3, Matrix6xX, Vector3};

use crate::error::{Error, InputError, Result};

/// Which rows of the Jacobian a measure uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Axes {
    /// All six rows.
    #[default]
    All,
    /// Translational rows \[vx vy vz\] (J_v in seed 004 eq. 16).
    Translation,
    /// Rotational rows \[ωx ωy ωz\] (J_ω in seed 004 eq. 16).
    Rotation,
}

pub(crate) fn rows(j: &Matrix6xX<f64>, axes: Axes) -> Result<DMatrix<f64>> {
    if let Some(&value) = j.iter().find(|v| !v.is_finite()) {
        return Err(Error::Input(InputError::NotFinite { what: "jacobian".into(), value }));
    }
    let (start, n) = match axes {
        Axes::All => (0, 6),
        Axes::Translation => (0, 3),
        Axes::Rotation => (3, 3),
    };
    Ok(DMatrix::from_fn(n, j.ncols(), |r, c| j[(start + r, c)]))
}

/// Singular values of the selected rows, largest first.
pub fn singular_values(j: &Matrix6xX<f64>, axes: Axes) -> Result<Vec<f64>> {
    let m = rows(j, axes)?;
    let mut s: Vec<f64> = m.singular_values().iter().copied().collect();
    s.sort_by(|a, b| b.total_cmp(a));
    Ok(s)
}

/// Yoshikawa manipulability √det(J·Jᵀ) of the selected rows (seed 004 eq. 17).
///
/// Computed as the product of the singular values, which equals √det(J·Jᵀ)
/// when the selected block has no more rows than columns; otherwise J·Jᵀ is
/// rank-deficient by construction and the measure is 0 (e.g. a 5-joint arm
/// with [`Axes::All`]).
///
/// # Examples
/// ```
/// use kinema::{Robot, Frame, analysis::{yoshikawa, Axes}};
/// let robot = Robot::builtin("lbr-iiwa-14-r820")?;
/// // Seed 004 Cuadro III: the coupled singularity q2 = … = q5 = 0.
/// let q = [std::f64::consts::FRAC_PI_6, 0.0, 0.0, 0.0, 0.0, std::f64::consts::FRAC_PI_6, std::f64::consts::FRAC_PI_3];
/// let j = robot.jacobian(&q, Frame::Base)?;
/// assert!(yoshikawa(&j, Axes::All)? < 1e-12);
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn yoshikawa(j: &Matrix6xX<f64>, axes: Axes) -> Result<f64> {
    let m = rows(j, axes)?;
    if m.nrows() > m.ncols() {
        return Ok(0.0);
    }
    Ok(m.singular_values().iter().product())
}

/// Condition number σmax/σmin over the min(rows, columns) singular values of
/// the selected rows; `f64::INFINITY` at an exact singularity.
pub fn condition(j: &Matrix6xX<f64>, axes: Axes) -> Result<f64> {
    let s = singular_values(j, axes)?;
    let (max, min) = (s[0], s[s.len() - 1]);
    Ok(if min > 0.0 { max / min } else { f64::INFINITY })
}

/// The default rank tolerance: max(rows, cols) · σmax · ε (as MATLAB's `rank`).
pub fn default_rank_tolerance(rows: usize, cols: usize, sigma_max: f64) -> f64 {
    rows.max(cols) as f64 * sigma_max * f64::EPSILON
}

/// Numerical rank: the number of singular values above `tol`
/// (default [`default_rank_tolerance`]). Returns `(rank, tolerance used)`.
pub fn rank(j: &Matrix6xX<f64>, axes: Axes, tol: Option<f64>) -> Result<(usize, f64)> {
    let m = rows(j, axes)?;
    let s = singular_values(j, axes)?;
    let tol = tol.unwrap_or_else(|| default_rank_tolerance(m.nrows(), m.ncols(), s[0]));
    if !(tol >= 0.0) {
        return Err(Error::Input(InputError::OutOfRange {
            what: "tolerance".into(),
            value: tol,
            expected: "a number ≥ 0".into(),
        }));
    }
    Ok((s.iter().filter(|&&v| v > tol).count(), tol))
}

/// A manipulability ellipsoid {v : vᵀ (J Jᵀ)⁻¹ v ≤ 1} (seed 004 eq. 15) for
/// the translational or rotational rows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ellipsoid {
    /// Principal axes as unit column vectors, largest radius first.
    pub axes: Matrix3<f64>,
    /// Radii along those axes \[m/s or rad/s per unit joint speed\].
    pub radii: Vector3<f64>,
}

/// The manipulability ellipsoid of the translational or rotational rows.
/// Errors for [`Axes::All`] (a 6-D ellipsoid has no 3×3 form).
pub fn ellipsoid(j: &Matrix6xX<f64>, axes: Axes) -> Result<Ellipsoid> {
    if axes == Axes::All {
        return Err(Error::Input(InputError::DoesNotFit {
            what: "axes".into(),
            reason: "an ellipsoid is drawn for translation or rotation, not both".into(),
        }));
    }
    let m = rows(j, axes)?;
    let a: Matrix3<f64> = {
        let p = &m * m.transpose();
        Matrix3::from_fn(|r, c| p[(r, c)])
    };
    let eig = a.symmetric_eigen();
    let mut idx = [0usize, 1, 2];
    idx.sort_by(|&x, &y| eig.eigenvalues[y].total_cmp(&eig.eigenvalues[x]));
    let mut axes_m = Matrix3::zeros();
    let mut radii = Vector3::zeros();
    for (k, &i) in idx.iter().enumerate() {
        axes_m.set_column(k, &eig.eigenvectors.column(i));
        radii[k] = eig.eigenvalues[i].max(0.0).sqrt();
    }
    Ok(Ellipsoid { axes: axes_m, radii })
}

/// Manipulability along a direction of motion (seed 004 eq. 12): the distance
/// from the centre of the translational (or rotational) ellipsoid to its
/// surface along `v`, i.e. 1/√(v̂ᵀ (J Jᵀ)⁻¹ v̂) for the unit vector v̂. It is
/// the largest speed reachable along v̂ with unit joint-speed norm; 0 if the
/// arm cannot move along v̂ at all.
pub fn manipulability_along(j: &Matrix6xX<f64>, axes: Axes, v: &Vector3<f64>) -> Result<f64> {
    let norm = v.norm();
    if !(norm > 0.0 && norm.is_finite()) {
        return Err(Error::Input(InputError::OutOfRange {
            what: "direction".into(),
            value: norm,
            expected: format!("a direction of finite, non-zero length (this is its length; {:?})", v.as_slice()),
        }));
    }
    let e = ellipsoid(j, axes)?;
    let u = v / norm;
    let smax = e.radii[0];
    let mut delta = 0.0;
    for k in 0..3 {
        let c = e.axes.column(k).dot(&u);
        let r = e.radii[k];
        if r <= smax * 1e-12 {
            if c.abs() > 1e-9 {
                return Ok(0.0);
            }
            continue;
        }
        delta += c * c / (r * r);
    }
    Ok(if delta > 0.0 { 1.0 / delta.sqrt() } else { 0.0 })
}

/// A joint whose velocity column is a linear combination of earlier joints'
/// columns — what Corke's `jsingu` reports.
#[derive(Debug, Clone, PartialEq)]
pub struct Dependency {
    /// 0-based index of the dependent joint.
    pub joint: usize,
    /// `(earlier joint, coefficient)`: column(joint) = Σ coefficient · column(earlier joint).
    pub on: Vec<(usize, f64)>,
}

/// Joints whose Jacobian column depends linearly on earlier ones, scanning
/// columns left to right (relative tolerance `tol`, default 1e-9).
///
/// A redundant arm is not reported merely for being redundant: a column is
/// dependent only if it lies in the span of the *earlier* columns, and those
/// do not already span all six task directions.
pub fn dependent_joints(j: &Matrix6xX<f64>, tol: Option<f64>) -> Result<Vec<Dependency>> {
    let m = rows(j, Axes::All)?;
    let tol = tol.unwrap_or(1e-9);
    if !(tol >= 0.0 && tol.is_finite()) {
        return Err(Error::Input(InputError::OutOfRange {
            what: "tolerance".into(),
            value: tol,
            expected: "a finite number ≥ 0".into(),
        }));
    }
    let scale = m.iter().fold(0.0f64, |a, v| a.max(v.abs())).max(1e-300);
    let mut basis: Vec<usize> = Vec::new();
    let mut out = Vec::new();
    for c in 0..m.ncols() {
        let col = m.column(c).into_owned();
        if col.norm() <= tol * scale {
            // A joint that cannot move the tool at all depends on nothing.
            out.push(Dependency { joint: c, on: Vec::new() });
            continue;
        }
        if basis.is_empty() {
            basis.push(c);
            continue;
        }
        if basis.len() == m.nrows() {
            // The earlier columns span every task direction: this column lies
            // in their span only because the arm is redundant.
            continue;
        }
        let b = DMatrix::from_fn(6, basis.len(), |r, k| m[(r, basis[k])]);
        let svd = b.clone().svd(true, true);
        let x: DVector<f64> = svd
            .solve(&col, tol * scale)
            // Fails only for a negative tolerance, refused above.
            .map_err(|e| Error::Infeasible { what: "tolerance".into(), reason: e.into() })?;
        let resid = (&b * &x - &col).norm();
        if resid <= tol * scale.max(col.norm()) * 10.0 {
            let on = basis.iter().zip(x.iter()).filter(|(_, &v)| v.abs() > 1e-9).map(|(&k, &v)| (k, v)).collect();
            out.push(Dependency { joint: c, on });
        } else {
            basis.push(c);
        }
    }
    Ok(out)
}

/// Everything `kinema manip` prints, at one configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// √det(J Jᵀ), all rows.
    pub yoshikawa: f64,
    /// √det(J_v J_vᵀ), translational rows.
    pub yoshikawa_translation: f64,
    /// √det(J_ω J_ωᵀ), rotational rows.
    pub yoshikawa_rotation: f64,
    /// σmax/σmin (∞ at an exact singularity).
    pub condition: f64,
    /// Numerical rank of J.
    pub rank: usize,
    /// Tolerance used for the rank.
    pub rank_tolerance: f64,
    /// Singular values, largest first.
    pub singular_values: Vec<f64>,
    /// Left singular vectors (task-space directions, 6-vectors \[v; ω\]) of the
    /// singular values below the rank tolerance: the directions the tool cannot move in.
    pub singular_directions: Vec<[f64; 6]>,
    /// Linearly dependent joints.
    pub dependent_joints: Vec<Dependency>,
}

/// The full analysis of a Jacobian.
pub fn report(j: &Matrix6xX<f64>) -> Result<Report> {
    let m = rows(j, Axes::All)?;
    let n = m.ncols();
    // One SVD of a 6×max(n, 6) matrix: with fewer than 6 joints, J is padded
    // with zero columns so that U is a full 6×6 basis (the extra singular
    // values are 0 and not reported).
    let mut padded = DMatrix::zeros(6, n.max(6));
    padded.view_mut((0, 0), (6, n)).copy_from(&m);
    let svd = padded.svd(true, false);
    let u = svd.u.as_ref().expect("requested");
    let mut order: Vec<usize> = (0..svd.singular_values.len()).collect();
    order.sort_by(|&a, &b| svd.singular_values[b].total_cmp(&svd.singular_values[a]));
    let s: Vec<f64> = order.iter().take(n.min(6)).map(|&i| svd.singular_values[i]).collect();
    let tol = default_rank_tolerance(m.nrows(), n, s[0]);
    let rank = s.iter().filter(|&&v| v > tol).count();
    // Task directions not reached: left singular vectors beyond the rank.
    let singular_directions = order[rank..6]
        .iter()
        .map(|&c| {
            let col = u.column(c);
            [col[0], col[1], col[2], col[3], col[4], col[5]]
        })
        .collect();
    let min = s[s.len() - 1];
    Ok(Report {
        yoshikawa: if n < 6 { 0.0 } else { s.iter().product() },
        yoshikawa_translation: yoshikawa(j, Axes::Translation)?,
        yoshikawa_rotation: yoshikawa(j, Axes::Rotation)?,
        condition: if min > 0.0 { s[0] / min } else { f64::INFINITY },
        rank,
        rank_tolerance: tol,
        singular_values: s,
        singular_directions,
        dependent_joints: dependent_joints(j, None)?,
    })
}
