//! `kinema cell FILE`: several robots on a common clock (seed 004 §VIII-E).
//! Numbers are checked against computations of the test's own: world tool
//! positions as base · FK of the q columns, distances and their minimum by
//! brute force over the CSV.

use std::path::{Path, PathBuf};

use kinema::math::rot_z;
use kinema::nalgebra::Vector3;
use kinema::{Pose, Robot};
use serde_json::Value;

use crate::common;

use crate::mutate;

use common::kinema;

fn tempdir(tag: &str) -> tempfile::TempDir {
    tempfile::Builder::new().prefix(&format!("kinema-cell-{tag}-")).tempdir().unwrap()
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn seed_cell() -> String {
    repo().join("examples/cells/seed004_two_iiwa.toml").display().to_string()
}

/// A CSV with a header: the names and the rows of numbers.
fn read_csv(text: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut lines = text.lines();
    let head: Vec<String> = lines.next().unwrap().split(',').map(str::to_string).collect();
    let rows: Vec<Vec<f64>> =
        lines.map(|l| l.split(',').map(|v| v.parse::<f64>().unwrap()).collect::<Vec<f64>>()).collect();
    assert!(rows.iter().all(|r| r.len() == head.len()));
    (head, rows)
}

fn col(head: &[String], name: &str) -> usize {
    head.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name} in {head:?}"))
}

/// The world tool positions of `name` in every row: base · FK(q), computed here.
fn check_tool_positions(head: &[String], rows: &[Vec<f64>], name: &str, robot: &Robot, base: &Pose) {
    let q0 = col(head, &format!("{name}_q1"));
    let x = col(head, &format!("{name}_x"));
    for row in rows {
        let q = &row[q0..q0 + robot.dof()];
        let want = base.transform_point(&robot.fk(q).unwrap().world_from_tool.pos);
        let got = Vector3::new(row[x], row[x + 1], row[x + 2]);
        assert!((got - want).norm() < 1e-9, "{name} at t = {}: {got} against {want}", row[0]);
    }
}

/// The distance column of `a`–`b` against the positions, and its minimum.
fn brute_force_closest(head: &[String], rows: &[Vec<f64>], a: &str, b: &str) -> (f64, f64) {
    let (xa, xb, d) = (col(head, &format!("{a}_x")), col(head, &format!("{b}_x")), col(head, &format!("d_{a}_{b}")));
    let mut best = (f64::NAN, f64::INFINITY);
    for row in rows {
        let pa = Vector3::new(row[xa], row[xa + 1], row[xa + 2]);
        let pb = Vector3::new(row[xb], row[xb + 1], row[xb + 2]);
        let dist = (pa - pb).norm();
        assert!((row[d] - dist).abs() < 1e-9, "t = {}", row[0]);
        if dist < best.1 {
            best = (row[0], dist);
        }
    }
    best
}

#[test]
fn the_seed_cell_agrees_with_fk_and_a_brute_force_minimum() {
    let dir = tempdir("seed");
    let out = dir.path().join("cell.csv");
    let r = kinema(&["cell", &seed_cell(), "--out", out.to_str().unwrap(), "--json"]);
    assert!(r.ok, "{}", r.stderr);
    let summary: Value = serde_json::from_str(&r.stdout).unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    let (head, rows) = read_csv(&text);
    let iiwa = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    check_tool_positions(&head, &rows, "holder", &iiwa, &Pose::IDENTITY);
    let drawer_base = Pose::new(rot_z(std::f64::consts::PI), Vector3::new(1.2, 0.0, 0.0));
    check_tool_positions(&head, &rows, "drawer", &iiwa, &drawer_base);
    let (t, d) = brute_force_closest(&head, &rows, "holder", "drawer");
    let pair = &summary["pairs"][0];
    assert_eq!(pair["robots"], serde_json::json!(["holder", "drawer"]));
    assert!((pair["closest"]["distance"].as_f64().unwrap() - d).abs() < 1e-9, "{pair}");
    assert!((pair["closest"]["t"].as_f64().unwrap() - t).abs() < 1e-9, "{pair}");
    // The file's minimum (100 mm) holds; the tools stay apart.
    assert!(d > 0.1 && pair["ok"] == true && summary["ok"] == true, "{summary}");
    assert_eq!(summary["min_distance"], 0.1);
    // A common clock every 0.01 s to the longer program's end; the holder
    // finishes first and holds its last configuration.
    let (end_h, end_d) = (summary["robots"][0]["end"].as_f64().unwrap(), summary["robots"][1]["end"].as_f64().unwrap());
    assert!(end_h < end_d - 0.5, "{end_h} {end_d}");
    assert_eq!(summary["samples"].as_u64().unwrap() as usize, rows.len());
    assert!(
        (rows.last().unwrap()[0] - end_d).abs() < 1e-9 && (summary["duration"].as_f64().unwrap() - end_d).abs() < 1e-12
    );
    for w in rows.windows(2) {
        assert!(w[1][0] - w[0][0] <= 0.01 + 1e-9);
    }
    let q0 = col(&head, "holder_q1");
    let held: Vec<&Vec<f64>> = rows.iter().filter(|r| r[0] >= end_h).collect();
    assert!(held.len() > 50);
    for r in &held {
        assert_eq!(r[q0..q0 + 7], held[0][q0..q0 + 7]);
    }
    // Each program passed its check (a singular start is a warning, not a violation).
    for robot in summary["robots"].as_array().unwrap() {
        assert_eq!(robot["check"]["ok"], true, "{robot}");
        assert_eq!(robot["check"]["violations"].as_array().unwrap().len(), 0);
        assert!(robot["program"].as_str().unwrap().ends_with(".prg"));
    }
    // The holder turns the part in place: its tool stays at (0.55, 0, 0.6)
    // once the PTP has brought it there.
    let x = col(&head, "holder_x");
    let last = rows.last().unwrap();
    assert!((Vector3::new(last[x], last[x + 1], last[x + 2]) - Vector3::new(0.55, 0.0, 0.6)).norm() < 1e-6);
    // The drawer's circle: 5 cm about the part's axis at x = 0.67 m.
    let x = col(&head, "drawer_x");
    let on_circle = rows
        .iter()
        .filter(|r| r[0] > 3.0 && r[0] < end_d - 0.5)
        .map(|r| ((r[x] - 0.67).abs(), (r[x + 1].hypot(r[x + 2] - 0.6) - 0.05).abs()))
        .fold(0.0f64, |m, (a, b)| m.max(a).max(b));
    assert!(on_circle < 2e-3, "{on_circle}");

    // The same report as text, with the same closest approach.
    let r = kinema(&["cell", &seed_cell()]);
    assert!(r.ok, "{}", r.stderr);
    assert!(
        r.stdout.contains(&format!("closest {d:.4} m")) && r.stdout.contains("holds its last configuration"),
        "{}",
        r.stdout
    );
    // `--out -`: the same CSV on standard output, nothing else there.
    let r = kinema(&["cell", &seed_cell(), "--out", "-"]);
    assert!(r.ok, "{}", r.stderr);
    assert_eq!(r.stdout, text);
    let r = kinema(&["cell", &seed_cell(), "--out", "-", "--json"]);
    assert!(!r.ok && r.code == Some(1) && r.stderr.contains("--json with --out -"), "{}", r.stderr);
}

#[test]
fn tools_closer_than_the_minimum_exit_with_code_3() {
    let dir = tempdir("close");
    let out = dir.path().join("cell.csv");
    let r = kinema(&["cell", &seed_cell(), "--min-distance", "200mm", "--json", "--out", out.to_str().unwrap()]);
    assert_eq!(r.code, Some(3), "{} {}", r.stdout, r.stderr);
    assert!(r.stderr.contains("`holder` and `drawer`") && r.stderr.contains("0.2 m"), "{}", r.stderr);
    let summary: Value = serde_json::from_str(&r.stdout).unwrap();
    assert_eq!(summary["ok"], false);
    let spans = summary["pairs"][0]["closer_than_minimum"].as_array().unwrap();
    assert!(!spans.is_empty());
    // The report is still written, so the approach can be looked at; every
    // sample inside a span is below 0.2 m, every one outside is not.
    let (head, rows) = read_csv(&std::fs::read_to_string(&out).unwrap());
    let d = col(&head, "d_holder_drawer");
    for row in &rows {
        let inside = spans
            .iter()
            .any(|s| s["from"].as_f64().unwrap() - 1e-9 <= row[0] && row[0] <= s["to"].as_f64().unwrap() + 1e-9);
        assert_eq!(inside, row[d] < 0.2, "t = {}", row[0]);
    }
    // A copy of the seed's file with min_distance = 0.2 m in it does the same.
    let text = std::fs::read_to_string(seed_cell()).unwrap().replace("\"100mm\"", "0.2");
    let cell = dir.path().join("close.toml");
    std::fs::write(&cell, text).unwrap();
    for prg in ["seed004_holder.prg", "seed004_drawer.prg"] {
        std::fs::copy(repo().join("examples/cells").join(prg), dir.path().join(prg)).unwrap();
    }
    let r = kinema(&["cell", cell.to_str().unwrap()]);
    assert_eq!(r.code, Some(3), "{} {}", r.stdout, r.stderr);
    assert!(r.stdout.contains("closer than 0.2 m during"), "{}", r.stdout);
    // …and passes with the flag lowering it.
    let r = kinema(&["cell", cell.to_str().unwrap(), "--min-distance", "0.05"]);
    assert!(r.ok, "{}", r.stderr);
    let r = kinema(&["cell", cell.to_str().unwrap(), "--min-distance", "5furlong"]);
    assert_eq!(r.code, Some(64), "{}", r.stderr);
    assert!(r.stderr.contains("unknown unit `furlong`"), "{}", r.stderr);
}

/// Two trajectory CSVs of different lengths and joint counts (`kinema traj ptp`).
fn two_ptp_files(dir: &Path) {
    for (file, robot, to, speed) in [
        ("ur5.csv", "ur5", "0.5,-1.2,1.0,-0.5,1.2,0.3", "100"),
        ("scorbot.csv", "scorbot-er-v-plus", "0.4,0.3,-0.4,-0.3,0.5", "40"),
    ] {
        let out = dir.join(file);
        let r = kinema(&[
            "traj",
            "ptp",
            "-r",
            robot,
            "--from",
            "home",
            "--to",
            to,
            "--speed",
            speed,
            "--vmax",
            "1",
            "--amax",
            "2",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(r.ok, "{}", r.stderr);
    }
}

#[test]
fn trajectory_files_of_different_lengths_hold_at_their_end() {
    let dir = tempdir("csv");
    two_ptp_files(dir.path());
    std::fs::create_dir(dir.path().join("arms")).unwrap();
    std::fs::copy(repo().join("robots/ur5.toml"), dir.path().join("arms/ur5.toml")).unwrap();
    let cell = dir.path().join("cell.toml");
    std::fs::write(
        &cell,
        r#"
dt = "20ms"
[[robot]]
name = "ur"
robot = "arms/ur5.toml"
trajectory = "ur5.csv"
[[robot]]
name = "scorbot"
robot = "scorbot-er-v-plus"
base = { xyz = [1, "-200mm", 0.1], rpy = [0, 0, "90deg"] }
trajectory = "scorbot.csv"
"#,
    )
    .unwrap();
    let out = dir.path().join("report.csv");
    let r = kinema(&["cell", cell.to_str().unwrap(), "--out", out.to_str().unwrap(), "--json"]);
    assert!(r.ok, "{}", r.stderr);
    let summary: Value = serde_json::from_str(&r.stdout).unwrap();
    let (head, rows) = read_csv(&std::fs::read_to_string(&out).unwrap());
    let ur5 = Robot::builtin("ur5").unwrap();
    let scorbot = Robot::builtin("scorbot-er-v-plus").unwrap();
    check_tool_positions(&head, &rows, "ur", &ur5, &Pose::IDENTITY);
    let base = Pose::new(rot_z(std::f64::consts::FRAC_PI_2), Vector3::new(1.0, -0.2, 0.1));
    check_tool_positions(&head, &rows, "scorbot", &scorbot, &base);
    let (t, d) = brute_force_closest(&head, &rows, "ur", "scorbot");
    assert!((summary["pairs"][0]["closest"]["distance"].as_f64().unwrap() - d).abs() < 1e-9);
    assert!((summary["pairs"][0]["closest"]["t"].as_f64().unwrap() - t).abs() < 1e-9);
    assert_eq!(head.len(), 1 + (6 + 4) + (5 + 4) + 1);
    // The slower Scorbot sets the clock; the UR5's q, from its own file, is held after its end.
    let (_, ur_rows) = read_csv(&std::fs::read_to_string(dir.path().join("ur5.csv")).unwrap());
    let (_, sc_rows) = read_csv(&std::fs::read_to_string(dir.path().join("scorbot.csv")).unwrap());
    let (ur_end, sc_end) = (ur_rows.last().unwrap()[0], sc_rows.last().unwrap()[0]);
    assert!(ur_end < sc_end);
    assert!((rows.last().unwrap()[0] - sc_end).abs() < 1e-9);
    assert!((summary["robots"][0]["end"].as_f64().unwrap() - ur_end).abs() < 1e-9);
    let q = col(&head, "ur_q1");
    for row in &rows {
        // Samples every 20 ms fall on every second sample of the 10 ms file.
        let k = ((row[0] / 0.01).round() as usize).min(ur_rows.len() - 1);
        if row[0] <= ur_end + 1e-9 {
            assert!((row[0] - ur_rows[k][0]).abs() < 1e-9, "t = {}", row[0]);
        }
        for j in 0..6 {
            assert!((row[q + j] - ur_rows[k][1 + j]).abs() < 1e-9, "t = {}, q{}", row[0], j + 1);
        }
    }
    assert!(summary["robots"][1]["trajectory"].as_str().unwrap().ends_with("scorbot.csv"));
    assert_eq!(summary["dt"], 0.02);
    // A clock too fine for the memory is refused before any sample is made.
    // (7 000 000 samples: within a single trajectory's limit, above the cell's for two robots.)
    let dt = format!("{:e}", sc_end / 7e6);
    let r = kinema(&["cell", cell.to_str().unwrap(), "--dt", &dt]);
    assert!(r.code == Some(1) && r.stderr.contains("above the limit of 10000000"), "{}", r.stderr);
}

#[test]
fn a_trajectory_that_breaks_a_limit_fails_its_check_with_code_1() {
    let dir = tempdir("limit");
    two_ptp_files(dir.path());
    // Joint 1 of the UR5 jumps by 0.5 rad at one sample.
    let path = dir.path().join("ur5.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let mut cells: Vec<String> = lines[20].split(',').map(str::to_string).collect();
    cells[1] = format!("{:.12}", cells[1].parse::<f64>().unwrap() + 0.5);
    lines[20] = cells.join(",");
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    let cell = dir.path().join("cell.toml");
    std::fs::write(
        &cell,
        "[[robot]]\nname = \"a\"\nrobot = \"ur5\"\ntrajectory = \"ur5.csv\"\n[[robot]]\nname = \"b\"\nrobot = \"scorbot-er-v-plus\"\nbase = { xyz = [1, 0, 0] }\ntrajectory = \"scorbot.csv\"\n",
    )
    .unwrap();
    let r = kinema(&["cell", cell.to_str().unwrap(), "--json"]);
    assert_eq!(r.code, Some(1), "{} {}", r.stdout, r.stderr);
    let summary: Value = serde_json::from_str(&r.stdout).unwrap();
    assert_eq!(summary["robots"][0]["check"]["ok"], false);
    assert_eq!(summary["robots"][1]["check"]["ok"], true);
    let v = &summary["robots"][0]["check"]["violations"][0];
    assert_eq!(v["joint"], 1, "{v}");
    assert!(r.stderr.contains("breaks its limits"), "{}", r.stderr);
    // The same file through `traj check` finds the same first violation.
    let r = kinema(&["traj", "check", "-r", "ur5", path.to_str().unwrap(), "--json"]);
    let check: Value = serde_json::from_str(&r.stdout).unwrap();
    assert_eq!(check, summary["robots"][0]["check"]);
}

/// Runs `kinema cell` on `toml` written into a fresh folder with the seed's
/// programs and a UR5 trajectory beside it; the error output.
fn cell_error(toml: &str) -> String {
    let dir = tempdir("err");
    for prg in ["seed004_holder.prg", "seed004_drawer.prg"] {
        std::fs::copy(repo().join("examples/cells").join(prg), dir.path().join(prg)).unwrap();
    }
    std::fs::write(dir.path().join("bad.prg"), "PTP home\nWAIT 5mm\n").unwrap();
    two_ptp_files(dir.path());
    let cell = dir.path().join("cell.toml");
    std::fs::write(&cell, toml).unwrap();
    let r = kinema(&["cell", cell.to_str().unwrap()]);
    assert_eq!(r.code, Some(1), "{toml}\n{} {}", r.stdout, r.stderr);
    assert!(!r.stderr.contains("panicked"), "{}", r.stderr);
    assert!(r.stdout.is_empty(), "{}", r.stdout);
    r.stderr
}

#[test]
fn bad_cells_name_the_file_the_key_and_what_was_expected() {
    let iiwa = "[[robot]]\nname = \"a\"\nrobot = \"lbr-iiwa-14-r820\"\n";
    let mut missed = Vec::new();
    for (toml, wanted) in [
        // Joint counts: a UR5 file for the iiwa.
        (format!("{iiwa}trajectory = \"ur5.csv\"\n"), &["robot `a` (robot[0])", "ur5.csv", "q1..q7"][..]),
        (format!("{iiwa}trajectory = \"scorbot.csv\"\n"), &["robot `a`", "q1..q7"][..]),
        // Missing files.
        (format!("{iiwa}trajectory = \"nowhere.csv\"\n"), &["robot `a`", "nowhere.csv"][..]),
        (format!("{iiwa}program = \"nowhere.prg\"\n"), &["robot `a`", "nowhere.prg"][..]),
        (
            "[[robot]]\nname = \"a\"\nrobot = \"arms/none.toml\"\nprogram = \"p.prg\"\n".into(),
            &["robot `a`", "none.toml"][..],
        ),
        ("[[robot]]\nname = \"a\"\nrobot = \"no-such-robot\"\nprogram = \"p.prg\"\n".into(), &["no-such-robot"][..]),
        // Keys and values.
        (
            format!("{iiwa}program = \"seed004_holder.prg\"\nbse = {{ xyz = [0, 0, 0] }}\n"),
            &["cell.toml:5:1", "`robot[0].bse`", "unknown field `bse`", "base"][..],
        ),
        ("dtt = 0.01\n".into(), &["cell.toml:1:1", "unknown field `dtt`"][..]),
        (
            format!("{iiwa}program = \"seed004_holder.prg\"\nbase = {{ xyz = [\"1furlong\", 0, 0] }}\n"),
            &["cell.toml:5:17", "`robot[0].base.xyz[0]`", "unknown unit `furlong`", "a length (m, cm, mm)"][..],
        ),
        (
            format!("{iiwa}program = \"seed004_holder.prg\"\nbase = {{ rpy = [0, 0, \"90mm\"] }}\n"),
            &["`robot[0].base.rpy[2]`", "an angle (rad, deg)"][..],
        ),
        (
            format!("{iiwa}program = \"seed004_holder.prg\"\nbase = {{ xyz = [0, 0] }}\n"),
            &["`robot[0].base.xyz`", "length 2", "3"][..],
        ),
        (
            format!("{iiwa}program = \"seed004_holder.prg\"\nbase = {{ xyz = [true, 0, 0] }}\n"),
            &["`robot[0].base.xyz[0]`", "a number or a string with a unit"][..],
        ),
        ("rpy = \"abc\"\n".into(), &["`rpy`", "zyx", "xyz"][..]),
        (
            "dt = \"-1s\"\n[[robot]]\nname = \"a\"\nrobot = \"ur5\"\ntrajectory = \"ur5.csv\"\n".into(),
            &["cell.toml:1:6", "`dt`", "> 0"][..],
        ),
        ("min_distance = \"1deg\"\n".into(), &["`min_distance`", "a length"][..]),
        ("[[robot]]\nrobot = \"ur5\"\ntrajectory = \"ur5.csv\"\n".into(), &["`robot[0]`", "missing field `name`"][..]),
        (
            "[[robot]]\nname = \"a b\"\nrobot = \"ur5\"\ntrajectory = \"ur5.csv\"\n".into(),
            &["`robot[0].name`", "letters, digits"][..],
        ),
        (
            format!("{iiwa}program = \"seed004_holder.prg\"\n{iiwa}program = \"seed004_drawer.prg\"\n"),
            &["cell.toml:6:8", "`robot[1].name`", "names two robots"][..],
        ),
        (iiwa.to_string(), &["`robot[0].trajectory`", "no motion"][..]),
        (
            format!("{iiwa}program = \"seed004_holder.prg\"\ntrajectory = \"ur5.csv\"\n"),
            &["`robot[0].program`", "not both"][..],
        ),
        (format!("{iiwa}trajectory = \"ur5.csv\"\nstart = \"home\"\n"), &["`robot[0].start`", "for a program"][..]),
        (format!("{iiwa}program = \"seed004_holder.prg\"\nstart = \"1,2\"\n"), &["`robot[0].start`", "7 joints"][..]),
        ("[robot]\nname = 1\n".into(), &["cell.toml", "`robot`"][..]),
        ("[[robot]\n".into(), &["cell.toml:1", "(syntax)"][..]),
        ("".into(), &["no [[robot]] tables"][..]),
    ] {
        let e = cell_error(&toml);
        for w in wanted {
            if !e.contains(w) {
                missed.push(format!("{toml}\nwanted `{w}` in:\n{e}"));
            }
        }
    }
    assert!(missed.is_empty(), "{}", missed.join("\n\n"));
    // A program that does not compile: its diagnostics, then which robot.
    let e = cell_error("[[robot]]\nname = \"a\"\nrobot = \"ur5\"\nprogram = \"bad.prg\"\n");
    assert!(e.contains("robot `a`") && e.contains("bad.prg:2:6") && e.contains("expected a time"), "{e}");
    // The cell file itself.
    let r = kinema(&["cell", "/nonexistent/cell.toml"]);
    assert!(r.code == Some(1) && r.stderr.contains("/nonexistent/cell.toml"), "{}", r.stderr);
    let r = kinema(&["cell", "/dev/zero"]);
    assert!(r.code == Some(1) && r.stderr.contains("larger than the limit"), "{}", r.stderr);
    let r = kinema(&["cell", &seed_cell(), "--dt", "0"]);
    assert!(r.code == Some(1) && r.stderr.contains("--dt"), "{}", r.stderr);
}

#[test]
#[cfg(unix)]
fn ctrl_c_and_the_time_limit_stop_the_programs_and_write_nothing() {
    use std::process::{Command, Stdio};
    let dir = tempdir("stop");
    // About 7 s of computing: 40 000 short LINs with IK at every sample.
    std::fs::write(
        dir.path().join("long.prg"),
        "JACC 90 deg/s^2\nVEL 1 m/s\nACC 10 m/s^2\nPTP CART(400mm, 100mm, 400mm, 0deg, 180deg, 0deg)\n\
         LOOP 20000\n  LIN REL CART(0mm, 10mm, 0mm)\n  LIN REL CART(0mm, -10mm, 0mm)\nEND\n",
    )
    .unwrap();
    let cell = dir.path().join("cell.toml");
    std::fs::write(&cell, "[[robot]]\nname = \"a\"\nrobot = \"ur5\"\nprogram = \"long.prg\"\n").unwrap();
    let out = dir.path().join("out.csv");
    let r = kinema(&["cell", cell.to_str().unwrap(), "--time-limit", "0.3", "--out", out.to_str().unwrap()]);
    assert_eq!(r.code, Some(1), "{}", r.stderr);
    assert!(r.stderr.contains("time budget of 0.300 s ran out") && r.stderr.contains("robot `a`"), "{}", r.stderr);
    assert!(!out.exists());
    let child = Command::new(env!("CARGO_BIN_EXE_kinema"))
        .args(["cell", cell.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(500));
    assert!(Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap().success());
    let done = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&done.stderr);
    assert_eq!(done.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("nothing was written"), "{stderr}");
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left.len(), 2, "only the cell and its program: {left:?}");
}

/// Issue 35, the fuzz target for cell files: random edits of a valid cell
/// (two robots, trajectory files, a base with units). Every run ends with
/// exit code 0, 1 or 3 (never a panic or a signal) within its time, a
/// failure says why, and an accepted cell's JSON and CSV hold no NaN or inf.
#[test]
fn random_cell_files_end_cleanly_and_give_finite_answers() {
    use rand::SeedableRng;
    let dir = tempdir("fuzz");
    two_ptp_files(dir.path());
    let valid =
        "dt = \"20ms\"\nmin_distance = \"50mm\"\n[[robot]]\nname = \"ur\"\nrobot = \"ur5\"\ntrajectory = \"ur5.csv\"\n\
                 [[robot]]\nname = \"scorbot\"\nrobot = \"scorbot-er-v-plus\"\n\
                 base = { xyz = [1, \"-200mm\", 0.1], rpy = [0, 0, \"90deg\"] }\ntrajectory = \"scorbot.csv\"\n";
    let cell = dir.path().join("cell.toml");
    let args: Vec<String> = ["cell", "cell.toml", "--out", "report.csv", "--json"].map(String::from).to_vec();
    std::fs::write(&cell, valid).unwrap();
    let r = common::kinema_in(dir.path(), &args, std::time::Duration::from_secs(60));
    assert!(r.ok, "the valid cell: {}", r.stderr);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0x35ce);
    let (mut ok, mut refused) = (0, 0);
    for case in 0..mutate::fuzz_cases(60) {
        let text = if case % 8 == 0 { mutate::random_text(&mut rng) } else { mutate::mutate(valid, &mut rng) };
        std::fs::write(&cell, &text).unwrap();
        let _ = std::fs::remove_file(dir.path().join("report.csv"));
        let r = common::kinema_in(dir.path(), &args, std::time::Duration::from_secs(60));
        assert!(matches!(r.code, Some(0 | 1 | 3)), "{text:?}: {:?} {}", r.code, r.stderr);
        assert!(!r.stderr.contains("panicked"), "{text:?}: {}", r.stderr);
        if r.ok {
            ok += 1;
            let report = std::fs::read_to_string(dir.path().join("report.csv")).unwrap().to_ascii_lowercase();
            assert!(!report.contains("nan") && !report.contains("inf"), "{text:?}: {report}");
            // JSON cannot carry NaN (serde_json would write null, as it writes an absent option).
            let summary: Value = serde_json::from_str(&r.stdout).unwrap_or_else(|e| panic!("{text:?}: {e}"));
            assert!(summary["robots"].is_array(), "{text:?}: {summary}");
        } else {
            refused += 1;
            assert!(!r.stderr.trim().is_empty(), "{text:?}: no message");
        }
    }
    assert!(ok >= 2 && refused >= 10, "ok {ok}, refused {refused}");
}

/// Seed 004's two iiwas checked link to link: the closest pair of link
/// shapes and when, never farther than the tools (they are on the links),
/// and a file's `[[obstacle]]` in the holder's way makes the cell fail with
/// code 3, naming the link and the obstacle.
#[test]
fn link_shapes_are_measured_between_robots_and_to_obstacles() {
    let r = kinema(&["cell", &seed_cell(), "--json"]);
    assert!(r.ok, "{}", r.stderr);
    let summary: Value = serde_json::from_str(&r.stdout).unwrap();
    let bodies = summary["bodies"].as_array().unwrap();
    assert_eq!(bodies.len(), 1, "{summary}");
    let b = &bodies[0];
    assert_eq!(b["robots"], serde_json::json!(["holder", "drawer"]));
    let links = b["links"].as_array().unwrap();
    assert!(links[0].as_str().unwrap().starts_with("holder/link"), "{b}");
    assert!(links[1].as_str().unwrap().starts_with("drawer/link"), "{b}");
    let link_d = b["closest"]["distance"].as_f64().unwrap();
    let tool_d = summary["pairs"][0]["closest"]["distance"].as_f64().unwrap();
    assert!(link_d > 0.0 && link_d < tool_d, "links {link_d}, tools {tool_d}");
    let text = kinema(&["cell", &seed_cell()]);
    assert!(text.stdout.contains("holder and drawer, link shapes: closest"), "{}", text.stdout);

    let dir = tempdir("obstacle");
    for prg in ["seed004_holder.prg", "seed004_drawer.prg"] {
        std::fs::copy(repo().join("examples/cells").join(prg), dir.path().join(prg)).unwrap();
    }
    let bench = "\n[[obstacle]]\nname = \"bench\"\nbox = [3, 2, 0.05]\npose = [0.6, 0, -0.025, 0, 0, 0]\n";
    let part = "\n[[obstacle]]\nname = \"fixture\"\nsphere = { radius = 0.05 }\npose = [0.55, 0, 0.6, 0, 0, 0]\n";
    let seed = std::fs::read_to_string(seed_cell()).unwrap();
    let with_bench = dir.path().join("bench.toml");
    std::fs::write(&with_bench, format!("{seed}{bench}")).unwrap();
    let r = kinema(&["cell", with_bench.to_str().unwrap(), "--json"]);
    assert!(r.ok, "the robots stand on the bench: {}", r.stderr);
    let summary: Value = serde_json::from_str(&r.stdout).unwrap();
    let scene: Vec<&Value> =
        summary["bodies"].as_array().unwrap().iter().filter(|b| b["robots"][1] == "scene").collect();
    assert_eq!(scene.len(), 2, "{summary}");
    assert!(scene.iter().all(|b| b["links"][1] == "bench" && b["ok"] == true), "{summary}");
    let with_part = dir.path().join("part.toml");
    std::fs::write(&with_part, format!("{seed}{bench}{part}")).unwrap();
    let r = kinema(&["cell", with_part.to_str().unwrap()]);
    assert_eq!(r.code, Some(3), "{} {}", r.stdout, r.stderr);
    assert!(r.stderr.contains("`holder` touches the scene") && r.stderr.contains("fixture"), "{}", r.stderr);
}

/// A URDF arm whose collision mesh is a `package://` path: without the
/// package's directory the cell still runs, with a warning and no link
/// distances for it; with `--package-path` its link is measured.
#[test]
fn a_cell_robot_whose_mesh_is_missing_warns_and_package_path_finds_it() {
    let dir = tempdir("package");
    let meshes = dir.path().join("pkgs/arm/meshes");
    std::fs::create_dir_all(&meshes).unwrap();
    let facets =
        [[[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 0.1, 0.0]], [[0.0, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 0.1]]];
    let mut stl = String::from("solid wedge\n");
    for f in facets {
        stl += "facet normal 0 0 0\nouter loop\n";
        for v in f {
            stl += &format!("vertex {} {} {}\n", v[0], v[1], v[2]);
        }
        stl += "endloop\nendfacet\n";
    }
    stl += "endsolid wedge\n";
    std::fs::write(meshes.join("link.stl"), stl).unwrap();
    let urdf = r#"<?xml version="1.0"?>
<robot name="arm">
  <link name="base"/>
  <link name="link1">
    <collision><geometry><mesh filename="package://arm/meshes/link.stl"/></geometry></collision>
  </link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="link1"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
</robot>
"#;
    std::fs::write(dir.path().join("arm.urdf"), urdf).unwrap();
    std::fs::write(dir.path().join("arm.csv"), "t,q1\n0,0\n1,0.5\n").unwrap();
    std::fs::write(dir.path().join("ur5.csv"), "t,q1,q2,q3,q4,q5,q6\n0,0,-1.5,1.5,0,1.5,0\n1,0.5,-1.5,1.5,0,1.5,0\n")
        .unwrap();
    let cell = dir.path().join("cell.toml");
    let text =
        "[[robot]]\nname = \"arm\"\nrobot = \"arm.urdf\"\ntrajectory = \"arm.csv\"\n\n[[robot]]\nname = \"ur\"\n\
                robot = \"ur5\"\nbase = { xyz = [1.5, 0, 0] }\ntrajectory = \"ur5.csv\"\n";
    std::fs::write(&cell, text).unwrap();
    let cell = cell.to_str().unwrap();

    let r = kinema(&["cell", cell, "--json"]);
    assert!(r.ok, "{}", r.stderr);
    assert!(r.stderr.contains("warning") && r.stderr.contains("no link distances for this robot"), "{}", r.stderr);
    assert!(r.stderr.contains("link.stl"), "the warning names the mesh: {}", r.stderr);
    let summary: Value = serde_json::from_str(&r.stdout).unwrap();
    assert!(summary.get("bodies").is_none(), "one robot without shapes: no pair to measure: {summary}");

    let packages = dir.path().join("pkgs");
    let r = kinema(&["cell", cell, "--json", "--package-path", packages.to_str().unwrap()]);
    assert!(r.ok && !r.stderr.contains("warning"), "{}", r.stderr);
    let summary: Value = serde_json::from_str(&r.stdout).unwrap();
    let b = &summary["bodies"][0];
    assert_eq!(b["links"][0], "arm/link1", "{summary}");
    let (links, tools) =
        (b["closest"]["distance"].as_f64().unwrap(), summary["pairs"][0]["closest"]["distance"].as_f64().unwrap());
    assert!(links > 0.5 && links < tools, "links {links} m, tools {tools} m: {summary}");
}
