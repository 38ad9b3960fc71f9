//! Allocation-free inverse dynamics ([`rnea_into`]) and mass matrix
//! ([`mass_matrix_into`]) over a reusable [`Data`](crate::Data), computing what the
//! plain [`rnea`](super::rnea) and [`mass_matrix`](super::mass_matrix)
//! compute (they are the reference these are tested against).
//!
//! Both work in the world frame like the reference, on the link frames of
//! the fast kinematics backend ([`crate::kin::link_frames_into`]), with moments
//! taken at the world origin. What differs is how the bodies enter:
//!
//! * RNEA never forms a 6 × 6 inertia. Each link's Newton–Euler equations
//!   are written at its centre of mass, the force from the classical
//!   acceleration of that point and the moment in the link's own axes, where
//!   the inertia tensor is constant (two rotations of a 3-vector instead of
//!   rotating the tensor).
//! * CRBA keeps each body as mass, first moment h = m·c and the symmetric
//!   rotational inertia about the origin (10 numbers instead of 36), so that
//!   the composite inertias stay plain sums and I·S is a handful of products.

use nalgebra::{DMatrix, Vector3};

use super::{check_gravity, check_rates};
use crate::data::{Data, Spatial};
use crate::error::{Error, InputError, Result};
use crate::kin::joint_axis;
use crate::math::Pose;
use crate::model::{Inertial, JointType};
use crate::robot::Robot;

/// The mass properties of every link, or the error naming the first link
/// without. Checked once per call so that the loops below need no error path.
fn bodies(robot: &Robot) -> Result<&[Option<Inertial>]> {
    let inertials = robot.inertials();
    match inertials.iter().position(Option::is_none) {
        None => Ok(inertials),
        Some(i) => Err(Error::NoInertial {
            robot: robot.name().to_string(),
            link: i + 1,
            joint: robot.joints()[i].name.clone(),
        }),
    }
}

/// A body's inertia about the world origin in world axes, in the compact
/// form CRBA sums: mass, first moment h = m·c, and the symmetric rotational
/// inertia Ī as its six values \[xx, yy, zz, xy, xz, yz\] (Featherstone eq.
/// 2.63's blocks). Six numbers instead of a 3 × 3 keep the sums and products
/// short.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Body {
    mass: f64,
    h: Vector3<f64>,
    i: [f64; 6],
}

impl Body {
    const ZERO: Body = Body { mass: 0.0, h: Vector3::new(0.0, 0.0, 0.0), i: [0.0; 6] };

    /// The body `b`, given in the link frame at `frame`, seen from the world.
    fn in_world(b: &Inertial, frame: &Pose) -> Body {
        let r = &frame.rot;
        let c = r * b.com + frame.pos;
        // R·I_c·Rᵀ (symmetric: the upper triangle), then the parallel-axis
        // shift to the origin, m·(|c|²·1 − c·cᵀ).
        let a = r * b.inertia;
        let e = |x: usize, y: usize| a[(x, 0)] * r[(y, 0)] + a[(x, 1)] * r[(y, 1)] + a[(x, 2)] * r[(y, 2)];
        let mc = c * b.mass;
        Body {
            mass: b.mass,
            h: mc,
            i: [
                e(0, 0) + mc.y * c.y + mc.z * c.z,
                e(1, 1) + mc.x * c.x + mc.z * c.z,
                e(2, 2) + mc.x * c.x + mc.y * c.y,
                e(0, 1) - mc.x * c.y,
                e(0, 2) - mc.x * c.z,
                e(1, 2) - mc.y * c.z,
            ],
        }
    }

    fn add(&mut self, other: &Body) {
        self.mass += other.mass;
        self.h += other.h;
        for (a, b) in self.i.iter_mut().zip(&other.i) {
            *a += b;
        }
    }

    /// The wrench I·s that moving with `s` needs (Featherstone eq. 2.63):
    /// \[Ī·ω + h × v; m·v − h × ω\].
    fn times(&self, s: &Spatial) -> Spatial {
        let ([xx, yy, zz, xy, xz, yz], w) = (self.i, &s.ang);
        let iw = Vector3::new(
            xx * w.x + xy * w.y + xz * w.z,
            xy * w.x + yy * w.y + yz * w.z,
            xz * w.x + yz * w.y + zz * w.z,
        );
        Spatial { ang: iw + self.h.cross(&s.lin), lin: s.lin * self.mass - self.h.cross(w) }
    }
}

/// Every joint's motion subspace in the world frame at the world origin,
/// from the link frames (`frames[i + 1]` is link i's), as in the reference's
/// `kinematics`.
fn subspaces(robot: &Robot, frames: &[Pose], out: &mut [Spatial]) {
    for (i, (j, s)) in robot.joints().iter().zip(out.iter_mut()).enumerate() {
        let (dir, point) = joint_axis(j, i, frames);
        *s = match j.kind {
            JointType::Revolute => Spatial { ang: dir, lin: point.cross(&dir) },
            JointType::Prismatic => Spatial { ang: Vector3::zeros(), lin: dir },
        };
    }
}

/// Inverse dynamics as [`rnea`](super::rnea) (same arguments, units and
/// errors), written into `tau` (one value per joint) without allocating.
/// On an error `tau` is left as it was.
///
/// # Examples
/// ```
/// use kinema::{dynamics, nalgebra::Vector3};
/// let robot = kinema::Robot::builtin("puma560")?;
/// let mut data = kinema::Data::new(&robot);
/// let (g, qd, qdd) = (Vector3::new(0.0, 0.0, -9.81), [0.1; 6], [0.2; 6]);
/// let mut tau = [0.0; 6];
/// dynamics::rnea_into(&robot, &mut data, robot.home(), &qd, &qdd, &g, &mut tau)?;
/// let reference = dynamics::rnea(&robot, robot.home(), &qd, &qdd, &g)?;
/// assert!(tau.iter().zip(&reference).all(|(a, b)| (a - b).abs() < 1e-12));
/// # Ok::<(), kinema::Error>(())
/// ```
#[allow(clippy::too_many_arguments)]
pub fn rnea_into(
    robot: &Robot,
    data: &mut Data,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    gravity: &Vector3<f64>,
    tau: &mut [f64],
) -> Result<()> {
    check_rates(robot, "qd", qd)?;
    check_rates(robot, "qdd", qdd)?;
    check_gravity(gravity)?;
    let n = robot.dof();
    check_len(robot, "tau", tau.len(), n)?;
    let bodies = bodies(robot)?;
    data.fit(robot);
    crate::kin::link_frames_into(robot, q, &mut data.frames)?;
    subspaces(robot, &data.frames, &mut data.subspace);

    // Outward, as in the reference: velocity and spatial acceleration of the
    // body point at the world origin; gravity as an upward base acceleration.
    let (mut w, mut v) = (Vector3::zeros(), Vector3::zeros());
    let (mut dw, mut dv) = (Vector3::zeros(), -gravity);
    for (i, b) in bodies.iter().enumerate() {
        let b = b.as_ref().unwrap_or(&Inertial::ZERO); // all present (checked above)
        let s = &data.subspace[i];
        let (sw, sv) = (s.ang * qd[i], s.lin * qd[i]);
        w += sw;
        v += sv;
        // a_i = a_{i−1} + S_i·q̈_i + v_i ×ₘ S_i·q̇_i
        dw += s.ang * qdd[i] + w.cross(&sw);
        dv += s.lin * qdd[i] + w.cross(&sv) + v.cross(&sw);

        // Newton at the centre of mass c: its classical acceleration is the
        // spatial one plus α × c plus ω × (velocity of c).
        let frame = &data.frames[i + 1];
        let c = frame.rot * b.com + frame.pos;
        let vc = v + w.cross(&c);
        let force = (dv + dw.cross(&c) + w.cross(&vc)) * b.mass;
        // Euler about c in the link's axes, where the inertia is constant.
        let (wl, dwl) = (frame.rot.tr_mul(&w), frame.rot.tr_mul(&dw));
        let moment = frame.rot * (b.inertia * dwl + wl.cross(&(b.inertia * wl)));
        data.wrench[i] = Spatial { ang: moment + c.cross(&force), lin: force };
    }
    // Inward: joint i carries the wrenches of links i..n (all at one point).
    let mut carried = Spatial::ZERO;
    for i in (0..n).rev() {
        carried.ang += data.wrench[i].ang;
        carried.lin += data.wrench[i].lin;
        tau[i] = data.subspace[i].dot(&carried);
    }
    let torque = |i: usize| format!("the torque of joint {}", i + 1);
    super::finite_result(robot, tau, torque, &[("q̇", qd), ("q̈", qdd)], Some(gravity))
}

/// The mass matrix as [`mass_matrix`](super::mass_matrix) (same units and
/// errors), written into `m` (must be dof × dof; both triangles are filled)
/// without allocating. On an input error `m` is left as it was (an
/// overflow, [`Error::Overflow`], leaves the values that are not finite).
///
/// # Examples
/// ```
/// use kinema::{dynamics, nalgebra::DMatrix};
/// let robot = kinema::Robot::builtin("puma560")?;
/// let mut data = kinema::Data::new(&robot);
/// let mut m = DMatrix::zeros(6, 6);
/// dynamics::mass_matrix_into(&robot, &mut data, robot.home(), &mut m)?;
/// assert!((m.clone() - dynamics::mass_matrix(&robot, robot.home())?).amax() < 1e-12);
/// # Ok::<(), kinema::Error>(())
/// ```
pub fn mass_matrix_into(robot: &Robot, data: &mut Data, q: &[f64], m: &mut DMatrix<f64>) -> Result<()> {
    let n = robot.dof();
    if m.nrows() != n || m.ncols() != n {
        return Err(Error::Input(InputError::WrongLength {
            what: "m".into(),
            got: m.len(),
            expected: n * n,
            of: format!("an {n} × {n} matrix for robot `{}`; it is {} × {}", robot.name(), m.nrows(), m.ncols()),
        }));
    }
    let bodies = bodies(robot)?;
    data.fit(robot);
    crate::kin::link_frames_into(robot, q, &mut data.frames)?;
    subspaces(robot, &data.frames, &mut data.subspace);

    // The composite body of links j..n: in one frame a plain sum.
    let mut composite = Body::ZERO;
    for j in (0..n).rev() {
        let b = bodies[j].as_ref().unwrap_or(&Inertial::ZERO); // all present (checked above)
        composite.add(&Body::in_world(b, &data.frames[j + 1]));
        // The wrench that q̈_j = 1 alone needs from the locked links j..n: I^c·S_j.
        let f = composite.times(&data.subspace[j]);
        for i in 0..=j {
            let mij = data.subspace[i].dot(&f);
            m[(i, j)] = mij;
            m[(j, i)] = mij;
        }
    }
    super::finite_result(robot, m.as_slice(), super::matrix_entry("M", n), &[], None)
}

fn check_len(robot: &Robot, what: &str, len: usize, n: usize) -> Result<()> {
    if len == n {
        return Ok(());
    }
    Err(Error::Input(InputError::WrongLength {
        what: what.into(),
        got: len,
        expected: n,
        of: format!("one per joint of `{}`", robot.name()),
    }))
}
