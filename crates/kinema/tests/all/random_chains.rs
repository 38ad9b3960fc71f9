//! Forward kinematics, link frames and Jacobians of random arms against an
//! independent computation.
//!
//! Most arms mix every kind of joint the compiled chain distinguishes:
//! standard and modified DH rows, revolute and prismatic, twists of 0, ±90°,
//! ±180° and arbitrary angles, general (URDF-style) joints about ±z or any
//! axis, random offsets, base and tool transforms, and chains longer than
//! one eight-joint angle block; a third are uniform chains of standard or of
//! modified DH revolute joints with exact twists, which the chain walks
//! without a branch per joint. The oracle is the textbook product of 4×4
//! homogeneous matrices, with the standard library's sine and cosine, written
//! here without any of the chain's tricks; the Jacobian is checked against
//! central differences of that product.

use kinema::nalgebra::{Matrix3, Matrix4, Matrix6xX, Rotation3, Unit, Vector3};
use kinema::{DhConvention, Frame, Joint, JointType, LinkGeometry, Pose, Robot};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::common;
use common::arms::{random_q, random_robot};

const ROBOTS: usize = 3000;
const CONFIGS_PER_ROBOT: usize = 3;

fn homogeneous(rot: Matrix3<f64>, pos: Vector3<f64>) -> Matrix4<f64> {
    let mut m = Matrix4::identity();
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(&rot);
    m.fixed_view_mut::<3, 1>(0, 3).copy_from(&pos);
    m
}

fn rz(t: f64) -> Matrix4<f64> {
    homogeneous(*Rotation3::from_axis_angle(&Vector3::z_axis(), t).matrix(), Vector3::zeros())
}

fn rx(t: f64) -> Matrix4<f64> {
    homogeneous(*Rotation3::from_axis_angle(&Vector3::x_axis(), t).matrix(), Vector3::zeros())
}

fn trans(x: f64, y: f64, z: f64) -> Matrix4<f64> {
    homogeneous(Matrix3::identity(), Vector3::new(x, y, z))
}

fn of_pose(p: &Pose) -> Matrix4<f64> {
    homogeneous(p.rot, p.pos)
}

/// The textbook transform of one joint at joint value `q`.
fn joint_matrix(j: &Joint, q: f64) -> Matrix4<f64> {
    let v = q + j.offset;
    let prismatic = j.kind == JointType::Prismatic;
    match j.geometry {
        LinkGeometry::Dh { convention, d, a, alpha, theta } => {
            let (th, d) = if prismatic { (theta, v) } else { (v, d) };
            match convention {
                DhConvention::Standard => rz(th) * trans(0.0, 0.0, d) * trans(a, 0.0, 0.0) * rx(alpha),
                DhConvention::Modified => rx(alpha) * trans(a, 0.0, 0.0) * rz(th) * trans(0.0, 0.0, d),
            }
        }
        LinkGeometry::General { origin, axis } => {
            let motion = if prismatic {
                homogeneous(Matrix3::identity(), axis * v)
            } else {
                homogeneous(*Rotation3::from_axis_angle(&Unit::new_normalize(axis), v).matrix(), Vector3::zeros())
            };
            of_pose(&origin) * motion
        }
    }
}

/// Link frames 1..=n and the tool frame, by the product of 4×4 matrices.
fn naive_frames(robot: &Robot, q: &[f64]) -> Vec<Matrix4<f64>> {
    let mut t = of_pose(robot.base());
    let mut out = Vec::with_capacity(q.len() + 1);
    for (j, &v) in robot.joints().iter().zip(q) {
        t *= joint_matrix(j, v);
        out.push(t);
    }
    out.push(t * of_pose(robot.tool()));
    out
}

fn pose_error(p: &Pose, m: &Matrix4<f64>) -> f64 {
    let dr = (p.rot - m.fixed_view::<3, 3>(0, 0)).abs().max();
    let dp = (p.pos - m.fixed_view::<3, 1>(0, 3)).abs().max();
    dr.max(dp)
}

#[test]
fn fk_and_link_frames_equal_the_matrix_product() {
    let mut rng = ChaCha8Rng::seed_from_u64(0xC4A1);
    let mut worst: f64 = 0.0;
    for _ in 0..ROBOTS {
        let robot = random_robot(&mut rng);
        let n = robot.dof();
        for _ in 0..CONFIGS_PER_ROBOT {
            let q = random_q(&mut rng, n);
            let naive = naive_frames(&robot, &q);
            let fk = robot.fk(&q).unwrap();
            // The matrix form is the same pose, value for value, and the same limit flags.
            let mut m = [0.0; 16];
            assert_eq!(kinema::kin::fk_matrix_into(&robot, &q, &mut m).unwrap(), fk.out_of_limits);
            let rows = fk.world_from_tool.to_rows();
            for (k, (a, b)) in m.iter().zip(rows.iter().flatten()).enumerate() {
                assert_eq!(a.to_bits(), b.to_bits(), "matrix entry {k}: {robot:?} at q = {q:?}");
            }
            let e = pose_error(&fk.world_from_tool, &naive[n]);
            // Chains reach up to ~20 × 1.2 m; errors stay at rounding level.
            assert!(e < 1e-12, "FK differs by {e:e}: {robot:?} at q = {q:?}");
            worst = worst.max(e);
            let frames = robot.link_frames(&q).unwrap();
            assert!(pose_error(&frames[0], &of_pose(robot.base())) == 0.0);
            for (i, (f, m)) in frames[1..].iter().zip(&naive).enumerate() {
                let e = pose_error(f, m);
                assert!(e < 1e-12, "frame {} differs by {e:e}: {robot:?} at q = {q:?}", i + 1);
            }
        }
    }
    eprintln!("worst FK difference over {ROBOTS} random arms: {worst:e}");
}

#[test]
fn jacobians_equal_central_differences_of_the_matrix_product() {
    const H: f64 = 1e-6;
    let mut rng = ChaCha8Rng::seed_from_u64(0xC4A2);
    let mut worst: f64 = 0.0;
    for _ in 0..ROBOTS / 3 {
        let robot = random_robot(&mut rng);
        let n = robot.dof();
        let q = random_q(&mut rng, n);
        let mut fd = Matrix6xX::zeros(n);
        for i in 0..n {
            let at = |h: f64| {
                let mut q = q.clone();
                q[i] += h;
                naive_frames(&robot, &q)[n]
            };
            let (p, m) = (at(H), at(-H));
            let v = (p.fixed_view::<3, 1>(0, 3) - m.fixed_view::<3, 1>(0, 3)) / (2.0 * H);
            // dR·Rᵀ ≈ [ω]× over the step.
            let dr = p.fixed_view::<3, 3>(0, 0) * m.fixed_view::<3, 3>(0, 0).transpose();
            let w = 0.5 * Vector3::new(dr[(2, 1)] - dr[(1, 2)], dr[(0, 2)] - dr[(2, 0)], dr[(1, 0)] - dr[(0, 1)])
                / (2.0 * H);
            fd.fixed_view_mut::<3, 1>(0, i).copy_from(&v);
            fd.fixed_view_mut::<3, 1>(3, i).copy_from(&w);
        }
        let j = robot.jacobian(&q, Frame::Base).unwrap();
        let e = (&j - &fd).abs().max();
        // The row-major form is the same matrix, value for value, in both
        // frames: every value written (the buffer starts as a NaN with a
        // payload no computation makes) and nothing past its end (4 guards).
        const POISON: u64 = 0x7ff8_dead_beef_0001;
        for frame in [Frame::Base, Frame::Tool] {
            let cols = robot.jacobian(&q, frame).unwrap();
            let mut buf = vec![f64::from_bits(POISON); 6 * n + 4];
            let outside = kinema::kin::jacobian_rows_into(&robot, &q, frame, &mut buf[..6 * n]).unwrap();
            assert!(buf[6 * n..].iter().all(|g| g.to_bits() == POISON), "wrote past the end: {robot:?}");
            let rows = &buf[..6 * n];
            assert_eq!(outside, robot.fk(&q).unwrap().out_of_limits);
            for r in 0..6 {
                for c in 0..n {
                    assert_eq!(rows[r * n + c].to_bits(), cols[(r, c)].to_bits(), "({r}, {c}) {frame:?}: {robot:?}");
                }
            }
        }
        assert!(e < 1e-6, "Jacobian differs from central differences by {e:e}: {robot:?} at q = {q:?}");
        worst = worst.max(e);
        // The tool-frame Jacobian is the base one in tool axes.
        let rt = naive_frames(&robot, &q)[n].fixed_view::<3, 3>(0, 0).transpose();
        let jt = robot.jacobian(&q, Frame::Tool).unwrap();
        for c in 0..n {
            let v = rt * j.fixed_view::<3, 1>(0, c);
            let w = rt * j.fixed_view::<3, 1>(3, c);
            let d = (jt.fixed_view::<3, 1>(0, c) - v).abs().max().max((jt.fixed_view::<3, 1>(3, c) - w).abs().max());
            assert!(d < 1e-12, "tool-frame column {c} differs by {d:e}: {robot:?}");
        }
    }
    eprintln!("worst Jacobian − central differences over {} random arms: {worst:e}", ROBOTS / 3);
}
