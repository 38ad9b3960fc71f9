//! URDF import: the serial chain from the root link to a tip link.
//!
//! Fixed joints are folded into their neighbours' transforms (into the base
//! transform before the first moving joint and into the tool transform after
//! the last). `revolute`, `continuous` and `prismatic` joints become joints of
//! the model with their `origin`, `axis` (any direction, also negative) and
//! `limit` (position, `velocity` and `effort`; 0 counts as unknown). Anything else on the path (`floating`, `planar`, `spherical`) is an
//! error.
//!
//! Mass properties (`<inertial>`) are read per moving joint: those of its
//! child link and of every link rigidly attached to it — through fixed joints,
//! and through joints off the chain, which are held at 0 — expressed in the
//! child link frame (kinema's link frame for that joint) and combined by the
//! parallel-axis theorem. A URDF in which no link has mass or inertia gives a
//! robot without mass properties.

use std::collections::{HashMap, HashSet};

use nalgebra::Vector3;

use crate::error::{Error, Result};
use crate::math::{Pose, RpyConvention};
use crate::model::{GeometryKind, Inertial, Joint, JointType, Limits, LinkGeometry, Metadata, Model};
use crate::robot::Robot;

/// Parses a URDF document and extracts the chain from its root link to `tip`
/// (default: the only leaf link). `file` is used in messages only.
pub fn robot_from_urdf(text: &str, file: &str, tip: Option<&str>) -> Result<Robot> {
    let err = |message: String| Error::Urdf { file: file.to_string(), message };
    let u = urdf_rs::read_from_string(text).map_err(|e| err(format!("not a readable URDF document: {e}")))?;
    if u.joints.is_empty() {
        return Err(err("the URDF has no <joint> elements; a robot arm needs at least one moving joint".into()));
    }
    let mut by_child: HashMap<&str, &urdf_rs::Joint> = HashMap::new();
    for j in &u.joints {
        if by_child.insert(j.child.link.as_str(), j).is_some() {
            return Err(err(format!(
                "link `{}` is the child of more than one joint; a URDF must be a tree",
                j.child.link
            )));
        }
    }
    let parents: HashSet<&str> = u.joints.iter().map(|j| j.parent.link.as_str()).collect();
    let mut links: Vec<&str> = u.links.iter().map(|l| l.name.as_str()).collect();
    for j in &u.joints {
        for l in [j.parent.link.as_str(), j.child.link.as_str()] {
            if !links.contains(&l) {
                links.push(l);
            }
        }
    }
    let roots: Vec<&str> = links.iter().copied().filter(|l| !by_child.contains_key(l)).collect();
    if roots.len() != 1 {
        return Err(err(format!(
            "expected exactly one root link (a link that is no joint's child), found {}: {}",
            roots.len(),
            if roots.is_empty() { "none (the joints form a cycle)".to_string() } else { roots.join(", ") }
        )));
    }
    let tip = match tip {
        Some(t) => {
            if !links.contains(&t) {
                return Err(err(format!("tip link `{t}` is not in the URDF; its links are: {}", links.join(", "))));
            }
            t
        }
        None => {
            let leaves: Vec<&str> = links.iter().copied().filter(|l| !parents.contains(l)).collect();
            match leaves.as_slice() {
                [one] => *one,
                _ => {
                    return Err(err(format!(
                        "the URDF is not a single serial chain: it has {} leaf links ({}); choose one with --tip LINK",
                        leaves.len(),
                        leaves.join(", ")
                    )))
                }
            }
        }
    };
    // Walk up from the tip to the root.
    let mut path = Vec::new();
    let mut at = tip;
    while let Some(j) = by_child.get(at) {
        if path.len() > u.joints.len() {
            return Err(err("the joints form a cycle".into()));
        }
        path.push(*j);
        at = j.parent.link.as_str();
    }
    path.reverse();

    let mut pending = Pose::IDENTITY; // fixed transforms not yet attached
    let mut moving_children = Vec::new();
    let mut base = None;
    let mut joints = Vec::new();
    for j in &path {
        let origin = Pose::from_xyz_rpy(*j.origin.xyz, *j.origin.rpy, RpyConvention::Zyx);
        if !origin.is_finite() {
            return Err(err(format!("joint `{}`: origin is not finite", j.name)));
        }
        let kind = match j.joint_type {
            urdf_rs::JointType::Fixed => {
                pending = pending * origin;
                continue;
            }
            urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => JointType::Revolute,
            urdf_rs::JointType::Prismatic => JointType::Prismatic,
            ref other => {
                return Err(err(format!(
                    "joint `{}` has type `{}`; only revolute, continuous, prismatic and fixed joints are supported in a serial chain",
                    j.name,
                    format!("{other:?}").to_lowercase()
                )))
            }
        };
        let axis = Vector3::from(*j.axis.xyz);
        let norm = axis.norm();
        if !(norm > 1e-12 && norm.is_finite()) {
            return Err(err(format!("joint `{}`: axis {:?} has no direction", j.name, *j.axis.xyz)));
        }
        let limits = if j.joint_type == urdf_rs::JointType::Continuous {
            Limits::unbounded()
        } else {
            let l = &j.limit;
            if !(l.lower.is_finite() && l.upper.is_finite()) || l.lower > l.upper {
                return Err(err(format!(
                    "joint `{}`: limit lower = {} upper = {} is not an interval (need lower ≤ upper)",
                    j.name, l.lower, l.upper
                )));
            }
            Limits::position(l.lower, l.upper)
        };
        let vel = (j.limit.velocity > 0.0 && j.limit.velocity.is_finite()).then_some(j.limit.velocity);
        // URDF requires `effort` on a <limit>, so files without a known value write 0: that
        // (or no <limit> at all) means unknown; a negative or non-finite value is a mistake.
        let effort = j.limit.effort;
        if effort.is_nan() || effort < 0.0 || effort.is_infinite() {
            return Err(err(format!(
                "joint `{}`: <limit effort=\"{effort}\"> is not a motor limit (need a finite value > 0 in N·m or N, or 0 if unknown)",
                j.name
            )));
        }
        let effort = (effort > 0.0).then_some(effort);
        let origin = if base.is_none() {
            base = Some(pending);
            origin
        } else {
            pending * origin
        };
        pending = Pose::IDENTITY;
        moving_children.push(j.child.link.as_str());
        joints.push(Joint {
            name: j.name.clone(),
            kind,
            geometry: LinkGeometry::General { origin, axis: axis / norm },
            offset: 0.0,
            limits: Limits { vel, effort, ..limits },
        });
    }
    if joints.is_empty() {
        return Err(err(format!("the chain from `{}` to `{tip}` has no moving joint", roots[0])));
    }
    let inertials = inertials(&u, &path, &moving_children, file)?;
    let home =
        joints.iter().map(|j| if j.limits.contains(0.0) { 0.0 } else { 0.5 * (j.limits.min + j.limits.max) }).collect();
    let name = if u.name.is_empty() { file.to_string() } else { u.name.clone() };
    let meta = Metadata {
        manufacturer: String::new(),
        source: format!("URDF {file}, chain {} → {tip}", roots[0]),
        notes: String::new(),
    };
    let mut model = Model::builder(name, GeometryKind::General)
        .metadata(meta)
        .joints(joints)
        .base(base.unwrap_or(Pose::IDENTITY))
        .tool(pending)
        .pose("home", home);
    if let Some(b) = inertials {
        model = model.inertials(b.into_iter().map(Some).collect());
    }
    Ok(Robot::new(model.build().map_err(|e| err(e.to_string()))?))
}

/// The mass properties of each moving joint's body, in its child link frame
/// (see the module documentation); `None` if no link of the URDF has any.
fn inertials(
    u: &urdf_rs::Robot,
    path: &[&urdf_rs::Joint],
    moving_children: &[&str],
    file: &str,
) -> Result<Option<Vec<Inertial>>> {
    let massless = |l: &urdf_rs::Link| {
        let i = &l.inertial.inertia;
        l.inertial.mass.value == 0.0 && [i.ixx, i.iyy, i.izz, i.ixy, i.ixz, i.iyz].iter().all(|v| *v == 0.0)
    };
    if u.links.iter().all(massless) {
        return Ok(None);
    }
    let link_by_name: HashMap<&str, &urdf_rs::Link> = u.links.iter().map(|l| (l.name.as_str(), l)).collect();
    // The chain's moving joints end a rigid body; every other joint is rigid (held at 0).
    let chain_moving: HashSet<&str> =
        path.iter().filter(|j| j.joint_type != urdf_rs::JointType::Fixed).map(|j| j.name.as_str()).collect();
    let mut out = Vec::with_capacity(moving_children.len());
    for &child in moving_children {
        let mut body = Inertial::ZERO;
        // (link, child_from_link), depth first.
        let mut stack = vec![(child, Pose::IDENTITY)];
        let mut visited = 0usize;
        while let Some((name, child_from_link)) = stack.pop() {
            visited += 1;
            if visited > u.links.len() + 1 {
                return Err(Error::Urdf { file: file.to_string(), message: "the joints form a cycle".into() });
            }
            if let Some(l) = link_by_name.get(name) {
                let o = &l.inertial.origin;
                let link_from_inertial = Pose::from_xyz_rpy(*o.xyz, *o.rpy, RpyConvention::Zyx);
                let i = &l.inertial.inertia;
                let own = Inertial::new(
                    l.inertial.mass.value,
                    nalgebra::Vector3::zeros(),
                    [i.ixx, i.iyy, i.izz, i.ixy, i.ixz, i.iyz],
                )
                .map_err(|e| Error::Urdf {
                    file: file.to_string(),
                    message: format!("link `{name}`: <inertial>: {e}"),
                })?;
                let own = own.transformed(&(child_from_link * link_from_inertial));
                body = body.combined(&own);
            }
            for j in u.joints.iter().filter(|j| j.parent.link == name && !chain_moving.contains(j.name.as_str())) {
                let origin = Pose::from_xyz_rpy(*j.origin.xyz, *j.origin.rpy, RpyConvention::Zyx);
                stack.push((j.child.link.as_str(), child_from_link * origin));
            }
        }
        out.push(body);
    }
    Ok(Some(out))
}
