//! The link geometry the page draws, as JSON: primitive shapes with their
//! dimensions and placement, meshes as base64 little-endian arrays (compact,
//! and read by the page straight into typed arrays).

use kinema::Pose;
use kinema_geometry::{Mesh, Obstacle, RobotGeometry, Shape};
use serde::Serialize;

/// The answer of `GET /api/robots/{name}/geometry`: every shape of the robot
/// in its link's frame (links as [`kinema::kin::link_frames_into`] numbers
/// them: 0 the base, i the body moved by joint i), sent once; the link poses
/// come with every FK answer (`frames`).
#[derive(Debug, Serialize)]
pub struct GeometryAnswer {
    /// The robot's name.
    pub robot: String,
    /// The number of links (degrees of freedom + 1).
    pub links: usize,
    /// The shapes to draw: the URDF's `<visual>` elements (empty when the
    /// robot has none).
    pub visual: Vec<ShapeAnswer>,
    /// The collision shapes: a URDF's `<collision>` elements or a robot
    /// file's `[[shape]]`s.
    pub collision: Vec<ShapeAnswer>,
}

/// The answer of `POST /api/scene`: a scene's obstacles in the world frame.
#[derive(Debug, Serialize)]
pub struct SceneAnswer {
    /// The obstacles (the scene's robots standing as obstacles included).
    pub obstacles: Vec<ShapeAnswer>,
}

/// One shape: its kind and dimensions, and its pose in its link's frame (an
/// obstacle's: in the world frame).
#[derive(Debug, Serialize)]
pub struct ShapeAnswer {
    /// The shape's name.
    pub name: String,
    /// The link it is fixed to (absent for an obstacle).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub link: Option<usize>,
    /// The body it belongs to as `/api/collide` names pairs: its link's
    /// name (a URDF link's, else `link i`) or its obstacle's body.
    pub body: String,
    /// `sphere`, `box`, `cylinder`, `capsule` or `mesh`.
    pub kind: &'static str,
    /// The shape's frame: 4 rows of 4 numbers, translation in metres.
    /// Round shapes are centred on it with their axis along its z axis.
    pub pose: [[f64; 4]; 4],
    /// A box's full edge lengths along x, y, z \[m\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub size: Option<[f64; 3]>,
    /// A sphere's, cylinder's or capsule's radius \[m\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// A cylinder's length, a capsule's segment length \[m\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub length: Option<f64>,
    /// A mesh's triangles.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mesh: Option<MeshAnswer>,
    /// Whether a mesh stands for its convex hull (as a collision shape).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub convex_hull: bool,
}

/// Triangles over shared vertices, base64-encoded little-endian arrays.
#[derive(Debug, Serialize)]
pub struct MeshAnswer {
    /// The number of vertices.
    pub vertex_count: usize,
    /// The number of triangles.
    pub triangle_count: usize,
    /// x, y, z of each vertex as f32 \[m\], in the shape's frame.
    pub vertices: String,
    /// Three u32 vertex indices per triangle.
    pub triangles: String,
}

impl GeometryAnswer {
    /// The shapes of a robot named `robot` with `dof` joints.
    pub fn new(robot: &str, dof: usize, visual: Option<&RobotGeometry>, collision: Option<&RobotGeometry>) -> Self {
        let shapes = |g: Option<&RobotGeometry>| {
            g.map_or_else(Vec::new, |g| {
                g.shapes()
                    .iter()
                    .map(|s| ShapeAnswer::new(s.name(), Some(s.link()), s.link_name(), s.link_from_shape(), s.shape()))
                    .collect()
            })
        };
        GeometryAnswer {
            robot: robot.to_string(),
            links: dof + 1,
            visual: shapes(visual),
            collision: shapes(collision),
        }
    }
}

impl SceneAnswer {
    /// A scene's obstacles.
    pub fn new(obstacles: &[Obstacle]) -> SceneAnswer {
        let obstacles =
            obstacles.iter().map(|o| ShapeAnswer::new(&o.name, None, &o.body, &o.world_from_shape, &o.shape)).collect();
        SceneAnswer { obstacles }
    }
}

impl ShapeAnswer {
    fn new(name: &str, link: Option<usize>, body: &str, pose: &Pose, shape: &Shape) -> ShapeAnswer {
        let mut answer = ShapeAnswer {
            name: name.to_string(),
            link,
            body: body.to_string(),
            kind: "mesh",
            pose: rows(pose),
            size: None,
            radius: None,
            length: None,
            mesh: None,
            convex_hull: false,
        };
        match shape {
            Shape::Sphere { radius } => (answer.kind, answer.radius) = ("sphere", Some(*radius)),
            Shape::Box { size } => (answer.kind, answer.size) = ("box", Some([size.x, size.y, size.z])),
            Shape::Cylinder { radius, length } => {
                (answer.kind, answer.radius, answer.length) = ("cylinder", Some(*radius), Some(*length));
            }
            Shape::Capsule { radius, length } => {
                (answer.kind, answer.radius, answer.length) = ("capsule", Some(*radius), Some(*length));
            }
            Shape::ConvexMesh(mesh) => (answer.mesh, answer.convex_hull) = (Some(MeshAnswer::new(mesh)), true),
            Shape::TriangleMesh(mesh) => answer.mesh = Some(MeshAnswer::new(mesh)),
        }
        answer
    }
}

impl MeshAnswer {
    fn new(mesh: &Mesh) -> MeshAnswer {
        let vertices: Vec<u8> =
            mesh.vertices.iter().flat_map(|v| v.coords.iter().flat_map(|&c| (c as f32).to_le_bytes())).collect();
        let triangles: Vec<u8> = mesh.triangles.iter().flatten().flat_map(|i| i.to_le_bytes()).collect();
        MeshAnswer {
            vertex_count: mesh.vertices.len(),
            triangle_count: mesh.triangles.len(),
            vertices: base64(&vertices),
            triangles: base64(&triangles),
        }
    }
}

fn rows(pose: &Pose) -> [[f64; 4]; 4] {
    let (r, p) = (&pose.rot, &pose.pos);
    let row = |i: usize| [r[(i, 0)], r[(i, 1)], r[(i, 2)], p[i]];
    [row(0), row(1), row(2), [0.0, 0.0, 0.0, 1.0]]
}

/// Standard base64 (RFC 4648, with padding).
pub(crate) fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
        let n = u32::from(b[0]) << 16 | u32::from(b[1]) << 8 | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use kinema_geometry::parry3d_f64::na::Point3;
    use std::sync::Arc;

    #[test]
    fn base64_matches_rfc_4648_vectors() {
        for (plain, coded) in
            [("", ""), ("f", "Zg=="), ("fo", "Zm8="), ("foo", "Zm9v"), ("foob", "Zm9vYg=="), ("foobar", "Zm9vYmFy")]
        {
            assert_eq!(base64(plain.as_bytes()), coded);
        }
    }

    #[test]
    fn a_mesh_is_sent_as_little_endian_arrays() {
        let vertices = vec![Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, 0.5, 0.25)];
        let mesh = Mesh::new(vertices, vec![[0, 1, 2]], "test").unwrap();
        let pose = Pose::translation(0.1, 0.2, 0.3);
        let s = ShapeAnswer::new("m", Some(2), "link 2", &pose, &Shape::TriangleMesh(Arc::new(mesh)));
        assert_eq!((s.kind, s.link, s.pose[1][3]), ("mesh", Some(2), 0.2));
        let m = s.mesh.unwrap();
        assert_eq!((m.vertex_count, m.triangle_count), (3, 1));
        let mut expected = Vec::new();
        for c in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.5, 0.25] {
            expected.extend(c.to_le_bytes());
        }
        assert_eq!(m.vertices, base64(&expected));
        assert_eq!(m.triangles, base64(&[0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0]));
    }
}
