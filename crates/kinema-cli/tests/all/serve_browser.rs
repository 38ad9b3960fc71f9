//! `kinema serve` in a real browser: the binary serves the page, headless
//! Chromium loads it through chromedriver (the WebDriver HTTP protocol), a
//! joint slider moves, the FK readout follows, the IK panel, the ellipsoid
//! and the program player answer, and a screenshot shows a drawn robot.
//!
//! Skipped (passes, printing `skipped: …`) when /usr/bin/chromium or
//! /usr/bin/chromedriver is missing. Set KINEMA_SERVE_SCREENSHOT=/path.png to
//! keep the screenshot.

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

#[test]
fn the_viewer_works_in_headless_chromium() {
    for p in [CHROMIUM, CHROMEDRIVER] {
        if !Path::new(p).exists() {
            println!("skipped: {p} is missing (apt-get install chromium chromium-driver)");
            return;
        }
    }
    let agent = ureq::AgentBuilder::new().timeout(Duration::from_secs(60)).build();
    let profile = std::env::temp_dir().join(format!("kinema-serve-browser-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&profile);
    std::fs::create_dir_all(&profile).unwrap();
    let mut guard = Guard { agent: agent.clone(), session: None, children: Vec::new(), profile: Some(profile.clone()) };

    // The server: its URL is the one line it prints on stdout.
    let mut server = Command::new(env!("CARGO_BIN_EXE_kinema"))
        .args(["serve", "--robot", "lbr-iiwa-14-r820", "--port", "0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("kinema serve starts");
    let stdout = server.stdout.take().unwrap();
    guard.children.push(server);
    let mut lines = BufReader::new(stdout).lines();
    let first = lines.next().expect("a line on stdout").expect("readable stdout");
    let url =
        first.strip_prefix("kinema serve: ").unwrap_or_else(|| panic!("unexpected first line `{first}`")).to_string();
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
    let caps = json!({"capabilities": {"alwaysMatch": {"goog:chromeOptions": {
        "binary": CHROMIUM,
        "args": ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-quic",
                 "--disable-component-update", "--disable-sync", "--no-first-run", "--window-size=1400,950",
                 format!("--user-data-dir={}", profile.display())],
    }}}});
    let created = wd(&agent, "POST", &format!("{base}/session"), Some(caps));
    let session = format!("{base}/session/{}", created["sessionId"].as_str().expect("a session id"));
    guard.session = Some(session.clone());
    let s = session.as_str();

    // Load the page; it sets data-ready once the robot is drawn.
    wd(&agent, "POST", &format!("{s}/url"), Some(json!({"url": url})));
    wait_for(&agent, s, "return document.body.dataset.ready || null", 30, "the page to be ready", |v| v == "1");
    let sliders = script(&agent, s, "return document.querySelectorAll('#sliders input[type=range]').length");
    assert_eq!(sliders, 7, "one slider per joint");
    let before = script(&agent, s, "return document.getElementById('fk-readout').textContent");
    let before = before.as_str().unwrap().to_string();
    assert!(before.contains("z 1.3060"), "home readout: {before}");

    // Move joint 2 as a user would (value + input event); the readout follows.
    // (The slider snaps to its step, so the value it took is read back.)
    let q2 = script(
        &agent,
        s,
        "const el = document.querySelector('input[data-joint=\"2\"]'); el.value = '0.8'; \
         el.dispatchEvent(new Event('input', {bubbles: true})); return el.value;",
    );
    let q2: f64 = q2.as_str().and_then(|v| v.parse().ok()).expect("the slider's value");
    assert!((q2 - 0.8).abs() < 0.002, "{q2}");
    let after =
        wait_for(&agent, s, "return document.getElementById('fk-readout').textContent", 10, "the FK readout", |v| {
            v.as_str().is_some_and(|t| t != before)
        });
    let after = after.as_str().unwrap();
    assert!(!after.contains("z 1.3060"), "{after}");
    // The arm stays straight above joint 2: z = 0.36 + (0.42 + 0.4 + 0.126)·cos q2.
    let z = 0.36 + (0.42 + 0.4 + 0.126) * q2.cos();
    assert!(after.contains(&format!("z {z:.4}")), "expected z {z:.4} in {after}");

    // Bend the elbow and the wrist (away from the stretched, singular arm).
    script(
        &agent,
        s,
        "for (const [j, v] of [[4, '-1.2'], [6, '0.6']]) { const el = document.querySelector(`input[data-joint=\"${j}\"]`); \
         el.value = v; el.dispatchEvent(new Event('input', {bubbles: true})); } return 1",
    );
    wait_for(&agent, s, "return window.kinemaViewer.fk.q[3]", 10, "the bent elbow", |v| {
        v.as_f64().is_some_and(|q| q < -1.0)
    });

    // IK at the current tool pose: every solution listed.
    script(
        &agent,
        s,
        "document.getElementById('ik-from-tool').click(); document.getElementById('ik-solve').click(); return 1",
    );
    let rows = wait_for(
        &agent,
        s,
        "return [document.querySelectorAll('#ik-solutions tbody tr').length, document.getElementById('ik-message').textContent]",
        10,
        "IK solutions",
        |v| v[0].as_u64().is_some_and(|n| n > 0),
    );
    assert!(rows[0].as_u64().unwrap() >= 2, "the iiwa has several branches at one q3: {rows}");
    // Pick the last solution: the robot moves there (the readout's joint values change).
    let q_before = script(&agent, s, "return window.kinemaViewer.q.join(',')");
    script(
        &agent,
        s,
        "const r = document.querySelectorAll('#ik-solutions tbody tr'); r[r.length - 1].cells[1].click(); return 1",
    );
    wait_for(&agent, s, "return window.kinemaViewer.fk.q.join(',')", 10, "the picked branch", |v| *v != q_before);

    // The manipulability ellipsoid.
    script(&agent, s, "document.getElementById('show-ellipsoid').click(); return 1");
    wait_for(
        &agent,
        s,
        "return document.getElementById('manip-readout').textContent",
        10,
        "the ellipsoid readout",
        |v| v.as_str().is_some_and(|t| t.contains("Yoshikawa")),
    );

    // The player: run the default program, jump to the middle.
    script(&agent, s, "document.getElementById('run-program').click(); return 1");
    wait_for(&agent, s, "return document.getElementById('play').disabled", 60, "the program's trajectory", |v| {
        *v == false
    });
    let label = script(
        &agent,
        s,
        "const t = document.getElementById('time-slider'); t.value = String((+t.max) / 2); \
         t.dispatchEvent(new Event('input', {bubbles: true})); return document.getElementById('time-label').textContent",
    );
    assert!(label.as_str().is_some_and(|t| t.contains(" / ")), "{label}");
    std::thread::sleep(Duration::from_millis(500));

    // A screenshot: the 3D view is drawn (many colours, robot-coloured pixels).
    let png = base64_decode(wd(&agent, "GET", &format!("{s}/screenshot"), None).as_str().expect("base64 PNG"));
    if let Some(path) = std::env::var_os("KINEMA_SERVE_SCREENSHOT") {
        std::fs::write(path, &png).unwrap();
    }
    let img = image::load_from_memory(&png).expect("a PNG").to_rgba8();
    let rect = script(
        &agent,
        s,
        "const r = document.getElementById('view').getBoundingClientRect(); \
         return [r.left, r.top, r.width, r.height, window.devicePixelRatio]",
    );
    let f = |i: usize| rect[i].as_f64().unwrap();
    let (x0, y0) = ((f(0) * f(4)) as u32, (f(1) * f(4)) as u32);
    let (w, h) = ((f(2) * f(4)) as u32, (f(3) * f(4)) as u32);
    assert!(w > 200 && h > 200, "the view is {w}×{h}");
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
    assert!(coloured > 2000, "only {coloured} strongly coloured pixels (links, joints, frames) in the 3D view");
    drop(guard);
}
