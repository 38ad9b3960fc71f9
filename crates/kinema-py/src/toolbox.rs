//! The toolbox's names where the meaning is kinema's own: Cartesian
//! interpolation between two poses (`ctraj`, in `python/kinema/_toolbox.py`),
//! and poses handed back as spatialmath `SE3` when asked.

use kinema::traj::cart::{Orientation, Segment};
use pyo3::prelude::*;
use pyo3::types::PyList;

use crate::args::{check_shape, f64_array, pose_from_rows, push_pose, to_numpy};
use crate::errors::{invalid, to_py};

/// The poses at fractions ``s`` (each in [0, 1]) of the straight line from
/// ``T0`` to ``T1`` (4×4 arrays): positions interpolated linearly, rotations
/// by slerp (what ``Robot.lin`` moves along), an (N, 4, 4) array.
#[pyfunction]
#[pyo3(name = "_interpolate_poses")]
#[allow(non_snake_case)]
pub(crate) fn interpolate_poses<'py>(
    py: Python<'py>,
    T0: &Bound<'py, PyAny>,
    T1: &Bound<'py, PyAny>,
    s: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let pose = |obj: &Bound<'py, PyAny>, what: &str| {
        let a = f64_array(obj, what)?;
        check_shape(&a, what, &[Some(4), Some(4)], " (one homogeneous transform)")?;
        pose_from_rows(a.as_slice()?, what)
    };
    let segment = Segment::lin(&pose(T0, "T0")?, &pose(T1, "T1")?, Orientation::Slerp).map_err(to_py)?;
    let s = f64_array(s, "s")?;
    check_shape(&s, "s", &[None], " (fractions of the path)")?;
    let s = s.as_slice()?;
    if let Some(bad) = s.iter().find(|v| !(0.0..=1.0).contains(*v)) {
        return Err(invalid(format!("`s` holds {bad}; fractions of the path lie in [0, 1]")));
    }
    let mut out = vec![0.0; 16 * s.len()];
    for (o, &u) in out.chunks_exact_mut(16).zip(s) {
        push_pose(o, &segment.pose(u));
    }
    Ok(to_numpy(py, (s.len(), 4, 4), out)?.into_any())
}

/// `matrices` (4×4 or (N, 4, 4)) as a spatialmath `SE3`, imported only now:
/// it is an optional dependency.
pub(crate) fn to_se3<'py>(py: Python<'py>, matrices: Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let module = py
        .import("spatialmath")
        .map_err(|_| invalid("`as_se3=True` needs spatialmath: pip install spatialmath-python".into()))?;
    let ndim = matrices.getattr("ndim")?.extract::<usize>()?;
    let arg = if ndim == 3 {
        PyList::new(py, matrices.try_iter()?.collect::<PyResult<Vec<_>>>()?)?.into_any()
    } else {
        matrices
    };
    let kwargs = pyo3::types::PyDict::new(py);
    kwargs.set_item("check", false)?;
    module.getattr("SE3")?.call((arg,), Some(&kwargs))
}

/// [`to_se3`] when `as_se3` asks for it, else the array itself.
pub(crate) fn maybe_se3<'py>(
    py: Python<'py>,
    matrices: Bound<'py, PyAny>,
    as_se3: bool,
) -> PyResult<Bound<'py, PyAny>> {
    if as_se3 {
        to_se3(py, matrices)
    } else {
        Ok(matrices)
    }
}

/// `to_se3` for Python code (`ctraj`), as ``kinema._to_se3``.
#[pyfunction]
#[pyo3(name = "_to_se3")]
pub(crate) fn to_se3_py<'py>(py: Python<'py>, matrices: Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    to_se3(py, matrices)
}
