//! Manipulability and singularity analysis against direct computations:
//! determinants, eigenvalues of Gram matrices, and seed 004 eq. (12).

use std::f64::consts::FRAC_PI_6;

use kinema::analysis::{self, Axes};
use kinema::nalgebra::{DMatrix, Matrix3, Matrix6xX, Vector3};
use kinema::{Frame, Robot};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const SAMPLES: usize = 1000;
/// 7, 7, 6, 5 (revolute) and 5 (two prismatic) joints.
const ROBOTS: &[&str] = &["lbr-iiwa-14-r820", "panda", "ur5", "scorbot-er-v-plus", "scara5"];

/// The selected rows as a dynamic matrix, copied here (not via the library).
fn block(j: &Matrix6xX<f64>, axes: Axes) -> DMatrix<f64> {
    let (start, n) = match axes {
        Axes::All => (0, 6),
        Axes::Translation => (0, 3),
        Axes::Rotation => (3, 3),
    };
    DMatrix::from_fn(n, j.ncols(), |r, c| j[(start + r, c)])
}

/// Squared singular values from the eigenvalues of the smaller Gram matrix
/// (J·Jᵀ or Jᵀ·J), largest first: exactly min(rows, cols) of them.
fn sigma_squared(m: &DMatrix<f64>) -> Vec<f64> {
    let g = if m.nrows() <= m.ncols() { m * m.transpose() } else { m.transpose() * m };
    let mut ev: Vec<f64> = g.symmetric_eigen().eigenvalues.iter().copied().collect();
    ev.sort_by(|a, b| b.total_cmp(a));
    ev
}

fn unit(rng: &mut ChaCha8Rng) -> Vector3<f64> {
    loop {
        let v = Vector3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
        let n = v.norm();
        if n > 0.1 && n <= 1.0 {
            return v / n;
        }
    }
}

fn for_each_config(mut f: impl FnMut(&Robot, &[f64], &Matrix6xX<f64>, &mut ChaCha8Rng)) {
    for name in ROBOTS {
        let robot = Robot::builtin(name).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(0xa1a1);
        for _ in 0..SAMPLES {
            let q = robot.random_q(&mut rng);
            let j = robot.jacobian(&q, Frame::Base).unwrap();
            f(&robot, &q, &j, &mut rng);
        }
    }
}

#[test]
fn yoshikawa_is_sqrt_det_j_jt() {
    for_each_config(|robot, q, j, _| {
        for axes in [Axes::All, Axes::Translation, Axes::Rotation] {
            let m = block(j, axes);
            let w = analysis::yoshikawa(j, axes).unwrap();
            let jjt = &m * m.transpose();
            let det = jjt.determinant();
            // An upper bound of det(J·Jᵀ): (trace)^rows ≥ (σmax²)^rows.
            let sc = jjt.trace().powi(m.nrows() as i32);
            if m.nrows() <= m.ncols() {
                assert!(w >= 0.0);
                assert!((w * w - det).abs() <= 1e-10 * sc, "{} {axes:?} q = {q:?}: {w}² vs det = {det}", robot.name());
                if det > 1e-6 * sc {
                    let want = det.sqrt();
                    assert!(
                        (w - want).abs() <= 1e-8 * want,
                        "{} {axes:?} q = {q:?}: {w} vs √det = {want}",
                        robot.name()
                    );
                }
            } else {
                // 6 rows, 5 joints: J·Jᵀ is singular by construction.
                assert_eq!(w, 0.0, "{} {axes:?}", robot.name());
                assert!(det.abs() < 1e-12 * sc, "{}: det = {det}", robot.name());
            }
        }
    });
}

#[test]
fn singular_values_are_roots_of_gram_eigenvalues() {
    for_each_config(|robot, q, j, _| {
        for axes in [Axes::All, Axes::Translation, Axes::Rotation] {
            let m = block(j, axes);
            let s = analysis::singular_values(j, axes).unwrap();
            let want = sigma_squared(&m);
            assert_eq!(s.len(), m.nrows().min(m.ncols()));
            assert_eq!(s.len(), want.len());
            let top = want[0];
            for (k, (a, b)) in s.iter().zip(&want).enumerate() {
                assert!(*a >= 0.0);
                assert!(
                    (a * a - b).abs() <= 1e-12 * top.max(1e-300),
                    "{} {axes:?} q = {q:?}: σ{k}² = {} vs eigenvalue {b}",
                    robot.name(),
                    a * a
                );
            }
            assert!(s.windows(2).all(|w| w[0] >= w[1]), "largest first");

            // Condition number σmax/σmin, where the Gram route is accurate
            // (σmin² well above ε·σmax²).
            let c = analysis::condition(j, axes).unwrap();
            let last = *want.last().unwrap();
            if last > 1e-8 * top {
                let want_c = (top / last).sqrt();
                assert!((c - want_c).abs() <= 1e-6 * want_c, "{} {axes:?}: condition {c} vs {want_c}", robot.name());
            }
            assert!(c >= 1.0);
        }
    });
}

#[test]
fn rank_counts_singular_values_above_tolerance() {
    for_each_config(|robot, _, j, rng| {
        let m = block(j, Axes::All);
        let want = sigma_squared(&m);
        let (rank, tol) = analysis::rank(j, Axes::All, None).unwrap();
        // MATLAB's default: max(rows, cols)·σmax·ε.
        let want_tol = 6usize.max(robot.dof()) as f64 * want[0].sqrt() * f64::EPSILON;
        assert!((tol - want_tol).abs() <= 1e-6 * want_tol);
        // Random configurations are generically of full rank.
        let generic = want.last().unwrap().sqrt() > 1e-6;
        if generic {
            assert_eq!(rank, 6.min(robot.dof()), "{}", robot.name());
        }
        // An explicit tolerance between two singular values splits them there.
        let s = analysis::singular_values(j, Axes::All).unwrap();
        let k = 1 + rng.random_range(0..s.len() - 1);
        {
            if s[k] < 0.99 * s[k - 1] {
                let mid = 0.5 * (s[k] + s[k - 1]);
                assert_eq!(analysis::rank(j, Axes::All, Some(mid)).unwrap().0, k);
            }
        }
    });
    let j = Robot::builtin("ur5").unwrap().jacobian(&[0.1; 6], Frame::Base).unwrap();
    assert!(analysis::rank(&j, Axes::All, Some(-1.0)).is_err());
    assert!(analysis::rank(&j, Axes::All, Some(f64::NAN)).is_err());
}

#[test]
fn ellipsoid_axes_are_eigenvectors_of_j_jt() {
    for_each_config(|robot, q, j, _| {
        for axes in [Axes::Translation, Axes::Rotation] {
            let e = analysis::ellipsoid(j, axes).unwrap();
            let m = block(j, axes);
            let p = &m * m.transpose();
            let a = Matrix3::from_fn(|r, c| p[(r, c)]);
            let scale = a.norm().max(1e-300);
            for k in 0..3 {
                let ax = e.axes.column(k).into_owned();
                let r = e.radii[k];
                assert!((ax.norm() - 1.0).abs() < 1e-12);
                assert!(
                    (a * ax - ax * (r * r)).norm() <= 1e-10 * scale,
                    "{} {axes:?} q = {q:?} axis {k}",
                    robot.name()
                );
            }
            // Orthonormal, largest radius first, volume = Yoshikawa.
            assert!((e.axes.transpose() * e.axes - Matrix3::identity()).norm() < 1e-12);
            assert!(e.radii[0] >= e.radii[1] && e.radii[1] >= e.radii[2] && e.radii[2] >= 0.0);
            let prod = e.radii.iter().product::<f64>();
            let det = a.determinant().max(0.0).sqrt();
            assert!((prod - det).abs() <= 1e-8 * det + 1e-9 * scale.sqrt().powi(3));
        }
    });
    let j = Robot::builtin("ur5").unwrap().jacobian(&[0.1; 6], Frame::Base).unwrap();
    assert!(matches!(
        analysis::ellipsoid(&j, Axes::All),
        Err(kinema::Error::Input(kinema::InputError::DoesNotFit { .. }))
    ));
}

/// (J·Jᵀ)⁻¹ through the adjugate, written out: the matrix [[a, d, e], [d, b, f],
/// [e, f, c]] of seed 004 eq. (12).
fn inverse_3x3(m: &Matrix3<f64>) -> Matrix3<f64> {
    let det = m[(0, 0)] * (m[(1, 1)] * m[(2, 2)] - m[(1, 2)] * m[(2, 1)])
        - m[(0, 1)] * (m[(1, 0)] * m[(2, 2)] - m[(1, 2)] * m[(2, 0)])
        + m[(0, 2)] * (m[(1, 0)] * m[(2, 1)] - m[(1, 1)] * m[(2, 0)]);
    let c = |r0: usize, c0: usize, r1: usize, c1: usize| m[(r0, c0)] * m[(r1, c1)] - m[(r0, c1)] * m[(r1, c0)];
    Matrix3::new(
        c(1, 1, 2, 2),
        -c(0, 1, 2, 2),
        c(0, 1, 1, 2),
        -c(1, 0, 2, 2),
        c(0, 0, 2, 2),
        -c(0, 0, 1, 2),
        c(1, 0, 2, 1),
        -c(0, 0, 2, 1),
        c(0, 0, 1, 1),
    ) / det
}

#[test]
fn manipulability_along_equals_seed004_eq12() {
    let mut checked = 0;
    for_each_config(|robot, q, j, rng| {
        for axes in [Axes::Translation, Axes::Rotation] {
            let m = block(j, axes);
            let p = &m * m.transpose();
            let jjt = Matrix3::from_fn(|r, c| p[(r, c)]);
            let ev = sigma_squared(&m);
            // Non-singular only: the closed form needs the inverse.
            if ev[2] < 1e-6 * ev[0] {
                continue;
            }
            let inv = inverse_3x3(&jjt);
            let (a, b, c) = (inv[(0, 0)], inv[(1, 1)], inv[(2, 2)]);
            let (d, e, f) = (inv[(0, 1)], inv[(0, 2)], inv[(1, 2)]);
            {
                let v = unit(rng);
                let (vx, vy, vz) = (v.x, v.y, v.z);
                let delta =
                    a * vx * vx + b * vy * vy + c * vz * vz + 2.0 * d * vx * vy + 2.0 * e * vx * vz + 2.0 * f * vy * vz;
                let t = 1.0 / delta.sqrt();
                let got = analysis::manipulability_along(j, axes, &v).unwrap();
                assert!(
                    (got - t).abs() <= 1e-7 * t,
                    "{} {axes:?} q = {q:?} v = {v:?}: {got} vs eq. (12) {t}",
                    robot.name()
                );
                // The direction's length does not matter, its sign neither.
                let scaled = analysis::manipulability_along(j, axes, &(v * -3.7)).unwrap();
                assert!((scaled - got).abs() <= 1e-12 * got);
                // It lies between the smallest and the largest radius.
                assert!(got <= ev[0].sqrt() * (1.0 + 1e-9) && got >= ev[2].sqrt() * (1.0 - 1e-9));
                checked += 1;
            }
        }
    });
    assert!(checked > 5_000, "{checked}");
}

/// The iiwa's coupled singularity.
///
/// Finding: at `sing-coupled` as printed in Cuadro III and with Fig. 13,
/// q = (π/6, 0, 0, 0, 0, π/6, π/3), neither 3-row block is singular — J_v and
/// J_ω both have rank 3 (the tilted flange, q6 = π/6, puts the tool point off
/// the common axis of joints 1, 3, 5); only the full 6×7 Jacobian loses rank
/// (4). So `manipulability_along` is positive in every direction there. The
/// "line" ellipsoid that Fig. 13 describes belongs to the configuration of
/// its caption, q2 = … = q6 = 0: tool point on the axis of joints 1, 3, 5, 7,
/// and the translational ellipsoid is a line along the horizontal direction
/// the parallel axes 2, 4, 6 push the tool in. There it is 0 across the line.
#[test]
fn manipulability_along_at_the_coupled_singularity() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let q = robot.pose("sing-coupled").unwrap();
    let j = robot.jacobian(q, Frame::Base).unwrap();
    for axes in [Axes::Translation, Axes::Rotation] {
        let m = block(&j, axes);
        let ev = sigma_squared(&m);
        assert!(ev[2] > 1e-4, "{axes:?}: {ev:?}");
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        for _ in 0..100 {
            assert!(analysis::manipulability_along(&j, axes, &unit(&mut rng)).unwrap() > 1e-3);
        }
    }

    // Fig. 13's caption: q2 … q6 = 0.
    let q = [FRAC_PI_6, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0 * FRAC_PI_6];
    let j = robot.jacobian(&q, Frame::Base).unwrap();
    let m = block(&j, Axes::Translation);
    assert_eq!(analysis::rank(&j, Axes::Translation, None).unwrap().0, 1);
    // The line: joint 2's axis is horizontal, z₁ = (−sin q1, cos q1, 0) in
    // standard DH; joints 2, 4, 6 all move the tool point along z₁ × ẑ.
    let z1 = Vector3::new(-FRAC_PI_6.sin(), FRAC_PI_6.cos(), 0.0);
    let line = z1.cross(&Vector3::z());
    // Its half-length: the joint-2 column's speed combined over the joints
    // (|J_v| restricted to that line), from the Gram matrix directly.
    let speed = (line.transpose() * &m * m.transpose() * line)[(0, 0)].sqrt();
    let along = analysis::manipulability_along(&j, Axes::Translation, &line).unwrap();
    assert!((along - speed).abs() < 1e-12 * speed && speed > 0.1, "{along} vs {speed}");
    let e = analysis::ellipsoid(&j, Axes::Translation).unwrap();
    assert!((e.radii[0] - speed).abs() < 1e-12);
    assert!(e.radii[1] < 1e-12 && e.radii[2] < 1e-12);
    for dir in [Vector3::z(), z1, (Vector3::z() + z1).normalize(), line + Vector3::z() * 0.1] {
        assert_eq!(analysis::manipulability_along(&j, Axes::Translation, &dir).unwrap(), 0.0, "{dir:?}");
    }
    // A direction that is not a usable vector.
    for bad in [Vector3::zeros(), Vector3::new(f64::NAN, 0.0, 1.0), Vector3::new(f64::INFINITY, 0.0, 0.0)] {
        assert!(analysis::manipulability_along(&j, Axes::Translation, &bad).is_err());
    }
}

/// column(joint) = Σ coefficient · column(on).
fn reproduces(j: &Matrix6xX<f64>, d: &analysis::Dependency) -> bool {
    let mut sum = kinema::nalgebra::Vector6::zeros();
    for &(k, c) in &d.on {
        assert!(k < d.joint, "depends on an earlier joint");
        sum += j.column(k) * c;
    }
    (sum - j.column(d.joint)).norm() < 1e-9 * j.norm()
}

#[test]
fn dependent_joints_at_generic_and_coupled_configurations() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0xde9);
    // Generic configurations: columns 1…6 independent (checked here through
    // their determinant). The 7th column then lies in their span, but only
    // because the arm is redundant: nothing is reported.
    let mut generic = 0;
    for _ in 0..SAMPLES {
        let q = robot.random_q(&mut rng);
        let j = robot.jacobian(&q, Frame::Base).unwrap();
        let six = DMatrix::from_fn(6, 6, |r, c| j[(r, c)]);
        if six.determinant().abs() < 1e-3 {
            continue;
        }
        let deps = analysis::dependent_joints(&j, None).unwrap();
        assert_eq!(deps, vec![], "{q:?}");
        generic += 1;
    }
    assert!(generic > SAMPLES / 2, "{generic}");
    // q2 = 0 alone is not a singularity of the redundant arm (rank 6), but
    // joints 1 and 3 are aligned, and that is reported.
    let q = [0.3, 0.0, -0.4, -1.1, 0.5, 0.9, 0.2];
    let j = robot.jacobian(&q, Frame::Base).unwrap();
    assert_eq!(analysis::rank(&j, Axes::All, None).unwrap().0, 6);
    let deps = analysis::dependent_joints(&j, None).unwrap();
    assert_eq!(deps.len(), 1, "{deps:?}");
    assert_eq!(deps[0].joint, 2);
    assert!(reproduces(&j, &deps[0]));
    assert_eq!(deps[0].on.len(), 1);
    assert!((deps[0].on[0].1 - 1.0).abs() < 1e-9 && deps[0].on[0].0 == 0);
    // A generic configuration of a 6-joint arm: nothing depends.
    let ur5 = Robot::builtin("ur5").unwrap();
    let j = ur5.jacobian(ur5.home(), Frame::Base).unwrap();
    assert_eq!(analysis::dependent_joints(&j, None).unwrap(), vec![]);
    // And the first six iiwa joints at a generic configuration.
    let q = [0.3, 0.7, -0.4, -1.1, 0.5, 0.9, 0.2];
    let j = robot.jacobian(&q, Frame::Base).unwrap();
    let j6 = Matrix6xX::from_fn(6, |r, c| j[(r, c)]);
    assert_eq!(analysis::dependent_joints(&j6, None).unwrap(), vec![]);

    // sing-coupled: joints 1, 3 and 5 turn about one vertical line, so
    // columns 3 and 5 equal column 1; one more dependency makes rank 4.
    let j = robot.jacobian(robot.pose("sing-coupled").unwrap(), Frame::Base).unwrap();
    let deps = analysis::dependent_joints(&j, None).unwrap();
    assert_eq!(deps.len(), 7 - 4, "{deps:?}");
    for d in &deps {
        assert!(reproduces(&j, d), "{d:?}");
    }
    for joint in [2, 4] {
        let d = deps.iter().find(|d| d.joint == joint).expect("q3 and q5 depend on q1");
        assert_eq!(d.on.len(), 1);
        assert_eq!(d.on[0].0, 0);
        assert!((d.on[0].1 - 1.0).abs() < 1e-9);
    }
    // The columns really are equal (checked on the matrix, not the report).
    assert!((j.column(2) - j.column(0)).norm() < 1e-12);
    assert!((j.column(4) - j.column(0)).norm() < 1e-12);
}

#[test]
fn report_singular_directions_are_unreachable() {
    let mut with_directions = 0;
    let mut calls = 0;
    let mut check = |robot: &Robot, q: &[f64]| {
        calls += 1;
        let j = robot.jacobian(q, Frame::Base).unwrap();
        let r = analysis::report(&j).unwrap();
        assert_eq!(r.singular_directions.len(), 6 - r.rank, "{} {q:?}", robot.name());
        let smax = r.singular_values[0];
        let dirs: Vec<kinema::nalgebra::Vector6<f64>> =
            r.singular_directions.iter().map(|u| kinema::nalgebra::Vector6::from_row_slice(u)).collect();
        for (a, u) in dirs.iter().enumerate() {
            assert!((u.norm() - 1.0).abs() < 1e-12);
            // Jᵀ·u ≈ 0: no joint motion moves the tool along u.
            let jt_u = j.transpose() * u;
            assert!(jt_u.norm() < 1e-10 * smax, "{} {q:?}: |Jᵀu| = {}", robot.name(), jt_u.norm());
            for b in &dirs[..a] {
                assert!(u.dot(b).abs() < 1e-12);
            }
            with_directions += 1;
        }
        if calls % 10 != 1 {
            return;
        }
        // The other fields agree with the single-purpose functions.
        for (a, b) in r.singular_values.iter().zip(analysis::singular_values(&j, Axes::All).unwrap()) {
            assert!((a - b).abs() <= 1e-12 * smax);
        }
        assert_eq!(r.rank, analysis::rank(&j, Axes::All, None).unwrap().0);
        assert_eq!(r.yoshikawa, analysis::yoshikawa(&j, Axes::All).unwrap());
        assert_eq!(r.dependent_joints, analysis::dependent_joints(&j, None).unwrap());
    };
    let iiwa = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    for (pose, rank) in [("sing-q4", 5), ("sing-q2-q3", 5), ("sing-coupled", 4)] {
        let q = iiwa.pose(pose).unwrap();
        check(&iiwa, q);
        let j = iiwa.jacobian(q, Frame::Base).unwrap();
        assert_eq!(analysis::report(&j).unwrap().singular_directions.len(), 6 - rank);
    }
    for name in ["puma560", "ur5", "scara5"] {
        let robot = Robot::builtin(name).unwrap();
        check(&robot, robot.pose("qz").unwrap());
    }
    // 5-joint arms always miss at least one direction (the padded SVD path).
    for name in ["scorbot-er-v-plus", "scara5"] {
        let robot = Robot::builtin(name).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(0x5d);
        for _ in 0..SAMPLES {
            check(&robot, &robot.random_q(&mut rng));
        }
    }
    assert!(with_directions >= 2 * SAMPLES, "{with_directions}");
}

#[test]
fn non_finite_jacobian_is_an_error() {
    let mut j = Robot::builtin("ur5").unwrap().jacobian(&[0.2; 6], Frame::Base).unwrap();
    j[(2, 3)] = f64::NAN;
    assert!(analysis::report(&j).is_err());
    assert!(analysis::yoshikawa(&j, Axes::Translation).is_err());
    assert!(analysis::singular_values(&j, Axes::All).is_err());
    assert!(analysis::condition(&j, Axes::All).is_err());
    assert!(analysis::rank(&j, Axes::All, None).is_err());
    assert!(analysis::dependent_joints(&j, None).is_err());
    assert!(analysis::ellipsoid(&j, Axes::Translation).is_err());
    assert!(analysis::manipulability_along(&j, Axes::Translation, &Vector3::x()).is_err());
    j[(2, 3)] = f64::INFINITY;
    assert!(analysis::report(&j).is_err());
}
