//! The parallel batch writer of `fkine_batch`, `jacob0_batch` and
//! `jacobe_batch`. (The per-call and per-row results, pose matrices and
//! Jacobian rows, are written by the core straight into numpy memory.) Reading `q` and creating
//! or checking the output arrays is in [`crate::npio`].

use std::mem::MaybeUninit;

use kinema::{Error, Robot};
use numpy::{PyArray3, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use rayon::prelude::*;

use crate::args::{check_shape, f64_array};
use crate::errors::{invalid, to_py};
use crate::npio::{check_out, elements, Dst};

/// Configurations per parallel task of the batch functions.
const BATCH_CHUNK: usize = 512;

/// A batch function: `row(q, out_row)` for every configuration `q`
/// of the (N, n) argument `qs` (`what` in messages), each writing all its
/// values into its row of an (N, `dims[0]`, `dims[1]`) float64 array: a new
/// one, or `out` (checked by [`check_out`], then returned).
///
/// Without `out`, `qs` is copied and the work runs without the GIL. With
/// `out`, nothing is copied and the GIL is held, so that no Python code can
/// use `out` while it is written. Either way the rows run in parallel over
/// all cores. A configuration that the core rejects fails the call with the
/// error of the first such row (`Error::InBatch`).
pub(crate) fn batch<'py>(
    py: Python<'py>,
    robot: &Robot,
    qs: &Bound<'py, PyAny>,
    what: &str,
    out: Option<&Bound<'py, PyAny>>,
    dims: [usize; 2],
    row: impl Fn(&[f64], &mut Dst) -> kinema::Result<()> + Sync + Send,
) -> PyResult<Bound<'py, PyAny>> {
    let n = robot.dof();
    let a = f64_array(qs, what)?;
    check_shape(&a, what, &[None, Some(n)], &format!(" (one row of {n} joint values per configuration)"))?;
    let shape = [a.shape()[0], dims[0], dims[1]];
    let run = |qs: &[f64], dst: &mut Dst| run_rows(robot, qs, dst, dims[0] * dims[1], &row);
    let Some(out) = out else {
        let qs = a.as_slice()?.to_vec();
        // SAFETY: a new C-order array that no one else knows of until it is
        // returned, so it may be written without the GIL; `run` writes every
        // element unless it fails, and then the array is dropped unseen.
        let array = unsafe { PyArray3::<f64>::new(py, shape, false) };
        let dst = unsafe { elements(&array) };
        py.allow_threads(|| run(&qs, dst)).map_err(to_py)?;
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
    run(a.as_slice()?, dst).map_err(to_py)?;
    Ok(out.clone())
}

/// The rows of [`batch`]: `width` values of `dst` per configuration of `qs`.
fn run_rows(
    robot: &Robot,
    qs: &[f64],
    dst: &mut Dst,
    width: usize,
    row: &(impl Fn(&[f64], &mut Dst) -> kinema::Result<()> + Sync + Send),
) -> kinema::Result<()> {
    let n = robot.dof();
    let chunk =
        |(o, q): (&mut Dst, &[f64])| o.chunks_exact_mut(width).zip(q.chunks_exact(n)).try_for_each(|(o, q)| row(q, o));
    let done = if qs.len() <= n * BATCH_CHUNK {
        chunk((dst, qs))
    } else {
        dst.par_chunks_mut(width * BATCH_CHUNK).zip(qs.par_chunks(n * BATCH_CHUNK)).try_for_each(chunk)
    };
    done.or_else(|e| {
        // Report the first bad configuration, as a check before any work would.
        for (index, q) in qs.chunks_exact(n).enumerate() {
            robot.check_q(q).map_err(|e| Error::InBatch { index, source: Box::new(e) })?;
        }
        Err(e)
    })
}
