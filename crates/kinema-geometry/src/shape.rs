//! Shapes: what a link's body is made of, in the shape's own frame, and
//! their collision-library form.
//!
//! A new shape kind is a variant of [`Shape`], its arm in
//! [`Shape::collider`] (the parry shape, and a fixed rotation when parry's
//! axis convention differs from the one documented here), and its reading
//! in `urdf.rs` (or the future scene file).

use std::sync::Arc;

use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};
use parry3d_f64::shape::{Ball, Capsule, ConvexPolyhedron, Cuboid, Cylinder, SharedShape, TriMesh};

use crate::convex::{mesh_hull, MeshHull};
use crate::error::{Error, Result};

/// A solid, in its own frame. Lengths in metres. Round shapes are centred on
/// the frame's origin with their axis along its z axis (the URDF convention).
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// A ball of `radius` \[m\].
    Sphere {
        /// Radius \[m\].
        radius: f64,
    },
    /// A box centred on the origin, edges along the axes.
    Box {
        /// Full edge lengths along x, y, z \[m\] (as URDF's `size`; not half extents).
        size: Vector3<f64>,
    },
    /// A cylinder along z, centred on the origin.
    Cylinder {
        /// Radius \[m\].
        radius: f64,
        /// Full length along z \[m\].
        length: f64,
    },
    /// A capsule along z, centred on the origin: the points within `radius`
    /// of the segment from z = −length/2 to z = +length/2.
    Capsule {
        /// Radius \[m\].
        radius: f64,
        /// Length of the segment between the two sphere centres \[m\] (the
        /// capsule's total length is `length + 2·radius`), as coal and
        /// MoveIt count it.
        length: f64,
    },
    /// The convex hull of a mesh's vertices (a solid).
    ConvexMesh(Arc<Mesh>),
    /// A triangle mesh as its surface: a shape inside a closed mesh does not
    /// touch it (as coal's BVH meshes behave).
    TriangleMesh(Arc<Mesh>),
}

/// Triangles over shared vertices, in the shape's frame (scale already applied).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mesh {
    /// Vertex positions \[m\].
    pub vertices: Vec<Point3<f64>>,
    /// Triangles, as indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// A checked mesh: at least one triangle, finite vertices, every index in range.
    /// `what` names it in errors (a file name, most often).
    pub fn new(vertices: Vec<Point3<f64>>, triangles: Vec<[u32; 3]>, what: &str) -> Result<Mesh> {
        let bad = |message: String| Err(Error::Mesh { path: what.to_string(), message });
        if triangles.is_empty() {
            return bad("has no triangles; a collision mesh needs at least one".into());
        }
        if let Some(i) = vertices.iter().position(|v| !v.coords.iter().all(|c| c.is_finite())) {
            return bad(format!("vertex {i} is {:?}; vertices must be finite", vertices[i].coords.as_slice()));
        }
        if let Some(t) = triangles.iter().find(|t| t.iter().any(|&i| i as usize >= vertices.len())) {
            return bad(format!("triangle {t:?} names a vertex beyond the {} vertices", vertices.len()));
        }
        Ok(Mesh { vertices, triangles })
    }
}

impl Shape {
    /// The kind, as a word for messages (`sphere`, `box`, …).
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Sphere { .. } => "sphere",
            Shape::Box { .. } => "box",
            Shape::Cylinder { .. } => "cylinder",
            Shape::Capsule { .. } => "capsule",
            Shape::ConvexMesh(_) => "convex mesh",
            Shape::TriangleMesh(_) => "triangle mesh",
        }
    }

    /// A triangle mesh's convex hull, marked exact if the mesh is convex
    /// (`None` for other shapes).
    pub(crate) fn surface_hull(&self) -> Option<MeshHull> {
        match self {
            Shape::TriangleMesh(mesh) => mesh_hull(mesh),
            _ => None,
        }
    }

    /// The shape in parry's form, and the pose of that form in the shape's
    /// frame (parry's cylinders stand along y, ours along z). Checks the
    /// dimensions; `name` names the shape in errors.
    pub(crate) fn collider(&self, name: &str) -> Result<(SharedShape, Option<Isometry3<f64>>)> {
        let bad = |message: String| Error::Shape { name: name.to_string(), message };
        let length = |what: &str, v: f64, zero_ok: bool| {
            if v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0)) {
                Ok(v)
            } else {
                Err(bad(format!("{what} is {v}; expected a finite length {} 0 m", if zero_ok { "≥" } else { ">" })))
            }
        };
        Ok(match self {
            Shape::Sphere { radius } => (SharedShape::new(Ball::new(length("radius", *radius, false)?)), None),
            Shape::Box { size } => {
                for (axis, v) in ["x", "y", "z"].iter().zip(size.iter()) {
                    length(&format!("box size along {axis}"), *v, false)?;
                }
                (SharedShape::new(Cuboid::new(size / 2.0)), None)
            }
            Shape::Cylinder { radius, length: l } => {
                let c = Cylinder::new(length("length", *l, false)? / 2.0, length("radius", *radius, false)?);
                let y_to_z = Isometry3::from_parts(
                    Default::default(),
                    UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2),
                );
                (SharedShape::new(c), Some(y_to_z))
            }
            Shape::Capsule { radius, length: l } => {
                let c = Capsule::new_z(length("length", *l, true)? / 2.0, length("radius", *radius, false)?);
                (SharedShape::new(c), None)
            }
            Shape::ConvexMesh(mesh) => {
                let hull = ConvexPolyhedron::from_convex_hull(&mesh.vertices).ok_or_else(|| {
                    bad("the mesh's convex hull encloses no volume (all vertices on a plane?)".into())
                })?;
                (SharedShape::new(hull), None)
            }
            Shape::TriangleMesh(mesh) => {
                let m = TriMesh::new(mesh.vertices.clone(), mesh.triangles.clone())
                    .map_err(|e| bad(format!("not a usable triangle mesh: {e}")))?;
                (SharedShape::new(m), None)
            }
        })
    }
}
