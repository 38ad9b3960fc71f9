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
#[allow(dead_code)] // The README test uses `kinema_in` only.
pub fn kinema(args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_kinema")).args(args).output().expect("kinema runs");
    Run {
        ok: out.status.success(),
        code: out.status.code(),
        stdout: String::from_utf8(out.stdout).expect("utf-8 stdout"),
        stderr: String::from_utf8(out.stderr).expect("utf-8 stderr"),
    }
}

/// Runs `kinema` with `args` in the directory `dir`, as [`kinema`] does, but
/// kills it after `timeout`: then `ok` is false, `code` is `None` and
/// `stderr` ends with a line saying so.
#[allow(dead_code)] // Only the README test runs commands in a directory.
pub fn kinema_in(dir: &std::path::Path, args: &[String], timeout: std::time::Duration) -> Run {
    use std::io::Read;
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_kinema"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("kinema starts");
    // Drained on their own threads so that a command printing more than a pipe holds does not block.
    let drain = |mut pipe: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            pipe.read_to_end(&mut bytes).expect("read kinema's output");
            String::from_utf8(bytes).expect("utf-8 output")
        })
    };
    let stdout = drain(Box::new(child.stdout.take().expect("piped stdout")));
    let stderr = drain(Box::new(child.stderr.take().expect("piped stderr")));
    let start = std::time::Instant::now();
    let (status, timed_out) = loop {
        if let Some(status) = child.try_wait().expect("wait for kinema") {
            break (Some(status), false);
        }
        if start.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            break (None, true);
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    };
    let mut stderr = stderr.join().expect("stderr reader");
    if timed_out {
        stderr.push_str(&format!("\n(killed: still running after {} s)\n", timeout.as_secs_f64()));
    }
    Run {
        ok: status.is_some_and(|s| s.success()),
        code: status.and_then(|s| s.code()),
        stdout: stdout.join().expect("stdout reader"),
        stderr,
    }
}

/// A copy of built-in robot `name` without its joint velocity and
/// acceleration limits, written into `dir`; returns its path. For tests of
/// what the checks find with no rate limit to break.
#[allow(dead_code)] // Not every test binary uses it.
pub fn builtin_without_rate_limits(dir: &std::path::Path, name: &str) -> String {
    let text = kinema::builtin_source(name).unwrap_or_else(|| panic!("no built-in `{name}`"));
    let kept: String =
        text.lines().filter(|l| !l.starts_with("vel =") && !l.starts_with("acc =")).map(|l| format!("{l}\n")).collect();
    let path = dir.join(format!("{name}-without-rate-limits.toml"));
    std::fs::write(&path, kept).unwrap();
    path.to_str().unwrap().to_string()
}
