//! The workspace from sampled forward kinematics (seed 000 Fig. 2, seed 004
//! Fig. 4, seed 003 Fig. 3).

use kinema::nalgebra::Vector3;
use kinema::{JointType, Robot};
use plotters::coord::Shift;
use plotters::prelude::*;
use rand::SeedableRng;

use crate::{drawing, tidy, title_area, Error, Plot, Result, FONT};

/// The side panel of a [`WorkspaceCloud`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Section {
    /// Horizontal distance from the vertical through the base origin against
    /// height (r–z): the section of a workspace swept by a base joint about
    /// the vertical (seed 000 Fig. 2).
    Radial,
    /// The projection on the world x–z plane (for robots whose first joint is
    /// not a rotation about the vertical, e.g. a rail).
    Xz,
}

/// How a workspace is sampled.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorkspaceOptions {
    /// Number of random configurations, uniform over the joint ranges
    /// (unbounded joints over one turn or ±1 m).
    pub samples: usize,
    /// Seed of the random generator: the same seed gives the same picture.
    pub seed: u64,
    /// The side panel; `None` chooses [`Section::Radial`] when joint 1 is
    /// revolute and [`Section::Xz`] otherwise.
    pub section: Option<Section>,
    /// Cells per side of the grid whose occupied cells' outline is the drawn
    /// boundary.
    pub grid: usize,
}

impl Default for WorkspaceOptions {
    fn default() -> Self {
        WorkspaceOptions { samples: 200_000, seed: 1, section: None, grid: 120 }
    }
}

/// Most points drawn per panel (the boundary uses all of them).
const DRAWN: usize = 20_000;

/// The tool positions of many random configurations, drawn as a side
/// section and a top view: a point cloud (at most 20 000 points drawn per
/// panel) and its boundary, the outline of the cells of a grid that hold at
/// least one sample (holes included), so the boundary is exact to one cell.
#[derive(Debug, Clone)]
pub struct WorkspaceCloud {
    name: String,
    section: Section,
    /// Tool positions in world coordinates \[m\].
    points: Vec<Vector3<f64>>,
    /// The base origin in world coordinates \[m\].
    base: Vector3<f64>,
    grid: usize,
}

impl WorkspaceCloud {
    /// Samples the workspace of `robot`; `progress` is called with the number
    /// of samples done so far (every 10 000 and at the end). Errors: no
    /// samples, a grid under 10 or over 1000 cells.
    pub fn sample(robot: &Robot, opts: &WorkspaceOptions, mut progress: impl FnMut(usize)) -> Result<Self> {
        if opts.samples == 0 {
            return Err(Error::TooFew { what: "workspace".into(), got: 0, min: 1, of: "samples".into() });
        }
        if !(10..=1000).contains(&opts.grid) {
            return Err(Error::OutOfRange {
                what: "grid".into(),
                value: opts.grid as f64,
                expected: "10 to 1000 cells".into(),
            });
        }
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(opts.seed);
        let mut q = vec![0.0; robot.dof()];
        let mut points = Vec::with_capacity(opts.samples);
        while points.len() < opts.samples {
            let chunk = (opts.samples - points.len()).min(10_000);
            for _ in 0..chunk {
                robot.random_q_into(&mut rng, &mut q);
                points.push(robot.fk(&q)?.world_from_tool.pos);
            }
            progress(points.len());
        }
        let section = opts.section.unwrap_or(match robot.joints()[0].kind {
            JointType::Revolute => Section::Radial,
            JointType::Prismatic => Section::Xz,
        });
        Ok(WorkspaceCloud { name: robot.name().to_string(), section, points, base: robot.base().pos, grid: opts.grid })
    }

    /// The sampled tool positions in world coordinates \[m\].
    pub fn points(&self) -> &[Vector3<f64>] {
        &self.points
    }

    /// The 2-D points of a panel: 0 = side section, 1 = top view.
    fn panel_points(&self, panel: usize) -> Vec<(f64, f64)> {
        self.points.iter().map(|p| self.project(panel, p)).collect()
    }

    fn project(&self, panel: usize, p: &Vector3<f64>) -> (f64, f64) {
        match (panel, self.section) {
            (0, Section::Radial) => ((p.x - self.base.x).hypot(p.y - self.base.y), p.z),
            (0, Section::Xz) => (p.x, p.z),
            _ => (p.x, p.y),
        }
    }

    /// The outline of the occupied cells of a `grid`² raster over `window`
    /// as segments between cell corners.
    pub(crate) fn boundary(pts: &[(f64, f64)], window: ((f64, f64), (f64, f64)), grid: usize) -> Vec<[(f64, f64); 2]> {
        let ((x0, x1), (y0, y1)) = window;
        let (cw, ch) = ((x1 - x0) / grid as f64, (y1 - y0) / grid as f64);
        let mut occ = vec![false; grid * grid];
        for &(x, y) in pts {
            let i = (((x - x0) / cw) as usize).min(grid - 1);
            let j = (((y - y0) / ch) as usize).min(grid - 1);
            occ[j * grid + i] = true;
        }
        // Close gaps of sparse sampling (a dilation then an erosion by one
        // cell, 8-neighbourhood): holes and notches up to two cells wide go,
        // real holes (a SCARA's inner circle) stay.
        let occ = erode(&dilate(&occ, grid), grid);
        let at = |i: isize, j: isize| {
            i >= 0 && j >= 0 && (i as usize) < grid && (j as usize) < grid && occ[j as usize * grid + i as usize]
        };
        let corner = |i: usize, j: usize| (x0 + i as f64 * cw, y0 + j as f64 * ch);
        let mut segs = Vec::new();
        for j in 0..grid {
            for i in 0..grid {
                if !occ[j * grid + i] {
                    continue;
                }
                let (ii, jj) = (i as isize, j as isize);
                if !at(ii - 1, jj) {
                    segs.push([corner(i, j), corner(i, j + 1)]);
                }
                if !at(ii + 1, jj) {
                    segs.push([corner(i + 1, j), corner(i + 1, j + 1)]);
                }
                if !at(ii, jj - 1) {
                    segs.push([corner(i, j), corner(i + 1, j)]);
                }
                if !at(ii, jj + 1) {
                    segs.push([corner(i, j + 1), corner(i + 1, j + 1)]);
                }
            }
        }
        segs
    }
}

/// Cells with an occupied cell among their 8 neighbours or themselves.
fn dilate(occ: &[bool], grid: usize) -> Vec<bool> {
    morph(occ, grid, true)
}

/// Cells whose 8 neighbours and themselves are all occupied (outside the
/// grid counts as occupied, so the data's edge is kept).
fn erode(occ: &[bool], grid: usize) -> Vec<bool> {
    morph(occ, grid, false)
}

fn morph(occ: &[bool], grid: usize, any: bool) -> Vec<bool> {
    let g = grid as isize;
    (0..grid * grid)
        .map(|k| {
            let (i, j) = ((k % grid) as isize, (k / grid) as isize);
            let mut cells = (-1..=1).flat_map(|dj| (-1..=1).map(move |di| (i + di, j + dj))).map(|(a, b)| {
                if a < 0 || b < 0 || a >= g || b >= g {
                    !any
                } else {
                    occ[(b * g + a) as usize]
                }
            });
            if any {
                cells.any(|c| c)
            } else {
                cells.all(|c| c)
            }
        })
        .collect()
}

/// The bounding box ((x0, x1), (y0, y1)) of `pts`.
fn bbox(pts: &[(f64, f64)]) -> ((f64, f64), (f64, f64)) {
    let (mut lo, mut hi) = ((f64::INFINITY, f64::INFINITY), (f64::NEG_INFINITY, f64::NEG_INFINITY));
    for &(x, y) in pts {
        lo = (lo.0.min(x), lo.1.min(y));
        hi = (hi.0.max(x), hi.1.max(y));
    }
    ((lo.0, hi.0), (lo.1, hi.1))
}

/// A window with equal scales on both axes around `pts`, padded.
fn window(pts: &[(f64, f64)], aspect: f64) -> ((f64, f64), (f64, f64)) {
    let ((x0, x1), (y0, y1)) = bbox(pts);
    let (lo, hi) = ((x0, y0), (x1, y1));
    let (cx, cy) = (0.5 * (lo.0 + hi.0), 0.5 * (lo.1 + hi.1));
    let (mut hw, mut hh) = ((0.5 * (hi.0 - lo.0)).max(0.01) * 1.08, (0.5 * (hi.1 - lo.1)).max(0.01) * 1.08);
    // Equal scales: widen the narrower extent to the panel's aspect.
    if hw / hh < aspect {
        hw = hh * aspect;
    } else {
        hh = hw / aspect;
    }
    ((cx - hw, cx + hw), (cy - hh, cy + hh))
}

impl Plot for WorkspaceCloud {
    fn draw<DB: DrawingBackend<ErrorType: 'static>>(&self, area: &DrawingArea<DB, Shift>) -> Result<()> {
        let title = format!("{}: workspace of the tool ({} samples)", self.name, self.points.len());
        let body = title_area(area, &title)?;
        let (w, _) = body.dim_in_pixel();
        let font_px = (w / 70).clamp(10, 16);
        let side = match self.section {
            Section::Radial => ("side section (r–z)", "r, distance from the base axis [m]", "z [m]"),
            Section::Xz => ("side view (x–z)", "x [m]", "z [m]"),
        };
        let captions = [side, ("top view (x–y)", "x [m]", "y [m]")];
        for (p, (panel, (caption, xd, yd))) in body.split_evenly((1, 2)).iter().zip(captions).enumerate() {
            let pts = self.panel_points(p);
            let (pw, ph) = panel.dim_in_pixel();
            let aspect = (pw as f64 - font_px as f64 * 4.0) / (ph as f64 - font_px as f64 * 5.0).max(1.0);
            let win = window(&pts, aspect.max(0.2));
            let mut chart = ChartBuilder::on(panel)
                .caption(caption, (FONT, font_px + 2))
                .margin(10)
                .x_label_area_size(font_px * 3)
                .y_label_area_size(font_px * 4)
                .build_cartesian_2d(win.0 .0..win.0 .1, win.1 .0..win.1 .1)
                .map_err(drawing)?;
            chart
                .configure_mesh()
                .x_desc(xd)
                .y_desc(yd)
                .x_label_formatter(&tidy)
                .y_label_formatter(&tidy)
                .label_style((FONT, font_px))
                .light_line_style(RGBColor(238, 238, 238))
                .draw()
                .map_err(drawing)?;
            let step = pts.len().div_ceil(DRAWN);
            chart
                .draw_series(pts.iter().step_by(step).map(|&p| Pixel::new(p, RGBColor(31, 119, 180).mix(0.6))))
                .map_err(drawing)?;
            // The boundary's grid covers the data, not the padded window.
            let segs = WorkspaceCloud::boundary(&pts, bbox(&pts), self.grid);
            chart
                .draw_series(segs.iter().map(|s| PathElement::new(s.to_vec(), BLACK.stroke_width(1))))
                .map_err(drawing)?;
            // The base.
            chart
                .draw_series([Circle::new(self.project(p, &self.base), 4, RGBColor(214, 39, 40).filled())])
                .map_err(drawing)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn boundary_of_a_square_block_is_its_perimeter() {
        // Points filling [0.2, 0.6]² on a 10-cell grid over [0, 1]²: 4×4 cells,
        // perimeter of 16 unit edges.
        let pts: Vec<(f64, f64)> = (0..40)
            .flat_map(|i| (0..40).map(move |j| (0.2 + 0.39 * i as f64 / 39.0, 0.2 + 0.39 * j as f64 / 39.0)))
            .collect();
        let segs = WorkspaceCloud::boundary(&pts, ((0.0, 1.0), (0.0, 1.0)), 10);
        assert_eq!(segs.len(), 16);
        let len: f64 = segs.iter().map(|s| (s[1].0 - s[0].0).hypot(s[1].1 - s[0].1)).sum();
        assert!((len - 1.6).abs() < 1e-12);
    }

    #[test]
    fn closing_fills_sampling_gaps_and_keeps_real_holes() {
        // An annulus 0.2 ≤ r ≤ 0.45 about (0.5, 0.5) on a 50-cell grid, sampled
        // densely but with a one-cell gap at r = 0.3: the gap closes, the inner
        // hole stays, so the outline is two circles of about 2π·0.45 + 2π·0.2.
        let mut pts = Vec::new();
        for i in 0..400 {
            for j in 0..400 {
                let (x, y) = (i as f64 / 399.0, j as f64 / 399.0);
                let r = (x - 0.5).hypot(y - 0.5);
                if (0.2..=0.45).contains(&r) && !(0.295..0.305).contains(&r) {
                    pts.push((x, y));
                }
            }
        }
        let segs = WorkspaceCloud::boundary(&pts, ((0.0, 1.0), (0.0, 1.0)), 50);
        let len: f64 = segs.iter().map(|s| (s[1].0 - s[0].0).hypot(s[1].1 - s[0].1)).sum();
        // A staircase outline of a circle is 4/π times its length.
        let expected = 4.0 / std::f64::consts::PI * 2.0 * std::f64::consts::PI * (0.45 + 0.2);
        assert!((len - expected).abs() < 0.12 * expected, "{len} vs {expected}");
    }
}
