//! The hot paths of `fkine`, `jacob0`, `jacobe` and their batch forms:
//! reading a joint vector without numpy's conversion machinery, creating or
//! checking output arrays, and writing results straight into numpy memory.
//!
//! Every reader here is a fast path for a common case; anything it does not
//! recognise goes through the general code in `lib.rs`, which also produces
//! every error message about `q`.

use std::cell::RefCell;
use std::mem::MaybeUninit;

use kinema::nalgebra::Matrix6xX;
use kinema::{Error, Pose, Robot};
use numpy::npyffi::{self, NPY_TYPES};
use numpy::{
    PyArray2, PyArray3, PyArrayDescrMethods, PyArrayDyn, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::{PyFloat, PyInt, PyList, PyTuple};
use rayon::prelude::*;

use crate::{check_shape, f64_array, invalid, shape_text};

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
fn is_f64(a: &Bound<'_, PyUntypedArray>) -> bool {
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
type Dst = [MaybeUninit<f64>];

/// Writes `src` into `dst` (same length).
#[inline]
pub(crate) fn put(dst: &mut Dst, src: &[f64]) {
    for (d, s) in dst.iter_mut().zip(src) {
        d.write(*s);
    }
}

/// `a`'s elements as write-only memory.
///
/// # Safety
/// `a` must be a C-contiguous array of float64 and nothing else may access
/// its elements while the returned slice lives.
// Like numpy's `as_slice_mut`, a mutable view from a shared handle; the
// contract above is what makes it exclusive.
#[allow(clippy::mut_from_ref)]
unsafe fn elements<'a, D>(a: &'a Bound<'_, numpy::PyArray<f64, D>>) -> &'a mut Dst {
    // `MaybeUninit<f64>` has the layout of `f64`; callers only write f64 values
    // through it (never read), so the view is valid for new and old arrays alike.
    std::slice::from_raw_parts_mut(a.data().cast::<MaybeUninit<f64>>(), a.len())
}

/// The result of a per-call function: `fill` writes its row-major values
/// (all of them) into `out` when given (checked by [`check_out`], then
/// returned), or else into a new array of shape `dims`.
pub(crate) fn result_array<'py>(
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
    // float64 array of shape `dims`. The GIL is held and `fill` runs no Python
    // code, so this write is what `out[...] = result` in Python does; the
    // joint values were copied out before, so `out` may alias `q`.
    fill(unsafe { elements(a.as_any().downcast_unchecked::<PyArray2<f64>>()) });
    Ok(out.clone())
}

/// The 4×4 row-major homogeneous matrix of `pose` (the same values as `Pose::to_rows`).
#[inline]
pub(crate) fn pose_rows(pose: &Pose) -> [f64; 16] {
    let (r, p) = (&pose.rot, &pose.pos);
    #[rustfmt::skip]
    let rows = [
        r[(0, 0)], r[(0, 1)], r[(0, 2)], p[0],
        r[(1, 0)], r[(1, 1)], r[(1, 2)], p[1],
        r[(2, 0)], r[(2, 1)], r[(2, 2)], p[2],
        0.0, 0.0, 0.0, 1.0,
    ];
    rows
}

/// Writes the column-major 6×n Jacobian `j` row-major into `out` (6·n values).
#[inline]
pub(crate) fn jacobian_rows(j: &Matrix6xX<f64>, out: &mut Dst) {
    let n = j.ncols();
    for (c, col) in j.as_slice().chunks_exact(6).enumerate() {
        for (r, v) in col.iter().enumerate() {
            out[r * n + c].write(*v);
        }
    }
}

thread_local! {
    /// A Jacobian buffer reused by the per-call functions of this thread.
    static JACOBIAN: RefCell<Matrix6xX<f64>> = RefCell::new(Matrix6xX::zeros(0));
}

/// Calls `f` with a 6×n Jacobian buffer, reused between calls on one thread.
pub(crate) fn with_jacobian<T>(n: usize, f: impl FnOnce(&mut Matrix6xX<f64>) -> T) -> T {
    JACOBIAN.with(|cell| match cell.try_borrow_mut() {
        Ok(mut j) => {
            if j.ncols() != n {
                *j = Matrix6xX::zeros(n);
            }
            f(&mut j)
        }
        // Re-entered (e.g. from an `__array__` method called while reading `q`).
        Err(_) => f(&mut Matrix6xX::zeros(n)),
    })
}

/// Configurations per parallel task of the batch functions.
const BATCH_CHUNK: usize = 512;

/// A batch function: `row(scratch, q, out_row)` for every configuration `q`
/// of the (N, n) argument `qs` (`what` in messages), each writing all its
/// values into its row of an (N, `dims[0]`, `dims[1]`) float64 array: a new
/// one, or `out` (checked by [`check_out`], then returned).
///
/// Without `out`, `qs` is copied and the work runs without the GIL. With
/// `out`, nothing is copied and the GIL is held, so that no Python code can
/// use `out` while it is written. Either way the rows run in parallel over
/// all cores. A configuration that the core rejects fails the call with the
/// error of the first such row (`Error::InBatch`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn batch<'py, S>(
    py: Python<'py>,
    robot: &Robot,
    qs: &Bound<'py, PyAny>,
    what: &str,
    out: Option<&Bound<'py, PyAny>>,
    dims: [usize; 2],
    init: impl Fn() -> S + Sync + Send,
    row: impl Fn(&mut S, &[f64], &mut Dst) -> kinema::Result<()> + Sync + Send,
) -> PyResult<Bound<'py, PyAny>> {
    let n = robot.dof();
    let a = f64_array(qs, what)?;
    check_shape(&a, what, &[None, Some(n)], &format!(" (one row of {n} joint values per configuration)"))?;
    let shape = [a.shape()[0], dims[0], dims[1]];
    let run = |qs: &[f64], dst: &mut Dst| run_rows(robot, qs, dst, dims[0] * dims[1], &init, &row);
    let Some(out) = out else {
        let qs = a.as_slice()?.to_vec();
        // SAFETY: a new C-order array that no one else knows of until it is
        // returned, so it may be written without the GIL; `run` writes every
        // element unless it fails, and then the array is dropped unseen.
        let array = unsafe { PyArray3::<f64>::new(py, shape, false) };
        let dst = unsafe { elements(&array) };
        py.allow_threads(|| run(&qs, dst)).map_err(crate::to_py)?;
        return Ok(array.into_any());
    };
    check_out(out, &shape)?;
    // The borrow checker of the numpy crate refuses an `out` that overlaps `qs`.
    let mut w = out
        .downcast::<PyArrayDyn<f64>>()?
        .try_readwrite()
        .map_err(|_| invalid(format!("`out` must not share memory with `{what}`")))?;
    let dst = w.as_slice_mut()?;
    // SAFETY: viewing initialised f64 as `MaybeUninit<f64>` and only writing
    // f64 values through it keeps every element initialised.
    let dst = unsafe { std::slice::from_raw_parts_mut(dst.as_mut_ptr().cast::<MaybeUninit<f64>>(), dst.len()) };
    run(a.as_slice()?, dst).map_err(crate::to_py)?;
    Ok(out.clone())
}

/// The rows of [`batch`]: `width` values of `dst` per configuration of `qs`.
fn run_rows<S>(
    robot: &Robot,
    qs: &[f64],
    dst: &mut Dst,
    width: usize,
    init: &(impl Fn() -> S + Sync + Send),
    row: &(impl Fn(&mut S, &[f64], &mut Dst) -> kinema::Result<()> + Sync + Send),
) -> kinema::Result<()> {
    let n = robot.dof();
    let chunk = |s: &mut S, (o, q): (&mut Dst, &[f64])| {
        o.chunks_exact_mut(width).zip(q.chunks_exact(n)).try_for_each(|(o, q)| row(s, q, o))
    };
    let done = if qs.len() <= n * BATCH_CHUNK {
        chunk(&mut init(), (dst, qs))
    } else {
        dst.par_chunks_mut(width * BATCH_CHUNK).zip(qs.par_chunks(n * BATCH_CHUNK)).try_for_each_init(init, chunk)
    };
    done.or_else(|e| {
        // Report the first bad configuration, as a check before any work would.
        for (index, q) in qs.chunks_exact(n).enumerate() {
            robot.check_q(q).map_err(|e| Error::InBatch { index, source: Box::new(e) })?;
        }
        Err(e)
    })
}
