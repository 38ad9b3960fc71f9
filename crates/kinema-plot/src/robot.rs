//! A robot at a configuration: side and top views (seed 000 Fig. 2).

use kinema::nalgebra::Vector3;
use kinema::{Pose, Robot};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::{drawing, tidy, Plot, Result, FONT};

/// A robot drawn at one configuration: the side view (world x horizontal, z
/// up) and the top view (x horizontal, y up) side by side, at the same scale
/// on both axes. Links are straight lines between the origins of consecutive
/// joint frames (base, frames 1…n, tool), joints are dots, the base a square,
/// and the tool frame's axes are drawn in red (x), green (y) and blue (z).
#[derive(Debug, Clone)]
pub struct RobotView {
    name: String,
    frames: Vec<Pose>,
}

/// The two projections: (horizontal, vertical) world axes and their names.
const VIEWS: [((usize, usize), &str, &str); 2] =
    [((0, 2), "side view (x–z)", "z [m]"), ((0, 1), "top view (x–y)", "y [m]")];

impl RobotView {
    /// The view of `robot` at `q` (rad and m). Errors: a wrong joint count or
    /// non-finite values.
    pub fn new(robot: &Robot, q: &[f64]) -> Result<Self> {
        let frames = robot.link_frames(q)?;
        Ok(RobotView { name: robot.name().to_string(), frames })
    }

    /// The points drawn: the origins of the base, of every joint frame and of the tool.
    pub fn points(&self) -> Vec<Vector3<f64>> {
        self.frames.iter().map(|f| f.pos).collect()
    }

    /// A square window (centre, half-width) around the points in one projection.
    fn window(&self, (h, v): (usize, usize)) -> ((f64, f64), f64) {
        let pts = self.points();
        let lo = |i: usize| pts.iter().map(|p| p[i]).fold(f64::INFINITY, f64::min);
        let hi = |i: usize| pts.iter().map(|p| p[i]).fold(f64::NEG_INFINITY, f64::max);
        let (h0, h1, v0, v1) = (lo(h), hi(h), lo(v).min(0.0), hi(v).max(0.0));
        let half = (0.5 * (h1 - h0).max(v1 - v0)).max(0.05) * 1.25;
        ((0.5 * (h0 + h1), 0.5 * (v0 + v1)), half)
    }
}

impl Plot for RobotView {
    fn draw<DB: DrawingBackend<ErrorType: 'static>>(&self, area: &DrawingArea<DB, Shift>) -> Result<()> {
        let (w, _) = area.dim_in_pixel();
        let body = crate::title_area(area, &format!("{} at the given configuration", self.name))?;
        let halves = body.split_evenly((1, 2));
        let pts = self.points();
        let n = pts.len();
        let tool = self.frames[n - 1];
        let font_px = (w / 60).clamp(10, 18);
        for (panel, ((hi, vi), caption, v_label)) in halves.iter().zip(VIEWS) {
            let ((ch, cv), half) = self.window((hi, vi));
            let mut chart = ChartBuilder::on(panel)
                .caption(caption, (FONT, font_px + 2))
                .margin(10)
                .x_label_area_size(font_px * 3)
                .y_label_area_size(font_px * 4)
                .build_cartesian_2d(ch - half..ch + half, cv - half..cv + half)
                .map_err(drawing)?;
            chart
                .configure_mesh()
                .x_desc("x [m]")
                .y_desc(v_label)
                .x_label_formatter(&tidy)
                .y_label_formatter(&tidy)
                .label_style((FONT, font_px))
                .light_line_style(RGBColor(235, 235, 235))
                .draw()
                .map_err(drawing)?;
            let proj = |p: &Vector3<f64>| (p[hi], p[vi]);
            if vi == 2 {
                // The floor of the base frame.
                chart
                    .draw_series(LineSeries::new([(ch - half, 0.0), (ch + half, 0.0)], BLACK.mix(0.4).stroke_width(1)))
                    .map_err(drawing)?;
            }
            chart
                .draw_series(LineSeries::new(pts.iter().map(proj), RGBColor(40, 80, 160).stroke_width(4)))
                .map_err(drawing)?;
            chart
                .draw_series(pts[1..n - 1].iter().map(|p| Circle::new(proj(p), 5, RGBColor(230, 140, 20).filled())))
                .map_err(drawing)?;
            let b = proj(&pts[0]);
            let s = half * 0.04;
            chart
                .draw_series([Rectangle::new([(b.0 - s, b.1 - s), (b.0 + s, b.1 + s)], BLACK.filled())])
                .map_err(drawing)?;
            let axis_len = half * 0.2;
            for (k, color) in [RED, GREEN, BLUE].into_iter().enumerate() {
                let end = tool.pos + tool.rot.column(k) * axis_len;
                chart
                    .draw_series(LineSeries::new([proj(&tool.pos), proj(&end)], color.stroke_width(2)))
                    .map_err(drawing)?;
            }
        }
        Ok(())
    }
}
