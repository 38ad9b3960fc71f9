//! Random edits of valid inputs, for the fuzz tests of every input format
//! (descriptions here; programs, server requests and CSV files from the
//! other crates' tests, which include this file by path).
//!
//! `KINEMA_FUZZ_SCALE=N` multiplies every fuzz test's case count: CI runs
//! them at 1 (a few minutes in all), the long run of benchmarks/README.md at
//! hundreds.

#![allow(dead_code)]

use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// `base` cases times `KINEMA_FUZZ_SCALE` (1 when unset or not a number).
pub fn fuzz_cases(base: usize) -> usize {
    let scale = std::env::var("KINEMA_FUZZ_SCALE").ok().and_then(|s| s.parse::<usize>().ok()).unwrap_or(1);
    base.saturating_mul(scale.max(1))
}

pub const INTERESTING: &[&str] = &[
    "=",
    "[",
    "]",
    "[[",
    "]]",
    "{",
    "}",
    "\"",
    "'",
    "#",
    "\n",
    ",",
    ".",
    "-",
    "+",
    "e",
    " ",
    "0",
    "1",
    "9",
    "1e308",
    "-1e308",
    "nan",
    "inf",
    "-inf",
    "1e-320",
    "é",
    "😀",
    "\u{0}",
    "<",
    ">",
    "/>",
    "</joint>",
    "<joint>",
    "&amp;",
    "&",
    "<!--",
    "-->",
    "xyz=\"",
    "\"0 0 1\"",
    "type=\"floating\"",
    "type=\"prismatic\"",
    "link",
    "joint",
    "prismatic",
    "general",
    "modified",
    "[[joint]]",
    "[poses]",
    "home = []",
    "axis = [0, 0, 0]",
    "type = \"prismatic\"",
    "\r\n",
    "\t",
    "\\",
    "\\u",
];

/// One random edit of `text`, always valid UTF-8.
pub fn mutate(text: &str, rng: &mut ChaCha8Rng) -> String {
    let bytes = text.as_bytes();
    let cut = |rng: &mut ChaCha8Rng| {
        // A char boundary.
        let mut i = rng.random_range(0..=bytes.len());
        while !text.is_char_boundary(i) {
            i -= 1;
        }
        i
    };
    let (a, b) = {
        let x = cut(rng);
        let y = cut(rng);
        (x.min(y), x.max(y))
    };
    let piece = INTERESTING[rng.random_range(0..INTERESTING.len())];
    match rng.random_range(0..8) {
        0 => format!("{}{}", &text[..a], &text[b..]),        // delete a range
        1 => format!("{}{piece}{}", &text[..a], &text[a..]), // insert
        2 => format!("{}{piece}{}", &text[..a], &text[b..]), // replace a range
        3 => text[..a].to_string(),                          // truncate
        4 => format!("{}{}{}", &text[..b], &text[a..b], &text[b..]), // duplicate a range
        5 => {
            // Swap two lines.
            let mut lines: Vec<&str> = text.lines().collect();
            if lines.len() > 1 {
                let i = rng.random_range(0..lines.len());
                let j = rng.random_range(0..lines.len());
                lines.swap(i, j);
            }
            lines.join("\n")
        }
        6 => {
            // Change a number.
            let nums: Vec<(usize, char)> = text.char_indices().filter(|(_, c)| c.is_ascii_digit()).collect();
            if nums.is_empty() {
                return text.to_string();
            }
            let (i, _) = nums[rng.random_range(0..nums.len())];
            let repl = ["0", "-", "999999", "1e400", "nan", ".", "-0", "3.5e-3"][rng.random_range(0..8)];
            format!("{}{repl}{}", &text[..i], &text[i + 1..])
        }
        _ => {
            // Several small edits at once.
            let mut t = text.to_string();
            for _ in 0..rng.random_range(2..6) {
                t = mutate(&t, rng);
            }
            t
        }
    }
}

pub fn random_text(rng: &mut ChaCha8Rng) -> String {
    let len = rng.random_range(0..400);
    match rng.random_range(0..3) {
        // Raw bytes, made valid UTF-8 the lossy way.
        0 => {
            let bytes: Vec<u8> = (0..len).map(|_| rng.random()).collect();
            String::from_utf8_lossy(&bytes).into_owned()
        }
        // Random chars.
        1 => (0..len).map(|_| rng.random::<char>()).collect(),
        // Random "tokens".
        _ => (0..len / 4).map(|_| INTERESTING[rng.random_range(0..INTERESTING.len())]).collect(),
    }
}
