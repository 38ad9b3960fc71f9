//! The compiled chain and the hot loops that run on it.
//!
//! A robot description (three kinds of link, see [`crate::LinkGeometry`]) is
//! compiled once into
//!
//! ```text
//! base_from_tool(q) = base · (pre1 · J(θ1) · post1) · … · (pren · J(θn) · postn) · tool
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

use nalgebra::{Matrix3, Vector3};

use crate::math::{sin_cos_kernel, Pose, SIN_COS_RANGE};
use crate::model::{DhConvention, Joint, JointType, LinkGeometry};

/// A rotation Rx(α) as (cos α, sin α), exact (0, ±1) for the common twists
/// 0, ±90° and 180°: applying it is four multiply-adds per lane and no branch,
/// and for those twists the products are exact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Twist {
    ca: f64,
    sa: f64,
}

impl Twist {
    fn new(alpha: f64) -> Twist {
        use std::f64::consts::{FRAC_PI_2, PI};
        let near = |v: f64| (alpha - v).abs() < 1e-12;
        let (ca, sa) = if near(0.0) {
            (1.0, 0.0)
        } else if near(FRAC_PI_2) {
            (0.0, 1.0)
        } else if near(-FRAC_PI_2) {
            (0.0, -1.0)
        } else if near(PI) || near(-PI) {
            (-1.0, 0.0)
        } else {
            let (sa, ca) = alpha.sin_cos();
            (ca, sa)
        };
        Twist { ca, sa }
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

/// One joint of the compiled chain: `pre · J(θ) · post`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Step {
    pre: Fixed,
    prismatic: bool,
    post: Fixed,
}

/// The compiled chain. Joint signs and offsets are kept as arrays of their
/// own so the joint angles of a whole chain are computed in one vector loop.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Chain {
    start: Xf,
    steps: Vec<Step>,
    /// Per joint: ±1, the direction of the joint axis along local z.
    signs: Vec<f64>,
    /// Per joint: θ (or d) = sign·q + offset.
    offsets: Vec<f64>,
    tool: Fixed,
    /// Per joint: position limits on q, for the one-pass input scan.
    min: Vec<f64>,
    max: Vec<f64>,
}

/// Compiles one joint into a [`Step`] with its axis sign and offset.
fn compile_joint(j: &Joint) -> (Step, f64, f64) {
    let prismatic = j.kind == JointType::Prismatic;
    let step = |pre, sign: f64, offset, post| (Step { pre, prismatic, post }, sign, offset);
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
        let compiled: Vec<(Step, f64, f64)> = joints.iter().map(compile_joint).collect();
        Chain {
            start: Xf::from_pose(base),
            steps: compiled.iter().map(|c| c.0).collect(),
            signs: compiled.iter().map(|c| c.1).collect(),
            offsets: compiled.iter().map(|c| c.2).collect(),
            tool: Fixed::from_pose(*tool),
            min: joints.iter().map(|j| j.limits.min).collect(),
            max: joints.iter().map(|j| j.limits.max).collect(),
        }
    }

    /// One branch-free pass over joint values of the right length: whether
    /// all are finite, and the bit set of those outside their limits.
    #[inline(always)]
    pub(crate) fn scan(&self, q: &[f64]) -> (bool, u64) {
        let mut finite = true;
        let mut bits = 0u64;
        for (i, ((&v, &lo), &hi)) in q.iter().zip(&self.min).zip(&self.max).enumerate() {
            finite &= v.is_finite();
            bits |= (((v < lo) | (v > hi)) as u64) << i;
        }
        (finite, bits)
    }

    /// `base_from_tool` for joint values already checked (length, finiteness).
    #[inline]
    pub(crate) fn fk(&self, q: &[f64]) -> Pose {
        #[cfg(target_arch = "x86_64")]
        if has_avx2_fma() {
            // SAFETY: the CPU supports AVX2 and FMA (checked just above).
            return unsafe { fk_avx2(self, q) };
        }
        self.walk::<Plain>(q, |_, _| {}, |_, _| {}).pose()
    }

    /// Link frames `out[1..=n]` and the tool frame `out[n + 1]`; `out` has n + 2 entries.
    pub(crate) fn link_frames(&self, q: &[f64], out: &mut [Pose]) {
        #[cfg(target_arch = "x86_64")]
        if has_avx2_fma() {
            // SAFETY: the CPU supports AVX2 and FMA (checked just above).
            return unsafe { link_frames_avx2(self, q, out) };
        }
        link_frames_core::<Plain>(self, q, out)
    }

    /// Geometric Jacobian into column-major 6 × n storage `data`; returns `base_from_tool`.
    #[inline]
    pub(crate) fn jacobian(&self, q: &[f64], tool_frame: bool, data: &mut [f64]) -> Pose {
        #[cfg(target_arch = "x86_64")]
        if has_avx2_fma() {
            // SAFETY: the CPU supports AVX2 and FMA (checked just above).
            return unsafe { jacobian_avx2(self, q, tool_frame, data) };
        }
        jacobian_core::<Plain>(self, q, tool_frame, data)
    }

    /// The portable code path, whatever the CPU (for tests that compare paths).
    #[cfg(test)]
    fn fk_portable(&self, q: &[f64]) -> Pose {
        self.walk::<Plain>(q, |_, _| {}, |_, _| {}).pose()
    }

    #[cfg(test)]
    fn jacobian_portable(&self, q: &[f64], tool_frame: bool, data: &mut [f64]) -> Pose {
        jacobian_core::<Plain>(self, q, tool_frame, data)
    }

    /// Walks the chain: `axis(i, f)` sees the frame whose z axis (times
    /// `signs[i]`) is joint i's axis, `link(i, f)` the frame of link i.
    /// Returns `base_from_tool`.
    #[inline(always)]
    fn walk<M: Madd>(&self, q: &[f64], mut axis: impl FnMut(usize, &Xf), mut link: impl FnMut(usize, &Xf)) -> Xf {
        let n = q.len().min(self.steps.len());
        let mut t = self.start;
        let mut base = 0;
        while base < n {
            let m = (n - base).min(8);
            let mut th = [0.0; 8];
            for k in 0..m {
                th[k] = M::madd(self.signs[base + k], q[base + k], self.offsets[base + k]);
            }
            let (mut s, mut c) = ([0.0; 8], [0.0; 8]);
            sin_cos_8::<M>(&th, &mut s, &mut c);
            for k in 0..m {
                let i = base + k;
                let step = &self.steps[i];
                t.fixed::<M>(&step.pre);
                axis(i, &t);
                if step.prismatic {
                    t.slide::<M>(th[k]);
                } else {
                    t.turn::<M>(s[k], c[k]);
                }
                t.fixed::<M>(&step.post);
                link(i, &t);
            }
            base += m;
        }
        t.fixed::<M>(&self.tool);
        t
    }
}

#[inline(always)]
fn link_frames_core<M: Madd>(ch: &Chain, q: &[f64], out: &mut [Pose]) {
    let t = ch.walk::<M>(q, |_, _| {}, |i, f| out[i + 1] = f.pose());
    out[q.len() + 1] = t.pose();
}

#[inline(always)]
fn jacobian_core<M: Madd>(ch: &Chain, q: &[f64], tool_frame: bool, data: &mut [f64]) -> Pose {
    // First pass: joint axis origins (rows 0..3) and directions (rows 3..6).
    let t = ch.walk::<M>(
        q,
        |i, f| {
            let col = &mut data[6 * i..6 * i + 6];
            let sign = ch.signs[i];
            col[..3].copy_from_slice(&f.p[..3]);
            for k in 0..3 {
                col[3 + k] = sign * f.z[k];
            }
        },
        |_, _| {},
    );
    let pe = t.p;
    for (col, step) in data.chunks_exact_mut(6).zip(&ch.steps) {
        let z = [col[3], col[4], col[5]];
        if step.prismatic {
            col[..3].copy_from_slice(&z);
            col[3..].fill(0.0);
        } else {
            // z × (p_tool − o)
            let r = [pe[0] - col[0], pe[1] - col[1], pe[2] - col[2]];
            col[0] = M::madd(z[1], r[2], -(z[2] * r[1]));
            col[1] = M::madd(z[2], r[0], -(z[0] * r[2]));
            col[2] = M::madd(z[0], r[1], -(z[1] * r[0]));
        }
        if tool_frame {
            // Rᵀ·v: dot products with the tool's axes.
            let dot = |c: &[f64], a: &[f64; 4]| M::madd(c[0], a[0], M::madd(c[1], a[1], c[2] * a[2]));
            let v = [dot(&col[..3], &t.x), dot(&col[..3], &t.y), dot(&col[..3], &t.z)];
            let w = [dot(&col[3..], &t.x), dot(&col[3..], &t.y), dot(&col[3..], &t.z)];
            col[..3].copy_from_slice(&v);
            col[3..].copy_from_slice(&w);
        }
    }
    t.pose()
}

#[cfg(target_arch = "x86_64")]
fn has_avx2_fma() -> bool {
    std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn fk_avx2(ch: &Chain, q: &[f64]) -> Pose {
    ch.walk::<Fused>(q, |_, _| {}, |_, _| {}).pose()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn link_frames_avx2(ch: &Chain, q: &[f64], out: &mut [Pose]) {
    link_frames_core::<Fused>(ch, q, out)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn jacobian_avx2(ch: &Chain, q: &[f64], tool_frame: bool, data: &mut [f64]) -> Pose {
    jacobian_core::<Fused>(ch, q, tool_frame, data)
}

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
struct Fused;

#[cfg(target_arch = "x86_64")]
impl Madd for Fused {
    #[inline(always)]
    fn madd(a: f64, b: f64, c: f64) -> f64 {
        a.mul_add(b, c)
    }
}

/// Sine and cosine of eight values at once (a loop LLVM vectorises), with
/// the standard library as fallback for |x| beyond the kernel's range.
#[inline(always)]
fn sin_cos_8<M: Madd>(x: &[f64; 8], s: &mut [f64; 8], c: &mut [f64; 8]) {
    for i in 0..8 {
        let (si, ci) = sin_cos_kernel::<M>(x[i]);
        s[i] = si;
        c[i] = ci;
    }
    for i in 0..8 {
        if !(x[i].abs() <= SIN_COS_RANGE) {
            (s[i], c[i]) = x[i].sin_cos();
        }
    }
}

/// A rigid transform as four 4-lane columns (x, y, z axes and position; lane
/// 3 is padding), the form the hot loops work on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Xf {
    x: [f64; 4],
    y: [f64; 4],
    z: [f64; 4],
    p: [f64; 4],
}

impl Xf {
    fn from_pose(t: &Pose) -> Xf {
        let c = |j: usize| [t.rot[(0, j)], t.rot[(1, j)], t.rot[(2, j)], 0.0];
        Xf { x: c(0), y: c(1), z: c(2), p: [t.pos.x, t.pos.y, t.pos.z, 0.0] }
    }

    #[inline(always)]
    fn pose(&self) -> Pose {
        let (x, y, z) = (self.x, self.y, self.z);
        Pose {
            rot: Matrix3::new(x[0], y[0], z[0], x[1], y[1], z[1], x[2], y[2], z[2]),
            pos: Vector3::new(self.p[0], self.p[1], self.p[2]),
        }
    }

    /// `self ← self · Rz(θ)` given sin θ and cos θ.
    #[inline(always)]
    fn turn<M: Madd>(&mut self, s: f64, c: f64) {
        let (x, y) = (self.x, self.y);
        for k in 0..4 {
            self.x[k] = M::madd(c, x[k], s * y[k]);
            self.y[k] = M::madd(c, y[k], -(s * x[k]));
        }
    }

    /// `self ← self · Tz(d)`.
    #[inline(always)]
    fn slide<M: Madd>(&mut self, d: f64) {
        for k in 0..4 {
            self.p[k] = M::madd(d, self.z[k], self.p[k]);
        }
    }

    /// `self ← self · Rx(α)`.
    #[inline(always)]
    fn twist<M: Madd>(&mut self, tw: Twist) {
        let (y, z) = (self.y, self.z);
        for k in 0..4 {
            self.y[k] = M::madd(tw.ca, y[k], tw.sa * z[k]);
            self.z[k] = M::madd(tw.ca, z[k], -(tw.sa * y[k]));
        }
    }

    /// `self ← self · f`.
    #[inline(always)]
    fn fixed<M: Madd>(&mut self, f: &Fixed) {
        match *f {
            Fixed::Identity => {}
            Fixed::TzTxRx { d, a, twist } => {
                for k in 0..4 {
                    self.p[k] = M::madd(d, self.z[k], M::madd(a, self.x[k], self.p[k]));
                }
                self.twist::<M>(twist);
            }
            Fixed::RxTxTz { twist, a, d } => {
                self.twist::<M>(twist);
                for k in 0..4 {
                    self.p[k] = M::madd(a, self.x[k], M::madd(d, self.z[k], self.p[k]));
                }
            }
            Fixed::General(ref g) => {
                let (x, y, z) = (self.x, self.y, self.z);
                // Column j of R·G, and the position p + R·g.
                let comb = |a: f64, b: f64, c: f64, base: [f64; 4]| {
                    let mut out = [0.0; 4];
                    for k in 0..4 {
                        out[k] = M::madd(x[k], a, M::madd(y[k], b, M::madd(z[k], c, base[k])));
                    }
                    out
                };
                self.p = comb(g.pos.x, g.pos.y, g.pos.z, self.p);
                let col = |j: usize| comb(g.rot[(0, j)], g.rot[(1, j)], g.rot[(2, j)], [0.0; 4]);
                self.x = col(0);
                self.y = col(1);
                self.z = col(2);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    use crate::Robot;

    /// The dispatched path (AVX2+FMA where available) and the portable path
    /// agree on every built-in robot; on a CPU without FMA they are the same code.
    #[test]
    fn vector_and_portable_paths_agree() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for name in crate::builtin_names() {
            let r = Robot::builtin(name).unwrap();
            let n = r.dof();
            let (mut a, mut b) = (vec![0.0; 6 * n], vec![0.0; 6 * n]);
            for _ in 0..2000 {
                let q = r.random_q(&mut rng);
                let (p1, p2) = (r.chain.fk(&q), r.chain.fk_portable(&q));
                assert!((p1.pos - p2.pos).norm() < 1e-14 && (p1.rot - p2.rot).norm() < 1e-14, "{name}");
                for tool in [false, true] {
                    r.chain.jacobian(&q, tool, &mut a);
                    r.chain.jacobian_portable(&q, tool, &mut b);
                    let diff = a.iter().zip(&b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
                    assert!(diff < 1e-14, "{name}: {diff}");
                }
            }
        }
    }
}
