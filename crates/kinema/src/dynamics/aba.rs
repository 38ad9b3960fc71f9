//! Forward dynamics by Featherstone's articulated-body algorithm (Featherstone,
//! *Rigid Body Dynamics Algorithms*, 2008, §7.3, Table 7.1), in the same
//! world-frame spatial algebra as the rest of [`super`]: every vector is
//! \[angular; linear\] about the world origin, so the tables' transforms
//! ⁱX_λ(i) are identities and the passes only add.

use nalgebra::{Matrix6, Vector3, Vector6};

use super::{check_gravity, check_rates, cross_force, cross_motion, join, kinematics};
use crate::error::{Error, ModelError, Result};
use crate::robot::Robot;

/// q̈ for τ at (q, q̇) under `gravity`, in O(n); see [`super::forward_dynamics`].
pub(super) fn aba(robot: &Robot, q: &[f64], qd: &[f64], tau: &[f64], gravity: &Vector3<f64>) -> Result<Vec<f64>> {
    check_rates(robot, "qd", qd)?;
    check_rates(robot, "tau", tau)?;
    check_gravity(gravity)?;
    let k = kinematics(robot, q)?;
    let n = robot.dof();

    // Pass 1, outward: velocities v_i, the velocity-product accelerations
    // c_i = v_i ×ₘ S_i·q̇_i (Ṡ_i·q̇_i, as in RNEA), and the bias forces
    // p_i = v_i ×* I_i·v_i (Table 7.1, first loop).
    let mut v = Vector6::zeros();
    let mut c = Vec::with_capacity(n);
    let mut ia: Vec<Matrix6<f64>> = k.inertia.clone();
    let mut pa = Vec::with_capacity(n);
    for ((s, inertia), &rate) in k.s.iter().zip(&k.inertia).zip(qd) {
        let sqd = s * rate;
        v += sqd;
        c.push(cross_motion(&v, &sqd));
        pa.push(cross_force(&v, &(inertia * v)));
    }

    // Pass 2, inward: articulated inertias I^A_i and bias forces p^A_i; each
    // link hands its parent what the parent feels through a joint that moves
    // freely under τ_i (Table 7.1, second loop, for one-DOF joints).
    let mut u = vec![Vector6::zeros(); n];
    let mut d = vec![0.0; n];
    let mut uu = vec![0.0; n];
    for i in (0..n).rev() {
        u[i] = ia[i] * k.s[i];
        d[i] = k.s[i].dot(&u[i]);
        // D_i is the articulated inertia the joint drives; it is positive
        // unless the joint moves no mass (then q̈_i is undetermined).
        if !(d[i] > 0.0 && d[i].is_finite()) {
            return Err(Error::Model(ModelError::InvalidModel {
                robot: robot.name().to_string(),
                message: format!(
                    "joint `{}` drives an articulated inertia of {:e} at this configuration; forward dynamics \
                     needs it positive (a joint that moves no mass?)",
                    robot.joints()[i].name,
                    d[i]
                ),
            }));
        }
        uu[i] = tau[i] - k.s[i].dot(&pa[i]);
        if i > 0 {
            let ia_hand = ia[i] - u[i] * u[i].transpose() / d[i];
            let pa_hand = pa[i] + ia_hand * c[i] + u[i] * (uu[i] / d[i]);
            ia[i - 1] += ia_hand;
            pa[i - 1] += pa_hand;
        }
    }

    // Pass 3, outward: accelerations. Gravity enters as an upward
    // acceleration of the base, as in RNEA (Table 7.1, third loop).
    let mut a = join(Vector3::zeros(), -gravity);
    let mut qdd = vec![0.0; n];
    for i in 0..n {
        let a_pre = a + c[i];
        qdd[i] = (uu[i] - u[i].dot(&a_pre)) / d[i];
        a = a_pre + k.s[i] * qdd[i];
    }
    Ok(qdd)
}
