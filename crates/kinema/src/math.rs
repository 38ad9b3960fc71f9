//! Spatial math: rigid transforms, orientation representations, pose errors.
//!
//! Everything is SI: metres and radians.
//!
//! Two roll-pitch-yaw conventions appear in the seed papers and both are
//! supported, always named explicitly through [`RpyConvention`]:
//!
//! * [`RpyConvention::Zyx`] — seed 000 eq. (6)–(7): R = Rz(yaw)·Ry(pitch)·Rx(roll).
//!   This is also URDF's `rpy` and the default everywhere in kinema.
//! * [`RpyConvention::Xyz`] — Corke's "arm" convention used by seed 004:
//!   R = Rx(a)·Ry(b)·Rz(c) for the triple (a, b, c).

use nalgebra::{Matrix3, Matrix4, Rotation3, UnitQuaternion, Vector3};

/// A rigid transform (rotation + translation), `child` expressed in `parent`.
///
/// Names of values of this type read like `base_from_tool`: the pose of the
/// tool frame expressed in the base frame, which maps tool coordinates to base
/// coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Rotation matrix (orthonormal, det +1).
    pub rot: Matrix3<f64>,
    /// Translation \[m\].
    pub pos: Vector3<f64>,
}

impl Default for Pose {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Pose {
    /// The identity transform.
    pub const IDENTITY: Pose =
        Pose { rot: Matrix3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0), pos: Vector3::new(0.0, 0.0, 0.0) };

    /// Builds a pose from a rotation matrix and a translation \[m\].
    pub fn new(rot: Matrix3<f64>, pos: Vector3<f64>) -> Self {
        Pose { rot, pos }
    }

    /// Pure translation \[m\].
    pub fn translation(x: f64, y: f64, z: f64) -> Self {
        Pose { rot: Matrix3::identity(), pos: Vector3::new(x, y, z) }
    }

    /// Pure rotation about x by `angle` \[rad\].
    pub fn rot_x(angle: f64) -> Self {
        Pose { rot: rot_x(angle), pos: Vector3::zeros() }
    }

    /// Pure rotation about y by `angle` \[rad\].
    pub fn rot_y(angle: f64) -> Self {
        Pose { rot: rot_y(angle), pos: Vector3::zeros() }
    }

    /// Pure rotation about z by `angle` \[rad\].
    pub fn rot_z(angle: f64) -> Self {
        Pose { rot: rot_z(angle), pos: Vector3::zeros() }
    }

    /// Translation `xyz` \[m\] and orientation `rpy` \[rad\] in the given convention.
    pub fn from_xyz_rpy(xyz: [f64; 3], rpy: [f64; 3], conv: RpyConvention) -> Self {
        Pose { rot: rpy_to_rot(rpy, conv), pos: Vector3::from(xyz) }
    }

    /// Composition `self · other`.
    #[inline]
    pub fn mul(&self, other: &Pose) -> Pose {
        Pose { rot: self.rot * other.rot, pos: self.pos + self.rot * other.pos }
    }

    /// The inverse transform.
    pub fn inverse(&self) -> Pose {
        let rt = self.rot.transpose();
        Pose { rot: rt, pos: -(rt * self.pos) }
    }

    /// Maps a point given in the child frame into the parent frame.
    pub fn transform_point(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.rot * p + self.pos
    }

    /// The 4×4 homogeneous matrix.
    pub fn to_matrix(&self) -> Matrix4<f64> {
        let mut m = Matrix4::identity();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.rot);
        m.fixed_view_mut::<3, 1>(0, 3).copy_from(&self.pos);
        m
    }

    /// The 4×4 homogeneous matrix as four rows (handy for JSON output).
    pub fn to_rows(&self) -> [[f64; 4]; 4] {
        let m = self.to_matrix();
        let mut rows = [[0.0; 4]; 4];
        for (r, row) in rows.iter_mut().enumerate() {
            for (c, v) in row.iter_mut().enumerate() {
                *v = m[(r, c)];
            }
        }
        rows
    }

    /// Builds a pose from a 4×4 homogeneous matrix. The rotation block is
    /// re-orthonormalised (nearest rotation) so small rounding in a file does
    /// not propagate. Returns `None` if the matrix is not finite, its last row
    /// is not `[0 0 0 1]`, or its rotation block is far from a rotation.
    pub fn from_matrix(m: &Matrix4<f64>) -> Option<Pose> {
        if m.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let last = [m[(3, 0)], m[(3, 1)], m[(3, 2)], m[(3, 3)]];
        if last.iter().zip([0.0, 0.0, 0.0, 1.0]).any(|(a, b)| (a - b).abs() > 1e-9) {
            return None;
        }
        let r: Matrix3<f64> = m.fixed_view::<3, 3>(0, 0).into();
        if (r.transpose() * r - Matrix3::identity()).norm() > 1e-6 || r.determinant() < 0.0 {
            return None;
        }
        let rot = Rotation3::from_matrix(&r).into_inner();
        Some(Pose { rot, pos: m.fixed_view::<3, 1>(0, 3).into() })
    }

    /// Orientation as a unit quaternion.
    pub fn quaternion(&self) -> UnitQuaternion<f64> {
        UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(self.rot))
    }

    /// Orientation as roll-pitch-yaw \[rad\] in the given convention.
    pub fn rpy(&self, conv: RpyConvention) -> [f64; 3] {
        rot_to_rpy(&self.rot, conv)
    }

    /// Orientation as an axis-angle vector (unit axis × angle in \[0, π\]) \[rad\].
    pub fn axis_angle(&self) -> Vector3<f64> {
        rot_to_axis_angle(&self.rot)
    }

    /// Whether every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.rot.iter().chain(self.pos.iter()).all(|v| v.is_finite())
    }
}

impl std::ops::Mul for Pose {
    type Output = Pose;
    fn mul(self, rhs: Pose) -> Pose {
        Pose::mul(&self, &rhs)
    }
}

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

/// The difference between two poses, as seen in the base frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseError {
    /// `target.pos − actual.pos` \[m\].
    pub translation: Vector3<f64>,
    /// Axis-angle vector of `target.rot · actual.rotᵀ` \[rad\]: the rotation that
    /// takes `actual` onto `target`, in base coordinates.
    pub rotation: Vector3<f64>,
}

impl PoseError {
    /// Distance between the two positions \[m\].
    pub fn position_norm(&self) -> f64 {
        self.translation.norm()
    }
    /// Angle of the rotation between the two orientations \[rad\].
    pub fn rotation_angle(&self) -> f64 {
        self.rotation.norm()
    }
}

/// The error that takes `actual` to `target` (both in the same frame).
pub fn pose_error(target: &Pose, actual: &Pose) -> PoseError {
    PoseError {
        translation: target.pos - actual.pos,
        rotation: rot_to_axis_angle(&(target.rot * actual.rot.transpose())),
    }
}

/// Sine and cosine of `x` together, fast and accurate.
///
/// Cody–Waite reduction by π/2 in three parts followed by Taylor polynomials
/// on \[−π/4, π/4\]; the error is a few ulp for |x| ≤ 1e5 (checked against
/// `f64::sin_cos` in the tests). Outside that range, and for non-finite input,
/// it defers to the standard library.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if !(x.abs() <= SIN_COS_RANGE) {
        return x.sin_cos();
    }
    sin_cos_kernel::<crate::chain::Plain>(x)
}

/// Largest |x| the fast [`sin_cos`] kernel handles itself.
pub(crate) const SIN_COS_RANGE: f64 = 1.0e5;

/// The branch-free core of [`sin_cos`], valid for |x| ≤ [`SIN_COS_RANGE`].
#[inline(always)]
pub(crate) fn sin_cos_kernel<M: crate::chain::Madd>(x: f64) -> (f64, f64) {
    // π/2 split into three parts, each exactly representable with trailing zeros.
    const PIO2_1: f64 = 1.570_796_326_734_125_6;
    const PIO2_2: f64 = 6.077_100_506_303_966e-11;
    const PIO2_3: f64 = 2.022_266_248_795_950_6e-21;
    const INV_PIO2: f64 = std::f64::consts::FRAC_2_PI;
    // Round to nearest without a libm call: adding 1.5·2^52 pushes the fraction out.
    const SHIFT: f64 = 6_755_399_441_055_744.0;
    let shifted = x * INV_PIO2 + SHIFT;
    let k = shifted - SHIFT;
    // k mod 4 sits in the low mantissa bits of `shifted` (2^51 + k, two's complement).
    let q = shifted.to_bits() as i64;
    let r = ((x - k * PIO2_1) - k * PIO2_2) - k * PIO2_3;
    let r2 = r * r;
    // Taylor series in r², Horner form: sin up to r^17, cos up to r^18.
    const SIN: [f64; 9] = [
        1.0,
        -1.0 / 6.0,
        1.0 / 120.0,
        -1.0 / 5040.0,
        1.0 / 362_880.0,
        -1.0 / 39_916_800.0,
        1.0 / 6_227_020_800.0,
        -1.0 / 1_307_674_368_000.0,
        1.0 / 355_687_428_096_000.0,
    ];
    const COS: [f64; 10] = [
        1.0,
        -0.5,
        1.0 / 24.0,
        -1.0 / 720.0,
        1.0 / 40_320.0,
        -1.0 / 3_628_800.0,
        1.0 / 479_001_600.0,
        -1.0 / 87_178_291_200.0,
        1.0 / 20_922_789_888_000.0,
        -1.0 / 6_402_373_705_728_000.0,
    ];
    let mut ps = SIN[8];
    for &k in SIN[..8].iter().rev() {
        ps = M::madd(ps, r2, k);
    }
    let mut pc = COS[9];
    for &k in COS[..9].iter().rev() {
        pc = M::madd(pc, r2, k);
    }
    let (sp, cp) = (r * ps, pc);
    // Quadrant k mod 4, branch-free: odd quadrants swap sine and cosine;
    // the sine is negated in quadrants 2, 3 and the cosine in 1, 2.
    let swap = q & 1 != 0;
    let (s, c) = if swap { (cp, sp) } else { (sp, cp) };
    let sign_s = 1.0 - 2.0 * (((q >> 1) & 1) as f64);
    let sign_c = 1.0 - 2.0 * ((((q + 1) >> 1) & 1) as f64);
    (s * sign_s, c * sign_c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn fast_sin_cos_matches_std() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut worst: f64 = 0.0;
        for i in 0..2_000_000 {
            let x: f64 = match i % 3 {
                0 => rng.random_range(-10.0..10.0),
                1 => rng.random_range(-1.0e5..1.0e5),
                _ => rng.random_range(-1e-3..1e-3),
            };
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
        }
        // 1e5 * 2^-52 ≈ 2e-11 is the conditioning of the argument itself; we do
        // much better than that thanks to the three-part reduction.
        assert!(worst < 4e-16, "worst abs error {worst}");
        for x in [0.0, -0.0, std::f64::consts::FRAC_PI_2, std::f64::consts::PI, 1e6, -3e7] {
            let (s, c) = sin_cos(x);
            assert!((s - x.sin()).abs() < 1e-15 && (c - x.cos()).abs() < 1e-15, "{x}");
        }
        assert!(sin_cos(f64::NAN).0.is_nan());
        assert!(sin_cos(f64::INFINITY).1.is_nan());
    }

    #[test]
    fn rpy_round_trip_both_conventions() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        for conv in [RpyConvention::Zyx, RpyConvention::Xyz] {
            for _ in 0..5000 {
                let t = [rng.random_range(-3.1..3.1), rng.random_range(-1.55..1.55), rng.random_range(-3.1..3.1)];
                let r = rpy_to_rot(t, conv);
                let back = rot_to_rpy(&r, conv);
                for k in 0..3 {
                    assert!((back[k] - t[k]).abs() < 1e-9, "{conv:?} {t:?} {back:?}");
                }
            }
        }
    }

    #[test]
    fn rpy_zyx_is_seed000_eq7() {
        // Seed 000 eq. (7), element by element, with α = yaw, β = pitch, γ = roll.
        let (a, b, g): (f64, f64, f64) = (0.3, -0.7, 1.9);
        let (ca, sa, cb, sb, cg, sg) = (a.cos(), a.sin(), b.cos(), b.sin(), g.cos(), g.sin());
        let eq7 = Matrix3::new(
            ca * cb,
            ca * sb * sg - sa * cg,
            ca * cg * sb + sa * sg,
            sa * cb,
            sa * sb * sg + ca * cg,
            sa * cg * sb - ca * sg,
            -sb,
            cb * sg,
            cb * cg,
        );
        assert!((rpy_to_rot([g, b, a], RpyConvention::Zyx) - eq7).norm() < 1e-14);
    }

    #[test]
    fn rpy_singularity_still_reconstructs() {
        for conv in [RpyConvention::Zyx, RpyConvention::Xyz] {
            let r = rpy_to_rot([0.4, std::f64::consts::FRAC_PI_2, -1.0], conv);
            let back = rpy_to_rot(rot_to_rpy(&r, conv), conv);
            assert!((r - back).norm() < 1e-9);
        }
    }

    #[test]
    fn pose_inverse_and_matrix_round_trip() {
        let p = Pose::from_xyz_rpy([0.1, -0.2, 0.3], [0.5, 0.2, -1.0], RpyConvention::Zyx);
        let i = p.mul(&p.inverse());
        assert!((i.rot - Matrix3::identity()).norm() < 1e-14 && i.pos.norm() < 1e-14);
        let back = Pose::from_matrix(&p.to_matrix()).unwrap();
        assert!((back.rot - p.rot).norm() < 1e-14 && (back.pos - p.pos).norm() < 1e-14);
        let mut bad = p.to_matrix();
        bad[(3, 0)] = 1.0;
        assert!(Pose::from_matrix(&bad).is_none());
    }

    #[test]
    fn axis_angle_closed_form_matches_quaternion_reference() {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let pi = std::f64::consts::PI;
        for i in 0..20_000 {
            let axis =
                Vector3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
            if axis.norm() < 1e-3 {
                continue;
            }
            let axis = axis.normalize();
            // Angles over the whole range, with many close to 0 and to π.
            let theta = match i % 4 {
                0 => rng.random_range(0.0..pi),
                1 => pi - 10f64.powf(rng.random_range(-12.0..-1.0)),
                2 => 10f64.powf(rng.random_range(-12.0..-1.0)),
                _ => pi,
            };
            let r = Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), theta).into_inner();
            let got = rot_to_axis_angle(&r);
            // Independent reference: nalgebra's quaternion of the same matrix.
            let reference = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r)).scaled_axis();
            assert!((got.norm() - theta).abs() < 1e-9, "θ = {theta}: got angle {}", got.norm());
            // At exactly π the axis sign is arbitrary: both ±u describe R.
            let same = (got - reference).norm() < 1e-7 || (theta > pi - 1e-7 && (got + reference).norm() < 1e-7);
            assert!(same, "θ = {theta}, axis {axis:?}: {got:?} vs {reference:?}");
            assert!((axis_angle_to_rot(&got) - r).norm() < 1e-9);
        }
        assert_eq!(rot_to_axis_angle(&Matrix3::identity()), Vector3::zeros());
    }

    #[test]
    fn pose_error_recovers_small_motion() {
        let a = Pose::from_xyz_rpy([0.1, 0.2, 0.3], [0.1, 0.2, 0.3], RpyConvention::Zyx);
        let w = Vector3::new(0.01, -0.02, 0.005);
        let b = Pose { rot: axis_angle_to_rot(&w) * a.rot, pos: a.pos + Vector3::new(0.001, 0.0, 0.0) };
        let e = pose_error(&b, &a);
        assert!((e.rotation - w).norm() < 1e-12);
        assert!((e.translation - Vector3::new(0.001, 0.0, 0.0)).norm() < 1e-15);
    }
}
