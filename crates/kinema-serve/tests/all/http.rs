//! The server's HTTP handling: oversized, malformed, stalled and half-closed
//! requests are refused or answered without blocking others, and stopping
//! frees the port at once.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::Duration;

use kinema::Robot;
use kinema_serve::{Server, MAX_BODY};
use serde_json::{json, Value};

use crate::api::{call, exchange, post, raw, start};

#[test]
fn oversized_bodies_get_413_without_being_read() {
    let server = start();
    let addr = server.local_addr();
    // Announce 2 MiB but send only a little: the answer comes before the body.
    let head = format!(
        "POST /api/run HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\nContent-Length: {}",
        2 * MAX_BODY
    );
    let a = raw(addr, &head, &[b'{'; 1000]);
    assert_eq!(a.status, 413, "{}", a.headers);
    assert!(a.json["error"].as_str().unwrap().contains("1048576"));
    // A body just over the limit, sent whole.
    let mut body = b"{\"program\": \"".to_vec();
    body.resize(MAX_BODY + 10, b' ');
    let a = call(addr, "POST", "/api/run", &body);
    assert_eq!(a.status, 413);
    // Still answering.
    let a = post(addr, "/api/fk", &json!({"q": [0, 0, 0, 0, 0, 0, 0]}));
    assert_eq!(a.status, 200);
}

#[test]
fn stops_and_frees_the_port() {
    let server = start();
    let addr = server.local_addr();
    assert_eq!(call(addr, "GET", "/api/robots", b"").status, 200);
    server.stop();
    // The workers and the acceptor are gone and the listener is closed.
    let start = std::time::Instant::now();
    while Server::bind(addr, None).is_err() {
        assert!(start.elapsed() < Duration::from_secs(5), "the port is free again");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Reads one answer from a connection that stays open: status, header block
/// and body (by its Content-Length; none for `HEAD`). `pending` keeps what
/// was read beyond it.
fn read_answer(s: &mut TcpStream, pending: &mut Vec<u8>, head_request: bool) -> (u16, String, Vec<u8>) {
    let mut chunk = [0u8; 65536];
    let end = loop {
        if let Some(i) = pending.windows(4).position(|w| w == b"\r\n\r\n") {
            break i;
        }
        let n = s.read(&mut chunk).expect("reads an answer");
        assert!(n > 0, "the connection closed before an answer: {}", String::from_utf8_lossy(pending));
        pending.extend_from_slice(&chunk[..n]);
    };
    let headers = String::from_utf8_lossy(&pending[..end]).into_owned();
    pending.drain(..end + 4);
    let status = headers.split_whitespace().nth(1).and_then(|s| s.parse().ok()).unwrap_or(0);
    let length: usize = headers
        .lines()
        .find_map(|l| l.to_ascii_lowercase().strip_prefix("content-length:").map(|v| v.trim().parse().unwrap()))
        .expect("a Content-Length");
    let length = if head_request || status == 100 { 0 } else { length };
    while pending.len() < length {
        let n = s.read(&mut chunk).expect("reads a body");
        assert!(n > 0, "the connection closed within a body");
        pending.extend_from_slice(&chunk[..n]);
    }
    let body = pending.drain(..length).collect();
    (status, headers, body)
}

/// Whether the server closes `s` within `limit` (reading and discarding).
fn closed_within(s: &mut TcpStream, limit: Duration) -> bool {
    let start = std::time::Instant::now();
    s.set_read_timeout(Some(Duration::from_millis(50))).unwrap();
    let mut sink = [0u8; 1024];
    while start.elapsed() < limit {
        match s.read(&mut sink) {
            Ok(0) => return true,
            Ok(_) => {}
            Err(e) if matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => {}
            Err(_) => return true,
        }
    }
    false
}

#[test]
fn huge_announced_bodies_are_refused_at_once_and_the_server_goes_on() {
    let server = start();
    let addr = server.local_addr();
    for length in ["100000000000", "1000000000000000000"] {
        for expect in ["", "\r\nExpect: 100-continue"] {
            let t0 = std::time::Instant::now();
            let head = format!("POST /api/run HTTP/1.1\r\nHost: {addr}\r\nContent-Length: {length}{expect}");
            let a = raw(addr, &head, b"{\"program\": ");
            assert_eq!(a.status, 413, "{}", a.headers);
            assert!(!a.headers.contains("100 Continue"), "{}", a.headers);
            assert!(a.headers.contains("Connection: close"), "{}", a.headers);
            assert!(a.json["error"].as_str().unwrap().contains("1048576"), "{}", a.json);
            assert!(t0.elapsed() < Duration::from_secs(3), "answered at once");
        }
    }
    // A length beyond u64 is not a length: hyper refuses the head (400, no body).
    let t0 = std::time::Instant::now();
    let head = format!("POST /api/run HTTP/1.1\r\nHost: {addr}\r\nContent-Length: 99999999999999999999999999999");
    let a = raw(addr, &head, b"{\"program\": ");
    assert_eq!(a.status, 400, "{}", a.headers);
    assert!(t0.elapsed() < Duration::from_secs(3), "answered at once");
    // Still answering.
    let a = post(addr, "/api/fk", &json!({"q": [0, 0, 0, 0, 0, 0, 0]}));
    assert_eq!(a.status, 200);
}

#[test]
fn oversized_heads_garbage_and_chunked_bodies_are_refused() {
    let server = start();
    let addr = server.local_addr();
    // Refused by hyper before the request reaches the handler: status only.
    let a = raw(addr, &format!("GET /api/robots HTTP/1.1\r\nHost: {addr}\r\nX-Filler: {}", "a".repeat(20_000)), b"");
    assert_eq!(a.status, 431, "{}", a.headers);
    let many: String = (0..100).map(|i| format!("\r\nX-{i}: y")).collect();
    let a = raw(addr, &format!("GET /api/robots HTTP/1.1\r\nHost: {addr}{many}"), b"");
    assert_eq!(a.status, 431, "{}", a.headers);
    for garbage in [
        &b"\x16\x03\x01\x02\x00\x01\x00\x01\xfc\x03\x03\r\n\r\n"[..],
        b"hello there\r\n\r\n",
        b"GET / HTTP/9.9\r\n\r\n",
    ] {
        let a = exchange(addr, garbage);
        assert_eq!(a.status, 400, "{}: {}", String::from_utf8_lossy(garbage), a.headers);
    }
    // Chunked bodies are read, within the same size limit.
    let fk = json!({"q": [0, 0, 0, 0, 0, 0, 0]}).to_string();
    let chunked = format!("{:x}\r\n{}\r\n{:x}\r\n{}\r\n0\r\n\r\n", 5, &fk[..5], fk.len() - 5, &fk[5..]);
    let a =
        raw(addr, &format!("POST /api/fk HTTP/1.1\r\nHost: {addr}\r\nTransfer-Encoding: chunked"), chunked.as_bytes());
    assert_eq!(a.status, 200, "{}", a.headers);
    assert!(a.json["T"].is_array(), "{}", a.json);
    let big = vec![b' '; 256 * 1024];
    let mut chunked = Vec::new();
    for _ in 0..5 {
        chunked.extend_from_slice(format!("{:x}\r\n", big.len()).as_bytes());
        chunked.extend_from_slice(&big);
        chunked.extend_from_slice(b"\r\n");
    }
    chunked.extend_from_slice(b"0\r\n\r\n");
    let a = raw(addr, &format!("POST /api/fk HTTP/1.1\r\nHost: {addr}\r\nTransfer-Encoding: chunked"), &chunked);
    assert_eq!(a.status, 413, "{}", a.headers);
    assert!(a.json["error"].as_str().unwrap().contains("1048576"), "{}", a.json);
    let a =
        raw(addr, &format!("POST /api/fk HTTP/1.1\r\nHost: {addr}\r\nContent-Length: 2\r\nContent-Length: 3"), b"{}");
    assert_eq!(a.status, 400, "{}", a.headers);
    let a = raw(addr, &format!("POST /api/fk HTTP/1.1\r\nHost: {addr}\r\nContent-Length: two"), b"{}");
    assert_eq!(a.status, 400, "{}", a.headers);
    // Still answering.
    assert_eq!(call(addr, "GET", "/api/robots", b"").status, 200);
}

#[test]
fn stalled_and_silent_clients_do_not_block_other_requests() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let server = Server::bind("127.0.0.1:0", Some(robot)).unwrap().with_read_timeout(Duration::from_secs(1)).spawn();
    let addr = server.local_addr();
    // Eight clients send half a head and stall.
    let mut stalled: Vec<TcpStream> = (0..8)
        .map(|_| {
            let mut s = TcpStream::connect(addr).unwrap();
            s.write_all(format!("POST /api/fk HTTP/1.1\r\nHost: {addr}\r\nContent-").as_bytes()).unwrap();
            s
        })
        .collect();
    std::thread::sleep(Duration::from_millis(100));
    let t0 = std::time::Instant::now();
    assert_eq!(call(addr, "GET", "/api/robots", b"").status, 200);
    assert!(t0.elapsed() < Duration::from_millis(500), "answered after {:?}", t0.elapsed());
    for s in &mut stalled {
        assert!(closed_within(s, Duration::from_secs(4)), "a stalled client is dropped");
    }
    // A client trickling its head is dropped at the read timeout too.
    let mut s = TcpStream::connect(addr).unwrap();
    s.write_all(b"GET /api/robots HTTP/1.1\r\n").unwrap();
    let t0 = std::time::Instant::now();
    let mut closed = false;
    while t0.elapsed() < Duration::from_secs(4) {
        if s.write_all(b"X-Slow: y\r\n").is_err() || closed_within(&mut s, Duration::from_millis(100)) {
            closed = true;
            break;
        }
    }
    assert!(closed, "a trickling client is dropped");
    drop(server);

    // Silent connections (as browsers open ahead of use) do not delay a
    // request either.
    let server = start();
    let addr = server.local_addr();
    let silent: Vec<TcpStream> = (0..6).map(|_| TcpStream::connect(addr).unwrap()).collect();
    std::thread::sleep(Duration::from_millis(100));
    let t0 = std::time::Instant::now();
    assert_eq!(call(addr, "GET", "/api/robots", b"").status, 200);
    assert!(t0.elapsed() < Duration::from_millis(500), "answered after {:?}", t0.elapsed());
    drop(silent);
}

#[test]
fn expect_100_continue_is_answered_before_the_body() {
    let server = start();
    let addr = server.local_addr();
    let mut body = json!({"q": [0, 0, 0, 0, 0, 0, 0], "robot": "lbr-iiwa-14-r820"}).to_string();
    body.push_str(&" ".repeat(2000));
    let mut s = TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    let head = format!(
        "POST /api/fk HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\nContent-Length: {}\r\nExpect: 100-continue\r\n\r\n",
        body.len()
    );
    s.write_all(head.as_bytes()).unwrap();
    let mut pending = Vec::new();
    let mut chunk = [0u8; 256];
    while !pending.ends_with(b"\r\n\r\n") {
        let n = s.read(&mut chunk).unwrap();
        assert!(n > 0);
        pending.extend_from_slice(&chunk[..n]);
    }
    assert_eq!(pending, b"HTTP/1.1 100 Continue\r\n\r\n");
    s.write_all(body.as_bytes()).unwrap();
    let (status, _, body) = read_answer(&mut s, &mut Vec::new(), false);
    assert_eq!(status, 200);
    let v: Value = serde_json::from_slice(&body).unwrap();
    assert_eq!(v["T"].as_array().map(Vec::len), Some(4));
}

#[test]
fn keep_alive_serves_requests_one_after_the_other() {
    let server = start();
    let addr = server.local_addr();
    let mut s = TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    let mut pending = Vec::new();
    s.write_all(format!("GET /api/robots HTTP/1.1\r\nHost: {addr}\r\n\r\n").as_bytes()).unwrap();
    let (status, headers, body) = read_answer(&mut s, &mut pending, false);
    assert_eq!(status, 200);
    assert!(!headers.contains("Connection: close"), "{headers}");
    assert!(headers.contains("X-Content-Type-Options: nosniff"), "{headers}");
    assert!(serde_json::from_slice::<Value>(&body).unwrap().is_array());
    let fk = json!({"q": [0, 0, 0, 0, 0, 0, 0]}).to_string();
    s.write_all(
        format!("POST /api/fk?x=1 HTTP/1.1\r\nHost: {addr}\r\nContent-Length: {}\r\n\r\n{fk}", fk.len()).as_bytes(),
    )
    .unwrap();
    let (status, _, body) = read_answer(&mut s, &mut pending, false);
    assert_eq!(status, 200);
    assert!(serde_json::from_slice::<Value>(&body).unwrap()["T"].is_array());
    // HEAD: the headers of GET, no body.
    s.write_all(format!("HEAD / HTTP/1.1\r\nHost: {addr}\r\n\r\n").as_bytes()).unwrap();
    let (status, headers, _) = read_answer(&mut s, &mut pending, true);
    assert_eq!(status, 200);
    assert!(headers.contains("text/html") && !headers.contains("Content-Length: 0"), "{headers}");
    // Two pipelined requests, the second asking to close.
    s.write_all(
        format!(
            "GET /api/robots/puma560 HTTP/1.1\r\nHost: {addr}\r\n\r\nGET /api/nothing HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
        )
        .as_bytes(),
    )
    .unwrap();
    let (status, _, body) = read_answer(&mut s, &mut pending, false);
    assert_eq!(status, 200, "{}", String::from_utf8_lossy(&body));
    assert_eq!(serde_json::from_slice::<Value>(&body).unwrap()["dof"], 6);
    let (status, headers, _) = read_answer(&mut s, &mut pending, false);
    assert_eq!(status, 404);
    assert!(headers.contains("Connection: close"), "{headers}");
    assert!(pending.is_empty() && closed_within(&mut s, Duration::from_secs(3)));
    // HTTP/1.0 closes unless asked to keep alive.
    let mut s = TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    s.write_all(b"GET /api/robots HTTP/1.0\r\nConnection: keep-alive\r\n\r\n").unwrap();
    let (status, headers, _) = read_answer(&mut s, &mut pending, false);
    assert_eq!(status, 200);
    assert!(headers.contains("Connection: keep-alive"), "{headers}");
    s.write_all(b"GET /style.css HTTP/1.0\r\n\r\n").unwrap();
    let (status, headers, _) = read_answer(&mut s, &mut pending, false);
    assert_eq!(status, 200);
    // HTTP/1.0 closes by default: hyper says so with the version, not a header.
    assert!(headers.starts_with("HTTP/1.0 200") || headers.contains("Connection: close"), "{headers}");
    assert!(headers.contains("text/css") && !headers.contains("keep-alive"), "{headers}");
    assert!(closed_within(&mut s, Duration::from_secs(3)));
}

#[test]
fn stop_is_prompt_with_connections_open() {
    let server = start();
    let addr = server.local_addr();
    let mut idle = TcpStream::connect(addr).unwrap();
    idle.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    idle.write_all(format!("GET /api/robots HTTP/1.1\r\nHost: {addr}\r\n\r\n").as_bytes()).unwrap();
    assert_eq!(read_answer(&mut idle, &mut Vec::new(), false).0, 200);
    let mut stalled = TcpStream::connect(addr).unwrap();
    stalled.write_all(b"GET /api/robots HTTP/1.1\r\n").unwrap();
    let _silent = TcpStream::connect(addr).unwrap();
    std::thread::sleep(Duration::from_millis(100));
    let t0 = std::time::Instant::now();
    server.stop();
    assert!(t0.elapsed() < Duration::from_secs(2), "stopped after {:?}", t0.elapsed());
    assert!(closed_within(&mut idle, Duration::from_secs(1)));
    assert!(closed_within(&mut stalled, Duration::from_secs(1)));
    // The listener is closed: the port can be bound again.
    assert!(Server::bind(addr, None).is_ok());
}

#[test]
fn an_address_in_use_keeps_the_os_error() {
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = taken.local_addr().unwrap();
    let e = match Server::bind(addr, None) {
        Err(e) => e,
        Ok(_) => panic!("bound {addr} twice"),
    };
    assert!(matches!(&e, kinema_serve::Error::Bind { addr: a, .. } if *a == addr.to_string()), "{e:?}");
    assert_eq!(e.status(), 500);
    let io = std::error::Error::source(&e)
        .and_then(|s| s.source())
        .and_then(|s| s.downcast_ref::<std::io::Error>())
        .map(|io| io.kind());
    assert_eq!(io, Some(std::io::ErrorKind::AddrInUse), "{e:?}");
}

/// Issue 35 item 7: a client that half-closes its connection right after
/// the request (shutdown of its sending side) still gets the whole answer,
/// every time — a heavy request (IK) and a light one, keep-alive or not.
#[test]
fn a_half_closed_client_gets_its_answer() {
    let server = start();
    let addr = server.local_addr();
    let q = [0.0, 0.5, 0.0, -1.0, 0.0, 0.5, 0.0];
    let target = Robot::builtin("lbr-iiwa-14-r820").unwrap().fk(&q).unwrap().world_from_tool;
    let ik = json!({"T": target.to_rows(), "q3": 0.0}).to_string();
    let fk = json!({ "q": q }).to_string();
    for k in 0..60 {
        let (path, body) = if k % 2 == 0 { ("/api/ik", ik.as_bytes()) } else { ("/api/fk", fk.as_bytes()) };
        let close = if k % 3 == 0 { "Connection: close\r\n" } else { "" };
        let req = format!(
            "POST {path} HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\n{close}Content-Length: {}\r\n\r\n",
            body.len()
        );
        let mut s = TcpStream::connect(addr).unwrap();
        s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
        s.write_all(req.as_bytes()).unwrap();
        s.write_all(body).unwrap();
        s.shutdown(std::net::Shutdown::Write).unwrap();
        let mut out = Vec::new();
        let _ = s.read_to_end(&mut out);
        let text = String::from_utf8_lossy(&out);
        assert!(text.starts_with("HTTP/1.1 200"), "request {k} ({path}): {text:?}");
        let split = out.windows(4).position(|w| w == b"\r\n\r\n").unwrap();
        let json: Value = serde_json::from_slice(&out[split + 4..]).unwrap();
        assert!(json.is_object(), "request {k}: {json}");
    }
    drop(server);
}
