//! `kinema_bare_call`: the floor of a native per-call function, for
//! `benchmarks/python_vs_peers.py` (issue 8: "per-call fkine/jacob0 within
//! 1.5× of a bare Python call's overhead").
//!
//! [`Bare`] has the methods `noop`, `array44` and `array6n`. They do no
//! kinematics but go through the same path as kinema's `Robot.fkine` and
//! `Robot.jacob0` (crates/kinema-py): a method of a frozen pyclass with the
//! signature `(q, out=None)`, the joint vector read as kinema-py's
//! `npio::read_joints` reads it, and the result created as its
//! `npio::result_array` creates it (a new C-order float64 array filled in
//! place, or a checked `out` array) and filled with q's values where kinema's
//! core writes the pose matrix or the Jacobian rows. What kinema's `fkine(q)`
//! costs beyond `array44(q)` is therefore its kinematics (and the core's
//! check of `q`).
//!
//! The readers and writers are kinema-py's own: `crates/kinema-py/src/npio.rs`
//! is compiled into this crate too (`#[path]` below), so the two cannot drift
//! apart. This crate does not depend on kinema.
//!
//! ```python
//! import numpy as np, kinema_bare_call
//! b = kinema_bare_call.Bare(7)          # n = 7 joint values per call
//! q = np.zeros(7)
//! b.noop(q)                             # None
//! b.array44(q).shape, b.array6n(q).shape  # (4, 4), (6, 7)
//! ```

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

#[path = "../../../crates/kinema-py/src/npio.rs"]
#[allow(dead_code)]
mod npio;

use npio::{read_joints, result_array, Dst, MAX_FAST_JOINTS};

/// Writes `src` into `dst` (same length): the floor's stand-in for the
/// values kinema's core writes into the result.
#[inline]
fn put(dst: &mut Dst, src: &[f64]) {
    for (d, s) in dst.iter_mut().zip(src) {
        d.write(*s);
    }
}

/// The error of a bad argument (kinema-py raises its own `InvalidInput`, a `ValueError`).
fn invalid(message: String) -> PyErr {
    PyValueError::new_err(message)
}

/// A shape as Python prints it, e.g. `(4, 4)` or `(7,)`.
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!("({})", shape.iter().map(usize::to_string).collect::<Vec<_>>().join(", ")),
    }
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
            put(o, &rows);
            Ok(())
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
                put(row, &buf[..n]);
            }
            Ok(())
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
