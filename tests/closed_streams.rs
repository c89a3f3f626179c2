//! The program's output streams closed under it: progress and results must not panic.
//!
//! `eprintln!`/`println!` panic ("failed printing to stderr/stdout") when the stream is a pipe
//! whose reader has gone (`critspeed … | head -1`, a closed log pipe). A panic exits with 101
//! and prints its message; the program must instead finish with its normal exit code. Each
//! case runs the fast Kalker `linear` command on the seed study.

mod common;
use std::process::{Command, Output, Stdio};

use common::{root, scratch};

const TABLE_TITLE: &str = "linear stability of the centred motion";

fn seed() -> String {
    root().join("studies/seed.toml").display().to_string()
}

/// Runs `critspeed args` in the scratch folder `name` with stdout (`close_stdout`) or stderr
/// writing into a pipe whose read end is already closed, so that every write to it fails with
/// a broken pipe; returns the output and the other stream's text.
fn with_dropped_reader(name: &str, args: &[&str], close_stdout: bool) -> (Output, String) {
    let dir = scratch(name);
    let (reader, writer) = std::io::pipe().expect("a pipe");
    drop(reader);
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_critspeed"));
    cmd.args(args).current_dir(&dir);
    if close_stdout {
        cmd.stdout(writer).stderr(Stdio::piped());
    } else {
        cmd.stdout(Stdio::piped()).stderr(writer);
    }
    let out = cmd.output().expect("the binary runs");
    let open = if close_stdout {
        &out.stderr
    } else {
        &out.stdout
    };
    let text = String::from_utf8_lossy(open).into_owned();
    (out, text)
}

#[test]
fn a_closed_stdout_pipe_ends_the_output_quietly() {
    let (out, stderr) = with_dropped_reader("stdout", &["linear", &seed()], true);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    // the status messages still arrive and the files are still written
    assert!(
        stderr.contains("wrote ") && stderr.contains("linear.json"),
        "{stderr}"
    );
}

#[test]
fn a_closed_stderr_pipe_does_not_stop_the_results() {
    let (out, stdout) = with_dropped_reader("stderr", &["linear", &seed()], false);
    assert_eq!(out.status.code(), Some(0), "stdout: {stdout}");
    assert!(stdout.contains(TABLE_TITLE), "{stdout}");
}

#[test]
fn a_user_error_keeps_exit_code_2_with_stderr_closed() {
    let (out, stdout) = with_dropped_reader("user-error", &["linear", "no-such-study.toml"], false);
    assert_eq!(out.status.code(), Some(2), "stdout: {stdout}");
}

/// `2>&-` and `>&-` (the descriptor itself closed, as a shell does it).
#[test]
fn closed_descriptors_give_the_normal_exit_code() {
    let dir = scratch("descriptors");
    let run = |redirect: &str| {
        Command::new("sh")
            .arg("-c")
            .arg(format!("exec \"$0\" linear \"$1\" {redirect}"))
            .arg(env!("CARGO_BIN_EXE_critspeed"))
            .arg(seed())
            .current_dir(&dir)
            .output()
            .expect("sh runs")
    };
    let no_stderr = run("2>&-");
    assert_eq!(no_stderr.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&no_stderr.stdout).contains(TABLE_TITLE));
    let no_stdout = run(">&-");
    let err = String::from_utf8_lossy(&no_stdout.stderr);
    assert_eq!(no_stdout.status.code(), Some(0), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}
