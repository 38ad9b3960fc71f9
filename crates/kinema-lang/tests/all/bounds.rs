//! Bounded work: every run ends within the step limit and the stop (deadline
//! or flag), whatever the program; parsing, checking and error recovery take
//! time linear in the program's size; nesting cannot overflow the stack.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use kinema::Robot;
use kinema_lang::{compile, render_all, Diagnostic, Options, Stop};

fn robot(name: &str) -> Robot {
    Robot::builtin(name).unwrap()
}

/// The errors of `src` and how long compiling and rendering them took.
fn timed_errors(src: &str, robot: &Robot, opts: &Options) -> (Vec<Diagnostic>, Duration) {
    let t = Instant::now();
    let d = match compile(src, robot, opts) {
        Ok(_) => panic!("expected errors for:\n{}", &src[..src.len().min(500)]),
        Err(d) => d,
    };
    let _ = render_all(&d, "test.prg", src);
    let elapsed = t.elapsed();
    (d.into_iter().filter(Diagnostic::is_error).collect(), elapsed)
}

fn line_of(src: &str, d: &Diagnostic) -> usize {
    kinema_lang::diag::line_col(src, d.span.start).0
}

/// Runs `f` on a thread with the default 2 MiB stack of a spawned thread (the main
/// test thread may have more), so that deep recursion would show as an overflow.
fn on_small_stack<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    std::thread::Builder::new().stack_size(2 << 20).spawn(f).unwrap().join().unwrap()
}

/// The program of issue 24 ran for ever (empty loop bodies were not counted): now it
/// is refused at once, at the loop, naming the limit.
#[test]
fn a_for_loop_of_9e18_empty_passes_ends_at_once_at_the_step_limit() {
    let src = "FOR i = 1 TO 9000000000000000000\nEND\n";
    let (e, took) = timed_errors(src, &robot("scara5"), &Options::default());
    assert!(took < Duration::from_secs(1), "{took:?}");
    assert_eq!(e.len(), 1, "{e:#?}");
    assert_eq!(line_of(src, &e[0]), 1);
    assert!(e[0].message.contains("step limit of 1000000"), "{}", e[0].message);
}

#[test]
fn an_empty_loop_of_a_billion_passes_ends_at_once() {
    let src = "LOOP 1000000000\nEND\n";
    let (e, took) = timed_errors(src, &robot("scara5"), &Options::default());
    assert!(took < Duration::from_secs(1), "{took:?}");
    assert_eq!(e.len(), 1, "{e:#?}");
    assert!(e[0].message.contains("this LOOP makes 1000000000 passes"), "{}", e[0].message);
    assert!(e[0].message.contains("step limit of 1000000"), "{}", e[0].message);
}

/// Every pass counts one step, empty or not: a loop that fits runs, one pass more is cut.
#[test]
fn loop_passes_count_toward_the_step_limit() {
    let r = robot("scara5");
    let opts = Options { max_steps: 1000, ..Options::default() };
    // The LOOP statement and its 999 passes: 1000 steps.
    assert!(compile("LOOP 999\nEND\n", &r, &opts).is_ok());
    assert!(compile("FOR i = 2 TO 1000\nEND\n", &r, &opts).is_ok());
    // One more: allowed by the count alone (1000 passes), refused once the LOOP itself counted.
    let e = compile("LOOP 1000\nEND\n", &r, &opts).unwrap_err();
    assert!(e[0].message.contains("makes 1000 passes, more than the step limit of 1000 allows (999 left"), "{e:#?}");
    // A count known only while running (a FOR counter) is checked before the loop's first pass.
    let src = "FOR i = 1 TO 2\n  LOOP 600 * i\n  END\nEND\n";
    let e = compile(src, &r, &opts).unwrap_err();
    assert_eq!(e.len(), 1, "{e:#?}");
    assert_eq!(line_of(src, &e[0]), 2);
    assert!(e[0].message.contains("makes 1200 passes, more than the step limit of 1000 allows"), "{e:#?}");
    // Nested loops whose product is too large: the first inner loop that cannot finish.
    let e = compile("LOOP 100\nLOOP 100\nEND\nEND\n", &r, &opts).unwrap_err();
    assert_eq!(e.len(), 1, "{e:#?}");
    assert!(e[0].message.contains("more than the step limit of 1000 allows (79 left at this point)"), "{e:#?}");
    // FOR bounds too large to count in exactly are refused, not looped on for ever.
    let e = compile("FOR i = 100000000000000000 TO 100000000000000010\nEND\n", &r, &opts).unwrap_err();
    assert!(e[0].message.contains("within ±9007199254740992"), "{e:#?}");
}

/// No step limit to speak of: only the stop ends these.
fn unlimited(stop: Stop) -> Options {
    Options { max_steps: usize::MAX, stop, ..Options::default() }
}

#[test]
fn a_deadline_stops_a_long_program_with_one_diagnostic() {
    let r = robot("scara5");
    for src in ["LOOP 1000000000\nEND\n", "LOOP 1000000000\n  WAIT 0s\nEND\n", "FOR i = 1 TO 1000000000\nEND\n"] {
        let (e, took) = timed_errors(src, &r, &unlimited(Stop::after(Duration::from_millis(200))));
        assert!(took < Duration::from_secs(2), "{src}: {took:?}");
        assert_eq!(e.len(), 1, "{e:#?}");
        assert!(e[0].message.starts_with("stopped here: the time budget of 0.200 s ran out"), "{e:#?}");
    }
}

#[test]
fn a_raised_flag_stops_a_long_program() {
    let flag = Arc::new(AtomicBool::new(false));
    let raiser = {
        let flag = flag.clone();
        std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(100));
            flag.store(true, Ordering::Relaxed);
        })
    };
    let src = "LOOP 1000000000\n  WAIT 0s\nEND\n";
    let (e, took) = timed_errors(src, &robot("scara5"), &unlimited(Stop::never().with_flag(flag)));
    raiser.join().unwrap();
    assert!(took < Duration::from_secs(2), "{took:?}");
    assert_eq!(e.len(), 1, "{e:#?}");
    assert_eq!(e[0].message, "stopped here: the run was cancelled");
}

/// A LIN and a CIRC that leave the workspace, in a loop: the failed conversion is the
/// same at every pass and is computed once (it was recomputed at each, ~7 ms a pass).
#[test]
fn a_failing_lin_in_a_loop_is_computed_once() {
    let iiwa = robot("lbr-iiwa-14-r820");
    let program = |n: usize| {
        format!(
            "PTP JOINT(10deg, 20deg, 0deg, -60deg, 0deg, 30deg, 0deg) IN 1s\nLOOP {n}\n  LIN REL CART(3000mm, 0mm, 0mm)\n  CIRC CART(0mm, 500mm, 500mm), CART(0mm, 3000mm, 400mm)\nEND\n"
        )
    };
    let (one, _) = timed_errors(&program(1), &iiwa, &Options::default());
    let (e, took) = timed_errors(&program(20_000), &iiwa, &Options::default());
    assert!(took < Duration::from_secs(5), "{took:?}");
    let messages = |e: &[Diagnostic]| e.iter().map(|d| d.message.clone()).collect::<Vec<_>>();
    assert_eq!(messages(&e), messages(&one));
    assert!(e.iter().any(|d| d.message.starts_with("LIN cannot be followed")), "{e:#?}");
}

/// 12 800 nested LOOPs: one error for the over-deep block (there were 25 472, rendered
/// in 46 s), on a 2 MiB stack.
#[test]
fn deep_nesting_is_one_error_and_fast() {
    let (e, took) = on_small_stack(|| {
        let n = 12_800;
        let src = "LOOP 1\n".repeat(n) + "WAIT 1s\n" + &"END\n".repeat(n);
        timed_errors(&src, &robot("scara5"), &Options::default())
    });
    assert!(took < Duration::from_secs(3), "{took:?}");
    assert_eq!(e.len(), 1, "{e:#?}");
    assert!(e[0].message.contains("nested more than 64 deep"), "{e:#?}");
    // Alternating FOR and LOOP, with statements and errors at every level.
    let (e, took) = on_small_stack(|| {
        let mut src = String::new();
        for k in 0..5000 {
            src.push_str(if k % 2 == 0 { "FOR i = 1 TO 2\n" } else { "LOOP 2\n" });
            src.push_str("WAIT 5mm\n");
        }
        src.push_str(&"END\n".repeat(5000));
        timed_errors(&src, &robot("scara5"), &Options::default())
    });
    assert!(took < Duration::from_secs(3), "{took:?}");
    assert_eq!(e.len(), 1, "{e:#?}");
}

/// Long expressions: a chain of 100 000 sums is not a recursion 100 000 deep.
#[test]
fn long_expressions_do_not_overflow_the_stack() {
    on_small_stack(|| {
        let r = robot("scara5");
        for src in [
            format!("WAIT 0s{}\n", " + 1ms".repeat(100_000)),
            format!("WAIT 1s{}\n", " * 1".repeat(100_000)),
            format!("WAIT 1s{}\n", " - -1ms".repeat(50_000)),
        ] {
            let _ = compile(&src, &r, &Options::default());
        }
    });
}

/// A program of 16 000 errors of every kind (syntax, names, units), some 300 KB: checked
/// and rendered in time linear in its size (it was quadratic: 57 s for 275 KB).
#[test]
fn an_error_full_program_is_checked_and_rendered_in_linear_time() {
    // Errors found by the static check (it runs only when the program parses) ...
    let checked = |n: usize| {
        let mut src = String::new();
        for i in 0..n {
            src.push_str(&format!(
                "POS p{i} = JOINT(0mm, 0deg, 0deg, 0mm, 0deg)\nLOOP 2\n  PTP q{i}\n  WAIT 5mm\nEND\n"
            ));
        }
        src
    };
    // ... and syntax errors, each followed by recovery.
    let syntax = |n: usize| "FROB 1\nWAIT (1s\nLOOP 2 3\nEND\nPTP JOINT(,)\nEND\n€\n".repeat(n);
    let r = robot("scara5");
    for (build, per_block) in [(&checked as &dyn Fn(usize) -> String, 2), (&syntax, 7)] {
        let (small, big) = (build(500), build(8000));
        assert!(big.len() > 250_000, "{}", big.len());
        let (e_small, t_small) = timed_errors(&small, &r, &Options::default());
        let (e_big, t_big) = timed_errors(&big, &r, &Options::default());
        assert_eq!(e_small.len(), per_block * 500, "{:#?}", &e_small[..per_block]);
        assert_eq!(e_big.len(), per_block * 8000);
        // 16 × the size: linear is ~16 × the time, quadratic ~256 ×.
        assert!(t_big < Duration::from_secs(10), "{t_big:?}");
        assert!(t_big.as_secs_f64() < 64.0 * t_small.as_secs_f64() + 0.5, "{t_small:?} then {t_big:?}");
    }
}
