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
