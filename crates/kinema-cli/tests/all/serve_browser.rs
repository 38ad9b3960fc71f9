//! `kinema serve` in a real browser: the binary serves the page, headless
//! Chromium (WebGL by SwiftShader, no GPU) loads it through chromedriver (the
//! WebDriver HTTP protocol). On the iiwa a joint slider moves, the FK readout
//! follows, the IK panel, the ellipsoid and the program player answer, and
//! the median frame time is printed; on a URDF arm whose STL meshes the test
//! writes, the link origins from kinema's FK, projected by the page's camera,
//! fall on the drawn meshes at two configurations, and the silhouette changes.
//!
//! Skipped (passes, printing `skipped: …`) when /usr/bin/chromium or
//! /usr/bin/chromedriver is missing. Set KINEMA_SERVE_SCREENSHOT=/path (a
//! prefix) to keep the screenshots.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

const CHROMIUM: &str = "/usr/bin/chromium";
const CHROMEDRIVER: &str = "/usr/bin/chromedriver";

/// Kills what the test started, also when it fails: the browser session
/// first (so chromedriver closes Chromium), then chromedriver and the server.
struct Guard {
    agent: ureq::Agent,
    session: Option<String>,
    children: Vec<Child>,
    profile: Option<PathBuf>,
}

impl Drop for Guard {
    fn drop(&mut self) {
        if let Some(s) = self.session.take() {
            let _ = self.agent.delete(&s).call();
        }
        for c in &mut self.children {
            let _ = c.kill();
            let _ = c.wait();
        }
        if let Some(p) = self.profile.take() {
            let _ = std::fs::remove_dir_all(p);
        }
    }
}

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port()
}

/// A WebDriver call; the answer's `value`, or the driver's error as a panic.
fn wd(agent: &ureq::Agent, method: &str, url: &str, body: Option<Value>) -> Value {
    let req = agent.request(method, url).set("Content-Type", "application/json");
    let res = match body {
        Some(b) => req.send_string(&b.to_string()),
        None => req.call(),
    };
    let text = match res {
        Ok(r) => r.into_string().expect("WebDriver answer"),
        Err(ureq::Error::Status(code, r)) => {
            panic!("WebDriver {method} {url}: HTTP {code}: {}", r.into_string().unwrap_or_default())
        }
        Err(e) => panic!("WebDriver {method} {url}: {e}"),
    };
    let v: Value = serde_json::from_str(&text).expect("WebDriver JSON");
    v["value"].clone()
}

fn script(agent: &ureq::Agent, session: &str, js: &str) -> Value {
    wd(agent, "POST", &format!("{session}/execute/sync"), Some(json!({"script": js, "args": []})))
}

/// Polls `js` until `ok` accepts its value (or panics after `secs`).
fn wait_for(agent: &ureq::Agent, session: &str, js: &str, secs: u64, what: &str, ok: impl Fn(&Value) -> bool) -> Value {
    let start = Instant::now();
    loop {
        let v = script(agent, session, js);
        if ok(&v) {
            return v;
        }
        if start.elapsed() > Duration::from_secs(secs) {
            panic!("timed out after {secs} s waiting for {what}; last value {v}");
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

fn base64_decode(text: &str) -> Vec<u8> {
    let val = |c: u8| match c {
        b'A'..=b'Z' => Some(c - b'A'),
        b'a'..=b'z' => Some(c - b'a' + 26),
        b'0'..=b'9' => Some(c - b'0' + 52),
        b'+' => Some(62),
        b'/' => Some(63),
        _ => None,
    };
    let (mut out, mut acc, mut bits) = (Vec::with_capacity(text.len() * 3 / 4), 0u32, 0);
    for v in text.bytes().filter_map(val) {
        acc = (acc << 6) | u32::from(v);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    out
}

/// A browser session on a `kinema serve` page, and what to stop afterwards.
struct Viewer {
    agent: ureq::Agent,
    session: String,
    /// The server's page, `http://127.0.0.1:PORT/`.
    url: String,
    _guard: Guard,
}

impl Viewer {
    /// `kinema serve --robot ROBOT` (and `args`), chromedriver and a headless
    /// Chromium on its page, once the page says it is ready; `None` (the test
    /// skipped) without Chromium.
    fn open(robot: &str, args: &[&str], env: &[(&str, &Path)]) -> Option<Viewer> {
        for p in [CHROMIUM, CHROMEDRIVER] {
            if !Path::new(p).exists() {
                println!("skipped: {p} is missing (apt-get install chromium chromium-driver)");
                return None;
            }
        }
        let agent = ureq::AgentBuilder::new().timeout(Duration::from_secs(120)).build();
        let profile = std::env::temp_dir().join(format!("kinema-serve-browser-{}-{}", std::process::id(), free_port()));
        let _ = std::fs::remove_dir_all(&profile);
        std::fs::create_dir_all(&profile).unwrap();
        let mut guard =
            Guard { agent: agent.clone(), session: None, children: Vec::new(), profile: Some(profile.clone()) };

        // The server: its URL is the one line it prints on stdout.
        let mut command = Command::new(env!("CARGO_BIN_EXE_kinema"));
        command
            .args(["serve", "--robot", robot, "--port", "0"])
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit());
        for (k, v) in env {
            command.env(k, v);
        }
        let mut server = command.spawn().expect("kinema serve starts");
        let stdout = server.stdout.take().unwrap();
        guard.children.push(server);
        let mut lines = BufReader::new(stdout).lines();
        let first = lines.next().expect("a line on stdout").expect("readable stdout");
        let url = first
            .strip_prefix("kinema serve: ")
            .unwrap_or_else(|| panic!("unexpected first line `{first}`"))
            .to_string();
        assert!(url.starts_with("http://127.0.0.1:") && url.ends_with('/'), "{url}");
        // Keep draining stdout so the server never blocks on it.
        std::thread::spawn(move || for _ in lines {});

        // chromedriver on a free port.
        let port = free_port();
        let driver = Command::new(CHROMEDRIVER)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("chromedriver starts");
        guard.children.push(driver);
        let base = format!("http://127.0.0.1:{port}");
        let start = Instant::now();
        loop {
            let ready = agent.get(&format!("{base}/status")).call().ok().and_then(|r| r.into_string().ok());
            if ready.is_some_and(|t| t.contains("\"ready\":true")) {
                break;
            }
            assert!(start.elapsed() < Duration::from_secs(30), "chromedriver did not become ready");
            std::thread::sleep(Duration::from_millis(100));
        }
        // WebGL without a GPU: ANGLE on SwiftShader, the software renderer.
        let caps = json!({"capabilities": {"alwaysMatch": {"goog:chromeOptions": {
            "binary": CHROMIUM,
            "args": ["--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
                     "--ignore-gpu-blocklist", "--disable-background-networking", "--disable-quic",
                     "--disable-component-update", "--disable-sync", "--no-first-run", "--window-size=1400,950",
                     format!("--user-data-dir={}", profile.display())],
        }}}});
        let created = wd(&agent, "POST", &format!("{base}/session"), Some(caps));
        let session = format!("{base}/session/{}", created["sessionId"].as_str().expect("a session id"));
        guard.session = Some(session.clone());

        // Load the page; it sets data-ready once the robot is drawn.
        wd(&agent, "POST", &format!("{session}/url"), Some(json!({"url": url})));
        let viewer = Viewer { agent, session, url, _guard: guard };
        viewer.wait_for("return document.body.dataset.ready || null", 60, "the page to be ready", |v| v == "1");
        Some(viewer)
    }

    fn script(&self, js: &str) -> Value {
        script(&self.agent, &self.session, js)
    }

    fn wait_for(&self, js: &str, secs: u64, what: &str, ok: impl Fn(&Value) -> bool) -> Value {
        wait_for(&self.agent, &self.session, js, secs, what, ok)
    }

    /// The page uses WebGL and has met no error.
    fn assert_webgl_and_no_errors(&self) {
        let context = self.script("return window.kinemaViewer.context");
        assert!(context == "webgl2" || context == "webgl", "the view's context is {context}");
        let errors = self.script("return window.kinemaViewer.errors");
        assert_eq!(errors, json!([]), "the page met errors");
    }

    /// Moves the robot to `q` and waits until the view has drawn it.
    fn show_q(&self, q: &[f64]) {
        let q = json!(q).to_string();
        self.script(&format!("window.kinemaViewer.setQ({q}); return 1"));
        let js = format!(
            "const v = window.kinemaViewer; return v.state.fk && JSON.stringify(v.state.fk.q) === JSON.stringify({q})"
        );
        self.wait_for(&js, 10, "the pose's link frames", |v| *v == true);
        let drawn = self.script("const v = window.kinemaViewer; v.redraw(); return v.frames").as_u64().unwrap();
        self.wait_for("return window.kinemaViewer.frames", 10, "a frame after the pose", |v| {
            v.as_u64().is_some_and(|n| n > drawn)
        });
    }

    /// A screenshot of the window, and the 3D view's rectangle in its pixels.
    fn screenshot(&self, name: &str) -> (image::RgbaImage, [u32; 4]) {
        let png = base64_decode(
            wd(&self.agent, "GET", &format!("{}/screenshot", self.session), None).as_str().expect("base64 PNG"),
        );
        if let Some(prefix) = std::env::var_os("KINEMA_SERVE_SCREENSHOT") {
            let mut path = prefix;
            path.push(format!("{name}.png"));
            std::fs::write(path, &png).unwrap();
        }
        let img = image::load_from_memory(&png).expect("a PNG").to_rgba8();
        let rect = self.script(
            "const r = document.getElementById('view').getBoundingClientRect(); \
             return [r.left, r.top, r.width, r.height, window.devicePixelRatio]",
        );
        let f = |i: usize| rect[i].as_f64().unwrap();
        let rect = [f(0) * f(4), f(1) * f(4), f(2) * f(4), f(3) * f(4)].map(|v| v as u32);
        assert!(rect[2] > 200 && rect[3] > 200, "the view is {}×{}", rect[2], rect[3]);
        (img, rect)
    }

    /// The link frame origins of the robot as drawn (kinema's FK, from the
    /// server) and where the page's camera projects them, in screenshot pixels.
    fn projected_origins(&self) -> Vec<([f64; 3], [f64; 2])> {
        let v = self.script(
            "const v = window.kinemaViewer; return v.state.fk.frames.map((f) => \
             [f.position, v.project(f.position).slice(0, 2).map((c) => c * window.devicePixelRatio)])",
        );
        let num = |v: &Value| v.as_f64().expect("a number");
        v.as_array()
            .expect("frames")
            .iter()
            .map(|f| {
                let p = f[0].as_array().unwrap();
                ([num(&p[0]), num(&p[1]), num(&p[2])], [num(&f[1][0]), num(&f[1][1])])
            })
            .collect()
    }
}

/// The view's background colour (scene.js), and whether a pixel differs from it.
const BACKGROUND: [u8; 3] = [0xee, 0xf2, 0xf6];

fn is_background(p: &image::Rgba<u8>) -> bool {
    (0..3).all(|k| p.0[k].abs_diff(BACKGROUND[k]) <= 6)
}

/// Whether the 5×5 pixels around (x, y) are all drawn (not background): a
/// solid, not a one-pixel grid line or frame axis.
fn solid_at(img: &image::RgbaImage, x: f64, y: f64) -> bool {
    let (x, y) = (x.round() as i64, y.round() as i64);
    (-2..=2).all(|dy| {
        (-2..=2).all(|dx| {
            let (px, py) = (x + dx, y + dy);
            px >= 0
                && py >= 0
                && (px as u32) < img.width()
                && (py as u32) < img.height()
                && !is_background(img.get_pixel(px as u32, py as u32))
        })
    })
}

#[test]
fn the_viewer_works_in_headless_chromium() {
    let Some(viewer) = Viewer::open("lbr-iiwa-14-r820", &[], &[]) else { return };
    let (agent, s) = (&viewer.agent, viewer.session.as_str());
    viewer.assert_webgl_and_no_errors();
    let sliders = script(agent, s, "return document.querySelectorAll('#sliders input[type=range]').length");
    assert_eq!(sliders, 7, "one slider per joint");
    let before = script(agent, s, "return document.getElementById('fk-readout').textContent");
    let before = before.as_str().unwrap().to_string();
    assert!(before.contains("z 1.3060"), "home readout: {before}");
    // The built-in iiwa's `[[shape]]`s are drawn (sent once, in link frames).
    let shapes = script(agent, s, "return window.kinemaViewer.state.geometry.collision.length");
    assert!(shapes.as_u64().is_some_and(|n| n >= 7), "{shapes}");
    // The pose updates come over the WebSocket.
    viewer.wait_for("return window.kinemaViewer.live", 10, "the pose WebSocket", |v| *v == true);

    // Move joint 2 as a user would (value + input event); the readout follows.
    // (The slider snaps to its step, so the value it took is read back.)
    let q2 = script(
        agent,
        s,
        "const el = document.querySelector('input[data-joint=\"2\"]'); el.value = '0.8'; \
         el.dispatchEvent(new Event('input', {bubbles: true})); return el.value;",
    );
    let q2: f64 = q2.as_str().and_then(|v| v.parse().ok()).expect("the slider's value");
    assert!((q2 - 0.8).abs() < 0.002, "{q2}");
    let after =
        wait_for(agent, s, "return document.getElementById('fk-readout').textContent", 10, "the FK readout", |v| {
            v.as_str().is_some_and(|t| t != before)
        });
    let after = after.as_str().unwrap();
    assert!(!after.contains("z 1.3060"), "{after}");
    // The arm stays straight above joint 2: z = 0.36 + (0.42 + 0.4 + 0.126)·cos q2.
    let z = 0.36 + (0.42 + 0.4 + 0.126) * q2.cos();
    assert!(after.contains(&format!("z {z:.4}")), "expected z {z:.4} in {after}");

    // Bend the elbow and the wrist (away from the stretched, singular arm).
    script(
        agent,
        s,
        "for (const [j, v] of [[4, '-1.2'], [6, '0.6']]) { const el = document.querySelector(`input[data-joint=\"${j}\"]`); \
         el.value = v; el.dispatchEvent(new Event('input', {bubbles: true})); } return 1",
    );
    wait_for(agent, s, "return window.kinemaViewer.state.fk.q[3]", 10, "the bent elbow", |v| {
        v.as_f64().is_some_and(|q| q < -1.0)
    });

    // IK at the current tool pose: every solution listed.
    script(
        agent,
        s,
        "document.getElementById('ik-from-tool').click(); document.getElementById('ik-solve').click(); return 1",
    );
    let rows = wait_for(
        agent,
        s,
        "return [document.querySelectorAll('#ik-solutions tbody tr').length, document.getElementById('ik-message').textContent]",
        10,
        "IK solutions",
        |v| v[0].as_u64().is_some_and(|n| n > 0),
    );
    assert!(rows[0].as_u64().unwrap() >= 2, "the iiwa has several branches at one q3: {rows}");
    // Pick the last solution: the robot moves there (the readout's joint values change).
    let q_before = script(agent, s, "return window.kinemaViewer.q.join(',')");
    script(
        agent,
        s,
        "const r = document.querySelectorAll('#ik-solutions tbody tr'); r[r.length - 1].cells[1].click(); return 1",
    );
    wait_for(agent, s, "return window.kinemaViewer.state.fk.q.join(',')", 10, "the picked branch", |v| *v != q_before);

    // The manipulability ellipsoid.
    script(agent, s, "document.getElementById('show-ellipsoid').click(); return 1");
    wait_for(
        agent,
        s,
        "return document.getElementById('manip-readout').textContent",
        10,
        "the ellipsoid readout",
        |v| v.as_str().is_some_and(|t| t.contains("Yoshikawa")),
    );

    // The player: run the default program, jump to the middle.
    script(agent, s, "document.getElementById('run-program').click(); return 1");
    wait_for(agent, s, "return document.getElementById('play').disabled", 60, "the program's trajectory", |v| {
        *v == false
    });
    let label = script(
        agent,
        s,
        "const t = document.getElementById('time-slider'); t.value = String((+t.max) / 2); \
         t.dispatchEvent(new Event('input', {bubbles: true})); return document.getElementById('time-label').textContent",
    );
    assert!(label.as_str().is_some_and(|t| t.contains(" / ")), "{label}");
    std::thread::sleep(Duration::from_millis(500));

    // A screenshot: the 3D view is drawn (many colours, robot-coloured pixels).
    let (img, [x0, y0, w, h]) = viewer.screenshot("iiwa");
    let mut colours = std::collections::HashSet::new();
    let mut coloured = 0usize;
    for y in y0..(y0 + h).min(img.height()) {
        for x in x0..(x0 + w).min(img.width()) {
            let p = img.get_pixel(x, y).0;
            colours.insert([p[0], p[1], p[2]]);
            let (hi, lo) = (p[0].max(p[1]).max(p[2]), p[0].min(p[1]).min(p[2]));
            if hi - lo > 60 {
                coloured += 1;
            }
        }
    }
    assert!(colours.len() > 200, "only {} distinct colours in the 3D view", colours.len());
    assert!(coloured > 2000, "only {coloured} strongly coloured pixels (links, frames) in the 3D view");

    // The frame time, drawing as fast as the browser lets the page.
    print_frame_time(&viewer, "the built-in iiwa (its [[shape]] capsules and spheres)");
    viewer.assert_webgl_and_no_errors();
}

/// Prints the median frame time of 60 frames with the camera turning.
fn print_frame_time(viewer: &Viewer, what: &str) {
    viewer.script("window.kinemaViewer.measured = null; window.kinemaViewer.measure(60).then((m) => { window.kinemaViewer.measured = m; }); return 1");
    let m = viewer.wait_for("return window.kinemaViewer.measured", 60, "the frame time", |v| v.is_object());
    let (frame, draw) = (m["frame_ms"].as_f64().unwrap(), m["draw_ms"].as_f64().unwrap());
    // SwiftShader is recognised, so the view is drawn without multisampling.
    assert_eq!(viewer.script("return window.kinemaViewer.software"), true);
    println!(
        "viewer frame time, {what}: median {frame:.1} ms per frame ({:.0} fps), {draw:.1} ms to draw one completely \
         (headless Chromium, SwiftShader)",
        1000.0 / frame
    );
    assert!(frame > 0.0 && draw > 0.0, "{m}");
}

/// A binary STL of `triangles` (each three vertices).
fn write_stl(path: &Path, triangles: &[[[f32; 3]; 3]]) {
    let mut bytes = vec![0u8; 80];
    bytes.extend((triangles.len() as u32).to_le_bytes());
    for t in triangles {
        let (a, b, c) = (t[0], t[1], t[2]);
        let (u, v) = ([b[0] - a[0], b[1] - a[1], b[2] - a[2]], [c[0] - a[0], c[1] - a[1], c[2] - a[2]]);
        let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt().max(1e-12);
        for x in n.iter().map(|x| x / len).chain(t.iter().flatten().copied()) {
            bytes.extend(x.to_le_bytes());
        }
        bytes.extend([0, 0]);
    }
    std::fs::write(path, bytes).unwrap();
}

/// The unit cube centred on the origin, outward-facing triangles.
fn cube() -> Vec<[[f32; 3]; 3]> {
    let mut out = Vec::new();
    for axis in 0..3 {
        for sign in [-0.5f32, 0.5] {
            let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
            let corner = |a: f32, b: f32| {
                let mut p = [0.0; 3];
                p[axis] = sign;
                p[i] = a;
                p[j] = b;
                p
            };
            let (p00, p10, p11, p01) = (corner(-0.5, -0.5), corner(0.5, -0.5), corner(0.5, 0.5), corner(-0.5, 0.5));
            if sign > 0.0 {
                out.extend([[p00, p10, p11], [p00, p11, p01]]);
            } else {
                out.extend([[p00, p11, p10], [p00, p01, p11]]);
            }
        }
    }
    out
}

/// A cylinder of radius 1 and length 1 along z, centred on the origin.
fn cylinder(segments: usize) -> Vec<[[f32; 3]; 3]> {
    let at = |k: usize, z: f32| {
        let a = 2.0 * std::f32::consts::PI * k as f32 / segments as f32;
        [a.cos(), a.sin(), z]
    };
    let mut out = Vec::new();
    for k in 0..segments {
        let (a0, a1, b0, b1) = (at(k, -0.5), at(k + 1, -0.5), at(k, 0.5), at(k + 1, 0.5));
        out.extend([[a0, a1, b1], [a0, b1, b0], [[0.0, 0.0, 0.5], b0, b1], [[0.0, 0.0, -0.5], a1, a0]]);
    }
    out
}

/// A three-joint arm whose visual elements are STL meshes; every link frame
/// origin lies inside its link's mesh.
const STL_ARM: &str = r#"<?xml version="1.0"?>
<robot name="stl-arm">
  <link name="base">
    <visual><geometry><mesh filename="cube.stl" scale="0.3 0.3 0.1"/></geometry></visual>
  </link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="column"/><origin xyz="0 0 0.3"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/>
  </joint>
  <link name="column">
    <visual><origin xyz="0 0 -0.1"/><geometry><mesh filename="cylinder.stl" scale="0.06 0.06 0.5"/></geometry></visual>
  </link>
  <joint name="j2" type="revolute">
    <parent link="column"/><child link="upper"/><origin xyz="0 0 0.12"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="10" velocity="1"/>
  </joint>
  <link name="upper">
    <visual><origin xyz="0.2 0 0"/><geometry><mesh filename="cube.stl" scale="0.52 0.09 0.09"/></geometry></visual>
    <collision><origin xyz="0.2 0 0"/><geometry><box size="0.6 0.25 0.25"/></geometry></collision>
  </link>
  <joint name="j3" type="revolute">
    <parent link="upper"/><child link="fore"/><origin xyz="0.4 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2.5" upper="2.5" effort="10" velocity="1"/>
  </joint>
  <link name="fore">
    <visual><origin xyz="0.1 0 0"/><geometry><mesh filename="cube.stl" scale="0.32 0.07 0.07"/></geometry></visual>
  </link>
</robot>
"#;

#[test]
fn link_origins_fall_on_the_drawn_meshes_of_an_stl_arm() {
    let dir = tempfile::tempdir().unwrap();
    write_stl(&dir.path().join("cube.stl"), &cube());
    write_stl(&dir.path().join("cylinder.stl"), &cylinder(32));
    let urdf = dir.path().join("stl-arm.urdf");
    std::fs::write(&urdf, STL_ARM).unwrap();
    let Some(viewer) = Viewer::open(urdf.to_str().unwrap(), &[], &[]) else { return };
    viewer.assert_webgl_and_no_errors();
    let status = viewer.script("return document.getElementById('status').textContent");
    assert!(status.as_str().is_some_and(|t| t.contains("visual meshes")), "{status}");
    // The frame triads off: only the meshes (and the tool's triad) are drawn.
    viewer.script("document.getElementById('show-frames').click(); return 1");
    silhouettes_follow_fk(&viewer, &[[0.0, 0.0, 0.0], [1.2, -0.7, 1.3]], 0, 0, "stl-arm");
    // The collision box, larger than the upper arm's mesh, covers more of the view when shown.
    let drawn = |name: &str| {
        let (img, [x0, y0, w, h]) = viewer.screenshot(name);
        let (xs, ys) = (x0..(x0 + w).min(img.width()), y0..(y0 + h).min(img.height()));
        ys.flat_map(|y| xs.clone().map(move |x| (x, y))).filter(|&(x, y)| !is_background(img.get_pixel(x, y))).count()
    };
    let without = drawn("stl-arm-visual");
    viewer.script("document.getElementById('show-collision').click(); window.kinemaViewer.redraw(); return 1");
    std::thread::sleep(Duration::from_millis(300));
    let with = drawn("stl-arm-collision");
    assert!(with > without + 500, "{without} drawn pixels without the collision box, {with} with it");
    // The screenshot button's picture.
    let png = viewer.script("return window.kinemaViewer.screenshot()");
    assert!(png.as_str().is_some_and(|p| p.starts_with("data:image/png;base64,") && p.len() > 10_000), "{png}");
    viewer.assert_webgl_and_no_errors();
}

/// At each configuration, every link origin from link `first` on (kinema's
/// FK, the page's camera) falls on drawn pixels (a solid within `near`
/// pixels: a mesh's frame origin may lie on its surface), and the silhouette
/// differs between the two.
fn silhouettes_follow_fk<const N: usize>(viewer: &Viewer, qs: &[[f64; N]; 2], first: usize, near: i64, name: &str) {
    let mut shots = Vec::new();
    for (k, q) in qs.iter().enumerate() {
        viewer.show_q(q);
        let origins = viewer.projected_origins();
        let (img, rect) = viewer.screenshot(&format!("{name}-{k}"));
        // The tool frame is not a link of its own.
        for (i, (p, [x, y])) in origins[..origins.len() - 1].iter().enumerate().skip(first) {
            let on_solid = (-near..=near).any(|dy| {
                (-near..=near)
                    .any(|dx| dx * dx + dy * dy <= near * near && solid_at(&img, x + dx as f64, y + dy as f64))
            });
            assert!(on_solid, "q = {q:?}: link {i}'s origin {p:?}, drawn at ({x:.0}, {y:.0}), is background");
        }
        shots.push((img, rect));
    }
    let ([x0, y0, w, h], (a, b)) = (shots[0].1, (&shots[0].0, &shots[1].0));
    let mut changed = 0usize;
    for y in y0..(y0 + h).min(a.height()) {
        for x in x0..(x0 + w).min(a.width()) {
            if is_background(a.get_pixel(x, y)) != is_background(b.get_pixel(x, y)) {
                changed += 1;
            }
        }
    }
    let share = changed as f64 / f64::from(w * h);
    assert!(share > 0.01, "the silhouette hardly changed: {changed} pixels ({:.2} %)", 100.0 * share);
}

/// The version of example-robot-data the real-mesh test downloads (as the coal benchmarks pin it).
const ERD_VERSION: &str = "6.0.0";

/// example-robot-data's Panda with its visual meshes (Collada, about 135 000
/// triangles): link origins on the drawn meshes at two configurations, and
/// the frame time. Needs the network (pip downloads the package into a
/// throwaway directory) or KINEMA_ERD_SHARE, a directory holding
/// `example-robot-data/robots/`; run by .ci/run.
#[test]
#[ignore = "downloads example-robot-data with pip (130 MB)"]
fn real_meshes_of_example_robot_data_s_panda() {
    let dir = tempfile::tempdir().unwrap();
    let share = match std::env::var_os("KINEMA_ERD_SHARE") {
        Some(share) => PathBuf::from(share),
        None => download_panda(dir.path()),
    };
    let urdf = share.join("example-robot-data/robots/panda_description/urdf/panda.urdf");
    assert!(urdf.is_file(), "{} is missing", urdf.display());
    let Some(viewer) =
        Viewer::open(urdf.to_str().unwrap(), &["--tip", "panda_hand"], &[("ROS_PACKAGE_PATH", share.as_path())])
    else {
        return;
    };
    viewer.assert_webgl_and_no_errors();
    let visual = viewer.script("return window.kinemaViewer.state.geometry.visual.length");
    assert!(visual.as_u64().is_some_and(|n| n >= 8), "{visual}");
    viewer.script("document.getElementById('show-frames').click(); return 1");
    // The base's origin is on its bottom face, at the floor: links 1… are
    // checked, each within 6 pixels (link 7's origin is on its mesh's top face).
    let qs = [[0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8], [1.1, 0.5, -0.4, -1.4, 0.6, 1.2, -0.5]];
    silhouettes_follow_fk(&viewer, &qs, 1, 6, "panda");
    print_frame_time(&viewer, "example-robot-data's Panda (visual meshes)");
    viewer.assert_webgl_and_no_errors();
}

/// pip downloads example-robot-data into `dir`; its Panda is extracted
/// there. Returns the directory holding `example-robot-data/`.
fn download_panda(dir: &Path) -> PathBuf {
    let status = Command::new("python3")
        .args(["-m", "pip", "download", "--no-deps", "--disable-pip-version-check", "-q", "-d"])
        .arg(dir)
        .arg(format!("example-robot-data=={ERD_VERSION}"))
        .status()
        .expect("python3 runs");
    assert!(status.success(), "pip download example-robot-data=={ERD_VERSION} failed");
    let wheel = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|x| x == "whl"))
        .expect("a wheel");
    let extract = "import sys, zipfile; z = zipfile.ZipFile(sys.argv[1]); \
                   z.extractall(sys.argv[2], [n for n in z.namelist() if '/panda_description/' in n])";
    let status = Command::new("python3").args(["-c", extract]).arg(&wheel).arg(dir).status().expect("python3 runs");
    assert!(status.success(), "extracting the Panda from {}", wheel.display());
    dir.join("cmeel.prefix/share")
}

/// Pixels of the 3D view drawn in the colliding red (robot.js), not the
/// orange or grey of the links nor the obstacles' brown.
fn red_pixels(img: &image::RgbaImage, [x0, y0, w, h]: [u32; 4]) -> usize {
    let mut n = 0;
    for y in y0..(y0 + h).min(img.height()) {
        for x in x0..(x0 + w).min(img.width()) {
            let [r, g, b, _] = img.get_pixel(x, y).0;
            let r = f64::from(r);
            if r >= 120.0 && f64::from(g) < 0.35 * r && f64::from(b) < 0.35 * r {
                n += 1;
            }
        }
    }
    n
}

/// The page's last collision answer once it is the one of the configuration shown.
fn collide_answer(viewer: &Viewer, q: &[f64]) -> Value {
    let js = format!(
        "const c = window.kinemaViewer.collide; return c && JSON.stringify(c.q) === JSON.stringify({}) ? c : null",
        json!(q)
    );
    let answer = viewer.wait_for(&js, 20, "the collision check of the configuration", |v| v.is_object());
    // One more frame, drawn after the colours changed.
    let drawn = viewer.script("const v = window.kinemaViewer; v.redraw(); return v.frames").as_u64().unwrap();
    viewer.wait_for("return window.kinemaViewer.frames", 10, "a frame after the check", |v| {
        v.as_u64().is_some_and(|n| n > drawn)
    });
    answer
}

#[test]
fn a_colliding_configuration_turns_the_pair_red_with_the_server_s_distance() {
    let dir = std::env::temp_dir().join(format!("kinema-serve-collide-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, "[[obstacle]]\nname = \"block\"\nbox = [0.2, 0.2, 0.2]\npose = [0.5, 0, 0.6, 0, 0, 0]\n")
        .unwrap();
    let Some(viewer) = Viewer::open("lbr-iiwa-14-r820", &["--scene", scene.to_str().unwrap()], &[]) else { return };
    viewer.assert_webgl_and_no_errors();
    assert_eq!(viewer.script("return window.kinemaViewer.state.obstacles"), 1, "the scene's block is drawn");

    // Free: nothing red, no pair.
    let free = [0.0, 0.3, 0.0, -1.2, 0.0, 0.6, 0.0];
    viewer.show_q(&free);
    let c = collide_answer(&viewer, &free);
    assert_eq!((&c["collision"], &c["pairs"]), (&json!(false), &json!([])), "{c}");
    assert_eq!(viewer.script("return window.kinemaViewer.red"), json!([]));
    let (img, rect) = viewer.screenshot("collide-free");
    let red_free = red_pixels(&img, rect);

    // Bent forward into the block: the pair's link and the block turn red.
    let hit = [0.0, 1.0, 0.0, -1.2, 0.0, 0.6, 0.0];
    viewer.show_q(&hit);
    let c = collide_answer(&viewer, &hit);
    assert_eq!(c["collision"], true, "{c}");
    let mut expected: Vec<String> = Vec::new();
    for p in c["pairs"].as_array().unwrap() {
        for body in [&p["a"], &p["b"]] {
            let body = body.as_str().unwrap().to_string();
            if !expected.contains(&body) {
                expected.push(body);
            }
        }
    }
    assert!(expected.iter().any(|b| b == "block"), "{c}");
    let mut red: Vec<String> = serde_json::from_value(viewer.script("return window.kinemaViewer.red")).unwrap();
    red.sort();
    expected.sort();
    assert_eq!(red, expected, "the bodies drawn red are the colliding pairs'");
    let (img, rect) = viewer.screenshot("collide-hit");
    let red_hit = red_pixels(&img, rect);
    println!("red pixels: {red_free} free, {red_hit} in collision");
    assert!(red_free < 50 && red_hit > 1000, "red pixels: {red_free} free, {red_hit} in collision");

    // The distance shown is the one `kinema collide` computes for the same robot and scene.
    let q = hit.map(|v| v.to_string()).join(",");
    let out = Command::new(env!("CARGO_BIN_EXE_kinema"))
        .args(["collide", "--robot", "lbr-iiwa-14-r820", "--q", &q, "--scene", scene.to_str().unwrap(), "--json"])
        .output()
        .unwrap();
    // Status 3: the configuration collides.
    assert_eq!(out.status.code(), Some(3), "{}", String::from_utf8_lossy(&out.stderr));
    let cli: Value = serde_json::from_slice(&out.stdout).unwrap();
    let expected = cli["min_distance"]["distance"].as_f64().unwrap();
    let text = viewer.script("return document.getElementById('collide-readout').textContent");
    let text = text.as_str().unwrap();
    let shown_mm: f64 = text
        .split("min distance ")
        .nth(1)
        .and_then(|t| t.split(" mm").next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("no distance in the readout: {text}"));
    assert!((shown_mm / 1000.0 - expected).abs() <= 1e-9, "shown {shown_mm} mm, kinema collide {expected} m");
    assert_eq!(c["min_distance"]["distance"].as_f64(), Some(expected), "{c}");
    viewer.assert_webgl_and_no_errors();
    let _ = std::fs::remove_dir_all(&dir);
}

/// Drags with the mouse, as a user would, from window CSS pixel `from` to `to`.
fn drag(viewer: &Viewer, from: [f64; 2], to: [f64; 2]) {
    let [x0, y0, x1, y1] = [from[0], from[1], to[0], to[1]].map(|v| v.round() as i64);
    let actions = json!({"actions": [{"type": "pointer", "id": "mouse", "parameters": {"pointerType": "mouse"}, "actions": [
        {"type": "pointerMove", "x": x0, "y": y0, "origin": "viewport", "duration": 0},
        {"type": "pointerDown", "button": 0},
        {"type": "pause", "duration": 100},
        {"type": "pointerMove", "x": x1, "y": y1, "origin": "viewport", "duration": 600},
        {"type": "pause", "duration": 100},
        {"type": "pointerUp", "button": 0},
    ]}]});
    wd(&viewer.agent, "POST", &format!("{}/actions", viewer.session), Some(actions));
}

/// The gizmo's last IK outcome once it is settled and the robot drawn at it.
fn gizmo_outcome(viewer: &Viewer) -> Value {
    viewer.wait_for(
        "const v = window.kinemaViewer, g = v.gizmo; \
         return g.target && !g.pending && v.state.fk && JSON.stringify(v.state.fk.q) === JSON.stringify(v.q) ? g : null",
        20,
        "the gizmo's IK answer",
        |v| v.is_object(),
    )
}

/// kinema's FK (the CLI) of the iiwa at `q`: the tool position.
fn iiwa_tool(q: &[f64]) -> [f64; 3] {
    let q = q.iter().map(f64::to_string).collect::<Vec<_>>().join(",");
    let out = Command::new(env!("CARGO_BIN_EXE_kinema"))
        .args(["fk", "--robot", "lbr-iiwa-14-r820", "--q", &q, "--json"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    serde_json::from_value(v["position"].clone()).unwrap()
}

#[test]
fn a_gizmo_drag_moves_the_tool_to_the_dropped_point_or_says_it_is_unreachable() {
    let Some(viewer) = Viewer::open("lbr-iiwa-14-r820", &[], &[]) else { return };
    viewer.show_q(&[0.0, 0.4, 0.0, 1.4, 0.0, -1.0, 0.0]);
    viewer.script("document.getElementById('gizmo-on').click(); window.kinemaViewer.redraw(); return 1");
    std::thread::sleep(Duration::from_millis(300));
    let tool = |v: &Viewer| -> [f64; 2] {
        serde_json::from_value(
            v.script("const v = window.kinemaViewer; return v.project(v.state.fk.position).slice(0, 2)"),
        )
        .unwrap()
    };
    let target_pixel = |g: &Value| -> ([f64; 3], [f64; 2]) {
        let p = [0, 1, 2].map(|r| g["target"][r][3].as_f64().unwrap());
        let px = viewer.script(&format!("return window.kinemaViewer.project({}).slice(0, 2)", json!(p)));
        (p, serde_json::from_value(px).unwrap())
    };

    // Drag the handle's centre (it moves in the plane facing the camera) a little.
    let start = tool(&viewer);
    let drop = [start[0] - 25.0, start[1] + 20.0];
    drag(&viewer, start, drop);
    let g = gizmo_outcome(&viewer);
    assert_eq!(g["reached"], true, "{g}");
    let (target, pixel) = target_pixel(&g);
    assert!(
        (pixel[0] - drop[0]).abs() < 2.0 && (pixel[1] - drop[1]).abs() < 2.0,
        "dropped at {drop:?}, handle at {pixel:?}"
    );
    let q: Vec<f64> = serde_json::from_value(viewer.script("return window.kinemaViewer.q")).unwrap();
    let reached = iiwa_tool(&q);
    let miss = ((0..3).map(|k| (reached[k] - target[k]).powi(2)).sum::<f64>()).sqrt();
    println!("gizmo: dropped at {target:?}, kinema's FK of the page's q puts the tool {:.3e} m from it", miss);
    assert!(miss < 1e-3, "the tool is {miss} m from the dropped point");
    assert!((target[0] - 0.6435).abs() + (target[2] - 0.7437).abs() > 0.05, "the handle moved: {target:?}");
    assert_eq!(q[2], 0.0, "the redundant arm keeps its q3");

    // Far out of reach: said so, and the robot shows the server's closest configuration.
    let start = tool(&viewer);
    drag(&viewer, start, [start[0] + 200.0, start[1] - 150.0]);
    let g = gizmo_outcome(&viewer);
    assert_eq!(g["reached"], false, "{g}");
    assert!(g["message"].as_str().unwrap().starts_with("UNREACHABLE"), "{g}");
    let shown = viewer.script("return document.getElementById('ik-message').textContent");
    assert_eq!(shown, g["message"]);
    assert_eq!(
        viewer.script("return window.kinemaViewer.q"),
        g["closest"]["q"],
        "the page shows the closest configuration"
    );
    viewer.assert_webgl_and_no_errors();
}

#[test]
fn cell_playback_reaches_the_last_configuration_of_both_robots() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cells/seed004_two_iiwa.toml");
    let file = file.to_str().unwrap();
    let Some(viewer) = Viewer::open("lbr-iiwa-14-r820", &["--cell", file], &[]) else { return };
    viewer.assert_webgl_and_no_errors();
    let c = viewer.script("return window.kinemaViewer.cell");
    assert_eq!((c["sample"].as_u64(), c["members"].as_array().map(Vec::len)), (Some(0), Some(2)), "{c}");
    let samples = c["samples"].as_u64().unwrap();

    // Scrub to the middle: the robots are shown there, paused.
    let middle = samples / 2;
    viewer.script(&format!(
        "const t = document.getElementById('cell-time'); t.value = '{middle}'; \
         t.dispatchEvent(new Event('input', {{bubbles: true}})); return 1"
    ));
    let c = viewer.script("return window.kinemaViewer.cell");
    assert_eq!((c["sample"].as_u64(), &c["playing"]), (Some(middle), &json!(false)), "{c}");
    // Play and pause: time goes on, then stands.
    viewer.script("document.getElementById('cell-play').click(); return 1");
    std::thread::sleep(Duration::from_millis(400));
    viewer.script("document.getElementById('cell-play').click(); return 1");
    let paused = viewer.script("return window.kinemaViewer.cell");
    assert!(paused["sample"].as_u64().unwrap() > middle && paused["playing"] == false, "{paused}");
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(viewer.script("return window.kinemaViewer.cell.sample"), paused["sample"]);

    // Play to the end at 4×.
    viewer.script(
        "const s = document.getElementById('cell-speed'); s.value = '4'; \
         document.getElementById('cell-play').click(); return 1",
    );
    let end = viewer
        .wait_for("const c = window.kinemaViewer.cell; return c.playing ? null : c", 60, "the end", |v| v.is_object());
    assert_eq!(end["sample"].as_u64(), Some(samples - 1), "{end}");

    // The last configurations are those `kinema cell` writes for the same file.
    let csv = std::env::temp_dir().join(format!("kinema-serve-cell-{}.csv", std::process::id()));
    let out = Command::new(env!("CARGO_BIN_EXE_kinema"))
        .args(["cell", file, "--out", csv.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&csv).unwrap();
    let _ = std::fs::remove_file(&csv);
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let last: Vec<f64> = text.lines().last().unwrap().split(',').map(|v| v.parse().unwrap()).collect();
    assert_eq!(text.lines().count() as u64 - 1, samples, "one CSV row per sample");
    for m in end["members"].as_array().unwrap() {
        let name = m["name"].as_str().unwrap();
        let q = m["q"].as_array().unwrap();
        for (k, v) in q.iter().enumerate() {
            let col = header.iter().position(|h| *h == format!("{name}_q{}", k + 1)).unwrap();
            assert!((v.as_f64().unwrap() - last[col]).abs() < 1e-9, "{name} q{}: {v} vs {}", k + 1, last[col]);
        }
    }
    let (img, rect) = viewer.screenshot("cell");
    let drawn = (rect[1]..rect[1] + rect[3])
        .flat_map(|y| (rect[0]..rect[0] + rect[2]).map(move |x| (x, y)))
        .filter(|&(x, y)| x < img.width() && y < img.height() && !is_background(img.get_pixel(x, y)))
        .count();
    assert!(drawn > 5000, "only {drawn} drawn pixels");
    viewer.assert_webgl_and_no_errors();
}

#[test]
fn a_point_cloud_csv_is_drawn_coloured_by_its_values() {
    let Some(viewer) = Viewer::open("lbr-iiwa-14-r820", &[], &[]) else { return };
    // A grid in front of the robot in `kinema reach`'s columns; fraction rises with x.
    let mut csv = String::from("x,y,z,reached,fraction\n");
    let mut count = 0;
    for i in 0..8 {
        for j in 0..8 {
            for k in 0..4 {
                let (x, y, z) = (0.4 + 0.05 * f64::from(i), -0.2 + 0.05 * f64::from(j), 0.2 + 0.05 * f64::from(k));
                csv += &format!("{x},{y},{z},{},{}\n", u8::from(i > 0), f64::from(i) / 7.0);
                count += 1;
            }
        }
    }
    let path = std::env::temp_dir().join(format!("kinema-serve-points-{}.csv", std::process::id()));
    std::fs::write(&path, csv).unwrap();
    let input = wd(
        &viewer.agent,
        "POST",
        &format!("{}/element", viewer.session),
        Some(json!({"using": "css selector", "value": "#points-file"})),
    );
    let id = input.as_object().and_then(|o| o.values().next()).and_then(Value::as_str).unwrap().to_string();
    wd(
        &viewer.agent,
        "POST",
        &format!("{}/element/{id}/value", viewer.session),
        Some(json!({"text": path.to_str().unwrap()})),
    );
    let s = viewer.wait_for("return window.kinemaViewer.points", 10, "the point cloud", |v| v.is_object());
    let _ = std::fs::remove_file(&path);
    assert_eq!((s["count"].as_u64(), s["valued"].as_u64()), (Some(count), Some(count)), "{s}");
    assert_eq!((s["min"].as_f64(), s["max"].as_f64()), (Some(0.0), Some(1.0)), "{s}");
    let drawn = viewer.script("const v = window.kinemaViewer; v.redraw(); return v.frames").as_u64().unwrap();
    viewer.wait_for("return window.kinemaViewer.frames", 10, "a frame", |v| v.as_u64().is_some_and(|n| n > drawn));
    // The low end (x = 0.4) is drawn blue, the high end (x = 0.75) red.
    let (img, _) = viewer.screenshot("points");
    let colour_near = |p: [f64; 3]| {
        let px: [f64; 2] = serde_json::from_value(
            viewer.script(&format!("return window.kinemaViewer.project({}).slice(0, 2)", json!(p))),
        )
        .unwrap();
        let (mut red, mut blue) = (0, 0);
        for dy in -4..=4 {
            for dx in -4..=4 {
                let [r, g, b, _] = img.get_pixel((px[0] as i64 + dx) as u32, (px[1] as i64 + dy) as u32).0;
                red += usize::from(r > 150 && g < 90 && b < 90);
                blue += usize::from(b > 150 && r < 90 && g < 120);
            }
        }
        (red, blue)
    };
    let (red_low, blue_low) = colour_near([0.4, -0.2, 0.2]);
    let (red_high, blue_high) = colour_near([0.75, 0.15, 0.35]);
    assert!(blue_low > 3 && red_low == 0, "low end: {blue_low} blue, {red_low} red pixels");
    assert!(red_high > 3 && blue_high == 0, "high end: {red_high} red, {blue_high} blue pixels");
    viewer.assert_webgl_and_no_errors();
}

#[test]
fn a_planned_motion_plays_around_the_sash_to_the_goal() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/fume-hood.toml");
    let Some(viewer) = Viewer::open("lbr-iiwa-14-r820", &["--scene", scene.to_str().unwrap()], &[]) else { return };
    viewer.assert_webgl_and_no_errors();
    let deg = std::f64::consts::PI / 180.0;
    let from = [-90.0 * deg, 60.0 * deg, 0.0, 0.0, 0.0, 0.0, 0.0];
    let goal = [90.0 * deg, 60.0 * deg, 0.0, 0.0, 0.0, 0.0, 0.0];
    viewer.show_q(&from);
    // The frame axes' red x arrows would count as red pixels.
    viewer.script("const f = document.getElementById('show-frames'); f.checked = false; f.dispatchEvent(new Event('change')); return 1");
    let plan = |text: &str| {
        viewer.script(&format!(
            "document.getElementById('plan-q').value = '{text}'; document.getElementById('plan').click(); return 1"
        ));
        viewer.wait_for("const p = window.kinemaViewer.plan; return p && !p.pending ? p : null", 60, "the plan", |v| {
            v.is_object()
        })
    };
    // A goal in collision (the arm folded down): the server's message is shown.
    let refused = plan("0, 115, 0, 0, 0, 0, 0");
    assert_eq!(refused["ok"], false, "{refused}");
    let shown = viewer.script("return document.getElementById('plan-message').textContent");
    assert_eq!(shown, refused["message"]);
    assert!(shown.as_str().unwrap().contains("goal"), "{shown}");

    let planned = plan("90, 60, 0, 0, 0, 0, 0");
    assert_eq!(planned["ok"], true, "{planned}");
    viewer.script("const s = document.getElementById('play-speed'); s.value = '2'; return 1");
    let end = viewer.wait_for(
        "const p = window.kinemaViewer.player; return p && !p.playing && p.time === p.end ? p : null",
        120,
        "the end of the playback",
        |v| v.is_object(),
    );
    assert_eq!(end["source"], "plan", "{end}");
    let q: Vec<f64> = serde_json::from_value(viewer.script("return window.kinemaViewer.q")).unwrap();
    for (k, (a, b)) in q.iter().zip(goal).enumerate() {
        assert!((a - b).abs() <= 1e-9, "q{}: {a} at the end, goal {b}", k + 1);
    }
    let c = collide_answer(&viewer, &q);
    assert_eq!(c["collision"], false, "{c}");
    assert_eq!(viewer.script("return window.kinemaViewer.red"), json!([]));
    let (img, rect) = viewer.screenshot("plan-end");
    let red = red_pixels(&img, rect);
    println!("red pixels at the end of the planned motion: {red}");
    // A colliding pair draws thousands (above); edges of the brown obstacles give a few.
    assert!(red < 50, "{red} red pixels at the end of the planned motion");
    viewer.assert_webgl_and_no_errors();
}

/// `POST /api/view` on the viewer's server, as `robot.show` and `robot.animate` send it.
fn ask_view(viewer: &Viewer, body: Value) -> Value {
    let url = format!("{}api/view", viewer.url);
    let answer = viewer.agent.post(&url).set("Content-Type", "application/json").send_string(&body.to_string());
    serde_json::from_str(&answer.expect("POST /api/view").into_string().unwrap()).unwrap()
}

fn same_q(v: &Value, q: &[f64]) -> bool {
    v.as_array().is_some_and(|a| a.len() == q.len() && a.iter().zip(q).all(|(x, y)| x.as_f64() == Some(*y)))
}

#[test]
fn the_page_shows_the_configuration_and_plays_the_trajectory_a_program_asks_for() {
    let Some(viewer) = Viewer::open("lbr-iiwa-14-r820", &[], &[]) else { return };
    let q = [0.3, -0.4, 0.2, 1.1, -0.5, 0.6, 0.1];
    let asked = ask_view(&viewer, json!({"robot": "lbr-iiwa-14-r820", "q": q}));
    assert_eq!(asked["version"], 1, "{asked}");
    viewer.wait_for("return kinemaViewer.followed", 10, "the page to take request 1", |v| v == 1);
    assert!(same_q(&viewer.script("return kinemaViewer.q"), &q));
    // The FK drawn is the server's for that configuration.
    viewer.wait_for("return kinemaViewer.state.fk && kinemaViewer.state.fk.q", 10, "the FK of q", |v| same_q(v, &q));

    let last = [-0.2, 0.5, -0.1, -0.9, 0.4, -0.3, 0.2];
    let traj =
        json!({"robot": "lbr-iiwa-14-r820", "t": [0.0, 0.3, 0.6], "q": [q, [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], last]});
    assert_eq!(ask_view(&viewer, traj)["version"], 2);
    viewer.wait_for("return kinemaViewer.followed", 10, "the page to take request 2", |v| v == 2);
    let player = viewer.wait_for("return kinemaViewer.player", 10, "the trajectory to play out", |p| {
        p["playing"] == false && p["time"] == p["end"]
    });
    assert_eq!(player["end"], 0.6, "{player}");
    assert!(same_q(&viewer.script("return kinemaViewer.q"), &last));
    let errors = viewer.script("return kinemaViewer.errors");
    assert_eq!(errors, json!([]), "page errors: {errors}");
}

#[test]
fn a_cell_loads_with_both_robots_and_their_links_in_view() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cells/seed004_two_iiwa.toml");
    let Some(viewer) = Viewer::open("lbr-iiwa-14-r820", &["--cell", file.to_str().unwrap()], &[]) else { return };
    let rect: [f64; 4] = serde_json::from_value(viewer.script(
        "const r = document.getElementById('view').getBoundingClientRect(); return [r.left, r.top, r.width, r.height]",
    ))
    .unwrap();
    // The robots' bases as the cell file places them, and every link origin at the first
    // sample as the server computed it.
    let cell = viewer.agent.get(&format!("{}api/cell", viewer.url)).call().unwrap().into_string().unwrap();
    let cell: Value = serde_json::from_str(&cell).unwrap();
    let mut points = vec![[0.0, 0.0, 0.0], [1.2, 0.0, 0.0]];
    for m in cell["members"].as_array().unwrap() {
        for f in m["frames"][0].as_array().unwrap() {
            points.push([9, 10, 11].map(|k| f[k].as_f64().unwrap()));
        }
    }
    assert!(points.len() > 10, "{points:?}");
    for p in points {
        let px: [f64; 3] =
            serde_json::from_value(viewer.script(&format!("return window.kinemaViewer.project({})", json!(p))))
                .unwrap();
        let inside = px[0] > rect[0] && px[0] < rect[0] + rect[2] && px[1] > rect[1] && px[1] < rect[1] + rect[3];
        assert!(inside, "{p:?} is drawn at {px:?}, outside the canvas {rect:?}");
    }
    viewer.assert_webgl_and_no_errors();
}

/// kinema's FK (the CLI) of the iiwa at `q`: the tool position and rotation (rows).
fn iiwa_tool_pose(q: &[f64]) -> ([f64; 3], [[f64; 3]; 3]) {
    let q = q.iter().map(f64::to_string).collect::<Vec<_>>().join(",");
    let out = Command::new(env!("CARGO_BIN_EXE_kinema"))
        .args(["fk", "--robot", "lbr-iiwa-14-r820", "--q", &q, "--json"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    let t: [[f64; 4]; 4] = serde_json::from_value(v["T"].clone()).unwrap();
    ([t[0][3], t[1][3], t[2][3]], [0, 1, 2].map(|r| [t[r][0], t[r][1], t[r][2]]))
}

/// Window pixel (and depth) of the point `offset` gizmo units from the handle's centre, along
/// the world axes: the gizmo's arrows and rings are drawn that far out at its drawn scale.
fn gizmo_pixel(viewer: &Viewer, offset: [f64; 3]) -> [f64; 3] {
    let js = format!(
        "const v = window.kinemaViewer, c = v.gizmoCentre, s = v.gizmoScale, o = {}; \
         return v.project([0, 1, 2].map((k) => c[k] + s * o[k]))",
        json!(offset)
    );
    serde_json::from_value(viewer.script(&js)).unwrap()
}

/// The iiwa with the gizmo on in `mode` ("translate" or "rotate"), drawn with it at the tool.
fn gizmo_viewer(q: &[f64], mode: &str) -> Option<Viewer> {
    let viewer = Viewer::open("lbr-iiwa-14-r820", &[], &[])?;
    viewer.show_q(q);
    viewer.script(&format!(
        "document.getElementById('gizmo-on').click(); const m = document.getElementById('gizmo-mode'); \
         m.value = '{mode}'; m.dispatchEvent(new Event('change')); return 1"
    ));
    // The gizmo's scale is set when it is drawn: wait for a frame after turning it on.
    let drawn = viewer.script("const v = window.kinemaViewer; v.redraw(); return v.frames").as_u64().unwrap();
    viewer.wait_for("return window.kinemaViewer.frames", 10, "a frame with the gizmo", |v| {
        v.as_u64().is_some_and(|n| n > drawn)
    });
    Some(viewer)
}

#[test]
fn dragging_a_gizmo_arrow_moves_the_tool_along_that_axis_only() {
    let q0 = [0.0, 0.4, 0.0, 1.4, 0.0, -1.0, 0.0];
    let Some(viewer) = gizmo_viewer(&q0, "translate") else { return };
    let (start, _) = iiwa_tool_pose(&q0);
    // The x arrow's pick cone is widest at 0.6 gizmo units out; grab it at 0.45 and
    // pull it 5 cm further along x.
    let s = viewer.script("return window.kinemaViewer.gizmoScale").as_f64().unwrap();
    let from = gizmo_pixel(&viewer, [0.45, 0.0, 0.0]);
    let to = gizmo_pixel(&viewer, [0.45 + 0.05 / s, 0.0, 0.0]);
    drag(&viewer, [from[0], from[1]], [to[0], to[1]]);
    let g = gizmo_outcome(&viewer);
    assert_eq!(g["reached"], true, "{g}");
    let q: Vec<f64> = serde_json::from_value(viewer.script("return window.kinemaViewer.q")).unwrap();
    let (tool, _) = iiwa_tool_pose(&q);
    let moved = [0, 1, 2].map(|k| tool[k] - start[k]);
    println!("gizmo x arrow: the tool moved by {moved:?} m");
    assert!(moved[0].abs() > 0.01, "the tool did not move along x: {moved:?}");
    assert!(moved[1].abs() < 1e-3 && moved[2].abs() < 1e-3, "the tool left the x axis: {moved:?}");
    viewer.assert_webgl_and_no_errors();
}

#[test]
fn dragging_a_gizmo_ring_turns_the_tool_about_that_axis_in_place() {
    let q0 = [0.0, 0.4, 0.0, 1.4, 0.0, -1.0, 0.0];
    let Some(viewer) = gizmo_viewer(&q0, "rotate") else { return };
    let (start, r0) = iiwa_tool_pose(&q0);
    // The x ring (radius 0.5 in the y-z plane), grabbed between the y and z axes
    // on the side nearer the camera (away from the other rings), pulled 25° along it.
    let ring = |a: f64| [0.0, 0.5 * a.cos(), 0.5 * a.sin()];
    let grab = [1.0f64, 3.0, 5.0, 7.0]
        .map(|k| k * std::f64::consts::FRAC_PI_4)
        .into_iter()
        .min_by(|a, b| gizmo_pixel(&viewer, ring(*a))[2].total_cmp(&gizmo_pixel(&viewer, ring(*b))[2]))
        .unwrap();
    let from = gizmo_pixel(&viewer, ring(grab));
    let to = gizmo_pixel(&viewer, ring(grab + 25f64.to_radians()));
    drag(&viewer, [from[0], from[1]], [to[0], to[1]]);
    let g = gizmo_outcome(&viewer);
    assert_eq!(g["reached"], true, "{g}");
    let q: Vec<f64> = serde_json::from_value(viewer.script("return window.kinemaViewer.q")).unwrap();
    let (tool, r1) = iiwa_tool_pose(&q);
    // The turn R1·R0ᵀ: its angle, and its axis from the skew-symmetric part.
    let d = |i: usize, j: usize| (0..3).map(|k| r1[i][k] * r0[j][k]).sum::<f64>();
    let angle = ((d(0, 0) + d(1, 1) + d(2, 2) - 1.0) / 2.0).clamp(-1.0, 1.0).acos();
    let axis = [d(2, 1) - d(1, 2), d(0, 2) - d(2, 0), d(1, 0) - d(0, 1)].map(|v| v / (2.0 * angle.sin()));
    let moved = (0..3).map(|k| (tool[k] - start[k]).powi(2)).sum::<f64>().sqrt();
    println!("gizmo x ring: the tool turned {:.2}° about {axis:?}, moved {moved:.2e} m", angle.to_degrees());
    assert!(angle.to_degrees() > 2.0, "the tool did not turn: {angle} rad");
    assert!(axis[0].abs() > 1.0 - 1e-6 && axis[1].abs() < 1e-3 && axis[2].abs() < 1e-3, "not about x: {axis:?}");
    assert!(moved < 1e-3, "the tool moved {moved} m while turning");
    viewer.assert_webgl_and_no_errors();
}
