//! The compiled chain and the hot loops that run on it.
//!
//! A robot description (three kinds of link, see [`crate::LinkGeometry`]) is
//! compiled once into
//!
//! ```text
//! world_from_tool(q) = base · (pre1 · J(θ1) · post1) · … · (pren · J(θn) · postn) · tool
//! ```
//!
//! with θi = signi·qi + offseti, `J` a rotation about (revolute) or
//! translation along (prismatic) the local z axis, and `pre`/`post` constant
//! transforms kept in a sparse form ([`Fixed`]): a DH row costs a few column
//! operations instead of a 4×4 product, and the usual twists 0, ±90° and 180°
//! cost swaps instead of multiplications.
//!
//! The loops work on [`Xf`], a frame as four 4-lane columns (the fourth lane
//! is padding) so that LLVM can keep it in vector registers. On x86-64 CPUs
//! with AVX2 and FMA the same code is also compiled with those features and
//! fused multiply-adds, and picked at run time; elsewhere the portable build
//! runs. Both give the same results to a few ulp (tested).

use std::mem::MaybeUninit;

use nalgebra::{Matrix3, Vector3};

#[cfg(target_arch = "x86_64")]
use crate::lanes::Avx2Fma;
use crate::lanes::{Lanes, MASK_FALSE, MASK_TRUE, P4};
use crate::math::{Pose, SIN_COS_RANGE};
use crate::model::{DhConvention, Joint, JointType, LinkGeometry, MAX_MAGNITUDE};

mod kernels;

pub(crate) use kernels::{as_uninit, fk_core, fk_rows_core, jacobian_core, link_frames_core, Layout, Xf};
use kernels::{join, out_of_kernel_range, quarter, COLUMN_MAJOR, ROW_MAJOR};

/// A rotation Rx(α) in the form that is cheapest to apply. The common twists
/// 0, ±90° and 180° are exact swaps and negations of two frame columns (no
/// multiplication, nothing added to the latency of the chain's serial
/// dependency); any other angle is (cos α, sin α).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Twist {
    /// α = 0.
    Zero,
    /// α = +90°: y ← z, z ← −y.
    Plus90,
    /// α = −90°: y ← −z, z ← y.
    Minus90,
    /// α = 180°: y ← −y, z ← −z.
    Half,
    /// Any other α, as (cos α, sin α).
    Any { ca: f64, sa: f64 },
}

impl Twist {
    fn new(alpha: f64) -> Twist {
        use std::f64::consts::{FRAC_PI_2, PI};
        let near = |v: f64| (alpha - v).abs() < 1e-12;
        if near(0.0) {
            Twist::Zero
        } else if near(FRAC_PI_2) {
            Twist::Plus90
        } else if near(-FRAC_PI_2) {
            Twist::Minus90
        } else if near(PI) || near(-PI) {
            Twist::Half
        } else {
            let (sa, ca) = alpha.sin_cos();
            Twist::Any { ca, sa }
        }
    }
}

/// A constant transform, stored in the form that is cheapest to apply.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Fixed {
    /// Nothing to do.
    Identity,
    /// Tz(d)·Tx(a)·Rx(α), the tail of a standard DH row.
    TzTxRx { d: f64, a: f64, twist: Twist },
    /// Rx(α)·Tx(a)·Tz(d), the head of a modified DH row.
    RxTxTz { twist: Twist, a: f64, d: f64 },
    /// Any rigid transform.
    General(Pose),
}

impl Fixed {
    fn from_pose(p: Pose) -> Fixed {
        if p == Pose::IDENTITY {
            Fixed::Identity
        } else {
            Fixed::General(p)
        }
    }
}

/// One joint of the compiled chain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Step {
    kind: StepKind,
    prismatic: bool,
    /// ±1, the direction of the joint axis along local z.
    sign: f64,
}

/// How a joint is applied. The two exact-twist DH forms cover the revolute
/// joints of every DH arm in the catalogue and run as straight-line code
/// (their numbers are in [`Chain::rows`]); see [`Shape`].
// The general variant is large, and kept inline: a box would add a pointer
// chase per general joint in the walk, and uniform DH chains never read it.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, PartialEq)]
enum StepKind {
    /// Revolute, standard DH: Rz(θ)·Tz(d)·Tx(a)·Rx(α), α exact.
    Standard,
    /// Revolute, modified DH: Rx(α)·Tx(a)·Tz(d)·Rz(θ), α exact.
    Modified,
    /// Anything else: `pre · J(θ) · post`.
    General { pre: Fixed, post: Fixed },
}

/// The numbers of a [`StepKind::Standard`] or [`StepKind::Modified`] joint
/// (zero for a general one).
#[derive(Debug, Clone, Copy, PartialEq)]
struct DhRow {
    d: f64,
    a: f64,
    twist: Exact,
}

impl DhRow {
    /// No length, no twist: a general joint's row, and a padding joint's.
    const NONE: DhRow =
        DhRow { d: 0.0, a: 0.0, twist: Exact { swap: [MASK_FALSE; 4], sy: 0.0, sz: 0.0, unturned: 0.0 } };
}

/// Whether all joints are of one straight-line kind. For such a chain the
/// walk is a loop with no branch inside a joint, so the frame stays in
/// registers from joint to joint; a per-joint `match` made the register
/// allocator spill the frame at every joint (a store and a reload on the
/// chain's serial dependency), and costs more again when the code runs cold,
/// between calls from Python.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Shape {
    Standard,
    Modified,
    Mixed,
}

const SHAPE_STANDARD: u8 = Shape::Standard as u8;
const SHAPE_MODIFIED: u8 = Shape::Modified as u8;
const SHAPE_MIXED: u8 = Shape::Mixed as u8;

/// An exact twist (0, ±90°, 180°) as lane masks, applied without a branch or
/// a multiplication: y ← select(swap, z, y) ^ sy, z ← select(swap, y, z) ^ sz,
/// where `swap` is [`MASK_TRUE`] or [`MASK_FALSE`] and `sy`, `sz` are −0.0 (flip the sign) or 0.0.
/// `swap` is stored in all four lanes, so the blend mask is one vector load:
/// from a broadcast scalar LLVM rebuilds the mask on every joint
/// (benchmarks/history.md, "Code comments moved here").
#[derive(Debug, Clone, Copy, PartialEq)]
struct Exact {
    swap: [f64; 4],
    sy: f64,
    sz: f64,
    /// Standard DH: the sign of the column that the joint's turn leaves
    /// alone, wherever the twist puts it (`sy` if swapped, else `sz`).
    unturned: f64,
}

impl Exact {
    fn of(t: Twist) -> Option<Exact> {
        let (swap, sy, sz) = match t {
            Twist::Zero => (false, false, false),
            // y ← z, z ← −y
            Twist::Plus90 => (true, false, true),
            // y ← −z, z ← y
            Twist::Minus90 => (true, true, false),
            // y ← −y, z ← −z
            Twist::Half => (false, true, true),
            Twist::Any { .. } => return None,
        };
        let sign = |flip: bool| if flip { -0.0 } else { 0.0 };
        let (sy, sz) = (sign(sy), sign(sz));
        let unturned = if swap { sy } else { sz };
        Some(Exact { swap: [if swap { MASK_TRUE } else { MASK_FALSE }; 4], sy, sz, unturned })
    }

    /// Standard DH: the sign of the column that the joint's turn produces,
    /// wherever the twist puts it (`sz` if swapped into z, else `sy`); the
    /// walk takes it into sin θ and cos θ ([`AngleBlock::flip`]).
    fn turned(&self) -> f64 {
        if self.swap[0] == MASK_TRUE {
            self.sz
        } else {
            self.sy
        }
    }
}

impl Step {
    /// The step `pre · J(θ) · post` and its DH numbers, in its straight-line
    /// form where it has one.
    fn new(pre: Fixed, prismatic: bool, post: Fixed, sign: f64) -> (Step, DhRow) {
        let row = |d, a, twist: Exact| DhRow { d, a, twist };
        let fast = match (pre, prismatic, post) {
            (Fixed::Identity, false, Fixed::TzTxRx { d, a, twist }) => {
                Exact::of(twist).map(|twist| (StepKind::Standard, row(d, a, twist)))
            }
            (Fixed::RxTxTz { twist, a, d }, false, Fixed::Identity) => {
                Exact::of(twist).map(|twist| (StepKind::Modified, row(d, a, twist)))
            }
            _ => None,
        };
        let (kind, row) = fast.unwrap_or((StepKind::General { pre, post }, DhRow::NONE));
        (Step { kind, prismatic, sign }, row)
    }
}

/// θ (or d) = sign·q + offset for eight joints, zero-padded past the last
/// joint, so that the angles of a block and their sines and cosines are
/// whole four-lane operations, and the input check of the block too.
#[derive(Debug, Clone, Copy, PartialEq)]
struct AngleBlock {
    sign: [f64; 8],
    offset: [f64; 8],
    /// Position limits on q, −∞/+∞ past the last joint: the walk scans q on the way.
    min: [f64; 8],
    max: [f64; 8],
    /// −0.0 where the straight-line step folds the twist's sign flip of the
    /// turned y column into sin θ and cos θ (see [`Angles`]), else 0.0.
    flip: [f64; 8],
}

/// The trigonometry of one block of joints, from [`AngleBlock::angles`].
struct Angles {
    /// θ (or d).
    th: [f64; BLOCK],
    s: [f64; BLOCK],
    c: [f64; BLOCK],
    /// sin θ and cos θ with the sign flip of `AngleBlock::flip`, which a
    /// straight-line step multiplies into its turned y column instead of
    /// flipping that column after the turn: one operation less on the
    /// chain's serial dependency per joint.
    sf: [f64; BLOCK],
    cf: [f64; BLOCK],
    /// Whether every joint value is finite.
    finite: bool,
    /// Bit k set when joint k of the block is outside its limits.
    outside: u32,
}

/// What a walk found out about the joint values on the way.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Scanned {
    /// Whether every value is finite (if not, the walk's results are meaningless).
    pub(crate) finite: bool,
    /// Bit i set when joint i + 1 is outside its position limits.
    pub(crate) outside: u64,
}

/// The compiled chain.
///
/// Steps, rows and angle blocks are padded with identity joints to a whole
/// number of eight-joint blocks (a padding joint has θ = 0, no offset, no
/// length and no twist, so it multiplies the frame by 1 and 0 and adds 0:
/// exactly the identity). The loops then always run over whole blocks of
/// eight joints: fully unrolled, without an exit after each joint, whose
/// merge points made the register allocator keep the frame on the stack.
/// Chains of [`EXACT`] joints also have walks of their own length, which
/// skip the padding joints (see [`by_length`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Chain {
    /// `world_from_base` as columns x, y, z, p (lane 3 zero).
    start: [[f64; 4]; 4],
    /// The number of joints (without padding).
    n: usize,
    steps: Vec<Step>,
    /// Per joint, the numbers of the straight-line kinds.
    rows: Vec<DhRow>,
    shape: Shape,
    /// Joint i is lane i % 8 of block i / 8.
    blocks: Vec<AngleBlock>,
    /// `flange_from_tool`, `None` for the identity. (Not a [`Fixed`]: a
    /// `match` on it compiles to an indirect jump, which the interpreter's
    /// own indirect jumps evict from the predictor between calls from Python.)
    tool: Option<Pose>,
    /// Per joint: position limits on q, for the one-pass input scan.
    min: Vec<f64>,
    max: Vec<f64>,
    /// Per joint of the padded chain (their length is the padded length, a
    /// multiple of [`BLOCK`]), for the Jacobian's second pass, which takes any
    /// four consecutive joints: the axis sign (0 for a padding joint), and
    /// [`MASK_TRUE`] for a prismatic joint.
    axis_sign: Vec<f64>,
    slides: Vec<f64>,
}

/// Joints per block of the padded chain.
const BLOCK: usize = 8;
/// Joints of the longest padded chain.
const MAX_PADDED: usize = crate::model::MAX_JOINTS.div_ceil(BLOCK) * BLOCK;

/// The joint counts whose hot loops are also compiled for exactly that many
/// joints ([`by_length`]): those of the built-in robots, and of most arms
/// (5, 6 and 7 axes).
pub(crate) const EXACT: [usize; 3] = [5, 6, 7];

/// Evaluates `$body` with the constant `$N` set to the chain's joint count
/// `$n` when that is one of [`EXACT`], else to 0 (the padded walk), and
/// `$CAP` to the Jacobian's axis buffer for that walk ([`BLOCK`] joints, or
/// [`MAX_PADDED`] for the padded walk).
///
/// Why (benchmarks/README.md, "Exact-length walks, one function per
/// shape"): a 7-joint chain walked as an 8-joint block pays a whole step for
/// its padding joint, about 50 instructions; the padded Jacobian's 4 KB axis
/// buffer makes a stack frame over a page, probed on every call; and with n
/// a constant the Jacobian's second pass has no loop and no bounds left.
///
/// Comparisons, not a `match`: a `match` of four arms or more can become a
/// jump table (docs/internals.md, "The hot loops").
macro_rules! by_length {
    ($n:expr, |$N:ident, $CAP:ident| $body:expr) => {{
        let n: usize = $n;
        if n == EXACT[2] {
            const $N: usize = EXACT[2];
            const $CAP: usize = BLOCK;
            $body
        } else if n == EXACT[1] {
            const $N: usize = EXACT[1];
            const $CAP: usize = BLOCK;
            $body
        } else if n == EXACT[0] {
            const $N: usize = EXACT[0];
            const $CAP: usize = BLOCK;
            $body
        } else {
            const $N: usize = 0;
            const $CAP: usize = MAX_PADDED;
            $body
        }
    }};
}

/// Evaluates `$body` with the constant `$S` set to the chain's [`Shape`]
/// (`SHAPE_*`), so that each kernel is compiled once per shape and a call
/// runs one straight-line function with no branch on the shape. With the
/// three walks in one function, the taken jumps between its distant parts
/// cost from Python, where each call starts with the branch predictors and
/// instruction caches holding the interpreter's code.
macro_rules! by_shape {
    ($shape:expr, |$S:ident| $body:expr) => {{
        match $shape {
            Shape::Standard => {
                const $S: u8 = SHAPE_STANDARD;
                $body
            }
            Shape::Modified => {
                const $S: u8 = SHAPE_MODIFIED;
                $body
            }
            Shape::Mixed => {
                const $S: u8 = SHAPE_MIXED;
                $body
            }
        }
    }};
}

/// Compiles one joint into a [`Step`] with its axis sign and offset.
fn compile_joint(j: &Joint) -> ((Step, DhRow), f64, f64) {
    let prismatic = j.kind == JointType::Prismatic;
    let step = |pre, sign: f64, offset, post| (Step::new(pre, prismatic, post, sign), sign, offset);
    match j.geometry {
        LinkGeometry::Dh { convention, d, a, alpha, theta } => {
            let twist = Twist::new(alpha);
            match (convention, prismatic) {
                // Rz(q + offset)·Tz(d)·Tx(a)·Rx(α)
                (DhConvention::Standard, false) => step(Fixed::Identity, 1.0, j.offset, Fixed::TzTxRx { d, a, twist }),
                // Rz(θ)·Tz(q + offset)·Tx(a)·Rx(α) = Tz(q + offset)·Rz(θ)·Tx(a)·Rx(α)
                (DhConvention::Standard, true) => {
                    let post = if theta == 0.0 {
                        Fixed::TzTxRx { d: 0.0, a, twist }
                    } else {
                        Fixed::General(Pose::rot_z(theta) * Pose::translation(a, 0.0, 0.0) * Pose::rot_x(alpha))
                    };
                    step(Fixed::Identity, 1.0, j.offset, post)
                }
                // Rx(α)·Tx(a)·Rz(q + offset)·Tz(d) = Rx(α)·Tx(a)·Tz(d)·Rz(q + offset)
                (DhConvention::Modified, false) => step(Fixed::RxTxTz { twist, a, d }, 1.0, j.offset, Fixed::Identity),
                // Rx(α)·Tx(a)·Rz(θ)·Tz(q + offset)
                (DhConvention::Modified, true) => {
                    let pre = if theta == 0.0 {
                        Fixed::RxTxTz { twist, a, d: 0.0 }
                    } else {
                        Fixed::General(Pose::rot_x(alpha) * Pose::translation(a, 0.0, 0.0) * Pose::rot_z(theta))
                    };
                    step(pre, 1.0, j.offset, Fixed::Identity)
                }
            }
        }
        LinkGeometry::General { origin, axis } => {
            // Motion about/along ±z needs no re-alignment, only the sign of q:
            // a motion of q about −z is a motion of −q about z.
            if (axis.z.abs() - 1.0).abs() < 1e-15 && axis.x == 0.0 && axis.y == 0.0 {
                let sign = axis.z.signum();
                return step(Fixed::from_pose(origin), sign, sign * j.offset, Fixed::Identity);
            }
            // Motion about/along `axis` = Ra · (motion about/along z) · Raᵀ with Ra·z = axis.
            let align = Pose::new(align_z_to(&axis), Vector3::zeros());
            step(Fixed::General(origin * align), 1.0, j.offset, Fixed::General(align.inverse()))
        }
    }
}

/// A rotation taking the z axis onto the unit vector `u`.
fn align_z_to(u: &Vector3<f64>) -> Matrix3<f64> {
    let z = Vector3::z();
    let c = z.dot(u);
    if c > 1.0 - 1e-15 {
        return Matrix3::identity();
    }
    if c < -1.0 + 1e-15 {
        // Half turn about x.
        return Matrix3::new(1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0);
    }
    let axis = z.cross(u).normalize();
    crate::math::axis_angle_to_rot(&(axis * c.clamp(-1.0, 1.0).acos()))
}

impl Chain {
    /// Compiles joints with base (`world_from_base`) and tool (`flange_from_tool`) transforms.
    pub(crate) fn new(joints: &[Joint], base: &Pose, tool: &Pose) -> Chain {
        let compiled: Vec<((Step, DhRow), f64, f64)> = joints.iter().map(compile_joint).collect();
        let mut steps: Vec<Step> = compiled.iter().map(|c| c.0 .0).collect();
        let mut rows: Vec<DhRow> = compiled.iter().map(|c| c.0 .1).collect();
        let shape = if steps.iter().all(|s| s.kind == StepKind::Standard) {
            Shape::Standard
        } else if steps.iter().all(|s| s.kind == StepKind::Modified) {
            Shape::Modified
        } else {
            Shape::Mixed
        };
        // Padding joints of the chain's own kind, so a uniform chain stays uniform.
        let pad_kind = match shape {
            Shape::Standard => StepKind::Standard,
            Shape::Modified => StepKind::Modified,
            Shape::Mixed => StepKind::General { pre: Fixed::Identity, post: Fixed::Identity },
        };
        while steps.len() % BLOCK != 0 {
            steps.push(Step { kind: pad_kind, prismatic: false, sign: 0.0 });
            rows.push(DhRow::NONE);
        }
        let empty = AngleBlock {
            sign: [0.0; BLOCK],
            offset: [0.0; BLOCK],
            min: [f64::NEG_INFINITY; BLOCK],
            max: [f64::INFINITY; BLOCK],
            flip: [0.0; BLOCK],
        };
        let mut blocks = vec![empty; steps.len() / BLOCK];
        let (mut axis_sign, mut slides) = (vec![0.0; steps.len()], vec![MASK_FALSE; steps.len()]);
        for (i, (&(_, sign, offset), j)) in compiled.iter().zip(joints).enumerate() {
            let (b, k) = (&mut blocks[i / BLOCK], i % BLOCK);
            (b.sign[k], b.offset[k], b.min[k], b.max[k]) = (sign, offset, j.limits.min, j.limits.max);
            axis_sign[i] = sign;
            slides[i] = if j.kind == JointType::Prismatic { MASK_TRUE } else { MASK_FALSE };
            let tw = &rows[i].twist;
            b.flip[k] = match steps[i].kind {
                StepKind::Standard => tw.turned(),
                // The twist's flip sy of y comes before the turn, which is linear in y.
                StepKind::Modified => tw.sy,
                StepKind::General { .. } => 0.0,
            };
        }
        let col = |j: usize| [base.rot[(0, j)], base.rot[(1, j)], base.rot[(2, j)], 0.0];
        Chain {
            start: [col(0), col(1), col(2), [base.pos.x, base.pos.y, base.pos.z, 0.0]],
            n: joints.len(),
            rows,
            steps,
            shape,
            blocks,
            tool: (*tool != Pose::IDENTITY).then_some(*tool),
            min: joints.iter().map(|j| j.limits.min).collect(),
            max: joints.iter().map(|j| j.limits.max).collect(),
            axis_sign,
            slides,
        }
    }

    /// One branch-free pass over joint values of the right length: whether
    /// all are finite and below [`MAX_MAGNITUDE`], and the bit set of those
    /// outside their limits.
    #[inline(always)]
    pub(crate) fn scan(&self, q: &[f64]) -> (bool, u64) {
        let mut finite = true;
        let mut bits = 0u64;
        for (i, ((&v, &lo), &hi)) in q.iter().zip(&self.min).zip(&self.max).enumerate() {
            finite &= v.abs() < MAX_MAGNITUDE;
            bits |= (((v < lo) | (v > hi)) as u64) << i;
        }
        (finite, bits)
    }

    /// `world_from_tool` for `q` of length n, and what the walk found about
    /// `q` (the pose is meaningless if a value is not finite).
    #[inline(always)]
    pub(crate) fn fk(&self, q: &[f64]) -> (Pose, Scanned) {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = Avx2Fma::detect() {
            return by_shape!(self.shape, |S| by_length!(self.n, |N, _CAP| avx.fk::<S, N>(self, q)));
        }
        by_shape!(self.shape, |S| fk_core::<P4, S, 0>(self, q))
    }

    /// `world_from_tool` as the rows of its 4 × 4 homogeneous matrix, written
    /// into `out` (nothing is written when a value of `q` is not finite),
    /// and what the walk found about `q`.
    #[inline(always)]
    pub(crate) fn fk_rows(&self, q: &[f64], out: &mut [MaybeUninit<f64>; 16]) -> Scanned {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = Avx2Fma::detect() {
            return by_shape!(self.shape, |S| by_length!(self.n, |N, _CAP| avx.fk_rows::<S, N>(self, q, out)));
        }
        by_shape!(self.shape, |S| fk_rows_core::<P4, S, 0>(self, q, out))
    }

    /// Link frames `out[1..=n]` and the tool frame `out[n + 1]`; `out` has n + 2 entries.
    pub(crate) fn link_frames(&self, q: &[f64], out: &mut [Pose]) {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = Avx2Fma::detect() {
            return by_shape!(self.shape, |S| by_length!(self.n, |N, _CAP| avx.link_frames::<S, N>(self, q, out)));
        }
        by_shape!(self.shape, |S| link_frames_core::<P4, S, 0>(self, q, out))
    }

    /// Geometric Jacobian into the 6 × n storage `data` (`layout`, at least
    /// 6·n values; all of the first 6·n are written), for `q` of length n,
    /// and `world_from_tool` into `pose` when one is given; returns what the
    /// walk found about `q`. Nothing is written when a value of `q` is not
    /// finite.
    #[inline(always)]
    pub(crate) fn jacobian(
        &self,
        q: &[f64],
        tool_frame: bool,
        layout: Layout,
        data: &mut [MaybeUninit<f64>],
        pose: Option<&mut Pose>,
    ) -> Scanned {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = Avx2Fma::detect() {
            return by_shape!(self.shape, |S| by_length!(self.n, |N, CAP| match (layout, tool_frame) {
                (Layout::ColumnMajor, false) => avx.jacobian::<COLUMN_MAJOR, false, S, N, CAP>(self, q, data, pose),
                (Layout::ColumnMajor, true) => avx.jacobian::<COLUMN_MAJOR, true, S, N, CAP>(self, q, data, pose),
                (Layout::RowMajor, false) => avx.jacobian::<ROW_MAJOR, false, S, N, CAP>(self, q, data, pose),
                (Layout::RowMajor, true) => avx.jacobian::<ROW_MAJOR, true, S, N, CAP>(self, q, data, pose),
            }));
        }
        self.jacobian_portable(q, tool_frame, layout, data, pose)
    }

    /// [`Chain::jacobian`] on the portable code path, whatever the CPU (also
    /// for tests that compare paths). It walks the padded chain whatever its
    /// length: compiled for every CPU, its code is kept small.
    #[inline]
    fn jacobian_portable(
        &self,
        q: &[f64],
        tool_frame: bool,
        layout: Layout,
        data: &mut [MaybeUninit<f64>],
        pose: Option<&mut Pose>,
    ) -> Scanned {
        by_shape!(self.shape, |S| match (layout, tool_frame) {
            (Layout::ColumnMajor, false) =>
                jacobian_core::<P4, COLUMN_MAJOR, false, S, 0, MAX_PADDED>(self, q, data, pose),
            (Layout::ColumnMajor, true) =>
                jacobian_core::<P4, COLUMN_MAJOR, true, S, 0, MAX_PADDED>(self, q, data, pose),
            (Layout::RowMajor, false) => jacobian_core::<P4, ROW_MAJOR, false, S, 0, MAX_PADDED>(self, q, data, pose),
            (Layout::RowMajor, true) => jacobian_core::<P4, ROW_MAJOR, true, S, 0, MAX_PADDED>(self, q, data, pose),
        })
    }

    /// The portable code path, whatever the CPU (for tests that compare paths).
    #[cfg(test)]
    fn fk_portable(&self, q: &[f64]) -> Pose {
        by_shape!(self.shape, |S| fk_core::<P4, S, 0>(self, q).0)
    }

    /// Walks the chain: `axis(i, f)` sees the frame whose z axis (times
    /// `steps[i].sign`) is joint i's axis, `link(i, f)` the frame of link i.
    /// With `N` = 0 the whole padded chain is walked and both are also called
    /// for the padding joints (i ≥ n); otherwise `N` must be n (one of
    /// [`EXACT`]) and only the n joints are walked. `q` must have n values.
    /// Returns `world_from_tool` and what was found about `q`.
    ///
    /// The chain is of shape `SHAPE` (the kernels are compiled per shape,
    /// see [`by_shape`]): for the uniform shapes the kind of every joint is
    /// known here and the loop body has no branch.
    #[inline(always)]
    fn walk<V: Lanes, const SHAPE: u8, const N: usize>(
        &self,
        q: &[f64],
        mut axis: impl FnMut(usize, &Xf<V>),
        mut link: impl FnMut(usize, &Xf<V>),
    ) -> (Xf<V>, Scanned) {
        debug_assert_eq!(SHAPE, self.shape as u8);
        let [x, y, z, p] = self.start;
        let mut scanned = Scanned { finite: true, outside: 0 };
        let mut t = Xf { x: V::from_array(x), y: V::from_array(y), z: V::from_array(z), p: V::from_array(p) };
        const { assert!(N <= BLOCK) };
        debug_assert!(N == 0 || N == self.n);
        // An exact-length walk: the first block's first N joints, the only real ones.
        let (blocks, per_block) = if N == 0 { (&self.blocks[..], BLOCK) } else { (&self.blocks[..1], N) };
        for (b, block) in blocks.iter().enumerate() {
            let start = b * BLOCK;
            // Indexed, not zipped: the bounds of four zipped sequences cost
            // some forty instructions per call.
            let qs = q.get(start..).unwrap_or(&[]);
            let qs = &qs[..qs.len().min(BLOCK)];
            // SAFETY: `steps` and `rows` have BLOCK values per block
            // (`Chain::new` pads them), so [start, start + BLOCK) is within both.
            let (steps, rows): (&[Step; BLOCK], &[DhRow; BLOCK]) =
                unsafe { (&*self.steps.as_ptr().add(start).cast(), &*self.rows.as_ptr().add(start).cast()) };
            let Angles { th, s, c, sf, cf, finite, outside } = block.angles::<V>(qs);
            scanned.finite &= finite;
            scanned.outside |= u64::from(outside) << (b * BLOCK);
            for k in 0..per_block {
                let (i, step, row) = (b * BLOCK + k, &steps[k], &rows[k]);
                let kind = match SHAPE {
                    SHAPE_STANDARD => StepKind::Standard,
                    SHAPE_MODIFIED => StepKind::Modified,
                    _ => step.kind,
                };
                match kind {
                    StepKind::Standard => {
                        axis(i, &t);
                        // Rz(θ) then the exact twist: x ← c·x + s·y,
                        // w = ±(c·y − s·x) with the twist's flip of this
                        // column already in (cf, sf), z ← ±z; then y, z ← w, z
                        // or z, w. The frame's serial dependency per joint is
                        // a multiply, a fused multiply-add and a blend; the
                        // sign flip that used to follow the blend is off it.
                        let (x, y, z) = (t.x, t.y, t.z);
                        let (sv, cv) = (V::splat(s[k]), V::splat(c[k]));
                        let xn = cv.madd(x, sv.mul(y));
                        let w = V::splat(cf[k]).msub(y, V::splat(sf[k]).mul(x));
                        let zs = z.xor(V::splat(row.twist.unturned));
                        let swap = V::from_array(row.twist.swap);
                        (t.x, t.y, t.z) = (xn, swap.select(zs, w), swap.select(w, zs));
                        // Tz(d)·Tx(a): p ← p + (a·x + d·z), one add on p's own
                        // dependency chain rather than two fused multiply-adds.
                        t.p = t.p.add(V::splat(row.a).madd(xn, V::splat(row.d).mul(z)));
                    }
                    StepKind::Modified => {
                        // The exact twist, its flip of y left to the turn's
                        // (cf, sf): u = y or z; z ← ±(z or y).
                        let (x, y, z) = (t.x, t.y, t.z);
                        let swap = V::from_array(row.twist.swap);
                        let u = swap.select(z, y);
                        t.z = swap.select(y, z).xor(V::splat(row.twist.sz));
                        t.y = u.xor(V::splat(row.twist.sy));
                        // Tx(a)·Tz(d): p ← p + d·z + a·x. (The one-add form of
                        // the standard step measured no faster for the panda.)
                        t.p = V::splat(row.a).madd(x, V::splat(row.d).madd(t.z, t.p));
                        axis(i, &t);
                        // Rz(θ) on (x, ±u): x ← c·x + (±s)·u, y ← (±c)·u − s·x.
                        let (sv, cv) = (V::splat(s[k]), V::splat(c[k]));
                        t.x = cv.madd(x, V::splat(sf[k]).mul(u));
                        t.y = V::splat(cf[k]).msub(u, sv.mul(x));
                    }
                    StepKind::General { ref pre, ref post } => {
                        t.fixed(pre);
                        axis(i, &t);
                        if step.prismatic {
                            t.slide(th[k]);
                        } else {
                            t.turn(s[k], c[k]);
                        }
                        t.fixed(post);
                    }
                }
                link(i, &t);
            }
        }
        if let Some(tool) = &self.tool {
            t.general(tool);
        }
        (t, scanned)
    }
}

impl AngleBlock {
    /// θ = sign·q + offset for the (up to eight) values `q`, sin θ, cos θ,
    /// whether every value of `q` is finite, and the bits of those outside
    /// their limits.
    #[inline(always)]
    fn angles<V: Lanes>(&self, q: &[f64]) -> Angles {
        // Masked loads (a copy of variable length would be a `memcpy` call
        // whose wide overlapping stores would not forward to the loads, and
        // a read per lane a branch per lane). No closures or iterator
        // adaptors around lane operations here: a closure is a function of
        // its own, compiled without the AVX2 target feature, and the
        // intrinsics would not be inlined into it.
        let split = q.len().min(4);
        let (q_lo, q_hi) = (V::load_prefix(&q[..split]), V::load_prefix(&q[split..]));
        let lo = V::from_array(quarter(&self.sign, 0)).madd(q_lo, V::from_array(quarter(&self.offset, 0)));
        let hi = V::from_array(quarter(&self.sign, 1)).madd(q_hi, V::from_array(quarter(&self.offset, 1)));
        let max = V::splat(MAX_MAGNITUDE);
        let finite = (q_lo.abs().lt_bits(max) | (q_hi.abs().lt_bits(max) << 4)) == 0xff;
        let below = q_lo.lt_bits(V::from_array(quarter(&self.min, 0)))
            | (q_hi.lt_bits(V::from_array(quarter(&self.min, 1))) << 4);
        let above = q_lo.gt_bits(V::from_array(quarter(&self.max, 0)))
            | (q_hi.gt_bits(V::from_array(quarter(&self.max, 1))) << 4);
        let (s_lo, c_lo) = lo.sin_cos();
        let (s_hi, c_hi) = hi.sin_cos();
        let angles = join(lo.to_array(), hi.to_array());
        let (mut s, mut c) = (join(s_lo.to_array(), s_hi.to_array()), join(c_lo.to_array(), c_hi.to_array()));
        if !(lo.all_abs_le(SIN_COS_RANGE) & hi.all_abs_le(SIN_COS_RANGE)) {
            out_of_kernel_range(&angles, &mut s, &mut c);
        }
        let (f_lo, f_hi) = (V::from_array(quarter(&self.flip, 0)), V::from_array(quarter(&self.flip, 1)));
        let [s_lo, s_hi, c_lo, c_hi] =
            [quarter(&s, 0), quarter(&s, 1), quarter(&c, 0), quarter(&c, 1)].map(V::from_array);
        let sf = join(s_lo.xor(f_lo).to_array(), s_hi.xor(f_hi).to_array());
        let cf = join(c_lo.xor(f_lo).to_array(), c_hi.xor(f_hi).to_array());
        Angles { th: angles, s, c, sf, cf, finite, outside: below | above }
    }
}

#[cfg(test)]
mod tests;
