//! Helpers shared by the test files: analytic-IK checks here, random arms in `arms`.
#![allow(dead_code)]

pub mod arms;

use kinema::ik::IkSolver;
use kinema::nalgebra::Vector3;
use kinema::{Error, GeometryKind, Joint, JointType, Limits, LinkGeometry, Model, Pose, Robot, RpyConvention};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Whether two joint vectors agree to `tol`, angles compared modulo 2π.
pub fn same_angles(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| kinema::ik::wrap_angle(x - y).abs() < tol)
}

/// 3000 random finite poses (a third with a vertical or level approach):
/// the solver never panics, never returns NaN, and every solution it returns
/// reaches the target position; anything else is `Unreachable`.
pub fn random_poses_never_panic_or_return_nan(solver: &dyn IkSolver) {
    let ik = solver.name();
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    for i in 0..3000 {
        let rpy = [rng.random_range(-4.0..4.0), rng.random_range(-4.0..4.0), rng.random_range(-4.0..4.0)];
        let mut rpy = rpy;
        if i % 3 == 0 {
            rpy[0] = 0.0;
            rpy[1] = [0.0, std::f64::consts::FRAC_PI_2, -std::f64::consts::FRAC_PI_2][i % 9 / 3];
        }
        let xyz = [rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0)];
        let t = Pose::from_xyz_rpy(xyz, rpy, RpyConvention::Zyx);
        match solver.solve(&t) {
            Ok(sols) => {
                assert!(!sols.is_empty(), "{ik}");
                for s in &sols {
                    assert!(s.q.iter().all(|v| v.is_finite()), "{ik}: {s:?}");
                    assert!(s.position_error < 1e-9 && s.orientation_error.is_finite(), "{ik}: {s:?}");
                }
            }
            Err(Error::Unreachable { .. }) => {}
            Err(e) => panic!("{ik}: {e}"),
        }
    }
}

/// The allocation-free kernel and the evaluating solve agree: the same joint
/// vectors and labels in the same order, and every candidate reaches the
/// target (FK position within 1e-9 m).
pub fn kernel_matches_solve<const N: usize, const M: usize>(
    robot: &kinema::Robot,
    candidates: &kinema::ik::Candidates<N, M>,
    solutions: &[kinema::ik::Solution],
    target_position: [f64; 3],
) {
    assert_eq!(candidates.len(), solutions.len());
    for ((q, label), s) in candidates.iter().zip(solutions) {
        assert_eq!(&q[..], &s.q[..]);
        assert_eq!(label, s.branch);
        let p = robot.fk(q).unwrap().world_from_tool.pos;
        let d = (p - kinema::nalgebra::Vector3::from(target_position)).norm();
        assert!(d < 1e-9, "{label}: {d}");
    }
}

/// A robot of `general` revolute joints (limits ±π) whose axes at q = 0 are
/// the unit directions `h` through the points `p`, in the world frame before
/// `base`; every joint frame at q = 0 is aligned with that frame, so origin i
/// is the translation from p_{i−1} to p_i.
pub fn robot_from_axes(name: &str, h: &[Vector3<f64>], p: &[Vector3<f64>], base: Pose, tool: Pose) -> Robot {
    let joints: Vec<Joint> = (0..h.len())
        .map(|i| {
            let d = p[i] - if i == 0 { Vector3::zeros() } else { p[i - 1] };
            Joint {
                name: format!("j{}", i + 1),
                kind: JointType::Revolute,
                geometry: LinkGeometry::General { origin: Pose::translation(d.x, d.y, d.z), axis: h[i] },
                offset: 0.0,
                limits: Limits::position(-std::f64::consts::PI, std::f64::consts::PI),
            }
        })
        .collect();
    Model::builder(name, GeometryKind::General)
        .joints(joints)
        .base(base)
        .tool(tool)
        .pose("home", vec![0.0; h.len()])
        .build()
        .map(Robot::new)
        .unwrap()
}
