//! The options that give a command's robot a body to check: a scene of
//! obstacles, an SRDF of pairs not to check, a safety margin and where
//! meshes are. `kinema collide` always checks; `kinema ik` and `kinema
//! traj` check when a scene, an SRDF or a margin is given (a margin alone:
//! self-collision), the rule Python's and the server's `scene=`/`margin=` follow.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use kinema_geometry::{CheckOptions, CollisionCheck};

use crate::RobotArg;

#[derive(Args, Clone, Default)]
pub struct BodyArgs {
    /// A scene file: `[[obstacle]]`s checked against the robot's moving links, and `[[robot]]`s (as in a
    /// `kinema cell` file) standing as obstacles at their `start` (else home). `--robot` may name one of
    /// them: that robot, on its base there.
    #[arg(long, value_name = "FILE")]
    scene: Option<PathBuf>,
    /// An SRDF whose `<disable_collisions>` link pairs are not checked.
    #[arg(long, value_name = "FILE")]
    srdf: Option<PathBuf>,
    /// Safety margin [m]: bodies closer than this count as colliding (default 0). Alone, it asks for a
    /// self-collision check.
    #[arg(long, value_name = "METRES")]
    margin: Option<f64>,
    /// For a URDF: directories holding the packages of `package://` meshes (ROS_PACKAGE_PATH is added).
    #[arg(long = "package-path", value_name = "DIR")]
    package_path: Vec<PathBuf>,
}

impl BodyArgs {
    /// The robot with its shapes, the scene's obstacles and the pairs to check.
    pub fn load(&self, robot: &RobotArg) -> Result<CollisionCheck> {
        let options = CheckOptions {
            tip: robot.tip.clone(),
            package_paths: self.package_path.clone(),
            scene: self.scene.clone(),
            srdf: self.srdf.clone(),
            margin: self.margin.unwrap_or(0.0),
        };
        let check = CollisionCheck::load(&robot.robot, &options)?;
        crate::print_load_warnings(&robot.robot, check.robot());
        Ok(check)
    }

    /// An error when any option that `flag` would ignore is given (`why`: what `flag` does instead).
    pub fn refuse_with(&self, flag: &str, why: &str) -> Result<()> {
        if self.scene.is_some() || self.srdf.is_some() || self.margin.is_some() {
            anyhow::bail!("{flag} takes no --scene, --srdf or --margin: {why}");
        }
        Ok(())
    }

    /// The robot, and its collision check when a scene, an SRDF or a margin asks for one
    /// (the check's robot then: loaded once).
    pub fn robot_and_check(&self, robot: &RobotArg) -> Result<(kinema::Robot, Option<CollisionCheck>)> {
        match self.load_if_asked(robot)? {
            Some(check) => Ok((check.robot().clone(), Some(check))),
            None => Ok((robot.load()?, None)),
        }
    }

    /// [`BodyArgs::load`] when a scene, an SRDF or a margin asks for collision checks.
    pub fn load_if_asked(&self, robot: &RobotArg) -> Result<Option<CollisionCheck>> {
        if self.scene.is_none() && self.srdf.is_none() && self.margin.is_none() {
            if !self.package_path.is_empty() {
                anyhow::bail!("--package-path applies to collision checks; give --scene, --srdf or --margin too");
            }
            return Ok(None);
        }
        self.load(robot).map(Some)
    }
}
