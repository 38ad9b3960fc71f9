//! End-to-end tests of the `kinema` binary: misuse: random command lines never panic or leave partial output; signals; usage errors; negative numbers.

use std::process::Command;

use crate::common::kinema;

use super::cli::{data, tempdir};

/// Runs `kinema` in the folder `cwd` with a time limit: its exit code, stdout and stderr, or
/// `None` if it had to be killed.
fn kinema_within(
    args: &[String],
    cwd: &std::path::Path,
    limit: std::time::Duration,
) -> Option<(Option<i32>, String, String)> {
    use std::io::Read;
    let mut child = Command::new(env!("CARGO_BIN_EXE_kinema"))
        .args(args)
        .current_dir(cwd)
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("kinema starts");
    // Both pipes read on threads, so that a long output cannot fill one and stall the child.
    let read = |mut pipe: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            let _ = pipe.read_to_end(&mut bytes);
            String::from_utf8_lossy(&bytes).into_owned()
        })
    };
    let stdout = read(Box::new(child.stdout.take().expect("piped stdout")));
    let stderr = read(Box::new(child.stderr.take().expect("piped stderr")));
    let start = std::time::Instant::now();
    loop {
        if let Some(status) = child.try_wait().expect("wait") {
            return Some((status.code(), stdout.join().expect("stdout"), stderr.join().expect("stderr")));
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
}

/// Seeded random misuse of the command line: valid invocations of most commands with one or
/// two values replaced by malformed ones (empty, NaN, ±inf, 1e999, subnormal, negative, text,
/// wrong counts, a flag for a value, a directory or a broken file for a file) or an argument
/// dropped. Every run must end with exit code 0, 1 or 2 (never a panic, code 101, nor a
/// signal), say why when it fails (on stderr, or with `--json` as an error object on stdout),
/// and leave no output file and no temporary file
/// behind when it fails. It runs in an output folder of its own, so that a value that became a
/// relative output path is seen there too.
#[test]
fn random_misuse_never_panics_and_leaves_no_partial_output() {
    use rand::{Rng, SeedableRng};
    let dir = tempdir("misuse");
    let d = |name: &str| dir.join(name).to_string_lossy().into_owned();
    // The input files, written anew before every case: a mutated output path may overwrite one.
    let fixtures = || {
        std::fs::write(dir.join("q.csv"), "0,0,0,0,0,0\n0.1,0.2,0.3,0.4,0.5,0.6\n").unwrap();
        std::fs::write(dir.join("traj.csv"), "t,q1,q2,q3,q4,q5,q6,q7\n0,0,0,0,0,0,0,0\n0.1,0.01,0,0,0,0,0,0\n")
            .unwrap();
        std::fs::write(dir.join("nan.csv"), "t,q1,q2,q3,q4,q5,q6\n0,0,NaN,0,0,0,0\n").unwrap();
        std::fs::write(dir.join("empty.csv"), "").unwrap();
        std::fs::write(dir.join("binary.bin"), [0xff, 0xfe, 0x00, 0x9f, 0x0a, 0x2c]).unwrap();
        std::fs::write(
            dir.join("prog.prg"),
            "JACC 90 deg/s^2\nPTP JOINT(10deg, 0deg, 0deg, -60deg, 0deg, 30deg, 0deg)\n",
        )
        .unwrap();
        // Copies of the repository's fixtures: a mutated output path may name one of them, and
        // the originals must never be written (a run of this test once overwrote malformed.toml).
        for name in ["malformed.toml", "iiwa14.urdf"] {
            std::fs::copy(data(name), dir.join(name)).unwrap();
        }
        let _ = std::fs::remove_file(dir.join("missing.csv"));
        // An output path that is a folder: the result is written, then cannot be moved there.
        for name in ["a-folder", "a-folder.csv", "a-folder.svg", "a-folder.png"] {
            std::fs::create_dir_all(dir.join("out").join(name)).unwrap();
        }
    };
    let out_dir = dir.join("out");
    std::fs::create_dir_all(&out_dir).unwrap();
    let o = |name: &str| out_dir.join(name).to_string_lossy().into_owned();
    // FK of puma560 at 0.1,-0.5,0.3,0.4,0.5,0.6, rounded.
    let t16 = "0.434277,-0.868632,-0.2385,0.497175,0.849726,0.482914,-0.211564,-0.100869,0.298946,-0.110782,0.947818,0.883944,0,0,0,1";
    let templates: Vec<Vec<String>> = [
        "fk --robot lbr-iiwa-14-r820 --q 0.1,0.2,0.3,-1.2,0.4,0.5,0.6 --json",
        "fk --robot puma560 --q 10,20,30,40,50,60 --deg --rpy xyz",
        "fk --robot puma560 --input {q.csv} --output {out:poses.csv}",
        "fk --robot {iiwa14.urdf} --q home --json",
        "jacobian --robot panda --q qr --frame tool --json",
        "jacobian --robot ur5 --q home --analytic zyx",
        "manip --robot lbr-iiwa-14-r820 --q fig9 --direction -0.4,0.5,0.75 --json",
        "ik --robot puma560 --T {t16} --all --json",
        "ik --robot lbr-iiwa-14-r820 --pose -0.06011,-0.074196,1.155594,-0.111347,-0.096668,0.614389 --q3 0.2 --json",
        "ik --robot scorbot-er-v-plus --position 0.3,0.1,0.4 --solver numeric --json",
        "ik --robot scara5 --position 0.4,0.6,0.2 --alpha 30 --deg",
        "ik-validate --robot scorbot-er-v-plus --n 50 --json",
        "selfmotion --robot lbr-iiwa-14-r820 --q fig9 --steps 12 --json",
        "traj law --profile scurve --distance 0.5 --vmax 1 --amax 2 --jmax 20 --dt 0.1 --json",
        "traj ptp -r puma560 --from home --to qr --vmax 1 --amax 3 --dt 0.05 --out {out:ptp.csv}",
        "traj lin -r lbr-iiwa-14-r820 --from fig9 --to 0.1,0.1,0.9,0,-1.3,0 --vmax 0.2 --amax 0.5 --dt 0.05 --out {out:lin.csv}",
        "traj expr -r rommel --joint 1 0.1*sin(2*pi*t) --duration 1 --dt 0.05 --out {out:expr.csv}",
        "traj check -r lbr-iiwa-14-r820 {traj.csv} --json",
        "run {prog.prg} --robot lbr-iiwa-14-r820 --dt 0.05 --out {out:run.csv}",
        "compile {prog.prg} --robot lbr-iiwa-14-r820 --listing",
        "plot robot --robot puma560 --q home --out {out:robot.svg} --size 300x200",
        "plot workspace --robot scara5 --samples 2000 --out {out:ws.png} --size 300x200",
        "scorbot counts --q 10,80,-70,-60,30 --deg --constants factory --json",
        "info --robot panda --json",
    ]
    .iter()
    .map(|t| {
        t.split(' ')
            .map(|w| match w {
                "{t16}" => t16.to_string(),
                w if w.starts_with("{out:") => o(&w[5..w.len() - 1]),
                w if w.starts_with('{') => d(&w[1..w.len() - 1]),
                w => w.to_string(),
            })
            .collect()
    })
    .collect();
    let long = "1,".repeat(5000) + "1";
    let values: Vec<String> = [
        "",
        " ",
        "-",
        "--q",
        "nan",
        "NaN,0,0",
        "inf",
        "-inf",
        "1e999",
        "-1e999",
        "1e-320",
        "0",
        "-1",
        "-0",
        "0x10",
        "1_000",
        "+5",
        "x",
        "1,,2",
        ",",
        "1;2",
        "1,2",
        "0,0,0,0,0,0,0,0,0",
        "home,home",
        "١٢",
        "𝟙",
        "é",
        "\u{1b}[0m",
        &long,
        "300x0",
        "0x0",
        "99999x99999",
        "zyx",
        "tool",
        "world",
        "numeric",
        "scurve",
        "bogus",
        // Plausible values, so that some changed runs still succeed and go deeper.
        "0.5",
        "2",
        "home",
        "0.1,0.2,0.3",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain(
        [&dir.to_string_lossy().into_owned(), &d("missing.csv"), &d("empty.csv"), &d("binary.bin"), &d("nan.csv")]
            .map(|s| s.to_string()),
    )
    .chain([
        d("malformed.toml"),
        o("sub/dir/x.csv"),
        o("x.pdf"),
        o("a-folder.csv"),
        o("a-folder.svg"),
        o("a-folder.png"),
    ])
    .collect();
    // Unchanged, every template runs and succeeds: the changes below start from valid runs.
    fixtures();
    for args in &templates {
        let (code, _, stderr) = kinema_within(args, &out_dir, std::time::Duration::from_secs(60)).expect("in time");
        assert_eq!(code, Some(0), "kinema {args:?}: {stderr}");
    }
    // The repository's fixtures as they were, to check that no run wrote to them.
    let repo_data = || -> Vec<(std::path::PathBuf, Vec<u8>)> {
        let folder = std::path::Path::new(&data("iiwa14.urdf")).parent().unwrap().to_path_buf();
        let mut files: Vec<_> = std::fs::read_dir(folder)
            .unwrap()
            .map(|f| f.unwrap().path())
            .filter(|p| p.is_file())
            .map(|p| {
                let bytes = std::fs::read(&p).unwrap();
                (p, bytes)
            })
            .collect();
        files.sort();
        files
    };
    let data_before = repo_data();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0x6b69);
    let (mut passed, mut failed, mut killed) = (0, 0, 0);
    for case in 0..1000 {
        let mut args = templates[rng.random_range(0..templates.len())].clone();
        let flag = |a: &str| a.starts_with("--") || a == "-r";
        for _ in 0..if rng.random_bool(0.8) { 1 } else { 2 } {
            // Mostly a value replaced (a flag's value or a file argument); else a flag dropped
            // with its value, or an unknown flag added.
            let values_at: Vec<usize> =
                (1..args.len()).filter(|&k| !flag(&args[k]) && (flag(&args[k - 1]) || args[k].contains('/'))).collect();
            let flags_at: Vec<usize> = (1..args.len()).filter(|&k| flag(&args[k])).collect();
            let roll = rng.random_range(0.0..1.0);
            if roll < 0.85 && !values_at.is_empty() {
                let k = values_at[rng.random_range(0..values_at.len())];
                args[k] = values[rng.random_range(0..values.len())].clone();
            } else if roll < 0.95 && !flags_at.is_empty() {
                let k = flags_at[rng.random_range(0..flags_at.len())];
                let with_value = k + 1 < args.len() && !flag(&args[k + 1]);
                args.drain(k..k + 1 + usize::from(with_value));
            } else {
                let k = rng.random_range(1..=args.len());
                args.insert(k, "--no-such-flag".into());
            }
        }
        for f in std::fs::read_dir(&out_dir).unwrap() {
            let p = f.unwrap().path();
            let _ = if p.is_dir() { std::fs::remove_dir_all(&p) } else { std::fs::remove_file(&p) };
        }
        fixtures();
        let Some((code, stdout, stderr)) = kinema_within(&args, &out_dir, std::time::Duration::from_secs(60)) else {
            killed += 1;
            continue;
        };
        let shown = format!("case {case}: kinema {args:?}");
        assert!(matches!(code, Some(0..=2 | 64)), "{shown}: exit {code:?}\n{stderr}");
        assert!(!stderr.contains("panicked"), "{shown}: {stderr}");
        let left: Vec<String> = std::fs::read_dir(&out_dir)
            .unwrap()
            .map(|f| f.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|f| !f.starts_with("a-folder"))
            .collect();
        assert!(left.iter().all(|f| !f.contains("kinema-tmp")), "{shown}: a temporary file is left: {left:?}");
        if std::env::var_os("KINEMA_MISUSE_SHOW").is_some() {
            eprintln!("{case} {code:?} {:.150}", stderr.lines().next().unwrap_or(""));
        }
        if code == Some(0) {
            passed += 1;
        } else {
            failed += 1;
            // The reason on stderr, or, with --json, as an "error" object on stdout.
            let json_error = args.iter().any(|a| a == "--json") && stdout.contains("\"error\"");
            assert!(!stderr.trim().is_empty() || json_error, "{shown}: failed without a word");
            // `ik` exits 2 for an unreachable target, which writes no file either.
            assert!(left.is_empty(), "{shown}: failed ({stderr}) but left {left:?}");
        }
    }
    assert!(repo_data() == data_before, "a run wrote into the repository's tests/data");
    // The draws reach both outcomes; a run that had to be killed is not misuse handled.
    assert!(passed > 40 && failed > 500 && killed == 0, "passed {passed}, failed {failed}, killed {killed}");
}

// ---------------------------------------------------------------- serve

#[cfg(feature = "serve")]
/// `kinema serve` stops cleanly on SIGTERM and on Ctrl-C (SIGINT), even with
/// a program running and a connection left open: it answers the program with
/// 503 and exits with success.
#[cfg(unix)]
#[test]
fn serve_stops_gracefully_on_sigterm_and_ctrl_c() {
    use std::io::{BufRead, Read, Write};
    use std::time::{Duration, Instant};
    for signal in ["-TERM", "-INT"] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_kinema"))
            .args(["serve", "--robot", "puma560", "--port", "0"])
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("kinema serve starts");
        let mut stdout = std::io::BufReader::new(child.stdout.take().unwrap());
        let mut line = String::new();
        stdout.read_line(&mut line).unwrap();
        let url = line.trim().strip_prefix("kinema serve: ").unwrap_or_else(|| panic!("first line `{line}`"));
        let addr = url.trim_start_matches("http://").trim_end_matches('/').to_string();
        let request = |body: &str| {
            let mut s = std::net::TcpStream::connect(&addr).unwrap();
            s.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
            let req = format!(
                "POST /api/run HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\nContent-Length: {}\r\n\r\n{body}",
                body.len()
            );
            s.write_all(req.as_bytes()).unwrap();
            s
        };
        let answer = |mut s: std::net::TcpStream| {
            let mut out = String::new();
            let _ = s.read_to_string(&mut out);
            out
        };
        assert!(answer(request(r#"{"program": "WAIT 1\n"}"#)).starts_with("HTTP/1.1 200"));
        // A program that runs for seconds, and an idle connection.
        // Within every cap of the language, about ten seconds of IK solves.
        let running = request(
            r#"{"program": "JACC 90 deg/s^2\nPOS p = CART(550mm, -150mm, 400mm, 0deg, 180deg, 0deg)\nPTP p\nFOR i = 1 TO 450000\n  PTP p\nEND\n", "dt": 0.5}"#,
        );
        let _idle = std::net::TcpStream::connect(&addr).unwrap();
        std::thread::sleep(Duration::from_millis(300));
        let t0 = Instant::now();
        let killed = Command::new("kill").args([signal, &child.id().to_string()]).status().unwrap();
        assert!(killed.success());
        let status = loop {
            if let Some(status) = child.try_wait().unwrap() {
                break status;
            }
            if t0.elapsed() > Duration::from_secs(10) {
                let _ = child.kill();
                panic!("kinema serve did not stop within 10 s of {signal}");
            }
            std::thread::sleep(Duration::from_millis(10));
        };
        let mut stderr = String::new();
        child.stderr.take().unwrap().read_to_string(&mut stderr).unwrap();
        assert!(status.success(), "{signal}: {status:?}: {stderr}");
        assert!(t0.elapsed() < Duration::from_secs(4), "{signal}: stopped after {:?}", t0.elapsed());
        assert!(stderr.contains("stopped"), "{stderr}");
        let answered = answer(running);
        assert!(answered.starts_with("HTTP/1.1 503") && answered.contains("shutting down"), "{answered}");
    }
}

/// Issue 34 item 13: `--seed -1` and `--tol-position -1` were "unexpected
/// argument" errors unless written with `=`. A negative number is now the
/// option's value, and the error says what is wrong with it.
#[test]
fn negative_numbers_are_values_and_refused_by_what_checks_them() {
    // Unsigned: the seed parser says what a seed is (usage error).
    for args in [
        &["ik", "--robot", "puma560", "--position", "0.5,0.2,0.3", "--seed", "-1"][..],
        &["ik-validate", "--robot", "puma560", "--n", "10", "--seed", "-1"][..],
        &["bench", "--robot", "puma560", "--seed", "-1"][..],
    ] {
        let r = kinema(args);
        assert_eq!(r.code, Some(64), "{args:?}: {}", r.stderr);
        assert!(r.stderr.contains("`-1` is not a seed: a seed is a whole number from 0 to"), "{args:?}: {}", r.stderr);
        assert!(!r.stderr.contains("unexpected argument"), "{}", r.stderr);
    }
    // Tolerances and times: the core's validation, naming the option.
    for (args, needle) in [
        (&["ik", "--robot", "puma560", "--position", "0.5,0.2,0.3", "--tol-position", "-1"][..], "--tol-position"),
        (
            &["ik", "--robot", "puma560", "--pose", "0.5,0.2,0.3,0,0,0", "--tol-orientation", "-1e-3"][..],
            "--tol-orientation",
        ),
        (&["traj", "ptp", "--robot", "ur5", "--from", "home", "--to", "qz", "--dt", "-0.01"][..], "`dt`"),
        (&["traj", "ptp", "--robot", "ur5", "--from", "home", "--to", "qz", "--duration", "-2"][..], "duration"),
    ] {
        let r = kinema(args);
        assert_eq!(r.code, Some(1), "{args:?}: {}", r.stderr);
        assert!(r.stderr.contains(needle) && !r.stderr.contains("unexpected argument"), "{args:?}: {}", r.stderr);
    }
    let r = kinema(&["ik", "--robot", "puma560", "--position", "0.5,0.2,0.3", "--tol-position", "-1"]);
    assert!(r.stderr.contains("positive tolerance"), "{}", r.stderr);
    // Combinations only the core refuses, named by their flags.
    let pose = "0.5,0.1,0.5,3.14159,0,0";
    for (args, flag) in [
        (&["ik", "--robot", "lbr-iiwa-14-r820", "--pose", pose, "--q3", "0.1", "--solver", "numeric"][..], "--solver"),
        (&["ik", "--robot", "lbr-iiwa-14-r820", "--pose", pose, "--q3", "0.1", "--mask", "1,1,1,1,1,0"][..], "--mask"),
        (&["ik", "--robot", "lbr-iiwa-14-r820", "--position", "0.5,0.1,0.5", "--q3", "0.1"][..], "the target"),
    ] {
        let r = kinema(args);
        assert_eq!(r.code, Some(1), "{args:?}: {}", r.stderr);
        assert!(r.stderr.contains(flag) && r.stderr.contains("invalid `"), "{args:?}: {}", r.stderr);
    }
    // A valid negative value is taken as it is: --q3 of the iiwa.
    let r = kinema(&["ik", "--robot", "lbr-iiwa-14-r820", "--pose", "0.5,0.1,0.5,3.14159,0,0", "--q3", "-0.3"]);
    assert!(r.ok, "{}", r.stderr);
}

/// Issue 34 item 13: `ik`/`fk --output` without `--input` wrote nothing and
/// exited 0 (clap skips `requires` when a flag that conflicts with the
/// required one is given); now a usage error that says what --output is for.
#[test]
fn output_without_input_is_a_usage_error() {
    let dir = tempdir("output-alone");
    let out = dir.join("answer.csv");
    let out = out.to_str().unwrap();
    for args in [
        &["ik", "--robot", "puma560", "--position", "0.5,0.2,0.3", "--output", out][..],
        &["ik", "--robot", "ur5", "--pose", "0.4,0.1,0.3,3.14159,0,0", "--output", out][..],
        &["fk", "--robot", "puma560", "--q", "home", "--output", out][..],
    ] {
        let r = kinema(args);
        assert_eq!(r.code, Some(64), "{args:?}: {} {}", r.stdout, r.stderr);
        assert!(r.stderr.contains("--output needs --input"), "{args:?}: {}", r.stderr);
        assert!(r.stdout.is_empty(), "{args:?}: {}", r.stdout);
        assert!(!std::path::Path::new(out).exists());
    }
}
