//! End-to-end tests of the `kinema` binary: The robot language (`kinema check|run|compile`) and `kinema plot`.

use std::path::PathBuf;
use std::process::Command;

use serde_json::Value;

use crate::common;

use common::kinema;

use super::cli::{fails, json, matrix, tempdir};

fn program(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/programs").join(name).display().to_string()
}

#[test]
fn language_check_run_and_compile() {
    let scara = program("scara_pick_place.prg");
    let r = kinema(&["check", &scara, "--robot", "scara5"]);
    assert!(r.ok, "{}", r.stderr);
    assert!(r.stdout.contains("ok on `scara5`") && r.stdout.contains("39.0000 s"), "{}", r.stdout);
    // run: CSV with `t` first and the trajectory issue's columns, plus a JSON summary.
    let dir = tempdir("lang-run");
    let out = dir.join("signals.csv");
    let s = json(&["run", &scara, "--robot", "scara5", "--dt", "0.05", "--out", out.to_str().unwrap(), "--json"]);
    assert!((s["duration"].as_f64().unwrap() - 39.0).abs() < 1e-9);
    assert_eq!(s["motions"].as_array().unwrap().len(), 32);
    assert_eq!(s["final_q"].as_array().unwrap().len(), 5);
    assert_eq!(matrix(&s["final_pose"]["T"]).len(), 4);
    let csv = std::fs::read_to_string(&out).unwrap();
    let mut lines = csv.lines();
    assert!(lines.next().unwrap().starts_with("t,q1,q2,q3,q4,q5,qd1"), "{csv:.200}");
    assert_eq!(lines.count(), 39 * 20 + 1);
    // compile --listing: one line per motion with its source line.
    let r = kinema(&["compile", &scara, "--robot", "scara5", "--listing"]);
    assert!(r.ok, "{}", r.stderr);
    assert_eq!(r.stdout.lines().filter(|l| l.contains("MOVEXY")).count(), 6);
    let iiwa = program("iiwa_draw.prg");
    let r = kinema(&["compile", &iiwa, "--robot", "lbr-iiwa-14-r820", "--json"]);
    assert!(r.ok, "{}", r.stderr);
    let v: Value = serde_json::from_str(&r.stdout).unwrap();
    assert!(v["motions"].as_array().unwrap().iter().any(|m| m["kind"] == "CIRC"));
}

#[test]
fn language_errors_exit_non_zero_and_write_nothing() {
    let dir = tempdir("lang-err");
    let prog = dir.join("bad.txt");
    std::fs::write(&prog, "HOME 1\nMOVEXY 0, 900, 2\nWAIT 5mm\n").unwrap();
    let out = dir.join("signals.csv");
    let err = fails(&["run", prog.to_str().unwrap(), "--robot", "scara5", "--out", out.to_str().unwrap()]);
    assert!(err.contains("bad.txt:3:6: error: expected a time"), "{err}");
    assert!(err.contains("WAIT 5mm"), "{err}");
    assert!(!out.exists(), "no file on error");
    // The reachability error comes once the static errors are fixed.
    std::fs::write(&prog, "HOME 1\nMOVEXY 0, 900, 2\n").unwrap();
    let err = fails(&["check", prog.to_str().unwrap(), "--robot", "scara5"]);
    assert!(err.contains("bad.txt:2:1: error: MOVEXY") && err.contains("unreachable"), "{err}");
    // A SCARA program on another robot.
    let err = fails(&["check", &program("scara_pick_place.prg"), "--robot", "puma560"]);
    assert!(err.contains("MOVEXY is an instruction of the SCARA"), "{err}");
    // Not a text file, or no file.
    std::fs::write(&prog, [0xff, 0xfe, 0x00]).unwrap();
    assert!(fails(&["check", prog.to_str().unwrap(), "--robot", "scara5"]).contains("not UTF-8"));
    assert!(fails(&["check", "/nonexistent/prog", "--robot", "scara5"]).contains("cannot read"));
}

/// A program that computes for seconds within every limit of the language (~500 000 IK
/// solutions, no samples to speak of).
const LONG_PROGRAM: &str = "JACC 90 deg/s^2\nPTP CART(500mm, 0mm, 400mm, 0deg, 180deg, 0deg) IN 3s\nLOOP 499000\n  PTP CART(500mm, 0mm, 400mm, 0deg, 180deg, 0deg)\nEND\n";

#[test]
fn language_time_limit_stops_a_long_program_and_writes_nothing() {
    let dir = tempdir("lang-time-limit");
    let prog = dir.join("long.prg");
    std::fs::write(&prog, LONG_PROGRAM).unwrap();
    let out = dir.join("signals.csv");
    let start = std::time::Instant::now();
    let r = kinema(&[
        "run",
        prog.to_str().unwrap(),
        "--robot",
        "lbr-iiwa-14-r820",
        "--time-limit",
        "0.3",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!r.ok);
    assert!(start.elapsed() < std::time::Duration::from_secs(5), "{:?}", start.elapsed());
    assert!(r.stderr.contains("error: stopped here: the time budget of 0.300 s ran out"), "{}", r.stderr);
    assert!(r.stderr.contains("1 error(s)"), "{}", r.stderr);
    assert!(!out.exists(), "no file when stopped");
    assert!(fails(&["check", prog.to_str().unwrap(), "--robot", "scara5", "--time-limit=-1"]).contains("--time-limit"));
    assert!(r.stderr.contains("note: --time-limit sets the budget (default 120 s"), "{}", r.stderr);
}

/// Issue 35 item 4: a loop of blended LIN motions is one chain, timed as one
/// statement after the loop; the time limit now reaches inside that timing,
/// and `inf` lifts the (default) limit.
#[test]
fn the_time_limit_stops_a_long_blended_chain() {
    let dir = tempdir("lang-chain-limit");
    let prog = dir.join("chain.prg");
    let text = "POS above = CART(550mm, -150mm, 400mm, 0deg, 180deg, 0deg)\nPTP above\nFOR i = 1 TO 3000\n  \
                LIN REL CART(0mm, 10mm, 0mm) BLEND 2mm\n  LIN REL CART(0mm, -10mm, 0mm) BLEND 2mm\nEND\n";
    std::fs::write(&prog, text).unwrap();
    let start = std::time::Instant::now();
    let r = kinema(&["check", prog.to_str().unwrap(), "--robot", "lbr-iiwa-14-r820", "--time-limit", "0.5"]);
    assert!(!r.ok);
    assert!(start.elapsed() < std::time::Duration::from_secs(5), "{:?}", start.elapsed());
    assert!(r.stderr.contains("stopped here: the time budget of 0.500 s ran out"), "{}", r.stderr);
    let short = dir.join("short.prg");
    std::fs::write(&short, "WAIT 1s\n").unwrap();
    let r = kinema(&["check", short.to_str().unwrap(), "--robot", "scara5", "--time-limit", "inf"]);
    assert!(r.ok, "{}", r.stderr);
}

/// Ctrl-C (SIGINT) stops `kinema run` at the statement reached: "cancelled", exit code
/// 130, no output file.
#[cfg(unix)]
#[test]
fn language_ctrl_c_cancels_a_run_and_writes_nothing() {
    let dir = tempdir("lang-ctrl-c");
    let prog = dir.join("long.prg");
    std::fs::write(&prog, LONG_PROGRAM).unwrap();
    let out = dir.join("signals.csv");
    let child = Command::new(env!("CARGO_BIN_EXE_kinema"))
        .args(["run", prog.to_str().unwrap(), "--robot", "lbr-iiwa-14-r820", "--out", out.to_str().unwrap()])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(500));
    let start = std::time::Instant::now();
    let killed = Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert!(killed.success());
    let output = child.wait_with_output().unwrap();
    assert!(start.elapsed() < std::time::Duration::from_secs(3), "{:?}", start.elapsed());
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert_eq!(output.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("stopped here: the run was cancelled"), "{stderr}");
    assert!(stderr.contains("cancelled (Ctrl-C); nothing was written"), "{stderr}");
    assert!(!out.exists(), "no file when cancelled");
}

#[cfg(feature = "plot")]
#[test]
fn plot_writes_every_kind_of_picture_or_nothing() {
    let dir = tempdir("plot");
    let p = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let iiwa_q = "0.3,0.6,0.4,-1.2,0.3,0.9,0.1";
    let square = program("scorbot_square.prg");
    // Desired square and a measured run 2 mm outside it.
    std::fs::write(dir.join("desired.csv"), "x,y,z\n0,0,0\n0.1,0,0\n0.1,0.1,0\n0,0.1,0\n0,0,0\n").unwrap();
    std::fs::write(dir.join("measured.csv"), "x,y,z\n0.05,-0.002,0\n0.102,0.05,0\n0.05,0.102,0\n-0.002,0.05,0\n")
        .unwrap();
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec!["robot", "--robot", "scorbot-er-v-plus", "--q", "home"].into_iter().map(String::from).collect(), "a.svg"),
        (
            vec!["robot", "--robot", "lbr-iiwa-14-r820", "--q", iiwa_q, "--3d"].into_iter().map(String::from).collect(),
            "b.png",
        ),
        (vec!["workspace", "--robot", "scara5", "--samples", "20000"].into_iter().map(String::from).collect(), "c.png"),
        (vec!["ellipsoid", "--robot", "puma560", "--q", "qn"].into_iter().map(String::from).collect(), "d.svg"),
        (
            vec!["selfmotion", "--robot", "lbr-iiwa-14-r820", "--q", iiwa_q, "--steps", "90"]
                .into_iter()
                .map(String::from)
                .collect(),
            "e.png",
        ),
        (
            vec!["ik-error", "--robot", "lbr-iiwa-14-r820", "--cases", "300"].into_iter().map(String::from).collect(),
            "f.svg",
        ),
        (
            vec!["traj", "--robot", "scorbot-er-v-plus", "--program", &square, "--dt", "0.05", "--kind", "cartesian"]
                .into_iter()
                .map(String::from)
                .collect(),
            "g.png",
        ),
        (
            vec!["tracking".into(), "--desired".into(), p("desired.csv"), "--measured".into(), p("measured.csv")],
            "h.svg",
        ),
    ];
    for (args, file) in &cases {
        let mut all: Vec<&str> = vec!["plot"];
        all.extend(args.iter().map(String::as_str));
        let out = p(file);
        all.extend(["--out", &out, "--size", "700x500"]);
        let r = kinema(&all);
        assert!(r.ok, "kinema {all:?}: {}", r.stderr);
        let bytes = std::fs::read(&out).unwrap();
        if file.ends_with(".png") {
            let img = image::load_from_memory(&bytes).unwrap();
            assert_eq!((img.width(), img.height()), (700, 500), "{file}");
        } else {
            assert!(String::from_utf8(bytes).unwrap().starts_with("<svg"), "{file}");
        }
    }
    let r = kinema(&[
        "plot",
        "tracking",
        "--desired",
        &p("desired.csv"),
        "--measured",
        &p("measured.csv"),
        "--out",
        &p("t.svg"),
    ]);
    assert!(r.stderr.contains("tracking error 2.000 ± 0.000 mm"), "{}", r.stderr);
    // Errors: nothing is written, the message says what was wrong.
    let bad = p("bad.png");
    assert!(fails(&["plot", "robot", "--robot", "puma560", "--q", "1,2", "--out", &bad]).contains("joint"));
    assert!(
        fails(&["plot", "robot", "--robot", "puma560", "--q", "home", "--out", &p("x.pdf")]).contains(".svg or .png")
    );
    assert!(fails(&["plot", "robot", "--robot", "puma560", "--q", "home", "--out", &bad, "--size", "big"])
        .contains("WIDTHxHEIGHT"));
    assert!(fails(&["plot", "selfmotion", "--robot", "puma560", "--q", "home", "--out", &bad]).contains("puma560"));
    std::fs::write(dir.join("nan.csv"), "x,y,z\n0,nan,0\n").unwrap();
    assert!(fails(&["plot", "tracking", "--desired", &p("desired.csv"), "--measured", &p("nan.csv"), "--out", &bad])
        .contains("row 2"));
    assert!(!std::path::Path::new(&bad).exists());
    assert!(std::fs::read_dir(&dir).unwrap().all(|e| !e.unwrap().file_name().to_string_lossy().contains("kinema-tmp")));
}
