//! One robot, three descriptions: a standard-DH table, a modified-DH table and
//! a URDF give the same forward kinematics.
//!
//! Run: `cargo run -p kinema --example 03_descriptions`

use kinema::Robot;

const STANDARD: &str = r#"
name = "rr-standard"
source = "example"
convention = "standard"
[units]
length = "m"
angle = "deg"
[[joint]]
name = "j1"
d = 0.3
a = 0.5
alpha = 90
min = -180
max = 180
[[joint]]
name = "j2"
a = 0.4
alpha = 0
min = -180
max = 180
[poses]
home = [0, 0]
"#;

// The same arm in Craig's convention: row i holds α(i−1), a(i−1); the last
// row's a = 0.4 becomes a tool offset.
const MODIFIED: &str = r#"
name = "rr-modified"
source = "example"
convention = "modified"
[units]
length = "m"
angle = "deg"
[tool]
xyz = [0.4, 0, 0]
[[joint]]
name = "j1"
d = 0.3
a = 0
alpha = 0
min = -180
max = 180
[[joint]]
name = "j2"
a = 0.5
alpha = 90
min = -180
max = 180
[poses]
home = [0, 0]
"#;

const URDF: &str = r#"<robot name="rr-urdf">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="tool"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 0 1"/><limit lower="-3.14" upper="3.14" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0.5 0 0" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/><limit lower="-3.14" upper="3.14" effort="1" velocity="1"/></joint>
  <joint name="flange" type="fixed"><parent link="l2"/><child link="tool"/><origin xyz="0.4 0 0"/></joint>
</robot>"#;

fn main() -> Result<(), kinema::Error> {
    let a = Robot::from_toml_str(STANDARD, "standard.toml")?;
    let b = Robot::from_toml_str(MODIFIED, "modified.toml")?;
    let c = Robot::from_urdf_str(URDF, "rr.urdf", None)?;
    for q in [[0.0, 0.0], [0.7, -1.1], [2.0, 0.4]] {
        let (pa, pb, pc) = (a.fk(&q)?.world_from_tool, b.fk(&q)?.world_from_tool, c.fk(&q)?.world_from_tool);
        println!(
            "q = {q:?}: standard {:?}  modified {:?}  urdf {:?}",
            pa.pos.as_slice(),
            pb.pos.as_slice(),
            pc.pos.as_slice()
        );
        let worst = (pa.pos - pb.pos).norm().max((pa.pos - pc.pos).norm());
        assert!(worst < 1e-12, "descriptions disagree by {worst} m");
    }
    println!("all three descriptions agree");
    Ok(())
}
