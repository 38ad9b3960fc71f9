//! One robot with its body, in a scene: what every door (`kinema collide`,
//! `kinema ik --scene`, Python, the server) checks a configuration against,
//! loaded the same way everywhere.

use std::path::PathBuf;

use kinema::ik::{Admissible, Assessment, Rejection};
use kinema::Robot;

use crate::error::{Error, Result};
use crate::geometry::RobotGeometry;
use crate::pairs::CollisionPairs;
use crate::placement::{place, Placement};
use crate::query::{collides, contacts, min_distance, Proximity};
use crate::robot_toml::{is_urdf, load_robot_geometry};
use crate::scene::Scene;
use crate::srdf::Srdf;
use crate::sweep::{LeverArms, Segment, SweptContact};
use crate::urdf::{load_urdf, ros_package_path, UrdfOptions};

/// Where a [`CollisionCheck`]'s parts come from.
#[derive(Debug, Clone, Default)]
pub struct CheckOptions {
    /// A URDF's tip link.
    pub tip: Option<String>,
    /// Directories holding the packages of `package://` meshes
    /// (`ROS_PACKAGE_PATH` is added after them).
    pub package_paths: Vec<PathBuf>,
    /// A scene file whose obstacles are checked against the robot's moving links.
    pub scene: Option<PathBuf>,
    /// An SRDF whose `<disable_collisions>` pairs are not checked.
    pub srdf: Option<PathBuf>,
    /// Safety margin \[m, ≥ 0\]: pairs closer than this count as colliding.
    pub margin: f64,
}

/// A robot, its shapes (and a scene's obstacles), the pairs to check and a
/// safety margin. Immutable and shareable across threads; every query
/// places the shapes into a [`Placement`] the caller owns (or one made for
/// the call).
#[derive(Debug, Clone)]
pub struct CollisionCheck {
    robot: Robot,
    geometry: RobotGeometry,
    pairs: CollisionPairs,
    margin: f64,
    arms: LeverArms,
}

impl CollisionCheck {
    /// The check of `pairs` of `geometry` (made for `robot`) with `margin`.
    pub fn new(robot: Robot, geometry: RobotGeometry, pairs: CollisionPairs, margin: f64) -> Result<CollisionCheck> {
        if !(margin >= 0.0 && margin.is_finite()) {
            return Err(Error::Kinema(kinema::Error::Input(kinema::InputError::OutOfRange {
                what: "margin".into(),
                value: margin,
                expected: "a finite distance ≥ 0 m".into(),
            })));
        }
        if pairs.shape_count() != geometry.len() {
            return Err(Error::Mismatch {
                what: "the pair list".into(),
                got: pairs.shape_count(),
                expected: geometry.len(),
            });
        }
        let arms = LeverArms::new(&robot, &geometry)?;
        Ok(CollisionCheck { robot, geometry, pairs, margin, arms })
    }

    /// Loads robot `spec` (a built-in name, a `.toml` or a `.urdf`) with its
    /// collision shapes, checks its self-collision pairs (less those an SRDF
    /// disables) and, with a scene, every moving link against every obstacle
    /// and every scene robot where it stands ([`Scene::standing`]). `spec`
    /// may name one of the scene's robots: that robot, on its base there.
    /// A robot without shapes is an error: there would be nothing to check.
    ///
    /// # Examples
    /// ```
    /// use kinema_geometry::{CheckOptions, CollisionCheck};
    /// let check = CollisionCheck::load("lbr-iiwa-14-r820", &CheckOptions::default())?;
    /// let home = check.robot().home().to_vec();
    /// assert_eq!(check.first_collision(&home)?, None);
    /// # Ok::<(), kinema_geometry::Error>(())
    /// ```
    pub fn load(spec: &str, options: &CheckOptions) -> Result<CollisionCheck> {
        let mut package_paths = options.package_paths.clone();
        package_paths.extend(ros_package_path());
        let urdf = UrdfOptions { tip: options.tip.clone(), package_paths, skip_visual: true };
        let scene = options.scene.as_deref().map(Scene::load).transpose()?;
        // A robot named as one of the scene's stands on its base there.
        let member = scene.as_ref().and_then(|s| s.member(spec));
        let (robot, geometry) = match member {
            Some(m) => m.load(&urdf)?,
            None => load_robot_geometry(spec, &urdf)?,
        };
        let description = member.map_or(spec, |m| m.robot.as_str());
        if geometry.is_empty() {
            return Err(Error::Shape {
                name: robot.name().to_string(),
                message: format!(
                    "robot `{spec}` has no link shapes to check; add [[shape]] tables (TOML) or <collision> elements (URDF)"
                ),
            });
        }
        let mut pairs = CollisionPairs::self_collision(&geometry);
        if let Some(path) = &options.srdf {
            let links = if is_urdf(description) { load_urdf(description, &urdf)?.links } else { Vec::new() };
            Srdf::load(path)?.apply(&geometry, &links, &mut pairs)?;
        }
        let standing = scene.as_ref().map(|s| s.standing(member.map(|m| m.name.as_str()), &urdf)).transpose()?;
        CollisionCheck::with_scene(robot, geometry, pairs, standing.as_ref(), options.margin)
    }

    /// The check of the robot's `pairs` and, with a scene, of every moving
    /// link against every obstacle of it (its robots count once
    /// [`Scene::standing`] has made them obstacles).
    pub fn with_scene(
        robot: Robot,
        geometry: RobotGeometry,
        pairs: CollisionPairs,
        scene: Option<&Scene>,
        margin: f64,
    ) -> Result<CollisionCheck> {
        let (geometry, pairs) = match scene {
            Some(scene) => scene.with_robot(&robot, &geometry, &pairs)?,
            None => (geometry, pairs),
        };
        CollisionCheck::new(robot, geometry, pairs, margin)
    }

    /// The robot.
    pub fn robot(&self) -> &Robot {
        &self.robot
    }

    /// The shapes: the robot's, then the scene's obstacles.
    pub fn geometry(&self) -> &RobotGeometry {
        &self.geometry
    }

    /// The pairs checked.
    pub fn pairs(&self) -> &CollisionPairs {
        &self.pairs
    }

    /// The safety margin \[m\].
    pub fn margin(&self) -> f64 {
        self.margin
    }

    /// A placement to reuse across queries (one per thread).
    pub fn placement(&self) -> Placement {
        Placement::new(&self.geometry)
    }

    /// The body shape `index` belongs to: its link's name, or its obstacle's.
    pub fn body(&self, index: usize) -> &str {
        self.geometry.shapes()[index].link_name()
    }

    /// Places the shapes at `q` (checked against the robot's joints).
    pub fn place(&self, q: &[f64], placement: &mut Placement) -> Result<()> {
        place(&self.robot, &self.geometry, q, placement).map(|_| ())
    }

    /// The first checked pair closer than the margin at `q`, by shape index.
    pub fn first_collision(&self, q: &[f64]) -> Result<Option<(usize, usize)>> {
        let mut placement = self.placement();
        self.place(q, &mut placement)?;
        collides(&self.geometry, &placement, &self.pairs, self.margin)
    }

    /// The first contact on the straight joint-space segment `from` → `to`
    /// (both checked against the robot's joints), certified by conservative
    /// advancement: no contact between the two is missed; a pair within
    /// [`CONTACT_TOLERANCE`](crate::CONTACT_TOLERANCE) of the margin counts.
    pub fn first_contact_between(
        &self,
        from: &[f64],
        to: &[f64],
        placement: &mut Placement,
    ) -> Result<Option<SweptContact>> {
        self.robot.check_q(from)?;
        self.robot.check_q(to)?;
        self.segment().first_contact(from, to, placement)
    }

    /// The lever arms bounding how far each shape moves on a joint step.
    pub(crate) fn arms(&self) -> &LeverArms {
        &self.arms
    }

    /// What the continuous check of one segment needs.
    pub(crate) fn segment(&self) -> Segment<'_> {
        Segment {
            robot: &self.robot,
            geometry: &self.geometry,
            pairs: &self.pairs,
            arms: &self.arms,
            margin: self.margin,
        }
    }

    /// Every body pair closer than the margin in the placed configuration,
    /// each once (by link or obstacle name), in check order.
    pub fn colliding_bodies(&self, placement: &Placement) -> Result<Vec<(String, String)>> {
        let mut bodies: Vec<(String, String)> = Vec::new();
        for p in contacts(&self.geometry, placement, &self.pairs, self.margin)? {
            let pair = (self.body(p.a).to_string(), self.body(p.b).to_string());
            if !bodies.contains(&pair) {
                bodies.push(pair);
            }
        }
        Ok(bodies)
    }

    /// The closest checked pair in the placed configuration (`None` when no
    /// pair is checked).
    pub fn closest(&self, placement: &Placement) -> Result<Option<Proximity>> {
        min_distance(&self.geometry, placement, &self.pairs)
    }
}

fn to_core(e: Error) -> kinema::Error {
    match e {
        Error::Kinema(e) => e,
        other => kinema::Error::Input(kinema::InputError::DoesNotFit {
            what: "collision check".into(),
            reason: other.to_string(),
        }),
    }
}

/// A scene as IK's admissibility test: a configuration closer than the
/// margin to anything it is checked against is not a solution.
impl Admissible for CollisionCheck {
    fn rejects(&self, q: &[f64]) -> kinema::Result<Option<Rejection>> {
        let pair = self.first_collision(q).map_err(to_core)?;
        Ok(pair.map(|pair| self.rejection(pair)))
    }

    fn assess(&self, q: &[f64]) -> kinema::Result<Assessment> {
        let mut placement = self.placement();
        self.place(q, &mut placement).map_err(to_core)?;
        if let Some(pair) = collides(&self.geometry, &placement, &self.pairs, self.margin).map_err(to_core)? {
            return Ok(Assessment::Rejected(self.rejection(pair)));
        }
        let closest = self.closest(&placement).map_err(to_core)?;
        Ok(Assessment::Clear(closest.map_or(f64::INFINITY, |p| p.distance - self.margin)))
    }

    fn first_rejection_between(&self, from: &[f64], to: &[f64]) -> kinema::Result<Option<(f64, Rejection)>> {
        let contact = self.first_contact_between(from, to, &mut self.placement()).map_err(to_core)?;
        Ok(contact.map(|c| (c.fraction, self.rejection(c.pair))))
    }
}

impl CollisionCheck {
    /// A colliding pair of shapes as IK's rejection, by body name.
    fn rejection(&self, (a, b): (usize, usize)) -> Rejection {
        Rejection { kind: "collision", detail: format!("{} – {}", self.body(a), self.body(b)) }
    }
}
