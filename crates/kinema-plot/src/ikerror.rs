//! The IK round-trip error over many cases (seed 004 §V-C, Fig. 6).

use kinema::ik::{round_trip_cases, IiwaIk, IkSolver};
use kinema::Robot;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::{drawing, title_area, Plot, Result, FONT};

/// Errors below this are drawn on it (an exact round trip has error 0).
const FLOOR: f64 = 1e-17;

/// The error of an IK round trip per case — random configuration → FK → IK
/// → the solution nearest to the original, max_i |Δq_i| — on a logarithmic
/// axis, with the largest and the mean error marked. Cases the solver could
/// not solve are counted in the title.
#[derive(Debug, Clone)]
pub struct IkErrorPlot {
    title: String,
    /// Per-case errors \[rad or m\]; `None` where the solver found nothing.
    pub errors: Vec<Option<f64>>,
}

impl IkErrorPlot {
    /// Seed 004's validation of the iiwa's closed form: IK with each case's
    /// own q3 ([`IiwaIk::validation_cases`]). Errors: a robot that is not iiwa-shaped.
    pub fn iiwa(robot: &Robot, cases: usize, seed: u64) -> Result<Self> {
        let ik = IiwaIk::new(robot)?;
        let errors =
            ik.validation_cases(cases, seed).into_iter().map(|c| c.error.is_finite().then_some(c.error)).collect();
        Ok(IkErrorPlot {
            title: format!("{}: IK with the same q3, {cases} random configurations", robot.name()),
            errors,
        })
    }

    /// The round trip of any solver ([`round_trip_cases`]).
    pub fn round_trip(robot: &Robot, solver: &dyn IkSolver, cases: usize, seed: u64) -> Result<Self> {
        let errors = round_trip_cases(robot, solver, cases, seed)?.into_iter().map(|c| c.map(|c| c.error)).collect();
        Ok(IkErrorPlot {
            title: format!("{}: IK round trip ({} solver), {cases} random configurations", robot.name(), solver.name()),
            errors,
        })
    }

    /// The largest and the mean error over the solved cases.
    pub fn max_mean(&self) -> (f64, f64) {
        let solved: Vec<f64> = self.errors.iter().flatten().copied().collect();
        let max = solved.iter().copied().fold(0.0, f64::max);
        (max, if solved.is_empty() { 0.0 } else { solved.iter().sum::<f64>() / solved.len() as f64 })
    }
}

impl Plot for IkErrorPlot {
    fn draw<DB: DrawingBackend<ErrorType: 'static>>(&self, area: &DrawingArea<DB, Shift>) -> Result<()> {
        let unsolved = self.errors.iter().filter(|e| e.is_none()).count();
        let (max, mean) = self.max_mean();
        let mut title = self.title.clone();
        if unsolved > 0 {
            title += &format!(", {unsolved} not solved");
        }
        let body = title_area(area, &title)?;
        let (w, _) = body.dim_in_pixel();
        let font_px = (w / 70).clamp(10, 16);
        let top = 10f64.powf(max.max(FLOOR * 10.0).log10().ceil() + 1.0);
        let n = self.errors.len().max(1) as f64;
        let mut chart = ChartBuilder::on(&body)
            .margin(12)
            .x_label_area_size(font_px * 3)
            .y_label_area_size(font_px * 5)
            .build_cartesian_2d(0.0..n, (FLOOR..top).log_scale())
            .map_err(drawing)?;
        chart
            .configure_mesh()
            .x_desc("case")
            .y_desc("max |Δq| [rad]")
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style((FONT, font_px))
            .light_line_style(RGBColor(238, 238, 238))
            .draw()
            .map_err(drawing)?;
        chart
            .draw_series(self.errors.iter().enumerate().filter_map(|(i, e)| {
                e.map(|e| Circle::new((i as f64, e.max(FLOOR)), 2, RGBColor(31, 119, 180).filled()))
            }))
            .map_err(drawing)?
            .label("one case (0 drawn at 1e-17)")
            .legend(|(x, y)| Circle::new((x + 8, y), 3, RGBColor(31, 119, 180).filled()));
        for (v, name, c) in [(max, "max", RGBColor(214, 39, 40)), (mean, "mean", RGBColor(44, 160, 44))] {
            chart
                .draw_series(LineSeries::new([(0.0, v.max(FLOOR)), (n, v.max(FLOOR))], c.stroke_width(2)))
                .map_err(drawing)?
                .label(format!("{name} {v:.2e}"))
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], c.stroke_width(2)));
        }
        crate::legend(&mut chart, font_px, SeriesLabelPosition::UpperRight)?;
        Ok(())
    }
}
