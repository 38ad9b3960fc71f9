//! Bad URDF and random descriptions give an error that says what was wrong,
//! and never a panic.

use kinema::{
    DhConvention, Error, Frame, GeometryKind, Joint, JointType, Limits, LinkGeometry, Model, Robot, RpyConvention,
};
use kinema::{InputError, ModelError};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::bad_input::{data, GOOD};
use crate::mutate::{fuzz_cases, mutate, random_text};

fn urdf_err(text: &str, tip: Option<&str>) -> String {
    let e = Robot::from_urdf_str(text, "bad.urdf", tip).expect_err("must be rejected");
    let Error::Model(ModelError::Urdf { file, message }) = &e else {
        panic!("expected Error::Model(ModelError::Urdf), got {e:?}")
    };
    assert_eq!(file, "bad.urdf");
    assert_eq!(e.to_string(), format!("bad.urdf: {message}"));
    message.clone()
}

/// A three-link URDF's head, up to its joints.
pub(crate) const GOOD_URDF_HEAD: &str = r#"<?xml version="1.0"?>
<robot name="r">
  <link name="base"/>
  <link name="l1"/>
  <link name="l2"/>
"#;

pub(crate) fn joint_xml(name: &str, kind: &str, parent: &str, child: &str, limit: &str) -> String {
    format!(
        r#"  <joint name="{name}" type="{kind}">
    <parent link="{parent}"/>
    <child link="{child}"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/>
    <axis xyz="0 0 1"/>
    {limit}
  </joint>
"#
    )
}

pub(crate) const LIMIT: &str = r#"<limit lower="-1" upper="1" effort="1" velocity="1"/>"#;

#[test]
fn urdf_valid_fixture_is_valid() {
    let text = format!(
        "{GOOD_URDF_HEAD}{}{}</robot>",
        joint_xml("j1", "revolute", "base", "l1", LIMIT),
        joint_xml("j2", "revolute", "l1", "l2", LIMIT)
    );
    let r = Robot::from_urdf_str(&text, "ok.urdf", None).unwrap();
    assert_eq!(r.dof(), 2);
    assert!((r.fk(&[0.3, -0.2]).unwrap().world_from_tool.pos.z - 0.2).abs() < 1e-15);
}

#[test]
fn urdf_not_xml() {
    for text in ["", "this is not xml", "name = \"toml\"\n", "<robot name=\"r\">"] {
        let m = urdf_err(text, None);
        assert!(!m.is_empty(), "{text:?}");
    }
    // XML that is not well formed: the line and column of the markup at fault.
    let e =
        Robot::from_urdf_str("<?xml version=\"1.0\"?>\n<robot>\n  <link>\n</robot>\n", "bad.urdf", None).unwrap_err();
    let Error::Model(ModelError::Description { line: 4, column: 1, field, message, .. }) = &e else { panic!("{e:?}") };
    assert_eq!(field, "XML");
    assert!(message.contains("not well-formed") && message.contains("</link>"), "{message}");
    let m = urdf_err("this is not xml", None);
    assert!(m.contains("not a readable URDF"), "{m}");
    // Valid XML with no joints.
    let m = urdf_err(&format!("{GOOD_URDF_HEAD}</robot>"), None);
    assert!(m.contains("no <joint>"), "{m}");
}

/// The `<joint>` of `joint_xml` as the second joint after `GOOD_URDF_HEAD`
/// and one other joint_xml starts on this line, column 3.
const SECOND_JOINT_LINE: usize = 13;

/// iCub (issue 34, item 12): an empty `<texture/>` (urdf-rs wants a filename)
/// does not matter, since visuals, collisions and materials are not read; an
/// element urdf-rs cannot read is named with its line.
#[test]
fn urdf_unread_elements_are_skipped_and_unreadable_ones_located() {
    let visual = r#"<link name="l2">
    <visual>
      <geometry><mesh/></geometry>
      <material name="material.metal">
        <texture />
        <color rgba="0 0 0 1" />
      </material>
    </visual>
    <collision><geometry><box/></geometry></collision>
  </link>
  <material name="top"><texture/></material>
"#;
    let text = format!(
        "{}{}{}</robot>",
        GOOD_URDF_HEAD.replace("<link name=\"l2\"/>\n", visual),
        joint_xml("j1", "revolute", "base", "l1", LIMIT),
        joint_xml("j2", "revolute", "l1", "l2", LIMIT)
    );
    let r = Robot::from_urdf_str(&text, "icub-like.urdf", None).unwrap();
    assert_eq!(r.dof(), 2);

    // A <limit> without its required `velocity`: urdf-rs says "missing field"; kinema says where.
    let text = format!(
        "{GOOD_URDF_HEAD}{}{}</robot>",
        joint_xml("j1", "revolute", "base", "l1", LIMIT),
        joint_xml("j2", "revolute", "l1", "l2", r#"<limit lower="-1" upper="1" effort="1"/>"#)
    );
    let e = Robot::from_urdf_str(&text, "bad.urdf", None).unwrap_err();
    let Error::Model(ModelError::Description { file, line, column, field, message }) = &e else { panic!("{e:?}") };
    assert_eq!((file.as_str(), *line, *column), ("bad.urdf", SECOND_JOINT_LINE, 3));
    assert_eq!(field, "<joint name=\"j2\">");
    assert!(message.contains("velocity") && message.contains("<joint>"), "{message}");
    assert!(e.to_string().starts_with(&format!("bad.urdf:{SECOND_JOINT_LINE}:3: `<joint name=\"j2\">`: ")), "{e}");
    // A link whose mass is not a number.
    let text = format!(
        "{}{}{}</robot>",
        GOOD_URDF_HEAD
            .replace("<link name=\"l1\"/>", "<link name=\"l1\"><inertial><mass value=\"heavy\"/></inertial></link>"),
        joint_xml("j1", "revolute", "base", "l1", LIMIT),
        joint_xml("j2", "revolute", "l1", "l2", LIMIT)
    );
    let e = Robot::from_urdf_str(&text, "bad.urdf", None).unwrap_err();
    let Error::Model(ModelError::Description { line: 4, column: 3, field, .. }) = &e else { panic!("{e:?}") };
    assert_eq!(field, "<link name=\"l1\">");
}

/// Issue 34, item 12: URDF requires <limit> on revolute and prismatic joints;
/// without one urdf-rs gives [0, 0], a locked joint. On the chain that is an
/// error naming the joint; a continuous joint needs none.
#[test]
fn urdf_joint_without_limit_is_refused() {
    for kind in ["revolute", "prismatic"] {
        let text = format!(
            "{GOOD_URDF_HEAD}{}{}</robot>",
            joint_xml("j1", "revolute", "base", "l1", LIMIT),
            joint_xml("j2", kind, "l1", "l2", "")
        );
        let e = Robot::from_urdf_str(&text, "bad.urdf", None).unwrap_err();
        let Error::Model(ModelError::Description { line, column: 3, field, message, .. }) = &e else { panic!("{e:?}") };
        assert_eq!(*line, SECOND_JOINT_LINE);
        assert_eq!(field, "<joint name=\"j2\">");
        assert!(message.contains(&format!("a {kind} joint needs a <limit")) && message.contains("[0, 0]"), "{message}");
        assert_eq!(message.contains("continuous"), kind == "revolute", "{message}");
    }
    let text = format!(
        "{GOOD_URDF_HEAD}  <link name=\"l3\"/>\n{}{}{}</robot>",
        joint_xml("j1", "revolute", "base", "l1", LIMIT),
        joint_xml("j2", "continuous", "l1", "l2", ""),
        joint_xml("j3", "revolute", "base", "l3", "")
    );
    // Continuous needs no <limit>; the limitless j3 is off the chain to l2.
    let r = Robot::from_urdf_str(&text, "ok.urdf", Some("l2")).unwrap();
    assert_eq!(r.joints()[1].limits.max, f64::INFINITY);
    let e = Robot::from_urdf_str(&text, "bad.urdf", Some("l3")).unwrap_err();
    assert!(
        matches!(&e, Error::Model(ModelError::Description { field, .. }) if field == "<joint name=\"j3\">"),
        "{e:?}"
    );
}

/// Issue 34, item 12: a `<mimic>` joint on the chain is refused with a typed
/// error naming it and the joint it follows; off the chain it does not matter.
#[test]
fn urdf_mimic_joint_on_the_chain_is_refused() {
    let mimic = format!("{LIMIT}\n    <mimic joint=\"j1\" multiplier=\"2\" offset=\"0.5\"/>");
    let text = format!(
        "{GOOD_URDF_HEAD}{}{}</robot>",
        joint_xml("j1", "revolute", "base", "l1", LIMIT),
        joint_xml("j2", "revolute", "l1", "l2", &mimic)
    );
    let e = Robot::from_urdf_str(&text, "bad.urdf", None).unwrap_err();
    assert_eq!(
        e,
        Error::Model(ModelError::MimicJoint {
            file: "bad.urdf".into(),
            line: SECOND_JOINT_LINE,
            joint: "j2".into(),
            follows: "j1".into(),
            multiplier: 2.0,
            offset: 0.5
        })
    );
    let m = e.to_string();
    assert!(m.starts_with(&format!("bad.urdf:{SECOND_JOINT_LINE}: joint `j2` on the chain mimics joint `j1`")), "{m}");
    assert!(m.contains("--tip"), "{m}");
    // Defaults: multiplier 1, offset 0.
    let text = text.replace(" multiplier=\"2\" offset=\"0.5\"", "");
    let Error::Model(ModelError::MimicJoint { multiplier, offset, .. }) =
        Robot::from_urdf_str(&text, "bad.urdf", None).unwrap_err()
    else {
        panic!()
    };
    assert_eq!((multiplier, offset), (1.0, 0.0));
    // Off the chain (a gripper finger beside the tip): the chain loads.
    let text = format!(
        "{GOOD_URDF_HEAD}  <link name=\"l3\"/>\n{}{}{}</robot>",
        joint_xml("j1", "revolute", "base", "l1", LIMIT),
        joint_xml("j2", "revolute", "l1", "l2", LIMIT),
        joint_xml("j3", "revolute", "l1", "l3", &mimic.replace("j1", "j2"))
    );
    assert_eq!(Robot::from_urdf_str(&text, "ok.urdf", Some("l2")).unwrap().dof(), 2);
    let e = Robot::from_urdf_str(&text, "bad.urdf", Some("l3")).unwrap_err();
    assert!(
        matches!(&e, Error::Model(ModelError::MimicJoint { joint, follows, .. }) if joint == "j3" && follows == "j2"),
        "{e:?}"
    );
}

#[test]
fn urdf_unsupported_joint_type_on_the_chain() {
    for kind in ["floating", "planar"] {
        let text = format!(
            "{GOOD_URDF_HEAD}{}{}</robot>",
            joint_xml("j1", "revolute", "base", "l1", LIMIT),
            joint_xml("free", kind, "l1", "l2", LIMIT)
        );
        let m = urdf_err(&text, None);
        assert!(m.contains("`free`") && m.contains(kind), "{m}");
    }
    // Off the chain it does not matter.
    let text = format!(
        "{GOOD_URDF_HEAD}  <link name=\"l3\"/>\n{}{}{}</robot>",
        joint_xml("j1", "revolute", "base", "l1", LIMIT),
        joint_xml("j2", "revolute", "l1", "l2", LIMIT),
        joint_xml("free", "floating", "base", "l3", LIMIT)
    );
    assert_eq!(Robot::from_urdf_str(&text, "t", Some("l2")).unwrap().dof(), 2);
    let m = urdf_err(&text, Some("l3"));
    assert!(m.contains("floating"), "{m}");
}

#[test]
fn urdf_cycle_and_two_roots() {
    // A cycle: every link is some joint's child, so there is no root.
    let text = format!(
        "{GOOD_URDF_HEAD}{}{}{}</robot>",
        joint_xml("j1", "revolute", "base", "l1", LIMIT),
        joint_xml("j2", "revolute", "l1", "l2", LIMIT),
        joint_xml("j3", "revolute", "l2", "base", LIMIT)
    );
    let m = urdf_err(&text, None);
    assert!(m.contains("root") && m.contains("cycle"), "{m}");
    let m = urdf_err(&text, Some("l2"));
    assert!(m.contains("cycle"), "{m}");
    // Two roots: two separate chains.
    let text = format!(
        "{GOOD_URDF_HEAD}  <link name=\"other\"/>\n  <link name=\"l4\"/>\n{}{}{}</robot>",
        joint_xml("j1", "revolute", "base", "l1", LIMIT),
        joint_xml("j2", "revolute", "l1", "l2", LIMIT),
        joint_xml("j3", "revolute", "other", "l4", LIMIT)
    );
    let m = urdf_err(&text, None);
    assert!(m.contains("found 2") && m.contains("base") && m.contains("other"), "{m}");
    // A link with two parents.
    let text = format!(
        "{GOOD_URDF_HEAD}{}{}</robot>",
        joint_xml("j1", "revolute", "base", "l2", LIMIT),
        joint_xml("j2", "revolute", "l1", "l2", LIMIT)
    );
    let m = urdf_err(&text, None);
    assert!(m.contains("`l2`") && m.contains("more than one joint"), "{m}");
}

#[test]
fn urdf_limit_lower_above_upper() {
    let text = format!(
        "{GOOD_URDF_HEAD}{}{}</robot>",
        joint_xml("j1", "revolute", "base", "l1", LIMIT),
        joint_xml("j2", "revolute", "l1", "l2", r#"<limit lower="2" upper="1" effort="1" velocity="1"/>"#)
    );
    let m = urdf_err(&text, None);
    assert!(m.contains("`j2`") && m.contains("lower = 2") && m.contains("upper = 1"), "{m}");
    // A zero axis.
    let text = format!(
        "{GOOD_URDF_HEAD}{}{}</robot>",
        joint_xml("j1", "revolute", "base", "l1", LIMIT).replace("\"0 0 1\"", "\"0 0 0\""),
        joint_xml("j2", "revolute", "l1", "l2", LIMIT)
    );
    let m = urdf_err(&text, None);
    assert!(m.contains("`j1`") && m.contains("axis"), "{m}");
}

#[test]
fn urdf_effort_zero_is_unknown_and_negative_is_an_error() {
    let limit = |effort: &str| format!(r#"<limit lower="-1" upper="1" effort="{effort}" velocity="1"/>"#);
    let text = format!(
        "{GOOD_URDF_HEAD}{}{}</robot>",
        joint_xml("j1", "revolute", "base", "l1", &limit("87")),
        joint_xml("j2", "revolute", "l1", "l2", &limit("0"))
    );
    let r = Robot::from_urdf_str(&text, "ok.urdf", None).unwrap();
    assert_eq!((r.joints()[0].limits.effort, r.joints()[1].limits.effort), (Some(87.0), None));
    for bad in ["-5", "NaN", "inf"] {
        let text = format!(
            "{GOOD_URDF_HEAD}{}{}</robot>",
            joint_xml("j1", "revolute", "base", "l1", LIMIT),
            joint_xml("j2", "revolute", "l1", "l2", &limit(bad))
        );
        let m = urdf_err(&text, None);
        assert!(m.contains("`j2`") && m.contains("effort") && m.contains("> 0"), "{bad}: {m}");
    }
}

#[test]
fn model_rejects_a_bad_effort_limit() {
    let joint = |effort| Joint {
        name: "j1".into(),
        kind: JointType::Revolute,
        geometry: LinkGeometry::Dh { convention: DhConvention::Standard, d: 0.0, a: 1.0, alpha: 0.0, theta: 0.0 },
        offset: 0.0,
        limits: Limits { effort, ..Limits::position(-1.0, 1.0) },
    };
    let make = |effort| {
        Model::builder("one", GeometryKind::Standard)
            .joints(vec![joint(effort)])
            .pose("home", vec![0.0])
            .build()
            .map(Robot::new)
    };
    assert_eq!(make(Some(5.0)).unwrap().joints()[0].limits.effort, Some(5.0));
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = make(Some(bad)).unwrap_err();
        assert!(matches!(&e, Error::Model(ModelError::InvalidModel { .. })), "{e:?}");
        let m = e.to_string();
        assert!(m.contains("`j1`") && m.contains("effort limit") && m.contains("positive and finite"), "{m}");
    }
}

#[test]
fn urdf_unknown_tip() {
    let text = std::fs::read_to_string(data("iiwa14.urdf")).unwrap();
    let m = urdf_err(&text, Some("link_99"));
    assert!(m.contains("`link_99`") && m.contains("link_7") && m.contains("tool0"), "{m}");
    // A tip for a TOML file makes no sense.
    let e = Robot::from_file(data("iiwa-modified.toml"), Some("tool0")).unwrap_err();
    assert!(matches!(&e, Error::Input(InputError::DoesNotFit { what, .. }) if what == "tip"), "{e:?}");
    let e = Robot::load("panda", Some("tool0")).unwrap_err();
    assert!(matches!(&e, Error::Input(InputError::DoesNotFit { what, .. }) if what == "tip"), "{e:?}");
}

// ---------------------------------------------------------------------------
// Random input: never a panic.

/// Uses a parsed robot the way a caller would; nothing here may panic either.
/// Every answer an accepted robot gives is finite (issue 35 item 6).
fn exercise(robot: &Robot, rng: &mut ChaCha8Rng) {
    let finite =
        |v: &[f64], what: &str| assert!(v.iter().all(|x| x.is_finite()), "{what} of `{}`: {v:?}", robot.name());
    for q in [robot.home().to_vec(), robot.random_q(rng)] {
        if let Ok(fk) = robot.fk(&q) {
            finite(fk.world_from_tool.to_matrix().as_slice(), "fk");
        }
        if let Ok(frames) = robot.link_frames(&q) {
            frames.iter().for_each(|f| finite(f.pos.as_slice(), "link frames"));
        }
        let _ = robot.analytic_jacobian(&q, RpyConvention::Zyx);
        if let Ok(j) = robot.jacobian(&q, Frame::Base) {
            finite(j.as_slice(), "jacobian");
            let _ = kinema::analysis::report(&j);
        }
        if let Ok(tau) = kinema::dynamics::gravity_torques(robot, &q, &kinema::nalgebra::Vector3::new(0.0, 0.0, -9.81))
        {
            finite(&tau, "gravity torques");
        }
    }
}

#[test]
fn random_toml_never_panics() {
    let sources = [
        GOOD.to_string(),
        kinema::builtin_source("scara5").unwrap().to_string(),
        kinema::builtin_source("rommel").unwrap().to_string(),
        std::fs::read_to_string(data("ur5-general.toml")).unwrap(),
        std::fs::read_to_string(data("iiwa-modified.toml")).unwrap(),
    ];
    let mut rng = ChaCha8Rng::seed_from_u64(0xf022);
    let (mut ok, mut err) = (0, 0);
    let cases = fuzz_cases(3000);
    for case in 0..cases {
        let text = if case % 5 == 0 { random_text(&mut rng) } else { mutate(&sources[case % sources.len()], &mut rng) };
        match Robot::from_toml_str(&text, "fuzz.toml") {
            Ok(robot) => {
                ok += 1;
                exercise(&robot, &mut rng);
            }
            Err(e) => {
                err += 1;
                assert!(!e.to_string().is_empty());
                if let Error::Model(ModelError::Description { line, column, .. }) = e {
                    assert!(line >= 1 && line <= text.lines().count().max(1) + 1, "{line} {text}");
                    assert!(column >= 1);
                }
            }
        }
    }
    // The mutations must produce both outcomes, or they test nothing.
    assert!(ok > 100 && err > 1000, "ok = {ok}, err = {err}");
}

#[test]
fn random_urdf_never_panics() {
    let sources = [
        std::fs::read_to_string(data("iiwa14.urdf")).unwrap(),
        std::fs::read_to_string(data("two-leaves.urdf")).unwrap(),
        std::fs::read_to_string(data("ros-industrial.urdf")).unwrap(),
        std::fs::read_to_string(data("off-chain-inertia.urdf")).unwrap(),
    ];
    let mut rng = ChaCha8Rng::seed_from_u64(0x0df);
    let (mut ok, mut err) = (0, 0);
    let cases = fuzz_cases(2500);
    for case in 0..cases {
        let text = if case % 5 == 0 { random_text(&mut rng) } else { mutate(&sources[case % sources.len()], &mut rng) };
        let tip = match rng.random_range(0..5) {
            0 => Some("leaf_a"),
            1 => Some("link_3"),
            2 => Some("r_tool"),
            _ => None,
        };
        match Robot::from_urdf_str(&text, "fuzz.urdf", tip) {
            Ok(robot) => {
                ok += 1;
                exercise(&robot, &mut rng);
            }
            Err(e) => {
                err += 1;
                assert!(!e.to_string().is_empty());
            }
        }
    }
    assert!(ok > 100 && err > 500, "ok = {ok}, err = {err}");
}
