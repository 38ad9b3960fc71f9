//! The HTTP side: a small HTTP/1.1 server on [`std::net::TcpListener`], with
//! the request head parsed by `httparse`, worker threads, size limits,
//! timeouts and the last-resort panic guard around [`App::handle`].
//!
//! How it works, and what it refuses:
//!
//! * One acceptor thread takes connections and hands them, through a bounded
//!   queue, to a fixed pool of four worker threads; a worker serves one
//!   connection at a time. Stopping ([`Running::stop`] or dropping
//!   [`Running`]) sets a flag, wakes the acceptor with one connection of its
//!   own, and joins the threads; a worker notices the flag within a fraction
//!   of a second (a request being handled is finished first).
//! * The request head (request line and header fields) is read into a buffer
//!   of at most 16 KiB and parsed with `httparse`: over 16 KiB or more than 64
//!   header fields → 431, not HTTP/1.x → 400.
//! * A body is read only by `Content-Length`, into a buffer of at most
//!   [`MAX_BODY`] bytes. `Transfer-Encoding` (chunked bodies) → 411; an
//!   invalid or conflicting `Content-Length` → 400; a length over
//!   [`MAX_BODY`] → 413 from the header alone, without reading (or
//!   allocating for) the body. `Expect: 100-continue` is answered with
//!   `100 Continue` before the body is read. Every refusal is a JSON error,
//!   sent with `Connection: close`, and the connection is closed.
//! * Timeouts: once its first byte has arrived, a request's head and body
//!   must arrive within 10 s (a total, so a client trickling bytes cannot hold
//!   a worker either); an answer must be taken within 10 s (plus 1 s per MiB).
//!   A connection on which no request has begun is closed after 10 s, or as
//!   soon as another connection is waiting for a worker (after 1 s of grace
//!   on a new connection; at once on a kept-alive one, between requests): so
//!   idle and speculative browser connections cannot starve the pool.
//! * Keep-alive: an HTTP/1.1 connection serves requests one after the other
//!   (pipelined ones too) until the client sends `Connection: close`; an
//!   HTTP/1.0 one only with `Connection: keep-alive`. The last answer says
//!   `Connection: close`. Before closing, the server stops sending, then reads
//!   and discards what the client still sends (at most 1 MiB or 1 s, into a
//!   small fixed buffer), so the client receives the answer rather than a
//!   reset.
//! * A `HEAD` request is answered like `GET` (by [`App::handle`]) without
//!   the body. Nothing in this module panics on input, and [`App::handle`]
//!   runs inside `catch_unwind` (a panic there is a 500 JSON answer); a
//!   read or write error, a timeout or an early end of input just ends the
//!   connection.

use std::fmt::Write as _;
use std::io::{self, Read, Write};
use std::net::{IpAddr, Ipv4Addr, Ipv6Addr, Shutdown, SocketAddr, TcpListener, TcpStream, ToSocketAddrs};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, SyncSender};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use kinema::Robot;
use serde_json::json;

use crate::api::{App, Reply, MAX_BODY};
use crate::error::{Error, Result};

/// Connections served at once (a slow IK or program does not block the page).
const WORKERS: usize = 4;
/// Accepted connections waiting for a worker (the kernel's backlog holds more).
const QUEUE: usize = 64;
/// Largest request head (request line and header fields) \[bytes\].
const MAX_HEAD: usize = 16 * 1024;
/// Most header fields in a request.
const MAX_HEADERS: usize = 64;
/// Time for a request's head and body to arrive.
const READ_TIMEOUT: Duration = Duration::from_secs(10);
/// Time for an answer to be taken (plus 1 s per MiB of body).
const WRITE_TIMEOUT: Duration = Duration::from_secs(10);
/// How long a new connection may stay silent while others wait for a worker.
const FRESH_GRACE: Duration = Duration::from_secs(1);
/// Longest single wait, after which the stop flag and the queue are looked at.
const POLL: Duration = Duration::from_millis(50);
/// Before closing: how long, and how much, what the client still sends is discarded.
const LINGER_TIME: Duration = Duration::from_secs(1);
const LINGER_BYTES: usize = MAX_BODY;

/// A bound, not yet running server.
pub struct Server {
    listener: TcpListener,
    app: Arc<App>,
    addr: SocketAddr,
    read_timeout: Duration,
}

impl Server {
    /// Listens on `addr` (port 0 picks a free port) and prepares the robots:
    /// the built-in ones and `default_robot` (shown first by the page; it may
    /// come from a file). Nothing is served until [`Server::run`] or
    /// [`Server::spawn`].
    pub fn bind(addr: impl ToSocketAddrs, default_robot: Option<Robot>) -> Result<Server> {
        let shown = |e: &dyn std::fmt::Display| e.to_string();
        let addrs: Vec<SocketAddr> = addr
            .to_socket_addrs()
            .map_err(|e| Error::Bind { addr: "the given address".into(), message: shown(&e) })?
            .collect();
        let listener = TcpListener::bind(&addrs[..]).map_err(|e| Error::Bind {
            addr: addrs.iter().map(ToString::to_string).collect::<Vec<_>>().join(", "),
            message: shown(&e),
        })?;
        let local =
            listener.local_addr().map_err(|e| Error::Bind { addr: format!("{addrs:?}"), message: shown(&e) })?;
        Ok(Server { listener, app: Arc::new(App::new(default_robot)?), addr: local, read_timeout: READ_TIMEOUT })
    }

    /// Sets the time a request's head and body have to arrive (10 s by
    /// default); for tests.
    #[doc(hidden)]
    pub fn with_read_timeout(mut self, timeout: Duration) -> Server {
        self.read_timeout = timeout.clamp(Duration::from_millis(1), Duration::from_secs(3600));
        self
    }

    /// The address actually bound.
    pub fn local_addr(&self) -> SocketAddr {
        self.addr
    }

    /// `http://HOST:PORT/`, the page's address.
    pub fn url(&self) -> String {
        format!("http://{}/", self.addr)
    }

    /// The request handler.
    pub fn app(&self) -> &App {
        &self.app
    }

    /// Serves requests (accepting on this thread, answering on a few
    /// workers) until the process ends.
    pub fn run(self) {
        let shared = self.shared();
        let (tx, rx) = mpsc::sync_channel(QUEUE);
        let workers = start_workers(&shared, rx);
        accept(&self.listener, &shared, tx);
        for w in workers {
            let _ = w.join();
        }
    }

    /// Serves requests on background threads; the server stops when the
    /// returned [`Running`] is stopped or dropped.
    pub fn spawn(self) -> Running {
        let shared = self.shared();
        let (tx, rx) = mpsc::sync_channel(QUEUE);
        let workers = start_workers(&shared, rx);
        let (url, addr, listener) = (self.url(), self.addr, self.listener);
        let s = Arc::clone(&shared);
        let acceptor = std::thread::Builder::new()
            .name("kinema-serve-accept".into())
            .spawn(move || accept(&listener, &s, tx))
            .ok();
        Running { url, addr, shared, workers, acceptor }
    }

    fn shared(&self) -> Arc<Shared> {
        Arc::new(Shared {
            app: Arc::clone(&self.app),
            stop: AtomicBool::new(false),
            queued: AtomicUsize::new(0),
            read_timeout: self.read_timeout,
        })
    }
}

/// What the acceptor and the workers share.
struct Shared {
    app: Arc<App>,
    /// Set when the server stops.
    stop: AtomicBool,
    /// Accepted connections not yet taken by a worker.
    queued: AtomicUsize,
    read_timeout: Duration,
}

impl Shared {
    fn stopping(&self) -> bool {
        self.stop.load(Ordering::SeqCst)
    }
}

/// A server running on background threads.
pub struct Running {
    url: String,
    addr: SocketAddr,
    shared: Arc<Shared>,
    workers: Vec<JoinHandle<()>>,
    acceptor: Option<JoinHandle<()>>,
}

impl Running {
    /// `http://HOST:PORT/`.
    pub fn url(&self) -> &str {
        &self.url
    }

    /// The address bound.
    pub fn local_addr(&self) -> SocketAddr {
        self.addr
    }

    /// Stops accepting, lets requests in progress finish, closes the
    /// connections and the listener, and waits for the threads.
    pub fn stop(mut self) {
        self.shutdown();
    }

    fn shutdown(&mut self) {
        if self.shared.stop.swap(true, Ordering::SeqCst) {
            return;
        }
        let woken = wake(self.addr);
        for w in self.workers.drain(..) {
            let _ = w.join();
        }
        if let Some(acceptor) = self.acceptor.take() {
            // Without the wake-up connection the acceptor would wait for the
            // next client; it is then left to end by itself.
            if woken {
                let _ = acceptor.join();
            }
        }
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        self.shutdown();
    }
}

/// Connects once to the listener so that a blocked `accept` returns.
fn wake(addr: SocketAddr) -> bool {
    let ip = match addr.ip() {
        IpAddr::V4(ip) if ip.is_unspecified() => IpAddr::V4(Ipv4Addr::LOCALHOST),
        IpAddr::V6(ip) if ip.is_unspecified() => IpAddr::V6(Ipv6Addr::LOCALHOST),
        ip => ip,
    };
    TcpStream::connect_timeout(&SocketAddr::new(ip, addr.port()), Duration::from_secs(1)).is_ok()
}

fn start_workers(shared: &Arc<Shared>, rx: Receiver<TcpStream>) -> Vec<JoinHandle<()>> {
    let rx = Arc::new(Mutex::new(rx));
    (0..WORKERS)
        .filter_map(|i| {
            let (shared, rx) = (Arc::clone(shared), Arc::clone(&rx));
            std::thread::Builder::new().name(format!("kinema-serve-{i}")).spawn(move || work(&shared, &rx)).ok()
        })
        .collect()
}

/// The acceptor: hands each connection to the workers, until the server stops.
fn accept(listener: &TcpListener, shared: &Shared, tx: SyncSender<TcpStream>) {
    loop {
        let accepted = listener.accept();
        if shared.stopping() {
            break;
        }
        match accepted {
            Ok((stream, _)) => {
                shared.queued.fetch_add(1, Ordering::SeqCst);
                if tx.send(stream).is_err() {
                    break;
                }
            }
            // An accept error (e.g. out of file descriptors): wait a little, go on.
            Err(_) => std::thread::sleep(Duration::from_millis(20)),
        }
    }
}

/// A worker: serves one connection after the other, until the server stops.
fn work(shared: &Shared, rx: &Mutex<Receiver<TcpStream>>) {
    while !shared.stopping() {
        let next = rx.lock().unwrap_or_else(PoisonError::into_inner).recv_timeout(POLL * 2);
        match next {
            Ok(stream) => {
                shared.queued.fetch_sub(1, Ordering::SeqCst);
                // Nothing below should panic; if it did, the worker lives on.
                let _ = catch_unwind(AssertUnwindSafe(|| serve(stream, shared)));
            }
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => break,
        }
    }
}

/// Serves the requests of one connection through [`App::handle`] (inside
/// `catch_unwind`), until it is closed, refused, idle or the server stops.
fn serve(stream: TcpStream, shared: &Shared) {
    let _ = stream.set_nodelay(true);
    let mut conn = Conn { stream, shared, buf: Vec::new() };
    let mut fresh = true;
    loop {
        let head = match conn.read_head(fresh) {
            Next::Request(head) => head,
            Next::Refuse(reply) => {
                if conn.answer(&reply, true, Some("close")) {
                    conn.linger();
                }
                return;
            }
            Next::Close => return,
        };
        fresh = false;
        if head.expect_continue
            && head.http11
            && conn.buf.len() < head.length
            && !conn.send(b"HTTP/1.1 100 Continue\r\n\r\n", Instant::now() + WRITE_TIMEOUT)
        {
            return;
        }
        let Some(body) = conn.read_body(head.length, head.deadline) else { return };
        let reply = guarded(|| shared.app.handle(&head.method, &head.path, &body));
        drop(body);
        let keep = head.keep_alive && !shared.stopping();
        let connection = match (keep, head.http11) {
            (false, _) => Some("close"),
            (true, false) => Some("keep-alive"),
            (true, true) => None,
        };
        if !conn.answer(&reply, head.method != "HEAD", connection) {
            return;
        }
        if !keep {
            conn.linger();
            return;
        }
    }
}

/// A parsed request head.
struct Head {
    method: String,
    /// The request target as sent, query included.
    path: String,
    http11: bool,
    /// The body's length (at most [`MAX_BODY`]).
    length: usize,
    expect_continue: bool,
    /// Whether the client lets the connection stay open after the answer.
    keep_alive: bool,
    /// When the rest of the request must have arrived.
    deadline: Instant,
}

/// What comes next on a connection.
enum Next {
    Request(Head),
    /// A request that is answered with this error, then the connection closed.
    Refuse(Reply),
    /// Closed by the client, timed out, or the server stops: close.
    Close,
}

/// How long a read may wait.
#[derive(Clone, Copy)]
enum Wait {
    /// For the first byte of a request: up to the read timeout from `since`,
    /// or, once `grace` has passed, until another connection waits for a worker.
    Idle { since: Instant, grace: Duration },
    /// Within a request.
    Until(Instant),
}

/// One connection: the socket and what was received but not used yet.
struct Conn<'a> {
    stream: TcpStream,
    shared: &'a Shared,
    buf: Vec<u8>,
}

impl Conn<'_> {
    /// Reads up to `max` (> 0) more bytes into `buf`; false at the end of
    /// input, on an error, when the wait is over or the server stops.
    fn fill(&mut self, max: usize, wait: Wait) -> bool {
        let mut chunk = [0u8; 8192];
        let max = max.clamp(1, chunk.len());
        loop {
            if self.shared.stopping() {
                return false;
            }
            let now = Instant::now();
            let slice = match wait {
                Wait::Idle { since, grace } => {
                    let waited = now.saturating_duration_since(since);
                    let others = self.shared.queued.load(Ordering::SeqCst) > 0;
                    if waited >= self.shared.read_timeout || (others && waited >= grace) {
                        return false;
                    }
                    (self.shared.read_timeout - waited).min(POLL)
                }
                Wait::Until(deadline) => {
                    let left = deadline.saturating_duration_since(now);
                    if left.is_zero() {
                        return false;
                    }
                    left.min(POLL * 4)
                }
            };
            if self.stream.set_read_timeout(Some(slice.max(Duration::from_millis(1)))).is_err() {
                return false;
            }
            match self.stream.read(&mut chunk[..max]) {
                Ok(0) => return false,
                Ok(n) => {
                    self.buf.extend_from_slice(chunk.get(..n).unwrap_or_default());
                    return true;
                }
                Err(e) if waiting(&e) => {}
                Err(_) => return false,
            }
        }
    }

    /// Reads and parses the next request head (and refuses a body it will not read).
    fn read_head(&mut self, fresh: bool) -> Next {
        let since = Instant::now();
        let mut deadline = None;
        loop {
            if self.buf.is_empty() {
                let grace = if fresh { FRESH_GRACE } else { Duration::ZERO };
                if !self.fill(MAX_HEAD, Wait::Idle { since, grace }) {
                    return Next::Close;
                }
                continue;
            }
            let deadline = *deadline.get_or_insert_with(|| Instant::now() + self.shared.read_timeout);
            match parse_head(&self.buf, deadline) {
                Parsed::Complete(n, head) => {
                    self.buf.drain(..n.min(self.buf.len()));
                    return Next::Request(head);
                }
                Parsed::Refuse(reply) => return Next::Refuse(reply),
                Parsed::Partial => {}
            }
            if self.buf.len() >= MAX_HEAD {
                return Next::Refuse(refusal(
                    431,
                    format!("the request head (request line and header fields) is over {MAX_HEAD} bytes"),
                ));
            }
            if !self.fill(MAX_HEAD - self.buf.len(), Wait::Until(deadline)) {
                return Next::Close;
            }
        }
    }

    /// The next `length` (≤ [`MAX_BODY`]) bytes; `None` if they do not come
    /// by `deadline`.
    fn read_body(&mut self, length: usize, deadline: Instant) -> Option<Vec<u8>> {
        self.buf.reserve(length.saturating_sub(self.buf.len()));
        while self.buf.len() < length {
            if !self.fill(length - self.buf.len(), Wait::Until(deadline)) {
                return None;
            }
        }
        let rest = self.buf.split_off(length);
        Some(std::mem::replace(&mut self.buf, rest))
    }

    /// Writes `reply` (without its body for `HEAD`), with a `Connection`
    /// header if given; false if it cannot be sent.
    fn answer(&mut self, reply: &Reply, with_body: bool, connection: Option<&str>) -> bool {
        let status = if (100..=999).contains(&reply.status) { reply.status } else { 500 };
        let mut head = format!(
            "HTTP/1.1 {status} {}\r\nContent-Type: {}\r\nContent-Length: {}\r\nX-Content-Type-Options: nosniff\r\n",
            reason(status),
            clean(reply.content_type),
            reply.body.len()
        );
        for (name, value) in &reply.headers {
            if header_allowed(name, value) {
                let _ = write!(head, "{name}: {value}\r\n");
            }
        }
        if let Some(c) = connection {
            let _ = write!(head, "Connection: {c}\r\n");
        }
        head.push_str("\r\n");
        let mib = u64::try_from(reply.body.len() >> 20).unwrap_or(u64::MAX);
        let deadline = Instant::now() + WRITE_TIMEOUT + Duration::from_secs(mib.min(3600));
        self.send(head.as_bytes(), deadline) && (!with_body || self.send(&reply.body, deadline))
    }

    /// Writes all of `data` by `deadline`; false if it cannot.
    fn send(&mut self, mut data: &[u8], deadline: Instant) -> bool {
        while !data.is_empty() {
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() || self.stream.set_write_timeout(Some(left.min(POLL * 4))).is_err() {
                return false;
            }
            match self.stream.write(data) {
                Ok(0) => return false,
                Ok(n) => data = data.get(n..).unwrap_or_default(),
                // A client that takes nothing for a while is given up when the server stops.
                Err(e) if waiting(&e) && !self.shared.stopping() => {}
                Err(_) => return false,
            }
        }
        true
    }

    /// Closes after an answer: stops sending, then discards what the client
    /// still sends (bounded), so that closing with unread input does not
    /// reset the connection before the client has read the answer.
    fn linger(mut self) {
        let _ = self.stream.shutdown(Shutdown::Write);
        let end = Instant::now() + LINGER_TIME;
        let mut sink = [0u8; 8192];
        let mut drained = 0;
        while drained < LINGER_BYTES && !self.shared.stopping() {
            let left = end.saturating_duration_since(Instant::now());
            if left.is_zero() || self.stream.set_read_timeout(Some(left.min(POLL))).is_err() {
                return;
            }
            match self.stream.read(&mut sink) {
                Ok(0) => return,
                Ok(n) => drained += n,
                Err(e) if waiting(&e) => {}
                Err(_) => return,
            }
        }
    }
}

/// Whether an I/O error only means "nothing yet" (a timeout slice ended).
fn waiting(e: &io::Error) -> bool {
    matches!(e.kind(), io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut | io::ErrorKind::Interrupted)
}

enum Parsed {
    /// The head is complete: its length and contents.
    Complete(usize, Head),
    /// More bytes are needed.
    Partial,
    Refuse(Reply),
}

/// Parses a request head at the start of `buf` and checks its framing.
fn parse_head(buf: &[u8], deadline: Instant) -> Parsed {
    let mut headers = [httparse::EMPTY_HEADER; MAX_HEADERS];
    let mut req = httparse::Request::new(&mut headers);
    let n = match req.parse(buf) {
        Ok(httparse::Status::Complete(n)) => n,
        Ok(httparse::Status::Partial) => return Parsed::Partial,
        Err(httparse::Error::TooManyHeaders) => {
            return Parsed::Refuse(refusal(431, format!("the request has more than {MAX_HEADERS} header fields")))
        }
        Err(e) => return Parsed::Refuse(refusal(400, format!("the request is not valid HTTP/1.1: {e}"))),
    };
    let (Some(method), Some(path), Some(version)) = (req.method, req.path, req.version) else {
        return Parsed::Refuse(refusal(400, "the request line is incomplete".into()));
    };
    let mut length: Option<u64> = None;
    let (mut chunked, mut expect_continue, mut close, mut keep_alive) = (false, false, false, false);
    for h in req.headers.iter() {
        let value = trim(h.value);
        if h.name.eq_ignore_ascii_case("content-length") {
            match parse_length(value) {
                Some(v) if length.is_none_or(|l| l == v) => length = Some(v),
                Some(_) => return Parsed::Refuse(refusal(400, "conflicting Content-Length header fields".into())),
                None => {
                    return Parsed::Refuse(refusal(
                        400,
                        format!("invalid Content-Length `{}`", String::from_utf8_lossy(value)),
                    ))
                }
            }
        } else if h.name.eq_ignore_ascii_case("transfer-encoding") {
            chunked = true;
        } else if h.name.eq_ignore_ascii_case("expect") {
            expect_continue |= value.eq_ignore_ascii_case(b"100-continue");
        } else if h.name.eq_ignore_ascii_case("connection") {
            for token in value.split(|&b| b == b',').map(trim) {
                close |= token.eq_ignore_ascii_case(b"close");
                keep_alive |= token.eq_ignore_ascii_case(b"keep-alive");
            }
        }
    }
    if chunked {
        return Parsed::Refuse(refusal(
            411,
            "request bodies with a Transfer-Encoding are not supported; send the body with a Content-Length".into(),
        ));
    }
    let length = length.unwrap_or(0);
    let length = match usize::try_from(length) {
        Ok(l) if l <= MAX_BODY => l,
        _ => return Parsed::Refuse(Reply::error(&Error::TooLarge { size: length, limit: MAX_BODY })),
    };
    let http11 = version >= 1;
    Parsed::Complete(
        n,
        Head {
            method: method.to_string(),
            path: path.to_string(),
            http11,
            length,
            expect_continue,
            keep_alive: !close && (http11 || keep_alive),
            deadline,
        },
    )
}

/// A `Content-Length` value: decimal digits only; a value too large for
/// `u64` is `u64::MAX` (refused as too large anyway).
fn parse_length(value: &[u8]) -> Option<u64> {
    if value.is_empty() || !value.iter().all(u8::is_ascii_digit) {
        return None;
    }
    Some(value.iter().try_fold(0u64, |n, &d| n.checked_mul(10)?.checked_add(u64::from(d - b'0'))).unwrap_or(u64::MAX))
}

/// `bytes` without surrounding spaces and tabs.
fn trim(bytes: &[u8]) -> &[u8] {
    let is_space = |b: &u8| *b == b' ' || *b == b'\t';
    let start = bytes.iter().position(|b| !is_space(b)).unwrap_or(bytes.len());
    let end = bytes.iter().rposition(|b| !is_space(b)).map_or(start, |i| i + 1);
    bytes.get(start..end).unwrap_or_default()
}

/// A JSON error answer for a request refused before [`App::handle`].
fn refusal(status: u16, message: String) -> Reply {
    Reply::json(status, &json!({ "error": message }))
}

/// Whether an extra header of a [`Reply`] can be sent: a plain name, no line
/// break in the value, and not one of the headers the server sets itself.
fn header_allowed(name: &str, value: &str) -> bool {
    let own = ["content-type", "content-length", "connection", "transfer-encoding", "x-content-type-options"];
    !name.is_empty()
        && name.bytes().all(|b| b.is_ascii_alphanumeric() || b"!#$%&'*+-.^_`|~".contains(&b))
        && !value.bytes().any(|b| b == b'\r' || b == b'\n')
        && !own.iter().any(|o| name.eq_ignore_ascii_case(o))
}

/// `text` without line breaks.
fn clean(text: &str) -> String {
    text.replace(['\r', '\n'], " ")
}

fn reason(status: u16) -> &'static str {
    match status {
        100 => "Continue",
        200 => "OK",
        204 => "No Content",
        400 => "Bad Request",
        404 => "Not Found",
        405 => "Method Not Allowed",
        408 => "Request Timeout",
        411 => "Length Required",
        413 => "Content Too Large",
        415 => "Unsupported Media Type",
        422 => "Unprocessable Content",
        431 => "Request Header Fields Too Large",
        500 => "Internal Server Error",
        501 => "Not Implemented",
        503 => "Service Unavailable",
        _ => "Status",
    }
}

/// `handle` (one request's [`App::handle`]) with a panic turned into a 500 JSON answer.
fn guarded(handle: impl FnOnce() -> Reply) -> Reply {
    catch_unwind(AssertUnwindSafe(handle)).unwrap_or_else(|payload| {
        let message = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a handler panicked".into());
        Reply::error(&Error::Internal { message })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panicking_handler_gives_500_with_a_json_error() {
        let reply = guarded(|| panic!("boom at {}", 42));
        assert_eq!(reply.status, 500);
        let v: serde_json::Value = serde_json::from_slice(&reply.body).unwrap();
        assert!(v["error"].as_str().unwrap().contains("boom at 42"));
        let reply = guarded(|| Reply::json(200, &serde_json::json!({"ok": true})));
        assert_eq!(reply.status, 200);
    }

    fn status(p: &Parsed) -> Option<u16> {
        match p {
            Parsed::Refuse(r) => Some(r.status),
            _ => None,
        }
    }

    #[test]
    fn heads_are_parsed_and_framing_is_checked() {
        let now = Instant::now();
        let bytes = b"\r\nPOST /api/fk?x=1 HTTP/1.1\r\nContent-Length: 12\r\nExpect: 100-continue\r\n\r\n{}";
        let Parsed::Complete(n, head) = parse_head(bytes, now) else { panic!("a complete head") };
        assert_eq!(n, bytes.len() - 2);
        assert_eq!((head.method.as_str(), head.path.as_str(), head.length), ("POST", "/api/fk?x=1", 12));
        assert!(head.http11 && head.keep_alive && head.expect_continue);
        let Parsed::Complete(_, head) = parse_head(b"GET / HTTP/1.0\r\nConnection: Keep-Alive\r\n\r\n", now) else {
            panic!("a complete head")
        };
        assert!(!head.http11 && head.keep_alive && head.length == 0);
        let Parsed::Complete(_, head) = parse_head(b"GET / HTTP/1.1\r\nConnection: foo, close\r\n\r\n", now) else {
            panic!("a complete head")
        };
        assert!(!head.keep_alive);
        assert!(matches!(parse_head(b"GET / HTTP/1.1\r\nHost: x\r\n", now), Parsed::Partial));
        let cases: &[(&[u8], u16)] = &[
            (b"\x00\x01\x02 garbage\r\n\r\n", 400),
            (b"GET / HTTP/2.0\r\n\r\n", 400),
            (b"POST / HTTP/1.1\r\nContent-Length: 1\r\nContent-Length: 2\r\n\r\n", 400),
            (b"POST / HTTP/1.1\r\nContent-Length: -1\r\n\r\n", 400),
            (b"POST / HTTP/1.1\r\nContent-Length: 1, 1\r\n\r\n", 400),
            (b"POST / HTTP/1.1\r\nContent-Length: 100000000000\r\n\r\n", 413),
            (b"POST / HTTP/1.1\r\nContent-Length: 99999999999999999999999999\r\n\r\n", 413),
            (b"POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n", 411),
        ];
        for (bytes, code) in cases {
            assert_eq!(status(&parse_head(bytes, now)), Some(*code), "{}", String::from_utf8_lossy(bytes));
        }
        let many = format!("GET / HTTP/1.1\r\n{}\r\n", "A: b\r\n".repeat(MAX_HEADERS + 1));
        assert_eq!(status(&parse_head(many.as_bytes(), now)), Some(431));
        let Parsed::Complete(_, head) =
            parse_head(b"POST / HTTP/1.1\r\nContent-Length: 5\r\ncontent-length:  5 \r\n\r\n", now)
        else {
            panic!("equal lengths are accepted")
        };
        assert_eq!(head.length, 5);
    }

    #[test]
    fn lengths_and_headers() {
        assert_eq!(parse_length(b"0"), Some(0));
        assert_eq!(parse_length(b"1048576"), Some(1 << 20));
        assert_eq!(parse_length(b"184467440737095516150"), Some(u64::MAX));
        assert_eq!(parse_length(b""), None);
        assert_eq!(parse_length(b"+1"), None);
        assert_eq!(trim(b" \t a b \t"), b"a b");
        assert_eq!(trim(b"   "), b"");
        assert!(header_allowed("Allow", "GET, HEAD"));
        assert!(!header_allowed("Allow", "GET\r\nX: y"));
        assert!(!header_allowed("Bad Name", "x"));
        assert!(!header_allowed("content-length", "1"));
        assert_eq!(reason(431), "Request Header Fields Too Large");
    }
}
