//! Pictures render in both formats, with text from the embedded font, and
//! bad input is an error.

use kinema::traj::JointTrajectory;
use kinema::Robot;
use kinema_plot::{render, Error, Format, JointCurves, RobotView};

/// Decodes a PNG to (width, height, RGB bytes).
fn decode(png: &[u8]) -> (u32, u32, Vec<u8>) {
    let img = image::load_from_memory_with_format(png, image::ImageFormat::Png).expect("a PNG").to_rgb8();
    (img.width(), img.height(), img.into_raw())
}

/// Fraction of non-white pixels in rows `y0..y1`.
fn ink(w: u32, rgb: &[u8], y0: u32, y1: u32) -> f64 {
    let row = 3 * w as usize;
    let px = &rgb[y0 as usize * row..y1 as usize * row];
    px.chunks(3).filter(|p| p.iter().any(|&c| c < 200)).count() as f64 / (px.len() / 3) as f64
}

#[test]
fn robot_view_in_svg_and_png() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let view = RobotView::new(&robot, robot.home()).unwrap();
    // Base, 7 joint frames, tool.
    assert_eq!(view.points().len(), 9);
    let svg = String::from_utf8(render(&view, Format::Svg, (900, 450)).unwrap()).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("side view (x–z)") && svg.contains("top view (x–y)"));
    assert!(svg.contains("DejaVu Sans, sans-serif"));
    let png = render(&view, Format::Png, (900, 450)).unwrap();
    let (w, h, rgb) = decode(&png);
    assert_eq!((w, h), (900, 450));
    // The title band holds rasterised text (the embedded font), the panels the drawing.
    assert!(ink(w, &rgb, 0, 30) > 0.01, "no title text");
    assert!(ink(w, &rgb, 60, 440) > 0.02, "no drawing");
}

#[test]
fn joint_curves_of_a_program() {
    let robot = Robot::builtin("scara5").unwrap();
    let src = "HOME 1\nMOVEXY 100, -100, 2\nMOVEZ -50, 1\n";
    let plan = kinema_lang::compile(src, &robot, &Default::default()).unwrap();
    let curves = JointCurves::new(&robot, &plan.trajectory).unwrap();
    let svg = String::from_utf8(render(&curves, Format::Svg, (1000, 900)).unwrap()).unwrap();
    for label in ["position", "velocity", "acceleration", "1 rail", "4 z"] {
        assert!(svg.contains(label), "{label} missing");
    }
    let (w, _, rgb) = decode(&render(&curves, Format::Png, (1000, 900)).unwrap());
    assert!(ink(w, &rgb, 0, 40) > 0.01);
}

#[test]
fn bad_input_is_an_error() {
    let robot = Robot::builtin("puma560").unwrap();
    assert!(RobotView::new(&robot, &[0.0; 5]).is_err());
    assert!(RobotView::new(&robot, &[f64::NAN; 6]).is_err());
    let view = RobotView::new(&robot, robot.home()).unwrap();
    let e = render(&view, Format::Png, (10, 10)).unwrap_err();
    assert!(matches!(&e, Error::OutOfRange { what, value, .. } if what == "width" && *value == 10.0), "{e:?}");
    let e = render(&view, Format::Svg, (500, 100_000)).unwrap_err();
    assert!(matches!(&e, Error::OutOfRange { what, value, .. } if what == "height" && *value == 1e5), "{e:?}");
    let mut one = JointTrajectory::new(6);
    one.push(0.0, &[0.0; 6], &[0.0; 6], &[0.0; 6]).unwrap();
    let e = JointCurves::new(&robot, &one).unwrap_err();
    assert!(matches!(&e, Error::TooFew { got: 1, min: 2, .. }), "{e:?}");
    assert!(e.to_string().contains("at least 2 needed"), "{e}");
    let seven = JointTrajectory::new(7);
    let e = JointCurves::new(&robot, &seven).unwrap_err();
    assert!(matches!(&e, Error::WrongLength { got: 7, expected: 6, .. }), "{e:?}");
    assert!(e.to_string().contains("7 joints"), "{e}");
    assert_eq!(Format::from_path(std::path::Path::new("a.PNG")), Some(Format::Png));
    assert_eq!(Format::from_path(std::path::Path::new("a.pdf")), None);
}

/// Renders `plot` as SVG (returning its text) and PNG (checking it decodes
/// to the size asked, with a title and a drawing).
fn both(plot: &impl kinema_plot::Plot, size: (u32, u32)) -> String {
    let svg = String::from_utf8(render(plot, Format::Svg, size).unwrap()).unwrap();
    assert!(svg.starts_with("<svg"));
    let (w, h, rgb) = decode(&render(plot, Format::Png, size).unwrap());
    assert_eq!((w, h), size);
    assert!(ink(w, &rgb, 0, 40) > 0.005, "no title text");
    assert!(ink(w, &rgb, 60, h - 10) > 0.01, "no drawing");
    svg
}

#[test]
fn three_d_views_render_with_their_labels() {
    let iiwa = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let q = [0.3, 0.6, 0.4, -1.2, 0.3, 0.9, 0.1];
    let svg = both(&kinema_plot::Robot3d::new(&iiwa, &q).unwrap(), (800, 700));
    assert!(svg.contains("link frames") && svg.contains("z axes"));
    // Frame numbers 1..7 are drawn (frames at one point share a label).
    let texts: Vec<&str> = svg.split("</text>").filter_map(|t| t.rsplit('>').next()).map(str::trim).collect();
    let numbers: Vec<usize> = texts.iter().flat_map(|t| t.split(',')).filter_map(|n| n.parse().ok()).collect();
    for i in 1..=7 {
        assert!(numbers.contains(&i), "frame {i} unlabelled: {texts:?}");
    }
    let sm = kinema_plot::SelfMotionView::new(&iiwa, &q, 72).unwrap();
    let svg = both(&sm, (1200, 600));
    assert!(svg.contains("arm angle ψ") && svg.contains("7 A7"));
    let e = kinema_plot::SelfMotionView::new(&iiwa, &q, 3).unwrap_err();
    assert!(matches!(&e, Error::TooFew { got: 3, min: 8, .. }), "{e:?}");
    let e = kinema_plot::SelfMotionView::new(&Robot::builtin("puma560").unwrap(), &[0.0; 6], 36).unwrap_err();
    assert!(matches!(&e, Error::DoesNotFit { what, .. } if what == "robot"), "{e:?}");
}

#[test]
fn ellipsoids_are_the_singular_values_of_the_jacobian_rows() {
    use kinema::nalgebra::{DMatrix, Matrix3};
    for name in ["lbr-iiwa-14-r820", "puma560", "scorbot-er-v-plus"] {
        let robot = Robot::builtin(name).unwrap();
        let mut rng = <rand_chacha::ChaCha8Rng as rand::SeedableRng>::seed_from_u64(4);
        for _ in 0..50 {
            let q = robot.random_q(&mut rng);
            let view = kinema_plot::EllipsoidView::new(&robot, &q).unwrap();
            let j = robot.jacobian(&q, kinema::Frame::Base).unwrap();
            for (k, e) in view.ellipsoids.iter().enumerate() {
                let rows = DMatrix::from_fn(3, robot.dof(), |r, c| j[(3 * k + r, c)]);
                let mut sv: Vec<f64> = rows.singular_values().iter().copied().collect();
                sv.sort_by(|a, b| b.total_cmp(a));
                for i in 0..3 {
                    assert!((e.radii[i] - sv[i]).abs() < 1e-9 * (1.0 + sv[0]), "{name}: {:?} vs {sv:?}", e.radii);
                }
                // Principal axes: orthonormal, and J Jᵀ a = r² a.
                let p = &rows * rows.transpose();
                let p = Matrix3::from_fn(|r, c| p[(r, c)]);
                assert!((e.axes.transpose() * e.axes - Matrix3::identity()).norm() < 1e-9);
                for i in 0..3 {
                    let a = e.axes.column(i);
                    assert!((p * a - a * e.radii[i].powi(2)).norm() < 1e-8 * (1.0 + sv[0] * sv[0]));
                }
            }
        }
        both(&kinema_plot::EllipsoidView::new(&robot, robot.home()).unwrap(), (1200, 600));
    }
}

#[test]
fn workspace_points_are_reachable_and_the_plot_shows_both_panels() {
    let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
    let mut calls = Vec::new();
    let opts = kinema_plot::WorkspaceOptions { samples: 25_000, ..Default::default() };
    let cloud = kinema_plot::WorkspaceCloud::sample(&robot, &opts, |n| calls.push(n)).unwrap();
    assert_eq!(calls, [10_000, 20_000, 25_000]);
    assert_eq!(cloud.points().len(), 25_000);
    // Independent: every point is the FK of a configuration within the limits,
    // so no farther from the base than the sum of the link lengths (a, d of the DH rows, tool).
    let frames = robot.link_frames(robot.home()).unwrap();
    let reach: f64 = frames.windows(2).map(|w| (w[1].pos - w[0].pos).norm()).sum();
    let base = robot.base().pos;
    assert!(cloud.points().iter().all(|p| (p - base).norm() <= reach + 1e-9));
    // The same seed gives the same cloud.
    let again = kinema_plot::WorkspaceCloud::sample(&robot, &opts, |_| {}).unwrap();
    assert_eq!(cloud.points(), again.points());
    let svg = both(&cloud, (1000, 500));
    assert!(svg.contains("side section (r–z)") && svg.contains("top view (x–y)"));
    let rail = Robot::builtin("scara5").unwrap();
    let cloud = kinema_plot::WorkspaceCloud::sample(&rail, &opts, |_| {}).unwrap();
    assert!(both(&cloud, (1000, 500)).contains("side view (x–z)"));
    let bad = kinema_plot::WorkspaceOptions { samples: 0, ..Default::default() };
    let e = kinema_plot::WorkspaceCloud::sample(&robot, &bad, |_| {}).unwrap_err();
    assert!(matches!(&e, Error::TooFew { got: 0, min: 1, .. }), "{e:?}");
    let bad = kinema_plot::WorkspaceOptions { grid: 5, ..Default::default() };
    let e = kinema_plot::WorkspaceCloud::sample(&robot, &bad, |_| {}).unwrap_err();
    assert!(matches!(&e, Error::OutOfRange { what, value, .. } if what == "grid" && *value == 5.0), "{e:?}");
}

#[test]
fn trajectory_plots_of_a_program() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let src =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/programs/iiwa_draw.prg")).unwrap();
    let plan = kinema_lang::compile(&src, &robot, &kinema_lang::Options { dt: 0.02, ..Default::default() }).unwrap();
    let t = &plan.trajectory;
    let svg = both(&kinema_plot::CartesianCurves::new(&robot, t).unwrap(), (1000, 800));
    assert!(svg.contains("velocity [m/s]") && svg.contains("norm"));
    let svg = both(&kinema_plot::ManipulabilityCurve::new(&robot, t).unwrap(), (1000, 700));
    assert!(svg.contains("along the motion (eq. 12)"));
    let svg = both(&kinema_plot::ToolPath3d::new(&robot, t).unwrap(), (800, 700));
    assert!(svg.contains("tool path"));
    let puma = Robot::builtin("puma560").unwrap();
    assert!(kinema_plot::CartesianCurves::new(&puma, t).is_err());
    assert!(kinema_plot::ToolPath3d::new(&robot, &JointTrajectory::new(7)).is_err());
}

#[test]
fn ik_error_plot_equals_the_validation_report() {
    let iiwa = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let plot = kinema_plot::IkErrorPlot::iiwa(&iiwa, 3000, 9).unwrap();
    let report = kinema::ik::IiwaIk::new(&iiwa).unwrap().validate(3000, 9);
    let (max, mean) = plot.max_mean();
    assert_eq!(max, report.max_error);
    assert!((mean - report.mean_error).abs() <= 1e-15 * report.mean_error.max(1e-300) + 1e-30);
    assert!(both(&plot, (1000, 500)).contains("max |Δq| [rad]"));
    let puma = Robot::builtin("puma560").unwrap();
    let solver = kinema::ik::analytic_solver(&puma).unwrap();
    let plot = kinema_plot::IkErrorPlot::round_trip(&puma, solver.as_ref(), 500, 2).unwrap();
    let report = kinema::ik::round_trip(&puma, solver.as_ref(), 500, 2).unwrap();
    assert_eq!(plot.max_mean().0, report.max_error);
    assert_eq!(plot.errors.iter().flatten().count(), report.solved);
}

#[test]
fn tracking_error_of_a_square_offset_by_known_distances() {
    use kinema::nalgebra::Vector3;
    // A 10 cm square at z = 0.2 (seed 000 Fig. 6) and two runs whose points are
    // 1 mm and 3 mm outside it, perpendicular to the sides.
    let c = [(0.3, -0.05), (0.4, -0.05), (0.4, 0.05), (0.3, 0.05), (0.3, -0.05)];
    let desired: Vec<Vector3<f64>> = c.iter().map(|&(x, y)| Vector3::new(x, y, 0.2)).collect();
    let run = |off: f64| -> Vec<Vector3<f64>> {
        (1..10)
            .flat_map(|k| {
                let s = 0.3 + 0.01 * k as f64;
                let y = -0.05 + 0.01 * k as f64;
                [
                    Vector3::new(s, -0.05 - off, 0.2),
                    Vector3::new(0.4 + off, y, 0.2),
                    Vector3::new(s, 0.05 + off, 0.2),
                    Vector3::new(0.3 - off, y, 0.2),
                ]
            })
            .collect()
    };
    let plot = kinema_plot::TrackingPlot::new(desired.clone(), vec![run(0.001), run(0.003)]).unwrap();
    assert!((plot.run_means[0] - 0.001).abs() < 1e-12 && (plot.run_means[1] - 0.003).abs() < 1e-12);
    let (mean, sd) = plot.mean_error();
    assert!((mean - 0.002).abs() < 1e-12 && (sd - 0.002 / 2f64.sqrt()).abs() < 1e-12);
    let svg = both(&plot, (1200, 550));
    assert!(svg.contains("2.00 ± 1.41 mm") && svg.contains("run 2: 3.00 mm"));
    let e = kinema_plot::TrackingPlot::new(desired.clone(), vec![]).unwrap_err();
    assert!(matches!(&e, Error::TooFew { got: 0, min: 1, .. }), "{e:?}");
    let e = kinema_plot::TrackingPlot::new(desired.clone(), vec![run(0.001), vec![]]).unwrap_err();
    assert!(matches!(&e, Error::TooFew { what, .. } if what == "measured run 2"), "{e:?}");
    assert!(kinema_plot::TrackingPlot::new(vec![desired[0]], vec![run(0.0)]).is_err());
}
