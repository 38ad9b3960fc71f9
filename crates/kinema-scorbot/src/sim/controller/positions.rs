//! Stored positions: joint counts or Cartesian coordinates, looked up,
//! stored, checked against the joint limits and solved.

use crate::encoder::MOTORS;

use super::commands::{bad, no_coordinates};
use super::{Controller, LIMIT_TOLERANCE};

/// Most stored positions (scalars plus vector elements).
const MAX_POSITIONS: usize = 10_000;

/// What a stored position holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Coords {
    /// Defined (`DEFP`, `DIMP`) but never given coordinates.
    None,
    /// Encoder counts of motors 1–5.
    Joint([i64; MOTORS]),
    /// X, Y, Z \[0.1 mm\], P, R \[0.1°\].
    Cartesian([i64; MOTORS]),
}

/// A position reference: `P1` or `V[3]` (names uppercase).
#[derive(Debug, Clone, PartialEq)]
pub(super) enum PosRef {
    Point(String),
    Element(String, usize),
}

impl PosRef {
    pub(super) fn label(&self) -> String {
        match self {
            PosRef::Point(n) => n.clone(),
            PosRef::Element(v, i) => format!("{v}[{i}]"),
        }
    }
}

impl Controller {
    pub(super) fn room_for(&self, extra: usize) -> std::result::Result<(), String> {
        let used = self.points.len() + self.vectors.values().map(Vec::len).sum::<usize>();
        if used + extra > MAX_POSITIONS {
            return Err(format!("*** BAD ARGUMENT: no room; at most {MAX_POSITIONS} positions"));
        }
        Ok(())
    }

    pub(super) fn lookup(&self, r: &PosRef) -> std::result::Result<Coords, String> {
        let found = match r {
            PosRef::Point(n) => self.points.get(n).copied(),
            PosRef::Element(v, i) => self.vectors.get(v).and_then(|e| e.get(i - 1)).copied(),
        };
        found.ok_or_else(|| format!("*** POSITION {} NOT DEFINED", r.label()))
    }

    /// Stores coordinates into a defined position (or, with `define`, into a
    /// scalar position created if needed).
    pub(super) fn store(&mut self, r: &PosRef, c: Coords, define: bool) -> std::result::Result<(), String> {
        match r {
            PosRef::Point(n) => {
                if self.vectors.contains_key(n) {
                    return Err(bad(&format!("{n} is a vector")));
                }
                if !self.points.contains_key(n) {
                    if !define {
                        return Err(format!("*** POSITION {n} NOT DEFINED"));
                    }
                    self.room_for(1)?;
                }
                self.points.insert(n.clone(), c);
                Ok(())
            }
            PosRef::Element(v, i) => match self.vectors.get_mut(v).and_then(|e| e.get_mut(i - 1)) {
                Some(slot) => {
                    *slot = c;
                    Ok(())
                }
                None => Err(format!("*** POSITION {} NOT DEFINED", r.label())),
            },
        }
    }

    /// The counts a position stands for, checked against the joint limits;
    /// Cartesian positions are solved nearest to `near`.
    pub(super) fn resolve(&self, r: &PosRef, near: [i64; MOTORS]) -> std::result::Result<[i64; MOTORS], String> {
        let c = match self.lookup(r)? {
            Coords::None => return Err(no_coordinates(r)),
            Coords::Joint(c) => c,
            Coords::Cartesian(x) => self.solve_cartesian(x, near)?,
        };
        self.check_limits(&c)?;
        Ok(c)
    }

    fn check_limits(&self, c: &[i64; MOTORS]) -> std::result::Result<(), String> {
        let q = self.constants.angles(&c.map(|v| v as f64)).map_err(|e| format!("*** BAD ARGUMENT: {e}"))?;
        for (i, (j, v)) in self.robot.joints().iter().zip(q).enumerate() {
            let l = j.limits;
            if !(v >= l.min - LIMIT_TOLERANCE && v <= l.max + LIMIT_TOLERANCE) {
                return Err(format!(
                    "*** OUT OF RANGE: axis {} (joint angle {:.1} deg, limits {:.1} to {:.1} deg)",
                    i + 1,
                    v.to_degrees(),
                    l.min.to_degrees(),
                    l.max.to_degrees()
                ));
            }
        }
        Ok(())
    }

    /// X, Y, Z \[0.1 mm\], P = θ2+θ3+θ4, R = θ5 \[0.1°\] of counts, by the
    /// controller's constants.
    pub(super) fn cartesian_of(&self, c: [i64; MOTORS]) -> std::result::Result<[i64; MOTORS], String> {
        let q = self.constants.angles(&c.map(|v| v as f64)).map_err(|e| format!("*** BAD ARGUMENT: {e}"))?;
        let p = self.robot.fk(&q).map_err(|e| format!("*** BAD ARGUMENT: {e}"))?.world_from_tool.pos;
        let tenths = |v: f64| (v * 10.0).round().clamp(-9e15, 9e15) as i64;
        Ok([
            tenths(p.x * 1000.0),
            tenths(p.y * 1000.0),
            tenths(p.z * 1000.0),
            tenths((q[1] + q[2] + q[3]).to_degrees()),
            tenths(q[4].to_degrees()),
        ])
    }

    /// Counts for Cartesian coordinates: the within-limits IK solution
    /// nearest (in joint space) to the configuration of `near`.
    pub(super) fn solve_cartesian(
        &self,
        x: [i64; MOTORS],
        near: [i64; MOTORS],
    ) -> std::result::Result<[i64; MOTORS], String> {
        const UNREACHABLE: &str = "*** POSITION NOT REACHABLE";
        let p = [x[0] as f64 * 1e-4, x[1] as f64 * 1e-4, x[2] as f64 * 1e-4];
        // The seed's pitch β = −(θ2+θ3+θ4) = −P.
        let pitch = -(x[3] as f64 / 10.0).to_radians();
        let roll = (x[4] as f64 / 10.0).to_radians();
        let q_near = self.constants.angles(&near.map(|v| v as f64)).map_err(|_| UNREACHABLE.to_string())?;
        let sols = self.ik.solve_xyz_pitch_roll(p, pitch, roll).map_err(|_| UNREACHABLE.to_string())?;
        let mut best: Option<(f64, [i64; MOTORS])> = None;
        for s in sols.iter().filter(|s| s.within_limits() && s.position_error < 1e-6) {
            let Ok(c) = self.constants.counts_rounded(&s.q) else { continue };
            if self.check_limits(&c).is_err() {
                continue;
            }
            let d: f64 = s.q.iter().zip(&q_near).map(|(a, b)| (a - b) * (a - b)).sum();
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, c));
            }
        }
        best.map(|b| b.1).ok_or_else(|| UNREACHABLE.to_string())
    }
}
