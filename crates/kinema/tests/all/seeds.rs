//! The built-in robots against the closed forms printed in the seed papers.
//!
//! Every expected value here is written out from the paper (equation or table
//! number in each test), not taken from the library.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_6, PI};

use kinema::analysis::{self, Axes};
use kinema::math::{rot_to_rpy, RpyConvention};
use kinema::nalgebra::{Matrix3, Vector3};
use kinema::{Frame, Robot};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Wraps an angle difference into (−π, π].
fn wrap(a: f64) -> f64 {
    let r = a.rem_euclid(2.0 * PI);
    if r > PI {
        r - 2.0 * PI
    } else {
        r
    }
}

/// Seed 000 eq. (3)-(4), written out element by element. `th` are the angles
/// θ1…θ5 as they appear in the paper's equations. Lengths in m.
fn scorbot_eq3_eq4(th: [f64; 5]) -> (Matrix3<f64>, Vector3<f64>) {
    // Tabla I prints cm; the values are mm (see robots/scorbot-er-v-plus.toml).
    let (d1, a1, a2, a3, d5) = (0.349, 0.016, 0.221, 0.221, 0.145);
    let (s1, c1) = th[0].sin_cos();
    let (s2, c2) = th[1].sin_cos();
    let (s5, c5) = th[4].sin_cos();
    let (s23, c23) = (th[1] + th[2]).sin_cos();
    let (s234, c234) = (th[1] + th[2] + th[3]).sin_cos();
    #[rustfmt::skip]
    let r = Matrix3::new(
        s1 * s5 - s234 * c1 * c5,  s1 * c5 + s234 * c1 * s5,  c234 * c1,
        -c1 * s5 - s234 * s1 * c5, s234 * s1 * s5 - c1 * c5,  c234 * s1,
        c234 * c5,                 -c234 * s5,                s234,
    );
    let reach = a1 + a2 * c2 + a3 * c23 + d5 * c234;
    let p = Vector3::new(c1 * reach, s1 * reach, d1 + a2 * s2 + a3 * s23 + d5 * s234);
    (r, p)
}

/// Seed 000 eq. (3)-(4) against the built-in Scorbot at 3000 random
/// configurations.
///
/// Finding (checked numerically, see `scorbot_eq3_uses_joint_value_not_dh_angle`):
/// the θ4 of eq. (3)-(4) is the *joint value* q4, not the DH angle q4 + π/2 of
/// Tabla I. With θ4 = q4 + π/2 substituted, the equations are off by a quarter
/// turn of the wrist. So eq. (3)-(4) hold with θi = qi for all i.
#[test]
fn scorbot_fk_equals_seed000_eq3_eq4() {
    let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0x5c0b);
    for _ in 0..3000 {
        let q = robot.random_q(&mut rng);
        let fk = robot.fk(&q).unwrap();
        let (r, p) = scorbot_eq3_eq4([q[0], q[1], q[2], q[3], q[4]]);
        assert!(
            (fk.world_from_tool.pos - p).norm() < 1e-12,
            "q = {q:?}: position {:?} vs eq. (4) {:?}",
            fk.world_from_tool.pos,
            p
        );
        assert!(
            (fk.world_from_tool.rot - r).norm() < 1e-12,
            "q = {q:?}: rotation {} vs eq. (3) {}",
            fk.world_from_tool.rot,
            r
        );
    }
}

/// The other reading of θ4 (the DH angle q4 + π/2) does not reproduce eq. (3)-(4):
/// this guards the finding documented above.
#[test]
fn scorbot_eq3_uses_joint_value_not_dh_angle() {
    let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let mut mismatches = 0;
    for _ in 0..200 {
        let q = robot.random_q(&mut rng);
        let fk = robot.fk(&q).unwrap();
        let (r, p) = scorbot_eq3_eq4([q[0], q[1], q[2], q[3] + FRAC_PI_2, q[4]]);
        if (fk.world_from_tool.pos - p).norm() > 1e-3 && (fk.world_from_tool.rot - r).norm() > 1e-3 {
            mismatches += 1;
        }
    }
    assert!(mismatches > 190, "{mismatches}");
}

/// Seed 000 eq. (8)-(13): with the tool frame R_h of eq. (9), the
/// roll-pitch-yaw angles of R·R_h (R = Rz(α)·Ry(β)·Rx(γ), eq. 6) are
/// α = θ1, β = −θ234, γ = θ5 (eq. 13).
///
/// Finding: eq. (13) is correct as printed (with θ4 = q4, as for eq. 3), and
/// eq. (12) is the correct product of eq. (3) and eq. (9). It holds for
/// |θ234| < π/2, the range of the representation's middle angle; outside it
/// the same rotation is returned as the equivalent triple
/// (γ + π, π − β, α + π) = (θ5 + π, π + θ234, θ1 + π), which is also checked.
#[test]
fn scorbot_rpy_equals_seed000_eq13() {
    let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
    #[rustfmt::skip]
    let rh = Matrix3::new(
        0.0, 0.0, 1.0,
        0.0, -1.0, 0.0,
        1.0, 0.0, 0.0,
    );
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let (mut inside, mut outside) = (0, 0);
    while inside < 2000 || outside < 500 {
        let q = robot.random_q(&mut rng);
        let th234 = q[1] + q[2] + q[3];
        // Stay away from the representation singularity |β| = π/2.
        if (wrap(th234).abs() - FRAC_PI_2).abs() < 1e-3 {
            continue;
        }
        let r = robot.fk(&q).unwrap().world_from_tool.rot * rh;
        let [roll, pitch, yaw] = rot_to_rpy(&r, RpyConvention::Zyx);
        let (want_roll, want_pitch, want_yaw) = if wrap(th234).abs() < FRAC_PI_2 {
            inside += 1;
            (q[4], -th234, q[0])
        } else {
            // Same rotation, other branch: (γ + π, π − β, α + π).
            outside += 1;
            (q[4] + PI, PI + th234, q[0] + PI)
        };
        for (name, got, want) in [("roll", roll, want_roll), ("pitch", pitch, want_pitch), ("yaw", yaw, want_yaw)] {
            assert!(wrap(got - want).abs() < 1e-9, "q = {q:?}: {name} = {got}, eq. (13) gives {want}");
        }
        assert!(pitch.abs() <= FRAC_PI_2);
    }
}

/// Seed 003 Anexo eq. (1) for the SCARA on a rail, at 3000 configurations.
#[test]
fn scara5_fk_equals_seed003_eq1() {
    let robot = Robot::builtin("scara5").unwrap();
    assert_eq!(robot.joint_types(), "PRRPR");
    let (l1, l2, h1, h2) = (0.35, 0.25, 0.40, 0.10);
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..3000 {
        let q = robot.random_q(&mut rng);
        let fk = robot.fk(&q).unwrap();
        let (s, c) = (q[1] + q[2] + q[4]).sin_cos();
        #[rustfmt::skip]
        let r = Matrix3::new(
            c, -s, 0.0,
            s, c, 0.0,
            0.0, 0.0, 1.0,
        );
        let p = Vector3::new(
            l2 * (q[1] + q[2]).cos() + l1 * q[1].cos(),
            l2 * (q[1] + q[2]).sin() + l1 * q[1].sin() + q[0],
            -h2 - q[3] + h1,
        );
        assert!((fk.world_from_tool.pos - p).norm() < 1e-12, "q = {q:?}");
        assert!((fk.world_from_tool.rot - r).norm() < 1e-12, "q = {q:?}");
    }
}

/// Seed 003 Anexo eq. (2): the Jacobian's translational rows (the paper
/// prints the columns of q1, q2, q3 and q4).
#[test]
fn scara5_jacobian_equals_seed003_eq2() {
    let robot = Robot::builtin("scara5").unwrap();
    let (l1, l2) = (0.35, 0.25);
    let mut rng = ChaCha8Rng::seed_from_u64(33);
    for _ in 0..2000 {
        let q = robot.random_q(&mut rng);
        let j = robot.jacobian(&q, Frame::Base).unwrap();
        let (s2, c2) = q[1].sin_cos();
        let (s23, c23) = (q[1] + q[2]).sin_cos();
        #[rustfmt::skip]
        let eq2 = [
            [0.0, -l2 * s23 - l1 * s2, -l2 * s23, 0.0],
            [1.0, l2 * c23 + l1 * c2, l2 * c23, 0.0],
            [0.0, 0.0, 0.0, -1.0],
        ];
        for (r, row) in eq2.iter().enumerate() {
            for (c, v) in row.iter().enumerate() {
                assert!((j[(r, c)] - v).abs() < 1e-12, "q = {q:?} ({r}, {c})");
            }
        }
    }
}

/// Seed 001 eq. (8): the ROMMEL home pose.
#[test]
fn rommel_home_equals_seed001_eq8() {
    let robot = Robot::builtin("rommel").unwrap();
    let fk = robot.fk(robot.home()).unwrap();
    let p = Vector3::new(-0.05, 0.743, 0.0);
    let r = Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, -1.0));
    assert!((fk.world_from_tool.pos - p).norm() < 1e-12, "{:?}", fk.world_from_tool.pos);
    assert!((fk.world_from_tool.rot - r).norm() < 1e-12, "{}", fk.world_from_tool.rot);
}

/// Eigenvalues of J·Jᵀ, square-rooted and sorted descending: the singular
/// values computed without the library's SVD.
fn sigma_from_jjt(j: &kinema::nalgebra::Matrix6xX<f64>) -> Vec<f64> {
    let jjt = j * j.transpose();
    let mut ev: Vec<f64> = jjt.symmetric_eigen().eigenvalues.iter().map(|v| v.max(0.0).sqrt()).collect();
    ev.sort_by(|a, b| b.total_cmp(a));
    ev
}

/// Seed 004 Cuadro III: rank 5, 5 and 4 at the three singular configurations,
/// Yoshikawa manipulability 0 there; rank 6 at a non-singular configuration.
#[test]
fn iiwa_singularities_of_seed004_cuadro_iii() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    // The configurations printed with Fig. 11, 12, 13.
    let printed: [(&str, [f64; 7], usize); 3] = [
        ("sing-q4", [FRAC_PI_6, FRAC_PI_6, FRAC_PI_6, 0.0, FRAC_PI_6, FRAC_PI_6, FRAC_PI_6], 5),
        ("sing-q2-q3", [FRAC_PI_6, 0.0, FRAC_PI_2, FRAC_PI_6, FRAC_PI_6, FRAC_PI_6, FRAC_PI_6], 5),
        ("sing-coupled", [FRAC_PI_6, 0.0, 0.0, 0.0, 0.0, FRAC_PI_6, 2.0 * FRAC_PI_6], 4),
    ];
    for (name, q_paper, want_rank) in printed {
        let q = robot.pose(name).unwrap();
        for (a, b) in q.iter().zip(q_paper) {
            assert!((a - b).abs() < 1e-14, "pose {name} is not the paper's {q_paper:?}");
        }
        let j = robot.jacobian(q, Frame::Base).unwrap();
        let (rank, _) = analysis::rank(&j, Axes::All, None).unwrap();
        assert_eq!(rank, want_rank, "{name}");
        // Independently: the singular values from the eigenvalues of J·Jᵀ.
        let sigma = sigma_from_jjt(&j);
        let lib = analysis::singular_values(&j, Axes::All).unwrap();
        for (k, (a, b)) in lib.iter().zip(&sigma).enumerate() {
            // Eigenvalues of J·Jᵀ carry an absolute error ~ ε·σmax², so their
            // square roots are accurate to ~1e-8 near zero.
            assert!((a - b).abs() < 1e-7, "{name}: σ{k} {a} vs {b}");
        }
        for (k, s) in lib.iter().enumerate() {
            if k < want_rank {
                assert!(*s > 1e-3, "{name}: σ{k} = {s} should be clearly non-zero");
            } else {
                assert!(*s < 1e-12, "{name}: σ{k} = {s} should be zero");
            }
        }
        let w = analysis::yoshikawa(&j, Axes::All).unwrap();
        assert!(w < 1e-9, "{name}: Yoshikawa {w}");
        // √det(J·Jᵀ) directly.
        let det = (&j * j.transpose()).determinant();
        assert!(det.abs() < 1e-15, "{name}: det(J·Jᵀ) = {det}");
    }

    // A non-singular configuration: full rank, clearly positive manipulability.
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let mut checked = 0;
    while checked < 200 {
        let q = robot.random_q(&mut rng);
        // Keep away from the singular sets of Cuadro III.
        if q[3].abs() < 0.2 || q[1].abs() < 0.2 || q[4].abs() < 0.2 || q[2].abs() < 0.2 {
            continue;
        }
        let j = robot.jacobian(&q, Frame::Base).unwrap();
        let det = (&j * j.transpose()).determinant();
        assert!(det > 0.0);
        let sigma = sigma_from_jjt(&j);
        if sigma[5] < 1e-3 {
            continue; // near some other singularity; not this test's business
        }
        assert_eq!(analysis::rank(&j, Axes::All, None).unwrap().0, 6, "q = {q:?}");
        let w = analysis::yoshikawa(&j, Axes::All).unwrap();
        assert!((w - det.sqrt()).abs() < 1e-9 * det.sqrt().max(1.0), "q = {q:?}");
        checked += 1;
    }
}

/// The iiwa `home` is the arm stretched upright: 0.36 + 0.42 + 0.40 + 0.126 m.
#[test]
fn iiwa_home_is_upright() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let fk = robot.fk(robot.home()).unwrap();
    assert!((fk.world_from_tool.pos - Vector3::new(0.0, 0.0, 1.306)).norm() < 1e-12);
    assert!((fk.world_from_tool.rot - Matrix3::identity()).norm() < 1e-12);
}

/// Seed 004 Cuadro I: the iiwa's position and velocity limits.
#[test]
fn iiwa_limits_equal_seed004_cuadro_i() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let pos = [170.0, 120.0, 170.0, 120.0, 170.0, 120.0, 175.0];
    let vel = [85.0, 85.0, 100.0, 75.0, 130.0, 135.0, 135.0];
    for (k, j) in robot.joints().iter().enumerate() {
        let lim = pos[k] * PI / 180.0;
        assert!((j.limits.max - lim).abs() < 1e-12 && (j.limits.min + lim).abs() < 1e-12);
        assert!((j.limits.vel.unwrap() - vel[k] * PI / 180.0).abs() < 1e-12);
    }
    // And random_q stays inside them.
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for _ in 0..1000 {
        let q = robot.random_q(&mut rng);
        assert!(robot.fk(&q).unwrap().within_limits());
    }
}

/// Seed 001 eq. (5)–(7), the printed closed-form position, contradict eq. (8)
/// and Tabla 1 whatever the link lengths: every term of eq. (6) carries s1, so
/// p_y = 0 at θ1 = 0, where eq. (8) prints p_y = 0.743 m; and eq. (5), (7)
/// depend on θ5, while in Tabla 1 (a4 = 0, d5 = 0) joint 5 turns about an axis
/// through the tool point and joint 4 about one through it too, so the
/// position cannot depend on θ4 or θ5. kinema follows Tabla 1 (with the values
/// corrected to give eq. 8).
#[test]
fn rommel_position_ignores_q4_q5_unlike_seed001_eq5_to_eq7() {
    // Eq. (5)–(7) as printed (the stray "m" of the scan dropped), lengths l1, l2, l3.
    let eq5_7 = |t: [f64; 5], l: [f64; 3]| {
        let (s1, c1) = t[0].sin_cos();
        let (s2, c2) = t[1].sin_cos();
        let (s3, c3) = t[2].sin_cos();
        let (s5, c5) = t[4].sin_cos();
        let [l1, l2, l3] = l;
        let px =
            l3 * s2 * c1 * c3 * c5 - l3 * s5 * c2 * c3 + l3 * s3 * c1 * c2 * c5 + l3 * s2 * s3 * s5 + l2 * s2 * s1 * s5
                - l2 * s5 * c2
                - l1 * c1 * c5;
        let py = -l3 * s1 * s2 * c3 - l3 * s1 * s3 * c2 - l2 * s1 * s2 + l1 * s1;
        let pz = -l3 * s2 * s5 * c1 * c3 - l3 * c2 * c3 * c5 - l3 * s3 * s5 * c1 * c2 + l3 * s2 * s3 * c5
            - l2 * s2 * s5 * c1
            - l2 * c2 * c5
            + l1 * s5 * c1;
        Vector3::new(px, py, pz)
    };
    let robot = Robot::builtin("rommel").unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for _ in 0..200 {
        let l = [rng.random_range(0.01..1.0), rng.random_range(0.01..1.0), rng.random_range(0.01..1.0)];
        // At home eq. (6) gives p_y = 0 for any lengths; eq. (8) prints 0.743 m.
        assert_eq!(eq5_7([0.0; 5], l).y, 0.0);
        // Eq. (5)–(7) move the tool point with θ5; the DH chain does not.
        let q = robot.random_q(&mut rng);
        let mut q5 = q.clone();
        q5[4] += 1.0;
        let mut q4 = q.clone();
        q4[3] -= 0.7;
        let p = robot.fk(&q).unwrap().world_from_tool.pos;
        assert!((robot.fk(&q5).unwrap().world_from_tool.pos - p).norm() < 1e-12);
        assert!((robot.fk(&q4).unwrap().world_from_tool.pos - p).norm() < 1e-12);
        let t = [q[0], q[1], q[2], q[3], q[4]];
        let t5 = [q[0], q[1], q[2], q[3], q[4] + 1.0];
        assert!((eq5_7(t, l) - eq5_7(t5, l)).norm() > 1e-6, "eq. (5)-(7) should depend on θ5 here");
    }
    assert!((robot.fk(robot.home()).unwrap().world_from_tool.pos - Vector3::new(-0.05, 0.743, 0.0)).norm() < 1e-12);
}

/// Seed 004 §VII-B says det J22 "is directly zero" (no orientation
/// singularities). J22 holds the angular rows of joints 5–7, [z5 z6 z7] in any
/// frame, so det J22 = ±sin q6: zero only when axes 5 and 7 line up (q6 = 0).
/// There the 7-joint arm keeps rank 6 (joints 1–4 supply the lost rotation),
/// so the seed's conclusion holds although its determinant does not.
#[test]
fn iiwa_det_j22_is_minus_sin_q6_not_zero() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(22);
    for _ in 0..500 {
        let q = robot.random_q(&mut rng);
        let j = robot.jacobian(&q, Frame::Base).unwrap();
        let j22 = Matrix3::from_fn(|r, c| j[(3 + r, 4 + c)]);
        assert!((j22.determinant() + q[5].sin()).abs() < 1e-12, "q = {q:?}");
    }
    let q = [0.3, 0.5, 0.2, -1.0, 0.4, 0.0, 0.1];
    let j = robot.jacobian(&q, Frame::Base).unwrap();
    assert_eq!(analysis::rank(&j, Axes::All, None).unwrap().0, 6);
}

/// Seed 000 Fig. 2 and Fig. 3 print tool poses (x = 400/600, y = 100, z = 600,
/// "cm", pitch 90°/0°, roll 0) that no configuration reaches, in mm or in cm:
/// the wrist point lies 11.8 cm (Fig. 2) and 7.1 cm (Fig. 3) beyond the
/// shoulder's 0.442 m reach. At Fig. 2's position the largest reachable pitch
/// is 38.0°; with the approach pointing up (pitch −90°) it is reachable, elbow
/// down as the caption says. Fig. 3's position is out of reach at any pitch.
#[test]
fn scorbot_fig2_fig3_poses_are_out_of_reach() {
    use kinema::ik::scorbot::ScorbotIk;
    let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
    let ik = ScorbotIk::new(&robot).unwrap();
    let deg = |d: f64| d.to_radians();
    for scale in [1e-3, 1e-2] {
        assert!(ik.solve_xyz_pitch_roll([400.0 * scale, 100.0 * scale, 600.0 * scale], deg(90.0), 0.0).is_err());
        assert!(ik.solve_xyz_pitch_roll([600.0 * scale, 100.0 * scale, 600.0 * scale], 0.0, 0.0).is_err());
    }
    let fig2 = [0.4, 0.1, 0.6];
    assert!(ik.solve_xyz_pitch_roll(fig2, deg(38.0), 0.0).is_ok());
    assert!(ik.solve_xyz_pitch_roll(fig2, deg(38.1), 0.0).is_err());
    let up = ik.solve_xyz_pitch_roll(fig2, deg(-90.0), 0.0).unwrap();
    assert!(up.iter().any(|s| s.branch == "front/elbow-down" && s.q[2] > 0.0 && robot.limit_flags(&s.q).is_empty()));
    for p in -90..=90 {
        assert!(ik.solve_xyz_pitch_roll([0.6, 0.1, 0.6], deg(p as f64), 0.0).is_err(), "pitch {p}°");
    }
}

/// Seed 004 eq. 30–31 derive the coupled singularity from det(J_ω·J_ωᵀ) = 0,
/// listing seven minors of the 3×7 J_ω (two of them 0). J_ω has 35 maximal
/// minors, none identically zero: three consecutive axes i−1, i, i+1 give
/// ±sin q_i. At the seed's own example (Fig. 13, q6 = π/6) det(J_ω·J_ωᵀ) =
/// 2.25, not 0; the configuration is singular (rank 4, Cuadro III) because
/// axes 1, 3, 5 coincide and joint 6 depends on joints 2 and 4, not because
/// J_ω loses rank.
#[test]
fn iiwa_coupled_singularity_keeps_j_omega_full_rank() {
    let robot = Robot::builtin("lbr-iiwa-14-r820").unwrap();
    let q = robot.pose("sing-coupled").unwrap();
    let j = robot.jacobian(q, Frame::Base).unwrap();
    assert_eq!(analysis::rank(&j, Axes::All, None).unwrap().0, 4);
    let w = kinema::nalgebra::Matrix3xX::from_fn(7, |r, c| j[(3 + r, c)]);
    assert!(((&w * w.transpose()).determinant() - 2.25).abs() < 1e-12);
    let mut rng = ChaCha8Rng::seed_from_u64(30);
    for _ in 0..200 {
        let q = robot.random_q(&mut rng);
        let j = robot.jacobian(&q, Frame::Base).unwrap();
        for i in 1..6 {
            let m = Matrix3::from_fn(|r, c| j[(3 + r, i - 1 + c)]);
            assert!((m.determinant().abs() - q[i].sin().abs()).abs() < 1e-12, "q = {q:?}, axes {i}..{}", i + 2);
        }
    }
}
