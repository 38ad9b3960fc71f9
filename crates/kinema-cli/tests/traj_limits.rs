//! `kinema traj`: limits too extreme to plan with, and `traj check` on what
//! q itself says — the same cases as the core, Python and /api/traj tests.

use serde_json::Value;

mod common;

use common::kinema;

fn tempdir(tag: &str) -> tempfile::TempDir {
    tempfile::Builder::new().prefix(&format!("kinema-traj-{tag}-")).tempdir().unwrap()
}

#[test]
fn limits_that_vanish_or_overflow_the_duration_are_errors() {
    let r =
        kinema(&["traj", "ptp", "-r", "puma560", "--from", "qz", "--to", "qr", "--vmax", "1e100", "--amax", "1e100"]);
    assert!(!r.ok && r.stderr.contains("shorter than"), "{} {}", r.stdout, r.stderr);
    assert!(r.stdout.is_empty(), "nothing is printed: {}", r.stdout);
    for args in [
        &["traj", "law", "--profile", "scurve", "--vmax", "1", "--amax", "1", "--jmax", "1e-300"][..],
        &["traj", "law", "--distance", "1e308", "--vmax", "0.5", "--amax", "1", "--json"][..],
    ] {
        let r = kinema(args);
        assert!(!r.ok && r.stderr.contains("overflows"), "{args:?}: {} {}", r.stdout, r.stderr);
    }
}

#[test]
fn the_pandas_trapezoid_is_refused_and_its_scurve_planned() {
    let (from, to) = ("0,-0.3,0,-2.2,0,2.0,0.785", "0.5,-0.3,0.2,-2.0,0.1,1.8,0.6");
    let r = kinema(&["traj", "ptp", "-r", "panda", "--from", from, "--to", to]);
    assert!(!r.ok && r.stderr.contains("jerk limit") && r.stderr.contains("scurve"), "{}", r.stderr);
    let r = kinema(&["traj", "ptp", "-r", "panda", "--from", from, "--to", to, "--profile", "scurve"]);
    assert!(r.ok, "{}", r.stderr);
}

/// A 7.4 mrad one-sample glitch in q with untouched q̇/q̈ columns passed
/// `traj check`; it is now found. The clean file passes, and a singular
/// passage is a warning by default.
#[test]
fn traj_check_finds_a_glitch_in_q_and_warns_of_singular_passages() {
    let dir = tempdir("check");
    let clean = dir.path().join("clean.csv");
    let q_obj = "-0.1090,1.2417,0.4463,1.9156,-0.9695,-1.8728,0.4876";
    let r = kinema(&[
        "traj",
        "ptp",
        "-r",
        "lbr-iiwa-14-r820",
        "--from",
        "home",
        "--to",
        q_obj,
        "--profile",
        "scurve",
        "--amax",
        "2",
        "--jmax",
        "15",
        "--out",
        clean.to_str().unwrap(),
    ]);
    assert!(r.ok, "{}", r.stderr);
    let check = |file: &std::path::Path| {
        let r = kinema(&["traj", "check", "-r", "lbr-iiwa-14-r820", "--amax", "2", "--json", file.to_str().unwrap()]);
        let v: Value = serde_json::from_str(&r.stdout).unwrap_or_else(|e| panic!("{e}: {} {}", r.stdout, r.stderr));
        (r.code, v)
    };
    let (code, v) = check(&clean);
    assert_eq!(code, Some(0), "{v}");
    assert_eq!(v["violations"].as_array().unwrap().len(), 0);

    let text = std::fs::read_to_string(&clean).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let k = lines.len() / 3;
    let mut cells: Vec<String> = lines[k].split(',').map(str::to_string).collect();
    cells[2] = format!("{:.12}", cells[2].parse::<f64>().unwrap() + 0.0074); // q2
    lines[k] = cells.join(",");
    let glitched = dir.path().join("glitch.csv");
    std::fs::write(&glitched, lines.join("\n") + "\n").unwrap();
    let (code, v) = check(&glitched);
    assert_eq!(code, Some(1), "{v}");
    let kinds: Vec<&str> = v["violations"].as_array().unwrap().iter().map(|x| x["kind"].as_str().unwrap()).collect();
    assert!(kinds.contains(&"inconsistent"), "{kinds:?}");

    // Through the stretched elbow (q4 = 0, Cuadro III): a warning, exit 0.
    let through = dir.path().join("through.csv");
    let r = kinema(&[
        "traj",
        "ptp",
        "-r",
        "lbr-iiwa-14-r820",
        "--from",
        "0.2,0.5,0.1,-0.5,0.3,0.8,0",
        "--to",
        "0.2,0.5,0.1,0.5,0.3,0.8,0",
        "--profile",
        "quintic",
        "--amax",
        "2",
        "--dt",
        "0.001",
        "--out",
        through.to_str().unwrap(),
    ]);
    assert!(r.ok, "{}", r.stderr);
    let (code, v) = check(&through);
    assert_eq!(code, Some(0), "{v}");
    let warnings = v["warnings"].as_array().unwrap();
    assert_eq!(warnings.len(), 1, "{v}");
    assert_eq!(warnings[0]["kind"], "singular");
}
