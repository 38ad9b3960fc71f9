//! The robot's body in Python: the `Scene` class, and `Robot.collides`,
//! `collide_dict`, `distance` and `collides_batch`, each a `CollisionCheck`
//! of `kinema-geometry` as `kinema collide` builds it.

use std::path::PathBuf;
use std::sync::Arc;

use kinema_geometry::{CheckOptions, CollisionCheck, Scene};
use kinema_io::CollideAnswer;
use numpy::ndarray::Array;
use numpy::{IntoPyArray, PyArrayDyn};
use pyo3::prelude::*;

use crate::answer::to_python;
use crate::args::{check_shape, f64_array, real};
use crate::errors::{geometry_to_py, to_py};
use crate::robot::PyRobot;

/// Obstacles with poses (a scene file's ``[[obstacle]]`` tables, as
/// ``kinema collide --scene`` reads them): boxes, spheres, cylinders,
/// capsules and meshes. Pass it as ``scene=`` to :meth:`Robot.collides`,
/// :meth:`Robot.distance`, :meth:`Robot.ik` and :meth:`Robot.check`.
#[pyclass(frozen, name = "Scene", module = "kinema")]
pub(crate) struct PyScene {
    pub(crate) scene: Arc<Scene>,
}

#[pymethods]
impl PyScene {
    /// Reads a scene file (TOML).
    ///
    /// Raises:
    ///     RobotFileError: the file cannot be read.
    ///     DescriptionError: a key or value is wrong (file, line and key in the message).
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<Self> {
        Scene::load(&path).map(|s| PyScene { scene: Arc::new(s) }).map_err(geometry_to_py)
    }

    /// A scene from TOML text; mesh paths are relative to ``base_dir``
    /// (default: the working directory).
    #[staticmethod]
    #[pyo3(signature = (text, base_dir=None))]
    fn from_toml(text: &str, base_dir: Option<PathBuf>) -> PyResult<Self> {
        let dir = base_dir.unwrap_or_else(|| PathBuf::from("."));
        Scene::from_toml(text, "scene", &dir).map(|s| PyScene { scene: Arc::new(s) }).map_err(geometry_to_py)
    }

    /// The obstacles' names, in file order.
    #[getter]
    fn obstacles(&self) -> Vec<String> {
        self.scene.obstacles.iter().map(|o| o.name.clone()).collect()
    }

    fn __repr__(&self) -> String {
        format!("Scene({} obstacle(s): {})", self.scene.obstacles.len(), self.obstacles().join(", "))
    }
}

/// Where a Python robot came from, so that its shapes can be loaded from the
/// same description when a collision check first needs them.
#[derive(Debug, Clone)]
pub(crate) struct Source {
    /// A built-in name or a description path.
    pub spec: String,
    /// A URDF's tip link.
    pub tip: Option<String>,
}

impl Source {
    /// The source of a `robot` argument: a `Robot`'s own, or the built-in
    /// name or path given instead.
    pub(crate) fn of(robot: &Bound<'_, PyAny>) -> Source {
        match robot.downcast::<PyRobot>() {
            Ok(r) => r.get().source.clone(),
            Err(_) => Source { spec: robot.extract().unwrap_or_default(), tip: None },
        }
    }
}

impl PyRobot {
    /// The robot's self-collision check, loaded once from its description.
    fn bare_check(&self) -> PyResult<&CollisionCheck> {
        if let Some(check) = self.body.get() {
            return Ok(check);
        }
        let options = CheckOptions { tip: self.source.tip.clone(), ..Default::default() };
        let check = CollisionCheck::load(&self.source.spec, &options).map_err(geometry_to_py)?;
        Ok(self.body.get_or_init(|| check))
    }

    /// The robot's check with `scene`'s obstacles and `margin` \[m\] (what
    /// `kinema collide --scene --margin` checks).
    pub(crate) fn collision_check(&self, scene: Option<&PyScene>, margin: f64) -> PyResult<CollisionCheck> {
        let bare = self.bare_check()?;
        let scene = scene.map(|s| s.scene.as_ref());
        // This robot, not the description's: a cell places it on another base.
        let robot = (*self.robot).clone();
        CollisionCheck::with_scene(robot, bare.geometry().clone(), bare.pairs().clone(), scene, margin)
            .map_err(geometry_to_py)
    }

    /// [`PyRobot::collision_check`] when a scene or a margin asks for one.
    pub(crate) fn collision_check_if_asked(
        &self,
        scene: Option<&PyScene>,
        margin: Option<f64>,
    ) -> PyResult<Option<CollisionCheck>> {
        match (scene, margin) {
            (None, None) => Ok(None),
            (scene, margin) => self.collision_check(scene, margin.unwrap_or(0.0)).map(Some),
        }
    }
}

/// Collision and distance queries (`kinema collide`).
#[pymethods]
impl PyRobot {
    /// Whether the robot at ``q`` collides with itself or with ``scene``'s
    /// obstacles: any checked pair of bodies closer than ``margin`` [m]. The
    /// shapes are the robot's own (``[[shape]]`` tables, or a URDF's
    /// ``<collision>`` elements), loaded at the first call.
    ///
    /// Raises:
    ///     InvalidInput: bad ``q`` or ``margin``.
    ///     DescriptionError: the robot has no shapes, or a mesh cannot be read.
    #[pyo3(signature = (q, scene=None, margin=0.0))]
    fn collides(
        &self,
        py: Python<'_>,
        q: &Bound<'_, PyAny>,
        scene: Option<PyRef<'_, PyScene>>,
        #[pyo3(from_py_with = real)] margin: f64,
    ) -> PyResult<bool> {
        let q = self.joint_vector(q, "q")?;
        let check = self.collision_check(scene.as_deref(), margin)?;
        py.allow_threads(|| check.first_collision(&q)).map(|pair| pair.is_some()).map_err(geometry_to_py)
    }

    /// The smallest distance [m] between checked pairs at ``q`` (negative
    /// when shapes overlap: the depth), ``inf`` when no pair is checked.
    #[pyo3(signature = (q, scene=None))]
    fn distance(&self, py: Python<'_>, q: &Bound<'_, PyAny>, scene: Option<PyRef<'_, PyScene>>) -> PyResult<f64> {
        let q = self.joint_vector(q, "q")?;
        let check = self.collision_check(scene.as_deref(), 0.0)?;
        let closest = py.allow_threads(|| {
            let mut placement = check.placement();
            check.place(&q, &mut placement)?;
            check.closest(&placement)
        });
        Ok(closest.map_err(geometry_to_py)?.map_or(f64::INFINITY, |p| p.distance))
    }

    /// The answer of ``kinema collide --json``: ``collision``, ``pairs``
    /// (the colliding bodies, by link or obstacle name), ``min_distance``
    /// (its pair and witness points), ``margin`` and ``q``.
    #[pyo3(signature = (q, scene=None, margin=0.0))]
    fn collide_dict<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'_, PyAny>,
        scene: Option<PyRef<'_, PyScene>>,
        #[pyo3(from_py_with = real)] margin: f64,
    ) -> PyResult<Bound<'py, PyAny>> {
        let q = self.joint_vector(q, "q")?;
        let check = self.collision_check(scene.as_deref(), margin)?;
        self.robot.check_q(&q).map_err(to_py)?;
        let answer = py.allow_threads(|| CollideAnswer::of(&check, q, &mut check.placement()));
        to_python(py, &answer.map_err(geometry_to_py)?)
    }

    /// :meth:`collides` for each row of ``Q`` (shape (V, n)), on all cores
    /// with the GIL released: a (V,) bool array.
    #[allow(non_snake_case)]
    #[pyo3(signature = (Q, scene=None, margin=0.0))]
    fn collides_batch<'py>(
        &self,
        py: Python<'py>,
        Q: &Bound<'py, PyAny>,
        scene: Option<PyRef<'_, PyScene>>,
        #[pyo3(from_py_with = real)] margin: f64,
    ) -> PyResult<Bound<'py, PyArrayDyn<bool>>> {
        use rayon::prelude::*;
        let qs = f64_array(Q, "Q")?;
        let n = self.dof();
        check_shape(&qs, "Q", &[None, Some(n)], " (one row per configuration)")?;
        let rows: Vec<f64> = qs.as_slice()?.to_vec();
        let check = self.collision_check(scene.as_deref(), margin)?;
        let hits = py.allow_threads(|| {
            rows.par_chunks_exact(n)
                .map_init(
                    || check.placement(),
                    |placement, q| -> kinema_geometry::Result<bool> {
                        check.place(q, placement)?;
                        Ok(kinema_geometry::collides(check.geometry(), placement, check.pairs(), check.margin())?
                            .is_some())
                    },
                )
                .collect::<kinema_geometry::Result<Vec<bool>>>()
        });
        Ok(Array::from_vec(hits.map_err(geometry_to_py)?).into_dyn().into_pyarray(py))
    }
}
