//! One command and its reply: the echo, the reply lines, the prompt,
//! paging, stale input and timeouts.

use std::io;
use std::time::{Duration, Instant};

use crate::error::{Error, Result};

use super::{Client, Reply, MAX_PAGES, MAX_REPLY_BYTES, MOTION, PAGING_BUDGET};

impl Client {
    pub(super) fn exchange(&mut self, line: &str, waiting: bool, skip_to_echo: bool) -> Result<Reply> {
        self.discard_stale(line)?;
        let mut out = Vec::with_capacity(line.len() + 1);
        out.extend_from_slice(line.as_bytes());
        out.push(b'\r');
        self.link
            .write_all(&out)
            .and_then(|_| self.link.flush())
            .map_err(|e| io_error(e, &format!("sending `{line}`")))?;

        let mut raw: Vec<u8> = Vec::new();
        let mut lines: Vec<String> = Vec::new();
        let mut echoed = false;
        let mut pages = 0usize;
        let wait = if waiting { self.motion_timeout } else { self.reply_timeout };
        let budget = self.reply_timeout + wait + PAGING_BUDGET;
        let hard_deadline = Instant::now() + budget;
        let mut deadline = Instant::now() + self.reply_timeout;
        loop {
            if raw.len() + self.pending.len() > MAX_REPLY_BYTES {
                raw.append(&mut self.pending);
                return Err(Error::Protocol {
                    command: line.into(),
                    message: format!("the reply is longer than {MAX_REPLY_BYTES} bytes"),
                    raw: String::from_utf8_lossy(&raw).into_owned(),
                });
            }
            // Consume complete lines.
            while let Some(nl) = self.pending.iter().position(|&b| b == b'\n') {
                let chunk: Vec<u8> = self.pending.drain(..=nl).collect();
                raw.extend_from_slice(&chunk);
                let text = String::from_utf8_lossy(&chunk).trim_matches(['\r', '\n']).to_string();
                if !echoed {
                    // The prompt of an earlier command may precede the echo.
                    let echo = text.trim_start_matches('>').trim();
                    if !echo.eq_ignore_ascii_case(line) && skip_to_echo {
                        // What a command interrupted by this one printed.
                        continue;
                    }
                    if !echo.eq_ignore_ascii_case(line) {
                        return Err(Error::Protocol {
                            command: line.into(),
                            message: format!("expected the echo `{line}`, got `{echo}`"),
                            raw: String::from_utf8_lossy(&raw).into_owned(),
                        });
                    }
                    echoed = true;
                    deadline = Instant::now() + wait;
                    continue;
                }
                if text.contains("Type <cr>") {
                    // A paged listing: ask for the next page.
                    deadline = self.next_page(&mut pages, line, &raw)?;
                    continue;
                }
                lines.push(text);
            }
            // The prompt ends the reply.
            if echoed
                && self.pending.iter().all(|b| b.is_ascii_whitespace() || *b == b'>')
                && self.pending.contains(&b'>')
            {
                raw.append(&mut self.pending);
                break;
            }
            let now = Instant::now();
            if now >= deadline.min(hard_deadline) {
                raw.extend_from_slice(&self.pending);
                self.pending.clear();
                let timeout = if now >= hard_deadline {
                    budget
                } else if echoed && waiting {
                    self.motion_timeout
                } else {
                    self.reply_timeout
                };
                return Err(Error::Timeout {
                    command: line.into(),
                    timeout,
                    received: String::from_utf8_lossy(&raw).into_owned(),
                });
            }
            let got = self.read_some(deadline.min(hard_deadline) - now, line)?;
            if !got && echoed && String::from_utf8_lossy(&self.pending).contains("Type <cr>") {
                // A page prompt printed without a line end, and nothing after it.
                deadline = self.next_page(&mut pages, line, &raw)?;
                raw.append(&mut self.pending);
            }
        }
        let raw = String::from_utf8_lossy(&raw).into_owned();
        if let Some(bad) = lines.iter().find(|l| l.contains("***")) {
            let message = bad.trim().chars().take(crate::error::EXCERPT_CHARS).collect();
            return Err(Error::Controller { command: line.into(), message, raw });
        }
        Ok(Reply { command: line.into(), lines, raw })
    }

    /// Asks a paged listing for its next page (a carriage return), at most
    /// [`MAX_PAGES`] times per command; returns the new reply deadline.
    fn next_page(&mut self, pages: &mut usize, line: &str, raw: &[u8]) -> Result<Instant> {
        *pages += 1;
        if *pages > MAX_PAGES {
            return Err(Error::Protocol {
                command: line.into(),
                message: format!("more than {MAX_PAGES} pages"),
                raw: String::from_utf8_lossy(raw).into_owned(),
            });
        }
        self.link.write_all(b"\r").map_err(|e| io_error(e, &format!("paging `{line}`")))?;
        Ok(Instant::now() + self.reply_timeout)
    }

    /// Reads what is available within `wait` into `pending`; whether
    /// anything arrived.
    fn read_some(&mut self, wait: Duration, line: &str) -> Result<bool> {
        self.link
            .set_timeout(wait.min(Duration::from_millis(200)))
            .map_err(|e| io_error(e, "setting the read timeout"))?;
        let mut buf = [0u8; 512];
        match self.link.read(&mut buf) {
            Ok(0) => Err(Error::Disconnected { during: format!("waiting for the reply to `{line}`") }),
            Ok(n) => {
                self.pending.extend_from_slice(&buf[..n]);
                Ok(true)
            }
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock | io::ErrorKind::Interrupted
                ) =>
            {
                Ok(false)
            }
            Err(e) => Err(io_error(e, &format!("waiting for the reply to `{line}`"))),
        }
    }

    /// Drops bytes left over from an earlier command (a late reply after a
    /// timeout) so they cannot be taken for this command's reply.
    fn discard_stale(&mut self, line: &str) -> Result<()> {
        self.pending.clear();
        let mut buf = [0u8; 512];
        let (mut dropped, deadline) = (0usize, Instant::now() + self.reply_timeout);
        loop {
            if dropped > MAX_REPLY_BYTES || Instant::now() >= deadline {
                return Err(Error::Protocol {
                    command: line.into(),
                    message: format!(
                        "before it was sent, the controller kept sending unasked ({dropped} bytes in {:?}); is it flooding the line?",
                        self.reply_timeout
                    ),
                    raw: String::from_utf8_lossy(&buf).into_owned(),
                });
            }
            match self.link.read_now(&mut buf) {
                Ok(0) => return Err(Error::Disconnected { during: "checking for stale input".into() }),
                Ok(n) => dropped += n,
                Err(e)
                    if matches!(
                        e.kind(),
                        io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock | io::ErrorKind::Interrupted
                    ) =>
                {
                    return Ok(())
                }
                Err(e) => return Err(io_error(e, "checking for stale input")),
            }
        }
    }

    /// Runs a command that answers `Done.` (required after a motion command;
    /// after the others, a reply without any line is accepted too, as some
    /// controller firmware prints nothing). Any other text is a protocol error.
    pub(super) fn done(&mut self, line: &str) -> Result<()> {
        let reply = self.command(line)?;
        let keyword = line.split_whitespace().next().unwrap_or("").to_ascii_uppercase();
        let motion = MOTION.contains(&keyword.as_str());
        let said_done = reply.lines.iter().any(|l| l.trim() == "Done.");
        // HOME announces itself before it ends.
        let other =
            reply.lines.iter().map(|l| l.trim()).any(|l| !l.is_empty() && l != "Done." && !l.starts_with("HOMING"));
        if (said_done || !motion) && !other {
            Ok(())
        } else {
            let message = if other { "expected only `Done.`" } else { "expected `Done.`" };
            let err = Error::Protocol { command: line.into(), message: message.into(), raw: reply.raw };
            self.fault = Some(err.to_string());
            Err(err)
        }
    }
}

fn io_error(e: io::Error, doing: &str) -> Error {
    match e.kind() {
        io::ErrorKind::BrokenPipe
        | io::ErrorKind::ConnectionReset
        | io::ErrorKind::ConnectionAborted
        | io::ErrorKind::UnexpectedEof => Error::Disconnected { during: doing.into() },
        // A pseudo-terminal whose other side closed reads EIO.
        _ if e.raw_os_error() == Some(5) => Error::Disconnected { during: doing.into() },
        _ => Error::io(format!("controller link: {doing}"), e),
    }
}
