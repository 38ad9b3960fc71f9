//! End-to-end tests of the `kinema` binary.

use std::path::PathBuf;
use std::process::Command;

use kinema::{Frame, Robot};
use serde_json::Value;

use crate::common;

use common::kinema;

/// Runs `kinema` expecting success and JSON on stdout.
pub(super) fn json(args: &[&str]) -> Value {
    let r = kinema(args);
    assert!(r.ok, "kinema {args:?} failed: {}", r.stderr);
    serde_json::from_str(&r.stdout).unwrap_or_else(|e| panic!("kinema {args:?}: not JSON ({e}): {}", r.stdout))
}

/// Runs `kinema` expecting failure; returns stderr.
pub(super) fn fails(args: &[&str]) -> String {
    let r = kinema(args);
    assert!(!r.ok, "kinema {args:?} should fail, printed {}", r.stdout);
    assert!(!r.stderr.trim().is_empty(), "kinema {args:?} failed silently");
    r.stderr
}

pub(super) fn data(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../kinema/tests/data").join(name).display().to_string()
}

pub(super) fn matrix(v: &Value) -> Vec<Vec<f64>> {
    v.as_array().unwrap().iter().map(|r| r.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()).collect()
}

/// A fresh directory for one test's files, removed when the test ends (pass or fail).
pub(super) struct TestDir(tempfile::TempDir);

impl std::ops::Deref for TestDir {
    type Target = std::path::Path;

    fn deref(&self) -> &std::path::Path {
        self.0.path()
    }
}

impl AsRef<std::path::Path> for TestDir {
    fn as_ref(&self) -> &std::path::Path {
        self.0.path()
    }
}

pub(super) fn tempdir(tag: &str) -> TestDir {
    TestDir(tempfile::Builder::new().prefix(&format!("kinema-cli-test-{tag}-")).tempdir().unwrap())
}

#[test]
fn robots_lists_the_catalogue() {
    let r = kinema(&["robots"]);
    assert!(r.ok);
    for name in kinema::builtin_names() {
        assert!(r.stdout.contains(name), "{name} missing from\n{}", r.stdout);
    }
    let v = json(&["robots", "--json"]);
    let list = v.as_array().unwrap();
    assert_eq!(list.len(), kinema::builtin_names().count());
    let scara = list.iter().find(|r| r["name"] == "scara5").unwrap();
    assert_eq!(scara["dof"], 5);
    assert_eq!(scara["joint_types"], "PRRPR");
}

#[test]
fn info_shows_table_limits_and_poses() {
    let r = kinema(&["info", "--robot", "scorbot-er-v-plus"]);
    assert!(r.ok, "{}", r.stderr);
    for needle in ["shoulder", "349", "-155", "home", "qz", "Tabla I"] {
        assert!(r.stdout.contains(needle), "`{needle}` missing:\n{}", r.stdout);
    }
    let v = json(&["info", "--robot", "panda", "--json"]);
    assert_eq!(v["dof"], 7);
    assert_eq!(v["convention"], "modified");
    assert!((v["joints"][3]["max"].as_f64().unwrap() + 0.0698).abs() < 1e-12);
    assert!((v["tool"]["position"][2].as_f64().unwrap() - 0.103).abs() < 1e-12);
    // Motor limits in N·m, from Franka's τ_max.
    assert_eq!(v["joints"][0]["effort"], 87.0);
    assert_eq!(v["joints"][6]["effort"], 12.0);
    let ur5 = kinema(&["info", "--robot", "ur5"]);
    assert!(ur5.stdout.contains("effort 150") && ur5.stdout.contains("effort 28"), "{}", ur5.stdout);
    // Text output of a general (URDF) robot prints its joint frames.
    let u = kinema(&["info", "--robot", &data("iiwa14.urdf")]);
    assert!(u.ok && u.stdout.contains("axis"), "{}{}", u.stdout, u.stderr);
}

#[test]
fn fk_json_matches_the_library() {
    let v = json(&["fk", "--robot", "lbr-iiwa-14-r820", "--q", "home", "--json"]);
    let t = matrix(&v["T"]);
    assert_eq!(t.len(), 4);
    assert!((t[2][3] - 1.306).abs() < 1e-12);
    assert_eq!(t[3], vec![0.0, 0.0, 0.0, 1.0]);
    assert_eq!(v["within_limits"], true);
    assert!((v["position"][2].as_f64().unwrap() - 1.306).abs() < 1e-12);

    let robot = Robot::builtin("ur5").unwrap();
    let q = [0.3, -1.2, 1.1, -0.4, 0.9, 2.0];
    let qs = q.iter().map(|x| x.to_string()).collect::<Vec<_>>().join(",");
    let v = json(&["fk", "--robot", "ur5", "--q", &qs, "--json"]);
    let pose = robot.fk(&q).unwrap().world_from_tool;
    let rows = pose.to_rows();
    let t = matrix(&v["T"]);
    for r in 0..4 {
        for c in 0..4 {
            assert!((t[r][c] - rows[r][c]).abs() < 1e-12);
        }
    }
    let rpy = pose.rpy(kinema::RpyConvention::Zyx);
    for k in 0..3 {
        assert!((v["rpy"][k].as_f64().unwrap() - rpy[k]).abs() < 1e-12);
    }
    // The other roll-pitch-yaw convention on request.
    let x = json(&["fk", "--robot", "ur5", "--q", &qs, "--json", "--rpy", "xyz"]);
    assert_eq!(x["rpy_convention"], "xyz");
    let rxyz = pose.rpy(kinema::RpyConvention::Xyz);
    assert!((x["rpy"][1].as_f64().unwrap() - rxyz[1]).abs() < 1e-12);
}

#[test]
fn fk_degrees_and_negative_values() {
    let deg = json(&["fk", "--robot", "scara5", "--q", "0.5,-30,60,0.05,-90", "--deg", "--json"]);
    let rad = json(&[
        "fk",
        "--robot",
        "scara5",
        "--q",
        &format!("0.5,{},{},0.05,{}", (-30f64).to_radians(), 60f64.to_radians(), (-90f64).to_radians()),
        "--json",
    ]);
    let (a, b) = (matrix(&deg["T"]), matrix(&rad["T"]));
    for r in 0..4 {
        for c in 0..4 {
            assert!((a[r][c] - b[r][c]).abs() < 1e-12);
        }
    }
    // Prismatic values stay in metres under --deg: y = L1 s2 + L2 s23 + q1.
    let y = 0.35 * (-30f64).to_radians().sin() + 0.25 * 30f64.to_radians().sin() + 0.5;
    assert!((a[1][3] - y).abs() < 1e-12);
}

#[test]
fn fk_flags_joints_outside_their_limits() {
    let v = json(&["fk", "--robot", "lbr-iiwa-14-r820", "--q", "0,0,0,2.5,0,0,0", "--json"]);
    assert_eq!(v["within_limits"], false);
    assert_eq!(v["out_of_limits"][0]["joint"], 4);
    assert_eq!(v["out_of_limits"][0]["name"], "A4");
    let text = kinema(&["fk", "--robot", "lbr-iiwa-14-r820", "--q", "0,0,0,2.5,0,0,0"]);
    assert!(text.ok && text.stdout.contains("joint 4 (A4)"), "{}", text.stdout);
}

#[test]
fn fk_from_files_and_urdf_tip() {
    let a = json(&["fk", "--robot", &data("iiwa14.urdf"), "--q", "0.1,0.2,0.3,0.4,0.5,0.6,0.7", "--json"]);
    let b = json(&["fk", "--robot", &data("iiwa-modified.toml"), "--q", "0.1,0.2,0.3,0.4,0.5,0.6,0.7", "--json"]);
    let (ta, tb) = (matrix(&a["T"]), matrix(&b["T"]));
    for r in 0..3 {
        for c in 0..4 {
            assert!((ta[r][c] - tb[r][c]).abs() < 1e-12);
        }
    }
    let e = fails(&["fk", "--robot", &data("two-leaves.urdf"), "--q", "0"]);
    assert!(e.contains("leaf_a") && e.contains("--tip"), "{e}");
    let tip = kinema(&["fk", "--robot", &data("two-leaves.urdf"), "--tip", "leaf_a", "--q", "home"]);
    assert!(tip.ok, "{}", tip.stderr);
}

/// Issue 34, items 11 and 12: a ROS-Industrial-style URDF loads without
/// `--tip`; a non-physical inertial off the chain is a warning on stderr, on
/// the chain an error.
#[test]
fn urdf_from_the_wild_tip_and_warnings() {
    let r = kinema(&["fk", "--robot", &data("ros-industrial.urdf"), "--q", "0,0,0", "--json"]);
    assert!(r.ok && r.stderr.is_empty(), "{}", r.stderr);
    let t = matrix(&serde_json::from_str::<Value>(&r.stdout).unwrap()["T"]);
    assert!((t[0][3] - 0.9).abs() < 1e-12 && (t[2][3] - 0.4).abs() < 1e-12, "{t:?}");

    let r = kinema(&["info", "--robot", &data("off-chain-inertia.urdf"), "--tip", "r_tool"]);
    assert!(r.ok, "{}", r.stderr);
    let warnings: Vec<&str> = r.stderr.lines().filter(|l| l.starts_with("warning: ")).collect();
    assert_eq!(warnings.len(), 2, "{}", r.stderr);
    assert!(warnings.iter().any(|w| w.contains("`sensor_mount` (off the chain")), "{}", r.stderr);
    assert!(!r.stdout.contains("warning"), "warnings go to stderr: {}", r.stdout);
    let e = fails(&["info", "--robot", &data("off-chain-inertia.urdf"), "--tip", "l_tool"]);
    assert!(e.contains("`l_arm` (on the chain)"), "{e}");
}

#[test]
fn fk_batch_file_round_trip_and_atomic_failure() {
    let dir = tempdir("batch");
    let robot = Robot::builtin("puma560").unwrap();
    let qs = [[0.1, 0.2, -0.3, 0.4, 0.5, 0.6], [0.0, 1.0, -1.0, 0.0, 0.5, 0.0], [-0.5, 0.3, -2.0, 1.0, -1.0, 2.0]];
    let mut text = String::from("q1,q2,q3,q4,q5,q6\n# a comment\n");
    for q in &qs {
        text += &q.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(",");
        text += "\n";
    }
    let input = dir.join("q.csv");
    let output = dir.join("poses.csv");
    std::fs::write(&input, &text).unwrap();
    let r =
        kinema(&["fk", "--robot", "puma560", "--input", input.to_str().unwrap(), "--output", output.to_str().unwrap()]);
    assert!(r.ok, "{}", r.stderr);
    let out = std::fs::read_to_string(&output).unwrap();
    let mut lines = out.lines();
    assert!(lines.next().unwrap().starts_with("x,y,z,roll,pitch,yaw"));
    for (line, q) in lines.zip(&qs) {
        let f: Vec<&str> = line.split(',').collect();
        let p = robot.fk(q).unwrap().world_from_tool;
        for (k, field) in f.iter().take(3).enumerate() {
            assert!((field.parse::<f64>().unwrap() - p.pos[k]).abs() < 1e-9, "{line}");
        }
        assert_eq!(f[10], "true");
    }
    // A bad line fails with its line number and leaves no output behind; an
    // existing output file is not touched.
    std::fs::write(&input, format!("{text}0.1,0.2,oops,0.4,0.5,0.6\n")).unwrap();
    let before = std::fs::read_to_string(&output).unwrap();
    let e =
        fails(&["fk", "--robot", "puma560", "--input", input.to_str().unwrap(), "--output", output.to_str().unwrap()]);
    assert!(e.contains("line 6"), "{e}");
    assert_eq!(std::fs::read_to_string(&output).unwrap(), before);
    let fresh = dir.join("fresh.csv");
    std::fs::write(&input, "0.1,0.2\n").unwrap();
    let e =
        fails(&["fk", "--robot", "puma560", "--input", input.to_str().unwrap(), "--output", fresh.to_str().unwrap()]);
    assert!(e.contains("2 values") && e.contains("6 joints"), "{e}");
    assert!(!fresh.exists());
    std::fs::write(&input, "0.1,0.2,NaN,0,0,0\n").unwrap();
    let e =
        fails(&["fk", "--robot", "puma560", "--input", input.to_str().unwrap(), "--output", fresh.to_str().unwrap()]);
    assert!(e.contains("line 1") && e.contains("finite"), "{e}");
    assert!(!fresh.exists());
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains("tmp"))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left behind");
}

#[test]
fn jacobian_json_base_tool_and_analytic() {
    let robot = Robot::builtin("panda").unwrap();
    let q = robot.pose("qr").unwrap().to_vec();
    let v = json(&["jacobian", "--robot", "panda", "--q", "qr", "--json"]);
    let j = matrix(&v["J"]);
    assert_eq!((j.len(), j[0].len()), (6, 7));
    let lib = robot.jacobian(&q, Frame::Base).unwrap();
    for r in 0..6 {
        for c in 0..7 {
            assert!((j[r][c] - lib[(r, c)]).abs() < 1e-12);
        }
    }
    let t = matrix(&json(&["jacobian", "--robot", "panda", "--q", "qr", "--frame", "tool", "--json"])["J"]);
    let lib_t = robot.jacobian(&q, Frame::Tool).unwrap();
    assert!((t[4][2] - lib_t[(4, 2)]).abs() < 1e-12);
    let a = json(&["jacobian", "--robot", "panda", "--q", "qr", "--analytic", "zyx", "--json"]);
    assert_eq!(matrix(&a["J"]).len(), 6);
    // Linear rows of the analytic Jacobian are the geometric ones.
    assert!((matrix(&a["J"])[1][3] - lib[(1, 3)]).abs() < 1e-12);
}

#[test]
fn manip_reports_seed004_singularities() {
    for (pose, rank) in [("sing-q4", 5), ("sing-q2-q3", 5), ("sing-coupled", 4), ("fig9", 6)] {
        let v = json(&["manip", "--robot", "lbr-iiwa-14-r820", "--q", pose, "--json"]);
        assert_eq!(v["rank"], rank, "{pose}");
        for key in [
            "yoshikawa",
            "yoshikawa_translation",
            "yoshikawa_rotation",
            "condition",
            "singular_values",
            "dependent_joints",
        ] {
            assert!(v.get(key).is_some(), "{pose}: no `{key}`");
        }
        assert_eq!(v["singular_values"].as_array().unwrap().len(), 6);
        if rank < 6 {
            assert!(v["yoshikawa"].as_f64().unwrap() < 1e-9, "{pose}");
        }
    }
    let v = json(&["manip", "--robot", "lbr-iiwa-14-r820", "--q", "sing-coupled", "--json"]);
    let deps = v["dependent_joints"].as_array().unwrap();
    let q3 = deps.iter().find(|d| d["joint"] == 3).expect("q3 depends on q1 at sing-coupled");
    assert_eq!(q3["depends_on"][0]["joint"], 1);
    let text = kinema(&["manip", "--robot", "lbr-iiwa-14-r820", "--q", "sing-coupled"]);
    assert!(text.stdout.contains("q3 depends on"), "{}", text.stdout);
    let d = json(&["manip", "--robot", "lbr-iiwa-14-r820", "--q", "fig9", "--direction", "-0.4,0.5,0.75", "--json"]);
    assert!(d["manipulability_along"].as_f64().unwrap() > 0.0);
}

#[test]
fn bench_prints_timings() {
    let v = json(&["bench", "--robot", "ur5", "--n", "5000", "--json"]);
    for key in ["fk_ns", "jacobian_ns", "fk_batch_ns_per_config"] {
        let x = v[key].as_f64().unwrap_or_else(|| panic!("no {key}"));
        assert!(x > 0.0 && x.is_finite(), "{key} = {x}");
    }
    assert_eq!(v["configurations"], 5000);
    let e = fails(&["bench", "--robot", "ur5", "--n", "10"]);
    assert!(e.contains("at least"), "{e}");
}

#[test]
fn bad_input_is_a_clear_error() {
    let e = fails(&["fk", "--robot", "r2d2", "--q", "0"]);
    assert!(e.contains("unknown robot `r2d2`") && e.contains("lbr-iiwa-14-r820"), "{e}");
    let e = fails(&["fk", "--robot", "ur5", "--q", "1,2,3"]);
    assert!(e.contains("6 joints") && e.contains("3 joint values"), "{e}");
    let e = fails(&["fk", "--robot", "ur5", "--q", "1,2,3,NaN,5,6"]);
    assert!(e.contains("joint 4") && e.contains("finite"), "{e}");
    let e = fails(&["fk", "--robot", "ur5", "--q", "1,2,x,4,5,6"]);
    assert!(e.contains("`x` is not a number"), "{e}");
    let e = fails(&["fk", "--robot", "ur5", "--q", "ready"]);
    assert!(e.contains("no named pose `ready`") && e.contains("home"), "{e}");
    let e = fails(&["fk", "--robot", &data("malformed.toml"), "--q", "home"]);
    assert!(e.contains("malformed.toml:"), "{e}");
    let e = fails(&["fk", "--robot", "/nonexistent/robot.urdf", "--q", "home"]);
    assert!(e.contains("cannot read"), "{e}");
    let e = fails(&["jacobian", "--robot", "ur5", "--q", "1,2,3,4,5,6", "--frame", "world"]);
    assert!(e.contains("world"), "{e}");
    let e = fails(&["manip", "--robot", "ur5", "--q", "home", "--direction", "1,2"]);
    assert!(e.contains("3 components"), "{e}");
    let e = fails(&["fk", "--robot", "ur5"]);
    assert!(e.contains("--q"), "{e}");
}

/// Runs `kinema` and returns its exit code and stdout.
pub(super) fn exit_and_stdout(args: &[&str]) -> (Option<i32>, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_kinema")).args(args).output().unwrap();
    (out.status.code(), String::from_utf8_lossy(&out.stdout).into_owned())
}

/// The analytic Jacobian's lower rows are roll-pitch-yaw rates and are
/// labelled so; the geometric one's are ω.
#[test]
fn jacobian_rows_are_labelled_by_what_they_are() {
    let analytic = kinema(&["jacobian", "--robot", "ur5", "--q", "home", "--analytic", "zyx"]);
    assert!(analytic.ok, "{}", analytic.stderr);
    assert!(analytic.stdout.contains("rows vx vy vz roll' pitch' yaw'"), "{}", analytic.stdout);
    assert!(!analytic.stdout.contains('ω'), "{}", analytic.stdout);
    let geometric = kinema(&["jacobian", "--robot", "ur5", "--q", "home"]);
    assert!(geometric.stdout.contains("rows vx vy vz ωx ωy ωz") && geometric.stdout.contains("  ωz ["));
}
