//! [`Robot`]: a [`Model`] together with what is derived from it once — the
//! compiled chain forward kinematics and Jacobians walk. The model is plain
//! data; the robot is what algorithms take.

use std::ops::Deref;

use crate::chain::Chain;
use crate::error::{Error, InputError, Result};
use crate::math::Pose;
use crate::model::{Inertial, JointSet, Model};

/// A robot arm ready to compute with: an immutable, `Clone + Send + Sync`
/// [`Model`] and its compiled chain. Reads the model's fields through
/// `Deref` (`robot.dof()`, `robot.joints()`, …).
///
/// Load one with [`Robot::builtin`], [`Robot::from_toml_str`],
/// [`Robot::from_urdf_str`] or [`Robot::from_file`], or build a [`Model`]
/// with [`Model::builder`] and pass it to [`Robot::new`].
#[derive(Debug, Clone, PartialEq)]
pub struct Robot {
    model: Model,
    pub(crate) chain: Chain,
}

impl Deref for Robot {
    type Target = Model;
    fn deref(&self) -> &Model {
        &self.model
    }
}

impl From<Model> for Robot {
    fn from(model: Model) -> Robot {
        Robot::new(model)
    }
}

impl Robot {
    /// Compiles a validated model into a robot.
    pub fn new(model: Model) -> Robot {
        let chain = Chain::new(model.joints(), model.base(), model.tool());
        Robot { model, chain }
    }

    /// The plain description.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// Copy of the robot with another tool transform (`flange_from_tool`).
    pub fn with_tool(&self, tool: Pose) -> Result<Robot> {
        Ok(Robot::new(self.model.to_builder().tool(tool).build()?))
    }

    /// Copy of the robot with another base transform (`world_from_base`).
    pub fn with_base(&self, base: Pose) -> Result<Robot> {
        Ok(Robot::new(self.model.to_builder().base(base).build()?))
    }

    /// Copy of the robot with mass properties per link: one entry per joint
    /// (`None` for a link without them), each checked by [`Inertial::validate`].
    ///
    /// # Examples
    /// ```
    /// use kinema::{Inertial, nalgebra::Vector3};
    /// let robot = kinema::Robot::builtin("scara5")?;
    /// let ball = Inertial::new(1.0, Vector3::zeros(), [0.0; 6])?;
    /// let heavy = robot.with_inertials(vec![Some(ball); robot.dof()])?;
    /// assert_eq!(heavy.inertials()[2], Some(ball));
    /// assert!(robot.with_inertials(vec![None]).is_err());
    /// # Ok::<(), kinema::Error>(())
    /// ```
    pub fn with_inertials(&self, inertials: Vec<Option<Inertial>>) -> Result<Robot> {
        let model = self.model.to_builder().inertials(inertials).build()?;
        // The chain depends on the geometry only, which did not change.
        Ok(Robot { model, chain: self.chain.clone() })
    }

    /// Checks length and finiteness of a joint vector.
    #[inline]
    pub fn check_q(&self, q: &[f64]) -> Result<()> {
        self.scan_q(q).map(|_| ())
    }

    /// Checks length and finiteness of `q` and returns the joints outside
    /// their limits, in one pass. The detailed error is only built on failure.
    #[inline]
    pub(crate) fn scan_q(&self, q: &[f64]) -> Result<JointSet> {
        if q.len() != self.dof() {
            return Err(self.bad_q(q));
        }
        let (finite, bits) = self.chain.scan(q);
        if !finite {
            return Err(self.bad_q(q));
        }
        Ok(JointSet(bits))
    }

    /// The error for a joint vector that failed [`Robot::scan_q`] (kept out of line).
    #[cold]
    #[inline(never)]
    pub(crate) fn bad_q(&self, q: &[f64]) -> Error {
        let joints = self.joints();
        if q.len() != joints.len() {
            return Error::Input(InputError::JointCount {
                robot: self.name().into(),
                expected: joints.len(),
                got: q.len(),
            });
        }
        let i = q.iter().position(|v| !(v.abs() < crate::MAX_MAGNITUDE)).unwrap_or(0);
        Error::Input(InputError::BadJointValue {
            robot: self.name().into(),
            joint: i + 1,
            name: joints[i].name.clone(),
            value: q[i],
        })
    }

    /// [`Robot::check_q`] and every value within its joint's position
    /// limits: else an error naming the joint, its value as `what` (`from`,
    /// `start`) and the limits.
    pub fn check_within_limits(&self, q: &[f64], what: &str) -> Result<()> {
        self.check_q(q)?;
        match self.limit_flags(q).indices().next() {
            None => Ok(()),
            Some(i) => {
                let l = self.joints()[i].limits;
                Err(self.for_joint(
                    i,
                    Error::Input(InputError::OutOfRange {
                        what: what.into(),
                        value: q[i],
                        expected: format!("a value within the joint's limits [{}, {}]", l.min, l.max),
                    }),
                ))
            }
        }
    }

    /// `source` as the error of joint `i` (0-based), named as the model names it.
    pub(crate) fn for_joint(&self, i: usize, source: Error) -> Error {
        Error::ForJoint { joint: i + 1, name: self.joints()[i].name.clone(), source: Box::new(source) }
    }

    /// Bit set of the joints whose value lies outside its position limits
    /// (bit i set for joint i + 1). `q` must have `dof()` values.
    #[inline]
    pub fn limit_flags(&self, q: &[f64]) -> JointSet {
        JointSet(self.chain.scan(q).1)
    }
}
