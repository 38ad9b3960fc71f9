//! SRDF allowed collisions: read and applied by URDF link name (fixed links
//! included), unknown links named with the known ones, and the generated
//! matrix written and read back unchanged.

use std::path::Path;

use kinema_geometry::{
    collides, generate_srdf, urdf_from_str, CollisionPairs, Placement, Srdf, UrdfOptions, UrdfRobot,
};

/// Four capsule links turning about parallel axes, with a hand folded onto
/// the last one by a fixed joint: far links can fold onto each other.
const URDF: &str = r#"<?xml version="1.0"?>
<robot name="folding_arm">
  <link name="base"><collision><origin xyz="0 0 -0.05"/><geometry><box size="0.3 0.3 0.1"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <link name="l1"><collision><origin xyz="0.15 0 0" rpy="0 1.5707963267948966 0"/><geometry><capsule radius="0.04" length="0.3"/></geometry></collision></link>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.3 0 0.1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <link name="l2"><collision><origin xyz="0.15 0 0" rpy="0 1.5707963267948966 0"/><geometry><capsule radius="0.04" length="0.3"/></geometry></collision></link>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/><origin xyz="0.3 0 -0.1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <link name="l3"><collision><origin xyz="0.15 0 0" rpy="0 1.5707963267948966 0"/><geometry><capsule radius="0.04" length="0.3"/></geometry></collision></link>
  <joint name="j4" type="revolute"><parent link="l3"/><child link="l4"/><origin xyz="0.3 0 0.1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <link name="l4"><collision><origin xyz="0.1 0 0" rpy="0 1.5707963267948966 0"/><geometry><capsule radius="0.04" length="0.2"/></geometry></collision></link>
  <joint name="hand_fixed" type="fixed"><parent link="l4"/><child link="hand"/><origin xyz="0.25 0 0"/></joint>
  <link name="hand"><collision><geometry><sphere radius="0.05"/></geometry></collision></link>
  <link name="camera_mount"/>
  <joint name="camera_fixed" type="fixed"><parent link="l2"/><child link="camera_mount"/><origin xyz="0.1 0 0.05"/></joint>
</robot>
"#;

fn arm() -> UrdfRobot {
    let options = UrdfOptions { tip: Some("hand".into()), skip_visual: true, ..Default::default() };
    urdf_from_str(URDF, "folding_arm.urdf", Path::new("."), &options).unwrap()
}

#[test]
fn disable_collisions_remove_pairs_by_urdf_link_name() {
    let arm = arm();
    let srdf = Srdf::from_str(
        r#"<?xml version="1.0"?>
        <!-- as MoveIt writes it, with other elements beside -->
        <robot name="folding_arm">
          <group name="arm"><chain base_link="base" tip_link="hand"/></group>
          <disable_collisions link1="l1" link2="l3" reason="Never"/>
          <disable_collisions link1="hand" link2="base" reason="User"></disable_collisions>
          <disable_collisions link1="camera_mount" link2="l4" reason="Never"/>
        </robot>"#,
        "folding_arm.srdf",
    )
    .unwrap();
    assert_eq!(srdf.disabled.len(), 3);
    let g = &arm.collision;
    let mut pairs = CollisionPairs::self_collision(g);
    let before = pairs.len();
    // l1–l3 and base–hand go; camera_mount has no shape, so its entry removes nothing.
    assert_eq!(srdf.apply(g, &arm.links, &mut pairs).unwrap(), 2);
    assert_eq!(pairs.len(), before - 2);
    let (base, l1, l3, hand) = (g.find("base_0"), g.find("l1_0"), g.find("l3_0"), g.find("hand_0"));
    assert!(!pairs.contains(l1.unwrap(), l3.unwrap()));
    assert!(!pairs.contains(base.unwrap(), hand.unwrap()));
    assert!(pairs.contains(base.unwrap(), l3.unwrap()));
}

#[test]
fn an_unknown_link_is_named_with_the_known_ones() {
    let arm = arm();
    let srdf = Srdf::from_str(
        r#"<robot name="other"><disable_collisions link1="l1" link2="panda_link3" reason="Never"/></robot>"#,
        "other.srdf",
    )
    .unwrap();
    let mut pairs = CollisionPairs::self_collision(&arm.collision);
    let message = srdf.apply(&arm.collision, &arm.links, &mut pairs).unwrap_err().to_string();
    assert!(message.contains("`panda_link3`"), "{message}");
    assert!(message.contains("base, camera_mount, hand, l1, l2, l3, l4"), "{message}");
    // Not XML, a missing attribute, a root that is not <robot>: errors that say so.
    let bad = |text: &str| Srdf::from_str(text, "bad.srdf").unwrap_err().to_string();
    assert!(bad("<robot><disable_collisions link1=\"a\"/></robot>").contains("no `link2` attribute"));
    assert!(bad("<robot><oops></robot>").contains("not well-formed XML"));
    assert!(bad("<urdf/>").contains("root element is <urdf>"));
}

#[test]
fn the_generated_matrix_round_trips_and_keeps_the_pairs_that_can_collide() {
    let arm = arm();
    let (robot, g) = (&arm.robot, &arm.collision);
    let srdf = generate_srdf(robot, g, 2000, 7).unwrap();
    let again = Srdf::from_str(&srdf.to_xml(), "written.srdf").unwrap();
    assert_eq!(again, srdf);
    assert_eq!(again.link_pairs(), srdf.link_pairs());
    assert_eq!(generate_srdf(robot, g, 2000, 7).unwrap(), srdf, "seeded: the same matrix every run");

    let reason = |a: &str, b: &str| {
        srdf.disabled
            .iter()
            .find(|d| (d.link1 == a && d.link2 == b) || (d.link1 == b && d.link2 == a))
            .map(|d| d.reason.as_str())
    };
    // Neighbours on the chain, and l4 with the hand folded onto it.
    assert_eq!(reason("l1", "l2"), Some("Adjacent"));
    assert_eq!(reason("l4", "hand"), Some("Adjacent"));
    assert_eq!(reason("l3", "hand"), Some("Adjacent"));
    // l1 and l3 are at the same height and fold onto each other: they stay checked.
    assert_eq!(reason("l1", "l3"), None);
    // l2 (raised) and l3 (lowered) share the joint j3, so they are adjacent; l2
    // and l4 are both raised by 0.1 m and can cross: checked.
    assert_eq!(reason("l2", "l4"), None);

    // Every pair the matrix leaves checked was seen in collision at some sample, so
    // applying it never removes a pair that collides at the home configuration.
    let mut pairs = CollisionPairs::self_collision(g);
    srdf.apply(g, &arm.links, &mut pairs).unwrap();
    assert!(!pairs.is_empty());
    let home = Placement::of(robot, g, robot.home()).unwrap();
    for (a, b) in CollisionPairs::self_collision(g).iter() {
        let one = CollisionPairs::from_pairs(g, [(a, b)]).unwrap();
        if collides(g, &home, &one, 0.0).unwrap().is_some() {
            let (la, lb) = (g.shapes()[a].link_name(), g.shapes()[b].link_name());
            assert!(matches!(reason(la, lb), Some("Default" | "Adjacent")), "{la}–{lb} collides at home");
        }
    }
}
