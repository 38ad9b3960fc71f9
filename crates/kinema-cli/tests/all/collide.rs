//! `kinema collide`: text and JSON, a free and a colliding configuration of a
//! built-in robot, an obstacle scene, an SRDF, batch order, and bad inputs;
//! and `kinema ik --scene`, checked by `kinema collide`.

use crate::common::kinema;

fn json(text: &str) -> serde_json::Value {
    serde_json::from_str(text).unwrap_or_else(|e| panic!("not JSON ({e}): {text}"))
}

fn has_pair(answer: &serde_json::Value, a: &str, b: &str) -> bool {
    answer["pairs"].as_array().unwrap().iter().any(|p| (p["a"] == a && p["b"] == b) || (p["a"] == b && p["b"] == a))
}

const FOLDED_UR5: &str = "0,-90,-180,-90,-90,0";

#[test]
fn free_and_folded_ur5_in_text_and_json() {
    let free = kinema(&["collide", "--robot", "ur5", "--q", "home"]);
    assert!(free.ok, "{}", free.stderr);
    assert!(free.stdout.starts_with("free; closest link "), "{}", free.stdout);

    let hit = kinema(&["collide", "--robot", "ur5", "--q", FOLDED_UR5, "--deg", "--json"]);
    assert_eq!(hit.code, Some(3), "{}", hit.stderr);
    let a = json(&hit.stdout);
    assert_eq!(a["collision"], true);
    assert!(has_pair(&a, "link 2", "link 4"), "{a}");
    let d = &a["min_distance"];
    assert!(d["distance"].as_f64().unwrap() < 0.0, "{d}");
    assert_eq!(d["point_a"].as_array().unwrap().len(), 3);

    let text = kinema(&["collide", "--robot", "ur5", "--q", FOLDED_UR5, "--deg"]);
    assert_eq!(text.code, Some(3));
    assert!(text.stdout.starts_with("collision: ") && text.stdout.contains("link 2 – link 4"), "{}", text.stdout);

    // A margin turns a near miss into a collision.
    let margin = kinema(&["collide", "--robot", "ur5", "--q", "home", "--margin", "0.5", "--json"]);
    assert_eq!(margin.code, Some(3), "{}", margin.stderr);
    assert_eq!(json(&margin.stdout)["margin"], 0.5);
}

#[test]
fn an_obstacle_scene_is_checked() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("lab.toml");
    let repo = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes/lab.toml");
    std::fs::copy(repo, &scene).unwrap();
    let scene = scene.to_str().unwrap();
    let home = kinema(&["collide", "--robot", "ur5", "--scene", scene, "--q", "home", "--json"]);
    assert!(home.ok, "{}{}", home.stdout, home.stderr);
    assert_eq!(json(&home.stdout)["collision"], false);
    // The shoulder lowered 30° below the horizontal: the upper arm reaches into the bench.
    let low = kinema(&["collide", "--robot", "ur5", "--scene", scene, "--q", "0,30,0,0,0,0", "--deg", "--json"]);
    assert_eq!(low.code, Some(3), "{}", low.stderr);
    let a = json(&low.stdout);
    assert!(has_pair(&a, "link 2", "bench"), "{a}");
}

#[test]
fn batch_answers_in_input_order() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("q.csv");
    let folded: Vec<f64> = FOLDED_UR5.split(',').map(|v| v.parse::<f64>().unwrap().to_radians()).collect();
    let home = [0.0, -90f64.to_radians(), 90f64.to_radians(), -90f64.to_radians(), -90f64.to_radians(), 0.0];
    let row = |q: &[f64]| q.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(",");
    let mut text = String::from("q1,q2,q3,q4,q5,q6\n");
    let expected: Vec<bool> = (0..50).map(|i| i % 3 == 1).collect();
    for &hit in &expected {
        text += &row(if hit { &folded } else { &home });
        text += "\n";
    }
    std::fs::write(&input, text).unwrap();
    let run = kinema(&["collide", "--robot", "ur5", "--input", input.to_str().unwrap(), "--json"]);
    assert_eq!(run.code, Some(3), "{}", run.stderr);
    let got: Vec<bool> = run.stdout.lines().map(|l| json(l)["collision"].as_bool().unwrap()).collect();
    assert_eq!(got, expected);
    let plain = kinema(&["collide", "--robot", "ur5", "--input", input.to_str().unwrap()]);
    let lines: Vec<&str> = plain.stdout.lines().collect();
    assert!(lines[0].starts_with("line 2: free") && lines[1].starts_with("line 3: collision"), "{lines:?}");
}

#[test]
fn bad_inputs_say_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let unknown = write("unknown.toml", "[[obstacle]]\nname = \"b\"\nbox = [1, 1, 1]\ncolor = 1\n");
    let r = kinema(&["collide", "--robot", "ur5", "--scene", &unknown, "--q", "home"]);
    assert_eq!(r.code, Some(1));
    assert!(r.stderr.contains("unknown.toml:4:") && r.stderr.contains("color"), "{}", r.stderr);

    let mesh = write("mesh.toml", "[[obstacle]]\nname = \"m\"\nmesh = \"fixture.stl\"\n");
    let r = kinema(&["collide", "--robot", "ur5", "--scene", &mesh, "--q", "home"]);
    assert_eq!(r.code, Some(1));
    assert!(r.stderr.contains("fixture.stl") && r.stderr.contains("not found"), "{}", r.stderr);

    let r = kinema(&["collide", "--robot", "ur5", "--q", "0,0"]);
    assert_eq!(r.code, Some(1));
    assert!(r.stderr.contains('2') && r.stderr.contains('6'), "{}", r.stderr);

    let short = write("short.csv", "0,0,0,0,0,0\n0,0,0\n");
    let r = kinema(&["collide", "--robot", "ur5", "--input", &short]);
    assert_eq!(r.code, Some(1));
    assert!(r.stderr.contains("line 2") && r.stderr.contains("expected one per joint"), "{}", r.stderr);
    assert!(r.stdout.is_empty(), "nothing printed before the input is checked");

    let r = kinema(&["collide", "--robot", "ur5", "--q", "home", "--margin", "-1"]);
    assert_eq!(r.code, Some(1));
    assert!(r.stderr.contains("margin"), "{}", r.stderr);
}

/// The repository's example scene `name`.
fn example_scene(name: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes").join(name);
    path.to_str().unwrap().to_string()
}

#[test]
fn an_srdf_disables_pairs() {
    let dir = tempfile::tempdir().unwrap();
    let srdf = dir.path().join("ur5.srdf");
    std::fs::write(
        &srdf,
        "<robot name=\"ur5\"><disable_collisions link1=\"link 2\" link2=\"link 4\" reason=\"Never\"/></robot>",
    )
    .unwrap();
    let srdf = srdf.to_str().unwrap();
    let hit = kinema(&["collide", "--robot", "ur5", "--q", FOLDED_UR5, "--deg", "--json"]);
    assert!(has_pair(&json(&hit.stdout), "link 2", "link 4"));
    let run = kinema(&["collide", "--robot", "ur5", "--srdf", srdf, "--q", FOLDED_UR5, "--deg", "--json"]);
    assert!(!has_pair(&json(&run.stdout), "link 2", "link 4"), "{}", run.stdout);
    let wrong = dir.path().join("other.srdf");
    std::fs::write(&wrong, "<robot name=\"x\"><disable_collisions link1=\"elbow\" link2=\"wrist\"/></robot>").unwrap();
    let r = kinema(&["collide", "--robot", "ur5", "--srdf", wrong.to_str().unwrap(), "--q", "home"]);
    assert_eq!(r.code, Some(1));
    assert!(r.stderr.contains("elbow"), "{}", r.stderr);
}

/// Seed 004's reason for a redundant arm: in the fume hood, the default
/// elbow-up solution hits the sash; `kinema ik --scene` discards it and turns
/// the elbow, and `kinema collide` confirms the answer is free.
#[test]
fn ik_in_the_fume_hood_turns_the_elbow_out_of_the_way() {
    let scene = example_scene("fume-hood.toml");
    let iiwa = "lbr-iiwa-14-r820";
    let pose = "0.6,0,0.3,180,0,0";
    let plain = kinema(&["ik", "--robot", iiwa, "--pose", pose, "--deg", "--json"]);
    assert!(plain.ok, "{}", plain.stderr);
    let default_q = json(&plain.stdout)["solutions"][0]["q"].to_string();
    let default_q = default_q.trim_matches(['[', ']']);
    let hit = kinema(&["collide", "--robot", iiwa, "--scene", &scene, "--q", default_q, "--deg", "--json"]);
    assert_eq!(hit.code, Some(3), "the default solution hits the sash: {}", hit.stdout);
    assert!(has_pair(&json(&hit.stdout), "link 4", "sash"), "{}", hit.stdout);

    let run = kinema(&["ik", "--robot", iiwa, "--pose", pose, "--deg", "--scene", &scene, "--json"]);
    assert!(run.ok, "{}", run.stderr);
    let a = json(&run.stdout);
    let q: Vec<f64> = a["solutions"][0]["q"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert!(q[2].abs() > 10.0, "the elbow turned: q3 = {}°", q[2]);
    let collided: Vec<&serde_json::Value> =
        a["discarded"]["candidates"].as_array().unwrap().iter().filter(|c| c["reason"] == "collision").collect();
    assert!(!collided.is_empty() && collided[0]["detail"].as_str().unwrap().contains("sash"), "{a}");
    assert!(a["discarded"]["reason"].as_str().unwrap().contains("collision"), "{a}");
    let shown: Vec<String> = q.iter().map(|v| v.to_string()).collect();
    let free = kinema(&["collide", "--robot", iiwa, "--scene", &scene, "--q", &shown.join(","), "--deg"]);
    assert!(free.ok && free.stdout.starts_with("free"), "{}{}", free.stdout, free.stderr);

    // Text: the discarded solutions and the first pair.
    let text = kinema(&["ik", "--robot", iiwa, "--pose", pose, "--deg", "--scene", &scene]);
    assert!(text.ok && text.stdout.contains("discarded, the first for collision: link"), "{}", text.stdout);
    // At a fixed q3 there is nothing to search: every solution collides.
    let fixed = kinema(&["ik", "--robot", iiwa, "--pose", pose, "--deg", "--scene", &scene, "--q3", "0"]);
    assert_eq!(fixed.code, Some(2), "{}", fixed.stdout);
    assert!(fixed.stderr.contains("every solution is rejected") && fixed.stderr.contains("sash"), "{}", fixed.stderr);
    // A margin alone asks for a self-collision check, as `margin=` does in Python and
    // on the server: 10 m around every link rejects every solution.
    let r = kinema(&["ik", "--robot", iiwa, "--pose", pose, "--deg", "--q3", "0", "--margin", "10"]);
    assert_eq!(r.code, Some(2), "{}", r.stdout);
    assert!(r.stderr.contains("every solution is rejected"), "{}", r.stderr);
    let r = kinema(&["ik", "--robot", iiwa, "--pose", pose, "--deg", "--package-path", "."]);
    assert_eq!(r.code, Some(1));
    assert!(r.stderr.contains("--package-path applies to collision checks"), "{}", r.stderr);
}

#[test]
fn ik_batch_answers_are_free_of_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    let scene = example_scene("fume-hood.toml");
    let targets = dir.path().join("targets.csv");
    std::fs::write(&targets, "0.6,0,0.3,3.14159265,0,0\n0.55,0.1,0.25,3.14159265,0,0\n0.65,-0.1,0.3,3.14159265,0,0\n")
        .unwrap();
    let out = dir.path().join("q.csv");
    let iiwa = "lbr-iiwa-14-r820";
    let args = ["ik", "--robot", iiwa, "--scene", &scene, "--input", targets.to_str().unwrap()];
    let run = kinema(&[&args[..], &["--output", out.to_str().unwrap()]].concat());
    assert!(run.ok, "{}", run.stderr);
    let text = std::fs::read_to_string(&out).unwrap();
    let rows: Vec<&str> = text.lines().filter(|l| !l.starts_with('#') && !l.starts_with("line")).collect();
    assert_eq!(rows.len(), 3, "{text}");
    let check = dir.path().join("check.csv");
    let qs: Vec<String> = rows.iter().map(|r| r.split(',').skip(3).take(7).collect::<Vec<_>>().join(",")).collect();
    std::fs::write(&check, qs.join("\n")).unwrap();
    let free = kinema(&["collide", "--robot", iiwa, "--scene", &scene, "--input", check.to_str().unwrap()]);
    assert!(free.ok, "every answer is free: {}{}", free.stdout, free.stderr);
}

/// `--generate-srdf` writes the pairs that need no check; read back with
/// `--srdf`, it keeps a folded arm's collision (those pairs do collide at
/// some samples) and every disabled pair is one the sampling justified.
#[test]
fn a_generated_srdf_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let srdf = dir.path().join("ur5.srdf");
    let path = srdf.to_str().unwrap();
    let run = kinema(&["collide", "--robot", "ur5", "--generate-srdf", path, "--samples", "2000", "--seed", "3"]);
    assert!(run.ok, "{}", run.stderr);
    assert!(run.stdout.contains("link pairs need no check") && run.stdout.contains("Adjacent"), "{}", run.stdout);
    let text = std::fs::read_to_string(&srdf).unwrap();
    assert!(text.contains("<robot name=\"ur5\">") && text.contains("reason=\"Adjacent\""), "{text}");
    assert!(!text.contains("link1=\"link 2\" link2=\"link 4\""), "link 2 and link 4 do collide when folded: {text}");
    let hit = kinema(&["collide", "--robot", "ur5", "--srdf", path, "--q", FOLDED_UR5, "--deg", "--json"]);
    assert_eq!(hit.code, Some(3), "{}", hit.stderr);
    assert!(has_pair(&json(&hit.stdout), "link 2", "link 4"), "{}", hit.stdout);
    // To standard output, the summary goes to stderr.
    let out = kinema(&["collide", "--robot", "ur5", "--generate-srdf", "-", "--samples", "10"]);
    assert!(out.ok && out.stdout.starts_with("<?xml") && out.stderr.contains("need no check"), "{}", out.stderr);
    // What it would ignore is refused.
    let scene = example_scene("fume-hood.toml");
    let r = kinema(&["collide", "--robot", "ur5", "--generate-srdf", path, "--scene", &scene]);
    assert_eq!(r.code, Some(1));
    assert!(r.stderr.contains("--generate-srdf takes no --scene"), "{}", r.stderr);
    let r = kinema(&["collide", "--robot", "ur5", "--samples", "10", "--q", "home"]);
    assert_eq!(r.code, Some(64), "{}", r.stderr);
}

/// `--scene` on `kinema traj`: a PTP that swings the iiwa's tilted arm past
/// the fume hood's sash is refused with the time and the pair, though both
/// ends are free; `traj check --scene` finds the same in the written file.
#[test]
fn a_motion_through_the_sash_is_refused() {
    let scene = example_scene("fume-hood.toml");
    let (from, to) = ("-1.5708,1.047,0,0,0,0,0", "1.5708,1.047,0,0,0,0,0");
    for q in [from, to] {
        let free = kinema(&["collide", "--robot", "lbr-iiwa-14-r820", "--scene", &scene, "--q", q]);
        assert!(free.ok, "{q}: {}", free.stdout);
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("swing.csv");
    let out = out.to_str().unwrap();
    let base = ["traj", "ptp", "--robot", "lbr-iiwa-14-r820", "--from", from, "--to", to, "--out", out];
    let refused = kinema(&[&base[..], &["--scene", &scene]].concat());
    assert_eq!(refused.code, Some(1), "{}", refused.stderr);
    assert!(refused.stderr.contains("collision: link") && refused.stderr.contains("– sash"), "{}", refused.stderr);
    assert!(!std::path::Path::new(out).exists(), "a refused motion writes nothing");

    let written = kinema(&base);
    assert!(written.ok, "{}", written.stderr);
    let checked = kinema(&["traj", "check", "--robot", "lbr-iiwa-14-r820", out, "--scene", &scene, "--json"]);
    assert_eq!(checked.code, Some(1), "{}", checked.stderr);
    let report = json(&checked.stdout);
    let hits: Vec<&serde_json::Value> =
        report["violations"].as_array().unwrap().iter().filter(|v| v["kind"] == "collision").collect();
    assert_eq!(hits.len(), 1, "one stretch through the sash: {report}");
    assert!(hits[0]["detail"].as_str().unwrap().ends_with("– sash"), "{}", hits[0]);
    let t = hits[0]["t"].as_f64().unwrap();
    assert!(t > 0.0 && t < 2.3, "{t}");
    // Without the scene the same file passes.
    let plain = kinema(&["traj", "check", "--robot", "lbr-iiwa-14-r820", out]);
    assert!(plain.ok, "{}", plain.stdout);
}

/// `kinema run --scene`: the same swing as a program is refused at the line
/// of its motion; without the scene it runs.
#[test]
fn a_program_through_the_sash_is_refused_at_its_line() {
    let scene = example_scene("fume-hood.toml");
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("swing.krl");
    std::fs::write(&program, "JVEL 50deg/s\nPTP JOINT(90deg, 60deg, 0, 0, 0, 0, 0)\n").unwrap();
    let (program, out) = (program.to_str().unwrap(), dir.path().join("swing.csv"));
    let out = out.to_str().unwrap();
    let base = ["run", program, "--robot", "lbr-iiwa-14-r820", "--start", "-1.5708,1.047,0,0,0,0,0", "--out", out];
    let plain = kinema(&base);
    assert!(plain.ok, "{}", plain.stderr);
    std::fs::remove_file(out).unwrap();
    let refused = kinema(&[&base[..], &["--scene", &scene]].concat());
    assert_eq!(refused.code, Some(1), "{}", refused.stderr);
    assert!(refused.stderr.contains(":2:") && refused.stderr.contains("– sash"), "{}", refused.stderr);
    assert!(!std::path::Path::new(out).exists(), "a refused program writes nothing");
}

/// A scene's robots stand as obstacles at their `start`; `--robot` may name
/// one of them, which then stands on its base there (examples/scenes/two-iiwas.toml,
/// as in the geometry crate's and Python's tests).
#[test]
fn scene_robots_stand_as_obstacles_and_robot_may_name_one() {
    let scene = example_scene("two-iiwas.toml");
    let scene = scene.as_str();
    let reach = kinema(&["collide", "--robot", "holder", "--scene", scene, "--q", "0,90,0,0,0,0,0", "--deg", "--json"]);
    assert_eq!(reach.code, Some(3), "{}", reach.stderr);
    assert!(json(&reach.stdout)["pairs"]
        .as_array()
        .unwrap()
        .iter()
        .any(|p| p["b"].as_str().unwrap().starts_with("drawer/")));
    let away = kinema(&["collide", "--robot", "holder", "--scene", scene, "--q", "90,90,0,0,0,0,0", "--deg"]);
    assert!(away.ok, "{}", away.stdout);
    // The drawer robot answers IK in the scene's world: its solution reaches the target from its base.
    let target = "0.9,0.2,0.6,180,0,0";
    let ik = kinema(&["ik", "--robot", "drawer", "--scene", scene, "--pose", target, "--deg", "--json"]);
    assert!(ik.ok, "{}", ik.stderr);
    let q: Vec<String> =
        json(&ik.stdout)["solutions"][0]["q"].as_array().unwrap().iter().map(|v| v.to_string()).collect();
    let drawer = kinema::traj::cell::placed(
        &kinema::Robot::builtin("lbr-iiwa-14-r820").unwrap(),
        &kinema::Pose::from_xyz_rpy([1.2, 0.0, 0.0], [0.0, 0.0, std::f64::consts::PI], kinema::RpyConvention::Zyx),
    )
    .unwrap();
    let qv: Vec<f64> = q.iter().map(|v| v.parse::<f64>().unwrap().to_radians()).collect();
    let tool = drawer.fk(&qv).unwrap().world_from_tool.pos;
    assert!((tool - kinema::nalgebra::Vector3::new(0.9, 0.2, 0.6)).norm() < 1e-9, "{tool}");
    let nobody = kinema(&["collide", "--robot", "nobody", "--scene", scene, "--q", "home"]);
    assert_eq!(nobody.code, Some(1), "{}", nobody.stderr);
}
