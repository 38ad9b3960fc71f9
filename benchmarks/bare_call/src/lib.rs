//! `kinema_bare_call`: the floor of a native per-call function, for
//! `benchmarks/python_vs_peers.py` (issue 8: "per-call fkine/jacob0 within
//! 1.5× of a bare Python call's overhead").
//!
//! [`Bare`] has the methods `noop`, `array44` and `array6n`. They do no
//! kinematics but go through the same path as kinema's `Robot.fkine` and
//! `Robot.jacob0` (crates/kinema-py): a method of a frozen pyclass with the
//! signature `(q, out=None)`, the joint vector read as
//! `crates/kinema-py/src/fast.rs` (`read_joints`) reads it, and the result
//! written as `fast::result_array` writes it (a new C-order float64 array
//! filled in place, or a checked `out` array). What kinema's `fkine(q)` costs
//! beyond `array44(q)` is therefore its kinematics (and the core's check of `q`).
//!
//! The readers below repeat those of fast.rs on purpose: this crate must not
//! depend on kinema, and the two must do the same work. Keep them in step.
//!
//! ```python
//! import numpy as np, kinema_bare_call
//! b = kinema_bare_call.Bare(7)          # n = 7 joint values per call
//! q = np.zeros(7)
//! b.noop(q)                             # None
//! b.array44(q).shape, b.array6n(q).shape  # (4, 4), (6, 7)
//! ```

use std::mem::MaybeUninit;

use numpy::npyffi::{self, NPY_TYPES};
use numpy::{PyArray2, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyFloat, PyInt, PyList, PyTuple};

/// Joint vectors longer than this are refused (kinema's fast-path limit).
const MAX_FAST_JOINTS: usize = 32;

/// Largest integer magnitude read as a joint value: every integer up to 2⁵³ is
/// exactly a float64.
const EXACT_INT: i64 = 1 << 53;

/// Output memory: initialised (an `out` array) or not (a new array); only written.
type Dst = [MaybeUninit<f64>];

/// Copies `obj` into `buf` and returns its length when `obj` is a 1-D native
/// float64 numpy array (any strides) or a `list`/`tuple` of `float`s and
/// `int`s (|value| ≤ 2⁵³), of at most [`MAX_FAST_JOINTS`] values; else `None`.
/// The same cases and the same reads as kinema-py's `fast::read_joints`.
fn read_joints(obj: &Bound<'_, PyAny>, buf: &mut [f64; MAX_FAST_JOINTS]) -> Option<usize> {
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
        // runs while the values are copied out.
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
fn is_f64(a: &Bound<'_, PyUntypedArray>) -> bool {
    let dtype = a.dtype();
    dtype.num() == NPY_TYPES::NPY_DOUBLE as i32 && dtype.is_native_byteorder() != Some(false)
}

/// Checks that `out` is a writeable, aligned, C-contiguous native float64
/// array of shape `shape` (as kinema-py's `fast::check_out`).
fn check_out<'a, 'py>(out: &'a Bound<'py, PyAny>, shape: &[usize]) -> PyResult<&'a Bound<'py, PyUntypedArray>> {
    let Ok(a) = out.downcast::<PyUntypedArray>() else {
        return Err(PyTypeError::new_err("`out` must be a numpy array of float64"));
    };
    if !is_f64(a) {
        return Err(PyValueError::new_err("`out` must have dtype float64"));
    }
    if a.shape() != shape {
        return Err(PyValueError::new_err(format!("`out` must have shape {shape:?}")));
    }
    // SAFETY: reads the flags field of the live array object `a`.
    let flags = unsafe { (*a.as_array_ptr()).flags };
    if flags & npyffi::NPY_ARRAY_C_CONTIGUOUS == 0 {
        return Err(PyValueError::new_err("`out` must be C-contiguous"));
    }
    if flags & npyffi::NPY_ARRAY_WRITEABLE == 0 {
        return Err(PyValueError::new_err("`out` is read-only"));
    }
    if flags & npyffi::NPY_ARRAY_ALIGNED == 0 {
        return Err(PyValueError::new_err("`out` must be aligned"));
    }
    Ok(a)
}

/// `a`'s elements as write-only memory.
///
/// # Safety
/// `a` must be a C-contiguous array of float64 and nothing else may access
/// its elements while the returned slice lives.
#[allow(clippy::mut_from_ref)]
unsafe fn elements<'a>(a: &'a Bound<'_, PyArray2<f64>>) -> &'a mut Dst {
    std::slice::from_raw_parts_mut(a.data().cast::<MaybeUninit<f64>>(), a.len())
}

/// `fill` writes all values of a `dims` result into `out` (checked, then
/// returned) or into a new C-order array (as kinema-py's `fast::result_array`).
fn result_array<'py>(
    py: Python<'py>,
    out: Option<&Bound<'py, PyAny>>,
    dims: [usize; 2],
    fill: impl FnOnce(&mut Dst),
) -> PyResult<Bound<'py, PyAny>> {
    let Some(out) = out else {
        // SAFETY: a new C-order array that no one else knows of yet; `fill`
        // writes every element before it is returned.
        let a = unsafe { PyArray2::<f64>::new(py, dims, false) };
        fill(unsafe { elements(&a) });
        return Ok(a.into_any());
    };
    let a = check_out(out, &dims)?;
    // SAFETY: `check_out` found `a` a writeable, aligned, C-contiguous native
    // float64 array of shape `dims`; the GIL is held and `fill` runs no Python code.
    fill(unsafe { elements(a.as_any().downcast_unchecked::<PyArray2<f64>>()) });
    Ok(out.clone())
}

/// Native calls with kinema's per-call argument and result path and no
/// kinematics, for a robot of `n` joints.
#[pyclass(frozen, name = "Bare", module = "kinema_bare_call")]
struct Bare {
    n: usize,
}

impl Bare {
    /// Calls `f` on the joint values of `q` (kinema's fast path only; the
    /// benchmark passes 1-D float64 arrays), which must be `n` of them.
    #[inline]
    fn with_q<T>(&self, q: &Bound<'_, PyAny>, f: impl FnOnce(&[f64]) -> T) -> PyResult<T> {
        let mut buf = [0.0; MAX_FAST_JOINTS];
        let Some(len) = read_joints(q, &mut buf) else {
            return Err(PyTypeError::new_err("`q` must be a 1-D float64 array or a list/tuple of numbers"));
        };
        if len != self.n {
            return Err(PyValueError::new_err(format!("`q` must have {} values, got {len}", self.n)));
        }
        Ok(f(&buf[..len]))
    }
}

#[pymethods]
impl Bare {
    /// ``Bare(n)``: calls taking ``n`` joint values (1 ≤ n ≤ 32).
    #[new]
    fn new(n: usize) -> PyResult<Self> {
        if !(1..=MAX_FAST_JOINTS).contains(&n) {
            return Err(PyValueError::new_err(format!("n must be in 1..={MAX_FAST_JOINTS}, got {n}")));
        }
        Ok(Bare { n })
    }

    /// Number of joint values per call.
    #[getter]
    fn n(&self) -> usize {
        self.n
    }

    /// Does nothing and returns None: the cost of calling a native method
    /// with ``fkine``'s signature ``(q, out=None)``. Neither argument is read.
    #[pyo3(signature = (q, out=None))]
    fn noop(&self, q: &Bound<'_, PyAny>, out: Option<&Bound<'_, PyAny>>) {
        let _ = (q, out);
    }

    /// Reads the ``n`` values of ``q`` and returns a 4×4 float64 array whose
    /// first ``min(n, 16)`` values (row-major) are ``q``, the rest 0: the
    /// work of ``Robot.fkine`` without the kinematics. ``out``: as in ``fkine``.
    #[pyo3(signature = (q, out=None))]
    fn array44<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let rows = self.with_q(q, |q| {
            let mut rows = [0.0; 16];
            let k = q.len().min(16);
            rows[..k].copy_from_slice(&q[..k]);
            rows
        })?;
        result_array(py, out, [4, 4], |o| {
            for (d, s) in o.iter_mut().zip(&rows) {
                d.write(*s);
            }
        })
    }

    /// Reads the ``n`` values of ``q`` and returns a 6×n float64 array whose
    /// six rows are ``q``: the work of ``Robot.jacob0`` without the
    /// kinematics. ``out``: as in ``jacob0``.
    #[pyo3(signature = (q, out=None))]
    fn array6n<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        out: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let n = self.n;
        let mut buf = [0.0; MAX_FAST_JOINTS];
        self.with_q(q, |q| buf[..n].copy_from_slice(q))?;
        result_array(py, out, [6, n], |o| {
            for row in o.chunks_exact_mut(n) {
                for (d, s) in row.iter_mut().zip(&buf[..n]) {
                    d.write(*s);
                }
            }
        })
    }
}

/// Benchmark reference for kinema: native per-call functions that do no kinematics.
#[pymodule]
fn kinema_bare_call(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Bare>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
