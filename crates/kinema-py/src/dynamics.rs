//! The arguments and results of the dynamics methods (`rne`, `inertia`,
//! `gravload`, `accel`): Corke's Robotics Toolbox conventions, with every
//! number from `kinema::dynamics`.
//!
//! Each joint-space argument is one configuration, shape (n,), or a batch of
//! N rows, shape (N, n); all of one call have the same shape, and the result
//! has that batch dimension in front (as `fkine_batch` and Corke's methods do).

use kinema::nalgebra::Vector3;
use kinema::{Error, Robot};
use numpy::PyUntypedArrayMethods;
use pyo3::prelude::*;
use pyo3::types::PyString;

use crate::{f64_array, invalid, shape_text, to_numpy, to_py};

/// Corke's default: the acceleration of gravity \[m/s²\] in the world frame,
/// pointing down its z axis (`roboticstoolbox`'s `Robot.gravity`).
const GRAVITY: [f64; 3] = [0.0, 0.0, -9.81];

/// Joint-space arguments read as rows: `values[k]` holds every row of
/// argument k, `rows` is the batch size (None for one configuration).
pub(crate) struct Rows {
    values: Vec<Vec<f64>>,
    rows: Option<usize>,
}

impl Rows {
    /// Reads `args` (`(object, name)`; the first is `q`, which may also be
    /// the name of a pose, as in `fkine`) for a robot of `robot.dof()` joints.
    pub(crate) fn read(robot: &Robot, args: &[(&Bound<'_, PyAny>, &str)]) -> PyResult<Rows> {
        let n = robot.dof();
        let mut values = Vec::with_capacity(args.len());
        let mut first: Option<(Vec<usize>, &str)> = None;
        for (k, &(obj, what)) in args.iter().enumerate() {
            let pose = if k == 0 { obj.downcast::<PyString>().ok() } else { None };
            let (shape, data) = if let Some(name) = pose {
                (vec![n], robot.pose(name.to_str()?).map_err(to_py)?.to_vec())
            } else {
                let a = f64_array(obj, what)?;
                (a.shape().to_vec(), a.as_slice()?.to_vec())
            };
            let fits = match shape.as_slice() {
                [m] => *m == n,
                [_, m] => *m == n,
                _ => false,
            };
            if !fits {
                return Err(invalid(format!(
                    "`{what}` must have shape ({n},) for one configuration or (N, {n}) for N of them, got shape {}",
                    shape_text(&shape)
                )));
            }
            match &first {
                None => first = Some((shape, what)),
                Some((s, w)) if *s != shape => {
                    return Err(invalid(format!(
                        "`{what}` has shape {} but `{w}` has shape {}; give them the same shape (one row per configuration)",
                        shape_text(&shape),
                        shape_text(s)
                    )))
                }
                Some(_) => {}
            }
            values.push(data);
        }
        let rows = first.and_then(|(s, _)| (s.len() == 2).then(|| s[0]));
        Ok(Rows { values, rows })
    }

    /// Runs `f(row of each argument)` for every row without the GIL, and
    /// returns the results as an array of shape `out` per row (with the batch
    /// dimension in front). An error in a batch names the row.
    pub(crate) fn map<'py>(
        &self,
        py: Python<'py>,
        robot: &Robot,
        out: &[usize],
        f: impl Fn(&[&[f64]]) -> kinema::Result<Vec<f64>> + Send + Sync,
    ) -> PyResult<Bound<'py, PyAny>> {
        let n = robot.dof();
        let count = self.rows.unwrap_or(1);
        let data = py
            .allow_threads(|| -> kinema::Result<Vec<f64>> {
                let mut data = Vec::with_capacity(count * out.iter().product::<usize>());
                for k in 0..count {
                    let row: Vec<&[f64]> = self.values.iter().map(|v| &v[k * n..(k + 1) * n]).collect();
                    let r = f(&row).map_err(|e| match self.rows {
                        Some(_) => Error::InBatch { index: k, source: Box::new(e) },
                        None => e,
                    })?;
                    data.extend(r);
                }
                Ok(data)
            })
            .map_err(to_py)?;
        let mut shape: Vec<usize> = self.rows.into_iter().collect();
        shape.extend_from_slice(out);
        Ok(to_numpy(py, shape, data)?.into_any())
    }
}

/// The `gravity` argument: None → [`GRAVITY`], else three finite numbers \[m/s²\].
pub(crate) fn gravity_arg(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Vector3<f64>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(Vector3::from(GRAVITY));
    };
    let a = f64_array(obj, "gravity")?;
    if a.shape() != [3] {
        return Err(invalid(format!(
            "`gravity` must have shape (3,), the acceleration of gravity in the world frame [m/s²] \
             such as [0, 0, -9.81], got shape {}",
            shape_text(a.shape())
        )));
    }
    let g = a.as_slice()?;
    if let Some(x) = g.iter().find(|x| !x.is_finite()) {
        return Err(invalid(format!("`gravity` holds {x}; its three values must be finite [m/s²]")));
    }
    Ok(Vector3::new(g[0], g[1], g[2]))
}

/// M(q) as a row-major n×n list.
pub(crate) fn mass_matrix_rows(robot: &Robot, q: &[f64]) -> kinema::Result<Vec<f64>> {
    Ok(row_major(&kinema::dynamics::mass_matrix(robot, q)?))
}

/// C(q, q̇) as a row-major n×n list.
pub(crate) fn coriolis_matrix_rows(robot: &Robot, q: &[f64], qd: &[f64]) -> kinema::Result<Vec<f64>> {
    Ok(row_major(&kinema::dynamics::coriolis_matrix(robot, q, qd)?))
}

fn row_major(m: &kinema::nalgebra::DMatrix<f64>) -> Vec<f64> {
    let n = m.ncols();
    (0..m.nrows() * n).map(|k| m[(k / n, k % n)]).collect()
}
