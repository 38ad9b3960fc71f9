//! Reading a file with a size limit, so that `/dev/zero` or a FIFO given by
//! mistake is refused instead of filling the memory.

use std::io::Read;
use std::path::Path;

use crate::error::{Error, FileError, Result};

/// The bytes of the file at `path`, refused when longer than `limit` bytes.
/// `what` names what the file is read as in the error (e.g. "a mesh").
pub fn read_bounded(path: &Path, what: &str, limit: u64) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    open(path)?.take(limit + 1).read_to_end(&mut bytes).map_err(io_error(path))?;
    check_size(path, what, limit, bytes.len())?;
    Ok(bytes)
}

/// The text of the file at `path` (UTF-8), refused when longer than `limit`
/// bytes; see [`read_bounded`].
pub fn read_bounded_text(path: &Path, what: &str, limit: u64) -> Result<String> {
    let mut text = String::new();
    open(path)?.take(limit + 1).read_to_string(&mut text).map_err(io_error(path))?;
    check_size(path, what, limit, text.len())?;
    Ok(text)
}

fn open(path: &Path) -> Result<std::fs::File> {
    std::fs::File::open(path).map_err(io_error(path))
}

fn io_error(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |e| Error::File(FileError::Io { path: path.display().to_string(), source: e.into() })
}

fn check_size(path: &Path, what: &str, limit: u64, len: usize) -> Result<()> {
    if len as u64 > limit {
        return Err(Error::File(FileError::FileTooLarge {
            path: path.display().to_string(),
            what: what.into(),
            limit,
        }));
    }
    Ok(())
}
