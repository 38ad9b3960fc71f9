//! The parameterised model the fit moves: constants and link lengths from
//! the parameter vector, predicted positions and the scaled Jacobian.

use std::f64::consts::PI;

use kinema::nalgebra::{DMatrix, DVector, Vector3};
use kinema::{Frame, LinkGeometry, Robot};

use crate::encoder::{joint_angles, Constants, MOTORS};
use crate::error::{Error, Result};

use super::{tool_position, CalibrationOptions, Sample, ENCODER, LINKS};

/// The parameterised model: x = (cg1…cg5, h1, h2, h3, c \[, d1, a1, a2, a3, d5\]).
pub(super) struct Model<'a> {
    robot: &'a Robot,
    pub(super) names: Vec<(&'static str, &'static str)>,
    pub(super) initial: DVector<f64>,
    /// r of the module documentation \[deg\], fixed.
    pub(super) roll_home: f64,
    estimate_links: bool,
}

impl<'a> Model<'a> {
    pub(super) fn new(robot: &'a Robot, options: &CalibrationOptions) -> Result<Self> {
        kinema::ik::scorbot::ScorbotIk::new(robot)
            .map_err(|e| Error::NeedsScorbot { needed_by: "the calibration model".into(), source: e })?;
        let c0 = &options.initial;
        c0.validate()?;
        let (cg, h) = (c0.counts_per_degree, c0.home_offsets);
        let mut names: Vec<(&str, &str)> = ENCODER.to_vec();
        let mut x = vec![cg[0], cg[1], cg[2], cg[3], cg[4], h[0], h[1], h[2], 0.5 * (h[4] / cg[4] - h[3] / cg[3])];
        if options.estimate_links {
            for (name, joint, is_d) in LINKS {
                names.push((name, "m"));
                x.push(dh_length(robot, joint, is_d));
            }
        }
        Ok(Model {
            robot,
            names,
            initial: DVector::from_vec(x),
            roll_home: 0.5 * (h[3] / cg[3] + h[4] / cg[4]),
            estimate_links: options.estimate_links,
        })
    }

    pub(super) fn constants(&self, x: &DVector<f64>) -> Result<Constants> {
        let cg = [x[0], x[1], x[2], x[3], x[4]];
        let c = x[8];
        let h = [x[5], x[6], x[7], cg[3] * (self.roll_home - c), cg[4] * (self.roll_home + c)];
        let out = Constants {
            name: String::new(),
            counts_per_degree: cg,
            counts_per_degree_sigma: [0.0; MOTORS],
            home_offsets: h,
            home_offsets_sigma: [0.0; MOTORS],
        };
        out.validate()?;
        Ok(out)
    }

    pub(super) fn robot(&self, x: &DVector<f64>) -> Result<Robot> {
        if !self.estimate_links {
            return Ok(self.robot.clone());
        }
        let links: Vec<f64> = (0..LINKS.len()).map(|k| x[ENCODER.len() + k]).collect();
        with_links(self.robot, &links)
    }

    /// Predicted positions, stacked (3N).
    pub(super) fn predict(&self, x: &DVector<f64>, samples: &[Sample]) -> Result<DVector<f64>> {
        let constants = self.constants(x)?;
        let robot = self.robot(x)?;
        let mut out = DVector::zeros(3 * samples.len());
        for (k, s) in samples.iter().enumerate() {
            out.fixed_rows_mut::<3>(3 * k).copy_from(&tool_position(&robot, &constants, &s.counts)?);
        }
        Ok(out)
    }

    /// The Jacobian of the predicted positions with its columns scaled to
    /// unit norm, the scales (column norms), and the SVD of the scaled one.
    #[allow(clippy::type_complexity)]
    pub(super) fn scaled_jacobian(
        &self,
        x: &DVector<f64>,
        samples: &[Sample],
    ) -> Result<(DMatrix<f64>, DVector<f64>, kinema::nalgebra::SVD<f64, kinema::nalgebra::Dyn, kinema::nalgebra::Dyn>)>
    {
        let p = self.names.len();
        let constants = self.constants(x)?;
        let robot = self.robot(x)?;
        // Models with one link length longer by 1 m (see the module docs).
        let longer: Vec<Robot> = if self.estimate_links {
            (0..LINKS.len())
                .map(|k| {
                    let mut links: Vec<f64> = (0..LINKS.len()).map(|j| x[ENCODER.len() + j]).collect();
                    links[k] += 1.0;
                    with_links(self.robot, &links)
                })
                .collect::<Result<_>>()?
        } else {
            Vec::new()
        };
        let cg = constants.counts_per_degree;
        let h = constants.home_offsets;
        let deg = PI / 180.0;
        // ∂θ/∂u_i [rad/deg], from the linear inverse of eq. 24.
        let dtheta: [[f64; MOTORS]; MOTORS] = std::array::from_fn(|i| {
            let mut e = [0.0; MOTORS];
            e[i] = deg;
            joint_angles(&e)
        });
        let mut j = DMatrix::zeros(3 * samples.len(), p);
        for (k, s) in samples.iter().enumerate() {
            let q = constants.angles(&s.counts)?;
            let jac = robot.jacobian(&q, Frame::Base)?;
            // g[i] = ∂p/∂u_i [m/deg]
            let g: [Vector3<f64>; MOTORS] = std::array::from_fn(|i| {
                let mut v = Vector3::zeros();
                for (jj, d) in dtheta[i].iter().enumerate() {
                    v += jac.fixed_view::<3, 1>(0, jj) * *d;
                }
                v
            });
            let ce = s.counts;
            let mut set = |col: usize, v: Vector3<f64>| j.fixed_view_mut::<3, 1>(3 * k, col).copy_from(&v);
            for i in 0..3 {
                let u = (ce[i] + h[i]) / cg[i];
                set(i, g[i] * (-u / cg[i]));
                set(5 + i, g[i] / cg[i]);
            }
            set(3, g[3] * (-ce[3] / (cg[3] * cg[3])));
            set(4, g[4] * (-ce[4] / (cg[4] * cg[4])));
            set(8, g[4] - g[3]);
            if self.estimate_links {
                let p0 = robot.fk(&q)?.world_from_tool.pos;
                for (l, r) in longer.iter().enumerate() {
                    set(ENCODER.len() + l, r.fk(&q)?.world_from_tool.pos - p0);
                }
            }
        }
        let scales = DVector::from_iterator(p, j.column_iter().map(|c| c.norm()));
        let mut js = j;
        for (c, s) in scales.iter().enumerate() {
            if *s > 0.0 {
                js.column_mut(c).scale_mut(1.0 / s);
            }
        }
        let svd = js.clone().svd(false, true);
        Ok((js, scales, svd))
    }
}

pub(super) fn dh_length(robot: &Robot, joint: usize, is_d: bool) -> f64 {
    match robot.joints()[joint].geometry {
        LinkGeometry::Dh { d, a, .. } => {
            if is_d {
                d
            } else {
                a
            }
        }
        // Model::new has checked the standard-DH structure.
        LinkGeometry::General { .. } => unreachable!("checked by ScorbotIk::new"),
    }
}

/// A copy of `robot` with the link lengths d1, a1, a2, a3, d5 \[m\] replaced.
pub(super) fn with_links(robot: &Robot, links: &[f64]) -> Result<Robot> {
    let mut joints = robot.joints().to_vec();
    for ((_, joint, is_d), value) in LINKS.iter().zip(links) {
        if let LinkGeometry::Dh { d, a, .. } = &mut joints[*joint].geometry {
            if *is_d {
                *d = *value;
            } else {
                *a = *value;
            }
        }
    }
    Ok(Robot::new(robot.model().to_builder().joints(joints).build()?))
}
