//! `Robot.show` and `Robot.animate`: the browser viewer (`kinema serve`) on
//! the robot. The server is run and talked to by `kinema._viewer`; this file
//! checks the arguments with the core and tells that module where the robot
//! and the scene come from.

use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::collision::{Inline, PyScene};
use crate::errors::{invalid, to_py};
use crate::robot::PyRobot;

#[pymethods]
impl PyRobot {
    /// Opens the browser viewer on the robot at configuration ``q`` (or
    /// moves the page already open): a local ``kinema serve`` started once
    /// per process. ``scene`` draws its obstacles too. In Jupyter the
    /// returned object displays the page inline. ``open_browser=False``
    /// starts the server without opening a tab (scripts, tests).
    ///
    /// Raises:
    ///     InvalidInput: ``q`` has the wrong length or a non-finite value.
    ///     FileNotFoundError: the ``kinema`` command line is not found.
    #[pyo3(signature = (q, scene=None, *, open_browser=true))]
    fn show<'py>(
        slf: &Bound<'py, Self>,
        q: &Bound<'py, PyAny>,
        scene: Option<&Bound<'py, PyScene>>,
        open_browser: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let q = slf.borrow()._viewer_q(q)?;
        let viewer = slf.py().import("kinema._viewer")?;
        viewer.getattr("show")?.call1((slf, q, scene, open_browser))
    }

    /// Plays ``trajectory`` (a :class:`JointTrajectory`, a :class:`Plan`, or
    /// a ``(t, q)`` pair: ``t`` [s] increasing, ``q`` one row per time) in
    /// the browser viewer, as :meth:`show` opens it; the page's player can
    /// replay and scrub it.
    ///
    /// Raises:
    ///     InvalidInput: a row of ``q`` has the wrong length or a non-finite
    ///     value, or ``t`` and ``q`` do not match.
    #[pyo3(signature = (trajectory, scene=None, *, open_browser=true))]
    fn animate<'py>(
        slf: &Bound<'py, Self>,
        trajectory: &Bound<'py, PyAny>,
        scene: Option<&Bound<'py, PyScene>>,
        open_browser: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let viewer = slf.py().import("kinema._viewer")?;
        viewer.getattr("animate")?.call1((slf, trajectory, scene, open_browser))
    }

    /// ``q`` as a list, checked by the core (length, finite values); a pose name is looked up.
    fn _viewer_q(&self, q: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
        let q = self.joint_vector(q, "q")?;
        self.robot.check_q(&q).map_err(to_py)?;
        Ok(q)
    }

    /// Where `kinema serve` finds this robot: ``{"spec", "tip"}`` for a
    /// built-in name or a file, ``{"text", "suffix", "tip"}`` for a
    /// description given as text; ``None`` for one it cannot load.
    fn _viewer_source<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = &self.source;
        let d = PyDict::new(py);
        d.set_item("tip", &s.tip)?;
        match (&s.member, &s.inline) {
            (Some(_), _) | (_, Some(Inline::Description(_))) => {
                return Err(invalid(format!(
                    "the viewer draws robots read from a built-in name, a file or a description text; `{}` is {}",
                    self.robot.name(),
                    if s.member.is_some() { "a scene's robot" } else { "defined by DH rows in code" }
                )))
            }
            (None, Some(Inline::Toml(t))) => {
                d.set_item("text", &t.text)?;
                d.set_item("suffix", ".toml")?;
            }
            (None, Some(Inline::Urdf(t))) => {
                d.set_item("text", &t.text)?;
                d.set_item("suffix", ".urdf")?;
            }
            (None, None) => d.set_item("spec", &s.spec)?,
        }
        Ok(d)
    }
}

#[pymethods]
impl PyScene {
    /// Where `kinema serve --scene` reads this scene: ``(text, file)``.
    fn _viewer_source(&self) -> (String, String) {
        (self.text.text.clone(), self.text.file.clone())
    }
}
