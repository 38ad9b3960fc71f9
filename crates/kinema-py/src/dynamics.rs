//! The dynamics methods of `Robot` (`rne`, `inertia`, `coriolis`, `gravload`,
//! `accel`), their arguments and results: Corke's Robotics Toolbox
//! conventions, with every number from `kinema::dynamics`.
//!
//! Each joint-space argument is one configuration, shape (n,), or a batch of
//! N rows, shape (N, n); all of one call have the same shape, and the result
//! has that batch dimension in front (as `fkine_batch` and Corke's methods do).

use kinema::nalgebra::Vector3;
use kinema::{Error, Robot};
use numpy::PyUntypedArrayMethods;
use pyo3::prelude::*;
use pyo3::types::PyString;

use crate::args::{f64_array, shape_text, to_numpy};
use crate::errors::{invalid, to_py};
use crate::robot::PyRobot;

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

#[pymethods]
impl PyRobot {
    /// Inverse dynamics (recursive Newton–Euler, Corke's ``rne``): the joint
    /// torques τ = M(q)·q̈ + C(q, q̇)·q̇ + g(q) [N·m revolute, N prismatic] at
    /// ``q`` [rad or m] with velocities ``qd`` and accelerations ``qdd``.
    /// Each argument has shape (n,), or (N, n) for N configurations (all the
    /// same shape); the result is (n,) or (N, n). ``gravity``: the acceleration
    /// of gravity in the world frame [m/s²], default ``[0, 0, -9.81]`` (as
    /// Corke's ``Robot.gravity``; the arm is pulled towards −z).
    ///
    /// Raises:
    ///     InvalidInput: wrong shapes, NaN/inf.
    ///     KinemaError: a link without mass properties (``[joint.inertial]``
    ///         in TOML, ``<inertial>`` in URDF).
    #[pyo3(signature = (q, qd, qdd, gravity=None))]
    fn rne<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qd: &Bound<'py, PyAny>,
        qdd: &Bound<'py, PyAny>,
        gravity: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let g = gravity_arg(gravity)?;
        let rows = Rows::read(&self.robot, &[(q, "q"), (qd, "qd"), (qdd, "qdd")])?;
        let robot = &*self.robot;
        rows.map(py, robot, &[robot.dof()], |a| kinema::dynamics::rnea(robot, a[0], a[1], a[2], &g))
    }

    /// The joint-space inertia (mass) matrix M(q) (Corke's ``inertia``),
    /// symmetric positive definite, shape (n, n), or (N, n, n) for an (N, n)
    /// ``q`` [kg·m², kg·m or kg].
    #[pyo3(signature = (q))]
    fn inertia<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let n = self.dof();
        let rows = Rows::read(&self.robot, &[(q, "q")])?;
        let robot = &*self.robot;
        rows.map(py, robot, &[n, n], |a| mass_matrix_rows(robot, a[0]))
    }

    /// The Coriolis and centrifugal matrix C(q, q̇) (Corke's ``coriolis``),
    /// shape (n, n), or (N, n, n) for (N, n) rows: C·q̇ is the velocity part
    /// of ``rne`` and Ṁ − 2C is skew-symmetric (Pinocchio's factorisation).
    #[pyo3(signature = (q, qd))]
    fn coriolis<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qd: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let n = self.dof();
        let rows = Rows::read(&self.robot, &[(q, "q"), (qd, "qd")])?;
        let robot = &*self.robot;
        rows.map(py, robot, &[n, n], |a| coriolis_matrix_rows(robot, a[0], a[1]))
    }

    /// The joint torques that hold the arm still against gravity, g(q)
    /// (Corke's ``gravload``; ``rne(q, 0, 0, gravity)``), shape (n,) or
    /// (N, n). ``gravity`` as in :meth:`rne`.
    #[pyo3(signature = (q, gravity=None))]
    fn gravload<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        gravity: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let g = gravity_arg(gravity)?;
        let rows = Rows::read(&self.robot, &[(q, "q")])?;
        let robot = &*self.robot;
        rows.map(py, robot, &[robot.dof()], |a| kinema::dynamics::gravity_torques(robot, a[0], &g))
    }

    /// Forward dynamics (Corke's ``accel``): the joint accelerations q̈
    /// [rad/s² or m/s²] that ``torque`` [N·m or N] gives at ``q`` and ``qd``,
    /// q̈ = M(q)⁻¹·(τ − C(q, q̇)·q̇ − g(q)). Shapes and ``gravity`` as in :meth:`rne`.
    #[pyo3(signature = (q, qd, torque, gravity=None))]
    fn accel<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qd: &Bound<'py, PyAny>,
        torque: &Bound<'py, PyAny>,
        gravity: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let g = gravity_arg(gravity)?;
        let rows = Rows::read(&self.robot, &[(q, "q"), (qd, "qd"), (torque, "torque")])?;
        let robot = &*self.robot;
        rows.map(py, robot, &[robot.dof()], |a| kinema::dynamics::forward_dynamics(robot, a[0], a[1], a[2], &g))
    }
}
