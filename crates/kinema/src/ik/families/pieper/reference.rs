//! The arm solve of the shoulder-plane and intersecting-shoulder
//! arrangements as `pieper` computed it in its own DH formulas, before it
//! called the geometric kernel (`geo/spherical_arm.rs`); kept for the tests
//! only, as the reference the delegation is checked against: the same
//! solutions, labels, order and refusals.

use std::f64::consts::PI;

use nalgebra::Vector3;

use super::rows::{arm_g, intersecting_coeffs, theta1};
use super::{ArmKind, PieperIk, AXIS_TOL, BOUNDARY_TOL};
use crate::ik::Unreachable;
use crate::math::FastMath;

impl PieperIk {
    /// The arm solutions (θ1, θ2, θ3, label) of the former DH solve.
    pub(super) fn reference_arm(
        &self,
        p: &Vector3<f64>,
    ) -> std::result::Result<Vec<([f64; 3], &'static str)>, Unreachable> {
        match self.arm {
            ArmKind::ShoulderPlane => self.reference_shoulder_plane(p),
            _ => self.reference_pieper(p),
        }
    }

    fn reference_shoulder_plane(
        &self,
        p: &Vector3<f64>,
    ) -> std::result::Result<Vec<([f64; 3], &'static str)>, Unreachable> {
        let [l1, l2, l3, l4, ..] = self.links;
        // v = A3·(0, 0, d4) = (f1, f2, f3) in frame 2.
        // g = Tz(d2)·Tx(a2)·Rx(α2)·v; with sα2 = 0: g = (f1 + a2, cα2 f2, cα2 f3 + d2).
        let f3 = l3.d + l4.d * l3.ca;
        let g3 = l2.ca * f3 + l2.d;
        // The component of p − o1 along axis 2 (z1) is g3; z1 = Rz(θ1)·(0, −sα1, 0), so
        // −s1·px + c1·py = −g3/sα1 =: ℓ.
        let ell = -g3 / l1.sa;
        let rho = p.x.fast_hypot(p.y);
        let phi = p.y.fast_atan2(p.x);
        let mut lateral2 = rho * rho - ell * ell;
        if lateral2 < 0.0 {
            if rho < ell.abs() * (1.0 - BOUNDARY_TOL) - AXIS_TOL {
                return Err(Unreachable::InsideExcluded {
                    by: ell.abs() - rho,
                    region: format!(
                        "cylinder of radius {:.4} m around axis 1 (the lateral offset of the arm), which the wrist centre cannot enter",
                        ell.abs()
                    ),
                });
            }
            lateral2 = 0.0;
        }
        let lateral = lateral2.sqrt();
        let l3len = l3.a.fast_hypot(l4.d * l3.sa);
        let (a, b) = (2.0 * l2.a * l3.a, 2.0 * l2.a * l4.d * l3.sa);
        let r = a.fast_hypot(b);
        let k0 = l2.a * l2.a + l3len * l3len;
        let dmax = l2.a.abs() + l3len;
        let dmin = (l2.a.abs() - l3len).abs();
        let mut out = Vec::with_capacity(4);
        let mut worst: Option<(f64, String)> = None;
        for (sh, sign) in [("right", 1.0), ("left", -1.0)] {
            // θ1 with c1·px + s1·py = ±lateral and −s1·px + c1·py = ℓ.
            let t1 = if rho <= AXIS_TOL && ell.abs() <= AXIS_TOL {
                // Shoulder singularity: θ1 free, q1 = 0 (q1 = π for the other branch).
                l1.offset + if sign > 0.0 { 0.0 } else { PI }
            } else {
                phi - ell.fast_atan2(sign * lateral)
            };
            let (s1, c1) = t1.fast_sin_cos();
            let u1 = c1 * p.x + s1 * p.y - l1.a;
            let u2 = (p.z - l1.d) / l1.sa;
            let dist = u1.fast_hypot(u2);
            let mut cosd = (dist * dist - k0) / r;
            if cosd.is_nan() || cosd.abs() > 1.0 {
                let (by, boundary) = if dist > dmax {
                    (dist - dmax, format!("outer reach of the arm ({dmax:.4} m from axis 2, in the arm plane)"))
                } else {
                    (dmin - dist, format!("inner reach of the arm ({dmin:.4} m from axis 2, in the arm plane)"))
                };
                if by > BOUNDARY_TOL * (1.0 + dmax) {
                    if worst.as_ref().is_none_or(|w| by < w.0) {
                        worst = Some((by, boundary));
                    }
                    continue;
                }
                cosd = cosd.clamp(-1.0, 1.0);
            }
            let phi3 = b.fast_atan2(a);
            let delta = cosd.acos();
            for t3 in [phi3 + delta, phi3 - delta] {
                let (s3, c3) = t3.fast_sin_cos();
                let f1 = l3.a * c3 + l4.d * l3.sa * s3;
                let f2 = l3.a * s3 - l4.d * l3.sa * c3;
                let (g1, g2) = (f1 + l2.a, l2.ca * f2);
                let t2 = if g1.fast_hypot(g2) <= AXIS_TOL { l2.offset } else { u2.fast_atan2(u1) - g2.fast_atan2(g1) };
                // Elbow label: elbow point a2·(c2, s2) against the shoulder→wrist line.
                let (s2, c2) = t2.fast_sin_cos();
                let cross = u1 * l2.a * s2 - u2 * l2.a * c2;
                let up_side = if u1.abs() > AXIS_TOL { u1.signum() } else { 1.0 };
                let up = cross * up_side * l1.sa >= 0.0;
                let label = match (sh, up) {
                    ("right", true) => "shoulder-right/elbow-up",
                    ("right", false) => "shoulder-right/elbow-down",
                    (_, true) => "shoulder-left/elbow-up",
                    (_, false) => "shoulder-left/elbow-down",
                };
                out.push(([t1, t2, t3], label));
            }
        }
        if out.is_empty() {
            // The miss in the arm plane is not the distance to the workspace (the
            // plane turns with θ1), so it is not quoted. With |sin α1| = 1 every
            // wrist centre lies within |a1| + hypot(dmax, ℓ) of the point of axis 1
            // at height d1: the distance outside that sphere is a true distance.
            let sphere = (l1.sa.abs() - 1.0).abs() <= AXIS_TOL;
            let radius = l1.a.abs() + dmax.fast_hypot(ell);
            let outside = rho.fast_hypot(p.z - l1.d) - radius;
            return Err(match worst {
                Some(_) if sphere && outside > BOUNDARY_TOL * (1.0 + radius) => Unreachable::OutsideReach {
                    by: outside,
                    boundary: format!(
                        "outer reach of the arm (the sphere of radius {radius:.4} m around axis 1 at the shoulder's \
                         height that holds every wrist centre)"
                    ),
                },
                Some((_, boundary)) => {
                    Unreachable::NotReached { detail: format!("the wrist centre is outside the {boundary}") }
                }
                None => Unreachable::NotReached { detail: "the arm has no solution for the wrist centre".into() },
            });
        }
        // Order: elbow-up before elbow-down within each shoulder branch.
        out.sort_by_key(|(_, l)| (l.starts_with("shoulder-left"), l.ends_with("elbow-down")));
        Ok(out)
    }

    /// The intersecting- and parallel-shoulder arrangements (Pieper's two
    /// special cases).
    fn reference_pieper(&self, p: &Vector3<f64>) -> std::result::Result<Vec<([f64; 3], &'static str)>, Unreachable> {
        let [l1, l2, l3, l4, ..] = self.links;
        let z = p.z - l1.d;
        let r2 = p.x * p.x + p.y * p.y + z * z;
        let g_of = |t3: f64| arm_g(&self.links, t3);
        // Step 1: θ3 from an equation A·c3 + B·s3 = C.
        let (a, b, c, what) = match self.arm {
            ArmKind::IntersectingShoulder => {
                let (k, (a, b)) = intersecting_coeffs(&self.links);
                (a, b, r2 - k, "sphere")
            }
            _ => {
                // g3 = cα1·z (sα1 = 0): sα2·(a3 s3 − d4 sα3 c3) + cα2 f3 + d2 = cα1 z.
                let f3 = l3.d + l4.d * l3.ca;
                (-l2.sa * l4.d * l3.sa, l2.sa * l3.a, l1.ca * z - l2.ca * f3 - l2.d, "slab")
            }
        };
        let r = a.fast_hypot(b);
        let mut cosd = c / r;
        if cosd.is_nan() || cosd.abs() > 1.0 {
            let over = c.abs() - r;
            let (by, boundary) = if what == "sphere" {
                let (k, _) = intersecting_coeffs(&self.links);
                let (rmax, rmin) = ((k + r).max(0.0).sqrt(), (k - r).max(0.0).sqrt());
                let d = r2.sqrt();
                if d > rmax {
                    (d - rmax, format!("outer sphere of radius {rmax:.4} m around the shoulder"))
                } else {
                    (rmin - d, format!("inner sphere of radius {rmin:.4} m around the shoulder"))
                }
            } else {
                // cα1·(z − d1) = g3 ∈ [g3₀ − R, g3₀ + R] with g3₀ = cα2·f3 + d2.
                let g30 = l2.ca * (l3.d + l4.d * l3.ca) + l2.d;
                let (lo, hi) = (l1.ca * (g30 - r) + l1.d, l1.ca * (g30 + r) + l1.d);
                let (lo, hi) = (lo.min(hi), lo.max(hi));
                (over, format!("slab {lo:.4} m ≤ z ≤ {hi:.4} m (along axis 1) that the wrist centre can reach"))
            };
            if by > BOUNDARY_TOL * (1.0 + r2.sqrt() + r) {
                return Err(Unreachable::OutsideReach { by, boundary });
            }
            cosd = cosd.clamp(-1.0, 1.0);
        }
        let phi3 = b.fast_atan2(a);
        let delta = cosd.acos();
        let mut out = Vec::with_capacity(4);
        for (e, t3) in [(1, phi3 + delta), (2, phi3 - delta)] {
            let g = g_of(t3);
            let h = g.x.fast_hypot(g.y);
            let psi = g.y.fast_atan2(g.x);
            // Step 2: θ2 from H·sin(θ2 + ψ) = Q (intersecting) or H·cos(θ2 + ψ) = P (parallel).
            let (val, is_sin) = match self.arm {
                ArmKind::IntersectingShoulder => ((z - l1.ca * g.z) / l1.sa, true),
                _ => ((r2 - g.norm_squared() - l1.a * l1.a) / (2.0 * l1.a), false),
            };
            let t2s: Vec<f64> = if h <= AXIS_TOL {
                vec![l2.offset, l2.offset]
            } else {
                let mut x = val / h;
                if x.is_nan() || x.abs() > 1.0 {
                    let over = val.abs() - h;
                    if over > BOUNDARY_TOL * (1.0 + h + val.abs()) {
                        continue;
                    }
                    x = x.clamp(-1.0, 1.0);
                }
                if is_sin {
                    let s = x.asin();
                    vec![s - psi, PI - s - psi]
                } else {
                    let s = x.acos();
                    vec![s - psi, -s - psi]
                }
            };
            for (sh, t2) in t2s.into_iter().enumerate() {
                // Step 3: θ1 from (px, py) = Rz(θ1)·(w1, w2).
                let t1 = theta1(l1, &g, t2, p);
                const LABELS: [[&str; 2]; 2] =
                    [["shoulder-1/elbow-1", "shoulder-1/elbow-2"], ["shoulder-2/elbow-1", "shoulder-2/elbow-2"]];
                out.push(([t1, t2, t3], LABELS[sh.min(1)][e - 1]));
            }
        }
        if out.is_empty() {
            // How far |val| exceeds h is a mismatch of the arm equation (in m² / m
            // for the parallel shoulder), not a distance: no figure.
            return Err(Unreachable::NotReached {
                detail: "the wrist centre is outside the region it can reach at the required distance from the \
                         shoulder"
                    .into(),
            });
        }
        Ok(out)
    }
}
