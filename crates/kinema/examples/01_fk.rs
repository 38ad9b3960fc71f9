//! Forward kinematics of a built-in robot: the tool pose, its orientation in
//! both roll-pitch-yaw conventions, and every link frame.
//!
//! Run: `cargo run -p kinema --example 01_fk`

use kinema::{Robot, RpyConvention};

fn main() -> Result<(), kinema::Error> {
    let robot = Robot::builtin("scorbot-er-v-plus")?;
    let q: Vec<f64> = [10.0f64, 60.0, -40.0, -60.0, 30.0].map(f64::to_radians).to_vec();
    let fk = robot.fk(&q)?;
    let p = fk.world_from_tool;
    println!("{}: tool at [{:.4}, {:.4}, {:.4}] m", robot.name(), p.pos.x, p.pos.y, p.pos.z);
    let zyx = p.rpy(RpyConvention::Zyx).map(f64::to_degrees);
    let xyz = p.rpy(RpyConvention::Xyz).map(f64::to_degrees);
    println!("rpy zyx (seed 000): roll {:.2}°, pitch {:.2}°, yaw {:.2}°", zyx[0], zyx[1], zyx[2]);
    println!("rpy xyz (seed 004): {:.2}°, {:.2}°, {:.2}°", xyz[0], xyz[1], xyz[2]);
    println!("within limits: {}", fk.within_limits());
    for (i, f) in robot.link_frames(&q)?.iter().enumerate() {
        println!("frame {i}: origin [{:.4}, {:.4}, {:.4}]", f.pos.x, f.pos.y, f.pos.z);
    }
    Ok(())
}
