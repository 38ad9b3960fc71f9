//! A triangle mesh's convex hull, and whether the mesh is convex. The hull
//! contains the mesh's surface, so the hulls' distance (GJK on two
//! `ConvexPolyhedron`s, microseconds) bounds the surfaces' distance from
//! below, and hulls apart prove the surfaces apart. When the mesh is convex
//! (its surface is the hull's boundary) the hull's distance to a shape it
//! is apart from is the mesh's exactly: a solid's nearest point lies on its
//! boundary. Either way this replaces triangle-by-triangle queries through a
//! bounding-volume tree wherever it decides.

use nalgebra::{Isometry3, Point3};
use parry3d_f64::query;
use parry3d_f64::shape::{ConvexPolyhedron, Shape as ParryShape, SharedShape};
use parry3d_f64::transformation::try_convex_hull;

use crate::geometry::{LinkShape, RobotGeometry};
use crate::placement::Placement;
use crate::shape::Mesh;

/// Coplanarity and area tolerance, relative to the mesh's size (its
/// bounding-box diagonal): rounding of vertices read as 32-bit floats, far
/// below any distance a collision query reports.
const RELATIVE_TOLERANCE: f64 = 1e-9;

/// Hulls with more vertices than this are not tested for convexity: the
/// test costs triangles × hull vertices.
const MAX_TESTED_HULL_VERTICES: usize = 4096;

/// A triangle mesh's convex hull and whether it is the mesh's own solid.
#[derive(Debug, Clone)]
pub(crate) struct MeshHull {
    /// The hull, in the mesh's frame.
    pub shape: SharedShape,
    /// Whether the mesh is convex: its surface is the hull's boundary.
    pub exact: bool,
}

/// The mesh's convex hull (`None` if parry makes none, as for fewer than
/// three distinct vertices), marked exact when the mesh's surface is that hull's boundary:
/// every triangle lies in a supporting plane of the vertices, and the
/// triangles cover the hull's area once.
pub(crate) fn mesh_hull(mesh: &Mesh) -> Option<MeshHull> {
    let (hull_points, hull_triangles) = try_convex_hull(&mesh.vertices).ok()?;
    let exact = hull_points.len() <= MAX_TESTED_HULL_VERTICES && is_hull_boundary(mesh, &hull_points, &hull_triangles);
    let shape = ConvexPolyhedron::from_convex_mesh(hull_points, &hull_triangles)?;
    Some(MeshHull { shape: SharedShape::new(shape), exact })
}

/// A pair's convex forms when at least one is a triangle mesh's hull and
/// the other is a hull, a box or a convex mesh (polytopes, on which GJK is
/// exact, unlike on curved shapes).
pub(crate) struct Hulls<'g> {
    pub pose_a: &'g Isometry3<f64>,
    pub a: &'g dyn ParryShape,
    pub pose_b: &'g Isometry3<f64>,
    pub b: &'g dyn ParryShape,
    /// Whether both forms are the shapes themselves (no non-convex mesh):
    /// their distance when apart is the shapes' distance, not only a bound.
    pub exact: bool,
}

impl Hulls<'_> {
    /// The forms' distance \[m\] (0 when they meet).
    pub fn distance(&self) -> std::result::Result<f64, query::Unsupported> {
        query::distance(self.pose_a, self.a, self.pose_b, self.b)
    }

    /// Whether the forms meet.
    pub fn intersect(&self) -> std::result::Result<bool, query::Unsupported> {
        query::intersection_test(self.pose_a, self.a, self.pose_b, self.b)
    }
}

/// The convex forms of placed shapes `a` and `b`, if they have them (see [`Hulls`]).
pub(crate) fn hulls_of<'g>(
    geometry: &'g RobotGeometry,
    placement: &'g Placement,
    a: usize,
    b: usize,
) -> Option<Hulls<'g>> {
    let shapes = geometry.shapes();
    hulls_of_shapes(placement.world_from_collider(a), &shapes[a], placement.world_from_collider(b), &shapes[b])
}

/// [`hulls_of`] for two shapes at their collision forms' world poses.
pub(crate) fn hulls_of_shapes<'g>(
    pose_a: &'g Isometry3<f64>,
    sa: &'g LinkShape,
    pose_b: &'g Isometry3<f64>,
    sb: &'g LinkShape,
) -> Option<Hulls<'g>> {
    if sa.hull().is_none() && sb.hull().is_none() {
        return None;
    }
    let convex = |s: &'g LinkShape| -> Option<(&'g dyn ParryShape, bool)> {
        match s.hull() {
            Some(h) => Some((h.shape.as_ref(), h.exact)),
            None => {
                let c = s.collider();
                (c.as_cuboid().is_some() || c.as_convex_polyhedron().is_some()).then(|| (c.as_ref(), true))
            }
        }
    };
    let ((ha, exact_a), (hb, exact_b)) = (convex(sa)?, convex(sb)?);
    Some(Hulls { pose_a, a: ha, pose_b, b: hb, exact: exact_a && exact_b })
}

/// Whether the mesh's surface is the boundary of the hull given by
/// `hull_points` and `hull_triangles`, within rounding.
fn is_hull_boundary(mesh: &Mesh, hull_points: &[Point3<f64>], hull_triangles: &[[u32; 3]]) -> bool {
    let size = diagonal(&mesh.vertices);
    let tolerance = RELATIVE_TOLERANCE * size.max(f64::MIN_POSITIVE);
    let area = |p: &[Point3<f64>], t: &[u32; 3]| triangle_area(&p[t[0] as usize], &p[t[1] as usize], &p[t[2] as usize]);
    let mesh_area: f64 = mesh.triangles.iter().map(|t| area(&mesh.vertices, t)).sum();
    let hull_area: f64 = hull_triangles.iter().map(|t| area(hull_points, t)).sum();
    (mesh_area - hull_area).abs() <= tolerance * size * 8.0
        && mesh.triangles.iter().all(|t| supporting(&mesh.vertices, t, hull_points, tolerance))
}

/// Whether every point of `points` lies on one side of triangle `t`'s plane
/// (within `tolerance`): the triangle is on the boundary of their hull.
/// A triangle without area has no plane and takes no part in the surface.
fn supporting(vertices: &[Point3<f64>], t: &[u32; 3], points: &[Point3<f64>], tolerance: f64) -> bool {
    let [a, b, c] = t.map(|i| vertices[i as usize]);
    let Some(normal) = (b - a).cross(&(c - a)).try_normalize(0.0) else {
        return true;
    };
    let (mut below, mut above) = (0.0f64, 0.0f64);
    for p in points {
        let side = normal.dot(&(p - a));
        below = below.min(side);
        above = above.max(side);
    }
    below >= -tolerance || above <= tolerance
}

fn triangle_area(a: &Point3<f64>, b: &Point3<f64>, c: &Point3<f64>) -> f64 {
    (b - a).cross(&(c - a)).norm() / 2.0
}

fn diagonal(points: &[Point3<f64>]) -> f64 {
    let Some(first) = points.first() else { return 0.0 };
    let (lo, hi) =
        points.iter().fold((first.coords, first.coords), |(lo, hi), p| (lo.inf(&p.coords), hi.sup(&p.coords)));
    (hi - lo).norm()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(dent: f64) -> Mesh {
        // A unit cube's 8 corners and the centre of its top face, pushed in by `dent`.
        let mut vertices: Vec<Point3<f64>> =
            (0..8).map(|i| Point3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64)).collect();
        vertices.push(Point3::new(0.5, 0.5, 1.0 - dent));
        let top = [[4, 5, 8], [5, 7, 8], [7, 6, 8], [6, 4, 8]];
        let sides = [
            [0, 2, 1],
            [1, 2, 3],
            [0, 1, 4],
            [1, 5, 4],
            [1, 3, 5],
            [3, 7, 5],
            [3, 2, 7],
            [2, 6, 7],
            [2, 0, 6],
            [0, 4, 6],
        ];
        Mesh::new(vertices, top.iter().chain(&sides).copied().collect(), "cube").unwrap()
    }

    #[test]
    fn a_closed_cube_is_convex_and_a_dented_one_is_not() {
        assert!(mesh_hull(&cube(0.0)).unwrap().exact);
        assert!(!mesh_hull(&cube(1e-3)).unwrap().exact);
    }

    #[test]
    fn open_and_flat_meshes_are_not_their_hulls() {
        let mut open = cube(0.0);
        open.triangles.drain(..4);
        assert!(!mesh_hull(&open).unwrap().exact);
        let flat = Mesh::new(
            vec![Point3::origin(), Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, 1.0, 0.0)],
            vec![[0, 1, 2]],
            "flat",
        );
        assert!(!mesh_hull(&flat.unwrap()).is_some_and(|h| h.exact));
    }
}
