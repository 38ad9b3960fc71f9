//! What the 3D page is sent: a robot's link geometry once (primitives and
//! base64 meshes in link frames), a scene's obstacles, and link poses on the
//! WebSocket `/api/ws` as the sliders move.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::sync::Arc;
use std::time::Duration;

use kinema::{Pose, Robot};
use kinema_geometry::parry3d_f64::na::Point3;
use kinema_geometry::{LinkShape, Mesh, RobotGeometry, Shape};
use kinema_serve::{App, Limits, Server};
use serde_json::{json, Value};

use crate::api::{call, post, start};

#[test]
fn a_builtin_robot_s_shapes_come_in_its_link_frames() {
    let app = App::new(None).unwrap();
    let (status, v) = app.api("GET", "/api/robots/panda/geometry", b"");
    assert_eq!(status, 200, "{v}");
    assert_eq!((v["robot"].as_str(), v["links"].as_u64()), (Some("panda"), Some(8)));
    assert_eq!(v["visual"], json!([]));
    let shapes = v["collision"].as_array().unwrap();
    assert!(shapes.len() >= 7, "{v}");
    for s in shapes {
        assert!(s["link"].as_u64().is_some_and(|l| l < 8), "{s}");
        assert_eq!(s["pose"][3], json!([0.0, 0.0, 0.0, 1.0]), "{s}");
        match s["kind"].as_str().unwrap() {
            "sphere" => assert!(s["radius"].as_f64().unwrap() > 0.0),
            "capsule" | "cylinder" => assert!(s["radius"].as_f64().unwrap() > 0.0 && s["length"].is_f64()),
            "box" => assert_eq!(s["size"].as_array().map(Vec::len), Some(3)),
            other => panic!("a built-in robot has no {other} shapes: {s}"),
        }
    }
    let (status, v) = app.api("GET", "/api/robots/nope/geometry", b"");
    assert_eq!(status, 404, "{v}");
    assert_eq!(app.api("POST", "/api/robots/panda/geometry", b"").0, 405);
}

#[test]
fn given_meshes_are_sent_as_base64_arrays() {
    let robot = Robot::builtin("ur5").unwrap();
    let vertices = vec![Point3::new(0.0, 0.0, 0.0), Point3::new(0.1, 0.0, 0.0), Point3::new(0.0, 0.2, 0.0)];
    let mesh = Arc::new(Mesh::new(vertices, vec![[0, 1, 2]], "triangle").unwrap());
    let shape = LinkShape::new("tri", 3, Pose::translation(0.0, 0.0, 0.5), Shape::TriangleMesh(mesh)).unwrap();
    let visual = RobotGeometry::new(&robot, vec![shape]).unwrap();
    let app = App::new(Some(robot.clone())).unwrap().with_link_shapes(Some(visual), None).unwrap();
    let (status, v) = app.api("GET", "/api/robots/ur5/geometry", b"");
    assert_eq!(status, 200, "{v}");
    let s = &v["visual"][0];
    assert_eq!((s["kind"].as_str(), s["link"].as_u64(), s["pose"][2][3].as_f64()), (Some("mesh"), Some(3), Some(0.5)));
    assert_eq!((s["mesh"]["vertex_count"].as_u64(), s["mesh"]["triangle_count"].as_u64()), (Some(3), Some(1)));
    // 9 f32 are 36 bytes, 48 base64 characters; 3 u32 are 12 bytes, 16 characters.
    assert_eq!(s["mesh"]["vertices"].as_str().map(str::len), Some(48));
    assert_eq!(s["mesh"]["triangles"].as_str(), Some("AAAAAAEAAAACAAAA"));
    assert_eq!(v["collision"], json!([]));
    // Other robots keep their built-in shapes.
    let (_, panda) = app.api("GET", "/api/robots/panda/geometry", b"");
    assert!(!panda["collision"].as_array().unwrap().is_empty());
    // Shapes of another robot are refused.
    let puma = Robot::builtin("puma560").unwrap();
    let other = RobotGeometry::new(&puma, Vec::new()).unwrap();
    let e = App::new(Some(robot)).unwrap().with_link_shapes(None, Some(other)).unwrap_err();
    assert!(e.to_string().contains("puma560"), "{e}");
}

#[test]
fn a_scene_s_obstacles_come_in_the_world_frame() {
    let app = App::new(None).unwrap();
    let scene = "[[obstacle]]\nname = \"table\"\nbox = [1.0, 0.8, 0.05]\npose = [0.6, 0, -0.025, 0, 0, 0]\n";
    let (status, v) = app.api("POST", "/api/scene", json!({ "scene": scene }).to_string().as_bytes());
    assert_eq!(status, 200, "{v}");
    let table = &v["obstacles"][0];
    assert_eq!((table["name"].as_str(), table["kind"].as_str()), (Some("table"), Some("box")));
    assert_eq!(table["size"], json!([1.0, 0.8, 0.05]));
    assert_eq!((table["pose"][0][3].as_f64(), table["pose"][2][3].as_f64()), (Some(0.6), Some(-0.025)));
    assert!(table.get("link").is_none());
    let (status, v) = app.api("POST", "/api/scene", br#"{"scene": "[[obstacle]]\nname = 3\n"}"#);
    assert_eq!(status, 422, "{v}");
    assert_eq!(app.api("POST", "/api/scene", br#"{"scene": 1}"#).0, 400);
}

/// A WebSocket client enough for the tests: the handshake, masked text
/// frames out, unmasked frames in.
struct Socket(TcpStream);

impl Socket {
    fn open(addr: SocketAddr) -> Socket {
        let (s, answer) = request_upgrade(addr);
        assert!(answer.starts_with("HTTP/1.1 101"), "{answer}");
        // RFC 6455's example key and accept value.
        assert!(answer.contains("s3pPLMBiTxaQ9kYGzzhZRbK+xOo="), "{answer}");
        Socket(s)
    }

    fn send(&mut self, text: &str) {
        let mask = [0x37u8, 0xfa, 0x21, 0x3d];
        let mut frame = vec![0x81u8];
        let n = text.len();
        if n < 126 {
            frame.push(0x80 | n as u8);
        } else if n < 65536 {
            frame.push(0x80 | 126);
            frame.extend((n as u16).to_be_bytes());
        } else {
            frame.push(0x80 | 127);
            frame.extend((n as u64).to_be_bytes());
        }
        frame.extend(mask);
        frame.extend(text.bytes().enumerate().map(|(i, b)| b ^ mask[i % 4]));
        let _ = self.0.write_all(&frame);
    }

    /// The next frame: its opcode and payload; `None` when the connection ended.
    fn receive(&mut self) -> Option<(u8, Vec<u8>)> {
        let mut head = [0u8; 2];
        self.0.read_exact(&mut head).ok()?;
        let mut n = u64::from(head[1] & 0x7f);
        if n == 126 {
            let mut b = [0u8; 2];
            self.0.read_exact(&mut b).ok()?;
            n = u64::from(u16::from_be_bytes(b));
        } else if n == 127 {
            let mut b = [0u8; 8];
            self.0.read_exact(&mut b).ok()?;
            n = u64::from_be_bytes(b);
        }
        let mut payload = vec![0u8; n as usize];
        self.0.read_exact(&mut payload).ok()?;
        Some((head[0] & 0x0f, payload))
    }

    fn json(&mut self) -> Value {
        let (opcode, payload) = self.receive().expect("a frame");
        assert_eq!(opcode, 1, "a text frame");
        serde_json::from_slice(&payload).unwrap()
    }
}

#[test]
fn the_websocket_answers_joint_values_with_link_poses() {
    let server = start();
    let addr = server.local_addr();
    let mut ws = Socket::open(addr);
    let q = json!([0.1, 0.4, -0.2, -1.1, 0.3, 0.7, 0.2]);
    ws.send(&json!({ "q": q }).to_string());
    let live = ws.json();
    // The same numbers as POST /api/fk.
    let fk = post(addr, "/api/fk", &json!({ "q": q }));
    assert_eq!(fk.status, 200);
    assert_eq!(live, fk.json);
    assert_eq!(live["frames"].as_array().map(Vec::len), Some(9), "base, 7 links, tool");
    // Errors are answered and the socket stays open.
    ws.send(r#"{"q": [0, 0]}"#);
    assert!(ws.json()["error"].as_str().unwrap().contains("7 joints"));
    ws.send("{");
    assert!(ws.json()["error"].is_string());
    ws.send(&json!({"robot": "ur5", "q": [0, -1.57, 1.57, 0, 1.57, 0]}).to_string());
    assert_eq!(ws.json()["robot"], "ur5");
    // A message over 64 KiB closes the socket.
    ws.send(&format!("{{\"q\": [{}0]}}", "0,".repeat(40_000)));
    match ws.receive() {
        None | Some((8, _)) => {}
        Some((opcode, payload)) => panic!("frame {opcode} after an oversized message: {payload:?}"),
    }
    // A plain GET is told what the path is, as JSON.
    let a = call(addr, "GET", "/api/ws", b"");
    assert!((400..500).contains(&a.status), "{}", a.status);
    assert!(a.json["error"].as_str().unwrap().contains("WebSocket"), "{}", a.json);
    server.stop();
}

/// Sends a WebSocket upgrade request to `addr`: the connection and the answer's head.
fn request_upgrade(addr: SocketAddr) -> (TcpStream, String) {
    let mut s = TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
    let head = format!(
        "GET /api/ws HTTP/1.1\r\nHost: {addr}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n\
         Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n"
    );
    s.write_all(head.as_bytes()).unwrap();
    let mut answer = Vec::new();
    let mut byte = [0u8];
    while !answer.ends_with(b"\r\n\r\n") && s.read_exact(&mut byte).is_ok() {
        answer.push(byte[0]);
    }
    (s, String::from_utf8_lossy(&answer).into_owned())
}

/// The status line of a WebSocket upgrade request to `addr`.
fn upgrade_status(addr: SocketAddr) -> String {
    request_upgrade(addr).1.lines().next().unwrap_or("").to_string()
}

#[test]
fn open_websockets_count_against_the_connection_limit() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    // Three slots: the accept loop holds one ready for the next connection, the first socket
    // takes one, and the second socket's upgrade request the last.
    let limits = Limits { max_connections: 3, ..Limits::default() };
    let server = Server::bind("127.0.0.1:0", Some(robot)).unwrap().with_limits(limits).spawn();
    let addr = server.local_addr();
    let mut first = Socket::open(addr);
    first.send(&json!({ "q": [0, 0, 0, 0, 0, 0, 0] }).to_string());
    assert!(first.json()["frames"].is_array());
    // No slot is left for a second socket once its upgrade request holds one.
    let refused = upgrade_status(addr);
    assert!(refused.starts_with("HTTP/1.1 503"), "{refused}");
    // Once the first socket is closed, its slot serves a new one.
    drop(first);
    let deadline = std::time::Instant::now() + Duration::from_secs(10);
    loop {
        let status = upgrade_status(addr);
        if status.starts_with("HTTP/1.1 101") {
            break;
        }
        assert!(std::time::Instant::now() < deadline, "no slot came back: {status}");
        std::thread::sleep(Duration::from_millis(50));
    }
    server.stop();
}

#[test]
fn the_server_takes_shapes_for_its_default_robot() {
    let robot = Robot::builtin("scara5").unwrap();
    let box_shape = Shape::Box { size: [0.1, 0.2, 0.3].into() };
    let shape = LinkShape::new("b", 1, Pose::IDENTITY, box_shape).unwrap();
    let collision = RobotGeometry::new(&robot, vec![shape]).unwrap();
    let server = Server::bind("127.0.0.1:0", Some(robot)).unwrap().with_link_shapes(None, Some(collision)).unwrap();
    let running = server.spawn();
    let a = call(running.local_addr(), "GET", "/api/robots/scara5/geometry", b"");
    assert_eq!(a.status, 200);
    assert_eq!(a.json["collision"][0]["size"], json!([0.1, 0.2, 0.3]));
    running.stop();
}

/// A scene with one box obstacle, as a scene file's text.
const BOX_SCENE: &str = "[[obstacle]]\nname = \"block\"\nbox = [0.2, 0.2, 0.2]\npose = [0.5, 0, 0.6, 0, 0, 0]\n";

#[test]
fn the_server_s_scene_is_drawn_and_checked_when_a_request_gives_none() {
    let plain = App::new(None).unwrap();
    assert_eq!(plain.api("GET", "/api/scene", b""), (200, json!({"obstacles": []})));
    let scene = kinema_geometry::Scene::from_toml(BOX_SCENE, "scene", std::path::Path::new(".")).unwrap();
    let app = App::new(None).unwrap().with_scene(&scene).unwrap();
    let (status, v) = app.api("GET", "/api/scene", b"");
    assert_eq!(status, 200, "{v}");
    let block = &v["obstacles"][0];
    assert_eq!((block["name"].as_str(), block["body"].as_str()), (Some("block"), Some("block")));
    assert_eq!(block["pose"][2][3].as_f64(), Some(0.6));

    // The iiwa bent forward into the block: the server's scene is checked,
    // and the answer is the library's check of the same robot and scene.
    let q = [0.0, 1.0, 0.0, -1.2, 0.0, 0.6, 0.0];
    let check = kinema_geometry::CollisionCheck::load("lbr-iiwa-14-r820", &Default::default()).unwrap();
    let with_scene = kinema_geometry::CollisionCheck::with_scene(
        check.robot().clone(),
        check.geometry().clone(),
        check.pairs().clone(),
        Some(&scene),
        0.0,
    )
    .unwrap();
    let mut placement = with_scene.placement();
    let expected = kinema_io::CollideAnswer::of(&with_scene, q.to_vec(), &mut placement).unwrap();
    let body = json!({"robot": "lbr-iiwa-14-r820", "q": q}).to_string();
    let (status, v) = app.api("POST", "/api/collide", body.as_bytes());
    assert_eq!(status, 200, "{v}");
    assert_eq!(v, serde_json::to_value(&expected).unwrap());
    assert_eq!(v["collision"], true, "{v}");
    assert!(v["pairs"].as_array().unwrap().iter().any(|p| p["b"] == "block"), "{v}");
    // Without the server's scene the same configuration is free.
    let (_, free) = plain.api("POST", "/api/collide", body.as_bytes());
    assert_eq!(free["collision"], false, "{free}");
    // A request's own scene replaces the server's.
    let empty = json!({"robot": "lbr-iiwa-14-r820", "q": q, "scene": ""}).to_string();
    let (status, own) = app.api("POST", "/api/collide", empty.as_bytes());
    assert_eq!((status, &own["collision"]), (200, &json!(false)), "{own}");
    // The robot's shapes name the bodies of the pairs the page colours.
    let (_, shapes) = app.api("GET", "/api/robots/lbr-iiwa-14-r820/geometry", b"");
    let bodies: Vec<&str> = shapes["collision"].as_array().unwrap().iter().filter_map(|s| s["body"].as_str()).collect();
    for p in v["pairs"].as_array().unwrap() {
        assert!(bodies.contains(&p["a"].as_str().unwrap()), "{p} not among {bodies:?}");
    }
}

#[test]
fn the_given_collision_meshes_of_the_default_robot_are_checked() {
    // A UR5 whose only shapes are given: a tetrahedron mesh at the tool and
    // a ball on the base, on links named as a URDF would name them.
    let robot = Robot::builtin("ur5").unwrap();
    let tetra = vec![
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(0.1, 0.0, 0.0),
        Point3::new(0.0, 0.1, 0.0),
        Point3::new(0.0, 0.0, 0.1),
    ];
    let mesh = Arc::new(Mesh::new(tetra, vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], "tetra").unwrap());
    let tool =
        LinkShape::new("tip", 6, Pose::IDENTITY, Shape::TriangleMesh(mesh)).unwrap().with_link_name("wrist_3_link");
    let base =
        LinkShape::new("foot", 0, Pose::IDENTITY, Shape::Sphere { radius: 0.05 }).unwrap().with_link_name("base_link");
    let collision = RobotGeometry::new(&robot, vec![tool, base]).unwrap();
    let app = App::new(Some(robot.clone())).unwrap().with_link_shapes(None, Some(collision)).unwrap();
    let home = robot.home().to_vec();
    let tip = robot.fk(&home).unwrap().world_from_tool.pos;
    let scene = format!(
        "[[obstacle]]\nname = \"post\"\nsphere = {{ radius = 0.03 }}\npose = [{}, {}, {}, 0, 0, 0]\n",
        tip[0], tip[1], tip[2]
    );
    let body = json!({"q": home, "scene": scene}).to_string();
    let (status, v) = app.api("POST", "/api/collide", body.as_bytes());
    assert_eq!(status, 200, "{v}");
    assert_eq!(v["pairs"], json!([{"a": "wrist_3_link", "b": "post"}]), "{v}");
    let (_, shapes) = app.api("GET", "/api/robots/ur5/geometry", b"");
    assert_eq!(shapes["collision"][0]["body"], "wrist_3_link");
}

#[test]
fn an_unreachable_ik_target_comes_with_the_closest_configuration() {
    let app = App::new(None).unwrap();
    let body = br#"{"robot": "ur5", "position": [2.0, 0, 0.5], "rpy": [0, 3.14, 0], "q0": [0, -1, 1, 0, 1, 0]}"#;
    let (status, v) = app.api("POST", "/api/ik", body);
    assert_eq!(status, 422, "{v}");
    assert!(v["error"].as_str().unwrap().starts_with("unreachable target"), "{v}");
    let q: Vec<f64> = serde_json::from_value(v["closest"]["q"].clone()).unwrap();
    assert_eq!(q.len(), 6, "{v}");
    // The miss it reports is the distance of its tool from the target.
    let tool = Robot::builtin("ur5").unwrap().fk(&q).unwrap().world_from_tool.pos;
    let miss = ((tool[0] - 2.0).powi(2) + tool[1].powi(2) + (tool[2] - 0.5).powi(2)).sqrt();
    assert!((v["closest"]["position_error"].as_f64().unwrap() - miss).abs() < 1e-9, "{v}; FK misses by {miss}");
    // Errors that are not an unreachable target carry no `closest`.
    let (status, v) = app.api("POST", "/api/ik", br#"{"robot": "ur5", "position": [0.4, 0, 0.5]}"#);
    assert!(status == 200 || v.get("closest").is_none(), "{v}");
    let (_, v) = app.api("POST", "/api/fk", br#"{"robot": "ur5", "q": [0]}"#);
    assert!(v.get("closest").is_none(), "{v}");
}

#[test]
fn a_cell_is_sent_with_every_sample_s_link_poses() {
    let app = App::new(None).unwrap();
    assert_eq!(app.api("GET", "/api/cell", b""), (200, json!({"times": [], "members": []})));
    let ur5 = Robot::builtin("ur5").unwrap();
    let moved = kinema::traj::cell::placed(&ur5, &Pose::translation(1.0, 0.0, 0.0)).unwrap();
    let geometry = |r: &Robot| RobotGeometry::new(r, Vec::new()).unwrap();
    let qs = |a: f64| vec![vec![0.0; 6], vec![a, -1.0, 1.0, 0.0, 0.5, 0.0]];
    let members = [
        kinema_serve::CellMotion { name: "left".into(), robot: ur5.clone(), geometry: geometry(&ur5), q: qs(0.3) },
        kinema_serve::CellMotion {
            name: "right".into(),
            robot: moved.clone(),
            geometry: geometry(&moved),
            q: qs(-0.3),
        },
    ];
    let app = app.with_cell(&[0.0, 0.5], &members).unwrap();
    let (status, v) = app.api("GET", "/api/cell", b"");
    assert_eq!(status, 200, "{v}");
    assert_eq!(v["times"], json!([0.0, 0.5]));
    for (m, member) in members.iter().enumerate() {
        let answer = &v["members"][m];
        assert_eq!(answer["name"].as_str(), Some(member.name.as_str()));
        assert_eq!(answer["q"], json!(member.q));
        for (k, q) in member.q.iter().enumerate() {
            let frames = member.robot.link_frames(q).unwrap();
            assert_eq!(answer["frames"][k].as_array().unwrap().len(), frames.len());
            let tool = &answer["frames"][k][frames.len() - 1];
            let p = frames.last().unwrap().pos;
            assert_eq!([&tool[9], &tool[10], &tool[11]], [&json!(p[0]), &json!(p[1]), &json!(p[2])], "{tool}");
            assert_eq!(tool[0].as_f64(), Some(frames.last().unwrap().rot[(0, 0)]));
        }
    }
    // The second robot stands 1 m along x.
    assert!((v["members"][1]["frames"][0][0][9].as_f64().unwrap() - 1.0).abs() < 1e-12, "{v}");
    // Samples that do not match the clock, and too many samples, are refused.
    let e = App::new(None).unwrap().with_cell(&[0.0], &members).unwrap_err();
    assert!(e.to_string().contains("2 samples for 1 times"), "{e}");
    let times: Vec<f64> = (0..kinema_serve::MAX_SAMPLES).map(|k| k as f64).collect();
    let e = App::new(None).unwrap().with_cell(&times, &members).unwrap_err();
    assert!(e.to_string().contains("give a larger dt"), "{e}");
    assert_eq!(app.api("POST", "/api/cell", b"{}").0, 405);
}
