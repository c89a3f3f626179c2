//! Where the command line writes, without panicking on a closed stream.
//!
//! `eprint!` and `print!` panic when their stream is closed (`critspeed sweep … 2>&-`, or
//! `critspeed linear … | head -1` once `head` has exited). Status and progress messages go
//! through [`status!`]/[`statusln!`], which write to stderr and ignore write errors: the
//! computation and its files matter more than the chatter. Results go through [`results`],
//! which treats a reader that went away (broken pipe) as the end of the output and any other
//! write error as an output failure (exit code 1). The text written is unchanged.

use std::fmt::Arguments;
use std::io::{self, Write};

use super::Failure;

/// `eprint!` that cannot panic: formats to stderr, ignoring write errors.
macro_rules! status {
    ($($arg:tt)*) => {
        $crate::cli::console::to_stderr(format_args!($($arg)*), false)
    };
}

/// `eprintln!` that cannot panic: one line to stderr, ignoring write errors.
macro_rules! statusln {
    () => {
        $crate::cli::console::to_stderr(format_args!(""), true)
    };
    ($($arg:tt)*) => {
        $crate::cli::console::to_stderr(format_args!($($arg)*), true)
    };
}

pub(crate) use {status, statusln};

/// Writes `args` (and a newline when `line`) to stderr under one lock; errors are ignored.
pub(crate) fn to_stderr(args: Arguments<'_>, line: bool) {
    let mut err = io::stderr().lock();
    let _ = err.write_fmt(args);
    if line {
        let _ = err.write_all(b"\n");
    }
}

/// Writes `text` to stdout and flushes. A closed pipe (the reader has exited) ends the output
/// quietly; another write error is a [`Failure::Compute`] naming stdout.
pub(crate) fn results(text: &str) -> Result<(), Failure> {
    let mut out = io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != io::ErrorKind::BrokenPipe => Err(Failure::Compute(
            anyhow::Error::new(e).context("writing the results to stdout"),
        )),
        _ => Ok(()),
    }
}
