//! The robot's body in Python: the `Scene` class, and `Robot.collides`,
//! `collide_dict`, `distance` and `collides_batch`, each a `CollisionCheck`
//! of `kinema-geometry` as `kinema collide` builds it.

use std::path::PathBuf;
use std::sync::{Arc, OnceLock};

use kinema_geometry::{load_shapes_or_none, CheckOptions, CollisionCheck, RobotGeometry, Scene, UrdfOptions};
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
/// capsules and meshes; and robots on their bases (``[[robot]]`` tables, as
/// in a ``kinema cell`` file), which stand as obstacles at their ``start``
/// (else home) when another robot is checked. Pass it as ``scene=`` to
/// :meth:`Robot.collides`, :meth:`Robot.distance`, :meth:`Robot.ik` and
/// :meth:`Robot.check`; :meth:`Scene.robot` gives one of its robots, which
/// is then not its own obstacle.
#[pyclass(frozen, name = "Scene", module = "kinema")]
pub(crate) struct PyScene {
    pub(crate) scene: Arc<Scene>,
    /// The TOML text it was read from, which it pickles as.
    pub(crate) text: Arc<SceneText>,
    /// The scene with all its robots as obstacles, made at the first check.
    standing: OnceLock<Arc<Scene>>,
}

impl PyScene {
    /// The scene of TOML `text`, named `file` in errors, with paths relative to `dir`.
    pub(crate) fn parse(text: SceneText) -> PyResult<PyScene> {
        let scene = Scene::from_toml(&text.text, &text.file, &text.dir).map_err(geometry_to_py)?;
        Ok(PyScene { scene: Arc::new(scene), text: Arc::new(text), standing: OnceLock::new() })
    }

    /// The scene for a check of the robot that is its robot `member` (or of
    /// another robot): every other robot an obstacle where it stands.
    pub(crate) fn standing(&self, member: Option<&str>) -> PyResult<Arc<Scene>> {
        let member = member.filter(|m| self.scene.member(m).is_some());
        let options = UrdfOptions { package_paths: kinema_geometry::ros_package_path(), ..Default::default() };
        if member.is_some() {
            return Ok(Arc::new(self.scene.standing(member, &options).map_err(geometry_to_py)?));
        }
        if let Some(s) = self.standing.get() {
            return Ok(s.clone());
        }
        let all = Arc::new(self.scene.standing(None, &options).map_err(geometry_to_py)?);
        Ok(self.standing.get_or_init(|| all).clone())
    }
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
        let text = kinema::read_bounded_text(&path, "a scene", kinema_geometry::MAX_SCENE_BYTES).map_err(to_py)?;
        let dir = path.parent().unwrap_or(std::path::Path::new(".")).to_path_buf();
        PyScene::parse(SceneText { text, file: path.display().to_string(), dir })
    }

    /// A scene from TOML text; mesh paths are relative to ``base_dir``
    /// (default: the working directory).
    #[staticmethod]
    #[pyo3(signature = (text, base_dir=None))]
    fn from_toml(text: &str, base_dir: Option<PathBuf>) -> PyResult<Self> {
        let dir = base_dir.unwrap_or_else(|| PathBuf::from("."));
        PyScene::parse(SceneText { text: text.to_string(), file: "scene".into(), dir })
    }

    /// The obstacles' names, in file order.
    #[getter]
    fn obstacles(&self) -> Vec<String> {
        self.scene.obstacles.iter().map(|o| o.name.clone()).collect()
    }

    /// The robots' names, in file order.
    #[getter]
    fn robots(&self) -> Vec<String> {
        self.scene.robots.iter().map(|r| r.name.clone()).collect()
    }

    /// The scene's robot ``name``, on its base in the scene's world; in a
    /// check with this scene it is not its own obstacle.
    ///
    /// Raises:
    ///     InvalidInput: the scene has no robot of that name.
    ///     RobotFileError, DescriptionError: its description cannot be read.
    pub(crate) fn robot(&self, name: &str) -> PyResult<PyRobot> {
        let Some(member) = self.scene.member(name) else {
            return Err(to_py(kinema::Error::Input(kinema::InputError::UnknownName {
                what: "scene robot".into(),
                name: name.to_string(),
                known: self.robots().join(", "),
            })));
        };
        let robot = kinema::Robot::load(&member.robot, member.tip.as_deref()).map_err(to_py)?;
        let placed = kinema::traj::cell::placed(&robot, &member.world_from_base).map_err(to_py)?;
        let source = Source {
            member: Some(name.to_string()),
            scene: Some(Arc::clone(&self.text)),
            ..Source::named(&member.robot, member.tip.clone())
        };
        Ok(PyRobot::new(Arc::new(placed), source))
    }

    fn __repr__(&self) -> String {
        let robots = if self.scene.robots.is_empty() {
            String::new()
        } else {
            format!("; robots: {}", self.robots().join(", "))
        };
        format!("Scene({} obstacle(s): {}{robots})", self.scene.obstacles.len(), self.obstacles().join(", "))
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
    /// The scene robot it is (from `Scene.robot`), not its own obstacle.
    pub member: Option<String>,
    /// The text of that scene, which such a robot pickles with.
    pub scene: Option<Arc<SceneText>>,
    /// The description itself, for a robot defined in code rather than read from `spec`.
    pub inline: Option<Inline>,
    /// The text of the file `spec` names, as it was read: what the robot pickles as.
    pub file_text: Option<Arc<String>>,
}

/// A description given in code (`Robot.from_dh`, `Robot.from_urdf_string`) or
/// unpickled, kept with its robot.
#[derive(Debug, Clone)]
pub(crate) enum Inline {
    /// DH rows, base, tool and poses: no link shapes.
    Description(Arc<kinema::description::Description>),
    /// A URDF document, with its `<collision>` shapes.
    Urdf(Arc<DescriptionText>),
    /// A kinema TOML description, with its `[[shape]]` tables.
    Toml(Arc<DescriptionText>),
}

/// The text of a robot description and where its relative mesh paths start.
#[derive(Debug, Clone)]
pub(crate) struct DescriptionText {
    pub text: String,
    /// The name of the text in messages (the file it was read from, if any).
    pub file: String,
    /// Where relative mesh paths start.
    pub dir: PathBuf,
    /// Where `package://` meshes are searched, before `ROS_PACKAGE_PATH`.
    pub package_paths: Vec<PathBuf>,
}

/// The text of a scene file, named `file` in errors; its paths are relative to `dir`.
#[derive(Debug, Clone)]
pub(crate) struct SceneText {
    pub text: String,
    pub file: String,
    pub dir: PathBuf,
}

impl Source {
    /// The source of a robot read from `spec` (a built-in name or a path).
    pub(crate) fn named(spec: &str, tip: Option<String>) -> Source {
        Source { spec: spec.to_string(), tip, member: None, scene: None, inline: None, file_text: None }
    }

    /// The collision shapes of an inline URDF (meshes searched in its
    /// package paths, then `ROS_PACKAGE_PATH`; relative paths from its `dir`).
    fn inline_urdf(&self, urdf: &DescriptionText) -> kinema_geometry::Result<kinema_geometry::UrdfRobot> {
        let mut package_paths = urdf.package_paths.clone();
        package_paths.extend(kinema_geometry::ros_package_path());
        let options = UrdfOptions { tip: self.tip.clone(), package_paths, skip_visual: true };
        kinema_geometry::urdf_from_str(&urdf.text, &urdf.file, &urdf.dir, &options)
    }

    /// The link shapes of `robot` (loaded from this source) for a check that
    /// can go without them, as `load_shapes_or_none`: none for DH rows; none
    /// and the error, for a warning, when an inline URDF's shapes cannot be read.
    pub(crate) fn shapes_or_none(
        &self,
        robot: &kinema::Robot,
    ) -> kinema_geometry::Result<(RobotGeometry, Option<kinema_geometry::Error>)> {
        match &self.inline {
            None => {
                let options = UrdfOptions { tip: self.tip.clone(), skip_visual: true, ..Default::default() };
                load_shapes_or_none(&self.spec, &options)
            }
            Some(Inline::Description(_)) => Ok((RobotGeometry::new(robot, Vec::new())?, None)),
            Some(Inline::Urdf(text)) => match self.inline_urdf(text) {
                Ok(u) => Ok((u.collision, None)),
                Err(e) => Ok((RobotGeometry::new(robot, Vec::new())?, Some(e))),
            },
            Some(Inline::Toml(toml)) => {
                match kinema_geometry::toml_geometry(robot, &toml.text, &toml.file, &toml.dir) {
                    Ok(geometry) => Ok((geometry, None)),
                    Err(e @ (kinema_geometry::Error::MeshNotFound { .. } | kinema_geometry::Error::Mesh { .. })) => {
                        Ok((RobotGeometry::new(robot, Vec::new())?, Some(e)))
                    }
                    Err(e) => Err(e),
                }
            }
        }
    }

    /// The source of a robot defined in code; `name` stands for it in messages.
    pub(crate) fn inline(name: &str, inline: Inline) -> Source {
        Source {
            spec: format!("<{name}, defined in code>"),
            tip: None,
            member: None,
            scene: None,
            inline: Some(inline),
            file_text: None,
        }
    }

    /// The source of a `robot` argument: a `Robot`'s own, or the built-in
    /// name or path given instead.
    pub(crate) fn of(robot: &Bound<'_, PyAny>) -> Source {
        match robot.downcast::<PyRobot>() {
            Ok(r) => r.get().source.clone(),
            Err(_) => Source::named(&robot.extract::<String>().unwrap_or_default(), None),
        }
    }
}

/// A robot's last collision check, with the scene and margin it was built for.
pub(crate) struct KeptCheck {
    /// The scene (held, so that its address cannot be reused by another).
    scene: Option<Arc<Scene>>,
    margin: f64,
    check: Arc<CollisionCheck>,
}

impl KeptCheck {
    fn fits(&self, scene: Option<&Arc<Scene>>, margin: f64) -> bool {
        let same_scene = match (&self.scene, scene) {
            (None, None) => true,
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            _ => false,
        };
        same_scene && self.margin.to_bits() == margin.to_bits()
    }
}

impl PyRobot {
    /// The robot's self-collision check, loaded once from its description.
    fn bare_check(&self) -> PyResult<&CollisionCheck> {
        if let Some(check) = self.body.get() {
            return Ok(check);
        }
        let check = match &self.source.inline {
            None => {
                let options = CheckOptions { tip: self.source.tip.clone(), ..Default::default() };
                CollisionCheck::load(&self.source.spec, &options)
            }
            Some(inline) => self.inline_check(inline),
        };
        let check = check.map_err(geometry_to_py)?;
        Ok(self.body.get_or_init(|| check))
    }

    /// The self-collision check of a robot defined in code: a URDF's
    /// `<collision>` shapes; DH rows have none, which is an error as for a file.
    fn inline_check(&self, inline: &Inline) -> kinema_geometry::Result<CollisionCheck> {
        let (robot, geometry) = match inline {
            Inline::Urdf(text) => {
                let u = self.source.inline_urdf(text)?;
                (u.robot, u.collision)
            }
            Inline::Toml(toml) => {
                let robot = (*self.robot).clone();
                let geometry = kinema_geometry::toml_geometry(&robot, &toml.text, &toml.file, &toml.dir)?;
                (robot, geometry)
            }
            Inline::Description(desc) => {
                return Err(kinema_geometry::Error::Shape {
                    name: desc.name.clone(),
                    message: format!(
                        "robot `{}` is made of DH rows, which have no link shapes to check; use a URDF with <collision> elements or a robot file with [[shape]] tables",
                        desc.name
                    ),
                })
            }
        };
        if geometry.is_empty() {
            return Err(kinema_geometry::Error::Shape {
                name: robot.name().to_string(),
                message: format!("robot `{}` has no link shapes to check; add <collision> elements", robot.name()),
            });
        }
        let pairs = kinema_geometry::CollisionPairs::self_collision(&geometry);
        CollisionCheck::new(robot, geometry, pairs, 0.0)
    }

    /// The robot's check with `scene`'s obstacles and `margin` \[m\] (what
    /// `kinema collide --scene --margin` checks). The last one built is kept
    /// and reused while the scene and margin stay the same, so a loop of
    /// single calls does not build it each time.
    pub(crate) fn collision_check(&self, scene: Option<&PyScene>, margin: f64) -> PyResult<Arc<CollisionCheck>> {
        let scene_key = scene.map(|s| Arc::clone(&s.scene));
        let mut last = self.last_check.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some(kept) = last.as_ref().filter(|k| k.fits(scene_key.as_ref(), margin)) {
            return Ok(Arc::clone(&kept.check));
        }
        let bare = self.bare_check()?;
        let standing = scene.map(|s| s.standing(self.source.member.as_deref())).transpose()?;
        // This robot, not the description's: a cell or a scene places it on another base.
        let robot = (*self.robot).clone();
        let check = CollisionCheck::with_scene(
            robot,
            bare.geometry().clone(),
            bare.pairs().clone(),
            standing.as_deref(),
            margin,
        )
        .map_err(geometry_to_py)?;
        let check = Arc::new(check);
        *last = Some(KeptCheck { scene: scene_key, margin, check: Arc::clone(&check) });
        Ok(check)
    }

    /// [`PyRobot::collision_check`] when a scene or a margin asks for one.
    pub(crate) fn collision_check_if_asked(
        &self,
        scene: Option<&PyScene>,
        margin: Option<f64>,
    ) -> PyResult<Option<Arc<CollisionCheck>>> {
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
