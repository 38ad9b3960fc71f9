//! The ACL commands: arguments parsed, positions and motions asked for,
//! replies.

use std::time::Duration;

use crate::encoder::MOTORS;

use super::motion::MotionKind;
use super::positions::{Coords, PosRef};
use super::terminal::{Ctx, Outcome, Reply};
use super::Controller;

/// Longest vector.
const MAX_VECTOR: usize = 1000;
/// Longest name of a position or vector \[characters\].
const MAX_NAME: usize = 16;
/// Largest |counts| or |coordinate| accepted in `SETPV`/`SETPVC`.
const MAX_VALUE: i64 = 1_000_000_000;
/// Longest motion time argument \[0.01 s\] (one hour).
const MAX_TIME_ARG: i64 = 360_000;

impl Controller {
    pub(super) fn run(&mut self, t: Duration, keyword: &str, args: &[&str], ctx: Ctx) -> Reply {
        let done = || Ok(Outcome::Lines(vec!["Done.".into()]));
        match keyword {
            "" => Ok(Outcome::Lines(Vec::new())),
            "HOME" => {
                no_args(keyword, args)?;
                self.may_move(false)?;
                self.enqueue(t, MotionKind::Home, Vec::new(), None, true, ctx)?;
                Ok(Outcome::Wait(vec!["HOMING...".into()]))
            }
            "CON" => {
                no_args(keyword, args)?;
                self.control = true;
                done()
            }
            "COFF" => {
                no_args(keyword, args)?;
                self.halt(t, true);
                self.control = false;
                done()
            }
            "SPEED" => {
                let [n] = args else { return Err(bad("SPEED takes one integer 1..100")) };
                match n.parse::<u32>() {
                    Ok(n) if (1..=100).contains(&n) => {
                        self.speed = n;
                        done()
                    }
                    _ => Err(bad(&format!("speed `{n}`; it must be an integer 1..100"))),
                }
            }
            "DEFP" => {
                let [p] = args else { return Err(bad("DEFP takes one position name")) };
                let name = parse_name(p)?;
                if self.vectors.contains_key(&name) {
                    return Err(bad(&format!("{name} is a vector")));
                }
                if !self.points.contains_key(&name) {
                    self.room_for(1)?;
                    self.points.insert(name, Coords::None);
                }
                done()
            }
            "DIMP" => {
                if args.is_empty() {
                    return Err(bad("DIMP takes a vector and its length, as V[n]"));
                }
                let spec = args.concat();
                let (name, n) = match parse_ref(&spec)? {
                    PosRef::Element(v, n) if n <= MAX_VECTOR => (v, n),
                    PosRef::Element(_, n) => return Err(bad(&format!("length {n}; at most {MAX_VECTOR}"))),
                    PosRef::Point(_) => return Err(bad("DIMP takes a vector and its length, as V[n]")),
                };
                if self.points.contains_key(&name) {
                    return Err(bad(&format!("{name} is a position, not a vector")));
                }
                let old = self.vectors.get(&name).map_or(0, Vec::len);
                self.room_for(n.saturating_sub(old))?;
                let v = self.vectors.entry(name).or_default();
                v.resize(n, Coords::None);
                done()
            }
            "HERE" => {
                let [p] = args else { return Err(bad("HERE takes one position")) };
                let r = parse_ref(p)?;
                let c = self.counts_at(t);
                self.store(&r, Coords::Joint(c), true)?;
                done()
            }
            "SETPV" => {
                let [p, axis, value] = args else { return Err(bad("SETPV takes a position, an axis 1..5 and counts")) };
                let r = parse_ref(p)?;
                let axis = match axis.parse::<usize>() {
                    Ok(a) if (1..=MOTORS).contains(&a) => a,
                    _ => return Err(bad(&format!("axis `{axis}`; it must be 1..5"))),
                };
                let value = parse_value(value)?;
                let mut c = match self.lookup(&r)? {
                    Coords::None => [0; MOTORS],
                    Coords::Joint(c) => c,
                    Coords::Cartesian(x) => self.solve_cartesian(x, self.counts_at(t))?,
                };
                c[axis - 1] = value;
                self.store(&r, Coords::Joint(c), false)?;
                done()
            }
            "SETPVC" => {
                let [p, coord, value] = args else {
                    return Err(bad("SETPVC takes a position, X|Y|Z|P|R and a value"));
                };
                let r = parse_ref(p)?;
                let k = match coord.to_ascii_uppercase().as_str() {
                    "X" => 0,
                    "Y" => 1,
                    "Z" => 2,
                    "P" => 3,
                    "R" => 4,
                    _ => return Err(bad(&format!("coordinate `{coord}`; it must be X, Y, Z, P or R"))),
                };
                let value = parse_value(value)?;
                let mut x = match self.lookup(&r)? {
                    Coords::None => return Err(no_coordinates(&r)),
                    Coords::Joint(c) => self.cartesian_of(c)?,
                    Coords::Cartesian(x) => x,
                };
                x[k] = value;
                self.store(&r, Coords::Cartesian(x), false)?;
                done()
            }
            "LISTPV" => {
                let [p] = args else { return Err(bad("LISTPV takes one position")) };
                let r = parse_ref(p)?;
                let (c, x) = match self.lookup(&r)? {
                    Coords::None => return Err(no_coordinates(&r)),
                    Coords::Joint(c) => (c, self.cartesian_of(c)?),
                    Coords::Cartesian(x) => (self.solve_cartesian(x, self.counts_at(t))?, x),
                };
                Ok(Outcome::Lines(vec![
                    format!("Position {}", r.label()),
                    format!(" 1:{} 2:{} 3:{} 4:{} 5:{}", c[0], c[1], c[2], c[3], c[4]),
                    format!(" X:{} Y:{} Z:{} P:{} R:{}", x[0], x[1], x[2], x[3], x[4]),
                ]))
            }
            "LISTP" => {
                no_args(keyword, args)?;
                let mut lines: Vec<String> = self.points.keys().cloned().collect();
                for (v, elems) in &self.vectors {
                    lines.extend((1..=elems.len()).map(|i| format!("{v}[{i}]")));
                }
                Ok(Outcome::Listing(lines))
            }
            "MOVE" | "MOVED" => {
                let (p, time) = match args {
                    [p] => (p, None),
                    [p, tm] => (p, Some(parse_time(tm)?)),
                    _ => return Err(bad(&format!("{keyword} takes a position and an optional time (0.01 s)"))),
                };
                self.may_move(true)?;
                let r = parse_ref(p)?;
                let target = self.resolve(&r, self.planned_end())?;
                let waits = keyword == "MOVED";
                self.enqueue(t, MotionKind::Arm, vec![target], time, waits, ctx)?;
                if waits {
                    Ok(Outcome::Wait(Vec::new()))
                } else {
                    done()
                }
            }
            "MOVES" => {
                let (v, a, b, time) = match args {
                    [v, a, b] => (v, a, b, None),
                    [v, a, b, tm] => (v, a, b, Some(parse_time(tm)?)),
                    _ => return Err(bad("MOVES takes a vector, a first and a last index, and an optional time")),
                };
                let name = parse_name(v)?;
                let len = match self.vectors.get(&name) {
                    Some(e) => e.len(),
                    None => return Err(format!("*** VECTOR {name} NOT DEFINED")),
                };
                let index = |s: &str| match s.parse::<usize>() {
                    Ok(i) if (1..=len).contains(&i) => Ok(i),
                    _ => Err(bad(&format!("index `{s}`; {name} has positions 1..{len}"))),
                };
                let (a, b) = (index(a)?, index(b)?);
                self.may_move(true)?;
                let order: Vec<usize> = if a <= b { (a..=b).collect() } else { (b..=a).rev().collect() };
                let mut near = self.planned_end();
                let mut targets = Vec::with_capacity(order.len());
                for i in order {
                    let c = self.resolve(&PosRef::Element(name.clone(), i), near)?;
                    targets.push(c);
                    near = c;
                }
                self.enqueue(t, MotionKind::Arm, targets, time, true, ctx)?;
                Ok(Outcome::Wait(Vec::new()))
            }
            "OPEN" | "CLOSE" => {
                no_args(keyword, args)?;
                self.may_move(false)?;
                let kind = MotionKind::Gripper { open: keyword == "OPEN" };
                self.enqueue(t, kind, Vec::new(), None, true, ctx)?;
                Ok(Outcome::Wait(Vec::new()))
            }
            "A" => {
                no_args(keyword, args)?;
                done()
            }
            "CLRBUF" => {
                no_args(keyword, args)?;
                let waiters: Vec<Ctx> = self.queue.drain(..).filter_map(|i| i.waiter).collect();
                self.abort_waiters(t, waiters);
                done()
            }
            _ => Ok(Outcome::Refused("*** UNKNOWN COMMAND".into())),
        }
    }

    /// Checks control (and homing, for the arm).
    fn may_move(&self, arm: bool) -> std::result::Result<(), String> {
        if !self.control {
            return Err("*** CONTROL DISABLED".into());
        }
        if arm && !self.homed {
            return Err("*** HOME NOT DONE".into());
        }
        Ok(())
    }
}

pub(super) fn bad(what: &str) -> String {
    format!("*** BAD ARGUMENT: {what}")
}

pub(super) fn no_coordinates(r: &PosRef) -> String {
    format!("*** POSITION {} HAS NO COORDINATES", r.label())
}

fn no_args(keyword: &str, args: &[&str]) -> std::result::Result<(), String> {
    if args.is_empty() {
        Ok(())
    } else {
        Err(bad(&format!("{keyword} takes no arguments")))
    }
}

/// A position or vector name: a letter, then letters, digits or `_`.
fn parse_name(s: &str) -> std::result::Result<String, String> {
    let ok = !s.is_empty()
        && s.len() <= MAX_NAME
        && s.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_')
        && s.as_bytes()[0].is_ascii_alphabetic();
    if ok {
        Ok(s.to_ascii_uppercase())
    } else {
        Err(bad(&format!("name `{s}`; names are a letter then letters, digits or _ (at most {MAX_NAME})")))
    }
}

/// `NAME` or `NAME[i]` with i ≥ 1.
fn parse_ref(s: &str) -> std::result::Result<PosRef, String> {
    match s.split_once('[') {
        None => Ok(PosRef::Point(parse_name(s)?)),
        Some((v, rest)) => {
            let name = parse_name(v)?;
            match rest.strip_suffix(']').map(str::parse::<usize>) {
                Some(Ok(i)) if i >= 1 => Ok(PosRef::Element(name, i)),
                _ => Err(bad(&format!("`{s}`; an element is written V[n] with n >= 1"))),
            }
        }
    }
}

fn parse_value(s: &str) -> std::result::Result<i64, String> {
    match s.parse::<i64>() {
        Ok(v) if (-MAX_VALUE..=MAX_VALUE).contains(&v) => Ok(v),
        _ => Err(bad(&format!("value `{s}`; an integer of at most {MAX_VALUE} in magnitude"))),
    }
}

/// A time argument \[0.01 s\] → nominal seconds.
fn parse_time(s: &str) -> std::result::Result<f64, String> {
    match s.parse::<i64>() {
        Ok(v) if (1..=MAX_TIME_ARG).contains(&v) => Ok(v as f64 / 100.0),
        _ => Err(bad(&format!("time `{s}`; an integer 1..{MAX_TIME_ARG} (hundredths of a second)"))),
    }
}
