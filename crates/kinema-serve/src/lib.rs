//! # kinema-serve — the interactive 3D viewer of kinema
//!
//! A local HTTP/1.1 server (axum's router on hyper, on a tokio runtime of its
//! own) with a JSON API backed by the `kinema` and `kinema-lang` libraries,
//! and a web page embedded in the binary that draws the robot with three.js
//! (bundled from npm by `build.rs`; nothing is downloaded at run time). The
//! page gets a robot's link shapes once (`GET /api/robots/{name}/geometry`)
//! and its link poses as the joints move (the WebSocket `/api/ws`).
//!
//! * [`Server`] — binds a TCP address ([`Server::bind`]), tells its
//!   [`Server::url`], and serves requests, either in the calling thread
//!   ([`Server::run`], [`Server::run_until`], [`Server::run_until_signal`]
//!   for Ctrl-C and SIGTERM) or in the background ([`Server::spawn`] →
//!   [`Running`], stopped by [`Running::stop`] or when dropped). Stopping is
//!   graceful: running programs are stopped and requests in progress finish.
//! * [`Limits`] — the server's timeouts and concurrency limits
//!   ([`Server::with_limits`]).
//! * [`App`] — the robots the server knows and the request handler as a pure
//!   function: [`App::handle`] takes a method, a path and a body and returns a
//!   [`Reply`]; [`App::api`] is the JSON part, `(status, json)`. No socket is
//!   needed to test it.
//! * [`Error`] — everything that can go wrong, each with the HTTP status it
//!   maps to ([`Error::status`]).
//!
//! The API (every answer is JSON; every error is `{"error": "…"}` with a 4xx
//! status, 503 when the server is busy or stopping, 500 only if a handler
//! panicked):
//!
//! | method and path | body | answer |
//! |---|---|---|
//! | `GET /api/robots` | — | `[{name, dof, description, joint_types, manufacturer, source, default}]` |
//! | `GET /api/robots/{name}` | — | the fields of `kinema info --json`, plus `home` and `ik` |
//! | `POST /api/fk` | `{robot?, q}` | `T` (4 rows), position, rpy, quaternion, `within_limits`, `frames`, `joints` |
//! | `POST /api/ik` | `{robot?, T}` or `{robot?, position, rpy}`, optional `q3` or `psi`, `q0`, `solver`, `scene`, `margin` | every solution: `q`, `branch`, `within_limits`, residuals |
//! | `POST /api/traj` | `{robot?, kind: "ptp", from, to}` or `{kind: "lin", from, T \| position+rpy}` | `t`, `q`, `qd`, `qdd` |
//! | `POST /api/run` | `{robot?, program, dt?, start?}` | `t`, `q`, `qd`, `qdd`, `motions`, `warnings` |
//! | `POST /api/plan` | `{robot?, from, to \| pose}`, optional `scene`, `margin`, `seed`, `time_limit`, `dt`, `profile`, `speed` | the fields of `kinema plan --json` (`plan`: via points, counts) and `t`, `q`, `qd`, `qdd` |
//! | `GET /api/robots/{name}/geometry` | — | `{robot, links, visual, collision}`: shapes in link frames ([`GeometryAnswer`]) |
//! | `POST /api/scene` | `{scene}` (TOML text) | `{obstacles}` in the world frame ([`SceneAnswer`]) |
//! | `GET /api/scene` | — | the server's scene ([`App::with_scene`]): `{obstacles}` |
//! | `GET /api/cell` | — | the server's cell ([`App::with_cell`]): `{times, members}` with every sample's link poses ([`CellAnswer`]) |
//! | `GET /api/ws` (WebSocket) | messages `{robot?, q}` | one message each: the `/api/fk` answer or `{"error": …}`; at most 64 KiB a message |
//! | `POST /api/view` | `{robot?, q}`, or `{robot?, t, q}` with one `q` row per time `t` | the request with its `version`; the page shows `q` or plays the trajectory |
//! | `GET /api/view` | — | the last `POST /api/view` answer, or `{version: 0}` (the page polls it) |
//! | `POST /api/manip` | `{robot?, q}` | manipulability, translational and rotational ellipsoids |
//! | `POST /api/collide` | `{robot?, q}`, optional `scene` (TOML text), `margin` | `collision`, `pairs`, `min_distance` |
//!
//! ## Limits, and how each failure is answered
//!
//! | what | limit ([`Limits::default`]) | answer |
//! |---|---|---|
//! | request head | 16 KiB, 100 header fields | 431 (from hyper, empty body) |
//! | a head that is not HTTP/1.x, a bad `Content-Length` | — | 400 (from hyper, empty body) |
//! | time for a head, from connecting or the previous answer (so also the keep-alive idle time) | 10 s | connection closed |
//! | request body | [`MAX_BODY`] = 1 MiB | 413 JSON, `Connection: close`; from the `Content-Length` alone, unread |
//! | time for the body after the head | 10 s | 408 JSON, `Connection: close` |
//! | CPU-heavy requests (`/api/ik`, `/api/traj`, `/api/run`, `/api/plan`, `/api/collide`, `/api/scene`) computed at once, on blocking threads | number of CPUs (≥ 2); the others wait | — |
//! | time from head to answer, waiting for a slot included | 30 s | 503 JSON, `Retry-After: 1` |
//! | a `/api/run` program's running time | [`RUN_BUDGET`] = 10 s | 422 JSON naming the budget, with `budget_s` and `diagnostics` |
//! | a `/api/plan` search's time | its `time_limit` (1 s), at most [`MAX_PLAN_TIME`] = 10 s and [`RUN_BUDGET`] | 422 JSON: the planner's message |
//! | samples of `/api/traj` and `/api/run` | [`MAX_SAMPLES`] = 200 000 | 422 JSON |
//! | connections at once | 1024 | further ones wait in the listen backlog |
//! | shutting down | 2 s for requests in progress | a running program is stopped → 503 JSON |
//!
//! A stalled or slow client holds only its own connection: the page,
//! `/api/robots`, `/api/fk` and `/api/manip` are answered at once on the
//! runtime's threads whatever the other connections do. A program whose
//! client disconnects is stopped (its stop flag is raised), so it does not
//! keep a slot.
//!
//! ## Example
//!
//! ```
//! use kinema_serve::{App, Server};
//!
//! // The handler alone, without a socket:
//! let app = App::new(None)?;
//! let (status, json) = app.api("POST", "/api/fk", br#"{"robot": "puma560", "q": [0, 0, 0, 0, 0, 0]}"#);
//! assert_eq!(status, 200);
//! assert_eq!(json["T"].as_array().map(Vec::len), Some(4));
//! let (status, json) = app.api("POST", "/api/fk", br#"{"robot": "puma560", "q": [0, 0]}"#);
//! assert_eq!(status, 422);
//! assert!(json["error"].as_str().unwrap().contains("6 joints"));
//!
//! // A real server on a free port, stopped when `running` is dropped:
//! let running = Server::bind("127.0.0.1:0", None)?.spawn();
//! assert!(running.url().starts_with("http://127.0.0.1:"));
//! running.stop();
//! # Ok::<(), kinema_serve::Error>(())
//! ```
#![warn(missing_docs)]
// As in the core library: `!(x > 0.0)` is used on purpose, since unlike
// `x <= 0.0` it is also true for NaN, which is how inputs are rejected.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod api;
mod cell;
mod error;
mod request;
mod shapes;
mod view;
// The only module that needs axum, hyper and tokio: without the `server`
// feature the crate is the request handler `App`, with no sockets.
#[cfg(feature = "server")]
mod server;

pub use api::{App, Reply, MAX_BODY, MAX_PLAN_TIME, MAX_SAMPLES, RUN_BUDGET};
pub use cell::{CellAnswer, CellMemberAnswer, CellMotion};
pub use error::{Error, JsonError, Result};
#[cfg(feature = "server")]
pub use server::{Limits, Running, Server};
pub use shapes::{GeometryAnswer, MeshAnswer, SceneAnswer, ShapeAnswer};
