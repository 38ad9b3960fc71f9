//! Jacobians of every built-in robot against finite differences of forward
//! kinematics, and the consistency of the different ways to get FK, frames and
//! Jacobians.

use std::f64::consts::{FRAC_PI_2, PI};

use kinema::nalgebra::{Matrix3, Matrix6xX, Vector3};
use kinema::{builtin_names, Data, Frame, GeometryKind, JointType, Pose, Robot, RpyConvention};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const SAMPLES: usize = 500;
const H: f64 = 1e-6;

fn robots() -> Vec<Robot> {
    let all: Vec<Robot> = builtin_names().map(|n| Robot::builtin(n).unwrap()).collect();
    assert!(all.len() >= 7, "expected the seven built-in robots");
    all
}

fn pose(robot: &Robot, q: &[f64]) -> Pose {
    robot.fk(q).unwrap().world_from_tool
}

fn shifted(q: &[f64], i: usize, h: f64) -> Vec<f64> {
    let mut q = q.to_vec();
    q[i] += h;
    q
}

/// Angular displacement of a small rotation `m` (≈ I + [ω]×): the vee of its
/// skew part, sin(θ)·axis, which is θ·axis to O(θ³).
fn small_rotation_vector(m: &Matrix3<f64>) -> Vector3<f64> {
    0.5 * Vector3::new(m[(2, 1)] - m[(1, 2)], m[(0, 2)] - m[(2, 0)], m[(1, 0)] - m[(0, 1)])
}

/// Central-difference geometric Jacobian in the base frame.
fn fd_jacobian(robot: &Robot, q: &[f64]) -> Matrix6xX<f64> {
    let n = robot.dof();
    let mut j = Matrix6xX::zeros(n);
    for i in 0..n {
        let p = pose(robot, &shifted(q, i, H));
        let m = pose(robot, &shifted(q, i, -H));
        let v = (p.pos - m.pos) / (2.0 * H);
        let w = small_rotation_vector(&(p.rot * m.rot.transpose())) / (2.0 * H);
        j.fixed_view_mut::<3, 1>(0, i).copy_from(&v);
        j.fixed_view_mut::<3, 1>(3, i).copy_from(&w);
    }
    j
}

fn max_abs(m: &Matrix6xX<f64>) -> f64 {
    m.iter().fold(0.0, |a, v| a.max(v.abs()))
}

#[test]
fn base_jacobian_equals_finite_differences() {
    for robot in robots() {
        let mut rng = ChaCha8Rng::seed_from_u64(0xfd);
        let mut worst: f64 = 0.0;
        for _ in 0..SAMPLES {
            let q = robot.random_q(&mut rng);
            let j = robot.jacobian(&q, Frame::Base).unwrap();
            let fd = fd_jacobian(&robot, &q);
            let err = max_abs(&(&j - &fd)) / max_abs(&fd).max(1.0);
            worst = worst.max(err);
            assert!(err < 1e-6, "{}: q = {q:?}\nJ = {j}\nfinite differences = {fd}", robot.name());
        }
        // Central differences with h = 1e-6 are good to ~1e-9 here; a loose
        // tolerance must not hide a systematically worse Jacobian.
        assert!(worst < 1e-8, "{}: worst relative error {worst}", robot.name());
    }
}

#[test]
fn tool_jacobian_is_base_jacobian_rotated() {
    for robot in robots() {
        let mut rng = ChaCha8Rng::seed_from_u64(0x700);
        for _ in 0..SAMPLES {
            let q = robot.random_q(&mut rng);
            let jb = robot.jacobian(&q, Frame::Base).unwrap();
            let jt = robot.jacobian(&q, Frame::Tool).unwrap();
            let rt = pose(&robot, &q).rot.transpose();
            let mut want = Matrix6xX::zeros(robot.dof());
            want.fixed_rows_mut::<3>(0).copy_from(&(rt * jb.fixed_rows::<3>(0)));
            want.fixed_rows_mut::<3>(3).copy_from(&(rt * jb.fixed_rows::<3>(3)));
            assert!(max_abs(&(&jt - &want)) < 1e-12, "{}: q = {q:?}", robot.name());
        }
    }
}

/// Roll-pitch-yaw written out here (not the library's `rot_to_rpy`).
/// Zyx: R = Rz(y)·Ry(p)·Rx(r) → (r, p, y). Xyz: R = Rx(a)·Ry(b)·Rz(c) → (a, b, c).
fn rpy_of(r: &Matrix3<f64>, conv: RpyConvention) -> [f64; 3] {
    match conv {
        RpyConvention::Zyx => [r[(2, 1)].atan2(r[(2, 2)]), (-r[(2, 0)]).asin(), r[(1, 0)].atan2(r[(0, 0)])],
        RpyConvention::Xyz => [(-r[(1, 2)]).atan2(r[(2, 2)]), r[(0, 2)].asin(), (-r[(0, 1)]).atan2(r[(0, 0)])],
    }
}

fn rot_from(rpy: [f64; 3], conv: RpyConvention) -> Matrix3<f64> {
    let rx = |a: f64| Matrix3::new(1.0, 0.0, 0.0, 0.0, a.cos(), -a.sin(), 0.0, a.sin(), a.cos());
    let ry = |a: f64| Matrix3::new(a.cos(), 0.0, a.sin(), 0.0, 1.0, 0.0, -a.sin(), 0.0, a.cos());
    let rz = |a: f64| Matrix3::new(a.cos(), -a.sin(), 0.0, a.sin(), a.cos(), 0.0, 0.0, 0.0, 1.0);
    match conv {
        RpyConvention::Zyx => rz(rpy[2]) * ry(rpy[1]) * rx(rpy[0]),
        RpyConvention::Xyz => rx(rpy[0]) * ry(rpy[1]) * rz(rpy[2]),
    }
}

fn wrap(a: f64) -> f64 {
    let r = a.rem_euclid(2.0 * PI);
    if r > PI {
        r - 2.0 * PI
    } else {
        r
    }
}

#[test]
fn analytic_jacobian_equals_finite_differences_of_rpy() {
    for conv in [RpyConvention::Zyx, RpyConvention::Xyz] {
        for robot in robots() {
            let mut rng = ChaCha8Rng::seed_from_u64(0xa7);
            let mut done = 0;
            while done < SAMPLES {
                let q = robot.random_q(&mut rng);
                let r = pose(&robot, &q).rot;
                let rpy = rpy_of(&r, conv);
                // Our own extraction must reproduce the rotation.
                assert!((rot_from(rpy, conv) - r).norm() < 1e-9);
                if (rpy[1].abs() - FRAC_PI_2).abs() < 0.05 {
                    continue;
                }
                let ja = robot.analytic_jacobian(&q, conv).unwrap();
                let jg = robot.jacobian(&q, Frame::Base).unwrap();
                let n = robot.dof();
                let mut fd = Matrix6xX::zeros(n);
                for i in 0..n {
                    let qp = shifted(&q, i, H);
                    let qm = shifted(&q, i, -H);
                    let (pp, pm) = (pose(&robot, &qp), pose(&robot, &qm));
                    let (ap, am) = (rpy_of(&pp.rot, conv), rpy_of(&pm.rot, conv));
                    let v = (pp.pos - pm.pos) / (2.0 * H);
                    fd.fixed_view_mut::<3, 1>(0, i).copy_from(&v);
                    for k in 0..3 {
                        fd[(3 + k, i)] = wrap(ap[k] - am[k]) / (2.0 * H);
                    }
                }
                let scale = max_abs(&fd).max(1.0);
                assert!(
                    max_abs(&(&ja - &fd)) < 1e-6 * scale,
                    "{} {conv:?}: q = {q:?} rpy = {rpy:?}\nanalytic = {ja}\nfinite differences = {fd}",
                    robot.name()
                );
                // The translational rows are the geometric ones, untouched.
                assert_eq!(ja.fixed_rows::<3>(0), jg.fixed_rows::<3>(0));
                done += 1;
            }
        }
    }
}

#[test]
fn analytic_jacobian_errors_at_the_rpy_singularity() {
    // iiwa with q6 = ±90°: the flange z axis lies along base x → Zyx pitch ±π/2.
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let mut q = vec![0.0; 7];
    q[5] = FRAC_PI_2;
    let rpy = rpy_of(&pose(&robot, &q).rot, RpyConvention::Zyx);
    if (rpy[1].abs() - FRAC_PI_2).abs() < 1e-9 {
        let e = robot.analytic_jacobian(&q, RpyConvention::Zyx).unwrap_err();
        assert!(
            matches!(e, kinema::Error::RpySingularity { pitch } if (pitch.abs() - FRAC_PI_2).abs() < 1e-6),
            "{e:?}"
        );
        assert!(e.to_string().contains("geometric Jacobian"), "{e}");
    } else {
        // Then the other convention must be the singular one here.
        let rpy = rpy_of(&pose(&robot, &q).rot, RpyConvention::Xyz);
        assert!((rpy[1].abs() - FRAC_PI_2).abs() < 1e-9, "{rpy:?}");
        let e = robot.analytic_jacobian(&q, RpyConvention::Xyz).unwrap_err();
        assert!(matches!(e, kinema::Error::RpySingularity { .. }), "{e:?}");
    }
}

#[test]
fn jacobian_forms_agree() {
    for robot in robots() {
        let mut rng = ChaCha8Rng::seed_from_u64(0x1f);
        let mut ws = Data::new(&robot);
        // A workspace sized for another robot must adapt.
        let mut other_ws = Data::new(&Robot::builtin("scara5").unwrap());
        let mut buf = Matrix6xX::from_element(robot.dof(), f64::NAN);
        for _ in 0..SAMPLES {
            let q = robot.random_q(&mut rng);
            for frame in [Frame::Base, Frame::Tool] {
                let j = robot.jacobian(&q, frame).unwrap();
                let fk = kinema::kin::jacobian_into(&robot, &q, frame, &mut buf).unwrap();
                assert_eq!(fk, robot.fk(&q).unwrap());
                assert_eq!(buf, j);
                assert_eq!(ws.jacobian(&robot, &q, frame).unwrap(), &j);
                assert_eq!(other_ws.jacobian(&robot, &q, frame).unwrap(), &j);
            }
        }
    }
}

/// For each joint: (origin, unit axis) in the base frame, from the link frames.
fn joint_axes_from_frames(robot: &Robot, frames: &[Pose]) -> Vec<(Vector3<f64>, Vector3<f64>)> {
    (0..robot.dof())
        .map(|i| match robot.geometry_kind() {
            // Standard DH: joint i + 1 moves about z of frame i (frame 0 = base).
            GeometryKind::Standard => (frames[i].pos, frames[i].rot.column(2).into_owned()),
            // Modified DH: joint i + 1 moves about z of frame i + 1.
            GeometryKind::Modified => (frames[i + 1].pos, frames[i + 1].rot.column(2).into_owned()),
            // General/URDF: about `axis`, given in the child link frame i + 1.
            GeometryKind::General => {
                let kinema::LinkGeometry::General { axis, .. } = robot.joints()[i].geometry else {
                    panic!("general robot with a DH joint")
                };
                (frames[i + 1].pos, frames[i + 1].rot * axis)
            }
        })
        .collect()
}

#[test]
fn link_frames_agree_with_fk_and_jacobian_columns() {
    for robot in robots() {
        let mut rng = ChaCha8Rng::seed_from_u64(0x11);
        let mut ws = Data::new(&robot);
        let n = robot.dof();
        for _ in 0..SAMPLES {
            let q = robot.random_q(&mut rng);
            let frames = robot.link_frames(&q).unwrap();
            assert_eq!(frames.len(), n + 2);
            assert_eq!(ws.link_frames(&robot, &q).unwrap(), frames.as_slice());
            let fk = robot.fk(&q).unwrap();
            assert_eq!(frames[0], *robot.base());
            let last = frames[n + 1];
            assert!(
                (last.pos - fk.world_from_tool.pos).norm() < 1e-14
                    && (last.rot - fk.world_from_tool.rot).norm() < 1e-14,
                "{}",
                robot.name()
            );
            // Flange (last link frame) · tool = tool frame.
            let flange_tool = frames[n] * *robot.tool();
            assert!((flange_tool.pos - fk.world_from_tool.pos).norm() < 1e-12);
            assert!((flange_tool.rot - fk.world_from_tool.rot).norm() < 1e-12);
            for f in &frames {
                assert!((f.rot.transpose() * f.rot - Matrix3::identity()).norm() < 1e-12);
                assert!((f.rot.determinant() - 1.0).abs() < 1e-12);
            }
            let j = robot.jacobian(&q, Frame::Base).unwrap();
            let pe = fk.world_from_tool.pos;
            for (i, (o, z)) in joint_axes_from_frames(&robot, &frames).into_iter().enumerate() {
                let (v, w) = match robot.joints()[i].kind {
                    JointType::Revolute => (z.cross(&(pe - o)), z),
                    JointType::Prismatic => (z, Vector3::zeros()),
                };
                let col = j.column(i);
                let err = (col.fixed_rows::<3>(0) - v).norm() + (col.fixed_rows::<3>(3) - w).norm();
                assert!(err < 1e-12, "{} joint {}: q = {q:?}", robot.name(), i + 1);
            }
        }
    }
}

/// DH frames: each link frame i is frame i−1 times the DH link transform, built
/// here from the table (standard: Rz Tz Tx Rx; modified: Rx Tx Rz Tz).
#[test]
fn link_frames_follow_the_dh_tables() {
    let rx = |a: f64| {
        Pose::new(Matrix3::new(1.0, 0.0, 0.0, 0.0, a.cos(), -a.sin(), 0.0, a.sin(), a.cos()), Vector3::zeros())
    };
    let rz = |a: f64| {
        Pose::new(Matrix3::new(a.cos(), -a.sin(), 0.0, a.sin(), a.cos(), 0.0, 0.0, 0.0, 1.0), Vector3::zeros())
    };
    let t = |x: f64, z: f64| Pose::new(Matrix3::identity(), Vector3::new(x, 0.0, z));
    for robot in robots() {
        let mut rng = ChaCha8Rng::seed_from_u64(0xd4);
        for _ in 0..100 {
            let q = robot.random_q(&mut rng);
            let frames = robot.link_frames(&q).unwrap();
            let mut acc = *robot.base();
            for (i, jt) in robot.joints().iter().enumerate() {
                let kinema::LinkGeometry::Dh { convention, d, a, alpha, theta } = jt.geometry else {
                    panic!("built-in robots are DH tables")
                };
                let (th, dd) = match jt.kind {
                    JointType::Revolute => (q[i] + jt.offset, d),
                    JointType::Prismatic => (theta, q[i] + jt.offset),
                };
                acc = match convention {
                    kinema::DhConvention::Standard => acc * rz(th) * t(0.0, dd) * t(a, 0.0) * rx(alpha),
                    kinema::DhConvention::Modified => acc * rx(alpha) * t(a, 0.0) * rz(th) * t(0.0, dd),
                };
                let f = frames[i + 1];
                assert!(
                    (f.pos - acc.pos).norm() < 1e-12 && (f.rot - acc.rot).norm() < 1e-12,
                    "{} frame {}",
                    robot.name(),
                    i + 1
                );
            }
            let tool = acc * *robot.tool();
            let fk = pose(&robot, &q);
            assert!((tool.pos - fk.pos).norm() < 1e-12 && (tool.rot - fk.rot).norm() < 1e-12);
        }
    }
}

#[test]
fn fk_batch_equals_fk_bitwise() {
    for robot in robots() {
        let mut rng = ChaCha8Rng::seed_from_u64(0xba7c);
        let n = robot.dof();
        let mut qs = Vec::with_capacity(10_000 * n);
        for k in 0..10_000 {
            let mut q = robot.random_q(&mut rng);
            if k % 7 == 0 {
                // Some outside the limits too: flags must match as well.
                q[k % n] += 10.0;
            }
            qs.extend_from_slice(&q);
        }
        let batch = robot.fk_batch(&qs).unwrap();
        assert_eq!(batch.len(), 10_000);
        for (q, b) in qs.chunks_exact(n).zip(&batch) {
            let one = robot.fk(q).unwrap();
            // Bitwise: same floating-point operations in the same order.
            for (x, y) in one
                .world_from_tool
                .rot
                .iter()
                .chain(one.world_from_tool.pos.iter())
                .zip(b.world_from_tool.rot.iter().chain(b.world_from_tool.pos.iter()))
            {
                assert_eq!(x.to_bits(), y.to_bits(), "{}: q = {q:?}", robot.name());
            }
            assert_eq!(one.out_of_limits, b.out_of_limits);
        }
        assert!(batch.iter().any(|f| !f.within_limits()));
        assert!(robot.fk_batch(&[]).unwrap().is_empty());
    }
}

#[test]
fn out_of_limits_flags_exactly_the_offending_joints() {
    for robot in robots() {
        let mut rng = ChaCha8Rng::seed_from_u64(0x0e);
        let n = robot.dof();
        let mut seen_empty = false;
        let mut seen_full = false;
        for _ in 0..2000 {
            let mut q = robot.random_q(&mut rng);
            let mut want = Vec::new();
            for (i, j) in robot.joints().iter().enumerate() {
                let l = j.limits;
                match rng.random_range(0..4) {
                    0 if l.min.is_finite() => {
                        q[i] = l.min - rng.random_range(1e-9..1.0);
                        want.push(i);
                    }
                    1 if l.max.is_finite() => {
                        q[i] = l.max + rng.random_range(1e-9..1.0);
                        want.push(i);
                    }
                    // Exactly on a limit is inside.
                    2 => q[i] = if rng.random_bool(0.5) { l.min } else { l.max },
                    _ => {}
                }
            }
            let fk = robot.fk(&q).unwrap();
            let got: Vec<usize> = fk.out_of_limits.indices().collect();
            assert_eq!(got, want, "{}: q = {q:?}", robot.name());
            assert_eq!(fk.within_limits(), want.is_empty());
            for i in 0..n {
                assert_eq!(fk.out_of_limits.contains(i), want.contains(&i));
            }
            // Every path reports the same flags.
            let mut j = Matrix6xX::zeros(n);
            assert_eq!(
                kinema::kin::jacobian_into(&robot, &q, Frame::Base, &mut j).unwrap().out_of_limits,
                fk.out_of_limits
            );
            let mut frames = vec![Pose::IDENTITY; n + 2];
            assert_eq!(kinema::kin::link_frames_into(&robot, &q, &mut frames).unwrap().out_of_limits, fk.out_of_limits);
            seen_empty |= want.is_empty();
            seen_full |= want.len() == n;
        }
        assert!(seen_empty && seen_full, "{}: sample did not cover both extremes", robot.name());
    }
}
