//! A scene's robots in a check of one robot: each other robot stands on its
//! base at its `start` (else at home) and its link shapes are obstacles, so
//! `kinema collide`, `kinema ik` and `kinema traj` with a scene see the
//! neighbour as well as the bench. The robot checked may be one of the scene's
//! robots, named as it is there: it then stands on that base and is not its
//! own obstacle.

use kinema::Robot;

use crate::error::{Error, Result};
use crate::placement::Placement;
use crate::robot_toml::load_robot_geometry;
use crate::scene::{Obstacle, Scene, SceneRobot};
use crate::urdf::UrdfOptions;

impl Scene {
    /// The scene's robot named `name`.
    pub fn member(&self, name: &str) -> Option<&SceneRobot> {
        self.robots.iter().find(|r| r.name == name)
    }

    /// This scene for a check of one robot: its obstacles, and every robot
    /// but the one named `except` as obstacles where it stands, each shape
    /// named `robot/shape` on the body `robot/link`. `options` says where
    /// the robots' meshes are (their tips are the scene's). The result has
    /// no robots.
    pub fn standing(&self, except: Option<&str>, options: &UrdfOptions) -> Result<Scene> {
        if let Some(name) = except.filter(|n| self.member(n).is_none()) {
            return Err(Error::Shape {
                name: name.to_string(),
                message: format!("the scene has no robot of this name; it has: {}", self.robot_names()),
            });
        }
        let mut obstacles = self.obstacles.clone();
        for member in self.robots.iter().filter(|r| Some(r.name.as_str()) != except) {
            obstacles.extend(member.as_obstacles(options)?);
        }
        Ok(Scene { obstacles, robots: Vec::new() })
    }

    fn robot_names(&self) -> String {
        let names: Vec<&str> = self.robots.iter().map(|r| r.name.as_str()).collect();
        if names.is_empty() {
            "none".into()
        } else {
            names.join(", ")
        }
    }
}

impl SceneRobot {
    /// The robot with its link shapes, placed on its base in the scene's
    /// world (after its description's own base transform).
    pub fn load(&self, options: &UrdfOptions) -> Result<(Robot, crate::RobotGeometry)> {
        let options = UrdfOptions { tip: self.tip.clone(), ..options.clone() };
        let (robot, geometry) = load_robot_geometry(&self.robot, &options)?;
        let placed = kinema::traj::cell::placed(&robot, &self.world_from_base)?;
        Ok((placed, geometry))
    }

    /// Where it stands: its `start`, else its home configuration.
    pub fn standing_q(&self, robot: &Robot) -> Result<Vec<f64>> {
        let Some(text) = &self.start else { return Ok(robot.home().to_vec()) };
        robot.parse_q(text, false).map_err(|e| Error::Shape {
            name: self.name.clone(),
            message: format!("robot `{}`: `start`: {e}", self.name),
        })
    }

    /// Its link shapes where it stands, as obstacles.
    fn as_obstacles(&self, options: &UrdfOptions) -> Result<Vec<Obstacle>> {
        let (robot, geometry) = self.load(options)?;
        let q = self.standing_q(&robot)?;
        let placement = Placement::of(&robot, &geometry, &q)?;
        let obstacles = geometry.shapes().iter().enumerate().map(|(s, shape)| Obstacle {
            name: format!("{}/{}", self.name, shape.name()),
            body: format!("{}/{}", self.name, shape.link_name()),
            world_from_shape: placement.world_from_shape(&geometry, s),
            shape: shape.shape().clone(),
        });
        Ok(obstacles.collect())
    }
}
