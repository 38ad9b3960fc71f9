//! Seed 000 Fig. 6 in simulation: a square planned with the assumed (factory)
//! constants, followed by an arm with the true (seed's calibrated/measured)
//! constants — before and after calibrating from simulated measurements.

use kinema::nalgebra::Vector3;
use kinema::traj::tracking_error;
use kinema::Robot;
use kinema_scorbot::calib::{calibrate, tool_position, CalibrationOptions, Sample};
use kinema_scorbot::encoder::Constants;
use kinema_scorbot::follow::{self, PathPoint, PlanOptions, SEED_MAX_STEP};
use kinema_scorbot::metrics::{track, TrackOptions};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Seed 000 Fig. 6: a 10 cm square in the xz plane (y = 0) centred at
/// x = 0.35 m, z = 0.30 m, with pitch 60° (pitch 0 needs more than the
/// elbow's ±130° there) and roll 0.
fn square() -> Vec<PathPoint> {
    let corners = [(0.30, 0.25), (0.40, 0.25), (0.40, 0.35), (0.30, 0.35), (0.30, 0.25)];
    corners.iter().map(|&(x, z)| PathPoint::new(Vector3::new(x, 0.0, z), 60f64.to_radians(), 0.0)).collect()
}

fn gauss(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = rng.random_range(f64::MIN_POSITIVE..1.0);
    let u2: f64 = rng.random_range(0.0..1.0);
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

#[test]
fn calibration_removes_the_systematic_error_of_the_square() {
    let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
    let assumed = Constants::named("factory").unwrap();
    let truth = Constants::named("calibrated").unwrap();

    // The desired path as sent (a point every cm) and what the arm does with
    // counts planned with `constants` (seed 000's path following), moving by
    // the true constants.
    let desired: Vec<Vector3<f64>> =
        follow::resample(&square(), SEED_MAX_STEP).unwrap().iter().map(|p| p.position).collect();
    let follow = |constants: &Constants| -> Vec<Vector3<f64>> {
        let plan = follow::plan(&robot, constants, &square(), &PlanOptions::default()).unwrap();
        assert!(plan.branches.iter().all(|b| b == "front/elbow-up"));
        plan.counts.iter().map(|c| tool_position(&robot, &truth, &c.map(|v| v as f64)).unwrap()).collect()
    };
    // Sanity: with the true constants the arm follows the square to within rounding of the counts.
    let ideal = tracking_error(&desired, &[follow(&truth)]).unwrap();
    assert!(ideal.mean < 1e-4, "{ideal:?}");

    let before = tracking_error(&desired, &[follow(&assumed)]).unwrap().mean;

    let mut rng = ChaCha8Rng::seed_from_u64(2017);
    let samples: Vec<Sample> = (0..150)
        .map(|_| {
            let q = robot.random_q(&mut rng);
            let counts = truth.counts_rounded(&q).unwrap().map(|c| c as f64);
            let noise = Vector3::new(gauss(&mut rng), gauss(&mut rng), gauss(&mut rng)) * 0.001;
            Sample { counts, position: tool_position(&robot, &truth, &counts).unwrap() + noise }
        })
        .collect();
    let options = CalibrationOptions { initial: assumed.clone(), ..CalibrationOptions::default() };
    let cal = calibrate(&robot, &samples, &options).unwrap();
    let run = follow(&cal.constants);
    let after = tracking_error(&desired, std::slice::from_ref(&run)).unwrap().mean;
    eprintln!("square: tracking error before {:.3} mm, after {:.3} mm", before * 1e3, after * 1e3);
    assert!(before > 0.005, "the factory constants should miss by millimetres: {before}");
    assert!(after < before / 5.0 && after < 0.001, "before {before}, after {after}");
    // ISO 9283 path accuracy improves likewise.
    let iso_after = track(&desired, &[run], &TrackOptions::default()).unwrap();
    let iso_before = track(&desired, &[follow(&assumed)], &TrackOptions::default()).unwrap();
    assert!(iso_after.at_p < iso_before.at_p / 5.0 && iso_after.at_p < 0.002, "{iso_before:?} {iso_after:?}");
}
