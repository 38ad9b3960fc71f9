//! End-to-end tests of the `kinema` binary: `kinema dyn`.

use kinema::Robot;

use crate::common;

use common::kinema;

use super::cli::{fails, tempdir};

/// Rows of a `kinema dyn` CSV (after its `t,tau1..taun` header).
fn torque_rows(text: &str, n: usize) -> Vec<Vec<f64>> {
    let mut lines = text.lines();
    let want: Vec<String> = std::iter::once("t".to_string()).chain((1..=n).map(|i| format!("tau{i}"))).collect();
    assert_eq!(lines.next().unwrap(), want.join(","), "{text}");
    lines.map(|l| l.split(',').map(|x| x.parse().unwrap()).collect()).collect()
}

/// Two unit links turning about horizontal axes (the base is rolled 90°), 1 kg each at mid-link,
/// joint 1 with a 5 N·m motor: held out straight it needs 9.81·(0.5 + 1.5) = 19.62 N·m.
const PENDULUM: &str = include_str!("../../../kinema/tests/data/pendulum2.toml");

#[test]
fn dyn_at_rest_gives_the_gravity_torques() {
    let dir = tempdir("dyn-rest");
    let robot = Robot::builtin("puma560").unwrap();
    let q = robot.home().to_vec();
    let row = q.iter().map(|v| format!("{v}")).collect::<Vec<_>>().join(",");
    let rest = dir.join("rest.csv");
    std::fs::write(&rest, format!("t,q1,q2,q3,q4,q5,q6\n0,{row}\n0.5,{row}\n1,{row}\n")).unwrap();
    let r = kinema(&["dyn", "-r", "puma560", rest.to_str().unwrap()]);
    assert!(r.ok, "{}", r.stderr);
    // No rate columns: both are differentiated, and the report (on stderr, stdout has the CSV) says so.
    assert!(r.stderr.contains("3 samples") && r.stderr.matches("differentiated from q").count() == 2, "{}", r.stderr);
    assert!(r.stderr.contains("no effort limits: nothing checked"), "{}", r.stderr);
    let g = kinema::nalgebra::Vector3::new(0.0, 0.0, -9.81);
    let want = kinema::dynamics::gravity_torques(&robot, &q, &g).unwrap();
    let rows = torque_rows(&r.stdout, 6);
    assert_eq!(rows.len(), 3);
    for row in &rows {
        for (got, want) in row[1..].iter().zip(&want) {
            assert!((got - want).abs() < 1e-8, "{row:?} vs {want:?}");
        }
    }
    assert!(want[1].abs() > 1.0, "{want:?}"); // the shoulder holds the arm up
                                              // Gravity is an argument: without it a resting arm needs no torque.
    let out = dir.join("tau.csv");
    let r =
        kinema(&["dyn", "-r", "puma560", rest.to_str().unwrap(), "--gravity", "0,0,0", "-o", out.to_str().unwrap()]);
    assert!(r.ok && r.stdout.contains("0 effort violation(s)"), "{}{}", r.stdout, r.stderr);
    let rows = torque_rows(&std::fs::read_to_string(&out).unwrap(), 6);
    assert!(rows.iter().all(|r| r[1..].iter().all(|v| v.abs() < 1e-12)), "{rows:?}");
}

#[test]
fn dyn_uses_the_rates_of_the_file_or_differentiates_q() {
    let dir = tempdir("dyn-rates");
    let robot = Robot::builtin("puma560").unwrap();
    let g = kinema::nalgebra::Vector3::new(0.0, 0.0, -9.81);
    // A PTP from `kinema traj ptp` carries q̇ and q̈: the torques are RNEA of those columns.
    let ptp = dir.join("ptp.csv");
    let r = kinema(&[
        "traj",
        "ptp",
        "-r",
        "puma560",
        "--from",
        "qz",
        "--to",
        "qr",
        "--vmax",
        "1",
        "--amax",
        "2",
        "--out",
        ptp.to_str().unwrap(),
    ]);
    assert!(r.ok, "{}", r.stderr);
    let r = kinema(&["dyn", "-r", "puma560", ptp.to_str().unwrap()]);
    assert!(r.ok, "{}", r.stderr);
    assert!(r.stderr.contains("q̇ from the file, q̈ from the file"), "{}", r.stderr);
    let file: Vec<Vec<f64>> = std::fs::read_to_string(&ptp)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    let rows = torque_rows(&r.stdout, 6);
    assert_eq!(rows.len(), file.len());
    for (row, s) in rows.iter().zip(&file) {
        let want = kinema::dynamics::rnea(&robot, &s[1..7], &s[7..13], &s[13..19], &g).unwrap();
        assert_eq!(row[0], s[0]);
        for (got, want) in row[1..].iter().zip(&want) {
            assert!((got - want).abs() < 1e-7 * (1.0 + want.abs()), "t = {}: {got} vs {want}", s[0]);
        }
    }
    // Only q, quadratic in t on uneven times: the three-point differences are exact, q̇ = 2ct, q̈ = 2c.
    let c = [0.3, -0.2, 0.1, 0.5, -0.4, 0.2];
    let times = [0.0, 0.1, 0.25, 0.3, 0.5];
    let mut text = "t,q1,q2,q3,q4,q5,q6\n".to_string();
    for t in times {
        let q: Vec<String> = c.iter().map(|c| format!("{}", c * t * t)).collect();
        text += &format!("{t},{}\n", q.join(","));
    }
    let bare = dir.join("bare.csv");
    std::fs::write(&bare, text).unwrap();
    let r = kinema(&["dyn", "-r", "puma560", bare.to_str().unwrap()]);
    assert!(r.ok, "{}", r.stderr);
    for (row, t) in torque_rows(&r.stdout, 6).iter().zip(times) {
        let q: Vec<f64> = c.iter().map(|c| c * t * t).collect();
        let qd: Vec<f64> = c.iter().map(|c| 2.0 * c * t).collect();
        let qdd: Vec<f64> = c.iter().map(|c| 2.0 * c).collect();
        let want = kinema::dynamics::rnea(&robot, &q, &qd, &qdd, &g).unwrap();
        for (got, want) in row[1..].iter().zip(&want) {
            assert!((got - want).abs() < 1e-6, "t = {t}: {got} vs {want}");
        }
    }
}

#[test]
fn dyn_reports_effort_violations_like_traj_check() {
    let dir = tempdir("dyn-effort");
    let arm = dir.join("pendulum2.toml");
    std::fs::write(&arm, PENDULUM).unwrap();
    let traj = dir.join("hold.csv");
    // Held straight out (19.62 N·m at joint 1), a swing down (about ±4 N·m for q̈ = ∓π/2 from the
    // three-point differences, on top of gravity), then hanging (no torque).
    let down = -std::f64::consts::FRAC_PI_2;
    std::fs::write(&traj, format!("t,q1,q2\n0,0,0\n1,0,0\n2,0,0\n3,{down},0\n4,{down},0\n5,{down},0\n")).unwrap();
    let out = dir.join("tau.csv");
    let r = kinema(&["dyn", "-r", arm.to_str().unwrap(), traj.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(r.code, Some(1), "{}{}", r.stdout, r.stderr);
    assert!(r.stdout.contains("6 samples on `pendulum2`, 3 effort violation(s)"), "{}", r.stdout);
    assert!(r.stdout.contains("t = 0.0000 s (sample 0): joint 1 torque"), "{}", r.stdout);
    assert!(r.stdout.contains("exceeds its effort limit 5.000000 N·m"), "{}", r.stdout);
    assert!(!r.stdout.contains("joint 2 torque"), "{}", r.stdout);
    // The torques are written all the same, to be looked at.
    let rows = torque_rows(&std::fs::read_to_string(&out).unwrap(), 2);
    assert_eq!(rows.len(), 6);
    assert!((rows[0][1].abs() - 9.81 * 2.0).abs() < 1e-6, "{rows:?}");
    assert!(rows[5][1].abs() < 1e-9 && rows[3][1].abs() < 5.0, "{rows:?}");
    assert!((rows[0][2].abs() - 9.81 * 0.5).abs() < 1e-6, "{rows:?}");
    // A stronger gravity-free world passes.
    let r = kinema(&["dyn", "-r", arm.to_str().unwrap(), traj.to_str().unwrap(), "--gravity=0,0,0", "-o", "-"]);
    assert!(r.ok && r.stderr.contains("0 effort violation(s)"), "{}", r.stderr);
}

#[test]
fn dyn_refuses_bad_input_and_arms_without_mass() {
    let dir = tempdir("dyn-bad");
    let csv = dir.join("t.csv");
    let puma = |csv: &std::path::Path, extra: &[&str]| {
        let mut args = vec!["dyn", "-r", "puma560", csv.to_str().unwrap()];
        args.extend_from_slice(extra);
        kinema(&args)
    };
    // Times that stand still or go back: named with the line.
    std::fs::write(&csv, "t,q1,q2,q3,q4,q5,q6\n0,0,0,0,0,0,0\n0.1,0,0,0,0,0,0\n0.1,0,0,0,0,0,0\n").unwrap();
    let r = puma(&csv, &[]);
    assert_eq!(r.code, Some(1));
    assert!(r.stderr.contains("line 4") && r.stderr.contains("does not increase"), "{}", r.stderr);
    assert!(r.stdout.is_empty(), "{}", r.stdout);
    std::fs::write(&csv, "t,q1,q2,q3,q4,q5,q6\n0,0,0,0,0,0,0\nnan,0,0,0,0,0,0\n").unwrap();
    assert!(puma(&csv, &[]).stderr.contains("times must be finite"));
    // Not numbers, too few columns, no samples.
    std::fs::write(&csv, "t,q1,q2,q3,q4,q5,q6\n0,0,0,zero,0,0,0\n").unwrap();
    let e = fails(&["dyn", "-r", "puma560", csv.to_str().unwrap()]);
    assert!(e.contains("line 2") && e.contains("q3") && e.contains("zero"), "{e}");
    std::fs::write(&csv, "t,q1,q2\n0,0,0\n").unwrap();
    let e = fails(&["dyn", "-r", "puma560", csv.to_str().unwrap()]);
    assert!(e.contains("q1..q6"), "{e}");
    std::fs::write(&csv, "t,q1,q2,q3,q4,q5,q6\n").unwrap();
    assert!(fails(&["dyn", "-r", "puma560", csv.to_str().unwrap()]).contains("no samples"));
    // A non-finite joint value is the core's error, with the line.
    std::fs::write(&csv, "t,q1,q2,q3,q4,q5,q6\n0,0,0,inf,0,0,0\n").unwrap();
    let e = fails(&["dyn", "-r", "puma560", csv.to_str().unwrap()]);
    assert!(e.contains("line 2") && e.contains("inf"), "{e}");
    // Rates so large the torques overflow (issue 35 item 6: they used to be
    // written as NaN with "0 effort violation(s)"): an error naming them, no output.
    std::fs::write(&csv, "t,q1,q2,q3,q4,q5,q6,qd1,qd2,qd3,qd4,qd5,qd6\n0,0,0,0,0,0,0,1e200,1e200,0,0,0,0\n").unwrap();
    let out = dir.join("tau.csv");
    let r = puma(&csv, &["-o", out.to_str().unwrap()]);
    assert_eq!(r.code, Some(1), "{}", r.stderr);
    assert!(r.stderr.contains("line 2") && r.stderr.contains("too large") && r.stderr.contains("q̇"), "{}", r.stderr);
    assert!(!out.exists());
    // A joint value beyond ±1e9.
    std::fs::write(&csv, "t,q1,q2,q3,q4,q5,q6\n0,0,0,1e12,0,0,0\n").unwrap();
    let e = fails(&["dyn", "-r", "puma560", csv.to_str().unwrap()]);
    assert!(e.contains("line 2") && e.contains("within ±1e9"), "{e}");
    // Bad gravity.
    std::fs::write(&csv, "t,q1,q2,q3,q4,q5,q6\n0,0,0,0,0,0,0\n").unwrap();
    assert!(puma(&csv, &["--gravity", "0,-9.81"]).stderr.contains("expected three"));
    assert!(puma(&csv, &["--gravity", "0,0,down"]).stderr.contains("`down` is not a number"));
    assert!(puma(&csv, &["--gravity", "0,0,inf"]).stderr.contains("not a finite number"));
    // A robot without mass properties: the core's message, an input error (exit code 1).
    let arm = dir.join("massless.toml");
    let massless: String = PENDULUM.split("[joint.inertial]").next().unwrap().to_string()
        + "[[joint]]\nname = \"j2\"\na = 1\nalpha = 0\nmin = -180\nmax = 180\n[poses]\nhome = [0, 0]\n";
    std::fs::write(&arm, massless).unwrap();
    std::fs::write(&csv, "t,q1,q2\n0,0,0\n").unwrap();
    let r = kinema(&["dyn", "-r", arm.to_str().unwrap(), csv.to_str().unwrap()]);
    assert_eq!(r.code, Some(1));
    assert!(r.stderr.contains("link 1 (moved by joint `j1`) has no mass properties"), "{}", r.stderr);
    assert!(r.stdout.is_empty(), "{}", r.stdout);
    // Said before the trajectory is read.
    let e = fails(&["dyn", "-r", arm.to_str().unwrap(), dir.join("none.csv").to_str().unwrap()]);
    assert!(e.contains("has no mass properties") && !e.contains("none.csv"), "{e}");
}
