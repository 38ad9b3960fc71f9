//! # kinema-plot — pictures of robots and their motions
//!
//! Every picture is a [`Plot`]: something that draws itself on a `plotters`
//! drawing area. [`render`] turns a plot into the bytes of an SVG or a PNG
//! file (the caller writes them). Text is drawn with DejaVu Sans, embedded in
//! the binary (the `dejavu` crate) and registered with `plotters`' own
//! `ab_glyph` renderer, so PNG text never depends on the fonts of the machine;
//! SVG text names the family `DejaVu Sans, sans-serif` for the viewer.
//!
//! * [`RobotView`] — a robot at a configuration, side view (x–z) and top view
//!   (x–y) side by side, as seed 000 Fig. 2: links between the joint frames,
//!   joints, the base and the tool frame's axes.
//! * [`JointCurves`] — joint positions, velocities and accelerations against
//!   time with the joint limits drawn (seed 001 Fig. 8, seed 004 Fig. 20–33).
//!
//! ## Example
//!
//! ```
//! let robot = kinema::Robot::builtin("scorbot-er-v-plus")?;
//! let view = kinema_plot::RobotView::new(&robot, robot.home())?;
//! let svg = kinema_plot::render(&view, kinema_plot::Format::Svg, (900, 450))?;
//! assert!(String::from_utf8(svg).unwrap().contains("<svg"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

mod curves;
mod ikerror;
mod joint;
mod robot;
mod scene;
mod tracking;
mod workspace;

use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;

pub use curves::{CartesianCurves, ManipulabilityCurve};
pub use ikerror::IkErrorPlot;
pub use joint::JointCurves;
pub use robot::RobotView;
pub use scene::{EllipsoidView, Robot3d, SelfMotionView, ToolPath3d};
pub use tracking::TrackingPlot;
pub use workspace::{Section, WorkspaceCloud, WorkspaceOptions};

/// What can go wrong while plotting.
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad input (a wrong joint count, an empty trajectory, …).
    #[error("{0}")]
    Kinema(#[from] kinema::Error),
    /// Too few items to draw: a trajectory of one sample, no measured run,
    /// too few self-motion steps.
    #[error("cannot plot `{what}`: it has {got} {of}; at least {min} needed")]
    TooFew {
        /// Which input.
        what: String,
        /// How many it has.
        got: usize,
        /// How many it needs at least.
        min: usize,
        /// What is counted (e.g. "samples", "points").
        of: String,
    },
    /// A list with the wrong number of values (a trajectory for another robot).
    #[error("cannot plot `{what}`: it has {got} {of}; {expected} expected")]
    WrongLength {
        /// Which input.
        what: String,
        /// How many it has.
        got: usize,
        /// How many it needs.
        expected: usize,
        /// What is counted (e.g. "joints").
        of: String,
    },
    /// A number outside the range its argument accepts (a picture size, a
    /// grid size).
    #[error("cannot plot: invalid `{what}`: {value}; expected {expected}")]
    OutOfRange {
        /// Which argument.
        what: String,
        /// The offending value.
        value: f64,
        /// The accepted range, in words.
        expected: String,
    },
    /// A valid input that this plot cannot show (a robot without a
    /// closed-form self-motion).
    #[error("cannot plot `{what}`: {reason}")]
    DoesNotFit {
        /// Which input.
        what: String,
        /// Why it cannot be drawn, and what would.
        reason: String,
    },
    /// The embedded font could not be registered with the drawing library.
    #[error("drawing failed: the embedded DejaVu Sans font could not be loaded")]
    Font,
    /// The drawing backend failed; its error (an I/O error for SVG, a
    /// bitmap error for PNG) is the source.
    #[error("drawing failed: {0}")]
    Drawing(#[source] Box<dyn std::error::Error + Send + Sync>),
}

/// Result with [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

/// Output file formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Scalable vector graphics (text as `<text>` elements).
    Svg,
    /// A PNG image (text rasterised from the embedded font).
    Png,
}

impl Format {
    /// The format of a file name by its extension (`.svg`, `.png`, any case).
    pub fn from_path(path: &std::path::Path) -> Option<Format> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "svg" => Some(Format::Svg),
            "png" => Some(Format::Png),
            _ => None,
        }
    }
}

/// A picture.
pub trait Plot {
    /// Draws the picture on `area` (already cleared to white).
    fn draw<DB: DrawingBackend<ErrorType: 'static>>(&self, area: &DrawingArea<DB, Shift>) -> Result<()>;
}

/// The font family every plot uses.
pub(crate) const FONT: &str = "DejaVu Sans";

/// Registers the embedded font with `plotters` (once per process).
fn register_font() -> Result<()> {
    static DONE: OnceLock<bool> = OnceLock::new();
    let ok = *DONE.get_or_init(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular()).is_ok()
            && plotters::style::register_font(FONT, FontStyle::Bold, dejavu::sans::bold()).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(Error::Font)
    }
}

/// Draws `title` in a band at the top of `area` and returns the rest.
pub(crate) fn title_area<DB: DrawingBackend<ErrorType: 'static>>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
) -> Result<DrawingArea<DB, Shift>> {
    let (_, h) = area.dim_in_pixel();
    let title_h = (h / 14).clamp(24, 50);
    let (top, body) = area.split_vertically(title_h);
    top.titled(title, (FONT, (title_h as f64 * 0.55) as u32)).map_err(drawing)?;
    Ok(body)
}

/// A tick label: at most three decimals, no trailing zeros, no "-0".
pub(crate) fn tidy(v: &f64) -> String {
    let s = format!("{v:.3}");
    let s = if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.') } else { &s };
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

/// Draws the legend of `chart`'s labelled series at `pos`.
pub(crate) fn legend<'a, DB: DrawingBackend<ErrorType: 'static> + 'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    font_px: u32,
    pos: SeriesLabelPosition,
) -> Result<()> {
    chart
        .configure_series_labels()
        .label_font((FONT, font_px))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.3))
        .position(pos)
        .draw()
        .map_err(drawing)
}

/// Checks that `traj` is a trajectory of `robot` with at least `min` samples.
pub(crate) fn check_traj(robot: &kinema::Robot, traj: &kinema::traj::JointTrajectory, min: usize) -> Result<()> {
    if traj.dof() != robot.dof() {
        return Err(Error::WrongLength {
            what: "trajectory".into(),
            got: traj.dof(),
            expected: robot.dof(),
            of: format!("joints (as many as `{}` has)", robot.name()),
        });
    }
    if traj.len() < min {
        return Err(Error::TooFew { what: "trajectory".into(), got: traj.len(), min, of: "samples".into() });
    }
    Ok(())
}

/// The colour of series `i` (joint `i + 1`, measured set `i + 1`, …).
pub(crate) fn color(i: usize) -> RGBColor {
    const C: [RGBColor; 8] = [
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(127, 127, 127),
    ];
    C[i % C.len()]
}

pub(crate) fn drawing<E: std::error::Error + Send + Sync + 'static>(e: E) -> Error {
    Error::Drawing(Box::new(e))
}

/// Renders `plot` at `size` (width, height in pixels) and returns the bytes
/// of the file.
pub fn render(plot: &impl Plot, format: Format, size: (u32, u32)) -> Result<Vec<u8>> {
    if size.0 < 100 || size.1 < 100 || size.0 > 10_000 || size.1 > 10_000 {
        let (what, value) = if (100..=10_000).contains(&size.0) { ("height", size.1) } else { ("width", size.0) };
        return Err(Error::OutOfRange {
            what: what.into(),
            value: value.into(),
            expected: "100 to 10000 pixels".into(),
        });
    }
    register_font()?;
    match format {
        Format::Svg => {
            let mut text = String::new();
            {
                let area = SVGBackend::with_string(&mut text, size).into_drawing_area();
                area.fill(&WHITE).map_err(drawing)?;
                plot.draw(&area)?;
                area.present().map_err(drawing)?;
            }
            // Let viewers without DejaVu fall back to their sans-serif.
            Ok(text.replace("font-family=\"DejaVu Sans\"", "font-family=\"DejaVu Sans, sans-serif\"").into_bytes())
        }
        Format::Png => {
            let (w, h) = size;
            let mut rgb = vec![0u8; (w * h * 3) as usize];
            {
                let area = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
                area.fill(&WHITE).map_err(drawing)?;
                plot.draw(&area)?;
                area.present().map_err(drawing)?;
            }
            let mut png = Vec::new();
            image::codecs::png::PngEncoder::new(&mut png)
                .write_image(&rgb, w, h, image::ColorType::Rgb8)
                .map_err(drawing)?;
            Ok(png)
        }
    }
}

use image::ImageEncoder;
