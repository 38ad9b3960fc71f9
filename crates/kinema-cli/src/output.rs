//! Writing an output file: every command that writes one goes through
//! [`write_atomically`].
//!
//! - `-` is standard output.
//! - A name of one of this process's descriptors (`/dev/stdout`,
//!   `/dev/stderr`, `/dev/fd/N`, `/proc/self/fd/N`, or a link to one) is
//!   written through a copy of that descriptor: at its offset and with its
//!   flags, so `>> log` appends and a pipe receives the data.
//! - A path that exists and is not a regular file (`/dev/null`, a FIFO, a
//!   terminal) is written in place: no temporary file, no rename, so a device
//!   node is never replaced by a file.
//! - A symbolic link is followed to its final target, which is replaced; the
//!   link stays.
//! - Anything else (a regular file, or a new one) is written to a temporary
//!   file in the target's folder (an unpredictable name, created exclusively,
//!   never following a link) that is flushed, synced and renamed over the
//!   target only when everything succeeded. On an error the temporary file is
//!   removed and the target is left as it was; on Ctrl-C, SIGTERM or SIGHUP
//!   before the rename it is removed too (see [`crate::interrupt`]), and
//!   once the rename has happened the command finishes with success.
//!
//! Two runs writing the same output each write their own temporary file; the
//! last rename wins, and the file then holds the complete output of that run.

use std::fs::{File, OpenOptions, Permissions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

use crate::interrupt::{interrupted, TempFiles, EXIT_INTERRUPTED};
use crate::Exit;

/// Whether `path` names standard output.
pub(crate) fn is_stdout(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// Where a command writes: a buffered file or standard output. Remembers a
/// failed write so that the error can name the output.
pub(crate) struct Output {
    inner: BufWriter<Sink>,
    failed: bool,
}

enum Sink {
    File(File),
    Stdout(io::StdoutLock<'static>),
}

impl Write for Sink {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match self {
            Sink::File(f) => f.write(buf),
            Sink::Stdout(s) => s.write(buf),
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        match self {
            Sink::File(f) => f.flush(),
            Sink::Stdout(s) => s.flush(),
        }
    }
}

impl Output {
    fn new(sink: Sink) -> Output {
        Output { inner: BufWriter::with_capacity(1 << 16, sink), failed: false }
    }

    fn note<T>(&mut self, r: io::Result<T>) -> io::Result<T> {
        if r.is_err() {
            self.failed = true;
        }
        r
    }

    /// Flushes the buffer; the sink, or the error that the flush met.
    fn finish(mut self) -> io::Result<Sink> {
        let r = self.inner.flush();
        self.note(r)?;
        self.inner.into_inner().map_err(|e| e.into_error())
    }
}

/// The write error once a signal asked a cooperative command to stop.
fn stopped() -> io::Result<()> {
    if interrupted() {
        return Err(io::Error::other("cancelled (Ctrl-C)"));
    }
    Ok(())
}

impl Write for Output {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let r = stopped().and_then(|()| self.inner.write(buf));
        self.note(r)
    }

    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        let r = stopped().and_then(|()| self.inner.write_all(buf));
        self.note(r)
    }

    fn flush(&mut self) -> io::Result<()> {
        let r = self.inner.flush();
        self.note(r)
    }
}

/// Writes the output `path` with `write` (see the module documentation for
/// what happens with `-`, devices, links and regular files). Errors name the
/// output; nothing is left half-written at `path` when it is a regular file.
pub(crate) fn write_atomically(path: &Path, write: impl FnOnce(&mut Output) -> Result<()>) -> Result<()> {
    if is_stdout(path) {
        let mut out = Output::new(Sink::Stdout(io::stdout().lock()));
        run(&mut out, write, "standard output")?;
        out.finish().context("cannot write to standard output")?;
        return Ok(());
    }
    let target = match final_target(path)? {
        Resolved::Path(p) => p,
        Resolved::Descriptor(fd) => return write_to_descriptor(fd, &format!("`{}`", path.display()), write),
    };
    let shown = if target == path {
        format!("`{}`", path.display())
    } else {
        format!("`{}` (the target of `{}`)", target.display(), path.display())
    };
    let existing = match std::fs::metadata(&target) {
        Ok(m) => Some(m),
        Err(e) if e.kind() == io::ErrorKind::NotFound => None,
        Err(e) => return Err(e).with_context(|| format!("cannot write {shown}")),
    };
    match existing {
        Some(m) if m.is_dir() => bail!("cannot write {shown}: it is a folder"),
        Some(m) if !m.is_file() => write_in_place(&target, &shown, write),
        Some(m) => write_replacing(&target, &shown, Some(m.permissions()), write),
        None => write_replacing(&target, &shown, None, write),
    }
}

/// Runs the caller's `write`; an error after a failed write names the
/// output, and a signal that stopped it gives exit code 130.
fn run(out: &mut Output, write: impl FnOnce(&mut Output) -> Result<()>, shown: &str) -> Result<()> {
    let result = write(out);
    if interrupted() {
        return Err(cancelled(shown));
    }
    match result {
        Err(e) if out.failed => Err(e.context(format!("cannot write {shown}"))),
        other => other,
    }
}

/// Exit code 130 after a signal, with a line saying what became of `shown`.
fn cancelled(shown: &str) -> anyhow::Error {
    eprintln!("cancelled (Ctrl-C) while writing {shown}; no file was replaced");
    Exit(EXIT_INTERRUPTED).into()
}

/// Where an output path leads.
enum Resolved {
    /// A file to write (its links followed).
    Path(PathBuf),
    /// One of this process's open descriptors.
    Descriptor(i32),
}

/// The descriptor `path` names when it is one of this process's own (see the
/// module documentation); checked on the name, before any link is followed,
/// because following `/proc/self/fd/1` leads to the file behind it, opened
/// afresh without the descriptor's offset and append flag (or, for a pipe,
/// to a name that cannot be opened).
fn own_descriptor(path: &Path) -> Option<i32> {
    let name = path.to_str()?;
    match name {
        "/dev/stdout" => return Some(1),
        "/dev/stderr" => return Some(2),
        _ => {}
    }
    let pid = format!("/proc/{}/fd/", std::process::id());
    let prefixes = ["/dev/fd/", "/proc/self/fd/", "/proc/thread-self/fd/", pid.as_str()];
    let number = prefixes.iter().find_map(|p| name.strip_prefix(p))?;
    number.parse().ok()
}

/// `path` with every symbolic link along its last component followed (the
/// folders on the way are left to the system); a dangling link gives the
/// path the link points at, which is then created.
fn final_target(path: &Path) -> Result<Resolved> {
    let mut p = path.to_path_buf();
    // As the kernel's limit on nested links (ELOOP).
    for _ in 0..40 {
        if let Some(fd) = own_descriptor(&p) {
            return Ok(Resolved::Descriptor(fd));
        }
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let link = std::fs::read_link(&p).with_context(|| format!("cannot read the link `{}`", p.display()))?;
                p = match p.parent() {
                    Some(dir) => dir.join(link),
                    None => link,
                };
            }
            _ => return Ok(Resolved::Path(p)),
        }
    }
    bail!("cannot write `{}`: too many levels of symbolic links", path.display())
}

/// A device, FIFO or socket: opened for writing as it is (never created,
/// never truncated, never renamed over).
fn write_in_place(target: &Path, shown: &str, write: impl FnOnce(&mut Output) -> Result<()>) -> Result<()> {
    let file = OpenOptions::new().write(true).open(target).with_context(|| format!("cannot open {shown}"))?;
    write_to_file(file, shown, write)
}

/// Descriptor `fd` of this process, through a copy of it (same open file:
/// same offset, same flags).
#[cfg(unix)]
fn write_to_descriptor(fd: i32, shown: &str, write: impl FnOnce(&mut Output) -> Result<()>) -> Result<()> {
    use std::os::fd::FromRawFd;
    // SAFETY: dup reads the descriptor table only; it fails with EBADF on a
    // closed descriptor.
    let copy = unsafe { libc::dup(fd) };
    if copy < 0 {
        let e = io::Error::last_os_error();
        return Err(e).with_context(|| format!("cannot write {shown}: descriptor {fd} is not open"));
    }
    // SAFETY: `copy` is a new descriptor that nothing else owns.
    let file = unsafe { File::from_raw_fd(copy) };
    write_to_file(file, shown, write)
}

#[cfg(not(unix))]
fn write_to_descriptor(fd: i32, shown: &str, _write: impl FnOnce(&mut Output) -> Result<()>) -> Result<()> {
    bail!("cannot write {shown}: descriptor {fd} cannot be named on this system")
}

/// An open file written as it is, flushed (no rename).
fn write_to_file(file: File, shown: &str, write: impl FnOnce(&mut Output) -> Result<()>) -> Result<()> {
    let mut out = Output::new(Sink::File(file));
    run(&mut out, write, shown)?;
    // Devices and FIFOs cannot be synced (EINVAL); the flush reports what
    // the device said (ENOSPC for /dev/full).
    out.finish().with_context(|| format!("cannot write {shown}"))?;
    Ok(())
}

/// A temporary file in the target's folder, deleted when dropped (also from
/// the signal handler's list).
struct Temp {
    file: Option<tempfile::NamedTempFile>,
}

impl Temp {
    fn create(target: &Path, permissions: Option<Permissions>) -> io::Result<Temp> {
        let dir = match target.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        let name = target.file_name().map_or_else(|| "out".into(), |n| n.to_string_lossy());
        let prefix = format!(".{name}.");
        let mut builder = tempfile::Builder::new();
        builder.prefix(&prefix).suffix(".kinema-tmp");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            // What `File::create` gives a new file: 0666 less the umask.
            builder.permissions(Permissions::from_mode(0o666));
        }
        let mut registry = TempFiles::lock();
        let file = builder.tempfile_in(dir)?;
        registry.add(file.path());
        drop(registry);
        if let Some(p) = permissions {
            // An existing file keeps its mode.
            file.as_file().set_permissions(p)?;
        }
        Ok(Temp { file: Some(file) })
    }

    fn path(&self) -> &Path {
        self.file.as_ref().map_or(Path::new(""), |f| f.path())
    }
}

impl Drop for Temp {
    fn drop(&mut self) {
        if let Some(file) = self.file.take() {
            let path = file.path().to_path_buf();
            drop(file);
            TempFiles::lock().remove(&path);
        }
    }
}

/// A regular file or a new one: through a temporary file renamed over it.
fn write_replacing(
    target: &Path,
    shown: &str,
    permissions: Option<Permissions>,
    write: impl FnOnce(&mut Output) -> Result<()>,
) -> Result<()> {
    let mut temp =
        Temp::create(target, permissions).with_context(|| format!("cannot create a file next to {shown}"))?;
    let file = temp.file.as_ref().map(|f| f.as_file().try_clone()).transpose()?;
    let Some(file) = file else { bail!("cannot write {shown}") };
    let mut out = Output::new(Sink::File(file));
    run(&mut out, write, shown)?;
    let written = || format!("cannot write {shown} (through `{}`)", temp.path().display());
    drop(out.finish().with_context(written)?);
    if let Some(f) = &temp.file {
        f.as_file().sync_all().with_context(written)?;
    }
    let mut registry = TempFiles::lock();
    if interrupted() {
        // The temporary file is removed when `temp` drops, after the lock.
        drop(registry);
        return Err(cancelled(shown));
    }
    let Some(named) = temp.file.take() else { bail!("cannot write {shown}") };
    let from = named.path().to_path_buf();
    let result = named.persist(target);
    registry.remove(&from);
    if result.is_ok() {
        registry.committed();
    }
    drop(registry);
    // On an error the temporary file comes back in the error and is deleted with it.
    result.map_err(|e| e.error).with_context(|| format!("cannot move the result to {shown}"))?;
    // The rename reaches the disk with the folder's entry; some file systems
    // cannot sync a folder, and the data itself is already synced.
    if let Some(dir) = target.parent().filter(|d| !d.as_os_str().is_empty()) {
        let _ = File::open(dir).and_then(|d| d.sync_all());
    }
    Ok(())
}
