//! The ACL commands as methods, their arguments checked before sending,
//! and their replies parsed.

use crate::error::{Error, Result};

use super::{CartesianAxis, Client, PositionReadout, Reply};

impl Client {
    /// `HOME`: homes every axis; returns when homing has ended.
    pub fn home(&mut self) -> Result<()> {
        self.done("HOME")
    }

    /// `CON`: servo control on.
    pub fn con(&mut self) -> Result<()> {
        self.done("CON")
    }

    /// `COFF`: servo control off.
    pub fn coff(&mut self) -> Result<()> {
        self.done("COFF")
    }

    /// `SPEED n`, n = 1…100 \[% of the maximum speed\].
    pub fn speed(&mut self, percent: u32) -> Result<()> {
        if !(1..=100).contains(&percent) {
            return Err(Error::out_of_range("speed", percent.into(), "1…100 (% of the maximum speed)"));
        }
        self.done(&format!("SPEED {percent}"))
    }

    /// `DEFP p`: defines a position.
    pub fn defp(&mut self, position: &str) -> Result<()> {
        check_name(position, false)?;
        self.done(&format!("DEFP {position}"))
    }

    /// `DIMP v[n]`: defines a vector of `len` positions `v[1]`…`v[len]`.
    pub fn dimp(&mut self, vector: &str, len: usize) -> Result<()> {
        check_name(vector, false)?;
        if len == 0 {
            return Err(Error::too_few("vector length", 0, 1, "positions"));
        }
        self.done(&format!("DIMP {vector}[{len}]"))
    }

    /// `HERE p`: records the arm's current counts into `position`.
    pub fn here(&mut self, position: &str) -> Result<()> {
        check_name(position, true)?;
        self.done(&format!("HERE {position}"))
    }

    /// `SETPV p axis counts`: one axis (1–5) of a joint position.
    pub fn setpv(&mut self, position: &str, axis: usize, counts: i64) -> Result<()> {
        check_name(position, true)?;
        if !(1..=5).contains(&axis) {
            return Err(Error::out_of_range("axis", axis as f64, "1…5 (the Scorbot's axes)"));
        }
        self.done(&format!("SETPV {position} {axis} {counts}"))
    }

    /// All five axes of a joint position (five `SETPV`s).
    pub fn set_joint_position(&mut self, position: &str, counts: [i64; 5]) -> Result<()> {
        for (i, c) in counts.iter().enumerate() {
            self.setpv(position, i + 1, *c)?;
        }
        Ok(())
    }

    /// `SETPVC p axis value`: one Cartesian coordinate \[0.1 mm or 0.1°\].
    pub fn setpvc(&mut self, position: &str, axis: CartesianAxis, value: i64) -> Result<()> {
        check_name(position, true)?;
        self.done(&format!("SETPVC {position} {axis:?} {value}"))
    }

    /// `LISTPV p`: the position's counts and, when printed, its Cartesian
    /// coordinates.
    pub fn listpv(&mut self, position: &str) -> Result<PositionReadout> {
        check_name(position, true)?;
        let line = format!("LISTPV {position}");
        let reply = self.command(&line)?;
        parse_listpv(&reply).inspect_err(|e| self.fault = Some(e.to_string()))
    }

    /// `LISTP`: the names of the defined positions (every page).
    pub fn list_positions(&mut self) -> Result<Vec<String>> {
        let reply = self.command("LISTP")?;
        Ok(reply.lines.into_iter().map(|l| l.trim().to_string()).filter(|l| !l.is_empty()).collect())
    }

    /// `MOVE p [t]`: starts a joint-interpolated move and returns at once.
    /// `time` in hundredths of a second.
    pub fn move_to(&mut self, position: &str, time: Option<u32>) -> Result<()> {
        check_name(position, true)?;
        self.done(&with_time(format!("MOVE {position}"), time))
    }

    /// `MOVED p [t]`: moves and returns when the motion has ended.
    pub fn move_d(&mut self, position: &str, time: Option<u32>) -> Result<()> {
        check_name(position, true)?;
        self.done(&with_time(format!("MOVED {position}"), time))
    }

    /// `MOVES v first last [t]`: a smooth move through `v[first]`…`v[last]`;
    /// returns when it has ended.
    pub fn moves(&mut self, vector: &str, first: usize, last: usize, time: Option<u32>) -> Result<()> {
        check_name(vector, false)?;
        if first == 0 || last < first {
            return Err(Error::DoesNotFit {
                what: "vector range".into(),
                reason: format!("{first}…{last}; need 1 ≤ first ≤ last"),
            });
        }
        self.done(&with_time(format!("MOVES {vector} {first} {last}"), time))
    }

    /// `OPEN`: opens the gripper.
    pub fn open(&mut self) -> Result<()> {
        self.done("OPEN")
    }

    /// `CLOSE`: closes the gripper.
    pub fn close(&mut self) -> Result<()> {
        self.done("CLOSE")
    }

    /// `A`: aborts any motion. Allowed while faulted; reads until its own
    /// echo and prompt, discarding what a pending motion command printed.
    /// Does not clear the fault.
    pub fn abort(&mut self) -> Result<()> {
        let fault = self.fault.clone();
        let r = self.exchange("A", false, true).and_then(|reply| {
            // Controller-A answers an abort with `Done.`; anything else is not an abort.
            match reply.lines.iter().map(|l| l.trim()).filter(|l| !l.is_empty()).collect::<Vec<_>>()[..] {
                [] | ["Done."] => Ok(()),
                _ => Err(Error::Protocol { command: "A".into(), message: "expected `Done.`".into(), raw: reply.raw }),
            }
        });
        // An abort never clears (nor, by itself, sets) the fault state… unless it fails.
        self.fault = match &r {
            Ok(_) => fault,
            Err(e) => Some(e.to_string()),
        };
        r
    }

    /// `CLRBUF`: clears queued motions.
    pub fn clrbuf(&mut self) -> Result<()> {
        self.done("CLRBUF")
    }
}

fn with_time(mut line: String, time: Option<u32>) -> String {
    if let Some(t) = time {
        line.push_str(&format!(" {t}"));
    }
    line
}

/// Position names: letters, digits and `_`; with `indexed`, also `v[n]`.
fn check_name(name: &str, indexed: bool) -> Result<()> {
    let (base, index) = match name.split_once('[') {
        Some((b, rest)) if indexed => (b, Some(rest)),
        _ => (name, None),
    };
    let ok_base = !base.is_empty()
        && base.len() <= 16
        && base.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && base.chars().next().is_some_and(|c| c.is_ascii_alphabetic());
    let ok_index = index.is_none_or(|r| r.strip_suffix(']').is_some_and(|n| n.parse::<u32>().is_ok_and(|n| n >= 1)));
    if ok_base && ok_index {
        Ok(())
    } else {
        Err(Error::Malformed {
            what: "position name".into(),
            text: name.into(),
            expected: format!(
                "names are a letter then letters, digits or _ (at most 16){}",
                if indexed { ", optionally indexed as NAME[n] with n ≥ 1" } else { "" }
            ),
        })
    }
}

/// Parses `LISTPV`'s lines: `k:value` pairs, 1–5 for counts and X Y Z P R.
fn parse_listpv(reply: &Reply) -> Result<PositionReadout> {
    let mut counts = [None; 5];
    let mut cart = [None; 5];
    let bad = |message: String| Error::Protocol { command: reply.command.clone(), message, raw: reply.raw.clone() };
    for line in &reply.lines {
        // Pairs `k:value`, with any spacing after the colon (`1:100`, `1: 100`,
        // `1:   100` when a controller right-aligns its columns).
        let mut tokens = line.split_whitespace();
        while let Some(tok) = tokens.next() {
            let Some((k, v)) = tok.split_once(':') else { continue };
            let slot = match k.to_ascii_uppercase().as_str() {
                "1" => &mut counts[0],
                "2" => &mut counts[1],
                "3" => &mut counts[2],
                "4" => &mut counts[3],
                "5" => &mut counts[4],
                "X" => &mut cart[0],
                "Y" => &mut cart[1],
                "Z" => &mut cart[2],
                "P" => &mut cart[3],
                "R" => &mut cart[4],
                _ => continue,
            };
            let v = if v.is_empty() { tokens.next().unwrap_or("") } else { v };
            *slot = Some(v.parse::<i64>().map_err(|_| bad(format!("`{k}:{v}` is not an integer coordinate")))?);
        }
    }
    let Some(counts) = collect(counts) else {
        return Err(bad("expected the counts of axes 1–5 as `1:c1 … 5:c5`".into()));
    };
    Ok(PositionReadout { counts, cartesian: collect(cart) })
}

fn collect(v: [Option<i64>; 5]) -> Option<[i64; 5]> {
    let mut out = [0; 5];
    for i in 0..5 {
        out[i] = v[i]?;
    }
    Some(out)
}
