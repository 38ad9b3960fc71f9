//! Plain-text lines to standard output. `println!` panics when the write
//! fails (a full disk, a closed stream); [`outln!`] and [`out!`] return the
//! error instead, naming standard output, so that the command fails with an
//! exit code and a message like any other error.

use std::fmt;
use std::io::{self, Write};

use anyhow::{Context, Result};

/// Writes `args` (and a newline when `newline`) to standard output.
pub(crate) fn write(args: fmt::Arguments<'_>, newline: bool) -> Result<()> {
    let mut s = io::stdout().lock();
    s.write_fmt(args)
        .and_then(|()| if newline { s.write_all(b"\n") } else { Ok(()) })
        .context("cannot write to standard output")
}

/// `println!` that returns the write error: `outln!("{x}")?`.
macro_rules! outln {
    () => {
        $crate::stdout::write(format_args!(""), true)
    };
    ($($arg:tt)*) => {
        $crate::stdout::write(format_args!($($arg)*), true)
    };
}

/// `print!` that returns the write error: `out!("{x}")?`.
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::stdout::write(format_args!($($arg)*), false)
    };
}

pub(crate) use {out, outln};
