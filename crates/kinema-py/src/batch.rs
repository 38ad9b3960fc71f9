//! `Robot.ik_batch` a chunk at a time: the targets are read from the input
//! array and solved [`CHUNK`] at once, so that what the call holds beyond its
//! input and its answer does not grow with the number of targets; the answer
//! is reserved first, and memory that cannot be had is a `MemoryError`
//! naming the figure, not an abort of the interpreter.

use kinema::ik::IkTarget;
use kinema::RpyConvention;
use numpy::{PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyMemoryError;
use pyo3::prelude::*;

use crate::args::{check_shape, finite_point, pose_from_rows, waypoint_from_xyz_rpy};

/// Targets solved at once: enough for every core, little memory.
pub(crate) const CHUNK: usize = 1 << 16;

/// How the rows of the target array read.
#[derive(Clone, Copy)]
enum Layout {
    /// x, y, z, roll, pitch, yaw.
    Rpy(RpyConvention),
    /// A 4 × 4 homogeneous transform.
    Matrix,
    /// x, y, z alone.
    Point,
}

/// The targets of one call, read row by row from their array.
pub(crate) struct Targets<'py> {
    array: PyReadonlyArrayDyn<'py, f64>,
    layout: Layout,
    what: &'static str,
}

impl<'py> Targets<'py> {
    /// Poses `T`: one (4×4 or 6 numbers) or V of them ((V, 4, 4) or (V, 6)).
    pub(crate) fn poses(array: PyReadonlyArrayDyn<'py, f64>, conv: RpyConvention) -> PyResult<Targets<'py>> {
        let layout = match array.shape() {
            [6] | [_, 6] => Layout::Rpy(conv),
            [4, 4] => Layout::Matrix,
            _ => {
                check_shape(
                    &array,
                    "T",
                    &[None, Some(4), Some(4)],
                    " (homogeneous transforms) or (V, 6) (x, y, z, roll, pitch, yaw each)",
                )?;
                Layout::Matrix
            }
        };
        Ok(Targets { array, layout, what: "T" })
    }

    /// Points `position`, (V, 3).
    pub(crate) fn points(array: PyReadonlyArrayDyn<'py, f64>) -> PyResult<Targets<'py>> {
        check_shape(&array, "position", &[None, Some(3)], " (x, y, z each)")?;
        Ok(Targets { array, layout: Layout::Point, what: "position" })
    }

    fn row_len(&self) -> usize {
        match self.layout {
            Layout::Rpy(_) => 6,
            Layout::Matrix => 16,
            Layout::Point => 3,
        }
    }

    /// How many targets.
    pub(crate) fn len(&self) -> usize {
        self.array.len() / self.row_len()
    }

    /// Targets `from..to`, each checked (errors name its index).
    pub(crate) fn read(&self, from: usize, to: usize) -> PyResult<Vec<IkTarget>> {
        let w = self.row_len();
        let values = &self.array.as_slice()?[from * w..to * w];
        let single = self.array.ndim() == 1 || self.array.shape() == [4, 4];
        let name = |i: usize| if single { self.what.to_string() } else { format!("{}[{}]", self.what, from + i) };
        values
            .chunks_exact(w)
            .enumerate()
            .map(|(i, row)| match self.layout {
                Layout::Rpy(conv) => Ok(IkTarget::Pose(*waypoint_from_xyz_rpy(row, &name(i), conv)?.pose())),
                Layout::Matrix => Ok(IkTarget::Pose(pose_from_rows(row, &name(i))?)),
                Layout::Point => Ok(IkTarget::Position(finite_point(row, &name(i))?)),
            })
            .collect()
    }
}

/// An empty vector with room for `len` values, or a `MemoryError` saying
/// what needed how much.
pub(crate) fn reserve<T>(len: usize, what: &str) -> PyResult<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(len).map_err(|_| {
        let bytes = len as f64 * std::mem::size_of::<T>() as f64;
        PyMemoryError::new_err(format!(
            "ik_batch: {what} would take {:.2} GB, which cannot be allocated; solve the targets in smaller batches",
            bytes / 1e9
        ))
    })?;
    Ok(v)
}
