//! Reading joint vectors from Python and writing numpy results, without
//! numpy's conversion machinery: the part of the per-call path that knows
//! nothing of kinematics.
//!
//! Shared, as source, by the package (`mod npio` in `lib.rs`, used there
//! and by `fast.rs`) and by the benchmark's native floor `benchmarks/bare_call`
//! (included there with `#[path]`), so that the floor does exactly the work
//! of kinema's call path. Each includer provides `invalid(String) -> PyErr`
//! and `shape_text(&[usize]) -> String` at its crate root.

use std::mem::MaybeUninit;

use numpy::npyffi::{self, NPY_TYPES};
use numpy::{PyArray2, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyFloat, PyInt, PyList, PyTuple};

use crate::{invalid, shape_text};

/// Joint vectors longer than this take the general path.
pub(crate) const MAX_FAST_JOINTS: usize = 32;

/// Largest integer magnitude read as a joint value by the fast path: every
/// integer up to 2⁵³ is exactly a float64, so the value is what numpy gives.
const EXACT_INT: i64 = 1 << 53;

/// Copies the joint vector `obj` into `buf` and returns its length, when `obj`
/// is one of the common forms: a 1-D float64 numpy array of native byte order
/// (any strides), or a `list`/`tuple` of `float`s and `int`s (|value| ≤ 2⁵³).
/// These give exactly the values `numpy.asarray(obj, dtype=float64)` gives.
/// Returns `None` for anything else (other dtypes, other sequences, strings,
/// more than [`MAX_FAST_JOINTS`] values, …): the caller then takes the general
/// path. The length is not checked against the robot here.
pub(crate) fn read_joints(obj: &Bound<'_, PyAny>, buf: &mut [f64; MAX_FAST_JOINTS]) -> Option<usize> {
    if let Ok(a) = obj.downcast::<PyUntypedArray>() {
        if a.ndim() != 1 || !is_f64(a) {
            return None;
        }
        let len = a.len();
        if len > MAX_FAST_JOINTS {
            return None;
        }
        let stride = a.strides()[0];
        // SAFETY: `a` is a 1-D numpy array of native float64 (checked above), so
        // element i lies at `data + i·stride` bytes for i < len; unaligned reads
        // cover arrays made from odd buffers. The GIL is held and no Python code
        // runs while the values are copied out, as in numpy's safe `to_vec`.
        unsafe {
            let data = (*a.as_array_ptr()).data as *const u8;
            for (i, v) in buf[..len].iter_mut().enumerate() {
                *v = data.offset(i as isize * stride).cast::<f64>().read_unaligned();
            }
        }
        return Some(len);
    }
    if let Ok(l) = obj.downcast_exact::<PyList>() {
        return read_items(l.len(), |i| l.get_item(i).ok(), buf);
    }
    if let Ok(t) = obj.downcast_exact::<PyTuple>() {
        return read_items(t.len(), |i| t.get_item(i).ok(), buf);
    }
    None
}

/// The `len` items `item(i)` of a list or tuple as float64, if all are plain numbers.
fn read_items<'py>(
    len: usize,
    item: impl Fn(usize) -> Option<Bound<'py, PyAny>>,
    buf: &mut [f64; MAX_FAST_JOINTS],
) -> Option<usize> {
    if len > MAX_FAST_JOINTS {
        return None;
    }
    for (i, v) in buf[..len].iter_mut().enumerate() {
        *v = number(&item(i)?)?;
    }
    Some(len)
}

/// An exact Python `float`, or an exact `int` of magnitude ≤ 2⁵³, as float64.
#[inline]
fn number(item: &Bound<'_, PyAny>) -> Option<f64> {
    if let Ok(f) = item.downcast_exact::<PyFloat>() {
        return Some(f.value());
    }
    let i = item.downcast_exact::<PyInt>().ok()?.extract::<i64>().ok()?;
    (-EXACT_INT..=EXACT_INT).contains(&i).then_some(i as f64)
}

/// Whether the elements of `a` are float64 in the machine's byte order.
pub(crate) fn is_f64(a: &Bound<'_, PyUntypedArray>) -> bool {
    let dtype = a.dtype();
    dtype.num() == NPY_TYPES::NPY_DOUBLE as i32 && dtype.is_native_byteorder() != Some(false)
}

/// Checks that `out` can receive a result of shape `shape`: a writeable,
/// aligned, C-contiguous numpy array of native float64 with exactly that shape.
pub(crate) fn check_out<'a, 'py>(
    out: &'a Bound<'py, PyAny>,
    shape: &[usize],
) -> PyResult<&'a Bound<'py, PyUntypedArray>> {
    let Ok(a) = out.downcast::<PyUntypedArray>() else {
        let kind = out.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "?".into());
        let want = shape_text(shape);
        return Err(invalid(format!("`out` must be a numpy array of float64 of shape {want}, got {kind}")));
    };
    if !is_f64(a) {
        return Err(invalid(format!("`out` must have dtype float64, got {}", a.dtype())));
    }
    if a.shape() != shape {
        let (want, got) = (shape_text(shape), shape_text(a.shape()));
        return Err(invalid(format!("`out` must have shape {want}, got shape {got}")));
    }
    // SAFETY: reads the flags field of the live array object `a`.
    let flags = unsafe { (*a.as_array_ptr()).flags };
    if flags & npyffi::NPY_ARRAY_C_CONTIGUOUS == 0 {
        return Err(invalid("`out` must be C-contiguous".into()));
    }
    if flags & npyffi::NPY_ARRAY_WRITEABLE == 0 {
        return Err(invalid("`out` is read-only".into()));
    }
    if flags & npyffi::NPY_ARRAY_ALIGNED == 0 {
        return Err(invalid("`out` must be aligned".into()));
    }
    Ok(a)
}

/// Output memory: initialised (an `out` array) or not (a new array); only written.
pub(crate) type Dst = [MaybeUninit<f64>];

/// `a`'s elements as write-only memory.
///
/// # Safety
/// `a` must be a C-contiguous array of float64 and nothing else may access
/// its elements while the returned slice lives.
// Like numpy's `as_slice_mut`, a mutable view from a shared handle; the
// contract above is what makes it exclusive.
#[allow(clippy::mut_from_ref)]
pub(crate) unsafe fn elements<'a, D>(a: &'a Bound<'_, numpy::PyArray<f64, D>>) -> &'a mut Dst {
    // `MaybeUninit<f64>` has the layout of `f64`; callers only write f64 values
    // through it (never read), so the view is valid for new and old arrays alike.
    std::slice::from_raw_parts_mut(a.data().cast::<MaybeUninit<f64>>(), a.len())
}

/// The result of a per-call function: `fill` writes its row-major values
/// (all of them, or none and fails) into `out` when given (checked by
/// [`check_out`], then returned), or else into a new array of shape `dims`
/// (dropped unseen if `fill` fails).
pub(crate) fn result_array<'py>(
    py: Python<'py>,
    out: Option<&Bound<'py, PyAny>>,
    dims: [usize; 2],
    fill: impl FnOnce(&mut Dst) -> PyResult<()>,
) -> PyResult<Bound<'py, PyAny>> {
    let Some(out) = out else {
        // SAFETY: a new C-order array that no one else knows of yet; `fill`
        // writes every element before it is returned, or it is not returned.
        let a = unsafe { PyArray2::<f64>::new(py, dims, false) };
        fill(unsafe { elements(&a) })?;
        return Ok(a.into_any());
    };
    let a = check_out(out, &dims)?;
    // SAFETY: `check_out` found `a` a writeable, aligned, C-contiguous native
    // float64 array of shape `dims`. The GIL is held and `fill` runs no Python
    // code, so this write is what `out[...] = result` in Python does; the
    // joint values were copied out before, so `out` may alias `q`.
    fill(unsafe { elements(a.as_any().downcast_unchecked::<PyArray2<f64>>()) })?;
    Ok(out.clone())
}
