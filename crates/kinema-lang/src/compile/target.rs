//! Where a motion goes: named and written targets as joint values or world
//! poses, and the configuration that reaches a pose.

use kinema::math::{rpy_to_rot, Pose};
use kinema::nalgebra::Vector3;
use kinema::{ik, traj, RpyConvention};

use crate::ast::{Expr, Stmt, Target};
use crate::diag::Diagnostic;
use crate::units::Dim;

use super::eval::joint_dim;
use super::{Compiler, PosValue};

impl Compiler<'_> {
    /// The value of a target: joint values or a world pose (with the BASE applied).
    pub(super) fn resolve(&mut self, t: &Target) -> Option<PosValue> {
        match t {
            Target::Named(name) => {
                if let Some(v) = self.positions.get(&name.key) {
                    return Some(v.clone());
                }
                match self.robot.pose(&name.key) {
                    Ok(q) => Some(PosValue::Joint(q.to_vec())),
                    Err(_) => {
                        self.err(Diagnostic::error(name.span.clone(), format!("unknown position `{}`", name.text)));
                        None
                    }
                }
            }
            Target::Joint(items, _) => {
                let mut q = Vec::with_capacity(items.len());
                for (i, e) in items.iter().enumerate() {
                    q.push(self.value(e, joint_dim(self.robot, i), None)?);
                }
                Some(PosValue::Joint(q))
            }
            Target::Cart(items, _) => {
                let p = self.cart_values(items)?;
                Some(PosValue::Cart(self.base.mul(&p)))
            }
        }
    }

    /// The values of CART(...) in SI: x, y, z and roll, pitch, yaw (0 where not written).
    fn cart_numbers(&mut self, items: &[Expr]) -> Option<[f64; 6]> {
        let mut v = [0.0; 6];
        for (i, e) in items.iter().enumerate().take(6) {
            v[i] = self.value(e, if i < 3 { Dim::Length } else { Dim::Angle }, None)?;
        }
        Some(v)
    }

    fn cart_values(&mut self, items: &[Expr]) -> Option<Pose> {
        let v = self.cart_numbers(items)?;
        if items.len() == 3 {
            // Position only: keep the orientation the robot will have (in the base frame).
            let current = self.base.inverse().mul(&self.chain_end());
            return Some(Pose::new(current.rot, Vector3::new(v[0], v[1], v[2])));
        }
        Some(Pose::from_xyz_rpy([v[0], v[1], v[2]], [v[3], v[4], v[5]], RpyConvention::Zyx))
    }

    /// A frame for TOOL/BASE: written in the robot's own frame, not the current BASE.
    pub(super) fn resolve_frame(&mut self, t: &Target) -> Option<PosValue> {
        match t {
            Target::Cart(items, _) => {
                let v = self.cart_numbers(items)?;
                Some(PosValue::Cart(Pose::from_xyz_rpy([v[0], v[1], v[2]], [v[3], v[4], v[5]], RpyConvention::Zyx)))
            }
            other => self.resolve(other),
        }
    }

    pub(super) fn current_pose(&self) -> Pose {
        self.robot_tool.fk(&self.q).map(|f| f.world_from_tool).unwrap_or_else(|_| Pose::IDENTITY)
    }

    /// The pose a Cartesian motion goes to (joint targets by FK).
    pub(super) fn cart_target(&mut self, t: &Target, relative: bool) -> Option<Pose> {
        if relative {
            let Target::Cart(items, _) = t else { return None };
            let v = self.cart_numbers(items)?;
            let from = self.chain_end();
            // An offset in the BASE frame: translation added, rotation applied on the left.
            let rb = self.base.rot;
            let dpos = rb * Vector3::new(v[0], v[1], v[2]);
            let drot = rb * rpy_to_rot([v[3], v[4], v[5]], RpyConvention::Zyx) * rb.transpose();
            return Some(Pose::new(drot * from.rot, from.pos + dpos));
        }
        match self.resolve(t)? {
            PosValue::Cart(p) => Some(p),
            PosValue::Joint(q) => match self.robot_tool.fk(&q) {
                Ok(f) => Some(f.world_from_tool),
                Err(e) => {
                    self.err(Diagnostic::error(t.span(), e.to_string()));
                    None
                }
            },
        }
    }

    /// The configuration reaching `pose` nearest to the current one, within
    /// limits: the request every door makes (`ik::solve_target`, then
    /// `ik::pick_one`), so a program gets exactly what `kinema ik --q0` gives.
    pub(super) fn ik(&mut self, s: &Stmt, pose: &Pose) -> Option<Vec<f64>> {
        let robot = &self.robot_tool;
        let request = ik::IkRequest { q0: Some(&self.q), ..Default::default() };
        let result = ik::solve_target(robot, &ik::IkTarget::Pose(*pose), &request)
            .and_then(|answer| ik::pick_one(robot, answer.solver, answer.solutions, Some(&self.q)));
        match result {
            Ok(sol) => Some(sol.q),
            Err(e @ kinema::Error::Unreachable { .. }) if self.opts.skip_unreachable => {
                self.skipped(s, &e);
                None
            }
            Err(e) => {
                self.err(Diagnostic::error(s.span.clone(), format!("target unreachable: {e}")).with_hint(
                    "check the position against the robot's reach and the orientation against what the arm can take",
                ));
                None
            }
        }
    }

    /// With [`Options::skip_unreachable`]: a warning that statement `s` was
    /// skipped, its target being out of reach.
    pub(super) fn skipped(&mut self, s: &Stmt, why: &kinema::Error) {
        self.warn(Diagnostic::warning(s.span.clone(), format!("skipped: {why}")).with_hint(
            "the robot stays where it is and the program goes on (skip-unreachable); without it this is an error",
        ));
    }

    /// With [`Options::skip_unreachable`], whether the Cartesian motion of
    /// `s` ends at a pose out of reach (then skipped with a warning).
    pub(super) fn skip_if_unreachable(&mut self, s: &Stmt, to: &Pose) -> bool {
        if !self.opts.skip_unreachable {
            return false;
        }
        match traj::waypoints::reach(&self.robot_tool, to) {
            Err(e @ kinema::Error::Unreachable { .. }) => {
                self.skipped(s, &e);
                true
            }
            _ => false,
        }
    }
}
