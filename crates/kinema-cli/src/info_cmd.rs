//! `kinema robots` and `kinema info`: the built-in robots, and one robot's
//! joints, limits, poses and IK family.

use anyhow::Result;
use kinema::{JointType, LinkGeometry, Pose, Robot, RpyConvention};
use kinema_io::{RobotInfo, RobotSummary};

use crate::print_json;
use crate::stdout::outln;

pub fn robots(as_json: bool) -> Result<()> {
    let all = Robot::builtins()?;
    if as_json {
        let list: Vec<RobotSummary> = all.iter().map(|r| RobotSummary::new(r, false)).collect();
        return print_json(&list);
    }
    outln!("{:<20} {:>3}  {:<8} source", "name", "dof", "joints")?;
    for r in &all {
        outln!("{:<20} {:>3}  {:<8} {}", r.name(), r.dof(), r.joint_types(), r.metadata().source)?;
    }
    Ok(())
}

/// A joint value in display units: degrees for revolute joints, metres for prismatic ones.
pub(crate) fn shown(kind: JointType, v: f64) -> f64 {
    match kind {
        JointType::Revolute => v.to_degrees(),
        JointType::Prismatic => v,
    }
}

pub fn info(r: &Robot, as_json: bool) -> Result<()> {
    if as_json {
        // The same JSON as the viewer's `GET /api/robots/{name}`.
        return print_json(&RobotInfo::new(r));
    }
    let m = r.metadata();
    outln!("{} — {} DOF ({}), {:?} description", r.name(), r.dof(), r.joint_types(), r.geometry_kind())?;
    if !m.manufacturer.is_empty() {
        outln!("manufacturer: {}", m.manufacturer)?;
    }
    outln!("source: {}", m.source)?;
    outln!("\nlengths in m, angles in deg; revolute θ = q + offset, prismatic d = q + offset")?;
    match r.geometry_kind() {
        kinema::GeometryKind::General => {
            outln!(
                "{:>2} {:<16} {:>4} {:>28} {:>26} {:>22}",
                "i",
                "joint",
                "type",
                "origin xyz",
                "origin rpy",
                "axis"
            )?;
            for (i, j) in r.joints().iter().enumerate() {
                if let LinkGeometry::General { origin, axis } = j.geometry {
                    let rpy = origin.rpy(RpyConvention::Zyx).map(f64::to_degrees);
                    outln!(
                        "{:>2} {:<16} {:>4} {:>8.4} {:>8.4} {:>8.4}  {:>8.2} {:>8.2} {:>8.2}  {:>6.3} {:>6.3} {:>6.3}",
                        i + 1,
                        j.name,
                        j.kind.letter(),
                        origin.pos.x,
                        origin.pos.y,
                        origin.pos.z,
                        rpy[0],
                        rpy[1],
                        rpy[2],
                        axis.x,
                        axis.y,
                        axis.z
                    )?;
                }
            }
        }
        _ => {
            let modified = r.geometry_kind() == kinema::GeometryKind::Modified;
            let (al, aa) = if modified { ("α(i-1)", "a(i-1)") } else { ("α", "a") };
            outln!(
                "{:>2} {:<16} {:>4} {:>9} {:>9} {:>9} {:>9} {:>9}",
                "i",
                "joint",
                "type",
                "θ",
                "d",
                aa,
                al,
                "offset"
            )?;
            for (i, j) in r.joints().iter().enumerate() {
                if let LinkGeometry::Dh { d, a, alpha, theta, .. } = j.geometry {
                    let (th, dd) = match j.kind {
                        JointType::Revolute => (format!("q{}", i + 1), format!("{d:.4}")),
                        JointType::Prismatic => (format!("{:.2}", theta.to_degrees()), format!("q{}", i + 1)),
                    };
                    outln!(
                        "{:>2} {:<16} {:>4} {:>9} {:>9} {:>9.4} {:>9.2} {:>9.4}",
                        i + 1,
                        j.name,
                        j.kind.letter(),
                        th,
                        dd,
                        a,
                        alpha.to_degrees(),
                        shown(j.kind, j.offset)
                    )?;
                }
            }
        }
    }
    outln!("\nlimits (deg or m, per s …; effort in N·m or N)")?;
    for (i, j) in r.joints().iter().enumerate() {
        let opt = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{:.4}", shown(j.kind, v)));
        outln!(
            "{:>2} {:<16} [{:>10.4}, {:>10.4}]  vel {}  acc {}  jerk {}  effort {}",
            i + 1,
            j.name,
            shown(j.kind, j.limits.min),
            shown(j.kind, j.limits.max),
            opt(j.limits.vel),
            opt(j.limits.acc),
            opt(j.limits.jerk),
            j.limits.effort.map_or("-".to_string(), |v| format!("{v}"))
        )?;
    }
    for (name, p) in [("base", r.base()), ("tool", r.tool())] {
        if *p != Pose::IDENTITY {
            let rpy = p.rpy(RpyConvention::Zyx).map(f64::to_degrees);
            outln!(
                "{name}: xyz = [{:.4}, {:.4}, {:.4}] m, rpy (zyx) = [{:.3}, {:.3}, {:.3}] deg",
                p.pos.x,
                p.pos.y,
                p.pos.z,
                rpy[0],
                rpy[1],
                rpy[2]
            )?;
        }
    }
    outln!("\nnamed poses (deg or m)")?;
    for p in r.poses() {
        let vals: Vec<String> = p.q.iter().zip(r.joints()).map(|(v, j)| format!("{:.4}", shown(j.kind, *v))).collect();
        outln!("  {:<14} [{}]", p.name, vals.join(", "))?;
    }
    if !m.notes.trim().is_empty() {
        outln!("\nnotes:\n{}", m.notes.trim())?;
    }
    Ok(())
}
