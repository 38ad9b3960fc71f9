//! Cartesian motions (seed 004 §VIII-C/D): LIN, CIRC, blending, and their
//! conversion to joint trajectories.
// The seed prints its angles to four decimals (1.5708 for π/2); the tests use
// the printed values.
#![allow(clippy::approx_constant)]

use kinema::ik::family::SelfMotionParameter;
use kinema::ik::iiwa::IiwaIk;
use kinema::ik::IkSolver;
use kinema::math::rot_to_axis_angle;
use kinema::nalgebra::Vector3;
use kinema::traj::self_motion::PARAMETER_ACCELERATION;
use kinema::traj::{
    check, to_joints, Blend, CartesianLimits, CartesianMotion, CheckOptions, JointMethod, Orientation, Profile,
    Segment, SelfMotion, ViolationKind, Waypoint,
};
use kinema::{Pose, Robot, RpyConvention};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn limits() -> CartesianLimits {
    CartesianLimits { vel: 0.2, acc: 0.5, jerk: Some(2.0), rot_vel: 0.5, rot_acc: 1.0, rot_jerk: Some(4.0) }
}

fn random_pose(rng: &mut ChaCha8Rng) -> Pose {
    let xyz = [rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5), rng.random_range(0.0..0.8)];
    let rpy = [rng.random_range(-3.0..3.0), rng.random_range(-1.4..1.4), rng.random_range(-3.0..3.0)];
    Pose::from_xyz_rpy(xyz, rpy, RpyConvention::Zyx)
}

/// Velocities and accelerations of `m` against central differences of its poses and velocities.
fn assert_derivatives_match(m: &CartesianMotion, label: &str) {
    let h = 1e-6;
    let t_end = m.duration();
    for k in 1..200 {
        let t = t_end * k as f64 / 200.0 + 3.7e-7; // off the phase boundaries
        let (a, b, c) = (m.at(t - h), m.at(t), m.at(t + h));
        let v_fd = (c.pose.pos - a.pose.pos) / (2.0 * h);
        let w_fd = rot_to_axis_angle(&(c.pose.rot * a.pose.rot.transpose())) / (2.0 * h);
        let acc_fd = (c.vel - a.vel) / (2.0 * h);
        let alpha_fd = (c.omega - a.omega) / (2.0 * h);
        let tol = |x: &Vector3<f64>| 1e-5 * (1.0 + x.norm());
        assert!((v_fd - b.vel).norm() < tol(&b.vel), "{label} t={t}: v {v_fd} vs {}", b.vel);
        assert!((w_fd - b.omega).norm() < tol(&b.omega), "{label} t={t}: ω {w_fd} vs {}", b.omega);
        assert!((acc_fd - b.acc).norm() < 1e-4 * (1.0 + b.acc.norm()), "{label} t={t}: a {acc_fd} vs {}", b.acc);
        assert!(
            (alpha_fd - b.alpha).norm() < 1e-4 * (1.0 + b.alpha.norm()),
            "{label} t={t}: α {alpha_fd} vs {}",
            b.alpha
        );
    }
}

#[test]
fn segments_velocities_and_accelerations_are_the_derivatives_of_their_poses() {
    let mut rng = ChaCha8Rng::seed_from_u64(41);
    for case in 0..60 {
        let (a, b, c) = (random_pose(&mut rng), random_pose(&mut rng), random_pose(&mut rng));
        let orientation =
            [Orientation::Slerp, Orientation::Rpy(RpyConvention::Zyx), Orientation::Rpy(RpyConvention::Xyz)][case % 3];
        let profile = [Profile::SCurve, Profile::Quintic, Profile::Trapezoid][case % 3];
        let segs = if case % 2 == 0 {
            vec![Segment::lin(&a, &b, orientation).unwrap(), Segment::lin(&b, &c, orientation).unwrap()]
        } else {
            let aux = (a.pos + c.pos) / 2.0 + Vector3::new(0.1, -0.2, 0.15);
            vec![Segment::circ_through(&a, &aux, &c).unwrap()]
        };
        let m = CartesianMotion::new(segs, profile, &limits(), Blend::Deceleration).unwrap();
        assert_derivatives_match(&m, &format!("case {case}"));
        // Exact ends.
        let end = m.at(m.duration()).pose;
        let want = c;
        assert!((end.pos - want.pos).norm() < 1e-12, "case {case}: {}", (end.pos - want.pos).norm());
        assert!(rot_to_axis_angle(&(end.rot * want.rot.transpose())).norm() < 1e-9, "case {case}");
    }
}

#[test]
fn blended_motions_respect_every_limit_and_keep_the_velocity_continuous() {
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    let lim = limits();
    for case in 0..40 {
        let pts: Vec<Pose> = (0..4).map(|_| random_pose(&mut rng)).collect();
        let segs: Vec<Segment> =
            pts.windows(2).map(|w| Segment::lin(&w[0], &w[1], Orientation::Slerp).unwrap()).collect();
        let blend = [Blend::Deceleration, Blend::Time(0.3), Blend::Distance(0.05), Blend::None][case % 4];
        let profile = [Profile::SCurve, Profile::Trapezoid, Profile::Quintic, Profile::Cubic][case / 4 % 4];
        let m = CartesianMotion::new(segs, profile, &lim, blend).unwrap();
        let n = 20_000;
        let mut prev = m.at(0.0);
        for k in 0..=n {
            let t = m.duration() * k as f64 / n as f64;
            let s = m.at(t);
            assert!(s.vel.norm() <= lim.vel * (1.0 + 1e-9), "case {case} t={t}: |v| = {}", s.vel.norm());
            assert!(s.omega.norm() <= lim.rot_vel * (1.0 + 1e-9), "case {case} t={t}: |ω| = {}", s.omega.norm());
            if profile != Profile::Cubic {
                assert!(s.acc.norm() <= lim.acc * (1.0 + 1e-9), "case {case} t={t}: |a| = {}", s.acc.norm());
                assert!(s.alpha.norm() <= lim.rot_acc * (1.0 + 1e-9), "case {case} t={t}: |α| = {}", s.alpha.norm());
            }
            // Continuous velocity: no jump between fine samples.
            let dt = m.duration() / n as f64;
            assert!(
                (s.vel - prev.vel).norm() <= lim.acc * 2.5 * dt + 1e-12 || profile == Profile::Cubic,
                "case {case} t={t}"
            );
            prev = s;
        }
        let end = m.at(m.duration()).pose;
        assert!((end.pos - pts[3].pos).norm() < 1e-12);
        if blend != Blend::None {
            // The corners are cut: the motion is shorter than stopping at every point.
            let stop = CartesianMotion::new(
                pts.windows(2).map(|w| Segment::lin(&w[0], &w[1], Orientation::Slerp).unwrap()).collect(),
                profile,
                &lim,
                Blend::None,
            )
            .unwrap();
            assert!(m.duration() <= stop.duration() + 1e-12, "case {case}: {} vs {}", m.duration(), stop.duration());
        }
    }
}

#[test]
fn circ_through_an_auxiliary_point() {
    let r = kinema::math::rot_y(std::f64::consts::FRAC_PI_2);
    let a = Pose::new(r, Vector3::new(0.5, -0.2, 0.4));
    let aux = Vector3::new(0.5, 0.0, 0.6);
    let b = Pose::new(r, Vector3::new(0.5, 0.2, 0.4));
    let seg = Segment::circ_through(&a, &aux, &b).unwrap();
    // The circle through the three points: centre (0.5, 0, 0.4), radius 0.2.
    let (len, rot) = seg.lengths();
    assert!((len - std::f64::consts::PI * 0.2).abs() < 1e-12, "{len}"); // a half circle of radius 0.2
    assert_eq!(rot, 0.0);
    let closest = (0..=1000).map(|k| (seg.pose(k as f64 / 1000.0).pos - aux).norm()).fold(f64::INFINITY, f64::min);
    assert!(closest < 1e-3, "{closest}");
    assert!((seg.pose(0.5).pos - aux).norm() < 1e-12);
    for k in 0..=100 {
        let p = seg.pose(k as f64 / 100.0).pos;
        assert!(((p - Vector3::new(0.5, 0.0, 0.4)).norm() - 0.2).abs() < 1e-12);
    }
    let line = Segment::circ_through(&a, &Vector3::new(0.5, 0.0, 0.4), &b).unwrap_err().to_string();
    assert!(line.contains("line"), "{line}");
    assert!(Segment::circ_through(&a, &Vector3::new(f64::NAN, 0.0, 0.0), &b).is_err());
}

#[test]
fn circ_about_a_centre_frame_as_in_seed_004() {
    let centre = Pose::new(kinema::math::rot_x(0.3), Vector3::new(0.5, 0.0, 0.5));
    let start = centre.transform_point(&Vector3::new(0.1, 0.0, 0.0));
    let rot = kinema::math::rot_y(1.0);
    let seg = Segment::circ_about(&centre, &start, std::f64::consts::PI, &rot).unwrap();
    let end = seg.end().pos;
    assert!((end - centre.transform_point(&Vector3::new(-0.1, 0.0, 0.0))).norm() < 1e-12);
    let quarter = seg.pose(0.5).pos;
    assert!((quarter - centre.transform_point(&Vector3::new(0.0, 0.1, 0.0))).norm() < 1e-12);
    assert!((seg.pose(0.3).rot - rot).norm() < 1e-12);
    let back = Segment::circ_about(&centre, &start, -std::f64::consts::FRAC_PI_2, &rot).unwrap();
    assert!((back.end().pos - centre.transform_point(&Vector3::new(0.0, -0.1, 0.0))).norm() < 1e-12);
    let off = centre.transform_point(&Vector3::new(0.1, 0.0, 0.05));
    assert!(Segment::circ_about(&centre, &off, 1.0, &rot).unwrap_err().to_string().contains("plane"));
}

fn iiwa() -> Robot {
    Robot::builtin("lbr-iiwa-14-r820").unwrap()
}

/// Seed 004 §VIII-C1's LIN: Φ in Corke's Rx·Ry·Rz convention (SEED-NOTES).
fn seed_lin(orientation: Orientation) -> (CartesianMotion, Pose) {
    let a = Pose::from_xyz_rpy([0.7373, -0.3271, 0.7325], [-0.6595, 1.4584, 1.2113], RpyConvention::Xyz);
    let b = Pose::from_xyz_rpy([0.6, -0.6, 0.3], [0.0, 1.5708, 0.0], RpyConvention::Xyz);
    let seg = Segment::lin(&a, &b, orientation).unwrap();
    (CartesianMotion::new(vec![seg], Profile::Trapezoid, &limits(), Blend::None).unwrap(), a)
}

/// Every sample of `traj` on the path of `m`, within 1e-6 m / 1e-6 rad.
fn assert_on_path(robot: &Robot, m: &CartesianMotion, traj: &kinema::traj::JointTrajectory) {
    for k in 0..traj.len() {
        let p = robot.fk(traj.q(k)).unwrap().world_from_tool;
        let want = m.at(traj.times()[k]).pose;
        assert!((p.pos - want.pos).norm() < 1e-6 && rot_to_axis_angle(&(p.rot * want.rot.transpose())).norm() < 1e-6);
    }
}

#[test]
fn seed_lin_example_within_cuadro_i() {
    let robot = iiwa();
    let (m, a) = seed_lin(Orientation::Slerp);
    let ik = IiwaIk::new(&robot).unwrap();
    let q0 = ik.solve_within_limits(&a).unwrap()[0].q.clone();
    // The default holds q3 at its start value; the seed's rule steers it.
    for policy in [SelfMotion::Auto, SelfMotion::Manipulability, SelfMotion::AvoidLimits, SelfMotion::Track] {
        let traj = to_joints(&robot, &m, &q0, 0.01, JointMethod::Ik(policy.clone())).unwrap();
        let report = check(&robot, &traj, &CheckOptions::default()).unwrap();
        assert!(report.violations.is_empty(), "{policy}: {}", report.violations[0]);
        assert_on_path(&robot, &m, &traj);
        let q3: Vec<f64> = (0..traj.len()).map(|k| traj.q(k)[2]).collect();
        let drift = q3.iter().map(|v| (v - q0[2]).abs()).fold(0.0, f64::max);
        match policy {
            SelfMotion::Auto => assert!(drift < 1e-12, "q3 held: drifted by {drift}"),
            SelfMotion::Manipulability | SelfMotion::AvoidLimits => {
                assert!(drift > 1e-3, "{policy}: q3 never moved");
                // q3 turns smoothly: its rate changes by at most
                // PARAMETER_ACCELERATION between decisions (the seed's greedy
                // rule alone reversed q3 at full speed, 131 rad/s²).
                let worst = (0..traj.len()).map(|k| traj.qdd(k)[2].abs()).fold(0.0, f64::max);
                assert!(worst <= 2.5 * PARAMETER_ACCELERATION, "{policy}: q̈3 up to {worst} rad/s²");
            }
            _ => {}
        }
    }
    // Resolved rate follows the same line (damped, with error feedback).
    let rr = to_joints(&robot, &m, &q0, 0.01, JointMethod::ResolvedRate { damping: 0.01, gain: 0.5 }).unwrap();
    let worst = (0..rr.len())
        .map(|k| (robot.fk(rr.q(k)).unwrap().world_from_tool.pos - m.at(rr.times()[k]).pose.pos).norm())
        .fold(0.0, f64::max);
    assert!(worst < 1e-3, "{worst}");
}

/// The rotation angle \[rad\] the tool turns through along `m` (2000 steps).
fn rotation_path(m: &CartesianMotion) -> f64 {
    let poses: Vec<Pose> = (0..=2000).map(|k| m.at(m.duration() * k as f64 / 2000.0).pose).collect();
    poses.windows(2).map(|w| rot_to_axis_angle(&(w[1].rot * w[0].rot.transpose())).norm()).sum()
}

/// The seed's LIN with eq. 40's roll-pitch-yaw interpolation in its own
/// convention (Rx·Ry·Rz), the triples interpolated as printed. The end pitch
/// 1.5708 lies 3.7e-6 rad past π/2; reading the triple back from the matrix
/// gives (±π, 1.5707927, ±π), and interpolating towards that one turned the
/// tool 6.8 rad. As printed, the tool turns 0.566 rad (net 0.563), and with
/// q3 held (the default) the 3.05 s motion stays below 40 % of Cuadro I from
/// every branch at q3 = 0. Built from poses alone, the start's triple is
/// read nearest the end's and the path is the same.
#[test]
fn seed_rpy_lin_runs_by_default_from_every_branch() {
    let robot = iiwa();
    let conv = RpyConvention::Xyz;
    let from = Waypoint::from_xyz_rpy([0.7373, -0.3271, 0.7325], [-0.6595, 1.4584, 1.2113], conv);
    let to = Waypoint::from_xyz_rpy([0.6, -0.6, 0.3], [0.0, 1.5708, 0.0], conv);
    let seg = Segment::lin_between(&from, &to, Orientation::Rpy(conv)).unwrap();
    let m = CartesianMotion::new(vec![seg], Profile::Trapezoid, &limits(), Blend::None).unwrap();
    let turn = rotation_path(&m);
    assert!((turn - 0.566).abs() < 0.002, "the tool turns {turn} rad");
    let net = rot_to_axis_angle(&(to.pose().rot * from.pose().rot.transpose())).norm();
    assert!((net - 0.563).abs() < 0.001, "net turn {net}");
    assert!((m.duration() - 3.05).abs() < 0.01, "{}", m.duration());
    let (from_poses, a) = seed_lin(Orientation::Rpy(conv));
    for k in 0..=100 {
        let t = m.duration() * k as f64 / 100.0;
        let (p, q) = (m.at(t).pose, from_poses.at(t).pose);
        assert!((p.pos - q.pos).norm() < 1e-12 && (p.rot - q.rot).amax() < 1e-9, "the paths part at t = {t}");
    }
    let ik = IiwaIk::new(&robot).unwrap();
    let starts: Vec<Vec<f64>> =
        ik.solve_q3(&a, 0.0).unwrap().into_iter().filter(|s| s.within_limits()).map(|s| s.q).collect();
    assert_eq!(starts.len(), 6);
    for q0 in &starts {
        let traj = to_joints(&robot, &m, q0, 0.01, JointMethod::default()).unwrap();
        let report = check(&robot, &traj, &CheckOptions::default()).unwrap();
        assert!(report.violations.is_empty(), "{}", report.violations[0]);
        assert_on_path(&robot, &m, &traj);
        assert!((0..traj.len()).all(|k| traj.q(k)[2].abs() < 1e-12), "q3 was not held at 0");
        let peak =
            report.peak_vel.iter().zip(robot.joints()).map(|(v, j)| v / j.limits.vel.unwrap()).fold(0.0, f64::max);
        assert!(peak < 0.4, "peak joint speed {peak:.3} of its limit");
    }
    // The same two poses with ZYX angles turn the tool by 0.76 rad.
    let (zyx, _) = seed_lin(Orientation::Rpy(RpyConvention::Zyx));
    assert!(rotation_path(&zyx) < 0.8);
    for q0 in &starts {
        let traj = to_joints(&robot, &zyx, q0, 0.01, JointMethod::default()).unwrap();
        let report = check(&robot, &traj, &CheckOptions::default()).unwrap();
        assert!(report.violations.is_empty(), "{}", report.violations[0]);
        assert_on_path(&robot, &zyx, &traj);
    }
}

/// Eq. 40 between a pose read from joints and a written triple never turns
/// the tool much farther than SLERP does between the same two poses: the
/// start's triple is the one nearest the end's (seeded poses, both
/// conventions, pitches near and on ±π/2 included).
#[test]
fn rpy_lin_from_a_pose_takes_the_near_triple() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x40);
    for i in 0..400 {
        let conv = if i % 2 == 0 { RpyConvention::Xyz } else { RpyConvention::Zyx };
        let mut rpy = |pitch: f64| [rng.random_range(-3.0..3.0), pitch, rng.random_range(-3.0..3.0)];
        let near_pole = std::f64::consts::FRAC_PI_2 + [0.0, 3.7e-6, -1e-9, 0.2][i % 4];
        let end = rpy(if i % 8 < 4 { near_pole } else { -near_pole });
        let start = end.map(|x| x + 0.3);
        let a = Pose::from_xyz_rpy([0.5, 0.0, 0.5], start, conv);
        let b = Waypoint::from_xyz_rpy([0.5, 0.1, 0.4], end, conv);
        let seg = Segment::lin_between(&Waypoint::from(a), &b, Orientation::Rpy(conv)).unwrap();
        let m = CartesianMotion::new(vec![seg], Profile::Trapezoid, &limits(), Blend::None).unwrap();
        // The written start triple is 0.3 rad from the end's in each angle:
        // the nearest one cannot turn the tool more than 3 × 0.3 rad.
        let turn = rotation_path(&m);
        assert!(turn < 0.9 + 1e-6, "{conv:?} {end:?}: the tool turns {turn} rad");
        assert!((m.at(m.duration()).pose.rot - b.pose().rot).amax() < 1e-12);
        assert!((m.at(0.0).pose.rot - a.rot).amax() < 1e-12);
    }
}

/// On a URDF iiwa (the geometric solver, no DH table) a held ψ holds along
/// a seeded LIN, each sample on the path; q3 moves meanwhile.
#[test]
fn a_held_arm_angle_holds_on_a_urdf_iiwa() {
    let robot = Robot::from_file(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/iiwa14.urdf"), None).unwrap();
    let ik = kinema::ik::geo::SrsIk::new(&robot).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(0x5135);
    let q0: Vec<f64> = [0.3, 0.7, -0.4, -1.3, 0.4, 0.9, 0.1].iter().map(|v| v + rng.random_range(-0.1..0.1)).collect();
    let a = robot.fk(&q0).unwrap().world_from_tool;
    let shift = Vector3::new(rng.random_range(-0.1..0.1), rng.random_range(-0.1..0.1), rng.random_range(-0.1..0.1));
    let b = Pose::new(a.rot, a.pos + shift);
    let m = lin_motion(&a, &b);
    let psi0 = ik.psi_of(&q0);
    for value in [Some(psi0), None] {
        let by_psi = SelfMotion::Fixed { parameter: SelfMotionParameter::ArmAngle, value };
        let traj = to_joints(&robot, &m, &q0, 0.01, JointMethod::Ik(by_psi)).unwrap();
        let worst = (0..traj.len()).map(|k| (ik.psi_of(traj.q(k)) - psi0).abs()).fold(0.0, f64::max);
        assert!(worst < 1e-9, "ψ drifted by {worst}");
        assert_on_path(&robot, &m, &traj);
        let q3_moved = (0..traj.len()).map(|k| (traj.q(k)[2] - q0[2]).abs()).fold(0.0, f64::max);
        assert!(q3_moved > 1e-4, "q3 moved only {q3_moved}");
        let report = check(&robot, &traj, &CheckOptions::default()).unwrap();
        assert!(report.violations.is_empty(), "{}", report.violations[0]);
    }
    let other = SelfMotion::Fixed { parameter: SelfMotionParameter::ArmAngle, value: Some(psi0 + 0.5) };
    let e = to_joints(&robot, &m, &q0, 0.01, JointMethod::Ik(other)).unwrap_err().to_string();
    assert!(e.contains("psi ="), "{e}");
}

/// A fixed q3 or ψ holds along the whole path; a start configuration with
/// another value is refused, naming both.
#[test]
fn a_fixed_parameter_holds_along_the_path() {
    let robot = iiwa();
    let (m, a) = seed_lin(Orientation::Slerp);
    let ik = IiwaIk::new(&robot).unwrap();
    let q0 = ik.solve_q3(&a, 0.4).unwrap().into_iter().find(|s| s.within_limits()).unwrap().q;
    let fixed = SelfMotion::Fixed { parameter: SelfMotionParameter::Q3, value: Some(0.4) };
    let traj = to_joints(&robot, &m, &q0, 0.01, JointMethod::Ik(fixed)).unwrap();
    assert!((0..traj.len()).all(|k| (traj.q(k)[2] - 0.4).abs() < 1e-12));
    assert_on_path(&robot, &m, &traj);
    let psi0 = ik.psi_of(&q0);
    let by_psi = SelfMotion::Fixed { parameter: SelfMotionParameter::ArmAngle, value: Some(psi0) };
    let traj = to_joints(&robot, &m, &q0, 0.01, JointMethod::Ik(by_psi)).unwrap();
    let worst = (0..traj.len()).map(|k| (ik.psi_of(traj.q(k)) - psi0).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-9, "ψ drifted by {worst}");
    assert_on_path(&robot, &m, &traj);
    let e = to_joints(
        &robot,
        &m,
        &q0,
        0.01,
        JointMethod::Ik(SelfMotion::Fixed { parameter: SelfMotionParameter::Q3, value: Some(0.1) }),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("q3 = 0.4") && e.contains("0.1"), "{e}");
    // A parameter no family has is refused when it is read, naming the ones there are.
    let e = "q5".parse::<SelfMotionParameter>().unwrap_err().to_string();
    assert!(e.contains("q5") && e.contains("q3, psi"), "{e}");
    // A six-joint arm has no self-motion to choose.
    let puma = Robot::builtin("puma560").unwrap();
    let q = [0.3, 0.6, -2.5, 0.2, 0.8, 0.9];
    let p = puma.fk(&q).unwrap().world_from_tool;
    let line = CartesianMotion::new(
        vec![Segment::lin(&p, &Pose::new(p.rot, p.pos + Vector3::new(0.05, 0.0, 0.0)), Orientation::Slerp).unwrap()],
        Profile::Trapezoid,
        &limits(),
        Blend::None,
    )
    .unwrap();
    let e = to_joints(&puma, &line, &q, 0.01, JointMethod::Ik(SelfMotion::Hold)).unwrap_err().to_string();
    assert!(e.contains("no self-motion"), "{e}");
}

#[test]
fn seed_continuous_lin_reports_or_avoids_the_wrist_flip() {
    // Seed 004 §VIII-C2: (0.6, −0.6, 0.1) → (0.6, −0.6, 0.3) → (0.6, 0, 0.2), Φ = (0, π/2, 0).
    let robot = iiwa();
    let r = kinema::math::rpy_to_rot([0.0, 1.5708, 0.0], RpyConvention::Xyz);
    let p = |x, y, z| Pose::new(r, Vector3::new(x, y, z));
    let (p0, p1, p2) = (p(0.6, -0.6, 0.1), p(0.6, -0.6, 0.3), p(0.6, 0.0, 0.2));
    let segs =
        vec![Segment::lin(&p0, &p1, Orientation::Slerp).unwrap(), Segment::lin(&p1, &p2, Orientation::Slerp).unwrap()];
    // The corner turns by ~99°: the trapezoid's constant accelerations cannot
    // blend it without exceeding a_max, the S-curve's ramps can.
    let trapezoid = CartesianMotion::new(segs.clone(), Profile::Trapezoid, &limits(), Blend::Deceleration).unwrap();
    assert_eq!(trapezoid.blend_times(), [0.0]);
    let m = CartesianMotion::new(segs, Profile::SCurve, &limits(), Blend::Deceleration).unwrap();
    assert!(m.blend_times()[0] > 0.1, "{:?}", m.blend_times());
    assert!(m.segment_starts()[1] < m.laws()[0].duration(), "the second segment starts before the first ends");
    let ik = IiwaIk::new(&robot).unwrap();
    // From the first within-limit solution with q3 = 0 the path cannot be
    // followed without a wrist flip (q3 held, joint 7 meets its limit; the
    // seed's rule crosses the wrist singularity the seed saw at t ≈ 3.25 s):
    // the check names the joint and the time.
    let q_a = ik.solve_within_limits(&p0).unwrap()[0].q.clone();
    let traj = to_joints(&robot, &m, &q_a, 0.01, JointMethod::default()).unwrap();
    let report = check(&robot, &traj, &CheckOptions::default()).unwrap();
    let v = report.violations.iter().find(|v| v.kind == ViolationKind::Velocity).expect("a velocity violation");
    assert!(v.joint.is_some() && v.time > 1.0 && v.time < m.duration());
    // With the elbow turned (q3 = −2.4) and q3 steered by seed 004's rule
    // the same path stays within Cuadro I's velocities; held at −2.4, joint
    // limits stop it.
    let q_b = ik.solve_q3(&p0, -2.4).unwrap().into_iter().find(|s| s.within_limits()).unwrap().q;
    let e = to_joints(&robot, &m, &q_b, 0.01, JointMethod::Ik(SelfMotion::Hold)).unwrap_err().to_string();
    assert!(e.contains("joint limit") && e.contains("q3 held at -2.4"), "{e}");
    let rule = to_joints(&robot, &m, &q_b, 0.01, JointMethod::Ik(SelfMotion::Manipulability)).unwrap();
    let cuadro_i = CheckOptions { acc: Some(vec![f64::INFINITY]), ..CheckOptions::default() };
    let report = check(&robot, &rule, &cuadro_i).unwrap();
    assert!(report.violations.is_empty(), "{}", report.violations[0]);
    // But the rule's turns of q3 ask joints 3 and 5 for over 100 rad/s², far
    // beyond the iiwa's (estimated) acceleration limits: the check refuses
    // the path, and the default, which takes the rule only when it passes,
    // reports the held path's joint limit.
    let report = check(&robot, &rule, &CheckOptions::default()).unwrap();
    let peak = report.peak_acc[2].max(report.peak_acc[4]);
    assert!(peak > 100.0 && report.violations.iter().any(|v| v.kind == ViolationKind::Acceleration), "{peak}");
    let e = to_joints(&robot, &m, &q_b, 0.01, JointMethod::default()).unwrap_err().to_string();
    assert!(e.contains("q3 held at -2.4"), "{e}");
}

#[test]
fn resampling_keeps_consecutive_poses_within_the_step() {
    let mut rng = ChaCha8Rng::seed_from_u64(43);
    // A centimetre (seed 000's controller) and finer steps down to 20 µm, where one of the
    // 20 000 coarse steps of a path spans several samples: no gap of two or more
    // steps may be left without an error.
    for case in 0..30 {
        let (step, angle) = if case < 10 {
            (0.01, 0.05)
        } else {
            (10f64.powf(rng.random_range(-4.7..-2.0)), 10f64.powf(rng.random_range(-3.5..-1.0)))
        };
        let pts: Vec<Pose> = (0..3).map(|_| random_pose(&mut rng)).collect();
        let segs = pts.windows(2).map(|w| Segment::lin(&w[0], &w[1], Orientation::Slerp).unwrap()).collect();
        let m = CartesianMotion::new(segs, Profile::SCurve, &limits(), Blend::Deceleration).unwrap();
        let times = m.resample_times(step, angle).unwrap();
        assert_eq!(times[0], 0.0);
        assert_eq!(*times.last().unwrap(), m.duration());
        for w in times.windows(2) {
            assert!(w[1] > w[0]);
            let (a, b) = (m.at(w[0]).pose, m.at(w[1]).pose);
            assert!((a.pos - b.pos).norm() <= step * (1.0 + 1e-9), "case {case}: {} > {step}", (a.pos - b.pos).norm());
            let turn = rot_to_axis_angle(&(a.rot * b.rot.transpose())).norm();
            assert!(turn <= angle * (1.0 + 1e-9), "case {case}: {turn} > {angle}");
        }
        // Not needlessly fine: every step but the last reaches the step or the angle.
        for w in times[..times.len() - 1].windows(2) {
            let (a, b) = (m.at(w[0]).pose, m.at(w[1]).pose);
            let used =
                ((a.pos - b.pos).norm() / step).max(rot_to_axis_angle(&(a.rot * b.rot.transpose())).norm() / angle);
            assert!(used > 0.99, "case {case}: {used}");
        }
    }
    assert!(CartesianMotion::new(vec![], Profile::SCurve, &limits(), Blend::None).is_err());
}

/// A step far too small for the path is refused at once, with the count it would take,
/// from the path's length and turn (it bisected up to the cap first, for minutes).
#[test]
fn resampling_refuses_a_step_too_small_for_the_path_before_sampling_it() {
    let a = Pose::from_xyz_rpy([0.5, 0.0, 0.5], [0.0, 0.0, 0.0], RpyConvention::Zyx);
    let b = Pose::from_xyz_rpy([0.5, 0.5, 0.5], [0.0, 0.0, 0.0], RpyConvention::Zyx);
    let turned = Pose::from_xyz_rpy([0.5, 0.5, 0.5], [std::f64::consts::FRAC_PI_2, 0.0, 0.0], RpyConvention::Zyx);
    let motion = |p: &Pose, q: &Pose| {
        CartesianMotion::new(
            vec![Segment::lin(p, q, Orientation::Slerp).unwrap()],
            Profile::Trapezoid,
            &limits(),
            Blend::None,
        )
        .unwrap()
    };
    let line = motion(&a, &b);
    let e = line.resample_times(1e-9, 1.0).unwrap_err().to_string();
    assert!(e.contains("into about 5.000e8 samples (at most 10000000)"), "{e}");
    assert!(e.starts_with("invalid `max_step`"), "{e}");
    let e = line.resample_times(5e-324, 1.0).unwrap_err().to_string();
    assert!(e.contains("into more than 10^308 samples"), "{e}");
    let turn = motion(&b, &turned);
    let e = turn.resample_times(1.0, 1e-9).unwrap_err().to_string();
    assert!(e.contains("into about 1.571e9 samples"), "{e}");
    assert!(e.starts_with("invalid `max_angle`"), "{e}");
    // Within the cap the same paths split as the limits say: 500 steps, and a sliver more
    // when each bisection stops a hair short of its step.
    assert!((501..=502).contains(&line.resample_times(0.001, 1.0).unwrap().len()));
    assert!((101..=102).contains(&turn.resample_times(1.0, std::f64::consts::FRAC_PI_2 / 100.0).unwrap().len()));
    for step in [0.0, -1.0, f64::NAN] {
        assert!(line.resample_times(step, 0.1).is_err(), "{step}");
        assert!(line.resample_times(0.1, step).is_err(), "{step}");
    }
}

#[test]
fn bad_cartesian_input_gives_clear_errors() {
    let a = Pose::from_xyz_rpy([0.5, 0.0, 0.5], [0.0, 0.0, 0.0], RpyConvention::Zyx);
    let b = Pose::from_xyz_rpy([0.6, 0.0, 0.5], [0.0, 0.0, 0.0], RpyConvention::Zyx);
    let c = Pose::from_xyz_rpy([0.7, 0.1, 0.5], [0.0, 0.0, 0.0], RpyConvention::Zyx);
    let mut nan = a;
    nan.pos.x = f64::NAN;
    assert!(Segment::lin(&nan, &b, Orientation::Slerp).is_err());
    // Segments that do not join.
    let e = CartesianMotion::new(
        vec![Segment::lin(&a, &b, Orientation::Slerp).unwrap(), Segment::lin(&c, &a, Orientation::Slerp).unwrap()],
        Profile::Trapezoid,
        &limits(),
        Blend::None,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("segment 2") && e.contains("segment 1"), "{e}");
    let mut l = limits();
    l.vel = 0.0;
    assert!(CartesianMotion::new(
        vec![Segment::lin(&a, &b, Orientation::Slerp).unwrap()],
        Profile::Trapezoid,
        &l,
        Blend::None
    )
    .is_err());
    let mut l = limits();
    l.jerk = None;
    l.rot_jerk = None;
    assert!(CartesianMotion::new(
        vec![Segment::lin(&a, &b, Orientation::Slerp).unwrap()],
        Profile::SCurve,
        &l,
        Blend::None
    )
    .is_err());
    // A start configuration that is not at the start pose.
    let robot = iiwa();
    let m = lin_motion(&a, &b);
    let e = to_joints(&robot, &m, robot.home(), 0.01, JointMethod::default()).unwrap_err().to_string();
    assert!(e.contains("start pose"), "{e}");
    // An unreachable path: the error says when.
    let far = Pose::from_xyz_rpy([2.0, 0.0, 0.5], [0.0, 0.0, 0.0], RpyConvention::Zyx);
    let start = Pose::from_xyz_rpy([0.5, 0.0, 0.5], [0.0, std::f64::consts::PI, 0.0], RpyConvention::Zyx);
    let far = Pose::new(start.rot, far.pos);
    let q0 = IiwaIk::new(&robot).unwrap().solve_within_limits(&start).unwrap()[0].q.clone();
    let m = lin_motion(&start, &far);
    let e = to_joints(&robot, &m, &q0, 0.05, JointMethod::default()).unwrap_err().to_string();
    assert!(e.contains("at t = "), "{e}");
    // The time as context, the solver named as a solver (once read "(iiwa, at t = … of the path solver)").
    assert!(e.starts_with("at t = "), "{e}");
    assert!(e.contains(" s of the path: unreachable target (iiwa solver): "), "{e}");
}

/// One straight SLERP segment from `a` to `b`, trapezoid law, the test limits, no blending.
fn lin_motion(a: &Pose, b: &Pose) -> CartesianMotion {
    CartesianMotion::new(
        vec![Segment::lin(a, b, Orientation::Slerp).unwrap()],
        Profile::Trapezoid,
        &limits(),
        Blend::None,
    )
    .unwrap()
}

/// The largest |a|, |ω| and |α| of `m` relative to `limits`, on a fine grid.
fn sampled_ratios(m: &CartesianMotion, limits: &CartesianLimits) -> [f64; 4] {
    let mut worst = [0.0f64; 4];
    for k in 0..=4000 {
        let st = m.at(m.duration() * k as f64 / 4000.0);
        let r = [
            st.vel.norm() / limits.vel,
            st.acc.norm() / limits.acc,
            st.omega.norm() / limits.rot_vel,
            st.alpha.norm() / limits.rot_acc,
        ];
        for (w, v) in worst.iter_mut().zip(r) {
            *w = w.max(v);
        }
    }
    worst
}

/// CIRC's law used to ignore the centripetal acceleration v²/r (the tool's
/// acceleration reached 2–3× amax on 1–3 cm arcs), and RPY interpolation
/// bounded each angle's rate (|ω| reached 1.45× rot_vmax). The real vectors
/// are now within the limits, and the arcs are not slowed down needlessly:
/// with the trapezoid (no jerk limit) the tool's acceleration or speed
/// reaches its limit within 1 %.
#[test]
fn the_tools_real_acceleration_and_angular_speed_stay_within_the_limits() {
    let mut rng = ChaCha8Rng::seed_from_u64(25);
    let limits = limits();
    for case in 0..120 {
        let profile = [Profile::Trapezoid, Profile::SCurve, Profile::Quintic][case % 3];
        let (m, label) = if case % 2 == 0 {
            let r = [0.01, 0.02, 0.03, 0.2][case / 2 % 4];
            let centre = random_pose(&mut rng);
            let start = centre.transform_point(&Vector3::new(r, 0.0, 0.0));
            let angle = rng.random_range(0.3..6.0);
            let seg = Segment::circ_about(&centre, &start, angle, &centre.rot).unwrap();
            (CartesianMotion::new(vec![seg], profile, &limits, Blend::None).unwrap(), format!("arc r {r} φ {angle:.2}"))
        } else {
            let conv = [RpyConvention::Zyx, RpyConvention::Xyz][case / 2 % 2];
            let (a, b) = (random_pose(&mut rng), random_pose(&mut rng));
            let seg = Segment::lin(&a, &b, Orientation::Rpy(conv)).unwrap();
            (CartesianMotion::new(vec![seg], profile, &limits, Blend::None).unwrap(), format!("RPY {conv:?}"))
        };
        let w = sampled_ratios(&m, &limits);
        for (what, r) in ["speed", "acceleration", "angular speed", "angular acceleration"].iter().zip(w) {
            assert!(r <= 1.0 + 1e-9, "{label} {profile:?}: {what} at {r:.6}× its limit");
        }
        if case % 2 == 0 && profile == Profile::Trapezoid {
            assert!(w[0].max(w[1]) > 0.99, "{label} {profile:?}: needlessly slow ({w:?})");
        }
    }
}

/// `at` composes only the segments running at t onto the pose the finished
/// ones reached: the same states as composing every segment (the reference),
/// over seeded blended chains of lines and arcs, times before, inside and
/// after the motion.
#[test]
fn the_state_from_running_segments_equals_the_state_from_all() {
    let mut rng = ChaCha8Rng::seed_from_u64(4_035);
    let lim = limits();
    for case in 0..60 {
        let n = rng.random_range(1..12);
        let pts: Vec<Pose> = (0..=n).map(|_| random_pose(&mut rng)).collect();
        let segs: Vec<Segment> = pts
            .windows(2)
            .map(|w| {
                Segment::lin(&w[0], &w[1], [Orientation::Slerp, Orientation::Rpy(RpyConvention::Zyx)][case % 2])
                    .unwrap()
            })
            .collect();
        let blend = [Blend::Deceleration, Blend::Time(0.3), Blend::Distance(0.05), Blend::None][case % 4];
        let profile = [Profile::SCurve, Profile::Trapezoid, Profile::Quintic][case / 4 % 3];
        let m = CartesianMotion::new(segs, profile, &lim, blend).unwrap();
        let m = if case % 5 == 0 { m.stretched_to(m.duration() * 1.7).unwrap() } else { m };
        for _ in 0..400 {
            let t = rng.random_range(-0.1..m.duration() + 0.1);
            let (fast, plain) = (m.at(t), m.at_reference(t));
            let close = |a: &Vector3<f64>, b: &Vector3<f64>| (a - b).norm() <= 1e-12 * (1.0 + b.norm());
            assert!(close(&fast.pose.pos, &plain.pose.pos), "case {case} t={t}");
            assert!((fast.pose.rot - plain.pose.rot).amax() <= 1e-12, "case {case} t={t}");
            for (a, b) in
                [(fast.vel, plain.vel), (fast.acc, plain.acc), (fast.omega, plain.omega), (fast.alpha, plain.alpha)]
            {
                assert!(close(&a, &b), "case {case} t={t}: {a:?} vs {b:?}");
            }
        }
    }
}

/// Issue 35 item 4: evaluating a chain of 4000 segments costs about what a
/// chain of 4 does (it used to cost 1000 times more: every segment was
/// composed at every t, so a program's blended loop grew quadratically).
#[test]
fn a_long_chain_costs_no_more_per_sample_than_a_short_one() {
    let lim = limits();
    let chain = |n: usize| {
        let pts: Vec<Pose> =
            (0..=n).map(|k| Pose::translation(0.5, if k % 2 == 0 { 0.0 } else { 0.01 }, 0.4)).collect();
        let segs = pts.windows(2).map(|w| Segment::lin(&w[0], &w[1], Orientation::Slerp).unwrap()).collect();
        CartesianMotion::new(segs, Profile::Trapezoid, &lim, Blend::None).unwrap()
    };
    let per_sample = |m: &CartesianMotion| {
        let start = std::time::Instant::now();
        let mut sum = 0.0;
        for k in 0..20_000 {
            sum += m.at(m.duration() * f64::from(k) / 20_000.0).pose.pos.y;
        }
        assert!(sum.is_finite());
        start.elapsed()
    };
    let (short, long) = (chain(4), chain(4000));
    let (a, b) = (per_sample(&short).min(per_sample(&short)), per_sample(&long).min(per_sample(&long)));
    assert!(b < a * 20, "4 segments: {a:?}, 4000 segments: {b:?} per 20 000 samples");
}
