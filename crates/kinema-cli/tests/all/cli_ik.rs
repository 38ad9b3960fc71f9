//! End-to-end tests of the `kinema` binary: `kinema ik`: solvers, the IK contract, batches, arm angles.

use std::process::Command;

use kinema::Robot;
use rand::SeedableRng;
use serde_json::Value;

use crate::common::kinema;

use super::cli::{data, exit_and_stdout, fails, json, tempdir};

#[test]
fn ik_numeric_reaches_fk_targets() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let q = [0.4, 0.6, -0.3, -1.1, 0.5, 0.9, -0.2];
    let rows = robot.fk(&q).unwrap().world_from_tool.to_rows();
    let t: Vec<String> = rows.iter().flatten().map(|v| format!("{v:.17}")).collect();
    let v = json(&["ik", "--robot", "lbr-iiwa-14-r820", "--T", &t.join(","), "--solver", "numeric", "--json"]);
    assert_eq!(v["solver"], "numeric");
    let s = &v["solutions"][0];
    assert!(s["position_error"].as_f64().unwrap() < 1e-6, "{s}");
    assert!(s["orientation_error"].as_f64().unwrap() < 1e-6, "{s}");
    assert_eq!(s["within_limits"], true);
    let sol: Vec<f64> = s["q"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    let reached = robot.fk(&sol).unwrap().world_from_tool;
    assert!((reached.pos - robot.fk(&q).unwrap().world_from_tool.pos).norm() < 1e-6);
    // --pose in degrees, started near the answer: converges to the nearby solution.
    let p = robot.fk(&q).unwrap().world_from_tool;
    let rpy = p.rpy(kinema::RpyConvention::Zyx).map(f64::to_degrees);
    let pose = format!("{},{},{},{},{},{}", p.pos.x, p.pos.y, p.pos.z, rpy[0], rpy[1], rpy[2]);
    let q0: Vec<String> = q.iter().map(|v| format!("{}", v.to_degrees() + 2.0)).collect();
    let v = json(&["ik", "--robot", "lbr-iiwa-14-r820", "--pose", &pose, "--deg", "--q0", &q0.join(","), "--json"]);
    let got: Vec<f64> = v["solutions"][0]["q"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    for (g, want) in got.iter().zip(&q) {
        assert!((g - want.to_degrees()).abs() < 5.0, "{got:?}");
    }
}

#[test]
fn ik_position_only_and_unreachable_exit_code() {
    let v = json(&["ik", "--robot", "scorbot-er-v-plus", "--position", "0.3,0.1,0.4", "--solver", "numeric", "--json"]);
    assert!(v["solutions"][0]["position_error"].as_f64().unwrap() < 1e-6);
    // No target orientation, so no orientation error to report.
    assert!(v["solutions"][0]["orientation_error"].is_null(), "{v}");
    let out = Command::new(env!("CARGO_BIN_EXE_kinema"))
        .args(["ik", "--robot", "ur5", "--position", "3,0,0", "--solver", "numeric", "--json"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["error"], "unreachable");
    assert!(v["reason"].as_str().unwrap().contains("no solution"), "{v}");
    let e = fails(&["ik", "--robot", "ur5", "--pose", "1,2,3"]);
    assert!(e.contains("6 numbers"), "{e}");
    let e = fails(&["ik", "--robot", "ur5", "--T", "1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,2"]);
    assert!(e.contains("rigid transform"), "{e}");
    let e = fails(&["ik", "--robot", "ur5"]);
    assert!(e.contains("give a target"), "{e}");
}

/// The IK contract on the command line: every listed solution meets the
/// target (FK re-measured here), candidates that miss it are counted under
/// `discarded`; a pose a 5-joint arm cannot take exits 2 with the closest
/// configuration, whichever solver, unless --mask frees what it cannot control.
#[test]
fn ik_lists_only_solutions_that_meet_the_target() {
    let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2301);
    let mut discarded = 0;
    for _ in 0..40 {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let t: Vec<String> = target.to_rows().iter().flatten().map(|v| format!("{v:.17}")).collect();
        let t = t.join(",");
        let q0: Vec<String> = q.iter().map(|v| format!("{v:.17}")).collect();
        let q0 = q0.join(",");
        for extra in [&["--all"][..], &["--q0", &q0][..]] {
            let mut args = vec!["ik", "--robot", "scorbot-er-v-plus", "--T", &t, "--json"];
            args.extend_from_slice(extra);
            let v = json(&args);
            for s in v["solutions"].as_array().unwrap() {
                let got: Vec<f64> = s["q"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
                let e = kinema::math::pose_error(&target, &robot.fk(&got).unwrap().world_from_tool);
                assert!(e.position_norm() < 1e-6 && e.rotation_angle() < 1e-6, "{args:?}: {s}");
            }
            discarded += v["discarded"]["count"].as_u64().unwrap();
        }
    }
    assert!(discarded > 0, "no candidate was ever discarded: the test does not exercise the contract");
    let pose = "0.35,0,0.3,0,1.2,0.5";
    for solver in ["auto", "analytic", "numeric"] {
        let args = ["ik", "--robot", "scorbot-er-v-plus", "--pose", pose, "--solver", solver, "--json"];
        let (code, stdout) = exit_and_stdout(&args);
        assert_eq!(code, Some(2), "{args:?}: {stdout}");
        let v: Value = serde_json::from_str(&stdout).unwrap();
        assert_eq!(v["error"], "unreachable");
        let miss =
            v["closest"]["position_error"].as_f64().unwrap() + v["closest"]["orientation_error"].as_f64().unwrap();
        assert!(miss > 1e-3, "{v}");
    }
    // Freeing the rotation about the world z axis makes it reachable.
    let v = json(&["ik", "--robot", "scorbot-er-v-plus", "--pose", pose, "--mask", "1,1,1,1,1,0", "--json"]);
    let got: Vec<f64> = v["solutions"][0]["q"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    let reached = robot.fk(&got).unwrap().world_from_tool;
    assert!((reached.pos - kinema::nalgebra::Vector3::new(0.35, 0.0, 0.3)).norm() < 1e-6);
    let e = fails(&["ik", "--robot", "ur5", "--pose", pose, "--mask", "1,1,1,0,0,2"]);
    assert!(e.contains("0/1"), "{e}");
    // Typed-target flags with a full pose are refused, not ignored.
    let e = fails(&["ik", "--robot", "scorbot-er-v-plus", "--pose", pose, "--pitch", "10", "--roll", "5"]);
    assert!(e.contains("--position"), "{e}");
    // A command line that does not parse is a usage error (64), not "unreachable" (2).
    assert_eq!(exit_and_stdout(&["ik", "--robot", "ur5", "--no-such-flag"]).0, Some(64));
    assert_eq!(exit_and_stdout(&["ik", "--robot", "ur5", "--pose", "1,2,3"]).0, Some(1));
}

/// Batch IK: every line of the input gets a line of output, a solution that
/// meets its target (FK re-measured here) or the stated reason there is none;
/// exit 2 when some line is not solved, 0 when all are, and no file on a
/// malformed input.
#[test]
fn ik_batch_from_a_csv_file() {
    let dir = tempdir("ik-batch");
    let robot = Robot::builtin("ur5").unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2304);
    let mut lines = vec!["# targets".to_string(), "a,b,c".to_string()];
    let mut targets = Vec::new();
    for k in 0..120 {
        let pose = robot.fk(&robot.random_q(&mut rng)).unwrap().world_from_tool;
        let line = match k % 3 {
            0 => pose.to_rows().iter().flatten().map(|v| format!("{v:.17}")).collect::<Vec<_>>().join(","),
            1 => {
                let rpy = pose.rpy(kinema::RpyConvention::Zyx);
                [pose.pos.x, pose.pos.y, pose.pos.z, rpy[0], rpy[1], rpy[2]].map(|v| format!("{v:.17}")).join(",")
            }
            _ => [pose.pos.x, pose.pos.y, pose.pos.z].map(|v| format!("{v:.17}")).join(","),
        };
        lines.push(line);
        targets.push((pose, k % 3 == 2));
    }
    let input = dir.join("targets.csv");
    std::fs::write(&input, lines.join("\n")).unwrap();
    let output = dir.join("q.csv");
    let (i, o) = (input.to_str().unwrap(), output.to_str().unwrap());
    let (code, _) = exit_and_stdout(&["ik", "--robot", "ur5", "--input", i, "--output", o]);
    assert_eq!(code, Some(0));
    let text = std::fs::read_to_string(&output).unwrap();
    let rows: Vec<Vec<String>> = text.lines().skip(1).map(|l| l.split(',').map(String::from).collect()).collect();
    assert_eq!(rows.len(), targets.len());
    for (row, (pose, position_only)) in rows.iter().zip(&targets) {
        assert_eq!(row[1], "solved", "{row:?}");
        let q: Vec<f64> = row[3..9].iter().map(|v| v.parse().unwrap()).collect();
        let e = kinema::math::pose_error(pose, &robot.fk(&q).unwrap().world_from_tool);
        assert!(e.position_norm() < 1e-6, "{row:?}");
        assert!(*position_only || e.rotation_angle() < 1e-6, "{row:?}");
    }
    // An unreachable line and a matrix that is not a rigid transform: stated, exit 2.
    std::fs::write(&input, "0.4,0.1,0.3\n5,0,0\n1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,2\n").unwrap();
    let (code, _) = exit_and_stdout(&["ik", "--robot", "ur5", "--input", i, "--output", o]);
    assert_eq!(code, Some(2));
    let text = std::fs::read_to_string(&output).unwrap();
    let status: Vec<&str> = text.lines().skip(1).map(|l| l.split(',').nth(1).unwrap()).collect();
    assert_eq!(status, ["solved", "unreachable", "invalid"], "{text}");
    // A line of the wrong length is a malformed file: no output at all.
    std::fs::remove_file(&output).unwrap();
    std::fs::write(&input, "0.4,0.1,0.3\n1,2,3,4\n").unwrap();
    let e = fails(&["ik", "--robot", "ur5", "--input", i, "--output", o]);
    assert!(e.contains("line 2") && e.contains("expected 16"), "{e}");
    assert!(!output.exists());
}

/// `kinema ik --psi` on a URDF iiwa: the geometric solver's closed form at
/// that arm angle; every solution has it and reaches the target.
#[test]
fn ik_at_an_arm_angle_on_a_urdf_iiwa() {
    let path = data("iiwa14.urdf");
    let robot = Robot::from_file(&path, None).unwrap();
    let ik = kinema::ik::geo::SrsIk::new(&robot).unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0x5136);
    let q = robot.random_q(&mut rng);
    let rows = robot.fk(&q).unwrap().world_from_tool.to_rows();
    let t: Vec<String> = rows.iter().flatten().map(|v| format!("{v:.17}")).collect();
    let t = t.join(",");
    let psi = kinema::ik::wrap_angle(ik.psi_of(&q) + 0.3);
    let psi_text = format!("{psi:.17}");
    for all in [true, false] {
        let mut args = vec!["ik", "--robot", &path, "--T", &t, "--psi", &psi_text, "--json"];
        if all {
            args.push("--all");
        }
        let v = json(&args);
        assert_eq!(v["solver"], "geo-srs");
        let sols = v["solutions"].as_array().unwrap();
        assert_eq!(sols.len(), if all { 8 } else { 1 }, "{sols:?}");
        for s in sols {
            let got: Vec<f64> = s["q"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
            assert!(kinema::ik::wrap_angle(ik.psi_of(&got) - psi).abs() < 1e-9, "{s}");
            assert!(s["position_error"].as_f64().unwrap() < 1e-9, "{s}");
        }
    }
}

#[test]
fn ik_analytic_solvers_from_the_command_line() {
    // PUMA 560: Pieper solver, all 8 branches, each reaching the target.
    let robot = Robot::builtin("puma560").unwrap();
    let q = [0.3, 0.7, -2.2, 0.4, 0.9, -0.5];
    let rows = robot.fk(&q).unwrap().world_from_tool.to_rows();
    let t: Vec<String> = rows.iter().flatten().map(|v| format!("{v:.17}")).collect();
    let v = json(&["ik", "--robot", "puma560", "--T", &t.join(","), "--all", "--json"]);
    assert_eq!(v["solver"], "pieper");
    let sols = v["solutions"].as_array().unwrap();
    assert_eq!(sols.len(), 8);
    for s in sols {
        assert!(s["position_error"].as_f64().unwrap() < 1e-10, "{s}");
        assert!(s["branch"].as_str().unwrap().contains("shoulder"), "{s}");
    }
    // iiwa with a fixed q3: the closed form keeps q3.
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let q = [0.4, 0.6, -0.3, -1.1, 0.5, 0.9, -0.2];
    let rows = robot.fk(&q).unwrap().world_from_tool.to_rows();
    let t: Vec<String> = rows.iter().flatten().map(|v| format!("{v:.17}")).collect();
    let v = json(&["ik", "--robot", "lbr-iiwa-14-r820", "--T", &t.join(","), "--q3", "-0.3", "--all", "--json"]);
    assert_eq!(v["solver"], "iiwa");
    let sols = v["solutions"].as_array().unwrap();
    assert!(sols.len() >= 2 && sols.len() <= 8);
    let found = sols.iter().any(|s| {
        let got: Vec<f64> = s["q"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        got.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9)
    });
    assert!(found, "original configuration not among {sols:?}");
    // Scorbot typed target, degrees.
    let v = json(&[
        "ik",
        "--robot",
        "scorbot-er-v-plus",
        "--position",
        "0.3,0.1,0.4",
        "--pitch",
        "-60",
        "--roll",
        "10",
        "--deg",
        "--all",
        "--json",
    ]);
    assert_eq!(v["solver"], "scorbot");
    assert!(v["solutions"].as_array().unwrap().len() >= 2);
    // SCARA with the zone rule.
    let v = json(&["ik", "--robot", "scara5", "--position", "0.4,0.6,0.2", "--alpha", "30", "--deg", "--json"]);
    assert_eq!(v["solver"], "scara");
    assert_eq!(v["solutions"][0]["within_limits"], true);
    // Two typed targets at once are refused, not silently reduced to one.
    let e = fails(&["ik", "--robot", "scara5", "--position", "0.4,0.6,0.2", "--alpha", "30", "--approach", "0,0,1"]);
    assert!(e.contains("`alpha` and `approach` belong to different typed targets"), "{e}");
    // A robot without an analytic solver, asked for one.
    let e = fails(&["ik", "--robot", "panda", "--pose", "0.4,0.1,0.5,3.14,0,0", "--solver", "analytic"]);
    assert!(e.contains("no analytic solver"), "{e}");
    // ROMMEL approach it cannot take: exit code 2 with the reason.
    let out = Command::new(env!("CARGO_BIN_EXE_kinema"))
        .args(["ik", "--robot", "rommel", "--position", "0.2,0.5,0.1", "--approach", "0,0,1", "--json"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(v["reason"].as_str().unwrap().contains("orientation"), "{v}");
}

#[test]
fn ik_validate_and_selfmotion() {
    let v = json(&["ik-validate", "--robot", "lbr-iiwa-14-r820", "--n", "500", "--json"]);
    assert!(v["max_error"].as_f64().unwrap() < 1e-9, "{v}");
    assert_eq!(v["recovered_fraction"], 1.0);
    assert!(v["max_error_well_conditioned"].as_f64().unwrap() <= 1e-12, "{v}");
    assert!(v["well_conditioned_cases"].as_u64().unwrap() > 450, "{v}");
    assert!(v["max_error_over_limit"].as_f64().unwrap() < 5.0, "{v}");
    let v = json(&["ik-validate", "--robot", "scorbot-er-v-plus", "--n", "500", "--json"]);
    assert_eq!(v["solver"], "scorbot");
    assert!(v["max_error"].as_f64().unwrap() < 1e-9, "{v}");
    let e = fails(&["ik-validate", "--robot", "panda", "--n", "10"]);
    assert!(e.contains("no analytic solver"), "{e}");
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let want = robot.fk(robot.pose("fig9").unwrap()).unwrap().world_from_tool;
    let v = json(&["selfmotion", "--robot", "lbr-iiwa-14-r820", "--q", "fig9", "--steps", "12", "--json"]);
    let samples = v["samples"].as_array().unwrap();
    assert_eq!(samples.len(), 12);
    for s in samples {
        let q: Vec<f64> = s["q"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        let p = robot.fk(&q).unwrap().world_from_tool;
        assert!((p.pos - want.pos).norm() < 1e-9 && (p.rot - want.rot).norm() < 1e-9);
    }
    let e = fails(&["selfmotion", "--robot", "puma560", "--q", "home"]);
    assert!(e.contains("puma560"), "{e}");
    // The same self-motion from the URDF: the tool pose held, ψ a full turn.
    let urdf = Robot::from_file(data("iiwa14.urdf"), None).unwrap();
    let q = [0.3, 0.5, -0.7, -1.2, 0.4, 0.8, 0.1];
    let want = urdf.fk(&q).unwrap().world_from_tool;
    let q_arg = q.map(|x| x.to_string()).join(",");
    let v = json(&["selfmotion", "--robot", &data("iiwa14.urdf"), "--q", &q_arg, "--steps", "12", "--json"]);
    let samples = v["samples"].as_array().unwrap();
    assert_eq!(samples.len(), 12);
    for s in samples {
        let q: Vec<f64> = s["q"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        let p = urdf.fk(&q).unwrap().world_from_tool;
        assert!((p.pos - want.pos).norm() < 1e-9 && (p.rot - want.rot).norm() < 1e-9);
    }
}

/// With `--deg`, the JSON's angles are degrees throughout: the solutions and
/// the target's rpy, q3 and ψ it echoes; without it, radians.
#[test]
fn ik_json_angles_follow_deg() {
    let pose = "0.5,0.1,0.5,180,0,30";
    let iiwa = "lbr-iiwa-14-r820";
    let deg = json(&["ik", "--robot", iiwa, "--pose", pose, "--deg", "--q3", "30", "--json"]);
    let rad = json(&[
        "ik",
        "--robot",
        iiwa,
        "--pose",
        "0.5,0.1,0.5,3.141592653589793,0,0.5235987755982988",
        "--q3",
        "0.5235987755982988",
        "--json",
    ]);
    assert!((deg["q3"].as_f64().unwrap() - 30.0).abs() < 1e-9, "{deg}");
    assert!((rad["q3"].as_f64().unwrap() - 30f64.to_radians()).abs() < 1e-12, "{rad}");
    for k in 0..3 {
        let (d, r) = (deg["target"]["rpy"][k].as_f64().unwrap(), rad["target"]["rpy"][k].as_f64().unwrap());
        assert!((d - r.to_degrees()).abs() < 1e-9, "rpy[{k}]: {d} ° against {r} rad");
        let (d, r) = (&deg["solutions"][0]["q"], &rad["solutions"][0]["q"]);
        assert!((d[k].as_f64().unwrap() - r[k].as_f64().unwrap().to_degrees()).abs() < 1e-9, "q[{k}]");
    }
    assert!((deg["target"]["rpy"][2].as_f64().unwrap() - 30.0).abs() < 1e-9, "{deg}");
    let psi = json(&["ik", "--robot", iiwa, "--pose", pose, "--deg", "--psi", "20", "--json"]);
    assert!((psi["psi"].as_f64().unwrap() - 20.0).abs() < 1e-9, "{psi}");
}

/// Issue 34, items 5, 6 and 8 through the binary: on a KR 16-like arm
/// (A4, A6 ±350°), `--q0` gets the within-limit solution nearest it (the
/// configuration itself) and `--all` lists it; a configuration with A2 on
/// its 35° limit is solved, strictly within limits; an absurdly far target is
/// refused without quoting a figure that is not a distance.
#[test]
fn ik_q0_turns_limits_and_unreachable_messages() {
    let urdf = data("kr16-like.urdf");
    let robot = Robot::load(&urdf, Some("tool0")).unwrap();
    let matrix_of = |q_deg: &[f64]| {
        let q: Vec<f64> = q_deg.iter().map(|v| v.to_radians()).collect();
        let rows = robot.fk(&q).unwrap().world_from_tool.to_rows();
        rows.iter().flatten().map(|v| format!("{v:.17}")).collect::<Vec<_>>().join(",")
    };
    let q_of = |s: &Value| s["q"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect::<Vec<f64>>();
    let close = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-6);
    for q0 in [[0.0, -30.0, 20.0, 200.0, 30.0, 10.0], [40.0, -60.0, 50.0, -300.0, -45.0, 250.0]] {
        let t = matrix_of(&q0);
        let q0s = q0.map(|v| v.to_string()).join(",");
        let base = ["ik", "--robot", urdf.as_str(), "--tip", "tool0", "--T", t.as_str(), "--q0", q0s.as_str(), "--deg"];
        let v = json(&[&base[..], &["--json"]].concat());
        assert!(close(&q_of(&v["solutions"][0]), &q0), "{v}");
        let all = json(&[&base[..], &["--all", "--json"]].concat());
        assert!(all["solutions"].as_array().unwrap().iter().any(|s| close(&q_of(s), &q0)), "{all}");
        assert_eq!(all["folded"], 0);
    }
    // A2 on its limit (35°).
    let q = [17.0, 35.0, 20.0, 10.0, 30.0, 40.0];
    let t = matrix_of(&q);
    let v = json(&["ik", "--robot", &urdf, "--tip", "tool0", "--T", &t, "--deg", "--json"]);
    let s = &v["solutions"][0];
    assert_eq!(s["within_limits"], true, "{v}");
    let v =
        json(&["ik", "--robot", &urdf, "--tip", "tool0", "--T", &t, "--q0", "17,35,20,10,30,40", "--deg", "--json"]);
    assert!(close(&q_of(&v["solutions"][0]), &q), "{v}");
    // Absurdly far: no "inf m", no figure.
    let far = "1,0,0,1e200,0,1,0,0,0,0,1,0,0,0,0,1";
    for robot in ["puma560", "lbr-iiwa-14-r820", urdf.as_str()] {
        let mut args = vec!["ik", "--robot", robot, "--T", far, "--solver", "analytic"];
        if robot == urdf {
            args.extend(["--tip", "tool0"]);
        }
        let r = kinema(&args);
        assert!(!r.ok && r.stderr.contains("unreachable"), "{robot}: {}", r.stderr);
        assert!(!r.stderr.contains("inf m") && !r.stderr.contains("NaN"), "{robot}: {}", r.stderr);
    }
}
