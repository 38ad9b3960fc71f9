//! Cartesian curves and manipulability against time (seed 004 Fig. 20–33).

use kinema::analysis::{manipulability_along, yoshikawa, Axes};
use kinema::nalgebra::Vector3;
use kinema::traj::JointTrajectory;
use kinema::{Frame, Robot};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::{color, drawing, title_area, Plot, Result, FONT};

/// One panel of curves sharing a time axis.
#[derive(Debug, Clone)]
struct Panel {
    y_desc: String,
    /// (legend, values); NaN values leave gaps.
    series: Vec<(String, Vec<f64>)>,
}

/// Panels of curves against time, stacked.
#[derive(Debug, Clone)]
struct TimePanels {
    title: String,
    t: Vec<f64>,
    panels: Vec<Panel>,
}

impl TimePanels {
    fn draw<DB: DrawingBackend<ErrorType: 'static>>(&self, area: &DrawingArea<DB, Shift>) -> Result<()> {
        let body = title_area(area, &self.title)?;
        let (w, _) = body.dim_in_pixel();
        let font_px = (w / 70).clamp(10, 16);
        let (t0, t1) = (self.t[0], self.t[self.t.len() - 1].max(self.t[0] + 1e-9));
        for (panel, p) in body.split_evenly((self.panels.len(), 1)).iter().zip(&self.panels) {
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for v in p.series.iter().flat_map(|s| s.1.iter()).filter(|v| v.is_finite()) {
                lo = lo.min(*v);
                hi = hi.max(*v);
            }
            if !lo.is_finite() {
                (lo, hi) = (0.0, 1.0);
            }
            let pad = 0.08 * (hi - lo).max(1e-9 * hi.abs().max(1.0));
            let mut chart = ChartBuilder::on(panel)
                .margin(8)
                .x_label_area_size(font_px * 2 + 6)
                .y_label_area_size(font_px * 5)
                .build_cartesian_2d(t0..t1, lo - pad..hi + pad)
                .map_err(drawing)?;
            chart
                .configure_mesh()
                .x_desc("t [s]")
                .y_desc(p.y_desc.as_str())
                .label_style((FONT, font_px))
                .light_line_style(RGBColor(238, 238, 238))
                .draw()
                .map_err(drawing)?;
            for (i, (name, vals)) in p.series.iter().enumerate() {
                let c = color(i);
                // Split at NaN gaps.
                let mut runs: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
                for (&t, &v) in self.t.iter().zip(vals) {
                    if v.is_finite() {
                        runs.last_mut().expect("one run").push((t, v));
                    } else if !runs.last().expect("one run").is_empty() {
                        runs.push(Vec::new());
                    }
                }
                for (k, run) in runs.into_iter().enumerate() {
                    let s = chart.draw_series(LineSeries::new(run, c.stroke_width(1))).map_err(drawing)?;
                    if k == 0 {
                        s.label(name.as_str())
                            .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], c.stroke_width(2)));
                    }
                }
            }
            crate::legend(&mut chart, font_px, SeriesLabelPosition::UpperRight)?;
        }
        Ok(())
    }
}

/// The tool's Cartesian position, velocity and acceleration against time
/// (x, y, z and the norm): positions by forward kinematics, velocity as J·q̇
/// (exact for the trajectory's q̇), acceleration by differentiating that
/// velocity (second-order differences on the sample times).
#[derive(Debug, Clone)]
pub struct CartesianCurves(TimePanels);

impl CartesianCurves {
    /// The curves of `traj` (a trajectory of `robot`). Errors: a joint count
    /// other than the robot's, fewer than two samples.
    pub fn new(robot: &Robot, traj: &JointTrajectory) -> Result<Self> {
        crate::check_traj(robot, traj, 2)?;
        let n = traj.len();
        let mut pos = Vec::with_capacity(n);
        let mut vel = Vec::with_capacity(3 * n);
        let mut j = kinema::nalgebra::Matrix6xX::zeros(robot.dof());
        for k in 0..n {
            // The Jacobian's forward kinematics gives the position too.
            let fk = kinema::kin::jacobian_into(robot, traj.q(k), Frame::Base, &mut j)?;
            let qd = kinema::nalgebra::DVector::from_column_slice(traj.qd(k));
            let v = j.fixed_rows::<3>(0) * qd;
            vel.extend_from_slice(v.as_slice());
            pos.push(fk.world_from_tool.pos);
        }
        let mut acc = vec![0.0; 3 * n];
        let (mut a, mut scratch) = ([0.0; 3], [0.0; 3]);
        for k in 0..n {
            kinema::traj::to_joints::derivatives(traj.times(), &vel, 3, k, &mut a, &mut scratch);
            acc[3 * k..3 * k + 3].copy_from_slice(&a);
        }
        let vecs = |flat: &[f64]| -> Vec<Vector3<f64>> { flat.chunks(3).map(Vector3::from_column_slice).collect() };
        let panel = |name: &str, unit: &str, v: &[Vector3<f64>]| Panel {
            y_desc: format!("{name} [{unit}]"),
            series: ["x", "y", "z"]
                .iter()
                .enumerate()
                .map(|(i, c)| (c.to_string(), v.iter().map(|p| p[i]).collect()))
                .chain((name != "position").then(|| ("norm".to_string(), v.iter().map(|p| p.norm()).collect())))
                .collect(),
        };
        Ok(CartesianCurves(TimePanels {
            title: format!("{}: tool position, velocity and acceleration", robot.name()),
            t: traj.times().to_vec(),
            panels: vec![
                panel("position", "m", &pos),
                panel("velocity", "m/s", &vecs(&vel)),
                panel("acceleration", "m/s²", &vecs(&acc)),
            ],
        }))
    }
}

impl Plot for CartesianCurves {
    fn draw<DB: DrawingBackend<ErrorType: 'static>>(&self, area: &DrawingArea<DB, Shift>) -> Result<()> {
        self.0.draw(area)
    }
}

/// Manipulability along a trajectory (seed 004 Fig. 30, 33): Yoshikawa's
/// measure of the translational and rotational rows, and the translational
/// manipulability along the tool's direction of motion (seed 004 eq. 12,
/// left out where the tool is nearly still).
#[derive(Debug, Clone)]
pub struct ManipulabilityCurve(TimePanels);

impl ManipulabilityCurve {
    /// The curves of `traj` (a trajectory of `robot`). Errors: a joint count
    /// other than the robot's, fewer than two samples.
    pub fn new(robot: &Robot, traj: &JointTrajectory) -> Result<Self> {
        crate::check_traj(robot, traj, 2)?;
        let n = traj.len();
        let (mut wt, mut wr, mut along) = (Vec::with_capacity(n), Vec::with_capacity(n), Vec::with_capacity(n));
        let mut ws = kinema::Data::new(robot);
        let mut speed = Vec::with_capacity(n);
        for k in 0..n {
            let j = ws.jacobian(robot, traj.q(k), Frame::Base)?;
            wt.push(yoshikawa(j, Axes::Translation)?);
            wr.push(yoshikawa(j, Axes::Rotation)?);
            let qd = kinema::nalgebra::DVector::from_column_slice(traj.qd(k));
            let v: Vector3<f64> = j.fixed_rows::<3>(0) * qd;
            speed.push(v.norm());
            along.push(if v.norm() > 0.0 { manipulability_along(j, Axes::Translation, &v)? } else { f64::NAN });
        }
        // Directions of a tool slower than 1 % of its top speed are noise.
        let vmax = speed.iter().copied().fold(0.0, f64::max);
        for (a, v) in along.iter_mut().zip(&speed) {
            if *v <= 0.01 * vmax {
                *a = f64::NAN;
            }
        }
        Ok(ManipulabilityCurve(TimePanels {
            title: format!("{}: manipulability along the trajectory", robot.name()),
            t: traj.times().to_vec(),
            panels: vec![
                Panel {
                    y_desc: "translation".into(),
                    series: vec![("w = √det(Jv Jvᵀ)".into(), wt), ("along the motion (eq. 12) [m/s]".into(), along)],
                },
                Panel { y_desc: "rotation".into(), series: vec![("w = √det(Jω Jωᵀ)".into(), wr)] },
            ],
        }))
    }
}

impl Plot for ManipulabilityCurve {
    fn draw<DB: DrawingBackend<ErrorType: 'static>>(&self, area: &DrawingArea<DB, Shift>) -> Result<()> {
        self.0.draw(area)
    }
}
