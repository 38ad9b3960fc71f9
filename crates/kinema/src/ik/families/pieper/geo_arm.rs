//! The shoulder-plane and intersecting-shoulder arms by the geometric arm
//! kernel (`geo/spherical_arm.rs`), built once from the axes of the DH table
//! at θ = 0: its branches get this solver's labels, computed from the
//! returned angles and the geometry as the module documentation defines
//! them, and its misses this solver's words.

use nalgebra::Vector3;

use super::rows::{arm_g, intersecting_coeffs};
use super::{rx, ArmKind, Link, PieperIk, AXIS_TOL, BOUNDARY_TOL, ROOT_LABELS};
use crate::ik::geo::spherical_arm::{ArmBranch, ArmMiss, Bound, SphericalArm};
use crate::ik::geo::ShoulderKind;
use crate::ik::Unreachable;
use crate::math::{FastMath, Pose};

/// Arm solutions (θ1, θ2, θ3) with their labels.
type Arms = Vec<([f64; 3], &'static str)>;

/// The kernel of the first three rows of `links` for the arrangements it
/// solves (none for the others): axes 1–3 at θ = 0 in DH frame 0, free
/// joints at θ = offset (q = 0).
pub(super) fn kernel(links: &[Link; 6], kind: ArmKind) -> Option<SphericalArm> {
    let shoulder = match kind {
        ArmKind::ShoulderPlane => ShoulderKind::Parallel23,
        // a1 = 0: axis 2 meets axis 1 (z0) at frame 1's origin, (0, 0, d1).
        ArmKind::IntersectingShoulder => ShoulderKind::Intersecting12 { c: Vector3::new(0.0, 0.0, links[0].d) },
        ArmKind::ParallelShoulder | ArmKind::General => return None,
    };
    let (mut h, mut p) = ([Vector3::z(); 3], [Vector3::zeros(); 3]);
    let mut frame = Pose::IDENTITY;
    for (i, l) in links[..3].iter().enumerate() {
        (h[i], p[i]) = (frame.rot * Vector3::z(), frame.pos);
        frame = frame * Pose::new(rx(*l), Vector3::new(l.a, 0.0, l.d));
    }
    Some(SphericalArm::new(h, p, shoulder, [links[0].offset, links[1].offset]))
}

/// Whether a branch is the first of its pair (right shoulder, elbow 1, …):
/// the one with the larger `key`, the kernel's index 0 on a tie within
/// [`AXIS_TOL`] (the two coincide, or the joint is free and the kernel's
/// first branch is the one at q = 0); without a partner, the one whose key
/// is not negative.
fn first_of_pair(key: f64, index: usize, partner: Option<f64>) -> bool {
    match partner {
        Some(k) if (key - k).abs() <= AXIS_TOL * (1.0 + key.abs() + k.abs()) => index == 0,
        Some(k) => key > k,
        None => key >= 0.0,
    }
}

impl PieperIk {
    /// The arm solutions for wrist centre `p` by `kernel`, labelled and
    /// ordered as the module documentation says.
    pub(super) fn arm_by_kernel(&self, kernel: &SphericalArm, p: &Vector3<f64>) -> Result<Arms, Unreachable> {
        let mut arms: [ArmBranch; 4] = [([0.0; 3], 0, 0); 4];
        let n = kernel.solve(&self.w0, p, &mut arms).map_err(|miss| self.arm_miss(miss, p))?;
        let arms = &arms[..n];
        let mut out = Vec::with_capacity(n);
        if self.arm == ArmKind::ShoulderPlane {
            // Right: the wrist centre ahead of the shoulder along link 1's x axis.
            let mut ahead = [0.0; 4];
            let mut up = [false; 4];
            for (i, &(t, ..)) in arms.iter().enumerate() {
                let (s1, c1) = t[0].fast_sin_cos();
                ahead[i] = c1 * p.x + s1 * p.y;
                up[i] = self.elbow_up((s1, c1), t[1], p);
            }
            let mut ranked = [((false, false), 0); 4];
            for (i, &(_, si, _)) in arms.iter().enumerate() {
                let partner = arms.iter().position(|b| b.1 != si).map(|j| ahead[j]);
                ranked[i] = ((!first_of_pair(ahead[i], si, partner), !up[i]), i);
            }
            // Right before left, elbow up before down; the kernel's order otherwise.
            ranked[..n].sort_unstable();
            for &((left, down), i) in &ranked[..n] {
                let label = match (left, down) {
                    (false, false) => "shoulder-right/elbow-up",
                    (false, true) => "shoulder-right/elbow-down",
                    (true, false) => "shoulder-left/elbow-up",
                    (true, true) => "shoulder-left/elbow-down",
                };
                out.push((arms[i].0, label));
            }
        } else {
            // Elbow 1: θ3 = φ3 + δ of A·c3 + B·s3 = C, so A·s3 − B·c3 = R·sin δ ≥ 0.
            // Shoulder 1: θ2 = asin(Q/H) − ψ, so H·cos(θ2 + ψ) = g1·c2 − g2·s2 ≥ 0.
            let (a, b) = intersecting_coeffs(&self.links).1;
            let elbow = |t3: f64| {
                let (s3, c3) = t3.fast_sin_cos();
                a * s3 - b * c3
            };
            let shoulder = |t: [f64; 3]| {
                let (g, (s2, c2)) = (arm_g(&self.links, t[2]), t[1].fast_sin_cos());
                g.x * c2 - g.y * s2
            };
            for &(t, si, ei) in arms {
                let e_partner = arms.iter().find(|b| b.2 != ei).map(|b| elbow(b.0[2]));
                let s_partner = arms.iter().find(|b| b.2 == ei && b.1 != si).map(|b| shoulder(b.0));
                let e = usize::from(!first_of_pair(elbow(t[2]), ei, e_partner));
                let s = usize::from(!first_of_pair(shoulder(t), si, s_partner));
                out.push((t, ROOT_LABELS[s][e]));
            }
            out.sort_by_key(|(_, l)| (l.ends_with("elbow-2"), l.starts_with("shoulder-2")));
        }
        Ok(out)
    }

    /// Elbow up (shoulder-plane arm): the elbow point a2·(c2, s2) lies above
    /// the shoulder–wrist-centre line, measured along the base z axis.
    /// `(s1, c1)` are the sine and cosine of θ1, `t2` is θ2.
    fn elbow_up(&self, (s1, c1): (f64, f64), t2: f64, p: &Vector3<f64>) -> bool {
        let [l1, l2, ..] = self.links;
        let (s2, c2) = t2.fast_sin_cos();
        // The wrist centre in the arm plane, from axis 2.
        let u1 = c1 * p.x + s1 * p.y - l1.a;
        let u2 = (p.z - l1.d) / l1.sa;
        let cross = u1 * l2.a * s2 - u2 * l2.a * c2;
        let up_side = if u1.abs() > AXIS_TOL { u1.signum() } else { 1.0 };
        cross * up_side * l1.sa >= 0.0
    }

    /// The kernel's miss in this solver's words.
    fn arm_miss(&self, miss: ArmMiss, p: &Vector3<f64>) -> Unreachable {
        let [l1, l2, l3, l4, ..] = self.links;
        let l3len = l3.a.fast_hypot(l4.d * l3.sa);
        let (dmax, dmin) = (l2.a.abs() + l3len, (l2.a.abs() - l3len).abs());
        // The component of p − o1 along axis 2 is g3 = cα2·f3 + d2, i.e. −s1·px + c1·py = ℓ.
        let ell = -(l2.ca * (l3.d + l4.d * l3.ca) + l2.d) / l1.sa;
        match miss {
            ArmMiss::LateralOffset { by } => Unreachable::InsideExcluded {
                by,
                region: format!(
                    "cylinder of radius {:.4} m around axis 1 (the lateral offset of the arm), which the wrist centre cannot enter",
                    ell.abs()
                ),
            },
            ArmMiss::Elbow { branches } => {
                // The branch nearest to its bound in the arm plane names the boundary.
                let u2 = (p.z - l1.d) / l1.sa;
                let [one, two] = branches.map(|(t1, bound, _)| {
                    let (s1, c1) = t1.fast_sin_cos();
                    let dist = (c1 * p.x + s1 * p.y - l1.a).fast_hypot(u2);
                    match bound {
                        Bound::Outer => {
                            (dist - dmax, format!("outer reach of the arm ({dmax:.4} m from axis 2, in the arm plane)"))
                        }
                        Bound::Inner => {
                            (dmin - dist, format!("inner reach of the arm ({dmin:.4} m from axis 2, in the arm plane)"))
                        }
                    }
                });
                let boundary = if two.0 < one.0 { two.1 } else { one.1 };
                // The miss in the arm plane is not the distance to the workspace (the
                // plane turns with θ1), so it is not quoted. With |sin α1| = 1 every
                // wrist centre lies within |a1| + hypot(dmax, ℓ) of the point of axis 1
                // at height d1: the distance outside that sphere is a true distance.
                let sphere = (l1.sa.abs() - 1.0).abs() <= AXIS_TOL;
                let radius = l1.a.abs() + dmax.fast_hypot(ell);
                let outside = p.x.fast_hypot(p.y).fast_hypot(p.z - l1.d) - radius;
                if sphere && outside > BOUNDARY_TOL * (1.0 + radius) {
                    Unreachable::OutsideReach {
                        by: outside,
                        boundary: format!(
                            "outer reach of the arm (the sphere of radius {radius:.4} m around axis 1 at the \
                             shoulder's height that holds every wrist centre)"
                        ),
                    }
                } else {
                    Unreachable::NotReached { detail: format!("the wrist centre is outside the {boundary}") }
                }
            }
            ArmMiss::Shell { bound, radius, by } => {
                let side = if bound == Bound::Outer { "outer" } else { "inner" };
                Unreachable::OutsideReach { by, boundary: format!("{side} sphere of radius {radius:.4} m around the shoulder") }
            }
            // How far the shoulder misses is not a distance to the workspace: no figure.
            ArmMiss::Shoulder { .. } => Unreachable::NotReached {
                detail: "the wrist centre is outside the region it can reach at the required distance from the \
                         shoulder"
                    .into(),
            },
        }
    }
}
