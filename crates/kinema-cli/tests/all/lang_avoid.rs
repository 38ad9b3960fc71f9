//! `PTP … AVOID` with `kinema run --scene`: a swing through the fume hood's
//! sash goes around it and passes `kinema traj check --scene`; the same
//! program gives the same file; a free PTP keeps its samples; a target in
//! the sash is an error at its statement.

use crate::common::kinema;

const IIWA: &str = "lbr-iiwa-14-r820";
/// The tilted arm on the left of the hood (as in collide.rs's refused swing).
const START: &str = "-1.5708,1.047,0,0,0,0,0";

fn fume_hood() -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/fume-hood.toml");
    path.to_str().unwrap().to_string()
}

/// `kinema run PROGRAM` from START in the fume hood (`scene`: with `--scene`), writing `out`.
fn run(dir: &std::path::Path, program: &str, out: &str, scene: bool) -> crate::common::Run {
    let file = dir.join("program.krl");
    std::fs::write(&file, program).unwrap();
    let out = dir.join(out);
    let mut args =
        vec!["run", file.to_str().unwrap(), "--robot", IIWA, "--start", START, "--out", out.to_str().unwrap()];
    let hood = fume_hood();
    if scene {
        args.extend(["--scene", hood.as_str()]);
    }
    kinema(&args)
}

#[test]
fn a_ptp_through_the_sash_goes_around_it_the_same_way_every_run() {
    let dir = tempfile::tempdir().unwrap();
    let program = "JVEL 50deg/s\nPTP JOINT(90deg, 60deg, 0, 0, 0, 0, 0) AVOID\n";
    // Without AVOID the straight swing is refused (collide.rs); with it, it runs.
    let first = run(dir.path(), program, "a.csv", true);
    assert!(first.ok, "{}", first.stderr);
    let out = dir.path().join("a.csv");
    let check = kinema(&["traj", "check", "--robot", IIWA, "--scene", &fume_hood(), out.to_str().unwrap()]);
    assert!(check.ok && check.stdout.contains(" 0 violation(s)"), "{}{}", check.stdout, check.stderr);
    let text = std::fs::read_to_string(&out).unwrap();
    let last: Vec<f64> = text.lines().last().unwrap().split(',').skip(1).take(7).map(|v| v.parse().unwrap()).collect();
    let target = [90f64.to_radians(), 60f64.to_radians(), 0.0, 0.0, 0.0, 0.0, 0.0];
    // The CSV holds 12 decimals.
    assert!(last.iter().zip(target).all(|(a, b)| (a - b).abs() < 1e-12), "ends at the PTP's target: {last:?}");
    // More than a straight motion: the path passes via points, at rest.
    let at_rest =
        text.lines().skip(1).filter(|l| l.split(',').skip(8).take(7).all(|v| v.parse::<f64>().unwrap() == 0.0));
    assert!(at_rest.count() >= 3, "start, at least one via point and the end are at rest");
    let again = run(dir.path(), program, "b.csv", true);
    assert!(again.ok, "{}", again.stderr);
    assert_eq!(std::fs::read(dir.path().join("b.csv")).unwrap(), text.as_bytes());
}

#[test]
fn a_free_ptp_with_avoid_keeps_its_samples() {
    let dir = tempfile::tempdir().unwrap();
    // A small turn of the base on the left of the hood, clear of it.
    let plain = run(dir.path(), "JVEL 50deg/s\nPTP JOINT(-80deg, 60deg, 0, 10deg, 0, 0, 0)\n", "plain.csv", false);
    assert!(plain.ok, "{}", plain.stderr);
    let avoid = run(dir.path(), "JVEL 50deg/s\nPTP JOINT(-80deg, 60deg, 0, 10deg, 0, 0, 0) AVOID\n", "avoid.csv", true);
    assert!(avoid.ok, "{}", avoid.stderr);
    assert_eq!(
        std::fs::read(dir.path().join("plain.csv")).unwrap(),
        std::fs::read(dir.path().join("avoid.csv")).unwrap()
    );
}

#[test]
fn a_target_in_the_sash_is_an_error_at_its_statement() {
    let dir = tempfile::tempdir().unwrap();
    let refused = run(dir.path(), "JVEL 50deg/s\nWAIT 1\nPTP JOINT(0, 60deg, 0, 0, 0, 0, 0) AVOID\n", "no.csv", true);
    assert_eq!(refused.code, Some(1), "{}", refused.stderr);
    let e = &refused.stderr;
    assert!(e.contains(":3:") && e.contains("no collision-free path") && e.contains("sash"), "{e}");
    assert!(!dir.path().join("no.csv").exists(), "a refused program writes nothing");
}

#[test]
fn avoid_without_a_scene_warns_and_avoid_on_lin_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let straight = run(dir.path(), "JVEL 50deg/s\nPTP JOINT(-80deg, 60deg, 0, 0, 0, 0, 0) AVOID\n", "w.csv", false);
    assert!(straight.ok && straight.stderr.contains("AVOID without a collision check"), "{}", straight.stderr);
    let lin = run(dir.path(), "LIN CART(0.3, 0.2, 0.5, 180deg, 0, 0) AVOID\n", "l.csv", true);
    assert_eq!(lin.code, Some(1), "{}", lin.stderr);
    assert!(lin.stderr.contains("AVOID applies to PTP only"), "{}", lin.stderr);
}
