//! The continuous check between two configurations: it finds a thin plate
//! that both ends miss, and on seeded segments through seed 004's lab it
//! never reports a contact later than dense sampling finds one.

use std::path::PathBuf;

use kinema::Robot;
use kinema_geometry::{CheckOptions, CollisionCheck, Placement, Scene, CONTACT_TOLERANCE};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn fume_hood() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/fume-hood.toml")
}

/// `from` + s·(`to` − `from`).
fn between(from: &[f64], to: &[f64], s: f64) -> Vec<f64> {
    from.iter().zip(to).map(|(a, b)| a + s * (b - a)).collect()
}

/// The smallest distance of any checked pair at `q`, less the margin.
fn clearance(check: &CollisionCheck, q: &[f64], placement: &mut Placement) -> f64 {
    check.place(q, placement).unwrap();
    check.closest(placement).unwrap().map_or(f64::INFINITY, |p| p.distance - check.margin())
}

/// A 1 mm plate across the UR5's flange path as joint 1 turns from −1 to
/// 1 rad: both ends are free, the middle is not.
fn ur5_and_plate() -> (CollisionCheck, Vec<f64>, Vec<f64>) {
    let robot = Robot::builtin("ur5").unwrap();
    let mut middle = robot.home().to_vec();
    middle[1] = -0.6;
    let p = robot.fk(&middle).unwrap().world_from_tool.pos;
    // Thin along the direction the flange moves (about the base z axis).
    let yaw = p.y.atan2(p.x) + std::f64::consts::FRAC_PI_2;
    let text = format!(
        "[[obstacle]]\nname = \"plate\"\nbox = [0.001, 0.05, 0.05]\npose = [{}, {}, {}, 0, 0, {yaw}]\n",
        p.x, p.y, p.z
    );
    let scene = Scene::from_toml(&text, "plate.toml", std::path::Path::new(".")).unwrap();
    let bare = CollisionCheck::load("ur5", &CheckOptions::default()).unwrap();
    let check = CollisionCheck::with_scene(
        bare.robot().clone(),
        bare.geometry().clone(),
        bare.pairs().clone(),
        Some(&scene),
        0.0,
    )
    .unwrap();
    let (mut from, mut to) = (middle.clone(), middle);
    from[0] -= 1.0;
    to[0] += 1.0;
    (check, from, to)
}

#[test]
fn a_thin_plate_between_two_free_samples_is_found() {
    let (check, from, to) = ur5_and_plate();
    assert_eq!(check.first_collision(&from).unwrap(), None);
    assert_eq!(check.first_collision(&to).unwrap(), None);
    assert!(check.first_collision(&between(&from, &to, 0.5)).unwrap().is_some());
    // Sampled every 0.01 of the segment (0.02 rad of joint 1), the plate is missed.
    let sampled = (0..=100).any(|k| check.first_collision(&between(&from, &to, k as f64 / 100.0)).unwrap().is_some());
    let contact = check.first_contact_between(&from, &to, &mut check.placement()).unwrap().expect("a contact");
    let mut placement = check.placement();
    assert!(contact.fraction > 0.4 && contact.fraction < 0.5, "{contact:?} (sampled: {sampled})");
    assert!(clearance(&check, &between(&from, &to, contact.fraction), &mut placement) <= CONTACT_TOLERANCE);
    assert_eq!(check.body(contact.pair.1), "plate");
    // Dense sampling up to the contact finds nothing earlier.
    for k in 0..1000 {
        let s = contact.fraction * k as f64 / 1000.0;
        assert!(clearance(&check, &between(&from, &to, s), &mut placement) > 0.0, "s = {s}");
    }
}

#[test]
fn the_continuous_check_is_never_later_than_dense_sampling() {
    let check =
        CollisionCheck::load("lbr-iiwa-14-r820", &CheckOptions { scene: Some(fume_hood()), ..Default::default() })
            .unwrap();
    let robot = check.robot().clone();
    let mut rng = ChaCha8Rng::seed_from_u64(37);
    let mut placement = check.placement();
    let (mut found, mut free) = (0, 0);
    for case in 0..60 {
        let from: Vec<f64> =
            robot.joints().iter().map(|j| rng.random_range(j.limits.min * 0.8..j.limits.max * 0.8)).collect();
        let to: Vec<f64> = from.iter().map(|x| x + rng.random_range(-0.6..0.6)).collect();
        let contact = check.first_contact_between(&from, &to, &mut placement).unwrap();
        let dense = (0..=400).map(|k| k as f64 / 400.0).find(|&s| {
            check.place(&between(&from, &to, s), &mut placement).unwrap();
            kinema_geometry::collides(check.geometry(), &placement, check.pairs(), 0.0).unwrap().is_some()
        });
        match (contact, dense) {
            (None, Some(s)) => panic!("case {case}: dense sampling collides at {s}, the continuous check found none"),
            (Some(c), Some(s)) => assert!(c.fraction <= s, "case {case}: contact at {} after {s}", c.fraction),
            _ => {}
        }
        if let Some(c) = contact {
            found += 1;
            assert!(clearance(&check, &between(&from, &to, c.fraction), &mut placement) <= CONTACT_TOLERANCE);
        } else {
            free += 1;
        }
    }
    assert!(found > 5 && free > 5, "a mix of cases: {found} with contact, {free} free");
}

/// Two box links swinging in the plane past a box post: near the post's
/// vertical edges parry's own box–box distance overstated the gap (by the
/// post's half height), and the advancement stepped over shallow contacts.
const BOX_ARM: &str = include_str!("../../../kinema/tests/data/box-arm.urdf");

#[test]
fn box_links_past_a_box_post_are_never_found_later_than_by_dense_sampling() {
    let dir = tempfile::tempdir().unwrap();
    let urdf = dir.path().join("box-arm.urdf");
    std::fs::write(&urdf, BOX_ARM).unwrap();
    let scene = dir.path().join("post.toml");
    std::fs::write(&scene, "[[obstacle]]\nname = \"post\"\nbox = [0.1, 0.1, 0.5]\npose = [0.7, 0, 0, 0, 0, 0]\n")
        .unwrap();
    let options = CheckOptions { scene: Some(scene), ..Default::default() };
    let check = CollisionCheck::load(urdf.to_str().unwrap(), &options).unwrap();
    // The segment that once slipped through: 0.1 mm into the post's edge, 7 ‰ along it.
    let (via, end) = ([0.7362723533835728, -1.6080153480763517], [1.0, 0.0]);
    let hit = check.first_contact_between(&via, &end, &mut check.placement()).unwrap();
    assert!(hit.is_some_and(|c| c.fraction < 0.01), "{hit:?}");
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let mut placement = check.placement();
    let (mut hits, mut cases) = (0, 0);
    while cases < 300 {
        let q = |rng: &mut ChaCha8Rng| [rng.random_range(-1.5..1.5), rng.random_range(-2.4..2.4)];
        let (a, b) = (q(&mut rng), q(&mut rng));
        if clearance(&check, &a, &mut placement) <= 0.0 {
            continue;
        }
        cases += 1;
        let first = check.first_contact_between(&a, &b, &mut check.placement()).unwrap().map(|c| c.fraction);
        let sampled = (0..=2000)
            .map(|k| k as f64 / 2000.0)
            .find(|&s| check.first_collision(&between(&a, &b, s)).unwrap().is_some());
        if let Some(s) = sampled {
            hits += 1;
            assert!(
                first.is_some_and(|f| f <= s + 1e-9),
                "case {cases}: sampling hits at {s}, the check says {first:?}"
            );
        }
    }
    assert!(hits > 30, "{hits} colliding segments");
}
