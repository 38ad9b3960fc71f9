//! The closest approach of robots' bodies over a common clock: between
//! samples it is never more than the tolerance above what dense sampling
//! finds, and the scene's obstacles count as a body.

use std::path::Path;

use kinema::traj::cell::placed;
use kinema::{Pose, Robot, RpyConvention};
use kinema_geometry::{closest_approaches, load_robot_geometry, Body, Scene, APPROACH_TOLERANCE};

/// UR5 `name` standing at `xyz`, turned by `yaw`.
fn ur5(name: &str, xyz: [f64; 3], yaw: f64, scene: Option<&Scene>) -> Body {
    let (robot, geometry) = load_robot_geometry("ur5", &Default::default()).unwrap();
    let robot: Robot = placed(&robot, &Pose::from_xyz_rpy(xyz, [0.0, 0.0, yaw], RpyConvention::Zyx)).unwrap();
    Body::new(name, robot, geometry, scene).unwrap()
}

/// Samples `from` → `to` in `n` straight steps.
fn line(from: &[f64], to: &[f64], n: usize) -> Vec<Vec<f64>> {
    (0..=n).map(|k| from.iter().zip(to).map(|(a, b)| a + (b - a) * k as f64 / n as f64).collect()).collect()
}

#[test]
fn between_samples_the_approach_is_found_within_the_tolerance() {
    // Two UR5s 1.8 m apart, the second's arm reaching towards the first; the
    // first swings its stretched arm past it in three coarse samples.
    let pi = std::f64::consts::PI;
    let bodies = [ur5("a", [0.0, 0.0, 0.0], 0.0, None), ur5("b", [1.8, 0.0, 0.0], pi, None)];
    let reach = [0.0, -0.3, 0.2, 0.0, 0.0, 0.0];
    let (mut from, mut to, mut still) = (reach, reach, reach);
    from[0] = pi - 1.4;
    to[0] = pi + 1.4;
    still[0] = pi;
    let times = [0.0, 1.0, 2.0, 3.0];
    let q = vec![line(&from, &to, 3), vec![still.to_vec(); 4]];
    let found = closest_approaches(&bodies, &times, &q).unwrap();
    assert_eq!(found.len(), 1);
    let ap = &found[0];
    assert_eq!(ap.robots, (0, Some(1)));
    // The same motion sampled 3000 times finds nothing closer than the tolerance below.
    let dense_q = [line(&from, &to, 3000), vec![still.to_vec(); 3001]];
    let dense_t: Vec<f64> = (0..=3000).map(|k| k as f64 / 1000.0).collect();
    let mut dense = f64::INFINITY;
    for k in 0..=3000 {
        let one = vec![vec![dense_q[0][k].clone()], vec![dense_q[1][k].clone()]];
        dense = dense.min(closest_approaches(&bodies, &[dense_t[k]], &one).unwrap()[0].distance);
    }
    assert!(ap.distance <= dense + APPROACH_TOLERANCE, "{} vs dense {dense}", ap.distance);
    assert!(ap.distance >= dense - 1e-3, "{} vs dense {dense}: a real distance", ap.distance);
    // At the samples alone it looks farther: the closest approach is between them.
    let coarse: f64 = (0..4)
        .map(|k| {
            closest_approaches(&bodies, &[0.0], &[vec![q[0][k].clone()], vec![q[1][k].clone()]]).unwrap()[0].distance
        })
        .fold(f64::INFINITY, f64::min);
    assert!(coarse > ap.distance + 0.01, "samples {coarse}, between {}", ap.distance);
    assert!(ap.time > 0.0 && ap.time < 3.0 && ap.time.fract() != 0.0, "{}", ap.time);
    assert!(ap.closest.0.starts_with("a/") && ap.closest.1.starts_with("b/"), "{:?}", ap.closest);
}

#[test]
fn a_scene_is_a_body_and_the_base_on_the_bench_does_not_count() {
    let scene = Scene::from_toml(
        "[[obstacle]]\nname = \"bench\"\nbox = [2, 2, 0.05]\npose = [0, 0, -0.025, 0, 0, 0]\n",
        "bench.toml",
        Path::new("."),
    )
    .unwrap();
    let body = ur5("a", [0.0, 0.0, 0.0], 0.0, Some(&scene));
    let home = [0.0, -1.2, 1.0, 0.0, 0.0, 0.0];
    let mut down = home;
    down[1] = 0.4; // the upper arm lowered below the horizontal, into the bench
    let found = closest_approaches(&[body], &[0.0, 1.0], &[vec![home.to_vec(), down.to_vec()]]).unwrap();
    assert_eq!(found.len(), 1);
    assert_eq!(found[0].robots, (0, None));
    assert_eq!(found[0].distance, 0.0, "{:?}", found[0]);
    assert_eq!(found[0].closest.1, "bench");
    assert!(found[0].time < 1.0, "contact before the end sample: {}", found[0].time);
}

#[test]
fn samples_that_do_not_fit_the_bodies_or_times_are_named() {
    let bodies = [ur5("a", [0.0, 0.0, 0.0], 0.0, None), ur5("b", [1.0, 0.0, 0.0], 0.0, None)];
    let home = vec![0.0, -1.2, 1.0, 0.0, 0.0, 0.0];
    let e = closest_approaches(&bodies, &[0.0], &[vec![home.clone()]]).unwrap_err().to_string();
    assert!(e.contains("`q` has 1 values; 2 expected") && e.contains("per body"), "{e}");
    let e = closest_approaches(&bodies, &[0.0, 1.0], &[vec![home.clone(); 2], vec![home]]).unwrap_err().to_string();
    assert!(e.contains("`q[1]` has 1 values; 2 expected") && e.contains("per time"), "{e}");
}
