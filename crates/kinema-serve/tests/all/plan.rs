//! `/api/plan`: the fume hood's swing planned around the sash over HTTP,
//! its samples ending at the goal and clear of the scene; a pose goal as six
//! numbers and as a matrix; the errors of the planner, of the request and
//! of the server's stop condition.

use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Duration;

use kinema::Robot;
use kinema_geometry::{CheckOptions, CollisionCheck};
use kinema_lang::Stop;
use kinema_serve::App;
use serde_json::{json, Value};

use crate::api::{post, start};

const IIWA: &str = "lbr-iiwa-14-r820";
const ZERO: [f64; 7] = [0.0; 7];

fn hood_path() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/fume-hood.toml")
}

fn hood() -> String {
    std::fs::read_to_string(hood_path()).unwrap()
}

/// Either side of the hood at 60° shoulder pitch: the straight swing hits the sash.
fn ends() -> ([f64; 7], [f64; 7]) {
    let (quarter, sixty) = (std::f64::consts::FRAC_PI_2, std::f64::consts::FRAC_PI_3);
    ([-quarter, sixty, 0.0, 0.0, 0.0, 0.0, 0.0], [quarter, sixty, 0.0, 0.0, 0.0, 0.0, 0.0])
}

fn rows(v: &Value) -> Vec<Vec<f64>> {
    v.as_array().unwrap().iter().map(|r| r.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()).collect()
}

#[test]
fn the_hood_swing_is_planned_around_the_sash() {
    let running = start();
    let (from, to) = ends();
    let body = json!({"robot": IIWA, "from": from, "to": to, "scene": hood(), "time_limit": 10.0, "dt": 0.02});
    let answer = post(running.local_addr(), "/api/plan", &body);
    assert_eq!(answer.status, 200, "{}", answer.json);
    let v = &answer.json;
    assert_eq!((v["motion"].as_str(), v["robot"].as_str()), (Some("plan"), Some(IIWA)));
    let q = rows(&v["q"]);
    assert_eq!(q.len() as u64, v["samples"].as_u64().unwrap());
    assert_eq!(q.first().unwrap().as_slice(), from);
    assert_eq!(q.last().unwrap().as_slice(), to);
    let vias = rows(&v["plan"]["via_points"]);
    assert!(vias.len() >= 3, "the straight swing is blocked, so the path turns: {vias:?}");
    let options = CheckOptions { scene: Some(hood_path()), ..Default::default() };
    let check = CollisionCheck::load(IIWA, &options).unwrap();
    assert!(check.first_collision(&from).unwrap().is_none());
    for (k, qk) in q.iter().enumerate() {
        assert_eq!(check.first_collision(qk).unwrap(), None, "sample {k} collides");
    }
    let t = v["t"].as_array().unwrap();
    assert!((t.last().unwrap().as_f64().unwrap() - v["duration"].as_f64().unwrap()).abs() < 1e-12);
}

#[test]
fn a_pose_goal_is_the_same_as_six_numbers_or_a_matrix() {
    let app = App::new(None).unwrap();
    let robot = Robot::builtin(IIWA).unwrap();
    let goal = [0.3, 0.4, 0.6, 0.2, 0.1, -0.4, 0.5];
    let pose = robot.fk(&goal).unwrap().world_from_tool;
    let rpy = pose.rpy(kinema::RpyConvention::Zyx);
    let six = [pose.pos.x, pose.pos.y, pose.pos.z, rpy[0], rpy[1], rpy[2]];
    let mut answers = Vec::new();
    for target in [json!(six), json!(pose.to_rows())] {
        let body = json!({"robot": IIWA, "from": ZERO, "pose": target, "seed": 3, "time_limit": 10.0});
        let (status, mut v) = app.api("POST", "/api/plan", body.to_string().as_bytes());
        assert_eq!(status, 200, "{v}");
        let last = rows(&v["q"]).pop().unwrap();
        let reached = robot.fk(&last).unwrap().world_from_tool;
        assert!((reached.pos - pose.pos).norm() < 1e-9, "{last:?}");
        assert!((reached.rot - pose.rot).norm() < 1e-9, "{last:?}");
        v["plan"]["planning_time"].take();
        answers.push(v);
    }
    // The rows go through a rotation and back, so the goal may differ in the last bits.
    assert_eq!(answers[0]["plan"]["goals"], answers[1]["plan"]["goals"]);
    assert_eq!(answers[0]["samples"], answers[1]["samples"]);
}

#[test]
fn the_planner_s_errors_are_answered_with_its_message() {
    let app = App::new(None).unwrap();
    let (from, to) = ends();
    let scene = hood();
    let ask = |body: Value| app.api("POST", "/api/plan", body.to_string().as_bytes());
    // The arm folded down onto itself.
    let (status, v) =
        ask(json!({"robot": IIWA, "from": [0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 0.0], "to": to, "scene": scene}));
    assert_eq!(status, 422, "{v}");
    let message = v["error"].as_str().unwrap();
    assert!(message.starts_with("the start configuration collides: `link"), "{message}");
    // A budget too small for any search.
    let (status, v) = ask(json!({"robot": IIWA, "from": from, "to": to, "scene": scene, "time_limit": 1e-9}));
    assert_eq!(status, 422, "{v}");
    assert!(v["error"].as_str().unwrap().contains("no collision-free path found before the time limit"), "{v}");
    // A wish above the server's cap is cut to it, and the free straight motion needs no search.
    let (status, v) =
        ask(json!({"robot": IIWA, "from": ZERO, "to": [0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], "time_limit": 1e300}));
    assert_eq!(status, 200, "{v}");
    assert_eq!(v["plan"]["iterations"], 0);
    for (body, part) in [
        (json!({"robot": IIWA, "from": from}), "\"to\" or \"pose\""),
        (json!({"robot": IIWA, "from": from, "to": to, "pose": [0.5, 0.0, 0.5, 0.0, 0.0, 0.0]}), "\"to\" or \"pose\""),
        (json!({"robot": IIWA, "from": from, "to": to, "time_limit": -1.0}), "time_limit"),
        (json!({"robot": IIWA, "from": from, "to": to, "speed": 0.0}), "speed"),
        (json!({"robot": IIWA, "from": from, "to": to, "dt": 0.0}), "dt"),
        (json!({"robot": IIWA, "from": from, "to": to, "profile": "zigzag"}), "zigzag"),
        (json!({"robot": IIWA, "from": from, "pose": [0.5, 0.0, 0.5]}), "expected"),
        (json!({"robot": IIWA, "from": from, "to": to, "iterations": 5}), "iterations"),
    ] {
        let (status, v) = ask(body.clone());
        assert_eq!(status, 400, "{body}: {v}");
        assert!(v["error"].as_str().unwrap().contains(part), "{body}: {v}");
    }
    let (status, v) = ask(json!({"robot": IIWA, "from": [0.0, 0.0], "to": to}));
    assert_eq!(status, 422, "{v}");
}

#[test]
fn a_search_stops_with_the_server_s_stop_condition() {
    let app = App::new(None).unwrap();
    let (from, to) = ends();
    let body = json!({"robot": IIWA, "from": from, "to": to, "scene": hood(), "time_limit": 10.0}).to_string();
    let raised = Stop::never().with_flag(Arc::new(AtomicBool::new(true)));
    let (status, v) = app.api_until("POST", "/api/plan", body.as_bytes(), &raised);
    assert_eq!(status, 503, "{v}");
    let (status, v) = app.api_until("POST", "/api/plan", body.as_bytes(), &Stop::after(Duration::ZERO));
    assert_eq!(status, 422, "{v}");
    assert!(v["error"].as_str().unwrap().contains("planning was stopped: the time budget"), "{v}");
}
