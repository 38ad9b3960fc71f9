//! Rotation matrices: about one axis, from and to roll-pitch-yaw angles
//! and axis-angle vectors.

use nalgebra::{Matrix3, Rotation3, Vector3};

/// Rotation matrix about x by `a` \[rad\].
pub fn rot_x(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
}

/// Rotation matrix about y by `a` \[rad\].
pub fn rot_y(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
}

/// Rotation matrix about z by `a` \[rad\].
pub fn rot_z(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// Which roll-pitch-yaw convention a triple of angles follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RpyConvention {
    /// Seed 000 eq. (6): the triple is (roll γ, pitch β, yaw α) and
    /// R = Rz(α)·Ry(β)·Rx(γ) — fixed-axis X, then Y, then Z. Same as URDF `rpy`.
    #[default]
    Zyx,
    /// Corke's "arm" roll-pitch-yaw used by seed 004: the triple (a, b, c) means
    /// R = Rx(a)·Ry(b)·Rz(c).
    Xyz,
}

/// Rotation matrix from a roll-pitch-yaw triple \[rad\].
///
/// For [`RpyConvention::Zyx`] the triple is `[roll, pitch, yaw]` and
/// R = Rz(yaw)·Ry(pitch)·Rx(roll) (seed 000 eq. 6–7).
///
/// # Examples
/// ```
/// use kinema::math::{rpy_to_rot, rot_to_rpy, RpyConvention};
/// let r = rpy_to_rot([0.1, -0.4, 2.0], RpyConvention::Zyx);
/// let back = rot_to_rpy(&r, RpyConvention::Zyx);
/// assert!((back[0] - 0.1).abs() < 1e-12 && (back[1] + 0.4).abs() < 1e-12 && (back[2] - 2.0).abs() < 1e-12);
/// ```
pub fn rpy_to_rot(rpy: [f64; 3], conv: RpyConvention) -> Matrix3<f64> {
    match conv {
        RpyConvention::Zyx => rot_z(rpy[2]) * rot_y(rpy[1]) * rot_x(rpy[0]),
        RpyConvention::Xyz => rot_x(rpy[0]) * rot_y(rpy[1]) * rot_z(rpy[2]),
    }
}

/// Roll-pitch-yaw \[rad\] of a rotation matrix, inverse of [`rpy_to_rot`].
///
/// The middle angle is returned in \[−π/2, π/2\]. At the representation
/// singularity (middle angle ±π/2) the first angle is set to 0 and the whole
/// remaining rotation is put into the last one.
pub fn rot_to_rpy(r: &Matrix3<f64>, conv: RpyConvention) -> [f64; 3] {
    const EPS: f64 = 1e-12;
    match conv {
        RpyConvention::Zyx => {
            // r20 = -sin(pitch)
            let sp = (-r[(2, 0)]).clamp(-1.0, 1.0);
            let cp = r[(2, 1)].hypot(r[(2, 2)]);
            if cp > EPS {
                let roll = r[(2, 1)].atan2(r[(2, 2)]);
                let pitch = sp.atan2(cp);
                let yaw = r[(1, 0)].atan2(r[(0, 0)]);
                [roll, pitch, yaw]
            } else {
                // roll and yaw are coupled; put everything into yaw.
                let pitch = if sp > 0.0 { std::f64::consts::FRAC_PI_2 } else { -std::f64::consts::FRAC_PI_2 };
                let yaw = (-r[(0, 1)]).atan2(r[(1, 1)]);
                [0.0, pitch, yaw]
            }
        }
        RpyConvention::Xyz => {
            // r02 = sin(b)
            let sb = r[(0, 2)].clamp(-1.0, 1.0);
            let cb = r[(0, 0)].hypot(r[(0, 1)]);
            if cb > EPS {
                let a = (-r[(1, 2)]).atan2(r[(2, 2)]);
                let b = sb.atan2(cb);
                let c = (-r[(0, 1)]).atan2(r[(0, 0)]);
                [a, b, c]
            } else {
                let b = if sb > 0.0 { std::f64::consts::FRAC_PI_2 } else { -std::f64::consts::FRAC_PI_2 };
                let c = r[(1, 0)].atan2(r[(1, 1)]);
                [0.0, b, c]
            }
        }
    }
}

/// The roll-pitch-yaw triple of `r` nearest to `near` \[rad\].
///
/// A rotation has many triples: each angle may move by 2π, (a, b, c) equals
/// (a + π, π − b, c + π), and where the middle angle is ±π/2 only a sum or a
/// difference of the outer two is fixed. [`rot_to_rpy`] returns one of them;
/// interpolating between triples (seed 004 eq. 40) needs the one nearest to
/// the other end's, or the tool turns the long way round.
///
/// # Examples
/// ```
/// use kinema::math::{rot_to_rpy, rot_to_rpy_near, rpy_to_rot, RpyConvention};
/// // Seed 004's end orientation: pitch 1.5708 is 3.7e-6 rad past π/2.
/// let r = rpy_to_rot([0.0, 1.5708, 0.0], RpyConvention::Xyz);
/// assert!((rot_to_rpy(&r, RpyConvention::Xyz)[0].abs() - std::f64::consts::PI).abs() < 1e-6);
/// let near = rot_to_rpy_near(&r, RpyConvention::Xyz, [-0.66, 1.46, 1.21]);
/// assert!((near[0]).abs() < 1e-9 && (near[1] - 1.5708).abs() < 1e-9 && near[2].abs() < 1e-9);
/// ```
pub fn rot_to_rpy_near(r: &Matrix3<f64>, conv: RpyConvention, near: [f64; 3]) -> [f64; 3] {
    let [a, b, c] = rot_to_rpy(r, conv);
    let pi = std::f64::consts::PI;
    let mut candidates = vec![[a, b, c], [a + pi, pi - b, c + pi]];
    if b.cos().abs() < 1e-9 {
        // At the representation singularity only a + c (or a − c) is fixed:
        // c moves by σ per unit of a (Ry(±π/2) turns z onto ±x, or x onto ∓z).
        // Split the reference's gap between the two angles equally.
        let sigma = match conv {
            RpyConvention::Xyz => -b.sin().signum(),
            RpyConvention::Zyx => b.sin().signum(),
        };
        let c0 = last_angle(r, near[0], b, conv);
        let gap = (c0 - near[2] + pi).rem_euclid(2.0 * pi) - pi;
        let first = near[0] - sigma * gap / 2.0;
        candidates.push([first, b, last_angle(r, first, b, conv)]);
    }
    let unwrap = |t: [f64; 3]| -> [f64; 3] {
        let mut u = t;
        for (x, n) in u.iter_mut().zip(near) {
            *x += (2.0 * pi) * ((n - *x) / (2.0 * pi)).round();
        }
        u
    };
    let gap = |t: &[f64; 3]| t.iter().zip(near).map(|(x, n)| (x - n) * (x - n)).sum::<f64>();
    candidates.into_iter().map(unwrap).min_by(|x, y| gap(x).total_cmp(&gap(y))).unwrap_or([a, b, c])
}

/// The last angle of a triple whose first two are `first` and `middle`:
/// the angle of the rotation about z left once those two are taken out of `r`.
fn last_angle(r: &Matrix3<f64>, first: f64, middle: f64, conv: RpyConvention) -> f64 {
    let rz = match conv {
        // R = Rz(yaw)·Ry(pitch)·Rx(roll), the triple being [roll, pitch, yaw].
        RpyConvention::Zyx => r * rot_x(first).transpose() * rot_y(middle).transpose(),
        // R = Rx(a)·Ry(b)·Rz(c).
        RpyConvention::Xyz => rot_y(middle).transpose() * rot_x(first).transpose() * r,
    };
    rz[(1, 0)].atan2(rz[(0, 0)])
}

/// Axis-angle vector (axis × angle, angle in \[0, π\]) of a rotation matrix.
///
/// Closed form (no iteration): with v = (r21 − r12, r02 − r20, r10 − r01) =
/// 2 sin θ · u and trace − 1 = 2 cos θ, θ = atan2(|v|, trace − 1) and
/// u = v/|v|; within 1e-3 rad of θ = π, where v vanishes, the axis comes from
/// the symmetric part instead (rᵢᵢ = cos θ + (1 − cos θ)·uᵢ²).
///
/// # Examples
/// ```
/// use kinema::math::{axis_angle_to_rot, rot_to_axis_angle};
/// use kinema::nalgebra::Vector3;
/// let w = Vector3::new(0.3, -1.2, 2.5);
/// assert!((rot_to_axis_angle(&axis_angle_to_rot(&w)) - w).norm() < 1e-12);
/// ```
pub fn rot_to_axis_angle(r: &Matrix3<f64>) -> Vector3<f64> {
    let v = Vector3::new(r[(2, 1)] - r[(1, 2)], r[(0, 2)] - r[(2, 0)], r[(1, 0)] - r[(0, 1)]);
    let s = v.norm(); // 2 sin θ
    let c = r.trace() - 1.0; // 2 cos θ
    let theta = s.atan2(c);
    if theta < std::f64::consts::PI - 1e-3 {
        // θ/(2 sin θ) → 1/2 as θ → 0.
        let k = if s > 1e-12 { theta / s } else { 0.5 };
        return v * k;
    }
    // Near π: uᵢ² = (rᵢᵢ − cos θ)/(1 − cos θ); take the largest component and
    // the others from rᵢⱼ + rⱼᵢ = 2(1 − cos θ)·uᵢuⱼ.
    let cos_t = (0.5 * c).clamp(-1.0, 1.0);
    let one_minus = 1.0 - cos_t;
    let d = [r[(0, 0)], r[(1, 1)], r[(2, 2)]];
    let k = (0..3).max_by(|&a, &b| d[a].total_cmp(&d[b])).unwrap_or(0);
    let uk = ((d[k] - cos_t) / one_minus).max(0.0).sqrt();
    let mut u = Vector3::zeros();
    u[k] = uk;
    for j in 0..3 {
        if j != k {
            u[j] = (r[(k, j)] + r[(j, k)]) / (2.0 * one_minus * uk);
        }
    }
    let u = u.normalize();
    // The sign of the axis follows v (2 sin θ · u) where it is still measurable.
    let u = if u.dot(&v) < 0.0 { -u } else { u };
    u * theta
}

/// Rotation matrix from an axis-angle vector (axis × angle) \[rad\].
pub fn axis_angle_to_rot(v: &Vector3<f64>) -> Matrix3<f64> {
    Rotation3::new(*v).into_inner()
}
