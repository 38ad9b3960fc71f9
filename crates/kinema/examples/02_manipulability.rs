//! Singularity analysis of the KUKA LBR iiwa at the configurations of seed 004:
//! Cuadro III's singular poses, and the manipulability along a direction of
//! motion of Fig. 8.
//!
//! Run: `cargo run -p kinema --example 02_manipulability`

use kinema::analysis::{self, Axes};
use kinema::nalgebra::Vector3;
use kinema::{Frame, Robot};

fn main() -> Result<(), kinema::Error> {
    let robot = Robot::builtin("lbr-iiwa-14-r820")?;
    for pose in ["fig9", "sing-q4", "sing-q2-q3", "sing-coupled"] {
        let j = robot.jacobian(robot.pose(pose)?, Frame::Base)?;
        let r = analysis::report(&j)?;
        println!(
            "{pose:<13} rank {}  yoshikawa {:.3e}  σmin {:.3e}  dependent joints {}",
            r.rank,
            r.yoshikawa,
            r.singular_values.last().copied().unwrap_or(0.0),
            r.dependent_joints.len()
        );
    }
    // Seed 004 Fig. 8: v = [−0.4, 0.5, 0.75] at q = [−2.5, −1, −2.7, 1.37, −0.42, −1.88, −1.24].
    let q = [-2.5, -1.0, -2.7, 1.37, -0.42, -1.88, -1.24];
    let j = robot.jacobian(&q, Frame::Base)?;
    let v = Vector3::new(-0.4, 0.5, 0.75);
    let m = analysis::manipulability_along(&j, Axes::Translation, &v)?;
    let e = analysis::ellipsoid(&j, Axes::Translation)?;
    println!("Fig. 8: ellipsoid radii {:.4} {:.4} {:.4} m/s, along v: {m:.4} m/s", e.radii[0], e.radii[1], e.radii[2]);
    Ok(())
}
