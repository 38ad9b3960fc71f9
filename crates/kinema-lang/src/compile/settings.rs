//! Statements that set how later motions run: SPEED, VEL, ACC, JVEL, JACC,
//! PROFILE, REDUNDANCY, TOOL and BASE.

use kinema::ik::family::SelfMotionParameter;
use kinema::traj::SelfMotion;

use crate::ast::{Expr, Name, StmtKind, Target};
use crate::diag::Diagnostic;
use crate::units::Dim;

use super::check::known_bad;
use super::eval::eval;
use super::text::parse_profile;
use super::{Compiler, PosValue};

impl Compiler<'_> {
    /// SPEED p%: scales the speed of later motions.
    pub(super) fn set_speed(&mut self, e: &Expr) {
        if let Some(v) = self.value(e, Dim::Percent, None) {
            if known_bad(v, |v| v > 0.0 && v <= 1.0) {
                self.err(Diagnostic::error(e.span(), format!("SPEED must be in (0 %, 100 %], not {} %", v * 100.0)));
            } else {
                self.speed = v;
            }
        }
    }

    /// VEL, ACC (a Cartesian limit or the ACC override), JVEL and JACC (a
    /// joint limit): which one the unit of the value says.
    pub(super) fn set_limit(&mut self, kind: &StmtKind, e: &Expr) {
        if let Ok(q) = eval(e, &self.counters) {
            if known_bad(q.value, |v| v > 0.0 && (q.dim != Dim::Percent || v <= 1.0)) {
                self.err(Diagnostic::error(
                    e.span(),
                    format!("out of range: {} (must be positive, at most 100 %)", q.value),
                ));
                return;
            }
            match (kind, q.dim) {
                (StmtKind::Vel(_), Dim::LinVel) => self.cart.vel = q.value,
                (StmtKind::Vel(_), Dim::AngVel) => self.cart.rot_vel = q.value,
                (StmtKind::Acc(_), Dim::LinAcc) => self.cart.acc = q.value,
                (StmtKind::Acc(_), Dim::AngAcc) => self.cart.rot_acc = q.value,
                (StmtKind::Acc(_), Dim::Percent) if q.value > 0.0 && q.value <= 1.0 => self.acc_override = q.value,
                (StmtKind::JVel(_), Dim::AngVel) => self.jvel[0] = Some(q.value),
                (StmtKind::JVel(_), Dim::LinVel) => self.jvel[1] = Some(q.value),
                (StmtKind::JAcc(_), Dim::AngAcc) => self.jacc[0] = Some(q.value),
                (StmtKind::JAcc(_), Dim::LinAcc) => self.jacc[1] = Some(q.value),
                _ => {}
            }
        }
    }

    /// PROFILE name: the time law of later motions.
    pub(super) fn set_profile(&mut self, name: &Name) {
        if let Some(p) = parse_profile(&name.key) {
            self.profile = p;
        }
    }

    /// REDUNDANCY policy, or REDUNDANCY parameter = value.
    pub(super) fn set_redundancy(&mut self, mode: &Name, value: Option<&Expr>) {
        let policy = match value {
            None => SelfMotion::parse(SelfMotionParameter::Q3, &mode.key, 1.0).ok(),
            Some(e) => {
                let value = self.value(e, Dim::Angle, None);
                mode.key.parse().ok().zip(value).map(|(parameter, v)| SelfMotion::Fixed { parameter, value: Some(v) })
            }
        };
        if let Some(policy) = policy {
            self.self_motion = policy;
        }
    }

    /// TOOL frame: the robot of later motions carries this tool.
    pub(super) fn set_tool(&mut self, t: &Target) {
        if let Some(PosValue::Cart(p)) = self.resolve_frame(t) {
            match self.robot.with_tool(p) {
                Ok(r) => {
                    self.refit_scara(&r, t);
                    self.robot_tool = r;
                    self.tool_generation += 1;
                }
                Err(e) => self.err(Diagnostic::error(t.span(), format!("TOOL: {e}"))),
            }
        }
    }

    /// BASE frame: later Cartesian targets are written in it.
    pub(super) fn set_base(&mut self, t: &Target) {
        if let Some(PosValue::Cart(p)) = self.resolve_frame(t) {
            self.base = p;
        }
    }
}
