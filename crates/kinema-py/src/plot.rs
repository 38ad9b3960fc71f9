//! `Robot.plot`, `plot_joints` and `plot_cartesian`: drawn by
//! `python/kinema/_plot.py` with matplotlib (an optional dependency), from
//! numbers the robot's own methods compute.

use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::robot::PyRobot;

/// Calls `kinema._plot.<function>(robot, what, **kwargs)`.
fn draw<'py>(
    robot: &Bound<'py, PyRobot>,
    function: &str,
    what: &Bound<'py, PyAny>,
    kwargs: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyAny>> {
    robot.py().import("kinema._plot")?.getattr(function)?.call((robot, what), Some(kwargs))
}

#[pymethods]
impl PyRobot {
    /// The robot at ``q`` as a 3D stick figure with its link frames (x, y, z
    /// axes red, green, blue). ``q``: a configuration, a pose name, an (N, n)
    /// array or a trajectory (a few configurations along it and the tool's
    /// path). Returns the matplotlib ``Figure``; ``file`` saves it there too
    /// (format from the extension); ``ax`` draws into a 3D Axes.
    ///
    /// Raises:
    ///     ImportError: matplotlib is not installed (``pip install matplotlib``).
    ///     InvalidInput: ``q`` has the wrong shape.
    #[pyo3(signature = (q, *, frames=true, file=None, ax=None))]
    fn plot<'py>(
        slf: &Bound<'py, Self>,
        q: &Bound<'py, PyAny>,
        frames: bool,
        file: Option<&Bound<'py, PyAny>>,
        ax: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let kwargs = PyDict::new(slf.py());
        kwargs.set_item("frames", frames)?;
        kwargs.set_item("file", file)?;
        kwargs.set_item("ax", ax)?;
        draw(slf, "plot_robot", q, &kwargs)
    }

    /// Joint positions, velocities and accelerations of ``trajectory`` (a
    /// :class:`JointTrajectory` or :class:`Plan`) against time, position
    /// limits dashed: what ``kinema plot joints`` draws. Returns the
    /// ``Figure``; ``file`` saves it there too.
    #[pyo3(signature = (trajectory, *, file=None))]
    fn plot_joints<'py>(
        slf: &Bound<'py, Self>,
        trajectory: &Bound<'py, PyAny>,
        file: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let kwargs = PyDict::new(slf.py());
        kwargs.set_item("file", file)?;
        draw(slf, "plot_joints", trajectory, &kwargs)
    }

    /// The tool's position and linear velocity (x, y, z, norm) along
    /// ``trajectory`` against time: what ``kinema plot cartesian`` draws.
    /// Returns the ``Figure``; ``file`` saves it there too.
    #[pyo3(signature = (trajectory, *, file=None))]
    fn plot_cartesian<'py>(
        slf: &Bound<'py, Self>,
        trajectory: &Bound<'py, PyAny>,
        file: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let kwargs = PyDict::new(slf.py());
        kwargs.set_item("file", file)?;
        draw(slf, "plot_cartesian", trajectory, &kwargs)
    }
}
