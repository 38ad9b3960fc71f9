//! The parser and the compiler never panic and always finish, on random
//! bytes and on random sequences of the language's own tokens (which reach
//! much deeper than random bytes do).

use kinema::Robot;
use kinema_lang::{compile, parse, Options};
use proptest::prelude::*;

use crate::mutate;

const WORDS: &[&str] = &[
    "POS",
    "PTP",
    "LIN",
    "CIRC",
    "REL",
    "BLEND",
    "IN",
    "SPEED",
    "VEL",
    "ACC",
    "JVEL",
    "JACC",
    "PROFILE",
    "REDUNDANCY",
    "TOOL",
    "BASE",
    "WAIT",
    "PAUSE",
    "HOME",
    "LOOP",
    "FOR",
    "TO",
    "END",
    "MOVEZ",
    "MOVETITA",
    "MOVEXY",
    "JOINT",
    "CART",
    "home",
    "p",
    "i",
    "scurve",
    "cubic",
    "(",
    ")",
    ",",
    "=",
    "+",
    "-",
    "*",
    "/",
    ";",
    "\n",
    "\n",
    "\n",
    "0",
    "1",
    "2.5",
    "50mm",
    "-30deg",
    "90 deg/s",
    "1m/s^2",
    "50%",
    "0.5s",
    "1e9",
    "1e-9",
    "// note",
    "€",
    "#",
];

fn program_from(idx: &[usize]) -> String {
    let mut s = String::new();
    for &i in idx {
        s.push_str(WORDS[i % WORDS.len()]);
        s.push(' ');
    }
    s
}

/// `base` proptest cases, times `KINEMA_FUZZ_SCALE`.
fn cases(base: u32) -> u32 {
    u32::try_from(mutate::fuzz_cases(base as usize)).unwrap_or(u32::MAX)
}

fn small() -> Options {
    Options { dt: 0.05, start: None, max_samples: 20_000, max_steps: 2_000, ..Options::default() }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(3000), ..ProptestConfig::default() })]

    #[test]
    fn parser_survives_random_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        let text = String::from_utf8_lossy(&bytes);
        let (_, diags) = parse(&text);
        for d in diags {
            prop_assert!(d.span.start <= d.span.end && d.span.end <= text.len());
            let _ = d.render("fuzz.prg", &text);
        }
    }

    #[test]
    fn parser_survives_random_token_sequences(idx in proptest::collection::vec(0usize..1000, 0..80)) {
        let text = program_from(&idx);
        let (_, diags) = parse(&text);
        for d in diags {
            prop_assert!(d.span.end <= text.len());
            let _ = d.render("fuzz.prg", &text);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(400), ..ProptestConfig::default() })]

    #[test]
    fn compiler_survives_random_token_sequences(idx in proptest::collection::vec(0usize..1000, 0..40), which in 0usize..3) {
        let robot = Robot::builtin(["scara5", "lbr-iiwa-14-r820", "puma560"][which]).unwrap();
        let text = program_from(&idx);
        match compile(&text, &robot, &small()) {
            Ok(plan) => prop_assert!(plan.trajectory.len() <= 20_000 + 1),
            Err(diags) => prop_assert!(diags.iter().any(|d| d.is_error())),
        }
    }
}

/// Deep nesting and long inputs are errors, not stack overflows.
#[test]
fn deep_nesting_is_bounded() {
    let robot = Robot::builtin("scara5").unwrap();
    let text = format!("WAIT {}1{}", "(".repeat(10_000), ")".repeat(10_000));
    assert!(compile(&text, &robot, &small()).is_err());
    let text = format!("WAIT {}1", "-".repeat(100_000));
    assert!(compile(&text, &robot, &small()).is_err());
    let text = "LOOP 1\n".repeat(1000) + &"END\n".repeat(1000);
    assert!(compile(&text, &robot, &small()).is_err());
}
