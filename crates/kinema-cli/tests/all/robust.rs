//! Robustness of the `kinema` binary (issue 24): output files that are
//! devices, FIFOs or links, Ctrl-C during a write, huge counts, endless
//! inputs, closed pipes and CSV first lines.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::cli::tempdir;
use crate::mutate;

fn kinema() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_kinema"));
    c.stdin(Stdio::null());
    c
}

fn run(args: &[&str]) -> Output {
    kinema().args(args).output().expect("kinema runs")
}

/// Runs `kinema`, killing it after `limit`: `None` when it had to be killed.
fn run_within(args: &[&str], limit: Duration) -> Option<Output> {
    let mut child = kinema().args(args).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    // Both pipes read on threads, so that a long output cannot stall the child.
    let read = |mut pipe: Box<dyn std::io::Read + Send>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            let _ = pipe.read_to_end(&mut bytes);
            bytes
        })
    };
    let out = read(Box::new(child.stdout.take().unwrap()));
    let err = read(Box::new(child.stderr.take().unwrap()));
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return Some(Output { status, stdout: out.join().unwrap(), stderr: err.join().unwrap() });
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Whether the `kinema` under test has the sub-command `args` start with:
/// `plot`, `scorbot` and `serve` are cargo features, and a case that needs
/// one left out of this build is skipped.
fn built(args: &[&str]) -> bool {
    let features =
        [("plot", cfg!(feature = "plot")), ("scorbot", cfg!(feature = "scorbot")), ("serve", cfg!(feature = "serve"))];
    features.iter().all(|&(name, on)| on || args.first() != Some(&name))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A small input for `kinema fk --input` on the puma560.
fn configurations(dir: &Path) -> PathBuf {
    let q = dir.join("q.csv");
    std::fs::write(&q, "q1,q2,q3,q4,q5,q6\n0,0,0,0,0,0\n0.1,0.2,0.3,0.4,0.5,0.6\n").unwrap();
    q
}

/// The names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    v.sort();
    v
}

#[cfg(unix)]
fn is_char_device(p: &Path) -> bool {
    use std::os::unix::fs::FileTypeExt;
    std::fs::metadata(p).is_ok_and(|m| m.file_type().is_char_device())
}

#[test]
#[cfg(unix)]
fn a_full_device_is_a_write_error_and_stays_a_device() {
    let full = Path::new("/dev/full");
    if !is_char_device(full) {
        eprintln!("no /dev/full here; skipped");
        return;
    }
    let dir = tempdir("full");
    let q = configurations(&dir);
    let o = run(&["fk", "-r", "puma560", "--input", s(&q), "--output", "/dev/full"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("/dev/full") && e.contains("No space left on device"), "{e}");
    assert!(is_char_device(full), "/dev/full was replaced");
    // The plots write through the same writer.
    let plot: &[&str] = &["plot", "robot", "-r", "puma560", "--q", "home", "--out", "/dev/full", "--size", "200x200"];
    if built(plot) {
        let o = run(plot);
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        assert!(is_char_device(full), "/dev/full was replaced");
    }
}

/// Issue 35 item 2: with standard output a full device, every plain-text
/// form (and --help, --version, the CSV and JSON ones) fails with exit code 1
/// and a message naming standard output — no panic (exit 101).
#[test]
#[cfg(unix)]
fn a_full_standard_output_is_a_write_error_not_a_panic() {
    let full = Path::new("/dev/full");
    if !is_char_device(full) {
        eprintln!("no /dev/full here; skipped");
        return;
    }
    let program = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/programs/scara_pick_place.prg");
    let cell = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/cells/seed004_two_iiwa.toml");
    let forms: &[&[&str]] = &[
        &["robots"],
        &["info", "-r", "puma560"],
        &["fk", "-r", "puma560", "--q", "home"],
        &["fk", "-r", "puma560", "--q", "home", "--json"],
        &["jacobian", "-r", "puma560", "--q", "home"],
        &["manip", "-r", "puma560", "--q", "home"],
        &["ik", "-r", "puma560", "--position", "0.5,0.2,0.3"],
        &["ik", "-r", "puma560", "--position", "0.5,0.2,0.3", "--all"],
        &["ik-validate", "-r", "puma560", "--n", "10"],
        &["selfmotion", "-r", "lbr-iiwa-14-r820", "--q", "home"],
        &["traj", "law", "--profile", "trapezoid", "--distance", "1", "--vmax", "0.5", "--amax", "1"],
        &["traj", "ptp", "-r", "puma560", "--from", "home", "--to", "qr"],
        &["check", program, "-r", "scara5"],
        &["compile", program, "-r", "scara5", "--listing"],
        &["run", program, "-r", "scara5", "--out", "-"],
        &["cell", cell],
        &["dyn", "--help"],
        &["--version"],
    ];
    for args in forms {
        let o = kinema().args(*args).stdout(std::fs::File::create(full).unwrap()).output().unwrap();
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {e}");
        assert!(e.contains("standard output") && e.contains("No space left on device"), "{args:?}: {e}");
        assert!(!e.contains("panicked"), "{args:?}: {e}");
    }
}

#[test]
#[cfg(unix)]
fn a_linked_output_updates_the_target_and_keeps_the_link() {
    let dir = tempdir("link");
    let q = configurations(&dir);
    std::fs::create_dir_all(dir.join("data")).unwrap();
    std::fs::write(dir.join("data/poses.csv"), "old\n").unwrap();
    std::os::unix::fs::symlink("data/poses.csv", dir.join("poses.csv")).unwrap();
    let o = run(&["fk", "-r", "puma560", "--input", s(&q), "--output", s(&dir.join("poses.csv"))]);
    assert!(o.status.success(), "{}", stderr(&o));
    let link = std::fs::symlink_metadata(dir.join("poses.csv")).unwrap();
    assert!(link.file_type().is_symlink(), "the link was replaced");
    assert_eq!(std::fs::read_link(dir.join("poses.csv")).unwrap(), Path::new("data/poses.csv"));
    let text = std::fs::read_to_string(dir.join("data/poses.csv")).unwrap();
    assert!(text.starts_with("x,y,z,") && text.lines().count() == 3, "{text}");
    // A dangling link: its target is created.
    std::os::unix::fs::symlink("data/new.csv", dir.join("new.csv")).unwrap();
    let o = run(&["fk", "-r", "puma560", "--input", s(&q), "--output", s(&dir.join("new.csv"))]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::symlink_metadata(dir.join("new.csv")).unwrap().file_type().is_symlink());
    assert!(std::fs::read_to_string(dir.join("data/new.csv")).unwrap().starts_with("x,y,z,"));
    assert_eq!(names(&dir.join("data")), ["new.csv", "poses.csv"]);
}

#[test]
#[cfg(unix)]
fn a_link_planted_at_the_old_temporary_name_is_not_followed() {
    let dir = tempdir("planted");
    let q = configurations(&dir);
    std::fs::write(dir.join("victim.txt"), "precious\n").unwrap();
    // Until issue 24 the temporary file was `.NAME.kinema-tmp`, opened following links.
    std::os::unix::fs::symlink(dir.join("victim.txt"), dir.join(".out.csv.kinema-tmp")).unwrap();
    let before = names(&dir);
    let o = run(&["fk", "-r", "puma560", "--input", s(&q), "--output", s(&dir.join("out.csv"))]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(dir.join("victim.txt")).unwrap(), "precious\n");
    assert_eq!(std::fs::read_link(dir.join(".out.csv.kinema-tmp")).unwrap(), dir.join("victim.txt"));
    let mut after = before.clone();
    after.push("out.csv".into());
    after.sort();
    assert_eq!(names(&dir), after, "only the output is new");
    assert!(std::fs::read_to_string(dir.join("out.csv")).unwrap().starts_with("x,y,z,"));
}

#[test]
#[cfg(unix)]
fn a_fifo_output_receives_the_data_and_stays_a_fifo() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tempdir("fifo");
    let q = configurations(&dir);
    let fifo = dir.join("poses.fifo");
    let made = Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        eprintln!("mkfifo is not available; skipped");
        return;
    }
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let o = run(&["fk", "-r", "puma560", "--input", s(&q), "--output", s(&fifo)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo(), "the FIFO was replaced");
    {
        // Should kinema not have opened the FIFO, this ends the reader's wait (with no data).
        use std::os::unix::fs::OpenOptionsExt;
        let _ = std::fs::OpenOptions::new().write(true).custom_flags(libc::O_NONBLOCK).open(&fifo);
    }
    let text = reader.join().unwrap();
    assert!(text.starts_with("x,y,z,") && text.lines().count() == 3, "{text}");
    assert_eq!(names(&dir), ["poses.fifo", "q.csv"]);
}

#[test]
fn a_dash_output_is_standard_output() {
    let dir = tempdir("dash");
    let q = configurations(&dir);
    let o = run(&["fk", "-r", "puma560", "--input", s(&q), "--output", "-"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(text.starts_with("x,y,z,") && text.lines().count() == 3, "{text}");
    assert_eq!(names(&dir), ["q.csv"]);
}

/// `run --out - --json` mixed the CSV and the JSON summary on standard output.
#[test]
fn a_dash_output_with_a_json_summary_is_refused() {
    let dir = tempdir("dash-json");
    let program = dir.join("home.prg");
    std::fs::write(&program, "HOME 1\n").unwrap();
    let o = run(&["run", s(&program), "-r", "scara5", "--out", "-", "--json"]);
    assert!(!o.status.success() && o.stdout.is_empty(), "{}", String::from_utf8_lossy(&o.stdout));
    assert!(stderr(&o).contains("both go to standard output"), "{}", stderr(&o));
    let o = run(&["run", s(&program), "-r", "scara5", "--out", "-"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8(o.stdout).unwrap().starts_with("t,q1,"));
}

/// Sends SIGINT to `child` as soon as its temporary output file appears in
/// `dir` (within `limit`), so the signal lands while it writes; its exit status.
#[cfg(unix)]
fn interrupt_while_writing(mut child: std::process::Child, dir: &Path, limit: Duration) -> std::process::ExitStatus {
    let start = Instant::now();
    let temp = |dir: &Path| names(dir).into_iter().any(|n| n.contains("kinema-tmp"));
    while !temp(dir) {
        assert!(child.try_wait().unwrap().is_none(), "kinema ended before its temporary file was seen");
        assert!(start.elapsed() < limit, "no temporary file after {limit:?}");
        std::thread::sleep(Duration::from_millis(1));
    }
    assert!(Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap().success());
    child.wait().unwrap()
}

#[test]
#[cfg(unix)]
fn an_interrupted_write_leaves_no_temporary_file() {
    use std::fmt::Write;
    let dir = tempdir("sigint");
    // Long enough that the temporary file exists for a second or so.
    let mut text = String::new();
    for i in 0..300_000u32 {
        let v = f64::from(i % 1000) * 1e-3;
        writeln!(text, "{v},{},{},{v},{},0.1", -v, 0.5 - v, v * 0.5).unwrap();
    }
    let q = dir.join("big.csv");
    std::fs::write(&q, text).unwrap();
    let out = dir.join("out.csv");
    let child = kinema()
        .args(["fk", "-r", "puma560", "--input", s(&q), "--output", s(&out)])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let status = interrupt_while_writing(child, &dir, Duration::from_secs(20));
    assert_eq!(status.code(), Some(130), "{status:?}");
    assert_eq!(names(&dir), ["big.csv"], "a temporary or partial file is left");
}

#[test]
#[cfg(unix)]
fn an_interrupted_ik_batch_stops_and_writes_nothing() {
    use std::fmt::Write;
    use std::os::unix::process::ExitStatusExt;
    let dir = tempdir("sigint-ik");
    // Far more numeric solves than a second allows.
    let mut text = String::new();
    for i in 0..300_000u32 {
        let k = f64::from(i % 997) / 997.0;
        writeln!(text, "{},{},{}", 0.2 + 0.3 * k, 0.3 - 0.6 * k, 0.1 + 0.5 * k).unwrap();
    }
    let targets = dir.join("targets.csv");
    std::fs::write(&targets, text).unwrap();
    let out = dir.join("q.csv");
    let mut child = kinema()
        .args(["ik", "-r", "puma560", "--solver", "numeric", "--input", s(&targets), "--output", s(&out)])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(700));
    assert!(child.try_wait().unwrap().is_none(), "the batch ended within 0.7 s; give it more targets");
    assert!(Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap().success());
    let status = child.wait().unwrap();
    // Solving: the solvers stop and the exit code is 130; still reading the input: SIGINT's default.
    assert!(status.code() == Some(130) || status.signal() == Some(libc::SIGINT), "{status:?}");
    assert_eq!(names(&dir), ["targets.csv"]);
}

#[test]
fn huge_counts_are_refused_at_once_with_the_limit() {
    let dir = tempdir("counts");
    let svg = dir.join("x.svg");
    let cases: [&[&str]; 9] = [
        &["plot", "workspace", "-r", "puma560", "--samples", "100000000000", "--out", s(&svg)],
        &["plot", "workspace", "-r", "puma560", "--samples", "1e11", "--out", s(&svg)],
        &["plot", "workspace", "-r", "puma560", "--grid", "100000", "--out", s(&svg)],
        &["plot", "selfmotion", "-r", "lbr-iiwa-14-r820", "--q", "fig9", "--steps", "1e10", "--out", s(&svg)],
        &["plot", "ik-error", "-r", "puma560", "--cases", "100000000000", "--out", s(&svg)],
        &["bench", "-r", "puma560", "--n", "100000000000"],
        &["bench", "-r", "puma560", "--ik", "--ik-n", "100000000000"],
        &["ik-validate", "-r", "puma560", "--n", "100000000000"],
        &["selfmotion", "-r", "lbr-iiwa-14-r820", "--q", "fig9", "--steps", "10000000000"],
    ];
    for args in cases.into_iter().filter(|a| built(a)) {
        let o = run_within(args, Duration::from_secs(10)).unwrap_or_else(|| panic!("{args:?} still ran after 10 s"));
        assert_eq!(o.status.code(), Some(64), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains("above the limit of"), "{args:?}: {}", stderr(&o));
    }
    let plot: &[&str] = &["plot", "robot", "-r", "puma560", "--q", "home", "--size", "100000x100000", "--out", s(&svg)];
    if built(plot) {
        let o = run(plot);
        assert_eq!(o.status.code(), Some(64), "{}", stderr(&o));
        assert!(stderr(&o).contains("10000 pixels"), "{}", stderr(&o));
    }
    let o = run(&["bench", "-r", "puma560", "--n", "10"]);
    assert!(stderr(&o).contains("at least 1000"), "{}", stderr(&o));
    assert_eq!(names(&dir), Vec::<String>::new());
}

#[test]
#[cfg(unix)]
fn endless_inputs_are_refused_at_the_size_limit() {
    let zero = Path::new("/dev/zero");
    if !is_char_device(zero) {
        eprintln!("no /dev/zero here; skipped");
        return;
    }
    let dir = tempdir("zero");
    std::os::unix::fs::symlink(zero, dir.join("zero.toml")).unwrap();
    std::os::unix::fs::symlink(zero, dir.join("zero.urdf")).unwrap();
    let out = dir.join("out.csv");
    let (toml, urdf) = (dir.join("zero.toml"), dir.join("zero.urdf"));
    let cases: [(&[&str], &str); 10] = [
        (&["fk", "-r", "puma560", "--input", "/dev/zero", "--output", s(&out)], "64 MiB"),
        (&["ik", "-r", "puma560", "--input", "/dev/zero", "--output", s(&out)], "64 MiB"),
        (&["traj", "check", "-r", "puma560", "/dev/zero"], "64 MiB"),
        (&["plot", "tracking", "--desired", "/dev/zero", "--measured", "/dev/zero", "--out", s(&out)], "64 MiB"),
        (&["scorbot", "track", "--desired", "/dev/zero", "--measured", "/dev/zero"], "64 MiB"),
        (&["scorbot", "calibrate", "--data", "/dev/zero"], "64 MiB"),
        (&["check", "/dev/zero", "-r", "puma560"], "16 MiB"),
        (&["info", "-r", s(&toml)], "16 MiB"),
        (&["info", "-r", s(&urdf)], "16 MiB"),
        (&["scorbot", "counts", "--q", "home", "--constants", s(&toml)], "16 MiB"),
    ];
    for (args, limit) in cases.into_iter().filter(|(a, _)| built(a)) {
        let o = run_within(args, Duration::from_secs(10)).unwrap_or_else(|| panic!("{args:?} still ran after 10 s"));
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {e}");
        assert!(e.contains("larger than the limit") && e.contains(limit), "{args:?}: {e}");
    }
    let follow: &[&str] = &["scorbot", "connect", "--tcp", "127.0.0.1:9", "follow", "/dev/zero", "--dry-run"];
    if built(follow) {
        let o = run(follow);
        assert!(stderr(&o).contains("not a regular file"), "{}", stderr(&o));
    }
    assert!(!out.exists());
}

#[test]
#[cfg(unix)]
fn a_closed_pipe_ends_the_command_quietly() {
    use std::os::unix::process::ExitStatusExt;
    let cases: [(&[&str], bool); 5] = [
        // A long output always meets the closed pipe; a short one may fit in it first.
        (&["selfmotion", "-r", "lbr-iiwa-14-r820", "--q", "fig9", "--steps", "100000"], true),
        (&["info", "-r", "puma560"], false),
        (&["robots"], false),
        (&["scorbot", "counts", "--q", "home"], false),
        (&["ik-validate", "-r", "scorbot-er-v-plus", "--n", "20"], false),
    ];
    for (args, long) in cases.into_iter().filter(|(a, _)| built(a)) {
        let mut child = kinema().args(args).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
        drop(child.stdout.take());
        let o = child.wait_with_output().unwrap();
        let e = stderr(&o);
        assert!(!e.contains("panicked") && !e.contains("Broken pipe"), "{args:?}: {e}");
        let sigpipe = o.status.signal() == Some(libc::SIGPIPE);
        assert!(sigpipe || (!long && o.status.success()), "{args:?}: {:?} {e}", o.status);
    }
}

#[test]
fn a_first_csv_line_that_mixes_numbers_and_names_is_an_error() {
    let dir = tempdir("header");
    let bad = dir.join("bad.csv");
    let out = dir.join("out.csv");
    std::fs::write(&bad, "0,0,0,0,0,zz\n0.1,0.2,0.3,0.4,0.5,0.6\n").unwrap();
    let o = run(&["fk", "-r", "puma560", "--input", s(&bad), "--output", s(&out)]);
    assert_eq!(o.status.code(), Some(1));
    let e = stderr(&o);
    assert!(e.contains("line 1") && e.contains("0,0,0,0,0,zz"), "{e}");
    std::fs::write(&bad, "# targets\n0.4,0.1,x\n0.4,0.1,0.3\n").unwrap();
    let o = run(&["ik", "-r", "puma560", "--input", s(&bad), "--output", s(&out)]);
    assert!(stderr(&o).contains("line 2"), "{}", stderr(&o));
    assert!(!out.exists());
    // A header of names only is skipped; a file whose header is missing says so.
    std::fs::write(&bad, "q1, q2 ,q3,q4,q5,q6\n0.1,0.2,0.3,0.4,0.5,0.6\n").unwrap();
    let o = run(&["fk", "-r", "puma560", "--input", s(&bad), "--output", s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::write(&bad, "0,0,0,0,0,0,0\n0.1,0,0,0,0,0,0\n").unwrap();
    let o = run(&["traj", "check", "-r", "puma560", s(&bad)]);
    let e = stderr(&o);
    assert!(e.contains("line 1") && e.contains("header"), "{e}");
    std::fs::write(&bad, "t,q1,q2,3,q4,q5,q6\n0,0,0,0,0,0,0\n").unwrap();
    let o = run(&["traj", "check", "-r", "puma560", s(&bad)]);
    assert!(stderr(&o).contains("mixes numbers and names"), "{}", stderr(&o));
}

/// Issue 35 item 1: an output named by one of the process's own descriptors
/// is written through that descriptor: `>>` keeps what the file held, a pipe
/// receives the data, and the file behind it is never replaced.
#[test]
#[cfg(unix)]
fn an_own_descriptor_output_is_written_through_it_in_place() {
    let dir = tempdir("own-fd");
    let q = configurations(&dir);
    let expected = run(&["fk", "-r", "puma560", "--input", s(&q), "--output", "-"]).stdout;
    assert!(!expected.is_empty());
    for name in ["/dev/stdout", "/dev/fd/1", "/proc/self/fd/1"] {
        let log = dir.join("log.txt");
        std::fs::write(&log, "old line\n").unwrap();
        let appending = std::fs::OpenOptions::new().append(true).open(&log).unwrap();
        let o = kinema()
            .args(["fk", "-r", "puma560", "--input", s(&q), "--output", name])
            .stdout(appending)
            .output()
            .unwrap();
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let mut want = b"old line\n".to_vec();
        want.extend_from_slice(&expected);
        assert_eq!(std::fs::read(&log).unwrap(), want, "{name} with >> log");
        // A pipe.
        let o = run(&["fk", "-r", "puma560", "--input", s(&q), "--output", name]);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        assert_eq!(o.stdout, expected, "{name} into a pipe");
    }
    // Standard error, appended, through a link to it.
    let link = dir.join("err-link");
    std::os::unix::fs::symlink("/dev/stderr", &link).unwrap();
    let log = dir.join("err.txt");
    std::fs::write(&log, "kept\n").unwrap();
    let appending = std::fs::OpenOptions::new().append(true).open(&log).unwrap();
    let o = kinema()
        .args(["fk", "-r", "puma560", "--input", s(&q), "--output", s(&link)])
        .stderr(appending)
        .output()
        .unwrap();
    assert!(o.status.success());
    let text = std::fs::read_to_string(&log).unwrap();
    assert!(text.starts_with("kept\n") && text.contains(std::str::from_utf8(&expected).unwrap()), "{text}");
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
    // A descriptor that is not open names itself.
    let o = run(&["fk", "-r", "puma560", "--input", s(&q), "--output", "/dev/fd/57"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("descriptor 57 is not open"), "{}", stderr(&o));
}

/// Issue 35 item 8: past a file size limit (`ulimit -f`) the write fails
/// with "File too large", exit code 1, and no temporary file is left.
#[test]
#[cfg(unix)]
fn a_file_size_limit_is_a_write_error_and_leaves_nothing() {
    use std::fmt::Write;
    let dir = tempdir("ulimit");
    let mut text = String::from("q1,q2,q3,q4,q5,q6\n");
    for i in 0..2000u32 {
        let v = f64::from(i) * 1e-3;
        writeln!(text, "{v},{},{},{v},{},0.1", -v, 0.5 - v, v * 0.5).unwrap();
    }
    let q = dir.join("q.csv");
    std::fs::write(&q, text).unwrap();
    let out = dir.join("out.csv");
    let script = format!(
        "ulimit -f 20 && exec '{}' fk -r puma560 --input '{}' --output '{}'",
        env!("CARGO_BIN_EXE_kinema"),
        s(&q),
        s(&out)
    );
    let o = Command::new("sh").args(["-c", &script]).stdin(Stdio::null()).output().unwrap();
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{:?}: {e}", o.status);
    assert!(e.contains("File too large"), "{e}");
    assert_eq!(names(&dir), ["q.csv"], "a temporary or partial file is left");
}

/// Issue 35 item 3: Ctrl-C while `kinema cell` writes its samples (the
/// temporary file exists, the rename has not happened) stops the command with
/// exit code 130 and leaves the old output as it was.
#[test]
#[cfg(unix)]
fn ctrl_c_while_a_cell_writes_leaves_the_old_output() {
    let dir = tempdir("sigint-cell");
    let cell = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/cells/seed004_two_iiwa.toml");
    let out = dir.join("cell.csv");
    std::fs::write(&out, "old\n").unwrap();
    let child = kinema()
        .args(["cell", cell, "--dt", "0.0002", "--out", s(&out)])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let status = interrupt_while_writing(child, &dir, Duration::from_secs(120));
    assert_eq!(status.code(), Some(130), "{status:?}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "old\n");
    assert_eq!(names(&dir), ["cell.csv"], "a temporary file is left");
}

/// Issue 35 item 3, the other side: a signal at any moment of `kinema run`
/// either leaves the old output (exit 130) or finds the new one in place
/// and complete (exit 0) — never exit 130 with the file replaced.
#[test]
#[cfg(unix)]
fn ctrl_c_at_any_moment_of_a_run_reports_what_happened_to_the_output() {
    use std::os::unix::process::ExitStatusExt;
    let dir = tempdir("sigint-run");
    let program = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/programs/scara_pick_place.prg");
    let out = dir.join("run.csv");
    let args = ["run", program, "-r", "scara5", "--dt", "0.0005", "--out", s(&out)];
    let full = run(&args);
    assert!(full.status.success(), "{}", stderr(&full));
    let complete = std::fs::read(&out).unwrap();
    let took = full_duration(&args);
    for k in 0..16u32 {
        std::fs::write(&out, "old\n").unwrap();
        let mut child = kinema().args(args).stdout(Stdio::null()).stderr(Stdio::null()).spawn().unwrap();
        std::thread::sleep(took.mul_f64(f64::from(k) / 12.0));
        let _ = Command::new("kill").args(["-INT", &child.id().to_string()]).status();
        let status = child.wait().unwrap();
        let now = std::fs::read(&out).unwrap();
        // Before the handler is installed, SIGINT's default ends the process.
        let stopped = status.code() == Some(130) || status.signal() == Some(libc::SIGINT);
        match status.code() {
            _ if stopped => assert_eq!(now, b"old\n", "stopped after the output was replaced (signal at {k}/12)"),
            Some(0) => assert_eq!(now, complete, "exit 0 with an incomplete output (signal at {k}/12)"),
            other => panic!("signal at {k}/12: {other:?}"),
        }
        assert_eq!(names(&dir), ["run.csv"], "a temporary file is left");
    }
}

/// How long `kinema args` takes, the best of three.
fn full_duration(args: &[&str]) -> Duration {
    (0..3)
        .map(|_| {
            let start = Instant::now();
            run(args);
            start.elapsed()
        })
        .min()
        .unwrap()
}

/// Issue 35, the fuzz target for CSV inputs: random edits of valid joint,
/// target and trajectory files, given to `fk`, `ik`, `traj check` and `dyn`.
/// Every run ends with exit code 0, 1 or 2 (never a panic, 101, or a signal),
/// an error names its cause, and an accepted `fk` or `dyn` writes no NaN or inf.
#[test]
fn random_csv_inputs_end_cleanly_and_give_finite_answers() {
    use rand::SeedableRng;
    let dir = tempdir("fuzz-csv");
    let q = std::fs::read_to_string(configurations(&dir)).unwrap();
    let traj =
        run(&["traj", "ptp", "-r", "puma560", "--from", "home", "--to", "0.3,0.2,0.1,0.4,0.5,0.6", "--dt", "0.05"]);
    assert!(traj.status.success(), "{}", stderr(&traj));
    let traj = String::from_utf8(traj.stdout).unwrap();
    let targets = "x,y,z\n0.5,0.2,0.3\n0.4,-0.1,0.5\n";
    let forms: [(&str, &[&str]); 4] = [
        (&q, &["fk", "-r", "puma560", "--input", "IN", "--output", "-"]),
        (targets, &["ik", "-r", "puma560", "--input", "IN", "--output", "-"]),
        (&traj, &["traj", "check", "-r", "puma560", "IN"]),
        (&traj, &["dyn", "-r", "puma560", "IN"]),
    ];
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0x35c);
    let input = dir.join("in.csv");
    let (mut ok, mut refused) = (0, 0);
    for case in 0..mutate::fuzz_cases(60) {
        let (source, args) = &forms[case % forms.len()];
        let text = if case % 8 == 0 { mutate::random_text(&mut rng) } else { mutate::mutate(source, &mut rng) };
        std::fs::write(&input, &text).unwrap();
        let args: Vec<&str> = args.iter().map(|a| if *a == "IN" { s(&input) } else { a }).collect();
        let o = run_within(&args, Duration::from_secs(60)).unwrap_or_else(|| panic!("{args:?} hangs on {text:?}"));
        let (e, out) = (stderr(&o), String::from_utf8_lossy(&o.stdout).into_owned());
        let text: String = text.chars().take(300).collect();
        assert!(matches!(o.status.code(), Some(0..=2)), "{args:?} on {text:?}: {:?} {e}", o.status);
        assert!(!e.contains("panicked"), "{args:?} on {text:?}: {e}");
        if o.status.success() {
            ok += 1;
            if matches!(args[0], "fk" | "dyn") {
                let lower = out.to_ascii_lowercase();
                assert!(!lower.contains("nan") && !lower.contains("inf"), "{args:?} on {text:?}: {out}");
            }
        } else {
            refused += 1;
            // An error on stderr, or a check's report (traj check, dyn) on stdout.
            assert!(!e.trim().is_empty() || !out.trim().is_empty(), "{args:?} on {text:?}: no message");
        }
    }
    assert!(ok >= 4 && refused >= 10, "ok {ok}, refused {refused}");
}
