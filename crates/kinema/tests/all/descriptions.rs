//! Three descriptions of one robot give one FK; the URDF `tip` argument; the
//! `general` TOML convention; and sanity of every built-in robot file.

use std::collections::BTreeSet;
use std::f64::consts::{FRAC_PI_6, PI};
use std::path::{Path, PathBuf};

use kinema::analysis::{self, Axes};
use kinema::nalgebra::{Matrix3, Matrix6xX, Vector3};
use kinema::{builtin_names, Frame, GeometryKind, JointType, Pose, Robot};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(name)
}

fn rot_z(a: f64) -> Matrix3<f64> {
    Matrix3::new(a.cos(), -a.sin(), 0.0, a.sin(), a.cos(), 0.0, 0.0, 0.0, 1.0)
}

fn rot_y(a: f64) -> Matrix3<f64> {
    Matrix3::new(a.cos(), 0.0, a.sin(), 0.0, 1.0, 0.0, -a.sin(), 0.0, a.cos())
}

fn max_abs(m: &Matrix6xX<f64>) -> f64 {
    m.iter().fold(0.0, |a, v| a.max(v.abs()))
}

fn assert_same_pose(a: &Pose, b: &Pose, tol: f64, what: &str) {
    assert!((a.pos - b.pos).norm() < tol && (a.rot - b.rot).norm() < tol, "{what}: {a:?} vs {b:?}");
}

/// The three iiwa descriptions, all with the mount (base) and flange offset
/// (tool) written into `tests/data/iiwa14.urdf`.
fn three_iiwas() -> [Robot; 3] {
    let base = Pose::new(rot_z(FRAC_PI_6), Vector3::new(0.1, -0.2, 0.05));
    let tool = Pose::translation(0.0, 0.0, 0.045);
    let standard = Robot::builtin("lbr-iiwa-14-r820").unwrap().with_base(base).unwrap().with_tool(tool).unwrap();
    let modified = Robot::from_file(data("iiwa-modified.toml"), None).unwrap();
    let urdf = Robot::from_file(data("iiwa14.urdf"), None).unwrap();
    [standard, modified, urdf]
}

#[test]
fn three_iiwa_descriptions_have_one_fk_and_one_jacobian() {
    let [standard, modified, urdf] = three_iiwas();
    assert_eq!(standard.geometry_kind(), GeometryKind::Standard);
    assert_eq!(modified.geometry_kind(), GeometryKind::Modified);
    assert_eq!(urdf.geometry_kind(), GeometryKind::General);
    assert_eq!(urdf.name(), "lbr_iiwa_14_r820");
    // The URDF's fixed joints are folded away: 7 moving joints remain.
    assert_eq!(urdf.dof(), 7);
    assert_eq!(urdf.joint_types(), "RRRRRRR");
    assert_eq!(urdf.home(), &[0.0; 7]);
    for r in [&modified, &urdf] {
        assert_eq!(r.dof(), 7);
        for (a, b) in r.joints().iter().zip(standard.joints()) {
            assert_eq!(a.name, b.name);
            assert!((a.limits.min - b.limits.min).abs() < 1e-12);
            assert!((a.limits.max - b.limits.max).abs() < 1e-12);
            assert!((a.limits.vel.unwrap() - b.limits.vel.unwrap()).abs() < 1e-12);
        }
    }
    // KUKA's axis torques reach the model from the TOML `effort` keys and from <limit effort>.
    let effort = |r: &Robot| r.joints().iter().map(|j| j.limits.effort).collect::<Vec<_>>();
    let kuka = [320.0, 320.0, 176.0, 176.0, 110.0, 40.0, 40.0].map(Some);
    assert_eq!(effort(&standard), kuka);
    assert_eq!(effort(&urdf), kuka);
    // The fixed mount joint became the URDF model's base.
    assert_same_pose(urdf.base(), standard.base(), 1e-15, "base");
    assert_same_pose(modified.base(), standard.base(), 1e-15, "base");

    // Upright home: mount + (0, 0, 1.306 + 0.045) rotated by nothing but the yaw.
    let home = standard.fk(standard.home()).unwrap().world_from_tool;
    assert_same_pose(&home, &Pose::new(rot_z(FRAC_PI_6), Vector3::new(0.1, -0.2, 0.05 + 1.306 + 0.045)), 1e-12, "home");

    let mut rng = ChaCha8Rng::seed_from_u64(0x3d);
    for _ in 0..3000 {
        let q = standard.random_q(&mut rng);
        let fs = standard.fk(&q).unwrap().world_from_tool;
        let fm = modified.fk(&q).unwrap().world_from_tool;
        let fu = urdf.fk(&q).unwrap().world_from_tool;
        assert_same_pose(&fm, &fs, 1e-12, &format!("modified vs standard at {q:?}"));
        assert_same_pose(&fu, &fs, 1e-12, &format!("URDF vs standard at {q:?}"));
        for frame in [Frame::Base, Frame::Tool] {
            let js = standard.jacobian(&q, frame).unwrap();
            let jm = modified.jacobian(&q, frame).unwrap();
            let ju = urdf.jacobian(&q, frame).unwrap();
            assert!(max_abs(&(&jm - &js)) < 1e-12, "{frame:?} modified at {q:?}");
            assert!(max_abs(&(&ju - &js)) < 1e-12, "{frame:?} URDF at {q:?}");
        }
        // The same limit flags from all three.
        let lim = standard.fk(&q).unwrap().out_of_limits;
        assert_eq!(urdf.fk(&q).unwrap().out_of_limits, lim);
    }
}

/// The URDF's negative axes really are negative, and the link frames of the
/// URDF model are the URDF's child links: with the compensating half turns,
/// link_3 and link_7 are flipped about x relative to the modified-DH frames.
#[test]
fn urdf_negative_axes_and_link_frames() {
    let [_, modified, urdf] = three_iiwas();
    let neg: Vec<usize> = urdf
        .joints()
        .iter()
        .enumerate()
        .filter_map(|(i, j)| match j.geometry {
            kinema::LinkGeometry::General { axis, .. } => (axis.z < 0.0).then_some(i),
            _ => panic!("URDF joints are general"),
        })
        .collect();
    assert_eq!(neg, vec![2, 6]);
    let flip = Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, -1.0));
    let mut rng = ChaCha8Rng::seed_from_u64(0x7);
    for _ in 0..500 {
        let q = urdf.random_q(&mut rng);
        let fu = urdf.link_frames(&q).unwrap();
        let fm = modified.link_frames(&q).unwrap();
        for i in 1..=7 {
            let want = if neg.contains(&(i - 1)) { fm[i].rot * flip } else { fm[i].rot };
            assert!((fu[i].pos - fm[i].pos).norm() < 1e-12, "link {i}");
            assert!((fu[i].rot - want).norm() < 1e-12, "link {i}");
        }
        assert_same_pose(&fu[8], &fm[8], 1e-12, "tool frame");
    }
}

/// `convention = "general"` (xyz, rpy, axis per joint, in mm and degrees, with
/// two negative axes) against the built-in standard-DH UR5.
#[test]
fn general_toml_equals_dh_toml() {
    let dh = Robot::builtin("ur5").unwrap();
    let general = Robot::from_file(data("ur5-general.toml"), None).unwrap();
    assert_eq!(general.geometry_kind(), GeometryKind::General);
    assert_eq!(general.dof(), 6);
    for (a, b) in general.poses().iter().zip(dh.poses()) {
        assert_eq!(a.name, b.name);
        for (x, y) in a.q.iter().zip(&b.q) {
            assert!((x - y).abs() < 1e-15);
        }
    }
    let mut rng = ChaCha8Rng::seed_from_u64(0x65);
    for _ in 0..2000 {
        let q = dh.random_q(&mut rng);
        assert_same_pose(
            &general.fk(&q).unwrap().world_from_tool,
            &dh.fk(&q).unwrap().world_from_tool,
            1e-12,
            &format!("q = {q:?}"),
        );
        let jg = general.jacobian(&q, Frame::Base).unwrap();
        let jd = dh.jacobian(&q, Frame::Base).unwrap();
        assert!(max_abs(&(&jg - &jd)) < 1e-12, "q = {q:?}");
    }
}

#[test]
fn urdf_tip_selects_the_chain() {
    let text = std::fs::read_to_string(data("two-leaves.urdf")).unwrap();
    // Two leaves: the default must refuse and name both.
    let e = Robot::from_urdf_str(&text, "two-leaves.urdf", None).unwrap_err();
    let kinema::Error::Model(kinema::ModelError::Urdf { file, message }) = &e else { panic!("{e:?}") };
    assert_eq!(file, "two-leaves.urdf");
    assert!(message.contains("leaf_a") && message.contains("leaf_b"), "{message}");
    assert!(message.contains("2 leaf links"), "{message}");
    assert!(e.to_string().starts_with("two-leaves.urdf: "), "{e}");

    // leaf_a: revolute about z at 0.5 m, then a continuous joint about y, 0.3 m out.
    let a = Robot::from_urdf_str(&text, "two-leaves.urdf", Some("leaf_a")).unwrap();
    assert_eq!(a.dof(), 2);
    assert_eq!(a.joint_types(), "RR");
    assert_eq!(a.joints()[1].name, "ja");
    assert_eq!(a.joints()[1].limits.min, f64::NEG_INFINITY);
    assert_eq!(a.joints()[1].limits.max, f64::INFINITY);
    // The same through from_file.
    assert_eq!(Robot::from_file(data("two-leaves.urdf"), Some("leaf_a")).unwrap().dof(), 2);
    let mut rng = ChaCha8Rng::seed_from_u64(0x1eaf);
    for _ in 0..2000 {
        let q = a.random_q(&mut rng);
        // Continuous joints are sampled in [−π, π].
        assert!(q[1].abs() <= PI);
        let fk = a.fk(&q).unwrap();
        assert!(fk.within_limits());
        let p = rot_z(q[0]) * Vector3::new(0.3, 0.0, 0.0) + Vector3::new(0.0, 0.0, 0.5);
        assert_same_pose(&fk.world_from_tool, &Pose::new(rot_z(q[0]) * rot_y(q[1]), p), 1e-12, "leaf_a");
    }
    // A continuous joint is never out of limits.
    assert!(a.fk(&[0.0, 1e6]).unwrap().within_limits());

    // leaf_b: the prismatic branch; home is mid-range since 0 is outside [0.1, 0.4].
    let b = Robot::from_urdf_str(&text, "two-leaves.urdf", Some("leaf_b")).unwrap();
    assert_eq!(b.joint_types(), "RP");
    assert!((b.home()[1] - 0.25).abs() < 1e-15);
    for _ in 0..2000 {
        let q = b.random_q(&mut rng);
        assert!((0.1..=0.4).contains(&q[1]));
        let fk = b.fk(&q).unwrap();
        let p = rot_z(q[0]) * Vector3::new(q[1], 0.2, 0.0) + Vector3::new(0.0, 0.0, 0.5);
        assert_same_pose(&fk.world_from_tool, &Pose::new(rot_z(q[0]), p), 1e-12, "leaf_b");
    }

    // An inner link as tip: the one joint above it.
    assert_eq!(Robot::from_urdf_str(&text, "t", Some("link1")).unwrap().dof(), 1);
    // The root as tip: no moving joint.
    let e = Robot::from_urdf_str(&text, "t", Some("world")).unwrap_err();
    assert!(e.to_string().contains("no moving joint"), "{e}");
}

/// ROS-Industrial's shape (issue 34, item 11): a fixed `base` frame off
/// `base_link` is a second leaf, but the only one reached through moving
/// joints is tool0, so no tip is needed. Leaves that share their joints end
/// the chain at their common link, with a warning; leaves on different joints
/// still need `--tip`.
#[test]
fn urdf_ros_industrial_base_frame_needs_no_tip() {
    let text = std::fs::read_to_string(data("ros-industrial.urdf")).unwrap();
    let r = Robot::from_urdf_str(&text, "rosi.urdf", None).unwrap();
    assert_eq!(r, Robot::from_urdf_str(&text, "rosi.urdf", Some("tool0")).unwrap());
    assert_eq!(r.dof(), 3);
    assert!(r.metadata().source.ends_with("chain base_link → tool0"), "{}", r.metadata().source);
    assert!(r.metadata().warnings.is_empty(), "{:?}", r.metadata().warnings);
    // The `base` frame (rotated, raised) is not on the chain: the base stays the identity.
    assert_same_pose(r.base(), &Pose::IDENTITY, 1e-15, "base");
    // At q = 0 tool0 is 0.1 + 0.5 + 0.3 m out at 0.4 m, turned by Ry(π/2); axis 1 points down.
    let fk = r.fk(&[0.0; 3]).unwrap().world_from_tool;
    assert_same_pose(&fk, &Pose::new(rot_y(PI / 2.0), Vector3::new(0.9, 0.0, 0.4)), 1e-12, "tool0 at 0");
    let fk = r.fk(&[0.5, 0.0, 0.0]).unwrap().world_from_tool;
    assert_same_pose(
        &fk,
        &Pose::new(rot_z(-0.5) * rot_y(PI / 2.0), rot_z(-0.5) * Vector3::new(0.9, 0.0, 0.4)),
        1e-12,
        "q1",
    );
    assert!(Robot::from_file(data("ros-industrial.urdf"), None).is_ok());

    // A camera frame on link_3 beside the flange: same joints, so the chain ends at link_3.
    let camera = r#"<link name="camera"/>
  <joint name="camera_joint" type="fixed">
    <parent link="link_3"/>
    <child link="camera"/>
    <origin rpy="0 0 0" xyz="0.1 0 0.1"/>
  </joint>
</robot>"#;
    let two = text.replace("</robot>", camera);
    let r = Robot::from_urdf_str(&two, "rosi.urdf", None).unwrap();
    assert_eq!(r.dof(), 3);
    assert!(r.metadata().source.ends_with("chain base_link → link_3"), "{}", r.metadata().source);
    let [w] = r.metadata().warnings.as_slice() else { panic!("{:?}", r.metadata().warnings) };
    assert!(w.contains("tool0, camera") && w.contains("`link_3`") && w.contains("--tip"), "{w}");
    assert_same_pose(
        &r.fk(&[0.0; 3]).unwrap().world_from_tool,
        &Pose::new(Matrix3::identity(), Vector3::new(0.6, 0.0, 0.4)),
        1e-12,
        "link_3",
    );
    // Either leaf can still be chosen.
    assert_eq!(Robot::from_urdf_str(&two, "rosi.urdf", Some("camera")).unwrap().dof(), 3);

    // A second arm off link_1: the choice changes the joints, so a tip is needed.
    let branch = r#"<link name="arm_b"/>
  <joint name="joint_b" type="continuous">
    <parent link="link_1"/>
    <child link="arm_b"/>
    <axis xyz="1 0 0"/>
  </joint>
</robot>"#;
    let e = Robot::from_urdf_str(&text.replace("</robot>", branch), "rosi.urdf", None).unwrap_err();
    let kinema::Error::Model(kinema::ModelError::Urdf { message, .. }) = &e else { panic!("{e:?}") };
    assert!(message.contains("2 leaf links reached through different moving joints (tool0, arm_b)"), "{message}");
    assert!(message.contains("--tip"), "{message}");
}

/// PR2's and Romeo's shape (issue 34, item 12): a link off the chain with a
/// non-physical inertia is left out of the body that carries it, with a
/// warning; on the chain it is an error.
#[test]
fn urdf_bad_inertial_off_the_chain_is_a_warning() {
    let r = Robot::from_file(data("off-chain-inertia.urdf"), Some("r_tool")).unwrap();
    assert_eq!(r.joint_types(), "PR");
    let w = &r.metadata().warnings;
    assert_eq!(w.len(), 2, "{w:?}");
    for link in ["`l_arm`", "`sensor_mount`"] {
        let w = w.iter().find(|w| w.contains(link)).unwrap_or_else(|| panic!("{link}: {w:?}"));
        assert!(w.contains("off the chain") && w.contains("triangle inequality") && w.contains("left out"), "{w}");
    }
    // The torso's body is the torso alone (l_arm and the mount left out); the arm is its own link.
    let inertials: Vec<_> = r.inertials().iter().map(|i| i.unwrap()).collect();
    assert_eq!(inertials[0].mass, 10.0);
    assert!((inertials[0].com - Vector3::new(0.0, 0.0, 0.2)).norm() < 1e-15);
    assert_eq!(inertials[1].mass, 2.0);
    // The dynamics run on what is left.
    assert!(kinema::dynamics::gravity_torques(&r, &[0.1, 0.2], &Vector3::new(0.0, 0.0, -9.81)).is_ok());

    // l_arm is on the chain to l_tool: refused, naming it.
    let e = Robot::from_file(data("off-chain-inertia.urdf"), Some("l_tool")).unwrap_err();
    let kinema::Error::Model(kinema::ModelError::Urdf { message, .. }) = &e else { panic!("{e:?}") };
    assert!(message.contains("`l_arm` (on the chain)") && message.contains("triangle inequality"), "{message}");
}

/// Every file in `robots/` is a built-in robot, and every built-in robot is
/// sane: its name is its file stem, `home` exists and is within limits, every
/// named pose has one value per joint.
#[test]
fn builtin_robot_files_are_consistent() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../robots");
    let stems: BTreeSet<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    let names: BTreeSet<String> = builtin_names().map(String::from).collect();
    assert_eq!(stems, names);
    assert!(names.len() >= 7);
    let sorted: Vec<&str> = builtin_names().collect();
    assert!(sorted.windows(2).all(|w| w[0] < w[1]), "builtin_names is sorted");

    for name in builtin_names() {
        let robot = Robot::builtin(name).unwrap();
        assert_eq!(robot.name(), name, "`name` must equal the file stem");
        // The embedded text is the file on disk.
        let on_disk = std::fs::read_to_string(dir.join(format!("{name}.toml"))).unwrap();
        assert_eq!(kinema::builtin_source(name).unwrap(), on_disk);
        assert_eq!(Robot::from_file(dir.join(format!("{name}.toml")), None).unwrap(), robot);
        assert!(!robot.metadata().source.is_empty(), "{name}: no source");
        assert!(robot.poses().iter().any(|p| p.name == "home"));
        let fk = robot.fk(robot.home()).unwrap();
        assert!(
            fk.within_limits(),
            "{name}: home is outside the limits of joints {:?}",
            fk.out_of_limits.indices().collect::<Vec<_>>()
        );
        for p in robot.poses() {
            assert_eq!(p.q.len(), robot.dof(), "{name}: pose {}", p.name);
            assert!(p.q.iter().all(|v| v.is_finite()));
            assert_eq!(robot.pose(&p.name).unwrap(), p.q.as_slice());
        }
        for j in robot.joints() {
            assert!(j.limits.min < j.limits.max, "{name}: joint {}", j.name);
        }
    }
}

/// `scara5`: `home` is not singular (the tool can translate in every
/// direction), `qz` (stretched arm) is.
#[test]
fn scara5_home_is_regular_and_qz_singular() {
    let robot = Robot::builtin("scara5").unwrap();
    let at = |pose: &str| robot.jacobian(robot.pose(pose).unwrap(), Frame::Base).unwrap();
    let j_home = at("home");
    let j_qz = at("qz");
    assert_eq!(analysis::rank(&j_home, Axes::Translation, None).unwrap().0, 3);
    assert!(analysis::rank(&j_qz, Axes::Translation, None).unwrap().0 < 3);
    // Independently: det(J_v·J_vᵀ).
    let det = |j: &Matrix6xX<f64>| {
        let jv = j.fixed_rows::<3>(0);
        (jv * jv.transpose()).determinant()
    };
    assert!(det(&j_home) > 1e-3, "{}", det(&j_home));
    assert!(det(&j_qz).abs() < 1e-15, "{}", det(&j_qz));
    // The rail and the vertical axis are prismatic and always present.
    assert_eq!(robot.joints()[0].kind, JointType::Prismatic);
    assert_eq!(robot.joints()[3].kind, JointType::Prismatic);
}

/// Issue 34: every named pose of every built-in robot is within its joint
/// limits (the Panda's `qz` was all zeros, outside Franka's joint 4 range
/// [−3.0718, −0.0698] rad).
#[test]
fn every_named_pose_of_every_builtin_is_within_its_limits() {
    for name in builtin_names() {
        let robot = Robot::builtin(name).unwrap();
        for p in robot.poses() {
            let out: Vec<usize> = robot.limit_flags(&p.q).indices().collect();
            assert!(out.is_empty(), "{name}: pose `{}` {:?} is outside the limits of joints {out:?}", p.name, p.q);
        }
    }
}
