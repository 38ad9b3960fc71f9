//! Unit tests of the client over a scripted link.

use super::*;
use std::collections::VecDeque;
use std::io::{Read, Write};
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// A scripted link: each write of a command line pops the next canned
/// answer into the read queue.
struct Script {
    answers: VecDeque<Vec<u8>>,
    inbox: VecDeque<u8>,
    sent: Arc<Mutex<Vec<String>>>,
    closed: bool,
}

impl Read for Script {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if self.inbox.is_empty() {
            if self.closed {
                return Ok(0);
            }
            return Err(io::Error::new(io::ErrorKind::TimedOut, "nothing"));
        }
        let n = buf.len().min(self.inbox.len()).min(7); // arrive in small pieces
        for b in buf.iter_mut().take(n) {
            *b = self.inbox.pop_front().unwrap();
        }
        Ok(n)
    }
}

impl Write for Script {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.sent.lock().unwrap().push(String::from_utf8_lossy(buf).into_owned());
        if let Some(a) = self.answers.pop_front() {
            self.inbox.extend(a);
        }
        Ok(buf.len())
    }
    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

impl Link for Script {
    fn set_timeout(&mut self, _: Duration) -> io::Result<()> {
        Ok(())
    }
}

fn client(answers: &[&str]) -> (Client, Arc<Mutex<Vec<String>>>) {
    let sent = Arc::new(Mutex::new(Vec::new()));
    let s = Script {
        answers: answers.iter().map(|a| a.as_bytes().to_vec()).collect(),
        inbox: VecDeque::new(),
        sent: sent.clone(),
        closed: false,
    };
    let mut c = Client::new(Box::new(s));
    c.reply_timeout = Duration::from_millis(50);
    c.motion_timeout = Duration::from_millis(50);
    (c, sent)
}

#[test]
fn parses_echo_lines_and_prompt_in_pieces() {
    let (mut c, sent) = client(&[
        "LISTPV P1\r\nPosition P1\r\n 1:0  2:-3437  3: 2867 4:738 5:-738\r\n X:1691 Y:0 Z:5044 P:-636 R:0\r\n>",
    ]);
    let r = c.listpv("P1").unwrap();
    assert_eq!(r.counts, [0, -3437, 2867, 738, -738]);
    assert_eq!(r.cartesian, Some([1691, 0, 5044, -636, 0]));
    // Right-aligned columns.
    let (mut c, _) = client(&["LISTPV P1\r\nPosition P1\r\n 1:     0  2: -3437  3:   2867 4:738 5:  -738\r\n>"]);
    let r = c.listpv("P1").unwrap();
    assert_eq!(r.counts, [0, -3437, 2867, 738, -738]);
    assert_eq!(r.cartesian, None);
    assert_eq!(sent.lock().unwrap()[0], "LISTPV P1\r");
}

#[test]
fn controller_errors_fault_the_client_until_cleared() {
    let (mut c, sent) = client(&[
        "MOVED P9\r\n*** POSITION P9 NOT DEFINED\r\n>",
        "LISTPV P1\r\nPosition P1\r\n 1:1 2:2 3:3 4:4 5:5\r\n>",
        "MOVED P1\r\nDone.\r\n>",
    ]);
    let e = c.move_d("P9", None).unwrap_err();
    assert!(matches!(&e, Error::Controller { message, .. } if message.contains("NOT DEFINED")), "{e}");
    // Motion is blocked, and nothing is sent for it.
    assert!(matches!(c.move_d("P1", None), Err(Error::Faulted { .. })));
    assert_eq!(sent.lock().unwrap().len(), 1);
    // Inspection still works.
    assert_eq!(c.listpv("P1").unwrap().counts, [1, 2, 3, 4, 5]);
    c.clear_fault();
    c.move_d("P1", None).unwrap();
}

#[test]
fn timeouts_wrong_echoes_and_missing_done_are_typed_errors() {
    let (mut c, _) = client(&["HOM"]);
    let e = c.home().unwrap_err();
    assert!(matches!(&e, Error::Timeout { received, .. } if received == "HOM"), "{e}");
    let (mut c, _) = client(&["XQ#@!\r\nDone.\r\n>"]);
    assert!(matches!(c.con(), Err(Error::Protocol { .. })));
    let (mut c, _) = client(&["CON\r\nqz%&\r\n>"]);
    let e = c.con().unwrap_err();
    assert!(matches!(&e, Error::Protocol { raw, .. } if raw.contains("qz%&")), "{e}");
    let (mut c, _) = client(&["LISTPV A\r\nPosition A\r\n 1:0 2:x\r\n>"]);
    assert!(c.listpv("A").unwrap_err().to_string().contains("`2:x`"));
    // A motion command must say `Done.`; a setting may say nothing.
    let (mut c, _) = client(&["MOVED P\r\n>"]);
    assert!(matches!(c.move_d("P", None), Err(Error::Protocol { .. })));
    let (mut c, _) = client(&["SPEED 20\r\n>", "HOME\r\nHOMING...\r\nDone.\r\n>"]);
    c.speed(20).unwrap();
    c.home().unwrap();
}

#[test]
fn endless_paging_is_cut_off() {
    let page = "X\r\nType <cr> to continue\r\n";
    let mut answers = vec![format!("LISTP\r\n{page}")];
    answers.extend(std::iter::repeat_n(page.to_string(), MAX_PAGES + 1));
    let refs: Vec<&str> = answers.iter().map(String::as_str).collect();
    let (mut c, _) = client(&refs);
    let e = c.list_positions().unwrap_err();
    assert!(e.to_string().contains("pages"), "{e}");
}

#[test]
fn paged_listings_are_continued() {
    let (mut c, sent) = client(&["LISTP\r\nA\r\nB\r\nType <cr> to continue\r\n", "C\r\n>"]);
    assert_eq!(c.list_positions().unwrap(), ["A", "B", "C"]);
    assert_eq!(sent.lock().unwrap()[1], "\r");
    // Without a line end after the page prompt.
    let (mut c, _) = client(&["LISTP\r\nA\r\nType <cr> to continue", "\r\nC\r\n>"]);
    assert_eq!(c.list_positions().unwrap(), ["A", "C"]);
}

#[test]
fn a_closed_link_is_a_disconnection() {
    let sent = Arc::new(Mutex::new(Vec::new()));
    let s = Script { answers: VecDeque::new(), inbox: VecDeque::new(), sent, closed: true };
    let mut c = Client::new(Box::new(s));
    assert!(matches!(c.home(), Err(Error::Disconnected { .. })));
    assert!(matches!(c.home(), Err(Error::Faulted { .. })));
}

#[test]
fn bad_arguments_are_refused_before_sending() {
    let (mut c, sent) = client(&[]);
    assert!(c.speed(0).is_err());
    assert!(c.defp("1abc").is_err());
    assert!(c.defp("P[1]").is_err());
    assert!(c.setpv("P", 6, 0).is_err());
    assert!(c.moves("V", 3, 2, None).is_err());
    assert!(c.command("MOVE A\rMOVE B").is_err());
    assert!(sent.lock().unwrap().is_empty());
    assert!(c.fault().is_none());
}

/// A controller that never stops talking: after `echo` (if any), the
/// same line over and over, as fast as it is read.
struct Flood {
    echo: Vec<u8>,
    line: &'static [u8],
    at: usize,
    started: bool,
    /// Floods before the command is sent, too.
    before: bool,
}

impl Read for Flood {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if !self.started && !self.before {
            return Err(io::Error::new(io::ErrorKind::TimedOut, "nothing yet"));
        }
        if self.started && !self.echo.is_empty() {
            let n = buf.len().min(self.echo.len());
            buf[..n].copy_from_slice(&self.echo[..n]);
            self.echo.drain(..n);
            return Ok(n);
        }
        self.fill(buf)
    }
}

impl Flood {
    fn fill(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        for b in buf.iter_mut() {
            *b = self.line[self.at % self.line.len()];
            self.at += 1;
        }
        Ok(buf.len())
    }
}

impl Write for Flood {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.started = true;
        Ok(buf.len())
    }
    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

impl Link for Flood {
    fn set_timeout(&mut self, _: Duration) -> io::Result<()> {
        Ok(())
    }
}

fn flooded(echo: &str, line: &'static [u8], before: bool) -> Client {
    let link = Flood { echo: echo.as_bytes().to_vec(), line, at: 0, started: false, before };
    let mut c = Client::new(Box::new(link));
    c.reply_timeout = Duration::from_millis(200);
    c.motion_timeout = Duration::from_millis(200);
    c
}

#[test]
fn a_flooding_controller_is_cut_off_quickly_with_a_short_message() {
    // After the echo: lines, a line without end, endless page prompts.
    for line in [&b"POSITION 1\r\n"[..], b"xxxxxxxxxxxxxxxx", b"Type <cr> to continue\r\n"] {
        let mut c = flooded("LISTP\r\n", line, false);
        let started = Instant::now();
        let e = c.list_positions().unwrap_err();
        assert!(started.elapsed() < Duration::from_secs(5), "{:?}", started.elapsed());
        let msg = e.to_string();
        assert!(msg.len() < 2 * crate::error::EXCERPT_CHARS + 300, "{} bytes: {}", msg.len(), &msg[..300]);
        assert!(matches!(e, Error::Protocol { .. } | Error::Timeout { .. }), "{msg}");
    }
    // Before the command is even sent.
    let mut c = flooded("", b"noise\r\n", true);
    let started = Instant::now();
    let e = c.con().unwrap_err();
    assert!(started.elapsed() < Duration::from_secs(5));
    assert!(e.to_string().contains("kept sending unasked"), "{e}");
}

#[test]
fn an_abort_must_be_answered_with_done() {
    let (mut c, _) = client(&["A\r\nDone.\r\n>"]);
    c.abort().unwrap();
    let (mut c, _) = client(&["A\r\n#$%&garble\r\n>"]);
    let e = c.abort().unwrap_err();
    assert!(matches!(&e, Error::Protocol { .. }), "{e}");
    assert!(c.fault().is_some());
}
