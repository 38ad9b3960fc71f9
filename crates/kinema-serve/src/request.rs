//! The bodies of the JSON API's requests: their serde types, the one parser
//! that names the endpoint and the expected shape, and the target pose and
//! self-motion policy read from them.

use kinema::ik::family::SelfMotionParameter;
use kinema::ik::IkTarget;
use kinema::nalgebra::Matrix4;
use kinema::traj::SelfMotion;
use kinema::{Pose, RpyConvention};
use serde::de::DeserializeOwned;
use serde::Deserialize;

use crate::api::{bad, named};
use crate::error::{Error, Result};

/// Parses a JSON body, naming the endpoint and the expected shape on failure.
pub(crate) fn parse<T: DeserializeOwned>(body: &[u8], endpoint: &str, shape: &str) -> Result<T> {
    let text = std::str::from_utf8(body).map_err(|e| Error::NotUtf8 {
        endpoint: endpoint.into(),
        shape: shape.into(),
        source: e,
    })?;
    if text.trim().is_empty() {
        return Err(bad(format!("{endpoint}: the body is empty; expected JSON {shape}")));
    }
    serde_json::from_str(text).map_err(|e| Error::Json {
        endpoint: endpoint.into(),
        shape: shape.into(),
        source: e.into(),
    })
}

/// A body with a robot and joint values.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct QReq {
    pub(crate) robot: Option<String>,
    pub(crate) q: Vec<f64>,
}

/// A target pose: a 4×4 matrix or a position and roll-pitch-yaw angles
/// (`rpy_convention`: `zyx`, the default, R = Rz·Ry·Rx, or `xyz`).
pub(crate) struct Target<'a> {
    pub(crate) t: &'a Option<[[f64; 4]; 4]>,
    pub(crate) position: &'a Option<[f64; 3]>,
    pub(crate) rpy: &'a Option<[f64; 3]>,
    pub(crate) rpy_convention: &'a Option<String>,
}

impl Target<'_> {
    pub(crate) fn pose(&self, path: &str, shape: &str) -> Result<Pose> {
        match (self.t, self.position, self.rpy) {
            (Some(t), None, None) => pose_from_rows(t, "T"),
            (None, Some(p), Some(rpy)) => {
                let conv = named(path, self.rpy_convention.as_deref(), RpyConvention::Zyx)?;
                Ok(Pose::from_xyz_rpy(*p, *rpy, conv))
            }
            _ => Err(bad(format!("give the target as \"T\" alone or as \"position\" and \"rpy\"; expected {shape}"))),
        }
    }
}

/// The rigid transform of a 4×4 matrix given as rows (`what`: its field's name).
fn pose_from_rows(t: &[[f64; 4]; 4], what: &str) -> Result<Pose> {
    let m = Matrix4::from_fn(|r, c| t[r][c]);
    if m.iter().any(|v| !v.is_finite()) {
        return Err(bad(format!("{what} contains a non-finite value")));
    }
    Pose::from_matrix(&m).ok_or_else(|| Error::Unprocessable {
        message: format!("{what} is not a rigid transform: the last row must be 0 0 0 1 and the 3×3 block a rotation"),
    })
}

// The target fields are repeated in `IkReq` and `TrajReq`: serde's `flatten`
// does not combine with `deny_unknown_fields`.
impl IkReq {
    pub(crate) fn target(&self) -> Target<'_> {
        Target { t: &self.t, position: &self.position, rpy: &self.rpy, rpy_convention: &self.rpy_convention }
    }
}

impl IkReq {
    /// The target of `/api/ik`: a pose, a position alone, or a position with
    /// the components of a family's typed target (as `kinema ik --position`
    /// with `--pitch`/`--roll`, `--approach` or `--alpha`).
    pub(crate) fn ik_target(&self, shape: &str) -> Result<IkTarget> {
        let given = [
            ("pitch", self.pitch.as_ref().map(std::slice::from_ref)),
            ("roll", self.roll.as_ref().map(std::slice::from_ref)),
            ("alpha", self.alpha.as_ref().map(std::slice::from_ref)),
            ("approach", self.approach.as_ref().map(|d| &d[..])),
        ];
        match (self.t, self.position, self.rpy) {
            (None, Some(position), None) => {
                Ok(kinema::ik::registry::typed_target(position, &given)?.map_or(IkTarget::Position(position), IkTarget::Typed))
            }
            _ if given.iter().any(|(_, v)| v.is_some()) => Err(bad(format!(
                "\"pitch\"/\"roll\", \"approach\" and \"alpha\" complete a \"position\" target; they do not apply to \"T\" or \"rpy\"; expected {shape}"
            ))),
            _ => Ok(IkTarget::Pose(self.target().pose("/api/ik", shape)?)),
        }
    }
}

impl TrajReq {
    pub(crate) fn target(&self) -> Target<'_> {
        Target { t: &self.t, position: &self.position, rpy: &self.rpy, rpy_convention: &self.rpy_convention }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct IkReq {
    pub(crate) robot: Option<String>,
    #[serde(rename = "T")]
    pub(crate) t: Option<[[f64; 4]; 4]>,
    pub(crate) position: Option<[f64; 3]>,
    pub(crate) rpy: Option<[f64; 3]>,
    pub(crate) rpy_convention: Option<String>,
    pub(crate) pitch: Option<f64>,
    pub(crate) roll: Option<f64>,
    pub(crate) alpha: Option<f64>,
    pub(crate) approach: Option<[f64; 3]>,
    pub(crate) q3: Option<f64>,
    pub(crate) psi: Option<f64>,
    pub(crate) q0: Option<Vec<f64>>,
    pub(crate) solver: Option<String>,
    pub(crate) seed: Option<u64>,
    pub(crate) mask: Option<[bool; 6]>,
    pub(crate) scene: Option<String>,
    pub(crate) margin: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct CollideReq {
    pub(crate) robot: Option<String>,
    pub(crate) q: Vec<f64>,
    pub(crate) scene: Option<String>,
    pub(crate) margin: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SceneReq {
    pub(crate) scene: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct TrajReq {
    pub(crate) robot: Option<String>,
    pub(crate) kind: String,
    pub(crate) from: Vec<f64>,
    pub(crate) to: Option<Vec<f64>>,
    #[serde(rename = "T")]
    pub(crate) t: Option<[[f64; 4]; 4]>,
    pub(crate) position: Option<[f64; 3]>,
    pub(crate) rpy: Option<[f64; 3]>,
    pub(crate) rpy_convention: Option<String>,
    pub(crate) dt: Option<f64>,
    pub(crate) profile: Option<String>,
    pub(crate) speed: Option<f64>,
    pub(crate) duration: Option<f64>,
    pub(crate) jvel: Option<OneOrMany>,
    pub(crate) jacc: Option<OneOrMany>,
    pub(crate) jjerk: Option<OneOrMany>,
    pub(crate) vmax: Option<f64>,
    pub(crate) amax: Option<f64>,
    pub(crate) q3: Option<PolicyValue>,
    pub(crate) psi: Option<PolicyValue>,
    pub(crate) scene: Option<String>,
    pub(crate) margin: Option<f64>,
}

/// A self-motion policy of `/api/traj`: a name (`"hold"`, `"track"`, …) or an angle \[rad\].
#[derive(Deserialize)]
#[serde(untagged)]
pub(crate) enum PolicyValue {
    Text(String),
    Angle(f64),
}

impl TrajReq {
    /// The self-motion policy its `q3` or `psi` asks for (as `kinema traj lin --q3/--psi`).
    pub(crate) fn self_motion(&self) -> Result<SelfMotion> {
        let (parameter, value) = match (&self.q3, &self.psi) {
            (Some(_), Some(_)) => return Err(bad("/api/traj: give \"q3\" or \"psi\", not both".into())),
            (Some(v), None) => (SelfMotionParameter::Q3, v),
            (None, Some(v)) => (SelfMotionParameter::ArmAngle, v),
            (None, None) => return Ok(SelfMotion::Auto),
        };
        match value {
            PolicyValue::Text(text) => Ok(SelfMotion::parse(parameter, text, 1.0)?),
            PolicyValue::Angle(v) => Ok(SelfMotion::Fixed { parameter, value: Some(*v) }),
        }
    }
}

/// Joint limits: one value for every joint or one per joint.
#[derive(Deserialize)]
#[serde(untagged)]
pub(crate) enum OneOrMany {
    One(f64),
    Many(Vec<f64>),
}

impl OneOrMany {
    pub(crate) fn values(&self) -> Vec<f64> {
        match self {
            OneOrMany::One(v) => vec![*v],
            OneOrMany::Many(v) => v.clone(),
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RunReq {
    pub(crate) robot: Option<String>,
    pub(crate) program: String,
    pub(crate) dt: Option<f64>,
    pub(crate) start: Option<Vec<f64>>,
    pub(crate) scene: Option<String>,
    pub(crate) margin: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PlanReq {
    pub(crate) robot: Option<String>,
    pub(crate) from: Vec<f64>,
    pub(crate) to: Option<Vec<f64>>,
    pub(crate) pose: Option<PoseValue>,
    pub(crate) rpy_convention: Option<String>,
    pub(crate) scene: Option<String>,
    pub(crate) margin: Option<f64>,
    pub(crate) seed: Option<u64>,
    pub(crate) time_limit: Option<f64>,
    pub(crate) dt: Option<f64>,
    pub(crate) profile: Option<String>,
    pub(crate) speed: Option<f64>,
}

/// A tool pose in one field: x, y, z, roll, pitch, yaw \[m, rad\] (as
/// `kinema plan --pose`) or the rows of a 4×4 transform.
#[derive(Deserialize)]
#[serde(untagged)]
pub(crate) enum PoseValue {
    XyzRpy([f64; 6]),
    Rows([[f64; 4]; 4]),
}

impl PoseValue {
    /// The pose, its roll-pitch-yaw angles read in `convention` (a name; default `zyx`).
    pub(crate) fn pose(&self, convention: Option<&str>) -> Result<Pose> {
        match self {
            PoseValue::XyzRpy(v) => {
                if v.iter().any(|x| !x.is_finite()) {
                    return Err(bad("pose contains a non-finite value".into()));
                }
                let conv = named("/api/plan", convention, RpyConvention::Zyx)?;
                Ok(Pose::from_xyz_rpy([v[0], v[1], v[2]], [v[3], v[4], v[5]], conv))
            }
            PoseValue::Rows(t) => pose_from_rows(t, "pose"),
        }
    }
}
