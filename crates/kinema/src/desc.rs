//! The TOML robot description format (documented in the project README).
//!
//! ```toml
//! name = "planar2"
//! manufacturer = "none"
//! source = "a textbook example"
//! convention = "standard"            # standard | modified | general
//! [units]
//! length = "mm"                      # m | mm
//! angle = "deg"                      # rad | deg
//! [[joint]]
//! name = "j1"
//! a = 1000
//! alpha = 0
//! min = -170
//! max = 170
//! [[joint]]
//! name = "j2"
//! a = 1000
//! alpha = 0
//! min = -170
//! max = 170
//! [poses]
//! home = [0, 90]
//! ```
//!
//! Everything is converted to SI (m, rad) on load. Errors name the file, the
//! line and column, and the field; the values are checked by
//! [`Description::problems`], the validation that robots built in code share.
//! `[[shape]]` tables (link geometry) belong to kinema-geometry, which reads
//! them from the same text; the core skips them.

use std::collections::BTreeMap;

use nalgebra::Vector3;
use serde::Deserialize;
use toml::Spanned;

use crate::description::{self, Description, Problem};
use crate::error::{Error, ModelError, Result};
use crate::math::{Pose, RpyConvention};
use crate::model::{DhConvention, GeometryKind, Inertial, Joint, JointType, Limits, LinkGeometry, Metadata, NamedPose};
use crate::robot::Robot;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RobotFile {
    name: String,
    #[serde(default)]
    manufacturer: String,
    source: String,
    #[serde(default)]
    notes: String,
    convention: GeometryKind,
    units: Units,
    base: Option<Spanned<FrameSpec>>,
    tool: Option<Spanned<FrameSpec>>,
    joint: Vec<Spanned<JointSpec>>,
    poses: BTreeMap<String, Spanned<Vec<f64>>>,
    /// `[[shape]]`: link geometry, read from the same text by kinema-geometry
    /// (the kinematic model carries no shapes); accepted here unread.
    #[serde(default, rename = "shape")]
    _shapes: Option<toml::Value>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Units {
    length: LengthUnit,
    angle: AngleUnit,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "lowercase")]
enum LengthUnit {
    M,
    Mm,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "lowercase")]
enum AngleUnit {
    Rad,
    Deg,
}

/// A fixed transform: translation `xyz` (length unit), then rotation `rpy`
/// (angle unit; roll, pitch, yaw with R = Rz(yaw)·Ry(pitch)·Rx(roll)).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FrameSpec {
    #[serde(default)]
    xyz: [f64; 3],
    #[serde(default)]
    rpy: [f64; 3],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct JointSpec {
    name: String,
    #[serde(rename = "type", default = "revolute")]
    kind: JointType,
    d: Option<f64>,
    a: Option<f64>,
    alpha: Option<f64>,
    theta: Option<f64>,
    xyz: Option<[f64; 3]>,
    rpy: Option<[f64; 3]>,
    axis: Option<[f64; 3]>,
    #[serde(default)]
    offset: f64,
    min: f64,
    max: f64,
    vel: Option<f64>,
    acc: Option<f64>,
    jerk: Option<f64>,
    /// Motor effort limit, always SI (N·m revolute, N prismatic) whatever `[units]`
    /// says: datasheets give torques in N·m, and `[units]` scales lengths and angles.
    effort: Option<f64>,
    inertial: Option<InertialSpec>,
}

/// `[joint.inertial]`: mass properties of the link the joint moves, in its
/// link frame. Mass in kg; `com` in the length unit; `inertia` (ixx, iyy, izz,
/// ixy, ixz, iyz, about the centre of mass) in kg·(length unit)².
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct InertialSpec {
    mass: f64,
    #[serde(default)]
    com: [f64; 3],
    #[serde(default)]
    inertia: [f64; 6],
}

fn revolute() -> JointType {
    JointType::Revolute
}

/// 1-based line and column of byte offset `at` in `text`.
pub(crate) fn line_col(text: &str, at: usize) -> (usize, usize) {
    let at = at.min(text.len());
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

struct Ctx<'a> {
    file: &'a str,
    text: &'a str,
}

impl Ctx<'_> {
    fn err(&self, span: std::ops::Range<usize>, field: impl Into<String>, message: impl Into<String>) -> Error {
        let (line, column) = line_col(self.text, span.start);
        Error::Model(ModelError::Description {
            file: self.file.to_string(),
            line,
            column,
            field: field.into(),
            message: message.into(),
        })
    }
}

/// Parses a TOML robot description. `file` is used in error messages only.
pub fn robot_from_toml(text: &str, file: &str) -> Result<Robot> {
    let ctx = Ctx { file, text };
    let de = toml::Deserializer::parse(text).map_err(|e| {
        let span = e.span().unwrap_or(0..0);
        ctx.err(span, "(syntax)", e.message().trim())
    })?;
    let parsed: RobotFile = serde_path_to_error::deserialize(de).map_err(|e| {
        // `Spanned<T>` shows up in the path as a private field; hide it.
        let path = e.path().to_string().replace(".$__serde_spanned_private_value", "");
        let inner = e.into_inner();
        let span = inner.span().unwrap_or(0..0);
        ctx.err(span, if path == "." { "(top level)".to_string() } else { path }, inner.message().trim())
    })?;
    build(parsed, &ctx)
}

fn build(f: RobotFile, ctx: &Ctx) -> Result<Robot> {
    let len = match f.units.length {
        LengthUnit::M => 1.0,
        LengthUnit::Mm => 1e-3,
    };
    let ang = match f.units.angle {
        AngleUnit::Rad => 1.0,
        AngleUnit::Deg => std::f64::consts::PI / 180.0,
    };
    let frame = |s: &Option<Spanned<FrameSpec>>| {
        s.as_ref().map_or(Pose::IDENTITY, |s| {
            let v = s.get_ref();
            Pose::from_xyz_rpy(v.xyz.map(|x| x * len), v.rpy.map(|x| x * ang), RpyConvention::Zyx)
        })
    };
    let mut joints = Vec::with_capacity(f.joint.len());
    let mut inertials = Vec::with_capacity(f.joint.len());
    for (i, sj) in f.joint.iter().enumerate() {
        let (joint, inertial) = joint_of(i, sj, f.convention, len, ang, ctx)?;
        joints.push(joint);
        inertials.push(inertial);
    }
    let poses = f
        .poses
        .iter()
        .map(|(name, sp)| {
            // Joint-value unit: angle for revolute joints, length for prismatic ones.
            let unit = |k: usize| if joints.get(k).is_some_and(|j| j.kind == JointType::Prismatic) { len } else { ang };
            let q = sp.get_ref().iter().enumerate().map(|(k, x)| x * unit(k)).collect();
            NamedPose { name: name.clone(), q }
        })
        .collect();
    let meta = Metadata { manufacturer: f.manufacturer, source: f.source, notes: f.notes, warnings: Vec::new() };
    let mut desc = Description::new(f.name, f.convention, joints);
    desc.metadata = meta;
    desc.base = frame(&f.base);
    desc.tool = frame(&f.tool);
    desc.poses = poses;
    if inertials.iter().any(Option::is_some) {
        desc.inertials = inertials;
    }
    if let Some(problem) = desc.problems().into_iter().next() {
        let span = match problem.joint {
            Some(i) => f.joint[i].span(),
            None => match problem.field.as_str() {
                "base" => f.base.as_ref().map_or(0..0, Spanned::span),
                "tool" => f.tool.as_ref().map_or(0..0, Spanned::span),
                field => field.strip_prefix("poses.").and_then(|name| f.poses.get(name)).map_or(0..0, Spanned::span),
            },
        };
        let message = match problem.joint {
            Some(i) => in_file_units(&problem, i, f.joint[i].get_ref()),
            None => problem.message,
        };
        return Err(ctx.err(span, problem.field, message));
    }
    desc.build().map_err(|e| match e {
        Error::Model(ModelError::InvalidModel { message, .. }) => ctx.err(0..0, "(model)", message),
        other => other,
    })
}

/// A problem of joint `i` with its limits quoted as the file writes them (in
/// its `[units]`), not converted to SI as the description holds them.
fn in_file_units(problem: &Problem, i: usize, j: &JointSpec) -> String {
    let field = problem.field.rsplit('.').next().unwrap_or_default();
    let rate = match field {
        "vel" => j.vel,
        "acc" => j.acc,
        "jerk" => j.jerk,
        _ => None,
    };
    let said = match (field, rate) {
        ("min", _) => description::not_an_interval(j.min, j.max),
        (name, Some(v)) if v <= 0.0 => description::not_positive(name, v),
        _ => return problem.message.clone(),
    };
    format!("joint {} (`{}`): {said}", i + 1, j.name)
}

/// Joint `i` of the file in SI units, with the mass properties of its link;
/// errors for what a DH row or a general joint may not hold (the values
/// themselves are checked by [`Description::problems`]).
fn joint_of(
    i: usize,
    sj: &Spanned<JointSpec>,
    convention: GeometryKind,
    len: f64,
    ang: f64,
    ctx: &Ctx,
) -> Result<(Joint, Option<Inertial>)> {
    let span = sj.span();
    let j = sj.get_ref();
    let e = |name: &str, msg: String| {
        ctx.err(span.clone(), format!("joint[{i}].{name}"), format!("joint {} (`{}`): {msg}", i + 1, j.name))
    };
    let prismatic = j.kind == JointType::Prismatic;
    // Joint-value unit: angle for revolute joints, length for prismatic ones.
    let qunit = if prismatic { len } else { ang };
    let geometry = match convention {
        GeometryKind::Standard | GeometryKind::Modified => {
            for (name, v) in [("xyz", j.xyz.is_some()), ("rpy", j.rpy.is_some()), ("axis", j.axis.is_some())] {
                if v {
                    return Err(e(name, "`xyz`/`rpy`/`axis` belong to convention = \"general\"; a DH row has d, a, alpha (and theta for prismatic joints)".into()));
                }
            }
            if prismatic && j.d.is_some() {
                return Err(e(
                    "d",
                    "a prismatic joint's d is its joint variable (d = q + offset); put a constant part into `offset`"
                        .into(),
                ));
            }
            if !prismatic && j.theta.is_some() {
                return Err(e(
                    "theta",
                    "a revolute joint's θ is its joint variable (θ = q + offset); put a constant part into `offset`"
                        .into(),
                ));
            }
            let a = j.a.ok_or_else(|| e("a", "missing DH link length `a`".into()))?;
            let alpha = j.alpha.ok_or_else(|| e("alpha", "missing DH link twist `alpha`".into()))?;
            let convention =
                if convention == GeometryKind::Standard { DhConvention::Standard } else { DhConvention::Modified };
            LinkGeometry::Dh {
                convention,
                d: j.d.unwrap_or(0.0) * len,
                a: a * len,
                alpha: alpha * ang,
                theta: j.theta.unwrap_or(0.0) * ang,
            }
        }
        GeometryKind::General => {
            for (name, v) in [("d", j.d), ("a", j.a), ("alpha", j.alpha), ("theta", j.theta)] {
                if v.is_some() {
                    return Err(e(name, "DH fields belong to convention = \"standard\" or \"modified\"; a general joint has xyz, rpy and axis".into()));
                }
            }
            let axis = j.axis.ok_or_else(|| {
                e("axis", "missing joint `axis` (a direction in the joint frame, e.g. [0, 0, 1])".into())
            })?;
            let axis = Vector3::from(axis);
            let norm = axis.norm();
            if !(norm > 1e-12 && norm.is_finite()) {
                return Err(e("axis", format!("axis {:?} has no direction", axis.as_slice())));
            }
            let xyz = j.xyz.unwrap_or([0.0; 3]).map(|x| x * len);
            let rpy = j.rpy.unwrap_or([0.0; 3]).map(|x| x * ang);
            LinkGeometry::General { origin: Pose::from_xyz_rpy(xyz, rpy, RpyConvention::Zyx), axis: axis / norm }
        }
    };
    let inertial = match &j.inertial {
        None => None,
        Some(b) => Some(
            Inertial::new(b.mass, Vector3::from(b.com) * len, b.inertia.map(|v| v * len * len))
                .map_err(|err| e("inertial", err.to_string()))?,
        ),
    };
    let joint = Joint {
        name: j.name.clone(),
        kind: j.kind,
        geometry,
        offset: j.offset * qunit,
        limits: Limits {
            min: j.min * qunit,
            max: j.max * qunit,
            vel: j.vel.map(|v| v * qunit),
            acc: j.acc.map(|v| v * qunit),
            jerk: j.jerk.map(|v| v * qunit),
            effort: j.effort,
        },
    };
    Ok((joint, inertial))
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"
name = "planar2"
source = "test"
convention = "standard"
[units]
length = "mm"
angle = "deg"
[[joint]]
name = "j1"
a = 1000
alpha = 0
min = -170
max = 170
[[joint]]
name = "j2"
a = 1000
alpha = 0
min = -170
max = 170
[poses]
home = [0, 90]
"#;

    #[test]
    fn parses_and_converts_units() {
        let r = robot_from_toml(GOOD, "good.toml").unwrap();
        assert_eq!(r.dof(), 2);
        assert!((r.joints()[0].limits.max - 170f64.to_radians()).abs() < 1e-15);
        let fk = r.fk(r.home()).unwrap();
        assert!((fk.world_from_tool.pos.x - 1.0).abs() < 1e-12 && (fk.world_from_tool.pos.y - 1.0).abs() < 1e-12);
    }

    fn err_of(text: &str) -> Error {
        robot_from_toml(text, "bad.toml").unwrap_err()
    }

    #[test]
    fn unknown_field_names_line_and_field() {
        let bad = GOOD.replacen("alpha = 0\nmin = -170", "alpah = 0\nmin = -170", 1);
        let Error::Model(ModelError::Description { file, line, field, message, .. }) = err_of(&bad) else { panic!() };
        assert_eq!(file, "bad.toml");
        assert_eq!(line, 11, "{message}");
        assert!(field.starts_with("joint[0]"), "{field}");
        assert!(message.contains("alpah"), "{message}");
    }

    #[test]
    fn wrong_type_and_syntax_errors() {
        let bad = GOOD.replacen("a = 1000", "a = \"long\"", 1);
        let Error::Model(ModelError::Description { line, field, .. }) = err_of(&bad) else { panic!() };
        assert_eq!((line, field.as_str()), (10, "joint[0].a"));
        let Error::Model(ModelError::Description { line, .. }) = err_of("name = \"x\"\nsource = \n") else { panic!() };
        assert_eq!(line, 2);
        let Error::Model(ModelError::Description { field, .. }) = err_of(&GOOD.replace("source = \"test\"\n", ""))
        else {
            panic!()
        };
        assert_eq!(field, "(top level)");
    }

    #[test]
    fn semantic_errors_point_at_the_joint() {
        let bad = GOOD.replacen("min = -170\nmax = 170", "min = 170\nmax = -170", 1);
        let Error::Model(ModelError::Description { line, field, message, .. }) = err_of(&bad) else { panic!() };
        assert_eq!(line, 8);
        assert_eq!(field, "joint[0].min");
        assert!(message.contains("not an interval"));
        let Error::Model(ModelError::Description { field, .. }) = err_of(&GOOD.replace("home = [0, 90]", "home = [0]"))
        else {
            panic!()
        };
        assert_eq!(field, "poses.home");
        let Error::Model(ModelError::Description { field, .. }) =
            err_of(&GOOD.replace("home = [0, 90]", "qz = [0, 0]"))
        else {
            panic!()
        };
        assert_eq!(field, "poses.home");
        let Error::Model(ModelError::Description { field, .. }) =
            err_of(&GOOD.replacen("name = \"j1\"", "name = \"j1\"\ntheta = 3", 1))
        else {
            panic!()
        };
        assert_eq!(field, "joint[0].theta");
        let Error::Model(ModelError::Description { field, .. }) = err_of(&GOOD.replacen("alpha = 0\n", "", 1)) else {
            panic!()
        };
        assert_eq!(field, "joint[0].alpha");
        let Error::Model(ModelError::Description { field, .. }) =
            err_of(&GOOD.replace("convention = \"standard\"", "convention = \"dh\""))
        else {
            panic!()
        };
        assert_eq!(field, "convention");
    }

    #[test]
    fn effort_is_si_whatever_the_units() {
        // GOOD is in mm and degrees; effort stays N·m, vel scales with the angle unit.
        let text = GOOD.replacen("max = 170\n", "max = 170\nvel = 90\neffort = 12.5\n", 1);
        let r = robot_from_toml(&text, "e.toml").unwrap();
        let l = r.joints()[0].limits;
        assert_eq!(l.effort, Some(12.5));
        assert!((l.vel.unwrap() - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert_eq!(r.joints()[1].limits.effort, None);
    }

    #[test]
    fn bad_effort_names_the_joint_and_what_is_expected() {
        for (value, says) in [("0", "must be positive"), ("-3", "must be positive"), ("inf", "not a finite number")] {
            let text = GOOD.replacen("max = 170\n", &format!("max = 170\neffort = {value}\n"), 1);
            let Error::Model(ModelError::Description { line, field, message, .. }) = err_of(&text) else { panic!() };
            assert_eq!((line, field.as_str()), (8, "joint[0].effort"), "{value}");
            assert!(message.contains("joint 1 (`j1`)") && message.contains(says), "{value}: {message}");
        }
        let text = GOOD.replacen("max = 170\n", "max = 170\neffort = \"high\"\n", 1);
        let Error::Model(ModelError::Description { field, .. }) = err_of(&text) else { panic!() };
        assert_eq!(field, "joint[0].effort");
    }

    #[test]
    fn line_col_counts_from_one() {
        assert_eq!(line_col("ab\ncd", 0), (1, 1));
        assert_eq!(line_col("ab\ncd", 4), (2, 2));
        assert_eq!(line_col("ab", 99), (1, 3));
    }
}
