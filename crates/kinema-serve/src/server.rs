//! The HTTP side: axum's router on hyper's HTTP/1.1 connections, driven by a
//! tokio runtime of the server's own; the limits, timeouts, the concurrency
//! limit of the CPU-heavy endpoints, graceful shutdown and the last-resort
//! panic guard around [`App::handle`].
//!
//! How it works, and what it refuses (the figures are [`Limits::default`]):
//!
//! * Every connection is a tokio task; hyper parses requests, keeps
//!   connections alive (pipelined requests too) and answers `Connection:
//!   close` when it closes one. A stalled client holds only its own task, so
//!   it cannot delay another client.
//! * A request head must arrive within [`Limits::head_timeout`] (10 s),
//!   counted from the opening of the connection or from the end of the
//!   previous answer on a kept-alive one (so it is also the idle timeout);
//!   then the connection is closed without an answer. Heads over 16 KiB or
//!   with more than 100 header fields get 431, bytes that are not HTTP/1.x
//!   400, both from hyper with an empty body.
//! * A body (by `Content-Length` or chunked) must arrive within
//!   [`Limits::body_timeout`] (10 s) after the head → 408. A body over
//!   [`MAX_BODY`] gets 413, from the `Content-Length` alone when there is one
//!   (nothing is read; `Expect: 100-continue` is not answered). Both close
//!   the connection (`Connection: close`); after a 413 the rest of the body is
//!   read and discarded for a moment (at most 1 MiB or 1 s), so that the
//!   client receives the answer rather than a reset.
//! * The page, `GET /api/robots…`, `/api/fk` and `/api/manip` are computed at
//!   once on the runtime's threads (microseconds each). The CPU-heavy
//!   endpoints, `/api/ik`, `/api/traj`, `/api/run`, `/api/plan`,
//!   `/api/collide` and `/api/scene`, run on tokio's
//!   blocking threads, at most [`Limits::heavy_concurrency`] at a time; the
//!   others wait for a slot. A request has [`Limits::request_timeout`] (30 s)
//!   from its head to its answer, waiting included → 503 with
//!   `Retry-After: 1`.
//! * A `/api/run` program has [`Limits::run_budget`] ([`RUN_BUDGET`], 10 s)
//!   from its start → 422 ([`Error::RunBudget`]). Its stop flag is raised when
//!   its connection breaks (a reset), when the request times out and when the
//!   server shuts down (→ 503). A client that closes its sending side after
//!   the request (a FIN) is answered: hyper runs with `half_close`, because
//!   that FIN cannot be told from one of a client that left; such a program
//!   then runs within its budget, as for a client that stays. A
//!   `/api/plan` search is stopped the same way (the budget → 422).
//! * [`App::handle`] runs inside `catch_unwind`: a panic is a 500 JSON answer
//!   and the server goes on.
//! * Stopping ([`Running::stop`], dropping [`Running`], or the future given to
//!   [`Server::run_until`] completing): the listener is closed, idle
//!   connections are closed, running programs are stopped, requests in
//!   progress get [`Limits::shutdown_grace`] (2 s) to finish, then every
//!   connection is dropped.

use std::future::Future;
use std::net::{SocketAddr, TcpListener, ToSocketAddrs};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Duration;

use axum::body::Body;
use axum::extract::ws::rejection::WebSocketUpgradeRejection;
use axum::extract::ws::{Message, WebSocket, WebSocketUpgrade};
use axum::extract::{Request, State};
use axum::http::{header, HeaderMap, HeaderValue, StatusCode};
use axum::response::Response;
use axum::Router;
use hyper_util::rt::{TokioIo, TokioTimer};
use hyper_util::service::TowerToHyperService;
use kinema::Robot;
use kinema_geometry::RobotGeometry;
use kinema_lang::Stop;
use tokio::sync::{watch, Semaphore};
use tokio::task::JoinSet;

use crate::api::{App, Reply, MAX_BODY, RUN_BUDGET};
use crate::error::{Error, Result};

/// Largest request head (request line and header fields) \[bytes\].
const MAX_HEAD: usize = 16 * 1024;
/// After a 413: how long, and how much, of the refused body is discarded.
const LINGER_TIME: Duration = Duration::from_secs(1);
const LINGER_BYTES: usize = MAX_BODY;

/// The server's limits; [`Limits::default`] gives the values in the module
/// documentation. [`Server::with_limits`] clamps durations to [1 ms, 1 h]
/// and counts to at least 1.
#[derive(Debug, Clone, PartialEq)]
pub struct Limits {
    /// Time for a request head to arrive, from the opening of the connection
    /// or the end of the previous answer (10 s); the connection is closed.
    pub head_timeout: Duration,
    /// Time for a request body to arrive once its head has (10 s) → 408.
    pub body_timeout: Duration,
    /// Time from a request's head to its answer, waiting for a slot of the
    /// CPU-heavy endpoints included (30 s) → 503.
    pub request_timeout: Duration,
    /// Time a `/api/run` program or a `/api/plan` search may run ([`RUN_BUDGET`]) → 422.
    pub run_budget: Duration,
    /// Requests to the CPU-heavy endpoints (`/api/ik`, `/api/traj`,
    /// `/api/run`, `/api/plan`, `/api/collide`, `/api/scene`) computed at once (the number
    /// of CPUs, at least 2).
    pub heavy_concurrency: usize,
    /// Connections served at once (1024), open WebSockets included; further
    /// ones wait in the listen backlog until one closes (a WebSocket upgrade
    /// beyond it → 503).
    pub max_connections: usize,
    /// On stop: time requests in progress get to finish (2 s).
    pub shutdown_grace: Duration,
}

impl Default for Limits {
    fn default() -> Self {
        let cpus = std::thread::available_parallelism().map_or(2, usize::from);
        Limits {
            head_timeout: Duration::from_secs(10),
            body_timeout: Duration::from_secs(10),
            request_timeout: Duration::from_secs(30),
            run_budget: RUN_BUDGET,
            heavy_concurrency: cpus.max(2),
            max_connections: 1024,
            shutdown_grace: Duration::from_secs(2),
        }
    }
}

impl Limits {
    fn clamped(mut self) -> Limits {
        let clamp = |d: Duration| d.clamp(Duration::from_millis(1), Duration::from_secs(3600));
        self.head_timeout = clamp(self.head_timeout);
        self.body_timeout = clamp(self.body_timeout);
        self.request_timeout = clamp(self.request_timeout);
        self.run_budget = clamp(self.run_budget);
        self.shutdown_grace = clamp(self.shutdown_grace);
        self.heavy_concurrency = self.heavy_concurrency.clamp(1, Semaphore::MAX_PERMITS);
        self.max_connections = self.max_connections.clamp(1, Semaphore::MAX_PERMITS);
        self
    }
}

/// A bound, not yet running server.
pub struct Server {
    listener: TcpListener,
    runtime: tokio::runtime::Runtime,
    app: Arc<App>,
    addr: SocketAddr,
    limits: Limits,
}

impl Server {
    /// Listens on `addr` (port 0 picks a free port) and prepares the robots:
    /// the built-in ones and `default_robot` (shown first by the page; it may
    /// come from a file). Nothing is served until [`Server::run`] or
    /// [`Server::spawn`].
    pub fn bind(addr: impl ToSocketAddrs, default_robot: Option<Robot>) -> Result<Server> {
        let addrs: Vec<SocketAddr> = addr
            .to_socket_addrs()
            .map_err(|e| Error::Bind { addr: "the given address".into(), source: e.into() })?
            .collect();
        let listed = || addrs.iter().map(ToString::to_string).collect::<Vec<_>>().join(", ");
        let bind_error = |e: std::io::Error| Error::Bind { addr: listed(), source: e.into() };
        let listener = TcpListener::bind(&addrs[..]).map_err(bind_error)?;
        let local = listener.local_addr().map_err(bind_error)?;
        listener.set_nonblocking(true).map_err(bind_error)?;
        let cpus = std::thread::available_parallelism().map_or(2, usize::from);
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(cpus.max(2))
            .thread_name("kinema-serve")
            .enable_io()
            .enable_time()
            .build()
            .map_err(|e| Error::Runtime { source: e.into() })?;
        Ok(Server {
            listener,
            runtime,
            app: Arc::new(App::new(default_robot)?),
            addr: local,
            limits: Limits::default(),
        })
    }

    /// Gives the default robot's shapes for the page to draw (see
    /// [`App::with_link_shapes`]).
    pub fn with_link_shapes(self, visual: Option<RobotGeometry>, collision: Option<RobotGeometry>) -> Result<Server> {
        let app = Arc::unwrap_or_clone(self.app).with_link_shapes(visual, collision)?;
        Ok(Server { app: Arc::new(app), ..self })
    }

    /// The scene the page draws and collision checks use (see
    /// [`App::with_scene`]).
    pub fn with_scene(self, scene: &kinema_geometry::Scene) -> Result<Server> {
        let app = Arc::unwrap_or_clone(self.app).with_scene(scene)?;
        Ok(Server { app: Arc::new(app), ..self })
    }

    /// The cell the page plays (see [`App::with_cell`]).
    pub fn with_cell(self, times: &[f64], members: &[crate::CellMotion]) -> Result<Server> {
        let app = Arc::unwrap_or_clone(self.app).with_cell(times, members)?;
        Ok(Server { app: Arc::new(app), ..self })
    }

    /// Sets the server's limits (see [`Limits`]).
    pub fn with_limits(mut self, limits: Limits) -> Server {
        self.limits = limits.clamped();
        self
    }

    /// Sets the time a request's head, and then its body, have to arrive
    /// ([`Limits::head_timeout`] and [`Limits::body_timeout`], 10 s each by
    /// default).
    pub fn with_read_timeout(self, timeout: Duration) -> Server {
        let limits = Limits { head_timeout: timeout, body_timeout: timeout, ..self.limits.clone() };
        self.with_limits(limits)
    }

    /// The limits in force.
    pub fn limits(&self) -> &Limits {
        &self.limits
    }

    /// The address actually bound.
    pub fn local_addr(&self) -> SocketAddr {
        self.addr
    }

    /// `http://HOST:PORT/`, the page's address.
    pub fn url(&self) -> String {
        format!("http://{}/", self.addr)
    }

    /// The request handler.
    pub fn app(&self) -> &App {
        &self.app
    }

    /// Serves requests, blocking the calling thread, until the process ends.
    pub fn run(self) {
        self.run_until(std::future::pending());
    }

    /// Serves requests, blocking the calling thread, until `shutdown`
    /// completes; then shuts down gracefully (see the module documentation)
    /// and returns.
    pub fn run_until(self, shutdown: impl Future<Output = ()>) {
        let Server { listener, runtime, app, limits, .. } = self;
        let grace = limits.shutdown_grace;
        runtime.block_on(serve(listener, app, limits, shutdown));
        runtime.shutdown_timeout(grace);
    }

    /// [`Server::run_until`] Ctrl-C (SIGINT) or, on Unix, SIGTERM.
    pub fn run_until_signal(self) {
        self.run_until(signal());
    }

    /// Serves requests on background threads; the server stops when the
    /// returned [`Running`] is stopped or dropped.
    pub fn spawn(self) -> Running {
        let url = self.url();
        let Server { listener, runtime, app, addr, limits } = self;
        let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
        let (done_tx, done) = std::sync::mpsc::channel();
        let grace = limits.shutdown_grace;
        runtime.spawn(async move {
            serve(listener, app, limits, async {
                let _ = stopped.await;
            })
            .await;
            let _ = done_tx.send(());
        });
        Running { url, addr, grace, stop: Some(stop), done, runtime: Some(runtime) }
    }
}

/// Ctrl-C, or SIGTERM on Unix (never, if the handlers cannot be installed).
async fn signal() {
    let ctrl_c = async {
        if tokio::signal::ctrl_c().await.is_err() {
            std::future::pending::<()>().await;
        }
    };
    #[cfg(unix)]
    let term = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut s) => {
                s.recv().await;
            }
            Err(_) => std::future::pending::<()>().await,
        }
    };
    #[cfg(not(unix))]
    let term = std::future::pending::<()>();
    tokio::select! {
        () = ctrl_c => {}
        () = term => {}
    }
}

/// A server running on background threads.
pub struct Running {
    url: String,
    addr: SocketAddr,
    grace: Duration,
    stop: Option<tokio::sync::oneshot::Sender<()>>,
    done: std::sync::mpsc::Receiver<()>,
    runtime: Option<tokio::runtime::Runtime>,
}

impl Running {
    /// `http://HOST:PORT/`.
    pub fn url(&self) -> &str {
        &self.url
    }

    /// The address bound.
    pub fn local_addr(&self) -> SocketAddr {
        self.addr
    }

    /// Shuts down gracefully (see the module documentation): closes the
    /// listener, lets requests in progress finish within the grace time, and
    /// waits for that.
    pub fn stop(mut self) {
        self.shutdown();
    }

    fn shutdown(&mut self) {
        let Some(stop) = self.stop.take() else { return };
        let _ = stop.send(());
        let _ = self.done.recv_timeout(self.grace + Duration::from_secs(1));
        if let Some(runtime) = self.runtime.take() {
            // Blocking there is not allowed inside another runtime.
            if tokio::runtime::Handle::try_current().is_ok() {
                runtime.shutdown_background();
            } else {
                runtime.shutdown_timeout(Duration::from_millis(500));
            }
        }
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        self.shutdown();
    }
}

/// What every request handler shares.
struct Shared {
    app: Arc<App>,
    limits: Limits,
    /// Slots of the CPU-heavy endpoints.
    heavy: Arc<Semaphore>,
    /// Connection slots ([`Limits::max_connections`]): an upgraded WebSocket
    /// keeps one of its own, since its HTTP connection ends at the upgrade.
    connections: Arc<Semaphore>,
    /// Becomes true when the server shuts down.
    shutdown: watch::Receiver<bool>,
}

/// Accepts and serves connections until `shutdown` completes, then shuts
/// down gracefully.
async fn serve(listener: TcpListener, app: Arc<App>, limits: Limits, shutdown: impl Future<Output = ()>) {
    let Ok(listener) = tokio::net::TcpListener::from_std(listener) else { return };
    let (shutting, shutdown_rx) = watch::channel(false);
    let grace = limits.shutdown_grace;
    let connections = Arc::new(Semaphore::new(limits.max_connections));
    let mut http = hyper::server::conn::http1::Builder::new();
    http.timer(TokioTimer::new())
        .header_read_timeout(limits.head_timeout)
        .max_header_size(MAX_HEAD)
        .title_case_headers(true)
        // A client that shuts its sending side after the request (`nc -N`,
        // `shutdown(SHUT_WR)`) still gets its answer.
        .half_close(true);
    let shared = Arc::new(Shared {
        heavy: Arc::new(Semaphore::new(limits.heavy_concurrency)),
        connections: Arc::clone(&connections),
        app,
        limits,
        shutdown: shutdown_rx.clone(),
    });
    let router = Router::new()
        .route("/api/ws", axum::routing::get(pose_socket))
        .fallback(handle)
        .with_state(Arc::clone(&shared));
    let mut tasks = JoinSet::new();
    let mut shutdown = std::pin::pin!(shutdown);
    loop {
        while tasks.try_join_next().is_some() {}
        let slot = tokio::select! {
            () = &mut shutdown => break,
            slot = Arc::clone(&connections).acquire_owned() => slot,
        };
        let Ok(slot) = slot else { break };
        let accepted = tokio::select! {
            () = &mut shutdown => break,
            accepted = listener.accept() => accepted,
        };
        let stream = match accepted {
            Ok((stream, _)) => stream,
            // E.g. out of file descriptors: wait a little, go on.
            Err(_) => {
                tokio::time::sleep(Duration::from_millis(20)).await;
                continue;
            }
        };
        // Answers are written whole; Nagle's algorithm would only delay them.
        let _ = stream.set_nodelay(true);
        // Requests of this connection between their head and their answer.
        let busy = Arc::new(AtomicUsize::new(0));
        let service = {
            let (tower, busy) = (TowerToHyperService::new(router.clone()), Arc::clone(&busy));
            hyper::service::service_fn(move |request| {
                let counted = Counted::new(&busy);
                let answer = hyper::service::Service::call(&tower, request);
                async move {
                    let answer = answer.await;
                    drop(counted);
                    answer
                }
            })
        };
        let connection = http.serve_connection(TokioIo::new(stream), service).with_upgrades();
        let mut stopping = shutdown_rx.clone();
        tasks.spawn(async move {
            let _slot = slot;
            let mut connection = std::pin::pin!(connection);
            tokio::select! {
                _ = connection.as_mut() => {}
                () = stopped(&mut stopping) => {
                    // Closes an idle connection; one with a request in
                    // progress is closed after its answer. A connection in the
                    // middle of a head or body is not waited for.
                    connection.as_mut().graceful_shutdown();
                    let quiet = async {
                        while busy.load(Ordering::SeqCst) > 0 {
                            tokio::time::sleep(Duration::from_millis(20)).await;
                        }
                        // Time to write an answer just made.
                        tokio::time::sleep(Duration::from_millis(50)).await;
                    };
                    tokio::select! {
                        _ = connection.as_mut() => {}
                        () = quiet => {}
                    }
                }
            }
        });
    }
    drop(listener);
    let _ = shutting.send(true);
    let drained = tokio::time::timeout(grace, async { while tasks.join_next().await.is_some() {} }).await;
    if drained.is_err() {
        tasks.shutdown().await;
    }
}

/// `GET /api/ws`: a WebSocket on which the page sends `{"robot", "q"}` as
/// its sliders move and gets each configuration's FK answer (the link
/// poses), or `{"error": …}`; one answer per message, in order.
async fn pose_socket(
    State(shared): State<Arc<Shared>>,
    upgrade: std::result::Result<WebSocketUpgrade, WebSocketUpgradeRejection>,
) -> Response {
    match upgrade {
        Ok(upgrade) => {
            let Ok(slot) = Arc::clone(&shared.connections).try_acquire_owned() else {
                let message = "/api/ws: the server holds its most connections; try again later";
                return response(Reply::json(503, &serde_json::json!({ "error": message })), false);
            };
            upgrade.max_message_size(MAX_WS_MESSAGE).max_frame_size(MAX_WS_MESSAGE).on_upgrade(
                move |socket| async move {
                    let _slot = slot;
                    answer_poses(socket, shared).await
                },
            )
        }
        Err(e) => {
            let message = format!("/api/ws is a WebSocket (GET with `Upgrade: websocket`): {e}");
            response(Reply::json(e.status().as_u16(), &serde_json::json!({ "error": message })), false)
        }
    }
}

/// Largest message on the pose WebSocket \[bytes\]; a larger one closes it.
const MAX_WS_MESSAGE: usize = 64 * 1024;
/// A pose WebSocket with no message for this long is closed.
const WS_IDLE: Duration = Duration::from_secs(600);

async fn answer_poses(mut socket: WebSocket, shared: Arc<Shared>) {
    let mut stopping = shared.shutdown.clone();
    loop {
        let received = tokio::select! {
            received = tokio::time::timeout(WS_IDLE, socket.recv()) => received,
            () = stopped(&mut stopping) => break,
        };
        let answer = match received {
            Ok(Some(Ok(Message::Text(text)))) => {
                let app = Arc::clone(&shared.app);
                let reply = guarded(move || Reply::json(200, &app.pose_update(text.as_bytes())));
                String::from_utf8(reply.body).unwrap_or_default()
            }
            Ok(Some(Ok(Message::Binary(_)))) => {
                serde_json::json!({"error": "/api/ws: send JSON text {\"robot\": NAME, \"q\": [...]}"}).to_string()
            }
            Ok(Some(Ok(Message::Ping(_) | Message::Pong(_)))) => continue,
            // Closed, broken, too large, or idle.
            _ => break,
        };
        if socket.send(Message::Text(answer.into())).await.is_err() {
            break;
        }
    }
    let _ = socket.send(Message::Close(None)).await;
}

/// Whether a request goes to the CPU-heavy endpoints.
fn heavy(method: &str, path: &str) -> bool {
    let path = path.split(['?', '#']).next().unwrap_or("");
    let path = path.strip_suffix('/').unwrap_or(path);
    method == "POST"
        && matches!(path, "/api/ik" | "/api/traj" | "/api/run" | "/api/plan" | "/api/collide" | "/api/scene")
}

/// The one handler: the body read within its limits, then [`App::handle`].
async fn handle(State(shared): State<Arc<Shared>>, request: Request) -> Response {
    let head_request = request.method() == axum::http::Method::HEAD;
    let timeout = shared.limits.request_timeout;
    let reply = match tokio::time::timeout(timeout, answer(&shared, request)).await {
        Ok(reply) => reply,
        Err(_) => {
            let mut reply = Reply::error(&Error::Busy { timeout });
            reply.headers.push(("Retry-After", "1".into()));
            reply
        }
    };
    response(reply, head_request)
}

async fn answer(shared: &Shared, request: Request) -> Reply {
    let (parts, mut body) = request.into_parts();
    let method = parts.method.as_str().to_owned();
    let path = parts.uri.path_and_query().map_or("/", |p| p.as_str()).to_owned();
    let bytes = match read_body(&parts.headers, &mut body, shared.limits.body_timeout).await {
        Ok(bytes) => bytes,
        Err(reply) => {
            if reply.status == 413 && !expects_continue(&parts.headers) {
                discard(body);
            }
            return reply;
        }
    };
    let app = Arc::clone(&shared.app);
    if !heavy(&method, &path) {
        let stop = Stop::after(shared.limits.run_budget);
        return guarded(|| app.handle_until(&method, &path, &bytes, &stop));
    }
    let Ok(slot) = Arc::clone(&shared.heavy).acquire_owned().await else {
        return Reply::error(&Error::ShuttingDown);
    };
    // Raised when the answer is no longer wanted: this future is dropped
    // (the client left, or the request timed out) or the server stops.
    let flag = Arc::new(AtomicBool::new(false));
    let _raise = Raise(Arc::clone(&flag));
    let budget = shared.limits.run_budget;
    let stop_flag = Arc::clone(&flag);
    let mut task = tokio::task::spawn_blocking(move || {
        let _slot = slot;
        let stop = Stop::after(budget).with_flag(stop_flag);
        guarded(|| app.handle_until(&method, &path, &bytes, &stop))
    });
    let mut stopping = shared.shutdown.clone();
    let joined = tokio::select! {
        joined = &mut task => joined,
        () = stopped(&mut stopping) => {
            flag.store(true, Ordering::Relaxed);
            task.await
        }
    };
    joined.unwrap_or_else(|e| Reply::error(&Error::Internal { message: format!("the handler did not finish: {e}") }))
}

/// Returns once the server shuts down.
async fn stopped(shutdown: &mut watch::Receiver<bool>) {
    // An error means the sender is gone: the server has stopped too.
    let _ = shutdown.wait_for(|s| *s).await;
}

/// Counts a request in progress while it lives.
struct Counted(Arc<AtomicUsize>);

impl Counted {
    fn new(count: &Arc<AtomicUsize>) -> Counted {
        count.fetch_add(1, Ordering::SeqCst);
        Counted(Arc::clone(count))
    }
}

impl Drop for Counted {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Sets its flag when dropped.
struct Raise(Arc<AtomicBool>);

impl Drop for Raise {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
    }
}

fn expects_continue(headers: &HeaderMap) -> bool {
    headers.get(header::EXPECT).is_some_and(|v| v.as_bytes().eq_ignore_ascii_case(b"100-continue"))
}

/// Reads a body of at most [`MAX_BODY`] bytes within `timeout`; the error
/// answer otherwise (413 at once when the `Content-Length` is too large).
async fn read_body(headers: &HeaderMap, body: &mut Body, timeout: Duration) -> Result<Vec<u8>, Reply> {
    use http_body_util::BodyExt;
    let closing = |e: &Error| {
        let mut reply = Reply::error(e);
        reply.headers.push(("Connection", "close".into()));
        reply
    };
    // hyper has checked that a Content-Length is a valid, single number.
    let announced = headers.get(header::CONTENT_LENGTH).and_then(|v| v.to_str().ok()?.parse::<u64>().ok());
    if let Some(size) = announced.filter(|&n| n > MAX_BODY as u64) {
        return Err(closing(&Error::TooLarge { size, limit: MAX_BODY }));
    }
    let mut bytes = Vec::with_capacity(announced.map_or(0, |n| n as usize));
    let read = async {
        while let Some(frame) = body.frame().await {
            let frame = frame.map_err(|e| closing(&Error::BodyBroken { source: std::io::Error::other(e).into() }))?;
            if let Ok(data) = frame.into_data() {
                if bytes.len() + data.len() > MAX_BODY {
                    let size = (bytes.len() + data.len()) as u64;
                    return Err(closing(&Error::TooLarge { size, limit: MAX_BODY }));
                }
                bytes.extend_from_slice(&data);
            }
        }
        Ok(())
    };
    match tokio::time::timeout(timeout, read).await {
        Ok(Ok(())) => Ok(bytes),
        Ok(Err(reply)) => Err(reply),
        Err(_) => Err(closing(&Error::BodyTimeout { timeout })),
    }
}

/// Reads and drops what is left of a refused body, for a moment, so that
/// closing the connection with unread input does not reset it before the
/// client has read the answer.
fn discard(mut body: Body) {
    use http_body_util::BodyExt;
    tokio::spawn(async move {
        let drain = async {
            let mut seen = 0;
            while let Some(Ok(frame)) = body.frame().await {
                seen += frame.data_ref().map_or(0, |d| d.len());
                if seen > LINGER_BYTES {
                    break;
                }
            }
        };
        let _ = tokio::time::timeout(LINGER_TIME, drain).await;
    });
}

/// The HTTP answer for `reply` (without its body for `HEAD`).
fn response(reply: Reply, head_request: bool) -> Response {
    let status = StatusCode::from_u16(reply.status).unwrap_or(StatusCode::INTERNAL_SERVER_ERROR);
    let length = reply.body.len();
    let body = if head_request { Body::empty() } else { Body::from(reply.body) };
    let mut response = Response::new(body);
    *response.status_mut() = status;
    let headers = response.headers_mut();
    if let Ok(v) = HeaderValue::from_str(reply.content_type) {
        headers.insert(header::CONTENT_TYPE, v);
    }
    headers.insert(header::CONTENT_LENGTH, HeaderValue::from(length));
    headers.insert(header::X_CONTENT_TYPE_OPTIONS, HeaderValue::from_static("nosniff"));
    for (name, value) in reply.headers {
        if let (Ok(name), Ok(value)) = (header::HeaderName::try_from(name), HeaderValue::try_from(value)) {
            headers.append(name, value);
        }
    }
    response
}

/// `handle` (one request's [`App::handle`]) with a panic turned into a 500 JSON answer.
fn guarded(handle: impl FnOnce() -> Reply) -> Reply {
    catch_unwind(AssertUnwindSafe(handle)).unwrap_or_else(|payload| {
        let message = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a handler panicked".into());
        Reply::error(&Error::Internal { message })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panicking_handler_gives_500_with_a_json_error() {
        let reply = guarded(|| panic!("boom at {}", 42));
        assert_eq!(reply.status, 500);
        let v: serde_json::Value = serde_json::from_slice(&reply.body).unwrap();
        assert!(v["error"].as_str().unwrap().contains("boom at 42"));
        let reply = guarded(|| Reply::json(200, &serde_json::json!({"ok": true})));
        assert_eq!(reply.status, 200);
    }

    #[test]
    fn heavy_endpoints_are_told_apart() {
        assert!(heavy("POST", "/api/run") && heavy("POST", "/api/ik/?x=1") && heavy("POST", "/api/traj"));
        assert!(heavy("POST", "/api/collide") && heavy("POST", "/api/scene") && heavy("POST", "/api/plan"));
        assert!(!heavy("GET", "/api/run") && !heavy("POST", "/api/fk") && !heavy("GET", "/api/robots"));
    }

    #[test]
    fn replies_become_responses() {
        let mut reply = Reply::json(405, &serde_json::json!({"error": "no"}));
        reply.headers.push(("Allow", "GET, HEAD".into()));
        reply.headers.push(("Bad Name", "x".into()));
        reply.headers.push(("X-Bad-Value", "a\r\nb".into()));
        let r = response(reply.clone(), false);
        assert_eq!(r.status(), 405);
        assert_eq!(r.headers()["allow"], "GET, HEAD");
        assert_eq!(r.headers()["content-length"], reply.body.len().to_string().as_str());
        assert!(r.headers().get("bad name").is_none() && r.headers().get("x-bad-value").is_none());
        reply.status = 42;
        assert_eq!(response(reply, true).status(), 500);
        let limits = Limits { heavy_concurrency: 0, head_timeout: Duration::ZERO, ..Limits::default() }.clamped();
        assert_eq!((limits.heavy_concurrency, limits.head_timeout), (1, Duration::from_millis(1)));
    }
}
