//! Desired versus measured path with the tracking error (seed 000 Fig. 5–6).

use kinema::nalgebra::Vector3;
use kinema::traj::{distances_to_path, tracking_error, TrackingError};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::{color, drawing, title_area, Error, Plot, Result, FONT};

/// A desired path and one or more measured runs of it: on the left, both
/// projected on the plane of the path's two widest axes; on the right, each
/// measured point's distance to the desired path (perpendicular to it, seed
/// 000 §IV) against the arc length of its nearest path point. The title gives
/// seed 000's error: the mean distance of a run, as mean ± standard deviation
/// over the runs.
#[derive(Debug, Clone)]
pub struct TrackingPlot {
    desired: Vec<Vector3<f64>>,
    measured: Vec<Vec<Vector3<f64>>>,
    /// Per run: (arc length \[m\], distance \[m\]) of every measured point.
    errors: Vec<Vec<(f64, f64)>>,
    /// Mean distance of each run \[m\].
    pub run_means: Vec<f64>,
    /// Seed 000's error over the runs, from [`kinema::traj::tracking_error`].
    summary: TrackingError,
    axes: (usize, usize),
}

impl TrackingPlot {
    /// Errors: a desired path of fewer than two distinct points, no measured
    /// run, an empty run, non-finite coordinates.
    pub fn new(desired: Vec<Vector3<f64>>, measured: Vec<Vec<Vector3<f64>>>) -> Result<Self> {
        if measured.is_empty() {
            return Err(Error::TooFew { what: "measured paths".into(), got: 0, min: 1, of: "runs".into() });
        }
        if let Some(i) = measured.iter().position(|m| m.is_empty()) {
            return Err(Error::TooFew { what: format!("measured run {}", i + 1), got: 0, min: 1, of: "points".into() });
        }
        let summary = tracking_error(&desired, &measured)?;
        let run_means = summary.run_means.clone();
        // The per-point distances, for the right-hand chart.
        let mut errors = Vec::with_capacity(measured.len());
        for m in &measured {
            let d = distances_to_path(m, &desired)?;
            errors.push(d.iter().map(|d| (d.arc_length, d.distance)).collect());
        }
        // Draw on the plane of the two widest axes of the desired path.
        let extent = |i: usize| {
            let (lo, hi) =
                desired.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p[i]), b.max(p[i])));
            hi - lo
        };
        let mut idx = [0usize, 1, 2];
        idx.sort_by(|&a, &b| extent(b).total_cmp(&extent(a)));
        let axes = (idx[0].min(idx[1]), idx[0].max(idx[1]));
        Ok(TrackingPlot { desired, measured, errors, run_means, summary, axes })
    }

    /// Mean and standard deviation over the runs of their mean distance \[m\]
    /// (the deviation is 0 for a single run).
    pub fn mean_error(&self) -> (f64, f64) {
        (self.summary.mean, self.summary.spread)
    }

    /// Seed 000's tracking error of the runs (per-run means, mean and spread \[m\]).
    pub fn tracking_error(&self) -> &TrackingError {
        &self.summary
    }
}

impl Plot for TrackingPlot {
    fn draw<DB: DrawingBackend<ErrorType: 'static>>(&self, area: &DrawingArea<DB, Shift>) -> Result<()> {
        let (mean, sd) = self.mean_error();
        let title =
            format!("tracking error: {:.2} ± {:.2} mm over {} run(s)", mean * 1e3, sd * 1e3, self.measured.len());
        let body = title_area(area, &title)?;
        let (w, _) = body.dim_in_pixel();
        let font_px = (w / 70).clamp(10, 16);
        let (left, right) = body.split_horizontally(w / 2);
        let (a, b) = self.axes;
        let names = ["x", "y", "z"];
        let proj = |p: &Vector3<f64>| (p[a] * 1e3, p[b] * 1e3);
        let all: Vec<(f64, f64)> = self.desired.iter().chain(self.measured.iter().flatten()).map(proj).collect();
        let (mut lo, mut hi) = ((f64::INFINITY, f64::INFINITY), (f64::NEG_INFINITY, f64::NEG_INFINITY));
        for &(x, y) in &all {
            lo = (lo.0.min(x), lo.1.min(y));
            hi = (hi.0.max(x), hi.1.max(y));
        }
        let half = (0.5 * (hi.0 - lo.0).max(hi.1 - lo.1)).max(1.0) * 1.1;
        let c = (0.5 * (lo.0 + hi.0), 0.5 * (lo.1 + hi.1));
        let mut chart = ChartBuilder::on(&left)
            .caption("desired and measured paths", (FONT, font_px + 2))
            .margin(10)
            .x_label_area_size(font_px * 3)
            .y_label_area_size(font_px * 4)
            .build_cartesian_2d(c.0 - half..c.0 + half, c.1 - half..c.1 + half)
            .map_err(drawing)?;
        chart
            .configure_mesh()
            .x_desc(format!("{} [mm]", names[a]))
            .y_desc(format!("{} [mm]", names[b]))
            .label_style((FONT, font_px))
            .light_line_style(RGBColor(238, 238, 238))
            .draw()
            .map_err(drawing)?;
        chart
            .draw_series(LineSeries::new(self.desired.iter().map(proj), BLACK.stroke_width(2)))
            .map_err(drawing)?
            .label("desired")
            .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], BLACK.stroke_width(2)));
        for (i, m) in self.measured.iter().enumerate() {
            let col = color(i);
            chart
                .draw_series(m.iter().map(|p| Circle::new(proj(p), 2, col.filled())))
                .map_err(drawing)?
                .label(format!("run {}: {:.2} mm", i + 1, self.run_means[i] * 1e3))
                .legend(move |(x, y)| Circle::new((x + 8, y), 3, col.filled()));
        }
        crate::legend(&mut chart, font_px, SeriesLabelPosition::UpperRight)?;
        let s_max = self.errors.iter().flatten().map(|e| e.0).fold(1e-6, f64::max);
        let d_max = self.errors.iter().flatten().map(|e| e.1).fold(1e-6, f64::max) * 1e3 * 1.1;
        let mut chart = ChartBuilder::on(&right)
            .caption("distance to the desired path", (FONT, font_px + 2))
            .margin(10)
            .x_label_area_size(font_px * 3)
            .y_label_area_size(font_px * 4)
            .build_cartesian_2d(0.0..s_max * 1e3, 0.0..d_max)
            .map_err(drawing)?;
        chart
            .configure_mesh()
            .x_desc("arc length along the desired path [mm]")
            .y_desc("error [mm]")
            .label_style((FONT, font_px))
            .light_line_style(RGBColor(238, 238, 238))
            .draw()
            .map_err(drawing)?;
        for (i, e) in self.errors.iter().enumerate() {
            let col = color(i);
            chart
                .draw_series(e.iter().map(|&(s, d)| Circle::new((s * 1e3, d * 1e3), 2, col.filled())))
                .map_err(drawing)?;
            let m = self.run_means[i] * 1e3;
            chart
                .draw_series(DashedLineSeries::new([(0.0, m), (s_max * 1e3, m)], 6, 4, col.stroke_width(1)))
                .map_err(drawing)?;
        }
        Ok(())
    }
}
