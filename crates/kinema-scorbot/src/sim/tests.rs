//! Unit tests of the controller state machine (no sockets, explicit time).

use std::time::Duration;

use kinema::Robot;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::*;
use crate::encoder::Constants;

fn ms(v: u64) -> Duration {
    Duration::from_millis(v)
}

fn sim(scale: f64) -> Controller {
    Controller::new(SimConfig { time_scale: scale, ..SimConfig::default() }).unwrap()
}

/// Sends one line at `t` and returns what is printed at once.
fn say(c: &mut Controller, t: Duration, line: &str) -> String {
    c.feed(t, format!("{line}\r").as_bytes());
    String::from_utf8_lossy(&c.take_output(t)).into_owned()
}

/// Sends a command that must answer `Done.` at once.
fn ok(c: &mut Controller, t: Duration, line: &str) {
    let out = say(c, t, line);
    assert_eq!(out, format!("{line}\r\nDone.\r\n>"), "{line}");
}

/// Advances in 1 ms steps from `from` until the output ends with the prompt;
/// returns the output and the time it completed.
fn wait_prompt(c: &mut Controller, from: Duration, limit: Duration) -> (String, Duration) {
    let mut out = Vec::new();
    let mut t = from;
    loop {
        c.advance(t);
        out.extend(c.take_output(t));
        if out.ends_with(b">") || t > limit {
            return (String::from_utf8_lossy(&out).into_owned(), t);
        }
        t += ms(1);
    }
}

fn homed(scale: f64) -> Controller {
    let mut c = sim(scale);
    assert_eq!(say(&mut c, ms(0), "HOME"), "HOME\r\nHOMING...\r\n");
    let (out, t) = wait_prompt(&mut c, ms(0), ms(10_000));
    assert_eq!(out, "Done.\r\n>");
    assert!(c.is_homed() && t <= ms(1_000));
    c
}

fn listpv(c: &mut Controller, t: Duration, p: &str) -> ([i64; 5], [i64; 5]) {
    let out = say(c, t, &format!("LISTPV {p}"));
    let lines: Vec<&str> = out.split("\r\n").collect();
    assert_eq!(lines.len(), 5, "{out:?}");
    assert_eq!(lines[1], format!("Position {}", p.to_ascii_uppercase()));
    let values = |l: &str| -> [i64; 5] {
        let v: Vec<i64> = l.split_whitespace().map(|kv| kv.split_once(':').unwrap().1.parse().unwrap()).collect();
        v.try_into().unwrap()
    };
    (values(lines[2]), values(lines[3]))
}

#[test]
fn framing_echo_replies_prompt_and_case() {
    let mut c = sim(1.0);
    assert_eq!(say(&mut c, ms(0), "con"), "con\r\nDone.\r\n>");
    assert_eq!(say(&mut c, ms(0), ""), "\r\n>");
    assert_eq!(say(&mut c, ms(0), "Jump 3"), "Jump 3\r\n*** UNKNOWN COMMAND\r\n>");
    assert_eq!(
        say(&mut c, ms(0), "speed 0"),
        "speed 0\r\n*** BAD ARGUMENT: speed `0`; it must be an integer 1..100\r\n>"
    );
    assert!(say(&mut c, ms(0), "SPEED").contains("*** BAD ARGUMENT"));
    assert!(say(&mut c, ms(0), "CON 1").contains("*** BAD ARGUMENT"));
    ok(&mut c, ms(0), "SpEeD 75");
    assert_eq!(c.speed(), 75);
    // Line feeds are ignored; several lines in one read; a line split over reads.
    c.feed(ms(1), b"CON\r\nCOF");
    c.feed(ms(1), b"F\r");
    assert_eq!(c.take_output(ms(1)), b"CON\r\nDone.\r\n>COFF\r\nDone.\r\n>");
    assert!(!c.control_on());
    // Nothing is printed before a line ends.
    c.feed(ms(2), b"CON");
    assert!(c.take_output(ms(2)).is_empty());
}

#[test]
fn home_takes_five_scaled_seconds_and_motion_before_home_is_refused() {
    let mut c = sim(0.01);
    ok(&mut c, ms(0), "DEFP P1");
    ok(&mut c, ms(0), "SETPV P1 1 1000");
    assert_eq!(say(&mut c, ms(0), "MOVE P1"), "MOVE P1\r\n*** HOME NOT DONE\r\n>");
    assert!(say(&mut c, ms(0), "MOVED P1").contains("*** HOME NOT DONE"));
    assert_eq!(say(&mut c, ms(10), "HOME"), "HOME\r\nHOMING...\r\n");
    c.advance(ms(59));
    assert!(c.take_output(ms(59)).is_empty());
    assert!(!c.is_homed());
    c.advance(ms(60));
    assert_eq!(c.take_output(ms(60)), b"Done.\r\n>");
    assert!(c.is_homed());
    ok(&mut c, ms(60), "MOVE P1");
}

#[test]
fn control_off_refuses_motion() {
    let mut c = homed(0.01);
    ok(&mut c, ms(100), "HERE P");
    ok(&mut c, ms(100), "COFF");
    for cmd in ["MOVE P", "MOVED P", "HOME", "OPEN", "CLOSE"] {
        assert_eq!(say(&mut c, ms(100), cmd), format!("{cmd}\r\n*** CONTROL DISABLED\r\n>"));
    }
    ok(&mut c, ms(100), "CON");
    ok(&mut c, ms(100), "MOVE P");
}

#[test]
fn moved_takes_the_slowest_motor_time_or_the_given_time() {
    let mut c = homed(0.01);
    let t0 = ms(1000);
    ok(&mut c, t0, "DEFP A");
    // Motor 1: 14188 counts = 100° at 45°/s (speed 50) = 2.222 s → 22.2 ms.
    ok(&mut c, t0, "SETPV A 1 14188");
    // Motor 4 and 5: 2790 counts = 100° at 90°/s = 1.111 s: not the slowest.
    ok(&mut c, t0, "SETPV A 4 2790");
    ok(&mut c, t0, "SETPV A 5 2790");
    assert_eq!(say(&mut c, t0, "MOVED A"), "MOVED A\r\n");
    assert!(c.is_moving());
    let (out, t) = wait_prompt(&mut c, t0, t0 + ms(1000));
    assert_eq!(out, "Done.\r\n>");
    assert_eq!(t - t0, ms(23), "2.222 s × 0.01");
    assert_eq!(c.counts(), [14188, 0, 0, 2790, 2790]);
    // With a time argument: 300 hundredths = 3 s → 30 ms.
    ok(&mut c, t, "DEFP B");
    ok(&mut c, t, "SETPV B 1 0");
    assert_eq!(say(&mut c, t, "moved b 300"), "moved b 300\r\n");
    let (out, t2) = wait_prompt(&mut c, t, t + ms(1000));
    assert_eq!(out, "Done.\r\n>");
    assert_eq!(t2 - t, ms(30));
    assert_eq!(c.counts(), [0; 5]);
    // Speed 100 halves the time.
    ok(&mut c, t2, "SPEED 100");
    say(&mut c, t2, "MOVED A");
    let (_, t3) = wait_prompt(&mut c, t2, t2 + ms(1000));
    assert_eq!(t3 - t2, ms(12));
    for bad in ["MOVED A 0", "MOVED A x", "MOVED A 1 2", "MOVED", "MOVED 9A", "MOVED NOPE"] {
        let out = say(&mut c, t3, bad);
        assert!(out.contains("***") && out.ends_with('>'), "{bad}: {out}");
    }
}

#[test]
fn setpv_listpv_here_and_the_home_reading() {
    let mut c = homed(0.01);
    let t = ms(500);
    ok(&mut c, t, "HERE H");
    let (counts, cart) = listpv(&mut c, t, "H");
    assert_eq!(counts, [0; 5]);
    // The README: the home reads X 1691, Z 5044, P −636 with the factory
    // constants; the model's FK gives 1690.27, 5043.27, −635.48 (rounded here).
    assert_eq!(cart, [1690, 0, 5043, -635, 0]);
    assert_eq!(say(&mut c, t, "SETPV Q 1 5"), "SETPV Q 1 5\r\n*** POSITION Q NOT DEFINED\r\n>");
    ok(&mut c, t, "DEFP Q");
    assert_eq!(say(&mut c, t, "LISTPV Q"), "LISTPV Q\r\n*** POSITION Q HAS NO COORDINATES\r\n>");
    ok(&mut c, t, "SETPV Q 2 -1000");
    ok(&mut c, t, "setpv q 5 300");
    let (counts, cart) = listpv(&mut c, t, "q");
    assert_eq!(counts, [0, -1000, 0, 0, 300]);
    let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
    let k = Constants::named("factory").unwrap();
    let q = k.angles(&[0.0, -1000.0, 0.0, 0.0, 300.0]).unwrap();
    let p = robot.fk(&q).unwrap().world_from_tool.pos;
    assert_eq!(cart[0], (p.x * 1e4).round() as i64);
    assert_eq!(cart[2], (p.z * 1e4).round() as i64);
    assert_eq!(cart[3], ((q[1] + q[2] + q[3]).to_degrees() * 10.0).round() as i64);
    assert_eq!(cart[4], (q[4].to_degrees() * 10.0).round() as i64);
    for bad in ["SETPV Q 6 1", "SETPV Q 0 1", "SETPV Q 1 1.5", "SETPV Q 1 99999999999", "SETPV Q[ 1 1", "SETPV Q"] {
        assert!(say(&mut c, t, bad).contains("*** BAD ARGUMENT"), "{bad}");
    }
}

#[test]
fn setpvc_solves_with_the_controllers_kinematics_nearest_the_arm() {
    let mut c = homed(0.01);
    let t = ms(500);
    ok(&mut c, t, "HERE C");
    ok(&mut c, t, "SETPVC C X 3000");
    ok(&mut c, t, "SETPVC C Z 3000");
    ok(&mut c, t, "SETPVC C P -900");
    let (counts, cart) = listpv(&mut c, t, "C");
    assert_eq!(cart, [3000, 0, 3000, -900, 0]);
    // The counts reproduce the coordinates (to the rounding of the counts).
    let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
    let k = Constants::named("factory").unwrap();
    let q = k.angles(&counts.map(|v| v as f64)).unwrap();
    let p = robot.fk(&q).unwrap().world_from_tool.pos;
    assert!((p.x - 0.3).abs() < 2e-4 && p.y.abs() < 2e-4 && (p.z - 0.3).abs() < 2e-4, "{p:?}");
    assert!(((q[1] + q[2] + q[3]).to_degrees() + 90.0).abs() < 0.05);
    assert!(robot.fk(&q).unwrap().within_limits());
    // Elbow up (θ3 < 0) is nearest the home configuration (θ3 ≈ −95°).
    assert!(q[2] < 0.0, "{q:?}");
    let (_, t2) = {
        say(&mut c, t, "MOVED C");
        wait_prompt(&mut c, t, t + ms(5000))
    };
    assert_eq!(c.counts(), counts);
    // Out of reach.
    ok(&mut c, t2, "SETPVC C X 9000");
    assert_eq!(say(&mut c, t2, "MOVED C"), "MOVED C\r\n*** POSITION NOT REACHABLE\r\n>");
    assert_eq!(say(&mut c, t2, "LISTPV C"), "LISTPV C\r\n*** POSITION NOT REACHABLE\r\n>");
    ok(&mut c, t2, "DEFP E");
    assert!(say(&mut c, t2, "SETPVC E X 10").contains("*** POSITION E HAS NO COORDINATES"));
    assert!(say(&mut c, t2, "SETPVC C W 10").contains("*** BAD ARGUMENT"));
    // SETPV on a Cartesian position solves it first.
    ok(&mut c, t2, "SETPVC C X 3000");
    ok(&mut c, t2, "SETPV C 1 100");
    let (c2, _) = listpv(&mut c, t2, "C");
    assert_eq!(c2, [100, counts[1], counts[2], counts[3], counts[4]]);
}

#[test]
fn out_of_range_targets_name_the_axis() {
    let mut c = homed(0.01);
    let t = ms(500);
    ok(&mut c, t, "DEFP P");
    // Shoulder: 0 counts is θ2 = 120.3°, the limit 130° is about +1100 counts away.
    ok(&mut c, t, "SETPV P 2 5000");
    let out = say(&mut c, t, "MOVE P");
    assert!(out.starts_with("MOVE P\r\n*** OUT OF RANGE: axis 2 ("), "{out}");
    assert!(out.ends_with("\r\n>"));
    ok(&mut c, t, "SETPV P 2 0");
    ok(&mut c, t, "SETPV P 1 -30000"); // −211°
    assert!(say(&mut c, t, "MOVED P").contains("*** OUT OF RANGE: axis 1 "));
    assert!(!c.is_moving());
    assert_eq!(c.counts(), [0; 5]);
}

#[test]
fn here_during_a_move_records_the_interpolated_counts_and_clrbuf_empties_the_queue() {
    let mut c = homed(0.01);
    let t0 = ms(1000);
    ok(&mut c, t0, "DEFP A");
    ok(&mut c, t0, "SETPV A 1 14188"); // 22.2 ms
    ok(&mut c, t0, "DEFP B");
    ok(&mut c, t0, "SETPV B 1 0");
    ok(&mut c, t0, "MOVE A");
    ok(&mut c, t0, "MOVE B"); // queued
    ok(&mut c, t0 + ms(11), "HERE M");
    let (m, _) = listpv(&mut c, t0 + ms(11), "M");
    let expect = (14188.0 * 11.0 / 22.222_222) as i64;
    assert!((m[0] - expect).abs() <= 1, "{m:?} vs {expect}");
    ok(&mut c, t0 + ms(12), "CLRBUF");
    c.advance(t0 + ms(100));
    assert!(!c.is_moving());
    assert_eq!(c.counts(), [14188, 0, 0, 0, 0], "B was dropped from the queue");
    // Without CLRBUF the queue runs in order.
    ok(&mut c, t0 + ms(100), "MOVE B");
    ok(&mut c, t0 + ms(100), "MOVE A");
    c.advance(t0 + ms(120));
    assert!(c.counts()[0] > 0 && c.counts()[0] < 14188, "on its way back to A");
    c.advance(t0 + ms(150));
    assert_eq!(c.counts(), [14188, 0, 0, 0, 0]);
    // MOVED after MOVE waits for both.
    ok(&mut c, t0 + ms(200), "MOVE B");
    assert_eq!(say(&mut c, t0 + ms(200), "MOVED A"), "MOVED A\r\n");
    let (out, t) = wait_prompt(&mut c, t0 + ms(200), t0 + ms(1000));
    assert_eq!(out, "Done.\r\n>");
    assert_eq!(t - (t0 + ms(200)), ms(45));
}

#[test]
fn abort_stops_a_moved_and_answers_after_it() {
    let mut c = homed(0.01);
    let t0 = ms(1000);
    ok(&mut c, t0, "DEFP A");
    ok(&mut c, t0, "SETPV A 1 14188");
    assert_eq!(say(&mut c, t0, "MOVED A"), "MOVED A\r\n");
    // Typed ahead: runs after the abort's prompt.
    assert_eq!(say(&mut c, t0 + ms(5), "SPEED 10"), "");
    let out = say(&mut c, t0 + ms(11), "a");
    assert_eq!(out, "*** MOTION ABORTED\r\n>a\r\nDone.\r\n>SPEED 10\r\nDone.\r\n>");
    let c1 = c.counts()[0];
    assert!((c1 - 7023).abs() <= 2, "{c1}");
    assert!(!c.is_moving());
    c.advance(t0 + ms(100));
    assert_eq!(c.counts()[0], c1);
    // A with nothing moving.
    ok(&mut c, t0 + ms(100), "A");
    // Aborting HOME leaves the arm not homed.
    say(&mut c, t0 + ms(100), "HOME");
    assert_eq!(say(&mut c, t0 + ms(110), "A"), "*** MOTION ABORTED\r\n>A\r\nDone.\r\n>");
    assert!(!c.is_homed());
    // COFF stops a MOVE.
    let mut c = homed(0.01);
    ok(&mut c, t0, "HERE Z");
    ok(&mut c, t0, "SETPV Z 1 14188");
    ok(&mut c, t0, "MOVE Z");
    ok(&mut c, t0 + ms(10), "COFF");
    assert!(!c.is_moving());
    let c1 = c.counts()[0];
    assert!(c1 > 5000 && c1 < 8000, "{c1}");
}

#[test]
fn gripper_open_close_take_half_a_second() {
    let mut c = sim(0.01);
    assert!(c.gripper_open());
    assert_eq!(say(&mut c, ms(0), "CLOSE"), "CLOSE\r\n");
    let (out, t) = wait_prompt(&mut c, ms(0), ms(100));
    assert_eq!((out.as_str(), t), ("Done.\r\n>", ms(5)));
    assert!(!c.gripper_open());
    say(&mut c, t, "OPEN");
    wait_prompt(&mut c, t, ms(100));
    assert!(c.gripper_open());
}

#[test]
fn dimp_and_moves_run_piecewise_through_the_vector() {
    let mut c = homed(0.01);
    let t0 = ms(1000);
    ok(&mut c, t0, "DIMP V[3]");
    ok(&mut c, t0, "SETPV V[1] 1 14188"); // 100° on motor 1 from home: 22.2 ms
    ok(&mut c, t0, "SETPV V[2] 1 0"); // back: 22.2 ms
    assert!(say(&mut c, t0, "MOVES V 1 3").contains("*** POSITION V[3] HAS NO COORDINATES"));
    ok(&mut c, t0, "SETPV V[3] 1 7094"); // 50°: 11.1 ms
    assert!(say(&mut c, t0, "MOVES V 1 4").contains("*** BAD ARGUMENT"));
    assert!(say(&mut c, t0, "MOVES W 1 2").contains("*** VECTOR W NOT DEFINED"));
    assert!(say(&mut c, t0, "SETPV V[4] 1 0").contains("*** POSITION V[4] NOT DEFINED"));
    assert_eq!(say(&mut c, t0, "MOVES V 1 3"), "MOVES V 1 3\r\n");
    c.advance(t0 + ms(22));
    assert!(c.counts()[0] > 14000);
    c.advance(t0 + ms(45));
    assert!(c.counts()[0] < 1000);
    let (out, t) = wait_prompt(&mut c, t0 + ms(45), t0 + ms(1000));
    assert_eq!(out, "Done.\r\n>");
    assert_eq!(t - t0, ms(56));
    assert_eq!(c.counts()[0], 7094);
    // Reversed, with a total time split in proportion to the segments' own
    // times: from V[3] (here) to V[3] (0°), V[2] (50°), V[1] (100°) in 1 s
    // (10 ms here): V[2] is reached at 3.33 ms.
    say(&mut c, t, "MOVES V 3 1 100");
    c.advance(t + ms(3));
    assert!((c.counts()[0] - 709).abs() <= 2, "{:?}", c.counts());
    c.advance(t + ms(5));
    assert!((c.counts()[0] - 3547).abs() <= 2, "{:?}", c.counts());
    let (out, t2) = wait_prompt(&mut c, t + ms(5), t + ms(1000));
    assert_eq!(out, "Done.\r\n>");
    assert_eq!(t2 - t, ms(10));
    assert_eq!(c.counts()[0], 14188);
    ok(&mut c, t2, "DIMP V[5]");
    assert_eq!(listpv(&mut c, t2, "V[1]").0[0], 14188, "re-dimensioning keeps the elements");
    assert!(say(&mut c, t2, "DIMP V[0]").contains("*** BAD ARGUMENT"));
    assert!(say(&mut c, t2, "DEFP V").contains("*** BAD ARGUMENT"));
}

#[test]
fn listp_pages_after_twenty_lines() {
    let mut c = sim(1.0);
    let t = ms(0);
    for i in 1..=25 {
        ok(&mut c, t, &format!("DEFP P{i:02}"));
    }
    let out = say(&mut c, t, "LISTP");
    let lines: Vec<&str> = out.split("\r\n").collect();
    assert_eq!(lines[0], "LISTP");
    assert_eq!(lines[1], "P01");
    assert_eq!(lines[20], "P20");
    assert_eq!(lines[21], "Type <cr> to continue");
    assert_eq!(lines[22], "", "no prompt while paused");
    c.feed(t, b"\r");
    assert_eq!(String::from_utf8(c.take_output(t)).unwrap(), "P21\r\nP22\r\nP23\r\nP24\r\nP25\r\n>");
    ok(&mut c, t, "CON");
    // Exactly 20 lines: no pause. A line typed during the pause only continues it.
    let mut c = sim(1.0);
    for i in 1..=20 {
        ok(&mut c, t, &format!("DEFP P{i}"));
    }
    assert!(say(&mut c, t, "LISTP").ends_with("P9\r\n>"));
    ok(&mut c, t, "DIMP V[2]");
    assert!(say(&mut c, t, "LISTP").ends_with("Type <cr> to continue\r\n"));
    assert_eq!(say(&mut c, t, "CON"), "V[1]\r\nV[2]\r\n>");
    assert!(c.control_on());
    // Empty list: just the prompt.
    assert_eq!(say(&mut sim(1.0), t, "LISTP"), "LISTP\r\n>");
    // An abort ends a paused listing with its prompt, then answers as usual.
    assert!(say(&mut c, t, "LISTP").ends_with("Type <cr> to continue\r\n"));
    assert_eq!(say(&mut c, t, "a"), ">a\r\nDone.\r\n>");
    ok(&mut c, t, "CON");
}

#[test]
fn extreme_values_are_refused_not_fatal() {
    let mut c = sim(1.0);
    ok(&mut c, ms(0), "DEFP A");
    for v in ["-9223372036854775808", "9223372036854775807", "99999999999999999999", "-0x10", "1e9"] {
        let out = say(&mut c, ms(0), &format!("SETPV A 1 {v}"));
        assert!(out.contains("*** BAD ARGUMENT"), "{v}: {out:?}");
    }
}

#[test]
fn long_and_binary_lines_are_answered_not_fatal() {
    let mut c = sim(1.0);
    let mut long = vec![b'X'; 1000];
    long.push(b'\r');
    c.feed(ms(0), &long);
    let out = c.take_output(ms(0));
    assert_eq!(&out[..MAX_LINE], &[b'X'; MAX_LINE][..]);
    assert_eq!(&out[MAX_LINE..], b"\r\n*** LINE TOO LONG\r\n>");
    c.feed(ms(0), b"\xff\xfe\x00HOME\xc3\r");
    let out = c.take_output(ms(0));
    assert!(out.ends_with(b"\r\n*** UNKNOWN COMMAND\r\n>"));
    ok(&mut c, ms(0), "CON");
}

#[test]
fn faults_drop_garble_delay_and_disconnect() {
    let faults: Vec<Fault> = [
        "drop@CON#2",
        "garble@LISTPV",
        "delay=0.25@SPEED",
        "disconnect@MOVED",
        "disconnect@CLRBUF#2",
        "garble@MOVED#2",
    ]
    .iter()
    .map(|s| s.parse().unwrap())
    .collect();
    let mut c = Controller::new(SimConfig { time_scale: 0.01, faults, ..SimConfig::default() }).unwrap();
    let t = ms(0);
    ok(&mut c, t, "CON");
    ok(&mut c, t, "COFF");
    assert_eq!(say(&mut c, t, "CON"), "", "dropped: no echo, no reply, no prompt");
    assert!(!c.control_on(), "and no effect");
    ok(&mut c, t, "CON");
    // Garble: echo intact, lines replaced, prompt follows.
    ok(&mut c, t, "HERE P");
    c.feed(t, b"LISTPV P\r");
    let out = c.take_output(t);
    assert!(out.starts_with(b"LISTPV P\r\n") && out.ends_with(b"\r\n>"));
    let body = &out[10..out.len() - 1];
    let lines: Vec<&[u8]> = body.split(|&b| b == b'\n').filter(|l| !l.is_empty()).collect();
    assert_eq!(lines.len(), 3);
    for l in lines {
        let l = l.strip_suffix(b"\r").unwrap();
        assert!(l.iter().all(|b| b.is_ascii_alphabetic() || *b >= 0x80), "{l:?}");
    }
    assert_eq!(listpv(&mut c, t, "P").0, [0; 5], "only the first LISTPV is garbled");
    // Delay: everything, echo included, 250 ms later; the effect is immediate.
    c.feed(t, b"SPEED 30\r");
    assert!(c.take_output(ms(249)).is_empty());
    assert_eq!(c.speed(), 30);
    assert_eq!(c.next_deadline(), Some(ms(250)));
    c.feed(ms(1), b"CON\r");
    assert!(c.take_output(ms(1)).is_empty(), "released behind the delayed reply");
    assert_eq!(c.take_output(ms(250)), b"SPEED 30\r\nDone.\r\n>CON\r\nDone.\r\n>");
    // Disconnect: halfway through the MOVED the arm stops and the link goes.
    let t0 = ms(300);
    say(&mut c, t0, "HOME");
    let (_, t0) = wait_prompt(&mut c, t0, ms(2000));
    ok(&mut c, t0, "SPEED 50");
    ok(&mut c, t0, "SETPV P 1 14188"); // 22.2 ms
    assert_eq!(say(&mut c, t0, "MOVED P"), "MOVED P\r\n");
    c.advance(t0 + ms(10));
    assert!(!c.wants_disconnect());
    c.advance(t0 + ms(12));
    assert!(c.wants_disconnect());
    assert!(!c.is_moving());
    assert!((c.counts()[0] - 7094).abs() <= 1, "{:?}", c.counts());
    assert!(c.take_output(t0 + ms(12)).is_empty());
    c.feed(t0 + ms(13), b"CON\r");
    assert!(c.take_output(t0 + ms(13)).is_empty(), "input is ignored until the link is back");
    c.connection_lost(t0 + ms(14));
    assert!(!c.wants_disconnect());
    ok(&mut c, t0 + ms(15), "CLRBUF");
    // A non-motion command under a disconnect fault: the link goes at once, no effect.
    c.feed(t0 + ms(15), b"CLRBUF\r");
    assert!(c.wants_disconnect() && c.take_output(t0 + ms(15)).is_empty());
    c.connection_lost(t0 + ms(15));
    // The second MOVED is garbled: its Done. too.
    say(&mut c, t0 + ms(20), "SETPV P 1 0");
    assert_eq!(say(&mut c, t0 + ms(20), "MOVED P"), "MOVED P\r\n");
    let (out, _) = wait_prompt(&mut c, t0 + ms(20), t0 + ms(200));
    assert!(!out.contains("Done.") && out.ends_with("\r\n>"), "{out:?}");
}

#[test]
fn a_dropped_connection_keeps_the_state_and_silences_the_waiting_command() {
    let mut c = homed(0.01);
    let t0 = ms(1000);
    ok(&mut c, t0, "DEFP A");
    ok(&mut c, t0, "SETPV A 1 14188");
    say(&mut c, t0, "MOVED A");
    c.feed(t0 + ms(1), b"SPE");
    c.connection_lost(t0 + ms(5));
    assert!(c.is_moving(), "the motion goes on");
    c.advance(t0 + ms(50));
    assert!(c.take_output(t0 + ms(50)).is_empty(), "no Done. for the next client");
    assert_eq!(c.counts()[0], 14188);
    ok(&mut c, t0 + ms(50), "CON");
    assert_eq!(listpv(&mut c, t0 + ms(50), "A").0[0], 14188);
}

#[test]
fn record_holds_the_physical_tool_positions() {
    let dir = std::env::temp_dir().join(format!("kinema-sim-unit-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("rec.csv");
    let cfg = SimConfig { time_scale: 0.01, record: Some(path.clone()), ..SimConfig::default() };
    let mut c = Controller::new(cfg.clone()).unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "x,y,z\n");
    say(&mut c, ms(0), "HOME");
    wait_prompt(&mut c, ms(0), ms(1000));
    // HOME from the home position: 5 s nominal = 501 samples at the same place.
    assert_eq!(c.recorded().len(), 501);
    let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
    let truth = cfg.true_constants.clone();
    let at = |counts: [f64; 5]| robot.fk(&truth.angles(&counts).unwrap()).unwrap().world_from_tool.pos;
    let p0 = at([0.0; 5]);
    assert!(c.recorded().iter().all(|s| s == &[p0.x, p0.y, p0.z]));
    ok(&mut c, ms(100), "DEFP A");
    ok(&mut c, ms(100), "SETPV A 1 14188");
    say(&mut c, ms(100), "MOVED A 100"); // 1 s nominal: 101 samples
    wait_prompt(&mut c, ms(100), ms(1000));
    let rec = c.recorded().to_vec();
    assert_eq!(rec.len(), 602);
    for k in 0..=100 {
        let p = at([14188.0 * k as f64 / 100.0, 0.0, 0.0, 0.0, 0.0]);
        let s = rec[501 + k];
        assert!((s[0] - p.x).abs() < 1e-12 && (s[1] - p.y).abs() < 1e-12 && (s[2] - p.z).abs() < 1e-12, "{k}");
    }
    let text = std::fs::read_to_string(&path).unwrap();
    let rows: Vec<&str> = text.lines().collect();
    assert_eq!(rows.len(), 603);
    let last: Vec<f64> = rows[602].split(',').map(|v| v.parse().unwrap()).collect();
    assert_eq!(last, rec[601].to_vec());
    // A very slow move (an hour nominal) is sampled more coarsely, not 360 000 times.
    ok(&mut c, ms(200), "SETPV A 1 0");
    say(&mut c, ms(200), "MOVED A 360000");
    wait_prompt(&mut c, ms(200), ms(100_000));
    let added = c.recorded().len() - 602;
    assert_eq!(added, MAX_SAMPLES_PER_MOTION + 1);
    assert_eq!(std::fs::read_to_string(&path).unwrap().lines().count(), 603 + added);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn record_noise_has_the_configured_sigma_and_follows_the_seed() {
    let dir = std::env::temp_dir().join(format!("kinema-sim-noise-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = |seed: u64| {
        let cfg = SimConfig {
            time_scale: 0.001,
            record: Some(dir.join(format!("n{seed}.csv"))),
            noise: 0.002,
            seed,
            ..SimConfig::default()
        };
        let mut c = Controller::new(cfg).unwrap();
        for i in 0..4u64 {
            say(&mut c, ms(100 * i), "HOME");
            c.advance(ms(100 * i + 10));
        }
        c.recorded().to_vec()
    };
    let a = run(1);
    assert_eq!(a.len(), 4 * 501);
    assert_eq!(a, run(1));
    assert_ne!(a, run(2));
    let robot = Robot::builtin("scorbot-er-v-plus").unwrap();
    let truth = Constants::named("calibrated").unwrap();
    let p = robot.fk(&truth.angles(&[0.0; 5]).unwrap()).unwrap().world_from_tool.pos;
    for (axis, centre) in [p.x, p.y, p.z].into_iter().enumerate() {
        let e: Vec<f64> = a.iter().map(|s| s[axis] - centre).collect();
        let n = e.len() as f64;
        let mean = e.iter().sum::<f64>() / n;
        let sd = (e.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0)).sqrt();
        assert!(mean.abs() < 4.0 * 0.002 / n.sqrt(), "axis {axis}: mean {mean}");
        assert!((sd / 0.002 - 1.0).abs() < 0.06, "axis {axis}: sd {sd}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_configurations_are_refused() {
    for cfg in [
        SimConfig { time_scale: 0.0, ..SimConfig::default() },
        SimConfig { time_scale: f64::NAN, ..SimConfig::default() },
        SimConfig { noise: -1.0, ..SimConfig::default() },
        SimConfig {
            faults: vec![Fault { kind: FaultKind::Drop, command: "move".into(), nth: 1 }],
            ..SimConfig::default()
        },
        SimConfig { record: Some("/nonexistent-dir-kinema/x.csv".into()), ..SimConfig::default() },
    ] {
        assert!(Controller::new(cfg).is_err());
    }
}

#[test]
fn random_input_never_panics_and_always_frames() {
    let words = [
        "HOME",
        "CON",
        "COFF",
        "SPEED",
        "DEFP",
        "DIMP",
        "HERE",
        "SETPV",
        "SETPVC",
        "LISTPV",
        "LISTP",
        "MOVE",
        "MOVED",
        "MOVES",
        "OPEN",
        "CLOSE",
        "A",
        "CLRBUF",
        "P",
        "V[2]",
        "V",
        "1",
        "2",
        "-5",
        "X",
        "P",
        "300",
        "99999999999999999999",
        "V[0]",
        "[",
        "]",
        "\u{e9}",
        "",
    ];
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    let faults = vec!["garble@LISTPV#3".parse().unwrap(), "delay=0.01@SPEED#2".parse().unwrap()];
    let mut c = Controller::new(SimConfig { time_scale: 0.001, faults, ..SimConfig::default() }).unwrap();
    let mut t = ms(0);
    for _ in 0..4000 {
        let mut line: Vec<u8> = Vec::new();
        if rng.random_bool(0.15) {
            let n = rng.random_range(0..400);
            line.extend((0..n).map(|_| rng.random::<u8>()));
        } else {
            for _ in 0..rng.random_range(1..5) {
                line.extend_from_slice(words[rng.random_range(0..words.len())].as_bytes());
                line.push(if rng.random_bool(0.9) { b' ' } else { b'\t' });
            }
        }
        line.push(b'\r');
        c.feed(t, &line);
        t += ms(rng.random_range(0..20));
        c.advance(t);
        let _ = c.take_output(t);
        if c.wants_disconnect() {
            c.connection_lost(t);
        }
    }
    // Still answering.
    c.advance(t + ms(100_000));
    c.take_output(t + ms(100_000));
    let mut out = Vec::new();
    for _ in 0..1000 {
        c.feed(t + ms(100_000), b"\r");
        out = c.take_output(t + ms(100_000));
        if out.ends_with(b">") {
            break;
        }
    }
    assert!(out.ends_with(b">"), "{:?}", String::from_utf8_lossy(&out));
    assert_eq!(c.take_output(t + ms(100_000)), b"");
    c.feed(t + ms(100_000), b"CON\r");
    assert_eq!(c.take_output(t + ms(100_000)), b"CON\r\nDone.\r\n>");
}
