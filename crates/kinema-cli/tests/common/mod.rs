//! Running the `kinema` binary from the integration tests.

use std::process::Command;

/// Output of one run of `kinema`.
pub struct Run {
    pub ok: bool,
    /// The exit code (`None` when a signal ended the process).
    #[allow(dead_code)] // Not every test binary looks at it.
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
}

/// Runs `kinema` with `args` and waits for it.
pub fn kinema(args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_kinema")).args(args).output().expect("kinema runs");
    Run {
        ok: out.status.success(),
        code: out.status.code(),
        stdout: String::from_utf8(out.stdout).expect("utf-8 stdout"),
        stderr: String::from_utf8(out.stderr).expect("utf-8 stderr"),
    }
}
