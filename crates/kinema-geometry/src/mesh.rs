//! Mesh files (STL, OBJ, COLLADA) read with `mesh-loader`, bounded in size.

use std::path::Path;

use nalgebra::{Point3, Vector3};

use crate::error::{Error, Result};
use crate::shape::Mesh;

/// The largest mesh file read \[bytes\]: 256 MiB, far above a robot's
/// collision or visual mesh, so that a device or FIFO named by mistake is
/// refused instead of filling the memory.
pub const MAX_MESH_BYTES: u64 = 256 << 20;

/// Reads the mesh at `path` (`.stl`, `.obj`, `.dae`; the format is told by
/// the extension and the content), all its parts merged into one, each
/// vertex multiplied by `scale` per axis (URDF's `scale`).
///
/// # Examples
/// ```
/// # let dir = tempfile::tempdir()?;
/// let path = dir.path().join("tri.obj");
/// std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")?;
/// let mesh = kinema_geometry::load_mesh(&path, [2.0, 2.0, 2.0])?;
/// assert_eq!(mesh.triangles.len(), 1);
/// assert_eq!(mesh.vertices[1].x, 2.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn load_mesh(path: &Path, scale: [f64; 3]) -> Result<Mesh> {
    let shown = path.display().to_string();
    let bytes = kinema::read_bounded(path, "a mesh", MAX_MESH_BYTES)?;
    let bad = |message: String| Error::Mesh { path: shown.clone(), message };
    if !scale.iter().all(|s| s.is_finite() && *s != 0.0) {
        return Err(bad(format!("scale {scale:?} must be three finite, non-zero factors")));
    }
    let scene = mesh_loader::Loader::default()
        .merge_meshes(true)
        .load_from_slice(&bytes, path)
        .map_err(|e| bad(format!("not a readable STL, OBJ or COLLADA mesh: {e}")))?;
    let scale = Vector3::from(scale);
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for part in &scene.meshes {
        let offset = vertices.len() as u32;
        vertices.extend(part.vertices.iter().map(|v| {
            let v = Vector3::new(v[0] as f64, v[1] as f64, v[2] as f64);
            Point3::from(v.component_mul(&scale))
        }));
        triangles.extend(part.faces.iter().map(|f| [f[0] + offset, f[1] + offset, f[2] + offset]));
    }
    Mesh::new(vertices, triangles, &shown)
}
