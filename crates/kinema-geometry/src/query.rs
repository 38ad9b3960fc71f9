//! Exact queries on placed shapes, on parry3d-f64: in collision or not
//! ([`collides`]), every contact ([`contacts`]), the minimum distance with its
//! witness points ([`min_distance`], [`pair_distance`]).
//!
//! Distances are signed: positive between separated shapes, the negated
//! penetration depth between overlapping ones. A bounding-box gap, a lower
//! bound of the distance, skips pairs that cannot matter. A new query is a
//! free function here over (geometry, placement, pairs) that calls parry per
//! pair through [`shapes_of`] and reports pairs by shape index.

use nalgebra::{Isometry3, Point3, Vector3};
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::query::{self, ClosestPoints};
use parry3d_f64::shape::{SegmentPointLocation, Shape as ParryShape};

use crate::convex::{hulls_of, hulls_of_shapes};
use crate::error::{Error, Result};
use crate::geometry::{LinkShape, RobotGeometry};
use crate::pairs::CollisionPairs;
use crate::placement::Placement;

/// How close two shapes are, with the points that show it (world frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Proximity {
    /// First shape's index (the lower one of the pair).
    pub a: usize,
    /// Second shape's index.
    pub b: usize,
    /// Signed distance \[m\]: > 0 apart, < 0 overlapping by that depth.
    pub distance: f64,
    /// The point of shape `a` nearest to `b` (deepest in `b` when overlapping) \[m\].
    pub point_a: Point3<f64>,
    /// The point of shape `b` nearest to `a` (deepest in `a` when overlapping) \[m\].
    pub point_b: Point3<f64>,
    /// Unit direction from `a` towards `b` along which they are closest
    /// (zero when the two points coincide and the library gave none).
    pub normal: Vector3<f64>,
}

/// The first pair of `pairs` (in its order) whose shapes are closer than
/// `margin` \[m, ≥ 0\]: with `margin` 0, shapes that overlap or touch; with a
/// safety margin, shapes less than `margin` apart as well.
///
/// # Examples
/// ```
/// use kinema::{Pose, Robot};
/// use kinema_geometry::{collides, CollisionPairs, LinkShape, Placement, RobotGeometry, Shape};
/// let robot = Robot::builtin("ur5")?;
/// let ball = Shape::Sphere { radius: 0.05 };
/// let base = LinkShape::new("base", 0, Pose::IDENTITY, ball.clone())?;
/// let wrist = LinkShape::new("wrist", 6, Pose::IDENTITY, ball)?;
/// let geometry = RobotGeometry::new(&robot, vec![base, wrist])?;
/// let pairs = CollisionPairs::self_collision(&geometry);
/// let at_home = Placement::of(&robot, &geometry, robot.home())?;
/// assert_eq!(collides(&geometry, &at_home, &pairs, 0.0)?, None);
/// // Closer than 10 km counts with a 10 km margin.
/// assert_eq!(collides(&geometry, &at_home, &pairs, 1e4)?, Some((0, 1)));
/// # Ok::<(), kinema_geometry::Error>(())
/// ```
pub fn collides(
    geometry: &RobotGeometry,
    placement: &Placement,
    pairs: &CollisionPairs,
    margin: f64,
) -> Result<Option<(usize, usize)>> {
    check(geometry, placement, pairs, margin)?;
    for (a, b) in pairs.iter() {
        let gap = aabb_gap(placement.aabb(a), placement.aabb(b));
        if gap > margin {
            continue;
        }
        if pair_hits(geometry, placement, a, b, margin)? {
            return Ok(Some((a, b)));
        }
    }
    Ok(None)
}

/// Whether shapes `a` and `b` are closer than `margin` (overlap or touch
/// with `margin` 0), past the bounding-box test; indices and margin checked
/// by the caller.
pub(crate) fn pair_hits(
    geometry: &RobotGeometry,
    placement: &Placement,
    a: usize,
    b: usize,
    margin: f64,
) -> Result<bool> {
    if let Some(p) = round_pair(geometry, placement, a, b) {
        return Ok(p.distance < margin || p.distance <= 0.0);
    }
    let err = |_| unsupported(geometry, a, b);
    if let Some(h) = hulls_of(geometry, placement, a, b) {
        // Hulls apart (by more than the margin) keep the shapes apart; exact
        // hulls apart decide; hulls that meet may hold surfaces that do not.
        if margin == 0.0 {
            if !h.intersect().map_err(err)? {
                return Ok(false);
            }
        } else {
            let d = h.distance().map_err(err)?;
            if d >= margin || (h.exact && d > 0.0) {
                return Ok(d < margin);
            }
        }
    }
    let (pa, sa, pb, sb) = shapes_of(geometry, placement, a, b);
    Ok(if margin == 0.0 {
        query::intersection_test(pa, sa, pb, sb).map_err(err)?
    } else {
        query::distance(pa, sa, pb, sb).map_err(err)? < margin
    })
}

/// Every pair of `pairs` closer than `margin` \[m, ≥ 0\] (see [`collides`]),
/// with its signed distance and points, in the order of `pairs`.
pub fn contacts(
    geometry: &RobotGeometry,
    placement: &Placement,
    pairs: &CollisionPairs,
    margin: f64,
) -> Result<Vec<Proximity>> {
    check(geometry, placement, pairs, margin)?;
    let mut out = Vec::new();
    for (a, b) in pairs.iter() {
        if aabb_gap(placement.aabb(a), placement.aabb(b)) > margin {
            continue;
        }
        if let Some(p) = round_pair(geometry, placement, a, b) {
            if p.distance < margin || p.distance <= 0.0 {
                out.push(p);
            }
            continue;
        }
        let (pa, sa, pb, sb) = shapes_of(geometry, placement, a, b);
        let contact = query::contact(pa, sa, pb, sb, margin).map_err(|_| unsupported(geometry, a, b))?;
        if let Some(c) = contact.filter(|c| c.dist < margin || c.dist <= 0.0) {
            out.push(Proximity {
                a,
                b,
                distance: c.dist,
                point_a: c.point1,
                point_b: c.point2,
                normal: c.normal1.into_inner(),
            });
        }
    }
    Ok(out)
}

/// The closest pair of `pairs` with its signed distance and witness points
/// (`None` if `pairs` is empty). Overlapping pairs come first, deepest first.
/// Pairs are visited nearest bounding box first and skipped once a lower
/// bound of their distance (the boxes' gap, a mesh's convex hull) reaches
/// the best so far; allocates the visiting order.
///
/// # Examples
/// ```
/// use kinema::{Pose, Robot};
/// use kinema_geometry::{min_distance, CollisionPairs, LinkShape, Placement, RobotGeometry, Shape};
/// let robot = Robot::builtin("ur5")?;
/// let base = LinkShape::new("base", 0, Pose::IDENTITY, Shape::Sphere { radius: 0.1 })?;
/// let flange = LinkShape::new("flange", 6, Pose::IDENTITY, Shape::Sphere { radius: 0.05 })?;
/// let geometry = RobotGeometry::new(&robot, vec![base, flange])?;
/// let placement = Placement::of(&robot, &geometry, robot.home())?;
/// let closest = min_distance(&geometry, &placement, &CollisionPairs::all(&geometry))?.unwrap();
/// let centres = placement.frames()[6].pos - placement.frames()[0].pos;
/// assert!((closest.distance - (centres.norm() - 0.15)).abs() < 1e-9);
/// # Ok::<(), kinema_geometry::Error>(())
/// ```
pub fn min_distance(
    geometry: &RobotGeometry,
    placement: &Placement,
    pairs: &CollisionPairs,
) -> Result<Option<Proximity>> {
    check(geometry, placement, pairs, 0.0)?;
    // Nearest boxes first, so that the best distance so far soon bounds the rest.
    let mut order: Vec<(f64, usize)> =
        pairs.iter().enumerate().map(|(n, (a, b))| (aabb_gap(placement.aabb(a), placement.aabb(b)), n)).collect();
    order.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    let mut best: Option<Proximity> = None;
    for (gap, n) in order {
        let bound = best.map_or(f64::INFINITY, |p| p.distance);
        // Once a pair overlaps, only pairs whose boxes overlap can be deeper.
        if gap >= bound.max(0.0) && (gap > 0.0 || bound > 0.0) {
            break;
        }
        let (a, b) = pairs.get(n);
        if let Some(p) = closer_than(geometry, placement, a, b, bound)? {
            best = Some(p);
        }
    }
    Ok(best)
}

/// The proximity of shapes `a` and `b` (as [`pair_distance`] gives it) if
/// their distance is below `bound` \[m\], else `None`.
fn closer_than(
    geometry: &RobotGeometry,
    placement: &Placement,
    a: usize,
    b: usize,
    bound: f64,
) -> Result<Option<Proximity>> {
    if let Some(p) = round_pair(geometry, placement, a, b) {
        return Ok((p.distance < bound).then_some(p));
    }
    let err = |_| unsupported(geometry, a, b);
    if let Some(h) = hulls_of(geometry, placement, a, b) {
        // Apart, a convex solid is nearest at its surface: exact hulls' distance
        // is the shapes'; other hulls' is a lower bound of it.
        let d = h.distance().map_err(err)?;
        if d > 0.0 && d >= bound {
            return Ok(None);
        }
        if d > 0.0 && h.exact {
            return separated(a, b, d, h.pose_a, h.a, h.pose_b, h.b).map(Some).map_err(err);
        }
    }
    let (pa, sa, pb, sb) = shapes_of(geometry, placement, a, b);
    let d = query::distance(pa, sa, pb, sb).map_err(err)?;
    if d >= bound.max(0.0) && d > 0.0 {
        return Ok(None);
    }
    let p = proximity(geometry, placement, a, b, d)?;
    Ok((p.distance < bound).then_some(p))
}

/// The closest pair of `pairs` by visiting every pair in order, each
/// measured in full: the plain reference [`min_distance`] is tested against
/// (the same distance within 1e-9 m, at the same pair or one as close).
///
/// # Examples
/// ```
/// use kinema::{Pose, Robot};
/// use kinema_geometry::{min_distance, min_distance_reference, CollisionPairs, LinkShape, Placement, RobotGeometry, Shape};
/// let robot = Robot::builtin("ur5")?;
/// let shapes = (0..=6)
///     .map(|link| LinkShape::new(format!("s{link}"), link, Pose::IDENTITY, Shape::Box { size: [0.1; 3].into() }))
///     .collect::<Result<Vec<_>, _>>()?;
/// let geometry = RobotGeometry::new(&robot, shapes)?;
/// let (pairs, placement) = (CollisionPairs::all(&geometry), Placement::of(&robot, &geometry, robot.home())?);
/// let plain = min_distance_reference(&geometry, &placement, &pairs)?.unwrap();
/// let fast = min_distance(&geometry, &placement, &pairs)?.unwrap();
/// assert!((plain.distance - fast.distance).abs() < 1e-9);
/// # Ok::<(), kinema_geometry::Error>(())
/// ```
pub fn min_distance_reference(
    geometry: &RobotGeometry,
    placement: &Placement,
    pairs: &CollisionPairs,
) -> Result<Option<Proximity>> {
    check(geometry, placement, pairs, 0.0)?;
    let mut best: Option<Proximity> = None;
    for (a, b) in pairs.iter() {
        let p = pair_distance(geometry, placement, a, b)?;
        if best.is_none_or(|q| p.distance < q.distance) {
            best = Some(p);
        }
    }
    Ok(best)
}

/// The signed distance between shapes `a` and `b` and their witness points.
pub fn pair_distance(geometry: &RobotGeometry, placement: &Placement, a: usize, b: usize) -> Result<Proximity> {
    if a.max(b) >= geometry.len() || placement.len() != geometry.len() {
        return Err(Error::Mismatch {
            what: format!("shape pair ({a}, {b}) or the placement"),
            got: a.max(b).max(placement.len()),
            expected: geometry.len(),
        });
    }
    if let Some(p) = round_pair(geometry, placement, a, b) {
        return Ok(p);
    }
    let (pa, sa, pb, sb) = shapes_of(geometry, placement, a, b);
    let d = query::distance(pa, sa, pb, sb).map_err(|_| unsupported(geometry, a, b))?;
    proximity(geometry, placement, a, b, d)
}

/// The proximity of shapes `a` and `b` (not balls or capsules both) whose
/// distance parry measured as `d`: witness points, and the depth when they overlap.
fn proximity(geometry: &RobotGeometry, placement: &Placement, a: usize, b: usize, d: f64) -> Result<Proximity> {
    let (pa, sa, pb, sb) = shapes_of(geometry, placement, a, b);
    let err = |_| unsupported(geometry, a, b);
    if d > 0.0 {
        return separated(a, b, d, pa, sa, pb, sb).map_err(err);
    }
    // Overlapping: the depth orders overlapping pairs.
    let prediction = 1e-12;
    if let Some(c) = query::contact(pa, sa, pb, sb, prediction).map_err(err)? {
        return Ok(Proximity {
            a,
            b,
            distance: c.dist.min(0.0),
            point_a: c.point1,
            point_b: c.point2,
            normal: c.normal1.into_inner(),
        });
    }
    witnessed(a, b, d, pa, sa, pb, sb, 2.0 * prediction).map_err(err)
}

/// The proximity of two shapes `d` \[m, > 0\] apart, with their witness points.
#[allow(clippy::too_many_arguments)] // a pair: each shape with its pose
fn separated(
    a: usize,
    b: usize,
    d: f64,
    pa: &Isometry3<f64>,
    sa: &dyn ParryShape,
    pb: &Isometry3<f64>,
    sb: &dyn ParryShape,
) -> std::result::Result<Proximity, query::Unsupported> {
    // A prediction just above the distance makes parry return the closest points.
    let prediction = d * (1.0 + 1e-9) + 1e-12;
    if let Some(c) = query::contact(pa, sa, pb, sb, prediction)? {
        // The witness points' distance: the same for a mesh and its hull, where
        // the two distance queries stop at their own tolerances.
        let distance = (c.point2 - c.point1).norm();
        return Ok(Proximity { a, b, distance, point_a: c.point1, point_b: c.point2, normal: c.normal1.into_inner() });
    }
    witnessed(a, b, d, pa, sa, pb, sb, 2.0 * prediction)
}

/// The proximity of two shapes `d` apart from their closest points within `margin`.
#[allow(clippy::too_many_arguments)] // a pair: each shape with its pose
fn witnessed(
    a: usize,
    b: usize,
    d: f64,
    pa: &Isometry3<f64>,
    sa: &dyn ParryShape,
    pb: &Isometry3<f64>,
    sb: &dyn ParryShape,
    margin: f64,
) -> std::result::Result<Proximity, query::Unsupported> {
    let (point_a, point_b) = match query::closest_points(pa, sa, pb, sb, margin)? {
        ClosestPoints::WithinMargin(p, q) => (p, q),
        _ => (pa.translation.vector.into(), pb.translation.vector.into()),
    };
    let normal = (point_b - point_a).try_normalize(0.0).unwrap_or_else(Vector3::zeros);
    Ok(Proximity { a, b, distance: d, point_a, point_b, normal })
}

/// The placed parry shapes of a pair: (pose of a, a, pose of b, b).
/// The distance \[m\] between shapes `a` and `b` in `placement` (0 when they
/// touch or overlap): [`pair_distance`] without the witness points.
pub(crate) fn pair_gap(geometry: &RobotGeometry, placement: &Placement, a: usize, b: usize) -> Result<f64> {
    let (sa, sb) = (&geometry.shapes()[a], &geometry.shapes()[b]);
    placed_gap(placement.world_from_collider(a), sa, placement.world_from_collider(b), sb)
        .map_err(|_| unsupported(geometry, a, b))
}

/// The distance \[m\] between shapes `a` and `b`, each's collision form at
/// the given world pose (0 when they touch or overlap): balls and capsules
/// in closed form, convex meshes as their hulls when apart, else parry's
/// distance. For shapes of two geometries (two robots) as of one.
pub(crate) fn placed_gap(
    pose_a: &Isometry3<f64>,
    a: &LinkShape,
    pose_b: &Isometry3<f64>,
    b: &LinkShape,
) -> std::result::Result<f64, query::Unsupported> {
    let (sa, sb) = (a.collider().as_ref(), b.collider().as_ref());
    if let Some((distance, ..)) = round_placed(pose_a, sa, pose_b, sb) {
        return Ok(distance.max(0.0));
    }
    if let Some(distance) = round_box_gap(pose_a, sa, pose_b, sb).or_else(|| round_box_gap(pose_b, sb, pose_a, sa)) {
        return Ok(distance);
    }
    if let Some(h) = hulls_of_shapes(pose_a, a, pose_b, b).filter(|h| h.exact) {
        let d = h.distance()?;
        if d > 0.0 {
            return Ok(d);
        }
    }
    if let (Some(ca), Some(cb)) = (sa.as_cuboid(), sb.as_cuboid()) {
        // parry's own cuboid pair projects one box's support vertex onto the
        // other, which overstates the gap when an edge is nearest (by 0.22 m
        // for a link 3 mm from a post's vertical edge); GJK is exact.
        return Ok(query::details::distance_support_map_support_map(&pose_a.inv_mul(pose_b), ca, cb));
    }
    query::distance(pose_a, sa, pose_b, sb)
}

pub(crate) fn shapes_of<'g>(
    geometry: &'g RobotGeometry,
    placement: &'g Placement,
    a: usize,
    b: usize,
) -> (&'g Isometry3<f64>, &'g dyn ParryShape, &'g Isometry3<f64>, &'g dyn ParryShape) {
    let shapes = geometry.shapes();
    (
        placement.world_from_collider(a),
        shapes[a].collider().as_ref(),
        placement.world_from_collider(b),
        shapes[b].collider().as_ref(),
    )
}

/// The core segment (world frame) and radius of a ball (a segment of no
/// length) or a capsule.
fn round(shape: &dyn ParryShape, pose: &Isometry3<f64>) -> Option<(Point3<f64>, Point3<f64>, f64)> {
    if let Some(ball) = shape.as_ball() {
        let c = Point3::from(pose.translation.vector);
        return Some((c, c, ball.radius));
    }
    let capsule = shape.as_capsule()?;
    Some((pose * capsule.segment.a, pose * capsule.segment.b, capsule.radius))
}

/// A ball or capsule `sr` against a box `sb` in closed form (its core
/// segment's distance to the box, less the radius; 0 when they meet), or
/// `None` for other shapes.
fn round_box_gap(pr: &Isometry3<f64>, sr: &dyn ParryShape, pb: &Isometry3<f64>, sb: &dyn ParryShape) -> Option<f64> {
    let cuboid = sb.as_cuboid()?;
    let (p, q, radius) = round(sr, pr)?;
    let (a, b) = (pb.inverse_transform_point(&p).coords, pb.inverse_transform_point(&q).coords);
    let core = crate::segment_box::segment_box_distance_squared(&a, &b, &cuboid.half_extents).sqrt();
    Some((core - radius).max(0.0))
}

/// Balls and capsules pairwise in closed form (their core segments' closest
/// points, less the radii): exact where parry's penetration depth (EPA) is
/// not, such as capsules overlapping along a common axis.
fn round_pair(geometry: &RobotGeometry, placement: &Placement, a: usize, b: usize) -> Option<Proximity> {
    let (pa, sa, pb, sb) = shapes_of(geometry, placement, a, b);
    let (distance, point_a, point_b, normal) = round_placed(pa, sa, pb, sb)?;
    Some(Proximity { a, b, distance, point_a, point_b, normal })
}

/// Two round shapes' signed distance, point of a, point of b and unit normal from a to b.
type RoundProximity = (f64, Point3<f64>, Point3<f64>, Vector3<f64>);

/// [`round_pair`] on two placed parry shapes: (signed distance, point of a,
/// point of b, unit normal from a to b), or `None` unless both are round.
fn round_placed(
    pa: &Isometry3<f64>,
    sa: &dyn ParryShape,
    pb: &Isometry3<f64>,
    sb: &dyn ParryShape,
) -> Option<RoundProximity> {
    let (a0, a1, ra) = round(sa, pa)?;
    let (b0, b1, rb) = round(sb, pb)?;
    let (la, lb) = query::details::closest_points_segment_segment_with_locations_nD((&a0, &a1), (&b0, &b1));
    let at = |(p, q): (Point3<f64>, Point3<f64>), loc: SegmentPointLocation| match loc {
        SegmentPointLocation::OnVertex(0) => p,
        SegmentPointLocation::OnVertex(_) => q,
        SegmentPointLocation::OnEdge([u, v]) => Point3::from(p.coords * u + q.coords * v),
    };
    let (ca, cb) = (at((a0, a1), la), at((b0, b1), lb));
    let between = cb - ca;
    let gap = between.norm();
    // Core segments that cross have no closest direction: any direction perpendicular to a does.
    let normal = if gap > 0.0 {
        between / gap
    } else {
        let axis = a1 - a0;
        axis.cross(&Vector3::x())
            .try_normalize(0.0)
            .or_else(|| axis.cross(&Vector3::y()).try_normalize(0.0))
            .unwrap_or(Vector3::x())
    };
    Some((gap - ra - rb, ca + normal * ra, cb - normal * rb, normal))
}

/// The distance between two boxes (0 when they overlap): a lower bound of
/// the distance between anything inside them.
pub(crate) fn aabb_gap(a: &Aabb, b: &Aabb) -> f64 {
    let below = a.mins - b.maxs;
    let above = b.mins - a.maxs;
    below.zip_map(&above, |x, y| x.max(y).max(0.0)).norm()
}

fn check(geometry: &RobotGeometry, placement: &Placement, pairs: &CollisionPairs, margin: f64) -> Result<()> {
    if placement.len() != geometry.len() {
        return Err(Error::Mismatch { what: "the placement".into(), got: placement.len(), expected: geometry.len() });
    }
    if pairs.shape_count() != geometry.len() {
        return Err(Error::Mismatch {
            what: "the pair list".into(),
            got: pairs.shape_count(),
            expected: geometry.len(),
        });
    }
    if !(margin >= 0.0 && margin.is_finite()) {
        return Err(Error::Margin { margin });
    }
    Ok(())
}

fn unsupported(geometry: &RobotGeometry, a: usize, b: usize) -> Error {
    let (sa, sb) = (&geometry.shapes()[a], &geometry.shapes()[b]);
    Error::UnsupportedPair {
        a: sa.name().into(),
        b: sb.name().into(),
        kinds: format!("{} – {}", sa.shape().kind(), sb.shape().kind()),
    }
}
