//! Allowed collisions as MoveIt writes them: the `<disable_collisions>`
//! entries of an SRDF, read ([`Srdf::from_str`], [`Srdf::load`]), applied to a
//! pair list ([`Srdf::apply`]), generated the way MoveIt's setup assistant
//! does ([`generate_srdf`]) and written back ([`Srdf::to_xml`]).
//!
//! Entries name URDF links. A shape keeps the name of the URDF link it was
//! declared on ([`crate::LinkShape::link_name`]) even when that link is fixed
//! to its parent and so folded onto the parent's body, so an entry disables
//! exactly the shapes Pinocchio's `removeCollisionPairs` would.

use std::collections::BTreeSet;
use std::path::Path;

use quick_xml::events::{BytesStart, Event};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use kinema::{Robot, UrdfLink};

use crate::error::{Error, Result};
use crate::geometry::RobotGeometry;
use crate::pairs::CollisionPairs;
use crate::placement::{place, Placement};
use crate::query::{aabb_gap, pair_hits};

/// One `<disable_collisions link1="…" link2="…" reason="…"/>` entry.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DisabledPair {
    /// First URDF link name.
    pub link1: String,
    /// Second URDF link name.
    pub link2: String,
    /// Why the pair is never checked (MoveIt's words: `Adjacent`, `Default`,
    /// `Never`, `Always`, `User`); kept as the file gives it.
    pub reason: String,
}

/// The allowed-collision part of an SRDF: the robot's name and its
/// `<disable_collisions>` entries in file order (other elements are ignored).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Srdf {
    /// The `name` of the `<robot>` element (empty if none).
    pub robot: String,
    /// The entries.
    pub disabled: Vec<DisabledPair>,
}

impl Srdf {
    /// Reads an SRDF file (at most [`kinema::MAX_DESCRIPTION_BYTES`]).
    pub fn load(path: impl AsRef<Path>) -> Result<Srdf> {
        let path = path.as_ref();
        let shown = path.display().to_string();
        let text = kinema::read_bounded_text(path, "an SRDF", kinema::MAX_DESCRIPTION_BYTES)?;
        Srdf::from_str(&text, &shown)
    }

    /// Reads the text of an SRDF; `file` names it in errors.
    ///
    /// # Examples
    /// ```
    /// let srdf = kinema_geometry::Srdf::from_str(
    ///     r#"<robot name="arm"><disable_collisions link1="a" link2="b" reason="Never"/></robot>"#,
    ///     "<string>",
    /// )?;
    /// assert_eq!(srdf.robot, "arm");
    /// assert_eq!((srdf.disabled[0].link1.as_str(), srdf.disabled[0].reason.as_str()), ("a", "Never"));
    /// # Ok::<(), kinema_geometry::Error>(())
    /// ```
    #[allow(clippy::should_implement_trait)] // two arguments: the file name is part of every error
    pub fn from_str(text: &str, file: &str) -> Result<Srdf> {
        let bad = |message: String| Error::Srdf { file: file.to_string(), message };
        let mut reader = quick_xml::Reader::from_str(text);
        let mut out = Srdf::default();
        let mut depth = 0usize;
        loop {
            let event = reader.read_event().map_err(|e| {
                let (line, column) = line_column(text, reader.error_position() as usize);
                bad(format!("line {line}, column {column}: not well-formed XML: {e}"))
            })?;
            let (element, empty) = match &event {
                Event::Start(e) => (e, false),
                Event::Empty(e) => (e, true),
                Event::End(_) => {
                    depth = depth.saturating_sub(1);
                    continue;
                }
                Event::Eof => break,
                _ => continue,
            };
            let at = reader.buffer_position() as usize;
            match (depth, element.name().as_ref()) {
                (0, b"robot") => out.robot = attribute(element, "name", text, at, &bad)?.unwrap_or_default(),
                (0, other) => {
                    return Err(bad(format!(
                        "the root element is <{}>; an SRDF's root element is <robot>",
                        String::from_utf8_lossy(other)
                    )))
                }
                (_, b"disable_collisions") => {
                    let need = |name: &str| {
                        attribute(element, name, text, at, &bad)?.ok_or_else(|| {
                            let (line, _) = line_column(text, at);
                            bad(format!("line {line}: <disable_collisions> has no `{name}` attribute"))
                        })
                    };
                    let (link1, link2) = (need("link1")?, need("link2")?);
                    let reason = attribute(element, "reason", text, at, &bad)?.unwrap_or_default();
                    out.disabled.push(DisabledPair { link1, link2, reason });
                }
                _ => {}
            }
            if !empty {
                depth += 1;
            }
        }
        Ok(out)
    }

    /// The SRDF text: a `<robot>` element holding one `<disable_collisions>`
    /// line per entry, as MoveIt's setup assistant writes it.
    pub fn to_xml(&self) -> String {
        let mut out = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
        out += &format!("<robot name=\"{}\">\n", escape(&self.robot));
        for d in &self.disabled {
            out += &format!(
                "    <disable_collisions link1=\"{}\" link2=\"{}\" reason=\"{}\"/>\n",
                escape(&d.link1),
                escape(&d.link2),
                escape(&d.reason)
            );
        }
        out + "</robot>\n"
    }

    /// Removes every entry's link pair from `pairs` (shapes of `geometry`)
    /// and returns how many shape pairs went. `links` are the URDF's links
    /// ([`crate::UrdfRobot::links`]); an entry naming a link that is neither
    /// there nor on a shape of `geometry` is an error that lists the known
    /// names (an SRDF for another robot, most often).
    pub fn apply(&self, geometry: &RobotGeometry, links: &[UrdfLink], pairs: &mut CollisionPairs) -> Result<usize> {
        let known: BTreeSet<&str> =
            links.iter().map(|l| l.name.as_str()).chain(geometry.shapes().iter().map(|s| s.link_name())).collect();
        for d in &self.disabled {
            for name in [&d.link1, &d.link2] {
                if !known.contains(name.as_str()) {
                    return Err(Error::Srdf {
                        file: format!("the SRDF of `{}`", self.robot),
                        message: format!(
                            "<disable_collisions> names link `{name}`, which robot `{}` does not have; its links are: {}",
                            geometry.robot(),
                            known.iter().copied().collect::<Vec<_>>().join(", ")
                        ),
                    });
                }
            }
        }
        Ok(self.disabled.iter().map(|d| pairs.disable_links(geometry, &d.link1, &d.link2)).sum())
    }

    /// The link pairs of the entries, each as (lower name, higher name).
    pub fn link_pairs(&self) -> BTreeSet<(String, String)> {
        self.disabled
            .iter()
            .map(|d| {
                let (a, b) = (d.link1.clone(), d.link2.clone());
                if a <= b {
                    (a, b)
                } else {
                    (b, a)
                }
            })
            .collect()
    }
}

/// The allowed-collision matrix of `geometry` on `robot`, found the way
/// MoveIt's setup assistant finds it, over pairs of URDF links that carry
/// shapes (each pair listed once, with the first reason that applies):
///
/// 1. `Adjacent`: links on the same body or on bodies next to each other on
///    the chain (they touch at their joint by construction);
/// 2. `Default`: links in collision at the robot's home configuration;
/// 3. `Always`: links in collision at every one of `samples` seeded random
///    configurations (within the joint limits);
/// 4. `Never`: links in collision at none of them.
///
/// Pairs seen both in and out of collision stay checked. More samples make
/// `Never` more trustworthy (MoveIt's default density is 10 000).
pub fn generate_srdf(robot: &Robot, geometry: &RobotGeometry, samples: usize, seed: u64) -> Result<Srdf> {
    // The URDF links that carry shapes: (name, kinema link, shape indices).
    let mut groups: Vec<(String, usize, Vec<usize>)> = Vec::new();
    for (i, s) in geometry.shapes().iter().enumerate() {
        match groups.iter_mut().find(|g| g.0 == s.link_name()) {
            Some(g) => g.2.push(i),
            None => groups.push((s.link_name().to_string(), s.link(), vec![i])),
        }
    }
    let mut out = Srdf { robot: robot.name().to_string(), disabled: Vec::new() };
    let mut open = Vec::new();
    for (a, ga) in groups.iter().enumerate() {
        for (b, gb) in groups.iter().enumerate().skip(a + 1) {
            if ga.1.abs_diff(gb.1) <= 1 {
                out.disabled.push(entry(ga, gb, "Adjacent"));
            } else {
                open.push((a, b));
            }
        }
    }
    let mut placement = Placement::new(geometry);
    let hit = |placement: &Placement, a: usize, b: usize| -> Result<bool> {
        for &i in &groups[a].2 {
            for &j in &groups[b].2 {
                if aabb_gap(placement.aabb(i), placement.aabb(j)) <= 0.0 && pair_hits(geometry, placement, i, j, 0.0)? {
                    return Ok(true);
                }
            }
        }
        Ok(false)
    };
    place(robot, geometry, robot.home(), &mut placement)?;
    let mut still = Vec::new();
    for (a, b) in open {
        if hit(&placement, a, b)? {
            out.disabled.push(entry(&groups[a], &groups[b], "Default"));
        } else {
            still.push((a, b, 0usize));
        }
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut q = vec![0.0; robot.dof()];
    for n in 0..samples {
        robot.random_q_into(&mut rng, &mut q);
        place(robot, geometry, &q, &mut placement)?;
        for (a, b, count) in &mut still {
            // A pair seen both in and out of collision is decided: checked.
            let undecided = *count == 0 || *count == n;
            if undecided && hit(&placement, *a, *b)? {
                *count += 1;
            }
        }
    }
    for (a, b, count) in still {
        if samples > 0 && count == samples {
            out.disabled.push(entry(&groups[a], &groups[b], "Always"));
        } else if count == 0 {
            out.disabled.push(entry(&groups[a], &groups[b], "Never"));
        }
    }
    Ok(out)
}

fn entry(a: &(String, usize, Vec<usize>), b: &(String, usize, Vec<usize>), reason: &str) -> DisabledPair {
    DisabledPair { link1: a.0.clone(), link2: b.0.clone(), reason: reason.to_string() }
}

fn attribute(
    element: &BytesStart,
    name: &str,
    text: &str,
    at: usize,
    bad: &dyn Fn(String) -> Error,
) -> Result<Option<String>> {
    let invalid = |e: String| {
        let (line, _) = line_column(text, at);
        bad(format!("line {line}: attribute `{name}`: {e}"))
    };
    match element.try_get_attribute(name).map_err(|e| invalid(e.to_string()))? {
        None => Ok(None),
        Some(a) => Ok(Some(a.unescape_value().map_err(|e| invalid(e.to_string()))?.into_owned())),
    }
}

/// 1-based line and column of byte `at`.
fn line_column(text: &str, at: usize) -> (usize, usize) {
    let before = &text[..at.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    (line, column)
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}
