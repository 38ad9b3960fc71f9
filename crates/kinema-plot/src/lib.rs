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

mod joint;
mod robot;

use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;

pub use joint::JointCurves;
pub use robot::RobotView;

/// What can go wrong while plotting.
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad input (a wrong joint count, an empty trajectory, …).
    #[error("{0}")]
    Kinema(#[from] kinema::Error),
    /// The input cannot be drawn.
    #[error("cannot plot {what}: {message}")]
    Invalid {
        /// What was given.
        what: String,
        /// Why it cannot be drawn.
        message: String,
    },
    /// The drawing backend failed.
    #[error("drawing failed: {0}")]
    Drawing(String),
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
    fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Result<()>;
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
        Err(Error::Drawing("the embedded DejaVu Sans font could not be loaded".into()))
    }
}

pub(crate) fn drawing<E: std::fmt::Debug>(e: E) -> Error {
    Error::Drawing(format!("{e:?}"))
}

/// Renders `plot` at `size` (width, height in pixels) and returns the bytes
/// of the file.
pub fn render(plot: &impl Plot, format: Format, size: (u32, u32)) -> Result<Vec<u8>> {
    if size.0 < 100 || size.1 < 100 || size.0 > 10_000 || size.1 > 10_000 {
        return Err(Error::Invalid {
            what: format!("a {}×{} picture", size.0, size.1),
            message: "width and height must be between 100 and 10000 pixels".into(),
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
