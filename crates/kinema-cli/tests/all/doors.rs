//! One answer per question across the doors (issue 36): the same request
//! through `kinema … --json` and through the HTTP API's handler gives the same
//! JSON, field for field, on every built-in robot at seeded configurations.
//! Both doors print `kinema_io`'s answer types, so a field added to one door
//! and not the other fails here.

use kinema::Robot;
use kinema_serve::App;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::{json, Value};

use crate::common::kinema;

/// A configuration within the joint limits (within ±π where a joint is unbounded).
fn random_q(robot: &Robot, rng: &mut ChaCha8Rng) -> Vec<f64> {
    robot
        .joints()
        .iter()
        .map(|j| {
            let (lo, hi) = (j.limits.min.max(-std::f64::consts::PI), j.limits.max.min(std::f64::consts::PI));
            rng.random_range(lo..=hi)
        })
        .collect()
}

fn cli_json(args: &[&str]) -> Value {
    let run = kinema(args);
    assert!(run.ok, "kinema {}: {}", args.join(" "), run.stderr);
    serde_json::from_str(&run.stdout).unwrap_or_else(|e| panic!("kinema {}: not JSON ({e})", args.join(" ")))
}

fn api(app: &App, method: &str, path: &str, body: &Value) -> Value {
    let body = if body.is_null() { Vec::new() } else { serde_json::to_vec(body).unwrap() };
    let (status, answer) = app.api(method, path, &body);
    assert_eq!(status, 200, "{method} {path}: {answer}");
    answer
}

#[test]
fn the_cli_and_the_server_answer_fk_manip_and_info_alike() {
    let app = App::new(None).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(36);
    for robot in Robot::builtins().unwrap() {
        let name = robot.name();
        for _ in 0..2 {
            let q = random_q(&robot, &mut rng);
            // Rust's shortest round-trip float text: the CLI reads back exactly these values.
            let q_text = q.iter().map(|v| format!("{v:?}")).collect::<Vec<_>>().join(",");
            let body = json!({"robot": name, "q": q});
            for (command, path) in [("fk", "/api/fk"), ("manip", "/api/manip")] {
                let cli = cli_json(&[command, "--robot", name, "--q", &q_text, "--json"]);
                assert_eq!(cli, api(&app, "POST", path, &body), "{command} of {name} at {q_text}");
            }
        }
        let cli = cli_json(&["info", "--robot", name, "--json"]);
        assert_eq!(cli, api(&app, "GET", &format!("/api/robots/{name}"), &Value::Null), "info of {name}");
    }
    let mut server = api(&app, "GET", "/api/robots", &Value::Null);
    // The server marks its default robot; the CLI has none.
    for r in server.as_array_mut().unwrap() {
        r["default"] = json!(false);
    }
    assert_eq!(cli_json(&["robots", "--json"]), server);
}

/// Shortest round-trip text of numbers, comma-separated: the CLI reads back exactly these values.
fn list(v: &[f64]) -> String {
    v.iter().map(|x| format!("{x:?}")).collect::<Vec<_>>().join(",")
}

#[test]
fn the_cli_and_the_server_answer_ik_alike() {
    let app = App::new(None).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(361);
    // Arms without a self-motion: the server's single answer (`picked`) is one
    // of the listed solutions, so both doors list the same ones.
    for name in ["puma560", "ur5", "scorbot-er-v-plus"] {
        let robot = Robot::builtin(name).unwrap();
        for _ in 0..2 {
            let q = random_q(&robot, &mut rng);
            let pose = robot.fk(&q).unwrap().world_from_tool;
            let p = [pose.pos.x, pose.pos.y, pose.pos.z];
            let rpy = pose.rpy(kinema::RpyConvention::Zyx);
            let text = list(&[p[0], p[1], p[2], rpy[0], rpy[1], rpy[2]]);
            let cli = cli_json(&["ik", "--robot", name, "--pose", &text, "--all", "--json"]);
            let mut server = api(&app, "POST", "/api/ik", &json!({"robot": name, "position": p, "rpy": rpy}));
            // Which solution a single-answer request returns: only the server lists all and marks it.
            let picked = server.as_object_mut().unwrap().remove("picked").unwrap();
            assert!(picked.as_u64().unwrap() < server["solutions"].as_array().unwrap().len() as u64);
            assert_eq!(cli, server, "ik of {name} at {text}");
        }
    }
}

#[test]
fn the_cli_and_the_server_answer_position_and_typed_targets_alike() {
    let app = App::new(None).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(362);
    let mut solved = 0;
    for name in ["scorbot-er-v-plus", "rommel", "scara5", "puma560"] {
        let robot = Robot::builtin(name).unwrap();
        for _ in 0..3 {
            let q = random_q(&robot, &mut rng);
            let pose = robot.fk(&q).unwrap().world_from_tool;
            let p = [pose.pos.x, pose.pos.y, pose.pos.z];
            let approach = pose.rot.column(2);
            // The components each family's arm controls, as flags and as JSON fields.
            let (flags, fields) = match name {
                "scorbot-er-v-plus" => {
                    let (pitch, roll) = (-(q[1] + q[2] + q[3]), q[4]);
                    (
                        vec!["--pitch".to_string(), format!("{pitch:?}"), "--roll".into(), format!("{roll:?}")],
                        json!({"pitch": pitch, "roll": roll}),
                    )
                }
                "rommel" => {
                    let a = [approach.x, approach.y, approach.z];
                    (vec!["--approach".to_string(), list(&a)], json!({"approach": a}))
                }
                "scara5" => {
                    let alpha = q[1] + q[2] + q[4];
                    (vec!["--alpha".to_string(), format!("{alpha:?}")], json!({"alpha": alpha}))
                }
                _ => (vec![], json!({})),
            };
            let mut args = vec!["ik", "--robot", name, "--position"];
            let position = list(&p);
            args.push(&position);
            args.extend(flags.iter().map(String::as_str));
            args.extend(["--all", "--json"]);
            let mut body = json!({"robot": name, "position": p});
            body.as_object_mut().unwrap().extend(fields.as_object().unwrap().clone());
            let run = kinema(&args);
            let (status, mut server) = app.api("POST", "/api/ik", &serde_json::to_vec(&body).unwrap());
            if !run.ok {
                // Out of the typed target's reach (e.g. the SCARA's zone rule): both doors refuse.
                assert_eq!(status, 422, "{body}: {server}");
                continue;
            }
            assert_eq!(status, 200, "{body}: {server}");
            let cli: Value = serde_json::from_str(&run.stdout).unwrap();
            server.as_object_mut().unwrap().remove("picked");
            assert_eq!(cli, server, "ik of {name}: {body}");
            solved += 1;
        }
    }
    assert!(solved >= 9, "only {solved} of 12 targets solved");
}

#[test]
fn the_cli_and_the_server_answer_ptp_and_a_program_alike() {
    let app = App::new(None).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(362);
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("out.csv");
    let csv = csv.to_str().unwrap();
    for name in ["puma560", "panda"] {
        let robot = Robot::builtin(name).unwrap();
        let (from, to) = (random_q(&robot, &mut rng), random_q(&robot, &mut rng));
        let cli = cli_json(&[
            "traj",
            "ptp",
            "--robot",
            name,
            "--from",
            &list(&from),
            "--to",
            &list(&to),
            "--out",
            csv,
            "--json",
        ]);
        let mut server = api(&app, "POST", "/api/traj", &json!({"robot": name, "kind": "ptp", "from": from, "to": to}));
        // The server adds the samples themselves; the CLI wrote them to the CSV.
        for key in ["t", "q", "qd", "qdd"] {
            assert!(server.as_object_mut().unwrap().remove(key).is_some(), "{key}");
        }
        assert_eq!(cli, server, "ptp of {name}");
    }
    let program = "POS a = CART(550mm, -150mm, 400mm, 0deg, 180deg, 0deg)\n\
                   POS b = CART(550mm, 50mm, 400mm, 0deg, 180deg, 0deg)\nPTP a\nWAIT 0.5\nLIN b\n";
    let file = dir.path().join("move.prg");
    std::fs::write(&file, program).unwrap();
    let cli = cli_json(&["run", file.to_str().unwrap(), "--robot", "lbr-iiwa-14-r820", "--out", csv, "--json"]);
    let mut server = api(&app, "POST", "/api/run", &json!({"robot": "lbr-iiwa-14-r820", "program": program}));
    for key in ["t", "q", "qd", "qdd", "warnings_rendered"] {
        assert!(server.as_object_mut().unwrap().remove(key).is_some(), "{key}");
    }
    assert!(cli["motions"].as_array().unwrap().len() == 3, "{cli}");
    assert_eq!(cli, server, "the program on the iiwa");
}

/// The fume hood's swing (its sash blocks the straight motion) and a pose
/// goal under the sash: `kinema plan --json` and `/api/plan` give the same
/// fields and the same samples for the same seed. The budgets are wide so
/// that both searches end by finding their path, not by the clock.
#[test]
fn the_cli_and_the_server_plan_alike() {
    let app = App::new(None).unwrap();
    let scene_path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/scenes/fume-hood.toml");
    let scene = std::fs::read_to_string(scene_path).unwrap();
    let iiwa = "lbr-iiwa-14-r820";
    let deg = std::f64::consts::PI / 180.0;
    let (from, to) =
        ([-90.0 * deg, 60.0 * deg, 0.0, 0.0, 0.0, 0.0, 0.0], [90.0 * deg, 60.0 * deg, 0.0, 0.0, 0.0, 0.0, 0.0]);
    let (home, pose) = ([0.0; 7], [0.6, 0.0, 0.3, std::f64::consts::PI, 0.0, 0.0]);
    let (from_text, to_text, pose_text) = (list(&from), list(&to), list(&pose));
    let cases = [
        (
            ["--from", from_text.as_str(), "--to", to_text.as_str(), "--seed", "7"],
            json!({"from": from, "to": to, "seed": 7}),
        ),
        (["--from", "home", "--pose", pose_text.as_str(), "--seed", "0"], json!({"from": home, "pose": pose})),
    ];
    for (flags, body) in cases {
        let mut args = vec!["plan", "--robot", iiwa, "--scene", scene_path, "--time-limit", "10", "--json"];
        args.extend(flags);
        let mut cli = cli_json(&args);
        let mut request = body.clone();
        request.as_object_mut().unwrap().extend([
            ("robot".to_string(), json!(iiwa)),
            ("scene".to_string(), json!(scene)),
            ("time_limit".to_string(), json!(10.0)),
        ]);
        let mut server = api(&app, "POST", "/api/plan", &request);
        // The CLI prints the samples as rows under its column names; the server as t, q, qd, qdd.
        let (columns, rows) = (cli["columns"].take(), cli["rows"].take());
        let index = |name: &str| columns.as_array().unwrap().iter().position(|c| c == name).unwrap();
        let rows = rows.as_array().unwrap();
        assert_eq!(rows.len(), server["q"].as_array().unwrap().len(), "{body}");
        for (k, row) in rows.iter().enumerate() {
            assert_eq!(row[index("t")], server["t"][k], "t at sample {k}");
            for j in 0..7 {
                for (prefix, key) in [("q", "q"), ("qd", "qd"), ("qdd", "qdd")] {
                    assert_eq!(row[index(&format!("{prefix}{}", j + 1))], server[key][k][j], "{key}{j} at sample {k}");
                }
            }
        }
        let fields = server.as_object_mut().unwrap();
        for key in ["t", "q", "qd", "qdd"] {
            assert!(fields.remove(key).is_some(), "{key}");
        }
        // Wall-clock time is the one field two runs do not share.
        for answer in [&mut cli, &mut server] {
            assert!(answer["plan"]["planning_time"].take().as_f64().unwrap() > 0.0);
        }
        cli.as_object_mut().unwrap().remove("columns");
        cli.as_object_mut().unwrap().remove("rows");
        assert_eq!(cli, server, "plan {body}");
    }
}

/// `PTP … AVOID` through the fume hood's sash: `kinema run --scene` and
/// `/api/run` with the scene plan the same path (the seed comes from the
/// program) and give the same answer.
#[test]
fn the_cli_and_the_server_run_a_ptp_avoid_alike() {
    let app = App::new(None).unwrap();
    let scene_path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/scenes/fume-hood.toml");
    let scene = std::fs::read_to_string(scene_path).unwrap();
    let program = "JVEL 50deg/s\nPTP JOINT(90deg, 60deg, 0, 0, 0, 0, 0) AVOID\n";
    let start = [-std::f64::consts::FRAC_PI_2, 60f64.to_radians(), 0.0, 0.0, 0.0, 0.0, 0.0];
    let dir = tempfile::tempdir().unwrap();
    let (file, csv) = (dir.path().join("swing.prg"), dir.path().join("swing.csv"));
    std::fs::write(&file, program).unwrap();
    let start_text = format!("--start={}", list(&start));
    let cli = cli_json(&[
        "run",
        file.to_str().unwrap(),
        "--robot",
        "lbr-iiwa-14-r820",
        &start_text,
        "--scene",
        scene_path,
        "--out",
        csv.to_str().unwrap(),
        "--json",
    ]);
    let body = json!({"robot": "lbr-iiwa-14-r820", "program": program, "start": start, "scene": scene});
    let mut server = api(&app, "POST", "/api/run", &body);
    let samples = server["q"].as_array().unwrap().len();
    assert!(samples > 100, "{server}");
    for key in ["t", "q", "qd", "qdd", "warnings_rendered"] {
        assert!(server.as_object_mut().unwrap().remove(key).is_some(), "{key}");
    }
    assert_eq!(cli, server, "the AVOID program in the fume hood");
    let written = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(written.lines().count() - 1, samples, "one CSV line per sample");
}
