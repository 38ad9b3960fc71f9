//! The language end to end: hand-computed SCARA programs, one test per
//! instruction, every diagnostic, golden listings.

use std::f64::consts::PI;

use kinema::Robot;
use kinema_lang::{compile, Diagnostic, Options, Plan};

fn robot(name: &str) -> Robot {
    Robot::builtin(name).unwrap()
}

/// A built-in robot without its velocity (`vel = false`: kept) and
/// acceleration limits, for tests of what a model without them does.
fn without_limits(name: &str, vel: bool) -> Robot {
    let text = kinema::builtin_source(name).unwrap();
    let keep = |l: &str| !l.starts_with("acc =") && (vel || !l.starts_with("vel ="));
    let text: String = text.lines().filter(|l| keep(l)).map(|l| format!("{l}\n")).collect();
    Robot::from_toml_str(&text, &format!("{name}.toml")).unwrap()
}

fn ok(src: &str, robot: &Robot) -> Plan {
    compile(src, robot, &Options::default())
        .unwrap_or_else(|d| panic!("{}", kinema_lang::render_all(&d, "test.prg", src)))
}

fn errors(src: &str, robot: &Robot) -> Vec<Diagnostic> {
    match compile(src, robot, &Options::default()) {
        Ok(_) => panic!("expected errors for:\n{src}"),
        Err(d) => d.into_iter().filter(|d| d.is_error()).collect(),
    }
}

/// The one error of `src`, its 1-based line and its message.
fn one_error(src: &str, robot: &Robot) -> (usize, String) {
    let e = errors(src, robot);
    assert_eq!(e.len(), 1, "{e:#?}");
    (kinema_lang::diag::line_col(src, e[0].span.start).0, e[0].message.clone())
}

fn tool(robot: &Robot, q: &[f64]) -> kinema::Pose {
    robot.fk(q).unwrap().world_from_tool
}

/// Seed 003's loop, computed by hand: every move is relative, so after each
/// pass of the loop the tool is back where it started; the duration is the
/// sum of the stated times.
#[test]
fn scara_loop_duration_and_final_pose_by_hand() {
    let r = robot("scara5");
    let src = "HOME 3;\nLOOP 4\n  MOVEXY 150, -200, 2;\n  MOVEZ -80, 1;\n  PAUSE 0.5;\n  MOVEZ +80, 1;\n  MOVETITA 90, 1;\n  MOVEXY -150, 200, 2;\n  MOVETITA -90, 1.5;\nEND\n";
    let plan = ok(src, &r);
    // 3 + 4 × (2 + 1 + 0.5 + 1 + 1 + 2 + 1.5) = 39 s.
    assert!((plan.duration() - 39.0).abs() < 1e-9, "{}", plan.duration());
    assert_eq!(plan.motions.len(), 1 + 4 * 7);
    let start = tool(&r, r.home());
    let end = tool(&r, plan.final_q());
    assert!((end.pos - start.pos).norm() < 1e-9, "{} vs {}", end.pos, start.pos);
    assert!((end.rot - start.rot).norm() < 1e-9);
    // Halfway through the first pass (after MOVEXY and MOVEZ): 150 mm, −200 mm, −80 mm away.
    let k = plan.trajectory.times().iter().position(|&t| (t - 6.0).abs() < 1e-9).unwrap();
    let p = tool(&r, plan.trajectory.q(k)).pos - start.pos;
    assert!((p - kinema::nalgebra::Vector3::new(0.15, -0.2, -0.08)).norm() < 1e-9, "{p}");
    // Continuous: no joint moves more than it could in one sample, velocities continuous
    // at the cubic's ends (zero at every instruction boundary of MOVEXY).
    for k in 1..plan.trajectory.len() {
        let (a, b) = (plan.trajectory.q(k - 1), plan.trajectory.q(k));
        assert!(a.iter().zip(b).all(|(x, y)| (x - y).abs() < 0.05), "jump at sample {k}");
    }
}

#[test]
fn the_shipped_scara_program_runs_39_s_and_ends_at_home() {
    let r = robot("scara5");
    let src = include_str!("../../../../examples/programs/scara_pick_place.prg");
    let plan = ok(src, &r);
    assert!((plan.duration() - 39.0).abs() < 1e-9);
    assert!(plan.final_q().iter().zip(r.home()).all(|(a, b)| (a - b).abs() < 1e-12));
}

#[test]
fn the_shipped_iiwa_program_runs_within_limits() {
    let r = robot("lbr-iiwa-14-r820");
    let src = include_str!("../../../../examples/programs/iiwa_draw.prg");
    let plan = ok(src, &r);
    assert!(plan.motions.iter().any(|m| m.kind == "CIRC"));
    let report = kinema::traj::check(&r, &plan.trajectory, &Default::default()).unwrap();
    assert!(report.violations.is_empty());
    assert!(plan.final_q().iter().zip(r.home()).all(|(a, b)| (a - b).abs() < 1e-9));
}

// ---------------------------------------------------------------- instructions

#[test]
fn movez_is_linear_in_time_and_exact() {
    let r = robot("scara5");
    let plan = ok("MOVEZ -50, 2", &r);
    let z0 = tool(&r, r.home()).pos.z;
    let n = plan.trajectory.len();
    for k in 0..n {
        let t = plan.trajectory.times()[k];
        let z = tool(&r, plan.trajectory.q(k)).pos.z;
        assert!((z - (z0 - 0.05 * t / 2.0)).abs() < 1e-12, "t {t}: {z}");
    }
    assert_eq!(plan.motions[0].profile, "linear");
}

#[test]
fn movetita_turns_the_tool_only() {
    let r = robot("scara5");
    let plan = ok("MOVETITA 45, 1.5", &r);
    let a = tool(&r, r.home());
    let b = tool(&r, plan.final_q());
    assert!((a.pos - b.pos).norm() < 1e-12);
    let turn = (a.rot.transpose() * b.rot)[(1, 0)].atan2((a.rot.transpose() * b.rot)[(0, 0)]);
    assert!((turn - PI / 4.0).abs() < 1e-12, "{turn}");
    assert!((plan.duration() - 1.5).abs() < 1e-12);
}

#[test]
fn movexy_follows_a_cubic_in_joint_space_and_keeps_the_tool_angle() {
    let r = robot("scara5");
    let plan = ok("MOVEXY 100, -100, 2", &r);
    let a = tool(&r, r.home());
    let b = tool(&r, plan.final_q());
    assert!((b.pos - a.pos - kinema::nalgebra::Vector3::new(0.1, -0.1, 0.0)).norm() < 1e-9);
    assert!((a.rot - b.rot).norm() < 1e-9, "the tool angle is kept");
    // Rest to rest: zero joint velocity at both ends, peak 1.5·Δ/T in the middle (cubic).
    let traj = &plan.trajectory;
    let last = traj.len() - 1;
    assert!(traj.qd(0).iter().chain(traj.qd(last)).all(|v| v.abs() < 1e-12));
    let mid = traj.times().iter().position(|&t| (t - 1.0).abs() < 1e-9).unwrap();
    for i in 0..3 {
        let d = plan.final_q()[i] - r.home()[i];
        assert!((traj.qd(mid)[i] - 1.5 * d / 2.0).abs() < 1e-9, "joint {i}");
    }
}

#[test]
fn home_and_pause_on_the_scara() {
    let r = robot("scara5");
    let plan = ok("MOVEXY 50, 0, 1; PAUSE 2; HOME 3", &r);
    assert!((plan.duration() - 6.0).abs() < 1e-12);
    assert_eq!(plan.motions.iter().map(|m| m.kind.as_str()).collect::<Vec<_>>(), ["MOVEXY", "WAIT", "HOME"]);
    assert!(plan.final_q().iter().zip(r.home()).all(|(a, b)| (a - b).abs() < 1e-12));
    // PAUSE holds every joint.
    let k = plan.trajectory.times().iter().position(|&t| (t - 2.0).abs() < 1e-9).unwrap();
    assert_eq!(plan.trajectory.q(k), plan.trajectory.q(k + 10));
}

#[test]
fn keywords_are_case_insensitive_and_the_seed_forms_parse_as_printed() {
    let r = robot("scara5");
    let a = ok("home 1;\nloop 2\nmovexy +10 , -10 , 1 ;\nMoveXY -10,+10,1;\nend\n", &r);
    assert!((a.duration() - 5.0).abs() < 1e-12);
}

#[test]
fn ptp_to_joints_cartesian_and_relative() {
    let r = robot("lbr-iiwa-14-r820");
    let src = "JACC 90deg/s^2\nPTP JOINT(10deg, 20deg, 0, -60deg, 0, 40deg, 0)\nPTP REL JOINT(5deg, 0, 0, 0, 0, 0, 0) IN 2s\n";
    let plan = ok(src, &r);
    let q = plan.final_q();
    assert!((q[0] - 15f64.to_radians()).abs() < 1e-12 && (q[3] + 60f64.to_radians()).abs() < 1e-12);
    let m = &plan.motions[1];
    assert!((m.end - m.start - 2.0).abs() < 1e-12, "IN gives the exact duration");
    // A Cartesian target by IK, nearest the current configuration.
    let p = tool(&r, q);
    let rpy = p.rpy(kinema::RpyConvention::Zyx);
    let src2 = format!(
        "{src}PTP CART({}m, {}m, {}m, {}rad, {}rad, {}rad)\nPTP REL CART(0mm, 0mm, 50mm)\n",
        p.pos.x,
        p.pos.y,
        p.pos.z - 0.1,
        rpy[0],
        rpy[1],
        rpy[2]
    );
    let plan = ok(&src2, &r);
    let end = tool(&r, plan.final_q());
    assert!((end.pos - (p.pos - kinema::nalgebra::Vector3::new(0.0, 0.0, 0.05))).norm() < 1e-9);
    assert!((end.rot - p.rot).norm() < 1e-9);
}

#[test]
fn lin_and_circ_follow_their_paths_and_blend() {
    let r = robot("lbr-iiwa-14-r820");
    let head = "VEL 200mm/s\nPOS a = CART(550mm, -150mm, 300mm, 0deg, 180deg, 0deg)\nJACC 90deg/s^2\nPTP a\n";
    // A straight line: every sample on the segment.
    let plan = ok(&format!("{head}LIN REL CART(0mm, 200mm, 0mm)\n"), &r);
    let k0 = plan.trajectory.times().iter().position(|&t| t >= plan.motions[1].start).unwrap();
    for k in k0..plan.trajectory.len() {
        let p = tool(&r, plan.trajectory.q(k)).pos;
        assert!((p.x - 0.55).abs() < 1e-6 && (p.z - 0.3).abs() < 1e-6 && p.y > -0.15 - 1e-9 && p.y < 0.05 + 1e-9);
    }
    // A CIRC through an auxiliary point: every sample on the circle.
    let plan =
        ok(&format!("{head}CIRC CART(600mm, -100mm, 300mm), CART(650mm, -150mm, 300mm, 0deg, 180deg, 0deg)\n"), &r);
    let k0 = plan.trajectory.times().iter().position(|&t| t >= plan.motions[1].start).unwrap();
    for k in k0..plan.trajectory.len() {
        let p = tool(&r, plan.trajectory.q(k)).pos;
        let d = ((p.x - 0.6).powi(2) + (p.y + 0.15).powi(2)).sqrt();
        assert!((d - 0.05).abs() < 1e-6 && (p.z - 0.3).abs() < 1e-6, "{p}");
    }
    // BLEND: the chain does not stop at the corner, and is shorter than stopping.
    let stop = ok(&format!("{head}PROFILE scurve\nLIN REL CART(0mm, 200mm, 0mm)\nLIN REL CART(100mm, 0mm, 0mm)\n"), &r);
    let blend = ok(
        &format!("{head}PROFILE scurve\nLIN REL CART(0mm, 200mm, 0mm) BLEND 30mm\nLIN REL CART(100mm, 0mm, 0mm)\n"),
        &r,
    );
    assert!(blend.warnings.is_empty(), "{:?}", blend.warnings);
    // The trapezoid cannot blend a right angle at full acceleration: a warning says so.
    let sharp = ok(&format!("{head}LIN REL CART(0mm, 200mm, 0mm) BLEND 30mm\nLIN REL CART(100mm, 0mm, 0mm)\n"), &r);
    assert!(sharp.warnings.iter().any(|w| w.message.contains("reduced to nothing")), "{:?}", sharp.warnings);
    assert!(blend.duration() < stop.duration() - 0.05, "{} vs {}", blend.duration(), stop.duration());
    let corner = blend.motions[2].start + 0.5 * (blend.motions[1].end - blend.motions[2].start);
    let k = blend.trajectory.times().iter().position(|&t| t >= blend.motions[2].start).unwrap();
    assert!(blend.trajectory.qd(k).iter().any(|v| v.abs() > 1e-3), "moving at {corner}");
}

#[test]
fn speed_override_scales_time() {
    let r = robot("lbr-iiwa-14-r820");
    let head = "POS a = CART(550mm, -150mm, 300mm, 0deg, 180deg, 0deg)\nJACC 90deg/s^2\nPTP a\n";
    let full = ok(&format!("{head}LIN REL CART(0mm, 200mm, 0mm)\n"), &r);
    let half = ok(&format!("{head}SPEED 50%\nLIN REL CART(0mm, 200mm, 0mm)\n"), &r);
    let (a, b) = (&full.motions[1], &half.motions[1]);
    assert!(((b.end - b.start) / (a.end - a.start) - 2.0).abs() < 1e-9, "v·k, a·k², j·k³ is a time scaling by 1/k");
}

#[test]
fn for_counts_and_its_counter_is_usable() {
    let r = robot("scara5");
    let plan = ok("FOR i = 1 TO 3\n  MOVEZ -10*i, 1\nEND\n", &r);
    assert_eq!(plan.motions.len(), 3);
    let dz = tool(&r, plan.final_q()).pos.z - tool(&r, r.home()).pos.z;
    assert!((dz + 0.06).abs() < 1e-12, "{dz}");
}

#[test]
fn tool_and_base_frames() {
    let r = robot("lbr-iiwa-14-r820");
    // With a 100 mm tool along z, the tool point of the same joints lies 100 mm further along the flange z.
    let plan = ok("TOOL CART(0mm, 0mm, 100mm, 0deg, 0deg, 0deg)\nWAIT 0.1s\n", &r);
    let flange = tool(&r, plan.final_q());
    let with_tool = plan.robot.fk(plan.final_q()).unwrap().world_from_tool;
    assert!((with_tool.pos - flange.pos - flange.rot.column(2) * 0.1).norm() < 1e-12);
    // A BASE shifts later Cartesian targets.
    let src = "JACC 90deg/s^2\nBASE CART(0mm, 100mm, 0mm, 0deg, 0deg, 0deg)\nPTP CART(550mm, -150mm, 300mm, 0deg, 180deg, 0deg)\n";
    let plan = ok(src, &r);
    let p = tool(&r, plan.final_q()).pos;
    assert!((p - kinema::nalgebra::Vector3::new(0.55, -0.05, 0.3)).norm() < 1e-9, "{p}");
}

/// The SCARA takes a tool offset and turned about z, and its relative moves then move that
/// tool point. A tilted tool is fine for PTP and HOME (a warning), but the relative moves,
/// which need the closed-form IK, are errors after it (not silently nothing), and HOME
/// keeps seed 003's law.
#[test]
fn scara_tool_offset_is_followed_and_a_tilted_one_stops_the_relative_moves() {
    let r = robot("scara5");
    let src = "TOOL CART(50mm, 0mm, 0mm, 0deg, 0deg, 30deg)\nHOME 1\nMOVEXY 20, -10, 1\nMOVEZ -30, 1\n";
    let plan = ok(src, &r);
    let start = plan.robot.fk(r.home()).unwrap().world_from_tool;
    let end = plan.robot.fk(plan.final_q()).unwrap().world_from_tool;
    let moved = end.pos - start.pos;
    assert!((moved - kinema::nalgebra::Vector3::new(0.02, -0.01, -0.03)).norm() < 1e-9, "{moved}");
    assert!((plan.duration() - 3.0).abs() < 1e-9, "{}", plan.duration());
    let tilted = "TOOL CART(0mm, 0mm, 50mm, 0deg, 20deg, 0deg)";
    // PTP and HOME (seed 003's law, its stated time) after the tilted tool: a warning at TOOL.
    let src = format!("{tilted}\nPTP JOINT(100mm, 10deg, 10deg, 50mm, 0deg) IN 1s\nHOME 2\n");
    let plan = ok(&src, &r);
    assert!((plan.duration() - 3.0).abs() < 1e-9, "{}", plan.duration());
    assert_eq!(plan.final_q(), r.home());
    let w: Vec<_> = compile(&src, &r, &Options::default()).unwrap().warnings.into_iter().collect();
    assert!(
        w.iter()
            .any(|d| d.message.contains("cannot tilt it") && kinema_lang::diag::line_col(&src, d.span.start).0 == 1),
        "{w:#?}"
    );
    for (moves, line) in [("MOVEZ -30, 1", 3), ("MOVEXY 10, 0, 1", 3), ("MOVETITA 10, 1", 3)] {
        let src = format!("HOME 1\n{tilted}\n{moves}\n");
        let (at, message) = one_error(&src, &r);
        assert_eq!(at, line, "{message}");
        assert!(message.contains("cannot take the TOOL at line 2: ") && message.contains("cannot tilt"), "{message}");
    }
    // A later tool the solver takes brings the relative moves back.
    ok(&format!("HOME 1\n{tilted}\nTOOL CART(0mm, 0mm, 50mm, 0deg, 0deg, 0deg)\nMOVEZ -30, 1\n"), &r);
}

#[test]
fn syntax_errors_are_all_reported_with_their_lines() {
    let r = robot("scara5");
    let src = "HOME 1\nMOVEXY 10 10, 1\nFOO 3\nMOVEZ , 1\nLOOP 2\nMOVEZ 1, 1\n";
    let e = errors(src, &r);
    let lines: Vec<usize> = e.iter().map(|d| kinema_lang::diag::line_col(src, d.span.start).0).collect();
    assert_eq!(lines, [2, 3, 4, 5], "{e:#?}");
    assert!(e[1].message.contains("unknown statement `FOO`"));
    assert!(e[3].message.contains("LOOP without END"));
    // A misspelt keyword gets a suggestion.
    let e = errors("MOVXY 1, 2, 3", &r);
    assert_eq!(e[0].hint.as_deref(), Some("did you mean MOVEXY?"));
    let e = errors("END\n", &r);
    assert!(e[0].message.contains("END without LOOP"));
}

#[test]
fn semantic_errors() {
    let s = robot("scara5");
    let iiwa = robot("lbr-iiwa-14-r820");
    let cases: &[(&Robot, &str, usize, &str)] = &[
        (&iiwa, "PTP nowhere", 1, "unknown position `nowhere`"),
        (&iiwa, "WAIT 1s\nPTP JOINT(0deg, 1deg)", 2, "JOINT has 2 values; `lbr-iiwa-14-r820` has 7 joints"),
        (&iiwa, "LIN CART(1m, 2m)", 1, "CART has 2 values"),
        (&iiwa, "WAIT 5mm", 1, "expected a time (s, ms), found a length"),
        (&iiwa, "PTP JOINT(1, 0, 0, 0, 0, 0, 0)", 1, "missing unit: expected an angle"),
        (&iiwa, "SPEED 150%", 1, "SPEED must be in (0 %, 100 %]"),
        (&iiwa, "VEL 2s", 1, "expected a linear speed"),
        (&iiwa, "LOOP 0\nWAIT 1s\nEND", 1, "a loop count must be a positive whole number, not 0"),
        (&iiwa, "LOOP 2.5\nWAIT 1s\nEND", 1, "not 2.5"),
        (&iiwa, "FOR i = 1 TO 2.5\nWAIT 1s\nEND", 1, "FOR bounds are whole numbers"),
        (&iiwa, "MOVEZ -10, 1", 1, "MOVEZ is an instruction of the SCARA on a rail"),
        (&iiwa, "PROFILE wobbly", 1, "unknown profile `wobbly`"),
        (&iiwa, "WAIT 1s + 2mm", 1, "cannot add a time (s, ms) and a length"),
        (&iiwa, "WAIT j", 1, "unknown name `j`"),
        (&iiwa, "WAIT 1s / 0", 1, "division by zero"),
        (&s, "MOVEZ 5s, 1", 1, "expected a length"),
        (&s, "HOME 0", 1, "a duration must be positive"),
        (&iiwa, "LIN REL JOINT(0, 0, 0, 0, 0, 0, 0)", 1, "LIN REL takes a Cartesian offset"),
    ];
    for (r, src, line, msg) in cases {
        let (l, m) = one_error(src, r);
        assert_eq!(l, *line, "{src}: {m}");
        assert!(m.contains(msg), "{src}: `{m}` does not contain `{msg}`");
    }
}

#[test]
fn several_semantic_errors_in_one_run() {
    let r = robot("lbr-iiwa-14-r820");
    let e = errors("PTP a\nWAIT 3mm\nLOOP 0\nWAIT 1s\nEND\nMOVEZ 1, 1\n", &r);
    assert_eq!(e.len(), 4, "{e:#?}");
}

#[test]
fn unreachable_targets_name_the_line_and_the_reason() {
    let s = robot("scara5");
    // Beyond the rail: the zone rule reports how far outside the rectangle.
    let (line, msg) = one_error("HOME 1\nMOVEXY 0, 900, 2\n", &s);
    assert_eq!(line, 2);
    assert!(msg.contains("unreachable") && msg.contains("outside"), "{msg}");
    let r = robot("lbr-iiwa-14-r820");
    let (line, msg) = one_error("JACC 90deg/s^2\nWAIT 1s\nPTP CART(3m, 0m, 0.5m, 0deg, 0deg, 0deg)\n", &r);
    assert_eq!(line, 3);
    assert!(msg.contains("target unreachable") && msg.contains("outside"), "{msg}");
}

#[test]
fn limit_violations_name_the_line_the_joint_and_the_time() {
    let s = robot("scara5");
    // z would go to 0.25 m of its 0.2 m stroke.
    let (line, msg) = one_error("HOME 1\nMOVEZ -150, 1\n", &s);
    assert_eq!(line, 2);
    assert!(msg.contains("joint 4 (z)") && msg.contains("outside its limits"), "{msg}");
    // The iiwa's A1 at 85 °/s (Cuadro I): 90° in 0.5 s is too fast; the check names the joint and the time.
    // (It breaks the estimated acceleration limit too: reported as well, from its first sample, t = 1 s,
    // which is also the WAIT's end.)
    let r = robot("lbr-iiwa-14-r820");
    let src = "WAIT 1s\nPTP REL JOINT(90deg, 0, 0, 0, 0, 0, 0) IN 0.5s\n";
    let e = errors(src, &r);
    let velocity = e.iter().find(|d| d.message.contains("velocity")).expect("a velocity error");
    assert_eq!(kinema_lang::diag::line_col(src, velocity.span.start).0, 2);
    let msg = &velocity.message;
    assert!(msg.contains("A1") && msg.contains("t = "), "{msg}");
}

#[test]
fn rendered_diagnostics_show_file_line_column_source_and_hint() {
    let r = robot("lbr-iiwa-14-r820");
    let src = "WAIT 1s\n  WAIT 5mm\n";
    let e = errors(src, &r);
    let text = kinema_lang::render_all(&e, "prog.krl", src);
    assert!(text.starts_with("prog.krl:2:8: error: expected a time"), "{text}");
    assert!(text.contains("  WAIT 5mm"), "{text}");
    assert!(text.contains("1 error(s)"), "{text}");
}

#[test]
fn runaway_programs_are_cut_with_an_error() {
    let r = robot("scara5");
    let opts = Options { max_steps: 1000, ..Options::default() };
    let e = compile("LOOP 1000000\nLOOP 1000000\nPAUSE 0.01\nEND\nEND\n", &r, &opts).unwrap_err();
    assert!(e.iter().any(|d| d.message.contains("more than the step limit of 1000 allows")), "{e:#?}");
    let opts = Options { max_samples: 500, ..Options::default() };
    let e = compile("PAUSE 100\n", &r, &opts).unwrap_err();
    assert!(e.iter().any(|d| d.message.contains("more than 500 samples")), "{e:#?}");
    // Exactly the cap fits: the start sample and 999 more (it was refused as "more than 1000").
    let opts = Options { max_samples: 1000, ..Options::default() };
    assert_eq!(compile("WAIT 9.99s\n", &r, &opts).unwrap().trajectory.len(), 1000);
    assert_eq!(compile("WAIT 5s\nWAIT 4.99s\n", &r, &opts).unwrap().trajectory.len(), 1000);
    assert!(compile("WAIT 10s\n", &r, &opts).is_err());
    assert!(compile("WAIT 5s\nWAIT 5s\n", &r, &opts).is_err());
}

/// One statement that alone lasts too long to sample is an error at that statement, not
/// dropped: a `WAIT` of 10⁷ s, or a timed motion the plan would end before.
#[test]
fn a_statement_too_long_to_sample_is_an_error_not_skipped() {
    let iiwa = robot("lbr-iiwa-14-r820");
    let scara = robot("scara5");
    for (src, r, line) in [
        ("WAIT 10000000s\n", &iiwa, 1),
        ("PTP HOME\nWAIT 1e9 s\n", &iiwa, 2),
        ("PTP JOINT(10deg, 0deg, 0deg, -60deg, 0deg, 30deg, 0deg) IN 3e6s\n", &iiwa, 1),
        ("// seed 003\nHOME 1;\nPAUSE 1e8;\n", &scara, 3),
        ("HOME 1;\nMOVEZ -50, 2e6;\n", &scara, 2),
    ] {
        let (at, message) = one_error(src, r);
        assert_eq!(at, line, "{src}: {message}");
        assert!(message.contains("samples (at most 10000000)"), "{src}: {message}");
    }
}

/// Under the per-statement limit but over the program's cap (5·10⁶ samples at dt = 0.01 s):
/// the error is at the statement that crosses it.
#[test]
fn a_program_over_the_sample_cap_stops_at_the_statement_that_crosses_it() {
    let iiwa = robot("lbr-iiwa-14-r820");
    let cap = "more than 5000000 samples";
    for (src, line) in [
        ("WAIT 60000s\n", 1),
        ("WAIT 30000s\nWAIT 19999.9s\nWAIT 1s\n", 3),
        // A PTP timed by joint limits, checked before it is sampled too.
        ("JVEL 0.001 deg/s\nJACC 90 deg/s^2\nWAIT 1s\nPTP JOINT(10deg, 0deg, 0deg, -60deg, 0deg, 30deg, 0deg)\n", 4),
        ("JACC 90 deg/s^2\nPTP JOINT(10deg, 0deg, 0deg, -60deg, 0deg, 30deg, 0deg)\nLIN REL CART(100mm, 0mm, 0mm) IN 60000s\n", 3),
    ] {
        let (at, message) = one_error(src, &iiwa);
        assert_eq!(at, line, "{src}: {message}");
        assert!(message.contains(cap), "{src}: {message}");
    }
}

/// The cap is checked before a motion's samples are computed: a line that would leave the
/// workspace after the cap is refused for the cap, not followed until IK fails (which, for a
/// motion of millions of samples, took minutes and gigabytes before the cap was seen).
#[test]
fn the_sample_cap_is_checked_before_a_motion_is_computed() {
    let iiwa = robot("lbr-iiwa-14-r820");
    let src = "JACC 90 deg/s^2\nPTP JOINT(10deg, 0deg, 0deg, -60deg, 0deg, 30deg, 0deg)\nLIN REL CART(3000mm, 0mm, 0mm) IN 20s\n";
    let unreachable = errors(src, &iiwa);
    assert!(unreachable[0].message.contains("cannot be followed"), "{unreachable:#?}");
    let opts = Options { max_samples: 900, ..Options::default() };
    let d: Vec<_> = compile(src, &iiwa, &opts).unwrap_err().into_iter().filter(|d| d.is_error()).collect();
    assert_eq!(d.len(), 1, "{d:#?}");
    assert!(d[0].message.contains("more than 900 samples"), "{d:#?}");
    assert_eq!(kinema_lang::diag::line_col(src, d[0].span.start).0, 3);
}

// ---------------------------------------------------------------- golden listings

/// Each `tests/golden/*.prg` compiles to exactly its `.listing` (robot named
/// on the first line as `// robot: NAME`). `UPDATE_GOLDEN=1` rewrites them.
#[test]
fn golden_listings() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    let mut count = 0;
    let mut entries: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for path in entries.into_iter().filter(|p| p.extension().is_some_and(|e| e == "prg")) {
        let src = std::fs::read_to_string(&path).unwrap();
        let name = src.lines().next().and_then(|l| l.strip_prefix("// robot: ")).expect("first line names the robot");
        let plan = ok(&src, &robot(name.trim()));
        let got = plan.listing();
        let want_path = path.with_extension("listing");
        if std::env::var_os("UPDATE_GOLDEN").is_some() {
            std::fs::write(&want_path, &got).unwrap();
        }
        let want = std::fs::read_to_string(&want_path).unwrap_or_default();
        assert_eq!(got, want, "{} changed; rerun with UPDATE_GOLDEN=1 if that is intended", path.display());
        count += 1;
    }
    assert!(count >= 3, "{count}");
}

/// The Scorbot square (seed 000 Fig. 6): each 100 mm edge at 20 mm/s with
/// 100 mm/s² takes 0.2 s to accelerate (2 mm), 4.8 s to cruise 96 mm and
/// 0.2 s to stop: 5.2 s; with the 4 s PTP and HOME, 4 + 8 × 5.2 + 4 = 49.6 s.
/// Every sample of the edges lies on the square, pen vertical.
#[test]
fn scorbot_square_by_hand() {
    let r = robot("scorbot-er-v-plus");
    let plan = ok(include_str!("../../../../examples/programs/scorbot_square.prg"), &r);
    assert!((plan.duration() - 49.6).abs() < 1e-9, "{}", plan.duration());
    let (t0, t1) = (plan.motions[1].start, plan.motions[8].end);
    for k in 0..plan.trajectory.len() {
        let t = plan.trajectory.times()[k];
        if t < t0 || t > t1 {
            continue;
        }
        let p = tool(&r, plan.trajectory.q(k));
        let on_x_edge = (p.pos.x - 0.35).abs() < 1e-6 || (p.pos.x - 0.45).abs() < 1e-6;
        let on_y_edge = (p.pos.y + 0.05).abs() < 1e-6 || (p.pos.y - 0.05).abs() < 1e-6;
        assert!(on_x_edge || on_y_edge, "t {t}: {}", p.pos);
        assert!((p.pos.z - 0.15).abs() < 1e-6 && (p.rot.column(2) + kinema::nalgebra::Vector3::z()).norm() < 1e-6);
    }
}

/// Found in review: JVEL/JACC on a robot with both joint kinds, counter
/// values out of range at run time, names with a dash after a digit, and a
/// start outside the limits.
#[test]
fn review_findings_stay_fixed() {
    let s = robot("scara5");
    // Only revolute joints move: the angular JVEL/JACC suffice.
    let plan = ok("JVEL 30deg/s\nJACC 60deg/s^2\nPTP REL JOINT(0mm, 10deg, 0deg, 0mm, 0deg)\n", &s);
    assert!(plan.duration() > 0.3);
    // The rail moves too and the model gives it no limits: the error names it and the statement to use.
    let bare = without_limits("scara5", false);
    let (line, msg) = one_error("JVEL 30deg/s\nJACC 60deg/s^2\nPTP REL JOINT(50mm, 10deg, 0deg, 0mm, 0deg)\n", &bare);
    assert_eq!(line, 3);
    assert!(msg.contains("joint 1 (rail)") && msg.contains("JVEL <value> mm/s"), "{msg}");
    // A counter makes SPEED 150 %.
    let iiwa = robot("lbr-iiwa-14-r820");
    let (line, msg) = one_error("FOR i = 1 TO 3\n  SPEED i * 50%\nEND\n", &iiwa);
    assert_eq!(line, 2);
    assert!(msg.contains("SPEED must be in"), "{msg}");
    let (_, msg) = one_error("FOR i = 1 TO 2\n  WAIT 1s - i * 1s\nEND\n", &iiwa);
    assert!(msg.contains("cannot be negative"), "{msg}");
    // The iiwa's named pose `sing-q2-q3` can be used by name.
    let e = kinema_lang::check("PTP sing-q2-q3 IN 3s\n", &iiwa, &Options::default());
    assert!(e.iter().all(|d| !d.message.contains("unknown")), "{e:?}");
    // A start outside the limits is refused up front.
    let opts = Options { start: Some(vec![0.0, 0.0, 0.0, 0.5, 0.0]), ..Options::default() };
    let e = compile("WAIT 1s", &s, &opts).unwrap_err();
    assert!(e[0].message.contains("start configuration: joint 4 (z)"), "{e:?}");
}

/// REDUNDANCY chooses the iiwa's self-motion in LIN: held, fixed at a
/// value, or steered; bad policies and arms without a self-motion are
/// errors at their line.
#[test]
fn redundancy_chooses_the_self_motion_of_later_lines() {
    // Without the iiwa's (estimated) acceleration limits: seed 004's rule
    // starts turning q3 at the LIN's first decision, and joint 1 follows at
    // 16.6 rad/s² (the rule bounds q3's acceleration, not the other joints').
    let r = without_limits("lbr-iiwa-14-r820", true);
    let head = "VEL 100mm/s\nJACC 90deg/s^2\nPTP JOINT(-20deg, 50deg, 20deg, -60deg, 10deg, 50deg, 0)\n";
    let line = "LIN REL CART(0mm, 100mm, 50mm)\n";
    // q3 over the LIN (the last motion).
    let q3_range = |plan: &Plan| {
        let t = &plan.trajectory;
        let from = plan.motions.last().unwrap().start;
        let q3: Vec<f64> = (0..t.len()).filter(|&k| t.times()[k] >= from).map(|k| t.q(k)[2]).collect();
        q3.iter().cloned().fold(f64::NEG_INFINITY, f64::max) - q3.iter().cloned().fold(f64::INFINITY, f64::min)
    };
    for policy in ["", "REDUNDANCY hold\n", "REDUNDANCY q3 = 20deg\n"] {
        let plan = ok(&format!("{head}{policy}{line}"), &r);
        assert!(q3_range(&plan) < 1e-9, "{policy:?}: q3 moved by {}", q3_range(&plan));
        assert!((plan.final_q()[2] - 20f64.to_radians()).abs() < 1e-9);
    }
    let steered = ok(&format!("{head}REDUNDANCY manipulability\n{line}"), &r);
    assert!(q3_range(&steered) > 1e-3, "the rule never moved q3");
    let tracked = ok(&format!("{head}REDUNDANCY track\n{line}"), &r);
    let end = tool(&r, tracked.final_q());
    let want = tool(&r, ok(&format!("{head}{line}"), &r).final_q());
    assert!((end.pos - want.pos).norm() < 1e-6);
    let (at, message) = one_error(&format!("{head}REDUNDANCY sideways\n{line}"), &r);
    assert_eq!(at, 4);
    assert!(message.contains("sideways"), "{message}");
    let (at, message) = one_error(&format!("{head}REDUNDANCY q3 = 10deg\n{line}"), &r);
    assert_eq!(at, 5);
    assert!(message.contains("q3 = 0.349") && message.contains("0.17453"), "{message}");
    let puma = robot("puma560");
    let (at, message) = one_error("REDUNDANCY hold\nLIN REL CART(0mm, 0mm, 20mm)\n", &puma);
    assert_eq!(at, 2);
    assert!(message.contains("no self-motion"), "{message}");
}

/// Seed 003 Fig. 9: with `skip_unreachable` a point outside the workspace is
/// left out with a warning at its line and the path goes on to the next
/// point, as if it had not been written; without it, an error there.
#[test]
fn skip_unreachable_leaves_out_a_point_outside_the_workspace() {
    let r = robot("scara5");
    let src = include_str!("../../../../examples/programs/seed003_fig9_skip.prg");
    let (at, message) = one_error(src, &r);
    assert_eq!(at, 4);
    assert!(message.contains("unreachable"), "{message}");
    let skip = Options { skip_unreachable: true, ..Options::default() };
    let plan = compile(src, &r, &skip).unwrap_or_else(|d| panic!("{}", kinema_lang::render_all(&d, "fig9", src)));
    assert_eq!(plan.warnings.len(), 1);
    assert_eq!(kinema_lang::diag::line_col(src, plan.warnings[0].span.start).0, 4);
    assert!(plan.warnings[0].message.contains("skipped"));
    // The same path without the point, written out.
    let without: String = src.lines().filter(|l| !l.contains("2000")).map(|l| format!("{l}\n")).collect();
    let reference = ok(&without, &r);
    assert_eq!(plan.trajectory, reference.trajectory);
    // Cartesian PTP and LIN targets out of reach are skipped the same way.
    let iiwa = robot("lbr-iiwa-14-r820");
    let src =
        "JACC 90deg/s^2\nPTP JOINT(0, 40deg, 0, -60deg, 0, 60deg, 0)\nPTP CART(3m, 0m, 0.5m, 0deg, 180deg, 0deg)\n\
               LIN CART(0m, 3m, 0.5m, 0deg, 180deg, 0deg)\nLIN REL CART(0mm, 0mm, 30mm)\n";
    assert_eq!(errors(src, &iiwa).len(), 2);
    let plan = compile(src, &iiwa, &skip).unwrap_or_else(|d| panic!("{}", kinema_lang::render_all(&d, "t", src)));
    let lines: Vec<usize> = plan
        .warnings
        .iter()
        .filter(|w| w.message.contains("skipped"))
        .map(|w| kinema_lang::diag::line_col(src, w.span.start).0)
        .collect();
    assert_eq!(lines, [3, 4]);
    assert_eq!(plan.motions.len(), 2, "the PTP and the last LIN ran");
}
