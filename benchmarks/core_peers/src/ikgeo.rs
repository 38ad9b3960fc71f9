//! IK-Geo's Rust crate (`ik-geo` on crates.io) on kinema's arms: its description of a 6R arm
//! (unit axes H and offsets P between points on them, at q = 0) read from kinema's model, and the
//! arms both are timed on. Behind the feature `ik-geo` (ik-geo builds nlopt with CMake). Issue 34 item 10: every closed-form family within 1.5× of IK-Geo per
//! call on the same arm.

use std::path::Path;

use ik_geo::robot::IKSolver;
use kinema::ik::geo::Kinematics;
use kinema::nalgebra::{Matrix3, Vector3};
use kinema::{Pose, Robot};
use nalgebra_ik_geo as na32;

/// One arm as both solvers hold it.
pub struct GeoArm {
    /// A short name for tables and benchmark ids.
    pub name: &'static str,
    pub robot: Robot,
    /// The IK-Geo family solving it (`spherical`, `spherical_two_parallel`, …).
    pub family: &'static str,
    pub geo: ik_geo::robot::Robot,
    /// The tool rotation at q = 0: IK-Geo's zero pose has the identity rotation.
    r0: Matrix3<f64>,
}

/// The arms of the comparison: the PUMA 560 and a KUKA-KR-like arm (Pieper, shoulder in a
/// plane; IK-Geo's spherical wrist with two parallel axes), a general spherical-wrist arm
/// (Pieper's quartic; IK-Geo's `spherical`, subproblem 5) and the UR5 (three parallel axes).
pub fn arms(repo: &Path) -> Result<Vec<GeoArm>, String> {
    let kr = Robot::from_file(repo.join("crates/kinema/tests/data/kr16-like.urdf"), Some("tool0"))
        .map_err(|e| e.to_string())?;
    let general = Robot::from_toml_str(GENERAL_ARM, "general-spherical.toml").map_err(|e| e.to_string())?;
    let builtin = |name: &str| Robot::builtin(name).map_err(|e| e.to_string());
    [
        ("puma560", builtin("puma560")?, "spherical_two_parallel"),
        ("kr16-like", kr, "spherical_two_parallel"),
        ("general-spherical", general, "spherical"),
        ("ur5", builtin("ur5")?, "three_parallel_two_intersecting"),
    ]
    .into_iter()
    .map(|(name, robot, family)| GeoArm::new(name, robot, family))
    .collect()
}

/// A spherical-wrist arm of Pieper's general case (a1 ≠ 0, α1 = α2 = 90°), standard DH; the
/// arm `general_90_90` of kinema's tests/ik_pieper.rs.
const GENERAL_ARM: &str = r#"
name = "general-spherical"
source = "synthetic: Pieper's general case, kinema tests/ik_pieper.rs general_90_90 without base and tool"
convention = "standard"
[units]
length = "m"
angle = "deg"
[[joint]]
name = "j1"
d = 0.35
a = 0.1
alpha = 90
offset = 0
min = -170
max = 170
[[joint]]
name = "j2"
d = 0.1
a = 0.3
alpha = 90
offset = 20
min = -170
max = 170
[[joint]]
name = "j3"
d = 0.05
a = 0.02
alpha = -90
offset = 0
min = -170
max = 170
[[joint]]
name = "j4"
d = 0.3
a = 0
alpha = 90
offset = 0
min = -170
max = 170
[[joint]]
name = "j5"
d = 0
a = 0
alpha = -90
offset = 0
min = -170
max = 170
[[joint]]
name = "j6"
d = 0.07
a = 0
alpha = 0
offset = 0
min = -170
max = 170
[poses]
home = [0, 0, 0, 0, 0, 0]
"#;

impl GeoArm {
    fn new(name: &'static str, robot: Robot, family: &'static str) -> Result<Self, String> {
        let (h, p, r0) = geo_hp(&robot)?;
        let h = na32::Matrix3x6::from_fn(|r, c| h[c][r]);
        let p = na32::SMatrix::<f64, 3, 7>::from_fn(|r, c| p[c][r]);
        let geo = match family {
            "spherical" => ik_geo::robot::spherical(h, p),
            "spherical_two_parallel" => ik_geo::robot::spherical_two_parallel(h, p),
            "spherical_two_intersecting" => ik_geo::robot::spherical_two_intersecting(h, p),
            "three_parallel_two_intersecting" => ik_geo::robot::three_parallel_two_intersecting(h, p),
            other => return Err(format!("no IK-Geo family `{other}` here")),
        };
        Ok(GeoArm { name, robot, family, geo, r0 })
    }

    /// IK-Geo's target for kinema's `world_from_tool`.
    pub fn geo_target(&self, target: &Pose) -> (na32::Matrix3<f64>, na32::Vector3<f64>) {
        let r = target.rot * self.r0.transpose();
        (na32::Matrix3::from_fn(|i, j| r[(i, j)]), na32::Vector3::new(target.pos.x, target.pos.y, target.pos.z))
    }

    /// IK-Geo's exact solutions (those it does not flag least-squares).
    pub fn geo_solve(&self, target: &Pose) -> Vec<[f64; 6]> {
        let (r, t) = self.geo_target(target);
        self.geo.ik(r, t).into_iter().filter(|(_, ls)| !ls).map(|(q, _)| std::array::from_fn(|i| q[i])).collect()
    }
}

/// IK-Geo's H, P and kinema's tool rotation at q = 0.
type GeoDescription = ([Vector3<f64>; 6], [Vector3<f64>; 7], Matrix3<f64>);

/// IK-Geo's H (unit axes), P (offsets: base to axis 1, axis i to axis i + 1, axis 6 to the tool
/// point) and kinema's tool rotation at q = 0. The point on each axis is its intersection with
/// the next axis, else with the previous one, else the foot of the perpendicular from the
/// previous point, so that the zero offsets IK-Geo's families assume come out exactly zero
/// (benchmarks/geo_kinematics.py does the same for the Python peers).
fn geo_hp(robot: &Robot) -> Result<GeoDescription, String> {
    let kin = Kinematics::new(robot).map_err(|e| e.to_string())?;
    if kin.h.len() != 6 {
        return Err(format!("{}: IK-Geo takes 6R arms", robot.name()));
    }
    let mut o: Vec<Vector3<f64>> = Vec::with_capacity(6);
    for i in 0..6 {
        let next = (i < 5).then(|| meet(&kin.p[i], &kin.h[i], &kin.p[i + 1], &kin.h[i + 1])).flatten();
        let x = next.or_else(|| (i > 0).then(|| meet(&kin.p[i], &kin.h[i], &kin.p[i - 1], &kin.h[i - 1])).flatten());
        let x = x.unwrap_or_else(|| {
            let prev = o.last().copied().unwrap_or_else(Vector3::zeros);
            kin.p[i] + kin.h[i] * (prev - kin.p[i]).dot(&kin.h[i])
        });
        o.push(x);
    }
    let snap = |v: Vector3<f64>| v.map(|c| if c.abs() < 1e-12 { 0.0 } else { c });
    let p: [Vector3<f64>; 7] = std::array::from_fn(|i| match i {
        0 => snap(o[0]),
        6 => snap(kin.tool.pos - o[5]),
        _ => snap(o[i] - o[i - 1]),
    });
    Ok((std::array::from_fn(|i| kin.h[i]), p, kin.tool.rot))
}

/// The point where the lines (a, h) and (b, k) meet, or None (parallel or skew).
fn meet(a: &Vector3<f64>, h: &Vector3<f64>, b: &Vector3<f64>, k: &Vector3<f64>) -> Option<Vector3<f64>> {
    let c = h.cross(k);
    let s = c.norm_squared();
    if s < 1e-18 {
        return None;
    }
    let d = b - a;
    let x = a + h * (d.cross(k).dot(&c) / s);
    let y = b + k * (d.cross(h).dot(&c) / s);
    ((x - y).norm() < 1e-9).then_some(x)
}
