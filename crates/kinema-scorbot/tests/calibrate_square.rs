//! Seed 000 Fig. 6 in simulation: a square planned with the assumed (factory)
//! constants, followed by an arm with the true (seed's calibrated/measured)
//! constants — before and after calibrating from simulated measurements.

use kinema::ik::scorbot::ScorbotIk;
use kinema::nalgebra::Vector3;
use kinema::traj::tracking_error;
use kinema::Robot;
use kinema_scorbot::calib::{calibrate, tool_position, CalibrationOptions, Sample};
use kinema_scorbot::encoder::Constants;
use kinema_scorbot::metrics::{track, TrackOptions};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A square of half side `h` \[m\] in the xz plane at y = 0 around (`cx`, `cz`),
/// a point every `step` \[m\], closed.
fn square(cx: f64, cz: f64, h: f64, step: f64) -> Vec<Vector3<f64>> {
    let corners = [(-h, -h), (h, -h), (h, h), (-h, h), (-h, -h)];
    let n = (2.0 * h / step).round() as usize;
    let mut out = Vec::new();
    for w in corners.windows(2) {
        for k in 0..n {
            let t = k as f64 / n as f64;
            out.push(Vector3::new(cx + w[0].0 + t * (w[1].0 - w[0].0), 0.0, cz + w[0].1 + t * (w[1].1 - w[0].1)));
        }
    }
    out.push(out[0]);
    out
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

    // 10 cm square at x = 0.35 m, z = 0.30 m, 1 cm between points; pitch 60°
    // (pitch 0 needs more than the elbow's ±130° there), roll 0.
    let desired = square(0.35, 0.30, 0.05, 0.01);
    let ik = ScorbotIk::new(&robot).unwrap();
    let plan: Vec<Vec<f64>> = desired
        .iter()
        .map(|p| {
            let sols = ik.solve_xyz_pitch_roll([p.x, p.y, p.z], 60f64.to_radians(), 0.0).unwrap();
            let s = sols.into_iter().find(|s| s.branch == "front/elbow-up" && s.within_limits()).unwrap();
            assert!(s.position_error < 1e-9);
            s.q
        })
        .collect();
    // The physical arm: counts from `constants`, motion by the true constants.
    let follow = |constants: &Constants| -> Vec<Vector3<f64>> {
        plan.iter()
            .map(|q| {
                let counts = constants.counts_rounded(q).unwrap().map(|c| c as f64);
                tool_position(&robot, &truth, &counts).unwrap()
            })
            .collect()
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
