//! The kinematics of a revolute chain as IK-Geo describes it: at q = 0, a
//! unit direction hᵢ and a point pᵢ on each joint axis in the world frame, and
//! the tool pose. Then FK(q) = E₁(q₁)·…·Eₙ(qₙ)·T_tool, where Eᵢ(θ) turns by θ
//! about the line (pᵢ, hᵢ) — a product of exponentials that does not care
//! whether the robot was described by DH rows, `general` joints or URDF.

use nalgebra::Vector3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::subproblems::rot;
use crate::error::{Error, Result};
use crate::kin::Frame;
use crate::math::Pose;
use crate::model::JointType;
use crate::robot::Robot;

type V3 = Vector3<f64>;

/// Axes and tool of a revolute chain at q = 0, in the world frame (the frame
/// of [`Robot::fk`], base transform included).
#[derive(Debug, Clone, PartialEq)]
pub struct Kinematics {
    /// Unit direction of each joint axis; q turns right-handed about it.
    pub h: Vec<V3>,
    /// A point on each joint axis \[m\] (the foot of the perpendicular from
    /// the tool point at q = 0).
    pub p: Vec<V3>,
    /// The tool pose at q = 0 (`world_from_tool`).
    pub tool: Pose,
}

impl Kinematics {
    /// Reads the axes off the base-frame Jacobian at q = 0: column i is
    /// [hᵢ × (p_tool − oᵢ); hᵢ] for a revolute joint, whatever the joint's
    /// sign or offset, so hᵢ is its lower half and p_tool + hᵢ × vᵢ is a point
    /// on the axis. Refuses prismatic joints, and checks the product of
    /// exponentials against [`Robot::fk`] at a few seeded configurations.
    ///
    /// # Examples
    /// ```
    /// use kinema::ik::geo::Kinematics;
    /// let robot = kinema::Robot::builtin("ur5")?;
    /// let kin = Kinematics::new(&robot)?;
    /// let q = [0.1, -0.7, 1.2, 0.3, -0.4, 2.0];
    /// let (a, b) = (kin.fk(&q), robot.fk(&q)?.world_from_tool);
    /// assert!((a.pos - b.pos).norm() < 1e-12 && (a.rot - b.rot).norm() < 1e-12);
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn new(robot: &Robot) -> Result<Self> {
        let name = robot.name();
        if let Some(i) = robot.joints().iter().position(|j| j.kind != JointType::Revolute) {
            return Err(Error::UnsupportedStructure {
                solver: "geometric".into(),
                robot: name.into(),
                reason: format!("joint {} is prismatic; the geometric solvers handle revolute joints only", i + 1),
            });
        }
        let n = robot.dof();
        let q0 = vec![0.0; n];
        let tool = robot.fk(&q0)?.world_from_tool;
        let jac = robot.jacobian(&q0, Frame::Base)?;
        let mut h = Vec::with_capacity(n);
        let mut p = Vec::with_capacity(n);
        for i in 0..n {
            let v = V3::new(jac[(0, i)], jac[(1, i)], jac[(2, i)]);
            let w = V3::new(jac[(3, i)], jac[(4, i)], jac[(5, i)]);
            let hi = w / w.norm();
            h.push(hi);
            p.push(tool.pos + hi.cross(&v));
        }
        let kin = Kinematics { h, p, tool };
        let mut rng = ChaCha8Rng::seed_from_u64(0x6765_6f6b);
        for _ in 0..3 {
            let q = robot.random_q(&mut rng);
            let (a, b) = (kin.fk(&q), robot.fk(&q)?.world_from_tool);
            let scale = 1.0 + b.pos.norm();
            let err = ((a.pos - b.pos).norm() / scale).max((a.rot - b.rot).norm());
            if !(err <= 1e-9) {
                return Err(Error::UnsupportedStructure {
                    solver: "geometric".into(),
                    robot: name.into(),
                    reason: format!("the axes read at q = 0 do not reproduce the forward kinematics (error {err:.3e})"),
                });
            }
        }
        Ok(kin)
    }

    /// Number of joints.
    pub fn dof(&self) -> usize {
        self.h.len()
    }

    /// Eᵢ(θ): the rigid motion turning by θ \[rad\] about axis i.
    pub fn joint_motion(&self, i: usize, theta: f64) -> Pose {
        screw(&self.h[i], &self.p[i], theta)
    }

    /// Forward kinematics as the product of exponentials,
    /// E₁(q₁)·…·Eₙ(qₙ)·T_tool (`world_from_tool`). Extra or missing joint
    /// values are ignored / taken as 0.
    pub fn fk(&self, q: &[f64]) -> Pose {
        let mut t = Pose::IDENTITY;
        for (i, qi) in q.iter().enumerate().take(self.dof()) {
            t = t * self.joint_motion(i, *qi);
        }
        t * self.tool
    }
}

/// The rigid motion turning by θ about the line through `p` along unit `h`.
pub(crate) fn screw(h: &V3, p: &V3, theta: f64) -> Pose {
    let r = rot(h, theta);
    Pose::new(r, p - r * p)
}

/// Whether two unit directions are parallel (or antiparallel) within `tol`.
pub(crate) fn parallel(a: &V3, b: &V3, tol: f64) -> bool {
    a.cross(b).norm() <= tol
}

/// Distance from point `x` to the line (p, unit h) \[m\].
pub(crate) fn distance_to_line(x: &V3, p: &V3, h: &V3) -> f64 {
    (x - p).cross(h).norm()
}

/// The point where two non-parallel lines (p1, h1), (p2, h2) meet, if their
/// distance is at most `tol` \[m\]: the midpoint of their common perpendicular.
pub(crate) fn intersection(p1: &V3, h1: &V3, p2: &V3, h2: &V3, tol: f64) -> Option<V3> {
    let n = h1.cross(h2);
    let nn = n.norm_squared();
    if nn <= tol * tol {
        return None;
    }
    let d = p2 - p1;
    if (d.dot(&n)).abs() / nn.sqrt() > tol {
        return None;
    }
    // p1 + s·h1 and p2 + t·h2 closest: s = (d × h2)·n / |n|², t = (d × h1)·n / |n|².
    let s = d.cross(h2).dot(&n) / nn;
    let t = d.cross(h1).dot(&n) / nn;
    Some(0.5 * ((p1 + h1 * s) + (p2 + h2 * t)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn intersection_finds_the_meeting_point_and_refuses_skew_lines() {
        let x = V3::new(0.3, -1.0, 2.0);
        let (h1, h2) = (V3::new(1.0, 2.0, 2.0) / 3.0, V3::new(0.0, 0.6, -0.8));
        let got = intersection(&(x + h1 * 1.5), &h1, &(x - h2 * 0.7), &h2, 1e-9).unwrap();
        assert!((got - x).norm() < 1e-14);
        let skew = x + h1.cross(&h2).normalize() * 1e-6;
        assert!(intersection(&skew, &h1, &(x - h2 * 0.7), &h2, 1e-9).is_none());
        assert!(intersection(&x, &h1, &V3::zeros(), &-h1, 1e-9).is_none());
        assert!(parallel(&h1, &-h1, 1e-12) && !parallel(&h1, &h2, 1e-3));
        assert!((distance_to_line(&V3::new(0.0, 1.0, 5.0), &V3::zeros(), &V3::z()) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn product_of_exponentials_equals_fk_on_the_builtin_revolute_robots() {
        use rand::Rng;
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut tried = 0;
        for name in crate::builtin_names() {
            let robot = Robot::builtin(name).unwrap();
            let Ok(kin) = Kinematics::new(&robot) else {
                assert!(robot.joint_types().contains('P'), "{name}");
                continue;
            };
            tried += 1;
            for _ in 0..500 {
                let q: Vec<f64> = (0..robot.dof()).map(|_| rng.random_range(-PI..PI)).collect();
                let (a, b) = (kin.fk(&q), robot.fk(&q).unwrap().world_from_tool);
                assert!((a.pos - b.pos).norm() < 1e-12 && (a.rot - b.rot).norm() < 1e-12, "{name} {q:?}");
            }
            for h in &kin.h {
                assert!((h.norm() - 1.0).abs() < 1e-15);
            }
        }
        assert!(tried >= 4, "{tried}");
    }
}
