//! The controller simulator driven with raw bytes over loopback TCP and a
//! pseudo-terminal.

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use kinema::Robot;
use kinema_scorbot::encoder::Constants;
use kinema_scorbot::sim::{serve_tcp, Fault, SimConfig};
use kinema_scorbot::Result;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A simulator serving on a loopback port; stops when dropped.
struct Server {
    addr: std::net::SocketAddr,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<Result<()>>>,
}

impl Server {
    fn start(config: SimConfig) -> Server {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = listener.local_addr().unwrap();
        let stop = Arc::new(AtomicBool::new(false));
        let s = stop.clone();
        let thread = Some(std::thread::spawn(move || serve_tcp(listener, config, s)));
        Server { addr, stop, thread }
    }

    fn connect(&self) -> Conn {
        let s = TcpStream::connect(self.addr).unwrap();
        s.set_nodelay(true).unwrap();
        Conn { s }
    }

    fn finish(mut self) -> Result<()> {
        self.stop.store(true, Ordering::Relaxed);
        self.thread.take().unwrap().join().unwrap()
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn scaled(scale: f64) -> SimConfig {
    SimConfig { time_scale: scale, ..SimConfig::default() }
}

/// Raw bytes over one connection.
struct Conn {
    s: TcpStream,
}

/// What a read loop saw.
#[derive(Debug, PartialEq)]
enum Got {
    /// Everything up to and including the awaited end.
    Text(Vec<u8>),
    /// The connection closed; what came before.
    Closed(Vec<u8>),
    /// Timed out; what came before.
    Timeout(Vec<u8>),
}

impl Conn {
    fn send(&mut self, bytes: &[u8]) {
        self.s.write_all(bytes).unwrap();
    }

    /// Reads until the bytes end with `end`.
    fn read_until(&mut self, end: &[u8], within: Duration) -> Got {
        let deadline = Instant::now() + within;
        let mut got = Vec::new();
        let mut buf = [0u8; 512];
        loop {
            if got.ends_with(end) {
                return Got::Text(got);
            }
            let now = Instant::now();
            if now >= deadline {
                return Got::Timeout(got);
            }
            self.s.set_read_timeout(Some(deadline - now)).unwrap();
            match self.s.read(&mut buf) {
                Ok(0) => return Got::Closed(got),
                Ok(n) => got.extend_from_slice(&buf[..n]),
                Err(e) if matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => {}
                Err(_) => return Got::Closed(got),
            }
        }
    }

    /// Sends a line and returns everything up to the prompt, as text.
    fn cmd(&mut self, line: &str) -> String {
        self.send(format!("{line}\r").as_bytes());
        match self.read_until(b">", Duration::from_secs(5)) {
            Got::Text(t) => String::from_utf8_lossy(&t).into_owned(),
            other => panic!("`{line}`: {other:?}"),
        }
    }

    fn ok(&mut self, line: &str) {
        assert_eq!(self.cmd(line), format!("{line}\r\nDone.\r\n>"));
    }
}

fn homed(server: &Server) -> Conn {
    let mut c = server.connect();
    assert_eq!(c.cmd("HOME"), "HOME\r\nHOMING...\r\nDone.\r\n>");
    c
}

#[test]
fn framing_home_and_moved_timing_over_tcp() {
    let server = Server::start(scaled(0.02));
    let mut c = server.connect();
    assert_eq!(c.cmd("con"), "con\r\nDone.\r\n>");
    assert_eq!(c.cmd(""), "\r\n>");
    assert_eq!(c.cmd("FLY"), "FLY\r\n*** UNKNOWN COMMAND\r\n>");
    c.ok("DEFP P1");
    c.ok("SETPV P1 1 14188"); // 100° on motor 1: 2.22 s at speed 50 → 44 ms
    assert_eq!(c.cmd("MOVED P1"), "MOVED P1\r\n*** HOME NOT DONE\r\n>");
    let t = Instant::now();
    assert_eq!(c.cmd("home"), "home\r\nHOMING...\r\nDone.\r\n>");
    let e = t.elapsed();
    assert!(e >= Duration::from_millis(95) && e < Duration::from_millis(400), "HOME took {e:?}, want 100 ms");
    let t = Instant::now();
    c.ok("MOVED P1");
    let e = t.elapsed();
    assert!(e >= Duration::from_millis(40) && e < Duration::from_millis(300), "MOVED took {e:?}, want 44 ms");
    let t = Instant::now();
    c.ok("MOVED P1 250"); // already there, but the time is given: 2.5 s → 50 ms
    let e = t.elapsed();
    assert!(e >= Duration::from_millis(45) && e < Duration::from_millis(300), "MOVED took {e:?}, want 50 ms");
    c.ok("HERE H");
    assert_eq!(
        c.cmd("LISTPV H"),
        format!("LISTPV H\r\nPosition H\r\n 1:14188 2:0 3:0 4:0 5:0\r\n {} Z:5043 P:-635 R:0\r\n>", listpv_xy(14188))
    );
    drop(c);
    server.finish().unwrap();
}

/// The `k:value` pairs of a reply.
fn values(reply: &str) -> std::collections::HashMap<String, i64> {
    reply
        .split_whitespace()
        .filter_map(|t| t.split_once(':'))
        .filter_map(|(k, v)| Some((k.to_string(), v.parse().ok()?)))
        .collect()
}

/// X and Y \[0.1 mm\] of the home configuration turned by `counts` on motor 1.
fn listpv_xy(counts: i64) -> String {
    let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
    let k = Constants::named("factory").unwrap();
    let q = k.angles(&[counts as f64, 0.0, 0.0, 0.0, 0.0]).unwrap();
    let p = robot.fk(&q).unwrap().world_from_tool.pos;
    format!("X:{} Y:{}", (p.x * 1e4).round() as i64, (p.y * 1e4).round() as i64)
}

#[test]
fn positions_vectors_and_paged_listing_over_tcp() {
    let server = Server::start(scaled(0.01));
    let mut c = homed(&server);
    c.ok("DEFP A");
    c.ok("SETPV A 2 -2000");
    c.ok("SETPV A 3 1500");
    let r = c.cmd("LISTPV A");
    assert!(r.contains("\r\n 1:0 2:-2000 3:1500 4:0 5:0\r\n X:"), "{r}");
    // SETPVC then MOVED: the controller solves it and goes there.
    c.ok("HERE C");
    c.ok("SETPVC C X 3500");
    c.ok("SETPVC C Z 2000");
    c.ok("MOVED C");
    c.ok("HERE D");
    let d = values(&c.cmd("LISTPV D"));
    for (k, want) in [("X", 3500), ("Y", 0), ("Z", 2000), ("P", -635), ("R", 0)] {
        assert!((d[k] - want).abs() <= 2, "{k}: {d:?}");
    }
    // DIMP + MOVES through three points.
    c.ok("DIMP PATH[3]");
    c.ok("SETPV PATH[1] 1 1000");
    c.ok("SETPV PATH[2] 1 2000");
    c.ok("SETPV PATH[3] 1 3000");
    let t = Instant::now();
    c.ok("MOVES PATH 1 3 200"); // 2 s → 20 ms
    assert!(t.elapsed() >= Duration::from_millis(18));
    c.ok("HERE E");
    assert!(c.cmd("LISTPV E").contains(" 1:3000 2:0 3:0 4:0 5:0"));
    // 25 positions in all: a page of 20, `Type <cr> to continue`, the rest.
    for i in 0..17 {
        c.ok(&format!("DEFP Q{i:02}"));
    }
    c.send(b"LISTP\r");
    let Got::Text(first) = c.read_until(b"Type <cr> to continue\r\n", Duration::from_secs(2)) else { panic!() };
    let first = String::from_utf8(first).unwrap();
    let lines: Vec<&str> = first.split("\r\n").collect();
    assert_eq!(lines.len(), 23, "echo, 20 names, pager, end: {first:?}");
    assert_eq!(&lines[1..5], ["A", "C", "D", "E"]);
    // Nothing more until the host sends `\r`.
    assert_eq!(c.read_until(b">", Duration::from_millis(100)), Got::Timeout(Vec::new()));
    c.send(b"\r");
    let Got::Text(rest) = c.read_until(b">", Duration::from_secs(2)) else { panic!() };
    assert_eq!(String::from_utf8(rest).unwrap(), "Q16\r\nPATH[1]\r\nPATH[2]\r\nPATH[3]\r\n>");
    drop(c);
    server.finish().unwrap();
}

#[test]
fn refusals_name_what_is_wrong() {
    let server = Server::start(scaled(0.01));
    let mut c = server.connect();
    c.ok("DEFP P");
    assert_eq!(c.cmd("MOVE P"), "MOVE P\r\n*** HOME NOT DONE\r\n>");
    assert_eq!(c.cmd("HOME"), "HOME\r\nHOMING...\r\nDone.\r\n>");
    assert_eq!(c.cmd("MOVE P"), "MOVE P\r\n*** POSITION P HAS NO COORDINATES\r\n>");
    assert_eq!(c.cmd("MOVE Q"), "MOVE Q\r\n*** POSITION Q NOT DEFINED\r\n>");
    // Both wrist motors +600°: a roll θ5 of 600°, beyond ±570°.
    c.ok("SETPV P 4 16740");
    c.ok("SETPV P 5 16740");
    let r = c.cmd("MOVED P");
    assert!(r.starts_with("MOVED P\r\n*** OUT OF RANGE: axis 5 (joint angle 600.0 deg"), "{r}");
    // The elbow motor sets the forearm's absolute angle (eq. 24): alone it
    // moves θ3 and, the gripper's pitch being kept, θ4 — past its limit first.
    c.ok("SETPV P 4 0");
    c.ok("SETPV P 5 0");
    c.ok("SETPV P 3 -9000");
    assert!(c.cmd("MOVED P").contains("*** OUT OF RANGE: axis 4 "));
    c.ok("SETPV P 3 0");
    c.ok("COFF");
    assert_eq!(c.cmd("MOVED P"), "MOVED P\r\n*** CONTROL DISABLED\r\n>");
    assert_eq!(c.cmd("HOME"), "HOME\r\n*** CONTROL DISABLED\r\n>");
    c.ok("CON");
    c.ok("MOVED P");
    drop(c);
    server.finish().unwrap();
}

#[test]
fn abort_during_moved_and_state_across_connections() {
    let server = Server::start(scaled(0.05));
    let mut c = homed(&server);
    c.ok("DEFP FAR");
    c.ok("SETPV FAR 1 14188"); // 2.22 s → 111 ms
    c.send(b"MOVED FAR\r");
    std::thread::sleep(Duration::from_millis(40));
    c.send(b"A\r");
    let Got::Text(r) = c.read_until(b"A\r\nDone.\r\n>", Duration::from_secs(2)) else { panic!() };
    assert_eq!(String::from_utf8(r).unwrap(), "MOVED FAR\r\n*** MOTION ABORTED\r\n>A\r\nDone.\r\n>");
    c.ok("HERE STOP");
    let r = c.cmd("LISTPV STOP");
    let c1 = values(&r)["1"];
    assert!(c1 > 2000 && c1 < 12000, "stopped part way: {c1}");
    // A new connection finds the same controller.
    drop(c);
    let mut c = server.connect();
    let again = c.cmd("LISTPV STOP");
    assert_eq!(again, r);
    c.ok("MOVED FAR");
    drop(c);
    server.finish().unwrap();
}

#[test]
fn drop_garble_and_delay_faults_over_tcp() {
    let faults: Vec<Fault> =
        ["drop@SPEED", "garble@LISTPV", "delay=0.3@CON#2"].iter().map(|f| f.parse().unwrap()).collect();
    let server = Server::start(SimConfig { time_scale: 0.01, faults, ..SimConfig::default() });
    let mut c = server.connect();
    c.send(b"SPEED 10\r");
    assert_eq!(c.read_until(b">", Duration::from_millis(300)), Got::Timeout(Vec::new()));
    c.ok("SPEED 20");
    c.ok("HERE P");
    let r = c.cmd("LISTPV P");
    assert!(r.starts_with("LISTPV P\r\n") && r.ends_with("\r\n>"));
    assert!(!r.contains("Position") && !r.contains("***") && !r.contains("Done."), "{r:?}");
    assert!(c.cmd("LISTPV P").contains("Position P\r\n"));
    c.ok("CON");
    let t = Instant::now();
    c.ok("CON");
    assert!(t.elapsed() >= Duration::from_millis(290), "{:?}", t.elapsed());
    drop(c);
    server.finish().unwrap();
}

#[test]
fn disconnect_fault_closes_halfway_and_the_arm_stays_there() {
    let faults = vec!["disconnect@MOVED".parse().unwrap()];
    let server = Server::start(SimConfig { time_scale: 0.05, faults, ..SimConfig::default() });
    let mut c = homed(&server);
    c.ok("DEFP FAR");
    c.ok("SETPV FAR 1 14188"); // 111 ms; the link goes at 55 ms
    let t = Instant::now();
    c.send(b"MOVED FAR\r");
    let got = c.read_until(b">", Duration::from_secs(2));
    assert_eq!(got, Got::Closed(b"MOVED FAR\r\n".to_vec()));
    let e = t.elapsed();
    assert!(e >= Duration::from_millis(50) && e < Duration::from_millis(500), "{e:?}");
    let mut c = server.connect();
    c.ok("HERE H");
    let r = c.cmd("LISTPV H");
    assert!(r.contains(" 1:7094 2:0") || r.contains(" 1:7093 2:0") || r.contains(" 1:7095 2:0"), "{r}");
    drop(c);
    server.finish().unwrap();
}

#[test]
fn record_file_is_the_physical_arm_seen_by_the_camera() {
    let dir = std::env::temp_dir().join(format!("kinema-sim-it-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("camera.csv");
    let cfg = SimConfig { time_scale: 0.01, record: Some(path.clone()), noise: 0.0, seed: 5, ..SimConfig::default() };
    let truth = cfg.true_constants.clone();
    let server = Server::start(cfg);
    let mut c = homed(&server);
    c.ok("DEFP P");
    c.ok("SETPV P 1 -7094");
    c.ok("SETPV P 4 500");
    c.ok("MOVED P 150");
    drop(c);
    server.finish().unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("x,y,z"));
    let rows: Vec<[f64; 3]> = lines
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    assert_eq!(rows.len(), 501 + 151, "HOME 5 s + MOVED 1.5 s, every 10 ms");
    let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
    for (k, row) in rows[501..].iter().enumerate() {
        let s = k as f64 / 150.0;
        let q = truth.angles(&[-7094.0 * s, 0.0, 0.0, 500.0 * s, 0.0]).unwrap();
        let p = robot.fk(&q).unwrap().world_from_tool.pos;
        assert!((row[0] - p.x).abs() < 1e-12 && (row[1] - p.y).abs() < 1e-12 && (row[2] - p.z).abs() < 1e-12);
    }
    // Not the controller's own model: the factory constants put the tool elsewhere.
    let factory = Constants::named("factory").unwrap();
    let p = robot.fk(&factory.angles(&[-7094.0, 0.0, 0.0, 500.0, 0.0]).unwrap()).unwrap().world_from_tool.pos;
    let last = rows[rows.len() - 1];
    assert!(((last[0] - p.x).powi(2) + (last[1] - p.y).powi(2) + (last[2] - p.z).powi(2)).sqrt() > 1e-3);
    assert!(std::fs::read_dir(&dir).unwrap().count() == 1, "no temporary file left");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn random_bytes_never_break_the_server() {
    let server = Server::start(scaled(0.001));
    let mut c = server.connect();
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let words = ["HOME", "MOVE", "MOVED", "SETPV", "LISTP", "LISTPV", "DIMP", "A", "P", "V[3]", "1", "-99", "X"];
    for _ in 0..3000 {
        let mut line = Vec::new();
        if rng.random_bool(0.2) {
            line.extend((0..rng.random_range(0..600)).map(|_| rng.random::<u8>()));
        } else {
            for _ in 0..rng.random_range(1..5) {
                line.extend_from_slice(words[rng.random_range(0..words.len())].as_bytes());
                line.push(b' ');
            }
        }
        line.push(b'\r');
        c.send(&line);
    }
    // Drain, then the controller still answers.
    std::thread::sleep(Duration::from_millis(300));
    let _ = c.read_until(b"\x00never", Duration::from_millis(300));
    for _ in 0..200 {
        c.send(b"\r");
        if let Got::Text(_) = c.read_until(b">", Duration::from_millis(50)) {
            break;
        }
    }
    let _ = c.read_until(b"\x00never", Duration::from_millis(200));
    assert_eq!(c.cmd("CON"), "CON\r\nDone.\r\n>");
    drop(c);
    server.finish().unwrap();
}

#[test]
fn serve_tcp_returns_soon_after_stop() {
    let server = Server::start(scaled(1.0));
    let c = server.connect();
    std::thread::sleep(Duration::from_millis(30));
    let t = Instant::now();
    server.finish().unwrap();
    assert!(t.elapsed() < Duration::from_millis(200), "{:?}", t.elapsed());
    drop(c);
}

#[test]
fn the_acl_client_talks_to_the_simulator() {
    let server = Server::start(scaled(0.01));
    let mut arm = kinema_scorbot::acl::Client::connect_tcp(&server.addr.to_string(), Duration::from_secs(2)).unwrap();
    arm.home().unwrap();
    arm.defp("P1").unwrap();
    arm.set_joint_position("P1", [1000, -2000, 1500, 300, -300]).unwrap();
    arm.move_d("P1", None).unwrap();
    let r = arm.listpv("P1").unwrap();
    assert_eq!(r.counts, [1000, -2000, 1500, 300, -300]);
    assert!(r.cartesian.is_some());
    assert!(arm.list_positions().unwrap().contains(&"P1".to_string()));
    drop(arm);
    server.finish().unwrap();
}

#[cfg(unix)]
mod pty {
    use super::*;
    use kinema_scorbot::sim::PtySim;

    fn open_sim(config: SimConfig) -> Option<PtySim> {
        match PtySim::open(config) {
            Ok(s) => Some(s),
            Err(e) => {
                println!("skipped: no pseudo-terminal available ({e})");
                None
            }
        }
    }

    fn read_until(port: &mut dyn Read, end: &[u8], within: Duration) -> Vec<u8> {
        let deadline = Instant::now() + within;
        let mut got = Vec::new();
        let mut buf = [0u8; 256];
        while !got.ends_with(end) && Instant::now() < deadline {
            match port.read(&mut buf) {
                Ok(n) => got.extend_from_slice(&buf[..n]),
                Err(e) if e.kind() == std::io::ErrorKind::TimedOut || e.kind() == std::io::ErrorKind::WouldBlock => {}
                Err(e) => panic!("{e}"),
            }
        }
        got
    }

    #[test]
    fn a_serial_client_talks_to_the_pty_in_raw_mode() {
        let Some(sim) = open_sim(scaled(0.01)) else { return };
        let path = sim.path();
        let stop = Arc::new(AtomicBool::new(false));
        let s = stop.clone();
        let run = std::thread::spawn(move || sim.run(s));
        // A plain file open (no termios set by any client yet): the simulator
        // put the terminal in raw mode, so the bytes arrive untouched.
        {
            let mut f = std::fs::OpenOptions::new().read(true).write(true).open(&path).unwrap();
            f.write_all(b"DEFP P\r").unwrap();
            let (tx, rx) = std::sync::mpsc::channel();
            let mut r = f.try_clone().unwrap();
            std::thread::spawn(move || {
                let got = read_until(&mut r, b">", Duration::from_secs(2));
                let _ = tx.send(got);
            });
            let got = rx.recv_timeout(Duration::from_secs(3)).expect("no reply on the plain file");
            let text = String::from_utf8(got).unwrap();
            assert_eq!(text, "DEFP P\r\nDone.\r\n>");
        }
        {
            let mut port = serialport::new(&path, 9600).timeout(Duration::from_millis(50)).open().unwrap();
            port.write_all(b"con\r").unwrap();
            // Exactly the controller's bytes: no echo by the terminal, no CR/LF translation.
            assert_eq!(read_until(&mut port, b">", Duration::from_secs(2)), b"con\r\nDone.\r\n>");
            port.write_all(b"HOME\r").unwrap();
            assert_eq!(read_until(&mut port, b">", Duration::from_secs(2)), b"HOME\r\nHOMING...\r\nDone.\r\n>");
        }
        // Closed and reopened: the simulator is still there, with its state.
        {
            let mut port = serialport::new(&path, 9600).timeout(Duration::from_millis(50)).open().unwrap();
            port.write_all(b"SETPV P 1 100\r").unwrap();
            assert_eq!(read_until(&mut port, b">", Duration::from_secs(2)), b"SETPV P 1 100\r\nDone.\r\n>");
            port.write_all(b"MOVED P\r").unwrap();
            assert_eq!(read_until(&mut port, b">", Duration::from_secs(2)), b"MOVED P\r\nDone.\r\n>");
        }
        stop.store(true, Ordering::Relaxed);
        run.join().unwrap().unwrap();
    }

    #[test]
    fn disconnect_on_a_pty_closes_it_and_run_returns() {
        let faults = vec!["disconnect@CLOSE".parse().unwrap()];
        let Some(sim) = open_sim(SimConfig { time_scale: 0.4, faults, ..SimConfig::default() }) else { return };
        let path = sim.path();
        let stop = Arc::new(AtomicBool::new(false));
        let run = std::thread::spawn(move || sim.run(stop));
        let mut port = serialport::new(&path, 9600).timeout(Duration::from_millis(10)).open().unwrap();
        let t = Instant::now();
        port.write_all(b"CLOSE\r").unwrap();
        // CLOSE takes 0.2 s here: the pty closes at 0.1 s.
        let mut got = Vec::new();
        let mut buf = [0u8; 64];
        let deadline = Instant::now() + Duration::from_secs(1);
        let mut hung_up = false;
        while Instant::now() < deadline {
            match port.read(&mut buf) {
                Ok(0) => {
                    hung_up = true;
                    break;
                }
                Ok(n) => got.extend_from_slice(&buf[..n]),
                Err(e) if e.kind() == std::io::ErrorKind::TimedOut => {}
                Err(_) => {
                    hung_up = true;
                    break;
                }
            }
        }
        assert_eq!(got, b"CLOSE\r\n");
        assert!(hung_up, "the client sees the line drop");
        run.join().unwrap().unwrap();
        let e = t.elapsed();
        assert!(e >= Duration::from_millis(90) && e < Duration::from_secs(1), "{e:?}");
    }
}
