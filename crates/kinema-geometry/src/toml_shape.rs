//! One shape as a TOML table, shared by a robot file's `[[shape]]` and a
//! scene's `[[obstacle]]`:
//!
//! ```toml
//! name = "upper_arm"
//! capsule = { radius = 0.06, length = 0.425 }   # or sphere = { radius = … },
//!                                                # cylinder = { radius, length },
//!                                                # box = [x, y, z] (full edges), mesh = "part.stl"
//! pose = [0.2, 0, 0, 0, 90, 0]                   # x y z, roll pitch yaw (R = Rz·Ry·Rx)
//! ```
//!
//! Numbers are in the file's units (a robot file's `[units]`; SI in a
//! scene); any value may also be a string with its unit (`"60mm"`, `"90deg"`).
//! Errors are [`ModelError::Description`](kinema::ModelError::Description)s naming file, line, column and field.

use std::ops::Range;
use std::path::Path;
use std::sync::Arc;

use nalgebra::Vector3;
use serde::Deserialize;
use toml::Spanned;

use kinema::quantity::{Dim, Quantity};
use kinema::{Pose, RpyConvention};

use crate::error::{Error, Result};
use crate::mesh::load_mesh;
use crate::shape::Shape;

/// `sphere = { radius = … }`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RadiusSpec {
    radius: Spanned<Quantity>,
}

/// `cylinder` / `capsule = { radius = …, length = … }`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RoundSpec {
    radius: Spanned<Quantity>,
    length: Spanned<Quantity>,
}

/// One shape table (the fields of both `[[shape]]` and `[[obstacle]]`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ShapeSpec {
    pub name: Spanned<String>,
    /// The link a robot's shape rides on (robot files only).
    pub link: Option<Spanned<usize>>,
    sphere: Option<RadiusSpec>,
    #[serde(rename = "box")]
    cuboid: Option<[Spanned<Quantity>; 3]>,
    cylinder: Option<RoundSpec>,
    capsule: Option<RoundSpec>,
    /// A mesh file (STL, OBJ, COLLADA), relative to the file's folder.
    mesh: Option<Spanned<String>>,
    /// Use a mesh's convex hull (a solid) instead of its surface.
    #[serde(default)]
    convex: bool,
    /// A mesh's scale along x, y, z (its file's units to metres).
    scale: Option<[f64; 3]>,
    pose: Option<[Spanned<Quantity>; 6]>,
}

/// The file being read, for errors.
pub(crate) struct Src<'a> {
    pub file: &'a str,
    pub text: &'a str,
    /// Metres per plain length number, radians per plain angle number.
    pub length_unit: f64,
    pub angle_unit: f64,
    pub rpy: RpyConvention,
}

impl Src<'_> {
    pub fn err(&self, span: Range<usize>, field: &str, message: impl Into<String>) -> Error {
        let mut at = span.start.min(self.text.len());
        while !self.text.is_char_boundary(at) {
            at -= 1;
        }
        let before = &self.text[..at];
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        Error::Kinema(kinema::Error::Model(kinema::ModelError::Description {
            file: self.file.to_string(),
            line,
            column,
            field: field.to_string(),
            message: message.into(),
        }))
    }

    /// Parses `text` into `T` with errors at the offending field.
    pub fn parse<T: for<'de> Deserialize<'de>>(&self) -> Result<T> {
        let de = toml::Deserializer::parse(self.text)
            .map_err(|e| self.err(e.span().unwrap_or(0..0), "(syntax)", e.message().trim()))?;
        serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string().replace(".$__serde_spanned_private_value", "");
            let inner = e.into_inner();
            let field = if path == "." { "(top level)".to_string() } else { path };
            self.err(inner.span().unwrap_or(0..0), &field, inner.message().trim())
        })
    }

    /// A value in SI units: a plain number times the file's unit, or a string with a unit.
    pub fn value(&self, q: &Spanned<Quantity>, dim: Dim, field: &str) -> Result<f64> {
        let plain = match dim {
            Dim::Length => self.length_unit,
            Dim::Angle => self.angle_unit,
            Dim::Time => 1.0,
        };
        q.get_ref().si(dim, plain).map_err(|m| self.err(q.span(), field, m))
    }

    /// A pose `[x, y, z, roll, pitch, yaw]` (identity when absent).
    pub fn pose(&self, pose: &Option<[Spanned<Quantity>; 6]>, field: &str) -> Result<Pose> {
        let Some(p) = pose else { return Ok(Pose::IDENTITY) };
        let mut v = [0.0; 6];
        for (i, q) in p.iter().enumerate() {
            v[i] = self.value(q, if i < 3 { Dim::Length } else { Dim::Angle }, field)?;
        }
        Ok(Pose::from_xyz_rpy([v[0], v[1], v[2]], [v[3], v[4], v[5]], self.rpy))
    }

    /// The shape and its pose of table `s` (at `field`, e.g. `shape[2]`);
    /// mesh paths are taken from `dir`.
    pub fn shape(&self, s: &Spanned<ShapeSpec>, field: &str, dir: &Path) -> Result<(Pose, Shape)> {
        let spec = s.get_ref();
        let at = |f: &str| format!("{field}.{f}");
        let given: Vec<&str> = [
            ("sphere", spec.sphere.is_some()),
            ("box", spec.cuboid.is_some()),
            ("cylinder", spec.cylinder.is_some()),
            ("capsule", spec.capsule.is_some()),
            ("mesh", spec.mesh.is_some()),
        ]
        .into_iter()
        .filter_map(|(k, v)| v.then_some(k))
        .collect();
        if given.len() != 1 {
            let message = format!(
                "shape `{}` gives {}; expected exactly one of sphere, box, cylinder, capsule, mesh",
                spec.name.get_ref(),
                if given.is_empty() { "none".to_string() } else { given.join(" and ") }
            );
            return Err(self.err(s.span(), field, message));
        }
        if spec.mesh.is_none() && (spec.convex || spec.scale.is_some()) {
            return Err(self.err(s.span(), &at("convex"), "`convex` and `scale` apply to a `mesh` only"));
        }
        let len = |q: &Spanned<Quantity>, f: &str| self.value(q, Dim::Length, &at(f));
        let shape = if let Some(r) = &spec.sphere {
            Shape::Sphere { radius: len(&r.radius, "sphere.radius")? }
        } else if let Some(b) = &spec.cuboid {
            Shape::Box { size: Vector3::new(len(&b[0], "box")?, len(&b[1], "box")?, len(&b[2], "box")?) }
        } else if let Some(c) = &spec.cylinder {
            Shape::Cylinder { radius: len(&c.radius, "cylinder.radius")?, length: len(&c.length, "cylinder.length")? }
        } else if let Some(c) = &spec.capsule {
            Shape::Capsule { radius: len(&c.radius, "capsule.radius")?, length: len(&c.length, "capsule.length")? }
        } else {
            let name = spec.mesh.as_ref().expect("one shape kind is given");
            let path = dir.join(name.get_ref());
            if !path.is_file() {
                let message =
                    format!("mesh `{}` not found (looked for `{}`); expected an STL, OBJ or COLLADA file relative to this file's folder", name.get_ref(), path.display());
                return Err(self.err(name.span(), &at("mesh"), message));
            }
            let mesh = Arc::new(load_mesh(&path, spec.scale.unwrap_or([1.0; 3]))?);
            if spec.convex {
                Shape::ConvexMesh(mesh)
            } else {
                Shape::TriangleMesh(mesh)
            }
        };
        Ok((self.pose(&spec.pose, &at("pose"))?, shape))
    }
}
