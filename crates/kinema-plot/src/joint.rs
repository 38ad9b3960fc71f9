//! Joint curves against time with the limits drawn.

use kinema::traj::JointTrajectory;
use kinema::{JointType, Robot};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::{color, drawing, Plot, Result, FONT};

/// Joint positions, velocities and accelerations of a trajectory against
/// time: three panels, one curve per joint (in degrees for revolute joints,
/// millimetres for prismatic ones when all joints are of one kind, else SI),
/// and each joint's limits as dashed lines of its colour.
#[derive(Debug, Clone)]
pub struct JointCurves {
    name: String,
    names: Vec<String>,
    t: Vec<f64>,
    /// \[panel\]\[joint\]\[sample\], in display units.
    series: [Vec<Vec<f64>>; 3],
    /// \[panel\]\[joint\]: symmetric or (min, max) limits in display units.
    limits: [Vec<Option<(f64, f64)>>; 3],
    units: [&'static str; 3],
}

impl JointCurves {
    /// The curves of `traj` (a trajectory of `robot`). Errors: a joint count
    /// other than the robot's, fewer than two samples.
    pub fn new(robot: &Robot, traj: &JointTrajectory) -> Result<Self> {
        crate::check_traj(robot, traj, 2)?;
        let n = robot.dof();
        let joints = robot.joints();
        let all_revolute = joints.iter().all(|j| j.kind == JointType::Revolute);
        let all_prismatic = joints.iter().all(|j| j.kind == JointType::Prismatic);
        let (scale, units) = if all_revolute {
            (180.0 / std::f64::consts::PI, ["deg", "deg/s", "deg/s²"])
        } else if all_prismatic {
            (1000.0, ["mm", "mm/s", "mm/s²"])
        } else {
            (1.0, ["rad or m", "rad/s or m/s", "rad/s² or m/s²"])
        };
        let mut series: [Vec<Vec<f64>>; 3] = Default::default();
        for (p, s) in series.iter_mut().enumerate() {
            *s = (0..n)
                .map(|i| {
                    (0..traj.len())
                        .map(|k| {
                            let v = match p {
                                0 => traj.q(k)[i],
                                1 => traj.qd(k)[i],
                                _ => traj.qdd(k)[i],
                            };
                            v * scale
                        })
                        .collect()
                })
                .collect();
        }
        let sym = |v: Option<f64>| v.map(|v| (-v * scale, v * scale));
        let limits = [
            joints
                .iter()
                .map(|j| {
                    (j.limits.min.is_finite() && j.limits.max.is_finite())
                        .then_some((j.limits.min * scale, j.limits.max * scale))
                })
                .collect(),
            joints.iter().map(|j| sym(j.limits.vel)).collect(),
            joints.iter().map(|j| sym(j.limits.acc)).collect(),
        ];
        Ok(JointCurves {
            name: robot.name().to_string(),
            names: joints.iter().map(|j| j.name.clone()).collect(),
            t: traj.times().to_vec(),
            series,
            limits,
            units,
        })
    }

    /// Lowest and highest value of panel `p`, limits included where they are
    /// within 3× the data's own range (far limits would flatten the curves).
    fn range(&self, p: usize) -> (f64, f64) {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for s in &self.series[p] {
            for &v in s {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
        let span = (hi - lo).max(1e-9);
        for (a, b) in self.limits[p].iter().flatten() {
            if *a > lo - 3.0 * span {
                lo = lo.min(*a);
            }
            if *b < hi + 3.0 * span {
                hi = hi.max(*b);
            }
        }
        let pad = 0.08 * (hi - lo).max(1e-6);
        (lo - pad, hi + pad)
    }
}

impl Plot for JointCurves {
    fn draw<DB: DrawingBackend<ErrorType: 'static>>(&self, area: &DrawingArea<DB, Shift>) -> Result<()> {
        let (w, _) = area.dim_in_pixel();
        let font_px = (w / 70).clamp(10, 16);
        let body = crate::title_area(area, &format!("{}: joint trajectory", self.name))?;
        let panels = body.split_evenly((3, 1));
        let (t0, t1) = (self.t[0], *self.t.last().expect("two samples"));
        let what = ["position", "velocity", "acceleration"];
        for (p, panel) in panels.iter().enumerate() {
            let (lo, hi) = self.range(p);
            let mut chart = ChartBuilder::on(panel)
                .margin(8)
                .x_label_area_size(font_px * 2 + 6)
                .y_label_area_size(font_px * 5)
                .build_cartesian_2d(t0..t1.max(t0 + 1e-9), lo..hi)
                .map_err(drawing)?;
            chart
                .configure_mesh()
                .x_desc("t [s]")
                .y_desc(format!("{} [{}]", what[p], self.units[p]))
                .label_style((FONT, font_px))
                .light_line_style(RGBColor(238, 238, 238))
                .draw()
                .map_err(drawing)?;
            for (i, s) in self.series[p].iter().enumerate() {
                let c = color(i);
                let series = chart
                    // Width 1: plotters joins wider polylines with unbounded miters,
                    // which draw spikes where a dense curve reverses.
                    .draw_series(LineSeries::new(
                        self.t.iter().copied().zip(s.iter().map(|v| v.clamp(lo, hi))),
                        c.stroke_width(1),
                    ))
                    .map_err(drawing)?;
                if p == 0 {
                    series
                        .label(format!("{} {}", i + 1, self.names[i]))
                        .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], c.stroke_width(2)));
                }
                if let Some((a, b)) = self.limits[p][i] {
                    for v in [a, b] {
                        if v >= lo && v <= hi {
                            chart
                                .draw_series(DashedLineSeries::new([(t0, v), (t1, v)], 6, 4, c.stroke_width(1)))
                                .map_err(drawing)?;
                        }
                    }
                }
            }
            if p == 0 {
                crate::legend(&mut chart, font_px, SeriesLabelPosition::UpperRight)?;
            }
        }
        Ok(())
    }
}
