//! The arm of a 6R robot with a spherical wrist: the first three joints,
//! which must carry the wrist centre w (at q = 0) to the target's wrist
//! centre W, E₁E₂E₃(w) = W. One closed form, [`SphericalArm`], built once per
//! robot from its first three axes and used by
//! [`SphericalWristIk`](super::SphericalWristIk), by
//! [`TwoIntersectingSearchIk`](super::TwoIntersectingSearchIk) (with the
//! point where axes 5 and 6 meet as w) and by the DH solver `pieper` (with
//! the axes of its table at θ = 0).
//!
//! * **Axes 2 ∥ 3** ([`ShoulderKind::Parallel23`]): turning about lines
//!   parallel to h₂ keeps the component along h₂, so
//!   h₂ᵀ·E₁⁻¹(W) = h₂ᵀ·w — subproblem 4 in q₁ (*shoulder* 1, 2). Then
//!   V = E₁⁻¹(W) = E₂E₃(w) and E₂ fixes p₂: |E₃(w) − p₂| = |V − p₂|,
//!   subproblem 3 in q₃ (*elbow* 1, 2); q₂ by subproblem 1.
//! * **Axes 1 and 2 meet at c** ([`ShoulderKind::Intersecting12`]): E₁, E₂
//!   fix c, so |E₃(w) − c| = |W − c| gives q₃ by subproblem 3 (*elbow*
//!   1, 2), and rot(h₁, q₁)·rot(h₂, q₂)·(E₃(w) − c) = W − c gives (q₁, q₂) by
//!   subproblem 2 (*shoulder* 1, 2).
//!
//! **Free joints** (conventions; the angles are the caller's, `free`):
//! W on axis 1 leaves q₁ free. With axes 2 ∥ 3 the arm then reaches either
//! way, so there are two shoulder branches, q₁ = `free[0]` and
//! `free[0]` + π, each with its elbows (a regular target has two as well);
//! with axes 1 and 2 meeting, q₁ = `free[0]`. E₃(w) on axis 2 (the elbow
//! folded onto the shoulder) leaves q₂ free: q₂ = `free[1]`.
//!
//! **Misses** ([`ArmMiss`]) say which bound the wrist centre is beyond and
//! by how much, as data; each solver words them its own way.

use std::f64::consts::PI;

use nalgebra::Vector3;

use super::spherical::ShoulderKind;
use super::subproblems::{rotate, sp1_angle, sp2, sp3, sp4};

type V3 = Vector3<f64>;

/// Below this distance \[m\] from its axis a point is on it: the joint that
/// turns about that axis is free.
const ON_AXIS: f64 = 1e-12;

/// The side of a reach interval the wrist centre is beyond.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Bound {
    /// Too far: beyond the largest distance the elbow makes.
    Outer,
    /// Too near: within the smallest distance the elbow makes.
    Inner,
}

/// Why the arm cannot carry the wrist centre to W (distances in m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum ArmMiss {
    /// Axes 2 ∥ 3: W is nearer to axis 1 than the arm's lateral offset
    /// (the component along h₂ that no joint changes) allows, by `by`.
    LateralOffset {
        /// How far inside \[m\].
        by: f64,
    },
    /// Axes 2 ∥ 3: for both shoulder branches, |V − p₂| is outside what the
    /// elbow makes. Per branch: its q₁ \[rad\], the bound passed, and by how
    /// much (in |E₃(w) − p₂|) \[m\].
    Elbow {
        /// (q₁, bound, by) of shoulder branch 1 and 2.
        branches: [(f64, Bound, f64); 2],
    },
    /// Axes 1 and 2 meet at c: |W − c| is outside the shell the elbow
    /// makes, beyond `bound` (whose radius is `radius`) by `by`.
    Shell {
        /// The bound passed.
        bound: Bound,
        /// Its radius around c \[m\].
        radius: f64,
        /// How far beyond \[m\].
        by: f64,
    },
    /// Axes 1 and 2 meet: the shell is met, but for no elbow can axes 1 and
    /// 2 turn E₃(w) onto W; subproblem 2's smallest miss \[m\].
    Shoulder {
        /// The miss.
        by: f64,
    },
}

impl ArmMiss {
    /// The one figure of the miss \[m\]: the smallest over branches.
    pub(crate) fn by(&self) -> f64 {
        match *self {
            ArmMiss::LateralOffset { by } | ArmMiss::Shell { by, .. } | ArmMiss::Shoulder { by } => by,
            ArmMiss::Elbow { branches } => branches[0].2.min(branches[1].2),
        }
    }
}

/// An arm branch: (\[q₁, q₂, q₃\] \[rad\], shoulder index, elbow index).
pub(crate) type ArmBranch = ([f64; 3], usize, usize);

/// The first three axes of a spherical-wrist arm, prepared once per robot.
#[derive(Debug, Clone)]
pub(crate) struct SphericalArm {
    /// Unit directions of axes 1–3 at q = 0.
    h: [V3; 3],
    /// A point on each of axes 1–3 at q = 0 \[m\].
    p: [V3; 3],
    shoulder: ShoulderKind,
    /// The angles q₁ and q₂ take where they are free \[rad\].
    free: [f64; 2],
}

impl SphericalArm {
    /// The arm of axes (`p`ᵢ, `h`ᵢ) in the arrangement `shoulder` (which
    /// the caller has tested), with `free` the angles of joints 1 and 2
    /// where the target leaves them free \[rad\].
    pub(crate) fn new(h: [V3; 3], p: [V3; 3], shoulder: ShoulderKind, free: [f64; 2]) -> Self {
        SphericalArm { h, p, shoulder, free }
    }

    /// The arrangement of the axes.
    pub(crate) fn shoulder(&self) -> ShoulderKind {
        self.shoulder
    }

    /// The branches that carry the point `w` (at q = 0) to `wt` into
    /// `arms`: how many (up to 4), or why there is none.
    pub(crate) fn solve(&self, w: &V3, wt: &V3, arms: &mut [ArmBranch; 4]) -> Result<usize, ArmMiss> {
        match self.shoulder {
            ShoulderKind::Parallel23 => self.parallel23(w, wt, arms),
            ShoulderKind::Intersecting12 { c } => self.intersecting12(&c, w, wt, arms),
        }
    }

    fn parallel23(&self, w: &V3, wt: &V3, arms: &mut [ArmBranch; 4]) -> Result<usize, ArmMiss> {
        let ([h1, h2, h3], [p1, p2, p3]) = (&self.h, &self.p);
        let s1 = sp4(h2, h1, &(wt - p1), h2.dot(&(w - p1)));
        if !s1.exact {
            return Err(ArmMiss::LateralOffset { by: s1.miss });
        }
        // One root means q₁ does not enter: W is on axis 1 and q₁ is free.
        let t1s = match *s1.as_slice() {
            [a, b] => [a, b],
            _ => [-self.free[0], -self.free[0] - PI],
        };
        let mut n = 0;
        let mut misses = [(0.0, Bound::Outer, 0.0); 2];
        for (si, &t1) in t1s.iter().enumerate() {
            // V = E₁⁻¹(W): rot(h₁, −q₁) = rot(h₁, t₁).
            let v = p1 + rotate(h1, t1, &(wt - p1));
            let d = (v - p2).norm();
            let s3 = sp3(h3, &(w - p3), &(p2 - p3), d);
            if !s3.exact {
                let reached = (p3 + rotate(h3, s3.first(), &(w - p3)) - p2).norm();
                misses[si] = (-t1, if d > reached { Bound::Outer } else { Bound::Inner }, s3.miss);
                continue;
            }
            for (ei, &q3) in s3.as_slice().iter().enumerate() {
                let x = p3 + rotate(h3, q3, &(w - p3));
                let q2 = self.angle_or_free(1, &(x - p2), &(v - p2));
                arms[n] = ([-t1, q2, q3], si, ei);
                n += 1;
            }
        }
        if n == 0 {
            return Err(ArmMiss::Elbow { branches: misses });
        }
        Ok(n)
    }

    fn intersecting12(&self, c: &V3, w: &V3, wt: &V3, arms: &mut [ArmBranch; 4]) -> Result<usize, ArmMiss> {
        let ([h1, h2, h3], p3) = (&self.h, &self.p[2]);
        let (wc, d) = (wt - c, (wt - c).norm());
        let s3 = sp3(h3, &(w - p3), &(c - p3), d);
        if !s3.exact {
            let radius = (p3 + rotate(h3, s3.first(), &(w - p3)) - c).norm();
            let bound = if d > radius { Bound::Outer } else { Bound::Inner };
            return Err(ArmMiss::Shell { bound, radius, by: s3.miss });
        }
        let w_on_axis1 = (wc - h1 * h1.dot(&wc)).norm() <= ON_AXIS;
        let mut n = 0;
        let mut miss = f64::INFINITY;
        for (ei, &q3) in s3.as_slice().iter().enumerate() {
            // |x − c| = |W − c| up to the rounding subproblem 3 accepts (relative to
            // the arm's lengths): made exact, so that subproblem 2 does not refuse a
            // wrist centre near the shoulder point for rounding relative to |W − c|.
            let xc = p3 + rotate(h3, q3, &(w - p3)) - c;
            let xc = if xc.norm() > 0.0 { xc * (d / xc.norm()) } else { xc };
            let (a1, a2) = sp2(h1, &wc, h2, &xc);
            if !a1.exact {
                miss = miss.min(a1.miss);
                continue;
            }
            for (si, (&t1, &q2)) in a1.as_slice().iter().zip(a2.as_slice()).enumerate() {
                // On its axis a vector fixes no angle: the free joint takes its convention.
                let q1 = if w_on_axis1 { self.free[0] } else { -t1 };
                let q2 = if self.off_axis(1, &xc) { q2 } else { self.free[1] };
                arms[n] = ([q1, q2, q3], si, ei);
                n += 1;
            }
        }
        if n == 0 {
            return Err(ArmMiss::Shoulder { by: miss });
        }
        Ok(n)
    }

    /// Whether `v` has a part of more than [`ON_AXIS`] normal to axis `i`.
    fn off_axis(&self, i: usize, v: &V3) -> bool {
        let h = &self.h[i];
        (v - h * h.dot(v)).norm() > ON_AXIS
    }

    /// Subproblem 1's angle turning `from` to `to` about axis `i`, or the
    /// joint's free angle when `from` lies on that axis.
    fn angle_or_free(&self, i: usize, from: &V3, to: &V3) -> f64 {
        if self.off_axis(i, from) {
            sp1_angle(&self.h[i], from, to)
        } else {
            self.free[i]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ik::geo::kin::screw;

    /// A PUMA-like arm without lateral offset: axis 1 vertical, axes 2 ∥ 3 horizontal.
    fn puma_like(free: [f64; 2]) -> (SphericalArm, V3) {
        let (z, y) = (V3::z(), V3::y());
        let p = [V3::zeros(), V3::new(0.0, 0.0, 0.67), V3::new(0.43, 0.0, 0.67)];
        (SphericalArm::new([z, y, y], p, ShoulderKind::Parallel23, free), V3::new(0.45, 0.0, 1.1))
    }

    #[test]
    fn a_wrist_centre_on_axis_1_gives_both_shoulder_branches() {
        for free in [[0.0, 0.0], [0.4, -0.2]] {
            let (arm, w) = puma_like(free);
            let wt = V3::new(0.0, 0.0, 0.9);
            let mut arms = [([0.0; 3], 0, 0); 4];
            let n = arm.solve(&w, &wt, &mut arms).unwrap();
            assert_eq!(n, 4);
            for &(q, si, _) in &arms[..n] {
                assert_eq!(q[0], free[0] + PI * si as f64, "{q:?}");
                let reached = (0..3).rev().fold(w, |v, i| screw(&arm.h[i], &arm.p[i], q[i]).transform_point(&v));
                assert!((reached - wt).norm() < 1e-12, "{q:?}: {reached:?}");
            }
        }
    }

    #[test]
    fn misses_say_which_bound_and_by_how_much() {
        let (arm, w) = puma_like([0.0; 2]);
        let mut arms = [([0.0; 3], 0, 0); 4];
        // Beyond the stretched arm (0.43 + hypot(0.02, 0.43) from axis 2): both shoulders miss outward.
        let Err(ArmMiss::Elbow { branches }) = arm.solve(&w, &V3::new(2.0, 0.0, 0.67), &mut arms) else { panic!() };
        assert!(branches.iter().all(|b| b.1 == Bound::Outer && b.2 > 1.0), "{branches:?}");
        // Near the shoulder point of an intersecting arm: inside the inner sphere.
        let c = V3::new(0.0, 0.0, 0.67);
        let p = [V3::zeros(), c, V3::new(0.43, 0.0, 0.67)];
        let arm = SphericalArm::new([V3::z(), V3::y(), V3::y()], p, ShoulderKind::Intersecting12 { c }, [0.0; 2]);
        let w = V3::new(0.6, 0.0, 1.1);
        let miss = arm.solve(&w, &(c + V3::new(0.0, 0.0, 0.01)), &mut arms);
        let Err(ArmMiss::Shell { bound: Bound::Inner, radius, by }) = miss else { panic!("{miss:?}") };
        let inner = (w - p[2]).norm() - 0.43;
        assert!((radius - inner).abs() < 1e-12 && (by - (inner - 0.01)).abs() < 1e-12, "{radius} {by}");
    }
}
