//! End-to-end tests of the `kinema` binary: `kinema traj`: laws, PTP, LIN, CIRC, expressions and checks of CSV files.

use kinema::Robot;
use serde_json::Value;

use crate::common;

use common::kinema;

use super::cli::{fails, json, tempdir};

#[test]
fn traj_law_prints_duration_and_phase_times() {
    let v =
        json(&["traj", "law", "--profile", "trapezoid", "--distance", "1", "--vmax", "0.5", "--amax", "1", "--json"]);
    assert!((v["duration"].as_f64().unwrap() - 2.5).abs() < 1e-12);
    assert!((v["t_acc"].as_f64().unwrap() - 0.5).abs() < 1e-12);
    // Short move: the cruise vanishes, a triangle of 2·√(D/a).
    let v = json(&["traj", "law", "--distance", "0.1", "--vmax", "1", "--amax", "1", "--json"]);
    assert!((v["duration"].as_f64().unwrap() - 2.0 * 0.1f64.sqrt()).abs() < 1e-12);
    assert_eq!(v["t_cruise"].as_f64(), Some(0.0));
    let v = json(&[
        "traj",
        "law",
        "--profile",
        "scurve",
        "--distance",
        "10",
        "--vmax",
        "1",
        "--amax",
        "1",
        "--jmax",
        "10",
        "--json",
    ]);
    assert!((v["duration"].as_f64().unwrap() - 11.1).abs() < 1e-12);
    let v = json(&["traj", "law", "--profile", "quintic", "--duration", "2", "--dt", "0.5", "--json"]);
    assert_eq!(v["samples"]["rows"].as_array().unwrap().len(), 5);
    let e = fails(&["traj", "law", "--profile", "scurve", "--vmax", "1", "--amax", "1"]);
    assert!(e.contains("jmax"), "{e}");
    let e = fails(&["traj", "law", "--vmax", "-1", "--amax", "1"]);
    assert!(e.contains("vmax"), "{e}");
}

#[test]
fn traj_ptp_writes_a_checked_csv_or_nothing() {
    let dir = tempdir("traj-ptp");
    let out = dir.join("ptp.csv");
    let to = "-0.1090,1.2417,0.4463,1.9156,-0.9695,-1.8728,0.4876";
    let r = kinema(&[
        "traj",
        "ptp",
        "-r",
        "lbr-iiwa-14-r820",
        "--from",
        "home",
        "--to",
        to,
        "--profile",
        "scurve",
        "--amax",
        "2",
        "--jmax",
        "15",
        "--dt",
        "0.01",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(r.ok, "{}", r.stderr);
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header.len(), 1 + 21 + 7);
    assert_eq!(
        (header[0], header[1], header[8], header[15], header[22], header[28]),
        ("t", "q1", "qd1", "qdd1", "x", "manipulability")
    );
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|x| x.parse().unwrap()).collect()).collect();
    let last = rows.last().unwrap();
    let goal: Vec<f64> = to.split(',').map(|x| x.parse().unwrap()).collect();
    assert!(last[1..8].iter().zip(&goal).all(|(a, b)| (a - b).abs() < 1e-9));
    // The pose columns are FK of the joint columns.
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let mid = &rows[rows.len() / 2];
    let p = robot.fk(&mid[1..8]).unwrap().world_from_tool.pos;
    assert!((p.x - mid[22]).abs() < 1e-9 && (p.z - mid[24]).abs() < 1e-9);
    // A non-positive acceleration limit: an error naming the flag, and no file.
    let bad = dir.join("bad.csv");
    let e = fails(&[
        "traj",
        "ptp",
        "-r",
        "lbr-iiwa-14-r820",
        "--from",
        "home",
        "--to",
        to,
        "--amax",
        "0",
        "--out",
        bad.to_str().unwrap(),
    ]);
    assert!(e.contains("amax"), "{e}");
    assert!(!bad.exists());
    assert!(std::fs::read_dir(&dir).unwrap().all(|f| !f.unwrap().file_name().to_string_lossy().contains("kinema-tmp")));
    let v = json(&[
        "traj", "ptp", "-r", "puma560", "--from", "home", "--to", "qr", "--vmax", "1", "--amax", "3", "--json", "--dt",
        "0.1",
    ]);
    assert!(
        v["duration"].as_f64().unwrap() > 0.0
            && v["rows"].as_array().unwrap().len() == v["samples"].as_u64().unwrap() as usize
    );
}

#[test]
fn traj_lin_circ_expr_and_check_from_the_command_line() {
    let dir = tempdir("traj-cart");
    // Seed 004 §VIII-C1 start pose (Φ in Rx·Ry·Rz), solved by the analytic IK.
    let ik = json(&[
        "ik",
        "-r",
        "lbr-iiwa-14-r820",
        "--pose",
        "0.7373,-0.3271,0.7325,-0.6595,1.4584,1.2113",
        "--rpy",
        "xyz",
        "--json",
    ]);
    let q0: Vec<String> = ik["solutions"][0]["q"].as_array().unwrap().iter().map(|v| v.to_string()).collect();
    let from = format!("--from={}", q0.join(","));
    let lin = dir.join("lin.csv");
    let r = kinema(&[
        "traj",
        "lin",
        "-r",
        "lbr-iiwa-14-r820",
        &from,
        "--to",
        "0.6,-0.6,0.3,0,1.5708,0",
        "--rpy",
        "xyz",
        "--vmax",
        "0.2",
        "--amax",
        "0.5",
        "--out",
        lin.to_str().unwrap(),
    ]);
    assert!(r.ok, "{}", r.stderr);
    let text = std::fs::read_to_string(&lin).unwrap();
    let last: Vec<f64> = text.lines().last().unwrap().split(',').map(|x| x.parse().unwrap()).collect();
    // The last sample's pose is the goal (compared as rotations: at pitch π/2
    // the Rx·Ry·Rz angles are not unique).
    let conv = kinema::RpyConvention::Xyz;
    let got = kinema::Pose::from_xyz_rpy([last[22], last[23], last[24]], [last[25], last[26], last[27]], conv);
    // 1.5708 is the program's literal pitch (90 deg rounded), not π/2.
    #[allow(clippy::approx_constant)]
    let want = kinema::Pose::from_xyz_rpy([0.6, -0.6, 0.3], [0.0, 1.5708, 0.0], conv);
    assert!((got.pos - want.pos).norm() < 1e-6 && (got.rot - want.rot).norm() < 1e-6, "{last:?}");
    // `traj check` accepts it, and rejects a copy with a jump, naming the time and the joint.
    let v = json(&["traj", "check", "-r", "lbr-iiwa-14-r820", lin.to_str().unwrap(), "--json"]);
    assert_eq!(v["ok"], true);
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let k = lines.len() / 2;
    let mut fields: Vec<String> = lines[k].split(',').map(str::to_string).collect();
    let q4: f64 = fields[4].parse().unwrap();
    fields[4] = format!("{}", q4 + 1.5);
    lines[k] = fields.join(",");
    let jumpy = dir.join("jumpy.csv");
    std::fs::write(&jumpy, lines.join("\n")).unwrap();
    let r = kinema(&["traj", "check", "-r", "lbr-iiwa-14-r820", jumpy.to_str().unwrap()]);
    assert!(!r.ok && r.stdout.contains("joint 4 jumps"), "{}", r.stdout);
    // Only t and q columns: velocities are estimated from the samples.
    let bare = dir.join("bare.csv");
    std::fs::write(&bare, "t,q1,q2,q3,q4,q5,q6,q7\n0,0,0,0,0,0,0,0\n0.1,0.01,0,0,0,0,0,0\n0.2,0.02,0,0,0,0,0,0\n")
        .unwrap();
    let v = json(&["traj", "check", "-r", "lbr-iiwa-14-r820", bare.to_str().unwrap(), "--json"]);
    assert!((v["peak_velocity"][0].as_f64().unwrap() - 0.1).abs() < 1e-12);
    std::fs::write(&bare, "t,q1,q2\n0,0,0\n").unwrap();
    let e = fails(&["traj", "check", "-r", "lbr-iiwa-14-r820", bare.to_str().unwrap()]);
    assert!(e.contains("q1..q7"), "{e}");
    std::fs::write(&bare, "t,q1,q2,q3,q4,q5,q6,q7\n0,0,0,zero,0,0,0,0\n").unwrap();
    let e = fails(&["traj", "check", "-r", "lbr-iiwa-14-r820", bare.to_str().unwrap()]);
    assert!(e.contains("line 2") && e.contains("q3") && e.contains("zero"), "{e}");

    // Seed 004 eq. 40: the printed roll-pitch-yaw triples interpolated as
    // written, under every self-motion policy, within Cuadro I.
    for policy in ["hold", "manipulability", "track", "avoid-limits"] {
        let v = json(&[
            "traj",
            "lin",
            "-r",
            "lbr-iiwa-14-r820",
            &from,
            "--to",
            "0.6,-0.6,0.3,0,1.5708,0",
            "--rpy",
            "xyz",
            "--orientation",
            "rpy",
            "--q3",
            policy,
            "--vmax",
            "0.2",
            "--amax",
            "0.5",
            "--json",
        ]);
        assert!((v["duration"].as_f64().unwrap() - 3.260063).abs() < 1e-6, "{policy}: {}", v["duration"]);
    }

    // Resampled so that consecutive tool positions are at most 1 cm apart (seed 000).
    let v = json(&[
        "traj",
        "lin",
        "-r",
        "lbr-iiwa-14-r820",
        &from,
        "--to",
        "0.6,-0.6,0.3,0,1.5708,0",
        "--rpy",
        "xyz",
        "--vmax",
        "0.2",
        "--amax",
        "0.5",
        "--max-step",
        "0.01",
        "--json",
    ]);
    let rows = v["rows"].as_array().unwrap();
    let xyz = |r: &Value| [22, 23, 24].map(|i| r[i].as_f64().unwrap());
    for w in rows.windows(2) {
        let (a, b) = (xyz(&w[0]), xyz(&w[1]));
        let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
        assert!(d <= 0.01 + 1e-9, "{d}");
    }
    assert!(rows.len() > 50 && rows.len() < 80, "{}", rows.len()); // ~0.6 m of path

    // CIRC through an auxiliary point, as JSON.
    let v = json(&[
        "traj",
        "circ",
        "-r",
        "lbr-iiwa-14-r820",
        &from,
        "--aux",
        "0.7,-0.5,0.6",
        "--to",
        "0.6,-0.6,0.3,0,1.5708,0",
        "--rpy",
        "xyz",
        "--vmax",
        "0.2",
        "--amax",
        "0.5",
        "--profile",
        "scurve",
        "--jmax",
        "2",
        "--json",
    ]);
    assert!(
        v["duration"].as_f64().unwrap() > 0.0
            && v["rows"].as_array().unwrap().len() == v["samples"].as_u64().unwrap() as usize
    );
    // Collinear points: an error.
    let e = fails(&[
        "traj",
        "circ",
        "-r",
        "lbr-iiwa-14-r820",
        &from,
        "--aux",
        "0.66865,-0.46355,0.51625",
        "--to",
        "0.6,-0.6,0.3,0,1.5708,0",
        "--rpy",
        "xyz",
        "--vmax",
        "0.2",
        "--amax",
        "0.5",
    ]);
    assert!(e.contains("line"), "{e}");

    // Seed 001's joint curve on ROMMEL.
    let v = json(&[
        "traj",
        "expr",
        "-r",
        "rommel",
        "--joint",
        "1",
        "0.5*sin(4*pi*t^2/2)",
        "--duration",
        "2",
        "--dt",
        "0.5",
        "--vmax",
        "20",
        "--amax",
        "400",
        "--json",
    ]);
    let rows = v["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 5);
    // Against ROMMEL's own (estimated) limits the seed's curve is too fast.
    let e = fails(&["traj", "expr", "-r", "rommel", "--joint", "1", "0.5*sin(4*pi*t^2/2)", "--duration", "2"]);
    assert!(e.contains("joint 1") && e.contains("exceeds its limit"), "{e}");
    let q1 = rows[1][1].as_f64().unwrap();
    assert!((q1 - 0.5 * (std::f64::consts::PI / 2.0).sin()).abs() < 1e-12, "{q1}");
    let e = fails(&["traj", "expr", "-r", "rommel", "--joint", "1", "sin(t", "--duration", "1"]);
    assert!(e.contains("column 6"), "{e}");
    let e = fails(&["traj", "expr", "-r", "rommel", "--joint", "9", "t", "--duration", "1"]);
    assert!(e.contains("invalid `joint`: 9; expected a joint of `rommel`, 1 to 5"), "{e}");
}

/// Seed 003 Fig. 9's LIN from `home`, on the SCARA without its rate limits:
/// the zone rule puts the first sample on
/// another rail position and elbow (the rail 0.24 m, the elbow 0.84 rad in
/// 10 ms while the tool moves 19 µm). It is not emitted, and `traj check`
/// reports the branch jump even with no velocity limit to break.
#[test]
fn a_branch_jump_is_refused_and_reported_without_limits() {
    let dir = tempdir("branch-jump");
    let csv = dir.join("jump.csv");
    let scara = common::builtin_without_rate_limits(&dir, "scara5");
    let r = kinema(&[
        "traj",
        "lin",
        "-r",
        &scara,
        "--from",
        "home",
        "--to",
        "0.35,-0.1,0.2,0,0,0",
        "--vmax",
        "0.2",
        "--amax",
        "1",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert!(!r.ok && r.stderr.contains("not emitted") && r.stderr.contains("jump"), "{}", r.stderr);
    assert!(!csv.exists(), "a refused trajectory was written");
    std::fs::write(
        &csv,
        "t,q1,q2,q3,q4,q5\n\
         0,0.5,0.523598775598,1.570796326795,0.1,0\n\
         0.01,0.738561026299,-0.085252903048,2.407183474292,0.1,-0.227585468851\n\
         0.02,0.738513068640,-0.085305507695,2.407179723496,0.1,-0.227679113408\n",
    )
    .unwrap();
    let r = kinema(&["traj", "check", "-r", &scara, csv.to_str().unwrap(), "--json"]);
    assert!(!r.ok, "a branch jump passed the check");
    let v: Value = serde_json::from_str(&r.stdout).unwrap();
    let kinds: Vec<(&str, u64)> = v["violations"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| (v["kind"].as_str().unwrap(), v["sample"].as_u64().unwrap()))
        .collect();
    assert_eq!(kinds, [("branch", 1)], "{v}");
}
