//! HTTP-level tests of the API: a real server on a free port, requests over
//! plain TCP sockets, answers compared with the library.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::Duration;

use kinema::ik::IiwaIk;
use kinema::{Frame, Robot};
use kinema_serve::{Running, Server};
use rand::SeedableRng;
use serde_json::{json, Value};

use crate::mutate;

/// One answer: status, raw header block, body parsed as JSON (Null if not JSON).
pub(crate) struct Answer {
    pub(crate) status: u16,
    pub(crate) headers: String,
    pub(crate) json: Value,
}

pub(crate) fn start() -> Running {
    let robot = Robot::builtin("lbr-iiwa-14-r820").expect("built-in robot");
    Server::bind("127.0.0.1:0", Some(robot)).expect("binds a free port").spawn()
}

/// Sends `head` (request line and headers, without the blank line) and
/// `body`, reads the whole answer (the request asks to close).
pub(crate) fn raw(addr: SocketAddr, head: &str, body: &[u8]) -> Answer {
    let mut req = format!("{head}\r\nConnection: close\r\n\r\n").into_bytes();
    req.extend_from_slice(body);
    exchange(addr, &req)
}

/// Sends `req` as it is and reads the whole answer (the server closes after it).
pub(crate) fn exchange(addr: SocketAddr, req: &[u8]) -> Answer {
    let mut s = TcpStream::connect(addr).expect("connects");
    s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
    // The server may answer (and close) before reading everything it was sent.
    let _ = s.write_all(req);
    let mut out = Vec::new();
    let _ = s.read_to_end(&mut out);
    let split = out.windows(4).position(|w| w == b"\r\n\r\n").unwrap_or(out.len());
    let headers = String::from_utf8_lossy(&out[..split]).into_owned();
    let body = out.get(split + 4..).unwrap_or_default();
    let status = headers.split_whitespace().nth(1).and_then(|s| s.parse().ok()).unwrap_or(0);
    assert!(!headers.to_ascii_lowercase().contains("transfer-encoding"), "bodies are sent with a Content-Length");
    Answer { status, headers, json: serde_json::from_slice(body).unwrap_or(Value::Null) }
}

pub(crate) fn call(addr: SocketAddr, method: &str, path: &str, body: &[u8]) -> Answer {
    let head = format!(
        "{method} {path} HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\nContent-Length: {}",
        body.len()
    );
    raw(addr, &head, body)
}

pub(crate) fn post(addr: SocketAddr, path: &str, body: &Value) -> Answer {
    call(addr, "POST", path, body.to_string().as_bytes())
}

fn rows(v: &Value) -> Vec<Vec<f64>> {
    v.as_array()
        .expect("rows")
        .iter()
        .map(|r| r.as_array().expect("row").iter().map(|x| x.as_f64().expect("number")).collect())
        .collect()
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array().expect("array").iter().map(|x| x.as_f64().expect("number")).collect()
}

#[test]
fn robots_list_and_info() {
    let server = start();
    let addr = server.local_addr();
    let list = call(addr, "GET", "/api/robots", b"");
    assert_eq!(list.status, 200);
    let names: Vec<&str> = list.json.as_array().unwrap().iter().map(|r| r["name"].as_str().unwrap()).collect();
    assert_eq!(names.len(), kinema::builtin_names().count());
    for r in list.json.as_array().unwrap() {
        assert!(r["dof"].as_u64().unwrap() >= 5);
        assert!(!r["description"].as_str().unwrap().is_empty());
        assert_eq!(r["default"].as_bool(), Some(r["name"] == "lbr-iiwa-14-r820"));
    }
    let info = call(addr, "GET", "/api/robots/puma560", b"");
    assert_eq!(info.status, 200);
    let puma = Robot::builtin("puma560").unwrap();
    assert_eq!(info.json["dof"], 6);
    assert_eq!(floats(&info.json["home"]), puma.home());
    assert_eq!(info.json["joints"].as_array().unwrap().len(), 6);
    assert_eq!(info.json["joints"][0]["type"], "revolute");
    assert!(info.json["joints"][0]["geometry"]["d"].is_number());
    assert!(info.json["poses"]["qr"].is_array());
    assert_eq!(info.json["ik"]["analytic"], "pieper");
    let iiwa = call(addr, "GET", "/api/robots/lbr-iiwa-14-r820", b"");
    assert_eq!(iiwa.json["ik"]["q3"], true);
    // The page and its assets.
    let page = raw(addr, &format!("GET / HTTP/1.1\r\nHost: {addr}"), b"");
    assert_eq!(page.status, 200);
    assert!(page.headers.contains("text/html"));
}

#[test]
fn fk_equals_the_library() {
    let server = start();
    let addr = server.local_addr();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    for name in kinema::builtin_names() {
        let robot = Robot::builtin(name).unwrap();
        for _ in 0..5 {
            let q = robot.random_q(&mut rng);
            let a = post(addr, "/api/fk", &json!({"robot": name, "q": q}));
            assert_eq!(a.status, 200, "{name}: {}", a.json);
            let fk = robot.fk(&q).unwrap();
            let t = rows(&a.json["T"]);
            let expected = fk.world_from_tool.to_rows();
            for r in 0..4 {
                for c in 0..4 {
                    assert!((t[r][c] - expected[r][c]).abs() <= 1e-12, "{name} T[{r}][{c}]");
                }
            }
            assert_eq!(a.json["within_limits"], fk.within_limits());
            let frames = robot.link_frames(&q).unwrap();
            let got = a.json["frames"].as_array().unwrap();
            assert_eq!(got.len(), frames.len());
            for (f, g) in frames.iter().zip(got) {
                let p = floats(&g["position"]);
                assert!((f.pos - kinema::nalgebra::Vector3::new(p[0], p[1], p[2])).norm() <= 1e-12);
            }
            assert_eq!(a.json["joints"].as_array().unwrap().len(), robot.dof());
        }
    }
}

#[test]
fn ik_reaches_the_target_and_recovers_q_with_its_q3() {
    let server = start();
    let addr = server.local_addr();
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
    for _ in 0..20 {
        let q = robot.random_q(&mut rng);
        let target = robot.fk(&q).unwrap().world_from_tool;
        let a = post(addr, "/api/ik", &json!({"T": target.to_rows(), "q3": q[2], "q0": q}));
        assert_eq!(a.status, 200, "{}", a.json);
        assert_eq!(a.json["solver"], "iiwa");
        let sols = a.json["solutions"].as_array().unwrap();
        assert!(!sols.is_empty());
        let mut best = f64::INFINITY;
        for s in sols {
            let sq = floats(&s["q"]);
            // Each solution reaches the target, as the server says and as FK says.
            assert!(s["position_error"].as_f64().unwrap() < 1e-9);
            assert!(s["orientation_error"].as_f64().unwrap() < 1e-9);
            let e = kinema::math::pose_error(&target, &robot.fk(&sq).unwrap().world_from_tool);
            assert!(e.position_norm() < 1e-9 && e.rotation_angle() < 1e-9);
            assert!(s["branch"].is_string() && s["within_limits"].is_boolean());
            let d = sq.iter().zip(&q).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            best = best.min(d);
        }
        assert!(best < 1e-7, "the original q is among the solutions (closest {best:e})");
        // `nearest` points at the original.
        let n = a.json["nearest"].as_u64().expect("nearest with q0") as usize;
        let nq = floats(&sols[n]["q"]);
        assert!(nq.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-7));
    }
    // The same through position + rpy, and through the library's closed form at q3.
    let q = [0.3, 0.6, -0.4, -1.1, 0.2, 0.9, -0.3];
    let p = robot.fk(&q).unwrap().world_from_tool;
    let rpy = p.rpy(kinema::RpyConvention::Zyx);
    let a = post(addr, "/api/ik", &json!({"position": [p.pos.x, p.pos.y, p.pos.z], "rpy": rpy, "q3": q[2]}));
    assert_eq!(a.status, 200);
    let lib = IiwaIk::new(&robot).unwrap().solve_q3(&p, q[2]).unwrap();
    assert_eq!(a.json["solutions"].as_array().unwrap().len(), lib.len());
}

/// A server for the URDF iiwa (the geometric solver): `/api/ik` solves at
/// an arm angle, each solution having it; `/api/traj` holds the start's ψ.
#[test]
fn arm_angle_on_a_urdf_iiwa() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../kinema/tests/data/iiwa14.urdf");
    let robot = Robot::from_file(path, None).unwrap();
    let ik = kinema::ik::geo::SrsIk::new(&robot).unwrap();
    let server = Server::bind("127.0.0.1:0", Some(robot.clone())).expect("binds a free port").spawn();
    let addr = server.local_addr();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0x5137);
    let q = robot.random_q(&mut rng);
    let target = robot.fk(&q).unwrap().world_from_tool;
    let psi = kinema::ik::wrap_angle(ik.psi_of(&q) - 0.4);
    let a = post(addr, "/api/ik", &json!({"T": target.to_rows(), "psi": psi}));
    assert_eq!(a.status, 200, "{}", a.json);
    assert_eq!((&a.json["solver"], &a.json["psi"], &a.json["q3"]), (&json!("geo-srs"), &json!(psi), &Value::Null));
    let sols = a.json["solutions"].as_array().unwrap();
    assert_eq!(sols.len(), 8);
    for s in sols {
        let sq = floats(&s["q"]);
        assert!(kinema::ik::wrap_angle(ik.psi_of(&sq) - psi).abs() < 1e-9, "{s}");
        assert!(s["position_error"].as_f64().unwrap() < 1e-9, "{s}");
    }
    let from = [0.3, 1.0, 0.4, -0.8, 0.2, 0.9, 0.1];
    let p = robot.fk(&from).unwrap().world_from_tool;
    let goal = [p.pos.x + 0.05, p.pos.y + 0.1, p.pos.z - 0.1];
    let body = json!({"kind": "lin", "from": from, "position": goal, "rpy": p.rpy(kinema::RpyConvention::Zyx),
        "vmax": 0.2, "amax": 1.0, "psi": "hold"});
    let a = post(addr, "/api/traj", &body);
    assert_eq!(a.status, 200, "{}", a.json);
    let psi0 = ik.psi_of(&from);
    let drift =
        rows(&a.json["q"]).iter().map(|q| kinema::ik::wrap_angle(ik.psi_of(q) - psi0).abs()).fold(0.0, f64::max);
    assert!(drift < 1e-9, "ψ drifted by {drift}");
}

#[test]
fn ik_unreachable_and_other_robots() {
    let server = start();
    let addr = server.local_addr();
    let a = post(addr, "/api/ik", &json!({"position": [3.0, 0.0, 0.5], "rpy": [0, 3.0, 0]}));
    assert_eq!(a.status, 422);
    assert!(a.json["error"].as_str().unwrap().contains("unreachable"), "{}", a.json);
    // A robot without an analytic solver: numeric, from q0.
    let panda = Robot::builtin("panda").unwrap();
    let q = [0.1, -0.3, 0.2, -2.0, 0.1, 1.8, 0.5];
    let t = panda.fk(&q).unwrap().world_from_tool;
    let a = post(addr, "/api/ik", &json!({"robot": "panda", "T": t.to_rows(), "q0": panda.home()}));
    assert_eq!(a.status, 200, "{}", a.json);
    assert_eq!(a.json["solver"], "numeric");
    assert!(a.json["solutions"][0]["position_error"].as_f64().unwrap() < 1e-6);
    // q3 on a robot that is not an iiwa.
    let a = post(addr, "/api/ik", &json!({"robot": "panda", "T": t.to_rows(), "q3": 0.1}));
    assert_eq!(a.status, 422);
    assert!(a.json["error"].as_str().unwrap().contains("q3"));
}

#[test]
fn manipulability_matches_the_library() {
    let server = start();
    let addr = server.local_addr();
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let q = [0.0, 0.5, 0.0, -1.2, 0.0, 0.6, 0.0];
    let a = post(addr, "/api/manip", &json!({"q": q}));
    assert_eq!(a.status, 200);
    let rep = kinema::analysis::report(&robot.jacobian(&q, Frame::Base).unwrap()).unwrap();
    assert!((a.json["yoshikawa"].as_f64().unwrap() - rep.yoshikawa).abs() < 1e-12);
    let e = &a.json["ellipsoid_translation"];
    assert_eq!(floats(&e["radii"]).len(), 3);
    assert_eq!(rows(&e["axes"]).len(), 3);
    let c = floats(&e["centre"]);
    assert!((c[2] - robot.fk(&q).unwrap().world_from_tool.pos.z).abs() < 1e-12);
}

#[test]
fn trajectories_and_programs() {
    let server = start();
    let addr = server.local_addr();
    let from = [0.0, 0.3, 0.0, -1.0, 0.0, 0.5, 0.0];
    let to = [0.5, 0.6, -0.2, -1.4, 0.3, 0.9, 0.4];
    let a = post(addr, "/api/traj", &json!({"kind": "ptp", "from": from, "to": to, "jacc": 2.0, "dt": 0.01}));
    assert_eq!(a.status, 200, "{}", a.json);
    let t = floats(&a.json["t"]);
    let q = rows(&a.json["q"]);
    assert_eq!(t.len(), q.len());
    assert_eq!(t[0], 0.0);
    assert!((t[t.len() - 1] - a.json["duration"].as_f64().unwrap()).abs() < 1e-12);
    assert!(q[0].iter().zip(&from).all(|(a, b)| (a - b).abs() < 1e-12));
    assert!(q[q.len() - 1].iter().zip(&to).all(|(a, b)| (a - b).abs() < 1e-9));
    assert_eq!(rows(&a.json["qd"]).len(), t.len());

    // LIN to a pose 10 cm lower, tool orientation kept.
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let start_q = [0.0, 0.6, 0.0, -1.3, 0.0, 0.8, 0.0];
    let p = robot.fk(&start_q).unwrap().world_from_tool;
    let goal = [p.pos.x + 0.05, p.pos.y, p.pos.z - 0.1];
    let a = post(
        addr,
        "/api/traj",
        &json!({"kind": "lin", "from": start_q, "position": goal, "rpy": p.rpy(kinema::RpyConvention::Zyx), "vmax": 0.2, "amax": 1.0}),
    );
    assert_eq!(a.status, 200, "{}", a.json);
    let q = rows(&a.json["q"]);
    let end = robot.fk(q.last().unwrap()).unwrap().world_from_tool.pos;
    assert!((end - kinema::nalgebra::Vector3::from(goal)).norm() < 1e-6);
    // The self-motion policy: q3 held by default and with "hold"; steered,
    // it moves; a value the start does not have, or both q3 and ψ, are 4xx.
    let from2 = [0.3, 1.0, 0.4, -0.8, 0.2, 0.9, 0.1];
    let p2 = robot.fk(&from2).unwrap().world_from_tool;
    let goal2 = [p2.pos.x + 0.05, p2.pos.y + 0.1, p2.pos.z - 0.1];
    let lin = |extra: Value| {
        let mut body = json!({"kind": "lin", "from": from2, "position": goal2,
            "rpy": p2.rpy(kinema::RpyConvention::Zyx), "vmax": 0.2, "amax": 1.0});
        body.as_object_mut().unwrap().extend(extra.as_object().unwrap().clone());
        post(addr, "/api/traj", &body)
    };
    let q3_moves = |a: &Answer| rows(&a.json["q"]).iter().map(|q| (q[2] - 0.4).abs()).fold(0.0, f64::max);
    for extra in [json!({}), json!({"q3": "hold"}), json!({"q3": 0.4})] {
        let a = lin(extra.clone());
        assert_eq!(a.status, 200, "{extra}: {}", a.json);
        assert!(q3_moves(&a) < 1e-9, "{extra}");
    }
    let a = lin(json!({"q3": "manipulability"}));
    assert_eq!(a.status, 200, "{}", a.json);
    assert!(q3_moves(&a) > 1e-3);
    for (extra, says) in [
        (json!({"q3": 0.5}), "q3 = 0.400000"),
        (json!({"q3": "hold", "psi": 0.1}), "not both"),
        (json!({"q3": "sideways"}), "sideways"),
    ] {
        let a = lin(extra.clone());
        assert!((400..500).contains(&a.status), "{extra}: {}", a.status);
        assert!(a.json["error"].as_str().unwrap().contains(says), "{extra}: {}", a.json);
    }

    // The sample cap.
    let a = post(
        addr,
        "/api/traj",
        &json!({"kind": "ptp", "from": from, "to": to, "jacc": 2.0, "duration": 100.0, "dt": 0.0001}),
    );
    assert_eq!(a.status, 422);
    assert!(a.json["error"].as_str().unwrap().contains("200000"), "{}", a.json);

    // A program from examples/.
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/programs/");
    let program = std::fs::read_to_string(format!("{dir}scorbot_square.prg")).unwrap();
    let a = post(addr, "/api/run", &json!({"robot": "scorbot-er-v-plus", "program": program, "dt": 0.05}));
    assert_eq!(a.status, 200, "{}", a.json);
    let t = floats(&a.json["t"]);
    assert!(t.len() > 10);
    assert_eq!(rows(&a.json["q"]).len(), t.len());
    assert_eq!(rows(&a.json["qdd"])[0].len(), 5);
    assert!(a.json["motions"].as_array().unwrap().len() >= 6);
    assert!(a.json["warnings"].is_array());
    // A program with an error: 422 with the rendered diagnostics, no colour codes.
    let a = post(addr, "/api/run", &json!({"program": "PTP nowhere\nWAIT 5mm\n"}));
    assert_eq!(a.status, 422);
    let d = a.json["diagnostics"].as_str().unwrap();
    assert!(d.contains("program:2:6") && d.contains("WAIT 5mm") && !d.contains('\u{1b}'), "{d}");
    assert!(a.json["error"].as_str().unwrap().starts_with("the program does not compile"));
    // A program that would produce too many samples.
    let a = post(addr, "/api/run", &json!({"program": "WAIT 100s\n", "dt": 0.0001}));
    assert_eq!(a.status, 422, "{}", a.json);
}

#[test]
fn bad_requests_get_4xx_and_a_json_error() {
    let server = start();
    let addr = server.local_addr();
    let cases: &[(&str, &str, &[u8], u16, &str)] = &[
        ("POST", "/api/fk", b"{\"q\": [0, 0.5", 400, "expected JSON"),
        ("POST", "/api/fk", b"", 400, "empty"),
        ("POST", "/api/fk", b"[1, 2]", 400, "expected JSON"),
        ("POST", "/api/fk", b"{\"q\": [NaN, 0, 0, 0, 0, 0, 0]}", 400, "expected"),
        ("POST", "/api/fk", b"{\"q\": [1e999, 0, 0, 0, 0, 0, 0]}", 400, "out of range"),
        ("POST", "/api/fk", b"{\"q\": [0, \"x\", 0, 0, 0, 0, 0]}", 400, "invalid type"),
        ("POST", "/api/fk", b"{\"q\": [0, 0, 0], \"qq\": 1}", 400, "unknown field"),
        ("POST", "/api/fk", b"{\"q\": [0, 0.5]}", 422, "7 joints, but 2"),
        ("POST", "/api/fk", b"{\"robot\": \"r2d2\", \"q\": [0]}", 422, "unknown robot `r2d2`"),
        ("POST", "/api/fk", b"\xff\xfe{}", 400, "UTF-8"),
        ("POST", "/api/manip", b"{\"q\": []}", 422, "7 joints"),
        ("POST", "/api/ik", b"{\"rpy\": [0, 0, 0]}", 400, "\"T\" alone or"),
        ("POST", "/api/ik", b"{\"position\": [0.5, 0, 0.5], \"rpy\": [0, 0, 0], \"alpha\": 1}", 400, "complete a"),
        ("POST", "/api/ik", b"{\"position\": [0.5, 0, 0.5], \"pitch\": 1}", 422, "invalid `roll`: missing"),
        ("POST", "/api/ik", b"{\"position\": [0.5, 0, 0.5], \"approach\": [0, 0, 0]}", 422, "zero vector"),
        ("POST", "/api/ik", b"{\"position\": [0.5, 0, 0.5], \"alpha\": 0}", 422, "SCARA"),
        ("POST", "/api/ik", b"{\"T\": [[1,0,0,0],[0,1,0,0],[0,0,1,0]]}", 400, "length 3"),
        ("POST", "/api/ik", b"{\"T\": [[2,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}", 422, "rotation"),
        ("POST", "/api/ik", b"{\"T\": [[1,0,0,0.5],[0,1,0,0],[0,0,1,0.5],[0,0,0,1]], \"q0\": [1]}", 422, "7 joints"),
        (
            "POST",
            "/api/ik",
            b"{\"T\": [[1,0,0,0.5],[0,1,0,0],[0,0,1,0.5],[0,0,0,1]], \"solver\": \"magic\"}",
            400,
            "solver",
        ),
        ("POST", "/api/traj", b"{\"kind\": \"ptp\", \"from\": [0,0,0,0,0,0,0]}", 400, "needs \"to\""),
        ("POST", "/api/traj", b"{\"kind\": \"spline\", \"from\": [0,0,0,0,0,0,0]}", 400, "kind `spline`"),
        (
            "POST",
            "/api/traj",
            b"{\"kind\": \"ptp\", \"from\": [0,0,0,0,0,0,0], \"to\": [0,0,0,0,0,0,0], \"dt\": 0}",
            400,
            "dt",
        ),
        (
            "POST",
            "/api/traj",
            b"{\"kind\": \"ptp\", \"from\": [0,0,0,0,0,0,0], \"to\": [9,0,0,0,0,0,0]}",
            422,
            "invalid `to`: 9; expected a value within the joint's limits",
        ),
        ("POST", "/api/run", b"{\"program\": 42}", 400, "invalid type"),
        ("POST", "/api/run", b"{\"program\": \"HOME\", \"start\": [0]}", 422, "7 joints"),
        ("GET", "/api/fk", b"", 405, "use POST"),
        ("PUT", "/api/run", b"{}", 405, "use POST"),
        ("POST", "/api/robots", b"{}", 405, "use GET"),
        ("DELETE", "/api/robots/puma560", b"", 405, "use GET"),
        ("GET", "/api/robots/r2d2", b"", 404, "unknown robot `r2d2`"),
        ("GET", "/api/nothing", b"", 404, "no such path"),
        ("GET", "/etc/passwd", b"", 404, "no such path"),
        ("POST", "/", b"{}", 405, "GET"),
    ];
    for (method, path, body, status, text) in cases {
        let a = call(addr, method, path, body);
        let shown = String::from_utf8_lossy(body);
        assert_eq!(a.status, *status, "{method} {path} {shown}: {}", a.json);
        let e = a.json["error"].as_str().unwrap_or_else(|| panic!("{method} {path}: no JSON error: {}", a.headers));
        assert!(e.contains(text), "{method} {path} {shown}: `{e}` lacks `{text}`");
        assert!(a.headers.to_ascii_lowercase().contains("content-type: application/json"));
        if *status == 405 {
            assert!(a.headers.contains("Allow:"), "{}", a.headers);
        }
    }
    // Still answering.
    assert_eq!(call(addr, "GET", "/api/robots", b"").status, 200);
}

/// Limits so large a PTP would last 1e-50 s used to give one sample at the
/// target; the Panda's trapezoid PTP broke its jerk limits. Both are 422s
/// naming the cause, as on the CLI and in Python.
#[test]
fn extreme_limits_and_acceleration_steps_are_refused() {
    let server = start();
    let addr = server.local_addr();
    let from = [0.0, 0.3, 0.0, -1.0, 0.0, 0.5, 0.0];
    let to = [0.5, 0.6, -0.2, -1.4, 0.3, 0.9, 0.4];
    let a = post(addr, "/api/traj", &json!({"kind": "ptp", "from": from, "to": to, "jvel": 1e100, "jacc": 1e100}));
    assert_eq!(a.status, 422, "{}", a.json);
    assert!(a.json["error"].as_str().unwrap().contains("shorter than"), "{}", a.json);
    let panda = [0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.785];
    let goal = [0.5, -0.3, 0.2, -2.0, 0.1, 1.8, 0.6];
    // The trapezoid named: without a profile the panda gets the S-curve its jerk limits need.
    let a = post(
        addr,
        "/api/traj",
        &json!({"robot": "panda", "kind": "ptp", "from": panda, "to": goal, "profile": "trapezoid"}),
    );
    assert_eq!(a.status, 422, "{}", a.json);
    assert!(a.json["error"].as_str().unwrap().contains("jerk limit"), "{}", a.json);
    let a = post(
        addr,
        "/api/traj",
        &json!({"robot": "panda", "kind": "ptp", "from": panda, "to": goal, "profile": "scurve"}),
    );
    assert_eq!(a.status, 200, "{}", a.json);
}

/// Issue 35, the fuzz target for server requests: random edits of valid
/// bodies for every endpoint (numbers made huge or NaN, brackets cut, keys
/// duplicated…) are answered in-process. No answer is a 500 (a panic or an
/// internal error), every answer is JSON, and an accepted one holds no
/// number JSON could not carry (serde_json writes NaN and inf as null).
#[test]
fn random_request_bodies_are_answered_never_with_a_500() {
    use rand::Rng;
    let app = kinema_serve::App::new(None).unwrap();
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let from = [0.3, 1.0, 0.4, -0.8, 0.2, 0.9, 0.1];
    let p = robot.fk(&from).unwrap().world_from_tool;
    let rpy = p.rpy(kinema::RpyConvention::Zyx);
    let valid = [
        ("/api/fk", json!({"robot": "puma560", "q": [0.1, 0.2, 0.3, 0.4, 0.5, 0.6]})),
        ("/api/ik", json!({"T": p.to_rows(), "q3": 0.4})),
        ("/api/manip", json!({"q": from})),
        (
            "/api/traj",
            json!({"kind": "ptp", "from": from, "to": [0.0, 0.5, 0.0, -1.0, 0.0, 0.5, 0.0], "jacc": 2.0, "dt": 0.05}),
        ),
        (
            "/api/traj",
            json!({"kind": "lin", "from": from, "position": [p.pos.x, p.pos.y + 0.1, p.pos.z], "rpy": rpy, "vmax": 0.2, "amax": 1.0}),
        ),
        ("/api/run", json!({"robot": "scara5", "program": "HOME 1\nMOVEZ -50, 1\nWAIT 0.5s\n", "dt": 0.05})),
        (
            "/api/scene",
            json!({"scene": "[[obstacle]]\nname = \"block\"\nbox = [0.2, 0.3, 0.1]\npose = [0.5, 0, 0.2, 0, 0, 0]\n"}),
        ),
    ];
    let sources: Vec<(&str, String)> = valid.iter().map(|(path, body)| (*path, body.to_string())).collect();
    for (path, body) in &sources {
        assert_eq!(app.handle("POST", path, body.as_bytes()).status, 200, "{path} {body}");
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0x35f);
    let (mut accepted, mut refused) = (0, 0);
    for case in 0..mutate::fuzz_cases(1500) {
        let (path, source) = &sources[case % sources.len()];
        let body = if case % 10 == 0 { mutate::random_text(&mut rng) } else { mutate::mutate(source, &mut rng) };
        let body = if rng.random_bool(0.1) { mutate::mutate(&body, &mut rng) } else { body };
        let reply = app.handle("POST", path, body.as_bytes());
        assert!((200..500).contains(&reply.status), "{path} {body}: {}", String::from_utf8_lossy(&reply.body));
        let answer: Value =
            serde_json::from_slice(&reply.body).unwrap_or_else(|e| panic!("{path} {body}: not JSON: {e}"));
        if reply.status == 200 {
            accepted += 1;
            // `condition` is null at a singularity (infinite there, as the README says); the
            // IK answer's `closest` and `branch` may be null.
            let text = answer.to_string().replace("\"condition\":null", "");
            assert!(!text.contains("null") || *path == "/api/ik", "{path} {body}: {answer}");
        } else {
            refused += 1;
            assert!(answer["error"].as_str().is_some_and(|e| !e.is_empty()), "{path} {body}: {answer}");
        }
    }
    assert!(accepted > 100 && refused > 500, "accepted {accepted}, refused {refused}");
}

/// `/api/collide` answers as `kinema collide --json` does (the same
/// `kinema_io::CollideAnswer`), with a scene sent as TOML text; `/api/ik`
/// with the same scene discards the solutions in collision.
#[test]
fn collide_and_ik_in_a_scene() {
    let running = start();
    let addr = running.local_addr();
    let scene_path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/fume-hood.toml");
    let scene = std::fs::read_to_string(&scene_path).unwrap();
    let iiwa = "lbr-iiwa-14-r820";

    let home = post(addr, "/api/collide", &json!({"robot": iiwa, "q": [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]}));
    assert_eq!(home.status, 200, "{}", home.json);
    assert_eq!(home.json["collision"], false);
    assert!(home.json["min_distance"]["distance"].as_f64().unwrap() > 0.0);

    // The default elbow-up solution of the fume-hood target hits the sash.
    let target = json!({"robot": iiwa, "position": [0.6, 0.0, 0.3], "rpy": [std::f64::consts::PI, 0.0, 0.0]});
    let plain = post(addr, "/api/ik", &target);
    let picked = plain.json["picked"].as_u64().unwrap() as usize;
    let q = plain.json["solutions"][picked]["q"].clone();
    let hit = post(addr, "/api/collide", &json!({"robot": iiwa, "q": q, "scene": scene}));
    assert_eq!(hit.status, 200, "{}", hit.json);
    assert_eq!(hit.json["collision"], true, "{}", hit.json);
    let pairs = hit.json["pairs"].as_array().unwrap();
    assert!(pairs.iter().any(|p| p["b"] == "sash" || p["a"] == "sash"), "{}", hit.json);

    let mut in_scene = target.clone();
    in_scene["scene"] = json!(scene);
    let solved = post(addr, "/api/ik", &in_scene);
    assert_eq!(solved.status, 200, "{}", solved.json);
    let solutions = solved.json["solutions"].as_array().unwrap();
    assert!(!solutions.is_empty());
    for s in solutions {
        let free = post(addr, "/api/collide", &json!({"robot": iiwa, "q": s["q"], "scene": scene}));
        assert_eq!(free.json["collision"], false, "{} is free: {}", s["q"], free.json);
    }
    let discarded = solved.json["discarded"]["candidates"].as_array().unwrap();
    assert!(discarded.iter().any(|c| c["reason"] == "collision"), "{}", solved.json);

    // Bad requests say what is wrong.
    let bad = post(
        addr,
        "/api/collide",
        &json!({"robot": iiwa, "q": [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], "scene": "[[obstacle]]\nname = 1\n"}),
    );
    assert_eq!(bad.status, 422, "{}", bad.json);
    assert!(bad.json["error"].as_str().unwrap().contains("scene"), "{}", bad.json);
    let short = post(addr, "/api/collide", &json!({"robot": iiwa, "q": [0.0, 0.0, 0.0]}));
    assert_eq!(short.status, 422, "{}", short.json);
    let margin =
        post(addr, "/api/collide", &json!({"robot": iiwa, "q": [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], "margin": -1.0}));
    assert_eq!(margin.status, 422, "{}", margin.json);
    assert!(margin.json["error"].as_str().unwrap().contains("margin"), "{}", margin.json);

    // A scene's robots stand as obstacles: an iiwa at the base of one standing at home hits it.
    let neighbour = "[[robot]]\nname = \"other\"\nrobot = \"lbr-iiwa-14-r820\"\n";
    let home = json!({"robot": iiwa, "q": [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], "scene": neighbour});
    let inside = post(addr, "/api/collide", &home);
    assert_eq!(inside.json["collision"], true, "{}", inside.json);
    assert!(inside.json["pairs"][0]["b"].as_str().unwrap().starts_with("other/link"), "{}", inside.json);
}

/// `scene` on `/api/traj` and `/api/run`: the iiwa's tilted arm swung past
/// the fume hood's sash is refused with the pair (422), though both ends are
/// free and the same motion without the scene is planned.
#[test]
fn motions_in_a_scene_are_refused_when_they_collide() {
    let running = start();
    let addr = running.local_addr();
    let scene_path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/fume-hood.toml");
    let scene = std::fs::read_to_string(&scene_path).unwrap();
    let iiwa = "lbr-iiwa-14-r820";
    let quarter = std::f64::consts::FRAC_PI_2;
    let (a, b) = ([-quarter, 1.047, 0.0, 0.0, 0.0, 0.0, 0.0], [quarter, 1.047, 0.0, 0.0, 0.0, 0.0, 0.0]);
    let ptp = json!({"robot": iiwa, "kind": "ptp", "from": a, "to": b});
    assert_eq!(post(addr, "/api/traj", &ptp).status, 200);
    let mut in_scene = ptp.clone();
    in_scene["scene"] = json!(scene);
    let refused = post(addr, "/api/traj", &in_scene);
    assert_eq!(refused.status, 422, "{}", refused.json);
    let message = refused.json["error"].as_str().unwrap();
    assert!(message.contains("collision: link") && message.contains("– sash"), "{message}");

    // The same swing written as a program, started at one end.
    let program = "PTP JOINT(90deg, 60deg, 0, 0, 0, 0, 0)\n";
    let run = json!({"robot": iiwa, "program": program, "start": a});
    assert_eq!(post(addr, "/api/run", &run).status, 200);
    let mut run_in_scene = run.clone();
    run_in_scene["scene"] = json!(scene);
    let refused = post(addr, "/api/run", &run_in_scene);
    assert_eq!(refused.status, 422, "{}", refused.json);
    assert!(refused.json.to_string().contains("– sash"), "{}", refused.json);
}
