//! `kinema traj`: limits too extreme to plan with, and `traj check` on what
//! q itself says — the same cases as the core, Python and /api/traj tests.

use serde_json::Value;

use crate::common;

use common::kinema;

fn tempdir(tag: &str) -> tempfile::TempDir {
    tempfile::Builder::new().prefix(&format!("kinema-traj-{tag}-")).tempdir().unwrap()
}

#[test]
fn limits_that_vanish_or_overflow_the_duration_are_errors() {
    let r =
        kinema(&["traj", "ptp", "-r", "puma560", "--from", "qz", "--to", "qr", "--vmax", "1e100", "--amax", "1e100"]);
    assert!(!r.ok && r.stderr.contains("shorter than"), "{} {}", r.stdout, r.stderr);
    assert!(r.stdout.is_empty(), "nothing is printed: {}", r.stdout);
    for args in [
        &["traj", "law", "--profile", "scurve", "--vmax", "1", "--amax", "1", "--jmax", "1e-300"][..],
        &["traj", "law", "--distance", "1e308", "--vmax", "0.5", "--amax", "1", "--json"][..],
    ] {
        let r = kinema(args);
        assert!(!r.ok && r.stderr.contains("overflows"), "{args:?}: {} {}", r.stdout, r.stderr);
    }
}

/// The Panda's trapezoid is refused when asked for (its jerk limits); without
/// --profile the Panda gets the S-curve (issue 34: the default failed).
#[test]
fn the_pandas_trapezoid_is_refused_and_its_default_is_the_scurve() {
    let (from, to) = ("0,-0.3,0,-2.2,0,2.0,0.785", "0.5,-0.3,0.2,-2.0,0.1,1.8,0.6");
    let r = kinema(&["traj", "ptp", "-r", "panda", "--from", from, "--to", to, "--profile", "trapezoid"]);
    assert!(!r.ok && r.stderr.contains("jerk limit") && r.stderr.contains("scurve"), "{}", r.stderr);
    for extra in [&[][..], &["--profile", "scurve"][..]] {
        let r = kinema(&[&["traj", "ptp", "-r", "panda", "--from", from, "--to", to, "--json"][..], extra].concat());
        assert!(r.ok, "{extra:?}: {}", r.stderr);
        let v: Value = serde_json::from_str(&r.stdout).unwrap();
        assert_eq!(v["profile"], "scurve");
    }
}

/// Issue 34: `kinema traj ptp --robot R --from home --to …` with every
/// default works on every built-in (from the registry), to seeded random
/// configurations within the limits and to every named pose; the profile is
/// the core's default for the robot.
#[test]
fn every_builtin_plans_a_default_ptp() {
    use rand::SeedableRng;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(34);
    for name in kinema::builtin_names() {
        let robot = kinema::Robot::builtin(name).unwrap();
        let mut targets: Vec<String> = robot.poses().iter().map(|p| p.name.clone()).collect();
        for _ in 0..2 {
            let q = robot.random_q(&mut rng);
            targets.push(q.iter().map(|v| format!("{v:.17}")).collect::<Vec<_>>().join(","));
        }
        for to in &targets {
            let r = kinema(&["traj", "ptp", "--robot", name, "--from", "home", "--to", to, "--json"]);
            assert_eq!(r.code, Some(0), "{name} home → {to}: {}", r.stderr);
            let v: Value = serde_json::from_str(&r.stdout).unwrap();
            let want = kinema::traj::default_profile(&robot);
            assert_eq!(v["profile"], want.name(), "{name}");
        }
    }
}

/// A 7.4 mrad one-sample glitch in q with untouched q̇/q̈ columns passed
/// `traj check`; it is now found. The clean file passes, and a singular
/// passage is a warning by default.
#[test]
fn traj_check_finds_a_glitch_in_q_and_warns_of_singular_passages() {
    let dir = tempdir("check");
    let clean = dir.path().join("clean.csv");
    let q_obj = "-0.1090,1.2417,0.4463,1.9156,-0.9695,-1.8728,0.4876";
    let r = kinema(&[
        "traj",
        "ptp",
        "-r",
        "lbr-iiwa-14-r820",
        "--from",
        "home",
        "--to",
        q_obj,
        "--profile",
        "scurve",
        "--amax",
        "2",
        "--jmax",
        "15",
        "--out",
        clean.to_str().unwrap(),
    ]);
    assert!(r.ok, "{}", r.stderr);
    let check = |file: &std::path::Path| {
        let r = kinema(&["traj", "check", "-r", "lbr-iiwa-14-r820", "--amax", "2", "--json", file.to_str().unwrap()]);
        let v: Value = serde_json::from_str(&r.stdout).unwrap_or_else(|e| panic!("{e}: {} {}", r.stdout, r.stderr));
        (r.code, v)
    };
    let (code, v) = check(&clean);
    assert_eq!(code, Some(0), "{v}");
    assert_eq!(v["violations"].as_array().unwrap().len(), 0);

    let text = std::fs::read_to_string(&clean).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let k = lines.len() / 3;
    let mut cells: Vec<String> = lines[k].split(',').map(str::to_string).collect();
    cells[2] = format!("{:.12}", cells[2].parse::<f64>().unwrap() + 0.0074); // q2
    lines[k] = cells.join(",");
    let glitched = dir.path().join("glitch.csv");
    std::fs::write(&glitched, lines.join("\n") + "\n").unwrap();
    let (code, v) = check(&glitched);
    assert_eq!(code, Some(1), "{v}");
    let kinds: Vec<&str> = v["violations"].as_array().unwrap().iter().map(|x| x["kind"].as_str().unwrap()).collect();
    assert!(kinds.contains(&"inconsistent"), "{kinds:?}");

    // Through the stretched elbow (q4 = 0, Cuadro III): a warning, exit 0.
    let through = dir.path().join("through.csv");
    let r = kinema(&[
        "traj",
        "ptp",
        "-r",
        "lbr-iiwa-14-r820",
        "--from",
        "0.2,0.5,0.1,-0.5,0.3,0.8,0",
        "--to",
        "0.2,0.5,0.1,0.5,0.3,0.8,0",
        "--profile",
        "quintic",
        "--amax",
        "2",
        "--dt",
        "0.001",
        "--out",
        through.to_str().unwrap(),
    ]);
    assert!(r.ok, "{}", r.stderr);
    let (code, v) = check(&through);
    assert_eq!(code, Some(0), "{v}");
    let warnings = v["warnings"].as_array().unwrap();
    assert_eq!(warnings.len(), 1, "{v}");
    assert_eq!(warnings[0]["kind"], "singular");
}

/// `--q3`/`--psi` choose the iiwa's self-motion along a LIN: held by
/// default, fixed, steered; malformed values are usage errors (64), a value
/// the start does not have and a six-joint arm are errors naming why.
#[test]
fn q3_and_psi_choose_the_self_motion_of_a_line() {
    let dir = tempdir("q3");
    let out = dir.path().join("lin.csv");
    let from = "--from=0.3,1.0,0.4,-0.8,0.2,0.9,0.1";
    let base =
        ["traj", "lin", "-r", "lbr-iiwa-14-r820", from, "--to", "0.50,0.20,0.90,0.6945,0.8387,1.3509", "--vmax", "0.2"];
    let q3_drift = |policy: &[&str]| -> Result<f64, String> {
        let mut args: Vec<&str> = base.to_vec();
        args.extend(["--amax", "1", "--out", out.to_str().unwrap()]);
        args.extend(policy);
        let r = kinema(&args);
        if !r.ok {
            return Err(format!("{:?} {}", r.code, r.stderr));
        }
        let text = std::fs::read_to_string(&out).unwrap();
        let q3: Vec<f64> = text.lines().skip(1).map(|l| l.split(',').nth(3).unwrap().parse().unwrap()).collect();
        Ok(q3.iter().map(|v| (v - 0.4).abs()).fold(0.0, f64::max))
    };
    for policy in [&[][..], &["--q3", "hold"], &["--q3", "0.4"]] {
        let drift = q3_drift(policy).unwrap();
        assert!(drift < 1e-9, "{policy:?}: q3 drifted by {drift}");
    }
    let drift = q3_drift(&["--q3", "manipulability"]).unwrap();
    assert!(drift > 1e-3, "the rule never moved q3");
    assert!(q3_drift(&["--q3", "track"]).is_ok());
    let e = q3_drift(&["--q3", "0.5"]).unwrap_err();
    assert!(e.starts_with("Some(1)") && e.contains("q3 = 0.400000"), "{e}");
    for bad in [&["--q3", "sideways"][..], &["--psi", "track"], &["--q3", "hold", "--psi", "hold"]] {
        let e = q3_drift(bad).unwrap_err();
        assert!(e.starts_with("Some(64)"), "{bad:?}: {e}");
    }
    let r = kinema(&[
        "traj",
        "lin",
        "-r",
        "puma560",
        "--from",
        "qn",
        "--to",
        "0.5,0.1,0.3,0,1.57,0",
        "--vmax",
        "0.2",
        "--amax",
        "1",
        "--q3",
        "hold",
    ]);
    assert!(!r.ok && r.stderr.contains("no self-motion"), "{}", r.stderr);
}

/// Seed 003 Fig. 9 on both doors: `traj lin --skip-unreachable` leaves out a
/// waypoint out of reach (named on stderr and in the JSON) and goes through
/// the others, the same path as without the point; `run --skip-unreachable`
/// skips the program's unreachable MOVEXY. Without the option both fail.
#[test]
fn skip_unreachable_leaves_out_points_outside_the_workspace() {
    let dir = tempdir("skip");
    let (a, b) = (dir.path().join("a.csv"), dir.path().join("b.csv"));
    // The SCARA without its (estimated) joint velocity and acceleration
    // limits: the path kinks where the zone rule moves the rail to another
    // zone, which those limits refuse; the skipping is what is tested here.
    let free_path = common::builtin_without_rate_limits(dir.path(), "scara5");
    let lin = |vias: &[&str], out: &std::path::Path, skip: bool| {
        // The zone rule's configuration for `home`'s tool pose (as in
        // docs/seeds.md, Fig. 9): from `home` itself the first sample moves the
        // rail to the rule's position at once, a branch jump refused on its own.
        let from = "0.738577,-0.085236,2.407185,0.1,-0.227554";
        let mut args = vec!["traj", "lin", "-r", &free_path, "--from", from, "--to", "0.35,-0.1,0.2,0,0,0"];
        for v in vias {
            args.extend(["--via", v]);
        }
        args.extend(["--vmax", "0.2", "--amax", "1", "--json", "--out", out.to_str().unwrap()]);
        if skip {
            args.push("--skip-unreachable");
        }
        kinema(&args)
    };
    let r = lin(&["0.3,0.1,0.2,0,0,0", "3,3,0.2,0,0,0"], &a, false);
    assert!(!r.ok && r.stderr.contains("unreachable"), "{}", r.stderr);
    assert!(!a.exists());
    let r = lin(&["0.3,0.1,0.2,0,0,0", "3,3,0.2,0,0,0"], &a, true);
    assert!(r.ok, "{}", r.stderr);
    assert!(r.stderr.contains("skipped --via #2"), "{}", r.stderr);
    let json: Value = serde_json::from_str(&r.stdout[r.stdout.find('{').unwrap()..]).unwrap();
    assert_eq!(json["skipped"][0]["index"], 1);
    assert!(lin(&["0.3,0.1,0.2,0,0,0"], &b, false).ok);
    assert_eq!(std::fs::read_to_string(&a).unwrap(), std::fs::read_to_string(&b).unwrap());
    let program = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/programs/seed003_fig9_skip.prg");
    let out = dir.path().join("run.csv");
    let run = |skip: bool| {
        let mut args = vec!["run", "-r", "scara5", program, "--out", out.to_str().unwrap()];
        if skip {
            args.push("--skip-unreachable");
        }
        kinema(&args)
    };
    assert_eq!(run(false).code, Some(1));
    let r = run(true);
    assert!(r.ok && r.stderr.contains("skipped"), "{}", r.stderr);
    assert!(out.exists());
}

/// `traj ptp --v0/--a0/--v1/--a1`: motions chained without stopping (issue 25).
mod boundary {
    use super::{kinema, tempdir};
    use serde_json::Value;

    const TO: &str = "-0.1090,1.2417,0.4463,1.9156,-0.9695,-1.8728,0.4876";
    const VIA: &str = "0.5,0.8,0.2,1.2,-0.4,-1.0,0.1";
    const W: &str = "0.3,0.3,0.3,0.3,-0.3,-0.3,0.3";

    fn rows(path: &std::path::Path) -> Vec<Vec<f64>> {
        let text = std::fs::read_to_string(path).unwrap();
        text.lines().skip(1).map(|l| l.split(',').map(|x| x.parse().unwrap()).collect()).collect()
    }

    #[test]
    fn chained_ptps_meet_at_the_via_point_with_its_velocity_and_pass_traj_check() {
        let dir = tempdir("boundary");
        let (a, b) = (dir.path().join("a.csv"), dir.path().join("b.csv"));
        let common = ["traj", "ptp", "-r", "lbr-iiwa-14-r820", "--profile", "scurve", "--amax", "2", "--jmax", "15"];
        let r = kinema(
            &[&common[..], &["--from", "home", "--to", VIA, "--v1", W, "--out", a.to_str().unwrap(), "--json"]]
                .concat(),
        );
        assert!(r.ok, "{}", r.stderr);
        let first: Value = serde_json::from_str(&r.stdout).unwrap();
        assert_eq!(first["joint_phase_times"].as_array().unwrap().len(), 7);
        let r = kinema(
            &[&common[..], &["--from", VIA, "--to", TO, "--v0", W, "--out", b.to_str().unwrap(), "--json"]].concat(),
        );
        assert!(r.ok, "{}", r.stderr);
        let (ra, rb) = (rows(&a), rows(&b));
        let (end, start) = (ra.last().unwrap(), &rb[0]);
        let w: Vec<f64> = W.split(',').map(|x| x.parse().unwrap()).collect();
        for i in 0..7 {
            assert!((end[1 + i] - start[1 + i]).abs() < 1e-9, "q{i}");
            assert!((end[8 + i] - w[i]).abs() < 1e-9 && (start[8 + i] - w[i]).abs() < 1e-9, "qd{i}");
        }
        for f in [&a, &b] {
            let r = kinema(&["traj", "check", "-r", "lbr-iiwa-14-r820", f.to_str().unwrap(), "--jmax", "15"]);
            assert!(r.ok, "{} {}", r.stdout, r.stderr);
        }
    }

    #[test]
    fn zero_boundaries_give_todays_straight_line_ptp() {
        let base = ["traj", "ptp", "-r", "lbr-iiwa-14-r820", "--from", "home", "--to", TO, "--profile", "scurve"];
        let base = [&base[..], &["--amax", "2", "--jmax", "9"]].concat();
        let plain = kinema(&base);
        let zeros = kinema(&[&base[..], &["--v0", "0,0,0,0,0,0,0", "--a1", "0,0,0,0,0,0,0"]].concat());
        assert!(plain.ok && zeros.ok, "{}", zeros.stderr);
        assert_eq!(plain.stdout, zeros.stdout);
    }

    #[test]
    fn bad_boundary_flags_are_usage_errors_naming_the_flag() {
        let base =
            ["traj", "ptp", "-r", "lbr-iiwa-14-r820", "--from", "home", "--to", TO, "--amax", "2", "--jmax", "15"];
        for (flag, value, expect) in [
            ("--v1", "0.1,0.2", "--v1: 2 values given; expected 7, one per joint of `lbr-iiwa-14-r820`"),
            ("--v0", "nan,0,0,0,0,0,0", "`nan` is not a finite number"),
            ("--a0", "0,x,0,0,0,0,0", "`x` is not a finite number"),
            ("--a1", "inf,0,0,0,0,0,0", "`inf` is not a finite number"),
        ] {
            let r = kinema(&[&base[..], &["--profile", "scurve", flag, value]].concat());
            assert_eq!(r.code, Some(64), "{flag} {value}: {}", r.stderr);
            assert!(r.stderr.contains(expect) && r.stderr.contains(&flag[2..]), "{flag}: {}", r.stderr);
            assert!(r.stdout.is_empty());
        }
        // Understood but not plannable: ordinary errors naming the problem.
        let r = kinema(&[&base[..], &["--profile", "cubic", "--v1", W]].concat());
        assert_eq!(r.code, Some(1));
        assert!(r.stderr.contains("only moves rest to rest"), "{}", r.stderr);
        let r = kinema(&[&base[..], &["--profile", "scurve", "--v1", "5,0,0,0,0,0,0"]].concat());
        assert_eq!(r.code, Some(1));
        assert!(r.stderr.contains("`target velocity`: 5; expected a velocity within ±"), "{}", r.stderr);
    }

    #[test]
    fn a_boundary_velocity_that_overshoots_a_joint_limit_is_reported_and_nothing_written() {
        let dir = tempdir("overshoot");
        let out = dir.path().join("x.csv");
        // Joint 4 starts at 2.05 (limit ≈ 2.094) moving up at 1.2 rad/s.
        let r = kinema(&[
            "traj",
            "ptp",
            "-r",
            "lbr-iiwa-14-r820",
            "--profile",
            "scurve",
            "--amax",
            "2",
            "--jmax",
            "15",
            "--from",
            "0,0,0,2.05,0,0,0",
            "--to",
            TO,
            "--v0",
            "0,0,0,1.2,0,0,0",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(!r.ok && r.stderr.contains("joint 4") && r.stderr.contains("position"), "{}", r.stderr);
        assert!(!out.exists());
    }
}
