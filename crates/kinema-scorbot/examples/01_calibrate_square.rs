//! Seed 000 Fig. 6 in simulation, then the calibration its §V asks for.
//!
//! A 10 cm square in the xz plane (y = 0, centred at x = 0.35 m, z = 0.30 m,
//! a point every centimetre; pitch 60° — with pitch 0 the elbow would need
//! more than its ±130° there — and roll 0) is planned with the closed-form
//! IK and converted to counts with the ASSUMED constants (factory, Tabla II–III).
//! The simulated arm really follows the TRUE constants (the seed's calibrated
//! Tabla II and measured Tabla III columns), so it misses the square. We then
//! measure 150 random configurations with 1 mm of noise per axis, calibrate
//! from the factory constants, replan with the estimates and follow the
//! square again.
//!
//! Run: `cargo run -p kinema-scorbot --example 01_calibrate_square`

use kinema::nalgebra::Vector3;
use kinema::traj::tracking_error;
use kinema::Robot;
use kinema_scorbot::calib::{calibrate, tool_position, CalibrationOptions, Sample};
use kinema_scorbot::encoder::Constants;
use kinema_scorbot::follow::{self, PathPoint, PlanOptions, SEED_MAX_STEP};
use kinema_scorbot::metrics::{track, TrackOptions};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let robot = Robot::builtin("scorbot-er-v-plus")?;
    let assumed = Constants::named("factory")?;
    let truth = Constants::named("calibrated")?;

    // The desired square as sent (a point every cm), and what the arm does
    // with counts planned from `constants` by seed 000's path following
    // (resampling, closed-form IK, eq. 24): it moves by the TRUE constants.
    let desired: Vec<Vector3<f64>> = follow::resample(&square(), SEED_MAX_STEP)?.iter().map(|p| p.position).collect();
    let follow = |constants: &Constants| -> Result<Vec<Vector3<f64>>, Box<dyn std::error::Error>> {
        let plan = follow::plan(&robot, constants, &square(), &PlanOptions::default())?;
        plan.counts.iter().map(|c| Ok(tool_position(&robot, &truth, &c.map(|v| v as f64))?)).collect()
    };
    let before = follow(&assumed)?;

    // Calibration data: 150 random configurations (roll varied), 1 mm noise.
    let mut rng = ChaCha8Rng::seed_from_u64(2017);
    let mut normal = || {
        let (u1, u2): (f64, f64) = (rng.random_range(f64::MIN_POSITIVE..1.0), rng.random_range(0.0..1.0));
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    };
    let mut qrng = ChaCha8Rng::seed_from_u64(5);
    let mut samples = Vec::new();
    for _ in 0..150 {
        let q = robot.random_q(&mut qrng);
        let counts = truth.counts_rounded(&q)?.map(|c| c as f64);
        let noise = Vector3::new(normal(), normal(), normal()) * 0.001;
        samples.push(Sample { counts, position: tool_position(&robot, &truth, &counts)? + noise });
    }
    let cal = calibrate(&robot, &samples, &CalibrationOptions { initial: assumed.clone(), ..Default::default() })?;
    let after = follow(&cal.constants)?;

    println!("calibration from {} samples, {} iterations", cal.samples, cal.iterations);
    println!(
        "  rms residual {:.3} mm, max {:.3} mm, σ per axis {:.3} mm, condition number {:.0}",
        cal.rms_residual * 1e3,
        cal.max_residual * 1e3,
        cal.sigma * 1e3,
        cal.condition_number
    );
    println!("  {:<11} {:>12} {:>12} {:>10} {:>12}", "parameter", "factory", "estimate", "± σ", "true");
    let t = (truth.counts_per_degree, truth.home_offsets);
    let true_values =
        [t.0[0], t.0[1], t.0[2], t.0[3], t.0[4], t.1[0], t.1[1], t.1[2], 0.5 * (t.1[4] / t.0[4] - t.1[3] / t.0[3])];
    for (p, tv) in cal.parameters.iter().zip(true_values) {
        println!("  {:<11} {:>12.3} {:>12.3} {:>10.3} {:>12.3}  {}", p.name, p.initial, p.value, p.sigma, tv, p.unit);
    }
    for (label, run) in [("before (factory constants)", &before), ("after calibration", &after)] {
        let e = tracking_error(&desired, std::slice::from_ref(run))?;
        let iso = track(&desired, std::slice::from_ref(run), &TrackOptions::default())?;
        println!(
            "square, {label}: tracking error {:.3} mm (seed 000's mean distance), AT_p {:.3} mm, AP_p {:.3} mm",
            e.mean * 1e3,
            iso.at_p * 1e3,
            iso.ap_p * 1e3
        );
    }
    Ok(())
}

/// Seed 000 Fig. 6: a 10 cm square in the xz plane (y = 0) centred at
/// x = 0.35 m, z = 0.30 m, with pitch 60° and roll 0.
fn square() -> Vec<PathPoint> {
    let corners = [(0.30, 0.25), (0.40, 0.25), (0.40, 0.35), (0.30, 0.35), (0.30, 0.25)];
    corners.iter().map(|&(x, z)| PathPoint::new(Vector3::new(x, 0.0, z), 60f64.to_radians(), 0.0)).collect()
}
