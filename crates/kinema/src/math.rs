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
        Some(Pose { rot: nearest_rotation(r), pos: m.fixed_view::<3, 1>(0, 3).into() })
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

/// The rotation nearest to `r` (its polar factor), for a matrix already
/// within about 1e-6 of a rotation (‖rᵀr − I‖ < 1e-6, which
/// [`Pose::from_matrix`] checks first). Newton–Schulz iteration
/// X ← X·(3I − XᵀX)/2 squares the error each step, so three steps reach
/// rounding level from that distance without the eigen-solver a general
/// projection needs.
fn nearest_rotation(r: Matrix3<f64>) -> Matrix3<f64> {
    let mut x = r;
    for _ in 0..3 {
        x = x * (Matrix3::identity() * 3.0 - x.transpose() * x) * 0.5;
    }
    x
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

/// tan(π/8) and hi + lo splits of π/4, π/2 and π (the reductions of [`atan2`]).
const TAN_PI_8: f64 = 0.414_213_562_373_095_03;
const PIO4_HI: f64 = std::f64::consts::FRAC_PI_4;
const PIO4_LO: f64 = 3.061_616_997_868_383e-17;
const PIO2_HI: f64 = std::f64::consts::FRAC_PI_2;
const PIO2_LO: f64 = 6.123_233_995_736_766e-17;
const PI_HI: f64 = std::f64::consts::PI;
const PI_LO: f64 = 1.224_646_799_147_353_2e-16;

/// z³·P(z²) for |z| ≤ tan(π/8): atan(z) = z + atan_tail(z) (the polynomial of
/// [`atan2`], shared with [`atan2_lanes`] so both round alike).
#[inline(always)]
fn atan_tail(z: f64) -> f64 {
    const C: [f64; 11] = ATAN_POLY;
    let s = z * z;
    let (s2, s4) = (s * s, s * s * (s * s));
    let p = (C[0] + C[1] * s + (C[2] + C[3] * s) * s2)
        + (C[4] + C[5] * s + (C[6] + C[7] * s) * s2) * s4
        + (C[8] + C[9] * s + C[10] * s2) * (s4 * s4);
    z * s * p
}

/// Coefficients of P in [`atan2`]: atan(z) = z + z³·P(z²) for |z| ≤ tan(π/8).
const ATAN_POLY: [f64; 11] = [
    -0.333_333_333_333_333_3,
    0.199_999_999_999_955_2,
    -0.142_857_142_846_665_42,
    0.111_111_110_152_563_61,
    -0.090_909_045_781_239_03,
    0.076_921_831_908_260_87,
    -0.066_645_114_473_819_48,
    0.058_581_489_128_022_1,
    -0.050_854_497_379_402_6,
    0.039_231_658_295_587_19,
    -0.019_176_887_119_062_26,
];

/// atan2(y, x), fast and accurate: the same quadrant conventions as
/// [`f64::atan2`] and an error of at most a few ulp (checked against it in the
/// tests), about twice as fast as the C library's.
///
/// The ratio of the smaller to the larger of |x|, |y| is reduced to
/// |z| ≤ tan(π/8) (via atan(t) = π/4 + atan((t − 1)/(t + 1)) above it); there
/// atan(z) = z + z³·P(z²) with P of degree 10, fitted for this crate at
/// Chebyshev nodes in 50-digit arithmetic (relative error of the fit below
/// 1e-17). Zero, infinite and NaN arguments go to the standard library.
#[inline]
pub fn atan2(y: f64, x: f64) -> f64 {
    let (ax, ay) = (x.abs(), y.abs());
    let swap = ay > ax;
    let (num, den) = if swap { (ax, ay) } else { (ay, ax) };
    if !(den > 0.0 && den < f64::INFINITY) {
        return y.atan2(x);
    }
    let big = num > TAN_PI_8 * den;
    let z = if big { (num - den) / (num + den) } else { num / den };
    let poly = atan_tail(z);
    let mut r = if big { PIO4_HI + (z + (poly + PIO4_LO)) } else { z + poly };
    if swap {
        r = (PIO2_HI - r) + PIO2_LO;
    }
    if x.is_sign_negative() {
        r = (PI_HI - r) + PI_LO;
    }
    r.copysign(y)
}

/// [`atan2`] of `L` independent pairs at once, lane `i` = `atan2(y[i], x[i])`
/// bit for bit. Written without branches on the data (selections by 0/1
/// factors and conditional moves) so the compiler evaluates the lanes in SIMD
/// registers; the IK kernels gather their independent angles into one call.
/// Lanes with a zero, infinite or NaN argument are redone by [`atan2`].
#[inline(always)]
pub fn atan2_lanes<const L: usize>(y: [f64; L], x: [f64; L]) -> [f64; L] {
    let mut out = [0.0; L];
    let mut special = false;
    for i in 0..L {
        let (ax, ay) = (x[i].abs(), y[i].abs());
        let swap = ay > ax;
        let num = if swap { ax } else { ay };
        let den = if swap { ay } else { ax };
        special |= !(den > 0.0 && den < f64::INFINITY);
        // b = 1 above tan(π/8): z = (num − den)/(num + den), else num/den (b·den
        // and b·num are exact, so both forms equal the scalar ones bit for bit).
        let b = if num > TAN_PI_8 * den { 1.0 } else { 0.0 };
        let z = (num - b * den) / (den + b * num);
        let poly = atan_tail(z);
        let r = b * PIO4_HI + (z + (poly + b * PIO4_LO));
        let r = if swap { (PIO2_HI - r) + PIO2_LO } else { r };
        let r = if x[i].is_sign_negative() { (PI_HI - r) + PI_LO } else { r };
        out[i] = r.copysign(y[i]);
    }
    if special {
        for i in 0..L {
            let den = x[i].abs().max(y[i].abs());
            if !(den > 0.0 && den < f64::INFINITY) {
                out[i] = atan2(y[i], x[i]);
            }
        }
    }
    out
}

/// [`atan2_lanes`] of 8 pairs, run with 256-bit vectors where the CPU has
/// AVX2 (checked at run time; the same operations in the same order, so the
/// result is the same bit for bit on either path).
#[inline]
pub fn atan2_x8(y: [f64; 8], x: [f64; 8]) -> [f64; 8] {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2 (checked just above).
            return unsafe { atan2_x8_avx2(y, x) };
        }
    }
    atan2_lanes(y, x)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn atan2_x8_avx2(y: [f64; 8], x: [f64; 8]) -> [f64; 8] {
    atan2_lanes(y, x)
}

/// √(x² + y²) without the C library's `hypot` cost: the plain formula where
/// it cannot overflow or underflow (error ≤ 1 ulp), `hypot` elsewhere.
#[inline]
pub fn hypot(x: f64, y: f64) -> f64 {
    let r = (x * x + y * y).sqrt();
    if r < 1e150 && r > 1e-150 {
        r
    } else {
        x.hypot(y)
    }
}

/// Method forms of [`atan2`], [`hypot`] and [`sin_cos`], for the solvers' kernels.
pub(crate) trait FastMath {
    /// [`atan2`]`(self, x)`.
    fn fast_atan2(self, x: f64) -> f64;
    /// [`hypot`]`(self, y)`.
    fn fast_hypot(self, y: f64) -> f64;
    /// [`sin_cos`]`(self)`.
    fn fast_sin_cos(self) -> (f64, f64);
}

impl FastMath for f64 {
    #[inline]
    fn fast_atan2(self, x: f64) -> f64 {
        atan2(self, x)
    }
    #[inline]
    fn fast_hypot(self, y: f64) -> f64 {
        hypot(self, y)
    }
    #[inline]
    fn fast_sin_cos(self) -> (f64, f64) {
        sin_cos(self)
    }
}

/// Sine and cosine of `x` together, fast and accurate.
///
/// Cody–Waite reduction by π/2 in three parts followed by Taylor polynomials
/// on \[−π/4, π/4\] evaluated by Estrin's scheme. For |x| ≤ 1e5 the error
/// against `f64::sin_cos` is at most 2.1 ulp of the result over 8·10⁶ random
/// arguments (0.45 % of the results differ by more than 1 ulp; the tests pin
/// 2.5 ulp). Horner's scheme was a little more accurate (2.0 ulp, 0.06 %) but
/// twice as deep a dependency chain, which starts every forward kinematics.
/// Outside that range, and for non-finite input, it defers to the standard
/// library.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if !(x.abs() <= SIN_COS_RANGE) {
        return x.sin_cos();
    }
    sin_cos_kernel::<Plain>(x)
}

/// Largest |x| the fast [`sin_cos`] kernel handles itself.
pub(crate) const SIN_COS_RANGE: f64 = 1.0e5;

// Constants of the sine/cosine kernel, shared by [`sin_cos_kernel`] and its
// four-lane AVX2 form (`lanes::A4::sin_cos`), so both round alike.

/// π/2 split into three parts, each exactly representable with trailing zeros (Cody–Waite).
pub(crate) const PIO2_1: f64 = 1.570_796_326_734_125_6;
pub(crate) const PIO2_2: f64 = 6.077_100_506_303_966e-11;
pub(crate) const PIO2_3: f64 = 2.022_266_248_795_950_6e-21;
/// 1.5·2^52: adding it rounds to an integer without a libm call (the fraction is pushed out).
pub(crate) const RINT_SHIFT: f64 = 6_755_399_441_055_744.0;
/// Taylor coefficients of sin(r)/r in r², constant term first (up to r^17).
pub(crate) const SIN_POLY: [f64; 9] = [
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
/// Taylor coefficients of cos(r) in r², constant term first (up to r^18).
pub(crate) const COS_POLY: [f64; 10] = [
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

/// `a·b + c`, plain on the portable path, fused where the CPU has FMA.
pub(crate) trait Madd {
    fn madd(a: f64, b: f64, c: f64) -> f64;
}

/// Separate multiply and add (portable).
pub(crate) struct Plain;

impl Madd for Plain {
    #[inline(always)]
    fn madd(a: f64, b: f64, c: f64) -> f64 {
        a * b + c
    }
}

/// Fused multiply-add; only used inside functions compiled with FMA enabled,
/// where `mul_add` is one instruction (elsewhere it would be a library call).
#[cfg(target_arch = "x86_64")]
pub(crate) struct Fused;

#[cfg(target_arch = "x86_64")]
impl Madd for Fused {
    #[inline(always)]
    fn madd(a: f64, b: f64, c: f64) -> f64 {
        a.mul_add(b, c)
    }
}

/// The branch-free core of [`sin_cos`], valid for |x| ≤ [`SIN_COS_RANGE`].
#[inline(always)]
pub(crate) fn sin_cos_kernel<M: Madd>(x: f64) -> (f64, f64) {
    let shifted = x * std::f64::consts::FRAC_2_PI + RINT_SHIFT;
    let k = shifted - RINT_SHIFT;
    // k mod 4 sits in the low mantissa bits of `shifted` (2^51 + k, two's complement).
    let q = shifted.to_bits() as i64;
    let r = ((x - k * PIO2_1) - k * PIO2_2) - k * PIO2_3;
    let r2 = r * r;
    // Estrin's scheme in z = r²: pairs, then pairs of pairs with z², z⁴, z⁸.
    // Its dependent depth is about half of Horner's (the polynomial is the
    // latency that starts every FK); the same operations in the same order
    // run four lanes wide in `lanes::A4::sin_cos`.
    let (z, z2) = (r2, r2 * r2);
    let (z4, z8) = (z2 * z2, (z2 * z2) * (z2 * z2));
    let s = &SIN_POLY;
    let s03 = M::madd(M::madd(s[3], z, s[2]), z2, M::madd(s[1], z, s[0]));
    let s47 = M::madd(M::madd(s[7], z, s[6]), z2, M::madd(s[5], z, s[4]));
    let ps = M::madd(s[8], z8, M::madd(s47, z4, s03));
    let c = &COS_POLY;
    let c03 = M::madd(M::madd(c[3], z, c[2]), z2, M::madd(c[1], z, c[0]));
    let c47 = M::madd(M::madd(c[7], z, c[6]), z2, M::madd(c[5], z, c[4]));
    let pc = M::madd(M::madd(c[9], z, c[8]), z8, M::madd(c47, z4, c03));
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
    #[test]
    fn atan2_lanes_equal_scalar_atan2_bit_for_bit() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(22);
        let specials = [0.0, -0.0, f64::INFINITY, f64::NEG_INFINITY, f64::NAN, 1e-310, -1e300];
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        for k in 0..200_000 {
            let (mut y, mut x) = ([0.0; 8], [0.0; 8]);
            for i in 0..8 {
                let mag = |rng: &mut rand_chacha::ChaCha8Rng| 10f64.powf(rng.random_range(-8.0..8.0));
                (y[i], x[i]) = (mag(&mut rng), mag(&mut rng));
                match rng.random_range(0..6) {
                    0 => y[i] = x[i] * std::f64::consts::FRAC_PI_8.tan() * (1.0 + rng.random_range(-1e-9..1e-9)),
                    1 => y[i] = x[i],
                    // Every 16th case one lane gets a zero, infinite, NaN or subnormal argument.
                    2 if k % 16 == 0 => y[i] = specials[rng.random_range(0..specials.len())],
                    3 if k % 16 == 0 => x[i] = specials[rng.random_range(0..specials.len())],
                    _ => {}
                }
                if rng.random_bool(0.5) {
                    y[i] = -y[i];
                }
                if rng.random_bool(0.5) {
                    x[i] = -x[i];
                }
            }
            let (portable, dispatched) = (super::atan2_lanes(y, x), super::atan2_x8(y, x));
            let four = super::atan2_lanes([y[0], y[1], y[2], y[3]], [x[0], x[1], x[2], x[3]]);
            for i in 0..8 {
                let want = super::atan2(y[i], x[i]);
                assert!(same(portable[i], want), "lane {i}: atan2({}, {}) = {} ≠ {want}", y[i], x[i], portable[i]);
                assert!(same(dispatched[i], want), "lane {i}: atan2_x8({}, {}) = {}", y[i], x[i], dispatched[i]);
                if i < 4 {
                    assert!(same(four[i], want), "4 lanes, lane {i}");
                }
            }
        }
    }

    #[test]
    fn fast_atan2_matches_the_standard_library() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(21);
        let mut worst = 0.0f64;
        for k in 0..1_000_000 {
            // Random magnitudes over many decades, every sign combination, and
            // ratios near the reduction points tan(π/8) and 1.
            let mag = |rng: &mut rand_chacha::ChaCha8Rng| 10f64.powf(rng.random_range(-8.0..8.0));
            let (mut y, mut x) = (mag(&mut rng), mag(&mut rng));
            match k % 4 {
                0 => y = x * (std::f64::consts::FRAC_PI_8.tan() * (1.0 + rng.random_range(-1e-6..1e-6))),
                1 => y = x * (1.0 + rng.random_range(-1e-6..1e-6)),
                _ => {}
            }
            if rng.random_bool(0.5) {
                y = -y;
            }
            if rng.random_bool(0.5) {
                x = -x;
            }
            let (got, want) = (super::atan2(y, x), y.atan2(x));
            let ulps = (got - want).abs() / (want.abs() * f64::EPSILON).max(f64::MIN_POSITIVE);
            worst = worst.max(ulps);
        }
        assert!(worst <= 2.0, "worst error {worst} ulp");
        for (y, x) in [
            (0.0, 1.0),
            (-0.0, 1.0),
            (0.0, -1.0),
            (-0.0, -1.0),
            (0.0, 0.0),
            (-0.0, -0.0),
            (1.0, 0.0),
            (1.0, -0.0),
            (-1.0, 0.0),
            (f64::INFINITY, 1.0),
            (1.0, f64::NEG_INFINITY),
            (f64::INFINITY, f64::INFINITY),
            (1e-300, 1e300),
            (3.0, 3.0),
            (-2.0, -2.0),
        ] {
            let (got, want) = (super::atan2(y, x), f64::atan2(y, x));
            assert!(
                got == want || (got - want).abs() <= 2.0 * want.abs() * f64::EPSILON,
                "atan2({y}, {x}) = {got}, want {want}"
            );
            assert_eq!(got.is_sign_negative(), want.is_sign_negative(), "atan2({y}, {x})");
        }
        assert!(super::atan2(f64::NAN, 1.0).is_nan() && super::atan2(1.0, f64::NAN).is_nan());
    }

    #[test]
    fn fast_hypot_matches_the_standard_library() {
        for (x, y) in [(3.0, 4.0), (1e-200, 1e-200), (1e200, 1e200), (0.0, 0.0), (-5.0, 12.0), (1e-3, 2e-3)] {
            let (got, want) = (super::hypot(x, y), f64::hypot(x, y));
            assert!((got - want).abs() <= 2.0 * want * f64::EPSILON, "hypot({x}, {y})");
        }
        assert!(super::hypot(f64::NAN, 1.0).is_nan() && super::hypot(f64::INFINITY, 1.0) == f64::INFINITY);
    }
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn fast_sin_cos_matches_std() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let (mut worst, mut worst_ulp): (f64, f64) = (0.0, 0.0);
        for i in 0..2_000_000 {
            let x: f64 = match i % 3 {
                0 => rng.random_range(-10.0..10.0),
                1 => rng.random_range(-1.0e5..1.0e5),
                _ => rng.random_range(-1e-3..1e-3),
            };
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
            for (v, v0) in [(s, s0), (c, c0)] {
                // In ulp of the result, where the result is not tiny (an
                // absolute error near a zero of sin or cos is the argument's).
                if v0.abs() > 1e-3 {
                    worst_ulp = worst_ulp.max((v - v0).abs() / (v0.abs() * f64::EPSILON));
                }
            }
        }
        assert!(worst_ulp <= 2.5, "worst error {worst_ulp} ulp");
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

    /// The triple nearest a reference: exact for the rotation, the true
    /// triple back where it is the only near one, and never farther than
    /// the true triple near the representation singularity.
    #[test]
    fn rpy_near_is_exact_and_no_farther_than_the_true_triple() {
        let mut rng = ChaCha8Rng::seed_from_u64(40);
        let gap = |t: [f64; 3], n: [f64; 3]| t.iter().zip(n).map(|(x, y)| (x - y) * (x - y)).sum::<f64>();
        for i in 0..20_000 {
            let conv = if i % 2 == 0 { RpyConvention::Xyz } else { RpyConvention::Zyx };
            let pitch = match i % 4 {
                // Away from the singularity, where the true triple is the only near one.
                0 | 1 => {
                    let b: f64 = rng.random_range(-1.2..1.2);
                    b + if rng.random_bool(0.5) { std::f64::consts::PI } else { 0.0 }
                }
                // Within 1e-5 of it, and on it.
                2 => std::f64::consts::FRAC_PI_2.copysign(rng.random_range(-1.0..1.0)) + rng.random_range(-1e-5..1e-5),
                _ => std::f64::consts::FRAC_PI_2.copysign(rng.random_range(-1.0..1.0)),
            };
            let truth = [rng.random_range(-9.0..9.0), pitch, rng.random_range(-9.0..9.0)];
            let near = truth.map(|x| x + rng.random_range(-0.4..0.4));
            let r = rpy_to_rot(truth, conv);
            let got = rot_to_rpy_near(&r, conv, near);
            assert!((rpy_to_rot(got, conv) - r).amax() < 1e-12, "{conv:?} {truth:?}: {got:?} is another rotation");
            if i % 4 < 2 {
                assert!(gap(got, truth) < 1e-18, "{conv:?} {truth:?} near {near:?}: got {got:?}");
            } else {
                assert!(gap(got, near) <= gap(truth, near) + 1e-12, "{conv:?} {truth:?} near {near:?}: got {got:?}");
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
    fn nearest_rotation_is_the_polar_factor_nalgebra_finds() {
        let mut rng = ChaCha8Rng::seed_from_u64(31);
        for _ in 0..20_000 {
            let rpy = [rng.random_range(-3.0..3.0), rng.random_range(-1.5..1.5), rng.random_range(-3.0..3.0)];
            let exact = rpy_to_rot(rpy, RpyConvention::Zyx);
            // Noise up to the largest departure Pose::from_matrix accepts.
            let scale = 10f64.powf(rng.random_range(-16.0..-6.5));
            let noisy = exact + Matrix3::from_fn(|_, _| rng.random_range(-1.0..1.0)) * scale;
            if (noisy.transpose() * noisy - Matrix3::identity()).norm() > 1e-6 {
                continue;
            }
            let ours = nearest_rotation(noisy);
            let reference = Rotation3::from_matrix(&noisy).into_inner();
            assert!((ours.transpose() * ours - Matrix3::identity()).norm() < 1e-15);
            assert!((ours.determinant() - 1.0).abs() < 1e-15);
            assert!((ours - reference).norm() < 1e-13, "{ours} vs {reference}");
        }
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
