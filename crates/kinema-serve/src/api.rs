//! The request handler: routing, the JSON API and the embedded page, as pure
//! functions of (method, path, body).

use kinema::ik::{solve_target, Admissible, IkRequest, IkTarget, NumericOptions, SolverChoice};
use kinema::traj::{
    check, to_joints, Blend, CartesianLimits, CartesianMotion, CheckOptions, JointMethod, Orientation, Profile, Ptp,
    PtpOptions, Segment,
};
use kinema::{Robot, RpyConvention};
use kinema_geometry::{
    load_robot_geometry, ros_package_path, CollisionCheck, CollisionPairs, RobotGeometry, Scene, UrdfOptions,
};
use std::path::Path;
use std::sync::{Arc, OnceLock};
use std::time::Duration;

use kinema_lang::{Stop, StopReason};
use serde::Serialize;
use serde_json::Value;

mod plan;

pub use plan::MAX_PLAN_TIME;

use crate::cell::{CellAnswer, CellMotion};
use crate::error::{Error, Result};
use crate::request::{parse, CollideReq, IkReq, OneOrMany, QReq, RunReq, SceneReq, TrajReq};
use crate::shapes::{GeometryAnswer, SceneAnswer};
use crate::view::{ViewReq, ViewSlot, VIEW_SHAPE};
use kinema_io::{
    ClosestAnswer, CollideAnswer, ErrorAnswer, FkAnswer, IkAnswer, ManipAnswer, ProgramAnswer, RobotInfo, RobotSummary,
    TrajSummary, TrajectoryAnswer,
};

/// Largest request body accepted \[bytes\] (1 MiB); larger ones get 413.
pub const MAX_BODY: usize = 1 << 20;

/// Largest number of samples `/api/traj` and `/api/run` produce.
pub const MAX_SAMPLES: usize = 200_000;

/// Time a `/api/run` program may run (10 s), counted from when it starts
/// compiling; a program still running then is stopped between two
/// statements and answered with 422 ([`Error::RunBudget`]).
pub const RUN_BUDGET: Duration = Duration::from_secs(10);

const INDEX_HTML: &str = include_str!("../assets/index.html");
/// The page's script: `web/src/*.js` and three.js, bundled by `build.rs`.
const VIEWER_JS: &str = include_str!(concat!(env!("OUT_DIR"), "/viewer.js"));
const STYLE_CSS: &str = include_str!("../assets/style.css");

/// An answer: status, content type, extra headers and body.
#[derive(Debug, Clone, PartialEq)]
pub struct Reply {
    /// HTTP status code.
    pub status: u16,
    /// The `Content-Type` header.
    pub content_type: &'static str,
    /// Further headers (name, value), e.g. `Allow` on a 405.
    pub headers: Vec<(&'static str, String)>,
    /// The body.
    pub body: Vec<u8>,
}

impl Reply {
    /// A JSON reply.
    pub fn json(status: u16, value: &Value) -> Reply {
        Reply {
            status,
            content_type: "application/json; charset=utf-8",
            headers: Vec::new(),
            body: serde_json::to_vec(value).unwrap_or_else(|_| b"{\"error\":\"unserialisable answer\"}".to_vec()),
        }
    }

    /// The JSON error reply for `e`: `{"error": message}` (a program's
    /// errors also carry `diagnostics`, the rendered report), with `Allow`
    /// on a 405.
    pub fn error(e: &Error) -> Reply {
        let (status, body) = error_json(e);
        let mut r = Reply::json(status, &body);
        if let Error::MethodNotAllowed { allowed, .. } = e {
            r.headers.push(("Allow", allowed.to_string()));
        }
        r
    }
}

fn error_json(e: &Error) -> (u16, Value) {
    let (diagnostics, budget_s) = match e {
        Error::Program { rendered, .. } => (Some(rendered.clone()), None),
        Error::RunBudget { rendered, budget, .. } => (Some(rendered.clone()), Some(budget.as_secs_f64())),
        _ => (None, None),
    };
    let body = ErrorAnswer { error: e.to_string(), diagnostics, budget_s };
    let mut value = serde_json::to_value(body).unwrap_or(Value::Null);
    // An unreachable IK target: the configuration that came closest, as
    // `kinema ik --json` reports it (the page shows it, saying so).
    if let (Error::Core(kinema::Error::Unreachable { closest: Some(c), .. }), Value::Object(fields)) = (e, &mut value) {
        let closest =
            ClosestAnswer { q: c.q.clone(), position_error: c.position_error, orientation_error: c.orientation_error };
        fields.insert("closest".into(), serde_json::to_value(closest).unwrap_or(Value::Null));
    }
    (e.status(), value)
}

/// The robots a server knows and its request handler.
///
/// The robots are the built-in ones plus, optionally, a default robot (which
/// may come from a file; it replaces a built-in robot of the same name).
/// Requests name robots only from this list — never a file path.
#[derive(Debug, Clone)]
pub struct App {
    robots: Vec<Robot>,
    /// The built-in robots' link shapes, by robot name, loaded at the first
    /// collision check.
    bodies: OnceLock<Vec<(String, RobotGeometry)>>,
    /// The default robot's shapes when they were given ([`App::with_link_shapes`]).
    default_shapes: Option<LinkShapes>,
    /// The server's scene ([`App::with_scene`]), its robots standing as
    /// obstacles: drawn by the page and checked when a request gives none.
    scene: Option<Scene>,
    /// The cell the page plays ([`App::with_cell`]), as its JSON answer.
    cell: Option<Arc<Value>>,
    /// What a program last asked the page to show (`/api/view`), shared by the app's clones.
    view: ViewSlot,
    default: usize,
}

/// A robot's shapes to draw: visual ones and collision ones, either may be missing.
#[derive(Debug, Clone, Default)]
struct LinkShapes {
    visual: Option<RobotGeometry>,
    collision: Option<RobotGeometry>,
}

impl App {
    /// The built-in robots and `default_robot` (default: the first built-in
    /// robot, in name order).
    pub fn new(default_robot: Option<Robot>) -> Result<App> {
        let mut robots = Robot::builtins()?;
        let default = match default_robot {
            Some(r) => match robots.iter().position(|b| b.name() == r.name()) {
                Some(i) => {
                    robots[i] = r;
                    i
                }
                None => {
                    robots.push(r);
                    robots.len() - 1
                }
            },
            None => 0,
        };
        if robots.is_empty() {
            return Err(Error::Unprocessable { message: "there are no robots to serve".into() });
        }
        Ok(App {
            robots,
            bodies: OnceLock::new(),
            default_shapes: None,
            scene: None,
            cell: None,
            view: ViewSlot::default(),
            default,
        })
    }

    /// The default robot's shapes for the page to draw: `visual` (a URDF's
    /// `<visual>` elements) and `collision` (its `<collision>` elements or a
    /// robot file's `[[shape]]`s). Without them the page draws a built-in
    /// robot's `[[shape]]`s, or else only the link frames (as when both are
    /// `None`). Both must belong
    /// to the default robot (its name and number of joints).
    pub fn with_link_shapes(mut self, visual: Option<RobotGeometry>, collision: Option<RobotGeometry>) -> Result<App> {
        let robot = self.default_robot();
        for g in visual.iter().chain(collision.iter()) {
            if g.robot() != robot.name() || g.dof() != robot.dof() {
                return Err(Error::Unprocessable {
                    message: format!(
                        "shapes of robot `{}` ({} joints) given for robot `{}` ({} joints)",
                        g.robot(),
                        g.dof(),
                        robot.name(),
                        robot.dof()
                    ),
                });
            }
        }
        self.default_shapes = (visual.is_some() || collision.is_some()).then_some(LinkShapes { visual, collision });
        Ok(self)
    }

    /// The scene the page draws and collision checks use when a request
    /// gives none (`kinema serve --scene`): its obstacles, and its robots
    /// standing where it puts them ([`Scene::standing`]).
    pub fn with_scene(mut self, scene: &Scene) -> Result<App> {
        let meshes = UrdfOptions { package_paths: ros_package_path(), ..Default::default() };
        let standing = scene.standing(None, &meshes).map_err(|e| Error::Unprocessable { message: e.to_string() })?;
        self.scene = Some(standing);
        Ok(self)
    }

    /// A cell for the page to play (`kinema serve --cell`): robots sampled on
    /// one clock, answered by `GET /api/cell` with their link poses at
    /// every sample. At most [`MAX_SAMPLES`] robot samples.
    pub fn with_cell(mut self, times: &[f64], members: &[CellMotion]) -> Result<App> {
        self.cell = Some(Arc::new(to_value(CellAnswer::new(times, members)?)?));
        Ok(self)
    }

    /// The link shapes of the built-in robots this server serves.
    fn bodies(&self) -> Result<&[(String, RobotGeometry)]> {
        if let Some(bodies) = self.bodies.get() {
            return Ok(bodies);
        }
        let mut bodies = Vec::new();
        for name in kinema::builtin_names() {
            let (builtin, geometry) = load_robot_geometry(name, &Default::default())
                .map_err(|e| Error::Internal { message: format!("built-in robot `{name}`'s shapes: {e}") })?;
            // A default robot that replaced a built-in of its name has other links: its shapes are not known.
            if self.robots.contains(&builtin) {
                bodies.push((name.to_string(), geometry));
            }
        }
        Ok(self.bodies.get_or_init(|| bodies))
    }

    /// The robot requests get when they name none.
    pub fn default_robot(&self) -> &Robot {
        &self.robots[self.default]
    }

    /// Answers one request: the page and its assets under `/`, the JSON API
    /// under `/api/`. Never panics on any input (the server also wraps it in
    /// `catch_unwind`). `path` may carry a query string, which is ignored.
    /// A `/api/run` program gets [`RUN_BUDGET`].
    pub fn handle(&self, method: &str, path: &str, body: &[u8]) -> Reply {
        self.handle_until(method, path, body, &Stop::after(RUN_BUDGET))
    }

    /// [`App::handle`] with the stop condition of a `/api/run` program given:
    /// its deadline (an [`Error::RunBudget`] answer, 422) and a flag another
    /// thread may raise (an [`Error::ShuttingDown`] answer, 503). Other
    /// endpoints ignore `stop`.
    pub fn handle_until(&self, method: &str, path: &str, body: &[u8], stop: &Stop) -> Reply {
        let path = path.split(['?', '#']).next().unwrap_or("");
        let asset = match path {
            "/" | "/index.html" => Some(("text/html; charset=utf-8", INDEX_HTML)),
            "/viewer.js" => Some(("text/javascript; charset=utf-8", VIEWER_JS)),
            "/style.css" => Some(("text/css; charset=utf-8", STYLE_CSS)),
            _ => None,
        };
        if let Some((content_type, text)) = asset {
            if method != "GET" && method != "HEAD" {
                return Reply::error(&Error::MethodNotAllowed {
                    method: method.into(),
                    path: path.into(),
                    allowed: "GET, HEAD",
                });
            }
            return Reply {
                status: 200,
                content_type,
                headers: vec![("Cache-Control", "no-cache".into())],
                body: text.as_bytes().to_vec(),
            };
        }
        let (status, value) = self.api_until(method, path, body, stop);
        let mut reply = Reply::json(status, &value);
        if status == 405 {
            let allowed = if path.starts_with("/api/robots") { "GET, HEAD" } else { "POST" };
            reply.headers.push(("Allow", allowed.into()));
        }
        reply
    }

    /// The JSON API alone: `(status, json)`; errors are `{"error": "…"}`
    /// with a 4xx status.
    pub fn api(&self, method: &str, path: &str, body: &[u8]) -> (u16, Value) {
        self.api_until(method, path, body, &Stop::after(RUN_BUDGET))
    }

    /// [`App::api`] with the stop condition of a `/api/run` program given
    /// (see [`App::handle_until`]).
    pub fn api_until(&self, method: &str, path: &str, body: &[u8], stop: &Stop) -> (u16, Value) {
        let path = path.split(['?', '#']).next().unwrap_or("");
        match self.route(method, path, body, stop) {
            Ok(v) => (200, v),
            Err(e) => error_json(&e),
        }
    }

    fn route(&self, method: &str, path: &str, body: &[u8], stop: &Stop) -> Result<Value> {
        let path = path.strip_suffix('/').filter(|p| !p.is_empty()).unwrap_or(path);
        let get = |allowed_ok: bool| -> Result<()> {
            if allowed_ok {
                Ok(())
            } else {
                Err(Error::MethodNotAllowed { method: method.into(), path: path.into(), allowed: "GET, HEAD" })
            }
        };
        let is_get = method == "GET" || method == "HEAD";
        if path == "/api/robots" {
            get(is_get)?;
            let summaries: Vec<RobotSummary> =
                self.robots.iter().enumerate().map(|(i, r)| RobotSummary::new(r, i == self.default)).collect();
            return to_value(summaries);
        }
        if let Some(name) = path.strip_prefix("/api/robots/").and_then(|p| p.strip_suffix("/geometry")) {
            get(is_get)?;
            return self.geometry(name);
        }
        if let Some(name) = path.strip_prefix("/api/robots/") {
            get(is_get)?;
            return to_value(RobotInfo::new(self.robot_named(name, true)?));
        }
        if path == "/api/cell" {
            get(is_get)?;
            let none = || to_value(CellAnswer::new(&[], &[])?);
            return self.cell.as_ref().map_or_else(none, |c| Ok(Value::clone(c)));
        }
        if path == "/api/view" && is_get {
            return Ok(self.view.get());
        }
        if path == "/api/scene" && is_get {
            let obstacles = self.scene.as_ref().map_or(&[][..], |s| &s.obstacles[..]);
            return to_value(SceneAnswer::new(obstacles));
        }
        let post: fn(&App, &[u8], &Stop) -> Result<Value> = match path {
            "/api/fk" => |a, b, _| a.fk(b),
            "/api/ik" => |a, b, _| a.ik(b),
            "/api/traj" => |a, b, _| a.traj(b),
            "/api/run" => App::run,
            "/api/plan" => App::plan,
            "/api/manip" => |a, b, _| a.manip(b),
            "/api/collide" => |a, b, _| a.collide(b),
            "/api/scene" => |a, b, _| a.scene(b),
            "/api/view" => |a, b, _| a.show(b),
            _ => return Err(Error::NotFound { path: path.into() }),
        };
        if method != "POST" {
            return Err(Error::MethodNotAllowed { method: method.into(), path: path.into(), allowed: "POST" });
        }
        post(self, body, stop)
    }

    fn robot_named(&self, name: &str, in_path: bool) -> Result<&Robot> {
        self.robots.iter().find(|r| r.name() == name).ok_or_else(|| Error::UnknownRobot {
            name: name.into(),
            known: self.robots.iter().map(|r| r.name()).collect::<Vec<_>>().join(", "),
            in_path,
        })
    }

    fn robot(&self, name: &Option<String>) -> Result<&Robot> {
        match name {
            Some(n) => self.robot_named(n, false),
            None => Ok(self.default_robot()),
        }
    }

    fn fk(&self, body: &[u8]) -> Result<Value> {
        let req: QReq = parse(body, "/api/fk", r#"{"robot": "NAME", "q": [joint values in rad and m]}"#)?;
        let r = self.robot(&req.robot)?;
        to_value(FkAnswer::new(r, &req.q, RpyConvention::Zyx)?)
    }

    /// A configuration or trajectory for the page to show (`POST /api/view`), checked first.
    fn show(&self, body: &[u8]) -> Result<Value> {
        let req: ViewReq = parse(body, "/api/view", VIEW_SHAPE)?;
        let robot = self.robot(&req.robot)?;
        self.view.set(robot, req)
    }

    /// A pose update asked on the WebSocket: the FK answer of a
    /// `{"robot": NAME, "q": [...]}` message (the body of `/api/fk`), or
    /// `{"error": …}`.
    pub fn pose_update(&self, message: &[u8]) -> Value {
        self.fk(message).unwrap_or_else(|e| error_json(&e).1)
    }

    /// The shapes of robot `name` to draw, in its link frames.
    fn geometry(&self, name: &str) -> Result<Value> {
        let robot = self.robot_named(name, true)?;
        let given = self.default_shapes.as_ref().filter(|_| robot == self.default_robot());
        let answer = match given {
            Some(s) => GeometryAnswer::new(robot.name(), robot.dof(), s.visual.as_ref(), s.collision.as_ref()),
            None => {
                let builtin = self.bodies()?.iter().find(|(n, _)| n == robot.name()).map(|(_, g)| g);
                GeometryAnswer::new(robot.name(), robot.dof(), None, builtin)
            }
        };
        to_value(answer)
    }

    /// A scene's obstacles in the world frame, its robots standing as obstacles.
    fn scene(&self, body: &[u8]) -> Result<Value> {
        const SHAPE: &str = r#"{"scene": "a scene file's TOML text"}"#;
        let req: SceneReq = parse(body, "/api/scene", SHAPE)?;
        let meshes = UrdfOptions { package_paths: ros_package_path(), ..Default::default() };
        let scene = Scene::from_toml(&req.scene, "scene", Path::new("."))
            .and_then(|s| s.standing(None, &meshes))
            .map_err(|e| Error::Unprocessable { message: e.to_string() })?;
        to_value(SceneAnswer::new(&scene.obstacles))
    }

    fn manip(&self, body: &[u8]) -> Result<Value> {
        let req: QReq = parse(body, "/api/manip", r#"{"robot": "NAME", "q": [joint values in rad and m]}"#)?;
        let r = self.robot(&req.robot)?;
        to_value(ManipAnswer::new(r, &req.q, None)?)
    }

    /// The collision check of robot `name` (the default robot's collision
    /// shapes when they were given, else a built-in's) with the obstacles of
    /// `scene` (a scene file's TOML text; the server's scene when `None`) and
    /// `margin` \[m\].
    fn collision_check(
        &self,
        name: &Option<String>,
        scene: Option<&str>,
        margin: Option<f64>,
    ) -> Result<CollisionCheck> {
        let robot = self.robot(name)?;
        let geometry = self.collision_shapes(robot)?.ok_or_else(|| Error::Unprocessable {
            message: format!(
                "robot `{}` has no link shapes known to the server (collision checks use a built-in robot's \
                 shapes or the collision shapes of the robot the server was started with)",
                robot.name()
            ),
        })?;
        let unprocessable = |e: kinema_geometry::Error| Error::Unprocessable { message: e.to_string() };
        // The scene's robots stand as obstacles; the robot checked is one the server serves.
        let meshes = UrdfOptions { package_paths: ros_package_path(), ..Default::default() };
        let standing = |text: &str| Scene::from_toml(text, "scene", Path::new("."))?.standing(None, &meshes);
        let given = scene.map(standing).transpose().map_err(unprocessable)?;
        let scene = given.as_ref().or(self.scene.as_ref());
        let pairs = CollisionPairs::self_collision(geometry);
        CollisionCheck::with_scene(robot.clone(), geometry.clone(), pairs, scene, margin.unwrap_or(0.0))
            .map_err(unprocessable)
    }

    /// The shapes collisions of `robot` are checked with: the default
    /// robot's collision shapes when they were given (a URDF's `<collision>`
    /// meshes included), else a built-in robot's `[[shape]]`s.
    fn collision_shapes(&self, robot: &Robot) -> Result<Option<&RobotGeometry>> {
        let given = self.default_shapes.as_ref().filter(|_| robot == self.default_robot());
        if let Some(collision) = given.and_then(|s| s.collision.as_ref()).filter(|g| !g.is_empty()) {
            return Ok(Some(collision));
        }
        Ok(self.bodies()?.iter().find(|(n, _)| n == robot.name()).map(|(_, g)| g))
    }

    /// [`App::collision_check`] when a scene or a margin asks for one.
    fn collision_check_if_asked(
        &self,
        name: &Option<String>,
        scene: Option<&str>,
        margin: Option<f64>,
    ) -> Result<Option<CollisionCheck>> {
        match (scene, margin) {
            (None, None) => Ok(None),
            (scene, margin) => self.collision_check(name, scene, margin).map(Some),
        }
    }

    fn collide(&self, body: &[u8]) -> Result<Value> {
        const SHAPE: &str = r#"{"robot": "NAME", "q": [joint values in rad and m], optional "scene" (a scene file's TOML text: [[obstacle]] tables), "margin" (m, ≥ 0)}"#;
        let req: CollideReq = parse(body, "/api/collide", SHAPE)?;
        let check = self.collision_check(&req.robot, req.scene.as_deref(), req.margin)?;
        check.robot().check_q(&req.q)?;
        let answer = CollideAnswer::of(&check, req.q, &mut check.placement())
            .map_err(|e| Error::Unprocessable { message: e.to_string() })?;
        to_value(answer)
    }

    fn ik(&self, body: &[u8]) -> Result<Value> {
        const SHAPE: &str = r#"{"robot": "NAME", "T": [[4 numbers] × 4 rows]} or {"robot": "NAME", "position": [x, y, z], "rpy": [roll, pitch, yaw]} or {"robot": "NAME", "position": [x, y, z]} (orientation free), with "pitch" and "roll" (Scorbot), "approach": [x, y, z] (ROMMEL) or "alpha" (SCARA) for a typed target; optional "q3" or "psi" (arm angle), "q0", "solver" ("auto" | "analytic" | "numeric"), "seed", "mask" ([6 booleans]: x, y, z, ωx, ωy, ωz to meet), "scene" (a scene file's TOML text; solutions in collision are discarded), "margin" (m)"#;
        let req: IkReq = parse(body, "/api/ik", SHAPE)?;
        let r = self.robot(&req.robot)?;
        let target = req.ik_target(SHAPE)?;
        if let IkTarget::Pose(pose) = &target {
            kinema::ik::check_target(pose)?;
        }
        if let Some(q0) = &req.q0 {
            r.check_q(q0)?;
        }
        let solver = named("/api/ik", req.solver.as_deref(), SolverChoice::Auto)?;
        let check = self.collision_check_if_asked(&req.robot, req.scene.as_deref(), req.margin)?;
        // Every solution (the viewer shows them all, `nearest` marks the one
        // nearest q0); for an iiwa-type arm the closed form at the request's q3
        // or ψ, else at q0's q3.
        let request = IkRequest {
            solver,
            q0: req.q0.as_deref(),
            all: true,
            q3: req.q3,
            psi: req.psi,
            mask: req.mask,
            tolerance: Default::default(),
            numeric: NumericOptions { seed: req.seed.unwrap_or(0), ..Default::default() },
            admissible: check.as_ref().map(|c| c as &dyn Admissible),
            ..Default::default()
        };
        let answer = solve_target(r, &target, &request)?;
        let mut solutions = answer.solutions.clone();
        let redundant = kinema::ik::registry::fit(r).is_some_and(|f| f.redundancy().is_some());
        let q3 = req
            .q3
            .or_else(|| req.q0.as_ref().and_then(|q| q.get(2).copied()))
            .filter(|_| redundant && req.psi.is_none());
        // The one the CLI and Python return for the same question (one solution
        // wanted: an iiwa-type arm may search its self-motion), marked among the
        // listed ones, or added to them when the search moved q3.
        let one = IkRequest { all: false, ..request.clone() };
        let picked = solve_target(r, &target, &one)
            .and_then(|a| kinema::ik::pick_one(r, a.solver, a.solutions, req.q0.as_deref()))
            .ok()
            .map(|best| match solutions.iter().position(|s| s.q == best.q) {
                Some(i) => i,
                None => {
                    solutions.push(best);
                    solutions.len() - 1
                }
            });
        let nearest = picked.filter(|_| req.q0.is_some());
        let ik = IkAnswer {
            q3,
            psi: req.psi,
            nearest,
            picked,
            ..IkAnswer::new(r, &answer, &solutions, &target, RpyConvention::Zyx)
        };
        to_value(ik)
    }

    fn traj(&self, body: &[u8]) -> Result<Value> {
        const SHAPE: &str = r#"{"robot": "NAME", "kind": "ptp", "from": [q], "to": [q]} or {"robot": "NAME", "kind": "lin", "from": [q], "T": [[…] × 4] or "position" + "rpy"}, optional "dt" [s], "profile", "speed" [%], "duration" [s], "jvel", "jacc", "jjerk" (ptp: one value or one per joint, rad/s… or m/s…), "vmax" [m/s], "amax" [m/s²] (lin), "scene" (a scene file's TOML text: a motion that collides is refused), "margin" (m)"#;
        let req: TrajReq = parse(body, "/api/traj", SHAPE)?;
        let r = self.robot(&req.robot)?;
        let collision = self.collision_check_if_asked(&req.robot, req.scene.as_deref(), req.margin)?;
        let dt = req.dt.unwrap_or(0.01);
        check_dt(dt)?;
        // PTP's default law is the core's choice for the robot, as `kinema traj ptp`'s.
        let default = if req.kind == "ptp" { kinema::traj::default_profile(r) } else { Profile::Trapezoid };
        let profile = named("/api/traj", req.profile.as_deref(), default)?;
        r.check_q(&req.from)?;
        let (traj, summary) = match req.kind.as_str() {
            "ptp" => {
                let to =
                    req.to.as_ref().ok_or_else(|| bad(format!("/api/traj: ptp needs \"to\"; expected {SHAPE}")))?;
                let speed = req.speed.unwrap_or(100.0);
                if !(speed > 0.0 && speed <= 100.0) {
                    return Err(bad(format!("/api/traj: speed {speed} must be a percentage in (0, 100]")));
                }
                let opts = PtpOptions {
                    profile,
                    speed: speed / 100.0,
                    vel: req.jvel.as_ref().map(OneOrMany::values),
                    acc: req.jacc.as_ref().map(OneOrMany::values),
                    jerk: req.jjerk.as_ref().map(OneOrMany::values),
                    duration: req.duration,
                };
                let plan = Ptp::new(r, &req.from, to, &opts)?;
                cap_samples(plan.duration(), dt)?;
                let traj = plan.sample(r, dt)?;
                let summary = TrajSummary::ptp(r, &plan, traj.len());
                (traj, summary)
            }
            "lin" => {
                let target = req.target().pose("/api/traj", SHAPE)?;
                kinema::ik::check_target(&target)?;
                let (vmax, amax) = (req.vmax.unwrap_or(0.25), req.amax.unwrap_or(1.0));
                for (what, v) in [("vmax", vmax), ("amax", amax)] {
                    if !(v.is_finite() && v > 0.0) {
                        return Err(bad(format!("/api/traj: {what} = {v} must be a positive number")));
                    }
                }
                let start = r.fk(&req.from)?.world_from_tool;
                let seg = Segment::lin(&start, &target, Orientation::Slerp)?;
                let mut limits = CartesianLimits::new(vmax, amax);
                if profile == Profile::SCurve {
                    limits.jerk = Some(amax * 10.0);
                    limits.rot_jerk = Some(amax * 10.0);
                }
                let motion = CartesianMotion::new(vec![seg], profile, &limits, Blend::None)?;
                cap_samples(motion.duration(), dt)?;
                let traj = to_joints(r, &motion, &req.from, dt, JointMethod::Ik(req.self_motion()?))?;
                check(r, &traj, &CheckOptions::default())?.into_result()?;
                let summary = TrajSummary::cartesian(r, &motion, profile, traj.len(), &[]);
                (traj, summary)
            }
            other => return Err(bad(format!("/api/traj: kind `{other}` is not ptp or lin; expected {SHAPE}"))),
        };
        if let Some(check) = &collision {
            kinema::traj::collision_free(&traj, check)?;
        }
        to_value(TrajAnswer { summary, samples: TrajectoryAnswer(&traj) })
    }

    fn run(&self, body: &[u8], stop: &Stop) -> Result<Value> {
        const SHAPE: &str =
            r#"{"robot": "NAME", "program": "TEXT", "dt": seconds, "start": [q], "scene": "TOML text", "margin": m}"#;
        let req: RunReq = parse(body, "/api/run", SHAPE)?;
        let r = self.robot(&req.robot)?;
        let collision = self.collision_check_if_asked(&req.robot, req.scene.as_deref(), req.margin)?.map(Arc::new);
        let dt = req.dt.unwrap_or(0.01);
        check_dt(dt)?;
        if let Some(q) = &req.start {
            r.check_q(q)?;
        }
        let opts = kinema_lang::Options {
            dt,
            start: req.start.clone(),
            max_samples: MAX_SAMPLES,
            stop: stop.clone(),
            planner: collision.clone().map(|c| kinema_io::ScenePlanner::shared(c, None)),
            admissible: collision.map(|c| c as Arc<dyn Admissible>),
            ..Default::default()
        };
        const FILE: &str = "program";
        let plan = kinema_lang::compile(&req.program, r, &opts).map_err(|diags| {
            let first = diags.iter().find(|d| d.is_error()).or(diags.first());
            let first = first.map_or_else(|| "no diagnostic".into(), |d| d.one_line(FILE, &req.program));
            let rendered = kinema_lang::render_all(&diags, FILE, &req.program);
            // A program that failed after its stop condition came true was
            // stopped by it (the compiler reports that as an error diagnostic).
            match stop.reason() {
                Some(StopReason::Deadline(budget)) => Error::RunBudget { budget, first, rendered },
                Some(StopReason::Cancelled) => Error::ShuttingDown,
                None => Error::Program { first, rendered },
            }
        })?;
        to_value(RunAnswer {
            program: ProgramAnswer::new(&plan, FILE, &req.program)?,
            samples: TrajectoryAnswer(&plan.trajectory),
            warnings_rendered: kinema_lang::render_all(&plan.warnings, FILE, &req.program),
        })
    }
}

/// The answer of `/api/traj`: the summary `kinema traj … --json` prints, and the samples.
#[derive(Serialize)]
struct TrajAnswer<'a> {
    #[serde(flatten)]
    summary: TrajSummary,
    #[serde(flatten)]
    samples: TrajectoryAnswer<'a>,
}

/// The answer of `/api/run`: what `kinema run --json` prints, the samples
/// and the warnings rendered with their source lines.
#[derive(Serialize)]
struct RunAnswer<'a> {
    #[serde(flatten)]
    program: ProgramAnswer,
    #[serde(flatten)]
    samples: TrajectoryAnswer<'a>,
    warnings_rendered: String,
}

/// An option value read by the core from its name (`default` when the request
/// leaves it out); a wrong name is a bad request to `path`.
pub(crate) fn named<T: std::str::FromStr<Err = kinema::Error>>(
    path: &str,
    name: Option<&str>,
    default: T,
) -> Result<T> {
    name.map_or(Ok(default), |n| n.parse().map_err(|e: kinema::Error| bad(format!("{path}: {e}"))))
}

/// An answer as a JSON value (to which a handler may add fields).
fn to_value(answer: impl serde::Serialize) -> Result<Value> {
    serde_json::to_value(answer)
        .map_err(|e| Error::Internal { message: format!("an answer could not be written as JSON: {e}") })
}

pub(crate) fn bad(message: String) -> Error {
    Error::BadRequest { message }
}

fn check_dt(dt: f64) -> Result<()> {
    if !(dt.is_finite() && (1e-4..=1.0).contains(&dt)) {
        return Err(bad(format!("dt = {dt} s; the sample period must lie in [0.0001, 1] s")));
    }
    Ok(())
}

fn cap_samples(duration: f64, dt: f64) -> Result<()> {
    let n = duration / dt + 2.0;
    if !(n <= MAX_SAMPLES as f64) {
        return Err(Error::Unprocessable {
            message: format!(
                "{duration:.3} s sampled every {dt} s gives about {n:.0} samples; at most {MAX_SAMPLES} are produced — use a larger dt"
            ),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn app() -> App {
        App::new(None).unwrap()
    }

    #[test]
    fn assets_are_served_and_the_query_is_ignored() {
        let a = app();
        for (path, kind) in [
            ("/", "text/html"),
            ("/index.html?x=1", "text/html"),
            ("/viewer.js", "javascript"),
            ("/style.css", "text/css"),
        ] {
            let r = a.handle("GET", path, b"");
            assert_eq!(r.status, 200, "{path}");
            assert!(r.content_type.contains(kind));
            assert!(!r.body.is_empty());
        }
        let r = a.handle("POST", "/viewer.js", b"");
        assert_eq!(r.status, 405);
        assert!(r.headers.iter().any(|(h, v)| *h == "Allow" && v.contains("GET")));
    }

    #[test]
    fn the_default_robot_is_first_choice_and_named_robots_are_found() {
        let puma = Robot::builtin("puma560").unwrap();
        let a = App::new(Some(puma)).unwrap();
        assert_eq!(a.default_robot().name(), "puma560");
        let (status, v) = a.api("POST", "/api/fk", br#"{"q": [0, 0, 0, 0, 0, 0]}"#);
        assert_eq!(status, 200);
        assert_eq!(v["robot"], "puma560");
        let (status, v) = a.api("GET", "/api/robots/", b"");
        assert_eq!(status, 200);
        assert!(v.as_array().unwrap().iter().any(|r| r["name"] == "puma560" && r["default"] == true));
    }

    #[test]
    fn a_program_is_stopped_by_its_budget_or_its_flag() {
        use std::sync::atomic::AtomicBool;
        use std::sync::Arc;
        let a = app();
        // Within every cap of the language, about ten seconds of IK solves.
        let body = br#"{"program": "JACC 90 deg/s^2\nPOS p = CART(550mm, -150mm, 400mm, 0deg, 180deg, 0deg)\nPTP p\nFOR i = 1 TO 450000\n  PTP p\nEND\n", "dt": 0.5}"#;
        let (status, v) = a.api_until("POST", "/api/run", body, &Stop::after(Duration::from_millis(20)));
        assert_eq!(status, 422, "{v}");
        assert!(v["error"].as_str().unwrap().contains("time budget of 0.02 s"), "{v}");
        assert_eq!(v["budget_s"], 0.02);
        assert!(v["diagnostics"].as_str().unwrap().contains("stopped here"), "{v}");
        let flag = Arc::new(AtomicBool::new(true));
        let (status, v) = a.api_until("POST", "/api/run", body, &Stop::never().with_flag(flag));
        assert_eq!(status, 503, "{v}");
        // A short program is not affected by the default budget.
        let (status, v) = a.api("POST", "/api/run", br#"{"program": "WAIT 1\n"}"#);
        assert_eq!(status, 200, "{v}");
    }

    #[test]
    fn every_error_is_json_with_its_status() {
        let a = app();
        for (method, path, body, status) in [
            ("GET", "/nope", &b""[..], 404),
            ("PATCH", "/api/ik", b"", 405),
            ("POST", "/api/ik", b"{", 400),
            ("POST", "/api/run", br#"{"program": "WAIT 1mm"}"#, 422),
        ] {
            let r = a.handle(method, path, body);
            assert_eq!(r.status, status, "{method} {path}");
            let v: Value = serde_json::from_slice(&r.body).unwrap();
            assert!(v["error"].is_string());
        }
    }

    #[test]
    fn malformed_bodies_keep_the_parser_error() {
        let e = parse::<Value>(b"{\"q\": [0, 0.5", "/api/fk", "{q}").unwrap_err();
        match &e {
            Error::Json { endpoint, shape, source } => {
                assert_eq!((endpoint.as_str(), shape.as_str()), ("/api/fk", "{q}"));
                assert!(source.0.is_eof() && source.0.line() == 1, "{source:?}");
            }
            other => panic!("{other:?}"),
        }
        let inner = std::error::Error::source(&e).and_then(|s| s.source());
        assert!(inner.is_some_and(|s| s.downcast_ref::<serde_json::Error>().is_some()), "{e:?}");
        assert_eq!(e.status(), 400);
        assert!(
            e.to_string().starts_with("/api/fk: EOF while parsing") && e.to_string().ends_with("; expected JSON {q}")
        );
        let e = parse::<Value>(b"{\"q\": \xff}", "/api/fk", "{q}").unwrap_err();
        assert!(matches!(&e, Error::NotUtf8 { source, .. } if source.valid_up_to() == 6), "{e:?}");
        assert_eq!(e.status(), 400);
        assert_eq!(e.to_string(), "/api/fk: the body is not UTF-8 text (byte 6); expected JSON {q}");
    }
}
