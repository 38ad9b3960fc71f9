//! Bad input gives an error that says what was wrong, and never a panic.

use std::path::{Path, PathBuf};

use kinema::nalgebra::Matrix6xX;
use kinema::{builtin_names, Data, Error, Frame, Pose, Robot, RpyConvention};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::bad_urdf::{joint_xml, GOOD_URDF_HEAD, LIMIT};
use kinema::{FileError, InputError, ModelError};

pub(crate) fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(name)
}

/// A valid two-joint (RP) description; the tests below break it one way at a time.
pub(crate) const GOOD: &str = r#"name = "rp"
source = "tests/bad_input.rs"
convention = "standard"
[units]
length = "mm"
angle = "deg"
[[joint]]
name = "turn"
d = 100
a = 200
alpha = 0
min = -90
max = 90
[[joint]]
name = "slide"
type = "prismatic"
theta = 0
a = 0
alpha = 0
min = 0
max = 300
[poses]
home = [0, 100]
qz = [0, 0]
"#;

/// 1-based line of the first occurrence of `needle` in `text`.
fn line_of(text: &str, needle: &str) -> usize {
    let at = text.find(needle).unwrap_or_else(|| panic!("`{needle}` not in text"));
    text[..at].matches('\n').count() + 1
}

/// 1-based line of the `n`-th (0-based) occurrence of `needle`.
fn nth_line_of(text: &str, needle: &str, n: usize) -> usize {
    let (at, _) = text.match_indices(needle).nth(n).unwrap();
    text[..at].matches('\n').count() + 1
}

/// Replaces exactly one occurrence (so a typo in a test cannot silently do nothing).
fn replace_once(text: &str, from: &str, to: &str) -> String {
    assert_eq!(text.matches(from).count(), 1, "`{from}` must occur once");
    text.replacen(from, to, 1)
}

/// The `Description` error of a TOML text, destructured.
fn desc_err(text: &str) -> (Error, usize, usize, String, String) {
    let e = Robot::from_toml_str(text, "bad.toml").expect_err("must be rejected");
    match &e {
        Error::Model(ModelError::Description { file, line, column, field, message }) => {
            assert_eq!(file, "bad.toml");
            assert!(*line >= 1 && *column >= 1);
            let shown = e.to_string();
            assert!(shown.starts_with(&format!("bad.toml:{line}:{column}: `{field}`: ")), "{shown}");
            assert!(shown.contains(message.as_str()));
            let (l, c, f, m) = (*line, *column, field.clone(), message.clone());
            (e, l, c, f, m)
        }
        other => panic!("expected Error::Model(ModelError::Description), got {other:?}"),
    }
}

#[test]
fn good_fixture_is_good() {
    let r = Robot::from_toml_str(GOOD, "good.toml").unwrap();
    assert_eq!(r.joint_types(), "RP");
    let fk = r.fk(r.home()).unwrap();
    assert!((fk.world_from_tool.pos.x - 0.2).abs() < 1e-12 && (fk.world_from_tool.pos.z - 0.2).abs() < 1e-12);
}

#[test]
fn toml_syntax_error_gives_line_and_column() {
    let bad = replace_once(GOOD, "a = 200", "a = 200 200");
    let (_, line, column, field, _) = desc_err(&bad);
    assert_eq!(line, line_of(GOOD, "a = 200"));
    assert_eq!(field, "(syntax)");
    assert!(column > 1, "the column points into the line, at the second number");

    let bad = replace_once(GOOD, "length = \"mm\"", "length = \"mm");
    let (_, line, _, field, message) = desc_err(&bad);
    assert_eq!(line, line_of(GOOD, "length"));
    assert_eq!(field, "(syntax)");
    assert!(!message.is_empty());

    let bad = replace_once(GOOD, "[poses]", "[poses");
    let (_, line, ..) = desc_err(&bad);
    assert_eq!(line, line_of(GOOD, "[poses]"));

    // From a file: the path is in the message.
    let path = data("malformed.toml");
    let e = Robot::from_file(&path, None).unwrap_err();
    let Error::Model(ModelError::Description { file, line, .. }) = &e else { panic!("{e:?}") };
    assert_eq!(file, &path.display().to_string());
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(*line, line_of(&text, "alpha = = 90"));
    assert!(e.to_string().contains("malformed.toml:"), "{e}");
}

#[test]
fn toml_unknown_field() {
    let bad = replace_once(GOOD, "alpha = 0\nmin = -90", "alpah = 0\nmin = -90");
    let (_, line, _, field, message) = desc_err(&bad);
    assert_eq!(line, line_of(&bad, "alpah"));
    assert!(field.starts_with("joint[0]"), "{field}");
    assert!(message.contains("alpah"), "{message}");
    // It says what is allowed.
    assert!(message.contains("alpha"), "{message}");

    let bad = replace_once(GOOD, "source =", "colour = \"red\"\nsource =");
    let (_, line, _, field, message) = desc_err(&bad);
    assert_eq!(line, line_of(&bad, "colour"));
    assert_eq!(field, "colour");
    assert!(message.contains("colour"), "{message}");
}

#[test]
fn toml_wrong_type() {
    let bad = replace_once(GOOD, "a = 200", "a = \"long\"");
    let (_, line, _, field, message) = desc_err(&bad);
    assert_eq!((line, field.as_str()), (line_of(&bad, "a = \"long\""), "joint[0].a"));
    assert!(message.contains("string") || message.contains("float"), "{message}");

    let bad = replace_once(GOOD, "home = [0, 100]", "home = [0, \"x\"]");
    let (_, line, _, field, _) = desc_err(&bad);
    assert_eq!(line, line_of(&bad, "home ="));
    assert!(field.starts_with("poses.home"), "{field}");

    let bad = replace_once(GOOD, "convention = \"standard\"", "convention = \"dh\"");
    let (_, line, _, field, message) = desc_err(&bad);
    assert_eq!((line, field.as_str()), (3, "convention"));
    assert!(message.contains("dh"), "{message}");

    let bad = replace_once(GOOD, "type = \"prismatic\"", "type = \"spherical\"");
    let (_, _, _, field, message) = desc_err(&bad);
    assert_eq!(field, "joint[1].type");
    assert!(message.contains("spherical"), "{message}");
}

#[test]
fn toml_missing_home() {
    let bad = replace_once(GOOD, "home = [0, 100]\n", "");
    let (_, _, _, field, message) = desc_err(&bad);
    assert_eq!(field, "poses.home");
    assert!(message.contains("home"), "{message}");

    let bad = replace_once(GOOD, "name = \"rp\"\n", "");
    let (_, _, _, field, message) = desc_err(&bad);
    assert_eq!(field, "(top level)");
    assert!(message.contains("name"), "{message}");
}

#[test]
fn toml_pose_with_wrong_length() {
    let bad = replace_once(GOOD, "qz = [0, 0]", "qz = [0, 0, 0]");
    let (_, line, _, field, message) = desc_err(&bad);
    assert_eq!(line, line_of(&bad, "qz ="));
    assert_eq!(field, "poses.qz");
    assert!(message.contains('3') && message.contains('2'), "{message}");

    let bad = replace_once(GOOD, "home = [0, 100]", "home = []");
    let (_, _, _, field, message) = desc_err(&bad);
    assert_eq!(field, "poses.home");
    assert!(message.contains("0 values"), "{message}");
}

#[test]
fn toml_min_greater_than_max() {
    let bad = replace_once(GOOD, "min = 0\nmax = 300", "min = 300\nmax = 0");
    let (_, line, _, field, message) = desc_err(&bad);
    // Points at the second joint's table.
    assert_eq!(line, nth_line_of(&bad, "[[joint]]", 1));
    assert_eq!(field, "joint[1].min");
    assert!(message.contains("slide"), "{message}");
    assert!(message.contains("300") && message.contains("not an interval"), "{message}");
}

#[test]
fn toml_prismatic_joint_with_d() {
    let bad = replace_once(GOOD, "theta = 0", "theta = 0\nd = 50");
    let (_, line, _, field, message) = desc_err(&bad);
    assert_eq!(line, nth_line_of(&bad, "[[joint]]", 1));
    assert_eq!(field, "joint[1].d");
    assert!(message.contains("prismatic") && message.contains("slide"), "{message}");

    // And the mirror image: a revolute joint with θ.
    let bad = replace_once(GOOD, "d = 100", "d = 100\ntheta = 5");
    let (_, line, _, field, _) = desc_err(&bad);
    assert_eq!(line, nth_line_of(&bad, "[[joint]]", 0));
    assert_eq!(field, "joint[0].theta");
}

#[test]
fn toml_other_semantic_errors() {
    // DH fields in a general description, and the other way round.
    let bad = replace_once(GOOD, "convention = \"standard\"", "convention = \"general\"");
    let (_, _, _, field, message) = desc_err(&bad);
    assert!(field.starts_with("joint[0]."), "{field}");
    assert!(message.contains("general"), "{message}");
    let bad = replace_once(GOOD, "d = 100", "d = 100\naxis = [0, 0, 1]");
    let (_, _, _, field, _) = desc_err(&bad);
    assert_eq!(field, "joint[0].axis");
    // A negative velocity limit.
    let bad = replace_once(GOOD, "max = 90", "max = 90\nvel = -1");
    let (_, _, _, field, message) = desc_err(&bad);
    assert_eq!(field, "joint[0].vel");
    assert!(message.contains("positive"), "{message}");
    // Non-finite numbers in the file (TOML has nan and inf literals).
    let bad = replace_once(GOOD, "a = 200", "a = nan");
    assert!(Robot::from_toml_str(&bad, "bad.toml").is_err());
    let bad = replace_once(GOOD, "qz = [0, 0]", "qz = [0, inf]");
    let (_, _, _, field, message) = desc_err(&bad);
    assert_eq!(field, "poses.qz");
    assert!(message.contains("inf"), "{message}");
    // No joints at all: no `joint` key, or an empty one.
    let head = GOOD.split("[[joint]]").next().unwrap();
    let (_, _, _, field, message) = desc_err(&format!("{head}[poses]\nhome = []\n"));
    assert_eq!(field, "(top level)");
    assert!(message.contains("joint"), "{message}");
    let (_, _, _, field, message) = desc_err(&format!("joint = []\n{head}[poses]\nhome = []\n"));
    assert_eq!(field, "joint");
    assert!(message.contains("at least one joint"), "{message}");
}

#[test]
fn wrong_joint_count() {
    let robot = Robot::builtin("puma560").unwrap();
    for len in [0, 1, 5, 7, 12] {
        let q = vec![0.1; len];
        let check = |e: Error| {
            assert_eq!(e, Error::Input(InputError::JointCount { robot: "puma560".into(), expected: 6, got: len }));
            assert!(e.to_string().contains(&format!("{len} joint values")), "{e}");
        };
        check(robot.fk(&q).unwrap_err());
        check(robot.jacobian(&q, Frame::Base).unwrap_err());
        check(robot.analytic_jacobian(&q, RpyConvention::Zyx).unwrap_err());
        check(robot.link_frames(&q).unwrap_err());
        check(Data::new(&robot).jacobian(&robot, &q, Frame::Tool).unwrap_err());
        check(Data::new(&robot).link_frames(&robot, &q).unwrap_err());
    }
    // fk_batch: not a whole number of configurations.
    let e = robot.fk_batch(&[0.0; 13]).unwrap_err();
    assert!(
        matches!(&e, Error::Input(InputError::WrongLength { what, got: 13, expected: 12, .. }) if what == "qs"),
        "{e:?}"
    );
    assert!(e.to_string().contains("a whole number of 6-joint configurations"), "{e}");
    // Wrongly sized output buffers.
    let mut j = Matrix6xX::zeros(5);
    let e = kinema::kin::jacobian_into(&robot, robot.home(), Frame::Base, &mut j).unwrap_err();
    assert!(
        matches!(&e, Error::Input(InputError::WrongLength { what, got: 5, expected: 6, .. }) if what == "out"),
        "{e:?}"
    );
    for len in [0, 15, 17] {
        let mut t = vec![7.5; len];
        let e = kinema::kin::fk_matrix_into(&robot, robot.home(), &mut t).unwrap_err();
        assert!(
            matches!(&e, Error::Input(InputError::WrongLength { what, got, expected: 16, .. }) if what == "out" && *got == len),
            "{e:?}"
        );
        assert_eq!(e.to_string(), format!("`out` has {len} values; 16 expected (a 4 × 4 matrix)"));
        assert!(t.iter().all(|&v| v == 7.5));
    }
    for len in [0, 35, 37, 42] {
        let mut rows = vec![7.5; len];
        let e = kinema::kin::jacobian_rows_into(&robot, robot.home(), Frame::Base, &mut rows).unwrap_err();
        assert!(
            matches!(&e, Error::Input(InputError::WrongLength { what, got, expected: 36, .. }) if what == "out" && *got == len),
            "{e:?}"
        );
        assert!(e.to_string().ends_with("(a 6 × 6 Jacobian of `puma560`)"), "{e}");
        assert!(rows.iter().all(|&v| v == 7.5));
    }
    let mut frames = vec![Pose::IDENTITY; 6];
    let e = kinema::kin::link_frames_into(&robot, robot.home(), &mut frames).unwrap_err();
    assert!(
        matches!(&e, Error::Input(InputError::WrongLength { what, got: 6, expected: 8, .. }) if what == "out"),
        "{e:?}"
    );
}

#[test]
fn non_finite_joint_values() {
    for name in builtin_names() {
        let robot = Robot::builtin(name).unwrap();
        let n = robot.dof();
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for joint in 0..n {
                let mut q = robot.home().to_vec();
                q[joint] = bad;
                let check = |e: Error| {
                    let Error::Input(InputError::BadJointValue { robot: r, joint: jn, name: jname, value }) = &e else {
                        panic!("{e:?}")
                    };
                    assert_eq!(r, name);
                    assert_eq!(*jn, joint + 1);
                    assert_eq!(jname, &robot.joints()[joint].name);
                    assert!(value.is_nan() == bad.is_nan() && (bad.is_nan() || *value == bad));
                    let s = e.to_string();
                    assert!(s.contains(&format!("joint {}", joint + 1)) && s.contains("finite"), "{s}");
                    assert!(s.contains(if bad.is_nan() { "NaN" } else { "inf" }), "{s}");
                };
                check(robot.fk(&q).unwrap_err());
                // A caller's buffer is left as it was.
                let mut t = [7.5; 16];
                check(kinema::kin::fk_matrix_into(&robot, &q, &mut t).unwrap_err());
                assert!(t.iter().all(|&v| v == 7.5), "{name}: fk_matrix_into wrote into `out` on bad input");
                let mut buf = kinema::nalgebra::Matrix6xX::from_element(n, 7.5);
                check(kinema::kin::jacobian_into(&robot, &q, Frame::Base, &mut buf).unwrap_err());
                assert!(buf.iter().all(|&v| v == 7.5), "{name}: jacobian_into wrote into `out` on bad input");
                let mut rows = vec![7.5; 6 * n];
                check(kinema::kin::jacobian_rows_into(&robot, &q, Frame::Tool, &mut rows).unwrap_err());
                assert!(rows.iter().all(|&v| v == 7.5), "{name}: jacobian_rows_into wrote into `out` on bad input");
                check(robot.jacobian(&q, Frame::Base).unwrap_err());
                check(robot.jacobian(&q, Frame::Tool).unwrap_err());
                check(robot.analytic_jacobian(&q, RpyConvention::Xyz).unwrap_err());
                check(robot.link_frames(&q).unwrap_err());
                let mut ws = Data::new(&robot);
                check(ws.jacobian(&robot, &q, Frame::Base).unwrap_err());
                check(ws.link_frames(&robot, &q).unwrap_err());
            }
        }
    }
}

#[test]
fn fk_batch_with_one_bad_row() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0xbad);
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let rows = 5000;
        let mut qs: Vec<f64> = (0..rows).flat_map(|_| robot.random_q(&mut rng)).collect();
        let row = rng.random_range(0..rows);
        let joint = rng.random_range(0..7);
        qs[row * 7 + joint] = bad;
        let e = robot.fk_batch(&qs).unwrap_err();
        let Error::InBatch { index, source } = &e else { panic!("{e:?}") };
        assert_eq!(*index, row, "{e}");
        let Error::Input(InputError::BadJointValue { joint: jn, .. }) = source.as_ref() else { panic!("{e:?}") };
        assert_eq!(*jn, joint + 1, "{e}");
        assert!(e.to_string().contains(&format!("configuration {row} ")), "{e}");
        // Fixing the row makes the batch work.
        qs[row * 7 + joint] = 0.0;
        assert_eq!(robot.fk_batch(&qs).unwrap().len(), rows);
    }
}

#[test]
fn unknown_robot_and_pose_names() {
    let e = Robot::builtin("r2d2").unwrap_err();
    let Error::Model(ModelError::UnknownRobot { name, known }) = &e else { panic!("{e:?}") };
    assert_eq!(name, "r2d2");
    let s = e.to_string();
    for b in builtin_names() {
        assert!(known.contains(b) && s.contains(b), "{s}");
    }
    assert!(s.contains("`r2d2`"), "{s}");
    let e = Robot::load("r2d2", None).unwrap_err();
    assert!(matches!(e, Error::Model(ModelError::UnknownRobot { .. })), "{e:?}");

    let robot = Robot::builtin("puma560").unwrap();
    let e = robot.pose("qx").unwrap_err();
    let Error::Input(InputError::UnknownPose { robot: r, pose, known }) = &e else { panic!("{e:?}") };
    assert_eq!((r.as_str(), pose.as_str()), ("puma560", "qx"));
    for p in ["home", "qn", "qr", "qs", "qz"] {
        assert!(known.contains(p), "{known}");
    }
    assert!(e.to_string().contains("`qx`"), "{e}");
}

#[test]
fn from_file_missing_and_wrong_extension() {
    let missing = data("no-such-robot.toml");
    let e = Robot::from_file(&missing, None).unwrap_err();
    let Error::File(FileError::Io { path, source }) = &e else { panic!("{e:?}") };
    assert_eq!(path, &missing.display().to_string());
    assert_eq!(source.0.kind(), std::io::ErrorKind::NotFound);
    // The operating system's error stays reachable as the source.
    let cause = std::error::Error::source(&e).and_then(|s| s.source()).expect("an io::Error source");
    assert!(cause.downcast_ref::<std::io::Error>().is_some(), "{cause:?}");
    assert!(e.to_string().contains("no-such-robot.toml"), "{e}");
    let e = Robot::from_file(data("no-such-robot.urdf"), None).unwrap_err();
    assert!(matches!(e, Error::File(FileError::Io { .. })), "{e:?}");
    // `load` of a path-looking name that does not exist is an I/O error too.
    let e = Robot::load(&missing.display().to_string(), None).unwrap_err();
    assert!(matches!(e, Error::File(FileError::Io { .. })), "{e:?}");

    for path in [data("robot.txt"), data("iiwa14"), PathBuf::from("Cargo.lock")] {
        let e = Robot::from_file(&path, None).unwrap_err();
        let Error::Input(InputError::DoesNotFit { what, reason }) = &e else { panic!("{e:?}") };
        assert_eq!(what, "robot file");
        assert!(reason.contains(".toml") && reason.contains(".urdf"), "{reason}");
    }
    // A directory with a robot extension.
    let dir = std::env::temp_dir().join(format!("kinema-test-dir-{}.toml", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let e = Robot::from_file(&dir, None).unwrap_err();
    std::fs::remove_dir(&dir).unwrap();
    assert!(matches!(e, Error::File(FileError::Io { .. })), "{e:?}");
}

// ---------------------------------------------------------------------------
// Typed argument errors: each kind is returned with its fields, and its
// message names what was wrong and what was expected.

#[test]
fn argument_errors_are_typed() {
    use kinema::nalgebra::Vector3;
    use kinema::traj::{distances_to_path, sample_count, Expr, MotionLimits, Profile, Ptp, PtpOptions, TimeLaw};

    // OutOfRange: a negative time step.
    let e = sample_count(1.0, -0.1).unwrap_err();
    assert!(
        matches!(&e, Error::Input(InputError::OutOfRange { what, value, .. }) if what == "dt" && *value == -0.1),
        "{e:?}"
    );
    assert_eq!(e.to_string(), "invalid `dt`: -0.1; expected a positive time step [s]");
    let e = sample_count(1e300, 1e-300).unwrap_err();
    assert!(matches!(&e, Error::Input(InputError::OutOfRange { what, .. }) if what == "dt"), "{e:?}");
    assert!(e.to_string().contains("expected a larger time step: over 1e300 s this one would give"), "{e}");

    // OutOfRange under the joint it concerns: a target beyond a joint's limits.
    let iiwa = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let mut to = iiwa.home().to_vec();
    to[1] = 3.0;
    let e = Ptp::new(&iiwa, iiwa.home(), &to, &PtpOptions::default()).unwrap_err();
    assert!(matches!(&e, Error::ForJoint { joint: 2, .. }), "{e:?}");
    assert!(matches!(e.root(), Error::Input(InputError::OutOfRange { what, value: 3.0, .. }) if what == "to"), "{e:?}");
    assert!(e.to_string().contains("invalid `to`: 3; expected a value within the joint's limits ["), "{e}");

    // TooFew: a path of one point.
    let o = Vector3::zeros();
    let e = distances_to_path(&[o], &[o]).unwrap_err();
    assert!(matches!(&e, Error::Input(InputError::TooFew { what, got: 1, min: 2, .. }) if what == "path"), "{e:?}");
    assert_eq!(e.to_string(), "`path` has 1 point(s); at least 2 needed");

    // MissingLimit: every built-in has acceleration limits, so the iiwa's file
    // without them; a trapezoid PTP needs them.
    to[1] = 0.5;
    let text = kinema::builtin_source("lbr-iiwa-14-r820").unwrap();
    let no_acc: String = text.lines().filter(|l| !l.starts_with("acc =")).map(|l| format!("{l}\n")).collect();
    let slow = Robot::from_toml_str(&no_acc, "iiwa-no-acc.toml").unwrap();
    assert!(slow.joints().iter().all(|j| j.limits.acc.is_none() && j.limits.vel.is_some()));
    let e = Ptp::new(&slow, slow.home(), &to, &PtpOptions::default()).unwrap_err();
    assert!(matches!(&e, Error::ForJoint { joint: 2, .. }), "{e:?}");
    assert!(
        matches!(e.root(), Error::Input(InputError::MissingLimit { limit, option, .. }) if limit == "acceleration" && option == "amax"),
        "{e:?}"
    );
    assert!(
        e.to_string().ends_with("no acceleration limit for its motion in the robot model; give one (`amax`)"),
        "{e}"
    );
    let e = TimeLaw::from_limits(Profile::SCurve, 1.0, &MotionLimits::new(1.0, 1.0)).unwrap_err();
    assert!(matches!(&e, Error::Input(InputError::MissingLimit { option, .. }) if option == "jmax"), "{e:?}");
    assert_eq!(e.to_string(), "no jerk limit for the scurve profile; give one (`jmax`)");

    // UnknownName: a profile that does not exist, with the known ones.
    let e = "zigzag".parse::<Profile>().unwrap_err();
    assert!(
        matches!(&e, Error::Input(InputError::UnknownName { what, name, known })
        if what == "profile" && name == "zigzag" && known.contains("scurve")),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        "invalid `profile`: unknown profile `zigzag`; expected one of: trapezoid, scurve, cubic, quintic, linear"
    );

    // DoesNotFit: a tip link for a built-in robot.
    let e = Robot::load("panda", Some("tool0")).unwrap_err();
    assert!(matches!(&e, Error::Input(InputError::DoesNotFit { what, .. }) if what == "tip"), "{e:?}");
    assert_eq!(e.to_string(), "invalid `tip`: a tip link only applies to URDF files");

    // Infeasible: limits so fast that the motion would be shorter than a motion may last.
    let e = TimeLaw::from_limits(Profile::Linear, 1e-12, &MotionLimits::new(1.0, 1.0)).unwrap_err();
    assert!(matches!(&e, Error::Infeasible { what, .. } if what == "duration"), "{e:?}");
    assert!(e.to_string().starts_with("infeasible `duration`: the limits give a duration of 1e-12 s"), "{e}");

    // Syntax: an unclosed call, with the column and a caret under it.
    let e = Expr::parse("sin(t").unwrap_err();
    assert!(matches!(&e, Error::Input(InputError::Syntax { what, column: 6, .. }) if what == "expression"), "{e:?}");
    assert_eq!(e.to_string(), "invalid `expression`: `sin(t`, column 6: expected `,` or `)`\n  sin(t\n       ^");
}

/// Issue 35 item 6: lengths and joint values beyond 1e9 are refused, naming
/// them, so that no product kinema forms overflows.
#[test]
fn absurd_lengths_and_joint_values_are_refused_by_name() {
    let far = joint_xml("j2", "revolute", "l1", "l2", LIMIT).replace("0 0 0.1", "0 0 1e308");
    let text = format!("{GOOD_URDF_HEAD}{}{far}</robot>", joint_xml("j1", "revolute", "base", "l1", LIMIT));
    let e = Robot::from_urdf_str(&text, "far.urdf", None).unwrap_err().to_string();
    assert!(e.contains("j2") && e.contains("1e308") && e.contains("below 1e9 m"), "{e}");
    let puma = Robot::builtin("puma560").unwrap();
    let e = puma.with_base(Pose::translation(0.0, 1e308, 0.0)).unwrap_err().to_string();
    assert!(e.contains("base") && e.contains("below 1e9 m"), "{e}");
    assert!(puma.with_base(Pose::translation(0.0, 1e8, 0.0)).is_ok());
    let e = puma.fk(&[0.0, 0.0, 0.0, 0.0, 0.0, 2e9]).unwrap_err().to_string();
    assert!(e.contains("joint 6") && e.contains("within ±1e9"), "{e}");
    let mut b = Data::new(&puma);
    assert!(b.jacobian(&puma, &[1e9, 0.0, 0.0, 0.0, 0.0, 0.0], Frame::Base).is_err());
}

/// Issue 35 item 6: over seeded inputs of every magnitude up to 1e300, each
/// dynamics function either answers with finite numbers or fails naming
/// the result that overflowed and the inputs; FK, Jacobians and
/// manipulability stay finite for every accepted input.
#[test]
fn every_numeric_answer_is_finite_or_an_error() {
    use kinema::analysis::{yoshikawa, Axes};
    use kinema::dynamics;
    use kinema::nalgebra::Vector3;
    let mut rng = ChaCha8Rng::seed_from_u64(356);
    let (mut answered, mut refused) = (0, 0);
    for name in ["puma560", "lbr-iiwa-14-r820", "scara5", "panda"] {
        let robot = Robot::builtin(name).unwrap();
        let n = robot.dof();
        for _ in 0..1500 {
            let huge = |rng: &mut ChaCha8Rng| {
                let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
                sign * 10f64.powf(rng.random_range(-3.0..300.0))
            };
            let q: Vec<f64> = (0..n).map(|_| huge(&mut rng).clamp(-9.9e8, 9.9e8)).collect();
            let qd: Vec<f64> = (0..n).map(|_| huge(&mut rng)).collect();
            let qdd: Vec<f64> = (0..n).map(|_| huge(&mut rng)).collect();
            let g = Vector3::new(huge(&mut rng), huge(&mut rng), huge(&mut rng));
            let fk = robot.fk(&q).unwrap();
            let p = fk.world_from_tool.pos;
            assert!(p.iter().all(|v| v.is_finite()), "{name} fk {q:?}");
            let j = robot.jacobian(&q, Frame::Base).unwrap();
            assert!(j.iter().all(|v| v.is_finite()) && yoshikawa(&j, Axes::All).unwrap().is_finite());
            if robot.inertials().iter().any(Option::is_none) {
                continue;
            }
            let results = [
                dynamics::rnea(&robot, &q, &qd, &qdd, &g),
                dynamics::forward_dynamics(&robot, &q, &qd, &qdd, &g),
                dynamics::coriolis_matrix(&robot, &q, &qd).map(|m| m.as_slice().to_vec()),
                dynamics::mass_matrix(&robot, &q).map(|m| m.as_slice().to_vec()),
            ];
            for r in results {
                match r {
                    Ok(v) => {
                        assert!(v.iter().all(|x| x.is_finite()), "{name}: {v:?}");
                        answered += 1;
                    }
                    Err(e @ Error::Overflow { .. }) => {
                        let text = e.to_string();
                        assert!(text.contains("too large") && text.contains("joint"), "{text}");
                        refused += 1;
                    }
                    Err(e) => panic!("{name}: unexpected {e}"),
                }
            }
        }
    }
    assert!(answered > 1000 && refused > 1000, "answered {answered}, refused {refused}");
}
