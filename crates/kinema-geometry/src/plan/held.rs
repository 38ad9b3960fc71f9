//! A cell robot's collision check with another robot of the cell held
//! still where it starts and where it stops: the path of
//! [`time_against`](super::time_against) is planned against it, so that both
//! places where the other robot rests are avoided and only its passage is
//! left to the timing.

use crate::check::CollisionCheck;
use crate::error::{Error, Result};
use crate::pairs::CollisionPairs;
use crate::scene::{Scene, SceneRobot};
use crate::urdf::UrdfOptions;

/// The check of `scene`'s robot `me` on its base: its self-collision pairs,
/// the scene's obstacles and robots (at their `start`), with the robot
/// `other` standing at `first` and, when different, a copy of it named
/// `other@end` at `last` (joint values \[rad, m\]). `options` says where
/// the robots' meshes are.
pub fn check_with_other_held(
    scene: &Scene,
    me: &str,
    other: &str,
    (first, last): (&[f64], &[f64]),
    options: &UrdfOptions,
) -> Result<CollisionCheck> {
    let member = |name: &str| {
        scene.member(name).ok_or_else(|| Error::Shape {
            name: name.to_string(),
            message: "the scene has no robot of this name".into(),
        })
    };
    let (mine, moving) = (member(me)?, member(other)?);
    let held = |name: String, q: &[f64]| {
        let start = q.iter().map(f64::to_string).collect::<Vec<_>>().join(",");
        SceneRobot { name, start: Some(start), ..moving.clone() }
    };
    let mut robots: Vec<SceneRobot> = scene.robots.iter().filter(|r| r.name != other).cloned().collect();
    robots.push(held(other.to_string(), first));
    if last != first {
        robots.push(held(format!("{other}@end"), last));
    }
    let standing = Scene { robots, ..scene.clone() }.standing(Some(me), options)?;
    let (robot, geometry) = mine.load(options)?;
    let pairs = CollisionPairs::self_collision(&geometry);
    CollisionCheck::with_scene(robot, geometry, pairs, Some(&standing), 0.0)
}
