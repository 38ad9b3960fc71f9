//! The error type of the server, with the HTTP status each error maps to.

/// Everything that can go wrong in `kinema-serve`: starting the server, and
/// every kind of bad request. [`Error::status`] gives the HTTP status a
/// request error is answered with.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// The address cannot be bound (in use, not local, …).
    #[error("cannot listen on {addr}: {message}")]
    Bind {
        /// The address as given.
        addr: String,
        /// The operating system's message.
        message: String,
    },
    /// A request body that is not what the endpoint expects (not UTF-8, not
    /// JSON, missing or mistyped fields).
    #[error("{message}")]
    BadRequest {
        /// What is wrong and what was expected.
        message: String,
    },
    /// A path the server does not serve.
    #[error("no such path `{path}`; the page is at / and the API under /api/ (robots, robots/NAME, fk, ik, traj, run, manip)")]
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
    /// A robot program with errors (rendered diagnostics without colour).
    #[error("the program does not compile: {first}")]
    Program {
        /// The first error on one line (`program:line:col: error: …`).
        first: String,
        /// Every diagnostic rendered with the source line underlined.
        rendered: String,
    },
    /// A handler panicked (a bug; the server keeps running).
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
            Error::BadRequest { .. } => 400,
            Error::NotFound { .. } => 404,
            Error::UnknownRobot { in_path: true, .. } => 404,
            Error::UnknownRobot { in_path: false, .. } => 422,
            Error::MethodNotAllowed { .. } => 405,
            Error::TooLarge { .. } => 413,
            Error::Unprocessable { .. } | Error::Program { .. } => 422,
            Error::Bind { .. } | Error::Internal { .. } => 500,
        }
    }
}

impl From<kinema::Error> for Error {
    fn from(e: kinema::Error) -> Self {
        Error::Unprocessable { message: e.to_string() }
    }
}

/// Result alias of the server.
pub type Result<T, E = Error> = std::result::Result<T, E>;
