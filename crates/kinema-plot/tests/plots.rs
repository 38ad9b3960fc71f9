//! Pictures render in both formats, with text from the embedded font, and
//! bad input is an error.

use kinema::traj::JointTrajectory;
use kinema::Robot;
use kinema_plot::{render, Format, JointCurves, RobotView};

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
    assert!(render(&view, Format::Png, (10, 10)).is_err());
    assert!(render(&view, Format::Svg, (100_000, 500)).is_err());
    let mut one = JointTrajectory::new(6);
    one.push(0.0, &[0.0; 6], &[0.0; 6], &[0.0; 6]).unwrap();
    assert!(JointCurves::new(&robot, &one).unwrap_err().to_string().contains("at least two samples"));
    let seven = JointTrajectory::new(7);
    assert!(JointCurves::new(&robot, &seven).unwrap_err().to_string().contains("7 joints"));
    assert_eq!(Format::from_path(std::path::Path::new("a.PNG")), Some(Format::Png));
    assert_eq!(Format::from_path(std::path::Path::new("a.pdf")), None);
}
