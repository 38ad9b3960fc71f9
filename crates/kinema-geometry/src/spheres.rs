//! The conservative fast path: every shape enclosed by a few spheres fixed
//! to its link ([`Spheres::fit`]), placed by forward kinematics and compared
//! pairwise ([`spheres_free`]). "Free" is a proof: spheres that contain the
//! shapes and are more than the margin apart keep the shapes apart too.
//! "Maybe" proves nothing; the exact query decides ([`collides_fast`]).
//!
//! Fitting splits a shape along its longest extent into pieces no longer
//! than they are wide and takes the sphere around each piece: slabs of a
//! cylinder, segment pieces of a capsule, boxes of a box, and for meshes the
//! pieces of the smaller of the mesh's bounding box in its own frame and in
//! its principal axes (every point of a mesh, triangle or hull, is a convex
//! combination of its vertices and so inside both boxes).

use nalgebra::{Matrix3, Point3, SymmetricEigen, Vector3};

use kinema::{kin, Pose, Robot};

use crate::error::{Error, Result};
use crate::geometry::RobotGeometry;
use crate::pairs::CollisionPairs;
use crate::placement::{place_at_frames, Placement};
use crate::query::{aabb_gap, pair_hits};
use crate::shape::Shape;

/// Radii are grown by this fraction of the shape's size (and at least 1 nm)
/// so that rounding in fitting and placing never leaves a point outside.
const PAD: f64 = 1e-9;

/// The spheres enclosing the shapes of one [`RobotGeometry`], in link frames.
#[derive(Debug, Clone)]
pub struct Spheres {
    dof: usize,
    /// Per sphere: the link it rides on, its centre in that link's frame, its radius.
    link: Vec<usize>,
    centre: Vec<Vector3<f64>>,
    radius: Vec<f64>,
    /// Per shape: the range of its spheres.
    of_shape: Vec<(usize, usize)>,
}

/// Reusable buffers for [`spheres_free`]: link frames and sphere centres in
/// the world frame for one configuration.
#[derive(Debug, Clone)]
pub struct SpherePlacement {
    frames: Vec<Pose>,
    centres: Vec<Point3<f64>>,
}

impl Spheres {
    /// Encloses every shape of `geometry` in at most `max_per_shape` (≥ 1)
    /// spheres.
    ///
    /// # Examples
    /// ```
    /// use kinema::{Pose, Robot};
    /// use kinema_geometry::{LinkShape, RobotGeometry, Shape, Spheres};
    /// let robot = Robot::builtin("ur5")?;
    /// let arm = LinkShape::new("arm", 2, Pose::IDENTITY, Shape::Cylinder { radius: 0.05, length: 0.4 })?;
    /// let spheres = Spheres::fit(&RobotGeometry::new(&robot, vec![arm])?, 4);
    /// assert_eq!(spheres.len(), 4); // 0.4 m long, 0.1 m wide: four slabs
    /// # Ok::<(), kinema_geometry::Error>(())
    /// ```
    pub fn fit(geometry: &RobotGeometry, max_per_shape: usize) -> Spheres {
        let max = max_per_shape.max(1);
        let mut out = Spheres {
            dof: geometry.dof(),
            link: Vec::new(),
            centre: Vec::new(),
            radius: Vec::new(),
            of_shape: Vec::new(),
        };
        for s in geometry.shapes() {
            let start = out.link.len();
            let link_from_shape = s.link_from_shape();
            for (c, r) in fit_shape(s.shape(), max) {
                out.link.push(s.link());
                out.centre.push(link_from_shape.rot * c + link_from_shape.pos);
                out.radius.push(r);
            }
            out.of_shape.push((start, out.link.len()));
        }
        out
    }

    /// The number of spheres.
    pub fn len(&self) -> usize {
        self.link.len()
    }

    /// Whether there are none (a geometry without shapes).
    pub fn is_empty(&self) -> bool {
        self.link.is_empty()
    }

    /// The spheres of shape `index`: (link, centre in the link frame, radius).
    pub fn of_shape(&self, index: usize) -> impl Iterator<Item = (usize, Vector3<f64>, f64)> + '_ {
        let (a, b) = self.of_shape[index];
        (a..b).map(|i| (self.link[i], self.centre[i], self.radius[i]))
    }

    /// The index range of shape `index`'s spheres.
    pub(crate) fn range_of(&self, index: usize) -> std::ops::Range<usize> {
        let (a, b) = self.of_shape[index];
        a..b
    }

    /// Every sphere's radius \[m\].
    pub(crate) fn radii(&self) -> &[f64] {
        &self.radius
    }

    /// Empty buffers for [`spheres_free`].
    pub fn placement(&self) -> SpherePlacement {
        SpherePlacement { frames: vec![Pose::IDENTITY; self.dof + 2], centres: vec![Point3::origin(); self.len()] }
    }
}

impl SpherePlacement {
    /// The link frames of the last placement (base, links, tool).
    pub(crate) fn frames(&self) -> &[Pose] {
        &self.frames
    }

    /// The world centre of every sphere at the last [`spheres_free`], in the
    /// order of [`Spheres::of_shape`] over the shapes.
    pub fn centres(&self) -> &[Point3<f64>] {
        &self.centres
    }
}

/// Whether the spheres prove every pair of `pairs` more than `margin` \[m\]
/// apart at joint values `q`: `true` means the exact shapes do not collide
/// (within the margin); `false` means they may. Forward kinematics included;
/// does not allocate.
pub fn spheres_free(
    robot: &Robot,
    spheres: &Spheres,
    q: &[f64],
    pairs: &CollisionPairs,
    margin: f64,
    out: &mut SpherePlacement,
) -> Result<bool> {
    Ok(first_maybe(robot, spheres, q, pairs, margin, out, 0)?.is_none())
}

/// [`collides`](crate::collides) through the fast path: the spheres at `q`
/// first, then the exact shapes (placed into `placement`) only for the
/// pairs whose spheres come within `margin`. The same answer as placing and
/// calling `collides`, which the property tests check.
#[allow(clippy::too_many_arguments)] // the query's inputs and its two reusable buffers
pub fn collides_fast(
    robot: &Robot,
    geometry: &RobotGeometry,
    spheres: &Spheres,
    q: &[f64],
    pairs: &CollisionPairs,
    margin: f64,
    sphere_placement: &mut SpherePlacement,
    placement: &mut Placement,
) -> Result<Option<(usize, usize)>> {
    let Some(mut next) = first_maybe(robot, spheres, q, pairs, margin, sphere_placement, 0)? else {
        return Ok(None);
    };
    place_at_frames(robot, geometry, &sphere_placement.frames, placement)?;
    loop {
        let (a, b) = pairs.get(next);
        if aabb_gap(placement.aabb(a), placement.aabb(b)) <= margin && pair_hits(geometry, placement, a, b, margin)? {
            return Ok(Some((a, b)));
        }
        match maybe_from(spheres, pairs, margin, sphere_placement, next + 1) {
            Some(n) => next = n,
            None => return Ok(None),
        }
    }
}

/// Places the spheres and returns the index (in `pairs`) of the first pair
/// at or after `from` whose spheres come within `margin`.
fn first_maybe(
    robot: &Robot,
    spheres: &Spheres,
    q: &[f64],
    pairs: &CollisionPairs,
    margin: f64,
    out: &mut SpherePlacement,
    from: usize,
) -> Result<Option<usize>> {
    if !(margin >= 0.0 && margin.is_finite()) {
        return Err(Error::Margin { margin });
    }
    if spheres.dof != robot.dof() || pairs.shape_count() != spheres.of_shape.len() {
        return Err(Error::Mismatch {
            what: "the spheres or the pair list".into(),
            got: pairs.shape_count(),
            expected: spheres.of_shape.len(),
        });
    }
    if out.frames.len() != robot.dof() + 2 || out.centres.len() != spheres.len() {
        return Err(Error::Mismatch {
            what: "the sphere placement".into(),
            got: out.centres.len(),
            expected: spheres.len(),
        });
    }
    place_spheres(robot, spheres, q, out)?;
    Ok(maybe_from(spheres, pairs, margin, out, from))
}

/// Forward kinematics at `q` and every sphere's world centre into `out`
/// (sized for `spheres` by the caller).
pub(crate) fn place_spheres(robot: &Robot, spheres: &Spheres, q: &[f64], out: &mut SpherePlacement) -> Result<()> {
    kin::link_frames_into(robot, q, &mut out.frames)?;
    for ((c, &link), local) in out.centres.iter_mut().zip(&spheres.link).zip(&spheres.centre) {
        let f = &out.frames[link];
        *c = Point3::from(crate::geometry::rotate(&f.rot, local) + f.pos);
    }
    Ok(())
}

fn maybe_from(
    spheres: &Spheres,
    pairs: &CollisionPairs,
    margin: f64,
    out: &SpherePlacement,
    from: usize,
) -> Option<usize> {
    let (c, r) = (&out.centres, &spheres.radius);
    for n in from..pairs.len() {
        let (a, b) = pairs.get(n);
        let ((a0, a1), (b0, b1)) = (spheres.of_shape[a], spheres.of_shape[b]);
        for i in a0..a1 {
            for j in b0..b1 {
                let reach = r[i] + r[j] + margin;
                if (c[i] - c[j]).norm_squared() <= reach * reach {
                    return Some(n);
                }
            }
        }
    }
    None
}

/// Spheres (centre in the shape frame, radius) enclosing `shape`.
fn fit_shape(shape: &Shape, max: usize) -> Vec<(Vector3<f64>, f64)> {
    let padded = |c: Vector3<f64>, r: f64, size: f64| (c, r + PAD * size.max(1.0));
    match shape {
        Shape::Sphere { radius } => vec![padded(Vector3::zeros(), *radius, *radius)],
        Shape::Capsule { radius, length } => {
            // A point is within `radius` of a segment point, which is within half
            // a piece of the piece's centre.
            let k = pieces(*length + 2.0 * radius, 2.0 * radius, max);
            let half = length / (2 * k) as f64;
            along_z(*length, k).map(|z| padded(Vector3::new(0.0, 0.0, z), radius + half, *length + radius)).collect()
        }
        Shape::Cylinder { radius, length } => {
            let k = pieces(*length, 2.0 * radius, max);
            let half = length / (2 * k) as f64;
            let r = (radius * radius + half * half).sqrt();
            along_z(*length, k).map(|z| padded(Vector3::new(0.0, 0.0, z), r, *length + radius)).collect()
        }
        Shape::Box { size } => split_box(&Matrix3::identity(), &Vector3::zeros(), &(size / 2.0), max),
        Shape::ConvexMesh(m) | Shape::TriangleMesh(m) => mesh_spheres(&m.vertices, max),
    }
}

/// How many pieces along a `long` extent so that each is about as long as
/// the shape is `wide`, at most `max`.
fn pieces(long: f64, wide: f64, max: usize) -> usize {
    if wide > 0.0 {
        ((long / wide).ceil() as usize).clamp(1, max)
    } else {
        max
    }
}

/// The centres of `k` equal pieces of [−length/2, length/2].
fn along_z(length: f64, k: usize) -> impl Iterator<Item = f64> {
    (0..k).map(move |i| -length / 2.0 + length * (i as f64 + 0.5) / k as f64)
}

/// A box (axes the columns of `axes`, centre `centre`, half extents `half`)
/// split along its longest axis, each piece in the sphere through its corners.
fn split_box(axes: &Matrix3<f64>, centre: &Vector3<f64>, half: &Vector3<f64>, max: usize) -> Vec<(Vector3<f64>, f64)> {
    let long = half.imax();
    let mut rest = *half;
    rest[long] = 0.0;
    let k = pieces(2.0 * half[long], 2.0 * rest.max(), max);
    let mut piece = *half;
    piece[long] = half[long] / k as f64;
    let r = piece.norm();
    let size = half.norm();
    along_z(2.0 * half[long], k).map(|t| (centre + axes.column(long) * t, r + PAD * size.max(1.0))).collect()
}

/// The spheres of the smaller (by the spheres' total volume) of the
/// vertices' bounding box in the shape frame and in their principal axes.
fn mesh_spheres(vertices: &[Point3<f64>], max: usize) -> Vec<(Vector3<f64>, f64)> {
    let n = vertices.len().max(1) as f64;
    let mean = vertices.iter().fold(Vector3::zeros(), |s, v| s + v.coords) / n;
    let cov = vertices.iter().fold(Matrix3::zeros(), |s, v| {
        let d = v.coords - mean;
        s + d * d.transpose()
    }) / n;
    let principal = SymmetricEigen::new(cov).eigenvectors;
    let volume = |s: &[(Vector3<f64>, f64)]| s.iter().map(|(_, r)| r.powi(3)).sum::<f64>();
    [Matrix3::identity(), principal]
        .iter()
        .map(|axes| {
            // The box in these axes: extents of the vertices' coordinates.
            let (mut lo, mut hi) = (Vector3::repeat(f64::INFINITY), Vector3::repeat(f64::NEG_INFINITY));
            for v in vertices {
                let p = axes.transpose() * v.coords;
                lo = lo.inf(&p);
                hi = hi.sup(&p);
            }
            split_box(axes, &(axes * ((lo + hi) / 2.0)), &((hi - lo) / 2.0), max)
        })
        .min_by(|a, b| volume(a).total_cmp(&volume(b)))
        .expect("two candidates")
}
