//! Oblique 3D views: the robot with its link frames (seed 004 Fig. 5), the
//! tool path, manipulability ellipsoids (Fig. 9–13) and the self-motion
//! (Fig. 7).

use kinema::analysis::{ellipsoid, Axes, Ellipsoid};
use kinema::nalgebra::{Matrix3, Vector3};
use kinema::traj::JointTrajectory;
use kinema::{Frame, Pose, Robot};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::{color, drawing, tidy, title_area, Error, Plot, Result, FONT};

/// The colour of links in 3D views (grey, so that blue z axes stand out).
const LINK: RGBColor = RGBColor(70, 70, 80);

/// A polyline in world coordinates.
#[derive(Debug, Clone)]
struct Line3 {
    pts: Vec<Vector3<f64>>,
    color: RGBColor,
    alpha: f64,
    width: u32,
}

/// What one 3D panel shows.
#[derive(Debug, Clone, Default)]
struct Scene {
    caption: String,
    lines: Vec<Line3>,
    dots: Vec<(Vector3<f64>, RGBColor, u32)>,
    labels: Vec<(Vector3<f64>, String)>,
    legend: Vec<(String, RGBColor)>,
    /// Whether the scene is in metres about the robot base (else unit-free).
    axis_names: [&'static str; 3],
}

impl Scene {
    fn new(caption: impl Into<String>) -> Self {
        Scene { caption: caption.into(), axis_names: ["x [m]", "y [m]", "z [m]"], ..Default::default() }
    }

    fn line(&mut self, pts: Vec<Vector3<f64>>, color: RGBColor, alpha: f64, width: u32) {
        self.lines.push(Line3 { pts, color, alpha, width });
    }

    /// The robot's links (joint frame origins joined), joints, base and, if
    /// `frames` is set, the axes of every link frame (`axis` long).
    fn robot(&mut self, frames: &[Pose], link: RGBColor, alpha: f64, axis: Option<f64>) {
        self.line(frames.iter().map(|f| f.pos).collect(), link, alpha, if alpha < 1.0 { 2 } else { 4 });
        let n = frames.len();
        if alpha >= 1.0 {
            for f in &frames[1..n - 1] {
                self.dots.push((f.pos, RGBColor(230, 140, 20), 4));
            }
            self.dots.push((frames[0].pos, BLACK, 5));
        }
        if let Some(len) = axis {
            for f in frames {
                for (k, c) in [RED, GREEN, BLUE].into_iter().enumerate() {
                    self.line(vec![f.pos, f.pos + f.rot.column(k) * len], c, 1.0, 1);
                }
            }
        }
    }

    /// The wireframe of an ellipsoid centred at `c`: 12 meridians, 7
    /// parallels and the three principal axes, radii scaled by `scale`.
    fn ellipsoid(&mut self, c: Vector3<f64>, e: &Ellipsoid, scale: f64, color: RGBColor) {
        let m: Matrix3<f64> = e.axes * Matrix3::from_diagonal(&(e.radii * scale));
        let at = |u: f64, v: f64| c + m * Vector3::new(u.cos() * v.sin(), u.sin() * v.sin(), v.cos());
        let pi = std::f64::consts::PI;
        for i in 0..12 {
            let u = 2.0 * pi * i as f64 / 12.0;
            self.line((0..=48).map(|k| at(u, pi * k as f64 / 48.0)).collect(), color, 0.5, 1);
        }
        for i in 1..8 {
            let v = pi * i as f64 / 8.0;
            self.line((0..=96).map(|k| at(2.0 * pi * k as f64 / 96.0, v)).collect(), color, 0.5, 1);
        }
        for k in 0..3 {
            let a = m.column(k).into_owned();
            self.line(vec![c - a, c + a], color, 1.0, 2);
        }
    }

    /// A cube (centre, half-width) holding every point.
    fn bounds(&self) -> (Vector3<f64>, f64) {
        let mut lo = Vector3::repeat(f64::INFINITY);
        let mut hi = Vector3::repeat(f64::NEG_INFINITY);
        let all = self.lines.iter().flat_map(|l| l.pts.iter()).chain(self.dots.iter().map(|d| &d.0));
        for p in all.chain(self.labels.iter().map(|l| &l.0)) {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        if !lo.x.is_finite() {
            return (Vector3::zeros(), 1.0);
        }
        let half = (0.5 * (hi - lo).max()).max(0.05) * 1.1;
        (0.5 * (lo + hi), half)
    }

    fn draw<DB: DrawingBackend<ErrorType: 'static>>(&self, area: &DrawingArea<DB, Shift>) -> Result<()> {
        let (w, _) = area.dim_in_pixel();
        let font_px = (w / 45).clamp(10, 16);
        let (c, half) = self.bounds();
        // plotters' 3D charts have y up: world (x, y, z) is drawn at (x, z, −y)
        // so that the view is right-handed with z up.
        let map = |p: &Vector3<f64>| (p.x, p.z, -p.y);
        let mut chart = ChartBuilder::on(area)
            .caption(&self.caption, (FONT, font_px + 2))
            .margin(8)
            .build_cartesian_3d(c.x - half..c.x + half, c.z - half..c.z + half, -c.y - half..-c.y + half)
            .map_err(drawing)?;
        chart.with_projection(|mut p| {
            p.yaw = 0.6;
            p.pitch = 0.35;
            p.scale = 0.85;
            p.into_matrix()
        });
        let neg = |v: &f64| tidy(&-v);
        chart
            .configure_axes()
            .x_formatter(&tidy)
            .y_formatter(&tidy)
            .z_formatter(&neg)
            .x_labels(6)
            .y_labels(6)
            .z_labels(6)
            .label_style((FONT, font_px.saturating_sub(3).max(9)))
            .light_grid_style(BLACK.mix(0.08))
            .max_light_lines(4)
            .draw()
            .map_err(drawing)?;
        // Axis names at the ends of the chart's axes.
        // Names beside the middle of the labelled edges (x along the front
        // left edge, y along the front right edge in this projection).
        let names = [
            (Vector3::new(c.x, c.y - half * 1.45, c.z - half), self.axis_names[0]),
            (Vector3::new(c.x + half * 1.4, c.y, c.z - half), self.axis_names[1]),
            (Vector3::new(c.x - half, c.y + half, c.z + half * 1.05), self.axis_names[2]),
        ];
        chart
            .draw_series(names.iter().map(|(p, s)| Text::new(s.to_string(), map(p), (FONT, font_px).into_font())))
            .map_err(drawing)?;
        for l in &self.lines {
            chart
                .draw_series(LineSeries::new(l.pts.iter().map(map), l.color.mix(l.alpha).stroke_width(l.width)))
                .map_err(drawing)?;
        }
        chart.draw_series(self.dots.iter().map(|(p, c, r)| Circle::new(map(p), *r, c.filled()))).map_err(drawing)?;
        chart
            .draw_series(
                self.labels
                    .iter()
                    .map(|(p, s)| Text::new(s.clone(), map(p), (FONT, font_px).into_font().color(&BLACK))),
            )
            .map_err(drawing)?;
        // The legend, as text in the bottom left corner.
        let (_, h) = area.dim_in_pixel();
        let rows = self.legend.len() as i32;
        for (i, (text, c)) in self.legend.iter().enumerate() {
            let y = h as i32 - 12 - (font_px as i32 + 6) * (rows - i as i32);
            area.draw(&PathElement::new([(10, y), (28, y)], c.stroke_width(3))).map_err(drawing)?;
            area.draw(&Text::new(text.clone(), (34, y - font_px as i32 / 2), (FONT, font_px))).map_err(drawing)?;
        }
        Ok(())
    }
}

/// Draws `scenes` side by side under a title.
fn draw_panels<DB: DrawingBackend<ErrorType: 'static>>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    scenes: &[Scene],
) -> Result<()> {
    let body = title_area(area, title)?;
    for (panel, s) in body.split_evenly((1, scenes.len())).iter().zip(scenes) {
        s.draw(panel)?;
    }
    Ok(())
}

/// The largest distance of a frame origin from the base \[m\] (at least 0.1).
fn size(frames: &[Pose]) -> f64 {
    frames.iter().map(|f| (f.pos - frames[0].pos).norm()).fold(0.1, f64::max)
}

/// The length of the frame axes drawn for a robot whose frames are `frames`.
fn axis_length(frames: &[Pose]) -> f64 {
    0.08 * size(frames)
}

/// A robot at one configuration in an oblique 3D view with the axes of every
/// link frame (x red, y green, z blue), as seed 004 Fig. 5.
#[derive(Debug, Clone)]
pub struct Robot3d {
    title: String,
    scene: Scene,
}

impl Robot3d {
    /// The view of `robot` at `q` (rad and m). Errors: a wrong joint count or non-finite values.
    pub fn new(robot: &Robot, q: &[f64]) -> Result<Self> {
        let frames = robot.link_frames(q)?;
        let mut scene = Scene::new("");
        scene.robot(&frames, LINK, 1.0, Some(axis_length(&frames)));
        // Frame numbers; frames at one point share a label ("3,4").
        let mut labels: Vec<(Vector3<f64>, String)> = Vec::new();
        for (i, f) in frames.iter().enumerate().skip(1).take(robot.dof()) {
            match labels.iter_mut().find(|(p, _)| (p - f.pos).norm() < 1e-9) {
                Some((_, s)) => *s += &format!(",{i}"),
                None => labels.push((f.pos, format!("  {i}"))),
            }
        }
        scene.labels = labels;
        scene.legend = vec![("x axes".into(), RED), ("y axes".into(), GREEN), ("z axes".into(), BLUE)];
        Ok(Robot3d { title: format!("{}: link frames", robot.name()), scene })
    }
}

impl Plot for Robot3d {
    fn draw<DB: DrawingBackend<ErrorType: 'static>>(&self, area: &DrawingArea<DB, Shift>) -> Result<()> {
        draw_panels(area, &self.title, std::slice::from_ref(&self.scene))
    }
}

/// The tool path of a joint trajectory in 3D, with the robot drawn faintly at
/// the first sample and fully at the last.
#[derive(Debug, Clone)]
pub struct ToolPath3d {
    title: String,
    scene: Scene,
}

impl ToolPath3d {
    /// The path of `traj` (a trajectory of `robot`). Errors: a joint count
    /// other than the robot's, an empty trajectory.
    pub fn new(robot: &Robot, traj: &JointTrajectory) -> Result<Self> {
        crate::check_traj(robot, traj, 1)?;
        let path: Vec<Vector3<f64>> = kinema::traj::to_joints::poses(robot, traj)?.iter().map(|p| p.pos).collect();
        let first = robot.link_frames(traj.q(0))?;
        let last = robot.link_frames(traj.q(traj.len() - 1))?;
        let mut scene = Scene::new("");
        scene.robot(&first, LINK, 0.3, None);
        scene.robot(&last, LINK, 1.0, None);
        scene.line(path.clone(), RGBColor(214, 39, 40), 1.0, 2);
        scene.dots.push((path[0], RGBColor(44, 160, 44), 5));
        scene.dots.push((path[path.len() - 1], RGBColor(214, 39, 40), 5));
        scene.legend = vec![
            ("tool path".into(), RGBColor(214, 39, 40)),
            ("start".into(), RGBColor(44, 160, 44)),
            ("robot at the end (faint: at the start)".into(), LINK),
        ];
        let duration = traj.times()[traj.len() - 1] - traj.times()[0];
        Ok(ToolPath3d {
            title: format!("{}: tool path ({} samples, {duration:.3} s)", robot.name(), traj.len()),
            scene,
        })
    }
}

impl Plot for ToolPath3d {
    fn draw<DB: DrawingBackend<ErrorType: 'static>>(&self, area: &DrawingArea<DB, Shift>) -> Result<()> {
        draw_panels(area, &self.title, std::slice::from_ref(&self.scene))
    }
}

/// The manipulability ellipsoids at the tool (seed 004 eq. 15, Fig. 9–13):
/// the translational one drawn at the tool over the robot (scaled so its
/// largest radius is a quarter of the robot's size; the scale is printed),
/// and the rotational one on its own axes in rad/s.
#[derive(Debug, Clone)]
pub struct EllipsoidView {
    title: String,
    scenes: [Scene; 2],
    /// The translational and rotational ellipsoids.
    pub ellipsoids: [Ellipsoid; 2],
}

impl EllipsoidView {
    /// The ellipsoids of `robot` at `q`. Errors: a wrong joint count or non-finite values.
    pub fn new(robot: &Robot, q: &[f64]) -> Result<Self> {
        let frames = robot.link_frames(q)?;
        let j = robot.jacobian(q, Frame::Base)?;
        let trans = ellipsoid(&j, Axes::Translation)?;
        let rot = ellipsoid(&j, Axes::Rotation)?;
        let tool = frames[frames.len() - 1].pos;
        let scale = if trans.radii[0] > 0.0 { 0.25 * size(&frames) / trans.radii[0] } else { 1.0 };
        let mut left = Scene::new(format!("translation, drawn at {scale:.3} m per m/s"));
        left.robot(&frames, LINK, 1.0, None);
        left.ellipsoid(tool, &trans, scale, RGBColor(214, 39, 40));
        left.legend = vec![(
            format!("radii {:.3}, {:.3}, {:.3} m/s per rad/s", trans.radii[0], trans.radii[1], trans.radii[2]),
            RGBColor(214, 39, 40),
        )];
        let mut right = Scene::new("rotation at the tool");
        right.axis_names = ["ωx", "ωy", "ωz"];
        right.ellipsoid(Vector3::zeros(), &rot, 1.0, RGBColor(148, 103, 189));
        right.legend = vec![(
            format!("radii {:.3}, {:.3}, {:.3} rad/s per rad/s", rot.radii[0], rot.radii[1], rot.radii[2]),
            RGBColor(148, 103, 189),
        )];
        Ok(EllipsoidView {
            title: format!("{}: manipulability ellipsoids", robot.name()),
            scenes: [left, right],
            ellipsoids: [trans, rot],
        })
    }
}

impl Plot for EllipsoidView {
    fn draw<DB: DrawingBackend<ErrorType: 'static>>(&self, area: &DrawingArea<DB, Shift>) -> Result<()> {
        draw_panels(area, &self.title, &self.scenes)
    }
}

/// The self-motion of a 7-joint iiwa-shaped arm through a configuration
/// (seed 004 §V-D, Fig. 7): the arm at `q`, faint arms at eight other arm
/// angles, and the circle of the elbow (green where every joint is within its
/// limits, red where one is not); beside it the joint values against ψ.
#[derive(Debug, Clone)]
pub struct SelfMotionView {
    title: String,
    scene: Scene,
    psi: Vec<f64>,
    q: Vec<Vec<f64>>,
    names: Vec<String>,
    limits: Vec<(f64, f64)>,
}

impl SelfMotionView {
    /// The self-motion through `q` with `steps` samples of ψ (at least 8).
    /// Errors: a robot without an arm angle (any description of an iiwa-type arm has one), a wrong joint count, too few steps.
    pub fn new(robot: &Robot, q: &[f64], steps: usize) -> Result<Self> {
        if steps < 8 {
            return Err(Error::TooFew { what: "self-motion".into(), got: steps, min: 8, of: "steps".into() });
        }
        let family = kinema::ik::registry::fit(robot);
        let Some(redundancy) = family.as_deref().and_then(|f| f.redundancy()) else {
            return Err(Error::DoesNotFit {
                what: "robot".into(),
                reason: format!(
                    "`{}` has no self-motion with a closed form (an arm of the iiwa's structure has one)",
                    robot.name()
                ),
            });
        };
        let samples = kinema::ik::family::self_motion(robot, redundancy, q, steps)?;
        let mut scene = Scene::new("");
        for k in 1..8 {
            let s = &samples[k * steps / 8];
            scene.robot(&robot.link_frames(&s.q)?, RGBColor(120, 120, 120), 0.35, None);
        }
        scene.robot(&robot.link_frames(q)?, LINK, 1.0, None);
        // The elbow circle, split into runs of equal feasibility.
        let mut run: Vec<Vector3<f64>> = Vec::new();
        let mut ok = samples[0].within_limits;
        for s in samples.iter().chain(std::iter::once(&samples[0])) {
            run.push(s.elbow);
            if s.within_limits != ok {
                let c = if ok { RGBColor(44, 160, 44) } else { RGBColor(214, 39, 40) };
                scene.line(std::mem::replace(&mut run, vec![s.elbow]), c, 1.0, 3);
                ok = s.within_limits;
            }
        }
        let c = if ok { RGBColor(44, 160, 44) } else { RGBColor(214, 39, 40) };
        scene.line(run, c, 1.0, 3);
        scene.legend = vec![
            ("elbow, every joint within limits".into(), RGBColor(44, 160, 44)),
            ("elbow, some joint out of limits".into(), RGBColor(214, 39, 40)),
        ];
        let d = 180.0 / std::f64::consts::PI;
        Ok(SelfMotionView {
            title: format!("{}: self-motion at a fixed tool pose", robot.name()),
            scene,
            psi: samples.iter().map(|s| s.psi * d).collect(),
            q: (0..robot.dof()).map(|i| samples.iter().map(|s| s.q[i] * d).collect()).collect(),
            names: robot.joints().iter().map(|j| j.name.clone()).collect(),
            limits: robot.joints().iter().map(|j| (j.limits.min * d, j.limits.max * d)).collect(),
        })
    }
}

impl Plot for SelfMotionView {
    fn draw<DB: DrawingBackend<ErrorType: 'static>>(&self, area: &DrawingArea<DB, Shift>) -> Result<()> {
        let body = title_area(area, &self.title)?;
        let (w, _) = body.dim_in_pixel();
        let (left, right) = body.split_horizontally(w / 2);
        self.scene.draw(&left)?;
        let font_px = (w / 90).clamp(10, 15);
        // Unwrap ψ for the x axis: samples start at ψ of q and go once round.
        let mut x = self.psi.clone();
        for k in 1..x.len() {
            while x[k] < x[k - 1] {
                x[k] += 360.0;
            }
        }
        let (x0, x1) = (x[0], x[x.len() - 1]);
        let mut chart = ChartBuilder::on(&right)
            .caption("joint values along the self-motion", (FONT, font_px + 2))
            .margin(10)
            .x_label_area_size(font_px * 3)
            .y_label_area_size(font_px * 4)
            .build_cartesian_2d(x0..x1, -185.0..185.0)
            .map_err(drawing)?;
        chart
            .configure_mesh()
            .x_desc("arm angle ψ [deg]")
            .y_desc("q [deg]")
            .x_label_formatter(&tidy)
            .y_label_formatter(&tidy)
            .label_style((FONT, font_px))
            .light_line_style(RGBColor(238, 238, 238))
            .draw()
            .map_err(drawing)?;
        for (i, qi) in self.q.iter().enumerate() {
            let c = color(i);
            // Break the curve where the joint wraps from +180° to −180°.
            let mut runs: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
            for (k, (&xk, &v)) in x.iter().zip(qi).enumerate() {
                if k > 0 && (v - qi[k - 1]).abs() > 180.0 {
                    runs.push(Vec::new());
                }
                runs.last_mut().expect("one run").push((xk, v));
            }
            for (k, run) in runs.into_iter().enumerate() {
                let s = chart.draw_series(LineSeries::new(run, c.stroke_width(1))).map_err(drawing)?;
                if k == 0 {
                    s.label(format!("{} {}", i + 1, self.names[i]))
                        .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], c.stroke_width(2)));
                }
            }
            let (lo, hi) = self.limits[i];
            for v in [lo, hi] {
                if v.is_finite() && v.abs() <= 185.0 {
                    chart
                        .draw_series(DashedLineSeries::new([(x0, v), (x1, v)], 6, 4, c.mix(0.6).stroke_width(1)))
                        .map_err(drawing)?;
                }
            }
        }
        crate::legend(&mut chart, font_px, SeriesLabelPosition::LowerRight)?;
        Ok(())
    }
}
