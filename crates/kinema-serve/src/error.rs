//! The error type of the server, with the HTTP status each error maps to.

/// Everything that can go wrong in `kinema-serve`: starting the server, and
/// every kind of bad request. [`Error::status`] gives the HTTP status a
/// request error is answered with.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// The address cannot be bound (in use, not local, …).
    #[error("cannot listen on {addr}: {source}")]
    Bind {
        /// The address as given.
        addr: String,
        /// The operating system's error.
        source: kinema::IoError,
    },
    /// The server's runtime cannot be started (no threads, no I/O driver).
    #[error("cannot start the runtime: {source}")]
    Runtime {
        /// The operating system's error.
        source: kinema::IoError,
    },
    /// A request body that is not UTF-8 text.
    #[error("{endpoint}: the body is not UTF-8 text (byte {}); expected JSON {shape}", source.valid_up_to())]
    NotUtf8 {
        /// The endpoint (e.g. `/api/fk`).
        endpoint: String,
        /// The JSON the endpoint expects.
        shape: String,
        /// Where the text stops being UTF-8.
        source: std::str::Utf8Error,
    },
    /// A request body that is not JSON of the endpoint's shape (malformed,
    /// missing or mistyped fields).
    #[error("{endpoint}: {source}; expected JSON {shape}")]
    Json {
        /// The endpoint (e.g. `/api/fk`).
        endpoint: String,
        /// The JSON the endpoint expects.
        shape: String,
        /// The parser's error, with its line and column.
        source: JsonError,
    },
    /// A request body that broke off while being read (the connection
    /// failed); the transport's error is kept inside the `std::io::Error`.
    #[error("the body is broken: {source}")]
    BodyBroken {
        /// The transport's error.
        source: kinema::IoError,
    },
    /// A request body whose values are not what the endpoint accepts (an
    /// unknown solver or profile, a field combination it does not take).
    #[error("{message}")]
    BadRequest {
        /// What is wrong and what was expected.
        message: String,
    },
    /// A path the server does not serve.
    #[error("no such path `{path}`; the page is at / and the API under /api/ (robots, robots/NAME, fk, ik, traj, run, plan, manip, collide, scene, cell)")]
    NotFound {
        /// The path asked for.
        path: String,
    },
    /// A robot name the server does not know.
    #[error("unknown robot `{name}`; the robots are: {known}")]
    UnknownRobot {
        /// What was asked for.
        name: String,
        /// Comma-separated list of the robots served.
        known: String,
        /// Whether the name came from the path (404) rather than a body (422).
        in_path: bool,
    },
    /// A method the path does not accept.
    #[error("method {method} is not allowed on {path}; use {allowed}")]
    MethodNotAllowed {
        /// The method used.
        method: String,
        /// The path.
        path: String,
        /// The methods the path accepts.
        allowed: &'static str,
    },
    /// A body larger than [`crate::MAX_BODY`].
    #[error("the request body has {size} bytes or more; at most {limit} bytes are accepted")]
    TooLarge {
        /// Size announced or read so far \[bytes\].
        size: u64,
        /// The limit \[bytes\].
        limit: usize,
    },
    /// A well-formed request whose values the library rejects (wrong joint
    /// count, non-finite values, an unreachable target, a limit violation, a
    /// trajectory with too many samples, …).
    #[error("{message}")]
    Unprocessable {
        /// What is wrong, in the library's words.
        message: String,
    },
    /// The core library refused the request (a bad joint vector, an
    /// unreachable target, a limit violation, …), with its typed error.
    #[error(transparent)]
    Core(#[from] kinema::Error),
    /// A robot program with errors (rendered diagnostics without colour).
    #[error("the program does not compile: {first}")]
    Program {
        /// The first error on one line (`program:line:col: error: …`).
        first: String,
        /// Every diagnostic rendered with the source line underlined.
        rendered: String,
    },
    /// A `/api/run` program stopped by its time budget ([`crate::RUN_BUDGET`]
    /// by default): it ran longer than that without finishing.
    #[error("the program did not finish within its time budget of {} s and was stopped: {first}", budget.as_secs_f64())]
    RunBudget {
        /// The budget.
        budget: std::time::Duration,
        /// Where it stopped, on one line (`program:line:col: error: stopped here: …`).
        first: String,
        /// The diagnostics rendered with the source line underlined.
        rendered: String,
    },
    /// A request body that did not arrive in time (408; the connection is closed).
    #[error("the request body did not arrive within {} s", timeout.as_secs_f64())]
    BodyTimeout {
        /// The time allowed for the body, from the end of the request head.
        timeout: std::time::Duration,
    },
    /// No answer within the request timeout: the request waited too long for
    /// one of the slots of the CPU-heavy endpoints, or took too long (503,
    /// with `Retry-After`).
    #[error("no answer within {} s: the server is busy with other CPU-heavy requests (ik, traj, run, plan) or this one takes too long; try again", timeout.as_secs_f64())]
    Busy {
        /// The request timeout.
        timeout: std::time::Duration,
    },
    /// The server is shutting down; a program that was running was stopped (503).
    #[error("the server is shutting down; the request was not finished")]
    ShuttingDown,
    /// A handler panicked or its answer could not be written as JSON (a
    /// bug; the server keeps running).
    #[error("internal error while handling the request: {message}")]
    Internal {
        /// The panic message.
        message: String,
    },
}

impl Error {
    /// The HTTP status a request error is answered with (500 for [`Error::Bind`],
    /// which never answers a request).
    pub fn status(&self) -> u16 {
        match self {
            Error::BadRequest { .. } | Error::NotUtf8 { .. } | Error::Json { .. } | Error::BodyBroken { .. } => 400,
            Error::NotFound { .. } => 404,
            Error::UnknownRobot { in_path: true, .. } => 404,
            Error::UnknownRobot { in_path: false, .. } => 422,
            Error::MethodNotAllowed { .. } => 405,
            Error::TooLarge { .. } => 413,
            Error::BodyTimeout { .. } => 408,
            Error::Unprocessable { .. } | Error::Core(_) | Error::Program { .. } | Error::RunBudget { .. } => 422,
            Error::Busy { .. } | Error::ShuttingDown => 503,
            Error::Bind { .. } | Error::Runtime { .. } | Error::Internal { .. } => 500,
        }
    }
}

/// A JSON parse error, shared so that [`Error`] stays `Clone`; two compare
/// equal when their category, position and message do.
#[derive(Debug, Clone)]
pub struct JsonError(pub std::sync::Arc<serde_json::Error>);

impl From<serde_json::Error> for JsonError {
    fn from(e: serde_json::Error) -> Self {
        JsonError(std::sync::Arc::new(e))
    }
}

impl PartialEq for JsonError {
    fn eq(&self, other: &Self) -> bool {
        let (a, b) = (&self.0, &other.0);
        a.classify() == b.classify()
            && a.line() == b.line()
            && a.column() == b.column()
            && a.to_string() == b.to_string()
    }
}

impl std::fmt::Display for JsonError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

impl std::error::Error for JsonError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(self.0.as_ref())
    }
}

/// Result alias of the server.
pub type Result<T, E = Error> = std::result::Result<T, E>;
