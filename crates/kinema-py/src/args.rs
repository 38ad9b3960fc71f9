//! Argument conversion: numbers, arrays, joint vectors, poses and option strings from Python, and numpy arrays back.

use kinema::analysis::Axes;
use kinema::nalgebra::{Matrix4, Vector3};
use kinema::traj::Waypoint;
use kinema::{Pose, RpyConvention};
use numpy::ndarray::{Array, Dimension, IntoDimension};
use numpy::{IntoPyArray, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyBytes, PyComplex, PyDict, PyFloat, PyInt, PyMemoryView, PyString};

use crate::errors::{invalid, to_py, KinemaError};

pub(crate) fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!("({})", shape.iter().map(usize::to_string).collect::<Vec<_>>().join(", ")),
    }
}

/// `obj` (a numpy array, list, tuple, …) as a C-contiguous float64 array.
/// Arrays that already are one are not copied.
pub(crate) fn f64_array<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<PyReadonlyArrayDyn<'py, f64>> {
    if let Ok(a) = obj.downcast::<PyArrayDyn<f64>>() {
        if a.is_c_contiguous() {
            return Ok(a.readonly());
        }
    }
    if obj.is_instance_of::<PyString>() {
        return Err(invalid(format!("`{what}` must be an array of numbers, not a string")));
    }
    if let Some(matrices) = se3_matrices(obj)? {
        return f64_array(&matrices, what);
    }
    let unreadable = |e: String| invalid(format!("`{what}` cannot be read as an array of float64 numbers: {e}"));
    let np = obj.py().import("numpy")?;
    // First as numpy reads it, so that what float64 would silently change is refused:
    // complex numbers (numpy drops the imaginary part with only a warning), text that
    // numpy would parse as numbers, dates and times.
    let natural = np.call_method1("asarray", (obj,)).map_err(|e| unreadable(e.to_string()))?;
    let dtype = natural.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    match kind.as_str() {
        "c" => {
            return Err(invalid(format!(
                "`{what}` holds complex numbers ({dtype}); joint values and poses are real (float64)"
            )))
        }
        "U" | "S" | "V" | "M" | "m" => return Err(unreadable(format!("it holds {dtype}, not numbers"))),
        // Python objects (a list mixing numbers with text or complex numbers, say): each must
        // be a real number, since float64 would parse the text and drop imaginary parts too.
        "O" => {
            for (k, x) in natural.call_method0("ravel")?.try_iter()?.enumerate() {
                if let Some(held) = not_a_real_number(&np, &x?)? {
                    return Err(invalid(format!(
                        "`{what}` holds {held} at flat index {k}; joint values and poses are real numbers"
                    )));
                }
            }
        }
        _ => {}
    }
    let kwargs = PyDict::new(obj.py());
    kwargs.set_item("dtype", "float64")?;
    kwargs.set_item("order", "C")?;
    let converted = np.call_method("asarray", (natural,), Some(&kwargs)).map_err(|e| unreadable(e.to_string()))?;
    Ok(converted.downcast_into::<PyArrayDyn<f64>>()?.readonly())
}

/// The matrices of a spatialmath `SE3` (anything with the attributes `A`
/// and `t`): one 4×4 array, or (N, 4, 4) for a sequence of N poses, so that a
/// sequence is a batch and never silently its first pose.
fn se3_matrices<'py>(obj: &Bound<'py, PyAny>) -> PyResult<Option<Bound<'py, PyAny>>> {
    if obj.downcast::<PyUntypedArray>().is_ok() || !obj.hasattr("A")? || !obj.hasattr("t")? {
        return Ok(None);
    }
    let a = obj.getattr("A")?;
    Ok(Some(obj.py().import("numpy")?.call_method1("asarray", (a,))?))
}

/// A real-number argument: what Python's `float()` takes, but for complex numbers, which
/// raise TypeError as Python's own `complex` does (numpy's complex scalars would convert,
/// dropping the imaginary part with only a warning).
pub(crate) fn real(obj: &Bound<'_, PyAny>) -> PyResult<f64> {
    if let Ok(f) = obj.downcast_exact::<PyFloat>() {
        return Ok(f.value());
    }
    if is_complex(obj)? {
        let name = obj.get_type().fully_qualified_name()?;
        return Err(pyo3::exceptions::PyTypeError::new_err(format!("must be real number, not {name}")));
    }
    obj.extract()
}

/// A complex number: Python's, or one of numpy's complex scalars (not all of which are
/// Python `complex` subclasses).
fn is_complex(x: &Bound<'_, PyAny>) -> PyResult<bool> {
    Ok(x.is_instance_of::<PyComplex>() || x.is_instance(&x.py().import("numpy")?.getattr("complexfloating")?)?)
}

/// [`real`], or None.
pub(crate) fn opt_real(obj: &Bound<'_, PyAny>) -> PyResult<Option<f64>> {
    if obj.is_none() {
        Ok(None)
    } else {
        real(obj).map(Some)
    }
}

/// What an element of an object array is, when float64 would change it silently rather
/// than take it as the number it is: text (numpy parses it), complex numbers (the
/// imaginary part is dropped), dates and times (turned into counts), arrays of those.
fn not_a_real_number(np: &Bound<'_, PyModule>, x: &Bound<'_, PyAny>) -> PyResult<Option<String>> {
    if x.is_exact_instance_of::<PyFloat>() || x.is_exact_instance_of::<PyInt>() {
        return Ok(None);
    }
    let name = || x.get_type().fully_qualified_name().map(|n| n.to_string());
    let text = x.is_instance_of::<PyString>()
        || x.is_instance_of::<PyBytes>()
        || x.is_instance_of::<PyByteArray>()
        || x.is_instance_of::<PyMemoryView>();
    if text {
        return Ok(Some(format!("text ({})", name()?)));
    }
    if is_complex(x)? {
        return Ok(Some(format!("a complex number ({})", name()?)));
    }
    if x.is_instance(&np.getattr("datetime64")?)? || x.is_instance(&np.getattr("timedelta64")?)? {
        return Ok(Some(format!("a date or time ({})", name()?)));
    }
    if let Ok(a) = x.downcast::<PyUntypedArray>() {
        let dtype = a.dtype();
        let kind: String = dtype.getattr("kind")?.extract()?;
        if "cUSVMmO".contains(kind.as_str()) {
            return Ok(Some(format!("an array of {dtype}")));
        }
    }
    Ok(None)
}

/// Checks that `a` has `ndim` dimensions and, where `expected` gives one, that size.
pub(crate) fn check_shape(
    a: &PyReadonlyArrayDyn<'_, f64>,
    what: &str,
    expected: &[Option<usize>],
    hint: &str,
) -> PyResult<()> {
    let shape = a.shape();
    let fits = shape.len() == expected.len() && shape.iter().zip(expected).all(|(s, e)| e.is_none_or(|e| *s == e));
    if fits {
        return Ok(());
    }
    let want: Vec<String> = expected.iter().map(|e| e.map_or("N".to_string(), |v| v.to_string())).collect();
    let want = if want.len() == 1 { format!("({},)", want[0]) } else { format!("({})", want.join(", ")) };
    Err(invalid(format!("`{what}` must have shape {want}{hint}, got shape {}", shape_text(shape))))
}

/// A C-order numpy array of `shape` from row-major `data` (moved, not copied).
pub(crate) fn to_numpy<'py, D: IntoDimension>(
    py: Python<'py>,
    shape: D,
    data: Vec<f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>>
where
    D::Dim: Dimension,
{
    let a = Array::from_shape_vec(shape.into_dimension(), data)
        .map_err(|e| KinemaError::new_err(format!("internal shape error: {e}")))?;
    Ok(a.into_dyn().into_pyarray(py))
}

pub(crate) fn push_pose(out: &mut [f64], pose: &Pose) {
    for (r, row) in pose.to_rows().iter().enumerate() {
        out[4 * r..4 * r + 4].copy_from_slice(row);
    }
}

pub(crate) fn parse_axes(axes: &str) -> PyResult<Axes> {
    match axes {
        "all" => Ok(Axes::All),
        "trans" => Ok(Axes::Translation),
        "rot" => Ok(Axes::Rotation),
        other => Err(invalid(format!("invalid `axes`: `{other}`; use \"all\", \"trans\" or \"rot\""))),
    }
}

/// A 4×4 row-major block as a pose, or the error naming `what`.
pub(crate) fn pose_from_rows(rows: &[f64], what: &str) -> PyResult<Pose> {
    Pose::from_matrix(&Matrix4::from_row_slice(rows)).ok_or_else(|| {
        invalid(format!(
            "`{what}` is not a rigid transform: it must be finite, the last row 0 0 0 1 and the 3×3 block a rotation"
        ))
    })
}

/// What a pose argument may be, for shape errors.
const POSE_SHAPES: &str = " (a homogeneous transform) or (6,) (x, y, z, roll, pitch, yaw)";

/// x, y, z \[m\], roll, pitch, yaw \[rad\] in `conv` as a pose (as the CLI
/// reads `--pose` and `--to`), or the error naming `what`.
fn pose_from_xyz_rpy(v: &[f64], what: &str, conv: RpyConvention) -> PyResult<Pose> {
    check_finite(v, what)?;
    Ok(Pose::from_xyz_rpy([v[0], v[1], v[2]], [v[3], v[4], v[5]], conv))
}

/// A pose argument: a 4×4 homogeneous transform, or 6 numbers x, y, z, roll,
/// pitch, yaw (roll-pitch-yaw convention `conv`).
pub(crate) fn pose_arg(obj: &Bound<'_, PyAny>, what: &str, conv: RpyConvention) -> PyResult<Pose> {
    Ok(*waypoint_arg(obj, what, conv)?.pose())
}

/// A pose argument that keeps a roll-pitch-yaw triple as written, for LIN
/// with `orientation="rpy"` (seed 004 eq. 40).
pub(crate) fn waypoint_arg(obj: &Bound<'_, PyAny>, what: &str, conv: RpyConvention) -> PyResult<Waypoint> {
    let t = f64_array(obj, what)?;
    if t.shape() == [6] {
        return waypoint_from_xyz_rpy(t.as_slice()?, what, conv);
    }
    check_shape(&t, what, &[Some(4), Some(4)], POSE_SHAPES)?;
    Ok(Waypoint::from(pose_from_rows(t.as_slice()?, what)?))
}

pub(crate) fn waypoint_from_xyz_rpy(v: &[f64], what: &str, conv: RpyConvention) -> PyResult<Waypoint> {
    pose_from_xyz_rpy(v, what, conv)?;
    Ok(Waypoint::from_xyz_rpy([v[0], v[1], v[2]], [v[3], v[4], v[5]], conv))
}

/// Several poses: a (V, 4, 4) array or a list of 4×4 arrays, a (V, 6) array
/// or a list of x, y, z, roll, pitch, yaw rows; one pose (4×4 or 6 numbers)
/// is a list of one. Roll-pitch-yaw triples are kept as written.
pub(crate) fn waypoint_list(obj: &Bound<'_, PyAny>, what: &str, conv: RpyConvention) -> PyResult<Vec<Waypoint>> {
    let t = f64_array(obj, what)?;
    match t.shape() {
        [6] | [4, 4] => Ok(vec![waypoint_arg(obj, what, conv)?]),
        [_, 6] => t
            .as_slice()?
            .chunks_exact(6)
            .enumerate()
            .map(|(i, row)| waypoint_from_xyz_rpy(row, &format!("{what}[{i}]"), conv))
            .collect(),
        _ => {
            check_shape(
                &t,
                what,
                &[None, Some(4), Some(4)],
                " (homogeneous transforms) or (V, 6) (x, y, z, roll, pitch, yaw each)",
            )?;
            t.as_slice()?
                .chunks_exact(16)
                .enumerate()
                .map(|(i, rows)| Ok(Waypoint::from(pose_from_rows(rows, &format!("{what}[{i}]"))?)))
                .collect()
        }
    }
}

/// A point x, y, z \[m\], or the position of a pose (4×4, or x, y, z, roll, pitch, yaw).
pub(crate) fn point_arg(obj: &Bound<'_, PyAny>, what: &str, conv: RpyConvention) -> PyResult<Vector3<f64>> {
    let a = f64_array(obj, what)?;
    if a.ndim() == 2 || a.shape() == [6] {
        return Ok(pose_arg(obj, what, conv)?.pos);
    }
    check_shape(&a, what, &[Some(3)], " (a point x, y, z, or a pose)")?;
    finite_point(a.as_slice()?, what).map(Vector3::from)
}

/// Three finite numbers, or the error naming `what` (as the CLI words it).
pub(crate) fn finite_point(v: &[f64], what: &str) -> PyResult<[f64; 3]> {
    check_finite(v, what)?;
    Ok([v[0], v[1], v[2]])
}

/// Checks that every value of `v` is finite, or the error naming `what` (as the CLI words it).
fn check_finite(v: &[f64], what: &str) -> PyResult<()> {
    match v.iter().find(|x| !x.is_finite()) {
        Some(x) => Err(invalid(format!("`{what}` contains {x}; all values must be finite"))),
        None => Ok(()),
    }
}

/// A 3-vector argument (x, y, z).
pub(crate) fn vec3_arg(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<[f64; 3]> {
    let a = f64_array(obj, what)?;
    check_shape(&a, what, &[Some(3)], " (x, y, z)")?;
    finite_point(a.as_slice()?, what)
}

/// The `rpy` argument, read by the core as every door reads it.
pub(crate) fn parse_rpy(text: &str) -> PyResult<RpyConvention> {
    text.parse().map_err(to_py)
}

/// A limit argument: None, one number (every joint) or one per joint.
pub(crate) fn limit_values(obj: Option<&Bound<'_, PyAny>>, what: &str) -> PyResult<Option<Vec<f64>>> {
    let Some(obj) = obj else { return Ok(None) };
    if obj.is_none() {
        return Ok(None);
    }
    let a = f64_array(obj, what)?;
    if a.ndim() > 1 {
        return Err(invalid(format!(
            "`{what}` must be one number or one per joint, got shape {}",
            shape_text(a.shape())
        )));
    }
    Ok(Some(a.as_slice()?.to_vec()))
}
