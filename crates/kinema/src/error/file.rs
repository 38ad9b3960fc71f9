//! [`FileError`]: a file that cannot be read, and the shared I/O error it carries.

/// A file that cannot be read (see [`Error::File`](super::Error::File)).
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FileError {
    /// A file that cannot be read.
    #[error("cannot read `{path}`: {source}")]
    Io {
        /// Path as given.
        path: String,
        /// The operating system's error.
        source: IoError,
    },
    /// A file larger than the limit for its kind (a FIFO or `/dev/zero` given
    /// by mistake, most often).
    #[error("cannot read `{path}`: the file is larger than the limit of {} for {what}", size_text(*limit))]
    FileTooLarge {
        /// Path as given.
        path: String,
        /// What the file was read as (e.g. "a robot description").
        what: String,
        /// The limit \[bytes\].
        limit: u64,
    },
}

/// An operating-system I/O error, shared so that [`Error`](super::Error) stays `Clone`;
/// two compare equal when their kind and message do.
#[derive(Debug, Clone)]
pub struct IoError(pub std::sync::Arc<std::io::Error>);

impl From<std::io::Error> for IoError {
    fn from(e: std::io::Error) -> Self {
        IoError(std::sync::Arc::new(e))
    }
}

impl PartialEq for IoError {
    fn eq(&self, other: &Self) -> bool {
        self.0.kind() == other.0.kind() && self.0.to_string() == other.0.to_string()
    }
}

impl std::fmt::Display for IoError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

impl std::error::Error for IoError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(self.0.as_ref())
    }
}

/// A size in bytes as people read it: "16 MiB" when whole, else bytes.
fn size_text(bytes: u64) -> String {
    if bytes >= 1 << 20 && bytes % (1 << 20) == 0 {
        format!("{} MiB", bytes >> 20)
    } else {
        format!("{bytes} bytes")
    }
}
