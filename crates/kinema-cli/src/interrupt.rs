//! Ctrl-C (SIGINT), SIGTERM and SIGHUP: the one handler of the process.
//!
//! A process can have one `ctrlc` handler, so every command that cares about
//! these signals goes through this module instead of installing its own:
//!
//! - [`TempFiles`] registers a temporary file that must not outlive the
//!   process: on a signal the handler deletes every registered file and exits
//!   with status 130 (128 + SIGINT, for SIGTERM and SIGHUP too).
//! - A long computation that can stop cleanly holds a [`cancellable`] guard
//!   and polls [`interrupted`] (or hands [`flag`] to a library): while a guard
//!   is held, the first signal only raises the flag, so the command unwinds
//!   and drops its temporary files itself; a second signal exits at once.
//!
//! - Once an output has been renamed into place ([`TempFiles::committed`]),
//!   the first signal only raises the flag: the command's work is done, so
//!   it finishes and reports success. Before the rename, a signal leaves the
//!   old file as it was.
//!
//! The handler is installed on first use, so that commands which never need
//! it keep the default behaviour (and a handler of their own, should one
//! ever be installed first, keeps working: installing here then fails and is
//! ignored).

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, Once, OnceLock};

/// Exit status after a signal: 128 + SIGINT, as shells report Ctrl-C.
pub(crate) const EXIT_INTERRUPTED: u8 = 130;

/// Raised by the first signal.
fn shared_flag() -> &'static Arc<AtomicBool> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    FLAG.get_or_init(|| Arc::new(AtomicBool::new(false)))
}

/// How many [`cancellable`] guards are alive.
static COOPERATIVE: AtomicUsize = AtomicUsize::new(0);

/// Set once an output is in place: from then on the first signal is deferred.
static COMMITTED: AtomicBool = AtomicBool::new(false);

/// Temporary files to delete on a signal.
static TEMPS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn temps() -> MutexGuard<'static, Vec<PathBuf>> {
    // A panic while holding the lock leaves a usable list.
    TEMPS.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Installs the handler (once; later calls do nothing).
pub(crate) fn install() {
    static INSTALL: Once = Once::new();
    INSTALL.call_once(|| {
        // An error means another handler owns the signals (or the system
        // refused): then signals keep their previous behaviour.
        let _ = ctrlc::set_handler(on_signal);
    });
}

fn on_signal() {
    let first = !shared_flag().swap(true, Ordering::SeqCst);
    if first && COOPERATIVE.load(Ordering::SeqCst) > 0 {
        return;
    }
    // Holding the lock until the exit: a file being registered or persisted
    // right now is either in the list (and deleted) or already in place.
    let list = temps();
    if first && COMMITTED.load(Ordering::SeqCst) {
        return;
    }
    for path in list.iter() {
        let _ = std::fs::remove_file(path);
    }
    std::process::exit(i32::from(EXIT_INTERRUPTED));
}

/// Whether a signal has arrived that the command should stop for: not once
/// its output is in place.
pub(crate) fn interrupted() -> bool {
    shared_flag().load(Ordering::SeqCst) && !COMMITTED.load(Ordering::SeqCst)
}

/// The flag a signal raises, for libraries that poll one (e.g. a program
/// run's `Stop`). Installs the handler.
pub(crate) fn flag() -> Arc<AtomicBool> {
    install();
    shared_flag().clone()
}

/// While the returned guard lives, the first signal only raises the flag.
/// Installs the handler.
pub(crate) fn cancellable() -> Cancellable {
    install();
    COOPERATIVE.fetch_add(1, Ordering::SeqCst);
    Cancellable(())
}

/// See [`cancellable`].
pub(crate) struct Cancellable(());

impl Drop for Cancellable {
    fn drop(&mut self) {
        COOPERATIVE.fetch_sub(1, Ordering::SeqCst);
    }
}

/// The registry of temporary files, locked: register, create and persist
/// files while holding it, so that a signal never sees a half-done step.
pub(crate) struct TempFiles(MutexGuard<'static, Vec<PathBuf>>);

impl TempFiles {
    /// Locks the registry (installing the handler first).
    pub(crate) fn lock() -> TempFiles {
        install();
        TempFiles(temps())
    }

    /// Deletes `path` on a signal from now on.
    pub(crate) fn add(&mut self, path: &Path) {
        self.0.push(path.to_path_buf());
    }

    /// Stops deleting `path` on a signal (it was persisted or removed).
    pub(crate) fn remove(&mut self, path: &Path) {
        self.0.retain(|p| p != path);
    }

    /// Records that an output has been renamed into place (call while the
    /// registry is still locked, right after the rename): a first signal
    /// from now on lets the command finish and report success.
    pub(crate) fn committed(&mut self) {
        COMMITTED.store(true, Ordering::SeqCst);
    }
}
