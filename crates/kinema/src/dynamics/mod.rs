//! Rigid-body dynamics of the serial chain: inverse dynamics by recursive
//! Newton–Euler ([`rnea`]), gravity torques ([`gravity_torques`]), the
//! joint-space mass matrix by the composite-rigid-body algorithm
//! ([`mass_matrix`]), Coriolis and centrifugal torques ([`coriolis`]) and
//! forward dynamics by the articulated-body algorithm ([`forward_dynamics`]).
//!
//! This is the plain reference path: every quantity is a 6-vector of
//! Featherstone's spatial algebra (Featherstone, *Rigid Body Dynamics
//! Algorithms*, 2008, ch. 2), ordered \[angular; linear\] and expressed in the
//! world frame — the frame [`Robot::link_frames`] returns its poses in, i.e.
//! the one the base transform maps into — with moments and linear velocities
//! taken at the world origin. In world coordinates the recursions need no
//! change of frame between links: each joint's motion subspace is read off
//! the link frames at `q`, and the body inertias are rotated into the world
//! once per call.
//!
//! Mass properties come from [`Model::inertials`](crate::Model::inertials); a link without them is the
//! error [`Error::NoInertial`]. Units: q in rad or m, q̇ in rad/s or m/s, q̈
//! in rad/s² or m/s², gravity in m/s² (world frame, e.g. \[0, 0, −9.81\]),
//! torques in N·m (revolute) or N (prismatic), the mass matrix in kg·m²,
//! kg·m or kg.

use nalgebra::{DMatrix, Matrix3, Matrix6, Vector3, Vector6};

mod aba;
mod coriolis;

use crate::error::{Error, InputError, Result};
use crate::kin::joint_axis;
use crate::math::Pose;
use crate::model::{Inertial, JointType};
use crate::robot::Robot;

mod fast;
pub use fast::{mass_matrix_into, rnea_into};

/// The skew-symmetric matrix of `v`: `skew(v)·w = v × w`.
fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// Angular and linear parts of a spatial vector.
fn split(v: &Vector6<f64>) -> (Vector3<f64>, Vector3<f64>) {
    (v.fixed_rows::<3>(0).into(), v.fixed_rows::<3>(3).into())
}

fn join(a: Vector3<f64>, b: Vector3<f64>) -> Vector6<f64> {
    Vector6::new(a.x, a.y, a.z, b.x, b.y, b.z)
}

/// Spatial cross product of motion vectors, v ×ₘ m (Featherstone eq. 2.31):
/// the rate of change of a motion vector m carried along by velocity v.
fn cross_motion(v: &Vector6<f64>, m: &Vector6<f64>) -> Vector6<f64> {
    let ((w, v0), (mw, m0)) = (split(v), split(m));
    join(w.cross(&mw), w.cross(&m0) + v0.cross(&mw))
}

/// Spatial cross product with a force vector, v ×* f (Featherstone eq. 2.32).
fn cross_force(v: &Vector6<f64>, f: &Vector6<f64>) -> Vector6<f64> {
    let ((w, v0), (n, f0)) = (split(v), split(f));
    join(w.cross(&n) + v0.cross(&f0), w.cross(&f0))
}

/// The spatial inertia about the world origin of a body with mass properties
/// `b` given in a frame at `world_from_link` (Featherstone eq. 2.63 with the
/// centre of mass at c): \[\[I_c + m·c̃·c̃ᵀ, m·c̃\], \[m·c̃ᵀ, m·1\]\].
fn spatial_inertia(b: &Inertial, world_from_link: &Pose) -> Matrix6<f64> {
    let w = b.transformed(world_from_link);
    let c = skew(&w.com);
    let mut out = Matrix6::zeros();
    out.fixed_view_mut::<3, 3>(0, 0).copy_from(&(w.inertia + w.mass * c * c.transpose()));
    out.fixed_view_mut::<3, 3>(0, 3).copy_from(&(w.mass * c));
    out.fixed_view_mut::<3, 3>(3, 0).copy_from(&(w.mass * c.transpose()));
    out.fixed_view_mut::<3, 3>(3, 3).copy_from(&(w.mass * Matrix3::identity()));
    out
}

/// What every algorithm needs at one configuration: per joint, its motion
/// subspace S (the spatial velocity of its link per unit q̇, in the world
/// frame) and the link's spatial inertia about the world origin.
struct Kinematics {
    s: Vec<Vector6<f64>>,
    inertia: Vec<Matrix6<f64>>,
}

fn kinematics(robot: &Robot, q: &[f64]) -> Result<Kinematics> {
    let bodies = bodies(robot)?;
    let frames = robot.link_frames(q)?;
    let n = robot.dof();
    let mut s = Vec::with_capacity(n);
    let mut inertia = Vec::with_capacity(n);
    for (i, j) in robot.joints().iter().enumerate() {
        let (dir, point) = joint_axis(j, i, &frames);
        // A turn ω = dir·q̇ about an axis through `point` moves the body point
        // at the world origin with ω × (0 − point) = point × dir per unit q̇;
        // a slide moves every point with dir.
        s.push(match j.kind {
            JointType::Revolute => join(dir, point.cross(&dir)),
            JointType::Prismatic => join(Vector3::zeros(), dir),
        });
        inertia.push(spatial_inertia(bodies[i], &frames[i + 1]));
    }
    Ok(Kinematics { s, inertia })
}

/// The mass properties of every link, or the error naming the first link without.
fn bodies(robot: &Robot) -> Result<Vec<&Inertial>> {
    robot
        .inertials()
        .iter()
        .enumerate()
        .map(|(i, b)| {
            b.as_ref().ok_or_else(|| Error::NoInertial {
                robot: robot.name().to_string(),
                link: i + 1,
                joint: robot.joints()[i].name.clone(),
            })
        })
        .collect()
}

/// Checks a vector of joint rates (`what` = "qd", "qdd", "tau"): length and finiteness.
fn check_rates(robot: &Robot, what: &str, v: &[f64]) -> Result<()> {
    if v.len() != robot.dof() {
        return Err(Error::Input(InputError::WrongLength {
            what: what.into(),
            got: v.len(),
            expected: robot.dof(),
            of: format!("one per joint of `{}`", robot.name()),
        }));
    }
    if let Some(i) = v.iter().position(|x| !x.is_finite()) {
        return Err(robot.for_joint(i, Error::Input(InputError::NotFinite { what: what.into(), value: v[i] })));
    }
    Ok(())
}

/// Ok if every value of a result is finite; else [`Error::Overflow`] naming
/// the first value that is not (`name` of its index) and the largest inputs:
/// per joint vector `rates` its largest entry, `gravity`, the heaviest link.
pub(crate) fn finite_result(
    robot: &Robot,
    values: &[f64],
    name: impl Fn(usize) -> String,
    rates: &[(&str, &[f64])],
    gravity: Option<&Vector3<f64>>,
) -> Result<()> {
    let Some(k) = values.iter().position(|v| !v.is_finite()) else { return Ok(()) };
    let mut inputs: Vec<String> = rates
        .iter()
        .filter_map(|(what, v)| {
            let (i, x) = v.iter().enumerate().max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))?;
            Some(format!("largest |{what}| {:e} at joint {}", x.abs(), i + 1))
        })
        .collect();
    if let Some(g) = gravity {
        inputs.push(format!("|gravity| {:e} m/s²", g.norm()));
    }
    let mass = robot.inertials().iter().flatten().map(|b| b.mass).fold(0.0, f64::max);
    inputs.push(format!("heaviest link {mass:e} kg"));
    Err(Error::Overflow { what: name(k), value: values[k], inputs: inputs.join(", ") })
}

/// The name of entry `k` (column-major) of an n × n matrix `m`.
pub(crate) fn matrix_entry(m: &str, n: usize) -> impl Fn(usize) -> String + '_ {
    move |k| format!("{m}({}, {})", k % n + 1, k / n + 1)
}

fn check_gravity(gravity: &Vector3<f64>) -> Result<()> {
    match gravity.iter().position(|g| !g.is_finite()) {
        None => Ok(()),
        Some(i) => Err(Error::Input(InputError::NotFinite { what: format!("gravity[{i}]"), value: gravity[i] })),
    }
}

/// Inverse dynamics by the recursive Newton–Euler algorithm: the joint
/// torques τ \[N·m or N\] that give accelerations `qdd` \[rad/s² or m/s²\] at
/// `q` \[rad or m\] and `qd` \[rad/s or m/s\] under `gravity` \[m/s², world
/// frame, e.g. \[0, 0, −9.81\]\]: τ = M(q)·q̈ + C(q, q̇)·q̇ + g(q).
///
/// # Examples
/// ```
/// use kinema::{dynamics, nalgebra::Vector3};
/// let robot = kinema::Robot::builtin("puma560")?;
/// let g = Vector3::new(0.0, 0.0, -9.81);
/// let tau = dynamics::rnea(&robot, robot.home(), &[0.0; 6], &[0.0; 6], &g)?;
/// assert_eq!(tau, dynamics::gravity_torques(&robot, robot.home(), &g)?);
/// assert!(tau[1].abs() > 1.0); // the shoulder holds the arm up
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn rnea(robot: &Robot, q: &[f64], qd: &[f64], qdd: &[f64], gravity: &Vector3<f64>) -> Result<Vec<f64>> {
    check_rates(robot, "qd", qd)?;
    check_rates(robot, "qdd", qdd)?;
    check_gravity(gravity)?;
    let k = kinematics(robot, q)?;
    let n = robot.dof();
    // Outward: velocities and accelerations. The base is at rest; gravity
    // enters as an upward acceleration of the base (Luh, Walker and Paul's
    // trick), so every link's inertial force includes its weight.
    let mut v = Vector6::zeros();
    let mut a = join(Vector3::zeros(), -gravity);
    let mut f = vec![Vector6::zeros(); n];
    for i in 0..n {
        let sqd = k.s[i] * qd[i];
        // Velocities add along the chain (all in one frame, at one point).
        v += sqd;
        // a_i = a_{i−1} + S_i·q̈_i + Ṡ_i·q̇_i, where S_i moves with link i: Ṡ_i = v_i ×ₘ S_i.
        a += k.s[i] * qdd[i] + cross_motion(&v, &sqd);
        // Newton–Euler for the body: f = I·a + v ×* (I·v).
        f[i] = k.inertia[i] * a + cross_force(&v, &(k.inertia[i] * v));
    }
    // Inward: joint i carries the forces of links i..n; its torque is that
    // wrench's component along the joint's motion subspace.
    let mut tau = vec![0.0; n];
    let mut carried = Vector6::zeros();
    for i in (0..n).rev() {
        carried += f[i];
        tau[i] = k.s[i].dot(&carried);
    }
    let torque = |i: usize| format!("the torque of joint {}", i + 1);
    finite_result(robot, &tau, torque, &[("q̇", qd), ("q̈", qdd)], Some(gravity))?;
    Ok(tau)
}

/// Gravity torques g(q) \[N·m or N\]: what holds the arm still at `q` under
/// `gravity` \[m/s², world frame\] (RNEA with q̇ = q̈ = 0).
pub fn gravity_torques(robot: &Robot, q: &[f64], gravity: &Vector3<f64>) -> Result<Vec<f64>> {
    let zero = vec![0.0; robot.dof()];
    rnea(robot, q, &zero, &zero, gravity)
}

/// Coriolis and centrifugal torques C(q, q̇)·q̇ \[N·m or N\] (RNEA with q̈ = 0
/// and no gravity).
pub fn coriolis(robot: &Robot, q: &[f64], qd: &[f64]) -> Result<Vec<f64>> {
    let zero = vec![0.0; robot.dof()];
    rnea(robot, q, qd, &zero, &Vector3::zeros())
}

/// The Coriolis matrix C(q, q̇) (dof × dof; N·m·s/rad, N·s/m or N·s for
/// the mixed entries of revolute and prismatic joints) with C(q, q̇)·q̇ =
/// [`coriolis`]`(q, q̇)` and Ṁ(q) − 2C(q, q̇) skew-symmetric. C is not unique;
/// this one is Echeandia and Wensing's factorisation (2021), the one
/// Pinocchio's `computeCoriolisMatrix` returns.
///
/// # Examples
/// ```
/// use kinema::dynamics;
/// let robot = kinema::Robot::builtin("puma560")?;
/// let (q, qd) = (robot.home(), [0.1, -0.2, 0.3, 0.0, 0.5, -1.0]);
/// let c = dynamics::coriolis_matrix(&robot, q, &qd)?;
/// let cqd = c * kinema::nalgebra::DVector::from_column_slice(&qd);
/// let h = dynamics::coriolis(&robot, q, &qd)?;
/// assert!((0..6).all(|i| (cqd[i] - h[i]).abs() < 1e-12));
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn coriolis_matrix(robot: &Robot, q: &[f64], qd: &[f64]) -> Result<DMatrix<f64>> {
    let c = coriolis::coriolis_matrix(robot, q, qd)?;
    finite_result(robot, c.as_slice(), matrix_entry("C", robot.dof()), &[("q̇", qd)], None)?;
    Ok(c)
}

/// The joint-space mass matrix M(q) (dof × dof, symmetric positive definite
/// for a chain whose every joint moves mass; kg·m², kg·m or kg) by the
/// composite-rigid-body algorithm: M_ij = S_iᵀ·I^c_j·S_j for i ≤ j, where
/// I^c_j is the inertia of links j..n locked together (Featherstone §6.2; in
/// one frame the composite inertia is a plain sum).
///
/// # Examples
/// ```
/// use kinema::{dynamics, nalgebra::Vector3};
/// let robot = kinema::Robot::builtin("puma560")?;
/// let m = dynamics::mass_matrix(&robot, robot.home())?;
/// assert!((m[(1, 2)] - m[(2, 1)]).abs() < 1e-12 && m[(0, 0)] > 0.0);
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn mass_matrix(robot: &Robot, q: &[f64]) -> Result<DMatrix<f64>> {
    let k = kinematics(robot, q)?;
    let n = robot.dof();
    let mut m = DMatrix::zeros(n, n);
    let mut composite = Matrix6::zeros();
    for j in (0..n).rev() {
        composite += k.inertia[j];
        // The wrench that accelerating joint j alone (q̈_j = 1) needs from the locked links j..n.
        let f = composite * k.s[j];
        for i in 0..=j {
            m[(i, j)] = k.s[i].dot(&f);
            m[(j, i)] = m[(i, j)];
        }
    }
    finite_result(robot, m.as_slice(), matrix_entry("M", n), &[], None)?;
    Ok(m)
}

/// Forward dynamics: the accelerations q̈ \[rad/s² or m/s²\] that torques
/// `tau` \[N·m or N\] produce at `q`, `qd` under `gravity` \[m/s², world frame\],
/// i.e. q̈ = M(q)⁻¹·(τ − C(q, q̇)·q̇ − g(q)), by Featherstone's
/// articulated-body algorithm (O(n), no matrix is formed). Errors if a joint
/// drives no mass at `q` (then M(q) is singular and q̈ undetermined).
///
/// # Examples
/// ```
/// use kinema::{dynamics, nalgebra::Vector3};
/// let robot = kinema::Robot::builtin("puma560")?;
/// let g = Vector3::new(0.0, 0.0, -9.81);
/// let (q, qd) = (robot.home(), [0.1, -0.2, 0.3, 0.0, 0.5, -1.0]);
/// let qdd = [1.0, 0.5, -0.5, 2.0, 0.0, 1.0];
/// let tau = dynamics::rnea(&robot, q, &qd, &qdd, &g)?;
/// let back = dynamics::forward_dynamics(&robot, q, &qd, &tau, &g)?;
/// assert!(back.iter().zip(&qdd).all(|(a, b)| (a - b).abs() < 1e-9));
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn forward_dynamics(robot: &Robot, q: &[f64], qd: &[f64], tau: &[f64], gravity: &Vector3<f64>) -> Result<Vec<f64>> {
    let qdd = aba::aba(robot, q, qd, tau, gravity)?;
    let acceleration = |i: usize| format!("the acceleration of joint {}", i + 1);
    finite_result(robot, &qdd, acceleration, &[("q̇", qd), ("τ", tau)], Some(gravity))?;
    Ok(qdd)
}
