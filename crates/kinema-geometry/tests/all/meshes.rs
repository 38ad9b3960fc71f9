//! Mesh files written by the tests (binary STL, OBJ, COLLADA) are read with
//! their scale, and distances to them match the cube they describe.

use std::path::Path;
use std::sync::Arc;

use kinema::{Pose, Robot};
use kinema_geometry::{load_mesh, min_distance, CollisionPairs, LinkShape, Mesh, Placement, RobotGeometry, Shape};

/// The unit cube [0, 1]³ as 8 vertices and 12 outward triangles.
pub fn cube() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let v = (0..8).map(|i| [(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32]).collect();
    let t = vec![
        [0, 2, 1],
        [1, 2, 3], // z = 0
        [4, 5, 6],
        [5, 7, 6], // z = 1
        [0, 1, 4],
        [1, 5, 4], // y = 0
        [2, 6, 3],
        [3, 6, 7], // y = 1
        [0, 4, 2],
        [2, 4, 6], // x = 0
        [1, 3, 5],
        [3, 7, 5], // x = 1
    ];
    (v, t)
}

/// A binary STL of the unit cube.
pub fn write_stl(path: &Path) {
    let (v, t) = cube();
    let mut bytes = vec![0u8; 80];
    bytes.extend((t.len() as u32).to_le_bytes());
    for tri in &t {
        bytes.extend([0f32; 3].iter().flat_map(|c| c.to_le_bytes()));
        for &i in tri {
            bytes.extend(v[i as usize].iter().flat_map(|c| c.to_le_bytes()));
        }
        bytes.extend(0u16.to_le_bytes());
    }
    std::fs::write(path, bytes).unwrap();
}

/// A Wavefront OBJ of the unit cube.
pub fn write_obj(path: &Path) {
    let (v, t) = cube();
    let mut text = String::from("# unit cube\no cube\n");
    for p in &v {
        text += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for f in &t {
        text += &format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1);
    }
    std::fs::write(path, text).unwrap();
}

/// A minimal COLLADA 1.4.1 document of the unit cube, in metres.
pub fn write_dae(path: &Path) {
    let (v, t) = cube();
    let positions: Vec<String> = v.iter().flat_map(|p| p.iter().map(|c| c.to_string())).collect();
    let indices: Vec<String> = t.iter().flat_map(|f| f.iter().map(|i| i.to_string())).collect();
    let text = format!(
        r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="cube" name="cube">
      <mesh>
        <source id="cube-positions">
          <float_array id="cube-positions-array" count="{}">{}</float_array>
          <technique_common>
            <accessor source="#cube-positions-array" count="8" stride="3">
              <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
            </accessor>
          </technique_common>
        </source>
        <vertices id="cube-vertices"><input semantic="POSITION" source="#cube-positions"/></vertices>
        <triangles count="{}"><input semantic="VERTEX" source="#cube-vertices" offset="0"/><p>{}</p></triangles>
      </mesh>
    </geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene"><node id="node"><instance_geometry url="#cube"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
"##,
        positions.len(),
        positions.join(" "),
        t.len(),
        indices.join(" ")
    );
    std::fs::write(path, text).unwrap();
}

/// The distance from a ball of radius 0.1 centred at `at` to the mesh, as a
/// triangle mesh and as its convex hull.
fn distances(mesh: Mesh, at: Pose) -> (f64, f64) {
    let robot = Robot::builtin("ur5").unwrap();
    let mesh = Arc::new(mesh);
    let mut out = [0.0; 2];
    for (i, shape) in [Shape::TriangleMesh(mesh.clone()), Shape::ConvexMesh(mesh)].into_iter().enumerate() {
        let shapes = vec![
            LinkShape::new("mesh", 0, Pose::IDENTITY, shape).unwrap(),
            LinkShape::new("ball", 0, at, Shape::Sphere { radius: 0.1 }).unwrap(),
        ];
        let geometry = RobotGeometry::new(&robot, shapes).unwrap();
        let placement = Placement::of(&robot, &geometry, robot.home()).unwrap();
        let pairs = CollisionPairs::from_pairs(&geometry, [(0, 1)]).unwrap();
        out[i] = min_distance(&geometry, &placement, &pairs).unwrap().unwrap().distance;
    }
    (out[0], out[1])
}

#[test]
fn stl_obj_and_collada_cubes() {
    let dir = tempfile::tempdir().unwrap();
    let files = [("cube.stl", write_stl as fn(&Path)), ("cube.obj", write_obj), ("cube.dae", write_dae)];
    for (name, write) in files {
        let path = dir.path().join(name);
        write(&path);
        let mesh = load_mesh(&path, [2.0, 1.0, 0.5]).unwrap();
        assert_eq!(mesh.triangles.len(), 12, "{name}");
        let max = mesh.vertices.iter().fold([0.0f64; 3], |m, v| [m[0].max(v.x), m[1].max(v.y), m[2].max(v.z)]);
        assert_eq!(max, [2.0, 1.0, 0.5], "{name}: scaled extent");
        // 0.3 m beyond the x = 2 face, at mid height: 0.2 m from the surface.
        let (tri, hull) = distances(mesh.clone(), Pose::translation(2.3, 0.5, 0.25));
        assert!((tri - 0.2).abs() < 1e-6 && (hull - 0.2).abs() < 1e-6, "{name}: {tri} {hull}");
        // Inside: the hull (a solid) overlaps; the triangle mesh is a surface 0.15 m away.
        let (tri, hull) = distances(mesh, Pose::translation(1.0, 0.5, 0.25));
        assert!(hull < -0.1, "{name}: hull {hull}");
        assert!((tri - 0.15).abs() < 1e-6, "{name}: surface {tri}");
    }
}

#[test]
fn unreadable_meshes_say_why() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nope.stl");
    let e = load_mesh(&missing, [1.0; 3]).unwrap_err().to_string();
    assert!(e.contains("nope.stl"), "{e}");
    let junk = dir.path().join("junk.xyz");
    std::fs::write(&junk, "hello").unwrap();
    let e = load_mesh(&junk, [1.0; 3]).unwrap_err().to_string();
    assert!(e.starts_with(&format!("mesh `{}`", junk.display())) && e.contains("STL, OBJ or COLLADA"), "{e}");
    let empty = dir.path().join("empty.obj");
    std::fs::write(&empty, "v 0 0 0\n").unwrap();
    let e = load_mesh(&empty, [1.0; 3]).unwrap_err().to_string();
    assert!(e.contains("no triangles"), "{e}");
    let cube = dir.path().join("cube.obj");
    write_obj(&cube);
    let e = load_mesh(&cube, [1.0, 0.0, 1.0]).unwrap_err().to_string();
    assert!(e.contains("scale"), "{e}");
}
