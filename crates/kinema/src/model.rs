//! The robot model: an immutable serial chain of revolute and prismatic joints.
//!
//! A link can be described in three ways ([`LinkGeometry`]): standard DH
//! (Spong/Corke), modified DH (Craig), or a general fixed transform followed by
//! a motion along/about a joint axis (URDF). All three are compiled on
//! construction of a [`Robot`](crate::Robot) into one form that forward
//! kinematics and Jacobians run on (see the private `chain` module).
//!
//! [`Model`] is the plain, validated description; it depends on nothing but
//! the spatial math. What is derived from it lives in [`crate::Robot`].

use nalgebra::{Matrix3, Vector3};

use crate::error::{Error, InputError, ModelError, Result};
use crate::math::Pose;

/// Largest number of joints a model may have (limit flags are a `u64` bit set).
pub const MAX_JOINTS: usize = 64;

/// Joint values \[rad or m\] and lengths in a robot's geometry \[m\] must
/// lie below this magnitude: it keeps every product kinema forms (Jacobians,
/// manipulability, mass matrices) finite, and 10⁹ m is farther than the Moon.
pub const MAX_MAGNITUDE: f64 = 1e9;

/// The error text for a translation (`what`) whose largest coordinate
/// `largest` \[m\] is at or beyond [`MAX_MAGNITUDE`].
fn check_length(what: &str, largest: f64) -> std::result::Result<(), String> {
    if largest < MAX_MAGNITUDE {
        return Ok(());
    }
    Err(format!("{what} has a coordinate of {largest:e} m; lengths must be below {MAX_MAGNITUDE:e} m"))
}

/// Revolute or prismatic.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum JointType {
    /// Rotation about the joint axis; the joint value is an angle \[rad\].
    Revolute,
    /// Translation along the joint axis; the joint value is a length \[m\].
    Prismatic,
}

impl JointType {
    /// One-letter code, `R` or `P` (as in "RRPR").
    pub fn letter(self) -> char {
        match self {
            JointType::Revolute => 'R',
            JointType::Prismatic => 'P',
        }
    }
}

/// Which Denavit–Hartenberg convention a table follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DhConvention {
    /// Spong/Corke: link i is Rz(θi)·Tz(di)·Tx(ai)·Rx(αi).
    Standard,
    /// Craig: link i is Rx(αi−1)·Tx(ai−1)·Rz(θi)·Tz(di); the table's row i holds
    /// αi−1 and ai−1.
    Modified,
}

/// How one link is described.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LinkGeometry {
    /// A row of a DH table. For a revolute joint θ = q + offset and `theta` is
    /// unused (0); for a prismatic joint d = q + offset and `d` is unused (0).
    Dh {
        /// Convention of the table.
        convention: DhConvention,
        /// Link offset d \[m\] (revolute joints).
        d: f64,
        /// Link length a \[m\].
        a: f64,
        /// Link twist α \[rad\].
        alpha: f64,
        /// Fixed joint angle θ \[rad\] (prismatic joints).
        theta: f64,
    },
    /// A fixed transform from the previous link frame to the joint frame, then a
    /// motion about/along `axis` (a unit vector in the joint frame) — URDF's model.
    General {
        /// `previous_link_from_joint` at q = 0 (URDF `origin`).
        origin: Pose,
        /// Unit joint axis in the joint frame (may point anywhere, also negative).
        axis: Vector3<f64>,
    },
}

/// Joint limits, all in SI (rad or m, per second …).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Lower position limit (may be −∞ for a continuous joint).
    pub min: f64,
    /// Upper position limit (may be +∞ for a continuous joint).
    pub max: f64,
    /// Velocity limit \[rad/s or m/s\], if known.
    pub vel: Option<f64>,
    /// Acceleration limit \[rad/s² or m/s²\], if known.
    pub acc: Option<f64>,
    /// Jerk limit \[rad/s³ or m/s³\], if known.
    pub jerk: Option<f64>,
    /// Motor effort limit: the largest |τ| the joint's drive delivers \[N·m for a revolute
    /// joint, N for a prismatic one\], if known.
    pub effort: Option<f64>,
}

impl Limits {
    /// Position limits only.
    pub fn position(min: f64, max: f64) -> Self {
        Limits { min, max, vel: None, acc: None, jerk: None, effort: None }
    }
    /// No limits at all (a continuous joint).
    pub fn unbounded() -> Self {
        Self::position(f64::NEG_INFINITY, f64::INFINITY)
    }
    /// Whether `v` lies within \[min, max\].
    pub fn contains(&self, v: f64) -> bool {
        v >= self.min && v <= self.max
    }
}

/// One joint with the link it moves.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    /// Name (e.g. `A1`, `shoulder`).
    pub name: String,
    /// Revolute or prismatic.
    pub kind: JointType,
    /// How the link is described.
    pub geometry: LinkGeometry,
    /// Joint offset: θ = q + offset \[rad\] or d = q + offset \[m\].
    pub offset: f64,
    /// Limits on the joint value q (not on θ).
    pub limits: Limits,
}

/// Mass properties of one link — the body that joint i moves — in that
/// link's frame (the frame [`Robot::link_frames`](crate::Robot::link_frames) returns for link i: DH frame
/// i, or the URDF child link frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inertial {
    /// Mass \[kg\] (≥ 0).
    pub mass: f64,
    /// Centre of mass in the link frame \[m\].
    pub com: Vector3<f64>,
    /// Inertia tensor about the centre of mass, in the axes of the link frame
    /// \[kg·m²\]; symmetric positive semi-definite, principal moments obeying
    /// the triangle inequalities.
    pub inertia: Matrix3<f64>,
}

impl Inertial {
    /// A massless link.
    pub const ZERO: Inertial = Inertial {
        mass: 0.0,
        com: Vector3::new(0.0, 0.0, 0.0),
        inertia: Matrix3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
    };

    /// Builds and validates mass properties: `mass` \[kg\], `com` \[m\] and the
    /// six inertia values `[ixx, iyy, izz, ixy, ixz, iyz]` \[kg·m²\] about the
    /// centre of mass (the products as they stand in the tensor, I = \[\[ixx ixy
    /// ixz\] \[ixy iyy iyz\] \[ixz iyz izz\]\], as in URDF). Errors
    /// ([`InputError::NotFinite`], [`InputError::OutOfRange`]) if a value is not finite, the mass is
    /// negative, or the tensor is not physical (a negative principal moment, or
    /// one larger than the sum of the other two, beyond 10⁻⁹ of the trace).
    ///
    /// # Examples
    /// ```
    /// use kinema::{Inertial, nalgebra::Vector3};
    /// let rod = Inertial::new(2.0, Vector3::new(0.5, 0.0, 0.0), [0.0, 1.0 / 6.0, 1.0 / 6.0, 0.0, 0.0, 0.0])?;
    /// assert_eq!(rod.inertia[(1, 1)], 1.0 / 6.0);
    /// assert!(Inertial::new(1.0, Vector3::zeros(), [1.0, 1.0, 3.0, 0.0, 0.0, 0.0]).is_err());
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn new(mass: f64, com: Vector3<f64>, inertia: [f64; 6]) -> Result<Inertial> {
        let [ixx, iyy, izz, ixy, ixz, iyz] = inertia;
        let i = Inertial { mass, com, inertia: Matrix3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz) };
        i.validate()?;
        Ok(i)
    }

    /// The checks of [`Inertial::new`] (and symmetry of the tensor), for
    /// values built field by field.
    pub fn validate(&self) -> Result<()> {
        let (mass, com, i) = (self.mass, self.com, self.inertia);
        let six = [i[(0, 0)], i[(1, 1)], i[(2, 2)], i[(0, 1)], i[(0, 2)], i[(1, 2)]];
        let not_finite = [("mass", mass), ("com.x", com.x), ("com.y", com.y), ("com.z", com.z)]
            .into_iter()
            .chain(["ixx", "iyy", "izz", "ixy", "ixz", "iyz"].into_iter().zip(six))
            .find(|(_, v)| !v.is_finite());
        if let Some((what, value)) = not_finite {
            return Err(Error::Input(InputError::NotFinite { what: format!("inertial {what}"), value }));
        }
        if i.iter().any(|v| !v.is_finite()) {
            // A tensor built field by field whose lower triangle alone is not finite.
            let value = i.iter().copied().find(|v| !v.is_finite()).unwrap_or(f64::NAN);
            return Err(Error::Input(InputError::NotFinite { what: "inertial inertia".into(), value }));
        }
        if mass < 0.0 {
            return Err(Error::Input(InputError::OutOfRange {
                what: "mass".into(),
                value: mass,
                expected: "a mass ≥ 0 [kg]".into(),
            }));
        }
        let tol = 1e-9 * (six[0].abs() + six[1].abs() + six[2].abs());
        let asymmetry = (i - i.transpose()).amax();
        if asymmetry > tol {
            return Err(Error::Input(InputError::OutOfRange {
                what: "inertia".into(),
                value: asymmetry,
                expected: format!(
                    "a symmetric tensor (the value is the largest |I − Iᵀ| entry of {:?}, at most {tol:e})",
                    i.as_slice()
                ),
            }));
        }
        let mut p = i.symmetric_eigenvalues();
        p.as_mut_slice().sort_by(f64::total_cmp);
        if p[0] < -tol {
            return Err(Error::Input(InputError::OutOfRange {
                what: "inertia".into(),
                value: p[0],
                expected: format!(
                    "principal moments ≥ 0 kg·m² (the value is the smallest of inertia {six:?}, as ixx, iyy, izz, ixy, ixz, iyz)"
                ),
            }));
        }
        if p[0] + p[1] < p[2] - tol {
            return Err(Error::Input(InputError::OutOfRange {
                what: "inertia".into(),
                value: p[2],
                expected: format!(
                    "a largest principal moment ≤ {:.6e} kg·m², the sum of the other two (the triangle \
                     inequality; inertia {six:?}, as ixx, iyy, izz, ixy, ixz, iyz)",
                    p[0] + p[1]
                ),
            }));
        }
        Ok(())
    }

    /// The same body described in a parent frame, given `parent_from_link`:
    /// centre of mass moved, inertia rotated (R·I·Rᵀ; still about the centre of mass).
    pub fn transformed(&self, parent_from_link: &Pose) -> Inertial {
        let r = parent_from_link.rot;
        Inertial {
            mass: self.mass,
            com: parent_from_link.transform_point(&self.com),
            inertia: r * self.inertia * r.transpose(),
        }
    }

    /// Two bodies rigidly joined, both described in the same frame: masses
    /// add, the centre of mass is the mass-weighted mean, and each inertia is
    /// moved to the common centre by the parallel-axis theorem
    /// (I + m·(|d|²·1 − d·dᵀ) for an offset d).
    pub fn combined(&self, other: &Inertial) -> Inertial {
        let mass = self.mass + other.mass;
        if mass <= 0.0 {
            return Inertial { mass: 0.0, com: Vector3::zeros(), inertia: self.inertia + other.inertia };
        }
        let com = (self.com * self.mass + other.com * other.mass) / mass;
        let shift = |b: &Inertial| {
            let d = b.com - com;
            b.inertia + b.mass * (Matrix3::identity() * d.norm_squared() - d * d.transpose())
        };
        Inertial { mass, com, inertia: shift(self) + shift(other) }
    }
}

/// A named joint configuration such as `home`, `qz` or `qr`.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedPose {
    /// Name.
    pub name: String,
    /// Joint values \[rad or m\].
    pub q: Vec<f64>,
}

/// Which link geometry a model's joints are described in (for display).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum GeometryKind {
    /// Standard DH table.
    Standard,
    /// Modified DH table.
    Modified,
    /// Fixed transform + axis per joint (URDF or `general` TOML).
    General,
}

/// Where a description came from and what it says about itself.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Metadata {
    /// Manufacturer.
    pub manufacturer: String,
    /// Paper, table or datasheet the numbers come from.
    pub source: String,
    /// Free text: corrections of the source, mapping of limits, …
    pub notes: String,
    /// What the loader left out or chose on its own, one sentence each (a
    /// URDF link off the chain whose `<inertial>` is not physical, a tip
    /// picked among leaves that share their joints). The library never prints
    /// them; doors show them (the CLI on stderr).
    pub warnings: Vec<String>,
}

/// A robot arm's description: joints, link geometry, limits, base and tool
/// transforms, named poses and mass properties. Plain, validated, immutable
/// data; build one with [`Model::builder`] (or load a
/// [`Robot`](crate::Robot), which holds one).
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    name: String,
    kind: GeometryKind,
    meta: Metadata,
    joints: Vec<Joint>,
    base: Pose,
    tool: Pose,
    poses: Vec<NamedPose>,
    inertials: Vec<Option<Inertial>>,
}

/// Builds a [`Model`] field by field; [`ModelBuilder::build`] validates it.
///
/// # Examples
/// ```
/// use kinema::{DhConvention, GeometryKind, Joint, JointType, Limits, LinkGeometry, Model, Robot};
/// // A planar two-link arm, 1 m links.
/// let link = |name: &str| Joint {
///     name: name.into(),
///     kind: JointType::Revolute,
///     geometry: LinkGeometry::Dh { convention: DhConvention::Standard, d: 0.0, a: 1.0, alpha: 0.0, theta: 0.0 },
///     offset: 0.0,
///     limits: Limits::position(-3.0, 3.0),
/// };
/// let model = Model::builder("planar2", GeometryKind::Standard)
///     .joints(vec![link("j1"), link("j2")])
///     .pose("home", vec![0.0, 0.0])
///     .build()?;
/// let robot = Robot::new(model);
/// let fk = robot.fk(&[0.0, std::f64::consts::FRAC_PI_2])?;
/// assert!((fk.world_from_tool.pos.x - 1.0).abs() < 1e-12 && (fk.world_from_tool.pos.y - 1.0).abs() < 1e-12);
/// # Ok::<(), kinema::Error>(())
/// ```
#[derive(Debug, Clone)]
#[must_use]
pub struct ModelBuilder {
    /// The model as given so far, not yet validated; no inertials given is
    /// an empty list.
    draft: Model,
}

impl ModelBuilder {
    /// The joints, base first.
    pub fn joints(mut self, joints: Vec<Joint>) -> Self {
        self.draft.joints = joints;
        self
    }
    /// Manufacturer, source and notes.
    pub fn metadata(mut self, meta: Metadata) -> Self {
        self.draft.meta = meta;
        self
    }
    /// The `world_from_base` transform (identity by default).
    pub fn base(mut self, base: Pose) -> Self {
        self.draft.base = base;
        self
    }
    /// The `flange_from_tool` transform (identity by default).
    pub fn tool(mut self, tool: Pose) -> Self {
        self.draft.tool = tool;
        self
    }
    /// Adds (or replaces) a named configuration; `home` is required.
    pub fn pose(mut self, name: &str, q: Vec<f64>) -> Self {
        self.draft.poses.retain(|p| p.name != name);
        self.draft.poses.push(NamedPose { name: name.into(), q });
        self
    }
    /// All named configurations at once, replacing any given before.
    pub fn poses(mut self, poses: Vec<NamedPose>) -> Self {
        self.draft.poses = poses;
        self
    }
    /// Mass properties per link, one entry per joint (`None` for a link
    /// without them); none at all by default or when `inertials` is empty.
    pub fn inertials(mut self, inertials: Vec<Option<Inertial>>) -> Self {
        self.draft.inertials = inertials;
        self
    }

    /// Validates and builds the model. Errors name the robot and what is
    /// inconsistent: no joints, non-finite geometry, limits that are not an
    /// interval, a pose of the wrong length, no `home`, invalid inertials.
    pub fn build(self) -> Result<Model> {
        let Model { name, kind, meta, joints, base, tool, poses, inertials } = self.draft;
        let invalid = |message: String| Error::Model(ModelError::InvalidModel { robot: name.clone(), message });
        if joints.is_empty() {
            return Err(invalid("a robot needs at least one joint".into()));
        }
        if joints.len() > MAX_JOINTS {
            return Err(invalid(format!("{} joints; at most {MAX_JOINTS} are supported", joints.len())));
        }
        if !base.is_finite() || !tool.is_finite() {
            return Err(invalid("base and tool transforms must be finite".into()));
        }
        for (what, pose) in [("base", &base), ("tool", &tool)] {
            check_length(what, pose.pos.amax()).map_err(invalid)?;
        }
        for (i, j) in joints.iter().enumerate() {
            let l = &j.limits;
            let geometry_finite = match j.geometry {
                LinkGeometry::Dh { d, a, alpha, theta, .. } => [d, a, alpha, theta].iter().all(|v| v.is_finite()),
                LinkGeometry::General { origin, axis } => origin.is_finite() && axis.iter().all(|v| v.is_finite()),
            };
            if !geometry_finite || !j.offset.is_finite() {
                return Err(invalid(format!("joint {} (`{}`): geometry and offset must be finite", i + 1, j.name)));
            }
            let length = match j.geometry {
                LinkGeometry::Dh { d, a, .. } => d.abs().max(a.abs()),
                LinkGeometry::General { origin, .. } => origin.pos.amax(),
            };
            let joint = format!("joint {} (`{}`)", i + 1, j.name);
            check_length(&format!("{joint}: the link's offset"), length).map_err(invalid)?;
            if j.offset.abs() >= MAX_MAGNITUDE {
                return Err(invalid(format!(
                    "{joint}: offset {}; offsets must lie within ±{MAX_MAGNITUDE:e}",
                    j.offset
                )));
            }
            if let LinkGeometry::General { axis, .. } = j.geometry {
                if (axis.norm() - 1.0).abs() > 1e-9 {
                    return Err(invalid(format!(
                        "joint {} (`{}`): axis {:?} is not a unit vector",
                        i + 1,
                        j.name,
                        axis.as_slice()
                    )));
                }
            }
            if l.min.is_nan() || l.max.is_nan() || l.min > l.max {
                return Err(invalid(format!(
                    "joint {} (`{}`): position limits [{}, {}] are not an interval (min must be ≤ max)",
                    i + 1,
                    j.name,
                    l.min,
                    l.max
                )));
            }
            for (what, v) in [("velocity", l.vel), ("acceleration", l.acc), ("jerk", l.jerk), ("effort", l.effort)] {
                if let Some(v) = v {
                    if !(v > 0.0 && v.is_finite()) {
                        return Err(invalid(format!(
                            "joint {} (`{}`): {what} limit {v} must be positive and finite",
                            i + 1,
                            j.name
                        )));
                    }
                }
            }
        }
        if !poses.iter().any(|p| p.name == "home") {
            return Err(invalid("every robot needs a named pose `home`".into()));
        }
        for p in &poses {
            if p.q.len() != joints.len() {
                return Err(invalid(format!("pose `{}` has {} values, expected {}", p.name, p.q.len(), joints.len())));
            }
            if let Some(v) = p.q.iter().find(|v| !(v.abs() < MAX_MAGNITUDE)) {
                return Err(invalid(format!(
                    "pose `{}` contains {v}; joint values must be finite numbers within ±{MAX_MAGNITUDE:e}",
                    p.name
                )));
            }
        }
        let inertials = if inertials.is_empty() { vec![None; joints.len()] } else { inertials };
        if inertials.len() != joints.len() {
            return Err(invalid(format!(
                "{} inertials given, one per joint ({}) expected",
                inertials.len(),
                joints.len()
            )));
        }
        for (i, b) in inertials.iter().enumerate() {
            if let Some(b) = b {
                b.validate().map_err(|e| invalid(format!("link {} (moved by `{}`): {e}", i + 1, joints[i].name)))?;
            }
        }
        Ok(Model { name, kind, meta, joints, base, tool, poses, inertials })
    }
}

impl Model {
    /// A builder for a model named `name` whose links are described in `kind`
    /// geometry: no joints yet, identity base and tool, no poses.
    pub fn builder(name: impl Into<String>, kind: GeometryKind) -> ModelBuilder {
        ModelBuilder {
            draft: Model {
                name: name.into(),
                kind,
                meta: Metadata::default(),
                joints: Vec::new(),
                base: Pose::IDENTITY,
                tool: Pose::IDENTITY,
                poses: Vec::new(),
                inertials: Vec::new(),
            },
        }
    }

    /// Robot name (e.g. `lbr-iiwa-14-r820`).
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Number of joints.
    pub fn dof(&self) -> usize {
        self.joints.len()
    }
    /// The joints, base first.
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }
    /// Which link geometry the model is described in.
    pub fn geometry_kind(&self) -> GeometryKind {
        self.kind
    }
    /// Manufacturer, source and notes.
    pub fn metadata(&self) -> &Metadata {
        &self.meta
    }
    /// `world_from_base` transform.
    pub fn base(&self) -> &Pose {
        &self.base
    }
    /// `flange_from_tool` transform (flange = last link frame).
    pub fn tool(&self) -> &Pose {
        &self.tool
    }
    /// Joint types as a string such as `RRRRR` or `PRRPR`.
    pub fn joint_types(&self) -> String {
        self.joints.iter().map(|j| j.kind.letter()).collect()
    }
    /// Named configurations, `home` among them.
    pub fn poses(&self) -> &[NamedPose] {
        &self.poses
    }
    /// A named configuration.
    pub fn pose(&self, name: &str) -> Result<&[f64]> {
        self.poses.iter().find(|p| p.name == name).map(|p| p.q.as_slice()).ok_or_else(|| {
            Error::Input(InputError::UnknownPose {
                robot: self.name.clone(),
                pose: name.to_string(),
                known: self.poses.iter().map(|p| p.name.as_str()).collect::<Vec<_>>().join(", "),
            })
        })
    }
    /// The `home` configuration.
    pub fn home(&self) -> &[f64] {
        self.pose("home").expect("validated by ModelBuilder::build")
    }

    /// Mass properties per link (entry i for the body joint i moves, in link
    /// frame i); `None` where the description gives none.
    pub fn inertials(&self) -> &[Option<Inertial>] {
        &self.inertials
    }

    /// A builder that starts from this model (to change its tool, base,
    /// inertials, …); `build` validates the result again.
    pub fn to_builder(&self) -> ModelBuilder {
        ModelBuilder { draft: self.clone() }
    }

    /// A uniformly random configuration within the position limits (joints
    /// without finite limits are drawn from \[−π, π\]).
    pub fn random_q<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> Vec<f64> {
        let mut q = vec![0.0; self.dof()];
        self.random_q_into(rng, &mut q);
        q
    }

    /// As [`Model::random_q`], writing into `q` (length must be `dof()`).
    pub fn random_q_into<R: rand::Rng + ?Sized>(&self, rng: &mut R, q: &mut [f64]) {
        for (v, j) in q.iter_mut().zip(&self.joints) {
            let (lo, hi) = sampling_range(&j.limits);
            *v = if hi > lo { rng.random_range(lo..=hi) } else { lo };
        }
    }
}

/// The interval random configurations are drawn from for one joint.
pub fn sampling_range(l: &Limits) -> (f64, f64) {
    let lo = if l.min.is_finite() { l.min } else { -std::f64::consts::PI };
    let hi = if l.max.is_finite() { l.max } else { std::f64::consts::PI };
    (lo, hi.max(lo))
}

/// A set of joints, as a bit set (bit i is joint i + 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct JointSet(pub u64);

impl JointSet {
    /// Whether no joint is in the set.
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }
    /// Whether joint `index` (0-based) is in the set.
    pub fn contains(self, index: usize) -> bool {
        index < 64 && self.0 & (1 << index) != 0
    }
    /// 0-based indices of the joints in the set.
    pub fn indices(self) -> impl Iterator<Item = usize> {
        (0..64).filter(move |i| self.0 & (1u64 << i) != 0)
    }
}
