//! The arm by the geometric kernel against the former DH arm solve
//! (`reference.rs`) on seeded random DH arms of the two arrangements the
//! kernel takes: the same solutions with the same labels in the same order,
//! the same refusals word for word, and FK round trips to 1e-9.

use std::f64::consts::PI;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{ArmKind, PieperIk};
use crate::ik::IkSolver;
use crate::math::{Pose, RpyConvention};
use crate::robot::Robot;

/// A random standard- or modified-DH arm with a spherical wrist: the
/// shoulder-plane arrangement (α1 = ±90°, α2 ∈ {0°, 180°}) or the
/// intersecting shoulder (a1 = 0, α1 and α2 anything else), random lengths,
/// offsets and limits (some wider than a turn).
fn random_arm(rng: &mut ChaCha8Rng, k: usize, plane: bool) -> Robot {
    let sign = |rng: &mut ChaCha8Rng| if rng.random_bool(0.5) { 1.0 } else { -1.0 };
    let len = |rng: &mut ChaCha8Rng, zero: f64| if rng.random_bool(zero) { 0.0 } else { rng.random_range(-0.4..0.4) };
    let (a1, alpha1, alpha2) = if plane {
        (len(rng, 0.5), 90.0 * sign(rng), if rng.random_bool(0.5) { 0.0 } else { 180.0 })
    } else {
        let alpha1 = if rng.random_bool(0.5) { 90.0 * sign(rng) } else { rng.random_range(20.0..160.0) * sign(rng) };
        (0.0, alpha1, rng.random_range(15.0..165.0) * sign(rng))
    };
    let a2 = rng.random_range(0.2..0.6) * sign(rng);
    let rows = [
        (rng.random_range(0.0..0.8), a1, alpha1),
        (len(rng, 0.5), a2, alpha2),
        (len(rng, 0.5), len(rng, 0.3), 90.0 * sign(rng)),
        (rng.random_range(0.2..0.6) * sign(rng), 0.0, 90.0 * sign(rng)),
        (0.0, 0.0, 90.0 * sign(rng)),
        (rng.random_range(0.0..0.2), 0.0, 0.0),
    ];
    let modified = rng.random_bool(0.25);
    let convention = if modified { "modified" } else { "standard" };
    let mut t = format!(
        "name = \"arm-{k}\"\nsource = \"random, pieper/tests.rs\"\nconvention = \"{convention}\"\n\
         [units]\nlength = \"m\"\nangle = \"deg\"\n"
    );
    for (i, (d, a, alpha)) in rows.iter().enumerate() {
        // A modified table's row i holds a(i−1), α(i−1): shift the standard a, α down a row.
        let (a, alpha) = if modified {
            if i == 0 {
                (0.0, 0.0)
            } else {
                (rows[i - 1].1, rows[i - 1].2)
            }
        } else {
            (*a, *alpha)
        };
        let offset = if rng.random_bool(0.5) { 0.0 } else { rng.random_range(-180.0..180.0) };
        let lim = if rng.random_bool(0.2) { 270.0 } else { rng.random_range(90.0..180.0) };
        t += &format!(
            "[[joint]]\nname = \"j{i}\"\nd = {d}\na = {a}\nalpha = {alpha}\noffset = {offset}\nmin = -{lim}\nmax = {lim}\n"
        );
    }
    t += "[poses]\nhome = [0, 0, 0, 0, 0, 0]\n";
    Robot::from_toml_str(&t, &format!("arm-{k}.toml")).expect("a valid description")
}

/// Equal angles up to a turn.
fn same_angle(a: f64, b: f64, tol: f64) -> bool {
    let d = (a - b).rem_euclid(2.0 * PI);
    d.min(2.0 * PI - d) <= tol
}

/// Compares the two arm solves at the wrist centre of `target`; returns
/// whether the target was reachable.
fn compare(ik: &PieperIk, target: &Pose, what: &str) -> bool {
    let p = ik.wrist_centre(target);
    match (ik.reference_arm(&p), ik.solve_arm(&p)) {
        (Ok(old), Ok(new)) => {
            let labels = |v: &[([f64; 3], &'static str)]| v.iter().map(|a| a.1).collect::<Vec<_>>();
            assert_eq!(labels(&old), labels(&new), "{what}: {old:?} vs {new:?}");
            for (o, n) in old.iter().zip(&new) {
                assert!((0..3).all(|i| same_angle(o.0[i], n.0[i], 1e-7)), "{what}: {old:?} vs {new:?}");
            }
            true
        }
        (Err(old), Err(new)) => {
            assert_eq!(old.to_string(), new.to_string(), "{what}");
            assert_eq!(std::mem::discriminant(&old), std::mem::discriminant(&new), "{what}");
            false
        }
        (old, new) => panic!("{what}: {old:?} vs {new:?}"),
    }
}

#[test]
fn the_kernel_gives_the_former_solutions_labels_and_refusals() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x6765_6f70);
    let (mut arms, mut reached, mut refused) = (0, 0, 0);
    for k in 0..3000 {
        let plane = k % 2 == 0;
        let robot = random_arm(&mut rng, k, plane);
        let Ok(ik) = PieperIk::new(&robot) else { continue };
        let kind = if plane { ArmKind::ShoulderPlane } else { ArmKind::IntersectingShoulder };
        assert_eq!(ik.arm_kind(), kind, "{}", robot.name());
        arms += 1;
        for j in 0..4 {
            let q = robot.random_q(&mut rng);
            let target = robot.fk(&q).expect("valid q").world_from_tool;
            assert!(compare(&ik, &target, &format!("{} q {q:?}", robot.name())));
            reached += 1;
            let sols = ik.solve(&target).expect("reachable");
            for s in &sols {
                assert!(s.position_error <= 1e-9 && s.orientation_error <= 1e-9, "{}: {s:?}", robot.name());
            }
            assert!(sols.iter().any(|s| s.q.iter().zip(&q).all(|(a, b)| same_angle(*a, *b, 1e-7))), "{}", robot.name());
            // Random poses, many of them out of reach.
            let xyz = [rng.random_range(-1.5..1.5), rng.random_range(-1.5..1.5), rng.random_range(-1.0..2.0)];
            let scale = if j == 3 { 0.05 } else { 1.0 };
            let xyz = xyz.map(|v| v * scale);
            let target = Pose::from_xyz_rpy(xyz, [0.3, -0.2, 1.0], RpyConvention::Zyx);
            refused += usize::from(!compare(&ik, &target, &format!("{} pose {xyz:?}", robot.name())));
        }
    }
    assert!(arms > 2900 && reached > 11000 && refused > 2000, "{arms} arms, {reached} reached, {refused} refused");
}

#[test]
fn the_shoulder_singularity_keeps_both_shoulder_branches() {
    // The PUMA without its lateral offset: the wrist centre on axis 1 leaves
    // q1 free; the right shoulder takes q1 = 0 and the left q1 = π.
    let mut t = String::from(
        "name = \"puma-no-offset\"\nsource = \"pieper/tests.rs\"\nconvention = \"standard\"\n\
         [units]\nlength = \"m\"\nangle = \"deg\"\n",
    );
    let rows = [
        (0.6718, 0.0, 90.0),
        (0.0, 0.4318, 0.0),
        (0.0, 0.0203, -90.0),
        (0.4318, 0.0, 90.0),
        (0.0, 0.0, -90.0),
        (0.0, 0.0, 0.0),
    ];
    for (i, (d, a, alpha)) in rows.iter().enumerate() {
        t += &format!("[[joint]]\nname = \"j{i}\"\nd = {d}\na = {a}\nalpha = {alpha}\nmin = -200\nmax = 200\n");
    }
    t += "[poses]\nhome = [0, 0, 0, 0, 0, 0]\n";
    let robot = Robot::from_toml_str(&t, "puma-no-offset.toml").unwrap();
    let ik = PieperIk::new(&robot).unwrap();
    // q3 with the wrist centre on axis 1 (x = 0 in the arm plane at q1 = 0), by bisection.
    let wc_x = |q3: f64| robot.link_frames(&[0.0, 1.0, q3, 0.3, 0.5, 0.1]).unwrap()[4].pos.x;
    let (mut lo, mut hi) = (0.0, 3.0);
    assert!(wc_x(lo) * wc_x(hi) < 0.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if wc_x(mid) * wc_x(lo) > 0.0 {
            lo = mid
        } else {
            hi = mid
        }
    }
    let q = [0.2, 1.0, lo, 0.3, 0.5, 0.1];
    let target = robot.fk(&q).unwrap().world_from_tool;
    let wc = robot.link_frames(&q).unwrap()[4].pos;
    assert!(wc.x.hypot(wc.y) < 1e-12, "{wc:?}");
    assert!(compare(&ik, &target, "wrist centre on axis 1"));
    let sols = ik.solve(&target).unwrap();
    assert_eq!(sols.len(), 8);
    for s in &sols {
        assert!(s.position_error < 1e-9 && s.orientation_error < 1e-9, "{s:?}");
        let q1 = if s.branch.starts_with("shoulder-right") { 0.0 } else { PI };
        assert!(same_angle(s.q[0], q1, 1e-12), "{s:?}");
    }
}
