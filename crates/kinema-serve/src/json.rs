//! JSON forms of the library's values, with the field names `kinema … --json`
//! prints (`info`, `fk`, `ik --all`), so the page and scripts read one schema.

use kinema::analysis::Ellipsoid;
use kinema::ik::Solution;
use kinema::traj::JointTrajectory;
use kinema::{Fk, JointType, LinkGeometry, Pose, Robot, RpyConvention};
use serde_json::{json, Map, Value};

/// A pose as `kinema fk --json` prints it (roll-pitch-yaw in the zyx convention).
pub(crate) fn pose(p: &Pose) -> Value {
    pose_in(p, RpyConvention::Zyx)
}

/// A pose with its roll-pitch-yaw in `conv`: `T` as 4 rows, `position`,
/// `rpy`, `rpy_convention` (`"zyx"` or `"xyz"`) and `quaternion_wxyz`.
pub fn pose_in(p: &Pose, conv: RpyConvention) -> Value {
    let q = p.quaternion();
    json!({
        "T": p.to_rows(),
        "position": [p.pos.x, p.pos.y, p.pos.z],
        "rpy": p.rpy(conv),
        "rpy_convention": conv_name(conv),
        "quaternion_wxyz": [q.w, q.i, q.j, q.k],
    })
}

/// The name of a roll-pitch-yaw convention in JSON and on the command line.
pub fn conv_name(c: RpyConvention) -> &'static str {
    match c {
        RpyConvention::Zyx => "zyx",
        RpyConvention::Xyz => "xyz",
    }
}

/// The joints `fk` flags as outside their limits: `[{"joint": i (from 1), "name"}]`.
pub fn out_of_limits(r: &Robot, fk: &Fk) -> Value {
    fk.out_of_limits.indices().map(|i| json!({"joint": i + 1, "name": r.joints()[i].name})).collect()
}

fn kind_name(kind: JointType) -> &'static str {
    match kind {
        JointType::Revolute => "revolute",
        JointType::Prismatic => "prismatic",
    }
}

/// A robot as `kinema info --json` prints it, plus `home` and which IK the
/// server can run (`analytic`: the solver's name or null; `q3`: the iiwa's
/// redundancy parameter is available).
pub fn robot_info(r: &Robot) -> Value {
    let joints: Vec<Value> = r
        .joints()
        .iter()
        .map(|j| {
            let geometry = match j.geometry {
                LinkGeometry::Dh { convention, d, a, alpha, theta } => json!({
                    "convention": format!("{convention:?}").to_lowercase(), "d": d, "a": a, "alpha": alpha, "theta": theta,
                }),
                LinkGeometry::General { origin, axis } => json!({
                    "xyz": [origin.pos.x, origin.pos.y, origin.pos.z],
                    "rpy": origin.rpy(RpyConvention::Zyx),
                    "axis": [axis.x, axis.y, axis.z],
                }),
            };
            json!({
                "name": j.name, "type": kind_name(j.kind), "offset": j.offset, "geometry": geometry,
                "min": finite_or_null(j.limits.min), "max": finite_or_null(j.limits.max),
                "vel": j.limits.vel, "acc": j.limits.acc, "jerk": j.limits.jerk, "effort": j.limits.effort,
            })
        })
        .collect();
    let poses: Map<String, Value> = r.poses().iter().map(|p| (p.name.clone(), json!(p.q))).collect();
    let family = kinema::ik::family::fit(r);
    let analytic = family.as_ref().map(|f| f.name());
    // The self-motion parameters a request may fix (the viewer's q3 slider).
    let redundancy = family.as_ref().and_then(|f| f.redundancy()).map_or(&[][..], |r| r.parameters());
    json!({
        "name": r.name(), "dof": r.dof(), "convention": format!("{:?}", r.geometry_kind()).to_lowercase(),
        "manufacturer": r.metadata().manufacturer, "source": r.metadata().source, "notes": r.metadata().notes,
        "joints": joints, "base": pose(r.base()), "tool": pose(r.tool()),
        "poses": poses, "home": r.home(),
        "ik": { "analytic": analytic, "q3": redundancy.contains(&"q3"), "redundancy": redundancy },
    })
}

/// An unbounded limit is ±∞, which JSON cannot hold: null.
fn finite_or_null(v: f64) -> Value {
    if v.is_finite() {
        json!(v)
    } else {
        Value::Null
    }
}

/// One line of `GET /api/robots`.
pub(crate) fn robot_summary(r: &Robot, default: bool) -> Value {
    let m = r.metadata();
    let description = if m.manufacturer.is_empty() {
        format!("{} DOF ({}); {}", r.dof(), r.joint_types(), m.source)
    } else {
        format!("{} {} DOF ({}); {}", m.manufacturer, r.dof(), r.joint_types(), m.source)
    };
    json!({
        "name": r.name(), "dof": r.dof(), "description": description, "joint_types": r.joint_types(),
        "manufacturer": m.manufacturer, "source": m.source, "default": default,
    })
}

/// The answer of `POST /api/fk`: what `kinema fk --json` prints, plus every
/// frame along the chain and every joint axis, for drawing.
///
/// `frames[0]` is the base, `frames[i]` link i, the last one the tool (as
/// [`Robot::link_frames`]). `joints[i]` is joint i + 1's axis in the base
/// frame: a point on it and its direction (standard DH: z of frame i − 1;
/// modified DH: z of frame i; general: the joint's axis in frame i).
pub(crate) fn fk(r: &Robot, q: &[f64], fk: &Fk, frames: &[Pose]) -> Value {
    let mut v = pose(&fk.world_from_tool);
    v["robot"] = json!(r.name());
    v["q"] = json!(q);
    v["within_limits"] = json!(fk.within_limits());
    v["out_of_limits"] = out_of_limits(r, fk);
    v["frames"] = frames
        .iter()
        .map(|f| {
            json!({
                "position": [f.pos.x, f.pos.y, f.pos.z],
                "rotation": (0..3).map(|k| [f.rot[(k, 0)], f.rot[(k, 1)], f.rot[(k, 2)]]).collect::<Vec<_>>(),
            })
        })
        .collect();
    v["joints"] = r
        .joints()
        .iter()
        .enumerate()
        .map(|(i, j)| {
            let (origin, dir) = match j.geometry {
                LinkGeometry::Dh { convention: kinema::DhConvention::Standard, .. } => {
                    (frames[i].pos, frames[i].rot.column(2).into_owned())
                }
                LinkGeometry::Dh { .. } => (frames[i + 1].pos, frames[i + 1].rot.column(2).into_owned()),
                LinkGeometry::General { axis, .. } => (frames[i + 1].pos, frames[i + 1].rot * axis),
            };
            json!({
                "name": j.name, "type": kind_name(j.kind),
                "origin": [origin.x, origin.y, origin.z], "axis": [dir.x, dir.y, dir.z],
                "within_limits": !fk.out_of_limits.contains(i),
            })
        })
        .collect();
    v
}

/// One IK solution with the fields of `kinema ik --json --all` (radians and metres).
pub fn solution(s: &Solution) -> Value {
    let mut v = json!({
        "q": s.q,
        "branch": s.branch,
        "within_limits": s.within_limits(),
        "position_error": s.position_error,
        "orientation_error": s.orientation_error,
    });
    if let Some(n) = s.numeric {
        v["iterations"] = json!(n.iterations);
        v["restarts"] = json!(n.restarts);
        v["stop"] = json!(n.stop.to_string());
    }
    v
}

/// A sampled trajectory: `t` and, per sample, the rows `q`, `qd`, `qdd`.
pub(crate) fn trajectory(traj: &JointTrajectory) -> Value {
    let rows = |f: fn(&JointTrajectory, usize) -> &[f64]| -> Vec<Value> {
        (0..traj.len()).map(|k| json!(f(traj, k))).collect()
    };
    json!({
        "t": traj.times(),
        "q": rows(JointTrajectory::q),
        "qd": rows(JointTrajectory::qd),
        "qdd": rows(JointTrajectory::qdd),
        "samples": traj.len(),
        "duration": traj.times().last().copied().unwrap_or(0.0),
    })
}

/// An ellipsoid as `kinema manip --json` prints it (axes as unit vectors,
/// largest radius first), with its centre.
pub(crate) fn ellipsoid(e: &Ellipsoid, centre: [f64; 3]) -> Value {
    json!({
        "centre": centre,
        "radii": [e.radii[0], e.radii[1], e.radii[2]],
        "axes": (0..3).map(|k| [e.axes[(0, k)], e.axes[(1, k)], e.axes[(2, k)]]).collect::<Vec<_>>(),
    })
}
