//! Geometry from a URDF: shapes of fixed links fold onto their parent's
//! body at the right pose (checked against a plain walk of the URDF tree),
//! `package://` and relative mesh paths resolve, and a missing mesh is named
//! with every place looked in.

use std::collections::HashMap;
use std::path::Path;

use kinema::{Pose, RpyConvention};
use kinema_geometry::{load_urdf, urdf_from_str, Placement, Shape, UrdfOptions};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::common::urdf_walk;
use crate::meshes::{write_obj, write_stl};

const URDF: &str = r#"<?xml version="1.0"?>
<robot name="bench_arm">
  <link name="world"/>
  <joint name="world_fixed" type="fixed">
    <parent link="world"/><child link="base_link"/><origin xyz="0.1 0.2 0.3" rpy="0 0 0.5"/>
  </joint>
  <link name="base_link">
    <collision><origin xyz="0 0 0.05"/><geometry><box size="0.2 0.2 0.1"/></geometry></collision>
  </link>
  <joint name="j1" type="revolute">
    <parent link="base_link"/><child link="l1"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/>
  </joint>
  <link name="l1">
    <collision name="column"><origin xyz="0 0 0.2" rpy="0.1 0.2 0.3"/><geometry><box size="0.1 0.1 0.4"/></geometry></collision>
    <collision><geometry><sphere radius="0.06"/></geometry></collision>
    <visual><geometry><mesh filename="package://bench_arm/meshes/l1.stl" scale="0.1 0.1 0.1"/></geometry></visual>
  </link>
  <joint name="mount_fixed" type="fixed">
    <parent link="l1"/><child link="mount"/><origin xyz="0 0 0.4" rpy="0 1.5707963 0"/>
  </joint>
  <link name="mount">
    <collision><origin xyz="0.05 0 0"/><geometry><cylinder radius="0.04" length="0.1"/></geometry></collision>
  </link>
  <joint name="j2" type="revolute">
    <parent link="mount"/><child link="l2"/><origin xyz="0 0 0.05" rpy="0.3 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="10" velocity="1"/>
  </joint>
  <link name="l2">
    <collision><origin xyz="0.15 0 0"/><geometry><box size="0.3 0.05 0.05"/></geometry></collision>
    <visual><geometry><mesh filename="meshes/l2.obj"/></geometry></visual>
  </link>
  <joint name="tool_fixed" type="fixed">
    <parent link="l2"/><child link="tool"/><origin xyz="0.3 0 0"/>
  </joint>
  <link name="tool">
    <collision><geometry><sphere radius="0.03"/></geometry></collision>
  </link>
</robot>
"#;

/// A package tree `<dir>/pkgs/bench_arm/meshes/l1.stl` and the URDF at
/// `<dir>/urdf/bench_arm.urdf` with `meshes/l2.obj` beside it.
fn lay_out(dir: &Path) -> std::path::PathBuf {
    let meshes = dir.join("pkgs/bench_arm/meshes");
    std::fs::create_dir_all(&meshes).unwrap();
    write_stl(&meshes.join("l1.stl"));
    std::fs::create_dir_all(dir.join("urdf/meshes")).unwrap();
    write_obj(&dir.join("urdf/meshes/l2.obj"));
    let urdf = dir.join("urdf/bench_arm.urdf");
    std::fs::write(&urdf, URDF).unwrap();
    urdf
}

#[test]
fn fixed_links_fold_onto_their_parent() {
    let dir = tempfile::tempdir().unwrap();
    let path = lay_out(dir.path());
    let options = UrdfOptions { package_paths: vec![dir.path().join("pkgs")], ..Default::default() };
    let loaded = load_urdf(&path, &options).unwrap();
    let (robot, collision) = (&loaded.robot, &loaded.collision);
    assert_eq!(robot.dof(), 2);
    let found: Vec<(&str, usize, &str, &str)> =
        collision.shapes().iter().map(|s| (s.name(), s.link(), s.link_name(), s.shape().kind())).collect();
    assert_eq!(
        found,
        [
            ("base_link_0", 0, "base_link", "box"),
            ("l1_0", 1, "l1", "box"),
            ("l1_1", 1, "l1", "sphere"),
            ("mount_0", 1, "mount", "cylinder"),
            ("l2_0", 2, "l2", "box"),
            ("tool_0", 2, "tool", "sphere"),
        ]
    );
    assert_eq!(collision.shapes()[1].shape(), &Shape::Box { size: [0.1, 0.1, 0.4].into() }, "full edge lengths");
    // The visual meshes: the STL through the package path, scaled; the OBJ beside the URDF.
    let visual = &loaded.visual;
    assert_eq!(visual.len(), 2);
    let Shape::TriangleMesh(l1) = visual.shapes()[0].shape() else { panic!("l1's visual is a mesh") };
    assert_eq!(l1.triangles.len(), 12);
    assert!(l1.vertices.iter().all(|v| v.coords.max() <= 0.1 + 1e-7));

    // World poses: a plain walk of the URDF tree composed with each element's <origin>.
    let u = urdf_rs::read_from_string(URDF).unwrap();
    let origins: Vec<Pose> = u
        .links
        .iter()
        .flat_map(|l| l.collision.iter().map(|c| Pose::from_xyz_rpy(*c.origin.xyz, *c.origin.rpy, RpyConvention::Zyx)))
        .collect();
    let links: Vec<&str> = u.links.iter().flat_map(|l| l.collision.iter().map(|_| l.name.as_str())).collect();
    let mut rng = ChaCha8Rng::seed_from_u64(0x0DF0);
    let mut placement = Placement::new(collision);
    for _ in 0..200 {
        let q = robot.random_q(&mut rng);
        kinema_geometry::place(robot, collision, &q, &mut placement).unwrap();
        let by_name = HashMap::from([("j1".to_string(), q[0]), ("j2".to_string(), q[1])]);
        let walked = urdf_walk(&u, &by_name);
        for i in 0..collision.len() {
            let ours = placement.world_from_shape(collision, i);
            let plain = walked[links[i]] * origins[i];
            let err = (ours.pos - plain.pos).norm() + (ours.rot - plain.rot).norm();
            assert!(err < 1e-12, "shape {} is off by {err:e}", collision.shapes()[i].name());
        }
    }
}

#[test]
fn package_paths_resolve_both_ways() {
    let dir = tempfile::tempdir().unwrap();
    let path = lay_out(dir.path());
    // The directory holding the package, or the package directory itself.
    for package_path in [dir.path().join("pkgs"), dir.path().join("pkgs/bench_arm")] {
        let options =
            UrdfOptions { package_paths: vec![dir.path().join("elsewhere"), package_path], ..Default::default() };
        assert_eq!(load_urdf(&path, &options).unwrap().visual.len(), 2);
    }
    // Collision only: the visual meshes are not needed.
    let options = UrdfOptions { skip_visual: true, ..Default::default() };
    let loaded = load_urdf(&path, &options).unwrap();
    assert_eq!((loaded.collision.len(), loaded.visual.len()), (6, 0));
}

#[test]
fn a_missing_mesh_is_named_with_where_it_was_looked_for() {
    let dir = tempfile::tempdir().unwrap();
    let path = lay_out(dir.path());
    let elsewhere = dir.path().join("elsewhere");
    let options = UrdfOptions { package_paths: vec![elsewhere.clone()], ..Default::default() };
    let e = load_urdf(&path, &options).unwrap_err().to_string();
    let expected = format!(
        "{}: link `l1`: mesh `package://bench_arm/meshes/l1.stl` not found; looked in: `{}` \
         (add the directory that holds the package to the package search path)",
        path.display(),
        elsewhere.join("bench_arm/meshes/l1.stl").display()
    );
    assert_eq!(e, expected);
    let e = load_urdf(&path, &UrdfOptions::default()).unwrap_err().to_string();
    assert!(e.contains("looked in: nowhere (no search directory applies)"), "{e}");

    // A relative path is looked for beside the URDF.
    std::fs::remove_file(dir.path().join("urdf/meshes/l2.obj")).unwrap();
    let options = UrdfOptions { package_paths: vec![dir.path().join("pkgs")], ..Default::default() };
    let e = load_urdf(&path, &options).unwrap_err().to_string();
    let beside = dir.path().join("urdf/meshes/l2.obj");
    assert!(e.contains("link `l2`: mesh `meshes/l2.obj` not found; looked in:"), "{e}");
    assert!(e.contains(&format!("`{}`", beside.display())) && !e.contains("package search path"), "{e}");
}

#[test]
fn urdf_errors_come_from_the_core() {
    let e = urdf_from_str("<robot name=\"x\"/>", "x.urdf", Path::new("."), &UrdfOptions::default()).unwrap_err();
    assert!(matches!(e, kinema_geometry::Error::Kinema(kinema::Error::Model(kinema::ModelError::Urdf { .. }))), "{e}");
    let bad_box = URDF.replace("0.2 0.2 0.1", "0.2 -0.2 0.1");
    let options = UrdfOptions { skip_visual: true, ..Default::default() };
    let e = urdf_from_str(&bad_box, "x.urdf", Path::new("."), &options).unwrap_err().to_string();
    assert!(e.contains("shape `base_link_0`: box size along y is -0.2"), "{e}");
}
