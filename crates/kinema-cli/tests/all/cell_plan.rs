//! `kinema plan --cell … --other-trajectory`: seed 004's two iiwas, one
//! swinging across the space the other's arm sweeps through. The planned
//! motion waits for the other arm to pass and `kinema cell` (its own
//! continuous check of the two bodies) finds them apart all along, where
//! the untimed swing touches; the same command gives the same file; an
//! impossible case names the robots and links that block it.

use std::path::Path;

use crate::common::kinema;

const CELL: &str =
    "dt = 0.01\n\n[[robot]]\nname = \"holder\"\nrobot = \"lbr-iiwa-14-r820\"\ntrajectory = \"holder.csv\"\n\n\
                    [[robot]]\nname = \"drawer\"\nrobot = \"lbr-iiwa-14-r820\"\n\
                    base = { xyz = [\"1200mm\", 0, 0], rpy = [0, 0, \"180deg\"] }\ntrajectory = \"drawer.csv\"\n";

/// The drawer's arm, stretched out sideways, swings into the middle, rests, and back.
const DRAWER: &str =
    "JVEL 60deg/s\nPTP JOINT(0, 90deg, 0, 0, 0, 0, 0)\nWAIT 0.5\nPTP JOINT(90deg, 90deg, 0, 0, 0, 0, 0)\n";
const SIDE: &str = "1.5707963267948966,1.5707963267948966,0,0,0,0,0";
const RIGHT: &str = "-1.5707963267948966,1.5707963267948966,0,0,0,0,0";
const AHEAD: &str = "0,1.5707963267948966,0,0,0,0,0";

fn json(text: &str) -> serde_json::Value {
    serde_json::from_str(text).unwrap_or_else(|e| panic!("not JSON ({e}): {text}"))
}

/// A folder with the cell file and the drawer's trajectory.
fn cell_folder() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("cell.toml"), CELL).unwrap();
    let program = dir.path().join("drawer.prg");
    std::fs::write(&program, DRAWER).unwrap();
    let out = dir.path().join("drawer.csv");
    let run = kinema(&[
        "run",
        program.to_str().unwrap(),
        "--robot",
        "lbr-iiwa-14-r820",
        "--start",
        SIDE,
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(run.ok, "{}", run.stderr);
    dir
}

/// `kinema plan` of the holder from `from` to `to` against the drawer's motion, into `out`.
fn plan_holder(dir: &Path, from: &str, to: &str, out: &str, extra: &[&str]) -> crate::common::Run {
    let (cell, drawer, out) = (dir.join("cell.toml"), dir.join("drawer.csv"), dir.join(out));
    let mut args = vec![
        "plan",
        "--cell",
        cell.to_str().unwrap(),
        "--robot",
        "holder",
        "--other-trajectory",
        drawer.to_str().unwrap(),
        "--from",
        from,
        "--to",
        to,
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    kinema(&args)
}

/// `kinema cell --json` of the folder's cell: the holder's and drawer's bodies' closest approach.
fn bodies_closest(dir: &Path) -> (Option<i32>, f64) {
    let run = kinema(&["cell", dir.join("cell.toml").to_str().unwrap(), "--json"]);
    let answer = json(&run.stdout);
    let pair = &answer["bodies"][0];
    assert_eq!(pair["robots"], serde_json::json!(["holder", "drawer"]), "{answer}");
    (run.code, pair["closest"]["distance"].as_f64().unwrap())
}

#[test]
fn the_holder_waits_for_the_drawer_to_pass_and_the_cell_check_finds_them_apart() {
    let dir = cell_folder();
    let planned = plan_holder(dir.path(), RIGHT, SIDE, "holder.csv", &[]);
    assert!(planned.ok, "{}", planned.stderr);
    let (code, closest) = bodies_closest(dir.path());
    assert_eq!(code, Some(0));
    assert!(closest > 0.0, "the bodies stay apart: {closest} m");
    // It waited: the first sample that leaves the start is well after t = 0.
    let text = std::fs::read_to_string(dir.path().join("holder.csv")).unwrap();
    let first_q = |line: &str| line.split(',').nth(1).unwrap().parse::<f64>().unwrap();
    let rows: Vec<&str> = text.lines().skip(1).collect();
    let leaves = rows.iter().find(|l| first_q(l) != first_q(rows[0])).unwrap();
    assert!(leaves.split(',').next().unwrap().parse::<f64>().unwrap() > 1.0, "{leaves}");
    let again = plan_holder(dir.path(), RIGHT, SIDE, "again.csv", &[]);
    assert!(again.ok, "{}", again.stderr);
    assert_eq!(std::fs::read_to_string(dir.path().join("again.csv")).unwrap(), text);

    // The same swing untimed (a plain PTP from t = 0) touches the drawer's arm.
    let out = dir.path().join("holder.csv");
    let straight = kinema(&[
        "traj",
        "ptp",
        "--robot",
        "lbr-iiwa-14-r820",
        "--from",
        RIGHT,
        "--to",
        SIDE,
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(straight.ok, "{}", straight.stderr);
    let (code, closest) = bodies_closest(dir.path());
    assert_eq!((code, closest), (Some(3), 0.0));
}

#[test]
fn an_impossible_crossing_names_the_robots_and_links() {
    let dir = cell_folder();
    // Slowed down, the holder cannot leave the middle before the drawer's arm comes, nor wait there.
    let caught = plan_holder(dir.path(), AHEAD, SIDE, "caught.csv", &["--speed", "20"]);
    assert_eq!(caught.code, Some(1), "{}", caught.stderr);
    let e = &caught.stderr;
    assert!(e.contains("`holder` cannot keep clear of `drawer` waiting at via point 0"), "{e}");
    assert!(e.contains("`holder/link") && e.contains("– `drawer/link"), "{e}");
    assert!(!dir.path().join("caught.csv").exists());
    // A goal where the drawer's arm rests in the middle: it cannot be held there.
    std::fs::write(dir.path().join("drawer.prg"), "JVEL 60deg/s\nPTP JOINT(0, 90deg, 0, 0, 0, 0, 0)\n").unwrap();
    let rerun = kinema(&[
        "run",
        dir.path().join("drawer.prg").to_str().unwrap(),
        "--robot",
        "lbr-iiwa-14-r820",
        "--start",
        SIDE,
        "--out",
        dir.path().join("drawer.csv").to_str().unwrap(),
    ]);
    assert!(rerun.ok, "{}", rerun.stderr);
    let blocked = plan_holder(dir.path(), RIGHT, AHEAD, "blocked.csv", &[]);
    assert_eq!(blocked.code, Some(1), "{}", blocked.stderr);
    assert!(blocked.stderr.contains("goal configuration collides") && blocked.stderr.contains("`drawer@end/link"));
}

#[test]
fn cell_options_are_checked() {
    let dir = cell_folder();
    let stranger = plan_holder(dir.path(), RIGHT, SIDE, "x.csv", &["--other", "nobody"]);
    assert!(!stranger.ok && stranger.stderr.contains("--other `nobody`"), "{}", stranger.stderr);
    let cell = dir.path().join("cell.toml");
    let alone = kinema(&["plan", "--cell", cell.to_str().unwrap(), "--robot", "holder", "--from", RIGHT, "--to", SIDE]);
    assert!(!alone.ok && alone.stderr.contains("--other-trajectory"), "{}", alone.stderr);
}
