//! Unit tests of the calibration: Jacobian against differences, recovery
//! from noise-free and noisy data, refusals.

use std::f64::consts::PI;
use std::path::Path;

use super::model::{dh_length, with_links};
use super::*;
use crate::encoder::{CountsPerDegree, HomeOffsets};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn scorbot() -> Robot {
    Robot::builtin("scorbot-er-v-plus").unwrap()
}

fn truth() -> Constants {
    Constants::preset(CountsPerDegree::Calibrated, HomeOffsets::Measured)
}

/// Standard normal deviate (Box–Muller).
fn gauss(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = rng.random_range(f64::MIN_POSITIVE..1.0);
    let u2: f64 = rng.random_range(0.0..1.0);
    (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
}

/// `n` random within-limits configurations of the true arm (`physical`,
/// the model with the true links), commanded with integer counts,
/// measured with `noise` \[m\] per axis.
fn simulate(physical: &Robot, truth: &Constants, n: usize, noise: f64, seed: u64) -> Vec<Sample> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let q = physical.random_q(&mut rng);
            let counts = truth.counts_rounded(&q).unwrap().map(|c| c as f64);
            let p = tool_position(physical, truth, &counts).unwrap();
            let e = Vector3::new(gauss(&mut rng), gauss(&mut rng), gauss(&mut rng)) * noise;
            Sample { counts, position: p + e }
        })
        .collect()
}

/// The true value of each parameter of a calibration.
fn true_values(cal: &Calibration, truth: &Constants, links: &[f64]) -> Vec<f64> {
    let (cg, h) = (truth.counts_per_degree, truth.home_offsets);
    cal.parameters
        .iter()
        .map(|p| match p.name.as_str() {
            "cg1" => cg[0],
            "cg2" => cg[1],
            "cg3" => cg[2],
            "cg4" => cg[3],
            "cg5" => cg[4],
            "h1" => h[0],
            "h2" => h[1],
            "h3" => h[2],
            "pitch_home" => 0.5 * (h[4] / cg[4] - h[3] / cg[3]),
            other => links[LINKS.iter().position(|l| l.0 == other).unwrap()],
        })
        .collect()
}

fn nominal_links(robot: &Robot) -> Vec<f64> {
    LINKS.iter().map(|(_, j, d)| dh_length(robot, *j, *d)).collect()
}

#[test]
fn jacobian_matches_central_differences() {
    let robot = scorbot();
    for estimate_links in [false, true] {
        let options = CalibrationOptions { estimate_links, ..CalibrationOptions::default() };
        let model = Model::new(&robot, &options).unwrap();
        let samples = simulate(&robot, &truth(), 20, 0.0, 3);
        let x = model.initial.clone();
        let (js, scales, _) = model.scaled_jacobian(&x, &samples).unwrap();
        for c in 0..x.len() {
            // A step of ~1e-6 of each parameter's natural scale, so that
            // every step turns a joint by about 1e-6 rad: rounding in FK
            // then costs ~1e-10 of the derivative and truncation ~1e-12.
            // (A home offset near 0 counts once got a step of 1e-6 counts,
            // 1e-10 rad, where rounding alone was ~1e-6 of the derivative.)
            let scale = match model.names[c].1 {
                "counts" => 1e4,
                "deg" => 60.0,
                _ => 1.0,
            };
            let h = 1e-6 * x[c].abs().max(scale);
            let (mut xp, mut xm) = (x.clone(), x.clone());
            xp[c] += h;
            xm[c] -= h;
            let fd = (model.predict(&xp, &samples).unwrap() - model.predict(&xm, &samples).unwrap()) / (2.0 * h);
            let an = js.column(c) * scales[c];
            assert!((&fd - &an).norm() <= 1e-7 * an.norm(), "{}: {} vs {}", model.names[c].0, fd, an);
        }
    }
}

#[test]
fn noise_free_data_recover_the_truth() {
    let robot = scorbot();
    let t = truth();
    let samples = simulate(&robot, &t, 60, 0.0, 11);
    let cal = calibrate(&robot, &samples, &CalibrationOptions::default()).unwrap();
    let want = true_values(&cal, &t, &[]);
    for (p, w) in cal.parameters.iter().zip(&want) {
        assert!((p.value - w).abs() <= 1e-6 * w.abs().max(1.0), "{}: {} vs {w}", p.name, p.value);
    }
    assert!(cal.rms_residual < 1e-9 && cal.max_residual < 1e-9, "{}", cal.rms_residual);
    // The roll part is kept, so h4 and h5 are those of the factory roll (0), not the truth's.
    assert!(cal.roll_home.abs() < 1e-12);
    let c = &cal.constants;
    assert!(
        (c.home_offsets[4] / c.counts_per_degree[4]
            - c.home_offsets[3] / c.counts_per_degree[3]
            - (t.home_offsets[4] / 29.0 - t.home_offsets[3] / 29.0))
            .abs()
            < 1e-6
    );
    // Links too.
    let mut physical_links = nominal_links(&robot);
    for (l, d) in physical_links.iter_mut().zip([0.002, -0.0015, 0.001, -0.002, 0.003]) {
        *l += d;
    }
    let physical = with_links(&robot, &physical_links).unwrap();
    let samples = simulate(&physical, &t, 80, 0.0, 12);
    let options = CalibrationOptions { estimate_links: true, ..CalibrationOptions::default() };
    let cal = calibrate(&robot, &samples, &options).unwrap();
    let want = true_values(&cal, &t, &physical_links);
    for (p, w) in cal.parameters.iter().zip(&want) {
        assert!((p.value - w).abs() <= 1e-6 * w.abs().max(1e-3), "{}: {} vs {w}", p.name, p.value);
    }
    assert_eq!(nominal_links(&cal.robot).len(), 5);
    for (a, b) in nominal_links(&cal.robot).iter().zip(&physical_links) {
        assert!((a - b).abs() < 1e-9);
    }
}

#[test]
fn one_millimetre_noise_estimates_are_within_their_sigmas() {
    // The acceptance test: truth = Tabla II "Calibración" and Tabla III
    // "Medido", start from the factory columns, 150 random configurations,
    // 1 mm of Gaussian noise per axis.
    let robot = scorbot();
    let t = truth();
    let mut physical_links = nominal_links(&robot);
    for (l, d) in physical_links.iter_mut().zip([0.002, -0.0015, 0.001, -0.002, 0.003]) {
        *l += d;
    }
    let physical = with_links(&robot, &physical_links).unwrap();
    let mut z2 = Vec::new();
    for (estimate_links, arm) in [(false, &robot), (true, &physical)] {
        for seed in 0..6 {
            let samples = simulate(arm, &t, 150, 0.001, 100 + seed);
            let options = CalibrationOptions { estimate_links, ..CalibrationOptions::default() };
            let cal = calibrate(&robot, &samples, &options).unwrap();
            let want = true_values(&cal, &t, &physical_links);
            for (p, w) in cal.parameters.iter().zip(&want) {
                let z = (p.value - w) / p.sigma;
                let bound = if seed == 0 { 3.0 } else { 4.0 };
                assert!(
                    z.abs() < bound,
                    "seed {seed}, links {estimate_links}: {} = {} ± {} vs {w} (z = {z})",
                    p.name,
                    p.value,
                    p.sigma
                );
                z2.push(z * z);
            }
            // rms residual ≈ 1 mm·√(3·(1 − P/3N)) (three axes of 1 mm noise).
            let p = cal.parameters.len() as f64;
            let expect = 0.001 * (3.0 * (1.0 - p / 450.0)).sqrt();
            assert!((cal.rms_residual / expect - 1.0).abs() < 0.15, "{} vs {expect}", cal.rms_residual);
            assert!((cal.sigma - 0.001).abs() < 0.00015, "{}", cal.sigma);
            assert!(cal.condition_number > 1.0 && cal.condition_number < 1e5, "{}", cal.condition_number);
            if seed == 0 {
                eprintln!(
                    "links {estimate_links}: condition number {:.1}, {} iterations",
                    cal.condition_number, cal.iterations
                );
            }
            // The reported constants carry the sigmas.
            assert_eq!(cal.constants.counts_per_degree_sigma[1], cal.parameters[1].sigma);
            assert!(cal.constants.home_offsets_sigma.iter().all(|s| *s > 0.0));
        }
    }
    let rms = (z2.iter().sum::<f64>() / z2.len() as f64).sqrt();
    eprintln!(
        "normalised errors: rms {rms:.3} over {} estimates, max |z| {:.2}",
        z2.len(),
        z2.iter().fold(0.0f64, |a, b| a.max(*b)).sqrt()
    );
    assert!((0.5..1.5).contains(&rms), "rms of normalised errors {rms}");
}

#[test]
fn data_that_cannot_determine_the_parameters_are_refused() {
    let robot = scorbot();
    let t = truth();
    let opts = CalibrationOptions::default();
    let err = |s: &[Sample], o: &CalibrationOptions| calibrate(&robot, s, o).unwrap_err();
    // Too few samples.
    let few = simulate(&robot, &t, 3, 0.0, 1);
    let e = err(&few, &opts);
    assert!(e.to_string().contains("at least 4 samples"), "{e}");
    // Motor 1 never moves.
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let mut fixed_base = simulate(&robot, &t, 50, 0.0, 2);
    for s in &mut fixed_base {
        s.counts[0] = 1234.0;
    }
    let e = err(&fixed_base, &opts);
    assert!(matches!(&e, Error::Calibration { parameters, .. } if parameters == &["cg1"]), "{e}");
    // Pure pitch motions: the roll never varies.
    let pitch_only: Vec<Sample> = (0..50)
        .map(|_| {
            let mut q = robot.random_q(&mut rng);
            q[4] = 0.3;
            let counts = t.counts_rounded(&q).unwrap().map(|c| c as f64);
            Sample { counts, position: tool_position(&robot, &t, &counts).unwrap() }
        })
        .collect();
    let e = err(&pitch_only, &opts);
    assert!(e.to_string().contains("cg4 and cg5 cannot be told apart"), "{e}");
    assert!(matches!(&e, Error::Calibration { parameters, .. } if parameters == &["cg4", "cg5"]));
    // The shoulder moving only a hair: the SVD check names what is undetermined.
    let mut narrow = Vec::new();
    for _ in 0..50 {
        let mut q = robot.random_q(&mut rng);
        q[1] = 1.0 + rng.random_range(-1e-9..1e-9);
        let counts = t.counts(&q).unwrap();
        let counts = [counts[0], 5000.0 + rng.random_range(0.0..2.5), counts[2], counts[3], counts[4]];
        narrow.push(Sample { counts, position: tool_position(&robot, &t, &counts).unwrap() });
    }
    // It is determined in principle (noise-free data), but barely: the
    // condition number is large …
    let cal = calibrate(&robot, &narrow, &opts).unwrap();
    assert!(cal.condition_number > 1e4, "{}", cal.condition_number);
    // … and a stricter limit refuses it, naming cg2 and h2 as the free combination.
    let strict = CalibrationOptions { max_condition: 1e4, ..opts.clone() };
    let e = err(&narrow, &strict);
    assert!(
        matches!(&e, Error::Calibration { parameters, .. } if parameters[..2] == ["h2", "cg2"] || parameters[..2] == ["cg2", "h2"]),
        "{e:?}"
    );
    assert!(e.to_string().contains("condition number"), "{e}");
    // Bad samples and options.
    let mut nan = few.clone();
    nan.extend(simulate(&robot, &t, 10, 0.0, 4));
    nan[5].position.y = f64::NAN;
    let e = err(&nan, &opts);
    assert!(matches!(&e, Error::NotFinite { what, .. } if what == "sample 6, position y"), "{e:?}");
    let good = simulate(&robot, &t, 20, 0.0, 5);
    let bad_opts = CalibrationOptions { max_iterations: 0, ..opts.clone() };
    let e = err(&good, &bad_opts);
    assert!(matches!(&e, Error::OutOfRange { what, value, .. } if what == "max_iterations" && *value == 0.0), "{e:?}");
    let mut bad_initial = opts.clone();
    bad_initial.initial.counts_per_degree[2] = 0.0;
    let e = err(&good, &bad_initial);
    assert!(matches!(&e, Error::OutOfRange { what, .. } if what == "counts_per_degree[3]"), "{e:?}");
    let five = Robot::builtin("scara5");
    if let Ok(other) = five {
        let e = calibrate(&other, &good, &opts).unwrap_err();
        assert!(matches!(&e, Error::NeedsScorbot { .. }), "{e:?}");
        assert!(e.to_string().contains("Scorbot structure"), "{e}");
    }
    let one_iteration = CalibrationOptions { max_iterations: 1, ..opts.clone() };
    let e = err(&simulate(&robot, &t, 30, 0.001, 6), &one_iteration);
    assert!(e.to_string().contains("no convergence in 1 iterations"), "{e}");
}

#[test]
fn samples_files() {
    let s = parse_samples_csv("# c\nc5,c4,c3,c2,c1,z,y,x,t\n5,4,3,2,1,0.3,0.2,0.1,0\n", "s.csv").unwrap();
    assert_eq!(s, vec![Sample { counts: [1.0, 2.0, 3.0, 4.0, 5.0], position: Vector3::new(0.1, 0.2, 0.3) }]);
    let e = parse_samples_csv("c1,c2,c3,c4,x,y,z\n1,2,3,4,0,0,0\n", "s.csv").unwrap_err().to_string();
    assert!(e.starts_with("s.csv:1") && e.contains("`c5`"), "{e}");
    let e = parse_samples_csv("c1,c2,c3,c4,c5,x,y,z\n1,2,3,4,5,0,zero,0\n", "s.csv").unwrap_err().to_string();
    assert!(e.starts_with("s.csv:2") && e.contains("`zero`"), "{e}");
    let e = read_samples_csv(Path::new("/nonexistent/s.csv")).unwrap_err();
    let io = std::error::Error::source(&e).and_then(|s| s.source()).and_then(|s| s.downcast_ref::<std::io::Error>());
    assert_eq!(io.map(|e| e.kind()), Some(std::io::ErrorKind::NotFound), "{e:?}");
}
