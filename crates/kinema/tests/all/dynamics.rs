//! Dynamics checked against oracles that share no code with it: closed forms
//! of planar arms, the potential energy from forward kinematics, the
//! work–energy identity, and the algorithms against each other (CRBA against
//! RNEA columns, forward dynamics against RNEA). Seeded random chains cover
//! every joint kind (standard/modified DH, general axes; revolute and
//! prismatic) with random base and tool transforms.

use std::f64::consts::PI;

use kinema::dynamics::{coriolis, coriolis_matrix, forward_dynamics, gravity_torques, mass_matrix, rnea};
use kinema::nalgebra::{DMatrix, DVector, Matrix3, Rotation3, Unit, Vector3};
use kinema::ModelError;
use kinema::{DhConvention, Error, GeometryKind, Inertial, Joint, JointType, Limits, LinkGeometry, Model, Pose, Robot};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const G: Vector3<f64> = Vector3::new(0.0, 0.0, -9.81);

fn random_rotation(rng: &mut ChaCha8Rng) -> Matrix3<f64> {
    let axis = Unit::new_normalize(Vector3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    ));
    Rotation3::from_axis_angle(&axis, rng.random_range(-PI..PI)).into_inner()
}

fn random_pose(rng: &mut ChaCha8Rng) -> Pose {
    let p = Vector3::new(rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5));
    Pose::new(random_rotation(rng), p)
}

/// A physically valid random body: principal moments from a random
/// ellipsoid-like mass distribution (triangle inequalities hold), rotated.
fn random_inertial(rng: &mut ChaCha8Rng) -> Inertial {
    let mass = rng.random_range(0.2..5.0);
    let s = [rng.random_range(0.01..0.3f64), rng.random_range(0.01..0.3), rng.random_range(0.01..0.3)];
    // Second moments of a mass distribution along its principal axes, a_k = m·s_k²;
    // the moment about axis x is a_y + a_z, and so on.
    let a = s.map(|v| mass * v * v);
    let d = Matrix3::from_diagonal(&Vector3::new(a[1] + a[2], a[0] + a[2], a[0] + a[1]));
    let r = random_rotation(rng);
    let i = r * d * r.transpose();
    let com = Vector3::new(rng.random_range(-0.3..0.3), rng.random_range(-0.3..0.3), rng.random_range(-0.3..0.3));
    Inertial::new(mass, com, [i[(0, 0)], i[(1, 1)], i[(2, 2)], i[(0, 1)], i[(0, 2)], i[(1, 2)]]).unwrap()
}

/// A random chain of 1–8 joints of every kind, with base, tool and masses.
fn random_robot(rng: &mut ChaCha8Rng) -> Robot {
    let n = rng.random_range(1..=8);
    let joints = (0..n)
        .map(|i| {
            let kind = if rng.random_bool(0.25) { JointType::Prismatic } else { JointType::Revolute };
            let len = |rng: &mut ChaCha8Rng| rng.random_range(-0.5..0.5);
            let geometry = match rng.random_range(0..3) {
                0 | 1 => LinkGeometry::Dh {
                    convention: if rng.random_bool(0.5) { DhConvention::Standard } else { DhConvention::Modified },
                    d: if kind == JointType::Revolute { len(rng) } else { 0.0 },
                    a: len(rng),
                    alpha: rng.random_range(-PI..PI),
                    theta: if kind == JointType::Prismatic { rng.random_range(-PI..PI) } else { 0.0 },
                },
                _ => LinkGeometry::General {
                    origin: random_pose(rng),
                    axis: Unit::new_normalize(random_rotation(rng) * Vector3::z()).into_inner(),
                },
            };
            Joint {
                name: format!("j{}", i + 1),
                kind,
                geometry,
                offset: rng.random_range(-1.0..1.0),
                limits: Limits::position(-PI, PI),
            }
        })
        .collect();
    let robot = Model::builder("random", GeometryKind::General)
        .joints(joints)
        .base(random_pose(rng))
        .tool(random_pose(rng))
        .pose("home", vec![0.0; n])
        .build()
        .map(Robot::new)
        .unwrap();
    robot.with_inertials((0..n).map(|_| Some(random_inertial(rng))).collect()).unwrap()
}

/// Random chains and every built-in robot (with its own masses, or random ones).
fn robots(rng: &mut ChaCha8Rng, random: usize) -> Vec<Robot> {
    let mut out: Vec<Robot> = (0..random).map(|_| random_robot(rng)).collect();
    for name in kinema::builtin_names() {
        let r = Robot::builtin(name).unwrap();
        let r = if r.inertials().iter().all(Option::is_some) {
            r
        } else {
            r.with_inertials((0..r.dof()).map(|_| Some(random_inertial(rng))).collect()).unwrap()
        };
        out.push(r);
    }
    out
}

fn random_vec(rng: &mut ChaCha8Rng, n: usize, scale: f64) -> Vec<f64> {
    (0..n).map(|_| rng.random_range(-scale..scale)).collect()
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

#[test]
fn mass_matrix_is_spd_and_the_columns_of_rnea() {
    let mut rng = ChaCha8Rng::seed_from_u64(26);
    let mut worst = 0.0f64;
    for robot in robots(&mut rng, 200) {
        let n = robot.dof();
        for _ in 0..5 {
            let q = robot.random_q(&mut rng);
            let m = mass_matrix(&robot, &q).unwrap();
            assert!((&m - m.transpose()).amax() < 1e-12, "{}: M not symmetric", robot.name());
            assert!(m.clone().cholesky().is_some(), "{}: M not positive definite\n{m}", robot.name());
            let g = gravity_torques(&robot, &q, &G).unwrap();
            for i in 0..n {
                let mut e = vec![0.0; n];
                e[i] = 1.0;
                let tau = rnea(&robot, &q, &vec![0.0; n], &e, &G).unwrap();
                let col: Vec<f64> = tau.iter().zip(&g).map(|(t, g)| t - g).collect();
                let err = max_abs_diff(&col, m.column(i).as_slice());
                worst = worst.max(err / (1.0 + m.amax()));
                assert!(err < 1e-10 * (1.0 + m.amax()), "{}: column {i} differs by {err}", robot.name());
            }
        }
    }
    eprintln!("mass matrix vs RNEA columns: worst relative difference {worst:.2e}");
}

#[test]
fn power_equals_rate_of_kinetic_energy() {
    // d/dt (½ q̇ᵀ M q̇) = q̇ᵀ τ without gravity, along q(t) = q + q̇ t + ½ q̈ t²:
    // this holds only if RNEA's velocity terms match how M changes with q.
    let mut rng = ChaCha8Rng::seed_from_u64(27);
    let mut worst = 0.0f64;
    for robot in robots(&mut rng, 200) {
        let n = robot.dof();
        for _ in 0..3 {
            let (q, qd, qdd) = (robot.random_q(&mut rng), random_vec(&mut rng, n, 2.0), random_vec(&mut rng, n, 3.0));
            let tau = rnea(&robot, &q, &qd, &qdd, &Vector3::zeros()).unwrap();
            let power: f64 = qd.iter().zip(&tau).map(|(a, b)| a * b).sum();
            let energy = |t: f64| {
                let qt: Vec<f64> = (0..n).map(|i| q[i] + qd[i] * t + 0.5 * qdd[i] * t * t).collect();
                let v = DVector::from_iterator(n, (0..n).map(|i| qd[i] + qdd[i] * t));
                0.5 * (v.transpose() * mass_matrix(&robot, &qt).unwrap() * &v)[(0, 0)]
            };
            let h = 1e-5;
            let rate = (energy(h) - energy(-h)) / (2.0 * h);
            let err = (rate - power).abs() / (1.0 + power.abs());
            worst = worst.max(err);
            assert!(err < 1e-6, "{}: dT/dt = {rate}, q̇ᵀτ = {power}", robot.name());
        }
    }
    eprintln!("kinetic energy rate vs power: worst relative difference {worst:.2e}");
}

/// Potential energy −Σ m·g·c from the link frames of forward kinematics.
fn potential(robot: &Robot, q: &[f64]) -> f64 {
    let frames = robot.link_frames(q).unwrap();
    robot
        .inertials()
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let b = b.unwrap();
            -b.mass * G.dot(&frames[i + 1].transform_point(&b.com))
        })
        .sum()
}

#[test]
fn gravity_torque_is_the_gradient_of_potential_energy() {
    let mut rng = ChaCha8Rng::seed_from_u64(28);
    let mut worst = 0.0f64;
    for robot in robots(&mut rng, 200) {
        let n = robot.dof();
        for _ in 0..5 {
            let q = robot.random_q(&mut rng);
            let g = gravity_torques(&robot, &q, &G).unwrap();
            let h = 1e-6;
            for i in 0..n {
                let (mut qp, mut qm) = (q.clone(), q.clone());
                qp[i] += h;
                qm[i] -= h;
                let grad = (potential(&robot, &qp) - potential(&robot, &qm)) / (2.0 * h);
                let err = (grad - g[i]).abs() / (1.0 + g[i].abs());
                worst = worst.max(err);
                assert!(err < 1e-6, "{}: joint {i}: ∂V/∂q = {grad}, g = {}", robot.name(), g[i]);
            }
        }
    }
    eprintln!("gravity torque vs ∂V/∂q: worst relative difference {worst:.2e}");
}

#[test]
fn forward_dynamics_inverts_rnea() {
    let mut rng = ChaCha8Rng::seed_from_u64(29);
    let mut worst = 0.0f64;
    for robot in robots(&mut rng, 200) {
        let n = robot.dof();
        for _ in 0..5 {
            let (q, qd, qdd) = (robot.random_q(&mut rng), random_vec(&mut rng, n, 2.0), random_vec(&mut rng, n, 3.0));
            let tau = rnea(&robot, &q, &qd, &qdd, &G).unwrap();
            let back = forward_dynamics(&robot, &q, &qd, &tau, &G).unwrap();
            let err = max_abs_diff(&back, &qdd);
            worst = worst.max(err);
            assert!(err < 1e-8, "{}: q̈ {qdd:?} came back as {back:?}", robot.name());
            // RNEA is M·q̈ + C·q̇ + g, term by term.
            let m = mass_matrix(&robot, &q).unwrap();
            let c = coriolis(&robot, &q, &qd).unwrap();
            let g = gravity_torques(&robot, &q, &G).unwrap();
            let mq = &m * DVector::from_column_slice(&qdd);
            let sum: Vec<f64> = (0..n).map(|i| mq[i] + c[i] + g[i]).collect();
            assert!(max_abs_diff(&sum, &tau) < 1e-9 * (1.0 + tau.iter().fold(0.0f64, |a, t| a.max(t.abs()))));
        }
    }
    eprintln!("forward dynamics vs RNEA: worst |Δq̈| {worst:.2e} rad/s²");
}

/// The oracle for forward dynamics: q̈ = M⁻¹·(τ − h) with M from CRBA and
/// h = C·q̇ + g from RNEA, solved by Cholesky — shares with ABA only the
/// model, not the recursion.
fn fd_by_mass_matrix(robot: &Robot, q: &[f64], qd: &[f64], tau: &[f64]) -> Vec<f64> {
    let n = robot.dof();
    let h = rnea(robot, q, qd, &vec![0.0; n], &G).unwrap();
    let m = mass_matrix(robot, q).unwrap();
    let rhs = DVector::from_iterator(n, tau.iter().zip(&h).map(|(t, h)| t - h));
    m.cholesky().expect("M positive definite").solve(&rhs).iter().copied().collect()
}

#[test]
fn aba_matches_the_mass_matrix_solve() {
    let mut rng = ChaCha8Rng::seed_from_u64(32);
    let mut worst = 0.0f64;
    let mut states = 0;
    for robot in robots(&mut rng, 400) {
        let n = robot.dof();
        for _ in 0..10 {
            let q = robot.random_q(&mut rng);
            let (qd, tau) = (random_vec(&mut rng, n, 2.0), random_vec(&mut rng, n, 20.0));
            let aba = forward_dynamics(&robot, &q, &qd, &tau, &G).unwrap();
            let oracle = fd_by_mass_matrix(&robot, &q, &qd, &tau);
            let scale = 1.0 + oracle.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            let err = max_abs_diff(&aba, &oracle) / scale;
            worst = worst.max(err);
            assert!(err < 1e-9, "{}: ABA {aba:?} vs M⁻¹(τ − h) {oracle:?}", robot.name());
            states += 1;
        }
    }
    eprintln!("ABA vs M⁻¹(τ − h): worst relative difference {worst:.2e} over {states} states");
}

#[test]
fn aba_refuses_a_joint_that_moves_no_mass() {
    let robot = planar(&[1.0, 1.0], &[1.0, 0.0], &[0.5, 0.5], &[0.1, 0.0]);
    let e = forward_dynamics(&robot, &[0.0, 0.0], &[0.0; 2], &[0.0; 2], &G).unwrap_err();
    assert!(e.to_string().contains("j2"), "{e}");
    assert!(forward_dynamics(&robot, &[0.0, 0.0], &[f64::NAN, 0.0], &[0.0; 2], &G).is_err());
}

#[test]
fn coriolis_matrix_times_qd_is_coriolis_and_mdot_minus_2c_is_skew() {
    let mut rng = ChaCha8Rng::seed_from_u64(33);
    let (mut worst_cqd, mut worst_skew) = (0.0f64, 0.0f64);
    for robot in robots(&mut rng, 200) {
        let n = robot.dof();
        for _ in 0..5 {
            let (q, qd) = (robot.random_q(&mut rng), random_vec(&mut rng, n, 2.0));
            let c = coriolis_matrix(&robot, &q, &qd).unwrap();
            let cqd = &c * DVector::from_column_slice(&qd);
            let h = coriolis(&robot, &q, &qd).unwrap();
            let scale = 1.0 + h.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            let err = max_abs_diff(cqd.as_slice(), &h) / scale;
            worst_cqd = worst_cqd.max(err);
            assert!(err < 1e-10, "{}: C·q̇ {cqd} vs {h:?}", robot.name());
            // Ṁ along q̇ by central differences of CRBA.
            let eps = 1e-6;
            let at = |t: f64| {
                let qt: Vec<f64> = (0..n).map(|i| q[i] + qd[i] * t).collect();
                mass_matrix(&robot, &qt).unwrap()
            };
            let mdot: DMatrix<f64> = (at(eps) - at(-eps)) / (2.0 * eps);
            let n_mat = &mdot - 2.0 * &c;
            let err = (&n_mat + n_mat.transpose()).amax() / (1.0 + mdot.amax() + c.amax());
            worst_skew = worst_skew.max(err);
            assert!(err < 1e-6, "{}: Ṁ − 2C not skew by {err}\n{n_mat}", robot.name());
        }
    }
    eprintln!("C·q̇ vs RNEA: worst relative {worst_cqd:.2e}; Ṁ − 2C skew to {worst_skew:.2e} (finite differences)");
}

/// A planar arm of revolute joints about z, links of length `l` along x of
/// their standard-DH frames, each with mass m at `lc` from its joint and
/// moment `izz` about its centre of mass.
fn planar(l: &[f64], m: &[f64], lc: &[f64], izz: &[f64]) -> Robot {
    let joints = l
        .iter()
        .enumerate()
        .map(|(i, &a)| Joint {
            name: format!("j{}", i + 1),
            kind: JointType::Revolute,
            geometry: LinkGeometry::Dh { convention: DhConvention::Standard, d: 0.0, a, alpha: 0.0, theta: 0.0 },
            offset: 0.0,
            limits: Limits::unbounded(),
        })
        .collect();
    let n = l.len();
    let r = Model::builder("planar", GeometryKind::Standard)
        .joints(joints)
        .pose("home", vec![0.0; n])
        .build()
        .map(Robot::new)
        .unwrap();
    // The DH frame of link i sits at the link's far end: the centre of mass is at x = lc − l.
    let bodies = (0..n)
        .map(|i| {
            let iz = izz[i];
            Some(
                Inertial::new(m[i], Vector3::new(lc[i] - l[i], 0.0, 0.0), [iz / 2.0, iz / 2.0, iz, 0.0, 0.0, 0.0])
                    .unwrap(),
            )
        })
        .collect();
    r.with_inertials(bodies).unwrap()
}

#[test]
fn one_and_two_link_planar_arms_match_closed_forms() {
    let mut rng = ChaCha8Rng::seed_from_u64(30);
    let g = Vector3::new(0.0, -9.81, 0.0); // in the plane of motion, along −y
    let gn = 9.81;
    for _ in 0..300 {
        let (l1, l2) = (rng.random_range(0.2..1.5), rng.random_range(0.2..1.5));
        let (m1, m2) = (rng.random_range(0.5..5.0), rng.random_range(0.5..5.0));
        let (c1, c2) = (rng.random_range(0.0..l1), rng.random_range(0.0..l2));
        let (i1, i2) = (rng.random_range(0.0..0.5), rng.random_range(0.0..0.5));
        let [q1, q2, d1, d2, a1, a2] = [0; 6].map(|_| rng.random_range(-3.0..3.0));

        // Pendulum: τ = (m·lc² + I)·q̈ + m·g·lc·cos q.
        let one = planar(&[l1], &[m1], &[c1], &[i1]);
        let tau = rnea(&one, &[q1], &[d1], &[a1], &g).unwrap();
        let expected = (m1 * c1 * c1 + i1) * a1 + m1 * gn * c1 * q1.cos();
        assert!((tau[0] - expected).abs() < 1e-10, "pendulum: {} vs {expected}", tau[0]);

        // Two links (Spong, Hutchinson and Vidyasagar, Robot Modeling and Control, §7.4.1).
        let two = planar(&[l1, l2], &[m1, m2], &[c1, c2], &[i1, i2]);
        let tau = rnea(&two, &[q1, q2], &[d1, d2], &[a1, a2], &g).unwrap();
        let m11 = m1 * c1 * c1 + m2 * (l1 * l1 + c2 * c2 + 2.0 * l1 * c2 * q2.cos()) + i1 + i2;
        let m12 = m2 * (c2 * c2 + l1 * c2 * q2.cos()) + i2;
        let m22 = m2 * c2 * c2 + i2;
        let h = -m2 * l1 * c2 * q2.sin();
        let phi2 = m2 * c2 * gn * (q1 + q2).cos();
        let phi1 = (m1 * c1 + m2 * l1) * gn * q1.cos() + phi2;
        let t1 = m11 * a1 + m12 * a2 + 2.0 * h * d1 * d2 + h * d2 * d2 + phi1;
        let t2 = m12 * a1 + m22 * a2 - h * d1 * d1 + phi2;
        assert!((tau[0] - t1).abs() < 1e-10 && (tau[1] - t2).abs() < 1e-10, "{tau:?} vs [{t1}, {t2}]");
        let m = mass_matrix(&two, &[q1, q2]).unwrap();
        assert!((m[(0, 0)] - m11).abs() < 1e-12 && (m[(0, 1)] - m12).abs() < 1e-12 && (m[(1, 1)] - m22).abs() < 1e-12);
    }
}

#[test]
fn a_link_without_mass_properties_is_named() {
    let robot = Robot::builtin("scara5").unwrap();
    let e = rnea(&robot, robot.home(), &[0.0; 5], &[0.0; 5], &G).unwrap_err();
    assert!(matches!(e, Error::NoInertial { link: 1, .. }), "{e}");
    let mut b: Vec<Option<Inertial>> = vec![
        Some(
            Inertial::new(
                1.0,
                Vector3::zeros(),
                [0.1; 3].into_iter().chain([0.0; 3]).collect::<Vec<_>>().try_into().unwrap()
            )
            .unwrap()
        );
        5
    ];
    b[3] = None;
    let robot = robot.with_inertials(b).unwrap();
    let e = mass_matrix(&robot, robot.home()).unwrap_err();
    assert!(matches!(&e, Error::NoInertial { link: 4, joint, .. } if joint == &robot.joints()[3].name), "{e}");
    assert!(e.to_string().contains("link 4"), "{e}");
    // Bad inputs are errors, not panics.
    let puma = Robot::builtin("puma560").unwrap();
    assert!(rnea(&puma, puma.home(), &[0.0; 5], &[0.0; 6], &G).is_err());
    assert!(rnea(&puma, puma.home(), &[f64::NAN; 6], &[0.0; 6], &G).is_err());
    assert!(rnea(&puma, puma.home(), &[0.0; 6], &[0.0; 6], &Vector3::new(f64::INFINITY, 0.0, 0.0)).is_err());
    assert!(forward_dynamics(&puma, puma.home(), &[0.0; 6], &[0.0; 7], &G).is_err());
    assert!(forward_dynamics(&puma, puma.home(), &[0.0; 5], &[0.0; 6], &G).is_err());
    assert!(forward_dynamics(&puma, puma.home(), &[0.0; 6], &[f64::INFINITY; 6], &G).is_err());
    assert!(coriolis_matrix(&puma, puma.home(), &[0.0; 7]).is_err());
    assert!(coriolis_matrix(&puma, puma.home(), &[f64::NAN; 6]).is_err());
    assert!(coriolis_matrix(&puma, &[0.0; 5], &[0.0; 6]).is_err());
    assert!(coriolis_matrix(&robot, robot.home(), &[0.0; 5]).is_err()); // link 4 has no mass properties
}

#[test]
fn the_builtins_with_published_inertias_have_every_link() {
    // Their files name the sources; Robot::builtin has validated every tensor (triangle inequality).
    for name in ["puma560", "panda", "ur5", "lbr-iiwa-14-r820"] {
        let r = Robot::builtin(name).unwrap();
        assert!(r.inertials().iter().all(Option::is_some), "{name}");
        let total: f64 = r.inertials().iter().map(|b| b.unwrap().mass).sum();
        assert!(total > 10.0 && total < 30.0, "{name}: {total} kg");
    }
}

#[test]
fn invalid_inertias_are_refused() {
    let z = Vector3::zeros();
    assert!(Inertial::new(-1.0, z, [0.0; 6]).is_err());
    assert!(Inertial::new(1.0, z, [-0.1, 0.1, 0.1, 0.0, 0.0, 0.0]).is_err());
    assert!(Inertial::new(1.0, z, [0.1, 0.1, 0.3, 0.0, 0.0, 0.0]).is_err()); // 0.1 + 0.1 < 0.3
    assert!(Inertial::new(1.0, z, [0.1, 0.1, 0.1, 0.2, 0.0, 0.0]).is_err()); // not positive semi-definite
    assert!(Inertial::new(f64::NAN, z, [0.0; 6]).is_err());
    assert!(Inertial::new(1.0, z, [0.1, 0.1, 0.2, 0.0, 0.0, 0.0]).is_ok()); // a thin disc: on the boundary
    let mut b = Inertial::new(1.0, z, [0.1, 0.1, 0.1, 0.0, 0.0, 0.0]).unwrap();
    b.inertia[(0, 1)] = 0.01; // not symmetric
    let robot = Robot::builtin("puma560").unwrap();
    let mut all = robot.inertials().to_vec();
    all[2] = Some(b);
    assert!(robot.with_inertials(all).is_err());
}

#[test]
fn base_transform_and_gravity_direction_agree() {
    // Turning the whole robot (its base) and gravity with it changes no torque.
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    for _ in 0..100 {
        let robot = random_robot(&mut rng);
        let n = robot.dof();
        let turn = random_pose(&mut rng);
        let turned = robot.with_base(turn * *robot.base()).unwrap();
        assert_eq!(turned.inertials(), robot.inertials());
        let (q, qd, qdd) = (robot.random_q(&mut rng), random_vec(&mut rng, n, 2.0), random_vec(&mut rng, n, 3.0));
        let a = rnea(&robot, &q, &qd, &qdd, &G).unwrap();
        let b = rnea(&turned, &q, &qd, &qdd, &(turn.rot * G)).unwrap();
        assert!(max_abs_diff(&a, &b) < 1e-9 * (1.0 + a.iter().fold(0.0f64, |m, t| m.max(t.abs()))), "{a:?} vs {b:?}");
    }
}

#[test]
fn toml_units_scale_centre_of_mass_and_inertia() {
    let text = |len: &str, k: f64| {
        format!(
            r#"
name = "p"
source = "test"
convention = "standard"
[units]
length = "{len}"
angle = "deg"
[[joint]]
name = "j1"
a = {a}
alpha = 90
min = -170
max = 170
[joint.inertial]
mass = 2.5
com = [{c}, 0, {c2}]
inertia = [{i1}, {i2}, {i2}, {i3}, 0, 0]
[poses]
home = [0]
"#,
            a = 0.5 * k,
            c = -0.2 * k,
            c2 = 0.05 * k,
            i1 = 0.02 * k * k,
            i2 = 0.03 * k * k,
            i3 = 0.001 * k * k
        )
    };
    let m = Robot::from_toml_str(&text("m", 1.0), "m.toml").unwrap();
    let mm = Robot::from_toml_str(&text("mm", 1000.0), "mm.toml").unwrap();
    let (a, b) = (m.inertials()[0].unwrap(), mm.inertials()[0].unwrap());
    assert_eq!(a.mass, 2.5);
    assert!((a.com - b.com).amax() < 1e-15 && (a.inertia - b.inertia).amax() < 1e-15, "{a:?} vs {b:?}");
    assert!((b.inertia[(0, 1)] - 0.001).abs() < 1e-15 && (b.com.x + 0.2).abs() < 1e-15);
    // An unphysical tensor is a description error at the joint.
    let bad = text("m", 1.0).replace("inertia = [0.02, 0.03, 0.03", "inertia = [0.02, 0.03, 0.3");
    let Err(Error::Model(ModelError::Description { field, message, .. })) = Robot::from_toml_str(&bad, "bad.toml")
    else {
        panic!()
    };
    assert_eq!(field, "joint[0].inertial", "{message}");
    assert!(message.contains("triangle"), "{message}");
}

#[test]
fn urdf_inertials_are_merged_across_fixed_joints_into_the_link_frame() {
    // Link b (moved by j2) carries a sensor s on a fixed joint and its own
    // inertial frame is turned and shifted; j2's axis is not z.
    let urdf = r#"<robot name="t">
      <link name="a"><inertial><origin xyz="0 0 0.1"/><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <link name="root"/>
      <link name="b"><inertial><origin xyz="0.2 0 0" rpy="0 0 1.5707963267948966"/><mass value="2"/>
        <inertia ixx="0.02" iyy="0.03" izz="0.04" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <link name="s"><inertial><mass value="0.5"/><inertia ixx="0.001" iyy="0.001" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <joint name="j1" type="revolute"><parent link="root"/><child link="a"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
      <joint name="j2" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 0.3"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
      <joint name="fix" type="fixed"><parent link="b"/><child link="s"/><origin xyz="0.4 0 0.1"/></joint>
    </robot>"#;
    let robot = Robot::from_urdf_str(urdf, "t.urdf", None).unwrap();
    assert_eq!(robot.dof(), 2);
    let a = robot.inertials()[0].unwrap();
    assert_eq!((a.mass, a.com), (1.0, Vector3::new(0.0, 0.0, 0.1)));
    let b = robot.inertials()[1].unwrap();
    // By hand: 2 kg at (0.2, 0, 0) with its x, y moments swapped by the quarter turn,
    // 0.5 kg at (0.4, 0, 0.1); centre (2·0.2 + 0.5·0.4, 0, 0.05)/2.5 = (0.24, 0, 0.02).
    assert!((b.mass - 2.5).abs() < 1e-15);
    assert!((b.com - Vector3::new(0.24, 0.0, 0.02)).amax() < 1e-15, "{:?}", b.com);
    let point = |m: f64, d: Vector3<f64>| m * (Matrix3::identity() * d.norm_squared() - d * d.transpose());
    let expected = Matrix3::from_diagonal(&Vector3::new(0.03, 0.02, 0.04))
        + point(2.0, Vector3::new(0.2, 0.0, 0.0) - b.com)
        + Matrix3::from_diagonal(&Vector3::new(0.001, 0.001, 0.001))
        + point(0.5, Vector3::new(0.4, 0.0, 0.1) - b.com);
    assert!((b.inertia - expected).amax() < 1e-15, "{}\nvs\n{expected}", b.inertia);
    // A URDF without any inertial has no mass properties.
    let bare = Robot::from_file(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/ur5.urdf"), None).unwrap();
    assert!(bare.inertials().iter().all(Option::is_none));
}

/// Against Pinocchio: reads the CSV written by benchmarks/dyn_peers.py (run by
/// benchmarks/run_dyn_peers.sh, which sets `KINEMA_DYN_PEERS_CSV`) and compares
/// RNEA, the mass matrix, forward dynamics (ABA) and the Coriolis matrix state
/// by state. A spec `builtin:NAME@FILE` is the built-in against Pinocchio's
/// model of the URDF its inertials came from.
#[test]
#[ignore = "needs the CSV from benchmarks/run_dyn_peers.sh (Pinocchio in a throwaway venv)"]
fn dynamics_matches_pinocchio() {
    let path = std::env::var("KINEMA_DYN_PEERS_CSV").expect("set KINEMA_DYN_PEERS_CSV to dyn_peers.py's output");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut loaded: std::collections::HashMap<String, Robot> = Default::default();
    let mut worst: std::collections::BTreeMap<String, [f64; 5]> = Default::default();
    for line in text.lines() {
        let mut fields = line.split(',');
        let spec = fields.next().unwrap().to_string();
        let n: usize = fields.next().unwrap().parse().unwrap();
        let v: Vec<f64> = fields.map(|x| x.parse().unwrap()).collect();
        assert_eq!(v.len(), 6 * n + 2 * n * n, "{spec}");
        let robot = loaded.entry(spec.clone()).or_insert_with(|| {
            if let Some(name) = spec.strip_prefix("builtin:") {
                Robot::builtin(name.split('@').next().unwrap()).unwrap()
            } else {
                let rest = spec.strip_prefix("urdf:").unwrap();
                let (file, tip) = rest.rsplit_once(':').unwrap();
                Robot::from_file(file, (!tip.is_empty()).then_some(tip)).unwrap()
            }
        });
        assert_eq!(robot.dof(), n, "{spec}");
        let (q, qd, qdd, tau) = (&v[..n], &v[n..2 * n], &v[2 * n..3 * n], &v[3 * n..4 * n]);
        let m_pin = &v[4 * n..4 * n + n * n];
        let (tau2, qdd2) = (&v[4 * n + n * n..5 * n + n * n], &v[5 * n + n * n..6 * n + n * n]);
        let c_pin = &v[6 * n + n * n..];
        let ours = rnea(robot, q, qd, qdd, &G).unwrap();
        let m = mass_matrix(robot, q).unwrap();
        let rows = |a: &DMatrix<f64>| -> Vec<f64> { (0..n * n).map(|k| a[(k / n, k % n)]).collect() };
        let fd = forward_dynamics(robot, q, qd, tau2, &G).unwrap();
        let c = coriolis_matrix(robot, q, qd).unwrap();
        let scale = 1.0 + tau.iter().fold(0.0f64, |a, t| a.max(t.abs()));
        let errs = [
            max_abs_diff(&ours, tau),
            max_abs_diff(&ours, tau) / scale,
            max_abs_diff(&rows(&m), m_pin),
            max_abs_diff(&fd, qdd2) / (1.0 + qdd2.iter().fold(0.0f64, |a, t| a.max(t.abs()))),
            max_abs_diff(&rows(&c), c_pin),
        ];
        let w = worst.entry(spec.rsplit('/').next().unwrap().to_string()).or_default();
        for (w, e) in w.iter_mut().zip(errs) {
            *w = w.max(e);
        }
        assert!(errs[1..].iter().all(|e| *e < 1e-10), "{spec}: {errs:?} at q = {q:?}, q̇ = {qd:?}");
    }
    for (spec, w) in &worst {
        eprintln!(
            "{spec}: max |Δτ| {:.2e} N·m ({:.2e} relative), max |ΔM| {:.2e}, max |Δq̈| {:.2e} relative, max |ΔC| {:.2e}",
            w[0], w[1], w[2], w[3], w[4]
        );
    }
}
