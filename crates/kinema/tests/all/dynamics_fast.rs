//! The allocation-free dynamics (`rnea_into`, `mass_matrix_into`) against
//! the plain reference (`rnea`, `mass_matrix`): thousands of seeded random
//! states on random arms of every joint kind (standard and modified DH,
//! general axes; revolute and prismatic; random base and tool) and on every
//! built-in robot, with one set of buffers reused across robots of
//! different sizes.

use crate::common;

use std::f64::consts::PI;

use common::arms;
use kinema::dynamics::{mass_matrix, mass_matrix_into, rnea, rnea_into};
use kinema::nalgebra::{DMatrix, Matrix3, Vector3};
use kinema::Data;
use kinema::{Error, Inertial, Robot};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Relative tolerance: differences are measured against 1 + the largest magnitude.
const TOL: f64 = 1e-12;

/// A physically valid random body (principal moments of a mass distribution, rotated).
fn random_inertial(rng: &mut ChaCha8Rng) -> Inertial {
    let mass = rng.random_range(0.2..5.0);
    let a: [f64; 3] = std::array::from_fn(|_| mass * rng.random_range(0.01..0.3f64).powi(2));
    let d = Matrix3::from_diagonal(&Vector3::new(a[1] + a[2], a[0] + a[2], a[0] + a[1]));
    let r = arms::random_rotation(rng);
    let i = r * d * r.transpose();
    let com = Vector3::new(rng.random_range(-0.3..0.3), rng.random_range(-0.3..0.3), rng.random_range(-0.3..0.3));
    Inertial::new(mass, com, [i[(0, 0)], i[(1, 1)], i[(2, 2)], i[(0, 1)], i[(0, 2)], i[(1, 2)]]).unwrap()
}

fn with_masses(robot: Robot, rng: &mut ChaCha8Rng) -> Robot {
    robot.with_inertials((0..robot.dof()).map(|_| Some(random_inertial(rng))).collect()).unwrap()
}

/// Random arms of 1–20 joints, then every built-in (its own masses where it has them).
fn robots(rng: &mut ChaCha8Rng, random: usize) -> Vec<Robot> {
    let mut out: Vec<Robot> = (0..random)
        .map(|_| {
            let arm = arms::random_robot(rng);
            with_masses(arm, rng)
        })
        .collect();
    for name in kinema::builtin_names() {
        let r = Robot::builtin(name).unwrap();
        out.push(if r.inertials().iter().all(Option::is_some) { r } else { with_masses(r, rng) });
    }
    out
}

fn random_vec(rng: &mut ChaCha8Rng, n: usize, scale: f64) -> Vec<f64> {
    (0..n).map(|_| rng.random_range(-scale..scale)).collect()
}

fn relative_diff(a: &[f64], b: &[f64]) -> f64 {
    let scale = 1.0 + b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / scale
}

#[test]
fn fast_rnea_and_crba_match_the_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(0xFA57);
    let mut buf = Data::new(&Robot::builtin("puma560").unwrap());
    let (mut states, mut worst_tau, mut worst_m) = (0, 0.0f64, 0.0f64);
    for robot in robots(&mut rng, 400) {
        let n = robot.dof();
        let mut tau = vec![0.0; n];
        let mut m = DMatrix::zeros(n, n);
        for _ in 0..8 {
            let q = arms::random_q(&mut rng, n);
            let (qd, qdd) = (random_vec(&mut rng, n, 2.0), random_vec(&mut rng, n, 3.0));
            let g = Vector3::new(rng.random_range(-10.0..10.0), rng.random_range(-10.0..10.0), -9.81);
            rnea_into(&robot, &mut buf, &q, &qd, &qdd, &g, &mut tau).unwrap();
            let reference = rnea(&robot, &q, &qd, &qdd, &g).unwrap();
            let d = relative_diff(&tau, &reference);
            assert!(d < TOL, "{} ({n} joints) τ at q = {q:?}: {tau:?} vs {reference:?} ({d:e})", robot.name());
            worst_tau = worst_tau.max(d);

            mass_matrix_into(&robot, &mut buf, &q, &mut m).unwrap();
            let reference = mass_matrix(&robot, &q).unwrap();
            let d = relative_diff(m.as_slice(), reference.as_slice());
            assert!(d < TOL, "{} ({n} joints) M at q = {q:?}: {m} vs {reference} ({d:e})", robot.name());
            assert_eq!(m, m.transpose(), "both triangles are filled");
            worst_m = worst_m.max(d);
            states += 1;
        }
    }
    assert!(states >= 3000, "{states} states");
    eprintln!("{states} states: worst relative difference τ {worst_tau:.1e}, M {worst_m:.1e}");
}

#[test]
fn urdf_robots_match_the_reference() {
    // A URDF with a fixed joint before, between and after the moving ones
    // (folded into base, link and tool transforms), axes any way round.
    let urdf = r#"<robot name="t">
      <link name="world"/><link name="base"><inertial><mass value="3"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <link name="a"><inertial><origin xyz="0.1 0 0.2" rpy="0.3 0 0"/><mass value="2"/><inertia ixx="0.03" iyy="0.02" izz="0.04" ixy="0.001" ixz="0" iyz="0"/></inertial></link>
      <link name="a2"><inertial><mass value="0.5"/><inertia ixx="0.001" iyy="0.001" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <link name="b"><inertial><origin xyz="0 0.2 0"/><mass value="1.5"/><inertia ixx="0.02" iyy="0.01" izz="0.02" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <link name="tip"/>
      <joint name="f0" type="fixed"><parent link="world"/><child link="base"/><origin xyz="0 0 0.5" rpy="0 0.2 0"/></joint>
      <joint name="j1" type="revolute"><parent link="base"/><child link="a"/><origin xyz="0 0 0.3"/><axis xyz="0 1 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
      <joint name="f1" type="fixed"><parent link="a"/><child link="a2"/><origin xyz="0.2 0 0"/></joint>
      <joint name="j2" type="prismatic"><parent link="a2"/><child link="b"/><origin xyz="0 0 0.1" rpy="1 0 0"/><axis xyz="-1 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
      <joint name="f2" type="fixed"><parent link="b"/><child link="tip"/><origin xyz="0.1 0 0"/></joint>
    </robot>"#;
    let robot = Robot::from_urdf_str(urdf, "t.urdf", None).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut buf = Data::new(&robot);
    let (mut tau, mut m) = ([0.0; 2], DMatrix::zeros(2, 2));
    let g = Vector3::new(0.0, 0.0, -9.81);
    for _ in 0..500 {
        let q = [rng.random_range(-PI..PI), rng.random_range(-1.0..1.0)];
        let (qd, qdd) = (random_vec(&mut rng, 2, 2.0), random_vec(&mut rng, 2, 3.0));
        rnea_into(&robot, &mut buf, &q, &qd, &qdd, &g, &mut tau).unwrap();
        assert!(relative_diff(&tau, &rnea(&robot, &q, &qd, &qdd, &g).unwrap()) < TOL);
        mass_matrix_into(&robot, &mut buf, &q, &mut m).unwrap();
        assert!(relative_diff(m.as_slice(), mass_matrix(&robot, &q).unwrap().as_slice()) < TOL);
    }
}

#[test]
fn bad_arguments_are_errors_and_leave_the_output_alone() {
    let robot = Robot::builtin("puma560").unwrap();
    let mut buf = Data::new(&robot);
    let (q, z, g) = (robot.home().to_vec(), [0.0; 6], Vector3::new(0.0, 0.0, -9.81));
    let mut tau = [7.0; 6];
    assert!(rnea_into(&robot, &mut buf, &q[..5], &z, &z, &g, &mut tau).is_err());
    assert!(rnea_into(&robot, &mut buf, &q, &z[..5], &z, &g, &mut tau).is_err());
    assert!(rnea_into(&robot, &mut buf, &q, &z, &[f64::NAN; 6], &g, &mut tau).is_err());
    assert!(rnea_into(&robot, &mut buf, &q, &z, &z, &Vector3::new(0.0, f64::INFINITY, 0.0), &mut tau).is_err());
    assert!(rnea_into(&robot, &mut buf, &q, &z, &z, &g, &mut [0.0; 5]).is_err());
    assert_eq!(tau, [7.0; 6]);
    let mut m = DMatrix::from_element(6, 6, 7.0);
    assert!(mass_matrix_into(&robot, &mut buf, &q, &mut DMatrix::zeros(5, 6)).is_err());
    assert!(mass_matrix_into(&robot, &mut buf, &[f64::NAN; 6], &mut m).is_err());
    assert_eq!(m, DMatrix::from_element(6, 6, 7.0));

    // A link without mass properties is named, as by the reference.
    let mut inertials = robot.inertials().to_vec();
    inertials[3] = None;
    let massless = robot.with_inertials(inertials).unwrap();
    for e in [
        rnea_into(&massless, &mut buf, &q, &z, &z, &g, &mut tau).unwrap_err(),
        mass_matrix_into(&massless, &mut buf, &q, &mut m).unwrap_err(),
    ] {
        assert!(matches!(e, Error::NoInertial { link: 4, .. }), "{e:?}");
    }
    assert_eq!(tau, [7.0; 6]);
    assert_eq!(m, DMatrix::from_element(6, 6, 7.0));
}
