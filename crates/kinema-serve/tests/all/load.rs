//! The server under load and under abuse, on 127.0.0.1: many keep-alive
//! clients next to stalled ones, programs that run too long, clients that
//! leave, and shutdown while programs run. Every test is bounded in time.

use std::io::{ErrorKind, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::sync::{Arc, Barrier, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use kinema::Robot;
use kinema_serve::{Limits, Running, Server};
use serde_json::{json, Value};

/// A program within every cap of the language (450 000 passes, each an IK
/// solve for a PTP to where the arm already is) that runs for about ten
/// seconds, looked at by the stop condition between every two statements.
const WEDGE: &str = "JACC 90 deg/s^2\nPOS p = CART(550mm, -150mm, 400mm, 0deg, 180deg, 0deg)\nPTP p\nFOR i = 1 TO 450000\n  PTP p\nEND\n";

/// The tests here run one at a time: the CPU-heavy ones would distort the
/// load test's latencies.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

fn one_at_a_time() -> MutexGuard<'static, ()> {
    ONE_AT_A_TIME.lock().unwrap_or_else(PoisonError::into_inner)
}

fn start(limits: Limits) -> Running {
    let robot = Robot::builtin("lbr-iiwa-14-r820").expect("built-in robot");
    Server::bind("127.0.0.1:0", Some(robot)).expect("binds a free port").with_limits(limits).spawn()
}

/// A keep-alive HTTP/1.1 client on one connection.
struct Client {
    s: TcpStream,
    pending: Vec<u8>,
}

impl Client {
    fn connect(addr: SocketAddr) -> std::io::Result<Client> {
        let s = TcpStream::connect(addr)?;
        s.set_read_timeout(Some(Duration::from_secs(20)))?;
        s.set_nodelay(true)?;
        Ok(Client { s, pending: Vec::new() })
    }

    /// Sends one request and reads its answer: status, headers, body.
    fn request(&mut self, method: &str, path: &str, body: &str) -> std::io::Result<(u16, String, Vec<u8>)> {
        let req = format!(
            "{method} {path} HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
            body.len()
        );
        self.s.write_all(req.as_bytes())?;
        let mut chunk = [0u8; 16384];
        let end = loop {
            if let Some(i) = self.pending.windows(4).position(|w| w == b"\r\n\r\n") {
                break i;
            }
            let n = self.s.read(&mut chunk)?;
            if n == 0 {
                return Err(ErrorKind::UnexpectedEof.into());
            }
            self.pending.extend_from_slice(&chunk[..n]);
        };
        let headers = String::from_utf8_lossy(&self.pending[..end]).into_owned();
        self.pending.drain(..end + 4);
        let status = headers.split_whitespace().nth(1).and_then(|s| s.parse().ok()).unwrap_or(0);
        let length: usize = headers
            .lines()
            .find_map(|l| l.to_ascii_lowercase().strip_prefix("content-length:").and_then(|v| v.trim().parse().ok()))
            .ok_or(ErrorKind::InvalidData)?;
        while self.pending.len() < length {
            let n = self.s.read(&mut chunk)?;
            if n == 0 {
                return Err(ErrorKind::UnexpectedEof.into());
            }
            self.pending.extend_from_slice(&chunk[..n]);
        }
        let body = self.pending.drain(..length).collect();
        Ok((status, headers, body))
    }
}

/// A connection that sends half a request head and then nothing.
fn stall(addr: SocketAddr) -> TcpStream {
    let mut s = TcpStream::connect(addr).expect("connects");
    s.write_all(b"POST /api/fk HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-").expect("sends half a head");
    s
}

/// Whether the server still holds `s` open (nothing to read, no end of input).
fn still_open(s: &TcpStream) -> bool {
    s.set_nonblocking(true).unwrap();
    let mut byte = [0u8; 1];
    let open = matches!((&*s).read(&mut byte), Err(e) if e.kind() == ErrorKind::WouldBlock);
    s.set_nonblocking(false).unwrap();
    open
}

fn percentile(sorted: &[Duration], p: f64) -> Duration {
    sorted[((sorted.len() - 1) as f64 * p).round() as usize]
}

#[test]
fn five_thousand_keep_alive_requests_next_to_stalled_clients() {
    let _serial = one_at_a_time();
    const CLIENTS: usize = 64;
    const PER_CLIENT: usize = 80;
    let server = start(Limits::default());
    let addr = server.local_addr();
    let stalled: Vec<TcpStream> = (0..8).map(|_| stall(addr)).collect();
    let barrier = Arc::new(Barrier::new(CLIENTS));
    let t0 = Instant::now();
    let threads: Vec<_> = (0..CLIENTS)
        .map(|c| {
            let barrier = Arc::clone(&barrier);
            std::thread::spawn(move || {
                let mut latencies = Vec::with_capacity(PER_CLIENT);
                let mut errors = Vec::new();
                let mut client = match Client::connect(addr) {
                    Ok(client) => Some(client),
                    Err(e) => {
                        errors.push(format!("connect: {e}"));
                        None
                    }
                };
                // One request each before the clock starts, as a warm-up.
                if let Some(c) = client.as_mut() {
                    if let Err(e) = c.request("GET", "/api/robots", "") {
                        errors.push(format!("warm-up: {e}"));
                    }
                }
                barrier.wait();
                let Some(client) = client.as_mut() else { return (latencies, errors) };
                let start = Instant::now();
                for i in 0..PER_CLIENT {
                    if start.elapsed() > Duration::from_secs(40) {
                        errors.push("out of time".into());
                        break;
                    }
                    let x = (c * PER_CLIENT + i) as f64 * 1e-4;
                    let body = json!({"q": [x, 0.5, -x, -1.2, 0.1, 0.6, x]}).to_string();
                    let sent = Instant::now();
                    match client.request("POST", "/api/fk", &body) {
                        Ok((200, headers, body)) if !headers.contains("Connection: close") => {
                            latencies.push(sent.elapsed());
                            // A light check (parsing every answer would load the CPU the server needs).
                            if !body.starts_with(b"{") || !body.windows(5).any(|w| w == b"\"T\":[") {
                                errors.push(format!("not an FK answer: {}", String::from_utf8_lossy(&body)));
                            }
                        }
                        Ok((status, headers, _)) => errors.push(format!("{status}: {headers}")),
                        Err(e) => {
                            errors.push(format!("transport: {e}"));
                            break;
                        }
                    }
                }
                (latencies, errors)
            })
        })
        .collect();
    let mut latencies = Vec::new();
    let mut errors = Vec::new();
    for t in threads {
        let (l, e) = t.join().expect("a client thread");
        latencies.extend(l);
        errors.extend(e);
    }
    let elapsed = t0.elapsed();
    latencies.sort();
    let (p50, p99) = (percentile(&latencies, 0.5), percentile(&latencies, 0.99));
    eprintln!(
        "load: {} requests over {CLIENTS} keep-alive clients with 8 stalled clients in {:.2} s \
         ({:.0} req/s); p50 {:.2} ms, p99 {:.2} ms, max {:.2} ms; {} errors",
        latencies.len(),
        elapsed.as_secs_f64(),
        latencies.len() as f64 / elapsed.as_secs_f64(),
        p50.as_secs_f64() * 1e3,
        p99.as_secs_f64() * 1e3,
        latencies.last().map_or(0.0, |d| d.as_secs_f64() * 1e3),
        errors.len()
    );
    assert!(errors.is_empty(), "{} errors, the first: {:?}", errors.len(), errors.first());
    assert_eq!(latencies.len(), CLIENTS * PER_CLIENT);
    assert!(p99 < Duration::from_millis(50), "p99 {p99:?}");
    // The stalled clients were connected all along (the head timeout is 10 s).
    assert!(elapsed < Duration::from_secs(9), "took {elapsed:?}");
    assert!(stalled.iter().all(still_open), "a stalled client was dropped early");
}

#[test]
fn a_stalled_client_does_not_delay_another() {
    let _serial = one_at_a_time();
    let server = start(Limits::default());
    let addr = server.local_addr();
    // One stalled in its head, one in its body, one silent.
    let _head = stall(addr);
    let mut body = TcpStream::connect(addr).unwrap();
    body.write_all(b"POST /api/fk HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 100\r\n\r\n{\"q\": ").unwrap();
    let _silent = TcpStream::connect(addr).unwrap();
    std::thread::sleep(Duration::from_millis(100));
    for _ in 0..3 {
        let t0 = Instant::now();
        let mut c = Client::connect(addr).unwrap();
        assert_eq!(c.request("GET", "/api/robots", "").unwrap().0, 200);
        assert_eq!(c.request("POST", "/api/fk", r#"{"q": [0, 0, 0, 0, 0, 0, 0]}"#).unwrap().0, 200);
        assert!(t0.elapsed() < Duration::from_millis(500), "answered after {:?}", t0.elapsed());
    }
}

#[test]
fn cheap_requests_stay_fast_while_programs_wedge_and_a_program_gets_its_budget() {
    let _serial = one_at_a_time();
    let limits = Limits { run_budget: Duration::from_millis(1500), heavy_concurrency: 2, ..Limits::default() };
    let server = start(limits);
    let addr = server.local_addr();
    // Twice as many wedging programs as there are slots for them.
    let runs: Vec<_> = (0..4)
        .map(|_| {
            std::thread::spawn(move || {
                let mut c = Client::connect(addr).unwrap();
                let t0 = Instant::now();
                let body = json!({"program": WEDGE, "dt": 0.5}).to_string();
                let (status, _, body) = c.request("POST", "/api/run", &body).expect("an answer");
                (status, serde_json::from_slice::<Value>(&body).unwrap(), t0.elapsed())
            })
        })
        .collect();
    std::thread::sleep(Duration::from_millis(200));
    let t0 = Instant::now();
    let mut worst = Duration::ZERO;
    let mut cheap = 0;
    while t0.elapsed() < Duration::from_millis(2500) {
        for (method, path, body) in
            [("GET", "/api/robots", ""), ("GET", "/", ""), ("POST", "/api/fk", r#"{"q": [0, 0, 0, 0, 0, 0, 0]}"#)]
        {
            let sent = Instant::now();
            let mut c = Client::connect(addr).unwrap();
            assert_eq!(c.request(method, path, body).unwrap().0, 200, "{method} {path}");
            worst = worst.max(sent.elapsed());
            cheap += 1;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    eprintln!("wedge: {cheap} cheap requests while 4 programs ran on 2 slots, slowest {worst:?}");
    assert!(worst < Duration::from_secs(1), "a cheap request took {worst:?}");
    for run in runs {
        let (status, v, took) = run.join().unwrap();
        assert_eq!(status, 422, "{v}");
        let error = v["error"].as_str().unwrap();
        assert!(error.contains("time budget of 1.5 s"), "{error}");
        assert_eq!(v["budget_s"], 1.5);
        assert!(v["diagnostics"].as_str().unwrap().contains("stopped here"), "{v}");
        // Two rounds of 1.5 s on two slots, and some slack for a busy machine.
        assert!(took < Duration::from_secs(8), "{took:?}");
    }
}

/// A client that closes its connection while its program runs cannot be
/// told from one that only closed its sending side and waits for the answer
/// (both send a FIN), so the program runs on within its budget, as it would
/// for a client that stays: leaving costs the server no more than staying.
#[test]
fn a_client_that_leaves_costs_at_most_the_run_budget() {
    let _serial = one_at_a_time();
    let limits = Limits { run_budget: Duration::from_secs(2), heavy_concurrency: 1, ..Limits::default() };
    let server = start(limits);
    let addr = server.local_addr();
    let mut gone = Client::connect(addr).unwrap();
    let body = json!({"program": WEDGE, "dt": 0.5}).to_string();
    let req = format!("POST /api/run HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: {}\r\n\r\n{body}", body.len());
    gone.s.write_all(req.as_bytes()).unwrap();
    std::thread::sleep(Duration::from_millis(300));
    drop(gone);
    // The one slot is free again once the budget has stopped the wedging program.
    let t0 = Instant::now();
    let mut c = Client::connect(addr).unwrap();
    let (status, _, body) = c.request("POST", "/api/run", r#"{"program": "WAIT 1\n"}"#).unwrap();
    assert_eq!(status, 200, "{}", String::from_utf8_lossy(&body));
    assert!(t0.elapsed() < Duration::from_millis(4000), "answered after {:?}", t0.elapsed());
}

#[test]
fn stopping_the_server_stops_running_programs() {
    let _serial = one_at_a_time();
    let limits = Limits { run_budget: Duration::from_secs(60), ..Limits::default() };
    let server = start(limits);
    let addr = server.local_addr();
    let run = std::thread::spawn(move || {
        let mut c = Client::connect(addr).unwrap();
        let body = json!({"program": WEDGE, "dt": 0.5}).to_string();
        c.request("POST", "/api/run", &body)
    });
    std::thread::sleep(Duration::from_millis(300));
    let t0 = Instant::now();
    server.stop();
    let took = t0.elapsed();
    let (status, headers, body) = run.join().unwrap().expect("an answer before the connection closes");
    assert_eq!(status, 503, "{headers}");
    let v: Value = serde_json::from_slice(&body).unwrap();
    assert!(v["error"].as_str().unwrap().contains("shutting down"), "{v}");
    assert!(took < Duration::from_secs(2), "stopped after {took:?}");
}
