//! The hot loops on a compiled [`Chain`]: forward kinematics, link frames
//! and Jacobians over lanes of [`Lanes`], generic over the chain's shape and
//! walk so that each combination compiles to straight-line code.

use super::*;

/// The dot products of the 3-vectors in the lanes of `v` with `axis`, in the
/// order of a scalar `v0·a0 + (v1·a1 + v2·a2)`.
#[inline(always)]
pub(super) fn dot3<V: Lanes>(v: [V; 3], axis: &[f64; 4]) -> V {
    v[0].madd(V::splat(axis[0]), v[1].madd(V::splat(axis[1]), v[2].mul(V::splat(axis[2]))))
}

/// `data` as memory to write the kernels' results into, which take
/// `MaybeUninit` so that they can also write into memory never initialised
/// (a fresh NumPy array).
///
/// # Safety
/// Only initialised values may be written through the view while it lives
/// (no `MaybeUninit::uninit()`): `data` is `f64` again afterwards, and
/// reading an uninitialised `f64` is undefined behaviour. The kernels of
/// this module write only computed `f64` values.
pub(crate) unsafe fn as_uninit(data: &mut [f64]) -> &mut [MaybeUninit<f64>] {
    // SAFETY: `MaybeUninit<f64>` has the layout of `f64`, and the caller
    // keeps the elements initialised (above).
    unsafe { std::slice::from_raw_parts_mut(data.as_mut_ptr().cast(), data.len()) }
}

/// Lanes 4h..4h+4 of `a`.
#[inline(always)]
pub(super) fn quarter(a: &[f64; 8], h: usize) -> [f64; 4] {
    [a[4 * h], a[4 * h + 1], a[4 * h + 2], a[4 * h + 3]]
}

/// Eight lanes from two fours.
#[inline(always)]
pub(super) fn join(a: [f64; 4], b: [f64; 4]) -> [f64; 8] {
    [a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]]
}

/// Sine and cosine from the standard library for the angles beyond the
/// fast kernel's range (huge or non-finite θ; never for checked joint values
/// within a robot's limits).
#[cold]
#[inline(never)]
pub(super) fn out_of_kernel_range(th: &[f64; 8], s: &mut [f64; 8], c: &mut [f64; 8]) {
    for k in 0..8 {
        if !(th[k].abs() <= SIN_COS_RANGE) {
            (s[k], c[k]) = th[k].sin_cos();
        }
    }
}

#[inline(always)]
pub(crate) fn fk_core<V: Lanes, const S: u8, const N: usize>(ch: &Chain, q: &[f64]) -> (Pose, Scanned) {
    let (t, scanned) = ch.walk::<V, S, N>(q, |_, _| {}, |_, _| {});
    (t.pose(), scanned)
}

/// The rows of the homogeneous matrix straight from the frame's lanes: the
/// transpose of the columns (x, y, z, p) is the three upper rows (lane 3 of
/// every column is zero), and the last row is (0, 0, 0, 1).
#[inline(always)]
pub(crate) fn fk_rows_core<V: Lanes, const S: u8, const N: usize>(
    ch: &Chain,
    q: &[f64],
    out: &mut [MaybeUninit<f64>; 16],
) -> Scanned {
    let (t, scanned) = ch.walk::<V, S, N>(q, |_, _| {}, |_, _| {});
    if scanned.finite {
        let [r0, r1, r2, _] = V::transpose([t.x, t.y, t.z, t.p]);
        let (head, tail) = out.split_at_mut(8);
        r0.store_prefix(&mut head[..4]);
        r1.store_prefix(&mut head[4..]);
        r2.store_prefix(&mut tail[..4]);
        V::from_array([0.0, 0.0, 0.0, 1.0]).store_prefix(&mut tail[4..]);
    }
    scanned
}

#[inline(always)]
pub(crate) fn link_frames_core<V: Lanes, const S: u8, const N: usize>(ch: &Chain, q: &[f64], out: &mut [Pose]) {
    let n = ch.n;
    let (t, _) = ch.walk::<V, S, N>(
        q,
        |_, _| {},
        |i, f| {
            if i < n {
                out[i + 1] = f.pose()
            }
        },
    );
    out[n + 1] = t.pose();
}

/// How [`Chain::jacobian`] lays out the 6 × n matrix in its output slice.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Layout {
    /// Column c is `data[6c..6c + 6]` (nalgebra's `Matrix6xX`).
    ColumnMajor,
    /// Row r is `data[r·n..(r + 1)·n]` (a C or numpy array).
    RowMajor,
}

pub(super) const COLUMN_MAJOR: bool = false;
pub(super) const ROW_MAJOR: bool = true;

/// The Jacobian for the walk `N` (see [`Chain::walk`]), with room for `CAP`
/// joints' axes: [`MAX_PADDED`] for the padded walk, [`BLOCK`] for an exact one.
#[inline(always)]
pub(crate) fn jacobian_core<
    V: Lanes,
    const ROWS: bool,
    const TOOL: bool,
    const S: u8,
    const N: usize,
    const CAP: usize,
>(
    ch: &Chain,
    q: &[f64],
    data: &mut [MaybeUninit<f64>],
    pose: Option<&mut Pose>,
) -> Scanned {
    // With an exact walk, n is a constant: the second pass's block bounds,
    // row offsets and store widths are then all known at compile time.
    let n = if N > 0 { N } else { ch.n };
    const { assert!(CAP % BLOCK == 0 && (N == 0 && CAP == MAX_PADDED || N > 0 && CAP == BLOCK)) };
    // First pass: each joint's axis origin and direction (unsigned), for the
    // padding joints too in a padded walk, so the walk has no branch (a
    // padding joint's axis is read only to fill the unused lanes of a short
    // last block).
    let mut axes = [MaybeUninit::<[[f64; 4]; 2]>::uninit(); CAP];
    let (t, scanned) = ch.walk::<V, S, N>(
        q,
        |i, f| {
            axes[i].write([f.p.to_array(), f.z.to_array()]);
        },
        |_, _| {},
    );
    if !scanned.finite {
        return scanned;
    }
    if let Some(pose) = pose {
        *pose = t.pose();
    }
    let whole = ROWS && n >= 4;
    if N > 0 && !whole {
        // An exact walk wrote axes 0..N only; the short last block's unused
        // lanes read up to 4·⌈N/4⌉ (N < CAP = BLOCK). Any values do there.
        for a in &mut axes[N..N.div_ceil(4) * 4] {
            a.write([t.p.to_array(), t.z.to_array()]);
        }
    }
    // Second pass, four joints at a time with one joint per lane: the six
    // rows of their columns are then six lane vectors. Per value, the same
    // operations as a column-by-column cross product.
    let data = &mut data[..6 * n];
    let pe = t.p.to_array();
    let (pex, pey, pez) = (V::splat(pe[0]), V::splat(pe[1]), V::splat(pe[2]));
    // (No closures around lane operations: see `AngleBlock::angles`.)
    let tool = [t.x.to_array(), t.y.to_array(), t.z.to_array()];
    let zero = V::splat(0.0);
    // Four consecutive joints per block. Row-major with n ≥ 4, the last
    // block is the last four joints (overlapping the one before when 4 does
    // not divide n, which then writes some values twice, the same both
    // times), so every row store is a whole unmasked one: masked AVX stores
    // are slow on some cores. Column-major, each column is two stores of its
    // own, and an overlapping block would only add stores.
    for b in 0..n.div_ceil(4) {
        let c0 = if whole { (4 * b).min(n - 4) } else { 4 * b };
        let cols = if whole { 4 } else { (n - c0).min(4) };
        // SAFETY: the padded walk wrote `axes[i]` for every i below the
        // padded length, a multiple of 8; an exact walk, with the loop above,
        // every i below 4·⌈n/4⌉ (n < 8); and c0 + 3 < 4·⌈n/4⌉.
        let ax: [[[f64; 4]; 2]; 4] = std::array::from_fn(|k| unsafe { axes[c0 + k].assume_init() });
        let lane = |k: usize, j: usize| ax[k][j];
        let four = |j: usize| [lane(0, j), lane(1, j), lane(2, j), lane(3, j)];
        let ([o0, o1, o2, o3], [z0, z1, z2, z3]) = (four(0), four(1));
        let [ox, oy, oz, _] =
            V::transpose([V::from_array(o0), V::from_array(o1), V::from_array(o2), V::from_array(o3)]);
        let [zx, zy, zz, _] =
            V::transpose([V::from_array(z0), V::from_array(z1), V::from_array(z2), V::from_array(z3)]);
        // SAFETY: `axis_sign` and `slides` have the padded length (see the
        // fields), and c0 + 3 is below it (above).
        let (sign, slide) = unsafe {
            (V::from_array(*ch.axis_sign.as_ptr().add(c0).cast()), V::from_array(*ch.slides.as_ptr().add(c0).cast()))
        };
        let (zx, zy, zz) = (zx.mul(sign), zy.mul(sign), zz.mul(sign));
        // z × (p_tool − o); a prismatic joint moves the tool along z and turns nothing.
        let (rx, ry, rz) = (pex.sub(ox), pey.sub(oy), pez.sub(oz));
        let cross = [zy.msub(rz, zz.mul(ry)), zz.msub(rx, zx.mul(rz)), zx.msub(ry, zy.mul(rx))];
        let mut rows = [
            slide.select(zx, cross[0]),
            slide.select(zy, cross[1]),
            slide.select(zz, cross[2]),
            slide.select(zero, zx),
            slide.select(zero, zy),
            slide.select(zero, zz),
        ];
        if TOOL {
            let [tx, ty, tz] = &tool;
            // Rᵀ·v for v = (rows 0..3) and (rows 3..6): dot products with the tool's axes.
            for h in [0, 3] {
                let v = [rows[h], rows[h + 1], rows[h + 2]];
                (rows[h], rows[h + 1], rows[h + 2]) = (dot3(v, tx), dot3(v, ty), dot3(v, tz));
            }
        }
        if ROWS {
            let base = data.as_mut_ptr();
            for (r, row) in rows.iter().enumerate() {
                // SAFETY: `data` has 6·n values (cut above), r < 6 and
                // c0 + cols ≤ n, so r·n + c0 + cols ≤ 6·n: the `cols` values
                // at r·n + c0 are within it. (Checked slicing here was a
                // tenth of the whole Jacobian's instructions.)
                let at = unsafe { std::slice::from_raw_parts_mut(base.add(r * n + c0), cols) };
                if whole {
                    row.store_prefix(at);
                } else {
                    row.store_prefix_masked(at);
                }
            }
        } else {
            // Back to one joint per register: (vx vy vz ωx) and (ωy ωz 0 0).
            let head = V::transpose([rows[0], rows[1], rows[2], rows[3]]);
            let tail = V::transpose([rows[4], rows[5], zero, zero]);
            for k in 0..cols {
                let col = &mut data[6 * (c0 + k)..6 * (c0 + k) + 6];
                head[k].store_prefix(&mut col[..4]);
                tail[k].store_prefix(&mut col[4..]);
            }
        }
    }
    scanned
}

/// A rigid transform as four columns of lanes (x, y, z axes and position;
/// lane 3 is padding and stays zero), the form the hot loops work on.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Xf<V> {
    pub(super) x: V,
    pub(super) y: V,
    pub(super) z: V,
    pub(super) p: V,
}

impl<V: Lanes> Xf<V> {
    #[inline(always)]
    pub(super) fn pose(&self) -> Pose {
        let (x, y, z, p) = (self.x.to_array(), self.y.to_array(), self.z.to_array(), self.p.to_array());
        Pose {
            rot: Matrix3::new(x[0], y[0], z[0], x[1], y[1], z[1], x[2], y[2], z[2]),
            pos: Vector3::new(p[0], p[1], p[2]),
        }
    }

    /// `self ← self · Rz(θ)` given sin θ and cos θ.
    #[inline(always)]
    pub(super) fn turn(&mut self, s: f64, c: f64) {
        let (s, c) = (V::splat(s), V::splat(c));
        let (x, y) = (self.x, self.y);
        self.x = c.madd(x, s.mul(y));
        self.y = c.msub(y, s.mul(x));
    }

    /// `self ← self · Tz(d)`.
    #[inline(always)]
    pub(super) fn slide(&mut self, d: f64) {
        self.p = V::splat(d).madd(self.z, self.p);
    }

    /// `self ← self · Rx(α)`.
    #[inline(always)]
    pub(super) fn twist(&mut self, tw: Twist) {
        let (y, z) = (self.y, self.z);
        match tw {
            Twist::Zero => {}
            Twist::Plus90 => {
                self.y = z;
                self.z = y.neg();
            }
            Twist::Minus90 => {
                self.y = z.neg();
                self.z = y;
            }
            Twist::Half => {
                self.y = y.neg();
                self.z = z.neg();
            }
            Twist::Any { ca, sa } => {
                let (ca, sa) = (V::splat(ca), V::splat(sa));
                self.y = ca.madd(y, sa.mul(z));
                self.z = ca.msub(z, sa.mul(y));
            }
        }
    }

    /// `self ← self · f`.
    #[inline(always)]
    pub(super) fn fixed(&mut self, f: &Fixed) {
        match *f {
            Fixed::Identity => {}
            Fixed::TzTxRx { d, a, twist } => {
                self.p = V::splat(d).madd(self.z, V::splat(a).madd(self.x, self.p));
                self.twist(twist);
            }
            Fixed::RxTxTz { twist, a, d } => {
                self.twist(twist);
                self.p = V::splat(a).madd(self.x, V::splat(d).madd(self.z, self.p));
            }
            Fixed::General(ref g) => self.general(g),
        }
    }

    /// `self ← self · g`.
    #[inline(always)]
    pub(super) fn general(&mut self, g: &Pose) {
        let (x, y, z) = (self.x, self.y, self.z);
        // The position p + R·g, then column j of R·G.
        self.p = x.madd(V::splat(g.pos.x), y.madd(V::splat(g.pos.y), z.madd(V::splat(g.pos.z), self.p)));
        self.x = combine(x, y, z, g.rot[(0, 0)], g.rot[(1, 0)], g.rot[(2, 0)]);
        self.y = combine(x, y, z, g.rot[(0, 1)], g.rot[(1, 1)], g.rot[(2, 1)]);
        self.z = combine(x, y, z, g.rot[(0, 2)], g.rot[(1, 2)], g.rot[(2, 2)]);
    }
}

/// x·a + (y·b + z·c), lane by lane. (A function, not a closure: see `AngleBlock::angles`.)
#[inline(always)]
pub(super) fn combine<V: Lanes>(x: V, y: V, z: V, a: f64, b: f64, c: f64) -> V {
    x.madd(V::splat(a), y.madd(V::splat(b), z.mul(V::splat(c))))
}
