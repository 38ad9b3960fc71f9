//! The command line: bytes into lines, faults applied, replies and paged
//! listings out.

use std::collections::VecDeque;
use std::time::Duration;

use rand::Rng;

use super::{Controller, MAX_TYPE_AHEAD};
use crate::sim::{FaultKind, COMMANDS, MOTION_COMMANDS};

/// Lines of a listing before `Type <cr> to continue`.
const PAGE: usize = 20;
/// The line that pauses a listing.
const PAGER: &str = "Type <cr> to continue";

/// How the faults hitting one command change its output.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Ctx {
    delay: Duration,
    garble: bool,
    pub(super) disconnect: bool,
}

/// A received line.
#[derive(Debug, Clone)]
pub(super) struct Line {
    pub(super) bytes: Vec<u8>,
    pub(super) too_long: bool,
}

/// What the command interpreter is doing.
#[derive(Debug, Clone)]
pub(super) enum Mode {
    /// The prompt has been printed.
    Idle,
    /// A command waits for the end of its motion.
    Waiting,
    /// A listing waits for `\r`.
    Paging { rest: VecDeque<String>, ctx: Ctx },
}

/// The result of running one command.
pub(super) enum Outcome {
    /// Reply lines, then the prompt.
    Lines(Vec<String>),
    /// An error line (`***`), then the prompt.
    Refused(String),
    /// These lines now; the rest when the queued motion ends.
    Wait(Vec<String>),
    /// A listing, paged.
    Listing(Vec<String>),
}

pub(super) type Reply = std::result::Result<Outcome, String>;

impl Controller {
    pub(super) fn on_line(&mut self, t: Duration, line: Line) {
        if matches!(self.mode, Mode::Waiting) && is_abort(&line) {
            self.execute(t, line);
        } else if is_abort(&line) && matches!(self.mode, Mode::Paging { .. }) {
            // An abort ends a paused listing (with its prompt), then runs.
            if let Mode::Paging { ctx, .. } = std::mem::replace(&mut self.mode, Mode::Idle) {
                self.emit_prompt(t, ctx);
            }
            self.execute(t, line);
        } else if self.type_ahead.len() < MAX_TYPE_AHEAD {
            self.type_ahead.push_back(line);
        }
        self.pump(t);
        // A motion of zero duration ends at once.
        self.advance(t);
    }

    /// Runs the lines typed ahead while the interpreter is not waiting.
    pub(super) fn pump(&mut self, t: Duration) {
        if self.pumping {
            return;
        }
        self.pumping = true;
        while !self.disconnect && !matches!(self.mode, Mode::Waiting) {
            let Some(line) = self.type_ahead.pop_front() else { break };
            if matches!(self.mode, Mode::Paging { .. }) {
                self.next_page(t);
            } else {
                self.execute(t, line);
            }
        }
        self.pumping = false;
    }

    fn execute(&mut self, t: Duration, line: Line) {
        let ctx0 = Ctx::default();
        if line.too_long {
            self.emit_echo(t, ctx0, &line.bytes);
            self.emit_line(t, ctx0, "*** LINE TOO LONG");
            self.emit_prompt(t, ctx0);
            return;
        }
        let text = String::from_utf8_lossy(&line.bytes).into_owned();
        let tokens: Vec<&str> = text.split_ascii_whitespace().collect();
        let keyword = tokens.first().map(|k| k.to_ascii_uppercase()).unwrap_or_default();
        let known = COMMANDS.iter().copied().find(|c| *c == keyword);
        let mut ctx = Ctx::default();
        let mut dropped = false;
        if let Some(k) = known {
            let n = self.seen.entry(k).or_insert(0);
            *n += 1;
            let n = *n;
            for f in self.faults.iter().filter(|f| f.command == k && f.nth == n) {
                match f.kind {
                    FaultKind::Drop => dropped = true,
                    FaultKind::Garble => ctx.garble = true,
                    FaultKind::Delay(d) => ctx.delay += d,
                    FaultKind::Disconnect => ctx.disconnect = true,
                }
            }
        }
        if dropped {
            return;
        }
        let motion = known.is_some_and(|k| MOTION_COMMANDS.contains(&k));
        if ctx.disconnect && !motion {
            self.request_disconnect(t);
            return;
        }
        if keyword == "A" && tokens.len() == 1 {
            // The interrupted command answers first, then the abort.
            self.halt(t, true);
        }
        let mark = self.out.len();
        self.emit_echo(t, ctx, &line.bytes);
        let args = &tokens[tokens.len().min(1)..];
        match self.run(t, &keyword, args, ctx) {
            Ok(Outcome::Lines(lines)) => {
                for l in &lines {
                    self.emit_line(t, ctx, l);
                }
                self.emit_prompt(t, ctx);
            }
            Ok(Outcome::Refused(e)) | Err(e) => {
                if ctx.disconnect {
                    // A refused motion command under a disconnect fault: the
                    // cable goes at once.
                    self.out.truncate(mark);
                    self.request_disconnect(t);
                    return;
                }
                self.emit_line(t, ctx, &e);
                self.emit_prompt(t, ctx);
            }
            Ok(Outcome::Wait(lines)) => {
                for l in &lines {
                    self.emit_line(t, ctx, l);
                }
                self.mode = Mode::Waiting;
            }
            Ok(Outcome::Listing(lines)) => {
                self.mode = Mode::Paging { rest: lines.into(), ctx };
                self.next_page(t);
            }
        }
    }

    fn next_page(&mut self, t: Duration) {
        let Mode::Paging { rest, ctx } = &mut self.mode else { return };
        let ctx = *ctx;
        let n = rest.len().min(PAGE);
        let page: Vec<String> = rest.drain(..n).collect();
        let more = !rest.is_empty();
        for l in &page {
            self.emit_line(t, ctx, l);
        }
        if more {
            self.emit_raw(t, ctx, format!("{PAGER}\r\n").into_bytes());
        } else {
            self.mode = Mode::Idle;
            self.emit_prompt(t, ctx);
        }
    }

    // ----- output -----------------------------------------------------------

    fn emit_raw(&mut self, t: Duration, ctx: Ctx, bytes: Vec<u8>) {
        let release = (t + ctx.delay).max(self.last_release);
        self.last_release = release;
        match self.out.back_mut() {
            Some((r, b)) if *r == release => b.extend_from_slice(&bytes),
            _ => self.out.push_back((release, bytes)),
        }
    }

    fn emit_echo(&mut self, t: Duration, ctx: Ctx, line: &[u8]) {
        let mut b = line.to_vec();
        b.extend_from_slice(b"\r\n");
        self.emit_raw(t, ctx, b);
    }

    pub(super) fn emit_line(&mut self, t: Duration, ctx: Ctx, line: &str) {
        let mut b = if ctx.garble { self.garbage() } else { line.as_bytes().to_vec() };
        b.extend_from_slice(b"\r\n");
        self.emit_raw(t, ctx, b);
    }

    pub(super) fn emit_prompt(&mut self, t: Duration, ctx: Ctx) {
        self.emit_raw(t, ctx, b">".to_vec());
    }

    /// Letters and non-ASCII bytes: never `*`, `.`, `>`, `\r` or `\n`.
    fn garbage(&mut self) -> Vec<u8> {
        let n = self.garble_rng.random_range(6..=24);
        (0..n)
            .map(|_| {
                if self.garble_rng.random_bool(0.5) {
                    let c = self.garble_rng.random_range(0..52u8);
                    if c < 26 {
                        b'A' + c
                    } else {
                        b'a' + (c - 26)
                    }
                } else {
                    self.garble_rng.random_range(0x80..=0xffu8)
                }
            })
            .collect()
    }

    pub(super) fn request_disconnect(&mut self, t: Duration) {
        self.disconnect = true;
        self.out.retain(|(r, _)| *r <= t);
        self.type_ahead.clear();
    }
}

fn is_abort(line: &Line) -> bool {
    !line.too_long && {
        let text = String::from_utf8_lossy(&line.bytes);
        let mut t = text.split_ascii_whitespace();
        t.next().is_some_and(|k| k.eq_ignore_ascii_case("A")) && t.next().is_none()
    }
}
