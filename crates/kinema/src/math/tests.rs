//! Unit tests of the spatial math and the fast trigonometry.

#[test]
fn atan2_lanes_equal_scalar_atan2_bit_for_bit() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(22);
    let specials = [0.0, -0.0, f64::INFINITY, f64::NEG_INFINITY, f64::NAN, 1e-310, -1e300];
    let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
    for k in 0..200_000 {
        let (mut y, mut x) = ([0.0; 8], [0.0; 8]);
        for i in 0..8 {
            let mag = |rng: &mut rand_chacha::ChaCha8Rng| 10f64.powf(rng.random_range(-8.0..8.0));
            (y[i], x[i]) = (mag(&mut rng), mag(&mut rng));
            match rng.random_range(0..6) {
                0 => y[i] = x[i] * std::f64::consts::FRAC_PI_8.tan() * (1.0 + rng.random_range(-1e-9..1e-9)),
                1 => y[i] = x[i],
                // Every 16th case one lane gets a zero, infinite, NaN or subnormal argument.
                2 if k % 16 == 0 => y[i] = specials[rng.random_range(0..specials.len())],
                3 if k % 16 == 0 => x[i] = specials[rng.random_range(0..specials.len())],
                _ => {}
            }
            if rng.random_bool(0.5) {
                y[i] = -y[i];
            }
            if rng.random_bool(0.5) {
                x[i] = -x[i];
            }
        }
        let (portable, dispatched) = (super::atan2_lanes(y, x), super::atan2_x8(y, x));
        let four = super::atan2_lanes([y[0], y[1], y[2], y[3]], [x[0], x[1], x[2], x[3]]);
        for i in 0..8 {
            let want = super::atan2(y[i], x[i]);
            assert!(same(portable[i], want), "lane {i}: atan2({}, {}) = {} ≠ {want}", y[i], x[i], portable[i]);
            assert!(same(dispatched[i], want), "lane {i}: atan2_x8({}, {}) = {}", y[i], x[i], dispatched[i]);
            if i < 4 {
                assert!(same(four[i], want), "4 lanes, lane {i}");
            }
        }
    }
}

#[test]
fn fast_atan2_matches_the_standard_library() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(21);
    let mut worst = 0.0f64;
    for k in 0..1_000_000 {
        // Random magnitudes over many decades, every sign combination, and
        // ratios near the reduction points tan(π/8) and 1.
        let mag = |rng: &mut rand_chacha::ChaCha8Rng| 10f64.powf(rng.random_range(-8.0..8.0));
        let (mut y, mut x) = (mag(&mut rng), mag(&mut rng));
        match k % 4 {
            0 => y = x * (std::f64::consts::FRAC_PI_8.tan() * (1.0 + rng.random_range(-1e-6..1e-6))),
            1 => y = x * (1.0 + rng.random_range(-1e-6..1e-6)),
            _ => {}
        }
        if rng.random_bool(0.5) {
            y = -y;
        }
        if rng.random_bool(0.5) {
            x = -x;
        }
        let (got, want) = (super::atan2(y, x), y.atan2(x));
        let ulps = (got - want).abs() / (want.abs() * f64::EPSILON).max(f64::MIN_POSITIVE);
        worst = worst.max(ulps);
    }
    assert!(worst <= 2.0, "worst error {worst} ulp");
    for (y, x) in [
        (0.0, 1.0),
        (-0.0, 1.0),
        (0.0, -1.0),
        (-0.0, -1.0),
        (0.0, 0.0),
        (-0.0, -0.0),
        (1.0, 0.0),
        (1.0, -0.0),
        (-1.0, 0.0),
        (f64::INFINITY, 1.0),
        (1.0, f64::NEG_INFINITY),
        (f64::INFINITY, f64::INFINITY),
        (1e-300, 1e300),
        (3.0, 3.0),
        (-2.0, -2.0),
    ] {
        let (got, want) = (super::atan2(y, x), f64::atan2(y, x));
        assert!(
            got == want || (got - want).abs() <= 2.0 * want.abs() * f64::EPSILON,
            "atan2({y}, {x}) = {got}, want {want}"
        );
        assert_eq!(got.is_sign_negative(), want.is_sign_negative(), "atan2({y}, {x})");
    }
    assert!(super::atan2(f64::NAN, 1.0).is_nan() && super::atan2(1.0, f64::NAN).is_nan());
}

#[test]
fn fast_hypot_matches_the_standard_library() {
    for (x, y) in [(3.0, 4.0), (1e-200, 1e-200), (1e200, 1e200), (0.0, 0.0), (-5.0, 12.0), (1e-3, 2e-3)] {
        let (got, want) = (super::hypot(x, y), f64::hypot(x, y));
        assert!((got - want).abs() <= 2.0 * want * f64::EPSILON, "hypot({x}, {y})");
    }
    assert!(super::hypot(f64::NAN, 1.0).is_nan() && super::hypot(f64::INFINITY, 1.0) == f64::INFINITY);
}
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

use super::pose::nearest_rotation;
use super::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[test]
fn fast_sin_cos_matches_std() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let (mut worst, mut worst_ulp): (f64, f64) = (0.0, 0.0);
    for i in 0..2_000_000 {
        let x: f64 = match i % 3 {
            0 => rng.random_range(-10.0..10.0),
            1 => rng.random_range(-1.0e5..1.0e5),
            _ => rng.random_range(-1e-3..1e-3),
        };
        let (s, c) = sin_cos(x);
        let (s0, c0) = x.sin_cos();
        worst = worst.max((s - s0).abs()).max((c - c0).abs());
        for (v, v0) in [(s, s0), (c, c0)] {
            // In ulp of the result, where the result is not tiny (an
            // absolute error near a zero of sin or cos is the argument's).
            if v0.abs() > 1e-3 {
                worst_ulp = worst_ulp.max((v - v0).abs() / (v0.abs() * f64::EPSILON));
            }
        }
    }
    assert!(worst_ulp <= 2.5, "worst error {worst_ulp} ulp");
    // 1e5 * 2^-52 ≈ 2e-11 is the conditioning of the argument itself; we do
    // much better than that thanks to the three-part reduction.
    assert!(worst < 4e-16, "worst abs error {worst}");
    for x in [0.0, -0.0, std::f64::consts::FRAC_PI_2, std::f64::consts::PI, 1e6, -3e7] {
        let (s, c) = sin_cos(x);
        assert!((s - x.sin()).abs() < 1e-15 && (c - x.cos()).abs() < 1e-15, "{x}");
    }
    assert!(sin_cos(f64::NAN).0.is_nan());
    assert!(sin_cos(f64::INFINITY).1.is_nan());
}

#[test]
fn rpy_round_trip_both_conventions() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for conv in [RpyConvention::Zyx, RpyConvention::Xyz] {
        for _ in 0..5000 {
            let t = [rng.random_range(-3.1..3.1), rng.random_range(-1.55..1.55), rng.random_range(-3.1..3.1)];
            let r = rpy_to_rot(t, conv);
            let back = rot_to_rpy(&r, conv);
            for k in 0..3 {
                assert!((back[k] - t[k]).abs() < 1e-9, "{conv:?} {t:?} {back:?}");
            }
        }
    }
}

/// The triple nearest a reference: exact for the rotation, the true
/// triple back where it is the only near one, and never farther than
/// the true triple near the representation singularity.
#[test]
fn rpy_near_is_exact_and_no_farther_than_the_true_triple() {
    let mut rng = ChaCha8Rng::seed_from_u64(40);
    let gap = |t: [f64; 3], n: [f64; 3]| t.iter().zip(n).map(|(x, y)| (x - y) * (x - y)).sum::<f64>();
    for i in 0..20_000 {
        let conv = if i % 2 == 0 { RpyConvention::Xyz } else { RpyConvention::Zyx };
        let pitch = match i % 4 {
            // Away from the singularity, where the true triple is the only near one.
            0 | 1 => {
                let b: f64 = rng.random_range(-1.2..1.2);
                b + if rng.random_bool(0.5) { std::f64::consts::PI } else { 0.0 }
            }
            // Within 1e-5 of it, and on it.
            2 => std::f64::consts::FRAC_PI_2.copysign(rng.random_range(-1.0..1.0)) + rng.random_range(-1e-5..1e-5),
            _ => std::f64::consts::FRAC_PI_2.copysign(rng.random_range(-1.0..1.0)),
        };
        let truth = [rng.random_range(-9.0..9.0), pitch, rng.random_range(-9.0..9.0)];
        let near = truth.map(|x| x + rng.random_range(-0.4..0.4));
        let r = rpy_to_rot(truth, conv);
        let got = rot_to_rpy_near(&r, conv, near);
        assert!((rpy_to_rot(got, conv) - r).amax() < 1e-12, "{conv:?} {truth:?}: {got:?} is another rotation");
        if i % 4 < 2 {
            assert!(gap(got, truth) < 1e-18, "{conv:?} {truth:?} near {near:?}: got {got:?}");
        } else {
            assert!(gap(got, near) <= gap(truth, near) + 1e-12, "{conv:?} {truth:?} near {near:?}: got {got:?}");
        }
    }
}

#[test]
fn rpy_zyx_is_seed000_eq7() {
    // Seed 000 eq. (7), element by element, with α = yaw, β = pitch, γ = roll.
    let (a, b, g): (f64, f64, f64) = (0.3, -0.7, 1.9);
    let (ca, sa, cb, sb, cg, sg) = (a.cos(), a.sin(), b.cos(), b.sin(), g.cos(), g.sin());
    let eq7 = Matrix3::new(
        ca * cb,
        ca * sb * sg - sa * cg,
        ca * cg * sb + sa * sg,
        sa * cb,
        sa * sb * sg + ca * cg,
        sa * cg * sb - ca * sg,
        -sb,
        cb * sg,
        cb * cg,
    );
    assert!((rpy_to_rot([g, b, a], RpyConvention::Zyx) - eq7).norm() < 1e-14);
}

#[test]
fn rpy_singularity_still_reconstructs() {
    for conv in [RpyConvention::Zyx, RpyConvention::Xyz] {
        let r = rpy_to_rot([0.4, std::f64::consts::FRAC_PI_2, -1.0], conv);
        let back = rpy_to_rot(rot_to_rpy(&r, conv), conv);
        assert!((r - back).norm() < 1e-9);
    }
}

#[test]
fn pose_inverse_and_matrix_round_trip() {
    let p = Pose::from_xyz_rpy([0.1, -0.2, 0.3], [0.5, 0.2, -1.0], RpyConvention::Zyx);
    let i = p.mul(&p.inverse());
    assert!((i.rot - Matrix3::identity()).norm() < 1e-14 && i.pos.norm() < 1e-14);
    let back = Pose::from_matrix(&p.to_matrix()).unwrap();
    assert!((back.rot - p.rot).norm() < 1e-14 && (back.pos - p.pos).norm() < 1e-14);
    let mut bad = p.to_matrix();
    bad[(3, 0)] = 1.0;
    assert!(Pose::from_matrix(&bad).is_none());
}

#[test]
fn nearest_rotation_is_the_polar_factor_nalgebra_finds() {
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    for _ in 0..20_000 {
        let rpy = [rng.random_range(-3.0..3.0), rng.random_range(-1.5..1.5), rng.random_range(-3.0..3.0)];
        let exact = rpy_to_rot(rpy, RpyConvention::Zyx);
        // Noise up to the largest departure Pose::from_matrix accepts.
        let scale = 10f64.powf(rng.random_range(-16.0..-6.5));
        let noisy = exact + Matrix3::from_fn(|_, _| rng.random_range(-1.0..1.0)) * scale;
        if (noisy.transpose() * noisy - Matrix3::identity()).norm() > 1e-6 {
            continue;
        }
        let ours = nearest_rotation(noisy);
        let reference = Rotation3::from_matrix(&noisy).into_inner();
        assert!((ours.transpose() * ours - Matrix3::identity()).norm() < 1e-15);
        assert!((ours.determinant() - 1.0).abs() < 1e-15);
        assert!((ours - reference).norm() < 1e-13, "{ours} vs {reference}");
    }
}

#[test]
fn axis_angle_closed_form_matches_quaternion_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let pi = std::f64::consts::PI;
    for i in 0..20_000 {
        let axis = Vector3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
        if axis.norm() < 1e-3 {
            continue;
        }
        let axis = axis.normalize();
        // Angles over the whole range, with many close to 0 and to π.
        let theta = match i % 4 {
            0 => rng.random_range(0.0..pi),
            1 => pi - 10f64.powf(rng.random_range(-12.0..-1.0)),
            2 => 10f64.powf(rng.random_range(-12.0..-1.0)),
            _ => pi,
        };
        let r = Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), theta).into_inner();
        let got = rot_to_axis_angle(&r);
        // Independent reference: nalgebra's quaternion of the same matrix.
        let reference = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r)).scaled_axis();
        assert!((got.norm() - theta).abs() < 1e-9, "θ = {theta}: got angle {}", got.norm());
        // At exactly π the axis sign is arbitrary: both ±u describe R.
        let same = (got - reference).norm() < 1e-7 || (theta > pi - 1e-7 && (got + reference).norm() < 1e-7);
        assert!(same, "θ = {theta}, axis {axis:?}: {got:?} vs {reference:?}");
        assert!((axis_angle_to_rot(&got) - r).norm() < 1e-9);
    }
    assert_eq!(rot_to_axis_angle(&Matrix3::identity()), Vector3::zeros());
}

#[test]
fn pose_error_recovers_small_motion() {
    let a = Pose::from_xyz_rpy([0.1, 0.2, 0.3], [0.1, 0.2, 0.3], RpyConvention::Zyx);
    let w = Vector3::new(0.01, -0.02, 0.005);
    let b = Pose { rot: axis_angle_to_rot(&w) * a.rot, pos: a.pos + Vector3::new(0.001, 0.0, 0.0) };
    let e = pose_error(&b, &a);
    assert!((e.rotation - w).norm() < 1e-12);
    assert!((e.translation - Vector3::new(0.001, 0.0, 0.0)).norm() < 1e-15);
}
