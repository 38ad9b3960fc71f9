//! URDF import: the serial chain from the root link to a tip link.
//!
//! The tip is the one given, else the only leaf link reached through moving
//! joints: leaves that hang off the root through fixed joints only (the
//! `base` frame ROS-Industrial descriptions attach to `base_link`) are not
//! candidates, and leaves reached through the same moving joints (a tool frame
//! and a camera frame on the flange) end the chain at their last common link,
//! with a warning. Only a choice that changes the joints needs a tip.
//!
//! Fixed joints are folded into their neighbours' transforms (into the base
//! transform before the first moving joint and into the tool transform after
//! the last). `revolute`, `continuous` and `prismatic` joints become joints of
//! the model with their `origin`, `axis` (any direction, also negative) and
//! `limit` (position, `velocity` and `effort`; 0 counts as unknown); a
//! revolute or prismatic joint on the chain without `<limit>` is an error, as
//! is a joint on the chain with `<mimic>` (kinema has no coupled joints).
//! Anything else on the path (`floating`, `planar`, `spherical`) is an error.
//!
//! Mass properties (`<inertial>`) are read per moving joint: those of its
//! child link and of every link rigidly attached to it — through fixed joints,
//! and through joints off the chain, which are held at 0 — expressed in the
//! child link frame (kinema's link frame for that joint) and combined by the
//! parallel-axis theorem. A link on the chain with a non-physical inertial is
//! an error; one off the chain is left out with a warning
//! ([`Metadata::warnings`]). A URDF in which no link has mass or inertia
//! gives a robot without mass properties.
//!
//! `<visual>`, `<collision>` and `<material>` elements are not read (they are
//! cut out before urdf-rs parses the rest), so their oddities, such as an
//! empty `<texture/>`, do not stop a load. An element urdf-rs cannot read is
//! reported with its line.

use std::collections::{HashMap, HashSet};
use std::ops::Range;

use nalgebra::Vector3;
use quick_xml::events::{BytesStart, Event};

use crate::error::{Error, ModelError, Result};
use crate::math::{Pose, RpyConvention};
use crate::model::{GeometryKind, Inertial, Joint, JointType, Limits, LinkGeometry, Metadata, Model};
use crate::robot::Robot;

/// Parses a URDF document and extracts the chain from its root link to `tip`
/// (default: the only leaf link reached through moving joints, see the module
/// documentation). `file` is used in messages only.
pub fn robot_from_urdf(text: &str, file: &str, tip: Option<&str>) -> Result<Robot> {
    robot_and_links_from_urdf(text, file, tip).map(|(robot, _)| robot)
}

/// Where one URDF `<link>` rides on the robot imported from its file: the
/// kinema link it is rigidly fixed to and its pose there. Link geometry
/// (`<collision>`, `<visual>`) is placed with it.
#[derive(Debug, Clone, PartialEq)]
pub struct UrdfLink {
    /// The URDF link's name.
    pub name: String,
    /// The kinema link (index of [`crate::kin::link_frames_into`]'s frames)
    /// it is fixed to: 0 for the base (links before the first moving joint),
    /// i for the body moved by joint i. Links after a fixed joint fold into
    /// their parent's body, and links off the chain are carried with their
    /// joints held at 0, as the mass properties are.
    pub link: usize,
    /// The URDF link frame in that kinema link frame.
    pub link_from_urdf: Pose,
}

/// As [`robot_from_urdf`], and where each `<link>` of the document rides
/// (in document order; see [`UrdfLink`]).
pub fn robot_and_links_from_urdf(text: &str, file: &str, tip: Option<&str>) -> Result<(Robot, Vec<UrdfLink>)> {
    let err = |message: String| Error::Model(ModelError::Urdf { file: file.to_string(), message });
    let scan = Scan::new(text, file)?;
    let u = urdf_rs::read_from_string(&scan.kept(0..text.len())).map_err(|e| scan.locate(file, e))?;
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
    // The joints from the root down to `link`.
    let path_to = |link: &str| -> Result<Vec<&urdf_rs::Joint>> {
        let mut path = Vec::new();
        let mut at = link;
        while let Some(j) = by_child.get(at) {
            if path.len() > u.joints.len() {
                return Err(err("the joints form a cycle".into()));
            }
            path.push(*j);
            at = j.parent.link.as_str();
        }
        path.reverse();
        Ok(path)
    };
    let mut warnings = Vec::new();
    let tip = match tip {
        Some(t) => {
            if !links.contains(&t) {
                return Err(err(format!("tip link `{t}` is not in the URDF; its links are: {}", links.join(", "))));
            }
            t
        }
        None => {
            let leaves: Vec<&str> = links.iter().copied().filter(|l| !parents.contains(l)).collect();
            default_tip(&leaves, &path_to, &mut warnings).map_err(err)?
        }
    };
    let path = path_to(tip)?;

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
        let at = scan.joint(&j.name);
        if let Some(m) = &j.mimic {
            return Err(Error::Model(ModelError::MimicJoint {
                file: file.to_string(),
                line: at.map_or(0, |e| e.line),
                joint: j.name.clone(),
                follows: m.joint.clone(),
                multiplier: m.multiplier.unwrap_or(1.0),
                offset: m.offset.unwrap_or(0.0),
            }));
        }
        let axis = Vector3::from(*j.axis.xyz);
        let norm = axis.norm();
        if !(norm > 1e-12 && norm.is_finite()) {
            return Err(err(format!("joint `{}`: axis {:?} has no direction", j.name, *j.axis.xyz)));
        }
        let limits = if j.joint_type == urdf_rs::JointType::Continuous {
            Limits::unbounded()
        } else {
            // urdf-rs reads a missing <limit> as all zeros: a locked joint nobody asked for.
            if let Some(e) = at.filter(|e| !e.has_limit) {
                let kind = if kind == JointType::Revolute { "revolute" } else { "prismatic" };
                return Err(Error::Model(ModelError::Description {
                    file: file.to_string(),
                    line: e.line,
                    column: e.column,
                    field: format!("<joint name=\"{}\">", j.name),
                    message: format!(
                        "a {kind} joint needs a <limit lower=\"…\" upper=\"…\" effort=\"…\" velocity=\"…\"/> element \
                         (the URDF format requires it; without one its range would be [0, 0]){}",
                        if kind == "revolute" { "; a joint that turns without end is type=\"continuous\"" } else { "" }
                    ),
                }));
            }
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
    let inertials = inertials(&u, &path, &moving_children, file, &mut warnings)?;
    let home =
        joints.iter().map(|j| if j.limits.contains(0.0) { 0.0 } else { 0.5 * (j.limits.min + j.limits.max) }).collect();
    let name = if u.name.is_empty() { file.to_string() } else { u.name.clone() };
    let meta = Metadata {
        manufacturer: String::new(),
        source: format!("URDF {file}, chain {} → {tip}", roots[0]),
        notes: String::new(),
        warnings,
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
    let robot = Robot::new(model.build().map_err(|e| err(e.to_string()))?);
    let links = urdf_links(&u, &path, &by_child, robot.base());
    Ok((robot, links))
}

/// Where each link of `u` rides: walk up from the link to the nearest moving
/// joint of the chain (its child link frame is kinema's link frame), composing
/// the origins of the joints passed (fixed ones, and joints off the chain at
/// 0); a link that reaches the root rides on the base, whose frame is the
/// root's fixed transforms up to the first moving joint (`base`).
fn urdf_links(
    u: &urdf_rs::Robot,
    path: &[&urdf_rs::Joint],
    by_child: &HashMap<&str, &urdf_rs::Joint>,
    base: &Pose,
) -> Vec<UrdfLink> {
    let moving: Vec<&str> =
        path.iter().filter(|j| j.joint_type != urdf_rs::JointType::Fixed).map(|j| j.name.as_str()).collect();
    let base_from_root = base.inverse();
    u.links
        .iter()
        .map(|l| {
            let mut above_from_link = Pose::IDENTITY;
            let mut at = l.name.as_str();
            // A cycle was refused while the chain was read; the bound keeps this walk finite anyway.
            for _ in 0..=u.joints.len() {
                let Some(j) = by_child.get(at) else { break };
                if let Some(i) = moving.iter().position(|m| *m == j.name) {
                    return UrdfLink { name: l.name.clone(), link: i + 1, link_from_urdf: above_from_link };
                }
                above_from_link =
                    Pose::from_xyz_rpy(*j.origin.xyz, *j.origin.rpy, RpyConvention::Zyx) * above_from_link;
                at = j.parent.link.as_str();
            }
            UrdfLink { name: l.name.clone(), link: 0, link_from_urdf: base_from_root * above_from_link }
        })
        .collect()
}

/// One way to choose the tip: the leaves reached through the same moving joints.
struct Choice<'a> {
    moving: Vec<&'a str>,
    leaves: Vec<&'a str>,
    paths: Vec<Vec<&'a urdf_rs::Joint>>,
}

/// The tip when none is given: among the leaf links reached through at least
/// one moving joint, those reached through the same moving joints are one
/// choice (ending at their last common link); exactly one choice must remain.
/// The error is the message of an [`ModelError::Urdf`].
fn default_tip<'a>(
    leaves: &[&'a str],
    path_to: &dyn Fn(&str) -> Result<Vec<&'a urdf_rs::Joint>>,
    warnings: &mut Vec<String>,
) -> std::result::Result<&'a str, String> {
    if let [one] = leaves {
        return Ok(one);
    }
    let mut choices: Vec<Choice> = Vec::new(); // in document order
    for &leaf in leaves {
        let path = path_to(leaf).map_err(|e| match e {
            Error::Model(ModelError::Urdf { message, .. }) => message,
            other => other.to_string(),
        })?;
        let moving: Vec<&str> =
            path.iter().filter(|j| j.joint_type != urdf_rs::JointType::Fixed).map(|j| j.name.as_str()).collect();
        if moving.is_empty() {
            continue;
        }
        match choices.iter_mut().find(|c| c.moving == moving) {
            Some(c) => {
                c.leaves.push(leaf);
                c.paths.push(path);
            }
            None => choices.push(Choice { moving, leaves: vec![leaf], paths: vec![path] }),
        }
    }
    match choices.as_slice() {
        [] => Err(format!(
            "none of its {} leaf links ({}) is reached from the root through a moving joint; \
             a robot arm needs at least one revolute, continuous or prismatic joint",
            leaves.len(),
            leaves.join(", ")
        )),
        [c] if c.leaves.len() == 1 => Ok(c.leaves[0]),
        [c] => {
            // The paths share every joint down to the last moving one, and maybe fixed ones after it.
            let first = &c.paths[0];
            let common = (0..first.len())
                .take_while(|&i| c.paths.iter().all(|p| p.get(i).is_some_and(|j| j.name == first[i].name)))
                .count();
            let tip = first[common - 1].child.link.as_str();
            warnings.push(format!(
                "the leaf links {} are reached through the same moving joints; the chain ends at their last \
                 common link `{tip}` (choose one of them with --tip LINK to include its fixed transform)",
                c.leaves.join(", ")
            ));
            Ok(tip)
        }
        _ => {
            let tips: Vec<&str> = choices.iter().flat_map(|c| c.leaves.iter().copied()).collect();
            Err(format!(
                "the URDF is not a single serial chain: it has {} leaf links reached through different moving \
                 joints ({}); choose one with --tip LINK",
                tips.len(),
                tips.join(", ")
            ))
        }
    }
}

/// The parts of the XML that urdf-rs does not tell: where each top-level
/// `<link>` and `<joint>` is, whether a joint has a `<limit>`, and the
/// elements the loader does not read (`<visual>`, `<collision>`, `<material>`).
struct Scan<'a> {
    text: &'a str,
    /// The root element's start tag (`<robot name=… …>`).
    root_tag: Range<usize>,
    elements: Vec<Element>,
    /// Byte ranges cut out before urdf-rs reads the text; sorted, disjoint.
    skipped: Vec<Range<usize>>,
}

/// A top-level `<link>` or `<joint>` element.
struct Element {
    tag: String,
    name: String,
    range: Range<usize>,
    line: usize,
    column: usize,
    has_limit: bool,
}

impl<'a> Scan<'a> {
    fn new(text: &'a str, file: &str) -> Result<Self> {
        let mut reader = quick_xml::Reader::from_str(text);
        let mut scan = Scan { text, root_tag: 0..0, elements: Vec::new(), skipped: Vec::new() };
        // Open elements: (tag, start byte).
        let mut open: Vec<(Vec<u8>, usize)> = Vec::new();
        loop {
            let start = reader.buffer_position() as usize;
            let event = reader.read_event().map_err(|e| {
                let (line, column) = line_column(text, reader.error_position() as usize);
                Error::Model(ModelError::Description {
                    file: file.to_string(),
                    line,
                    column,
                    field: "XML".into(),
                    message: format!("not well-formed XML: {e}"),
                })
            })?;
            let end = reader.buffer_position() as usize;
            match event {
                Event::Start(s) => {
                    scan.opened(&s, open.len() + 1, start, end);
                    open.push((s.name().as_ref().to_vec(), start));
                }
                Event::Empty(s) => {
                    scan.opened(&s, open.len() + 1, start, end);
                    scan.closed(s.name().as_ref(), open.len() + 1, open.get(1).map(|o| o.0.as_slice()), start..end);
                }
                Event::End(_) => {
                    if let Some((tag, start)) = open.pop() {
                        let parent = open.get(1).map(|o| o.0.as_slice());
                        scan.closed(&tag, open.len() + 1, parent, start..end);
                    }
                }
                Event::Eof => break,
                _ => {}
            }
        }
        Ok(scan)
    }

    /// An element starts at `depth` (the root is 1).
    fn opened(&mut self, s: &BytesStart, depth: usize, start: usize, end: usize) {
        let tag = s.name();
        match (depth, tag.as_ref()) {
            (1, _) => self.root_tag = start..end,
            (2, b"link" | b"joint") => {
                let name = match s.try_get_attribute("name") {
                    Ok(Some(a)) => a.unescape_value().map(|v| v.into_owned()).unwrap_or_default(),
                    _ => String::new(),
                };
                let (line, column) = line_column(self.text, start);
                self.elements.push(Element {
                    tag: String::from_utf8_lossy(tag.as_ref()).into_owned(),
                    name,
                    range: start..start,
                    line,
                    column,
                    has_limit: false,
                });
            }
            (3, b"limit") => {
                if let Some(e) = self.elements.last_mut().filter(|e| e.range.is_empty() && e.tag == "joint") {
                    e.has_limit = true;
                }
            }
            _ => {}
        }
    }

    /// An element at `depth` ends; `parent` is the tag of the element that
    /// holds it when that is a top-level one.
    fn closed(&mut self, tag: &[u8], depth: usize, parent: Option<&[u8]>, range: Range<usize>) {
        match (depth, tag) {
            (2, b"link" | b"joint") => {
                if let Some(e) = self.elements.last_mut().filter(|e| e.range.is_empty()) {
                    e.range = range;
                }
            }
            (2, b"material") => self.skipped.push(range),
            (3, b"visual" | b"collision") if parent == Some(b"link") => self.skipped.push(range),
            _ => {}
        }
    }

    /// The text of `range` without the skipped elements in it.
    fn kept(&self, range: Range<usize>) -> String {
        let mut out = String::with_capacity(range.len());
        let mut at = range.start;
        for s in self.skipped.iter().filter(|s| s.start >= range.start && s.end <= range.end) {
            out.push_str(&self.text[at..s.start]);
            at = s.end;
        }
        out.push_str(&self.text[at..range.end]);
        out
    }

    /// The first top-level `<joint>` named `name`.
    fn joint(&self, name: &str) -> Option<&Element> {
        self.elements.iter().find(|e| e.tag == "joint" && e.name == name)
    }

    /// urdf-rs's error, at the first `<link>` or `<joint>` it cannot read on
    /// its own (its messages name a field but no element or line).
    fn locate(&self, file: &str, e: urdf_rs::UrdfError) -> Error {
        let clean = |m: String| m.strip_prefix("custom: ").map(str::to_string).unwrap_or(m);
        let whole = || {
            Error::Model(ModelError::Urdf {
                file: file.to_string(),
                message: format!("not a readable URDF document: {}", clean(e.to_string())),
            })
        };
        // Each element is tried alone under the document's own root tag (its version, namespaces).
        let root = &self.text[self.root_tag.clone()];
        if root.is_empty() || root.ends_with("/>") {
            return whole();
        }
        let closing =
            root.strip_prefix('<').and_then(|r| r.split(|c: char| c.is_whitespace() || c == '>').next()).unwrap_or("");
        for el in self.elements.iter().filter(|el| !el.range.is_empty()) {
            let one = format!("{root}{}</{closing}>", self.kept(el.range.clone()));
            if let Err(why) = urdf_rs::read_from_string(&one) {
                return Error::Model(ModelError::Description {
                    file: file.to_string(),
                    line: el.line,
                    column: el.column,
                    field: format!("<{} name=\"{}\">", el.tag, el.name),
                    message: format!(
                        "not a readable <{}> element: {}; expected one as the URDF format defines it",
                        el.tag,
                        clean(why.to_string())
                    ),
                });
            }
        }
        whole()
    }
}

/// 1-based line and column (in characters) of byte `at` of `text`.
fn line_column(text: &str, at: usize) -> (usize, usize) {
    let mut at = at.min(text.len());
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

/// The mass properties of each moving joint's body, in its child link frame
/// (see the module documentation); `None` if no link of the URDF has any.
fn inertials(
    u: &urdf_rs::Robot,
    path: &[&urdf_rs::Joint],
    moving_children: &[&str],
    file: &str,
    warnings: &mut Vec<String>,
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
    let on_chain: HashSet<&str> = path.iter().map(|j| j.child.link.as_str()).collect();
    let mut out = Vec::with_capacity(moving_children.len());
    for &child in moving_children {
        let mut body = Inertial::ZERO;
        // (link, child_from_link), depth first.
        let mut stack = vec![(child, Pose::IDENTITY)];
        let mut visited = 0usize;
        while let Some((name, child_from_link)) = stack.pop() {
            visited += 1;
            if visited > u.links.len() + 1 {
                return Err(Error::Model(ModelError::Urdf {
                    file: file.to_string(),
                    message: "the joints form a cycle".into(),
                }));
            }
            if let Some(l) = link_by_name.get(name) {
                let o = &l.inertial.origin;
                let link_from_inertial = Pose::from_xyz_rpy(*o.xyz, *o.rpy, RpyConvention::Zyx);
                let i = &l.inertial.inertia;
                match Inertial::new(
                    l.inertial.mass.value,
                    nalgebra::Vector3::zeros(),
                    [i.ixx, i.iyy, i.izz, i.ixy, i.ixz, i.iyz],
                ) {
                    Ok(own) => body = body.combined(&own.transformed(&(child_from_link * link_from_inertial))),
                    Err(e) if on_chain.contains(name) => {
                        return Err(Error::Model(ModelError::Urdf {
                            file: file.to_string(),
                            message: format!("link `{name}` (on the chain): <inertial>: {e}"),
                        }))
                    }
                    // Off the chain it only adds to a body's mass: leave it out and say so.
                    Err(e) => warnings.push(format!(
                        "link `{name}` (off the chain, carried by `{child}`): <inertial>: {e}; its mass properties are left out"
                    )),
                }
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
