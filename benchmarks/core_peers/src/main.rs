//! `core-peers`, the helper run_core_peers.sh calls around the timing:
//!
//! ```text
//! core-peers urdf BUILTIN OUT.urdf        kinema's built-in robot written as a URDF (tip link `tool`)
//! core-peers joints URDF TIP              the moving joints from the root to TIP, comma-separated
//! core-peers check URDF TIP STATES.csv    kinema and k against Pinocchio's results; exit 1 above the bound
//! core-peers ik-geo-check REPO [N]        (feature ik-geo) kinema's closed forms against IK-Geo's
//!                                         on the arms of benches/ik_geo.rs; exit 1 if kinema
//!                                         misses a solution
//! ```

use std::path::Path;
use std::process::ExitCode;

use kinema::dynamics::{mass_matrix, mass_matrix_into, rnea, rnea_into};
use kinema::nalgebra::{DMatrix, Vector3};
use kinema::Data;
use kinema::{Frame, Robot};
#[cfg(feature = "ik-geo")]
use kinema_core_peers::ikgeo::{arms, GeoArm};
use kinema_core_peers::{load, read_states, urdf_of};
#[cfg(feature = "ik-geo")]
use rand::SeedableRng;

/// Largest difference accepted: absolute for the pose and the Jacobian, relative to
/// 1 + the largest magnitude for τ and M.
const BOUND: f64 = 1e-12;

fn max_diff(a: impl IntoIterator<Item = f64>, b: &[f64]) -> f64 {
    a.into_iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

fn scale(b: &[f64]) -> f64 {
    1.0 + b.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

fn check(urdf: &Path, tip: &str, states: &Path) -> Result<bool, String> {
    let peers = load(urdf, tip)?;
    let (robot, chain) = (&peers.robot, &peers.k);
    let n = robot.dof();
    let states = read_states(states, n)?;
    let g = Vector3::new(0.0, 0.0, -9.81);
    let mut buf = Data::new(robot);
    let (mut tau, mut m) = (vec![0.0; n], DMatrix::zeros(n, n));
    // Worst difference per quantity: kinema's pose, Jacobian, τ (plain, fast), M (plain, fast); k's pose, Jacobian.
    let mut worst = [0.0f64; 8];
    let names = [
        "kinema pose",
        "kinema J",
        "kinema rnea",
        "kinema rnea_into",
        "kinema crba",
        "kinema mass_matrix_into",
        "k pose",
        "k J",
    ];
    for s in &states {
        let pose = robot.fk(&s.q).map_err(|e| e.to_string())?.world_from_tool;
        let mine = (0..3)
            .flat_map(|r| (0..3).map(move |c| (r, c)))
            .map(|(r, c)| pose.rot[(r, c)])
            .chain(pose.pos.iter().copied());
        worst[0] = worst[0].max(max_diff(mine, &s.pose));
        let j = robot.jacobian(&s.q, Frame::Base).map_err(|e| e.to_string())?;
        worst[1] =
            worst[1].max(max_diff((0..6).flat_map(|r| (0..n).map(move |c| (r, c))).map(|rc| j[rc]), &s.jacobian));

        let reference = rnea(robot, &s.q, &s.qd, &s.qdd, &g).map_err(|e| e.to_string())?;
        worst[2] = worst[2].max(max_diff(reference, &s.tau) / scale(&s.tau));
        rnea_into(robot, &mut buf, &s.q, &s.qd, &s.qdd, &g, &mut tau).map_err(|e| e.to_string())?;
        worst[3] = worst[3].max(max_diff(tau.iter().copied(), &s.tau) / scale(&s.tau));
        let reference = mass_matrix(robot, &s.q).map_err(|e| e.to_string())?;
        worst[4] = worst[4].max(max_diff(reference.transpose().iter().copied(), &s.m) / scale(&s.m));
        mass_matrix_into(robot, &mut buf, &s.q, &mut m).map_err(|e| e.to_string())?;
        worst[5] = worst[5].max(max_diff(m.transpose().iter().copied(), &s.m) / scale(&s.m));

        chain.set_joint_positions_unchecked(&s.q);
        let t = chain.end_transform();
        let r = t.rotation.to_rotation_matrix();
        let theirs = (0..3)
            .flat_map(|a| (0..3).map(move |b| (a, b)))
            .map(|(a, b)| r[(a, b)])
            .chain(t.translation.vector.iter().copied());
        worst[6] = worst[6].max(max_diff(theirs, &s.pose));
        let jk = k::jacobian(chain);
        worst[7] =
            worst[7].max(max_diff((0..6).flat_map(|r| (0..n).map(move |c| (r, c))).map(|rc| jk[rc]), &s.jacobian));
    }
    let ok = worst.iter().all(|w| *w <= BOUND);
    let listed: Vec<String> = names.iter().zip(worst).map(|(n, w)| format!("{n} {w:.1e}")).collect();
    println!(
        "  {} states, max difference from Pinocchio: {}{}",
        states.len(),
        listed.join(", "),
        if ok { "" } else { "  ABOVE 1e-12" }
    );
    Ok(ok)
}

/// Same configuration up to whole turns of each joint.
#[cfg(feature = "ik-geo")]
fn same_angles(a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).all(|(x, y)| kinema::ik::wrap_angle(x - y).abs() < 1e-6)
}

/// On `n` targets from seeded configurations within the limits: IK-Geo's exact solutions that
/// reach the target (FK residual below 1e-9) must all be among kinema's; prints the counts.
#[cfg(feature = "ik-geo")]
fn ik_geo_check(arm: &GeoArm, n: usize) -> Result<bool, String> {
    let solver = kinema::ik::analytic_solver(&arm.robot).ok_or("no closed form in kinema")?;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(34);
    let (mut mine, mut theirs, mut missing) = (0, 0, 0);
    for _ in 0..n {
        let q = arm.robot.random_q(&mut rng);
        let target = arm.robot.fk(&q).map_err(|e| e.to_string())?.world_from_tool;
        let sols = solver.solve(&target).map_err(|e| e.to_string())?;
        mine += sols.len();
        for g in arm.geo_solve(&target) {
            let reached = arm.robot.fk(&g).map_err(|e| e.to_string())?.world_from_tool;
            let e = kinema::math::pose_error(&target, &reached);
            if e.position_norm() > 1e-9 || e.rotation_angle() > 1e-9 {
                continue;
            }
            theirs += 1;
            if !sols.iter().any(|s| same_angles(&s.q, &g)) {
                missing += 1;
                println!("    {}: IK-Geo's {g:?} is not among kinema's {} solutions", arm.name, sols.len());
            }
        }
    }
    println!(
        "  {:<18} {} ({}): {n} targets, kinema {mine} solutions, IK-Geo {theirs} exact ones reaching the target, {missing} of them missing from kinema's",
        arm.name,
        solver.name(),
        arm.family
    );
    Ok(missing == 0)
}

fn run(args: &[String]) -> Result<bool, String> {
    match args {
        [cmd, name, out] if cmd == "urdf" => {
            let robot = Robot::builtin(name).map_err(|e| e.to_string())?;
            std::fs::write(out, urdf_of(&robot)).map_err(|e| format!("{out}: {e}"))?;
            Ok(true)
        }
        [cmd, urdf, tip] if cmd == "joints" => {
            let robot = Robot::from_file(urdf, Some(tip)).map_err(|e| e.to_string())?;
            let names: Vec<&str> = robot.joints().iter().map(|j| j.name.as_str()).collect();
            println!("{}", names.join(","));
            Ok(true)
        }
        [cmd, urdf, tip, states] if cmd == "check" => check(Path::new(urdf), tip, Path::new(states)),
        #[cfg(feature = "ik-geo")]
        [cmd, repo, rest @ ..] if cmd == "ik-geo-check" && rest.len() <= 1 => {
            let n = rest.first().map_or(Ok(1000), |v| v.parse().map_err(|e| format!("N `{v}`: {e}")))?;
            let mut ok = true;
            for arm in arms(Path::new(repo))? {
                ok &= ik_geo_check(&arm, n)?;
            }
            Ok(ok)
        }
        _ => Err(
            "usage: core-peers urdf BUILTIN OUT | joints URDF TIP | check URDF TIP STATES.csv | ik-geo-check REPO [N]"
                .into(),
        ),
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("core-peers: {e}");
            ExitCode::FAILURE
        }
    }
}
