//! Four `f64` lanes for the hot loops of [`crate::chain`]: a frame column, or
//! four joint angles at once.
//!
//! [`Lanes`] has two implementations. [`P4`] is a plain array with separate
//! multiplies and adds; it runs everywhere. On x86-64, `A4` is one AVX2
//! register with fused multiply-adds. The loops of `chain` are written once,
//! generic over `Lanes`; `chain` runs them on `P4` itself, and on `A4`
//! through the methods of [`Avx2Fma`], which run them in functions compiled
//! with `avx2,fma` enabled.
//!
//! `A4` executes AVX2 and FMA instructions from safe methods, so it must
//! never exist on a CPU without them. It is private to this module, and the
//! only code that makes one is reached through an [`Avx2Fma`]: a token that
//! only [`Avx2Fma::detect`] makes, after the CPU was found to have both
//! features. The `unsafe` blocks of `A4` rely on that.
//!
//! The lanes are written out explicitly rather than left to the
//! autovectoriser: with plain `[f64; 4]` code LLVM split frame columns into a
//! 2-lane register and a scalar and kept per-joint bounds checks, about three
//! times the instructions of this form.

use std::mem::MaybeUninit;

use crate::math::sin_cos_kernel;
use crate::math::{Madd, Plain};

/// Four `f64` lanes with the arithmetic the kinematic loops need.
pub(crate) trait Lanes: Copy {
    /// The scalar multiply-add that matches these lanes' `madd`.
    type M: Madd;
    /// `v` in every lane.
    fn splat(v: f64) -> Self;
    /// The lanes of `a`.
    fn from_array(a: [f64; 4]) -> Self;
    /// The lanes as an array.
    fn to_array(self) -> [f64; 4];
    /// `self · b`, lane by lane.
    fn mul(self, b: Self) -> Self;
    /// `self + b`, lane by lane.
    fn add(self, b: Self) -> Self;
    /// `self − b`, lane by lane.
    fn sub(self, b: Self) -> Self;
    /// `self · b + c`, lane by lane (fused on [`A4`]).
    fn madd(self, b: Self, c: Self) -> Self;
    /// `self · b − c`, lane by lane (fused on [`A4`]).
    fn msub(self, b: Self, c: Self) -> Self;
    /// `−self`, lane by lane (a sign flip, exact).
    fn neg(self) -> Self;
    /// The bits of `self` xor the bits of `b`, lane by lane (with `b` = ±0.0
    /// in a lane: a sign flip where `b` is −0.0).
    fn xor(self, b: Self) -> Self;
    /// Lane by lane: `a` where the mask `self` has its sign bit set
    /// ([`MASK_TRUE`]), else `b` ([`MASK_FALSE`]).
    fn select(self, a: Self, b: Self) -> Self;
    /// Sine and cosine of every lane with the arithmetic of
    /// [`sin_cos_kernel`] for `Self::M`, bit for bit (tested); valid where
    /// [`Lanes::all_abs_le`] holds for [`crate::math::SIN_COS_RANGE`].
    fn sin_cos(self) -> (Self, Self);
    /// Whether |x| ≤ `bound` in every lane (false if a lane is NaN).
    fn all_abs_le(self, bound: f64) -> bool;
    /// |self|, lane by lane.
    fn abs(self) -> Self;
    /// The 4 × 4 transpose of the rows `m`: lane k of result j is lane j of `m[k]`.
    fn transpose(m: [Self; 4]) -> [Self; 4];
    /// Writes the first `dst.len()` lanes (at most 4) into `dst`, branching
    /// on the length: for lengths the compiler knows.
    fn store_prefix(self, dst: &mut [MaybeUninit<f64>]);
    /// The same with one masked store and no branch: for a length known
    /// only at run time, where a branch per store costs more than the mask.
    fn store_prefix_masked(self, dst: &mut [MaybeUninit<f64>]);
    /// The first `src.len()` (at most 4) values of `src` in the first lanes,
    /// zero in the others, without a branch per lane.
    fn load_prefix(src: &[f64]) -> Self;
    /// Bit k set where lane k of `self` < lane k of `b` (false if either is NaN).
    fn lt_bits(self, b: Self) -> u32;
    /// Bit k set where lane k of `self` > lane k of `b` (false if either is NaN).
    fn gt_bits(self, b: Self) -> u32;
}

/// A mask lane that [`Lanes::select`] reads as true: only the sign bit
/// counts, and −1.0 (unlike an all-ones NaN) compares equal to itself, so
/// structures holding masks keep a meaningful `PartialEq`. False is +1.0.
pub(crate) const MASK_TRUE: f64 = -1.0;
/// A mask lane that [`Lanes::select`] reads as false.
pub(crate) const MASK_FALSE: f64 = 1.0;

/// Portable lanes: an array, separate multiplies and adds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct P4([f64; 4]);

impl P4 {
    #[inline(always)]
    fn map2(self, b: P4, f: impl Fn(f64, f64) -> f64) -> P4 {
        P4([f(self.0[0], b.0[0]), f(self.0[1], b.0[1]), f(self.0[2], b.0[2]), f(self.0[3], b.0[3])])
    }
}

impl Lanes for P4 {
    type M = Plain;

    #[inline(always)]
    fn splat(v: f64) -> P4 {
        P4([v; 4])
    }

    #[inline(always)]
    fn from_array(a: [f64; 4]) -> P4 {
        P4(a)
    }

    #[inline(always)]
    fn to_array(self) -> [f64; 4] {
        self.0
    }

    #[inline(always)]
    fn mul(self, b: P4) -> P4 {
        self.map2(b, |x, y| x * y)
    }

    #[inline(always)]
    fn add(self, b: P4) -> P4 {
        self.map2(b, |x, y| x + y)
    }

    #[inline(always)]
    fn sub(self, b: P4) -> P4 {
        self.map2(b, |x, y| x - y)
    }

    #[inline(always)]
    fn madd(self, b: P4, c: P4) -> P4 {
        let ab = self.mul(b);
        ab.map2(c, |x, y| x + y)
    }

    #[inline(always)]
    fn msub(self, b: P4, c: P4) -> P4 {
        let ab = self.mul(b);
        ab.map2(c, |x, y| x - y)
    }

    #[inline(always)]
    fn neg(self) -> P4 {
        P4(self.0.map(|x| -x))
    }

    #[inline(always)]
    fn xor(self, b: P4) -> P4 {
        self.map2(b, |x, y| f64::from_bits(x.to_bits() ^ y.to_bits()))
    }

    #[inline(always)]
    fn select(self, a: P4, b: P4) -> P4 {
        let pick = |k: usize| if self.0[k].is_sign_negative() { a.0[k] } else { b.0[k] };
        P4([pick(0), pick(1), pick(2), pick(3)])
    }

    #[inline(always)]
    fn sin_cos(self) -> (P4, P4) {
        let (mut s, mut c) = ([0.0; 4], [0.0; 4]);
        for k in 0..4 {
            (s[k], c[k]) = sin_cos_kernel::<Plain>(self.0[k]);
        }
        (P4(s), P4(c))
    }

    #[inline(always)]
    fn all_abs_le(self, bound: f64) -> bool {
        self.0.iter().fold(true, |all, x| all & (x.abs() <= bound))
    }

    #[inline(always)]
    fn abs(self) -> P4 {
        P4(self.0.map(f64::abs))
    }

    #[inline(always)]
    fn transpose(m: [P4; 4]) -> [P4; 4] {
        std::array::from_fn(|j| P4([m[0].0[j], m[1].0[j], m[2].0[j], m[3].0[j]]))
    }

    #[inline(always)]
    fn store_prefix(self, dst: &mut [MaybeUninit<f64>]) {
        for (d, v) in dst.iter_mut().zip(self.0) {
            d.write(v);
        }
    }

    #[inline(always)]
    fn store_prefix_masked(self, dst: &mut [MaybeUninit<f64>]) {
        self.store_prefix(dst);
    }

    #[inline(always)]
    fn load_prefix(src: &[f64]) -> P4 {
        P4(std::array::from_fn(|k| src.get(k).copied().unwrap_or(0.0)))
    }

    #[inline(always)]
    fn lt_bits(self, b: P4) -> u32 {
        (0..4).fold(0, |bits, k| bits | (((self.0[k] < b.0[k]) as u32) << k))
    }

    #[inline(always)]
    fn gt_bits(self, b: P4) -> u32 {
        (0..4).fold(0, |bits, k| bits | (((self.0[k] > b.0[k]) as u32) << k))
    }
}

#[cfg(target_arch = "x86_64")]
pub(crate) use avx2::Avx2Fma;
#[cfg(all(test, target_arch = "x86_64"))]
use avx2::A4;

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use std::arch::x86_64::*;
    use std::mem::MaybeUninit;

    use super::Lanes;
    use crate::chain::{self, Chain, Scanned};
    use crate::math::Fused;
    use crate::math::{Pose, COS_POLY, PIO2_1, PIO2_2, PIO2_3, RINT_SHIFT, SIN_POLY};

    /// Proof that this CPU has AVX2 and FMA: the private field keeps any
    /// constructor but [`Avx2Fma::detect`] out. Its methods run the chain's
    /// kernels on [`A4`]. (One entry point per kernel with the kernel's own
    /// arguments, not one generic entry taking a struct of arguments: such a
    /// struct is passed through memory, and a `&mut` inside it loses the
    /// no-alias guarantee of a `&mut` argument, so LLVM reloads the chain's
    /// arrays after every store into the output.)
    #[derive(Debug, Clone, Copy)]
    pub(crate) struct Avx2Fma(());

    impl Avx2Fma {
        /// The token if this CPU has AVX2 and FMA (after the first call, the
        /// check is a test of a cached flag).
        #[inline(always)]
        pub(crate) fn detect() -> Option<Avx2Fma> {
            (is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma")).then_some(Avx2Fma(()))
        }

        /// [`chain::fk_core`] on AVX2 lanes.
        #[inline(always)]
        pub(crate) fn fk<const S: u8, const N: usize>(self, ch: &Chain, q: &[f64]) -> (Pose, Scanned) {
            // SAFETY: `self` proves that the CPU has AVX2 and FMA (`detect`).
            unsafe { fk_avx2::<S, N>(ch, q) }
        }

        /// [`chain::fk_rows_core`] on AVX2 lanes.
        #[inline(always)]
        pub(crate) fn fk_rows<const S: u8, const N: usize>(
            self,
            ch: &Chain,
            q: &[f64],
            out: &mut [MaybeUninit<f64>; 16],
        ) -> Scanned {
            // SAFETY: as in `fk`.
            unsafe { fk_rows_avx2::<S, N>(ch, q, out) }
        }

        /// [`chain::link_frames_core`] on AVX2 lanes.
        #[inline(always)]
        pub(crate) fn link_frames<const S: u8, const N: usize>(self, ch: &Chain, q: &[f64], out: &mut [Pose]) {
            // SAFETY: as in `fk`.
            unsafe { link_frames_avx2::<S, N>(ch, q, out) }
        }

        /// [`chain::jacobian_core`] on AVX2 lanes.
        #[inline(always)]
        pub(crate) fn jacobian<const ROWS: bool, const TOOL: bool, const S: u8, const N: usize, const CAP: usize>(
            self,
            ch: &Chain,
            q: &[f64],
            data: &mut [MaybeUninit<f64>],
            pose: Option<&mut Pose>,
        ) -> Scanned {
            // SAFETY: as in `fk`.
            unsafe { jacobian_avx2::<ROWS, TOOL, S, N, CAP>(ch, q, data, pose) }
        }

        /// Runs `f` in a function compiled with AVX2 and FMA enabled, for
        /// the tests of `A4` (which make their `A4`s inside `f`).
        #[cfg(test)]
        pub(super) fn run_closure<T>(self, f: impl FnOnce() -> T) -> T {
            // SAFETY: as in `fk`.
            unsafe { closure_avx2(f) }
        }
    }

    // The functions compiled with AVX2 and FMA enabled. Safety, for each:
    // the CPU must have AVX2 and FMA.

    #[target_feature(enable = "avx2,fma")]
    unsafe fn fk_avx2<const S: u8, const N: usize>(ch: &Chain, q: &[f64]) -> (Pose, Scanned) {
        chain::fk_core::<A4, S, N>(ch, q)
    }

    #[target_feature(enable = "avx2,fma")]
    unsafe fn fk_rows_avx2<const S: u8, const N: usize>(
        ch: &Chain,
        q: &[f64],
        out: &mut [MaybeUninit<f64>; 16],
    ) -> Scanned {
        chain::fk_rows_core::<A4, S, N>(ch, q, out)
    }

    #[target_feature(enable = "avx2,fma")]
    unsafe fn link_frames_avx2<const S: u8, const N: usize>(ch: &Chain, q: &[f64], out: &mut [Pose]) {
        chain::link_frames_core::<A4, S, N>(ch, q, out)
    }

    #[target_feature(enable = "avx2,fma")]
    unsafe fn jacobian_avx2<const ROWS: bool, const TOOL: bool, const S: u8, const N: usize, const CAP: usize>(
        ch: &Chain,
        q: &[f64],
        data: &mut [MaybeUninit<f64>],
        pose: Option<&mut Pose>,
    ) -> Scanned {
        chain::jacobian_core::<A4, ROWS, TOOL, S, N, CAP>(ch, q, data, pose)
    }

    #[cfg(test)]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn closure_avx2<T>(f: impl FnOnce() -> T) -> T {
        f()
    }

    /// AVX2 lanes with fused multiply-adds.
    ///
    /// Invariant: an `A4` exists only on a CPU with AVX2 and FMA. Outside
    /// `lanes` the type cannot be named; `A4`s are made only in the kernels
    /// that the `*_avx2` functions above run, which only [`Avx2Fma`]'s
    /// methods call (and in the tests of `lanes`, inside
    /// [`Avx2Fma::run_closure`]). Every `unsafe` block below relies on the
    /// invariant; the intrinsics touch no memory but the arrays passed by
    /// reference. The private helpers after the `impl` are called only from
    /// `A4`'s methods.
    #[derive(Debug, Clone, Copy)]
    pub(super) struct A4(__m256d);

    impl Lanes for A4 {
        type M = Fused;

        #[inline(always)]
        fn splat(v: f64) -> A4 {
            // SAFETY: AVX is available (type invariant, see above).
            A4(unsafe { _mm256_set1_pd(v) })
        }

        #[inline(always)]
        fn from_array(a: [f64; 4]) -> A4 {
            // SAFETY: AVX is available; reads the four values of `a`.
            A4(unsafe { _mm256_loadu_pd(a.as_ptr()) })
        }

        #[inline(always)]
        fn to_array(self) -> [f64; 4] {
            let mut a = [0.0; 4];
            // SAFETY: AVX is available; writes the four values of `a`.
            unsafe { _mm256_storeu_pd(a.as_mut_ptr(), self.0) };
            a
        }

        #[inline(always)]
        fn mul(self, b: A4) -> A4 {
            // SAFETY: AVX is available.
            A4(unsafe { _mm256_mul_pd(self.0, b.0) })
        }

        #[inline(always)]
        fn add(self, b: A4) -> A4 {
            // SAFETY: AVX is available.
            A4(unsafe { _mm256_add_pd(self.0, b.0) })
        }

        #[inline(always)]
        fn sub(self, b: A4) -> A4 {
            // SAFETY: AVX is available.
            A4(unsafe { _mm256_sub_pd(self.0, b.0) })
        }

        #[inline(always)]
        fn madd(self, b: A4, c: A4) -> A4 {
            // SAFETY: FMA is available.
            A4(unsafe { _mm256_fmadd_pd(self.0, b.0, c.0) })
        }

        #[inline(always)]
        fn msub(self, b: A4, c: A4) -> A4 {
            // SAFETY: FMA is available.
            A4(unsafe { _mm256_fmsub_pd(self.0, b.0, c.0) })
        }

        #[inline(always)]
        fn neg(self) -> A4 {
            // SAFETY: AVX is available.
            A4(unsafe { _mm256_xor_pd(self.0, _mm256_set1_pd(-0.0)) })
        }

        #[inline(always)]
        fn xor(self, b: A4) -> A4 {
            // SAFETY: AVX is available.
            A4(unsafe { _mm256_xor_pd(self.0, b.0) })
        }

        #[inline(always)]
        fn select(self, a: A4, b: A4) -> A4 {
            // SAFETY: AVX is available. `blendv` picks by the sign bit of each mask lane.
            A4(unsafe { _mm256_blendv_pd(b.0, a.0, self.0) })
        }

        /// [`crate::math::sin_cos_kernel`] for [`Fused`], four lanes at once:
        /// the same operations in the same order, so the same bits.
        #[inline(always)]
        fn sin_cos(self) -> (A4, A4) {
            // SAFETY: AVX2 and FMA are available.
            unsafe {
                let x = self.0;
                let shift = splat(RINT_SHIFT);
                let shifted = _mm256_add_pd(_mm256_mul_pd(x, splat(std::f64::consts::FRAC_2_PI)), shift);
                let k = _mm256_sub_pd(shifted, shift);
                let r = _mm256_sub_pd(x, _mm256_mul_pd(k, splat(PIO2_1)));
                let r = _mm256_sub_pd(r, _mm256_mul_pd(k, splat(PIO2_2)));
                let r = _mm256_sub_pd(r, _mm256_mul_pd(k, splat(PIO2_3)));
                let r2 = _mm256_mul_pd(r, r);
                // Estrin's scheme, as in `sin_cos_kernel`.
                let (z, z2) = (r2, _mm256_mul_pd(r2, r2));
                let z4 = _mm256_mul_pd(z2, z2);
                let z8 = _mm256_mul_pd(z4, z4);
                let s03 = _mm256_fmadd_pd(pair(&SIN4, 2, z), z2, pair(&SIN4, 0, z));
                let s47 = _mm256_fmadd_pd(pair(&SIN4, 6, z), z2, pair(&SIN4, 4, z));
                let ps = _mm256_fmadd_pd(coef(&SIN4[8]), z8, _mm256_fmadd_pd(s47, z4, s03));
                let c03 = _mm256_fmadd_pd(pair(&COS4, 2, z), z2, pair(&COS4, 0, z));
                let c47 = _mm256_fmadd_pd(pair(&COS4, 6, z), z2, pair(&COS4, 4, z));
                let pc = _mm256_fmadd_pd(pair(&COS4, 8, z), z8, _mm256_fmadd_pd(c47, z4, c03));
                let sp = _mm256_mul_pd(r, ps);
                let cp = pc;
                // Quadrant k mod 4 from the low bits of `shifted`: odd quadrants
                // swap sine and cosine; bit 1 of k (of k + 1) is the sign of
                // the sine (cosine), moved to the sign bit and flipped in.
                let q = _mm256_castpd_si256(shifted);
                let one = _mm256_set1_epi64x(1);
                let two = _mm256_set1_epi64x(2);
                let swap = _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(q, one), one));
                let s = _mm256_blendv_pd(sp, cp, swap);
                let c = _mm256_blendv_pd(cp, sp, swap);
                let sign_s = _mm256_slli_epi64::<62>(_mm256_and_si256(q, two));
                let sign_c = _mm256_slli_epi64::<62>(_mm256_and_si256(_mm256_add_epi64(q, one), two));
                (A4(_mm256_xor_pd(s, _mm256_castsi256_pd(sign_s))), A4(_mm256_xor_pd(c, _mm256_castsi256_pd(sign_c))))
            }
        }

        #[inline(always)]
        fn all_abs_le(self, bound: f64) -> bool {
            // SAFETY: AVX is available.
            unsafe {
                let abs = _mm256_andnot_pd(_mm256_set1_pd(-0.0), self.0);
                // Ordered, non-signalling ≤: false for NaN lanes.
                _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LE_OQ>(abs, _mm256_set1_pd(bound))) == 0b1111
            }
        }

        #[inline(always)]
        fn abs(self) -> A4 {
            // SAFETY: AVX is available.
            A4(unsafe { _mm256_andnot_pd(_mm256_set1_pd(-0.0), self.0) })
        }

        #[inline(always)]
        fn transpose(m: [A4; 4]) -> [A4; 4] {
            // SAFETY: AVX is available.
            unsafe {
                let (t0, t1) = (_mm256_unpacklo_pd(m[0].0, m[1].0), _mm256_unpackhi_pd(m[0].0, m[1].0));
                let (t2, t3) = (_mm256_unpacklo_pd(m[2].0, m[3].0), _mm256_unpackhi_pd(m[2].0, m[3].0));
                [
                    A4(_mm256_permute2f128_pd::<0x20>(t0, t2)),
                    A4(_mm256_permute2f128_pd::<0x20>(t1, t3)),
                    A4(_mm256_permute2f128_pd::<0x31>(t0, t2)),
                    A4(_mm256_permute2f128_pd::<0x31>(t1, t3)),
                ]
            }
        }

        #[inline(always)]
        fn store_prefix(self, dst: &mut [MaybeUninit<f64>]) {
            // Plain 256/128/64-bit stores, not `maskstore`, which is slow on
            // some cores (benchmarks/history.md).
            // SAFETY: AVX is available; only the first min(len, 4) ≤ dst.len()
            // elements of `dst` are written.
            unsafe {
                let p = dst.as_mut_ptr().cast::<f64>();
                let (len, lo) = (dst.len(), _mm256_castpd256_pd128(self.0));
                // Range tests, not a `match`: a match on the length becomes a
                // jump table (see docs/internals.md, "The hot loops").
                if len >= 4 {
                    _mm256_storeu_pd(p, self.0);
                } else if len >= 2 {
                    _mm_storeu_pd(p, lo);
                    if len > 2 {
                        _mm_store_sd(p.add(2), _mm256_extractf128_pd::<1>(self.0));
                    }
                } else if len > 0 {
                    _mm_store_sd(p, lo);
                }
            }
        }

        #[inline(always)]
        fn store_prefix_masked(self, dst: &mut [MaybeUninit<f64>]) {
            // SAFETY: AVX is available; the mask enables the first
            // min(len, 4) ≤ dst.len() lanes and `maskstore` writes no others.
            unsafe { _mm256_maskstore_pd(dst.as_mut_ptr().cast(), prefix_mask(dst.len().min(4)), self.0) }
        }

        #[inline(always)]
        fn load_prefix(src: &[f64]) -> A4 {
            // SAFETY: AVX is available. The mask enables the first
            // min(len, 4) ≤ src.len() lanes; `maskload` reads no memory for
            // the others (no fault, even past the end of `src`) and gives 0.
            A4(unsafe { _mm256_maskload_pd(src.as_ptr(), prefix_mask(src.len().min(4))) })
        }

        #[inline(always)]
        fn lt_bits(self, b: A4) -> u32 {
            // SAFETY: AVX is available. Ordered, non-signalling: false for NaN.
            unsafe { _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(self.0, b.0)) as u32 }
        }

        #[inline(always)]
        fn gt_bits(self, b: A4) -> u32 {
            // SAFETY: AVX is available. Ordered, non-signalling: false for NaN.
            unsafe { _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_GT_OQ>(self.0, b.0)) as u32 }
        }
    }

    /// The `maskload`/`maskstore` mask of the first `len` ≤ 4 lanes (sign bit set: used).
    #[inline(always)]
    fn prefix_mask(len: usize) -> __m256i {
        static PREFIX: [[i64; 4]; 5] = [[0, 0, 0, 0], [-1, 0, 0, 0], [-1, -1, 0, 0], [-1, -1, -1, 0], [-1, -1, -1, -1]];
        // SAFETY: AVX is available (see `A4`); reads one row of the table.
        unsafe { _mm256_loadu_si256(PREFIX[len].as_ptr().cast()) }
    }

    /// `v` in four lanes. (Helpers here are functions, not closures: a
    /// closure would be compiled without the AVX2 feature, and the intrinsics
    /// would not be inlined into it.)
    #[inline(always)]
    fn splat(v: f64) -> __m256d {
        // SAFETY: AVX is available (see `A4`).
        unsafe { _mm256_set1_pd(v) }
    }

    /// The coefficients of [`SIN_POLY`] and [`COS_POLY`] in four lanes each,
    /// in memory: an FMA then reads one as its memory operand, where a
    /// splatted constant would cost a broadcast instruction per use.
    static SIN4: [[f64; 4]; 9] = splat_all(SIN_POLY);
    static COS4: [[f64; 4]; 10] = splat_all(COS_POLY);

    const fn splat_all<const N: usize>(c: [f64; N]) -> [[f64; 4]; N] {
        let mut out = [[0.0; 4]; N];
        let mut i = 0;
        while i < N {
            out[i] = [c[i]; 4];
            i += 1;
        }
        out
    }

    /// c[k + 1]·z + c[k].
    #[inline(always)]
    fn pair(c: &[[f64; 4]], k: usize, z: __m256d) -> __m256d {
        // SAFETY: FMA is available (see `A4`).
        unsafe { _mm256_fmadd_pd(coef(&c[k + 1]), z, coef(&c[k])) }
    }

    /// A coefficient row of [`SIN4`] or [`COS4`] as a register.
    #[inline(always)]
    fn coef(c: &[f64; 4]) -> __m256d {
        // SAFETY: AVX is available (see `A4`); reads the four values of `c`.
        unsafe { _mm256_loadu_pd(c.as_ptr()) }
    }
}

#[cfg(test)]
mod tests {
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use std::mem::MaybeUninit;

    use super::*;
    use crate::math::SIN_COS_RANGE;

    /// Angles that exercise every quadrant, the reduction's edges and the ends of the range.
    fn angles(rng: &mut ChaCha8Rng) -> [f64; 4] {
        std::array::from_fn(|_| match rng.random_range(0..4) {
            0 => rng.random_range(-7.0..7.0),
            1 => rng.random_range(-SIN_COS_RANGE..=SIN_COS_RANGE),
            2 => (rng.random_range(-64..64) as f64) * std::f64::consts::FRAC_PI_4 + rng.random_range(-1e-12..1e-12),
            _ => rng.random_range(-1e-300..1e-300),
        })
    }

    #[test]
    fn portable_sin_cos_is_the_scalar_kernel() {
        let mut rng = ChaCha8Rng::seed_from_u64(41);
        for _ in 0..50_000 {
            let x = angles(&mut rng);
            let (s, c) = P4::from_array(x).sin_cos();
            for (k, &xk) in x.iter().enumerate() {
                let (es, ec) = sin_cos_kernel::<Plain>(xk);
                assert_eq!((s.0[k].to_bits(), c.0[k].to_bits()), (es.to_bits(), ec.to_bits()), "x = {xk:e}");
            }
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx2_sin_cos_is_the_fused_scalar_kernel_bit_for_bit() {
        let Some(avx) = Avx2Fma::detect() else {
            eprintln!("skipped: this CPU has no AVX2+FMA");
            return;
        };
        let mut rng = ChaCha8Rng::seed_from_u64(42);
        for _ in 0..200_000 {
            let x = angles(&mut rng);
            let (s, c, exp) = avx.run_closure(|| {
                let (s, c) = A4::from_array(x).sin_cos();
                (s.to_array(), c.to_array(), x.map(sin_cos_kernel::<crate::math::Fused>))
            });
            for k in 0..4 {
                assert_eq!(
                    (s[k].to_bits(), c[k].to_bits()),
                    (exp[k].0.to_bits(), exp[k].1.to_bits()),
                    "x = {:e}",
                    x[k]
                );
            }
        }
    }

    #[test]
    fn transpose_and_prefix_stores() {
        let m = [[1.0, 2.0, 3.0, 4.0], [5.0, 6.0, 7.0, 8.0], [9.0, 10.0, 11.0, 12.0], [13.0, 14.0, 15.0, 16.0]];
        let want = [[1.0, 5.0, 9.0, 13.0], [2.0, 6.0, 10.0, 14.0], [3.0, 7.0, 11.0, 15.0], [4.0, 8.0, 12.0, 16.0]];
        let prefixes = |store: &dyn Fn(&mut [MaybeUninit<f64>])| {
            (0..=4)
                .map(|len| {
                    let mut buf = [MaybeUninit::new(-1.0); 5];
                    store(&mut buf[..len]);
                    // SAFETY: every element was initialised with −1.0 or written.
                    buf.map(|v| unsafe { v.assume_init() })
                })
                .collect::<Vec<_>>()
        };
        let expect: Vec<[f64; 5]> =
            (0..=4).map(|len| std::array::from_fn(|k| if k < len { m[0][k] } else { -1.0 })).collect();
        assert_eq!(P4::transpose(m.map(P4::from_array)).map(P4::to_array), want);
        assert_eq!(prefixes(&|d| P4::from_array(m[0]).store_prefix(d)), expect);
        assert_eq!(prefixes(&|d| P4::from_array(m[0]).store_prefix_masked(d)), expect);
        let src = [1.5, -2.5, 3.5, -4.5, 5.5];
        let loads: Vec<[f64; 4]> = (0..=5).map(|len| P4::load_prefix(&src[..len]).to_array()).collect();
        for (len, l) in loads.iter().enumerate() {
            assert_eq!(*l, std::array::from_fn(|k| if k < len { src[k] } else { 0.0 }), "{len}");
        }
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = Avx2Fma::detect() {
            let t = avx.run_closure(|| A4::transpose(m.map(A4::from_array)).map(A4::to_array));
            assert_eq!(t, want);
            let stored = prefixes(&|d| avx.run_closure(|| A4::from_array(m[0]).store_prefix(d)));
            assert_eq!(stored, expect);
            let masked = prefixes(&|d| avx.run_closure(|| A4::from_array(m[0]).store_prefix_masked(d)));
            assert_eq!(masked, expect);
            for len in 0..=5 {
                let l = avx.run_closure(|| A4::load_prefix(&src[..len]).to_array());
                assert_eq!(l, loads[len], "{len}");
            }
        }
    }

    #[test]
    fn sub_is_lane_by_lane() {
        let x = [1.0, 2.0, 3.0, 4.0];
        assert_eq!(P4::from_array(x).sub(P4::splat(1.0)).to_array(), [0.0, 1.0, 2.0, 3.0]);
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = Avx2Fma::detect() {
            let a = avx.run_closure(|| A4::from_array(x).sub(A4::splat(1.0)).to_array());
            assert_eq!(a, [0.0, 1.0, 2.0, 3.0]);
        }
    }

    #[test]
    fn comparisons_give_lane_bits_and_false_for_nan() {
        let x = [1.0, f64::NAN, -3.0, f64::INFINITY];
        let b = [2.0, 0.0, -3.0, 1.0];
        let p = (P4::from_array(x).lt_bits(P4::from_array(b)), P4::from_array(x).gt_bits(P4::from_array(b)));
        assert_eq!(p, (0b0001, 0b1000));
        assert_eq!(P4::from_array(x).abs().to_array()[2], 3.0);
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = Avx2Fma::detect() {
            let a = avx.run_closure(|| {
                let (x, b) = (A4::from_array(x), A4::from_array(b));
                (x.lt_bits(b), x.gt_bits(b), x.abs().to_array())
            });
            assert_eq!((a.0, a.1), p);
            let abs = a.2;
            assert!(abs[0] == 1.0 && abs[1].is_nan() && abs[2] == 3.0 && abs[3] == f64::INFINITY, "{abs:?}");
        }
    }

    #[test]
    fn range_check_rejects_out_of_range_and_nan() {
        let cases: [([f64; 4], bool); 5] = [
            ([0.0, 1.0, -2.0, SIN_COS_RANGE], true),
            ([0.0, 1.0, -2.0, -SIN_COS_RANGE], true),
            ([0.0, 1.0, SIN_COS_RANGE * 1.5, 0.0], false),
            ([f64::NAN, 0.0, 0.0, 0.0], false),
            ([0.0, 0.0, 0.0, f64::NEG_INFINITY], false),
        ];
        for (x, want) in cases {
            assert_eq!(P4::from_array(x).all_abs_le(SIN_COS_RANGE), want, "{x:?}");
            #[cfg(target_arch = "x86_64")]
            if let Some(avx) = Avx2Fma::detect() {
                let got = avx.run_closure(|| A4::from_array(x).all_abs_le(SIN_COS_RANGE));
                assert_eq!(got, want, "{x:?}");
            }
        }
    }
}
