//! Capability maps checked against independent computations: a voxel and
//! orientation the map counts has a configuration within limits whose FK
//! (not the solver's residual) meets the pose; one it does not count is not
//! found by the numeric solver either, from many seeded starts.

use kinema::ik::{IkRequest, NumericIk, NumericOptions};
use kinema::math::{pose_error, Pose};
use kinema::nalgebra::Vector3;
use kinema::reach::{capability_map, orientation_samples, reaches, voxel_centres};
use kinema::Robot;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Whether the numeric solver, started from home and `starts` seeded random
/// configurations, finds a configuration within limits meeting `target`.
fn numeric_finds(robot: &Robot, target: &Pose, starts: u64) -> bool {
    (0..starts).any(|seed| {
        let opts = NumericOptions { seed, max_restarts: 0, ..Default::default() };
        let ik = NumericIk::with_options(robot, opts).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let q0 = if seed == 0 { robot.home().to_vec() } else { robot.random_q(&mut rng) };
        ik.solve_from(target, &q0)
            .is_ok_and(|s| s.within_limits() && s.position_error < 1e-6 && s.orientation_error < 1e-6)
    })
}

fn check_map(name: &str, resolution: f64, orientations: usize, samples: usize) {
    let robot = Robot::builtin(name).unwrap();
    let centres = voxel_centres(&robot, resolution).unwrap();
    let rots = orientation_samples(orientations, 1);
    let request = IkRequest::default();
    let counts = capability_map(&robot, &centres, &rots, &request, &|| {}, &|| false).unwrap();
    assert_eq!(counts.len(), centres.len());
    assert!(counts.iter().any(|&c| c > 0) && counts.contains(&0), "{name}: a map with nothing to say");
    let family = kinema::ik::registry::fit(&robot);
    let mut rng = ChaCha8Rng::seed_from_u64(0x39);
    let (mut reached, mut missed) = (0, 0);
    for _ in 0..samples {
        // Half the samples among reached voxels, so both claims are tested often.
        let pool: Vec<usize> = (0..centres.len()).filter(|&i| (counts[i] > 0) == rng.random_bool(0.5)).collect();
        let v = pool[rng.random_range(0..pool.len())];
        let position = Vector3::from(centres[v]);
        let mut counted = 0;
        for rot in &rots {
            let target = Pose::new(*rot, position);
            if reaches(&robot, family.as_deref(), &target, &request) {
                counted += 1;
                reached += 1;
                let answer = kinema::ik::solve_target(&robot, &kinema::ik::IkTarget::Pose(target), &request).unwrap();
                let ok = answer.solutions.iter().any(|s| {
                    let e = pose_error(&target, &robot.fk(&s.q).unwrap().world_from_tool);
                    robot.limit_flags(&s.q).is_empty() && e.position_norm() < 1e-6 && e.rotation_angle() < 1e-6
                });
                assert!(ok, "{name}: voxel {:?} counted but no solution meets it by FK", centres[v]);
            } else {
                missed += 1;
                assert!(
                    !numeric_finds(&robot, &target, 12),
                    "{name}: voxel {:?} not counted, numeric IK reaches it",
                    centres[v]
                );
            }
        }
        assert_eq!(counted, counts[v], "{name}: voxel {:?}", centres[v]);
    }
    assert!(reached > 10 && missed > 10, "{name}: {reached} reached, {missed} missed");
}

#[test]
fn puma_map_agrees_with_fk_and_numeric_ik() {
    check_map("puma560", 0.2, 8, 40);
}

#[test]
fn iiwa_map_agrees_with_fk_and_numeric_ik() {
    check_map("lbr-iiwa-14-r820", 0.25, 8, 25);
}

#[test]
fn a_cancelled_map_stops() {
    let robot = Robot::builtin("puma560").unwrap();
    let centres = voxel_centres(&robot, 0.3).unwrap();
    let e = capability_map(&robot, &centres, &orientation_samples(4, 0), &IkRequest::default(), &|| {}, &|| true);
    assert!(matches!(e, Err(kinema::Error::Cancelled)));
}

/// The figure: the iiwa at 5 cm and 32 orientations on this machine
/// (`cargo test --release -p kinema --test all reach::iiwa_map_time -- --ignored --nocapture`).
#[test]
#[ignore]
fn iiwa_map_time() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let start = std::time::Instant::now();
    let resolution: f64 = std::env::var("KINEMA_REACH_RESOLUTION").map_or(0.05, |v| v.parse().unwrap());
    let centres = voxel_centres(&robot, resolution).unwrap();
    let counts =
        capability_map(&robot, &centres, &orientation_samples(32, 1), &IkRequest::default(), &|| {}, &|| false)
            .unwrap();
    let reached = counts.iter().filter(|&&c| c > 0).count();
    println!(
        "iiwa capability map: {} voxels, {reached} reached, {:.1} s on {} threads",
        centres.len(),
        start.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    );
}
