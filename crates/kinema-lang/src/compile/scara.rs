//! Seed 003's relative instructions for the SCARA on a rail (MOVEXY, MOVEZ,
//! MOVETITA) and its HOME.

use std::f64::consts::PI;
use std::rc::Rc;

use kinema::ik::family::{Family, ToolAngleJoints};
use kinema::ik::registry;
use kinema::ik::{self, IkTarget};
use kinema::nalgebra::Vector3;
use kinema::traj::{Profile, TimeLaw};
use kinema::Robot;

use crate::ast::{Expr, Stmt, Target};
use crate::diag::Diagnostic;
use crate::units::Dim;

use super::text::{fmt_angle, fmt_xyz};
use super::trajectory_check::outside_limits;
use super::Compiler;

/// The solver of seed 003's relative instructions (MOVEXY, MOVEZ, MOVETITA):
/// the family that owns tool-angle targets (a point and the angle α about
/// z), fitted to the robot with the present TOOL.
pub(super) enum Scara {
    /// No family takes tool-angle targets on this robot: the instructions are
    /// refused before the program runs.
    No,
    /// The fitted family, and what its joints move.
    Solver(Rc<dyn Family>, ToolAngleJoints),
    /// The SCARA with a tool its IK cannot take (a tilted one): which TOOL, and why. HOME
    /// and PTP/LIN still work; MOVEXY/MOVEZ/MOVETITA are errors.
    ToolRefused(String, ToolAngleJoints),
}

impl Scara {
    /// The family that owns tool-angle targets on `robot`, if one does and
    /// says what its joints move.
    pub(super) fn fit(robot: &Robot) -> Scara {
        match registry::for_tool_angle(robot) {
            Some((family, joints)) => Scara::Solver(Rc::from(family), joints),
            None => Scara::No,
        }
    }

    /// What the joints move; `None` for [`Scara::No`].
    fn joints(&self) -> Option<ToolAngleJoints> {
        match self {
            Scara::No => None,
            Scara::Solver(_, j) | Scara::ToolRefused(_, j) => Some(*j),
        }
    }
}

impl Compiler<'_> {
    /// After a TOOL: the SCARA's relative moves need its solver with the new
    /// tool. A tool it cannot take (a tilted one) is fine for PTP/LIN and HOME;
    /// MOVEXY/MOVEZ/MOVETITA after it are errors (they did nothing).
    pub(super) fn refit_scara(&mut self, with_tool: &Robot, t: &Target) {
        let Some(joints) = self.scara.joints() else { return };
        match registry::for_typed(with_tool, joints.kind) {
            Ok(f) => self.scara = Scara::Solver(Rc::from(f), joints),
            Err(e) => {
                let why = match e {
                    kinema::Error::UnsupportedStructure { reason, .. } => reason,
                    e => e.to_string(),
                };
                let line = self.line(&t.span());
                self.warn(Diagnostic::warning(
                    t.span(),
                    format!("the SCARA's closed-form IK cannot take this tool: {why}; MOVEXY, MOVEZ and MOVETITA cannot follow it"),
                ));
                self.scara = Scara::ToolRefused(format!("the TOOL at line {line}: {why}"), joints);
            }
        }
    }

    /// MOVEZ dz, t.
    pub(super) fn move_z(&mut self, s: &Stmt, dz: &Expr, time: &Expr) {
        let (Some(dz), Some(t)) = (self.value(dz, Dim::Length, Some(1e-3)), self.value(time, Dim::Time, Some(1.0)))
        else {
            return;
        };
        self.scara_relative(s, [0.0, 0.0, dz, 0.0], t, "MOVEZ");
    }

    /// MOVETITA dθ, t.
    pub(super) fn move_tita(&mut self, s: &Stmt, dtheta: &Expr, time: &Expr) {
        let (Some(da), Some(t)) =
            (self.value(dtheta, Dim::Angle, Some(PI / 180.0)), self.value(time, Dim::Time, Some(1.0)))
        else {
            return;
        };
        self.scara_relative(s, [0.0, 0.0, 0.0, da], t, "MOVETITA");
    }

    /// MOVEXY dx, dy, t.
    pub(super) fn move_xy(&mut self, s: &Stmt, dx: &Expr, dy: &Expr, time: &Expr) {
        let (Some(dx), Some(dy), Some(t)) = (
            self.value(dx, Dim::Length, Some(1e-3)),
            self.value(dy, Dim::Length, Some(1e-3)),
            self.value(time, Dim::Time, Some(1.0)),
        ) else {
            return;
        };
        self.scara_relative(s, [dx, dy, 0.0, 0.0], t, "MOVEXY");
    }

    /// Seed 003's relative moves: `delta` = [dx, dy, dz, dα] of the tool.
    fn scara_relative(&mut self, s: &Stmt, delta: [f64; 4], t: f64, kw: &str) {
        let (ik, joints) = match &self.scara {
            Scara::Solver(ik, joints) => (Rc::clone(ik), *joints),
            // Other robots are refused before running.
            Scara::No => return,
            Scara::ToolRefused(why, _) => {
                let why = why.clone();
                self.err(
                    Diagnostic::error(
                        s.span.clone(),
                        format!("{kw} needs the SCARA's closed-form IK, which cannot take {why}"),
                    )
                    .with_hint("a SCARA tool may be offset and turned about z, not tilted; or move with PTP"),
                );
                return;
            }
        };
        let pose = self.current_pose();
        let alpha = pose.rot[(1, 0)].atan2(pose.rot[(0, 0)]);
        let target = [pose.pos.x + delta[0], pose.pos.y + delta[1], pose.pos.z + delta[2], alpha + delta[3]];
        let q_to = if delta[0] == 0.0 && delta[1] == 0.0 {
            // Z and θ alone: only the vertical or the roll joint moves, as the seed's linear law does.
            let mut q = self.q.clone();
            if delta[2] != 0.0 {
                q[joints.vertical] += delta[2] / self.dz_dq(joints.vertical);
            }
            q[joints.roll] += delta[3];
            q
        } else {
            // The request every door makes, so the point is held to the contract and picked alike.
            let request = ik::IkRequest { q0: Some(&self.q), ..Default::default() };
            let robot = &self.robot_tool;
            let solved = joints
                .target([target[0], target[1], target[2]], target[3])
                .and_then(|typed| ik::solve_target_with(robot, Some(&*ik), &IkTarget::Typed(typed), &request))
                .and_then(|answer| ik::pick_one(robot, answer.solver, answer.solutions, Some(&self.q)));
            match solved {
                Ok(sol) => {
                    let mut q = sol.q;
                    // Keep θ continuous: the nearest equivalent of the roll joint to the present one.
                    let r = joints.roll;
                    while q[r] - self.q[r] > PI {
                        q[r] -= 2.0 * PI;
                    }
                    while self.q[r] - q[r] > PI {
                        q[r] += 2.0 * PI;
                    }
                    q
                }
                Err(e @ kinema::Error::Unreachable { .. }) if self.opts.skip_unreachable => {
                    self.skipped(s, &e);
                    return;
                }
                Err(e) => {
                    self.err(
                        Diagnostic::error(s.span.clone(), format!("{kw} to ({:.4}, {:.4}) m is unreachable: {e}", target[0], target[1]))
                            .with_hint("seed 003 skips points outside the workspace: run with skip-unreachable (`kinema run --skip-unreachable`) to do the same"),
                    );
                    return;
                }
            }
        };
        let text = format!(
            "tool ({}) m, θ {} rad",
            fmt_xyz(&Vector3::new(target[0], target[1], target[2])),
            fmt_angle(target[3])
        );
        self.scara_move(s, q_to, t, kw, text);
    }

    /// ∂z/∂q of the tool for the vertical joint `vertical` (z is linear in it).
    fn dz_dq(&self, vertical: usize) -> f64 {
        let mut q = self.q.clone();
        let z0 = self.current_pose().pos.z;
        q[vertical] += 0.01;
        let z1 = self.robot_tool.fk(&q).map(|f| f.world_from_tool.pos.z).unwrap_or(z0 - 0.01);
        (z1 - z0) / 0.01
    }

    /// Seed 003 §III-D: the planar joints (rail, shoulder, elbow: the XY plane) and the
    /// wrist's compensation of them follow a cubic; z and θ alone follow a
    /// linear law. Lasts exactly `t`.
    pub(super) fn scara_move(&mut self, s: &Stmt, q_to: Vec<f64>, t: f64, kw: &str, text: String) {
        let Some(joints) = self.scara.joints() else { return };
        if let Some(m) = outside_limits(self.robot, &q_to) {
            self.err(Diagnostic::error(s.span.clone(), format!("{kw} puts {m}")));
            return;
        }
        let (Some(cubic), Some(linear)) = (self.law_for(s, Profile::Cubic, t), self.law_for(s, Profile::Linear, t))
        else {
            return;
        };
        let xy_moves = joints.planar.iter().any(|&i| q_to[i] != self.q[i]);
        let follows_the_plane = |i: usize| joints.planar.contains(&i) || (i == joints.roll && xy_moves);
        let laws: Vec<TimeLaw> = (0..q_to.len()).map(|i| if follows_the_plane(i) { cubic } else { linear }).collect();
        let from = self.q.clone();
        let Some(j) = self.sample_laws(s, &from, &q_to, &laws) else { return };
        let t0 = self.traj.times().last().copied().unwrap_or(0.0);
        let profile = match (xy_moves, kw) {
            (true, "HOME") => "cubic + linear (z)",
            (true, _) => "cubic",
            (false, _) => "linear",
        };
        let linear: Vec<bool> =
            (0..q_to.len()).map(|i| laws[i].profile() == Profile::Linear && q_to[i] != from[i]).collect();
        self.velocity_steps.push((t0, t0 + t, linear));
        self.record(s, kw, t0, t0 + t, profile, text);
        self.append(&j, t0);
    }
}
