//! Fast, accurate scalar trigonometry for the hot loops: atan2, hypot and
//! sin_cos, with lane-parallel forms.

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
